//! Kelvin–Voigt damping of an element: the pre-integrated path against the
//! law stated point by point, and its Jacobians against differences.

mod common;

use ancf_core::element::ElementIntegration;
use ancf_core::forces::damping::{kelvin_voigt_element, kelvin_voigt_points};
use common::*;

const L: f64 = 0.25;

type Evaluation = ([f64; 24], [f64; 576], [f64; 576], f64);

/// An element's damping force: `kelvin_voigt_element` or `kelvin_voigt_points`.
type Path = fn(
    &ElementIntegration,
    f64,
    &[f64; 24],
    &[f64; 24],
    &mut [f64; 24],
    Option<&mut [f64; 576]>,
    Option<&mut [f64; 576]>,
) -> f64;

fn evaluate(
    path: Path,
    el: &ElementIntegration,
    c: f64,
    e: &[f64; 24],
    v: &[f64; 24],
) -> Evaluation {
    let (mut q, mut kq, mut kv) = ([0.0; 24], [0.0; 576], [0.0; 576]);
    let p = path(el, c, e, v, &mut q, Some(&mut kq), Some(&mut kv));
    (q, kq, kv, p)
}

/// Sections whose linear laws the plan pre-integrates, in every way it
/// does: one layer, two proportional layers merged into one ring rule, a
/// weakened bending (ω < 1: a centerline law), ν ≠ 0, and a linear layer
/// beside a Mooney–Rivlin one (that one point by point).
fn sections() -> Vec<(&'static str, ElementIntegration)> {
    let one = ancf_core::section::Section::circular(&[(0.0, 0.02, svk(2e11, 0.3, 1.0))], 3);
    vec![
        ("one layer, ν = 0.3", element(one, L, 3)),
        (
            "two layers, ω = 0.1, ν = 0",
            element(
                two_layer(svk(1.5e11, 0.0, 0.1), svk(5e10, 0.0, 0.1), 3),
                L,
                3,
            ),
        ),
        (
            "two layers, ω = 0.5, ν = 0.3, order 5",
            element(
                two_layer(svk(2e11, 0.3, 0.5), svk(7e10, 0.33, 0.5), 5),
                L,
                4,
            ),
        ),
        (
            "linear core, Mooney–Rivlin jacket",
            element(two_layer(svk(2e9, 0.3, 0.5), mooney_rivlin(1e3), 3), L, 3),
        ),
    ]
}

/// The pre-integrated force, power and both Jacobians equal the
/// point-by-point law's over each layer's own rule (exact: the section
/// integrand is a polynomial the rules integrate exactly).
#[test]
fn preintegrated_damping_equals_the_law_point_by_point() {
    let mut rng = Rng::new(11);
    for (name, el) in sections() {
        assert!(el.plan.is_preintegrated(), "{name}: not pre-integrated");
        for _ in 0..3 {
            let e = deformed(&mut rng, L, 0.1);
            let v: [f64; 24] = std::array::from_fn(|_| rng.uniform());
            let c = 1e-3;
            let (q, kq, kv, p) = evaluate(kelvin_voigt_element, &el, c, &e, &v);
            let (q0, kq0, kv0, p0) = evaluate(kelvin_voigt_points, &el, c, &e, &v);
            assert!(
                p0 > 0.0 && (p - p0).abs() <= 1e-12 * p0,
                "{name}: power {p} vs {p0}"
            );
            assert!(rel(&q, &q0) < 1e-12, "{name}: force {:e}", rel(&q, &q0));
            assert!(rel(&kq, &kq0) < 1e-12, "{name}: ∂Q/∂q {:e}", rel(&kq, &kq0));
            assert!(rel(&kv, &kv0) < 1e-12, "{name}: ∂Q/∂v {:e}", rel(&kv, &kv0));
        }
    }
}

/// The Kelvin–Voigt force's Jacobians against central differences, and its
/// power is Q · v > 0.
#[test]
fn kelvin_voigt_jacobians_match_finite_differences() {
    let mut rng = Rng::new(4);
    for (name, el) in sections() {
        let e = deformed(&mut rng, L, 0.1);
        let v: [f64; 24] = std::array::from_fn(|_| rng.uniform());
        let eval = |e: &[f64; 24], v: &[f64; 24]| evaluate(kelvin_voigt_element, &el, 1e-3, e, v);
        let (q, kq, kv, power) = eval(&e, &v);
        let qv: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
        assert!(
            (power - qv).abs() < 1e-10 * power.abs() && power > 0.0,
            "{name}: power {power} vs Q·v {qv}"
        );
        let h = 1e-6;
        let (fq, fv) = central_differences(|e, v| eval(e, v).0, &e, &v, h);
        assert!(rel(&fq, &kq) < 1e-6, "{name}: ∂Q/∂q {:e}", rel(&fq, &kq));
        assert!(rel(&fv, &kv) < 1e-6, "{name}: ∂Q/∂v {:e}", rel(&fv, &kv));
    }
}

