//! Issue 8: a hanging span against the elastic catenary, the release of a
//! support, and the static initial state of a dynamic run.

use ancf_core::scene::Scene;
use ancf_core::solve::statics::{StaticSettings, solve_static};

/// A conductor of unstretched length `l0` pinned at (0,0,0) and at `(span, 0, 0)`.
fn span_scene(l0: f64, span: f64, elements: usize, extra: &str) -> String {
    format!(
        r#"
[analysis]
kind = "static"
load_steps = 1

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "core"
model = "st-venant-kirchhoff"
density = 5990.0
youngs_modulus = 154e9
bending_factor = 0.001

[[material]]
name = "strands"
model = "st-venant-kirchhoff"
density = 2026.0
youngs_modulus = 51.7e9
bending_factor = 0.001

[wire]
length = {l0}
elements = {elements}
layers = [ {{ material = "core", outer_radius = 0.0052 }}, {{ material = "strands", outer_radius = 0.01407 }} ]
quadrature = {{ axial = 3, section = 3 }}

[[support]]
node = 0
kind = "pin"

[[support]]
node = "last"
kind = "pin"
position = [{span}, 0.0, 0.0]
{extra}
"#
    )
}

/// Elastic catenary (Irvine 1981) with equal-height supports: returns
/// (horizontal tension H, midspan sag). Unstretched coordinate s from the
/// left support, V = w L0 / 2:
///   x(s) = H s / EA + (H / w) [asinh(V/H) − asinh((V − w s)/H)]
///   z(s) = (w s / EA)(V/w − s/2) + (H / w) [√(1 + (V/H)²) − √(1 + ((V − w s)/H)²)]
/// H from x(L0) = span by bisection; sag = z(L0 / 2).
fn elastic_catenary(l0: f64, span: f64, w: f64, ea: f64) -> (f64, f64) {
    let v = w * l0 / 2.0;
    let x = |h: f64, s: f64| h * s / ea + (h / w) * ((v / h).asinh() - ((v - w * s) / h).asinh());
    let (mut lo, mut hi) = (1e-3f64, 1e9f64);
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if x(mid, l0) < span {
            lo = mid
        } else {
            hi = mid
        }
    }
    let h = (lo * hi).sqrt();
    let s = l0 / 2.0;
    let sag = (w * s / ea) * (v / w - s / 2.0)
        + (h / w) * ((1.0 + (v / h).powi(2)).sqrt() - (1.0 + ((v - w * s) / h).powi(2)).sqrt());
    (h, sag)
}

#[test]
fn hanging_span_matches_the_elastic_catenary() {
    for (l0, span) in [(50.06, 50.0), (50.5, 50.0)] {
        let scene = Scene::from_toml(&span_scene(l0, span, 50, "")).unwrap();
        let model = &scene.model;
        let section = model.section();
        let w = section.mass_per_length() * 9.81;
        let ea = section.axial_stiffness();
        let (h_exact, sag_exact) = elastic_catenary(l0, span, w, ea);
        let res =
            solve_static(model, &StaticSettings::default()).expect("the hanging span converges");
        let mid = model.node_position(&res.q, 25);
        let sag = -mid[2];
        let h = res.reactions.iter().find(|(n, _)| *n == 0).unwrap().1[0].abs();
        println!(
            "L0 = {l0}: sag {sag:.5} m (catenary {sag_exact:.5}), H {h:.2} N (catenary {h_exact:.2}), iterations {:?}",
            res.iterations
        );
        assert!(
            ((sag - sag_exact) / sag_exact).abs() < 5e-3,
            "sag {sag} vs {sag_exact}"
        );
        assert!(((h - h_exact) / h_exact).abs() < 5e-3, "H {h} vs {h_exact}");
        // Vertical reactions carry the weight.
        let v: f64 = res.reactions.iter().map(|(_, r)| r[2]).sum();
        assert!(
            (v - w * l0).abs() < 1e-6 * w * l0,
            "vertical reactions {v} vs weight {}",
            w * l0
        );
    }
}

