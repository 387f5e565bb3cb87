//! `ancf sweep` as a user runs it: variants checked before any
//! work, run on the local executor, one failing without stopping the
//! others, Ctrl-C keeping what is done, reruns doing only what is missing,
//! and results.csv holding each variant's own summary numbers.

#[path = "../ancf-core/tests/common/mod.rs"]
mod common;

use common::split_csv;
use std::path::{Path, PathBuf};
use std::process::Command;

fn ancf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ancf"))
}

/// `ancf sweep SWEEP --out OUT --quiet ARGS…`.
fn sweep_cmd(sweep: &Path, out: &Path, args: &[&str]) -> Command {
    let mut c = ancf();
    c.arg("sweep")
        .arg(sweep)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(args);
    c
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ancf-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A pendulum scene of `elements` over `end_time` s, checkpointing every 100 steps.
fn write_scene(dir: &Path, elements: usize, end_time: f64) -> PathBuf {
    let path = dir.join("pendulum.toml");
    std::fs::write(
        &path,
        format!(
            r#"
[analysis]
kind = "dynamic"
end_time = {end_time}
time_step = 1e-3
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[material]]
name = "core"
model = "st-venant-kirchhoff"
density = 7200.0
youngs_modulus = 2e9
[wire]
length = 1.0
elements = {elements}
layers = [ {{ material = "core", outer_radius = 0.02 }} ]
[[support]]
node = 0
kind = "pin"
[output]
every = 10
vtk = false
plots = false
checkpoint_every = 100
"#
        ),
    )
    .unwrap();
    path
}

fn write_sweep(dir: &Path, body: &str) -> PathBuf {
    let path = dir.join("sweep.toml");
    std::fs::write(&path, format!("scene = \"pendulum.toml\"\n{body}")).unwrap();
    path
}

/// results.csv as (header, rows).
fn results(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines = text.lines();
    let header = split_csv(lines.next().unwrap());
    (header, lines.map(split_csv).collect())
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// A grid of 2 × 2 variants: every variant completes, results.csv has one
/// row per variant in order with its values, and each row's tip equals an
/// ordinary `ancf run` of that variant's scene.
#[test]
fn a_grid_runs_every_variant_and_tabulates_its_summary() {
    let dir = tmp("grid");
    write_scene(&dir, 4, 0.05);
    let sweep = write_sweep(
        &dir,
        "mode = \"grid\"\n[parameters]\n\"wire.length\" = [1.0, 1.5]\n\"analysis.time_step\" = [1e-3, 5e-4]\n",
    );
    let out = dir.join("out");
    let status = sweep_cmd(&sweep, &out, &["--jobs", "2"]).status().unwrap();
    assert!(status.success());
    let (header, rows) = results(&out);
    assert_eq!(rows.len(), 4);
    let (id, len, h, st) = (
        column(&header, "id"),
        column(&header, "wire.length"),
        column(&header, "analysis.time_step"),
        column(&header, "status"),
    );
    let tip = column(&header, "tip_dz");
    let cuts = column(&header, "step_cuts");
    let expected = [
        ("1.0", "0.001"),
        ("1.0", "0.0005"),
        ("1.5", "0.001"),
        ("1.5", "0.0005"),
    ];
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[id], format!("v{k:03}"));
        assert_eq!(row[st], "completed");
        assert_eq!(row[cuts], "0", "a pendulum needs no cut");
        assert_eq!(
            row[len].parse::<f64>().unwrap(),
            expected[k].0.parse::<f64>().unwrap()
        );
        assert_eq!(
            row[h].parse::<f64>().unwrap(),
            expected[k].1.parse::<f64>().unwrap()
        );
    }
    // The last variant run by hand gives the tip in its row.
    let own = dir.join("own");
    let run = ancf()
        .arg("run")
        .arg(out.join("runs/v003/scene.toml"))
        .arg("--out")
        .arg(&own)
        .arg("--quiet")
        .status()
        .unwrap();
    assert!(run.success());
    let dz = summary(&own)["tip"]["displacement"][2].as_f64().unwrap();
    let row_dz: f64 = rows[3][tip].parse().unwrap();
    assert!(
        (row_dz - dz).abs() <= 1e-9 * dz.abs().max(1.0),
        "{row_dz} vs {dz}"
    );
    // The pin's load is a column of its own, the variant's summary's.
    let pin = summary(&own)["supports"][0]["filtered_peak_force"]
        .as_f64()
        .unwrap();
    let row_pin: f64 = rows[3][column(&header, "support0_filtered_peak_force")]
        .parse()
        .unwrap();
    assert!((row_pin - pin).abs() <= 1e-9 * pin, "{row_pin} vs {pin}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("| support 0 (wire node 0): filtered peak force (N) | 4 |"));
    assert!(report.contains("plots/wire_length.png") && out.join("plots/wire_length.png").exists());
    // The spread over the variants: the tip displacement's min and max are
    // those of results.csv's column (report.md rounds to 4 decimals).
    let magnitude = column(&header, "tip_displacement");
    let tips: Vec<f64> = rows.iter().map(|r| r[magnitude].parse().unwrap()).collect();
    let spread = report
        .lines()
        .find(|l| l.starts_with("| tip displacement (m) |"))
        .expect("spread row");
    // | quantity | n | min | mean | max | spread |
    let cells: Vec<f64> = spread
        .split('|')
        .skip(3)
        .take(3)
        .map(|c| c.trim().parse().unwrap())
        .collect();
    let (lo, hi) = tips
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    assert!((cells[0] - lo).abs() < 1e-4 * lo.abs().max(1.0), "{spread}");
    assert!((cells[2] - hi).abs() < 1e-4 * hi.abs().max(1.0), "{spread}");
    let _ = std::fs::remove_dir_all(dir);
}

