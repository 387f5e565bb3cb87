//! Clearance zones (`[[clearance]]`): a run reports the smallest distance
//! of the wire's surface to each zone, when and where, and whether the wire
//! entered — against the run's own node positions.

use ancf::run::run_in_memory;
use ancf_core::loads::clearance_record::SAMPLES_PER_ELEMENT;
use ancf_core::prelude::*;

/// The pendulum (a 1 m wire of radius 2 cm pinned at the origin, released
/// horizontally) with a half-space below z = −0.5 m, which its tip swings
/// through, and a box it never reaches.
fn scene(write_every: usize) -> Scene {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/pendulum.toml"))
            .unwrap()
            .replace("end_time = 1.0", "end_time = 0.6")
            .replace("every = 5", &format!("every = {write_every}"))
            + r#"
[[clearance]]
kind = "half-space"
point = [0.0, 0.0, -0.5]
normal = [0.0, 0.0, 1.0]

[[clearance]]
kind = "box"
min = [2.0, -1.0, -1.0]
max = [3.0, 1.0, 1.0]
"#;
    let mut scene = Scene::from_toml(&text).expect("a valid scene");
    scene.output.vtk = false;
    scene.output.plots = false;
    scene
}

#[test]
fn the_smallest_distance_is_the_runs_own() {
    let scene = scene(1);
    let run = run_in_memory(&scene);
    let (below, far) = (&run.summary.clearance[0], &run.summary.clearance[1]);
    assert_eq!(
        (below.kind.as_str(), far.kind.as_str()),
        ("half-space", "box")
    );
    // Every step is written: the lowest tip over the history, less the
    // radius, bounds the record from above (the record samples between
    // nodes too, and the tip is the lowest point of a hanging pendulum).
    let lowest_tip = run
        .history
        .tip
        .iter()
        .map(|p| p[2])
        .fold(f64::INFINITY, f64::min);
    let from_history = lowest_tip + 0.5 - 0.02;
    let d = below.record.min_distance.unwrap();
    assert!(d <= from_history + 1e-12, "{d} against {from_history}");
    assert!(
        (d - from_history).abs() < 1e-3,
        "{d} m against the tip's {from_history} m"
    );
    assert!(below.record.entered && d < -0.3, "{below:?}");
    assert!(
        run.summary
            .message
            .contains("the wire entered clearance[0]")
    );
    assert!(!run.summary.message.contains("clearance[1]"));
    // The box: the closest the wire came is its tip at the start, 1 m away
    // from x = 2 m less the radius (horizontal at t = 0).
    let f = far.record;
    assert!(!f.entered);
    assert!(
        (f.min_distance.unwrap() - (1.0 - 0.02)).abs() < 1e-9,
        "{f:?}"
    );
    assert_eq!(f.time, 0.0);
    assert_eq!(SAMPLES_PER_ELEMENT, 4);
}

#[test]
fn zones_are_checked_naming_the_field() {
    let base =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/pendulum.toml"))
            .unwrap();
    let error = |zone: &str| {
        Scene::from_toml(&format!("{base}\n[[clearance]]\n{zone}\n"))
            .unwrap_err()
            .to_string()
    };
    let e = error("kind = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 0.0, 1.0]");
    assert!(
        e.starts_with("clearance[0].max[1]: must exceed min[1]"),
        "{e}"
    );
    let e = error("kind = \"half-space\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 0.0]");
    assert!(e.starts_with("clearance[0].normal"), "{e}");
    let e = error("kind = \"half-space\"\nnormal = [0.0, 0.0, 1.0]");
    assert!(e.starts_with("clearance[0].point: missing"), "{e}");
    let e = error(
        "kind = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nnormal = [0.0, 0.0, 1.0]",
    );
    assert!(e.starts_with("clearance[0].normal"), "{e}");
}
