//! The core's front door: a simulation run through `Simulation`
//! alone — no files — switches phase at a support release, keeps the rod
//! loads, and a simulation resumed from a snapshot ends bit for bit like
//! the uninterrupted one.

use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::simulation::{Initial, Simulation};

/// The impact scene with `edit` applied to its text, and its settings.
fn impact(edit: impl Fn(String) -> String) -> (Scene, ancf_core::solve::dynamics::DynamicSettings) {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    ))
    .unwrap();
    let scene = Scene::from_toml(&edit(text)).expect("valid scene");
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        panic!("dynamic")
    };
    let settings = settings.clone();
    (scene, settings)
}

/// The impact scene shortened to 0.4 s on 16 elements, with a pinned second
/// support at the free end released at 0.05 s.
fn scene() -> (Scene, ancf_core::solve::dynamics::DynamicSettings) {
    impact(|text| {
        text.replace("end_time = 1.0", "end_time = 0.4")
            .replace("elements = 64", "elements = 16")
            + "\n[[support]]\nnode = \"last\"\nkind = \"pin\"\nrelease_time = 0.05\n"
    })
}

#[test]
fn release_contact_and_resume_bit_for_bit() {
    let (scene, settings) = scene();
    let mut sim = Simulation::new(&scene.model, settings.clone(), Initial::Reference).unwrap();
    let mut snapshot = None;
    let mut held_tip = None;
    while !sim.is_finished() {
        sim.step().unwrap();
        let (k, _) = sim.steps();
        if k == 400 {
            // Before the release the free end is held: its position is the reference's.
            held_tip = Some(
                sim.model()
                    .node_position(&sim.state().q, sim.model().n_elements),
            );
        }
        if k == 1500 {
            snapshot = Some(sim.snapshot());
        }
    }
    let reference_tip = scene
        .model
        .node_position(&scene.model.reference, scene.model.n_elements);
    assert_eq!(
        held_tip.unwrap(),
        reference_tip,
        "the support holds until its release"
    );
    let progress = sim.progress();
    assert_eq!(progress.released, 1);
    assert_eq!(progress.step, 4000);
    assert!((sim.state().time - 0.4).abs() < 1e-12);
    // The released wire swings onto the rod: its force history has every step.
    let loads = &sim.rod_loads()[0];
    assert_eq!(loads.time.len(), 4000);
    assert!(
        loads.force.iter().any(|f| f[2] != 0.0),
        "the wire reaches the rod"
    );
    // Resume from step 1500: the same bits at the end.
    let mut resumed = Simulation::resume(&scene.model, settings, snapshot.unwrap()).unwrap();
    while !resumed.is_finished() {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.state().q, sim.state().q);
    assert_eq!(resumed.state().v, sim.state().v);
    assert_eq!(resumed.rod_loads(), sim.rod_loads());
    assert_eq!(
        resumed.progress().newton_iterations,
        progress.newton_iterations
    );
}

/// Contact damping remembers each contact event's approach speed in the
/// state: a simulation resumed from a snapshot taken during contact (sent
/// through JSON, as a checkpoint file is) ends bit for bit like the
/// uninterrupted one.
#[test]
fn damped_contact_resumes_bit_for_bit_from_inside_an_event() {
    let (_, settings) = scene();
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    ))
    .unwrap()
    .replace("end_time = 1.0", "end_time = 0.3")
    .replace("elements = 64", "elements = 16")
    .replace("[[rod]]\n", "[[rod]]\nrestitution = 0.4\n");
    let damped = Scene::from_toml(&text).expect("valid scene");
    assert!(damped.model.contact().unwrap().rods[0].damping.is_some());
    let settings = ancf_core::solve::dynamics::DynamicSettings {
        end_time: 0.3,
        ..settings
    };
    let mut sim = Simulation::new(&damped.model, settings.clone(), Initial::Reference).unwrap();
    let mut snapshot = None;
    let mut in_event = 0;
    while !sim.is_finished() {
        sim.step().unwrap();
        if sim.state().contact_events.iter().any(|&v| v > 0.0) {
            in_event += 1;
            if in_event == 20 {
                let json = serde_json::to_string(&sim.snapshot()).unwrap();
                snapshot = Some(serde_json::from_str(&json).unwrap());
            }
        }
    }
    assert!(
        in_event > 20,
        "the wire must stay on the rod a while ({in_event} steps)"
    );
    assert!(sim.energies().dissipated > 0.0);
    let mut resumed = Simulation::resume(&damped.model, settings, snapshot.unwrap()).unwrap();
    while !resumed.is_finished() {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.state().q, sim.state().q);
    assert_eq!(resumed.state().v, sim.state().v);
    assert_eq!(resumed.rod_loads(), sim.rod_loads());
}

