//! A tip moment, applied through the tip node's gradient coordinates,
//! twists a straight, solid circular bar by T L / (G J), J = π R⁴ / 2 — for
//! ν = 0. With ν > 0 the default locking remedy (the Poisson part of D on
//! the centerline, where torsion has no shear strain) leaves the section
//! the shear modulus E / 2 of ν = 0: torsion is (1 + ν) too stiff, which the
//! second test pins down until the remedy keeps G in the section.

use ancf_core::prelude::*;

/// The twist (rad) of node `n` about x: the angle of its r_y in the y–z plane.
fn twist(q: &[f64], n: usize) -> f64 {
    let b = 12 * n + 6;
    q[b + 2].atan2(q[b + 1])
}

#[test]
fn a_tip_moment_twists_a_bar_by_t_l_over_g_j() {
    let (l, r, e, t) = (1.0_f64, 0.01_f64, 2e11_f64, 20.0_f64);
    {
        let nu = 0.0;
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

/// With ν = 0.3 the plain formulation (no locking remedy) twists by
/// T L / (G J) too; the default remedy is (1 + ν) stiffer (the known
/// limitation above).
#[test]
fn with_poisson_the_remedy_stiffens_torsion_by_one_plus_nu() {
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
    let plain = solve(ancf_core::material::Locking::None);
    assert!(
        (plain / theory - 1.0).abs() < 0.02,
        "plain: {plain} against {theory}"
    );
    let remedy = solve(ancf_core::material::Locking::Centerline);
    assert!(
        (theory / remedy / (1.0 + nu) - 1.0).abs() < 0.02,
        "remedy: {remedy} against {theory}"
    );
}
