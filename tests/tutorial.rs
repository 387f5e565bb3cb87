//! docs/tutorial.md cannot rot: every shell command it shows runs here
//! (with this build's `ancf` first on PATH, in a scratch folder holding
//! docs/tutorial/), except building, installing and the Python step (which
//! ancf-python/tests/test_tutorial.py runs); then the outputs it describes
//! exist and the numbers it quotes hold.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The commands of the tutorial's ```sh blocks, in order.
fn commands(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in markdown.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            inside = !inside && t == "```sh";
            continue;
        }
        if inside && !t.is_empty() && !t.starts_with('#') {
            out.push(t.to_string());
        }
    }
    out
}

/// Whether a command sets the machine up (build, PATH, Python install) or
/// is the Python step: the harness does those itself.
fn is_setup(command: &str) -> bool {
    ["cargo ", "export ", "python3 -m venv", ".venv/"]
        .iter()
        .any(|p| command.starts_with(p))
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn close(value: &serde_json::Value, quoted: f64, digits: f64) -> bool {
    value
        .as_f64()
        .is_some_and(|v| (v - quoted).abs() <= 0.5 * digits)
}

#[test]
fn every_command_of_the_tutorial_runs_and_says_what_it_shows() {
    let text = std::fs::read_to_string(root().join("docs/tutorial.md")).unwrap();
    let all = commands(&text);
    let run: Vec<&String> = all.iter().filter(|c| !is_setup(c)).collect();
    assert!(run.len() >= 6, "{all:?}");
    let dir = std::env::temp_dir().join(format!("ancf-tutorial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(&root().join("docs/tutorial"), &dir.join("docs/tutorial"));
    std::fs::create_dir_all(dir.join("out")).unwrap();
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_ancf"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for c in &run {
        let out = Command::new("sh")
            .args(["-c", c])
            .current_dir(&dir)
            .env("PATH", &path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "`{c}` failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        if c.starts_with("ancf check") {
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(
                stdout.contains("valid, 0 warnings (24 elements, 297 unknowns"),
                "{stdout}"
            );
        }
        if c.starts_with("ancf run docs/tutorial/drop_cable.toml") {
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(stdout.starts_with("completed: 8000 steps"), "{stdout}");
        }
    }
    // Step 5: the files and numbers it names.
    let out = dir.join("out/drop_cable");
    for f in [
        "summary.json",
        "rod_forces.png",
        "energy.png",
        "configurations.png",
        "timeseries.csv",
        "rod_forces.csv",
        "final_nodes.csv",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let s = summary(&out);
    assert_eq!(s["status"], "completed");
    assert!(s.get("warnings").is_none(), "{}", s["warnings"]);
    let rail = &s["contact"]["rods"][0];
    assert!(close(&rail["first_contact_time"], 0.2627, 1e-4), "{rail}");
    assert!(close(&rail["filtered_peak_force"], 159.0, 1.0), "{rail}");
    assert!(close(&rail["peak_force"], 662.0, 1.0), "{rail}");
    assert!(close(&rail["impulse"], 8.03, 0.01), "{rail}");
    // Started at rest, not in equilibrium: no static load to compare with.
    assert!(s["supports"][0]["filtered_peak_force"].as_f64().unwrap() > 0.0);
    assert!(s["supports"][0].get("ratio_to_static").is_none());
    for layer in s["strains"][0]["layers"].as_array().unwrap() {
        assert!(layer["max_strain"].as_f64().unwrap() < 0.01, "{layer}");
    }
    assert!(s["energy"]["max_drift"].is_number());
    // Step 6.
    let smooth = summary(&dir.join("out/frictionless"));
    let rail = &smooth["contact"]["rods"][0];
    assert!(close(&rail["filtered_peak_force"], 161.0, 1.0), "{rail}");
    assert!(close(&rail["impulse"], 8.52, 0.01), "{rail}");
    // Steps 7 and 8.
    assert!(dir.join("out/study/report.md").is_file());
    let results = std::fs::read_to_string(dir.join("out/sweep/results.csv")).unwrap();
    assert_eq!(results.lines().count(), 7, "{results}");
    assert!(dir.join("out/sweep/report.md").is_file());
    // Step 3's two asides.
    let scene = std::fs::read_to_string(dir.join("docs/tutorial/drop_cable.toml")).unwrap();
    for (from, to, expected) in [
        (
            "elements = 24",
            "elements = 0",
            "wire.elements: must be at least 1",
        ),
        (
            "youngs_modulus = 117e9",
            "youngs_modulus = 117e3",
            "warning: material[0].youngs_modulus = 1.17e5 is outside 1e7–1.2e12",
        ),
    ] {
        assert!(scene.contains(from));
        let edited = dir.join("edited.toml");
        std::fs::write(&edited, scene.replace(from, to)).unwrap();
        let out = Command::new(&bin)
            .arg("check")
            .arg(&edited)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(expected), "{stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
