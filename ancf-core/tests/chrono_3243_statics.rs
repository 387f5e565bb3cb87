//! Project Chrono's statics checks of its 3243 beam element
//! (`utest_FEA_ANCFbeam_3243_Formulation.cpp`), on the same beam: the
//! Princeton beam's dimensions (20 × 0.125 × 0.5 in) in aluminium 7075-T651
//! (E = 71.7 GPa, ν = 0.33, ρ = 2810 kg/m³), 20 elements, the root fixed in
//! all its coordinates, against the same closed forms and Chrono's 2 %:
//! an axial pull P L / (E A), a tip load P L³ / (3 E I), its own weight
//! w L⁴ / (8 E I), and the twist of the square variant (0.5 × 0.5 in) under
//! a tip torque, T L / (G J) with J = 2.25 (a / 2)⁴ — and of the original
//! 4 : 1 section, which Chrono's check leaves out.

use ancf_core::material::Material;
use ancf_core::model::{SupportKind, WireBuilder};
use ancf_core::solve::statics::{StaticSettings, solve_static};

const INCH: f64 = 0.0254;
const L: f64 = 20.0 * INCH;
const E: f64 = 71.7e9;
const NU: f64 = 0.33;
const RHO: f64 = 2810.0;
const N: usize = 20;

fn aluminium() -> Material {
    Material::st_venant_kirchhoff(RHO, E, NU, 1.0)
}

/// The beam (width along y, height along z) fixed at its root, loaded by
/// `build`; its tip node's twelve coordinates at equilibrium.
fn tip(width: f64, height: f64, build: impl Fn(WireBuilder) -> WireBuilder) -> [f64; 12] {
    let builder = WireBuilder::new(L, N)
        .rectangle(aluminium(), width, height)
        .support(0, SupportKind::Fixed);
    let model = build(builder).build().unwrap();
    let res = solve_static(&model, &StaticSettings::default()).unwrap();
    std::array::from_fn(|k| res.q[12 * N + k])
}

fn check(what: &str, got: f64, theory: f64) {
    let error = got / theory - 1.0;
    eprintln!(
        "{what}: {got:.6e} against {theory:.6e} ({:+.3} %)",
        100.0 * error
    );
    assert!(error.abs() < 0.02, "{what}: {:+.3} %", 100.0 * error);
}

#[test]
fn chronos_3243_statics_cases_on_the_princeton_beam() {
    let (w, h) = (0.125 * INCH, 0.5 * INCH);
    let (area, inertia) = (w * h, w * h.powi(3) / 12.0);
    // Axial pull, 1 N.
    let q = tip(w, h, |b| b.load(N, [1.0, 0.0, 0.0]));
    check("axial pull", q[0] - L, L / (E * area));
    // Tip load across the height, 1 N.
    let q = tip(w, h, |b| b.load(N, [0.0, 0.0, 1.0]));
    check("tip load", q[2], L.powi(3) / (3.0 * E * inertia));
    // Its own weight.
    let g = 9.80665;
    let q = tip(w, h, |b| b.gravity([0.0, 0.0, -g]));
    check(
        "gravity",
        -q[2],
        RHO * area * g * L.powi(4) / (8.0 * E * inertia),
    );
    // The square variant twisted by 1 N m.
    let a = 0.5 * INCH;
    let q = tip(a, a, |b| b.moment(N, [1.0, 0.0, 0.0]));
    let twist = q[8].atan2(q[7]);
    let shear = E / (2.0 * (1.0 + NU));
    check("twist", twist, L / (shear * 2.25 * (0.5 * a).powi(4)));
    // And the original 4 : 1 section, which Chrono leaves out ("the error
    // is noticeably higher"): Saint-Venant's J from the exact series.
    let q = tip(w, h, |b| b.moment(N, [1.0, 0.0, 0.0]));
    let twist = q[8].atan2(q[7]);
    let j = ancf_core::section::saint_venant_torsion(w, h);
    check("twist, 4 : 1", twist, L / (shear * j));
}
