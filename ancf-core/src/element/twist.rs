//! Saint-Venant torsion for sections that warp: a rectangle's twist.
//!
//! The element's section field is linear in (y, z), so a twisted section
//! cannot warp, and a twist rate θ' meets the shear stiffness G I_p
//! instead of Saint-Venant's G J (I_p / J = 1.19 for a square, 2.7 for a
//! 4 : 1 strip). A twist makes the shear strains vary across the section
//! as 2E_xz = y (a · r_z) and 2E_xy = z (b · r_y), a = ∂r_y/∂x, b =
//! ∂r_z/∂x: their energy over the section is ½ G (∫y² s² + ∫z² t²), s =
//! a · r_z, t = b · r_y. Adding ½ G (J / I_p − 1)(∫y² s² + ∫z² t²) at each
//! axial point turns it into ½ G J θ'² and leaves axial strain, bending
//! and transverse shear, whose strains do not vary so, as they are — the
//! torsion correction of the shear terms (the choice over an enhanced
//! warping field: exact for Saint-Venant torsion with no new unknowns).
//! Circles and rings do not warp (J = I_p) and get none.

use crate::element::{ElementMatrix, ElementVector};
use crate::math::vec3::dot;
use crate::section::{Section, SectionShape, saint_venant_torsion};

/// G (J / I_p − 1) ∫y² and ∫z² (N m²) of a rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistCorrection {
    yy: f64,
    zz: f64,
}

/// r_y at node 1 and 2, r_z at node 1 and 2: their first coordinate.
const RY: [usize; 2] = [6, 18];
const RZ: [usize; 2] = [9, 21];

impl TwistCorrection {
    /// The correction of a rectangle of one layer (`None` for circles and
    /// rings, which do not warp).
    pub fn of(section: &Section) -> Option<Self> {
        let SectionShape::Rectangular { width, height } = section.shape else {
            return None;
        };
        // The shear modulus the section's law integrates (its D's xz entry;
        // a law that is not linear: the material's small-strain one).
        let layer = section.layers.first()?;
        let g = match &layer.laws.section {
            crate::material::Law::Linear(d) => d[(4, 4)],
            _ => layer.material.model.small_strain_shear_modulus(),
        };
        let (iyy, izz) = (height * width.powi(3) / 12.0, width * height.powi(3) / 12.0);
        let factor = saint_venant_torsion(width, height) / (iyy + izz) - 1.0;
        Some(TwistCorrection {
            yy: g * factor * iyy,
            zz: g * factor * izz,
        })
    }

    /// Its energy over an element of length `l` (m) with coordinates `e`
    /// by the axial rule (`nodes` ξ ∈ [0, 1], `weights` summing to 1): its
    /// force added to `q` and, with `k`, its Jacobian to `k`; returns the
    /// energy (J).
    pub fn add(
        &self,
        (nodes, weights, l): (&[f64], &[f64], f64),
        e: &ElementVector,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let v = |at: usize| -> [f64; 3] { [e[at], e[at + 1], e[at + 2]] };
        let (ry, rz) = (RY.map(v), RZ.map(v));
        let diff =
            |x: [[f64; 3]; 2]| -> [f64; 3] { std::array::from_fn(|i| (x[1][i] - x[0][i]) / l) };
        let (a, b) = (diff(ry), diff(rz));
        let mut energy = 0.0;
        for (xi, w) in nodes.iter().zip(weights) {
            let w = w * l;
            let mid = |x: [[f64; 3]; 2]| -> [f64; 3] {
                std::array::from_fn(|i| (1.0 - xi) * x[0][i] + xi * x[1][i])
            };
            let (ry_at, rz_at) = (mid(ry), mid(rz));
            // s = a · r_z(ξ) and t = b · r_y(ξ), and their gradients.
            // (Δ: −1/l, +1/l on the nodes' vector; the mix: 1 − ξ, ξ.)
            let delta = [-1.0 / l, 1.0 / l];
            let mix = [1.0 - xi, *xi];
            // s: a = Δ r_y with r_z mixed; t: b = Δ r_z with r_y mixed.
            for (coef, (diffs, mixes), (grad_d, grad_m)) in [
                (self.yy, (RY, RZ), (rz_at, a)),
                (self.zz, (RZ, RY), (ry_at, b)),
            ] {
                let value = dot(grad_m, grad_d);
                energy += 0.5 * w * coef * value * value;
                // ∂value/∂e: Δ_n grad_d on the differenced vectors, mix_n grad_m on the mixed.
                let mut grad = [0.0; 24];
                for n in 0..2 {
                    for c in 0..3 {
                        grad[diffs[n] + c] += delta[n] * grad_d[c];
                        grad[mixes[n] + c] += mix[n] * grad_m[c];
                    }
                }
                for (qi, gi) in q.iter_mut().zip(&grad) {
                    *qi += w * coef * value * gi;
                }
                if let Some(k) = k.as_deref_mut() {
                    for i in 0..24 {
                        if grad[i] == 0.0 {
                            continue;
                        }
                        for j in 0..24 {
                            k[24 * i + j] += w * coef * grad[i] * grad[j];
                        }
                    }
                    // value ∂²value: Δ_n mix_m I between the differenced and the mixed vectors.
                    for n in 0..2 {
                        for m in 0..2 {
                            let h = w * coef * value * delta[n] * mix[m];
                            for c in 0..3 {
                                k[24 * (diffs[n] + c) + mixes[m] + c] += h;
                                k[24 * (mixes[m] + c) + diffs[n] + c] += h;
                            }
                        }
                    }
                }
            }
        }
        energy
    }
}
