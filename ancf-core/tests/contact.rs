//! Issues 4 and 14: contact forces derive from the penalty potential, and
//! their Jacobians with respect to positions and velocities (friction and
//! contact damping included) match central finite differences — for the
//! surface test points (away from the contact boundary) and for the line law.

mod common;
use ancf_core::forces::contact::ContactEvaluator;
use ancf_core::model::contact::{Contact, ContactLaw, ContactSettings, RestitutionModel, Rod};
use common::*;

const L: f64 = 0.25;
const RW: f64 = 0.02;

const LAWS: [ContactLaw; 2] = [ContactLaw::Surface, ContactLaw::Line];

fn rod(law: ContactLaw, friction: f64) -> Rod {
    // Rod along y under the element's middle, pressing 3 mm into the wire.
    Rod {
        center: [0.4 * L, 0.0, -(RW + 0.02) + 0.003],
        axis: [0.0, 1.0, 0.0],
        radius: 0.02,
        shape: Default::default(),
        length: None,
        law,
        contact_stiffness: if law == ContactLaw::Surface {
            1e10
        } else {
            5e8
        },
        friction,
        damping: None,
    }
}

fn setup(law: ContactLaw, friction: f64) -> (ContactEvaluator, [f64; 24], [f64; 24]) {
    let c = Contact::new(
        vec![rod(law, friction)],
        ContactSettings {
            stations: 6,
            angles: 12,
            slip_velocity: 1e-2,
            // The line law's tangent leaves out the motion of its Gauss
            // points with the zone's ends (zero for the exact integral,
            // p = 0 there); what remains is the quadrature error: 1.4e-6
            // of the friction Jacobian with 6 points here, below 1e-8 with 12.
            zone_points: 12,
            ..Default::default()
        },
        RW,
    );
    let c = ContactEvaluator::new(&c, &[L]);
    let mut rng = Rng::new(21);
    let mut e = reference(L);
    for v in e.iter_mut() {
        *v += 1e-3 * rng.uniform();
    }
    let v: [f64; 24] = std::array::from_fn(|_| 0.3 * rng.uniform());
    (c, e, v)
}

fn eval(
    c: &ContactEvaluator,
    e: &[f64; 24],
    v: &[f64; 24],
) -> ([f64; 24], [f64; 576], [f64; 576], f64) {
    let (mut q, mut kq, mut kv) = ([0.0; 24], [0.0; 576], [0.0; 576]);
    let (s, _) = c.element(0, e, v, &mut q, Some(&mut kq), Some(&mut kv));
    (q, kq, kv, s.energy)
}

/// No test point within `margin` of the rod surface, so FD does not cross the kink at g = 0.
fn away_from_boundary(c: &ContactEvaluator, e: &[f64; 24], margin: f64) -> bool {
    let r = &c.rods[0];
    c.geometry[0].points.iter().all(|tp| {
        let p: [f64; 3] = std::array::from_fn(|k| (0..8).map(|i| tp.s[i] * e[3 * i + k]).sum());
        let rel = [p[0] - r.center[0], p[2] - r.center[2]];
        ((rel[0] * rel[0] + rel[1] * rel[1]).sqrt() - r.radius).abs() > margin
    })
}

#[test]
fn normal_force_is_minus_gradient_of_penalty_energy() {
    for law in LAWS {
        let (c, e, v) = setup(law, 0.0);
        assert!(away_from_boundary(&c, &e, 1e-5));
        let (q, _, _, energy) = eval(&c, &e, &v);
        assert!(energy > 0.0, "the setup must penetrate");
        let h = 1e-8;
        let fd: Vec<f64> = (0..24)
            .map(|j| {
                let (mut ep, mut em) = (e, e);
                ep[j] += h;
                em[j] -= h;
                -(eval(&c, &ep, &v).3 - eval(&c, &em, &v).3) / (2.0 * h)
            })
            .collect();
        let err = rel(&fd, &q);
        assert!(err < 1e-6, "{law:?}: force vs −dV/dq: {err:e}");
    }
}

#[test]
fn jacobians_match_finite_differences_with_and_without_friction() {
    for (law, mu) in LAWS.iter().flat_map(|l| [(*l, 0.0), (*l, 0.3)]) {
        let (c, e, v) = setup(law, mu);
        assert!(away_from_boundary(&c, &e, 1e-5));
        let (_, kq, kv, _) = eval(&c, &e, &v);
        // The matrices are −∂Q/∂q and −∂Q/∂v.
        let (fq, fv) = central_differences(|e, v| eval(&c, e, v).0, &e, &v, 1e-8);
        let (fq, fv) = (fq.map(|x| -x), fv.map(|x| -x));
        let eq = rel(&fq, &kq);
        assert!(eq < 1e-6, "{law:?}, μ = {mu}: −∂Q/∂q vs FD {eq:e}");
        if mu > 0.0 {
            let ev = rel(&fv, &kv);
            assert!(ev < 1e-6, "{law:?}, μ = {mu}: −∂Q/∂v vs FD {ev:e}");
        } else {
            assert!(
                kv.iter().all(|x| *x == 0.0),
                "frictionless contact has no velocity Jacobian"
            );
        }
    }
}

