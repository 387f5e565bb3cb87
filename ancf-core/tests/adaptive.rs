//! Adaptive time steps (`DynamicSettings::step_control`): against closed
//! forms, the tolerance's order, the contact's resolution limit, and a
//! resumed run.

use ancf_core::model::spring::Spring;
use ancf_core::prelude::*;
use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::dynamics::StepControl;
use ancf_core::solve::simulation::Snapshot;
use std::ops::ControlFlow;

const G: f64 = 9.81;

fn steel(e: f64) -> Material {
    Material::st_venant_kirchhoff(7800.0, e, 0.3, 1.0)
}

fn adaptive(tolerance: f64, max_step: f64, end_time: f64) -> DynamicSettings {
    let control = StepControl {
        tolerance,
        max_step,
    };
    DynamicSettings {
        time_step: control.first_step(end_time),
        end_time,
        spectral_radius: 1.0,
        step_control: Some(control),
        ..Default::default()
    }
}

/// The mean height of the wire's nodes (m).
fn mean_z(model: &Model, q: &[f64]) -> f64 {
    let n = model.n_nodes();
    (0..n).map(|i| model.node_position(q, i)[2]).sum::<f64>() / n as f64
}

/// A wire with nothing holding it falls as z = −g t²/2: generalized-α
/// integrates a constant acceleration exactly, the estimate is zero, and
/// the steps grow to the longest allowed.
#[test]
fn a_free_falling_wire_matches_the_closed_form_with_the_longest_steps() {
    let model = WireBuilder::new(1.0, 4)
        .layer(steel(2e11), 0.01)
        .gravity([0.0, 0.0, -G])
        .build()
        .unwrap();
    let tolerance = 1e-6;
    let mut sim =
        Simulation::new(&model, adaptive(tolerance, 0.05, 1.0), Initial::Reference).unwrap();
    let mut worst = 0.0f64;
    sim.run_until(1.0, |sim, _| {
        let s = sim.state();
        let exact = -0.5 * G * s.time * s.time;
        worst = worst.max((mean_z(sim.model(), &s.q) - exact).abs());
        ControlFlow::Continue(())
    })
    .unwrap();
    assert!(worst <= tolerance, "off the closed form by {worst:e} m");
    assert_eq!(sim.state().time, 1.0, "ends at the end time exactly");
    let [_, longest] = sim.progress().step_range.unwrap();
    assert!(
        (longest / 0.05 - 1.0).abs() < 1e-12,
        "steps grow to the longest allowed: {longest} s"
    );
    assert!(sim.steps().0 < 40, "{} steps", sim.steps().0);
}

/// A stiff wire on two vertical springs: a rigid body on a spring of 2k,
/// z(t) = −(g/ω²)(1 − cos ω t) with ω² = 2k/m. Its bending sag under
/// gravity is ~0.2 µm (E = 2e14 Pa), so the closed form holds to well
/// below the tolerances tried.
fn oscillator() -> (Model, f64) {
    let (length, radius, density) = (1.0, 0.01, 7800.0);
    let mass = density * std::f64::consts::PI * radius * radius * length;
    let omega = 2.0 * std::f64::consts::PI * 2.0;
    let k = 0.5 * omega * omega * mass;
    let spring = Spring {
        stiffness: [0.0, 0.0, k],
        ..Default::default()
    };
    let model = WireBuilder::new(length, 4)
        .layer(steel(2e14), radius)
        .spring(0, spring)
        .spring(4, spring)
        .gravity([0.0, 0.0, -G])
        .build()
        .unwrap();
    (model, omega)
}

struct OscillatorRun {
    /// The largest error of one step: the step's end against the closed
    /// form started from the step's start (m).
    worst_local: f64,
    /// The largest error against the closed form from t = 0 (m).
    worst_global: f64,
    steps: usize,
}

fn run_oscillator(tolerance: f64) -> OscillatorRun {
    let (model, omega) = oscillator();
    let z_eq = -G / (omega * omega);
    let mut sim =
        Simulation::new(&model, adaptive(tolerance, 0.05, 1.0), Initial::Reference).unwrap();
    let start = |sim: &Simulation| {
        let s = sim.state();
        let n = sim.model().n_nodes() as f64;
        let vz = (0..sim.model().n_nodes())
            .map(|i| s.v[12 * i + 2])
            .sum::<f64>()
            / n;
        (s.time, mean_z(sim.model(), &s.q), vz)
    };
    let mut before = start(&sim);
    let (mut worst_local, mut worst_global) = (0.0f64, 0.0f64);
    sim.run_until(1.0, |sim, _| {
        let (t0, z0, v0) = before;
        let (t, z, _) = start(sim);
        let dt = t - t0;
        let local = z_eq + (z0 - z_eq) * (omega * dt).cos() + v0 / omega * (omega * dt).sin();
        worst_local = worst_local.max((z - local).abs());
        let global = z_eq * (1.0 - (omega * t).cos());
        worst_global = worst_global.max((z - global).abs());
        before = start(sim);
        ControlFlow::Continue(())
    })
    .unwrap();
    OscillatorRun {
        worst_local,
        worst_global,
        steps: sim.steps().0,
    }
}

