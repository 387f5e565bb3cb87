//! Elastic supports (`SupportKind::Spring`): translational and rotational
//! springs with a dashpot at a node, against beam theory and the energy
//! balance.

use ancf_core::model::spring::Spring;
use ancf_core::prelude::*;

const E: f64 = 2e11;
const R: f64 = 0.01;
const L: f64 = 2.0;

fn ei() -> f64 {
    E * std::f64::consts::PI * R.powi(4) / 4.0
}

fn steel() -> Material {
    Material::st_venant_kirchhoff(7800.0, E, 0.3, 1.0)
}

fn spring(stiffness: [f64; 3], rotational: f64, damping: f64) -> Spring {
    Spring {
        stiffness,
        rotational_stiffness: rotational,
        damping,
        ..Default::default()
    }
}

/// A cantilever whose tip rests on a spring k: the tip load P is shared,
/// P = k δ + 3 EI δ / L³, and the clamp and the spring carry it together.
#[test]
fn a_tip_spring_shares_a_cantilevers_load() {
    let n = 16;
    let k = 3.0 * ei() / L.powi(3);
    let p = 0.1;
    let model = WireBuilder::new(L, n)
        .layer(steel(), R)
        .support(0, SupportKind::Clamp)
        .spring(n, spring([0.0, 0.0, k], 0.0, 0.0))
        .load(n, [0.0, 0.0, -p])
        .build()
        .unwrap();
    let res = solve_static(&model, &StaticSettings::default()).unwrap();
    let tip = model.node_position(&res.q, n)[2];
    let expected = -p / (k + 3.0 * ei() / L.powi(3));
    assert!(
        (tip / expected - 1.0).abs() < 2e-3,
        "tip {tip:e} m against {expected:e} m"
    );
    let (clamp, held) = (res.reactions[0].1, res.reactions[1].1);
    assert!(
        (held[2] + k * tip).abs() <= 1e-12 * p,
        "the spring's force is −k δ"
    );
    assert!(
        (clamp[2] + held[2] - p).abs() <= 1e-9 * p,
        "{} + {} N hold {p} N",
        clamp[2],
        held[2]
    );
}

/// A cantilever whose tip is held against turning by a rotational spring
/// k_θ (on the tangent, SPEC §9): beam theory's tip flexibility with the
/// restoring moment M = k_θ θ gives θ = (P L² / 2EI) / (1 + k_θ L / EI) and
/// δ = P L³ / 3EI − M L² / 2EI.
#[test]
fn a_rotational_spring_holds_a_tip_against_turning() {
    let n = 16;
    let k_theta = ei() / L;
    let p = 0.1;
    let model = WireBuilder::new(L, n)
        .layer(steel(), R)
        .support(0, SupportKind::Clamp)
        .spring(n, spring([0.0; 3], k_theta, 0.0))
        .load(n, [0.0, 0.0, -p])
        .build()
        .unwrap();
    let res = solve_static(&model, &StaticSettings::default()).unwrap();
    let tip = model.node_position(&res.q, n)[2];
    let theta = (p * L * L / (2.0 * ei())) / (1.0 + k_theta * L / ei());
    let expected = -(p * L.powi(3) / (3.0 * ei()) - k_theta * theta * L * L / (2.0 * ei()));
    assert!(
        (tip / expected - 1.0).abs() < 5e-3,
        "tip {tip:e} m against {expected:e} m"
    );
    // Without the spring the tip goes down by P L³ / 3EI: the spring
    // takes 3/8 of that off.
    assert!((expected / (p * L.powi(3) / (3.0 * ei())) + 0.625).abs() < 1e-12);
}

