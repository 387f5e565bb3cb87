//! The element's force is the gradient of its energy, its
//! Jacobian the gradient of the force, both vanish under rigid motion, the
//! generated kernel equals the generic one, and the mass and gravity are exact.

mod common;
use ancf_core::element::{ElementIntegration, KernelPath};
use ancf_core::section::Section;
use common::*;

const L: f64 = 0.5;

fn cases() -> Vec<(&'static str, Section)> {
    vec![
        (
            "SVK nu=0",
            two_layer(svk(2e9, 0.0, 1.0), svk(2e9, 0.0, 1.0), 3),
        ),
        (
            "SVK nu=0.3",
            two_layer(svk(2e9, 0.3, 1.0), svk(1e9, 0.3, 1.0), 3),
        ),
        (
            "weakened SVK omega=0.3",
            two_layer(svk(2e9, 0.0, 0.3), svk(2e9, 0.2, 0.3), 3),
        ),
        (
            "Mooney-Rivlin kappa=1e3",
            Section::circular(&[(0.0, 0.02, mooney_rivlin(1e3))], 4),
        ),
        (
            "SVK core + Mooney-Rivlin cover",
            two_layer(svk(2e9, 0.3, 0.5), mooney_rivlin(1e3), 4),
        ),
        (
            "rectangle SVK nu=0.3",
            Section::rectangular(0.03, 0.02, svk(2e9, 0.3, 1.0), 2),
        ),
    ]
}

fn force_jacobian(el: &ElementIntegration, e: &[f64; 24]) -> ([f64; 24], [f64; 576], f64) {
    let mut q = [0.0; 24];
    let mut k = [0.0; 576];
    let u = el.evaluate(e, &mut q, Some(&mut k));
    (q, k, u)
}

#[test]
fn force_and_jacobian_match_central_differences() {
    let mut rng = Rng::new(7);
    for (name, section) in cases() {
        let el = element(section, L, 3);
        for _ in 0..3 {
            let e = deformed(&mut rng, L, 0.15);
            let (q, k, _) = force_jacobian(&el, &e);
            let h = 1e-6;
            let mut fd_q = [0.0; 24];
            let mut fd_k = [0.0; 576];
            for j in 0..24 {
                let (mut ep, mut em) = (e, e);
                ep[j] += h;
                em[j] -= h;
                fd_q[j] = (el.energy(&ep) - el.energy(&em)) / (2.0 * h);
                let (qp, _, _) = force_jacobian(&el, &ep);
                let (qm, _, _) = force_jacobian(&el, &em);
                for i in 0..24 {
                    fd_k[i * 24 + j] = (qp[i] - qm[i]) / (2.0 * h);
                }
            }
            let eq = rel(&fd_q, &q);
            let ek = rel(&fd_k, &k);
            assert!(
                eq < 1e-6,
                "{name}: force vs FD of energy, relative error {eq:e}"
            );
            assert!(
                ek < 1e-6,
                "{name}: Jacobian vs FD of force, relative error {ek:e}"
            );
        }
    }
}

#[test]
fn jacobian_is_symmetric() {
    let mut rng = Rng::new(11);
    for (name, section) in cases() {
        let el = element(section, L, 3);
        let e = deformed(&mut rng, L, 0.2);
        let (_, k, _) = force_jacobian(&el, &e);
        let norm = k.iter().map(|v| v * v).sum::<f64>().sqrt();
        for i in 0..24 {
            for j in 0..24 {
                assert!(
                    (k[i * 24 + j] - k[j * 24 + i]).abs() < 1e-12 * norm,
                    "{name}: K[{i},{j}]"
                );
            }
        }
    }
}

#[test]
fn zero_energy_and_force_under_rigid_motion() {
    for (name, section) in cases() {
        let el = element(section, L, 3);
        let e0 = reference(L);
        let moved = rigid_motion(&e0, &rotation([0.3, -1.1, 0.7]), [0.4, -2.0, 1.5]);
        for e in [e0, moved] {
            let (q, k, u) = force_jacobian(&el, &e);
            let kn = k.iter().map(|v| v * v).sum::<f64>().sqrt();
            let qn = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            // Scale: the force a 1 % strain would produce.
            assert!(
                qn < 1e-9 * kn * 0.01,
                "{name}: force {qn:e} at a stress-free state"
            );
            assert!(
                u.abs() < 1e-9 * kn * 1e-4,
                "{name}: energy {u:e} at a stress-free state"
            );
        }
    }
}

