//! The core's front door (issue 15): a simulation run through `Simulation`
//! alone — no files — switches phase at a support release, keeps the rod
//! loads, and a simulation resumed from a snapshot ends bit for bit like
//! the uninterrupted one.

use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::simulation::{Initial, Simulation};

/// The impact scene shortened to 0.4 s on 16 elements, with a pinned second
/// support at the free end released at 0.05 s.
fn scene() -> (Scene, ancf_core::solve::dynamics::DynamicSettings) {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    ))
    .unwrap()
    .replace("end_time = 1.0", "end_time = 0.4")
    .replace("elements = 64", "elements = 16")
        + "\n[[support]]\nnode = \"last\"\nkind = \"pin\"\nrelease_time = 0.05\n";
    let scene = Scene::from_toml(&text).expect("valid scene");
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        panic!("dynamic")
    };
    let settings = settings.clone();
    (scene, settings)
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
            sim.refresh_factorization();
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
                sim.refresh_factorization();
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
