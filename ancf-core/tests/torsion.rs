//! A tip moment, applied through the tip node's section gradients,
//! twists a straight, solid circular bar by T L / (G J), J = π R⁴ / 2, with
//! and without Poisson's ratio: the locking remedy keeps the true shear
//! modulus in the section, where torsion's shear strain lives (on the
//! centerline it vanishes).

use ancf_core::prelude::*;

/// The twist (rad) of node `n` about x: the angle of its r_y in the y–z plane.
fn twist(q: &[f64], n: usize) -> f64 {
    let b = 12 * n + 6;
    q[b + 2].atan2(q[b + 1])
}

#[test]
fn a_tip_moment_twists_a_bar_by_t_l_over_g_j() {
    let (l, r, e, t) = (1.0_f64, 0.01_f64, 2e11_f64, 20.0_f64);
    for nu in [0.0, 0.3] {
        let g = e / (2.0 * (1.0 + nu));
        let j = std::f64::consts::PI * r.powi(4) / 2.0;
        let theory = t * l / (g * j);
        let steel = Material::st_venant_kirchhoff(7800.0, e, nu, 1.0);
        let elements = 8;
        let model = WireBuilder::new(l, elements)
            .layer(steel, r)
            .support(0, SupportKind::Clamp)
            .moment(elements, [t, 0.0, 0.0])
            .build()
            .unwrap();
        let result = solve_static(&model, &StaticSettings::default()).expect("converges");
        let phi = twist(&result.q, elements);
        // The model's own reading of the twist (the outputs') is the same.
        let read = model.node_twist(&result.q, model.n_nodes() - 1);
        assert!(
            (read - phi).abs() < 1e-6 * phi.abs(),
            "{read} against {phi}"
        );
        let error = (phi - theory) / theory;
        assert!(
            error.abs() < 0.02,
            "ν = {nu}: twist {phi:.6e} rad against {theory:.6e} ({:+.3} %)",
            100.0 * error
        );
        // Halfway along, half the twist.
        let half = twist(&result.q, elements / 2);
        assert!(
            (half / phi - 0.5).abs() < 0.02,
            "midpoint twist {half} of {phi}"
        );
    }
}

/// With ν = 0.3 the plain formulation (no locking remedy) and the default
/// remedy twist alike, by T L / (G J).
#[test]
fn with_poisson_both_formulations_twist_by_t_l_over_g_j() {
    let (l, r, e, t, nu) = (1.0_f64, 0.01_f64, 2e11_f64, 20.0_f64, 0.3_f64);
    let g = e / (2.0 * (1.0 + nu));
    let theory = t * l / (g * std::f64::consts::PI * r.powi(4) / 2.0);
    let solve = |locking| {
        let mut steel = Material::st_venant_kirchhoff(7800.0, e, nu, 1.0);
        steel.locking = locking;
        let model = WireBuilder::new(l, 8)
            .layer(steel, r)
            .support(0, SupportKind::Clamp)
            .moment(8, [t, 0.0, 0.0])
            .build()
            .unwrap();
        twist(
            &solve_static(&model, &StaticSettings::default()).unwrap().q,
            8,
        )
    };
    for locking in [
        ancf_core::material::Locking::None,
        ancf_core::material::Locking::Centerline,
    ] {
        let phi = solve(locking);
        assert!(
            (phi / theory - 1.0).abs() < 0.02,
            "{locking:?}: {phi} against {theory}"
        );
    }
}

/// A rectangle twists with Saint-Venant's G J, not the G I_p that the
/// element's linear section field alone would give (I_p / J = 1.19 for a
/// square, 2.7 for a 4 : 1 strip): T L / (G J) within 1 %, with and
/// without Poisson's ratio, either way up. J from the exact series (the
/// square's 0.1406 a⁴).
#[test]
fn a_rectangle_twists_by_t_l_over_saint_venants_g_j() {
    let (l, e, t) = (1.0_f64, 2e11_f64, 20.0_f64);
    let j_square = ancf_core::section::saint_venant_torsion(0.02, 0.02);
    assert!(
        (j_square / 0.02f64.powi(4) - 0.1406).abs() < 1e-4,
        "{j_square}"
    );
    for (width, height) in [(0.02, 0.02), (0.04, 0.01), (0.01, 0.04)] {
        for nu in [0.0, 0.3] {
            let g = e / (2.0 * (1.0 + nu));
            let j = ancf_core::section::saint_venant_torsion(width, height);
            let theory = t * l / (g * j);
            let steel = Material::st_venant_kirchhoff(7800.0, e, nu, 1.0);
            let elements = 8;
            let model = WireBuilder::new(l, elements)
                .rectangle(steel, width, height)
                .support(0, SupportKind::Clamp)
                .moment(elements, [t, 0.0, 0.0])
                .build()
                .unwrap();
            let result = solve_static(&model, &StaticSettings::default()).expect("converges");
            let phi = twist(&result.q, elements);
            let error = phi / theory - 1.0;
            eprintln!(
                "{width} × {height}, ν = {nu}: twist {phi:.5e} against {theory:.5e} ({:+.3} %)",
                100.0 * error
            );
            assert!(
                error.abs() < 0.01,
                "{width} × {height}, ν = {nu}: {:+.3} %",
                100.0 * error
            );
        }
    }
}
