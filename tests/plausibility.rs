//! Plainly wrong input is said, before the run and after it, and
//! `--strict` turns what is said into a failing exit code (3): a slip of
//! units in Young's modulus, moduli so low that the wire stretches by
//! tens of per cent, a time step that does not resolve the contact, many
//! step cuts.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn ancf(args: &[&str], scene: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ancf"))
        .args(args.iter().take(1))
        .arg(scene)
        .args(args.iter().skip(1))
        .output()
        .unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ancf-plausible-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The shipped scene `name` with `edit` applied, written into `dir`.
fn edited(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(Path::new("scenes").join(name)).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// `ancf run SCENE --strict --quiet --out OUT`.
fn run_strict(scene: &Path, out: &Path) -> Output {
    ancf(
        &["run", "--strict", "--quiet", "--out", out.to_str().unwrap()],
        scene,
    )
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// E = 2e5 Pa on the pendulum (a slip of units): `check`
/// names the field and the range and passes; `--strict` fails `check` and
/// refuses `run` before any output is written.
#[test]
fn a_modulus_in_the_wrong_units_is_named() {
    let dir = tmp("units");
    let scene = edited(&dir, "pendulum.toml", |t| {
        t.replace("youngs_modulus = 2e9", "youngs_modulus = 2e5")
    });
    let warning = "warning: material[0].youngs_modulus = 2e5 is outside 1e7–1.2e12";
    let check = ancf(&["check"], &scene);
    assert!(check.status.success(), "{}", stderr(&check));
    assert!(stderr(&check).contains(warning), "{}", stderr(&check));
    let strict = ancf(&["check", "--strict"], &scene);
    assert_eq!(strict.status.code(), Some(3), "{}", stderr(&strict));
    let out = dir.join("out");
    let run = run_strict(&scene, &out);
    assert_eq!(run.status.code(), Some(3), "{}", stderr(&run));
    assert!(!out.join("summary.json").exists());
    // The shipped scenes warn of nothing.
    for shipped in std::fs::read_dir("scenes").unwrap() {
        let check = ancf(&["check", "--strict"], &shipped.unwrap().path());
        assert!(check.status.success(), "{}", stderr(&check));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A damping ratio of 2 % written as the Kelvin–Voigt coefficient (a time,
/// s): `check` names it with what it would mean and passes; `--strict`
/// fails it.
#[test]
fn a_damping_ratio_written_as_a_time_is_named() {
    let dir = tmp("damping");
    let scene = edited(&dir, "pendulum.toml", |t| {
        t + "\n[damping]\nkind = \"kelvin-voigt\"\nstrain_rate_coefficient = 0.02\n"
    });
    let check = ancf(&["check"], &scene);
    assert!(check.status.success(), "{}", stderr(&check));
    let warning = "warning: damping.strain_rate_coefficient = 2e-2 s is above 1e-3 s";
    assert!(stderr(&check).contains(warning), "{}", stderr(&check));
    let strict = ancf(&["check", "--strict"], &scene);
    assert_eq!(strict.status.code(), Some(3), "{}", stderr(&strict));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Both of the impact wire's moduli divided by 10⁶: each is named before
/// the run, and after it the wire's stretch (about 40 %) is in
/// summary.json's `strains` and its warnings; the shipped impact reports a
/// stretch below 1e-4 and warns of nothing.
#[test]
fn a_wire_that_stretches_like_rubber_is_reported() {
    let dir = tmp("stretch");
    let scene = edited(&dir, "wire_rod_impact.toml", |t| {
        t.replace("youngs_modulus = 154e9", "youngs_modulus = 154e3")
            .replace("youngs_modulus = 51.7e9", "youngs_modulus = 51.7e3")
    });
    for (path, soft) in [
        (scene, true),
        (PathBuf::from("scenes/wire_rod_impact.toml"), false),
    ] {
        let out = dir.join(if soft { "soft" } else { "shipped" });
        let run = ancf(&["run", "--quiet", "--out", out.to_str().unwrap()], &path);
        assert!(run.status.success(), "{}", stderr(&run));
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let wire = &s["strains"][0];
        assert_eq!(wire["beam"], "wire");
        let stretch = wire["max_stretch"].as_f64().unwrap();
        let warnings: Vec<String> = s["warnings"]
            .as_array()
            .map(|w| w.iter().map(|x| x.as_str().unwrap().to_string()).collect())
            .unwrap_or_default();
        let stretched = warnings.iter().any(|w| w.starts_with("wire stretched by"));
        if soft {
            assert!(stretch > 0.3, "{wire}");
            assert!(stretched, "{warnings:?}");
            assert!(stderr(&run).contains("warning: wire stretched by"));
            assert!(
                (warnings.iter())
                    .filter(|w| w.contains(".youngs_modulus = "))
                    .count()
                    >= 2,
                "{warnings:?}"
            );
        } else {
            assert!(stretch < 1e-4, "{wire}");
            assert!(warnings.is_empty(), "{warnings:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The impact at h = 5e-3 s: warned before the run (the contact is not
/// resolved); without `--strict` it runs, with `--strict` it fails before
/// any work.
#[test]
fn a_coarse_step_fails_under_strict() {
    let dir = tmp("coarse");
    let scene = edited(&dir, "wire_rod_impact.toml", |t| {
        t.replace("time_step = 1e-4", "time_step = 5e-3")
    });
    let out = dir.join("out");
    let strict = run_strict(&scene, &out);
    assert_eq!(strict.status.code(), Some(3), "{}", stderr(&strict));
    assert!(stderr(&strict).contains("does not resolve rod 0's line contact"));
    assert!(!out.join("summary.json").exists());
    let check = ancf(&["check", "--strict"], &scene);
    assert_eq!(check.status.code(), Some(3));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Many step cuts and no warning before the run: the run completes and
/// writes its outputs, and `--strict` makes its exit code 3. Newton is held
/// to 7 iterations at tolerance 1e-10, which cuts about 550 steps; with 6
/// it cuts over 1000, and whether it then reaches the end depends on the
/// Newton path.
#[test]
fn many_step_cuts_fail_under_strict() {
    let dir = tmp("cuts");
    let scene = edited(&dir, "wire_rod_impact.toml", |t| {
        t.replace("end_time = 1.0", "end_time = 0.4")
            .replace("elements = 64", "elements = 8")
            .replace("time_step = 1e-4", "time_step = 5e-4")
            .replace("tolerance = 1e-4", "tolerance = 1e-10\nmax_iterations = 7")
    });
    assert!(ancf(&["check", "--strict"], &scene).status.success());
    let out = dir.join("out");
    let run = run_strict(&scene, &out);
    assert_eq!(run.status.code(), Some(3), "{}", stderr(&run));
    assert!(stderr(&run).contains("error: --strict"), "{}", stderr(&run));
    assert!(out.join("summary.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