/// The impact scene on 8 elements with steps of 2 ms, a 1e-10 tolerance and
/// three Newton iterations allowed: from the fourth step on a full step does
/// not converge in time and is cut in halves.
fn strained() -> (Scene, ancf_core::solve::dynamics::DynamicSettings) {
    let (scene, mut settings) = impact(|text| {
        text.replace("end_time = 1.0", "end_time = 0.06")
            .replace("elements = 64", "elements = 8")
    });
    settings.time_step = 2e-3;
    settings.tolerance = 1e-10;
    settings.max_iterations = 3;
    (scene, settings)
}

/// A step whose attempt failed counts that attempt's work, and the next
/// steps start at the size that worked instead of failing again.
#[test]
fn a_newton_failure_counts_its_work_and_subdivides_the_next_steps() {
    let (scene, settings) = strained();
    let max_iterations = settings.max_iterations;
    let mut sim = Simulation::new(&scene.model, settings, Initial::Reference).unwrap();
    let mut first_cut = None;
    while !sim.is_finished() {
        let info = sim.step().unwrap();
        if info.rejected > 0 {
            // The rejected attempt ran out of iterations; each sub-step took at least one.
            assert!(
                info.iterations >= max_iterations * info.rejected + info.substeps,
                "{info:?}"
            );
            first_cut = Some(sim.steps().0);
            break;
        }
        assert_eq!(info.substeps, 1);
    }
    let k = first_cut.expect("a step is cut");
    assert_eq!(sim.progress().step_cuts, 1);
    // The step after starts in halves: two sub-steps, none rejected.
    let info = sim.step().unwrap();
    assert_eq!((info.substeps, info.rejected), (2, 0), "step {}", k + 1);
    // Iterations and factorizations are summed step by step, rejected work included.
    let (iterations, factorizations) = (
        sim.progress().newton_iterations,
        sim.progress().factorizations,
    );
    let info = sim.step().unwrap();
    assert_eq!(
        sim.progress().newton_iterations,
        iterations + info.iterations
    );
    assert_eq!(
        sim.progress().factorizations,
        factorizations + info.factorizations
    );
}

/// Steps held at a subdivision try twice the size after SUBDIVISION_HOLD
/// steps without a Newton failure, down to whole steps.
#[test]
fn a_subdivision_grows_back_after_steps_without_failure() {
    use ancf_core::solve::dynamics::{Integrator, SUBDIVISION_HOLD, Subdivision};
    let (scene, settings) = scene();
    let model = std::sync::Arc::new(scene.model.clone());
    let h = settings.time_step;
    let mut integ = Integrator::new(model.clone(), settings).unwrap();
    let mut s = integ
        .initial_state(model.reference.clone(), vec![0.0; model.reference.len()])
        .unwrap();
    integ.restore_subdivision(Subdivision { depth: 2, held: 0 });
    let mut substeps = Vec::new();
    for _ in 0..2 * SUBDIVISION_HOLD + 1 {
        let (next, info) = integ.step(&s, h).unwrap();
        assert_eq!(info.rejected, 0, "free flight at 1e-4 s needs no cut");
        substeps.push(info.substeps);
        s = next;
    }
    let expected: Vec<usize> = (0..2 * SUBDIVISION_HOLD + 1)
        .map(|k| 4 >> (k / SUBDIVISION_HOLD))
        .collect();
    assert_eq!(substeps, expected);
    assert_eq!(integ.subdivision(), Subdivision::default());
}

/// A snapshot taken while steps start subdivided resumes bit for bit.
#[test]
fn a_subdivided_run_resumes_bit_for_bit() {
    let (scene, settings) = strained();
    let mut sim = Simulation::new(&scene.model, settings.clone(), Initial::Reference).unwrap();
    let mut snapshot = None;
    while !sim.is_finished() {
        sim.step().unwrap();
        if snapshot.is_none() && sim.progress().step_cuts > 0 {
            snapshot = Some(sim.checkpoint());
        }
    }
    let snapshot = snapshot.expect("a step is cut");
    assert!(
        snapshot.subdivision.depth > 0,
        "the snapshot holds the subdivision"
    );
    let mut resumed = Simulation::resume(&scene.model, settings, snapshot).unwrap();
    while !resumed.is_finished() {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.state().q, sim.state().q);
    assert_eq!(resumed.state().v, sim.state().v);
    assert_eq!(resumed.progress().step_cuts, sim.progress().step_cuts);
    assert_eq!(
        resumed.progress().newton_iterations,
        sim.progress().newton_iterations
    );
}

