//! Beam-type J2 plasticity at a point and over a section: a bar's
//! stress–strain curve, the consistent tangent against central
//! differences, the Bauschinger effect and the loop's area, the
//! Cowper–Symonds rate law, and the moment–curvature relation of a tube
//! and a solid circle against their closed forms.

use ancf_core::material::Material;
use ancf_core::material::beam_plasticity::{
    BeamPlasticity, CowperSymonds, Hardening, PlasticState, PointResponse,
};
use ancf_core::section::Section;

const E: f64 = 210e9;
const G: f64 = 210e9 / 2.6;
const FY: f64 = 235e6;

fn law(h: f64, hardening: Hardening) -> BeamPlasticity {
    BeamPlasticity {
        youngs_modulus: E,
        shear_modulus: G,
        yield_stress: FY,
        hardening_modulus: h,
        hardening,
        rate: None,
    }
}

/// Strain the point along `path` (each row ε₁₁, γ₂, γ₃), keeping the
/// state; returns each step's response.
fn follow(l: &BeamPlasticity, path: &[[f64; 3]], dt: Option<f64>) -> Vec<PointResponse> {
    let mut state = PlasticState::default();
    path.iter()
        .map(|&e| {
            let r = l.respond(e, &state, dt);
            state = r.state;
            r
        })
        .collect()
}

#[test]
fn a_bar_in_tension_follows_the_bilinear_curve() {
    let h = E / 100.0;
    for hardening in [Hardening::Kinematic, Hardening::Isotropic] {
        let l = law(h, hardening);
        let path: Vec<[f64; 3]> = (1..=50).map(|k| [k as f64 * 1e-4, 0.0, 0.0]).collect();
        for (e, r) in path.iter().zip(follow(&l, &path, None)) {
            let ey = FY / E;
            let expected = if e[0] <= ey {
                E * e[0]
            } else {
                FY + E * h / (E + h) * (e[0] - ey)
            };
            assert!(
                (r.stress[0] - expected).abs() < 1e-9 * expected,
                "{hardening:?}, ε = {}: σ = {}, expected {expected}",
                e[0],
                r.stress[0]
            );
        }
    }
}

#[test]
fn the_tangent_is_the_derivative_of_the_return_map() {
    let cases = [
        (0.0, Hardening::Kinematic, None),
        (E / 50.0, Hardening::Kinematic, None),
        (E / 50.0, Hardening::Isotropic, None),
        (
            E / 50.0,
            Hardening::Kinematic,
            Some(CowperSymonds { d: 40.4, q: 5.0 }),
        ),
    ];
    // A prior plastic step, so the state carries plastic strain and back
    // stress; then a mixed axial–shear step that yields again.
    let old_path = [[3e-3, 1e-3, -5e-4]];
    let strain = [4e-3, 2e-3, -1e-3];
    for (h, hardening, rate) in cases {
        let l = BeamPlasticity {
            rate,
            ..law(h, hardening)
        };
        let dt = Some(1e-4);
        let old = follow(&l, &old_path, dt)[0].state;
        let r = l.respond(strain, &old, dt);
        assert!(r.yielding);
        let step = 1e-9;
        for m in 0..3 {
            let (mut ep, mut em) = (strain, strain);
            ep[m] += step;
            em[m] -= step;
            let (sp, sm) = (
                l.respond(ep, &old, dt).stress,
                l.respond(em, &old, dt).stress,
            );
            for i in 0..3 {
                let fd = (sp[i] - sm[i]) / (2.0 * step);
                let err = (fd - r.tangent[i][m]).abs() / E;
                assert!(
                    err < 1e-6,
                    "H = {h:e} {hardening:?} {rate:?}: ∂σ{i}/∂ε{m} = {} vs FD {fd} ({err:e})",
                    r.tangent[i][m]
                );
            }
        }
        // On the yield surface after the step.
        let xi: Vec<f64> = (0..3)
            .map(|i| r.stress[i] - r.state.back_stress[i])
            .collect();
        let q = (xi[0] * xi[0] + 3.0 * (xi[1] * xi[1] + xi[2] * xi[2])).sqrt();
        assert!(q >= FY * (1.0 - 1e-12));
    }
}

