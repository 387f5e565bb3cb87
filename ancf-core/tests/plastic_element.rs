//! Elastic–plastic layers in the element and the static solver: the
//! consistent tangent against central differences, a cantilever's
//! elastic–plastic tip deflection against the beam solution, plastic
//! hinges at collapse, and the residual deflection after unloading.

mod common;

use ancf_core::element::{ElementIntegration, PlasticInput};
use ancf_core::material::Material;
use ancf_core::material::beam_plasticity::PlasticState;
use ancf_core::model::spring::Spring;
use ancf_core::model::{SupportKind, WireBuilder};
use ancf_core::section::Section;
use ancf_core::solve::statics::{
    StaticResult, StaticSettings, solve_static, solve_static_continuing,
};
use std::f64::consts::PI;

/// Ø 100 × 4 mm tube, S235: E, f_y (Pa), outer and inner radius (m).
const E: f64 = 210e9;
const FY: f64 = 235e6;
const R: f64 = 0.05;
const RI: f64 = 0.046;

fn steel(hardening: f64) -> Material {
    Material::elastic_plastic(7850.0, E, 0.3, FY, hardening)
}

/// W_pl f_y of the tube (N m).
fn plastic_moment() -> f64 {
    ((2.0 * R).powi(3) - (2.0 * RI).powi(3)) / 6.0 * FY
}

fn second_moment() -> f64 {
    PI * (R.powi(4) - RI.powi(4)) / 4.0
}

/// The moment of a solid circle of radius `a` at curvature `k` with the
/// elastic–perfectly-plastic stress σ = clip(E k y, ±f_y) (closed form).
fn solid_moment(a: f64, k: f64) -> f64 {
    let c = FY / (E * k);
    if c >= a {
        return E * k * PI * a.powi(4) / 4.0;
    }
    let s = (a * a - c * c).sqrt();
    4.0 * E * k * (c * (2.0 * c * c - a * a) * s / 8.0 + a.powi(4) / 8.0 * (c / a).asin())
        + 4.0 * FY * s.powi(3) / 3.0
}

/// The tube's moment: σ depends on y alone, so the ring is the outer
/// circle less the inner.
fn tube_moment(k: f64) -> f64 {
    solid_moment(R, k) - solid_moment(RI, k)
}

