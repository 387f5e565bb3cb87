//! Frame members: more beams of the same element in one model with the
//! wire (SPEC §9), each with its own mesh, section, placement, supports and
//! loads — against beam theory, and unchanged by the wire beside them.

use ancf_core::model::Segment;
use ancf_core::prelude::*;

const E: f64 = 2e11;
/// Steel Ø 100 × 4 mm.
const R: f64 = 0.05;
const BORE: f64 = 0.046;

fn steel(nu: f64) -> Material {
    Material::st_venant_kirchhoff(7800.0, E, nu, 1.0)
}

/// A 4 m tube across the y axis, 2 m below the wire's start.
fn tube(name: &str, elements: usize) -> BeamBuilder {
    BeamBuilder::new(name, 4.0, elements)
        .placed([1.0, -2.0, -2.0], [0.0, 1.0, 0.0])
        .layer(steel(0.3), R)
        .bore(BORE)
}

/// The wire of the frame scenes: 10 m, clamped at its start.
fn wire() -> WireBuilder {
    WireBuilder::new(10.0, 20)
        .layer(steel(0.3), 0.01)
        .support(0, SupportKind::Clamp)
}

/// A tube clamped at one end and pinned at the other (a propped
/// cantilever, which also holds its twist), loaded at midspan:
/// δ(L/2) = 7 P L³ / (768 E I) within 1 %; its supports carry the load to
/// 1e-9; the wire beside it does not move and does not change it.
#[test]
fn a_propped_tube_member_bends_as_beam_theory_says() {
    let (n, p, l) = (16, 1000.0, 4.0_f64);
    let i = std::f64::consts::PI * (R.powi(4) - BORE.powi(4)) / 4.0;
    let theory = 7.0 * p * l.powi(3) / (768.0 * E * i);
    let load = PointLoad {
        node: n / 2,
        force: [0.0, 0.0, -p],
        ..Default::default()
    };
    let with_member = |b: WireBuilder| {
        b.member(tube("tube", n))
            .support_on("tube", Support::new(0, SupportKind::Clamp))
            .support_on("tube", Support::new(n, SupportKind::Pin))
            .load_on("tube", load)
            .build()
            .unwrap()
    };
    let model = with_member(wire());
    assert_eq!(model.beams.len(), 2);
    let tube_beam = &model.beams[1];
    assert_eq!(
        (tube_beam.name.as_str(), tube_beam.nodes.clone()),
        ("tube", 21..38)
    );
    assert!(model.is_gap(20));
    let res = solve_static(&model, &StaticSettings::default()).unwrap();
    let mid = tube_beam.node(n / 2);
    let delta = model.node_position(&model.reference, mid)[2] - model.node_position(&res.q, mid)[2];
    assert!(
        (delta / theory - 1.0).abs() < 0.01,
        "midspan {delta:e} m against {theory:e} m"
    );
    // The supports (the wire's clamp too, which carries nothing) hold P.
    let lifted: f64 = res.reactions.iter().map(|(_, f)| f[2]).sum();
    assert!((lifted - p).abs() < 1e-9 * p, "{lifted} N against {p} N");
    assert!(res.reactions[0].1.iter().all(|f| f.abs() < 1e-9 * p));
    // The wire stays where it was.
    for node in model.wire().nodes.clone() {
        let moved = (0..3)
            .map(|k| (res.q[12 * node + k] - model.reference[12 * node + k]).abs())
            .fold(0.0, f64::max);
        assert!(moved < 1e-12, "wire node {node} moved {moved} m");
    }
    // The largest moment is the clamp's, 3 P L / 16 (measured: +0.007 %),
    // and its fiber stress M R / I, plus N / A: the pin cannot slide, so the
    // bent tube also stretches (N ≈ 160 N, +0.5 %).
    let mut record = ancf_core::loads::member_load::MemberRecord::default();
    let virgin = ancf_core::forces::plastic::History::default();
    record.observe(&model, tube_beam, (&res.q, virgin), 0.0, None);
    let m_clamp = 3.0 * p * l / 16.0;
    assert!(
        (record.max_bending_moment / m_clamp - 1.0).abs() < 0.005,
        "{record:?} against {m_clamp} N m at the clamp"
    );
    assert!(record.max_bending_moment_at < 1e-12, "{record:?}");
    let sigma = m_clamp * R / i;
    assert!(
        (record.max_von_mises / sigma - 1.0).abs() < 0.01,
        "{record:?} against {sigma:e} Pa"
    );
    // The member alone (held by a wire that is only itself) deflects alike.
    let alone = WireBuilder::new(4.0, n)
        .placed([1.0, -2.0, -2.0], [0.0, 1.0, 0.0])
        .layer(steel(0.3), R)
        .bore(BORE)
        .support(0, SupportKind::Clamp)
        .support(n, SupportKind::Pin)
        .load(n / 2, [0.0, 0.0, -p])
        .build()
        .unwrap();
    let res_alone = solve_static(&alone, &StaticSettings::default()).unwrap();
    let delta_alone = alone.node_position(&alone.reference, n / 2)[2]
        - alone.node_position(&res_alone.q, n / 2)[2];
    assert!(
        (delta / delta_alone - 1.0).abs() < 1e-9,
        "{delta} m beside the wire, {delta_alone} m alone"
    );
}

