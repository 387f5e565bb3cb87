//! Elastic supports: a node held by translational springs, a rotational
//! spring and a dashpot whose far ends are fixed — a post's or a clamp's
//! compliance, which a pin or a clamp idealises away (SPEC §9).
//!
//! The force on the node is f = −K (r − r⁰) − C ṙ, K = diag(k_x, k_y, k_z),
//! r⁰ where the node starts. The rotational spring acts on the unit tangent
//! t = r_x / |r_x|: V = ½ k_θ |t − t⁰|², which is ½ k_θ θ² for a small
//! rotation θ of the tangent — a bending spring about both axes normal to
//! the member, free in torsion and blind to the section's stretch. Its
//! gradient and Hessian with respect to r_x, with n = |r_x|, c = t · t⁰ and
//! w = t⁰ − c t:
//!
//! ∂V/∂r_x = −(k_θ / n) w,  ∂²V/∂r_x² = (k_θ / n²) (c (I − t tᵀ) + t wᵀ + w tᵀ).
//!
//! The torsional spring holds the twist: with the section's rest unit
//! vectors y⁰, z⁰, s = ½ (z⁰ · r_y − y⁰ · r_z) is sin φ for a twist φ about
//! the tangent and zero for a bend, a stretch or a symmetric shear of the
//! section; V_t = ½ k_t s² is quadratic in the coordinates, its Hessian the
//! constant k_t a aᵀ with a = ½ (z⁰ on r_y, −y⁰ on r_z). A member resting
//! on posts without it turns freely about its own axis (frictionless
//! centerline contact cannot hold it), and a static solve is then singular.

use crate::check::{ParameterError, non_negative};
use crate::math::vec3::{dot, norm};
use crate::model::NODE_DOFS;

/// The springs and dashpot of an elastic support.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spring {
    /// Translational stiffness along x, y, z (N/m).
    pub stiffness: [f64; 3],
    /// Rotational stiffness of the tangent: bending about both axes normal
    /// to the member (N m/rad).
    pub rotational_stiffness: f64,
    /// Torsional stiffness about the member's axis (N m/rad).
    pub torsional_stiffness: f64,
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
        non_negative("torsional_stiffness", self.torsional_stiffness)?;
        non_negative("damping", self.damping)?;
        Ok(())
    }
}

/// An elastic support placed on the model: its node, its springs and the
/// node's rest position and tangent.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringAt {
    /// The support (index into the model's supports).
    pub support: usize,
    /// The node held.
    pub node: usize,
    /// Its springs and dashpot.
    pub spring: Spring,
    /// Where the springs are relaxed: the node's position (m) …
    pub rest: [f64; 3],
    /// … its unit tangent …
    pub rest_tangent: [f64; 3],
    /// … and its section's unit vectors y⁰, z⁰.
    pub rest_section: [[f64; 3]; 2],
}

impl SpringAt {
    /// The support `support` of `spring` at `node`, relaxed at the node's
    /// coordinates `start` (its twelve).
    pub fn new(support: usize, node: usize, spring: Spring, start: &[f64]) -> Self {
        let rest = [start[0], start[1], start[2]];
        let unit = |k: usize| {
            let v = [start[k], start[k + 1], start[k + 2]];
            let n = norm(v);
            v.map(|x| x / n)
        };
        SpringAt {
            support,
            node,
            spring,
            rest,
            rest_tangent: unit(3),
            rest_section: [unit(6), unit(9)],
        }
    }

    /// The first of the node's coordinates in the model's vectors.
    pub fn first_coordinate(&self) -> usize {
        NODE_DOFS * self.node
    }

    fn position(&self, q: &[f64]) -> [f64; 3] {
        let b = self.first_coordinate();
        [q[b], q[b + 1], q[b + 2]]
    }

    fn gradient(&self, q: &[f64]) -> [f64; 3] {
        let b = self.first_coordinate() + 3;
        [q[b], q[b + 1], q[b + 2]]
    }

    /// The torsional spring's a = ∂s/∂(r_y, r_z) (six entries) and s at `q`.
    fn twist(&self, q: &[f64]) -> ([f64; 6], f64) {
        let b = self.first_coordinate();
        let [y0, z0] = self.rest_section;
        let a: [f64; 6] =
            std::array::from_fn(|i| if i < 3 { 0.5 * z0[i] } else { -0.5 * y0[i - 3] });
        let s = (0..6).map(|i| a[i] * q[b + 6 + i]).sum();
        (a, s)
    }

