//! Kelvin–Voigt damping of the pre-integrated linear laws (SPEC §6).
//!
//! The strain-rate stress σ_v = c D Ė of a linear law D is the elastic
//! stress of the strain c Ė. Ė is linear in the Gram rates
//! ẋ_ij = u̇_i · u_j + u_i · u̇_j exactly as E is in x = u_i · u_j (with no
//! constant part), so over the section the damping force is the elastic
//! force's map applied to the strain moments c J ẋ: the same M, no section
//! points. Point by point the same force costs a 6 × 24 strain matrix and
//! its products at every section point (`forces::damping`), about twenty
//! times more (BENCHMARKS.md).
//!
//! Jacobians, in the five vectors u (u̇ = T v with the same T):
//! * ∂Q/∂v = c Gᵀ A G, the elastic Hessian's material part (G = ∂x/∂u);
//! * ∂Q/∂q = Σ_g s_g ∂²x_g/∂u² + c Gᵀ A G(u̇), the geometric part of the
//!   damping stress s = c A ẋ, and the material part with its right factor
//!   taken at u̇ (∂ẋ/∂u = G(u̇), G being linear): not symmetric.

use super::{
    GRAM_PAIRS, Lanes, NODE_BLOCKS, PreIntegrated, STRAIN_MOMENT_OF_GRAM, STRAIN_MOMENTS, T_VECTOR,
    add_force, add_force_lanes, m_times_lanes, t_coefficients, vectors, vectors_lanes,
};
use crate::element::{ElementMatrix, ElementVector};
use crate::math::simd::Arith;
use nalgebra::Vector3;

/// The 3 × 3 blocks (index 5 i + j, row-major) Σ coef L_l R_rᵀ of the
/// material Hessian's terms, with the left factor from `left` and the right
/// from `right`; a block below the diagonal takes the terms of its mirror
/// (j, i) with the roles of l and r exchanged. With `left` = `right` this is
/// the (symmetric) material part of the elastic Hessian.
fn material_blocks(
    pre: &PreIntegrated,
    left: &[Vector3<f64>; 5],
    right: &[Vector3<f64>; 5],
    scale: f64,
) -> [[f64; 9]; 25] {
    let mut h = [[0.0f64; 9]; 25];
    for (g, &(i, j)) in GRAM_PAIRS.iter().enumerate() {
        let (start, end) = pre.hessian_ranges[g];
        let terms = &pre.hessian_terms[start..end];
        let outer = |acc: &mut [f64; 9], a: &Vector3<f64>, b: &Vector3<f64>, coef: f64| {
            for r in 0..3 {
                for c in 0..3 {
                    acc[3 * r + c] += scale * coef * a[r] * b[c];
                }
            }
        };
        for &(l, r, coef) in terms {
            outer(&mut h[5 * i + j], &left[l], &right[r], coef);
            if i != j {
                outer(&mut h[5 * j + i], &left[r], &right[l], coef);
            }
        }
    }
    h
}

/// What one station of the damping force leaves for its Jacobians.
struct RateStation {
    tc: [f64; 12],
    u: [Vector3<f64>; 5],
    ud: [Vector3<f64>; 5],
    /// ∂W/∂x-like coefficients of the damping stress (S_ii = 2σ_ii, S_ij = σ_ij).
    s: [f64; 15],
}

