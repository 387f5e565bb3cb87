//! Structural damping, an effect only when a scene names it (SPEC §6).
//!
//! * Kelvin–Voigt: the stress gains a strain-rate term σ_v = c D₀ Ė with
//!   Ė = sym(Fᵀ Ḟ) (in Voigt form Ė = B(q) ė), c in seconds and D₀ the law's
//!   small-strain tangent. Its force depends on q and v; both Jacobians are
//!   returned (the q-Jacobian is not symmetric, so the Newton matrix is
//!   then factored by LU).
//! * Rayleigh: Q_d = (α M + β K₀) v with K₀ the stiffness at the reference
//!   (assembled once by the integrator).
//!
//! The dissipated power Q_d · v ≥ 0 is integrated into the energy balance.

use crate::element::{
    ElementIntegration, ElementMatrix, ElementVector, deformation_gradient, shape_gradients,
    strain_matrix,
};
use crate::linalg::pattern::Pattern;
use crate::material::{Law, tensor_from_stress};
use crate::model::{Model, NODE_DOFS};
use nalgebra::{SMatrix, Vector6};

/// One point of the Kelvin–Voigt force: adds w Bᵀσ_v to `q`, ∂/∂q to `kq`,
/// ∂/∂v to `kv`; returns the dissipated power w σ_v · Ė (W).
#[allow(clippy::too_many_arguments)]
fn kelvin_voigt_point(
    e: &ElementVector,
    v: &ElementVector,
    g: &[[f64; 3]; 8],
    w: f64,
    law: &Law,
    c: f64,
    q: &mut ElementVector,
    kq: Option<&mut ElementMatrix>,
    kv: Option<&mut ElementMatrix>,
) -> f64 {
    let f = deformation_gradient(e, g);
    let fdot = deformation_gradient(v, g);
    let b = strain_matrix(&f, g);
    let ve = SMatrix::<f64, 24, 1>::from_column_slice(v);
    let rate: Vector6<f64> = b * ve;
    let d0 = law.stress_tangent(&Vector6::zeros()).tangent * c;
    let sigma = d0 * rate;
    let force = b.transpose() * sigma;
    for i in 0..24 {
        q[i] += w * force[i];
    }
    if let Some(kv) = kv {
        let m = b.transpose() * d0 * b;
        for r in 0..24 {
            for col in 0..24 {
                kv[r * 24 + col] += w * m[(r, col)];
            }
        }
    }
    if let Some(kq) = kq {
        let bt = strain_matrix(&fdot, g);
        let m = b.transpose() * d0 * bt;
        let s = tensor_from_stress(&sigma);
        for r in 0..24 {
            for col in 0..24 {
                let (i, k, j, mm) = (r / 3, r % 3, col / 3, col % 3);
                let mut val = m[(r, col)];
                if k == mm {
                    for a in 0..3 {
                        for bb in 0..3 {
                            val += g[i][a] * s[(a, bb)] * g[j][bb];
                        }
                    }
                }
                kq[r * 24 + col] += w * val;
            }
        }
    }
    w * sigma.dot(&rate)
}

/// Kelvin–Voigt force of one element with coordinates `e` and velocities
/// `v`, over the same laws as its elastic force and as its plan integrates
/// them: the pre-integrated linear laws in closed form over the section
/// ([`crate::element::preintegration::PreIntegrated::strain_rate_force`]),
/// the others point by point.
pub fn kelvin_voigt_element(
    ei: &ElementIntegration,
    c: f64,
    e: &ElementVector,
    v: &ElementVector,
    q: &mut ElementVector,
    mut kq: Option<&mut ElementMatrix>,
    mut kv: Option<&mut ElementMatrix>,
) -> f64 {
    let (l, plan) = (ei.length, &ei.plan);
    let (nodes, weights) = (&ei.axial.nodes, &ei.axial.weights);
    let mut power = 0.0;
    if let Some(pre) = &plan.preintegrated {
        power += pre.strain_rate_force(
            nodes,
            weights,
            l,
            c,
            e,
            v,
            q,
            kq.as_deref_mut(),
            kv.as_deref_mut(),
        );
    }
    for (xi, w) in nodes.iter().zip(weights) {
        let wx = w * l;
        for group in &plan.groups {
            for p in &group.points {
                let g = shape_gradients(*xi, p.y, p.z, l);
                power += kelvin_voigt_point(
                    e,
                    v,
                    &g,
                    wx * p.weight,
                    &group.law,
                    c,
                    q,
                    kq.as_deref_mut(),
                    kv.as_deref_mut(),
                );
            }
        }
        for (law, area) in &plan.centerline {
            let g = shape_gradients(*xi, 0.0, 0.0, l);
            power += kelvin_voigt_point(
                e,
                v,
                &g,
                wx * area,
                law,
                c,
                q,
                kq.as_deref_mut(),
                kv.as_deref_mut(),
            );
        }
    }
    power
}

/// [`kelvin_voigt_element`] point by point over every layer's own section
/// rule and centerline, as the law is stated: the reference the
/// pre-integrated path is tested against.
pub fn kelvin_voigt_points(
    ei: &ElementIntegration,
    c: f64,
    e: &ElementVector,
    v: &ElementVector,
    q: &mut ElementVector,
    mut kq: Option<&mut ElementMatrix>,
    mut kv: Option<&mut ElementMatrix>,
) -> f64 {
    let mut power = 0.0;
    ei.for_each_point(|g, w, law| {
        power += kelvin_voigt_point(e, v, g, w, law, c, q, kq.as_deref_mut(), kv.as_deref_mut());
    });
    power
}

/// Kelvin–Voigt force of the whole wire at (q, v) on the unknowns (N) and
/// its power (W); adds ∂Q_d/∂q to `kq` and ∂Q_d/∂v to `kv` (pattern slots).
pub fn kelvin_voigt_force(
    model: &Model,
    pattern: &Pattern,
    c: f64,
    q: &[f64],
    v: &[f64],
    mut kq: Option<&mut [f64]>,
    mut kv: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    let mut full = vec![0.0; q.len()];
    let mut power = 0.0;
    let (mut mq, mut mv) = ([0.0; 576], [0.0; 576]);
    for el in (0..model.n_elements).filter(|&el| !model.is_gap(el)) {
        let e = model.element_coordinates(q, el);
        let ve = model.element_coordinates(v, el);
        let mut qe = [0.0; 24];
        if kq.is_some() {
            mq.fill(0.0);
        }
        if kv.is_some() {
            mv.fill(0.0);
        }
        power += kelvin_voigt_element(
            model.element(el),
            c,
            &e,
            &ve,
            &mut qe,
            kq.is_some().then_some(&mut mq),
            kv.is_some().then_some(&mut mv),
        );
        for i in 0..24 {
            full[NODE_DOFS * el + i] += qe[i];
        }
        if let Some(k) = kq.as_deref_mut() {
            pattern.add_element(k, el, &mq);
        }
        if let Some(k) = kv.as_deref_mut() {
            pattern.add_element(k, el, &mv);
        }
    }
    (model.gather(&full), power)
}