/// Force and Jacobians of the only rod within a contact event that began
/// at `impact_speed` (m/s).
fn eval_event(
    c: &ContactEvaluator,
    e: &[f64; 24],
    v: &[f64; 24],
    impact_speed: f64,
) -> ([f64; 24], [f64; 576], [f64; 576], f64) {
    let (mut q, mut kq, mut kv) = ([0.0; 24], [0.0; 576], [0.0; 576]);
    let (s, _) = c.element_rod(
        0,
        0,
        e,
        v,
        impact_speed,
        &mut q,
        Some(&mut kq),
        Some(&mut kv),
    );
    (q, kq, kv, s.damping_power)
}

#[test]
fn contact_damping_jacobians_match_finite_differences() {
    for (law, mu) in LAWS.iter().flat_map(|l| [(*l, 0.0), (*l, 0.3)]) {
        for model in [
            RestitutionModel::Flores,
            RestitutionModel::LankaraniNikravesh,
        ] {
            let (mut c, e, v) = setup(law, mu);
            c.rods[0] = c.rods[0].clone().with_restitution(0.5, model);
            let speed = 2.0;
            let (q, kq, kv, power) = eval_event(&c, &e, &v, speed);
            let (q0, _, _, _) = eval(&c, &e, &v);
            assert!(power > 0.0, "the setup must approach the rod");
            // Outside an event (impact speed 0) the rod is elastic …
            assert_eq!(eval_event(&c, &e, &v, 0.0).0, q0);
            // … within one the damping force takes exactly the reported
            // power from the wire (without friction: the normal part only).
            if mu == 0.0 {
                let work: f64 = (0..24).map(|i| (q[i] - q0[i]) * v[i]).sum();
                assert!(
                    (work + power).abs() < 1e-12 * power.abs().max(1.0),
                    "{law:?}: damping work {work:e} vs power {power:e}"
                );
            }
            let (fq, fv) = central_differences(|e, v| eval_event(&c, e, v, speed).0, &e, &v, 1e-8);
            let (fq, fv) = (fq.map(|x| -x), fv.map(|x| -x));
            let eq = rel(&fq, &kq);
            assert!(
                eq < 1e-6,
                "{law:?}, μ = {mu}, {model:?}: −∂Q/∂q vs FD {eq:e}"
            );
            let ev = rel(&fv, &kv);
            assert!(
                ev < 1e-6,
                "{law:?}, μ = {mu}, {model:?}: −∂Q/∂v vs FD {ev:e}"
            );
        }
    }
}

#[test]
fn far_elements_are_skipped_by_the_broad_phase() {
    let (c, mut e, v) = setup(ContactLaw::Surface, 0.3);
    for blk in [0, 4] {
        e[3 * blk + 2] += 1.0; // lift the element 1 m
    }
    assert!(!c.may_touch(0, &c.rods[0], &e));
    let (q, kq, _, energy) = eval(&c, &e, &v);
    assert_eq!(energy, 0.0);
    assert!(q.iter().chain(kq.iter()).all(|x| *x == 0.0));
}

