//! Each beam's own damping: a conductor and the steel of the frame that
//! catches it dissipate differently. A beam's own damping acts on that beam
//! alone, replaces the model's for it, mixes with another kind on another
//! beam, and its Jacobians are the derivatives of its force.

mod common;

use ancf_core::forces::sum::{At, ForceSum};
use ancf_core::model::ModelError;
use ancf_core::model::damping::Damping;
use ancf_core::prelude::*;
use ancf_core::scene::Scene;
use common::{JacobianErrors, Rng, jacobian_errors};

const CONDUCTOR: Damping = Damping::KelvinVoigt { coefficient: 1e-4 };
const STEEL: Damping = Damping::Rayleigh {
    mass: 0.5,
    stiffness: 2e-5,
};

/// A 2 m wire pinned at its start, and a tube clamped at one end below it
/// (no contact: the two are coupled by nothing but their damping's
/// evaluation).
fn frame() -> WireBuilder {
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let tube = BeamBuilder::new("tube", 1.0, 4)
        .placed([0.5, -0.5, -1.0], [0.0, 1.0, 0.0])
        .layer(steel.clone(), 0.03)
        .bore(0.027);
    WireBuilder::new(2.0, 8)
        .layer(Material::st_venant_kirchhoff(2700.0, 5e10, 0.0, 0.1), 0.01)
        .support(0, SupportKind::Pin)
        .member(tube)
        .support_on("tube", Support::new(0, SupportKind::Clamp))
}

/// Coordinates near the reference and velocities, deterministic.
fn state(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(5);
    let q = (model.reference.iter())
        .map(|x| x + 1e-3 * rng.uniform())
        .collect();
    let v = model.reference.iter().map(|_| rng.uniform()).collect();
    (q, v)
}

/// Q_d (unknowns), its power and ∂Q_d/∂v (pattern slots) at (q, v); with
/// `jacobians`, ∂Q_d/∂q too (else empty).
fn damping_of(model: &Model, q: &[f64], v: &[f64], jacobians: bool) -> Damped {
    let mut sum = ForceSum::new(model);
    let (mut kq, mut kv) = (sum.pattern().zeros(), sum.pattern().zeros());
    let (kq_in, kv_in) = match jacobians {
        true => (Some(&mut kq[..]), Some(&mut kv[..])),
        false => (None, None),
    };
    sum.evaluate(model, At::moving(q, v), kq_in, kv_in);
    let (force, power) = sum
        .damping()
        .map_or((Vec::new(), 0.0), |(f, p)| (f.to_vec(), p));
    // ∂Q/∂q of the elastic force is in kq as well: take it out.
    let mut elastic = sum.pattern().zeros();
    if jacobians {
        sum.evaluate(model, At::rest(q), Some(&mut elastic), None);
    }
    let kq = kq.iter().zip(&elastic).map(|(a, b)| a - b).collect();
    Damped {
        force,
        power,
        kq,
        kv,
        nodes: (model.beams.iter())
            .map(|b| sum.pattern().node_values(b.nodes.clone()))
            .collect(),
    }
}

struct Damped {
    force: Vec<f64>,
    power: f64,
    kq: Vec<f64>,
    kv: Vec<f64>,
    /// Each beam's value slots.
    nodes: Vec<std::ops::Range<usize>>,
}

/// The unknowns of beam `b`'s coordinates.
fn unknowns(model: &Model, b: usize) -> Vec<usize> {
    let nodes = model.beams[b].nodes.clone();
    (12 * nodes.start..12 * nodes.end)
        .filter_map(|c| model.dof_map[c])
        .collect()
}

#[test]
fn a_beams_own_damping_acts_on_that_beam_alone() {
    let all = frame().damping(CONDUCTOR).build().unwrap();
    let wire = frame().damping_on("wire", CONDUCTOR).build().unwrap();
    let tube = frame().damping_on("tube", CONDUCTOR).build().unwrap();
    assert_eq!(all.beam_damping(1), Some(&CONDUCTOR));
    assert_eq!(
        (wire.beam_damping(0), wire.beam_damping(1)),
        (Some(&CONDUCTOR), None)
    );
    assert_eq!(
        (tube.beam_damping(0), tube.beam_damping(1)),
        (None, Some(&CONDUCTOR))
    );
    let (q, v) = state(&all);
    for jacobians in [false, true] {
        let (a, w, t) = (
            damping_of(&all, &q, &v, jacobians),
            damping_of(&wire, &q, &v, jacobians),
            damping_of(&tube, &q, &v, jacobians),
        );
        assert!(w.power > 0.0 && t.power > 0.0, "both beams dissipate");
        assert!(
            (a.power - w.power - t.power).abs() <= 1e-12 * a.power,
            "power {} against {} + {}",
            a.power,
            w.power,
            t.power
        );
        for (own, other, b) in [(&w, &t, 0), (&t, &w, 1)] {
            for u in unknowns(&all, b) {
                assert_eq!(own.force[u], a.force[u], "beam {b}, unknown {u}");
                assert_eq!(
                    other.force[u], 0.0,
                    "beam {b}, unknown {u}, damped by the other"
                );
            }
            if jacobians {
                for s in a.nodes[b].clone() {
                    assert_eq!((own.kq[s], own.kv[s]), (a.kq[s], a.kv[s]), "slot {s}");
                    assert_eq!((other.kq[s], other.kv[s]), (0.0, 0.0), "slot {s}");
                }
            }
        }
    }
}

