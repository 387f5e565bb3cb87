//! Contact between the wire and a frame member (SPEC §9): the line law
//! against the member's deformed centerline, with both beams' coordinates
//! in the force and its Jacobians — checked by differences, by sliding a
//! crossing through the member's element ends, and by beam theory.

use ancf_core::forces::sum::{At, ForceSum};
use ancf_core::prelude::*;
use common::jacobian_errors;

mod common;

/// Outer radius of the wire and of the member, m.
const RW: f64 = 0.01;
const RM: f64 = 0.02;

fn steel() -> Material {
    Material::st_venant_kirchhoff(7800.0, 2e9, 0.3, 1.0)
}

/// A 1 m wire along x at z = 0 crossing, at x = `at`, a 1 m member at
/// crossing angle `angle` (rad from the wire) 1 mm below contact, with
/// `contact`; neither held.
fn crossing(at: f64, angle: f64, member_elements: usize, contact: BeamContact) -> Model {
    let (c, s) = (angle.cos(), angle.sin());
    let member = BeamBuilder::new("member", 1.0, member_elements)
        .placed([at - 0.5 * c, -0.5 * s, -(RW + RM + 1e-3)], [c, s, 0.0])
        .layer(steel(), RM)
        .contact(contact);
    WireBuilder::new(1.0, 4)
        .layer(steel(), RW)
        .member(member)
        .build()
        .expect("a valid model")
}

/// The wire moved down by `depth` (m) onto the member, every coordinate
/// wobbled a little (deterministic), and velocities.
fn pressed(model: &Model, depth: f64) -> (Vec<f64>, Vec<f64>) {
    let mut q = model.reference.clone();
    for node in model.wire().nodes.clone() {
        q[12 * node + 2] -= depth;
    }
    let q = q
        .iter()
        .enumerate()
        .map(|(i, x)| x + 2e-4 * (i as f64 * 1.3).sin())
        .collect();
    let v = (0..model.reference.len())
        .map(|i| 0.3 * (i as f64 * 0.7).cos())
        .collect();
    (q, v)
}

/// Q on the unknowns at (q, v) within `events`.
fn force(sum: &mut ForceSum, model: &Model, q: &[f64], v: &[f64], events: &[f64]) -> Vec<f64> {
    let at = At {
        q,
        v: Some(v),
        events,
        pairs: None,
        ..At::moving(q, v)
    };
    sum.evaluate(model, at, None, None);
    model.gather(sum.internal())
}

/// Column `j` of the Jacobian held as pattern values plus coupling blocks.
fn column(sum: &ForceSum, model: &Model, values: &[f64], velocity: bool, j: usize) -> Vec<f64> {
    let m = model.n_unknowns;
    let mut unit = vec![0.0; m];
    unit[j] = 1.0;
    let mut col = vec![0.0; m];
    sum.pattern().mul_add(values, &unit, 1.0, &mut col);
    for b in &sum.coupling().blocks {
        let (rows, cols) = (
            model.element_unknowns(b.rows),
            model.element_unknowns(b.cols),
        );
        let k = if velocity { &b.kv } else { &b.kq };
        for (jj, c) in cols.iter().enumerate() {
            if *c == Some(j) {
                for (i, r) in rows.iter().enumerate() {
                    if let Some(r) = r {
                        col[*r] += k[i * 24 + jj];
                    }
                }
            }
        }
    }
    col
}