fn run_to_dir(text: &str, name: &str) -> (std::path::PathBuf, serde_json::Value) {
    let scene = Scene::from_toml(text).unwrap();
    let dir = std::env::temp_dir().join(format!("ancf-span-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let summary = ancf::run::run_scene(
        &scene,
        &ancf::run::RunOptions {
            out: dir.clone(),
            quiet: true,
        },
    )
    .unwrap();
    assert_eq!(summary.status, "completed", "{}", summary.message);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    (dir, json)
}

fn columns(dir: &std::path::Path, file: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    (
        header,
        lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect(),
    )
}

/// A dynamic run of the 50 m span from its static equilibrium; the right
/// support lets go at `release`. ρ∞ = 1 (no numerical damping) unless `rho` says otherwise.
fn released_span(release: f64, end: f64, rho: f64, damping: &str) -> String {
    span_scene(50.06, 50.0, 25, &format!("release_time = {release}\n{damping}"))
        .replace("kind = \"static\"\nload_steps = 1", &format!("kind = \"dynamic\"\ninitial = \"static\"\nend_time = {end}\ntime_step = 2e-3\nspectral_radius = {rho}"))
        + "\n[output]\nvtk = false\nplots = false\n"
}

/// ρ∞ = 0.9 here: with ρ∞ = 1 and no damping, the free end of this nearly
/// bendless cable (ω = 0.001) whips after 0.5 s and Newton fails at 0.54 s
/// (energy conserved to 0.05 % until then); numerical damping of the
/// highest frequencies carries it through.
#[test]
fn released_support_holds_exactly_then_the_span_swings_down() {
    let (dir, summary) = run_to_dir(&released_span(0.1, 0.6, 0.9, ""), "release");
    let (h, rows) = columns(&dir, "timeseries.csv");
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (t, x, z) = (col("time"), col("tip_x"), col("tip_z"));
    for r in rows.iter().filter(|r| r[t] <= 0.1 + 1e-12) {
        assert_eq!(
            (r[x], r[z]),
            (50.0, 0.0),
            "before its release time the support holds exactly (t = {})",
            r[t]
        );
    }
    let last = rows.last().unwrap();
    // Free fall of the tip for 0.5 s would be 1.2 m; the span pulls it towards the pivot too.
    assert!(last[z] < -0.5, "tip z {} after the release", last[z]);
    assert!(last[x] < 50.0, "tip x {} moves towards the pivot", last[x]);
    let drift = summary["energy"]["max_drift"].as_f64().unwrap();
    let scale = summary["energy"]["gravity"].as_f64().unwrap().abs();
    println!(
        "release: tip ({:.3}, {:.3}), drift {drift:.3e} J of {scale:.3e} J",
        last[x], last[z]
    );
    // Numerical damping only removes energy, and only a little.
    let (e_first, e_last) = (rows[0][col("total")], last[col("total")]);
    assert!(
        e_last <= e_first + 1e-6 * scale,
        "energy rose from {e_first} to {e_last}"
    );
    assert!(drift < 0.01 * scale, "energy drift {drift} J");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn damping_dissipation_closes_the_energy_balance() {
    for (name, damping) in [
        (
            "kelvin-voigt",
            "\n[damping]\nkind = \"kelvin-voigt\"\nstrain_rate_coefficient = 1e-3\n",
        ),
        (
            "rayleigh",
            "\n[damping]\nkind = \"rayleigh\"\nmass = 0.5\nstiffness = 1e-4\n",
        ),
    ] {
        let (dir, summary) = run_to_dir(&released_span(0.0, 0.4, 1.0, damping), name);
        let e = &summary["energy"];
        let dissipated = e["dissipated"].as_f64().unwrap();
        let drift = e["max_drift"].as_f64().unwrap();
        let scale = e["gravity"].as_f64().unwrap().abs();
        println!(
            "{name}: dissipated {dissipated:.3} J, drift of total + dissipated {drift:.3e} J (scale {scale:.3} J)"
        );
        assert!(dissipated > 1e-3 * scale, "{name}: damping must dissipate");
        assert!(
            drift < 0.01 * scale,
            "{name}: total + dissipated drifts by {drift} J"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