/// The force and the tangent turn with the element: Q(R q) = T Q(q) and
/// K(R q) = T K(q) Tᵀ, T rotating each of its eight vectors by R. Modified
/// Newton's kept matrix relies on this when it turns with the nodes.
#[test]
fn force_and_tangent_turn_with_a_rigid_rotation() {
    let mut rng = Rng::new(11);
    for (name, section) in cases() {
        let el = element(section, L, 3);
        let e = deformed(&mut rng, L, 0.1);
        let r = rotation([0.9, -0.4, 1.3]);
        let (q, k, u) = force_jacobian(&el, &e);
        let (qr, kr, ur) = force_jacobian(&el, &rigid_motion(&e, &r, [0.2, 0.5, -0.3]));
        // T x for a 24-vector, and T M Tᵀ entry (i, j).
        let t = |i: usize, j: usize| if i / 3 == j / 3 { r[i % 3][j % 3] } else { 0.0 };
        let kn = k.iter().map(|v| v * v).sum::<f64>().sqrt();
        for i in 0..24 {
            let tq: f64 = (0..24).map(|j| t(i, j) * q[j]).sum();
            assert!((qr[i] - tq).abs() < 1e-12 * kn * L, "{name}: Q row {i}");
            for j in 0..24 {
                let tkt: f64 = (0..24)
                    .flat_map(|a| (0..24).map(move |b| (a, b)))
                    .filter(|&(a, b)| a / 3 == i / 3 && b / 3 == j / 3)
                    .map(|(a, b)| t(i, a) * k[a * 24 + b] * t(j, b))
                    .sum();
                assert!(
                    (kr[i * 24 + j] - tkt).abs() < 1e-12 * kn,
                    "{name}: K ({i}, {j}) {} against {tkt}",
                    kr[i * 24 + j]
                );
            }
        }
        assert!((ur - u).abs() < 1e-12 * kn * L * L, "{name}: energy");
    }
}

#[test]
fn generated_kernel_equals_generic_kernel() {
    let mut rng = Rng::new(3);
    for &order in ancf_core::element::COMPILED_AXIAL_ORDERS {
        for (name, section) in cases() {
            let el = element(section, L, order);
            assert_eq!(
                el.kernel_path(),
                KernelPath::Generated { axial_order: order }
            );
            let generic = el.clone().with_generic_kernel();
            assert_eq!(
                generic.kernel_path(),
                KernelPath::Generic { axial_order: order }
            );
            for _ in 0..2 {
                let e = deformed(&mut rng, L, 0.3);
                let (q1, k1, u1) = force_jacobian(&el, &e);
                let (q2, k2, u2) = force_jacobian(&generic, &e);
                assert!(rel(&q1, &q2) < 1e-12, "{name} order {order}: force");
                assert!(rel(&k1, &k2) < 1e-12, "{name} order {order}: Jacobian");
                assert!(
                    (u1 - u2).abs() <= 1e-12 * u2.abs(),
                    "{name} order {order}: energy"
                );
            }
        }
    }
}

#[test]
fn uncompiled_order_runs_the_generic_path_and_says_so() {
    let el = element(two_layer(svk(2e9, 0.0, 1.0), svk(2e9, 0.0, 1.0), 3), L, 7);
    assert_eq!(el.kernel_path(), KernelPath::Generic { axial_order: 7 });
    assert!(el.kernel_path().to_string().contains("ANCF_KERNEL_ORDERS"));
}

