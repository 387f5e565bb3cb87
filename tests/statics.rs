//! The two-layer cantilever against beam theory (SPEC §8), the
//! slower axial convergence of `fixed`, and the large-deflection elastica.

#[path = "../ancf-core/tests/common/mod.rs"]
mod common;
use ancf_core::element::ElementIntegration;
use ancf_core::model::{Model, PointLoad, Support, SupportKind};
use ancf_core::section::Section;
use ancf_core::solve::statics::{StaticSettings, solve_static};
use common::*;

const LENGTH: f64 = 1.0;

fn cantilever(section: Section, n: usize, kind: SupportKind, force: [f64; 3]) -> Model {
    let el = ElementIntegration::new(LENGTH / n as f64, 5, section);
    Model::new(
        el,
        n,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        vec![Support::new(0, kind)],
        None,
        vec![PointLoad {
            node: n,
            force,
            ..Default::default()
        }],
    )
    .unwrap()
}

fn tip_displacement(model: &Model, steps: usize) -> [f64; 3] {
    let settings = StaticSettings {
        load_steps: steps,
        ..Default::default()
    };
    let res = solve_static(model, &settings).expect("static solve converges");
    let n = model.n_elements;
    let p = model.node_position(&res.q, n);
    let p0 = model.node_position(&model.reference, n);
    [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]]
}

/// Exact St. Venant–Kirchhoff bar: Σ E_k A_k · λ(λ² − 1)/2 = F, elongation (λ − 1) L.
fn svk_bar_elongation(ea: f64, f: f64) -> f64 {
    ancf::study::reference::svk_bar_strain(ea, f) * LENGTH
}

fn paper_section(e1: f64, e2: f64) -> Section {
    two_layer(svk(e1, 0.0, 1.0), svk(e2, 0.0, 1.0), 3)
}

#[test]
fn axial_elongation_is_the_exact_svk_bar_value_for_every_mesh() {
    let section = paper_section(2e9, 2e9);
    let exact = svk_bar_elongation(section.axial_stiffness(), 1000.0);
    assert!((exact - 3.97650e-4).abs() < 5e-9, "SVK bar value {exact:e}");
    for n in [1, 2, 4, 8, 16] {
        let d = tip_displacement(
            &cantilever(section.clone(), n, SupportKind::Clamp, [1000.0, 0.0, 0.0]),
            1,
        );
        let err = (d[0] - exact).abs() / exact;
        println!(
            "axial clamp n={n}: {:.6e} (exact {exact:.6e}) rel err {err:.2e}",
            d[0]
        );
        assert!(err < 1e-4, "n={n}: elongation {} vs {exact}", d[0]);
    }
}

#[test]
fn fixed_root_converges_slowly_in_axial_elongation() {
    let section = paper_section(2e9, 2e9);
    let exact = svk_bar_elongation(section.axial_stiffness(), 1000.0);
    let errs: Vec<f64> = [1, 4, 16]
        .iter()
        .map(|&n| {
            let d = tip_displacement(
                &cantilever(section.clone(), n, SupportKind::Fixed, [1000.0, 0.0, 0.0]),
                1,
            );
            (d[0] - exact) / exact
        })
        .collect();
    println!("axial fixed errors n=1,4,16: {errs:?}");
    // Too stiff (zero axial strain imposed at the root), error falling with n.
    assert!(errs.iter().all(|e| *e < -1e-3));
    assert!(errs[0].abs() > errs[1].abs() && errs[1].abs() > errs[2].abs());
}

#[test]
fn transverse_deflection_within_half_percent_at_8_elements() {
    let section = paper_section(2e9, 2e9);
    let ei = section.bending_stiffness();
    let theory = 1.0 * LENGTH.powi(3) / (3.0 * ei);
    assert!((theory - 1.326e-3).abs() < 1e-6);
    let mut errs = Vec::new();
    for n in [1, 2, 4, 8, 16] {
        let d = tip_displacement(
            &cantilever(section.clone(), n, SupportKind::Clamp, [0.0, 0.0, -1.0]),
            1,
        );
        let err = (-d[2] - theory).abs() / theory;
        println!(
            "transverse n={n}: {:.6e} (theory {theory:.6e}) rel err {err:.2e}",
            -d[2]
        );
        errs.push(err);
    }
    assert!(errs[3] < 5e-3, "8 elements: {:.3e}", errs[3]);
}

#[test]
fn different_moduli_per_layer_within_one_percent_at_16_elements() {
    let section = paper_section(2e9, 5e8);
    let ei = section.bending_stiffness();
    let d = tip_displacement(
        &cantilever(section.clone(), 16, SupportKind::Clamp, [0.0, 0.0, -1.0]),
        1,
    );
    let theory = LENGTH.powi(3) / (3.0 * ei);
    assert!(
        ((-d[2] - theory) / theory).abs() < 0.01,
        "transverse {} vs {theory}",
        -d[2]
    );
    let exact = svk_bar_elongation(section.axial_stiffness(), 1000.0);
    let d = tip_displacement(
        &cantilever(section, 16, SupportKind::Clamp, [1000.0, 0.0, 0.0]),
        1,
    );
    assert!(
        ((d[0] - exact) / exact).abs() < 0.01,
        "axial {} vs {exact}",
        d[0]
    );
}

#[test]
fn large_deflection_matches_the_inextensible_elastica() {
    let section = paper_section(2e9, 2e9);
    let ei = section.bending_stiffness();
    let f = ei / LENGTH.powi(2);
    let d = tip_displacement(
        &cantilever(section, 16, SupportKind::Clamp, [0.0, 0.0, -f]),
        10,
    );
    let (dz, dx) = (-d[2] / LENGTH, d[0] / LENGTH);
    println!("elastica: dz/L = {dz:.5} (0.30172), dx/L = {dx:.5} (-0.05643)");
    assert!((dz - 0.30172).abs() / 0.30172 < 5e-3);
    assert!((dx + 0.05643).abs() / 0.05643 < 5e-3);
}
