//! The one place forces are added up ([`ForceSum`]): with every effect at
//! once — elasticity, gravity, a frictional rod with contact damping inside
//! a contact event, Kelvin–Voigt damping and an elastic support with a
//! dashpot — its Jacobians are the derivatives of its force, and its parts
//! are the ones each effect gives alone.

use ancf_core::forces::assembly::assemble;
use ancf_core::forces::damping::kelvin_voigt_force;
use ancf_core::forces::sum::{At, ForceSum};
use ancf_core::model::damping::Damping;
use ancf_core::model::spring::Spring;
use ancf_core::prelude::*;
use common::jacobian_errors;

mod common;

/// A 1 m two-element wire of radius 1 cm lying along x at z = 0, pressed
/// 2 mm into a rod across it at x = 0.3 m, with all effects named; with
/// `spring`, its far end on an elastic support with a dashpot.
fn model_with(spring: bool) -> Model {
    let steel = Material::st_venant_kirchhoff(7800.0, 2e9, 0.3, 1.0);
    let rod = Rod::line([0.3, 0.0, -0.028], [0.0, 1.0, 0.0], 0.02, 1e7)
        .with_friction(0.3)
        .with_restitution(0.5, RestitutionModel::Exact);
    let builder = WireBuilder::new(1.0, 2)
        .layer(steel, 0.01)
        .support(0, SupportKind::Pin)
        .gravity([0.0, 0.0, -9.81])
        .rod(rod)
        .damping(Damping::KelvinVoigt { coefficient: 1e-3 });
    let builder = if spring {
        builder.spring(
            2,
            Spring {
                stiffness: [3e4, 1e4, 2e4],
                rotational_stiffness: 50.0,
                torsional_stiffness: 30.0,
                damping: 20.0,
            },
        )
    } else {
        builder
    };
    builder.build().expect("a valid model")
}

fn model() -> Model {
    model_with(false)
}

/// Coordinates and velocities near the reference, deterministic.
fn state(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let n = model.reference.len();
    let wobble = |i: usize, k: f64| 1e-3 * ((i as f64 * k).sin());
    let q = (0..n)
        .map(|i| model.reference[i] + wobble(i, 1.7))
        .collect();
    let v = (0..n).map(|i| 0.05 * (i as f64 * 0.9).cos()).collect();
    (q, v)
}

/// Q + Q_d on the unknowns at (q, v) within the events `events`.
fn total(sum: &mut ForceSum, model: &Model, q: &[f64], v: &[f64], events: &[f64]) -> Vec<f64> {
    let at = At {
        q,
        v: Some(v),
        events,
        pairs: None,
        ..At::moving(q, v)
    };
    sum.evaluate(model, at, None, None);
    let mut f = model.gather(sum.internal());
    if let Some((qd, _)) = sum.damping() {
        f.iter_mut().zip(qd).for_each(|(a, b)| *a += b);
    }
    f
}

#[test]
fn jacobians_are_the_derivatives_of_the_sum() {
    let model = model_with(true);
    let mut sum = ForceSum::new(&model);
    let (q, v) = state(&model);
    // Inside a contact event that began at 2 m/s: contact damping acts.
    let events = vec![2.0; model.n_elements];
    let at = At {
        q: &q,
        v: Some(&v),
        events: &events,
        pairs: None,
        ..At::moving(&q, &v)
    };
    let (mut kq, mut kv) = (sum.pattern().zeros(), sum.pattern().zeros());
    sum.evaluate(&model, at, Some(&mut kq), Some(&mut kv));
    let contact = sum.contact().expect("the model has a rod");
    assert!(contact.total.active > 0, "the wire presses on the rod");
    assert!(contact.total.damping_power > 0.0, "contact damping acts");
    assert!(contact.total.friction_power > 0.0, "friction acts");
    assert!(sum.damping().unwrap().1 > 0.0, "Kelvin–Voigt acts");

    let column = |j: usize, velocity: bool| {
        let mut unit = vec![0.0; model.n_unknowns];
        unit[j] = 1.0;
        let mut col = vec![0.0; model.n_unknowns];
        sum.pattern()
            .mul_add(if velocity { &kv } else { &kq }, &unit, 1.0, &mut col);
        col
    };
    let mut again = ForceSum::new(&model);
    let force = |q: &[f64], v: &[f64]| total(&mut again, &model, q, v, &events);
    let e = jacobian_errors(&model, (&q, &v), 1e-7, column, force);
    let (worst_q, worst_v, largest) = (e.worst_q, e.worst_v, e.largest_q);
    assert!(
        worst_q <= 1e-6 * largest,
        "∂/∂q: {worst_q:e} of {largest:e}"
    );
    assert!(
        worst_v <= 1e-6 * largest,
        "∂/∂v: {worst_v:e} of {largest:e}"
    );
}

