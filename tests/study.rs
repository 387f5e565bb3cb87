//! `ancf study` on a user's own scene — a reduced study (`--level
//! quick`) of a small static and a small dynamic scene: the report has its
//! parts, and the error falls as the resolution rises.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A study's output folder in the system's temporary folder, removed when
/// the test ends (kept when it fails, to look at).
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

fn tmp(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("ancf-study-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

/// `runs.csv` as rows of (column → value).
fn runs(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &std::collections::HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {:?}", row[key]))
}

fn study(scene: &Path, out: &Path) -> String {
    study_at("quick", scene, out)
}

fn study_at(level: &str, scene: &Path, out: &Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_ancf"))
        .args(["study", "--level", level, "--quiet", "--out"])
        .arg(out)
        .arg(scene)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "study failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read_to_string(out.join("report.md")).unwrap()
}

fn assert_report_parts(report: &str, out: &Path) {
    assert!(report.starts_with("# Accuracy and cost"), "{report}");
    assert!(report.contains("**Reference**"));
    for level in ["| 1 % |", "| 0.1 % |", "| 0.01 % |"] {
        assert!(report.contains(level), "threshold row {level} missing");
    }
    // Every plot the report shows exists and is a PNG.
    let mut plots = 0;
    for line in report.lines().filter(|l| l.starts_with("![")) {
        let file = &line[line.find('(').unwrap() + 1..line.len() - 1];
        let bytes = std::fs::read(out.join(file)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{file}");
        plots += 1;
    }
    assert!(plots >= 1);
    assert!(
        !out.join(".runs").exists(),
        "run directories are cleaned up"
    );
}

#[test]
fn static_study_reports_errors_that_fall_with_the_mesh() {
    let out = tmp("static");
    let report = study(Path::new("scenes/two_layer_cantilever.toml"), &out);
    assert_report_parts(&report, &out);
    assert!(report.contains("analytic — Timoshenko"), "{report}");
    let rows = runs(&out);
    assert_eq!(rows.len(), 6, "1, 2, 4 elements × axial 3, 5");
    for axial in ["3", "5"] {
        let errs: Vec<f64> = [1, 2, 4]
            .iter()
            .map(|n| {
                let r = rows
                    .iter()
                    .find(|r| r["axial"] == axial && num(r, "elements") == *n as f64)
                    .unwrap();
                assert_eq!(r["status"], "completed");
                num(r, "tip_error")
            })
            .collect();
        // Cubic elements against beam theory: the error falls about 4× per halving.
        assert!(
            errs[0] > 3.0 * errs[1] && errs[1] > 3.0 * errs[2],
            "axial {axial}: {errs:?}"
        );
    }
}

#[test]
fn dynamic_study_reports_errors_that_fall_with_resolution() {
    let out = tmp("dynamic");
    let scene = out.join("small_pendulum.toml");
    std::fs::write(
        &scene,
        r#"
[analysis]
kind = "dynamic"
end_time = 0.3
time_step = 5e-3
spectral_radius = 1.0

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e9
poisson_ratio = 0.0

[wire]
length = 1.0
elements = 2
layers = [ { material = "steel", outer_radius = 0.02 } ]

[[support]]
node = 0
kind = "pin"
"#,
    )
    .unwrap();
    let report_dir = out.join("report");
    let report = study(&scene, &report_dir);
    assert_report_parts(&report, &report_dir);
    assert!(report.contains("a finer run computed by the study"));
    assert!(report.contains("energy error"));
    let rows = runs(&report_dir);
    assert_eq!(
        rows.len(),
        5,
        "h ∈ {{1e-2, 5e-3}} × elements ∈ {{2, 4}}, and adaptive steps"
    );
    let (adaptive, fixed): (Vec<_>, Vec<_>) =
        rows.iter().partition(|r| !r["error_tolerance"].is_empty());
    let err = |h: f64, n: f64| {
        let r = fixed
            .iter()
            .find(|r| (num(r, "time_step") - h).abs() < 1e-12 && num(r, "elements") == n)
            .unwrap();
        assert_eq!(r["status"], "completed");
        num(r, "tip_error")
    };
    let coarse = err(1e-2, 2.0);
    let fine = err(5e-3, 4.0);
    assert!(coarse > 0.0 && fine > 0.0);
    assert!(fine < coarse / 2.0, "coarse {coarse:e}, fine {fine:e}");
    // The adaptive run (1e-6 m per step, on the scene's 2 elements) is
    // compared at the same sample times. Its steps resolve the swing in
    // time: its energy error is far below the fixed steps' on that mesh,
    // and its trajectory error is the mesh's own (the fixed runs' errors
    // on 2 elements grow from h = 1e-2 to 5e-3 s, time and mesh errors
    // cancelling at the coarser step).
    let [a] = &adaptive[..] else {
        panic!("one adaptive run, got {}", adaptive.len())
    };
    assert_eq!(a["status"], "completed");
    assert_eq!(num(a, "error_tolerance"), 1e-6);
    let fixed_row = |h: f64| {
        fixed
            .iter()
            .find(|r| (num(r, "time_step") - h).abs() < 1e-12 && num(r, "elements") == 2.0)
            .unwrap()
    };
    let finer = fixed_row(5e-3);
    assert!(
        num(a, "energy_error") < 0.1 * num(finer, "energy_error"),
        "energy error: adaptive {:e}, h = 5e-3 s {:e}",
        num(a, "energy_error"),
        num(finer, "energy_error")
    );
    let (tip_a, tip_f) = (num(a, "tip_error"), num(finer, "tip_error"));
    assert!(
        (tip_a / tip_f - 1.0).abs() < 0.25,
        "trajectory error: adaptive {tip_a:e}, h = 5e-3 s {tip_f:e}"
    );
    assert!(report.contains("Fixed and adaptive steps side by side"));
}

/// `--level refinement` on a graded wire striking two
/// rods refines h, the elements (every segment) and the zone points three
/// levels each, and reports each rod's first impact with an error band.
#[test]
fn refinement_study_gives_each_rods_loads_with_a_band() {
    let out = tmp("refinement");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/wire_rod_impact.toml"))
        .unwrap()
        .replace("end_time = 1.0", "end_time = 0.4")
        .replace("time_step = 1e-4", "time_step = 2e-4")
        .replace(
            "elements = 64",
            "segments = [ { length = 0.75, elements = 3 }, { length = 1.25, elements = 10 } ]",
        )
        + "\n[[rod]]\ncenter = [1.5, 0.0, -0.45]\naxis = [0.0, 1.0, 0.0]\nradius = 0.02\n\
           contact_law = \"line\"\ncontact_stiffness = 5e7\n";
    let scene = out.join("two_rods.toml");
    std::fs::write(&scene, text).unwrap();
    let report_dir = out.join("report");
    let report = study_at("refinement", &scene, &report_dir);
    let rows = runs(&report_dir);
    assert_eq!(
        rows.len(),
        7,
        "h, h/2, h/4; ½, 1, 2 × elements; ½, 2 × zone points"
    );
    assert!(rows.iter().all(|r| r["status"] == "completed"));
    let elements: Vec<f64> = rows.iter().map(|r| num(r, "elements")).collect();
    for n in [6.0, 13.0, 26.0] {
        assert!(elements.contains(&n), "{n} elements: {elements:?}");
    }
    for h in ["time step h", "| elements |", "contact integration points"] {
        assert!(report.contains(h), "refinement {h} missing");
    }
    assert!(report.contains("**Loads at the scene's setting**"));
    for rod in 0..2 {
        for q in [
            "first impact, filtered peak (N)",
            "first impact, impulse (N s)",
        ] {
            let line = report
                .lines()
                .find(|l| l.starts_with(&format!("| rod {rod}: {q} | ")))
                .unwrap_or_else(|| panic!("rod {rod}: {q}: no load row"));
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let value: f64 = cells[2].parse().unwrap();
            let band: f64 = cells[3]
                .trim_start_matches('±')
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(value > 0.0 && band.is_finite() && band >= 0.0, "{line}");
        }
    }
    // The pin's load converges, or says it does not, as the rods' do.
    assert!(
        report.contains("| support 0 (wire node 0): filtered peak force (N) | "),
        "no row for the pin's load"
    );
}