    /// The springs' energy at coordinates `q` (all of the model's), J.
    pub fn energy(&self, q: &[f64]) -> f64 {
        let r = self.position(q);
        let k = &self.spring.stiffness;
        let mut translation: f64 = (0..3)
            .map(|i| 0.5 * k[i] * (r[i] - self.rest[i]).powi(2))
            .sum();
        if self.spring.torsional_stiffness != 0.0 {
            let (_, s) = self.twist(q);
            translation += 0.5 * self.spring.torsional_stiffness * s * s;
        }
        if self.spring.rotational_stiffness == 0.0 {
            return translation;
        }
        let rx = self.gradient(q);
        let n = norm(rx);
        let d: f64 = (0..3)
            .map(|i| (rx[i] / n - self.rest_tangent[i]).powi(2))
            .sum();
        translation + 0.5 * self.spring.rotational_stiffness * d
    }

    /// The rotational spring's t, n, c = t · t⁰ and w = t⁰ − c t at `q`.
    fn tangent_terms(&self, q: &[f64]) -> ([f64; 3], f64, f64, [f64; 3]) {
        let rx = self.gradient(q);
        let n = norm(rx);
        let t = rx.map(|x| x / n);
        let c = dot(t, self.rest_tangent);
        let w = std::array::from_fn(|i| self.rest_tangent[i] - c * t[i]);
        (t, n, c, w)
    }

    /// Adds the springs' generalized force ∂V/∂q (the internal-force sign
    /// convention: the body feels its negative) to `out`.
    pub fn add_force(&self, q: &[f64], out: &mut [f64]) {
        let base = self.first_coordinate();
        for (o, f) in out[base..base + 12].iter_mut().zip(self.node_force(q)) {
            *o += f;
        }
    }

    /// ∂V/∂q on the node's twelve coordinates (r, r_x, r_y, r_z).
    fn node_force(&self, q: &[f64]) -> [f64; 12] {
        let mut out = [0.0; 12];
        let r = self.position(q);
        for i in 0..3 {
            out[i] = self.spring.stiffness[i] * (r[i] - self.rest[i]);
        }
        let k = self.spring.rotational_stiffness;
        if k != 0.0 {
            let (_, n, _, w) = self.tangent_terms(q);
            for i in 0..3 {
                out[3 + i] = -k / n * w[i];
            }
        }
        let kt = self.spring.torsional_stiffness;
        if kt != 0.0 {
            let (a, s) = self.twist(q);
            for i in 0..6 {
                out[6 + i] = kt * s * a[i];
            }
        }
        out
    }

    /// ∂²V/∂(r_y, r_z)² (row-major 6 × 6): the torsional spring's constant
    /// stiffness k_t a aᵀ on the node's section gradients.
    pub fn torsional_jacobian(&self) -> [[f64; 6]; 6] {
        let kt = self.spring.torsional_stiffness;
        let [y0, z0] = self.rest_section;
        let a: [f64; 6] =
            std::array::from_fn(|i| if i < 3 { 0.5 * z0[i] } else { -0.5 * y0[i - 3] });
        std::array::from_fn(|i| std::array::from_fn(|j| kt * a[i] * a[j]))
    }