#[test]
fn rayleigh_on_the_tube_and_kelvin_voigt_on_the_wire_add_up() {
    // The model's damping for the wire, the tube's own in its place.
    let mixed = frame()
        .damping(CONDUCTOR)
        .damping_on("tube", STEEL)
        .build()
        .unwrap();
    let wire = frame().damping_on("wire", CONDUCTOR).build().unwrap();
    let tube = frame().damping_on("tube", STEEL).build().unwrap();
    let steel_everywhere = frame().damping(STEEL).build().unwrap();
    assert_eq!(
        (mixed.beam_damping(0), mixed.beam_damping(1)),
        (Some(&CONDUCTOR), Some(&STEEL))
    );
    assert!(!ForceSum::symmetric(&mixed) && ForceSum::symmetric(&tube));
    let (q, v) = state(&mixed);
    let (m, w, t, s) = (
        damping_of(&mixed, &q, &v, true),
        damping_of(&wire, &q, &v, true),
        damping_of(&tube, &q, &v, true),
        damping_of(&steel_everywhere, &q, &v, true),
    );
    for i in 0..m.force.len() {
        assert!(
            (m.force[i] - w.force[i] - t.force[i]).abs() <= 1e-12 * m.force[i].abs().max(1.0),
            "unknown {i}"
        );
    }
    for k in 0..m.kv.len() {
        assert_eq!(m.kv[k], w.kv[k] + t.kv[k], "∂/∂v, slot {k}");
        assert_eq!(m.kq[k], w.kq[k] + t.kq[k], "∂/∂q, slot {k}");
    }
    assert!((m.power - w.power - t.power).abs() <= 1e-12 * m.power);
    // The tube's Rayleigh matrix is its part of the model-wide one.
    for u in unknowns(&mixed, 1) {
        assert!((t.force[u] - s.force[u]).abs() <= 1e-12 * s.force[u].abs().max(1.0));
    }
    for u in unknowns(&mixed, 0) {
        assert_eq!(
            t.force[u], 0.0,
            "the wire is not damped by the tube's Rayleigh"
        );
    }
}

#[test]
fn jacobians_of_beams_own_damping_are_its_derivatives() {
    let model = frame()
        .damping_on("wire", CONDUCTOR)
        .damping_on("tube", STEEL)
        .build()
        .unwrap();
    let (q, v) = state(&model);
    let d = damping_of(&model, &q, &v, true);
    let pattern = ForceSum::new(&model).pattern().clone();
    let column = |j: usize, velocity: bool| {
        let mut unit = vec![0.0; model.n_unknowns];
        unit[j] = 1.0;
        let mut col = vec![0.0; model.n_unknowns];
        pattern.mul_add(if velocity { &d.kv } else { &d.kq }, &unit, 1.0, &mut col);
        col
    };
    let force = |q: &[f64], v: &[f64]| damping_of(&model, q, v, false).force;
    let JacobianErrors {
        worst_q,
        worst_v,
        largest_q,
        largest_v,
    } = jacobian_errors(&model, (&q, &v), 1e-7, column, force);
    assert!(largest_q > 0.0 && largest_v > 0.0);
    assert!(
        worst_q <= 1e-6 * largest_q,
        "∂/∂q: {worst_q:e} of {largest_q:e}"
    );
    assert!(
        worst_v <= 1e-6 * largest_v,
        "∂/∂v: {worst_v:e} of {largest_v:e}"
    );
}

