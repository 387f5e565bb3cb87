//! A hollow section (a tube: the first layer starts at an inner radius, the
//! paper's ring quadrature) bends as beam theory says, through the builder
//! and through a scene; a bore the section cannot have is refused.

use ancf_core::prelude::*;

/// Steel Ø 100 × 4 mm: the protective frame's tube.
const R: f64 = 0.05;
const BORE: f64 = 0.046;
const E: f64 = 2e11;

/// Tip deflection of a clamped tube of length `l` under a tip load `p`
/// (downwards), from a static solve.
fn tip_deflection(l: f64, elements: usize, nu: f64, p: f64) -> f64 {
    let steel = Material::st_venant_kirchhoff(7800.0, E, nu, 1.0);
    let model = WireBuilder::new(l, elements)
        .layer(steel, R)
        .bore(BORE)
        .support(0, SupportKind::Clamp)
        .load(elements, [0.0, 0.0, -p])
        .build()
        .expect("a valid tube");
    let result = solve_static(&model, &StaticSettings::default()).expect("converges");
    -(model.node_position(&result.q, elements)[2]
        - model.node_position(&model.reference, elements)[2])
}

/// Cantilever: δ = P L³ / (3 E I) with I = π (R⁴ − r⁴) / 4 of the ring,
/// within 1 % (shear adds P L / (κ G A) ≈ 0.35 % here: κ ≈ 0.5 for a thin
/// tube, G = E / 2 (1 + ν)), with ν = 0 and with steel's 0.3 (the
/// centerline remedy keeps ν from locking bending).
#[test]
fn a_clamped_tube_bends_as_beam_theory_says() {
    let (l, p) = (2.0_f64, 100.0_f64);
    let i = std::f64::consts::PI * (R.powi(4) - BORE.powi(4)) / 4.0;
    let theory = p * l.powi(3) / (3.0 * E * i);
    for nu in [0.0, 0.3] {
        let delta = tip_deflection(l, 16, nu, p);
        let error = (delta - theory) / theory;
        assert!(
            error.abs() < 0.01,
            "ν = {nu}: tip {delta:.6e} m against {theory:.6e} m ({:+.3} %)",
            100.0 * error
        );
        // A solid bar of the same radius is far stiffer: the bore is used.
        assert!(delta > 3.0 * p * l.powi(3) / (3.0 * E * std::f64::consts::PI * R.powi(4) / 4.0));
    }
}

#[test]
fn a_scene_names_a_tube_by_its_first_layers_inner_radius() {
    let scene = |layers: &str| {
        format!(
            r#"
[analysis]
kind = "static"

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11

[wire]
length = 2.0
elements = 8
layers = {layers}

[[support]]
node = 0
kind = "clamp"
"#
        )
    };
    let tube = Scene::from_toml(&scene(
        r#"[{ material = "steel", inner_radius = 0.046, outer_radius = 0.05 }]"#,
    ))
    .expect("a tube");
    let a = tube.model.section().layers[0].area;
    let ring = std::f64::consts::PI * (R * R - BORE * BORE);
    assert!((a - ring).abs() < 1e-12 * ring, "area {a} against {ring}");
    for (layers, field, words) in [
        (
            r#"[{ material = "steel", inner_radius = 0.05, outer_radius = 0.05 }]"#,
            "wire.layers[0].outer_radius",
            "must exceed the layer's inner radius 0.05 m (its inner_radius)",
        ),
        (
            r#"[{ material = "steel", inner_radius = -0.01, outer_radius = 0.05 }]"#,
            "wire.layers[0].inner_radius",
            "must be ≥ 0",
        ),
        (
            r#"[{ material = "steel", outer_radius = 0.04 }, { material = "steel", inner_radius = 0.04, outer_radius = 0.05 }]"#,
            "wire.layers[1].inner_radius",
            "only the first layer has one",
        ),
    ] {
        let Err(e) = Scene::from_toml(&scene(layers)) else {
            panic!("{layers} is accepted");
        };
        assert_eq!(e.field, field, "{layers}: {e}");
        assert!(e.message.contains(words), "{layers}: {e}");
    }
}
