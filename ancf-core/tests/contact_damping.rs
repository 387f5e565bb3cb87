//! Contact damping with a coefficient of restitution. A straight
//! wire dropped flat onto a parallel rod, without gravity, moves as one
//! body: every point has the same penetration δ and rate δ̇, so the line
//! law's force is μ_L-independent Hunt–Crossley, F = K δ (1 + χ δ̇), on a
//! single degree of freedom. Its equation m δ̇ dδ̇/dδ = −K δ (1 + χ δ̇)
//! integrates in closed form between touch and release (both at δ = 0):
//!
//!   χ v⁻ − ln(1 + χ v⁻) = −χ v⁺ − ln(1 − χ v⁺),
//!
//! whatever m, K and the power of δ. With χ = c(e)/v⁻ the rebound ratio
//! v⁺/v⁻ is therefore a number of c alone; the simulation must give it.

use std::sync::Arc;

use ancf_core::material::Material;
use ancf_core::model::contact::{ContactDamping, RestitutionModel, Rod, hunt_crossley_rebound};
use ancf_core::model::{Model, WireBuilder};
use ancf_core::solve::dynamics::{DynamicSettings, Integrator, State};

const RW: f64 = 0.01;
const RR: f64 = 0.02;
const V0: f64 = 1.0;

/// A 1 m steel wire in two elements along x, 1 mm above an infinite rod
/// parallel to it, with line stiffness `eps_l` (N/m²) and `damping`.
fn wire_over_rod(eps_l: f64, damping: Option<(f64, RestitutionModel)>) -> Model {
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let mut rod = Rod::line([0.5, 0.0, -(RW + RR) - 1e-3], [1.0, 0.0, 0.0], RR, eps_l);
    if let Some((e, model)) = damping {
        rod = rod.with_restitution(e, model);
    }
    WireBuilder::new(1.0, 2)
        .layer(steel, RW)
        .rod(rod)
        .build()
        .unwrap()
}