/// A tip moment twists a solid member by T L / (G J), J = π R⁴ / 2,
/// within 2 %; the member lies along y (its clamp holds the gradients
/// normal to its own axis).
#[test]
fn a_tip_moment_twists_a_member_by_t_l_over_g_j() {
    let (l, r, t, n) = (1.0_f64, 0.01_f64, 20.0_f64, 8);
    let g = E / (2.0 * 1.3);
    let theory = t * l / (g * std::f64::consts::PI * r.powi(4) / 2.0);
    let bar = BeamBuilder::new("bar", l, n)
        .placed([0.0, 0.0, -1.0], [0.0, 1.0, 0.0])
        .layer(steel(0.3), r);
    let model = wire()
        .member(bar)
        .support_on("bar", Support::new(0, SupportKind::Clamp))
        .load_on(
            "bar",
            PointLoad {
                node: n,
                moment: [0.0, t, 0.0],
                ..Default::default()
            },
        )
        .build()
        .unwrap();
    let res = solve_static(&model, &StaticSettings::default()).unwrap();
    // The twist about y: the angle of the tip's r_z in the z–x plane.
    let b = 12 * model.beams[1].node(n) + 9;
    let phi = res.q[b].atan2(res.q[b + 2]);
    assert!(
        (phi / theory - 1.0).abs() < 0.02,
        "twist {phi:e} rad against {theory:e} rad"
    );
}

/// A member beside a falling wire: both move under gravity, the member as
/// it would alone (to the Newton tolerance), the wire as it would alone.
#[test]
fn a_member_and_the_wire_move_as_they_would_alone() {
    move_as_alone(E);
}

/// The same beside a member 10⁴ times stiffer: its round-off (ε times its
/// stiffness) is far above the wire's residual, and must not end the
/// wire's Newton iterations.
#[test]
fn a_stiff_member_leaves_the_wire_moving_as_alone() {
    move_as_alone(1e4 * E);
}

/// Both checks of a wire pendulum and a clamped tube of Young's modulus
/// `modulus` (Pa) in one model.
fn move_as_alone(modulus: f64) {
    let n = 8;
    let tube_steel = Material::st_venant_kirchhoff(7800.0, modulus, 0.3, 1.0);
    let settings = DynamicSettings {
        time_step: 1e-3,
        end_time: 0.05,
        spectral_radius: 1.0,
        ..Default::default()
    };
    let run = |model: &Model| {
        let mut sim = Simulation::new(model, settings.clone(), Initial::Reference).unwrap();
        while !sim.is_finished() {
            sim.step().unwrap();
        }
        sim.state().q.clone()
    };
    let g = [0.0, 0.0, -9.81];
    let pendulum = || {
        WireBuilder::new(1.0, 4)
            .layer(steel(0.0), 0.02)
            .support(0, SupportKind::Pin)
            .gravity(g)
    };
    let both = pendulum()
        .member(
            BeamBuilder::new("tube", 4.0, n)
                .placed([1.0, -2.0, -2.0], [0.0, 1.0, 0.0])
                .layer(tube_steel.clone(), R)
                .bore(BORE),
        )
        .support_on("tube", Support::new(0, SupportKind::Clamp))
        .build()
        .unwrap();
    let wire_alone = pendulum().build().unwrap();
    let tube_alone = WireBuilder::new(4.0, n)
        .placed([1.0, -2.0, -2.0], [0.0, 1.0, 0.0])
        .layer(tube_steel, R)
        .bore(BORE)
        .support(0, SupportKind::Clamp)
        .gravity(g)
        .build()
        .unwrap();
    let (q, qw, qt) = (run(&both), run(&wire_alone), run(&tube_alone));
    let tube_nodes = both.beams[1].nodes.clone();
    let tip = |q: &[f64], node: usize, base: &[f64]| {
        (0..3)
            .map(|k| q[12 * node + k] - base[12 * node + k])
            .collect::<Vec<f64>>()
    };
    let (a, b) = (
        tip(&q, tube_nodes.end - 1, &both.reference),
        tip(&qt, n, &tube_alone.reference),
    );
    assert!(b[2] < -1e-5 * E / modulus, "the tube sags: {b:?}");
    assert!(
        (a[2] - b[2]).abs() < 1e-6 * b[2].abs(),
        "{a:?} beside the wire, {b:?} alone"
    );
    let (a, b) = (
        tip(&q, 4, &both.reference),
        tip(&qw, 4, &wire_alone.reference),
    );
    assert!(
        (a[2] - b[2]).abs() < 1e-6 * b[2].abs(),
        "{a:?} beside the tube, {b:?} alone"
    );
}