#[test]
fn a_beams_own_damping_is_checked_and_named() {
    let unknown = frame().damping_on("tower", CONDUCTOR).build().unwrap_err();
    assert!(
        matches!(&unknown, ModelError::Damping { field, message }
            if field == "beam" && message.contains("\"tower\"")),
        "{unknown:?}"
    );
    let bad = Damping::KelvinVoigt { coefficient: -1.0 };
    let on_tube = frame().damping_on("tube", bad.clone()).build().unwrap_err();
    assert!(
        matches!(&on_tube, ModelError::Member { index: 0, error, .. }
            if matches!(&**error, ModelError::Wire { what, .. }
                if what == "damping.strain_rate_coefficient")),
        "{on_tube:?}"
    );
    let on_wire = frame().damping_on("wire", bad).build().unwrap_err();
    assert!(
        matches!(&on_wire, ModelError::Wire { what, .. } if what == "damping.strain_rate_coefficient"),
        "{on_wire:?}"
    );
}

/// A scene of the frame above with `extra` appended to the wire's table
/// and `beam` to the tube's.
fn scene(wire: &str, beam: &str, global: &str) -> String {
    format!(
        r#"
[analysis]
kind = "dynamic"
end_time = 0.001
time_step = 1e-4

[[material]]
name = "al"
model = "st-venant-kirchhoff"
density = 2700.0
youngs_modulus = 5e10
poisson_ratio = 0.0

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3

[wire]
length = 2.0
elements = 8
layers = [ {{ material = "al", outer_radius = 0.01 }} ]
{wire}

[[beam]]
name = "tube"
length = 1.0
elements = 4
origin = [0.5, -0.5, -1.0]
direction = [0.0, 1.0, 0.0]
layers = [ {{ material = "steel", outer_radius = 0.03, inner_radius = 0.027 }} ]
{beam}

[[support]]
node = 0
kind = "pin"

[[support]]
beam = "tube"
node = 0
kind = "clamp"

{global}
"#
    )
}

#[test]
fn a_scene_names_each_beams_damping_by_its_table() {
    let conductor = r#"damping = { kind = "kelvin-voigt", strain_rate_coefficient = 1e-4 }"#;
    let steel = r#"damping = { kind = "rayleigh", mass = 0.5, stiffness = 2e-5 }"#;
    let s = Scene::from_toml(&scene(conductor, steel, "")).unwrap();
    assert_eq!(
        (s.model.beam_damping(0), s.model.beam_damping(1)),
        (Some(&CONDUCTOR), Some(&STEEL))
    );
    // `[damping]` for every beam without its own.
    let global = "[damping]\nkind = \"kelvin-voigt\"\nstrain_rate_coefficient = 1e-4";
    let s = Scene::from_toml(&scene("", steel, global)).unwrap();
    assert_eq!(
        (s.model.beam_damping(0), s.model.beam_damping(1)),
        (Some(&CONDUCTOR), Some(&STEEL))
    );
    let s = Scene::from_toml(&scene(conductor, "", "")).unwrap();
    assert_eq!(
        (s.model.beam_damping(0), s.model.beam_damping(1)),
        (Some(&CONDUCTOR), None)
    );

    let field =
        |wire: &str, beam: &str| Scene::from_toml(&scene(wire, beam, "")).unwrap_err().field;
    assert_eq!(
        field("", r#"damping = { kind = "kelvin-voigt" }"#),
        "beam[0].damping.strain_rate_coefficient"
    );
    assert_eq!(
        field(
            r#"damping = { kind = "kelvin-voigt", strain_rate_coefficient = -1.0 }"#,
            ""
        ),
        "wire.damping.strain_rate_coefficient"
    );
    assert_eq!(
        field("", r#"damping = { kind = "rayleigh", mass = -1.0 }"#),
        "beam[0].damping.mass"
    );
    assert_eq!(
        field(
            "",
            r#"damping = { kind = "rayleigh", strain_rate_coefficient = 1.0 }"#
        ),
        "beam[0].damping.strain_rate_coefficient"
    );
    assert_eq!(
        field("", r#"damping = { kind = "viscous" }"#),
        "beam[0].damping.kind"
    );

    // A ratio written as a time is named where it is written.
    let ratio = r#"damping = { kind = "kelvin-voigt", strain_rate_coefficient = 0.02 }"#;
    let s = Scene::from_toml(&scene("", ratio, "")).unwrap();
    let about_damping: Vec<String> = (s.warnings().into_iter())
        .filter(|w| w.contains("damping"))
        .collect();
    assert_eq!(about_damping.len(), 1, "{about_damping:?}");
    assert!(
        about_damping[0].starts_with("beam[0].damping.strain_rate_coefficient = 2e-2"),
        "{about_damping:?}"
    );
}