/// ∂Q/∂q and ∂Q/∂v, pattern and coupling blocks together, against central
/// differences for a crossing at 70°, frictional and damped inside a
/// contact event; the coupling blocks are really there.
fn jacobians_match_differences(contact: BeamContact) {
    let model = crossing(0.37, 70f64.to_radians(), 3, contact);
    let mut sum = ForceSum::new(&model);
    let (q, v) = pressed(&model, 4e-3);
    let partners = 1;
    let events = vec![1.5; model.n_elements * partners];
    let at = At {
        q: &q,
        v: Some(&v),
        events: &events,
        pairs: None,
        ..At::moving(&q, &v)
    };
    let (mut kq, mut kv) = (sum.pattern().zeros(), sum.pattern().zeros());
    sum.evaluate(&model, at, Some(&mut kq), Some(&mut kv));
    let c = sum.contact().expect("contact");
    assert!(c.total.active > 0, "the wire presses on the member");
    assert!(!sum.coupling().is_empty(), "the two beams are coupled");
    let mut again = ForceSum::new(&model);
    let e = jacobian_errors(
        &model,
        (&q, &v),
        1e-7,
        |j, velocity| column(&sum, &model, if velocity { &kv } else { &kq }, velocity, j),
        |q, v| force(&mut again, &model, q, v, &events),
    );
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
fn frictionless_jacobians_match_differences() {
    jacobians_match_differences(BeamContact {
        law: ContactLaw::Line,
        contact_stiffness: Some(1e8),
        ..Default::default()
    });
}

#[test]
fn frictional_damped_jacobians_match_differences() {
    jacobians_match_differences(BeamContact {
        law: ContactLaw::Line,
        contact_stiffness: Some(1e8),
        friction: 0.3,
        damping: Some(ancf_core::model::contact::ContactDamping::new(
            0.5,
            RestitutionModel::Exact,
        )),
    });
}

/// The contact force on the wire, summed (N), of `model` at `q` (at rest).
fn contact_force(sum: &mut ForceSum, model: &Model, q: &[f64]) -> [f64; 3] {
    sum.evaluate(model, At::rest(q), None, None);
    sum.contact().expect("contact").member_forces[0].map(|f| -f)
}

/// A crossing that slides along a straight member through its element
/// ends keeps its force to round-off (a straight member is exact in every
/// element); on a member bent into a parabola, the force is continuous
/// through the element end (1e-9 m either side: less than 1e-6 relative).
#[test]
fn a_crossing_slides_through_the_members_element_ends_smoothly() {
    let contact = BeamContact {
        law: ContactLaw::Line,
        contact_stiffness: Some(1e8),
        ..Default::default()
    };
    let model = crossing(0.37, 90f64.to_radians(), 3, contact);
    let mut sum = ForceSum::new(&model);
    let node_y = -0.5 + 1.0 / 3.0;
    let at = |bend: f64, y: f64| {
        let mut q = model.reference.clone();
        for node in model.wire().nodes.clone() {
            q[12 * node + 1] += y;
            q[12 * node + 2] -= 3e-3;
        }
        // The member bent into z = z₀ + bend · y² (exact in every element).
        for node in model.beams[1].nodes.clone() {
            let y = q[12 * node + 1];
            q[12 * node + 2] += bend * y * y;
            q[12 * node + 5] += 2.0 * bend * y;
        }
        q
    };
    let straight: Vec<[f64; 3]> = [-0.3, node_y - 1e-6, node_y, node_y + 1e-6, 0.05, 0.3]
        .iter()
        .map(|&y| contact_force(&mut sum, &model, &at(0.0, y)))
        .collect();
    let f0 = straight[0][2];
    assert!(f0 > 0.0, "{straight:?}");
    for f in &straight {
        assert!((f[2] / f0 - 1.0).abs() < 1e-9, "{f:?} against {f0}");
    }
    let bend = 2e-3;
    let before = contact_force(&mut sum, &model, &at(bend, node_y - 1e-9));
    let after = contact_force(&mut sum, &model, &at(bend, node_y + 1e-9));
    let away = contact_force(&mut sum, &model, &at(bend, node_y + 0.05));
    let change = (0..3)
        .map(|k| (after[k] - before[k]).abs())
        .fold(0.0, f64::max);
    let size = after.iter().map(|f| f * f).sum::<f64>().sqrt();
    assert!(change < 1e-6 * size, "{before:?} → {after:?}");
    // The bend matters (the check is not of a constant).
    let moved = (0..3)
        .map(|k| (away[k] - after[k]).abs())
        .fold(0.0, f64::max);
    assert!(moved > 1e-3 * size, "{after:?} {away:?}");
}

/// A wire pressed onto a simply supported (hinged) tube at midspan by a
/// small load P: the tube's midspan deflection is P L³ / (48 E I) within
/// 1 % (I of the ring section), the contact carries P to 1e-6, and the
/// supports' reactions add up to P to 1e-9.
///
/// The wire is hinged at its start (it turns about y, so the tube alone
/// holds it up) and loaded on its node above the tube. A wire that ends
/// tilted presses the tube a little sideways, and its hinge then takes
/// that sideways force and a share of P (measured: 0.14 N of 1000 N with
/// the hinge at the wire's unloaded height); so the hinge is held level
/// with the crossing's equilibrium height, found by a first solve.
#[test]
fn a_wire_pressed_on_a_hinged_tube_bends_it_as_beam_theory_says() {
    let (l, n, p) = (2.0_f64, 16, 1000.0);
    let (r, bore, e) = (0.05_f64, 0.046_f64, 2e11);
    let steel = Material::st_venant_kirchhoff(7800.0, e, 0.3, 1.0);
    let i = std::f64::consts::PI * (r.powi(4) - bore.powi(4)) / 4.0;
    let theory = p * l.powi(3) / (48.0 * e * i);
    let touch = r + RW;
    // The wire from `start` (m, on the hinge) rising by `rise` per metre
    // (to start clear of the tube), solved from lying level at `level`.
    let solve = |start: f64, rise: f64, level: f64| {
        let tube = BeamBuilder::new("tube", l, n)
            .placed([0.5, -0.5 * l, 0.0], [0.0, 1.0, 0.0])
            .layer(steel.clone(), r)
            .bore(bore)
            .contact(BeamContact {
                law: ContactLaw::Line,
                contact_stiffness: Some(1e11),
                ..Default::default()
            });
        let model = WireBuilder::new(1.0, 8)
            .placed([0.0, 0.0, start], [1.0, 0.0, rise])
            .layer(steel.clone(), RW)
            .support(0, SupportKind::Hinge)
            .load(4, [0.0, 0.0, -p])
            .member(tube)
            .support_on("tube", Support::new(0, SupportKind::Hinge))
            .support_on("tube", Support::new(n, SupportKind::Hinge))
            .build()
            .unwrap();
        let mut q0 = model.reference.clone();
        for node in model.wire().nodes.clone() {
            let level_node = [node as f64 / 8.0, 0.0, level, 1.0, 0.0, 0.0];
            q0[12 * node..12 * node + 6].copy_from_slice(&level_node);
            q0[12 * node + 6..12 * node + 12].copy_from_slice(&[0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        }
        let res =
            ancf_core::solve::statics::solve_static_from(&model, &StaticSettings::default(), q0)
                .unwrap();
        (model, res)
    };
    let first = solve(touch + 1e-3, 0.0, touch - 1e-5).1;
    let crossing = first.q[12 * 4 + 2];
    let (model, res) = solve(crossing, 0.01, crossing);
    let tube = &model.beams[1];
    let mid = tube.node(n / 2);
    let delta = model.node_position(&model.reference, mid)[2] - model.node_position(&res.q, mid)[2];
    assert!(
        (delta / theory - 1.0).abs() < 0.01,
        "midspan {delta:e} m against {theory:e} m"
    );
    let carried = -res.contact.as_ref().unwrap().member_forces[0][2];
    let lifted: f64 = res.reactions.iter().map(|(_, f)| f[2]).sum();
    assert!(
        (carried - p).abs() < 1e-6 * p,
        "contact {carried} N against {p} N"
    );
    assert!(
        (lifted - p).abs() < 1e-9 * p,
        "supports {lifted} N against {p} N"
    );
}