#[test]
fn kinematic_hardening_shows_the_bauschinger_effect_and_the_loop_area_is_the_plastic_work() {
    let h = E / 100.0;
    let amplitude = 3e-3;
    // Two full cycles 0 → +a → −a → +a → −a → +a in fine steps.
    let n = 400;
    let mut path = Vec::new();
    let mut push_leg = |from: f64, to: f64| {
        for k in 1..=n {
            path.push([from + (to - from) * k as f64 / n as f64, 0.0, 0.0]);
        }
    };
    push_leg(0.0, amplitude);
    for _ in 0..2 {
        push_leg(amplitude, -amplitude);
        push_leg(-amplitude, amplitude);
    }
    for hardening in [Hardening::Kinematic, Hardening::Isotropic] {
        let l = law(h, hardening);
        let res = follow(&l, &path, None);
        // The first reversal: where unloading from +a yields again.
        let peak = res[n - 1].stress[0];
        let reverse = res[n..2 * n]
            .iter()
            .find(|r| r.yielding)
            .map(|r| r.stress[0])
            .unwrap();
        let expected = match hardening {
            Hardening::Kinematic => peak - 2.0 * FY,
            Hardening::Isotropic => -peak,
        };
        // Yield is detected a step after it starts: one step's stress change.
        let tol = E * 2.0 * amplitude / n as f64;
        assert!(
            (reverse - expected).abs() < tol,
            "{hardening:?}: reverse yield at {reverse:e}, expected {expected:e}"
        );
        if hardening == Hardening::Kinematic {
            // The second (stabilized) cycle: ∮ σ dε against Σ σ Δεᵖ and the
            // parallelogram 2 f_y Δεᵖ, σ_a = (f_y + H ε_a) / (1 + H / E).
            let cycle = &res[3 * n - 1..5 * n];
            let (mut area, mut work) = (0.0, 0.0);
            for w in cycle.windows(2) {
                let de = path_strain(&path, w, &res);
                area += 0.5 * (w[0].stress[0] + w[1].stress[0]) * de;
                work +=
                    w[1].stress[0] * (w[1].state.plastic_strain[0] - w[0].state.plastic_strain[0]);
            }
            let sigma_a = (FY + h * amplitude) / (1.0 + h / E);
            let closed = 2.0 * FY * 2.0 * (amplitude - sigma_a / E);
            assert!(
                (area - closed).abs() < 2e-3 * closed,
                "loop {area}, closed form {closed}"
            );
            assert!(
                (work - area).abs() < 2e-3 * area,
                "plastic work {work}, loop area {area}"
            );
        }
    }
}

/// The strain step between two consecutive responses `w` of `res`.
fn path_strain(path: &[[f64; 3]], w: &[PointResponse], res: &[PointResponse]) -> f64 {
    let i = (w.as_ptr() as usize - res.as_ptr() as usize) / std::mem::size_of::<PointResponse>();
    path[i + 1][0] - path[i][0]
}

#[test]
fn a_bar_stretched_at_a_constant_rate_yields_at_the_cowper_symonds_stress() {
    let (d, q) = (40.4, 5.0);
    for rate in [1.0, 10.0, 100.0] {
        let l = BeamPlasticity {
            rate: Some(CowperSymonds { d, q }),
            ..law(0.0, Hardening::Kinematic)
        };
        let dt = 1e-5;
        let de = rate * dt;
        // Far enough that the flow is steady: all the strain rate plastic.
        let expected = FY * (1.0 + (rate / d).powf(1.0 / q));
        let steps = (10.0 * expected / E / de).ceil() as usize;
        let path: Vec<[f64; 3]> = (1..=steps).map(|k| [k as f64 * de, 0.0, 0.0]).collect();
        let last = follow(&l, &path, Some(dt)).last().unwrap().stress[0];
        assert!(
            (last - expected).abs() < 5e-3 * expected,
            "ε̇ = {rate}/s: flows at {last:e} Pa, expected {expected:e}"
        );
    }
}

/// The closed-form moment (N m) of a solid circle of radius `a` (m) of an
/// elastic–perfectly plastic material at curvature `k` (1/m).
fn solid_moment(a: f64, k: f64) -> f64 {
    let ye = FY / (E * k);
    if ye >= a {
        return E * k * std::f64::consts::PI * a.powi(4) / 4.0;
    }
    // 4 [∫₀^ye E k y² √(a² − y²) dy + ∫_ye^a f_y y √(a² − y²) dy]
    let root = (a * a - ye * ye).sqrt();
    let elastic = ye * (2.0 * ye * ye - a * a) * root / 8.0 + a.powi(4) / 8.0 * (ye / a).asin();
    4.0 * (E * k * elastic + FY * root.powi(3) / 3.0)
}

/// M(κ) of a tube: the outer circle's less the bore's.
fn ring_moment(inner: f64, outer: f64, k: f64) -> f64 {
    solid_moment(outer, k)
        - if inner > 0.0 {
            solid_moment(inner, k)
        } else {
            0.0
        }
}