/// A time step finds its candidate (element, rod) pairs once, at
/// its start, with a margin; its Newton iterates visit only them while their
/// centerline stays within the margin. Within it the contact must be the
/// same, bit for bit, as with every pair visited — also for iterates that
/// moved almost the whole margin toward the rod; and so is the contact
/// energy the energy guard reads at the step's end.
#[test]
fn step_candidates_give_the_contact_of_every_pair_within_their_margin() {
    use ancf_core::forces::assembly::{
        assemble_contact, assemble_contact_reusing, centerline_shift, contact_candidates, pattern,
    };
    use ancf_core::material::Material;
    use ancf_core::model::WireBuilder;
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let model = WireBuilder::new(2.0, 40)
        .layer(steel, RW)
        .rod(Rod::line([1.0, 0.0, -0.045], [0.0, 1.0, 0.0], 0.02, 5e8))
        .rod(Rod::line([1.6, 0.0, -0.12], [0.3, 1.0, 0.2], 0.03, 5e8).with_length(0.5))
        .build()
        .unwrap();
    let c = ContactEvaluator::new(model.contact().unwrap(), &model.element_lengths());
    let c = &c;
    let pattern = pattern(&model);
    let margin = 4.0 * RW;
    let mut rng = Rng::new(7);
    let mut pairs = Vec::new();
    let (mut moved_in, mut compared) = (0, 0);
    // The force buffer handed from one evaluation to the next, as a Newton
    // loop does: only its nonzero rows are cleared.
    let mut buffer = (Vec::new(), Vec::new());
    for _ in 0..300 {
        // A start a few centimetres above the rods, gently bent.
        let mut q0 = model.reference.clone();
        let lift = 0.05 * rng.uniform();
        for (i, x) in q0.iter_mut().enumerate() {
            *x += 0.002 * rng.uniform() + if i % 12 == 2 { lift } else { 0.0 };
        }
        contact_candidates(&model, c, &q0, margin, &mut pairs);
        // An iterate that moved down by up to the margin, with noise,
        // scaled so that the bound on its shift is just inside the margin.
        let down = -rng.uniform().abs() * margin;
        let mut dq: Vec<f64> = (0..q0.len())
            .map(|i| 0.003 * rng.uniform() + if i % 12 == 2 { down } else { 0.0 })
            .collect();
        let q1: Vec<f64> = q0.iter().zip(&dq).map(|(a, b)| a + b).collect();
        let scale = 0.999 * margin / centerline_shift(&model, &q0, &q1);
        if scale < 1.0 {
            dq.iter_mut().for_each(|d| *d *= scale);
        }
        let q1: Vec<f64> = q0.iter().zip(&dq).map(|(a, b)| a + b).collect();
        assert!(centerline_shift(&model, &q0, &q1) <= margin);
        let v = vec![0.0; q1.len()];
        let all = assemble_contact(&model, c, &pattern, &q1, &v, None, None);
        let some = assemble_contact_reusing(
            &model,
            c,
            &pattern,
            &q1,
            &v,
            &[],
            Some(&pairs),
            (None, None, None),
            std::mem::take(&mut buffer),
        );
        assert_eq!(all.force, some.force);
        assert_eq!(all.force_nodes, some.force_nodes);
        // Every row outside the listed nodes is zero.
        let mut listed = vec![false; all.force.len() / 12];
        all.force_nodes.iter().for_each(|&n| listed[n] = true);
        for (n, rows) in all.force.chunks(12).enumerate() {
            assert!(listed[n] || rows.iter().all(|f| *f == 0.0), "node {n}");
        }
        assert_eq!(all.rod_forces, some.rod_forces);
        // The energy guard sums the step end's contact energy over them too.
        assert_eq!(all.total.energy.to_bits(), some.total.energy.to_bits());
        compared += 1;
        buffer = (some.force, some.force_nodes);
        if all.total.active > 0
            && assemble_contact(&model, c, &pattern, &q0, &v, None, None)
                .total
                .active
                == 0
        {
            moved_in += 1;
        }
    }
    // The iterates must have brought the wire onto the rods from apart.
    assert!(
        compared == 300 && moved_in > 20,
        "{moved_in} iterates moved into contact"
    );
}

/// A Newton step clears and adds only the part of −∂Q/∂v that contact
/// wrote (`ContactForces::velocity_elements`): every nonzero value of a
/// frictional contact's velocity Jacobian must lie in the columns of the
/// elements it names, and it names none when nothing touches.
#[test]
fn the_velocity_jacobian_lies_in_the_elements_contact_names() {
    use ancf_core::forces::assembly::{assemble_contact, pattern};
    use ancf_core::material::Material;
    use ancf_core::model::WireBuilder;
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let model = WireBuilder::new(2.0, 40)
        .layer(steel, RW)
        .rod(Rod::line([0.5, 0.0, -0.045], [0.0, 1.0, 0.0], 0.02, 5e8).with_friction(0.3))
        .rod(
            Rod::line([1.6, 0.0, -0.12], [0.3, 1.0, 0.2], 0.03, 5e8)
                .with_length(0.5)
                .with_friction(0.5),
        )
        .build()
        .unwrap();
    let c = ContactEvaluator::new(model.contact().unwrap(), &model.element_lengths());
    let pattern = pattern(&model);
    let mut rng = Rng::new(11);
    let (mut touched, mut apart, mut narrow) = (0, 0, 0);
    for _ in 0..200 {
        let mut q = model.reference.clone();
        let drop = 0.08 * rng.uniform();
        for (i, x) in q.iter_mut().enumerate() {
            *x += 0.002 * rng.uniform() - if i % 12 == 2 { drop } else { 0.0 };
        }
        let v: Vec<f64> = (0..q.len()).map(|_| rng.uniform()).collect();
        let mut kv = pattern.zeros();
        let cf = assemble_contact(&model, &c, &pattern, &q, &v, None, Some(&mut kv));
        match cf.velocity_elements {
            Some((first, last)) => {
                touched += 1;
                let inside = pattern.node_values(first..last + 2);
                if inside.len() < kv.len() / 2 {
                    narrow += 1;
                }
                for (slot, value) in kv.iter().enumerate() {
                    assert!(
                        *value == 0.0 || inside.contains(&slot),
                        "slot {slot} = {value:e} outside elements {first}..={last}"
                    );
                }
                assert!(kv[inside].iter().any(|x| *x != 0.0));
            }
            None => {
                apart += 1;
                assert_eq!(cf.total.active, 0);
                assert!(kv.iter().all(|x| *x == 0.0));
            }
        }
    }
    assert!(
        touched > 20 && apart > 20 && narrow > 10,
        "{touched} / {apart} / {narrow}"
    );
}
