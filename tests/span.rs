//! Issue 8: a hanging span against the elastic catenary, the release of a
//! support, and the static initial state of a dynamic run.

use ancf_core::scene::{Analysis, Scene};
use ancf_core::statics::{StaticSettings, solve_static};

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
        let section = &model.element.section;
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