#[test]
fn bad_members_are_refused_naming_the_part() {
    let build = |b: WireBuilder| b.build().unwrap_err();
    let segments = [
        Segment {
            length: 1.0,
            elements: 0,
        },
        Segment {
            length: 3.0,
            elements: 6,
        },
    ];
    match build(wire().member(tube("tube", 4).graded(&segments))) {
        ModelError::Member {
            index: 0,
            name,
            error,
        } => {
            assert_eq!(name, "tube");
            assert!(matches!(
                *error,
                ModelError::Segment {
                    index: 0,
                    what: "elements",
                    ..
                }
            ));
        }
        other => panic!("{other:?}"),
    }
    match build(wire().member(BeamBuilder::new("t", 0.0, 4).layer(steel(0.3), 0.01))) {
        ModelError::Member { error, .. } => {
            assert!(matches!(*error, ModelError::Wire { ref what, .. } if what == "length"))
        }
        other => panic!("{other:?}"),
    }
    for name in ["wire", ""] {
        let e = build(wire().member(tube(name, 4)));
        assert!(matches!(e, ModelError::Member { .. }), "{e:?}");
    }
    let e = build(wire().member(tube("a", 4)).member(tube("a", 4)));
    assert!(matches!(e, ModelError::Member { index: 1, .. }), "{e:?}");
    let e = build(
        wire()
            .member(tube("a", 4))
            .support_on("b", Support::new(0, SupportKind::Pin)),
    );
    assert!(
        matches!(&e, ModelError::Support { index: 1, what, .. } if what == "beam"),
        "{e:?}"
    );
    let e = build(
        wire()
            .member(tube("a", 4))
            .support_on("a", Support::new(5, SupportKind::Pin)),
    );
    assert!(
        e.to_string().contains("member \"a\" has nodes 0..=4"),
        "{e}"
    );
    let e = build(wire().member(tube("a", 4)).support(21, SupportKind::Pin));
    assert!(e.to_string().contains("the wire has nodes 0..=20"), "{e}");
}

/// A member that overlaps the wire where both start is refused, naming it.
#[test]
fn a_member_overlapping_the_wire_is_refused() {
    // The wire lies along x at z = 0; a tube across it 3 cm below the axis
    // (radii 1 cm + 5 cm) overlaps, 7 cm below it does not.
    let across = |z: f64| {
        BeamBuilder::new("tube", 4.0, 8)
            .placed([5.03, -2.0, z], [0.0, 1.0, 0.0])
            .layer(steel(0.3), R)
            .bore(BORE)
    };
    let e = wire().member(across(-0.03)).build().unwrap_err();
    match &e {
        ModelError::Member {
            index: 0,
            name,
            error,
        } => {
            assert_eq!(name, "tube");
            assert!(
                matches!(&**error, ModelError::Wire { what, .. } if what == "origin"),
                "{e}"
            );
            assert!(e.to_string().contains("0.0300 m apart"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    assert!(wire().member(across(-0.07)).build().is_ok());
}

/// What makes Newton's work hard is named: a wire of slenderness 1e5, a
/// Mooney–Rivlin penalty beyond 1e7; an ordinary wire has nothing to name.
#[test]
fn ill_conditioning_is_named() {
    let slender = WireBuilder::new(1000.0, 10)
        .layer(steel(0.3), 0.01)
        .support(0, SupportKind::Pin)
        .build()
        .unwrap();
    let note = slender.ill_conditioning().expect("slender");
    assert!(note.contains("L / R = 1.0e5"), "{note}");
    assert!(wire().build().unwrap().ill_conditioning().is_none());
    let rubber = Material::mooney_rivlin(1100.0, 5e5, 1e5, 1e9);
    let locking = WireBuilder::new(1.0, 4)
        .layer(steel(0.3), 0.01)
        .layer(rubber, 0.02)
        .support(0, SupportKind::Clamp)
        .build()
        .unwrap();
    assert!(locking.ill_conditioning().unwrap().contains("κ = 1.0e9"));
}