#[test]
fn mass_matrix_translation_rotation_and_gravity() {
    let pi = std::f64::consts::PI;
    let (rho1, rho2) = (7200.0, 2700.0);
    let mut core = svk(2e9, 0.0, 1.0);
    core.density = rho1;
    let mut cover = svk(7e10, 0.3, 1.0);
    cover.density = rho2;
    let el = element(two_layer(core, cover, 3), L, 3);
    let m = el.mass_matrix();
    let mass = (rho1 * pi * 0.01f64.powi(2) + rho2 * pi * (0.02f64.powi(2) - 0.01f64.powi(2))) * L;
    let quad = |v: &[f64; 24]| -> f64 {
        (0..24)
            .map(|i| (0..24).map(|j| v[i] * m[i * 24 + j] * v[j]).sum::<f64>())
            .sum()
    };
    // Uniform translation u: every position entry = u, gradients 0.
    let mut u = [0.0; 24];
    for blk in [0, 4] {
        u[3 * blk + 2] = 1.0;
    }
    assert!(
        (quad(&u) - mass).abs() < 1e-13 * mass,
        "translational mass {} vs {}",
        quad(&u),
        mass
    );
    // Rigid rotation about the beam axis at Ω: ė = Ω × (each 3-vector), KE = ½ J Ω².
    let omega = 2.0;
    let e0 = reference(L);
    let mut v = [0.0; 24];
    for blk in 0..8 {
        let (a, b, c) = (e0[3 * blk], e0[3 * blk + 1], e0[3 * blk + 2]);
        // Ω = (ω, 0, 0): Ω × (a, b, c) = (0, −ω c, ω b)
        let _ = a;
        v[3 * blk + 1] = -omega * c;
        v[3 * blk + 2] = omega * b;
    }
    let polar =
        rho1 * pi * 0.01f64.powi(4) / 2.0 + rho2 * pi * (0.02f64.powi(4) - 0.01f64.powi(4)) / 2.0;
    let ke = 0.5 * quad(&v);
    let expected = 0.5 * polar * L * omega * omega;
    assert!(
        (ke - expected).abs() < 1e-12 * expected,
        "rotary KE {ke} vs {expected}"
    );
    // Gravity sums to m g in the translation direction.
    let qg = el.gravity_force([0.0, 0.0, -9.81]);
    let total: f64 = [0, 4].iter().map(|blk| qg[3 * blk + 2]).sum();
    assert!((total + mass * 9.81).abs() < 1e-12 * mass * 9.81);
    // And the mass matrix is symmetric positive definite on a random vector.
    let mut rng = Rng::new(5);
    let w: [f64; 24] = std::array::from_fn(|_| rng.uniform());
    assert!(quad(&w) > 0.0);
}

/// Linear (SVK) laws are pre-integrated over the section — no
/// section points, whatever the section order and number of layers — and
/// equal the per-layer point quadrature to 1e-12.
#[test]
fn preintegrated_svk_layers_equal_point_quadrature() {
    let mut rng = Rng::new(17);
    for order in [2, 3, 5, 7] {
        for omega in [1.0, 0.3] {
            let section = two_layer(svk(2e9, 0.3, omega), svk(7e10, 0.3, omega), order);
            let el = element(section, L, 3);
            assert!(el.plan.is_preintegrated());
            assert_eq!(
                el.plan.points(),
                0,
                "order {order}, ω {omega}: no point work left"
            );
            let generic = el.clone().with_generic_kernel();
            for _ in 0..2 {
                let e = deformed(&mut rng, L, 0.2);
                let (q1, k1, u1) = force_jacobian(&el, &e);
                let (q2, k2, u2) = force_jacobian(&generic, &e);
                assert!(
                    rel(&q1, &q2) < 1e-12 && rel(&k1, &k2) < 1e-12,
                    "order {order}, ω {omega}"
                );
                assert!(
                    (u1 - u2).abs() <= 1e-12 * u2.abs(),
                    "energy, order {order}, ω {omega}"
                );
            }
        }
    }
    // The rectangle too (its own 2×2 rule's moments).
    let rect = element(
        ancf_core::section::Section::rectangular(0.03, 0.02, svk(2e9, 0.3, 1.0), 2),
        L,
        3,
    );
    assert!(rect.plan.is_preintegrated() && rect.plan.points() == 0);
    // A Mooney–Rivlin cover with the locking remedy: its section part (ν = 0
    // SVK) is pre-integrated with the core; the remainder stays on the centerline.
    let mixed = element(two_layer(svk(2e9, 0.0, 1.0), mooney_rivlin(1e3), 4), L, 3);
    assert!(mixed.plan.is_preintegrated() && mixed.plan.groups.is_empty());
    assert!(
        mixed
            .plan
            .centerline
            .iter()
            .any(|(law, _)| law.is_mooney_rivlin())
    );
    // With the plain formulation the cover keeps its own points and law.
    let plain = ancf_core::material::Material {
        locking: ancf_core::material::Locking::None,
        ..mooney_rivlin(1e3)
    };
    let mixed = element(two_layer(svk(2e9, 0.0, 1.0), plain, 4), L, 3);
    assert_eq!(mixed.plan.groups.len(), 1);
    assert!(mixed.plan.groups[0].law.is_mooney_rivlin());
}
