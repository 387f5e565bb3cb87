//! The ring/disk rule and Gauss–Legendre are exact where theory
//! says, and only there.

use ancf_core::math::quadrature::{gauss_legendre_unit, ring_monomial_integral, ring_rule};

/// Largest relative error over the monomials of total degree `deg`.
fn worst_error(n: usize, r1: f64, r2: f64, deg: u32) -> f64 {
    let pts = ring_rule(n, r1, r2);
    let scale = ring_monomial_integral(deg + deg % 2, 0, r1, r2).abs(); // size of a degree-`deg` integral
    (0..=deg)
        .map(|a| {
            let b = deg - a;
            let q: f64 = pts
                .iter()
                .map(|p| p.weight * p.y.powi(a as i32) * p.z.powi(b as i32))
                .sum();
            (q - ring_monomial_integral(a, b, r1, r2)).abs() / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn ring_rule_is_exact_to_degree_2n_minus_1_on_disks_and_rings() {
    for (r1, r2) in [(0.0, 1.0), (0.5, 1.0), (0.01, 0.02), (0.0, 0.013)] {
        for n in 1..=8 {
            for deg in 0..=(2 * n as u32 - 1) {
                let err = worst_error(n, r1, r2, deg);
                assert!(
                    err < 1e-12,
                    "ring ({r1}, {r2}) n={n} degree {deg}: relative error {err:e}"
                );
            }
            let err = worst_error(n, r1, r2, 2 * n as u32);
            assert!(
                err > 1e-6,
                "ring ({r1}, {r2}) n={n} must not be exact at degree 2n (error {err:e})"
            );
        }
    }
}

#[test]
fn ring_rule_point_counts_merge_the_centre() {
    for n in 1..=8 {
        let disk = ring_rule(n, 0.0, 1.0).len();
        let ring = ring_rule(n, 0.5, 1.0).len();
        let expected = if n % 2 == 0 { n * n } else { n * n - n + 1 };
        assert_eq!(disk, expected, "disk n={n}");
        // On a ring, odd n also puts one (merged) node at the centre, in the hole.
        assert_eq!(ring, expected, "ring n={n}");
        assert!(ring_rule(n, 0.5, 1.0).iter().all(|p| p.weight > 0.0));
    }
}

#[test]
fn ring_rule_area_and_second_moment() {
    let pts = ring_rule(3, 0.01, 0.02);
    let area: f64 = pts.iter().map(|p| p.weight).sum();
    let iy: f64 = pts.iter().map(|p| p.weight * p.z * p.z).sum();
    let pi = std::f64::consts::PI;
    assert!((area - pi * (0.02f64.powi(2) - 0.01f64.powi(2))).abs() < 1e-16);
    assert!((iy - pi * (0.02f64.powi(4) - 0.01f64.powi(4)) / 4.0).abs() < 1e-20);
}

#[test]
fn build_time_axial_constants_match_runtime_rules() {
    // The generated kernels use the rule computed by build.rs (Newton on P_n);
    // the runtime uses Golub–Welsch. They must agree.
    use ancf_core::element::{COMPILED_AXIAL_ORDERS, compiled_axial_rule};
    assert!(!COMPILED_AXIAL_ORDERS.is_empty());
    for &n in COMPILED_AXIAL_ORDERS {
        let r = gauss_legendre_unit(n);
        let (nodes, weights) = compiled_axial_rule(n).expect("a compiled order has a rule");
        assert_eq!(nodes.len(), n);
        for i in 0..n {
            assert!((nodes[i] - r.nodes[i]).abs() < 1e-15, "order {n} node {i}");
            assert!(
                (weights[i] - r.weights[i]).abs() < 1e-15,
                "order {n} weight {i}"
            );
        }
    }
    assert!(compiled_axial_rule(17).is_none());
}

#[test]
fn weighted_ring_rule_integrates_layered_stiffness_exactly() {
    use ancf_core::math::quadrature::ring_rule_weighted;
    let pieces = [(0.0, 0.0052, 3.0), (0.0052, 0.01407, 1.0)];
    for n in 1..=6 {
        let pts = ring_rule_weighted(n, &pieces);
        for deg in 0..=(2 * n as u32 - 1) {
            for a in 0..=deg {
                let b = deg - a;
                let q: f64 = pts
                    .iter()
                    .map(|p| p.weight * p.y.powi(a as i32) * p.z.powi(b as i32))
                    .sum();
                let exact: f64 = pieces
                    .iter()
                    .map(|&(r1, r2, c)| c * ring_monomial_integral(a, b, r1, r2))
                    .sum();
                let scale = pieces
                    .iter()
                    .map(|&(r1, r2, c)| c * ring_monomial_integral(deg + deg % 2, 0, r1, r2))
                    .sum::<f64>();
                assert!(
                    (q - exact).abs() < 1e-12 * scale,
                    "n={n} y^{a} z^{b}: {q} vs {exact}"
                );
            }
        }
    }
}