/// A span hanging from two elastic supports with dashpots, dropped from its
/// straight reference: the dashpots take energy out, and what they take is
/// the mechanical energy lost. With ρ∞ = 1 the scheme dissipates nothing of
/// its own and the dashpot's power is taken at the step's midpoint, as the
/// scheme moves, so the balance closes to the Newton tolerance at any step
/// (measured: a few parts in 1e6 of the dissipated energy at h = 2 ms and 1 ms).
#[test]
fn dashpots_dissipate_what_the_span_loses() {
    for h in [2e-3, 1e-3] {
        let n = 8;
        let s = spring([2e4, 2e4, 2e4], 10.0, 50.0);
        let model = WireBuilder::new(L, n)
            .layer(steel(), R)
            .spring(0, s)
            .spring(n, s)
            .gravity([0.0, 0.0, -9.81])
            .build()
            .unwrap();
        let settings = DynamicSettings {
            time_step: h,
            end_time: 0.2,
            spectral_radius: 1.0,
            ..Default::default()
        };
        let mut sim = Simulation::new(&model, settings, Initial::Reference).unwrap();
        let e0 = sim.energies();
        while !sim.is_finished() {
            sim.step().unwrap();
        }
        let e = sim.energies();
        // The dashpots take a tenth of the energy gravity released or more.
        assert!(e.dissipated > 0.1 * e.gravity.abs(), "{e:?}");
        let drift = (e.total() + e.dissipated - e0.total()).abs();
        assert!(
            drift < 1e-4 * e.dissipated,
            "h = {h}: drift {drift:e} J of {:e} J dissipated",
            e.dissipated
        );
    }
}

#[test]
fn bad_springs_are_refused_naming_the_field() {
    let build = |s: Spring, release: Option<f64>| {
        WireBuilder::new(L, 4)
            .layer(steel(), R)
            .support(0, SupportKind::Pin)
            .support_with(Support {
                node: 4,
                kind: SupportKind::Spring(s),
                position: None,
                release_time: release,
            })
            .build()
    };
    let field = |r: Result<Model, ModelError>| match r {
        Err(ModelError::Support { index: 1, what, .. }) => what,
        other => panic!("{other:?}"),
    };
    assert_eq!(
        field(build(spring([1.0, -1.0, 1.0], 0.0, 0.0), None)),
        "stiffness[1]"
    );
    assert_eq!(
        field(build(spring([1.0; 3], f64::NAN, 0.0), None)),
        "rotational_stiffness"
    );
    assert_eq!(field(build(spring([1.0; 3], 0.0, -2.0), None)), "damping");
    assert_eq!(
        field(build(spring([1.0; 3], 0.0, 0.0), Some(0.1))),
        "release_time"
    );
}

/// The scene file's `kind = "spring"`: its keys go with that kind only, and
/// its values are refused by the same rules, named by the file's field.
#[test]
fn scene_springs_are_checked_by_the_files_fields() {
    let scene = |support: &str| {
        format!(
            r#"
[analysis]
kind = "static"
[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3
[wire]
length = 2.0
elements = 4
layers = [{{ material = "steel", outer_radius = 0.01 }}]
[[support]]
node = 0
kind = "clamp"
[[support]]
node = "last"
{support}
[[load]]
node = "last"
force = [0.0, 0.0, -0.1]
"#
        )
    };
    let error = |s: &str| Scene::from_toml(&scene(s)).unwrap_err().to_string();
    let ok = Scene::from_toml(&scene(
        "kind = \"spring\"\nstiffness = [0.0, 0.0, 100.0]\nrotational_stiffness = 5.0\ndamping = 1.0",
    ))
    .unwrap();
    assert_eq!(ok.model.springs().len(), 1);
    let e = error("kind = \"spring\"\nstiffness = [0.0, -1.0, 100.0]");
    assert!(
        e.contains("support[1].stiffness[1]") && e.contains("≥ 0"),
        "{e}"
    );
    let e = error("kind = \"spring\"");
    assert!(
        e.contains("support[1].stiffness") && e.contains("missing"),
        "{e}"
    );
    let e = error("kind = \"pin\"\ndamping = 3.0");
    assert!(
        e.contains("support[1].damping") && e.contains("spring"),
        "{e}"
    );
}