/// Drop the wire at V0 and step until it has left the rod moving up;
/// returns the rebound ratio, the state and the integrator.
fn drop(model: Model, h: f64) -> (f64, State, Integrator) {
    let model = Arc::new(model);
    let settings = DynamicSettings {
        time_step: h,
        end_time: 1.0,
        spectral_radius: 1.0,
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut integrator = Integrator::new(Arc::clone(&model), settings).unwrap();
    let q0 = model.reference.clone();
    let mut v0 = vec![0.0; q0.len()];
    for n in 0..model.n_nodes() {
        v0[12 * n + 2] = -V0;
    }
    let mut s = integrator.initial_state(q0, v0).unwrap();
    let mut touched = false;
    for _ in 0..100_000 {
        let (next, info) = integrator.step(&s, h).unwrap();
        s = next;
        touched |= info.contact.active > 0;
        if touched && info.contact.active == 0 && s.v[2] > 0.0 {
            break;
        }
    }
    assert!(touched, "the wire must reach the rod");
    // One body: every node leaves at the same speed.
    for n in 0..model.n_nodes() {
        let vz = s.v[12 * n + 2];
        assert!(
            (vz - s.v[2]).abs() < 1e-9 * V0,
            "node {n} leaves at {vz}, node 0 at {}",
            s.v[2]
        );
    }
    (s.v[2] / V0, s, integrator)
}

/// K = 1e7 N/m² on 2.45 kg/m: the elastic contact lasts π √(m/K) ≈ 1.6 ms.
const EPS_L: f64 = 1e7;
const H: f64 = 1e-5;

const MODELS: [RestitutionModel; 3] = [
    RestitutionModel::Exact,
    RestitutionModel::Flores,
    RestitutionModel::LankaraniNikravesh,
];

#[test]
fn elastic_contact_returns_the_approach_speed() {
    // The kinks of the force at touch and release cost O((h/T)²), T the
    // contact time, with a factor that depends on where they fall in a
    // step (measured at h = 4, 2, 1, 0.5 × 1e-5 s: 3.3e-5, 4.4e-5, 4.7e-5,
    // 5e-8): a bound, not a ratio.
    let errors: Vec<f64> = [H, 0.25 * H]
        .iter()
        .map(|&h| (drop(wire_over_rod(EPS_L, None), h).0 - 1.0).abs())
        .collect();
    assert!(
        errors[0] < 1e-4,
        "rebound ratio off by {:.2e} at h = 1e-5 s",
        errors[0]
    );
    assert!(
        errors[1] < 1e-5,
        "rebound ratio off by {:.2e} at h = 2.5e-6 s",
        errors[1]
    );
}

#[test]
fn the_rebound_ratio_is_the_closed_form_one() {
    for model in MODELS {
        for restitution in [0.3, 0.6, 0.9] {
            let c = ContactDamping::new(restitution, model).coefficient();
            let expected = hunt_crossley_rebound(c);
            let (e, _, _) = drop(wire_over_rod(EPS_L, Some((restitution, model))), H);
            let err = (e - expected).abs() / expected;
            // Measured 1e-4 at most (Flores, e = 0.6).
            assert!(
                err < 2e-4,
                "{model:?}, e = {restitution}: rebound {e:.5}, closed form {expected:.5} ({err:.1e})"
            );
        }
    }
}

#[test]
fn the_rebound_error_falls_with_the_time_step() {
    let model = (0.6, RestitutionModel::Exact);
    let expected = 0.6;
    let errors: Vec<f64> = [4.0 * H, 2.0 * H, H]
        .iter()
        .map(|&h| (drop(wire_over_rod(EPS_L, Some(model)), h).0 - expected).abs())
        .collect();
    // Second order (measured 1.5e-3, 3.6e-4, 8.8e-5): the event's undamped
    // first step and its approach speed read at that step's midpoint cost
    // no more than the scheme.
    assert!(
        errors[1] < 0.35 * errors[0] && errors[2] < 0.35 * errors[1],
        "errors at h = 4, 2, 1 × 1e-5 s: {errors:?}"
    );
}

#[test]
fn the_models_rebound_as_documented() {
    // The exact model inverts the closed form; Flores et al. fitted it;
    // Lankarani–Nikravesh expanded it for e → 1 and overshoots at low e
    // (the values RestitutionModel's documentation gives).
    let rebound = |e, model| hunt_crossley_rebound(ContactDamping::new(e, model).coefficient());
    for e in [0.05, 0.3, 0.5, 0.7, 0.9, 0.99] {
        let exact = rebound(e, RestitutionModel::Exact);
        assert!((exact - e).abs() < 1e-10, "exact at e = {e}: {exact}");
    }
    let documented = [
        (RestitutionModel::Flores, [0.256, 0.470, 0.894]),
        (RestitutionModel::LankaraniNikravesh, [0.684, 0.725, 0.913]),
    ];
    for (model, values) in documented {
        for (e, v) in [0.3, 0.5, 0.9].into_iter().zip(values) {
            let r = rebound(e, model);
            assert!(
                (r - v).abs() < 5e-4,
                "{model:?} at e = {e}: {r:.4}, documented {v}"
            );
        }
    }
}

#[test]
fn damping_takes_the_energy_the_state_records() {
    let (_, s, integrator) = drop(
        wire_over_rod(EPS_L, Some((0.5, RestitutionModel::Flores))),
        H,
    );
    let e1 = integrator.energies(&s);
    let kinetic0 = 0.5 * 7800.0 * std::f64::consts::PI * RW * RW * 1.0 * V0 * V0;
    // Total + dissipated is conserved to the step's accuracy.
    let balance = (e1.total() + e1.dissipated - kinetic0).abs() / kinetic0;
    assert!(
        e1.dissipated > 0.5 * kinetic0,
        "dissipated {:.4} J of {kinetic0:.4} J",
        e1.dissipated
    );
    assert!(
        balance < 1e-3,
        "energy balance off by {balance:.2e} of the start"
    );
    // After the event the pair's memory is cleared.
    assert!(s.contact_events.iter().all(|&v| v == 0.0));
}

#[test]
fn a_model_built_in_code_refuses_a_restitution_outside_0_1() {
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    for e in [0.0, 1.5, f64::NAN] {
        let rod = Rod::line([0.5, 0.0, -0.1], [0.0, 1.0, 0.0], RR, EPS_L)
            .with_restitution(e, RestitutionModel::Exact);
        let err = WireBuilder::new(1.0, 2)
            .layer(steel.clone(), RW)
            .rod(rod)
            .build();
        assert!(
            matches!(&err, Err(ancf_core::model::ModelError::Rod { index: 0, field, .. }) if field == "restitution"),
            "e = {e}: {err:?}"
        );
    }
}
