//! The command line as a user runs it: quadrature tables, check, run and its outputs.

use std::path::{Path, PathBuf};
use std::process::Command;

fn ancf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ancf"))
}

/// `ancf run SCENE --out DIR --quiet`, ready to run or spawn.
fn run_quiet(scene: &Path, out: &Path) -> Command {
    let mut c = ancf();
    c.arg("run").arg(scene).arg("--out").arg(out).arg("--quiet");
    c
}

/// A run's `summary.json`.
fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Runs `a` and `b` wrote the same `files` bit for bit, and the same
/// summary.json but for its timings (which differ between any two runs).
fn assert_same_outputs(a: &Path, b: &Path, files: &[&str], when: &str) {
    for file in files {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(x == y, "{file} differs {when}");
    }
    let (mut sa, mut sb) = (summary(a), summary(b));
    for key in ["wall_time_s", "performance"] {
        sa[key] = serde_json::Value::Null;
        sb[key] = serde_json::Value::Null;
    }
    assert_eq!(sa, sb, "summary.json differs {when}");
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ancf-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn quadrature_csv_prints_one_row_per_point() {
    for (inner, outer, order, rows) in [
        ("0", "1", "3", 7),
        ("0.5", "1", "3", 7),
        ("0", "1", "4", 16),
        ("0.01", "0.02", "2", 4),
    ] {
        let out = ancf()
            .args([
                "quadrature",
                "--inner",
                inner,
                "--outer",
                outer,
                "--order",
                order,
                "--format",
                "csv",
            ])
            .output()
            .unwrap();
        assert!(out.status.success());
        let text = String::from_utf8(out.stdout).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("y,z,weight"));
        let pts: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(pts.len(), rows, "{inner}..{outer} order {order}");
        let (r1, r2): (f64, f64) = (inner.parse().unwrap(), outer.parse().unwrap());
        let area: f64 = pts.iter().map(|p| p[2]).sum();
        assert!((area - std::f64::consts::PI * (r2 * r2 - r1 * r1)).abs() < 1e-12 * r2 * r2);
    }
}

