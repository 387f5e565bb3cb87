//! The ground: a plane under the line law. A wire laid on it rests at the
//! closed-form height and the ground carries its weight; a wire dropped
//! flat on it rebounds at the coefficient of restitution; a wire pulled
//! along it needs μ times its weight; the force's Jacobians match central
//! differences where the plane cuts an element part way; a scene names its
//! ground's fields.

mod common;

use std::sync::Arc;

use ancf_core::Scene;
use ancf_core::forces::contact::ContactEvaluator;
use ancf_core::material::Material;
use ancf_core::model::contact::{
    Contact, ContactDamping, ContactSettings, RestitutionModel, Rod, hunt_crossley_rebound,
};
use ancf_core::model::spring::Spring;
use ancf_core::model::{Model, WireBuilder};
use ancf_core::solve::dynamics::{DynamicSettings, Integrator, State};
use ancf_core::solve::statics::{StaticSettings, solve_static};
use common::*;

const RW: f64 = 0.01;
const G: f64 = 9.81;

fn steel() -> Material {
    Material::st_venant_kirchhoff(7800.0, 2e11, 0.0, 1.0)
}

/// Weight per length of the wire, N/m.
fn weight_per_length() -> f64 {
    7800.0 * std::f64::consts::PI * RW * RW * G
}

/// A 1 m steel wire in four elements along x at z = 0, held in the plane
/// only by horizontal springs at both ends (and a torsional one), above a
/// ground at height `ground_z` (m) with `eps` N/m² and Coulomb `friction`.
fn wire_on_ground(ground_z: f64, eps: f64, friction: f64, gravity: bool) -> Model {
    let horizontal = Spring {
        stiffness: [0.0, 1e3, 0.0],
        torsional_stiffness: 1.0,
        ..Default::default()
    };
    let ground = Rod::plane([0.3, -0.2, ground_z], [0.0, 0.0, 1.0], eps).with_friction(friction);
    let mut b = WireBuilder::new(1.0, 4)
        .layer(steel(), RW)
        .spring(0, horizontal)
        .spring(4, horizontal)
        .ground(ground);
    if gravity {
        b = b.gravity([0.0, 0.0, -G]);
    }
    b.build().unwrap()
}

#[test]
fn a_wire_laid_on_the_ground_rests_at_r_less_w_over_eps_and_the_ground_carries_its_weight() {
    let w = weight_per_length();
    for eps in [1e6, 1e7, 5e7] {
        // Start pressed in by half the final penetration: the contact
        // holds the wire vertically from the first iterate on.
        let ground_z = -(RW - 0.5 * w / eps);
        let model = wire_on_ground(ground_z, eps, 0.0, true);
        let res = solve_static(&model, &StaticSettings::default()).unwrap();
        let expected = RW - w / eps;
        for n in 0..model.n_nodes() {
            let height = res.q[12 * n + 2] - ground_z;
            let err = (height - expected).abs() / expected;
            assert!(
                err < 1e-6,
                "ε_L = {eps:e}: node {n} at {height:.9} m above the ground, expected {expected:.9} ({err:.1e})"
            );
        }
        let contact = res.contact.expect("the wire touches the ground");
        let f = contact.rod_forces[0];
        let weight = w * 1.0;
        assert!(
            (-f[2] - weight).abs() < 1e-8 * weight && f[0].abs() < 1e-9 * weight,
            "ε_L = {eps:e}: the ground carries {f:?} N, the wire weighs {weight} N"
        );
    }
}

const V0: f64 = 1.0;

/// The wire 1 mm above the ground, without gravity, dropped at V0; steps
/// until it has left the ground moving up and returns the rebound ratio.
fn drop(damping: Option<(f64, RestitutionModel)>, h: f64) -> f64 {
    let mut ground = Rod::plane([0.0, 0.0, -RW - 1e-3], [0.0, 0.0, 1.0], 1e7);
    if let Some((e, m)) = damping {
        ground = ground.with_restitution(e, m);
    }
    let model = WireBuilder::new(1.0, 2)
        .layer(steel(), RW)
        .ground(ground)
        .build()
        .unwrap();
    let nodes = 0..model.n_nodes();
    rebound(model, nodes, h)
}