/// A rigid motion of a deformed element (a translation and a rotation
/// rate that keeps its shape) dissipates nothing and is damped by no force.
#[test]
fn a_rigid_velocity_is_not_damped() {
    let mut rng = Rng::new(5);
    for (name, el) in sections() {
        let e = deformed(&mut rng, L, 0.1);
        // v = ω × (coordinate) for the vectors and ω × r + t for positions.
        let (w, t) = ([0.3, -1.2, 0.7], [0.5, 0.1, -0.4]);
        let v: [f64; 24] = std::array::from_fn(|i| {
            let (blk, k) = (i / 3, i % 3);
            let x = &e[3 * blk..3 * blk + 3];
            let cross = [
                w[1] * x[2] - w[2] * x[1],
                w[2] * x[0] - w[0] * x[2],
                w[0] * x[1] - w[1] * x[0],
            ];
            cross[k] + if blk % 4 == 0 { t[k] } else { 0.0 }
        });
        let (q, _, _, p) = evaluate(kelvin_voigt_element, &el, 1e-3, &e, &v);
        // The scale: the same element at a deforming velocity.
        let v1: [f64; 24] = std::array::from_fn(|_| rng.uniform());
        let (q1, _, _, p1) = evaluate(kelvin_voigt_element, &el, 1e-3, &e, &v1);
        let norm = |a: &[f64]| a.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(norm(&q) < 1e-10 * norm(&q1), "{name}: force {:e}", norm(&q));
        assert!(p.abs() < 1e-10 * p1, "{name}: power {p:e} against {p1:e}");
    }
}

/// The wire's damping force alone (eight elements at a time where the
/// laws are pre-integrated, a long wire in two halves on two threads)
/// equals the one its Jacobians come with (one element at a time), with a
/// Mooney–Rivlin jacket integrated by points and counts of elements no
/// multiple of eight; and it has the same bits on one thread and on two.
#[test]
fn the_batched_wire_force_equals_the_element_by_element_one() {
    use ancf_core::forces::assembly::{pattern, runs_in_parallel};
    use ancf_core::forces::damping::kelvin_voigt_force;
    use ancf_core::model::WireBuilder;
    use ancf_core::model::damping::Damping;
    let cases = [
        (21, svk(5e10, 0.3, 0.1)),
        (21, mooney_rivlin(1e3)),
        (1003, svk(5e10, 0.3, 0.1)),
    ];
    for (elements, jacket) in cases {
        let model = WireBuilder::new(1.0, elements)
            .layer(svk(1.5e11, 0.0, 0.1), 0.005)
            .layer(jacket, 0.014)
            .damping(Damping::KelvinVoigt { coefficient: 1e-4 })
            .build()
            .unwrap();
        let pattern = pattern(&model);
        let c = vec![Some(1e-4); model.groups.len()];
        // The long wire is split as the elastic force alone would be.
        assert_eq!(
            elements > 100,
            runs_in_parallel(&model, false),
            "{elements} elements"
        );
        let mut rng = Rng::new(9);
        let q: Vec<f64> = (model.reference.iter())
            .map(|x| x + 1e-4 * rng.uniform())
            .collect();
        let v: Vec<f64> = q.iter().map(|_| rng.uniform()).collect();
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| kelvin_voigt_force(&model, &pattern, &c, &q, &v, None, None))
        };
        let ((f, p), (f2, p2)) = (on(1), on(2));
        assert!(
            p == p2 && f.iter().zip(&f2).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{elements} elements: 1 and 2 threads differ"
        );
        let mut kv = vec![0.0; pattern.nnz()];
        let (f1, p1) = kelvin_voigt_force(&model, &pattern, &c, &q, &v, None, Some(&mut kv));
        assert!(
            p1 > 0.0 && (p - p1).abs() <= 1e-12 * p1,
            "power {p} against {p1}"
        );
        assert!(rel(&f, &f1) < 1e-12, "force {:e}", rel(&f, &f1));
    }
}