/// Every step's own error (its end against the closed form started from
/// its start) stays near the tolerance asked for. Not below it everywhere:
/// the estimate fits ȧ over the last two steps, while the error's leading
/// term h³ ȧ(t₁)/12 (ρ∞ = 1) has it at the step's end, so a step in which
/// ȧ passes through zero is underestimated — measured here up to 2.09 ×
/// the tolerance at 1e-5 m, 1.19–1.44 × at 1e-4 … 1e-8 m; the step-size
/// module says so.
#[test]
fn each_step_of_an_oscillator_keeps_the_tolerance_to_the_estimates_accuracy() {
    for tolerance in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
        let run = run_oscillator(tolerance);
        assert!(
            run.worst_local <= 2.5 * tolerance,
            "a step's error {:e} m against the tolerance {tolerance:e} m ({} steps)",
            run.worst_local,
            run.steps
        );
        assert!(
            run.worst_local >= 0.5 * tolerance,
            "steps far shorter than the tolerance needs: error {:e} m ({} steps)",
            run.worst_local,
            run.steps
        );
    }
}

/// Steps go as tolerance^⅓ and the run's error (many steps' phase errors
/// added) as h², so halving the tolerance divides it by 2^⅔ = 1.59.
#[test]
fn halving_the_tolerance_reduces_the_error_by_two_to_the_two_thirds() {
    let tolerances = [1e-6, 0.5e-6, 0.25e-6, 0.125e-6];
    let runs: Vec<OscillatorRun> = tolerances.iter().map(|&t| run_oscillator(t)).collect();
    let errors: Vec<f64> = runs.iter().map(|r| r.worst_global).collect();
    // The observed order in the tolerance: the least-squares slope of
    // log error against log tolerance.
    let xs: Vec<f64> = tolerances.iter().map(|t| t.ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / 4.0, ys.iter().sum::<f64>() / 4.0);
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    assert!(
        (slope - 2.0 / 3.0).abs() < 0.15,
        "observed order {slope:.3} (errors {errors:?} m, steps {:?})",
        runs.iter().map(|r| r.steps).collect::<Vec<_>>()
    );
}

fn impact(end_time: f64, tolerance: f64) -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    ))
    .unwrap();
    let text = text
        .replace("end_time = 1.0 ", &format!("end_time = {end_time} "))
        .replace(
            "time_step = 1e-4 ",
            &format!("time_step = \"auto\"\nerror_tolerance = {tolerance:e} #"),
        );
    Scene::from_toml(&text).expect("adaptive impact scene is valid")
}

fn settings(scene: &Scene) -> DynamicSettings {
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        panic!("dynamic scene")
    };
    settings.clone()
}

/// Near the rod no step exceeds the contact's resolution limit
/// h ω_c ≤ 3, so a contact is met, not stepped over: no step that ends in
/// contact is longer, and the first contact is located to a 32nd of it.
#[test]
fn a_contact_is_never_stepped_over() {
    let scene = impact(0.3, 1e-5);
    let model = &scene.model;
    let limit = model.contact_step_limit().expect("a line-law rod");
    let mut sim = Simulation::new(model, settings(&scene), Initial::Reference).unwrap();
    let mut last = 0.0;
    let mut longest_in_contact = 0.0f64;
    let mut longest = 0.0f64;
    sim.run_until(0.3, |sim, info| {
        let h = sim.state().time - last;
        last = sim.state().time;
        longest = longest.max(h);
        if info.contact.active > 0 {
            longest_in_contact = longest_in_contact.max(h);
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    assert!(
        longest > 2.0 * limit,
        "free flight runs at longer steps ({longest:e} s)"
    );
    assert!(
        longest_in_contact > 0.0 && longest_in_contact <= limit * (1.0 + 1e-12),
        "a step in contact of {longest_in_contact:e} s against the limit {limit:e} s"
    );
    // Located: within a 32nd of the limit of where a fixed step of
    // 2e-5 s (a 27th) finds it.
    let first = sim.contact().and_then(|c| c.first_time).unwrap();
    let fine = {
        let mut fixed = settings(&scene);
        fixed.step_control = None;
        fixed.time_step = 2e-5;
        fixed.end_time = 0.3;
        let mut sim = Simulation::new(model, fixed, Initial::Reference).unwrap();
        sim.run_until(0.3, |sim, _| {
            if sim.contact().and_then(|c| c.first_time).is_some() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
        sim.contact().and_then(|c| c.first_time).unwrap()
    };
    assert!(
        (first - fine).abs() <= limit / 32.0 + 2e-5,
        "first contact at {first} s, with h = 2e-5 s at {fine} s (limit {limit:e} s)"
    );
}

/// A run checkpointed in the middle and resumed from the JSON of its
/// snapshot ends as the uninterrupted one, bit for bit.
#[test]
fn an_adaptive_run_resumes_bit_for_bit() {
    let scene = impact(0.3, 1e-5);
    let model = &scene.model;
    let s = settings(&scene);
    let mut whole = Simulation::new(model, s.clone(), Initial::Reference).unwrap();
    whole
        .run_until(0.3, |_, _| ControlFlow::Continue(()))
        .unwrap();
    let mut first = Simulation::new(model, s.clone(), Initial::Reference).unwrap();
    first
        .run_until(0.27, |_, _| ControlFlow::Continue(()))
        .unwrap();
    let json = serde_json::to_string(&first.checkpoint()).unwrap();
    drop(first);
    let snapshot: Snapshot = serde_json::from_str(&json).unwrap();
    let mut resumed = Simulation::resume(model, s, snapshot).unwrap();
    resumed
        .run_until(0.3, |_, _| ControlFlow::Continue(()))
        .unwrap();
    let (a, b) = (whole.state(), resumed.state());
    assert_eq!(whole.steps().0, resumed.steps().0);
    assert_eq!(a.time.to_bits(), b.time.to_bits());
    assert!(
        a.q.iter()
            .zip(&b.q)
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
    assert!(
        a.v.iter()
            .zip(&b.v)
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
    assert_eq!(whole.rod_loads()[0].force, resumed.rod_loads()[0].force);
}