/// A variant whose time step does not resolve its rod's contact is named
/// before the sweep runs (stderr, even quiet), and results.csv and
/// report.md carry the warning; the resolved variant has none.
#[test]
fn a_variant_with_an_unresolved_contact_is_warned_of() {
    let dir = tmp("unresolved");
    let impact = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/wire_rod_impact.toml"
    ))
    .unwrap()
    .replace("end_time = 1.0", "end_time = 0.002")
    .replace("elements = 64", "elements = 8")
    .replace("every = 50", "every = 10\nvtk = false\nplots = false");
    std::fs::write(dir.join("impact.toml"), impact).unwrap();
    let sweep = dir.join("sweep.toml");
    std::fs::write(
        &sweep,
        "scene = \"impact.toml\"\n[parameters]\n\"rod[0].contact_stiffness\" = [5e7, 5e9]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let run = sweep_cmd(&sweep, &out, &["--jobs", "2"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let warning = "analysis.time_step = 1e-4 s does not resolve rod 0's line contact";
    assert!(
        stderr.contains(&format!("warning: v001: {warning}")),
        "{stderr}"
    );
    assert!(!stderr.contains("v000:"), "{stderr}");
    let (header, rows) = results(&out);
    let w = column(&header, "warnings");
    assert_eq!(rows[0][w], "");
    assert!(rows[1][w].contains(warning), "{:?}", rows[1]);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains(&format!("* v001: {warning}")), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// One bad variant refuses the sweep before anything runs, naming the
/// variant, its values and the field.
#[test]
fn a_bad_variant_refuses_the_sweep_before_any_work() {
    let dir = tmp("bad");
    write_scene(&dir, 4, 0.05);
    let sweep = write_sweep(&dir, "[parameters]\n\"wire.length\" = [1.0, -1.0]\n");
    let out = dir.join("out");
    let result = ancf()
        .args(["sweep"])
        .arg(&sweep)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("variant v001 (wire.length = -1.0)") && stderr.contains("wire.length:"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing may be written for a refused sweep");
    let _ = std::fs::remove_dir_all(dir);
}

/// A variant that fails is recorded with its cause and the others finish;
/// rerunning the same command reruns only that one and leaves completed
/// runs untouched.
#[test]
fn a_failing_variant_is_recorded_and_only_it_is_retried() {
    let dir = tmp("failing");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(
        root.join("scenes/cantilever_large_deflection.toml"),
        dir.join("cantilever.toml"),
    )
    .unwrap();
    // The large-deflection cantilever in one load step with two Newton
    // iterations does not converge: that variant fails.
    let sweep = dir.join("sweep.toml");
    std::fs::write(
        &sweep,
        "scene = \"cantilever.toml\"\nmode = \"zip\"\n[parameters]\n\"analysis.load_steps\" = [4, 1]\n\"analysis.max_iterations\" = [50, 2]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let run = || sweep_cmd(&sweep, &out, &[]).output().unwrap();
    let first = run();
    assert_eq!(
        first.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let (header, rows) = results(&out);
    let (st, msg) = (column(&header, "status"), column(&header, "message"));
    assert_eq!(rows[0][st], "completed");
    assert_eq!(rows[1][st], "failed");
    assert!(
        rows[1][msg].contains("Newton did not converge"),
        "{}",
        rows[1][msg]
    );
    let done = out.join("runs/v000/summary.json");
    let stamp = std::fs::metadata(&done).unwrap().modified().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    let again = run();
    assert_eq!(again.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&again.stderr).contains("1 variant(s) failed"));
    assert_eq!(
        std::fs::metadata(&done).unwrap().modified().unwrap(),
        stamp,
        "completed run redone"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Ctrl-C (SIGINT to the sweep) stops the running variants with their
/// checkpoints and starts no others; rerunning resumes them, and the
/// results equal an uninterrupted sweep's.
#[test]
fn an_interrupted_sweep_resumes_where_it_stopped() {
    let dir = tmp("interrupt");
    write_scene(&dir, 48, 8.0);
    let sweep = write_sweep(&dir, "[parameters]\n\"wire.length\" = [1.0, 1.1, 1.2]\n");
    let out = dir.join("out");
    let mut child = sweep_cmd(&sweep, &out, &["--jobs", "2"]).spawn().unwrap();
    // Interrupt once the first checkpoints exist.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !out.join("runs/v000/checkpoint.json").exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "no checkpoint appeared"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert_eq!(child.wait().unwrap().code(), Some(130));
    let (header, rows) = results(&out);
    let st = column(&header, "status");
    assert!(rows.iter().any(|r| r[st] == "interrupted"), "{rows:?}");
    assert_eq!(rows[2][st], "missing", "no variant starts after Ctrl-C");
    assert!(out.join("runs/v000/checkpoint.json").exists());
    let resumed = sweep_cmd(&sweep, &out, &["--jobs", "2"]).status().unwrap();
    assert!(resumed.success());
    let (_, rows) = results(&out);
    assert!(rows.iter().all(|r| r[st] == "completed"));
    // Completed variants keep no checkpoint, and a sweep writes no frames.
    for id in ["v000", "v001", "v002"] {
        let run = out.join("runs").join(id);
        assert!(run.join("summary.json").exists());
        assert!(!run.join("checkpoint.json").exists(), "{id}");
        assert!(!run.join("vtk").exists(), "{id}");
    }
    // The same sweep without interruption.
    let plain = dir.join("plain");
    let status = sweep_cmd(&sweep, &plain, &["--jobs", "2"])
        .status()
        .unwrap();
    assert!(status.success());
    let (header, clean) = results(&plain);
    let tip = column(&header, "tip_dz");
    for (a, b) in rows.iter().zip(&clean) {
        assert_eq!(a[tip], b[tip], "resumed variant {} differs", a[0]);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Waits until `path` holds a process id (a run or sweep took its lock).
fn holder(path: &Path) -> u32 {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    loop {
        if let Some(pid) = std::fs::read_to_string(path)
            .ok()
            .and_then(|t| t.trim().parse().ok())
        {
            return pid;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "{} never locked",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// A sweep's parent killed with SIGKILL: its running child gets SIGTERM
/// and stops (with its checkpoint) instead of running on unseen; a second
/// sweep into the folder while the first runs is refused naming it.
#[test]
fn a_killed_sweeps_children_stop_and_a_second_sweep_is_refused() {
    let dir = tmp("orphans");
    write_scene(&dir, 48, 30.0);
    let sweep = write_sweep(&dir, "[parameters]\n\"wire.length\" = [1.0, 1.1]\n");
    let out = dir.join("out");
    let mut parent = sweep_cmd(&sweep, &out, &["--jobs", "1"]).spawn().unwrap();
    let child = holder(&out.join("runs/v000/.ancf.lock"));
    let second = sweep_cmd(&sweep, &out, &["--jobs", "1"]).output().unwrap();
    assert!(!second.status.success());
    let message = String::from_utf8_lossy(&second.stderr);
    assert!(
        message.contains(&format!("process {}", parent.id())),
        "{message}"
    );
    parent.kill().unwrap();
    parent.wait().unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    while Path::new(&format!("/proc/{child}")).exists() {
        // A zombie has no command line left: it has ended.
        let cmdline = std::fs::read(format!("/proc/{child}/cmdline")).unwrap_or_default();
        if cmdline.is_empty() {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the orphaned run {child} kept going"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// report.md leaves a rod the wire never touched out of its statistics
/// (its zeros are no load), prints numbers to four significant figures and
/// plots no parameter that has one value only.
#[test]
fn the_report_counts_only_touched_rods_and_plots_only_varied_parameters() {
    let dir = tmp("report");
    let scene = std::fs::read_to_string("docs/tutorial/drop_cable.toml")
        .unwrap()
        .replace("end_time = 0.8 ", "end_time = 0.4 ");
    std::fs::write(dir.join("cable.toml"), scene).unwrap();
    let sweep = dir.join("sweep.toml");
    std::fs::write(
        &sweep,
        "scene = \"cable.toml\"\n[parameters]\n\"rod[0].radius\" = [0.02]\n\"rod[0].center\" = [[2.0, 0.0, -0.4], [2.0, 0.0, -5.0]]\n",
    )
    .unwrap();
    let out = dir.join("out");
    assert!(sweep_cmd(&sweep, &out, &[]).status().unwrap().success());
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let row = report
        .lines()
        .find(|l| l.starts_with("| rod 0: filtered peak force (N) | "))
        .unwrap();
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    assert_eq!(cells[2], "1", "{row}");
    assert_eq!(cells[3], cells[5], "one value: min = max ({row})");
    // Where the extremes are: the touched variant, v000, for both.
    assert_eq!((cells[7], cells[8]), ("v000", "v000"), "{row}");
    // Two chosen rod positions are no sample: no quantiles. Marked an
    // ensemble, the same variants get them.
    assert!(!report.contains("Quantiles over the variants"), "{report}");
    let ensemble = dir.join("ensemble.toml");
    let text = std::fs::read_to_string(&sweep).unwrap();
    std::fs::write(&ensemble, format!("ensemble = true\n{text}")).unwrap();
    let out_e = dir.join("out_ensemble");
    assert!(
        sweep_cmd(&ensemble, &out_e, &[])
            .status()
            .unwrap()
            .success()
    );
    let report_e = std::fs::read_to_string(out_e.join("report.md")).unwrap();
    assert!(
        report_e.contains("Quantiles over the variants"),
        "{report_e}"
    );
    assert!(cells[3].parse::<f64>().unwrap() > 100.0, "{row}");
    assert!(
        cells[3].split('.').nth(1).is_some_and(|d| d.len() == 1),
        "4 figures: {row}"
    );
    assert!(report.contains("One value (0.02) in every variant: nothing to plot."));
    assert!(!out.join("plots/rod_0__radius.png").exists());
    assert!(out.join("plots/rod_0__center.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Errors name the sweep file's own line and the parameter: a bad value
/// with the variant it makes (not a line of a generated scene), a value
/// that is not a list, a table the base scene lacks, a TOML error.
#[test]
fn sweep_errors_name_the_sweep_files_line_and_parameter() {
    let dir = tmp("lines");
    write_scene(&dir, 4, 0.05);
    for (body, expected) in [
        (
            "mode = \"grid\"\n\n[parameters]\n\"wire.length\" = [1.0, -1.0]\n",
            "sweep.toml:5: parameters.\"wire.length\": the value -1.0 makes variant v001 (wire.length = -1.0) an invalid scene: wire.length: must be > 0",
        ),
        (
            "[parameters]\n\"wire.elements\" = [4, \"x\"]\n",
            "sweep.toml:3: parameters.\"wire.elements\": the value x makes variant v001 (wire.elements = x) an invalid scene: wire.elements: invalid type",
        ),
        (
            "[parameters]\n\"wire.length\" = 2.0\n",
            "sweep.toml:3: parameters.\"wire.length\": a list of values",
        ),
        (
            "[parameters]\n\"rod[0].radius\" = [0.1]\n",
            "sweep.toml:3: parameters.\"rod[0].radius\": rod[0].radius: the scene has no [[rod]] table",
        ),
        (
            "mode = 3\n[parameters]\n\"wire.length\" = [1.0]\n",
            "sweep.toml:2: mode: ",
        ),
    ] {
        let sweep = write_sweep(&dir, body);
        let out = sweep_cmd(&sweep, &dir.join("out"), &[]).output().unwrap();
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(expected), "{body}\n{stderr}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A finished sweep is extended in place: a new value runs alone (the
/// finished variants keep their ids and runs), the results hold all of
/// them; a base scene changed under the same values is refused.
#[test]
fn a_sweep_is_extended_in_place() {
    let dir = tmp("extend");
    let scene = write_scene(&dir, 4, 0.05);
    let out = dir.join("out");
    let first = write_sweep(&dir, "[parameters]\n\"wire.length\" = [1.0, 1.1]\n");
    assert!(sweep_cmd(&first, &out, &[]).status().unwrap().success());
    let summary_of =
        |id: &str| std::fs::read_to_string(out.join("runs").join(id).join("summary.json")).unwrap();
    let before = summary_of("v001");
    let more = write_sweep(&dir, "[parameters]\n\"wire.length\" = [1.0, 1.2, 1.1]\n");
    let run = sweep_cmd(&more, &out, &[]).output().unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(
        summary_of("v001"),
        before,
        "a finished variant was run again"
    );
    let (header, rows) = results(&out);
    let (id, length) = (column(&header, "id"), column(&header, "wire.length"));
    let got: Vec<(String, String)> = rows
        .iter()
        .map(|r| (r[id].clone(), r[length].clone()))
        .collect();
    assert_eq!(
        got,
        [("v000", "1.0"), ("v001", "1.1"), ("v002", "1.2")]
            .map(|(a, b)| (a.to_string(), b.to_string()))
    );
    let st = column(&header, "status");
    assert!(rows.iter().all(|r| r[st] == "completed"), "{rows:?}");
    // The same values over another base scene: refused, nothing touched.
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("end_time = 0.05", "end_time = 0.06")).unwrap();
    let refused = sweep_cmd(&more, &out, &[]).output().unwrap();
    assert_eq!(refused.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("the base scene changed"), "{stderr}");
    assert_eq!(summary_of("v001"), before);
    let _ = std::fs::remove_dir_all(dir);
}

/// A wire dropped across a frame member (a tube, fixed at one end and
/// hinged at the other): results.csv has the member's contact loads and
/// internal loads and each support's load, each the variant's own
/// summary's, and report.md tabulates them over the variants but for a
/// support that let go at the start.
#[test]
fn a_frame_sweep_reports_member_and_support_loads() {
    let dir = tmp("frame");
    std::fs::write(
        dir.join("frame.toml"),
        r#"
[analysis]
kind = "dynamic"
end_time = 0.22
time_step = 1e-4
spectral_radius = 0.8
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[material]]
name = "cu"
model = "st-venant-kirchhoff"
density = 8900.0
youngs_modulus = 110e9
bending_factor = 0.1
[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7850.0
youngs_modulus = 210e9
poisson_ratio = 0.3
[wire]
length = 2.0
elements = 20
origin = [-1.0, 0.0, 0.2]
layers = [ { material = "cu", outer_radius = 0.01 } ]
[[beam]]
name = "bar"
length = 2.0
elements = 8
origin = [0.0, -1.0, 0.0]
direction = [0.0, 1.0, 0.0]
layers = [ { material = "steel", inner_radius = 0.02, outer_radius = 0.025 } ]
contact_law = "line"
contact_stiffness = 5e8
friction = 0.3
[[support]]
beam = "bar"
node = 0
kind = "fixed"
[[support]]
beam = "bar"
node = "last"
kind = "hinge"
[[support]]
node = 0
kind = "pin"
release_time = 0.0
[output]
every = 100
vtk = false
plots = false
response_frequencies = [20.0]
"#,
    )
    .unwrap();
    let sweep = dir.join("sweep.toml");
    std::fs::write(
        &sweep,
        "scene = \"frame.toml\"\n[parameters]\n\"wire.length\" = [2.0, 2.1]\n",
    )
    .unwrap();
    let out = dir.join("out");
    assert!(sweep_cmd(&sweep, &out, &[]).status().unwrap().success());
    let (header, rows) = results(&out);
    for (k, row) in rows.iter().enumerate() {
        let s = summary(&out.join(format!("runs/v{k:03}")));
        let bar = &s["beams"][0];
        for (col, value) in [
            (
                "bar_first_impact_filtered_peak",
                &bar["first_impact_filtered_peak"],
            ),
            ("bar_max_bending_moment", &bar["max_bending_moment"]),
            ("bar_max_von_mises", &bar["max_von_mises"]),
            (
                "support0_filtered_peak_force",
                &s["supports"][0]["filtered_peak_force"],
            ),
            ("support1_peak_force", &s["supports"][1]["peak_force"]),
            (
                "support0_response_20hz",
                &s["supports"][0]["response"][0]["peak_magnitude"],
            ),
        ] {
            let want = value.as_f64().unwrap();
            assert!(want > 0.0, "{col}: {want}");
            let got: f64 = row[column(&header, col)].parse().unwrap();
            assert!((got - want).abs() <= 1e-9 * want, "{col}: {got} vs {want}");
        }
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for quantity in [
        "| bar: first impact, filtered peak (N) | 2 |",
        "| bar: max von Mises stress (Pa) | 2 |",
        "| support 1 (bar node 8): filtered peak force (N) | 2 |",
        "| support 0 (bar node 0): response at 20 Hz (N) | 2 |",
    ] {
        assert!(report.contains(quantity), "report.md lacks {quantity}");
    }
    // The wire's pin lets go at once: it holds nothing, and report.md
    // leaves it out (results.csv keeps its zeros).
    assert!(!report.contains("support 2"), "{report}");
    let released: f64 = rows[0][column(&header, "support2_filtered_peak_force")]
        .parse()
        .unwrap();
    assert_eq!(released, 0.0);
    let _ = std::fs::remove_dir_all(dir);
}

/// Every sweep file shipped in sweeps/ loads, and each of its variants is
/// a scene that passes its checks (what `ancf sweep` does before any work).
#[test]
fn every_shipped_sweep_loads_with_valid_variants() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let sweep = ancf::sweep::file::load(&path).unwrap_or_else(|e| panic!("{}", e.0));
            assert!(!sweep.variants.is_empty(), "{}", path.display());
            seen += 1;
        }
    }
    assert!(seen >= 3, "only {seen} sweep files in {}", dir.display());
}
