//! Graded meshes: one wire with elements of several
//! lengths — fine where it meets a rod, coarse elsewhere. The mass and the
//! weight are the wire's exactly; a "graded" mesh whose segments share one
//! element length is the uniform mesh bit for bit (the group boundaries
//! change only how elements are batched); the line law's resultant stays
//! exact while a crossing slides over the junction of two element lengths.

use ancf_core::element::reference_coordinates;
use ancf_core::forces::contact::ContactEvaluator;
use ancf_core::material::Material;
use ancf_core::model::contact::{Contact, ContactLaw, ContactSettings, Rod};
use ancf_core::model::{NODE_DOFS, Segment, WireBuilder};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::simulation::{Initial, Simulation};

fn segment(length: f64, elements: usize) -> Segment {
    Segment { length, elements }
}

#[test]
fn a_graded_wire_has_the_mass_and_weight_of_the_wire() {
    let (rho, radius, g) = (7850.0, 0.01, 9.81);
    let steel = Material::st_venant_kirchhoff(rho, 2e11, 0.3, 1.0);
    let segments = [segment(0.5, 2), segment(1.0, 10), segment(0.5, 1)];
    let model = WireBuilder::new(1.0, 1)
        .graded(&segments)
        .layer(steel, radius)
        .gravity([0.0, 0.0, -g])
        .build()
        .unwrap();
    assert_eq!(model.n_elements, 13);
    assert_eq!(model.groups.len(), 3);
    let lengths: Vec<f64> = (0..13).map(|el| model.element(el).length).collect();
    assert_eq!(&lengths[..3], &[0.25, 0.25, 0.1]);
    assert_eq!(lengths[12], 0.5);
    // Nodes sit at their arc length along the (x) axis.
    for n in 0..model.n_nodes() {
        let x = model.node_position(&model.reference, n)[0];
        assert!((x - model.node_arc(n)).abs() < 1e-15, "node {n}: {x}");
    }
    assert!((model.length() - 2.0).abs() < 1e-15);

    let mass = rho * std::f64::consts::PI * radius * radius * 2.0;
    assert!((model.total_mass() - mass).abs() < 1e-12 * mass);
    // M times a unit translation along x: the position rows carry the mass.
    let mut x = vec![0.0; model.reference.len()];
    for n in 0..model.n_nodes() {
        x[NODE_DOFS * n] = 1.0;
    }
    let mx = model.mass_times(&x);
    let carried: f64 = (0..model.n_nodes()).map(|n| mx[NODE_DOFS * n]).sum();
    assert!((carried - mass).abs() < 1e-12 * mass, "{carried} vs {mass}");
    // The generalized weight's position rows add up to m g.
    let w = model.gravity_force().unwrap();
    let weight: f64 = (0..model.n_nodes()).map(|n| w[NODE_DOFS * n + 2]).sum();
    assert!((weight + mass * g).abs() < 1e-12 * mass * g, "{weight}");
}

/// The impact scene on `mesh` (a `[wire]` line), shortened to 0.35 s: the
/// wire strikes the rod at about 0.24 s.
fn impact(mesh: &str) -> Simulation {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    ))
    .unwrap()
    .replace("end_time = 1.0", "end_time = 0.35")
    .replace("elements = 64", mesh);
    let scene = Scene::from_toml(&text).expect("valid scene");
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        panic!("dynamic")
    };
    let mut sim = Simulation::new(&scene.model, settings.clone(), Initial::Reference).unwrap();
    while !sim.is_finished() {
        sim.step().unwrap();
    }
    sim
}

#[test]
fn segments_of_one_element_length_are_the_uniform_mesh_bit_for_bit() {
    // 11 + 21 elements of 1/16 m: both group ends fall inside a batch of
    // four elements of the uniform mesh's force and mass loops.
    let uniform = impact("elements = 32");
    let graded = impact(
        "segments = [ { length = 0.6875, elements = 11 }, { length = 1.3125, elements = 21 } ]",
    );
    assert_eq!(graded.model().groups.len(), 2);
    assert!(
        uniform.rod_loads()[0].force.iter().any(|f| f[2] != 0.0),
        "the wire reached the rod"
    );
    assert_eq!(uniform.state().q, graded.state().q);
    assert_eq!(uniform.state().v, graded.state().v);
    assert_eq!(uniform.rod_loads(), graded.rod_loads());
}