/// `model`'s `nodes` dropped at V0 (the rest at rest), stepped at `h`
/// until they touched the ground and left it moving up: the first node's
/// rebound speed over V0.
fn rebound(model: Model, nodes: std::ops::Range<usize>, h: f64) -> f64 {
    let model = Arc::new(model);
    let settings = DynamicSettings {
        time_step: h,
        end_time: 1.0,
        spectral_radius: 1.0,
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut integrator = Integrator::new(Arc::clone(&model), settings).unwrap();
    let q0 = model.reference.clone();
    let mut v0 = vec![0.0; q0.len()];
    let first = 12 * nodes.start + 2;
    for n in nodes {
        v0[12 * n + 2] = -V0;
    }
    let mut s: State = integrator.initial_state(q0, v0).unwrap();
    let mut touched = false;
    for _ in 0..100_000 {
        let (next, info) = integrator.step(&s, h).unwrap();
        s = next;
        touched |= info.contact.active > 0;
        if touched && info.contact.active == 0 && s.v[first] > 0.0 {
            break;
        }
    }
    assert!(touched, "the beam must reach the ground");
    s.v[first] / V0
}

#[test]
fn a_wire_dropped_flat_rebounds_at_the_coefficient_of_restitution() {
    // The rod's tolerances (contact_damping.rs): the same line law on the
    // same single degree of freedom.
    let elastic = drop(None, 1e-5);
    assert!(
        (elastic - 1.0).abs() < 1e-4,
        "elastic rebound ratio {elastic}"
    );
    for model in [RestitutionModel::Exact, RestitutionModel::Flores] {
        for e in [0.3, 0.6] {
            let expected = hunt_crossley_rebound(ContactDamping::new(e, model).coefficient());
            let got = drop(Some((e, model)), 1e-5);
            let err = (got - expected).abs() / expected;
            assert!(
                err < 2e-4,
                "{model:?}, e = {e}: rebound {got:.5}, closed form {expected:.5} ({err:.1e})"
            );
        }
    }
}

#[test]
fn a_wire_pulled_along_the_ground_needs_mu_times_its_weight() {
    let (eps, mu) = (1e7, 0.3);
    let w = weight_per_length();
    // At rest in equilibrium on the ground, then pulled at its front end
    // by twice the friction it can take.
    let ground_z = -(RW - w / eps);
    let ground = Rod::plane([0.0, 0.0, ground_z], [0.0, 0.0, 1.0], eps).with_friction(mu);
    let pull = 2.0 * mu * w;
    let model = Arc::new(
        WireBuilder::new(1.0, 4)
            .layer(steel(), RW)
            .gravity([0.0, 0.0, -G])
            .ground(ground)
            .load(4, [pull, 0.0, 0.0])
            .build()
            .unwrap(),
    );
    let h = 1e-4;
    let settings = DynamicSettings {
        time_step: h,
        end_time: 1.0,
        spectral_radius: 1.0,
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut integrator = Integrator::new(Arc::clone(&model), settings).unwrap();
    let q0 = model.reference.clone();
    let v0 = vec![0.0; q0.len()];
    let mut s = integrator.initial_state(q0, v0).unwrap();
    let steps = 300;
    let mut last = None;
    for _ in 0..steps {
        let (next, info) = integrator.step(&s, h).unwrap();
        s = next;
        last = Some(info);
    }
    let info = last.unwrap();
    // The force on the wire: the weight up, friction back.
    let f = info.contact.force;
    assert!(
        (f[2] - w).abs() < 1e-3 * w,
        "normal force {} N for a weight of {w} N",
        f[2]
    );
    let ratio = -f[0] / f[2];
    assert!(
        (ratio - mu).abs() < 1e-3 * mu,
        "sliding friction {ratio:.5} of the normal force, μ = {mu}"
    );
    // The wire as a body: m a = pull − μ W.
    let mass = model.total_mass();
    let t = steps as f64 * h;
    let mean_v: f64 =
        (0..model.n_nodes()).map(|n| s.v[12 * n]).sum::<f64>() / model.n_nodes() as f64;
    let expected = (pull - mu * w) / mass * t;
    assert!(
        (mean_v - expected).abs() < 0.02 * expected,
        "after {t} s the wire slides at {mean_v:.5} m/s, expected {expected:.5}"
    );
}

/// An element sagging 6 mm at its middle (its end slopes ∓ 0.1) over a
/// plane tilted 0.01 rad that its middle enters by 2 mm and its ends clear:
/// the zone ends lie inside the element.
fn tilted(friction: f64, damped: bool) -> (ContactEvaluator, [f64; 24], [f64; 24]) {
    let l = 0.25;
    let a = 0.01_f64;
    let normal = [a.sin(), 0.0, a.cos()];
    let mut e = reference(l);
    e[5] = -0.1;
    e[17] = 0.1;
    // The plane through the point RW − 2 mm below the middle along the normal.
    let mid = [0.5 * l, 0.0, -0.025 * l];
    let point: [f64; 3] = std::array::from_fn(|k| mid[k] - (RW - 2e-3) * normal[k]);
    let mut ground = Rod::plane(point, normal, 5e8).with_friction(friction);
    if damped {
        ground = ground.with_restitution(0.5, RestitutionModel::Exact);
    }
    let contact = Contact::new(
        vec![ground],
        ContactSettings {
            slip_velocity: 1e-2,
            zone_points: 12,
            ..Default::default()
        },
        RW,
    );
    let c = ContactEvaluator::new(&contact, &[l]);
    let mut rng = Rng::new(5);
    for v in e.iter_mut() {
        *v += 1e-4 * rng.uniform();
    }
    let v: [f64; 24] = std::array::from_fn(|_| 0.3 * rng.uniform());
    (c, e, v)
}

fn eval(
    c: &ContactEvaluator,
    e: &[f64; 24],
    v: &[f64; 24],
    speed: f64,
) -> ([f64; 24], [f64; 576], [f64; 576], f64, usize) {
    let (mut q, mut kq, mut kv) = ([0.0; 24], [0.0; 576], [0.0; 576]);
    let (s, _) = c.element_rod(0, 0, e, v, speed, &mut q, Some(&mut kq), Some(&mut kv));
    (q, kq, kv, s.energy, s.active)
}

#[test]
fn the_ground_force_is_the_gradient_of_its_energy_and_its_jacobians_match_differences() {
    let (c, e, v) = tilted(0.0, false);
    let (q, _, _, energy, active) = eval(&c, &e, &v, 0.0);
    assert!(energy > 0.0 && active > 0, "the element must touch");
    // Both element ends clear of the plane: the zone ends inside.
    let g = &c.rods[0];
    for node in [0, 12] {
        let height: f64 = (0..3)
            .map(|k| (e[node + k] - g.center[k]) * g.axis[k])
            .sum();
        assert!(height > RW, "node at {node}: {height} m above the plane");
    }
    let h = 1e-8;
    let fd: Vec<f64> = (0..24)
        .map(|j| {
            let (mut ep, mut em) = (e, e);
            ep[j] += h;
            em[j] -= h;
            -(eval(&c, &ep, &v, 0.0).3 - eval(&c, &em, &v, 0.0).3) / (2.0 * h)
        })
        .collect();
    assert!(rel(&fd, &q) < 1e-6, "force vs −dV/dq: {:e}", rel(&fd, &q));
    for (mu, damped) in [(0.0, false), (0.4, false), (0.4, true)] {
        let (c, e, v) = tilted(mu, damped);
        let speed = if damped { 0.5 } else { 0.0 };
        let (_, kq, kv, _, _) = eval(&c, &e, &v, speed);
        let (fq, fv) = central_differences(|e, v| eval(&c, e, v, speed).0, &e, &v, 1e-8);
        let (fq, fv) = (fq.map(|x| -x), fv.map(|x| -x));
        let (eq, ev) = (rel(&fq, &kq), rel(&fv, &kv));
        assert!(eq < 1e-6, "μ = {mu}, damped {damped}: −∂Q/∂q vs FD {eq:e}");
        if mu > 0.0 || damped {
            assert!(ev < 1e-6, "μ = {mu}, damped {damped}: −∂Q/∂v vs FD {ev:e}");
        }
    }
}

#[test]
fn a_wire_below_the_ground_is_pushed_up_not_through() {
    // The centerline 1.5 radii below the plane: the gap is signed, so the
    // force still points along the normal.
    let l = 0.25;
    let ground = Rod::plane([0.0, 0.0, 1.5 * RW], [0.0, 0.0, 1.0], 1e7);
    let contact = Contact::new(vec![ground], ContactSettings::default(), RW);
    let c = ContactEvaluator::new(&contact, &[l]);
    let e = reference(l);
    let v = [0.0; 24];
    let (q, _, _, _, _) = eval(&c, &e, &v, 0.0);
    let fz: f64 = [2, 14].iter().map(|&i| q[i]).sum();
    let expected = 1e7 * 2.5 * RW * l;
    assert!(
        (fz - expected).abs() < 1e-9 * expected,
        "force {fz} N up, expected ε_L (2.5 R) l = {expected} N"
    );
}

const SCENE: &str = r#"
[analysis]
kind = "dynamic"
end_time = 0.01
time_step = 1e-4

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11

[wire]
length = 1.0
elements = 4
layers = [{ material = "steel", outer_radius = 0.01 }]

[[ground]]
point = [0.0, 0.0, -0.05]
normal = [0.0, 0.0, 2.0]
contact_stiffness = 1e7
friction = 0.2
"#;

#[test]
fn a_scene_reads_its_ground_and_names_its_fields() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let c = scene.model.contact().expect("the ground is contact");
    assert_eq!(c.rods.len(), 1);
    assert!(c.rods[0].is_ground());
    assert_eq!(c.rods[0].axis, [0.0, 0.0, 1.0], "the normal is normalised");
    assert_eq!(c.rods[0].friction, 0.2);
    assert_eq!(c.rigid_name(0), "ground[0]");
    let bad = |from: &str, to: &str| Scene::from_toml(&SCENE.replace(from, to)).expect_err(to);
    assert_eq!(
        bad("normal = [0.0, 0.0, 2.0]", "normal = [0.0, 0.0, 0.0]").field,
        "ground[0].normal"
    );
    assert_eq!(
        bad("contact_stiffness = 1e7", "contact_stiffness = -1.0").field,
        "ground[0].contact_stiffness"
    );
    assert_eq!(
        bad(
            "friction = 0.2",
            "friction = 0.2\nrestitution_model = \"flores\""
        )
        .field,
        "ground[0].restitution"
    );
    assert_eq!(
        bad("friction = 0.2", "friction = 0.2\nbeams = [\"tube\"]").field,
        "ground[0].beams"
    );
    let e = bad(
        "friction = 0.2",
        "friction = 0.2\nbeams = [\"wire\", \"tube\"]",
    );
    assert_eq!(e.field, "ground[0].beams", "{e}");
    assert!(
        e.message.contains("no frame member is named \"tube\""),
        "{e}"
    );
    // The wire starting under the ground is the geometry's fault.
    let e = bad("point = [0.0, 0.0, -0.05]", "point = [0.0, 0.0, 0.05]");
    assert_eq!(e.field, "ground[0].point", "{e}");
    // A clearance zone under the ground.
    let with_zone =
        |index: usize| format!("{SCENE}\n[[clearance]]\nkind = \"ground\"\nground = {index}\n");
    let zoned = Scene::from_toml(&with_zone(0)).unwrap();
    assert_eq!(
        zoned.clearance,
        vec![ancf_core::model::clearance::ClearanceZone::HalfSpace {
            point: [0.0, 0.0, -0.05],
            normal: [0.0, 0.0, 2.0],
        }]
    );
    let e = Scene::from_toml(&with_zone(1)).expect_err("no ground 1");
    assert_eq!(e.field, "clearance[0].ground", "{e}");
    // An unresolved ground is named as a ground.
    let coarse = Scene::from_toml(&SCENE.replace("time_step = 1e-4", "time_step = 4e-3")).unwrap();
    let warnings = coarse.unresolved_contacts();
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].to_string().contains("ground 0"),
        "{}",
        warnings[0]
    );
}