    /// ∂²V/∂r_x² (row-major 3 × 3) at `q`: the rotational spring's
    /// stiffness on the node's r_x (the translational one is K, constant).
    pub fn rotational_jacobian(&self, q: &[f64]) -> [[f64; 3]; 3] {
        let k = self.spring.rotational_stiffness;
        if k == 0.0 {
            return [[0.0; 3]; 3];
        }
        let (t, n, c, w) = self.tangent_terms(q);
        let s = k / (n * n);
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let p = if i == j { 1.0 } else { 0.0 } - t[i] * t[j];
                s * (c * p + t[i] * w[j] + w[i] * t[j])
            })
        })
    }

    /// Whether the support carries a moment: a rotational or a torsional
    /// spring.
    pub fn carries_moment(&self) -> bool {
        self.spring.rotational_stiffness != 0.0 || self.spring.torsional_stiffness != 0.0
    }

    /// The moment the rotational and torsional springs exert on the node
    /// (N m) at coordinates `q`: a rotation δθ of the node's triad moves
    /// each gradient r_i by δθ × r_i, so the moment of the generalized
    /// forces −∂V/∂r_i on them is Σ_i r_i × (−∂V/∂r_i).
    pub fn moment_on_body(&self, q: &[f64]) -> [f64; 3] {
        let base = self.first_coordinate();
        let local = self.node_force(q);
        let mut m = [0.0; 3];
        for i in 0..3 {
            let (at, l) = (base + 3 + 3 * i, 3 + 3 * i);
            let r = [q[at], q[at + 1], q[at + 2]];
            let f = [-local[l], -local[l + 1], -local[l + 2]];
            let c = crate::math::vec3::cross(r, f);
            m = std::array::from_fn(|k| m[k] + c[k]);
        }
        m
    }

    /// The force the support exerts on the node (N): −K (r − r⁰), less the
    /// dashpot's C ṙ when velocities `v` are given.
    pub fn force_on_body(&self, q: &[f64], v: Option<&[f64]>) -> [f64; 3] {
        let base = self.first_coordinate();
        let r = self.position(q);
        std::array::from_fn(|k| {
            let damping = v.map_or(0.0, |v| self.spring.damping * v[base + k]);
            -self.spring.stiffness[k] * (r[k] - self.rest[k]) - damping
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rotational spring's force and Jacobian are the derivatives of
    /// its energy, at a tangent turned 0.4 rad and stretched.
    #[test]
    fn rotational_spring_derivatives_match_differences() {
        let spring = Spring {
            stiffness: [0.0; 3],
            rotational_stiffness: 7.0,
            ..Default::default()
        };
        let mut start = [0.0; NODE_DOFS];
        start[3..6].copy_from_slice(&[0.6, 0.0, 0.8]);
        let s = SpringAt::new(0, 0, spring, &start);
        let mut q = start;
        q[3..6].copy_from_slice(&[0.9, 0.3, 0.4]);
        let h = 1e-6;
        let mut force = [0.0; NODE_DOFS];
        s.add_force(&q, &mut force);
        let jac = s.rotational_jacobian(&q);
        for j in 0..3 {
            let (mut up, mut down) = (q, q);
            up[3 + j] += h;
            down[3 + j] -= h;
            let de = (s.energy(&up) - s.energy(&down)) / (2.0 * h);
            assert!((de - force[3 + j]).abs() < 1e-8, "∂V/∂r_x[{j}]");
            let (mut fu, mut fd) = ([0.0; NODE_DOFS], [0.0; NODE_DOFS]);
            s.add_force(&up, &mut fu);
            s.add_force(&down, &mut fd);
            for i in 0..3 {
                let d = (fu[3 + i] - fd[3 + i]) / (2.0 * h);
                assert!((d - jac[i][j]).abs() < 1e-7, "∂²V/∂r_x[{i}]∂r_x[{j}]");
            }
        }
        // Small rotations: ½ k_θ θ².
        let theta: f64 = 1e-3;
        let (c, sn) = (theta.cos(), theta.sin());
        q[3..6].copy_from_slice(&[0.6 * c - 0.8 * sn, 0.0, 0.6 * sn + 0.8 * c]);
        assert!((s.energy(&q) / (0.5 * 7.0 * theta * theta) - 1.0).abs() < 1e-6);
    }

    /// The torsional spring: ½ k_t sin² φ for a twist φ, nothing for a
    /// bend of the tangent or a stretch of the section; its force and
    /// Jacobian are its energy's derivatives.
    #[test]
    fn torsional_spring_holds_the_twist_only() {
        let kt = 11.0;
        let spring = Spring {
            torsional_stiffness: kt,
            ..Default::default()
        };
        let mut start = [0.0; NODE_DOFS];
        start[3..12].copy_from_slice(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let s = SpringAt::new(0, 0, spring, &start);
        let phi: f64 = 0.3;
        let mut q = start;
        q[6..12].copy_from_slice(&[0.0, phi.cos(), phi.sin(), 0.0, -phi.sin(), phi.cos()]);
        assert!((s.energy(&q) - 0.5 * kt * phi.sin().powi(2)).abs() < 1e-14);
        // A bend about y (the tangent and r_z turn) and a stretched section.
        let mut bent = start;
        let b: f64 = 0.2;
        bent[3..6].copy_from_slice(&[b.cos(), 0.0, -b.sin()]);
        bent[6..12].copy_from_slice(&[0.0, 1.1, 0.0, b.sin(), 0.0, 0.9 * b.cos()]);
        assert!(s.energy(&bent).abs() < 1e-14);
        let h = 1e-6;
        let mut twisted = q;
        twisted[7] += 0.05;
        twisted[9] -= 0.02;
        let mut force = [0.0; NODE_DOFS];
        s.add_force(&twisted, &mut force);
        let jac = s.torsional_jacobian();
        for j in 0..6 {
            let (mut up, mut down) = (twisted, twisted);
            up[6 + j] += h;
            down[6 + j] -= h;
            let de = (s.energy(&up) - s.energy(&down)) / (2.0 * h);
            assert!((de - force[6 + j]).abs() < 1e-8, "∂V/∂q[{j}]");
            let (mut fu, mut fd) = ([0.0; NODE_DOFS], [0.0; NODE_DOFS]);
            s.add_force(&up, &mut fu);
            s.add_force(&down, &mut fd);
            for i in 0..6 {
                let d = (fu[6 + i] - fd[6 + i]) / (2.0 * h);
                assert!((d - jac[i][j]).abs() < 1e-7, "∂²V/∂q[{i}]∂q[{j}]");
            }
        }
    }
}