/// The moment the law gives at curvature `k` (ε₁₁ = −κ y, bending about
/// z) over the points a section gives a yielding layer from `inner` to
/// `outer` (the element integrates it so).
fn section_moment(l: &BeamPlasticity, inner: f64, outer: f64, k: f64) -> f64 {
    let material = Material::elastic_plastic(7850.0, E, 0.3, FY, 0.0);
    let section = Section::circular(&[(inner, outer, material)], 3);
    section.layers[0]
        .points
        .iter()
        .map(|p| {
            let s = l
                .respond([-k * p.y, 0.0, 0.0], &PlasticState::default(), None)
                .stress[0];
            -s * p.y * p.weight
        })
        .sum()
}

#[test]
fn a_tube_and_a_solid_circle_follow_the_elastic_perfectly_plastic_moment_curvature() {
    let l = law(0.0, Hardening::Kinematic);
    for (inner, outer, w_pl) in [
        (0.046f64, 0.05f64, (0.1f64.powi(3) - 0.092f64.powi(3)) / 6.0),
        (
            0.02015,
            0.02415,
            (0.0483f64.powi(3) - 0.0403f64.powi(3)) / 6.0,
        ),
        (0.0, 0.05, 0.1f64.powi(3) / 6.0),
    ] {
        let ky = FY / (E * outer);
        // Yield at M_y = f_y I / R.
        let i = std::f64::consts::PI * (outer.powi(4) - inner.powi(4)) / 4.0;
        assert!((ring_moment(inner, outer, ky) - FY * i / outer).abs() < 1e-9 * FY * i / outer);
        // Fully plastic W_pl f_y approached as κ grows.
        let m_far = ring_moment(inner, outer, 1e3 * ky);
        assert!(m_far < w_pl * FY && m_far > 0.999 * w_pl * FY);
        for factor in [0.5, 1.0, 1.2, 1.5, 2.0, 3.0, 4.0, 10.0, 30.0] {
            let k = factor * ky;
            let (ours, exact) = (
                section_moment(&l, inner, outer, k),
                ring_moment(inner, outer, k),
            );
            assert!(
                (ours - exact).abs() < 0.01 * exact,
                "R_i = {inner}: κ = {factor} κ_y: M = {ours:.1} N m, closed form {exact:.1}"
            );
        }
    }
}

/// The incremental potential's derivative in the strain is the stress the
/// return map gives (the variational structure the static line search
/// relies on), for perfect plasticity and both hardenings.
#[test]
fn the_incremental_potential_derives_to_the_stress() {
    let old_path = [[3e-3, 1e-3, -5e-4]];
    let strain = [4e-3, 2e-3, -1e-3];
    for (h, hardening) in [
        (0.0, Hardening::Kinematic),
        (E / 50.0, Hardening::Kinematic),
        (E / 50.0, Hardening::Isotropic),
    ] {
        let l = law(h, hardening);
        let old = follow(&l, &old_path, None)[0].state;
        let psi = |e: [f64; 3]| l.incremental_energy(e, &old, &l.respond(e, &old, None).state);
        let r = l.respond(strain, &old, None);
        assert!(r.yielding);
        let step = 1e-8;
        for m in 0..3 {
            let (mut ep, mut em) = (strain, strain);
            ep[m] += step;
            em[m] -= step;
            let fd = (psi(ep) - psi(em)) / (2.0 * step);
            assert!(
                (fd - r.stress[m]).abs() < 1e-6 * FY,
                "H = {h:e} {hardening:?}: ∂ψ/∂ε{m} = {fd:e}, σ = {:e}",
                r.stress[m]
            );
        }
    }
}

/// Along a cyclic path the stresses' trapezoid work equals the change of
/// the stored energy plus the plastic work, step by step.
#[test]
fn stored_energy_and_plastic_work_balance_the_stress_work() {
    let path: Vec<[f64; 3]> = (1..=600)
        .map(|k| {
            let t = k as f64 / 600.0 * 4.0 * std::f64::consts::PI;
            [4e-3 * t.sin(), 2e-3 * (0.7 * t).sin(), -1e-3 * t.cos()]
        })
        .collect();
    for hardening in [Hardening::Kinematic, Hardening::Isotropic] {
        let l = law(E / 80.0, hardening);
        let mut state = PlasticState::default();
        let mut before = [0.0; 3];
        let (mut work, mut dissipated) = (0.0, 0.0);
        for &e in &path {
            let next = l.respond(e, &state, None).state;
            work += (0..3)
                .map(|i| 0.5 * (state.stress[i] + next.stress[i]) * (e[i] - before[i]))
                .sum::<f64>();
            dissipated += l.plastic_work(&state, &next);
            (state, before) = (next, e);
        }
        let stored = l.incremental_energy(before, &state, &state);
        assert!(dissipated > 0.0);
        assert!(
            (work - stored - dissipated).abs() < 1e-9 * work.abs(),
            "{hardening:?}: work {work:e}, stored {stored:e} + plastic {dissipated:e}"
        );
    }
}
