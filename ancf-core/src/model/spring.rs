//! Elastic supports: a node held by translational and rotational springs,
//! with dashpots, whose far ends are fixed — a post's or a clamp's
//! compliance, which a pin or a clamp idealises away.
//!
//! The translational spring acts on the node's position r, the rotational
//! one on its gradients r_x, r_y, r_z, each from its rest value (the node's
//! starting coordinates): the energy is
//!
//! ½ Σ_k k_k (r_k − r⁰_k)² + ¼ k_θ Σ_i |r_i − r⁰_i|² / |r⁰_i|²,
//!
//! a constant, diagonal stiffness. A small rotation δθ of an orthonormal
//! triad moves each r_i by δθ × r_i, and Σ_i |δθ × r̂_i|² = 2 |δθ|², so the
//! second term is ½ k_θ |δθ|²: a rotational spring of k_θ (N m/rad) about
//! every axis, the same convention as a point load's moment
//! ([`super::PointLoad::moment_forces`]). It also resists a change of the
//! gradients' length (the section's stretch at the node) with k_θ / (2 |r⁰_i|²);
//! for clamp stiffnesses far below the wire's EA times its element length
//! that is negligible. The dashpot (N s/m) acts on the position's velocity.

use crate::check::{ParameterError, non_negative};
use crate::model::NODE_DOFS;

/// The springs and dashpot of an elastic support.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spring {
    /// Translational stiffness along x, y, z (N/m).
    pub stiffness: [f64; 3],
    /// Rotational stiffness about every axis (N m/rad).
    pub rotational_stiffness: f64,
    /// Translational dashpot (N s/m), on every direction.
    pub damping: f64,
}

impl Spring {
    /// Every stiffness and the damping finite and ≥ 0, named by their scene
    /// keys (`stiffness[1]`, `rotational_stiffness`, `damping`).
    pub fn check(&self) -> Result<(), ParameterError> {
        for (i, k) in self.stiffness.iter().enumerate() {
            non_negative("stiffness", *k).map_err(|e| ParameterError {
                field: format!("stiffness[{i}]"),
                message: e.message,
            })?;
        }
        non_negative("rotational_stiffness", self.rotational_stiffness)?;
        non_negative("damping", self.damping)?;
        Ok(())
    }
}

/// An elastic support placed on the model: its node, its springs and the
/// node's rest coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringAt {
    /// The support (index into the model's supports).
    pub support: usize,
    /// The node held.
    pub node: usize,
    /// Its springs and dashpot.
    pub spring: Spring,
    /// The node's twelve coordinates where the springs are relaxed.
    pub rest: [f64; NODE_DOFS],
    /// The stiffness on each of the twelve coordinates (N/m on r, N on the
    /// gradients: k_θ / (2 |r⁰_i|²)).
    pub diagonal: [f64; NODE_DOFS],
}

impl SpringAt {
    /// The support `support` of `spring` at `node`, relaxed at `rest`.
    pub fn new(support: usize, node: usize, spring: Spring, rest: [f64; NODE_DOFS]) -> Self {
        let mut diagonal = [0.0; NODE_DOFS];
        diagonal[..3].copy_from_slice(&spring.stiffness);
        for i in 0..3 {
            let g = &rest[3 + 3 * i..6 + 3 * i];
            let k = 0.5 * spring.rotational_stiffness / g.iter().map(|x| x * x).sum::<f64>();
            diagonal[3 + 3 * i..6 + 3 * i].fill(k);
        }
        SpringAt {
            support,
            node,
            spring,
            rest,
            diagonal,
        }
    }

    /// The first of the node's coordinates in the model's vectors.
    pub fn first_coordinate(&self) -> usize {
        NODE_DOFS * self.node
    }

    /// The springs' energy at coordinates `q` (all of the model's), J.
    pub fn energy(&self, q: &[f64]) -> f64 {
        let base = self.first_coordinate();
        (0..NODE_DOFS)
            .map(|c| {
                let d = q[base + c] - self.rest[c];
                0.5 * self.diagonal[c] * d * d
            })
            .sum()
    }

    /// Adds the springs' generalized force ∂E/∂q (the internal-force sign
    /// convention: the body feels its negative) to `out`.
    pub fn add_force(&self, q: &[f64], out: &mut [f64]) {
        let base = self.first_coordinate();
        for c in 0..NODE_DOFS {
            out[base + c] += self.diagonal[c] * (q[base + c] - self.rest[c]);
        }
    }

    /// The force the support exerts on the node (N): −k (r − r⁰), less the
    /// dashpot's c ṙ when velocities `v` are given.
    pub fn force_on_body(&self, q: &[f64], v: Option<&[f64]>) -> [f64; 3] {
        let base = self.first_coordinate();
        std::array::from_fn(|k| {
            let c = base + k;
            let damping = v.map_or(0.0, |v| self.spring.damping * v[c]);
            -self.diagonal[k] * (q[c] - self.rest[k]) - damping
        })
    }
}
