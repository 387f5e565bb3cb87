//! The locking remedies (the default) against beam theory, the
//! paper's plain formulation kept selectable, uniform stretch unchanged.

mod common;
use ancf_core::element::ElementIntegration;
use ancf_core::material::{Locking, Material};
use ancf_core::model::{Model, PointLoad, Support, SupportKind};
use ancf_core::section::Section;
use ancf_core::solve::statics::{StaticSettings, solve_static};
use common::*;
use std::f64::consts::PI;

fn tip(section: Section, n: usize, force: [f64; 3]) -> [f64; 3] {
    let el = ElementIntegration::new(1.0 / n as f64, 5, section);
    let model = Model::new(
        el,
        n,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        vec![Support::new(0, SupportKind::Clamp)],
        None,
        vec![PointLoad {
            node: n,
            force,
            ..Default::default()
        }],
    )
    .unwrap();
    let res = solve_static(
        &model,
        &StaticSettings {
            load_steps: 2,
            ..Default::default()
        },
    )
    .expect("converges");
    let p = model.node_position(&res.q, n);
    let p0 = model.node_position(&model.reference, n);
    [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]]
}

fn with(m: Material, locking: Locking) -> Material {
    Material { locking, ..m }
}

#[test]
fn poisson_cantilever_within_two_percent_of_timoshenko() {
    let (e, nu, r): (f64, f64, f64) = (2e9, 0.3, 0.02);
    let i = PI * r.powi(4) / 4.0;
    let a = PI * r * r;
    let g = e / (2.0 * (1.0 + nu));
    let kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu); // solid circle
    let f = 1.0;
    let theory = f / (3.0 * e * i) + f / (kappa * g * a);
    let section = |lock| {
        Section::circular(
            &[
                (0.0, 0.01, with(svk(e, nu, 1.0), lock)),
                (0.01, 0.02, with(svk(e, nu, 1.0), lock)),
            ],
            3,
        )
    };
    let remedy = -tip(section(Locking::Centerline), 16, [0.0, 0.0, -f])[2];
    let plain = -tip(section(Locking::None), 16, [0.0, 0.0, -f])[2];
    println!(
        "ν = 0.3 cantilever: remedy {:.2} %, plain {:.2} % against F L³/(3EI) + F L/(κGA)",
        100.0 * (remedy / theory - 1.0),
        100.0 * (plain / theory - 1.0)
    );
    assert!(
        (remedy / theory - 1.0).abs() < 0.02,
        "remedy {remedy} vs {theory}"
    );
    assert!(
        plain / theory < 0.85,
        "the plain formulation locks (too stiff): {plain} vs {theory}"
    );
}

#[test]
fn rubber_rod_bends_within_five_percent_of_small_strain_theory() {
    let mr = mooney_rivlin(1e3);
    let ec = 6.0 * (5e5 + 1e5);
    let i = PI * 0.02f64.powi(4) / 4.0;
    let f = 1e-3;
    let theory = f / (3.0 * ec * i);
    let remedy = -tip(
        Section::circular(&[(0.0, 0.02, with(mr.clone(), Locking::Centerline))], 4),
        16,
        [0.0, 0.0, -f],
    )[2];
    let plain = -tip(
        Section::circular(&[(0.0, 0.02, with(mr, Locking::None))], 4),
        16,
        [0.0, 0.0, -f],
    )[2];
    println!(
        "rubber rod: remedy {:.2} %, plain {:.0}× too stiff",
        100.0 * (remedy / theory - 1.0),
        theory / plain
    );
    assert!(
        (remedy / theory - 1.0).abs() < 0.05,
        "remedy {remedy} vs {theory}"
    );
    assert!(
        theory / plain > 100.0,
        "the plain Mooney–Rivlin rod locks: {plain} vs {theory}"
    );
}

#[test]
fn svk_core_with_rubber_cover_within_two_percent_of_composite_theory() {
    let ec = 6.0 * (5e5 + 1e5);
    let ei = 2e9 * PI * 0.01f64.powi(4) / 4.0 + ec * PI * (0.02f64.powi(4) - 0.01f64.powi(4)) / 4.0;
    let f = 0.01;
    let theory = f / (3.0 * ei);
    let section = |lock| {
        Section::circular(
            &[
                (0.0, 0.01, with(svk(2e9, 0.0, 1.0), lock)),
                (0.01, 0.02, with(mooney_rivlin(1e3), lock)),
            ],
            4,
        )
    };
    let remedy = -tip(section(Locking::Centerline), 16, [0.0, 0.0, -f])[2];
    let plain = -tip(section(Locking::None), 16, [0.0, 0.0, -f])[2];
    println!(
        "core + cover: remedy {:.2} %, plain {:.1}× too stiff",
        100.0 * (remedy / theory - 1.0),
        theory / plain
    );
    assert!(
        (remedy / theory - 1.0).abs() < 0.02,
        "remedy {remedy} vs {theory}"
    );
}

#[test]
fn uniform_stretch_is_unchanged_by_the_remedies() {
    for (name, m) in [
        ("SVK ν=0.3", svk(2e9, 0.3, 1.0)),
        ("Mooney-Rivlin", mooney_rivlin(1e3)),
        ("SVK ω=0.3", svk(2e9, 0.3, 0.3)),
    ] {
        let f = if name.starts_with("Mooney") {
            50.0
        } else {
            1e4
        };
        let remedy = tip(
            Section::circular(&[(0.0, 0.02, with(m.clone(), Locking::Centerline))], 4),
            4,
            [f, 0.0, 0.0],
        )[0];
        let plain = tip(
            Section::circular(&[(0.0, 0.02, with(m, Locking::None))], 4),
            4,
            [f, 0.0, 0.0],
        )[0];
        println!("{name}: stretch remedy {remedy:.6e}, plain {plain:.6e}");
        assert!(
            (remedy / plain - 1.0).abs() < 1e-4,
            "{name}: {remedy} vs {plain}"
        );
    }
}