#[test]
fn parts_are_the_effects_alone() {
    let model = model();
    let mut sum = ForceSum::new(&model);
    let (q, v) = state(&model);
    sum.evaluate(&model, At::moving(&q, &v), None, None);
    let (elastic, strain) = assemble(&model, sum.pattern(), &q, None);
    let contact = &sum.contact().unwrap().force;
    for c in 0..q.len() {
        assert_eq!(sum.internal()[c], elastic[c] - contact[c]);
    }
    assert_eq!(sum.strain_energy(), strain);
    let (kv, power) = kelvin_voigt_force(&model, sum.pattern(), &[Some(1e-3)], &q, &v, None, None);
    assert_eq!(sum.damping(), Some((&kv[..], power)));
    assert_eq!(sum.external(), &model.external_force(1.0)[..]);
    sum.set_load_factor(&model, 0.25);
    assert_eq!(sum.external(), &model.external_force(0.25)[..]);
    // At rest (statics): no damping is evaluated, and contact has no friction.
    let mut rest = ForceSum::new(&model);
    rest.evaluate(&model, At::rest(&q), None, None);
    assert_eq!(rest.contact().unwrap().total.friction_power, 0.0);
    assert_eq!(rest.damping(), None);
    // The energies: strain as assembled, potentials as the model's.
    let p = sum.potentials(&model, &q, &v);
    assert_eq!(p.strain, strain);
    assert_eq!((p.gravity, p.loads), model.external_potential(&q));
    assert!(p.contact > 0.0);
}

#[test]
fn an_elastic_support_adds_its_springs_and_dashpot() {
    let (with, without) = (model_with(true), model());
    let (q, v) = state(&with);
    let (mut a, mut b) = (ForceSum::new(&with), ForceSum::new(&without));
    a.evaluate(&with, At::moving(&q, &v), None, None);
    b.evaluate(&without, At::moving(&q, &v), None, None);
    let spring = &with.springs()[0];
    let mut expected = vec![0.0; q.len()];
    spring.add_force(&q, &mut expected);
    for (c, expected) in expected.iter().enumerate() {
        let added = a.internal()[c] - b.internal()[c];
        assert!(
            (added - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "coordinate {c}: {added} against {expected}"
        );
    }
    assert!(((a.strain_energy() - b.strain_energy()) - spring.energy(&q)).abs() < 1e-12);
    // The dashpot: c ṙ on the node's position, power c |ṙ|².
    let r_dot = &v[24..27];
    let power = 20.0 * r_dot.iter().map(|x| x * x).sum::<f64>();
    let (pa, pb) = (a.damping().unwrap().1, b.damping().unwrap().1);
    assert!(((pa - pb) - power).abs() <= 1e-12 * power);
    // The force on the node: −k Δr − c ṙ.
    let f = spring.force_on_body(&q, Some(&v));
    let k = [3e4, 1e4, 2e4];
    for i in 0..3 {
        let expected = -k[i] * (q[24 + i] - with.reference[24 + i]) - 20.0 * v[24 + i];
        assert!((f[i] - expected).abs() <= 1e-12 * expected.abs());
    }
}