const RW: f64 = 0.01407; // wire radius, m
const RR: f64 = 0.02; // rod radius, m
const EPS_L: f64 = 5e7; // N/m²

#[test]
fn a_crossing_slides_over_a_change_of_element_length_with_the_exact_force() {
    // Two elements of 0.125 m (group 0), then three of 0.04 m (group 1).
    let (l0, l1) = (0.125, 0.04);
    let delta = 1e-3;
    let rs = RW + RR;
    let d = rs - delta;
    let s0 = (rs * rs - d * d).sqrt();
    let exact = 2.0 * EPS_L * d * (rs * (s0 / d).asinh() - s0);
    let mut worst = 0.0f64;
    // From mid-element 1 over the junction at x = 0.25 m to mid-element 3.
    for k in 0..=50 {
        let x = 1.5 * l0 + k as f64 * (0.5 * l0 + 1.5 * l1) / 50.0;
        let rod = Rod {
            center: [x, 0.0, -rs + delta],
            axis: [0.0, 1.0, 0.0],
            radius: RR,
            shape: Default::default(),
            length: None,
            law: ContactLaw::Line,
            contact_stiffness: EPS_L,
            friction: 0.0,
            damping: None,
        };
        let c = ContactEvaluator::new(
            &Contact::new(vec![rod], ContactSettings::default(), RW),
            &[l0, l1],
        );
        let elements = [
            (0, 0.0, l0),
            (0, l0, l0),
            (1, 2.0 * l0, l1),
            (1, 2.0 * l0 + l1, l1),
        ];
        let mut force = 0.0;
        for (group, start, l) in elements {
            let e = reference_coordinates(
                [start, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                l,
            );
            let mut q = [0.0; 24];
            let (s, _) = c.element(group, &e, &[0.0; 24], &mut q, None, None);
            force += s.force[2];
        }
        worst = worst.max((force - exact).abs() / exact);
    }
    assert!(worst < 1e-6, "largest deviation {worst:e} of {exact} N");
}

#[test]
fn a_uniformly_stretched_graded_wire_carries_one_stress() {
    // ν = 0, ω = 1: a uniform stretch λ along the axis is an exact state of
    // every element, whatever its length, with E_xx = (λ² − 1)/2. The
    // internal forces cancel at interior nodes and the energy is
    // ½ E A L E_xx² — only if each element is integrated with its own length.
    let (e_mod, radius) = (2e11, 0.01);
    let steel = Material::st_venant_kirchhoff(7850.0, e_mod, 0.0, 1.0);
    let segments = [segment(0.3, 1), segment(0.7, 14), segment(1.0, 2)];
    let model = WireBuilder::new(1.0, 1)
        .graded(&segments)
        .layer(steel, radius)
        .build()
        .unwrap();
    let lambda = 1.001;
    let mut q = model.reference.clone();
    for n in 0..model.n_nodes() {
        q[NODE_DOFS * n] *= lambda;
        q[NODE_DOFS * n + 3] *= lambda;
    }
    let pattern = ancf_core::forces::assembly::pattern(&model);
    let (force, energy) = ancf_core::forces::assembly::assemble(&model, &pattern, &q, None);
    let exx = 0.5 * (lambda * lambda - 1.0);
    let area = std::f64::consts::PI * radius * radius;
    let expected = 0.5 * e_mod * area * 2.0 * exx * exx;
    assert!(
        (energy - expected).abs() < 1e-9 * expected,
        "{energy} vs {expected}"
    );
    // The end force: EA E_xx λ (N) on the position rows of the end nodes.
    let end = e_mod * area * exx * lambda;
    let last = model.n_elements;
    assert!((force[NODE_DOFS * last] - end).abs() < 1e-8 * end);
    assert!((force[0] + end).abs() < 1e-8 * end);
    for n in 1..last {
        for c in 0..NODE_DOFS {
            let f = force[NODE_DOFS * n + c];
            assert!(f.abs() < 1e-8 * end, "node {n}, coordinate {c}: {f} N");
        }
    }
}