#[test]
fn quadrature_refuses_bad_radii() {
    let out = ancf()
        .args(["quadrature", "--inner", "1", "--outer", "0.5"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--inner"));
}

#[test]
fn check_accepts_the_shipped_scenes() {
    for scene in ["scenes/pendulum.toml", "scenes/two_layer_cantilever.toml"] {
        let out = ancf().args(["check", scene]).output().unwrap();
        assert!(
            out.status.success(),
            "{scene}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(String::from_utf8_lossy(&out.stdout).contains("valid"));
    }
}

#[test]
fn dynamic_run_writes_summary_timeseries_and_plot() {
    let dir = tmp("dyn");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/pendulum.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.05");
    let path = dir.join("short.toml");
    std::fs::write(&path, scene).unwrap();
    let out_dir = dir.join("out");
    let out = run_quiet(&path, &out_dir).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = summary(&out_dir);
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["analysis"], "dynamic");
    assert_eq!(summary["elements"], 4);
    assert_eq!(summary["steps"], 50);
    assert!((summary["time"].as_f64().unwrap() - 0.05).abs() < 1e-12);
    for key in ["unknowns", "newton_iterations", "wall_time_s", "message"] {
        assert!(!summary[key].is_null(), "summary lacks {key}");
    }
    assert_eq!(summary["step_cuts"], 0);
    // The steps' cost against one force evaluation and one solve.
    let p = &summary["performance"];
    let us = |k: &str| p[k].as_f64().unwrap();
    assert!(us("force_us") > 0.0 && us("solve_us") > 0.0, "{p}");
    assert!(us("step_us") > us("force_us") + us("solve_us"), "{p}");
    let ratio = us("step_us") / (us("force_us") + us("solve_us"));
    assert!((us("limit_ratio") - ratio).abs() < 1e-9 * ratio, "{p}");
    assert!(us("iterations_per_step") >= 1.0, "{p}");
    // The Newton method's own work: every evaluation, solve, Jacobian and
    // factorization at its mean time, a part of the whole step.
    let per_step = |k: &str| summary[k].as_f64().unwrap() / 50.0;
    assert!(
        us("jacobian_us") > 0.0 && us("factorization_us") > 0.0,
        "{p}"
    );
    assert!(us("evaluations_per_step") >= 1.0, "{p}");
    let newton = us("evaluations_per_step") * us("force_us")
        + us("iterations_per_step") * us("solve_us")
        + per_step("factorizations") * (us("jacobian_us") + us("factorization_us"));
    let newton_ratio = newton / (us("force_us") + us("solve_us"));
    assert!(
        (us("newton_ratio") - newton_ratio).abs() < 1e-9 * newton_ratio,
        "{p}"
    );
    assert!(us("newton_ratio") < us("limit_ratio"), "{p}");
    assert!(!String::from_utf8_lossy(&out.stderr).contains("note:"));
    assert_eq!(summary["tip"]["position"].as_array().unwrap().len(), 3);
    assert_eq!(summary["tip"]["displacement"].as_array().unwrap().len(), 3);
    for key in ["kinetic", "strain", "gravity", "total", "max_drift"] {
        assert!(summary["energy"][key].is_f64(), "energy.{key}");
    }
    let ts = std::fs::read_to_string(out_dir.join("timeseries.csv")).unwrap();
    assert!(ts.starts_with("time,tip_x,tip_y,tip_z,kinetic,strain,gravity,total"));
    assert_eq!(
        ts.lines().count(),
        12,
        "header + t=0 + every 5th of 50 steps"
    );
    assert!(out_dir.join("energy.png").metadata().unwrap().len() > 1000);
    assert!(out_dir.join("final_nodes.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run whose steps Newton cannot finish in the iterations allowed is cut
/// into halves: summary.json counts the cuts and the terminal says so.
#[test]
fn a_run_with_step_cuts_says_so() {
    let dir = tmp("cuts");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.06")
        .replace("elements = 64", "elements = 8")
        .replace("time_step = 1e-4", "time_step = 2e-3")
        .replace("tolerance = 1e-4", "tolerance = 1e-10\nmax_iterations = 3");
    let path = dir.join("strained.toml");
    std::fs::write(&path, scene).unwrap();
    let out_dir = dir.join("out");
    let out = run_quiet(&path, &out_dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let summary = summary(&out_dir);
    let cuts = summary["step_cuts"].as_u64().unwrap();
    assert!(cuts > 0, "{summary}");
    let note = format!("note: {cuts} step attempt(s) rejected and cut in halves (so many");
    assert!(stderr.contains(&note), "{stderr}");
    assert!(
        summary["message"]
            .as_str()
            .unwrap()
            .contains("reduce analysis.time_step")
    );
    // The rejected attempts' iterations are counted: more than the steps' own.
    assert!(summary["newton_iterations"].as_u64().unwrap() > 3 * 30);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A time step that does not resolve a rod's contact is named before the
/// run: by `check` and by `run` on the terminal (quiet or not) and in
/// summary.json; the shipped scene says nothing.
#[test]
fn an_unresolved_contact_is_named_before_the_run() {
    let dir = tmp("unresolved");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.01")
        .replace("contact_stiffness = 5e7", "contact_stiffness = 5e9");
    let path = dir.join("stiff.toml");
    std::fs::write(&path, scene).unwrap();
    let warning = "warning: analysis.time_step = 1e-4 s does not resolve rod 0's line contact";
    let check = ancf().arg("check").arg(&path).output().unwrap();
    let stderr = String::from_utf8_lossy(&check.stderr);
    assert!(
        check.status.success() && stderr.contains(warning),
        "{stderr}"
    );
    // The verdict, last, counts them.
    let stdout = String::from_utf8_lossy(&check.stdout);
    assert!(stdout.contains(": valid, 1 warning ("), "{stdout}");
    let out_dir = dir.join("out");
    let run = run_quiet(&path, &out_dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success() && stderr.contains(warning), "{stderr}");
    let warnings = summary(&out_dir)["warnings"].clone();
    assert_eq!(warnings.as_array().map(Vec::len), Some(1), "{warnings}");
    assert!(
        warnings[0]
            .as_str()
            .unwrap()
            .contains("a time step ≤ 5.36e-5 s resolves it")
    );
    let shipped = ancf()
        .arg("check")
        .arg("scenes/wire_rod_impact.toml")
        .output()
        .unwrap();
    assert!(!String::from_utf8_lossy(&shipped.stderr).contains("warning"));
    assert!(String::from_utf8_lossy(&shipped.stdout).contains(": valid, 0 warnings ("));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn static_run_reports_the_tip() {
    let dir = tmp("static");
    let out = run_quiet(Path::new("scenes/two_layer_cantilever.toml"), &dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let summary = summary(&dir);
    assert_eq!(summary["status"], "completed");
    let dz = summary["tip"]["displacement"][2].as_f64().unwrap();
    let theory = 1.0 / (3.0 * 2e9 * std::f64::consts::PI * 0.02f64.powi(4) / 4.0);
    assert!(((-dz - theory) / theory).abs() < 5e-3, "{dz} vs {theory}");
    let nodes = std::fs::read_to_string(dir.join("final_nodes.csv")).unwrap();
    assert!(nodes.starts_with("node,x,y,z"));
    assert_eq!(nodes.lines().count(), 1 + 17);
    // The summary says what computed it, as `ancf --version` does.
    let build = &summary["build"];
    assert_eq!(build["version"], env!("CARGO_PKG_VERSION"));
    let commit = build["commit"].as_str().unwrap();
    assert!(commit == "unknown" || commit.len() == 40, "{commit}");
    assert!(build["rustc"].as_str().unwrap().starts_with("rustc "));
    assert!(build["dirty"].is_boolean());
    assert!(!build["kernel_orders"].as_array().unwrap().is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn version_names_the_commit_the_compiler_and_the_kernels() {
    for flag in ["--version", "-V"] {
        let out = ancf().arg(flag).output().unwrap();
        assert!(out.status.success());
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.starts_with(&format!("ancf {} (commit ", env!("CARGO_PKG_VERSION"))),
            "{text}"
        );
        assert!(
            text.contains("rustc ") && text.contains("kernels for axial orders"),
            "{text}"
        );
    }
}

#[test]
fn impact_run_writes_contact_outputs_vtk_and_plots() {
    let dir = tmp("impact");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.3")
        .replace("every = 50", "every = 100");
    let path = dir.join("impact.toml");
    std::fs::write(&path, scene).unwrap();
    let out_dir = dir.join("out");
    let out = run_quiet(&path, &out_dir).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = summary(&out_dir);
    let contact = &summary["contact"];
    let first = contact["first_time"]
        .as_f64()
        .expect("the wire hits the rod before 0.3 s");
    assert!(first > 0.2 && first < 0.3, "{first}");
    assert!(contact["max_normal_force"].as_f64().unwrap() > 0.0);
    assert!(contact["max_penetration"].as_f64().unwrap() > 0.0);
    let ts = std::fs::read_to_string(out_dir.join("timeseries.csv")).unwrap();
    let header = ts.lines().next().unwrap();
    for col in [
        "contact_force",
        "penetration",
        "contact_energy",
        "dissipated",
    ] {
        assert!(
            header.split(',').any(|c| c == col),
            "timeseries lacks {col}"
        );
    }
    let pvd = std::fs::read_to_string(out_dir.join("vtk/wire.pvd")).unwrap();
    assert_eq!(
        pvd.matches("part=\"0\"").count(),
        31,
        "frames at t = 0 and every 100 steps"
    );
    assert_eq!(pvd.matches("rod_0.vtu").count(), 31);
    let vtu = std::fs::read_to_string(out_dir.join("vtk/wire_000003.vtu")).unwrap();
    for name in ["displacement", "velocity", "green_lagrange_strain", "twist"] {
        assert!(
            vtu.contains(&format!("Name=\"{name}\"")),
            "vtu lacks {name}"
        );
    }
    // 64 elements × 4 stations + 1 rings of 16 points.
    assert!(vtu.contains("NumberOfPoints=\"4112\""));
    // Per-rod loads, raw and filtered, at every step.
    let rod = &contact["rods"][0];
    assert_eq!(rod["law"], "line");
    for key in [
        "peak_force",
        "filtered_peak_force",
        "impulse",
        "contact_duration",
        "cfc",
    ] {
        assert!(
            rod[key].as_f64().is_some_and(|v| v > 0.0),
            "rods[0].{key}: {rod}"
        );
    }
    let rf = std::fs::read_to_string(out_dir.join("rod_forces.csv")).unwrap();
    assert!(rf.starts_with("time,rod0_force,rod0_filtered,rod0_fx,rod0_fy,rod0_fz\n"));
    assert_eq!(rf.lines().count(), 3001, "a row per step (3000 steps)");
    for png in [
        "energy.png",
        "configurations.png",
        "contact_point.png",
        "rod_forces.png",
    ] {
        assert!(out_dir.join(png).metadata().unwrap().len() > 5000, "{png}");
    }
    let cp = std::fs::read_to_string(out_dir.join("contact_point.csv")).unwrap();
    assert!(cp.starts_with("time,dz,exx,eyy,ezz"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bench_json_has_the_documented_keys() {
    let out = ancf()
        .args(["bench", "--quick", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "force_us",
        "jacobian_us",
        "step_ms_32_full_newton",
        "parallel_speedup_256",
        "impact_realtime_factor",
        "impact_limit_ratio",
        "impact_newton_ratio",
        "span_break_limit_ratio",
        "span_break_newton_ratio",
    ] {
        assert!(
            v[key].as_f64().is_some_and(|x| x > 0.0 && x.is_finite()),
            "{key}: {}",
            v[key]
        );
    }
    for n in ["4", "16", "32"] {
        assert!(
            v["step_ms"][n].as_f64().is_some_and(|x| x > 0.0),
            "step_ms[{n}]"
        );
    }
}

/// Ctrl-C keeps everything computed so far and says so.
#[test]
fn interrupted_run_keeps_its_output() {
    let dir = tmp("interrupt");
    let mut child = run_quiet(Path::new("scenes/wire_rod_impact.toml"), &dir)
        .spawn()
        .unwrap();
    // Wait until a few rows exist, then interrupt.
    let series = dir.join("timeseries.csv");
    for _ in 0..200 {
        std::thread::sleep(std::time::Duration::from_millis(50));
        if std::fs::read_to_string(&series)
            .map(|t| t.lines().count() > 3)
            .unwrap_or(false)
        {
            break;
        }
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let summary = summary(&dir);
    assert_eq!(summary["status"], "interrupted");
    let message = summary["message"].as_str().unwrap();
    assert!(
        message.contains("stopped by Ctrl-C")
            && message.contains(&format!("ancf run --resume {}", dir.display())),
        "{message}"
    );
    let t = summary["time"].as_f64().unwrap();
    assert!(t > 0.0 && t < 1.0, "stopped early at {t}");
    let rows = std::fs::read_to_string(&series).unwrap().lines().count();
    assert!(rows > 3, "time series kept ({rows} lines)");
    assert!(dir.join("vtk/wire.pvd").exists() && dir.join("final_nodes.csv").exists());
    assert!(
        !dir.join(".ancf.lock").exists(),
        "an interrupted run leaves its lock file"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// timeseries.csv removed while the run writes it: the run ends with
/// every other output and says, in summary.json's warnings and under
/// `--strict`, that its rows are lost.
#[test]
fn a_time_series_removed_during_the_run_is_said_to_be_lost() {
    let dir = tmp("lost-series");
    let mut child = run_quiet(Path::new("scenes/wire_rod_impact.toml"), &dir)
        .arg("--strict")
        .spawn()
        .unwrap();
    let series = dir.join("timeseries.csv");
    for _ in 0..200 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        if std::fs::read_to_string(&series).is_ok_and(|t| t.lines().count() > 3) {
            break;
        }
    }
    std::fs::remove_file(&series).unwrap();
    let status = child.wait().unwrap();
    assert!(!status.success(), "--strict fails on the lost file");
    let summary = summary(&dir);
    assert_eq!(summary["status"], "completed");
    let warned = (summary["warnings"].as_array().unwrap().iter()).any(|w| {
        w.as_str()
            .unwrap()
            .contains("timeseries.csv was removed while the run wrote it")
    });
    assert!(warned, "{}", summary["warnings"]);
    assert!(dir.join("final_nodes.csv").exists() && dir.join("rod_forces.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// An output that cannot be written at the run's end (here a folder
/// planted where rod_forces.csv goes) fails the run naming that file, and
/// summary.json still keeps what the run computed.
#[test]
fn an_output_that_cannot_be_written_is_named_and_the_summary_kept() {
    let dir = tmp("unwritable");
    let child = run_quiet(Path::new("scenes/wire_rod_impact.toml"), &dir)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let series = dir.join("timeseries.csv");
    for _ in 0..200 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        if std::fs::read_to_string(&series).is_ok_and(|t| t.lines().count() > 3) {
            break;
        }
    }
    std::fs::create_dir(dir.join("rod_forces.csv")).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let file = dir.join("rod_forces.csv");
    assert!(stderr.contains(&file.display().to_string()), "{stderr}");
    let summary = summary(&dir);
    assert_eq!(summary["status"], "failed");
    assert!(
        summary["message"]
            .as_str()
            .unwrap()
            .contains("rod_forces.csv")
    );
    assert!(
        summary["contact"]["rods"][0]["filtered_peak_force"]
            .as_f64()
            .is_some_and(|f| f > 0.0)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run interrupted after a checkpoint and continued with
/// `ancf run --resume DIR` ends bit for bit like an uninterrupted run.
#[test]
fn resumed_run_equals_uninterrupted_run_bit_for_bit() {
    let dir = tmp("resume");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.4")
        .replace("every = 50 ", "every = 50\ncheckpoint_every = 700 ");
    assert!(scene.contains("checkpoint_every = 700"));
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    let run = |out: &Path| run_quiet(&path, out).output().unwrap();
    assert!(run(&a).status.success());
    let mut child = run_quiet(&path, &b).spawn().unwrap();
    for _ in 0..400 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        if b.join("checkpoint.json").exists() {
            break;
        }
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert_eq!(
        child.wait().unwrap().code(),
        Some(130),
        "the run must still be going when interrupted"
    );
    let resumed = ancf()
        .args(["run", "--resume", b.to_str().unwrap(), "--quiet"])
        .output()
        .unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_same_outputs(
        &a,
        &b,
        &[
            "final_nodes.csv",
            "timeseries.csv",
            "rod_forces.csv",
            "vtk/wire.pvd",
        ],
        "after resuming",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Static contact with every law. A stiff wire pinned at x = 0
/// rests on a rod at x = a under its weight W: the rod carries W (L/2)/a
/// (moment about the pin), reported as the rod's peak force of the static run.
#[test]
fn static_contact_balances_the_weight_with_every_law() {
    let dir = tmp("static-contact");
    std::fs::create_dir_all(&dir).unwrap();
    let (length, radius, rod_radius, a, density) = (1.0, 0.01, 0.03, 0.75, 7850.0);
    let weight = density * std::f64::consts::PI * radius * radius * length * 9.81;
    let expected = weight * 0.5 * length / a;
    for (law, rod_keys) in [
        ("line", "contact_law = \"line\"\ncontact_stiffness = 1e8"),
        ("hertz", "contact_law = \"hertz\"\nmaterial = \"steel\""),
        (
            "surface",
            "contact_law = \"surface\"\ncontact_stiffness = 1e12",
        ),
    ] {
        let scene = format!(
            "[analysis]\nkind = \"static\"\nload_steps = 2\n\n[gravity]\nacceleration = [0.0, 0.0, -9.81]\n\n\
             [[material]]\nname = \"steel\"\nmodel = \"st-venant-kirchhoff\"\ndensity = {density}\n\
             youngs_modulus = 2e11\npoisson_ratio = 0.3\n\n\
             [wire]\nlength = {length}\nelements = 8\nlayers = [ {{ material = \"steel\", outer_radius = {radius} }} ]\n\n\
             [[support]]\nnode = 0\nkind = \"pin\"\n\n\
             [[rod]]\ncenter = [{a}, 0.0, {z}]\naxis = [0.0, 1.0, 0.0]\nradius = {rod_radius}\n{rod_keys}\n",
            // 1 mm of initial overlap: the pinned wire is a mechanism until it
            // touches. (With 0.1 mm the line laws still hold, but no surface
            // test point overlaps the rod, Newton meets a free rotation and
            // the wire swings through the rod to hang from the pin.)
            z = -(radius + rod_radius) + 1e-3,
        );
        let path = dir.join(format!("{law}.toml"));
        std::fs::write(&path, scene).unwrap();
        let out_dir = dir.join(law);
        let st = run_quiet(&path, &out_dir).status().unwrap();
        assert!(st.success(), "{law}");
        let s = summary(&out_dir);
        assert_eq!(s["status"], "completed", "{law}: {}", s["message"]);
        let rod = &s["contact"]["rods"][0];
        assert_eq!(rod["law"], law);
        let force = rod["peak_force"].as_f64().unwrap();
        println!("{law}: rod force {force:.5} N, expected {expected:.5} N");
        // Line laws: 7e-5 (the wire's slope on the rod). Surface law: its test
        // stations sit 2.5 mm either side of the rod's axis, so the contact
        // normals tilt and the resultant is 0.8 % high.
        let tolerance = if law == "surface" { 1e-2 } else { 2e-4 };
        assert!(
            (force - expected).abs() < tolerance * expected,
            "{law}: {force} vs {expected}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// An output folder belongs to one run at a time: a second run into it is
/// refused naming the first's process; a lock left by a killed run is
/// taken over; a new run removes the outputs an earlier run left there
/// (a static run after a dynamic one keeps no time series), and nothing
/// else.
#[test]
fn one_run_per_output_folder() {
    let out = tmp("lock");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/wire_rod_impact.toml");
    let mut first = run_quiet(&scene, &out).spawn().unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    while !std::fs::read_to_string(out.join(".ancf.lock"))
        .is_ok_and(|t| t.trim() == first.id().to_string())
    {
        assert!(
            std::time::Instant::now() < deadline,
            "the run never locked its folder"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let second = run_quiet(&scene, &out).output().unwrap();
    assert!(!second.status.success());
    let message = String::from_utf8_lossy(&second.stderr);
    assert!(
        message.contains(&format!("process {}", first.id())) && message.contains("--out"),
        "{message}"
    );
    // Killed: the lock goes with the process, and the next run takes over.
    first.kill().unwrap();
    first.wait().unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let static_scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cantilever_large_deflection.toml");
    assert!(run_quiet(&static_scene, &out).status().unwrap().success());
    assert_eq!(summary(&out)["status"], "completed");
    assert!(
        !out.join(".ancf.lock").exists(),
        "a completed run leaves its lock file"
    );
    for stale in ["timeseries.csv", "rod_forces.csv", "checkpoint.json", "vtk"] {
        assert!(
            !out.join(stale).exists(),
            "{stale} of the killed run was left"
        );
    }
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A run without rods guards its energy too: the pendulum with Newton
/// stopped far from convergence (tolerance 0.3) at 20 ms steps gains
/// energy (about 5 J at every tolerance from 0.1 to 0.5; at 10 ms steps
/// the sign of the change depends on the tolerance), and its summary says
/// so in `warnings` and the message; the scene as shipped does not.
#[test]
fn a_run_that_gains_energy_says_so() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/pendulum.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let loose = text
        .replace("time_step = 1e-3 ", "time_step = 2e-2 ")
        .replace(
            "spectral_radius = 1.0 ",
            "spectral_radius = 1.0\ntolerance = 0.3 ",
        );
    let dir = tmp("energy-gain");
    std::fs::create_dir_all(&dir).unwrap();
    let edited = dir.join("loose.toml");
    std::fs::write(&edited, loose).unwrap();
    for (path, gains) in [(&edited, true), (&scene, false)] {
        let out = dir.join(if gains { "loose" } else { "shipped" });
        assert!(run_quiet(path, &out).status().unwrap().success());
        let s = summary(&out);
        assert_eq!(s["status"], "completed");
        let warned = s["warnings"].as_array().is_some_and(|w| {
            w.iter().any(|w| {
                w.as_str()
                    .unwrap()
                    .starts_with("energy: total + dissipated rose")
            })
        });
        assert_eq!(warned, gains, "{s}");
        assert_eq!(
            s["message"].as_str().unwrap().contains("warning: energy"),
            gains
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--resume` verifies what it reads back: a checkpoint with one digit
/// changed (its checksum no longer matches), of another format version, or
/// a timeseries.csv cut short behind its back are refused before any work,
/// naming the file; the untouched checkpoint resumes.
#[test]
fn a_damaged_checkpoint_is_refused() {
    let dir = tmp("damaged");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.2")
        .replace("every = 50 ", "every = 50\ncheckpoint_every = 500 ");
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let good = dir.join("good");
    assert!(run_quiet(&path, &good).status().unwrap().success());
    let copy = |name: &str| {
        let to = dir.join(name);
        std::fs::create_dir_all(&to).unwrap();
        for f in ["checkpoint.json", "timeseries.csv"] {
            std::fs::copy(good.join(f), to.join(f)).unwrap();
        }
        to
    };
    let resume = |d: &Path| {
        ancf()
            .args(["run", "--resume", d.to_str().unwrap(), "--quiet"])
            .output()
            .unwrap()
    };
    let text = std::fs::read_to_string(good.join("checkpoint.json")).unwrap();
    // One digit of the state changed.
    let flipped = copy("flipped");
    let at = text.find("\"q\":[").unwrap() + 8;
    let mut bytes = text.clone().into_bytes();
    let k = (at..)
        .find(|&i| bytes[i].is_ascii_digit() && bytes[i] != b'7')
        .unwrap();
    bytes[k] = b'7';
    std::fs::write(flipped.join("checkpoint.json"), bytes).unwrap();
    // Another format version.
    let versioned = copy("versioned");
    std::fs::write(
        versioned.join("checkpoint.json"),
        text.replacen("\"version\":2", "\"version\":1", 1),
    )
    .unwrap();
    // The time series cut to its first 5 rows.
    let cut = copy("cut");
    let series = std::fs::read_to_string(cut.join("timeseries.csv")).unwrap();
    let head: Vec<&str> = series.lines().take(6).collect();
    std::fs::write(cut.join("timeseries.csv"), head.join("\n") + "\n").unwrap();
    for (d, expect) in [
        (&flipped, "checkpoint.json: checksum does not match"),
        (&versioned, "checkpoint.json: version is 1"),
        (&cut, "timeseries.csv: 5 rows"),
    ] {
        let out = resume(d);
        let message = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && message.contains(expect),
            "{message}"
        );
        assert!(!d.join("summary.json").exists(), "no work was done");
    }
    let untouched = copy("untouched");
    let out = resume(&untouched);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A wire the machine cannot hold is refused by `ancf check` before any
/// work, naming the field and the element count that would fit (where the
/// machine has less than the 56 GB a million elements need).
#[test]
fn a_wire_too_large_for_the_memory_is_refused_before_work() {
    let needed = ancf_core::model::memory::needed_bytes(999_999);
    if ancf_core::model::memory::available_bytes().is_none_or(|a| a >= needed) {
        return;
    }
    let dir = tmp("memory");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("scenes/pendulum.toml")
        .unwrap()
        .replace("elements = 4\n", "elements = 999999\n");
    let path = dir.join("big.toml");
    std::fs::write(&path, text).unwrap();
    let out = ancf().arg("check").arg(&path).output().unwrap();
    let message = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{message}");
    assert!(
        message.contains("wire.elements: 999999 elements need about")
            && message.contains("elements fit"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A failed solve names what made it hard: a Mooney–Rivlin cover with
/// κ = 1e9 is blamed on the penalty, not on the load steps.
#[test]
fn a_locking_penalty_is_named_as_the_cause() {
    let dir = tmp("penalty");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("scenes/two_layer_cantilever.toml")
        .unwrap()
        .replace(
            "[wire]",
            "[[material]]\nname = \"rubber\"\nmodel = \"mooney-rivlin\"\ndensity = 1100.0\n\
             mu10 = 5e5\nmu01 = 1e5\npenalty = 1e9\n\n[wire]",
        )
        .replace(
            "{ material = \"core\", outer_radius = 0.02 }",
            "{ material = \"rubber\", outer_radius = 0.02 }",
        )
        .replace("force = [0.0, 0.0, -1.0]", "force = [0.0, 0.0, -2000.0]");
    assert!(text.contains("\"rubber\", outer_radius"));
    let path = dir.join("locking.toml");
    std::fs::write(&path, text).unwrap();
    let out = dir.join("out");
    assert!(!run_quiet(&path, &out).status().unwrap().success());
    assert!(
        !out.join(".ancf.lock").exists(),
        "a failed run leaves its lock file"
    );
    let s = summary(&out);
    let message = s["message"].as_str().unwrap();
    assert!(
        message.contains("Likely cause: the Mooney–Rivlin volume penalty κ = 1.0e9 is beyond 1e7"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Results do not depend on how often a run checkpoints: the impact scene
/// to 0.3 s with checkpoint_every 0, 7 and 1000 writes the same time
/// series and rod forces, bit for bit (a checkpoint keeps where the Newton
/// matrix was factored, so the run goes on as without one).
#[test]
fn results_do_not_depend_on_checkpoint_every() {
    let dir = tmp("checkpoint-every");
    std::fs::create_dir_all(&dir).unwrap();
    let mut outputs = Vec::new();
    for every in [0, 7, 1000] {
        let text = std::fs::read_to_string("scenes/wire_rod_impact.toml")
            .unwrap()
            .replace("end_time = 1.0", "end_time = 0.3")
            .replace(
                "every = 50 ",
                &format!("every = 50\ncheckpoint_every = {every} "),
            );
        let path = dir.join(format!("c{every}.toml"));
        std::fs::write(&path, text).unwrap();
        let out = dir.join(format!("c{every}"));
        assert!(run_quiet(&path, &out).status().unwrap().success());
        let read = |f: &str| std::fs::read(out.join(f)).unwrap();
        outputs.push((read("timeseries.csv"), read("rod_forces.csv")));
    }
    for o in &outputs[1..] {
        assert!(o.0 == outputs[0].0, "timeseries.csv differs");
        assert!(o.1 == outputs[0].1, "rod_forces.csv differs");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Killed with SIGKILL five times at different moments and resumed each
/// time, a run that checkpoints every 37 steps ends with the outputs of an
/// uninterrupted run, bit for bit.
#[test]
fn five_kills_and_resumes_end_as_an_uninterrupted_run() {
    let dir = tmp("kills");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.3")
        .replace(
            "every = 50 ",
            "every = 50\ncheckpoint_every = 37\nvtk = false ",
        );
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let (whole, killed) = (dir.join("whole"), dir.join("killed"));
    assert!(run_quiet(&path, &whole).status().unwrap().success());
    let resume = || {
        let mut c = ancf();
        c.args(["run", "--resume", killed.to_str().unwrap(), "--quiet"]);
        c
    };
    for (round, wait_ms) in [15u64, 60, 25, 90, 40].into_iter().enumerate() {
        let mut child = if round == 0 {
            run_quiet(&path, &killed).spawn().unwrap()
        } else {
            resume().spawn().unwrap()
        };
        // A checkpoint must exist before the first kill (else nothing resumes).
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while !killed.join("checkpoint.json").exists() {
            assert!(std::time::Instant::now() < deadline, "no checkpoint");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        std::thread::sleep(std::time::Duration::from_millis(wait_ms));
        let _ = child.kill();
        child.wait().unwrap();
    }
    let last = resume().output().unwrap();
    assert!(
        last.status.success(),
        "{}",
        String::from_utf8_lossy(&last.stderr)
    );
    assert_same_outputs(
        &whole,
        &killed,
        &[
            "timeseries.csv",
            "rod_forces.csv",
            "final_nodes.csv",
            "supports.csv",
        ],
        "after five kills",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An adaptive run's ParaView frames come by time: one each fiftieth of
/// the run, whatever its steps (a count of steps is not known ahead).
#[test]
fn adaptive_runs_write_a_frame_each_fiftieth_of_the_run() {
    let dir = tmp("vtk-adaptive");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("scenes/pendulum.toml")
        .unwrap()
        .replace(
            "time_step = 1e-3 ",
            "time_step = \"auto\"\nerror_tolerance = 1e-4 ",
        );
    assert!(scene.contains("\"auto\""));
    let path = dir.join("auto.toml");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out");
    let run = run_quiet(&path, &out).output().unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let pvd = std::fs::read_to_string(out.join("vtk/wire.pvd")).unwrap();
    let times: Vec<f64> = pvd
        .lines()
        .filter_map(|l| l.split("timestep=\"").nth(1))
        .map(|t| t.split('"').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 51, "t = 0 and one per 0.02 s: {times:?}");
    assert_eq!((times[0], times[50]), (0.0, 1.0));
    // Each frame is the first state at or past its fiftieth, and the steps
    // are far shorter than a fiftieth (≤ end_time / 100).
    for (k, t) in times.iter().enumerate().skip(1) {
        let due = k as f64 * 0.02;
        assert!(*t >= due - 1e-12 && *t < due + 0.01, "frame {k} at {t} s");
    }
    let steps = summary(&out)["steps"].as_u64().unwrap();
    assert!(steps != 1000 && steps > 100, "{steps} steps");
    let _ = std::fs::remove_dir_all(&dir);
}

/// ParaView frames: at most 50 over a run unless `output.vtk_every` asks
/// for more (a multiple of `output.every`, else refused naming the field).
#[test]
fn vtk_frames_follow_their_budget_or_vtk_every() {
    let dir = tmp("vtk-every");
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string("scenes/wire_rod_impact.toml")
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.3")
        .replace("every = 50 ", "every = 1 ");
    let frames = |extra: &str, name: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(
            &path,
            base.replace("every = 1 ", &format!("every = 1\n{extra} ")),
        )
        .unwrap();
        let out = dir.join(name);
        let run = run_quiet(&path, &out).output().unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        std::fs::read_dir(out.join("vtk"))
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                name.to_string_lossy().starts_with("wire_")
            })
            .count()
    };
    // 3000 steps: a frame every 60 steps, 0 … 3000.
    assert_eq!(frames("", "budget"), 51);
    assert_eq!(frames("vtk_every = 1000", "every_1000"), 4);
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        base.replace("every = 1 ", "every = 2\nvtk_every = 3 "),
    )
    .unwrap();
    let check = ancf().arg("check").arg(&path).output().unwrap();
    assert_eq!(check.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&check.stderr);
    assert!(
        stderr.contains("output.vtk_every: must be a positive multiple of output.every (2), got 3"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Shell completions and manual pages come from the command definitions.
#[test]
fn completions_and_manual_pages() {
    for shell in ["bash", "zsh", "fish"] {
        let out = ancf().args(["completions", shell]).output().unwrap();
        assert!(out.status.success(), "{shell}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.contains("ancf") && text.contains("sweep") && text.contains("strict"),
            "{shell}"
        );
    }
    let page = ancf().arg("man").output().unwrap();
    assert!(page.status.success());
    let text = String::from_utf8_lossy(&page.stdout);
    assert!(
        text.contains(".TH ancf 1") && text.contains("quadrature"),
        "{text}"
    );
    let run = ancf().args(["man", "run"]).output().unwrap();
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains(".TH ancf-run 1") && text.contains("strict"),
        "{text}"
    );
    let bad = ancf().args(["man", "nope"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
}

/// Both span-break scenes keep the wire on their ground: the falling span
/// reaches it at t ≈ 1.2 s and no point of it goes deeper than the wire's
/// radius (the run's first 1.5 s hold the ground's blow and the deepest
/// point; the summary says how deep).
#[test]
fn the_span_break_scenes_hold_the_wire_on_their_ground() {
    let radius = 0.01407;
    for name in ["span_break_frame", "span_break_elastic_frame"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.contains("end_time = 2.5") && text.contains("[[ground]]"));
        let text = text
            .replace("end_time = 2.5", "end_time = 1.5")
            .replace("[output]", "[output]\nvtk = false\nplots = false");
        let dir = tmp(&format!("ground-{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, text).unwrap();
        let out = dir.join("out");
        let status = run_quiet(&scene, &out).status().unwrap();
        assert!(status.success(), "{name}");
        let s = summary(&out);
        // The conductor's layers (ω = 0.1) report the continuum's strain.
        assert_eq!(
            s["strains"][0]["layer_strains"],
            serde_json::json!(["continuum", "continuum"])
        );
        let ground = &s["contact"]["ground"][0];
        let (depth, first) = (
            ground["max_depth"].as_f64().unwrap(),
            ground["first_contact_time"].as_f64().unwrap(),
        );
        assert!(
            depth > 0.0 && depth < radius,
            "{name}: the wire went {depth} m into the ground"
        );
        assert!((1.1..1.3).contains(&first), "{name}: touched at {first} s");
        assert!(ground["filtered_peak_force"].as_f64().unwrap() > 0.0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// A clamped S235 tube cantilever, Ø 100 × 4 mm, 2 m, under a tip load
/// `p` N, with the wire held clear of it; static.
fn cantilever_tube_scene(p: f64) -> String {
    format!(
        r#"
[analysis]
kind = "static"

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7850.0
youngs_modulus = 210e9
yield_stress = 235e6

[wire]
length = 1.0
elements = 2
layers = [{{ material = "steel", outer_radius = 0.01 }}]

[[support]]
node = 0
kind = "fixed"

[[support]]
node = "last"
kind = "fixed"

[[beam]]
name = "tube"
length = 2.0
elements = 8
origin = [0.0, 5.0, 0.0]
direction = [1.0, 0.0, 0.0]
layers = [{{ material = "steel", inner_radius = 0.046, outer_radius = 0.05 }}]

[[support]]
beam = "tube"
node = 0
kind = "clamp"

[[load]]
beam = "tube"
node = "last"
force = [0.0, 0.0, -{p}]

[output]
plots = false
vtk = false
"#
    )
}

/// The tube's utilization is its root moment over M_pl,Rd = W_pl f_y
/// (EN 1993-1-1, no axial force); past f_y the run warns, naming the beam,
/// and `--strict` fails it.
#[test]
fn a_tube_member_reports_its_utilization_and_warns_past_yield() {
    let dir = tmp("utilization");
    std::fs::create_dir_all(&dir).unwrap();
    let w_pl = (0.1f64.powi(3) - 0.092f64.powi(3)) / 6.0;
    let m_pl = w_pl * 235e6;
    for (p, yields) in [(2000.0, false), (4000.0, true)] {
        let scene = dir.join(format!("tube_{p}.toml"));
        std::fs::write(&scene, cantilever_tube_scene(p)).unwrap();
        let out = dir.join(format!("out_{p}"));
        assert!(run_quiet(&scene, &out).status().unwrap().success());
        let s = summary(&out);
        let tube = &s["beams"][0];
        // Solid layers (ω = 1) report their own fibres' strain.
        assert_eq!(
            s["strains"][1]["layer_strains"],
            serde_json::json!(["material"])
        );
        let u = tube["utilization"].as_f64().unwrap();
        let expected = p * 2.0 / m_pl;
        assert!(
            (u - expected).abs() < 5e-3 * expected,
            "P = {p} N: utilization {u}, P L / M_pl = {expected}"
        );
        assert!(
            tube["utilization_at"].as_f64().unwrap() < 1e-9,
            "at the root"
        );
        let warned = s["warnings"].as_array().is_some_and(|w| {
            w.iter()
                .any(|w| w.as_str().unwrap().contains("beam \"tube\""))
        });
        assert_eq!(warned, yields, "P = {p} N: {:?}", s["warnings"]);
        let strict = run_quiet(&scene, &dir.join(format!("strict_{p}")))
            .arg("--strict")
            .status()
            .unwrap();
        assert_eq!(strict.success(), !yields, "P = {p} N under --strict");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A yielding member's permanent set is its spring-back with the load and
/// the wire taken away: the static tube cantilever loaded to 0.95 M_p / L
/// keeps a set at its tip, below its deflection under the load; the same
/// tube elastic reports none.
#[test]
fn a_yielding_member_reports_its_permanent_set() {
    let dir = tmp("permanent-set");
    std::fs::create_dir_all(&dir).unwrap();
    let m_pl = (0.1f64.powi(3) - 0.092f64.powi(3)) / 6.0 * 235e6;
    let elastic = cantilever_tube_scene(0.95 * m_pl / 2.0)
        .replace("kind = \"static\"", "kind = \"static\"\nload_steps = 10");
    let plastic = elastic.replace(
        "model = \"st-venant-kirchhoff\"",
        "model = \"elastic-plastic\"\npoisson_ratio = 0.3",
    );
    for (name, text) in [("elastic", &elastic), ("plastic", &plastic)] {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.join(name);
        assert!(run_quiet(&scene, &out).status().unwrap().success());
        let s = summary(&out);
        let tube = &s["beams"][0];
        if name == "elastic" {
            assert!(tube.get("permanent_set").is_none(), "{tube}");
            continue;
        }
        let set = tube["permanent_set"].as_f64().unwrap();
        let loaded = tube["end_displacement"].as_f64().unwrap();
        assert!(
            set > 1e-3 && set < 0.5 * loaded,
            "set {set} m, loaded {loaded} m"
        );
        assert!((tube["permanent_set_at"].as_f64().unwrap() - 2.0).abs() < 1e-12);
        assert!(tube.get("end_speed").is_none(), "a static run has no speed");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// final_nodes.csv gives each node's gradients after its position: a bar
/// twisted by a tip torque shows its sections turned by T L / (G J) in
/// the r_y and r_z columns, half of it halfway.
#[test]
fn final_nodes_give_the_sections_orientation() {
    let dir = tmp("final-gradients");
    std::fs::create_dir_all(&dir).unwrap();
    let (l, r, e, t) = (1.0_f64, 0.01_f64, 2e11_f64, 20.0_f64);
    let scene = format!(
        r#"
[analysis]
kind = "static"

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = {e}

[wire]
length = {l}
elements = 8
layers = [{{ material = "steel", outer_radius = {r} }}]

[[support]]
node = 0
kind = "clamp"

[[load]]
node = "last"
moment = [{t}, 0.0, 0.0]

[output]
plots = false
"#
    );
    let path = dir.join("twist.toml");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out");
    assert!(run_quiet(&path, &out).status().unwrap().success());
    let csv = std::fs::read_to_string(out.join("final_nodes.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "node,x,y,z,rx_x,rx_y,rx_z,ry_x,ry_y,ry_z,rz_x,rz_y,rz_z"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let theory = t * l / (0.5 * e * std::f64::consts::PI * r.powi(4) / 2.0);
    let turned = |row: &[f64]| row[9].atan2(row[8]);
    let (tip, half) = (turned(&rows[8]), turned(&rows[4]));
    assert!((tip / theory - 1.0).abs() < 0.02, "{tip} against {theory}");
    assert!((half / tip - 0.5).abs() < 0.02, "{half} of {tip}");
    // r_z turned with r_y; r_x stays the axis.
    assert!((rows[8][12].atan2(rows[8][11]) - 0.5 * std::f64::consts::PI - tip).abs() < 1e-3);
    assert!((rows[8][4] - 1.0).abs() < 1e-3 && rows[8][5].abs() < 1e-6);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A wire's support is read against its static force, a frame member's
/// against the member's own limit: a post standing on a spring support
/// reports its base force and moment over its section's N_pl,Rd = A f_y
/// and M_pl,Rd = W_pl f_y, and no ratio to its self-weight reaction. The
/// response to the support force is a magnitude, compared as one.
#[test]
fn a_post_is_read_against_its_limit_and_the_wire_against_its_static_force() {
    let dir = tmp("post-limit");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |analysis: &str| {
        format!(
            r#"
[analysis]
{analysis}

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7850.0
youngs_modulus = 2.1e11
yield_stress = 235e6

[wire]
length = 2.0
elements = 8
layers = [{{ material = "steel", outer_radius = 0.002 }}]

[[support]]
node = 0
kind = "pin"

[[support]]
node = "last"
kind = "pin"

[[beam]]
name = "post"
length = 1.0
elements = 4
origin = [0.5, 1.0, -1.0]
direction = [0.0, 0.0, 1.0]
layers = [{{ material = "steel", inner_radius = 0.02015, outer_radius = 0.02415 }}]

[[support]]
beam = "post"
node = 0
kind = "spring"
stiffness = [1e8, 1e8, 1e8]
rotational_stiffness = 1e5
torsional_stiffness = 1e5

[output]
plots = false
vtk = false
response_frequencies = [2.0]
"#
        )
    };
    let (d, di) = (0.0483f64, 0.0403f64);
    let area = 0.25 * std::f64::consts::PI * (d * d - di * di);
    let (axial, moment) = (area * 235e6, (d.powi(3) - di.powi(3)) / 6.0 * 235e6);
    let weight = 7850.0 * area * 1.0 * 9.81;
    for (name, analysis) in [
        ("static", "kind = \"static\""),
        (
            "dynamic",
            "kind = \"dynamic\"\ninitial = \"static\"\nend_time = 0.01\ntime_step = 1e-3",
        ),
    ] {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, scene(analysis)).unwrap();
        let out = dir.join(name);
        assert!(run_quiet(&path, &out).status().unwrap().success(), "{name}");
        let s = summary(&out);
        let get = |i: usize, key: &str| s["supports"][i][key].as_f64();
        let post = 2;
        let force: Vec<f64> = (0..3)
            .map(|c| s["supports"][post]["static_force"][c].as_f64().unwrap())
            .collect();
        let static_force = force.iter().map(|f| f * f).sum::<f64>().sqrt();
        assert!(
            (static_force / weight - 1.0).abs() < 1e-6,
            "{name}: {force:?}"
        );
        assert_eq!(get(post, "ratio_to_static"), None, "{name}");
        assert_eq!(get(post, "filtered_ratio_to_static"), None, "{name}");
        let limit = get(post, "limit_force").unwrap();
        assert!(
            (limit / axial - 1.0).abs() < 1e-12,
            "{name}: {limit} against {axial}"
        );
        let limit_moment = get(post, "limit_moment").unwrap();
        assert!((limit_moment / moment - 1.0).abs() < 1e-12, "{name}");
        let m = get(post, "peak_moment").unwrap();
        assert_eq!(get(post, "moment_ratio_to_limit"), Some(m / limit_moment));
        assert_eq!(
            get(0, "limit_force"),
            None,
            "{name}: the wire has no section check"
        );
        if name == "static" {
            assert_eq!(get(post, "ratio_to_limit"), Some(static_force / limit));
            continue;
        }
        let peak = get(post, "peak_force").unwrap();
        assert_eq!(get(post, "ratio_to_limit"), Some(peak / limit));
        let filtered = get(post, "filtered_peak_force").unwrap();
        assert_eq!(get(post, "filtered_ratio_to_limit"), Some(filtered / limit));
        // The wire's support keeps its dynamic amplification.
        let wire_static: f64 = (0..3)
            .map(|c| {
                s["supports"][0]["static_force"][c]
                    .as_f64()
                    .unwrap()
                    .powi(2)
            })
            .sum::<f64>()
            .sqrt();
        let wire_peak = get(0, "peak_force").unwrap();
        assert_eq!(get(0, "ratio_to_static"), Some(wire_peak / wire_static));
        // A response is a vector: its magnitude is at least each component
        // and at most their root sum of squares.
        for (i, reference) in [(0, wire_static), (post, limit)] {
            let r = &s["supports"][i]["response"][0];
            let peak: Vec<f64> = (0..3).map(|c| r["peak"][c].as_f64().unwrap()).collect();
            let magnitude = r["peak_magnitude"].as_f64().unwrap();
            let largest = peak.iter().copied().fold(0.0, f64::max);
            let rss = peak.iter().map(|p| p * p).sum::<f64>().sqrt();
            assert!(largest <= magnitude * (1.0 + 1e-12) && magnitude <= rss * (1.0 + 1e-12));
            let key = if i == 0 {
                "ratio_to_static"
            } else {
                "ratio_to_limit"
            };
            assert_eq!(r[key].as_f64(), Some(magnitude / reference), "support {i}");
        }
        assert!(
            s["supports"][post]["response"][0]
                .get("ratio_to_static")
                .is_none()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A cantilever held at its root by springs only (translational, a
/// rotational spring on the tangent and a torsional one): the moment the
/// springs carry is the weight's w L² / 2, in summary.json and supports.csv.
#[test]
fn a_spring_support_reports_the_moment_it_carries() {
    let dir = tmp("spring-moment");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |analysis: &str| {
        format!(
            r#"
[analysis]
{analysis}

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11

[wire]
length = 1.0
elements = 8
layers = [{{ material = "steel", outer_radius = 0.01 }}]

[[support]]
node = 0
kind = "spring"
stiffness = [1e9, 1e9, 1e9]
rotational_stiffness = 1e6
torsional_stiffness = 1e6

[output]
plots = false
vtk = false
"#
        )
    };
    let w = 7800.0 * std::f64::consts::PI * 1e-4 * 9.81;
    let expected = 0.5 * w;
    for (name, analysis) in [
        ("static", "kind = \"static\""),
        (
            "dynamic",
            "kind = \"dynamic\"\ninitial = \"static\"\nend_time = 0.002\ntime_step = 1e-4",
        ),
    ] {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, scene(analysis)).unwrap();
        let out = dir.join(name);
        assert!(run_quiet(&path, &out).status().unwrap().success(), "{name}");
        let m = summary(&out)["supports"][0]["peak_moment"]
            .as_f64()
            .unwrap();
        assert!(
            (m - expected).abs() < 1e-3 * expected,
            "{name}: the springs carry {m} N m, w L² / 2 = {expected}"
        );
        if name == "dynamic" {
            let csv = std::fs::read_to_string(out.join("supports.csv")).unwrap();
            let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
            assert_eq!(header[4..], ["s0_mx", "s0_my", "s0_mz"]);
            let first: Vec<f64> = csv
                .lines()
                .nth(1)
                .unwrap()
                .split(',')
                .map(|x| x.parse().unwrap())
                .collect();
            assert!(
                (first[5].abs() - expected).abs() < 1e-3 * expected,
                "t = 0: {first:?}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A file no scene could be is refused unread past its size bound:
/// `/dev/zero` would otherwise fill the memory.
#[cfg(unix)]
#[test]
fn check_refuses_an_endless_file() {
    let out = ancf().args(["check", "/dev/zero"]).output().unwrap();
    assert!(!out.status.success());
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(text.contains("larger than a scene file may be"), "{text}");
}

/// Ctrl-C stops a static solve and a dynamic run's static start within
/// about a second, ending `interrupted` with the last converged state.
#[test]
fn ctrl_c_stops_static_solves() {
    let dir = tmp("static-interrupt");
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string("scenes/cantilever_large_deflection.toml").unwrap();
    // A million increments: minutes of work unless stopped.
    let cases = [
        (
            "static",
            with_analysis_line(&base, "load_steps", "load_steps = 1000000"),
        ),
        (
            "start",
            with_analysis_line(&base, "load_steps", "load_steps = 1000000").replace(
                "kind = \"static\"",
                "kind = \"dynamic\"\ninitial = \"static\"\nend_time = 0.01\ntime_step = 1e-3",
            ),
        ),
    ];
    for (name, text) in cases {
        assert!(text.contains("load_steps = 1000000"), "{name}");
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let out = dir.join(name);
        let mut child = run_quiet(&path, &out).spawn().unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1500));
        assert!(
            child.try_wait().unwrap().is_none(),
            "{name}: ended before the signal"
        );
        let sent = std::time::Instant::now();
        Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        let status = child.wait().unwrap();
        assert!(
            sent.elapsed() < std::time::Duration::from_secs(3),
            "{name}: took {:?} to stop",
            sent.elapsed()
        );
        assert_eq!(status.code(), Some(130), "{name}");
        let s = summary(&out);
        assert_eq!(s["status"], "interrupted", "{name}: {}", s["message"]);
        assert!(s["message"].as_str().unwrap().contains("Ctrl-C"), "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `text` with the line that sets `key` replaced by `line` (or `line`
/// added after `[analysis]` when the key is absent).
fn with_analysis_line(text: &str, key: &str, line: &str) -> String {
    let mut found = false;
    let mut out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.trim_start().starts_with(&format!("{key} "))
                || l.trim_start().starts_with(&format!("{key}="))
            {
                found = true;
                line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    if !found {
        let at = out.iter().position(|l| l.trim() == "[analysis]").unwrap();
        out.insert(at + 1, line.to_string());
    }
    out.join("\n") + "\n"
}

/// A Newton failure that Newton's own settings cause is blamed on them,
/// not on the time step.
#[test]
fn a_newton_failure_names_newtons_settings_when_they_are_the_cause() {
    let dir = tmp("newton-settings");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("scenes/pendulum.toml").unwrap();
    for (settings, field) in [
        (
            "max_iterations = 1\ntolerance = 1e-15",
            "analysis.tolerance",
        ),
        ("max_iterations = 1", "analysis.max_iterations"),
    ] {
        let scene = text.replace("[analysis]", &format!("[analysis]\n{settings}"));
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene).unwrap();
        let out = dir.join("out");
        let _ = run_quiet(&path, &out).status().unwrap();
        let s = summary(&out);
        let message = s["message"].as_str().unwrap();
        assert_eq!(s["status"], "failed", "{settings}: {message}");
        assert!(
            message.contains(field) && !message.contains("reduce analysis.time_step"),
            "{settings}: {message}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A folder under the name of a file the run writes is refused, not
/// deleted with its contents; an --out that is a link to nothing says so.
#[cfg(unix)]
#[test]
fn a_run_does_not_delete_a_folder_and_names_a_dangling_out() {
    let dir = tmp("owned-folder");
    let out = dir.join("out");
    let keep = out.join("final_nodes_tube.csv");
    std::fs::create_dir_all(&keep).unwrap();
    std::fs::write(keep.join("mine.txt"), "mine").unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/pendulum.toml");
    let run = run_quiet(&scene, &out).output().unwrap();
    assert!(!run.status.success());
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(
        message.contains("final_nodes_tube.csv is a folder"),
        "{message}"
    );
    assert_eq!(
        std::fs::read_to_string(keep.join("mine.txt")).unwrap(),
        "mine"
    );
    let dangling = dir.join("dangling");
    std::os::unix::fs::symlink(dir.join("nowhere"), &dangling).unwrap();
    let run = run_quiet(&scene, &dangling).output().unwrap();
    assert!(!run.status.success());
    let message = String::from_utf8_lossy(&run.stderr);
    assert!(message.contains("does not exist"), "{message}");
    std::fs::remove_dir_all(&dir).unwrap();
}