impl PreIntegrated {
    /// One station ξ with weight `wx` (m): adds the damping force to `q`,
    /// returns its power (W) and what the Jacobians need.
    #[allow(clippy::too_many_arguments)]
    fn rate_station(
        &self,
        xi: f64,
        l: f64,
        wx: f64,
        c: f64,
        e: &ElementVector,
        v: &ElementVector,
        q: &mut ElementVector,
    ) -> (f64, RateStation) {
        let tc = t_coefficients(xi, l);
        let (u, ud) = (vectors(&tc, e), vectors(&tc, v));
        // The strain moments' rates J ẋ (J: one coefficient per row).
        let rate: [f64; 15] = unrolled!(r in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
            let (g, coef) = STRAIN_MOMENTS[r];
            let (i, j) = GRAM_PAIRS[g];
            coef * (ud[i].dot(&u[j]) + u[i].dot(&ud[j]))
        });
        let mr = self.m_times(&rate);
        let power: f64 = rate.iter().zip(&mr).map(|(a, b)| a * b).sum();
        // S_ii = 2σ_ii, S_ij = σ_ij of the damping stress σ = c Jᵀ M J ẋ.
        let s: [f64; 15] = unrolled!(g in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
            let r = STRAIN_MOMENT_OF_GRAM[g];
            let (i, j) = GRAM_PAIRS[g];
            let coef = STRAIN_MOMENTS[r].1;
            if i == j { 2.0 * c * coef * mr[r] } else { c * coef * mr[r] }
        });
        add_force(&tc, wx, &u, &s, q);
        (wx * c * power, RateStation { tc, u, ud, s })
    }

    /// Kelvin–Voigt force (N) of the pre-integrated laws with coefficient
    /// `c` (s) at coordinates `e` and velocities `v`, over the axial rule
    /// (`nodes` ξ ∈ [0, 1], `weights` summing to 1) of an element of length
    /// `l` (m), added to `q`; with `kq` and `kv`, ∂Q/∂q and ∂Q/∂v added
    /// (row-major 24 × 24). Returns the dissipated power Q · v (W).
    #[allow(clippy::too_many_arguments)]
    pub fn strain_rate_force(
        &self,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        c: f64,
        e: &ElementVector,
        v: &ElementVector,
        q: &mut ElementVector,
        mut kq: Option<&mut ElementMatrix>,
        mut kv: Option<&mut ElementMatrix>,
    ) -> f64 {
        let mut power = 0.0;
        for (xi, w) in nodes.iter().zip(weights) {
            let wx = w * l;
            let (p, st) = self.rate_station(*xi, l, wx, c, e, v, q);
            power += p;
            if let Some(kv) = kv.as_deref_mut() {
                let h = material_blocks(self, &st.u, &st.u, c);
                add_node_blocks(&h, &st.tc, wx, kv);
            }
            if let Some(kq) = kq.as_deref_mut() {
                let mut h = material_blocks(self, &st.u, &st.ud, c);
                for (g, &(i, j)) in GRAM_PAIRS.iter().enumerate() {
                    for d in [0, 4, 8] {
                        h[5 * i + j][d] += st.s[g];
                        if i != j {
                            h[5 * j + i][d] += st.s[g];
                        }
                    }
                }
                add_node_blocks(&h, &st.tc, wx, kq);
            }
        }
        power
    }

    /// [`PreIntegrated::strain_rate_force`] without Jacobians for eight
    /// elements of length `l` given by lanes (`e[i][k]`, `v[i][k]`:
    /// coordinate i of element k), on the CPU's SIMD path; their forces are
    /// added to `q`, their powers (W) returned.
    #[allow(clippy::too_many_arguments)]
    pub fn strain_rate_forces_8(
        &self,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        c: f64,
        e: &[[f64; 8]; 24],
        v: &[[f64; 8]; 24],
        q: &mut [[f64; 8]; 24],
    ) -> [f64; 8] {
        strain_rate_8(
            crate::math::simd::path(),
            self,
            nodes,
            weights,
            l,
            c,
            e,
            v,
            q,
        )
    }
}

/// k += wx Tᵀ H T for the blocks H of one station (all 25; H need not be
/// symmetric): node block (a, b) sums T_p1 T_p2 H(v(p1), v(p2)) over T's
/// entries p1 at node a and p2 at node b.
fn add_node_blocks(h: &[[f64; 9]; 25], tc: &[f64; 12], wx: f64, k: &mut ElementMatrix) {
    for blk in &NODE_BLOCKS {
        let (a, b) = (blk.a, blk.b);
        let (mut upper, mut lower) = ([0.0f64; 9], [0.0f64; 9]);
        for &(p1, p2, _) in &blk.terms[..blk.len] {
            let w = wx * tc[p1] * tc[p2];
            let (v1, v2) = (T_VECTOR[p1], T_VECTOR[p2]);
            for x in 0..9 {
                upper[x] += w * h[5 * v1 + v2][x];
                lower[x] += w * h[5 * v2 + v1][x];
            }
        }
        for r in 0..3 {
            for c in 0..3 {
                k[(3 * a + r) * 24 + 3 * b + c] += upper[3 * r + c];
                if a != b {
                    k[(3 * b + r) * 24 + 3 * a + c] += lower[3 * r + c];
                }
            }
        }
    }
}