/// The curvature at which the tube carries `m` (< M_p), by bisection.
fn tube_curvature(m: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    while tube_moment(hi) < m {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tube_moment(mid) < m {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

/// The tip deflection of a cantilever of length `l` under a tip load `p`:
/// ∫ κ(P (l − x)) (l − x) dx (Simpson, fine enough for the kink at the
/// elastic–plastic boundary).
fn cantilever_tip(l: f64, p: f64) -> f64 {
    let n = 20_000;
    let h = l / n as f64;
    (0..=n)
        .map(|i| {
            let x = i as f64 * h;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * tube_curvature(p * (l - x)) * (l - x)
        })
        .sum::<f64>()
        * h
        / 3.0
}

fn settings(load_steps: usize) -> StaticSettings {
    StaticSettings {
        load_steps,
        max_iterations: 40,
        ..Default::default()
    }
}

/// A clamped tube cantilever along x with a tip force `p` downwards.
fn cantilever(l: f64, elements: usize, p: f64) -> ancf_core::Model {
    WireBuilder::new(l, elements)
        .layer(steel(0.0), R)
        .bore(RI)
        .quadrature(5, 3)
        .support(0, SupportKind::Clamp)
        .load(elements, [0.0, 0.0, -p])
        .build()
        .unwrap()
}

fn tip_z(model: &ancf_core::Model, r: &StaticResult) -> f64 {
    let n = model.beams[0].nodes.end - 1;
    model.node_position(&r.q, n)[2]
}

/// An element of length `l` along x bent about y and sheared a little
/// along y, both growing with θ: r_x at B turned by θ (curvature θ / l),
/// r_y, r_z turned with it.
fn bent(l: f64, theta: f64) -> ancf_core::element::ElementVector {
    let (c, s) = (theta.cos(), theta.sin());
    let mut e = common::reference(l);
    e[15..18].copy_from_slice(&[c, 0.0, s]);
    e[21..24].copy_from_slice(&[-s, 0.0, c]);
    e[12..15].copy_from_slice(&[
        l * (1.0 - theta * theta / 6.0),
        0.02 * theta * l,
        l * theta / 2.0,
    ]);
    e
}

/// The force's Jacobian of a yielding element equals its central
/// differences: the return map's tangent is consistent.
#[test]
fn the_tangent_of_a_yielding_element_is_consistent() {
    let l = 0.25;
    for hardening in [0.0, 2e9] {
        let section = Section::circular(&[(RI, R, steel(hardening))], 3);
        let el = ElementIntegration::new(l, 4, section);
        assert!(el.plan.is_plastic());
        // Bent past yield (shear and bend both grow from the first
        // configuration to the next, so that no point sits on its yield
        // surface at the kink).
        let bend = |theta: f64| bent(l, theta);
        let ky = FY / (E * R);
        let first = bend(8.0 * ky * l);
        // The history of a first, accepted step there.
        let mut states = vec![PlasticState::default(); el.plastic_points()];
        let step = el.plastic_step(&first, PlasticInput::default(), &mut states);
        assert!(step.max_equivalent > 0.0, "the first step yields");
        assert!(step.work > 0.0);
        // The next iterate: bent further, yielding again.
        let e = bend(11.0 * ky * l);
        let input = PlasticInput {
            states: &states,
            dt: None,
        };
        let mut q = [0.0; 24];
        let mut k = [0.0; 576];
        el.evaluate_with(&e, input, &mut q, Some(&mut k));
        let scale = k.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let mut worst = 0.0f64;
        for j in 0..24 {
            let h = 1e-7 * if (j / 3) % 4 == 0 { l } else { 1.0 };
            let (mut ep, mut em) = (e, e);
            ep[j] += h;
            em[j] -= h;
            let (mut qp, mut qm) = ([0.0; 24], [0.0; 24]);
            el.evaluate_with(&ep, input, &mut qp, None);
            el.evaluate_with(&em, input, &mut qm, None);
            for i in 0..24 {
                let fd = (qp[i] - qm[i]) / (2.0 * h);
                worst = worst.max((fd - k[i * 24 + j]).abs() / scale);
            }
        }
        assert!(
            worst < 1e-6,
            "H = {hardening:e}: tangent off its differences by {worst:e} of its largest entry"
        );
    }
}

/// A clamped elastic–perfectly-plastic tube cantilever loaded to 0.95 M_p
/// at the root: its tip deflection is the beam solution's (curvature from
/// the section's moment–curvature relation, integrated along the beam)
/// within 2 %, and Newton converges quadratically (few iterations a step).
#[test]
fn a_yielding_cantilever_deflects_as_the_beam_solution() {
    let l = 3.0;
    let mp = plastic_moment();
    let p = 0.95 * mp / l;
    let elastic = p * l.powi(3) / (3.0 * E * second_moment());
    let exact = cantilever_tip(l, p);
    assert!(
        exact > 1.05 * elastic,
        "the root yields: {exact} vs elastic {elastic}"
    );
    let model = cantilever(l, 24, p);
    let r = solve_static(&model, &settings(10)).unwrap();
    let tip = -tip_z(&model, &r);
    let error = tip / exact - 1.0;
    assert!(
        error.abs() < 0.02,
        "tip {tip} m vs beam solution {exact} m ({:+.2} %)",
        100.0 * error
    );
    assert!(r.plastic.iter().any(|s| s.equivalent > 0.0));
    assert!(r.plastic_work[0] > 0.0);
    // Quadratic convergence, the consistent tangent's: few iterations a
    // step, and once the relative residual is below 1e-2 each iteration
    // squares it (r_{k+1} ≤ 100 r_k², which a linear rate such as
    // r_{k+1} = 0.1 r_k fails from r_k < 1e-3 on) until it reaches the
    // tolerance's round-off floor.
    assert_eq!(r.iterations.len(), 10, "one increment per load step");
    let most = r.iterations.iter().max().unwrap();
    assert!(*most <= 6, "iterations per load step {:?}", r.iterations);
    let mut squared = 0;
    for (step, history) in r.residuals.iter().enumerate() {
        let shown: Vec<String> = history.iter().map(|r| format!("{r:.1e}")).collect();
        eprintln!("load step {step}: relative residuals {shown:?}");
        for pair in history.windows(2) {
            if pair[0] < 1e-2 && pair[1] > 1e-10 {
                assert!(
                    pair[1] <= 100.0 * pair[0] * pair[0],
                    "step {step}: {shown:?}"
                );
                squared += 1;
            }
        }
    }
    assert!(squared >= 10, "the rate was seen {squared} times");
}

/// Unloaded elastically, the cantilever keeps the residual deflection
/// δ(P) − P l³ / 3EI (the unloading stays below the reversed yield).
#[test]
fn an_unloaded_cantilever_keeps_its_permanent_set() {
    let l = 3.0;
    let p = 0.95 * plastic_moment() / l;
    let loaded_model = cantilever(l, 24, p);
    let loaded = solve_static(&loaded_model, &settings(10)).unwrap();
    let unloaded_model = cantilever(l, 24, 0.0);
    let start = (loaded.q.clone(), loaded.plastic.clone());
    let unloaded = solve_static_continuing(&unloaded_model, &settings(4), start, None).unwrap();
    let set = -tip_z(&unloaded_model, &unloaded);
    let exact = cantilever_tip(l, p) - p * l.powi(3) / (3.0 * E * second_moment());
    let error = set / exact - 1.0;
    assert!(
        error.abs() < 0.05,
        "permanent set {set} m vs {exact} m ({:+.2} %)",
        100.0 * error
    );
    // Elastic unloading: no further plastic work.
    assert!(loaded.plastic_work[0] > 0.0);
    assert!(unloaded.plastic_work[0].abs() < 1e-9 * loaded.plastic_work[0]);
}

/// Past M_p / l a perfectly plastic cantilever has no equilibrium near
/// its straight shape: a hinge forms at the root and the beam swings down
/// until the load's lever arm has shortened to about M_p / P. A
/// displacement-based element carries a hinge's moment as an average over
/// its element, so the root moment overshoots M_p on a coarse mesh and
/// approaches it as the mesh is refined (measured: 1.047, 1.041, 1.025 M_p
/// at 12, 24, 48 elements).
#[test]
fn a_cantilever_past_its_plastic_moment_hinges_at_the_root() {
    let l = 3.0;
    let mp = plastic_moment();
    let p = 1.05 * mp / l;
    let root_moment = |n: usize| {
        let model = cantilever(l, n, p);
        let r = solve_static(&model, &settings(20)).unwrap();
        let arm = model.node_position(&r.q, n)[0];
        // The hinge: the largest plastic strain sits in the root element.
        let layout = ancf_core::forces::plastic::PlasticLayout::of(&model);
        let peak = |el: usize| {
            (layout.element(&r.plastic, el).iter()).fold(0.0f64, |m, s| m.max(s.equivalent))
        };
        assert!(
            peak(0) > 10.0 * peak(n / 4),
            "n = {n}: root {} vs a quarter along {}",
            peak(0),
            peak(n / 4)
        );
        p * arm / mp
    };
    let (coarse, fine) = (root_moment(12), root_moment(48));
    assert!(
        fine < coarse,
        "the overshoot shrinks: {coarse} → {fine} M_p"
    );
    assert!(
        (0.97..=1.03).contains(&fine),
        "root moment {fine} M_p at 48 elements"
    );
}

/// A stocky tube column pushed along its axis past its squash load A f_y
/// (perfectly plastic, far below its buckling load) has no equilibrium:
/// the axial stress cannot pass f_y and shortening only lowers the force
/// it carries. The static solve ends with an error that names the plastic
/// mechanism and the load factor it reached, about A f_y / P; with the
/// tube elastic the same load is carried.
#[test]
fn a_column_past_its_squash_load_is_a_named_mechanism() {
    let l = 0.5;
    let area = PI * (R * R - RI * RI);
    let squash = area * FY;
    let column = |material: Material| {
        WireBuilder::new(l, 4)
            .layer(material, R)
            .bore(RI)
            .quadrature(5, 3)
            .support(0, SupportKind::Clamp)
            .load(4, [-1.25 * squash, 0.0, 0.0])
            .build()
            .unwrap()
    };
    let buckling = PI * PI * E * second_moment() / (4.0 * l * l);
    assert!(buckling > 5.0 * squash, "{buckling} vs {squash}");
    let elastic = Material::st_venant_kirchhoff(7850.0, E, 0.3, 1.0);
    assert!(solve_static(&column(elastic), &settings(8)).is_ok());
    let err = solve_static(&column(steel(0.0)), &settings(8)).unwrap_err();
    eprintln!("{} (load factor {})", err.message, err.load_factor);
    assert!(!err.interrupted);
    assert!(err.message.contains("plastic mechanism"), "{}", err.message);
    let carried = 1.0 / 1.25;
    assert!(
        (carried - 0.01..=carried).contains(&err.load_factor),
        "carried {} of the load, A f_y / P = {carried}: {}",
        err.load_factor,
        err.message
    );
}

/// The same column with the load applied suddenly, in a dynamic run: it
/// crushes at the loaded end (measured: the tip node's r_x falls from 1
/// to 0.004 within 0.5 ms) and, once the element there would be crushed
/// through itself, the step is refused and the run ends naming the node,
/// not with a state no solid reaches.
#[test]
fn a_column_crushed_through_itself_ends_the_run() {
    use ancf_core::solve::dynamics::{DynamicSettings, Integrator, StepError};
    let (l, n) = (0.5, 4);
    let squash = PI * (R * R - RI * RI) * FY;
    let model = WireBuilder::new(l, n)
        .layer(steel(0.0), R)
        .bore(RI)
        .quadrature(5, 3)
        .support(0, SupportKind::Clamp)
        .load(n, [-1.25 * squash, 0.0, 0.0])
        .build()
        .unwrap();
    let model = std::sync::Arc::new(model);
    let h = 2e-5;
    let settings = DynamicSettings {
        time_step: h,
        end_time: 0.05,
        ..Default::default()
    };
    let mut integ = Integrator::new(model.clone(), settings).unwrap();
    let len = model.reference.len();
    let mut s = integ
        .initial_state(model.reference.clone(), vec![0.0; len])
        .unwrap();
    let mut failure = None;
    for _ in 0..(0.05 / h) as usize {
        match integ.step(&s, h) {
            Ok((next, _)) => s = next,
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }
    let failure = failure.expect("a column past its squash load cannot stand");
    assert!(
        matches!(failure.cause(), StepError::Inverted { .. }),
        "{failure}: {}",
        failure.likely_cause()
    );
    assert!(
        model.inverted_node(&s.q).is_none(),
        "the last state kept is a solid's"
    );
    eprintln!("{failure} at t = {:.4} s", s.time);
}

/// A simply supported tube under a midspan load carries 4 M_p / l at small
/// deflection (no axial restraint: one end slides): below it the sag stays
/// small; past it the midspan hinge folds the beam until the supports'
/// lever arms carry about M_p, the mesh's overshoot shrinking as for the
/// cantilever (measured: 1.045 and 1.035 M_p at 24 and 48 elements; the
/// hinge sits at the loaded node, between two elements).
#[test]
fn a_simply_supported_tube_collapses_at_four_plastic_moments_over_its_span() {
    let l = 4.0;
    let beam = |n: usize, p: f64| {
        WireBuilder::new(l, n)
            .layer(steel(0.0), R)
            .bore(RI)
            .quadrature(5, 3)
            .support(0, SupportKind::Hinge)
            // The far end rests on stiff springs across the span and slides
            // along it.
            .spring(
                n,
                Spring {
                    stiffness: [0.0, 1e11, 1e11],
                    rotational_stiffness: 0.0,
                    torsional_stiffness: 0.0,
                    damping: 0.0,
                },
            )
            .load(n / 2, [0.0, 0.0, -p])
            .build()
            .unwrap()
    };
    let mp = plastic_moment();
    let pc = 4.0 * mp / l;
    let below = beam(48, 0.95 * pc);
    let rb = solve_static(&below, &settings(10)).unwrap();
    let sag_below = -below.node_position(&rb.q, 24)[2];
    let folded = |n: usize| {
        let above = beam(n, 1.05 * pc);
        let ra = solve_static(&above, &settings(20)).unwrap();
        let [x, _, z] = above.node_position(&ra.q, n / 2);
        assert!(
            -z > 3.0 * sag_below,
            "n = {n}: sag {} m vs {sag_below} m below collapse",
            -z
        );
        0.5 * 1.05 * pc * x / mp
    };
    let (coarse, fine) = (folded(24), folded(48));
    assert!(
        fine < coarse,
        "the overshoot shrinks: {coarse} → {fine} M_p"
    );
    assert!(
        (0.97..=1.04).contains(&fine),
        "midspan moment {fine} M_p at 48 elements"
    );
}

/// A tube cantilever under a tip load applied suddenly (twice the static
/// moment at the first swing: it yields) with ρ∞ = 1 and no damping:
/// kinetic + stored + load potential + plastic work stays constant to the
/// integrator's accuracy, the drift falling with the step (trapezoid
/// plastic work, second order).
#[test]
fn a_yielding_swing_conserves_energy_with_its_plastic_work() {
    use ancf_core::solve::dynamics::{DynamicSettings, Integrator};
    let l = 3.0;
    let p = 0.6 * plastic_moment() / l;
    let model = std::sync::Arc::new(cantilever(l, 8, p));
    let run = |h: f64| {
        let settings = DynamicSettings {
            time_step: h,
            end_time: 0.06,
            spectral_radius: 1.0,
            ..Default::default()
        };
        let mut integ = Integrator::new(model.clone(), settings).unwrap();
        let n = model.reference.len();
        let mut s = integ
            .initial_state(model.reference.clone(), vec![0.0; n])
            .unwrap();
        let e0 = integ.energies(&s).balance();
        let mut drift = 0.0f64;
        let steps = (0.06 / h).round() as usize;
        for _ in 0..steps {
            s = integ.step(&s, h).unwrap().0;
            drift = drift.max((integ.energies(&s).balance() - e0).abs());
        }
        let e = integ.energies(&s);
        (drift, e.plastic)
    };
    let (coarse, work) = run(4e-4);
    let (fine, _) = run(2e-4);
    eprintln!("drift {coarse:e} -> {fine:e} J, plastic work {work:e} J");
    assert!(work > 0.0, "the swing yields");
    assert!(
        fine < 0.01 * work,
        "drift {fine:e} J against {work:e} J of plastic work"
    );
    assert!(
        fine < 0.5 * coarse,
        "the drift falls with the step: {coarse:e} → {fine:e} J"
    );
}

/// A yielding member's internal loads come from its history: the root of
/// the cantilever at 0.95 M_p carries P times the tip's lever arm, and once
/// unloaded it carries nothing, while its bent shape read from the virgin
/// state (the plastic strain taken for elastic) would claim a moment.
#[test]
fn a_yielding_beam_reports_the_moment_it_carries() {
    use ancf_core::forces::plastic::{History, PlasticLayout};
    use ancf_core::loads::member_load::end_resultants;
    let l = 3.0;
    let mp = plastic_moment();
    let p = 0.95 * mp / l;
    let model = cantilever(l, 24, p);
    let r = solve_static(&model, &settings(10)).unwrap();
    let layout = PlasticLayout::of(&model);
    let history = History::of(&layout, &r.plastic, None);
    let arm = model.node_position(&r.q, 24)[0];
    let (_, m, _) = end_resultants(&model, 0, 0, &r.q, history);
    let carried = p * arm;
    assert!(
        (m / carried - 1.0).abs() < 0.01,
        "root moment {m} N m, P × arm = {carried} N m"
    );
    let free = cantilever(l, 24, 0.0);
    let u = solve_static_continuing(&free, &settings(4), (r.q.clone(), r.plastic.clone()), None)
        .unwrap();
    let history = History::of(&layout, &u.plastic, None);
    let (_, residual, _) = end_resultants(&free, 0, 0, &u.q, history);
    assert!(residual < 1e-3 * mp, "unloaded root moment {residual} N m");
    let (_, virgin, _) = end_resultants(&free, 0, 0, &u.q, History::default());
    assert!(
        virgin > 0.1 * mp,
        "read from the virgin state: {virgin} N m"
    );
}

/// The yielding layer's elastic law pre-integrated with corrections at the
/// points that yield gives the point-by-point evaluation's force, Jacobian
/// and potential, elastic, yielding and unloading, with a second layer.
#[test]
fn corrections_on_the_pre_integrated_law_equal_the_point_by_point_evaluation() {
    let l = 0.25;
    let section = Section::circular(
        &[
            (0.02, RI, Material::st_venant_kirchhoff(7850.0, E, 0.3, 1.0)),
            (RI, R, steel(2e9)),
        ],
        3,
    );
    let el = ElementIntegration::new(l, 4, section);
    let bend = |theta: f64| bent(l, theta);
    let ky = FY / (E * R);
    let mut states = vec![PlasticState::default(); el.plastic_points()];
    el.plastic_step(&bend(6.0 * ky * l), PlasticInput::default(), &mut states);
    // Elastic (small bend, virgin), yielding (virgin, past yield), and
    // unloading from the yielded history.
    for (theta, history) in [
        (0.3 * ky * l, false),
        (8.0 * ky * l, false),
        (2.0 * ky * l, true),
    ] {
        let input = PlasticInput {
            states: if history { &states } else { &[] },
            dt: None,
        };
        let e = bend(theta);
        let (mut qa, mut qb) = ([0.0; 24], [0.0; 24]);
        let (mut ka, mut kb) = ([0.0; 576], [0.0; 576]);
        let ua = el.evaluate_with(&e, input, &mut qa, Some(&mut ka));
        let ub = el.evaluate_plastic_reference(&e, input, &mut qb, Some(&mut kb));
        let scale = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        };
        assert!(
            diff(&qa, &qb) < 1e-10 * scale(&qb),
            "θ = {theta}: force off by {:e}",
            diff(&qa, &qb)
        );
        assert!(
            diff(&ka, &kb) < 1e-10 * scale(&kb),
            "θ = {theta}: Jacobian off by {:e}",
            diff(&ka, &kb)
        );
        assert!(
            (ua - ub).abs() < 1e-10 * ub.abs(),
            "θ = {theta}: energy {ua} vs {ub}"
        );
        // The force alone (its own, lighter form) is the same force.
        let mut qc = [0.0; 24];
        el.evaluate_with(&e, input, &mut qc, None);
        assert!(
            diff(&qc, &qb) < 1e-10 * scale(&qb),
            "θ = {theta}: force alone off by {:e}",
            diff(&qc, &qb)
        );
    }
}

/// The assembly takes a yielding member's pre-integrated laws eight and
/// four elements at a time and adds each element's corrections: the force
/// and energies have the bits of the elements evaluated one by one.
#[test]
fn batched_yielding_elements_have_the_bits_of_one_by_one() {
    use ancf_core::forces::assembly::{assemble_into_with, pattern};
    use ancf_core::forces::plastic::{History, PlasticLayout};
    let l = 3.0;
    let n = 23; // batches of 8 and 4 and a rest
    let model = cantilever(l, n, 0.95 * plastic_moment() / l);
    let r = solve_static(&model, &settings(10)).unwrap();
    let layout = PlasticLayout::of(&model);
    let history = History::of(&layout, &r.plastic, None);
    let pattern = pattern(&model);
    let mut force = vec![0.0; r.q.len()];
    let mut energy = vec![0.0; model.n_elements];
    assemble_into_with(
        &model,
        &pattern,
        &r.q,
        history,
        None,
        &mut force,
        &mut energy,
    );
    let mut expected = vec![0.0; r.q.len()];
    for el in 0..model.n_elements {
        let e = model.element_coordinates(&r.q, el);
        let mut qe = [0.0; 24];
        let u = model
            .element(el)
            .evaluate_with(&e, history.element(el), &mut qe, None);
        assert_eq!(u.to_bits(), energy[el].to_bits(), "element {el}'s energy");
        for i in 0..24 {
            expected[12 * el + i] += qe[i];
        }
    }
    for (i, (a, b)) in force.iter().zip(&expected).enumerate() {
        assert_eq!(a.to_bits(), b.to_bits(), "force {i}: {a} vs {b}");
    }
}

/// A yielding run resumed from a snapshot taken after it yielded, sent
/// through JSON as a checkpoint file is, ends bit for bit like the
/// uninterrupted one, its plastic states and work included; a snapshot
/// whose plastic states do not fit the model is refused naming the field.
#[test]
fn a_yielding_run_resumes_bit_for_bit() {
    use ancf_core::solve::dynamics::DynamicSettings;
    use ancf_core::solve::simulation::{Initial, Simulation, Snapshot};
    let l = 3.0;
    let model = cantilever(l, 8, 0.6 * plastic_moment() / l);
    let settings = DynamicSettings {
        time_step: 4e-4,
        end_time: 0.08,
        ..Default::default()
    };
    let mut sim = Simulation::new(&model, settings.clone(), Initial::Reference).unwrap();
    let mut snapshot = None;
    while !sim.is_finished() {
        sim.step().unwrap();
        if sim.steps().0 == 130 {
            assert!(
                sim.state().plastic.iter().any(|p| p.equivalent > 0.0),
                "yielded by then"
            );
            let json = serde_json::to_string(&sim.snapshot()).unwrap();
            snapshot = Some(serde_json::from_str::<Snapshot>(&json).unwrap());
        }
    }
    let snapshot = snapshot.unwrap();
    let mut resumed = Simulation::resume(&model, settings.clone(), snapshot.clone()).unwrap();
    while !resumed.is_finished() {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.state().q, sim.state().q);
    assert_eq!(resumed.state().plastic, sim.state().plastic);
    assert_eq!(resumed.state().plastic_work, sim.state().plastic_work);
    let mut damaged = snapshot;
    damaged.state.plastic.pop();
    let error = Simulation::resume(&model, settings, damaged).err().unwrap();
    assert!(error.to_string().contains("state.plastic"), "{error}");
}

/// A member's permanent set is its rest shape with everything but its own
/// supports and weight taken away: a tube cantilever beside a wire, loaded
/// past yield at its tip, springs back to the closed-form residual
/// deflection δ(P) − P l³ / 3EI (as the unloaded wire cantilever above
/// does). Without its
/// plastic history the same member springs back to its rest shape: no set.
#[test]
fn a_members_permanent_set_is_its_spring_back_with_the_wire_lifted_off() {
    use ancf_core::model::{BeamBuilder, PointLoad, Support};
    use ancf_core::solve::permanent_set::permanent_set;
    let (l, n) = (3.0, 24);
    let p = 0.95 * plastic_moment() / l;
    let model = WireBuilder::new(1.0, 4)
        .layer(Material::st_venant_kirchhoff(7850.0, E, 0.3, 1.0), 0.01)
        .support(0, SupportKind::Fixed)
        .member(
            BeamBuilder::new("tube", l, n)
                .placed([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
                .layer(steel(0.0), R)
                .bore(RI)
                .quadrature(5, 3),
        )
        .support_on("tube", Support::new(0, SupportKind::Clamp))
        .load_on(
            "tube",
            PointLoad {
                node: n,
                force: [0.0, 0.0, -p],
                ..Default::default()
            },
        )
        .build()
        .unwrap();
    let loaded = solve_static(&model, &settings(10)).unwrap();
    assert!(loaded.plastic.iter().any(|s| s.equivalent > 0.0));
    let set = permanent_set(&model, 1, (&loaded.q, &loaded.plastic), &settings(1)).unwrap();
    let exact = cantilever_tip(l, p) - p * l.powi(3) / (3.0 * E * second_moment());
    let error = set.set / exact - 1.0;
    eprintln!(
        "permanent set {} m vs {exact} m ({:+.2} %)",
        set.set,
        100.0 * error
    );
    assert!(
        error.abs() < 0.05,
        "permanent set {} m vs {exact} m ({:+.2} %)",
        set.set,
        100.0 * error
    );
    assert!((set.at - l).abs() < 1e-12, "largest at {} m", set.at);
    let tip_down = set.displacement[n][2];
    assert!(tip_down < 0.0 && (tip_down.abs() - set.set).abs() < 1e-3 * set.set);
    // The loaded shape without its history springs back all the way.
    let virgin = permanent_set(&model, 1, (&loaded.q, &[]), &settings(1)).unwrap();
    assert!(virgin.set < 1e-9 * l, "elastic set {} m", virgin.set);
}