/// A frame member named by a ground touches it as the wire does, with its
/// own outer radius: a tube of radius 2 R_w laid on the ground rests at
/// R_m − w_m/ε_L and the ground carries its weight, while the wire, held
/// above, touches nothing; the same tube through a ground that does not
/// name it finds no support there (its static solve has none).
#[test]
fn a_member_named_by_a_ground_rests_on_it_at_its_own_radius() {
    use ancf_core::model::{BeamBuilder, Support, SupportKind};
    let rm = 2.0 * RW;
    let w = 7800.0 * std::f64::consts::PI * rm * rm * G;
    let horizontal = Spring {
        stiffness: [0.0, 1e3, 0.0],
        torsional_stiffness: 1.0,
        ..Default::default()
    };
    let model = |eps: f64, named: bool| {
        let ground_z = -(rm - 0.5 * w / eps);
        let ground = Rod::plane([0.3, 0.7, ground_z], [0.0, 0.0, 1.0], eps);
        let tube = BeamBuilder::new("tube", 1.0, 4)
            .placed([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
            .layer(steel(), rm);
        let b = WireBuilder::new(1.0, 4)
            .placed([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
            .layer(steel(), RW)
            .support(0, ancf_core::model::SupportKind::Fixed)
            .support(4, ancf_core::model::SupportKind::Fixed)
            .member(tube)
            .support_on("tube", Support::new(0, SupportKind::Spring(horizontal)))
            .support_on("tube", Support::new(4, SupportKind::Spring(horizontal)))
            .gravity([0.0, 0.0, -G]);
        let b = match named {
            true => b.ground_touching(ground, &["wire", "tube"]),
            false => b.ground(ground),
        };
        (b.build().unwrap(), ground_z)
    };
    for eps in [1e6, 1e7, 5e7] {
        let (model, ground_z) = model(eps, true);
        let res = solve_static(&model, &StaticSettings::default()).unwrap();
        let expected = rm - w / eps;
        for n in model.beams[1].nodes.clone() {
            let height = res.q[12 * n + 2] - ground_z;
            let err = (height - expected).abs() / expected;
            assert!(
                err < 1e-6,
                "ε_L = {eps:e}: tube node {n} at {height:.9} m above the ground, expected {expected:.9} ({err:.1e})"
            );
        }
        let contact = res.contact.expect("the tube touches the ground");
        let f = contact.rod_forces[0];
        assert!(
            (-f[2] - w).abs() < 1e-8 * w && f[0].abs() < 1e-9 * w,
            "ε_L = {eps:e}: the ground carries {f:?} N, the tube weighs {w} N"
        );
    }
    let (unnamed, _) = model(1e7, false);
    assert!(solve_static(&unnamed, &StaticSettings::default()).is_err());
}

/// A member dropped flat onto a ground that names it rebounds at the
/// coefficient of restitution, as the wire does (the time step's contact
/// candidates include the member's elements); the wire, held above,
/// touches nothing.
#[test]
fn a_member_dropped_flat_rebounds_at_the_coefficient_of_restitution() {
    use ancf_core::model::{BeamBuilder, SupportKind};
    let (rm, h, e) = (2.0 * RW, 1e-5, 0.6);
    let model = |damped: bool| {
        let mut ground = Rod::plane([0.0, 0.0, -rm - 1e-3], [0.0, 0.0, 1.0], 1e7);
        if damped {
            ground = ground.with_restitution(e, RestitutionModel::Exact);
        }
        let tube = BeamBuilder::new("tube", 1.0, 2)
            .placed([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
            .layer(steel(), rm);
        WireBuilder::new(1.0, 2)
            .placed([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
            .layer(steel(), RW)
            .support(0, SupportKind::Fixed)
            .support(2, SupportKind::Fixed)
            .member(tube)
            .ground_touching(ground, &["wire", "tube"])
            .build()
            .unwrap()
    };
    let tube_rebound = |damped: bool| {
        let model = model(damped);
        let nodes = model.beams[1].nodes.clone();
        rebound(model, nodes, h)
    };
    let elastic = tube_rebound(false);
    assert!(
        (elastic - 1.0).abs() < 1e-4,
        "elastic rebound ratio {elastic}"
    );
    // Its contact's resolution is judged on its own mass per length (four
    // times the wire's): at h = 4 ms neither resolves, at 2 ms the tube's
    // does and the wire's does not.
    let partners = |h: f64| -> Vec<String> {
        let u = model(false).unresolved_contacts(h);
        u.iter().map(|u| u.partner.clone()).collect()
    };
    let under = "ground 0 under member \"tube\"".to_string();
    let coarse = partners(4e-3);
    assert!(
        coarse.contains(&under) && coarse.contains(&"ground 0".into()),
        "{coarse:?}"
    );
    let finer = partners(2e-3);
    assert!(
        !finer.contains(&under) && finer.contains(&"ground 0".into()),
        "{finer:?}"
    );
    let expected =
        hunt_crossley_rebound(ContactDamping::new(e, RestitutionModel::Exact).coefficient());
    let got = tube_rebound(true);
    let err = (got - expected).abs() / expected;
    assert!(
        err < 2e-4,
        "rebound {got:.5}, closed form {expected:.5} ({err:.1e})"
    );
}