/// [`PreIntegrated::strain_rate_force`] without Jacobians for W elements at
/// once (`e[i]`, `v[i]`: coordinate i of each element), lane by lane as the
/// elastic force kernel runs them; returns each element's power (W).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn strain_rate_lanes<F: Arith, const W: usize>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    c: f64,
    e: &[[f64; W]; 24],
    v: &[[f64; W]; 24],
    q: &mut [[f64; W]; 24],
) -> [f64; W] {
    let mut el = [Lanes([0.0; W]); 24];
    let mut vl = [Lanes([0.0; W]); 24];
    let mut ql = [Lanes([0.0; W]); 24];
    for i in 0..24 {
        (el[i], vl[i], ql[i]) = (Lanes(e[i]), Lanes(v[i]), Lanes(q[i]));
    }
    let mut power = Lanes::<W>::splat(0.0);
    for (&xi, &w) in nodes.iter().zip(weights) {
        let (tc, wx) = (t_coefficients(xi, l), w * l);
        let (u, ud) = (
            vectors_lanes::<F, W>(&tc, &el),
            vectors_lanes::<F, W>(&tc, &vl),
        );
        let dot = |a: &[Lanes<W>; 3], b: &[Lanes<W>; 3]| {
            a[2].mul_add::<F>(b[2], a[1].mul_add::<F>(b[1], a[0] * b[0]))
        };
        let rate: [Lanes<W>; 15] = unrolled!(r in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
            let (g, coef) = STRAIN_MOMENTS[r];
            let (i, j) = GRAM_PAIRS[g];
            (dot(&ud[i], &u[j]) + dot(&u[i], &ud[j])) * coef
        });
        let mr = m_times_lanes::<F, W>(pre, &rate);
        let mut p = Lanes::<W>::splat(0.0);
        for r in 0..15 {
            p = rate[r].mul_add::<F>(mr[r], p);
        }
        power = p.mul_add_s::<F>(wx * c, power);
        let s: [Lanes<W>; 15] = unrolled!(g in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
            let r = STRAIN_MOMENT_OF_GRAM[g];
            let (i, j) = GRAM_PAIRS[g];
            mr[r] * (if i == j { 2.0 } else { 1.0 } * c * STRAIN_MOMENTS[r].1)
        });
        add_force_lanes::<F, W>(&tc, wx, &u, &s, &mut ql);
    }
    for (qi, x) in q.iter_mut().zip(&ql) {
        *qi = x.0;
    }
    power.0
}

/// [`strain_rate_lanes`] with eight lanes (one AVX-512 register).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn strain_rate_8_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    c: f64,
    e: &[[f64; 8]; 24],
    v: &[[f64; 8]; 24],
    q: &mut [[f64; 8]; 24],
) -> [f64; 8] {
    strain_rate_lanes::<F, 8>(pre, nodes, weights, l, c, e, v, q)
}

crate::simd_dispatch! {
    /// Kelvin–Voigt forces (added to `q`) and powers of eight elements
    /// given by lanes (`e[i][k]`: coordinate i of element k).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn strain_rate_8(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        c: f64,
        e: &[[f64; 8]; 24],
        v: &[[f64; 8]; 24],
        q: &mut [[f64; 8]; 24],
    ) -> [f64; 8] = strain_rate_8_with;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementIntegration;
    use crate::material::Material;
    use crate::math::simd::SimdPath;
    use crate::section::Section;

    /// The eight-lane kernel gives each element the force and power of
    /// the scalar station form, on every path this CPU has (to round-off:
    /// the two forms order their sums differently).
    #[test]
    fn lane_kernel_equals_the_scalar_form_on_every_path() {
        let (l, c) = (0.05, 1e-4);
        let section = Section::circular(
            &[
                (
                    0.0,
                    0.005,
                    Material::st_venant_kirchhoff(6000.0, 1.5e11, 0.0, 0.1),
                ),
                (
                    0.005,
                    0.014,
                    Material::st_venant_kirchhoff(2000.0, 5e10, 0.3, 0.1),
                ),
            ],
            3,
        );
        let ei = ElementIntegration::new(l, 3, section);
        let pre = ei.plan.preintegrated.as_ref().expect("linear laws");
        let (nodes, weights) = (&ei.axial.nodes, &ei.axial.weights);
        let mut seed = 1u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // Eight elements along x, each bent and stretched a little, moving.
        let mut e = [[0.0; 8]; 24];
        let mut v = [[0.0; 8]; 24];
        for k in 0..8 {
            let reference = crate::element::reference_coordinates(
                [k as f64 * l, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                l,
            );
            for i in 0..24 {
                e[i][k] = reference[i] + 0.05 * uniform() * if (i / 3) % 4 == 0 { l } else { 1.0 };
                v[i][k] = uniform();
            }
        }
        for path in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
            let mut q8 = [[0.0; 8]; 24];
            let p8 = strain_rate_8(path, pre, nodes, weights, l, c, &e, &v, &mut q8);
            for k in 0..8 {
                let (ek, vk) = (
                    std::array::from_fn(|i| e[i][k]),
                    std::array::from_fn(|i| v[i][k]),
                );
                let mut q = [0.0; 24];
                let p = pre.strain_rate_force(nodes, weights, l, c, &ek, &vk, &mut q, None, None);
                let scale = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                assert!(
                    p > 0.0 && (p8[k] - p).abs() <= 1e-12 * p,
                    "{}: power",
                    path.name()
                );
                for i in 0..24 {
                    assert!(
                        (q8[i][k] - q[i]).abs() <= 1e-12 * scale,
                        "{}: element {k}, coordinate {i}: {} against {}",
                        path.name(),
                        q8[i][k],
                        q[i]
                    );
                }
            }
        }
    }
}
