//! A hanging span against the elastic catenary, the release of a
//! support, and the static initial state of a dynamic run — through the
//! core's `solve_static` and `Simulation`.

use ancf_core::prelude::*;
use std::ops::ControlFlow;

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

/// A dynamic scene run with `Simulation` from its initial state: every
/// step's time, tip and energies (total + dissipated in `.1`), and the
/// largest |total + dissipated − E(0)| over the steps (J).
struct Run {
    time: Vec<f64>,
    tip: Vec<[f64; 3]>,
    energies: Vec<Energies>,
    max_drift: f64,
}

fn run(text: &str) -> Run {
    let scene = Scene::from_toml(text).unwrap();
    let Analysis::Dynamic {
        settings,
        initial_static,
        load_steps,
    } = &scene.analysis
    else {
        panic!("a dynamic scene")
    };
    let initial = if *initial_static {
        Initial::Static {
            load_steps: *load_steps,
        }
    } else {
        Initial::Reference
    };
    let model = &scene.model;
    let mut sim = Simulation::new(model, settings.clone(), initial).expect("the run starts");
    let e0 = sim.energies();
    let mut run = Run {
        time: vec![0.0],
        tip: vec![model.node_position(&sim.state().q, model.n_elements)],
        energies: vec![e0],
        max_drift: 0.0,
    };
    sim.run_until(settings.end_time, |sim, _| {
        let e = sim.energies();
        run.max_drift = run
            .max_drift
            .max((e.total() + e.dissipated - e0.total()).abs());
        run.time.push(sim.state().time);
        run.tip
            .push(model.node_position(&sim.state().q, model.n_elements));
        run.energies.push(e);
        ControlFlow::Continue(())
    })
    .expect("the run completes");
    assert!(sim.is_finished());
    run
}

/// A dynamic run of the 50 m span from its static equilibrium; the right
/// support lets go at `release`. ρ∞ = 1 (no numerical damping) unless `rho` says otherwise.
fn released_span(release: f64, end: f64, rho: f64, damping: &str) -> String {
    span_scene(50.06, 50.0, 25, &format!("release_time = {release}\n{damping}"))
        .replace("kind = \"static\"\nload_steps = 1", &format!("kind = \"dynamic\"\ninitial = \"static\"\nend_time = {end}\ntime_step = 2e-3\nspectral_radius = {rho}"))
}

/// ρ∞ = 0.9 here: with ρ∞ = 1 and no damping, the free end of this nearly
/// bendless cable (ω = 0.001) whips after 0.5 s and Newton fails at 0.54 s
/// (energy conserved to 0.05 % until then); numerical damping of the
/// highest frequencies carries it through.
#[test]
fn released_support_holds_exactly_then_the_span_swings_down() {
    let r = run(&released_span(0.1, 0.6, 0.9, ""));
    for (t, tip) in r.time.iter().zip(&r.tip) {
        if *t <= 0.1 + 1e-12 {
            assert_eq!(
                (tip[0], tip[2]),
                (50.0, 0.0),
                "before its release time the support holds exactly (t = {t})"
            );
        }
    }
    let last = r.tip.last().unwrap();
    // Free fall of the tip for 0.5 s would be 1.2 m; the span pulls it towards the pivot too.
    assert!(last[2] < -0.5, "tip z {} after the release", last[2]);
    assert!(last[0] < 50.0, "tip x {} moves towards the pivot", last[0]);
    let drift = r.max_drift;
    let scale = r.energies.last().unwrap().gravity.abs();
    println!(
        "release: tip ({:.3}, {:.3}), drift {drift:.3e} J of {scale:.3e} J",
        last[0], last[2]
    );
    // Numerical damping only removes energy, and only a little.
    let (e_first, e_last) = (r.energies[0].total(), r.energies.last().unwrap().total());
    assert!(
        e_last <= e_first + 1e-6 * scale,
        "energy rose from {e_first} to {e_last}"
    );
    assert!(drift < 0.01 * scale, "energy drift {drift} J");
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
        let r = run(&released_span(0.0, 0.4, 1.0, damping));
        let e = r.energies.last().unwrap();
        let dissipated = e.dissipated;
        let drift = r.max_drift;
        let scale = e.gravity.abs();
        println!(
            "{name}: dissipated {dissipated:.3} J, drift of total + dissipated {drift:.3e} J (scale {scale:.3} J)"
        );
        assert!(dissipated > 1e-3 * scale, "{name}: damping must dissipate");
        assert!(
            drift < 0.01 * scale,
            "{name}: total + dissipated drifts by {drift} J"
        );
    }
}
