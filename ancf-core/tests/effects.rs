//! A model holds only the effects its scene names. Contact
//! code runs only through `Model::contact()`, friction only where a rod has
//! μ > 0, the centerline term only for layers with ω < 1, and the
//! Mooney–Rivlin law only in layers that use it.

use ancf_core::forces::contact::ContactEvaluator;
use ancf_core::model::Effect;
use ancf_core::model::contact::ContactSettings;
use ancf_core::scene::Scene;

fn load(path: &str, edit: impl Fn(String) -> String) -> Scene {
    Scene::from_toml(&edit(
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(path),
        )
        .unwrap(),
    ))
    .unwrap()
}

#[test]
fn pendulum_has_elasticity_and_gravity_only() {
    let s = load("scenes/pendulum.toml", |t| t);
    let m = &s.model;
    assert_eq!(m.effects.len(), 2);
    assert!(matches!(
        m.effects[0],
        Effect::Elasticity {
            mooney_rivlin: false,
            centerline: false
        }
    ));
    assert!(matches!(m.effects[1], Effect::Gravity { .. }));
    assert!(m.contact().is_none());
    assert!(m.point_loads().is_empty());
    for layer in &m.section().layers {
        assert!(!layer.laws.section.is_mooney_rivlin());
        assert!(
            layer.laws.centerline.is_none(),
            "ω = 1 must not build a centerline term"
        );
    }
}

#[test]
fn no_gravity_table_means_no_gravity_force() {
    let s = load("scenes/two_layer_cantilever.toml", |t| t);
    assert!(s.model.gravity_force().is_none());
    assert!(
        s.model
            .effects
            .iter()
            .all(|e| !matches!(e, Effect::Gravity { .. } | Effect::Contact(_)))
    );
    assert_eq!(s.model.point_loads().len(), 1);
}

#[test]
fn rods_bring_contact_and_friction_only_when_named() {
    let with = load("scenes/wire_rod_impact.toml", |t| t);
    let c = with.model.contact().expect("rods → contact effect");
    assert!(c.has_friction());
    let frictionless = load("scenes/wire_rod_impact.toml", |t| {
        t.replace("friction = 0.3", "")
    });
    assert!(!frictionless.model.contact().unwrap().has_friction());
    // Velocity Jacobian of frictionless contact stays exactly zero (no friction code ran).
    let c = ContactEvaluator::new(
        frictionless.model.contact().unwrap(),
        &frictionless.model.element_lengths(),
    );
    // The element starting at mid-span, above the rod (x = 1 m).
    let mid = frictionless.model.n_elements / 2;
    let mut e = frictionless
        .model
        .element_coordinates(&frictionless.model.reference, mid);
    for k in [0, 12] {
        e[k + 2] -= 0.28; // push the element onto the rod
    }
    let v = [0.5; 24];
    let (mut q, mut kq, mut kv) = ([0.0; 24], [0.0; 576], [0.0; 576]);
    let (sample, _) = c.element(0, &e, &v, &mut q, Some(&mut kq), Some(&mut kv));
    assert!(
        sample.active > 0,
        "the test configuration must touch the rod"
    );
    assert_eq!(sample.friction_power, 0.0);
    assert!(kv.iter().all(|x| *x == 0.0));
    // And a model built without rods has no contact, even with settings.
    let mut without = frictionless.model.clone();
    without.effects.retain(|e| !matches!(e, Effect::Contact(_)));
    assert!(without.contact().is_none());
    assert!(
        without
            .clone()
            .with_rods(vec![], ContactSettings::default())
            .contact()
            .is_none()
    );
}

#[test]
fn centerline_and_mooney_rivlin_only_where_the_layer_needs_them() {
    let s = load("scenes/wire_rod_impact.toml", |t| {
        t.replacen("bending_factor = 0.1", "bending_factor = 1.0", 1).replace(
            "[[material]]\nname = \"aluminium-strands\"\nmodel = \"st-venant-kirchhoff\"\ndensity = 2026.0\nyoungs_modulus = 51.7e9\npoisson_ratio = 0.0\nbending_factor = 0.1",
            "[[material]]\nname = \"aluminium-strands\"\nmodel = \"mooney-rivlin\"\ndensity = 1100.0\nmu10 = 5e5\nmu01 = 1e5\npenalty = 1e3",
        )
    });
    let layers = &s.model.section().layers;
    // The SVK core with ω = 1 and ν = 0: no centerline term, no Mooney–Rivlin.
    assert!(layers[0].laws.centerline.is_none() && !layers[0].laws.section.is_mooney_rivlin());
    // The cover with the default locking remedy: a ν = 0 SVK law over the
    // section, Mooney–Rivlin only in the centerline remainder.
    assert!(!layers[1].laws.section.is_mooney_rivlin());
    assert!(
        layers[1]
            .laws
            .centerline
            .as_ref()
            .is_some_and(|l| l.is_mooney_rivlin())
    );
    assert!(matches!(
        s.model.effects[0],
        Effect::Elasticity {
            mooney_rivlin: true,
            centerline: true
        }
    ));
    // The paper's plain formulation: Mooney–Rivlin over the section, nothing on the centerline.
    let plain = load("scenes/wire_rod_impact.toml", |t| {
        t.replacen("bending_factor = 0.1", "bending_factor = 1.0", 1).replace(
            "[[material]]\nname = \"aluminium-strands\"\nmodel = \"st-venant-kirchhoff\"\ndensity = 2026.0\nyoungs_modulus = 51.7e9\npoisson_ratio = 0.0\nbending_factor = 0.1",
            "[[material]]\nname = \"aluminium-strands\"\nmodel = \"mooney-rivlin\"\nlocking = \"none\"\ndensity = 1100.0\nmu10 = 5e5\nmu01 = 1e5\npenalty = 1e3",
        )
    });
    let cover = &plain.model.section().layers[1];
    assert!(cover.laws.section.is_mooney_rivlin() && cover.laws.centerline.is_none());
    assert!(matches!(
        plain.model.effects[0],
        Effect::Elasticity {
            mooney_rivlin: true,
            centerline: false
        }
    ));
    let weakened = load("scenes/wire_rod_impact.toml", |t| t);
    assert!(
        weakened
            .model
            .section()
            .layers
            .iter()
            .all(|l| l.laws.centerline.is_some())
    );
    assert!(matches!(
        weakened.model.effects[0],
        Effect::Elasticity {
            mooney_rivlin: false,
            centerline: true
        }
    ));
}