/// Every step's energy is checked, whatever a run writes: a state with a
/// non-finite coordinate fails the check on a wire without rods (where no
/// energy guard runs) and with a Mooney–Rivlin layer (where the energy is
/// evaluated), and a finite one passes.
#[test]
fn a_state_with_a_non_finite_energy_is_refused_without_rods() {
    use ancf_core::prelude::*;
    use ancf_core::solve::dynamics::Integrator;
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let rubber = Material::mooney_rivlin(1100.0, 5e5, 1e5, 1e3);
    for cover in [steel.clone(), rubber] {
        let model = WireBuilder::new(1.0, 4)
            .layer(steel.clone(), 0.005)
            .layer(cover, 0.01)
            .support(0, SupportKind::Pin)
            .gravity([0.0, 0.0, -9.81])
            .build()
            .unwrap();
        let mut integrator = Integrator::new(
            std::sync::Arc::new(model.clone()),
            DynamicSettings::default(),
        )
        .unwrap();
        assert!(!integrator.guards_energy());
        let n = model.reference.len();
        let mut s = integrator
            .initial_state(model.reference.clone(), vec![0.0; n])
            .unwrap();
        assert!(integrator.energy_is_finite(&s));
        s.q[30] = f64::NAN;
        assert!(!integrator.energy_is_finite(&s));
    }
}

/// Modified Newton keeps its matrix in single precision; a fresh one that
/// does not contract 4× is formed again in double. A thin steel cable
/// (r = 4 mm, 32 elements over 10 m, pinned at both ends) sagging at
/// 50 ms steps with ρ∞ = 0 has a Newton matrix conditioned like its
/// stiffness (section stretch over bending, ~1e7), where single
/// precision's rounding spoils the directions: rounded matrices alone
/// took 623 iterations for the first 40 steps, double ones 426. The run
/// converges within 12.5 iterations a step, keeps some matrices in
/// double, and resumes bit for bit from a snapshot whose kept matrix is
/// double.
#[test]
fn an_ill_conditioned_kept_matrix_is_formed_again_in_double_and_resumes() {
    use ancf_core::linalg::block_tridiagonal::Precision;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/pendulum.toml"
    ))
    .unwrap();
    let edits = [
        ("end_time = 1.0", "end_time = 3.0"),
        ("time_step = 1e-3", "time_step = 0.05"),
        ("spectral_radius = 1.0", "spectral_radius = 0.0"),
        ("density = 7200.0", "density = 7850.0"),
        ("youngs_modulus = 2e9", "youngs_modulus = 2e11"),
        ("length = 1.0", "length = 10.0"),
        ("elements = 4", "elements = 32"),
        ("outer_radius = 0.01 }", "outer_radius = 0.002 }"),
        ("outer_radius = 0.02 }", "outer_radius = 0.004 }"),
    ];
    let mut text = edits.iter().fold(text, |t, (a, b)| {
        assert!(t.contains(a), "{a}");
        t.replace(a, b)
    });
    text += "\n[[support]]\nnode = \"last\"\nkind = \"pin\"\nposition = [9.99, 0.0, 0.0]\n";
    let scene = Scene::from_toml(&text).expect("valid scene");
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        panic!("dynamic")
    };
    let mut sim = Simulation::new(&scene.model, settings.clone(), Initial::Reference).unwrap();
    let (mut kept, mut snapshot) = ([0, 0], None);
    while !sim.is_finished() {
        sim.step().unwrap();
        let (k, _) = sim.steps();
        let now = sim.snapshot();
        match now.factorization.as_ref().map(|f| f.precision) {
            Some(Precision::Single) => kept[0] += 1,
            Some(Precision::Double) => {
                kept[1] += 1;
                if k <= 40 {
                    snapshot = Some(now);
                }
            }
            None => {}
        }
        if k == 40 {
            let iterations = sim.progress().newton_iterations;
            println!("{iterations} iterations in 40 steps; kept single, double: {kept:?}");
            assert!(iterations < 500, "{iterations} iterations in 40 steps");
        }
    }
    assert_eq!(sim.steps().0, 60, "3 s of 50 ms steps");
    assert!(kept[0] > 0 && kept[1] > 0, "kept single, double: {kept:?}");
    let snapshot = snapshot.expect("a double matrix kept within 40 steps");
    let mut resumed = Simulation::resume(&scene.model, settings.clone(), snapshot).unwrap();
    while !resumed.is_finished() {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.state().q, sim.state().q);
    assert_eq!(resumed.state().v, sim.state().v);
}
