//! One binary, three instruction-set paths. The shipped scenes run
//! on every path this CPU supports (`ancf --simd PATH`) and agree with the
//! baseline path to round-off; the summary names the path that ran; a path
//! the CPU lacks is refused before any work.

use ancf_core::math::simd::SimdPath;
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ancf-simd-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `scene` on `path` into a fresh directory and returns it.
fn run_on(path: SimdPath, scene: &Path, name: &str) -> PathBuf {
    let out = tmp(&format!("{name}-{}", path.name()));
    let status = Command::new(env!("CARGO_BIN_EXE_ancf"))
        .args(["--simd", path.name(), "run"])
        .arg(scene)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .status()
        .unwrap();
    assert!(status.success(), "{name} on {}", path.name());
    let summary = summary(&out);
    assert_eq!(summary["simd"], path.name());
    out
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Node positions from `final_nodes.csv` (m).
fn final_nodes(dir: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("final_nodes.csv")).unwrap();
    text.lines()
        .skip(1)
        .flat_map(|l| {
            l.split(',')
                .skip(1)
                .map(|v| v.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect()
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The pendulum (1 m) and the impact scene up to 0.1 s after its first
/// contact (2 m wire, 64 elements, friction): the final nodes on every path
/// within 1e-9 of the wire's length of the baseline's (measured on AMD
/// EPYC: 1.7e-12 m and 7.3e-10 m). The rod's filtered peak and impulse
/// within 1e-7 relative (measured 2e-8 and 3e-9): Newton stops at the
/// residual's round-off floor, about 3e-7 of the contact force, so each
/// step's force is fixed only to that and the paths, rounding differently,
/// stop at different iterates within it.
#[test]
fn shipped_scenes_agree_across_paths() {
    let paths: Vec<SimdPath> = SimdPath::ALL
        .into_iter()
        .filter(|p| p.supported())
        .collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let impact = tmp("impact-scene.toml");
    let text = std::fs::read_to_string(root.join("scenes/wire_rod_impact.toml")).unwrap();
    let text = text
        .replace("end_time = 1.0 ", "end_time = 0.45 ")
        .replace("[output]", "[output]\nvtk = false\nplots = false");
    std::fs::write(&impact, text).unwrap();
    for (scene, name, length) in [
        (root.join("scenes/pendulum.toml"), "pendulum", 1.0),
        (impact.clone(), "impact", 2.0),
    ] {
        let runs: Vec<PathBuf> = paths.iter().map(|&p| run_on(p, &scene, name)).collect();
        let base = final_nodes(&runs[0]);
        for (path, dir) in paths.iter().zip(&runs).skip(1) {
            let diff = max_difference(&final_nodes(dir), &base);
            assert!(
                diff <= 1e-9 * length,
                "{name} on {}: nodes differ by {diff:e} m",
                path.name()
            );
            if name == "impact" {
                let (a, b) = (summary(dir), summary(&runs[0]));
                for key in ["filtered_peak_force", "impulse"] {
                    let (x, y) = (
                        a["contact"]["rods"][0][key].as_f64().unwrap(),
                        b["contact"]["rods"][0][key].as_f64().unwrap(),
                    );
                    assert!(
                        (x - y).abs() <= 1e-7 * y.abs(),
                        "{key} on {}: {x} vs {y}",
                        path.name()
                    );
                }
            }
        }
        for dir in runs {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
    let _ = std::fs::remove_file(impact);
}

/// A path the CPU cannot run is refused naming the option, before any work.
#[test]
fn an_unsupported_path_is_refused() {
    let Some(missing) = SimdPath::ALL.into_iter().find(|p| !p.supported()) else {
        return; // this CPU runs every path
    };
    let out = tmp("refused");
    let result = Command::new(env!("CARGO_BIN_EXE_ancf"))
        .args([
            "--simd",
            missing.name(),
            "run",
            "scenes/pendulum.toml",
            "--out",
        ])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("--simd") && stderr.contains(missing.name()),
        "{stderr}"
    );
    assert!(!out.join("summary.json").exists());
}
