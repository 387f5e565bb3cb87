//! A run in memory (the study's) computes what the same run with files
//! writes: the same summary, and its history holds timeseries.csv's rows —
//! also when the scene checkpoints (a checkpoint drops the factorization,
//! which a run in memory must do too to keep the same bits).

use ancf::output::RunStatus;
use ancf::run::{RunOptions, run_in_memory, run_scene};
use ancf_core::scene::Scene;

/// The impact scene on 16 elements for 0.32 s (contact from ≈ 0.26 s on),
/// checkpointing every 500 steps.
fn scene() -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/wire_rod_impact.toml"
    ))
    .unwrap()
    .replace("end_time = 1.0", "end_time = 0.32")
    .replace("elements = 64", "elements = 16")
        + "\n";
    let mut scene = Scene::from_toml(&text).expect("a valid scene");
    scene.output.checkpoint_every = 500;
    scene.output.vtk = false;
    scene.output.plots = false;
    scene
}

#[test]
fn memory_and_files_agree() {
    let scene = scene();
    let dir = std::env::temp_dir().join(format!("ancf-memory-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = RunOptions {
        out: dir.clone(),
        quiet: true,
        cancel: Default::default(),
    };
    let written = run_scene(&scene, &opts).unwrap();
    let memory = run_in_memory(&scene);
    assert_eq!(written.status, RunStatus::Completed, "{}", written.message);
    let json = |s: &ancf::output::Summary| {
        let mut v = serde_json::to_value(s).unwrap();
        // Timings differ between any two runs.
        v.as_object_mut().unwrap().remove("wall_time_s");
        v.as_object_mut().unwrap().remove("performance");
        v
    };
    assert_eq!(json(&written), json(&memory.summary));
    let contact = memory.summary.contact.as_ref().expect("rods");
    assert!(contact.first_time.is_some(), "the wire reaches the rod");

    // timeseries.csv's rows are the history's, to the file's precision.
    let text = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let h = &memory.history;
    assert_eq!(rows.len(), h.time.len());
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-8 * b.abs().max(1e-12);
    for (k, row) in rows.iter().enumerate() {
        assert!(close(row[0], h.time[k]));
        for c in 0..3 {
            assert!(close(row[1 + c], h.tip[k][c]), "row {k} tip");
        }
        assert!(close(row[4], h.energies[k].kinetic), "row {k} kinetic");
        assert!(close(row[7], h.energies[k].total()), "row {k} total");
    }
    // The rod loads are rod_forces.csv's.
    let forces = std::fs::read_to_string(dir.join("rod_forces.csv")).unwrap();
    assert_eq!(forces.lines().count() - 1, memory.rod_loads[0].time.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two runs in one process (as two Python threads would run them), each
/// with its own cancellation token: cancelling one stops it at its next
/// step with status "interrupted" and its outputs kept, and the other
/// completes untouched.
#[test]
fn two_runs_in_one_process_stop_independently() {
    let mut scene = scene();
    scene.output.checkpoint_every = 0;
    let base = std::env::temp_dir().join(format!("ancf-cancel-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let options = |name: &str| RunOptions {
        out: base.join(name),
        quiet: true,
        cancel: Default::default(),
    };
    let (stopped, kept) = (options("stopped"), options("kept"));
    let token = stopped.cancel.clone();
    let (a, b) = (scene.clone(), scene.clone());
    let first = std::thread::spawn(move || run_scene(&a, &stopped));
    let second = std::thread::spawn(move || run_scene(&b, &kept));
    // Cancel the first once it has written some steps.
    let series = base.join("stopped").join("timeseries.csv");
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&series).map_or(0, |t| t.lines().count()) < 20 {
        assert!(start.elapsed().as_secs() < 60, "the first run never wrote");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    token.cancel();
    let first = first.join().unwrap().unwrap();
    let second = second.join().unwrap().unwrap();
    assert_eq!(first.status, RunStatus::Interrupted, "{}", first.message);
    assert!(first.steps < 3200, "stopped early: {} steps", first.steps);
    let written = std::fs::read_to_string(&series).unwrap().lines().count();
    assert!(written >= 20, "{written} rows kept, {} steps", first.steps);
    assert_eq!(second.status, RunStatus::Completed, "{}", second.message);
    assert_eq!(second.steps, 3200);
    let _ = std::fs::remove_dir_all(&base);
}
