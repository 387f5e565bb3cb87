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
    ElementIntegration, ElementMatrix, ElementVector, deformation_gradient, strain_matrix,
};
use crate::forces::assembly::{lanes, per_element_in_halves};
use crate::linalg::pattern::Pattern;
use crate::material::{Law, tensor_from_stress};
use crate::model::{ElementGroup, Model, NODE_DOFS};
use nalgebra::{SMatrix, Vector6};
use std::ops::Range;

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
/// (`PreIntegrated::strain_rate_force`),
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
    let mut power = 0.0;
    if let Some(pre) = &ei.plan.preintegrated {
        let (nodes, weights) = (&ei.axial.nodes, &ei.axial.weights);
        power += pre.strain_rate_force(
            nodes,
            weights,
            ei.length,
            c,
            e,
            v,
            q,
            kq.as_deref_mut(),
            kv.as_deref_mut(),
        );
    }
    power + kelvin_voigt_point_laws(ei, c, e, v, q, kq, kv)
}

/// The part of [`kelvin_voigt_element`] that the plan integrates point by
/// point (its groups of section points and non-linear centerline laws).
fn kelvin_voigt_point_laws(
    ei: &ElementIntegration,
    c: f64,
    e: &ElementVector,
    v: &ElementVector,
    q: &mut ElementVector,
    mut kq: Option<&mut ElementMatrix>,
    mut kv: Option<&mut ElementMatrix>,
) -> f64 {
    let mut power = 0.0;
    ei.for_each_plan_point(&ei.axial.nodes, &ei.axial.weights, |g, w, law| {
        power += kelvin_voigt_point(e, v, g, w, law, c, q, kq.as_deref_mut(), kv.as_deref_mut());
    });
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

/// Kelvin–Voigt force of the model at (q, v) on the unknowns (N) and its
/// power (W), each group with its coefficient `c[group]` (s; `None`:
/// undamped, not evaluated); adds ∂Q_d/∂q to `kq` and ∂Q_d/∂v to `kv`
/// (pattern slots). Allocates its result and workspace: a solver calls
/// [`kelvin_voigt_force_into`] with buffers it keeps.
pub fn kelvin_voigt_force(
    model: &Model,
    pattern: &Pattern,
    c: &[Option<f64>],
    q: &[f64],
    v: &[f64],
    kq: Option<&mut [f64]>,
    kv: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    let mut force = vec![0.0; model.n_unknowns];
    let mut work = KelvinVoigtWork::default();
    let power = kelvin_voigt_force_into(model, pattern, c, (q, v), (kq, kv), &mut work, &mut force);
    (force, power)
}

/// The buffers of [`kelvin_voigt_force_into`], sized at its first call:
/// each element's force and power, and the force on all coordinates.
#[derive(Clone, Debug, Default)]
pub struct KelvinVoigtWork {
    per: Vec<(ElementVector, f64)>,
    full: Vec<f64>,
}

/// [`kelvin_voigt_force`] added to `force` (unknowns, N), with the
/// buffers in `work`; returns the power (W). The force alone goes as the
/// elastic force does (`force_alone`); with Jacobians, one element at a
/// time.
pub fn kelvin_voigt_force_into(
    model: &Model,
    pattern: &Pattern,
    c: &[Option<f64>],
    (q, v): (&[f64], &[f64]),
    (mut kq, mut kv): (Option<&mut [f64]>, Option<&mut [f64]>),
    work: &mut KelvinVoigtWork,
    force: &mut [f64],
) -> f64 {
    work.full.clear();
    work.full.resize(q.len(), 0.0);
    let power = if kq.is_none() && kv.is_none() {
        force_alone(model, c, (q, v), work)
    } else {
        let mut power = 0.0;
        let (mut mq, mut mv) = ([0.0; 576], [0.0; 576]);
        for (group, c) in model.groups.iter().zip(c) {
            let Some(c) = *c else { continue };
            for el in group.elements.clone() {
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
                    &group.integration,
                    c,
                    &e,
                    &ve,
                    &mut qe,
                    kq.is_some().then_some(&mut mq),
                    kv.is_some().then_some(&mut mv),
                );
                add_element(&mut work.full, el, &qe);
                if let Some(k) = kq.as_deref_mut() {
                    pattern.add_element(k, el, &mq);
                }
                if let Some(k) = kv.as_deref_mut() {
                    pattern.add_element(k, el, &mv);
                }
            }
        }
        power
    };
    model.gather_add(&work.full, force);
    power
}

/// Adds element `el`'s force `qe` to the all-coordinates vector `full`.
fn add_element(full: &mut [f64], el: usize, qe: &ElementVector) {
    let rows = &mut full[NODE_DOFS * el..NODE_DOFS * el + 24];
    rows.iter_mut().zip(qe).for_each(|(f, x)| *f += x);
}

/// The damping force alone into `work.full` (all coordinates, cleared by
/// the caller): each element's force and power, the pre-integrated laws
/// eight elements at a time (SIMD lanes), a long group in two halves on
/// two threads as the elastic energy goes ([`per_element_in_halves`]),
/// then added up in element order — the same bits on any number of
/// threads. Returns the power (W).
fn force_alone(
    model: &Model,
    c: &[Option<f64>],
    (q, v): (&[f64], &[f64]),
    work: &mut KelvinVoigtWork,
) -> f64 {
    // Written for the damped groups' elements at every call; the others
    // (undamped groups, gaps) stay zero from here.
    if work.per.len() != model.n_elements {
        work.per = vec![([0.0; 24], 0.0); model.n_elements];
    }
    per_element_in_halves(model, &mut work.per, |group, els, out| {
        if let Some(c) = c[model.group(group.elements.start)] {
            group_forces(model, group, c, (q, v), els, out)
        }
    });
    let mut power = 0.0;
    for (el, (force, p)) in work.per.iter().enumerate() {
        power += p;
        add_element(&mut work.full, el, force);
    }
    power
}

/// The damping forces and powers of `group`'s elements `els` at
/// (q, v) into `out` (one per element).
fn group_forces(
    model: &Model,
    group: &ElementGroup,
    c: f64,
    (q, v): (&[f64], &[f64]),
    els: Range<usize>,
    out: &mut [(ElementVector, f64)],
) {
    let ei = &group.integration;
    let mut first = els.start;
    if let Some(pre) = &ei.plan.preintegrated {
        let (nodes, weights) = (&ei.axial.nodes, &ei.axial.weights);
        while first + 8 <= els.end {
            let (e8, v8) = (lanes::<8>(model, q, first), lanes::<8>(model, v, first));
            let mut q8 = [[0.0; 8]; 24];
            let p8 = pre.strain_rate_forces_8(nodes, weights, ei.length, c, &e8, &v8, &mut q8);
            for (k, p) in p8.iter().enumerate() {
                let el = first + k;
                let mut force: ElementVector = std::array::from_fn(|i| q8[i][k]);
                let mut power = *p;
                if ei.plan.points() > 0 {
                    let e = model.element_coordinates(q, el);
                    let ve = model.element_coordinates(v, el);
                    power += kelvin_voigt_point_laws(ei, c, &e, &ve, &mut force, None, None);
                }
                out[el - els.start] = (force, power);
            }
            first += 8;
        }
    }
    for el in first..els.end {
        let e = model.element_coordinates(q, el);
        let ve = model.element_coordinates(v, el);
        let mut force = [0.0; 24];
        let power = kelvin_voigt_element(ei, c, &e, &ve, &mut force, None, None);
        out[el - els.start] = (force, power);
    }
}
