//! Shared helpers for the integration tests.
#![allow(dead_code)]

use ancf_core::element::{ElementIntegration, ElementVector, reference_coordinates};
use ancf_core::material::{Material, MaterialModel};
use ancf_core::section::Section;

/// A small deterministic generator (xorshift64*), so tests need no extra crate.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1)
    }
    /// Uniform in [-1, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11;
        2.0 * (v as f64 / (1u64 << 53) as f64) - 1.0
    }
}

pub fn svk(e: f64, nu: f64, omega: f64) -> Material {
    Material {
        locking: Default::default(),
        yield_stress: None,
        density: 7200.0,
        model: MaterialModel::StVenantKirchhoff {
            youngs_modulus: e,
            poisson_ratio: nu,
            bending_factor: omega,
        },
    }
}

pub fn mooney_rivlin(penalty: f64) -> Material {
    Material {
        locking: Default::default(),
        yield_stress: None,
        density: 1100.0,
        model: MaterialModel::MooneyRivlin {
            mu10: 5e5,
            mu01: 1e5,
            penalty,
        },
    }
}

/// Two concentric layers: core 0–0.01 m and ring 0.01–0.02 m.
pub fn two_layer(core: Material, cover: Material, order: usize) -> Section {
    Section::circular(&[(0.0, 0.01, core), (0.01, 0.02, cover)], order)
}

/// A straight reference element of length `l` along x.
pub fn reference(l: f64) -> ElementVector {
    reference_coordinates(
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        l,
    )
}

/// A random large deformation of the reference: every coordinate moved by
/// up to `amplitude` (positions scaled by the length).
pub fn deformed(rng: &mut Rng, l: f64, amplitude: f64) -> ElementVector {
    let mut e = reference(l);
    for (i, v) in e.iter_mut().enumerate() {
        let scale = if (i / 3) % 4 == 0 { l } else { 1.0 };
        *v += amplitude * scale * rng.uniform();
    }
    e
}

/// Rotation matrix from a rotation vector (Rodrigues).
pub fn rotation(v: [f64; 3]) -> [[f64; 3]; 3] {
    let th = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let k = [v[0] / th, v[1] / th, v[2] / th];
    let (s, c) = th.sin_cos();
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let kk = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
            let k2: f64 = (0..3).map(|m| kk[i][m] * kk[m][j]).sum();
            r[i][j] = if i == j { 1.0 } else { 0.0 } + s * kk[i][j] + (1.0 - c) * k2;
        }
    }
    r
}

/// Apply x → R x (+ t for the position entries) to an element vector.
pub fn rigid_motion(e: &ElementVector, r: &[[f64; 3]; 3], t: [f64; 3]) -> ElementVector {
    let mut out = [0.0; 24];
    for blk in 0..8 {
        for i in 0..3 {
            out[3 * blk + i] = (0..3).map(|j| r[i][j] * e[3 * blk + j]).sum::<f64>();
            if blk % 4 == 0 {
                out[3 * blk + i] += t[i];
            }
        }
    }
    out
}

pub fn element(section: Section, l: f64, axial_order: usize) -> ElementIntegration {
    ElementIntegration::new(l, axial_order, section)
}

/// Relative difference ‖a − b‖ / ‖b‖ (Euclidean), for finite-difference checks.
pub fn rel(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    d / b.iter().map(|y| y * y).sum::<f64>().sqrt()
}

/// Central differences with step `h` of `f` with respect to its first and
/// its second argument: ∂f/∂e and ∂f/∂v, row-major 24 × 24.
pub fn central_differences(
    f: impl Fn(&[f64; 24], &[f64; 24]) -> [f64; 24],
    e: &[f64; 24],
    v: &[f64; 24],
    h: f64,
) -> ([f64; 576], [f64; 576]) {
    let (mut fq, mut fv) = ([0.0; 576], [0.0; 576]);
    for j in 0..24 {
        let (mut ep, mut em) = (*e, *e);
        ep[j] += h;
        em[j] -= h;
        let (qp, qm) = (f(&ep, v), f(&em, v));
        let (mut vp, mut vm) = (*v, *v);
        vp[j] += h;
        vm[j] -= h;
        let (rp, rm) = (f(e, &vp), f(e, &vm));
        for i in 0..24 {
            fq[i * 24 + j] = (qp[i] - qm[i]) / (2.0 * h);
            fv[i * 24 + j] = (rp[i] - rm[i]) / (2.0 * h);
        }
    }
    (fq, fv)
}

/// Splits a CSV line (quoted fields may hold commas).
pub fn split_csv(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
}

/// How far a Jacobian's columns lie from central differences of the force
/// they claim to differentiate: the largest difference and the largest
/// difference quotient, for ∂/∂q and for ∂/∂v.
pub struct JacobianErrors {
    pub worst_q: f64,
    pub worst_v: f64,
    pub largest_q: f64,
    pub largest_v: f64,
}

/// Central differences with step `h` of `force(q, v)` (on the unknowns) in
/// each unknown of q and of v, against `column(j, velocity)`: column j of
/// ∂/∂q, or of ∂/∂v with `velocity`.
pub fn jacobian_errors(
    model: &ancf_core::model::Model,
    (q, v): (&[f64], &[f64]),
    h: f64,
    column: impl Fn(usize, bool) -> Vec<f64>,
    mut force: impl FnMut(&[f64], &[f64]) -> Vec<f64>,
) -> JacobianErrors {
    let m = model.n_unknowns;
    let mut e = JacobianErrors {
        worst_q: 0.0,
        worst_v: 0.0,
        largest_q: 0.0,
        largest_v: 0.0,
    };
    for j in 0..m {
        let (col_q, col_v) = (column(j, false), column(j, true));
        let mut unit = vec![0.0; m];
        unit[j] = 1.0;
        let shifted = |x: &[f64], s: f64| {
            let mut y = x.to_vec();
            model.scatter_add(&unit, s, &mut y);
            y
        };
        let quotient = |plus: Vec<f64>, minus: Vec<f64>| -> Vec<f64> {
            plus.iter()
                .zip(minus)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect()
        };
        let dq = quotient(force(&shifted(q, h), v), force(&shifted(q, -h), v));
        let dv = quotient(force(q, &shifted(v, h)), force(q, &shifted(v, -h)));
        for i in 0..m {
            e.worst_q = e.worst_q.max((col_q[i] - dq[i]).abs());
            e.worst_v = e.worst_v.max((col_v[i] - dv[i]).abs());
            e.largest_q = e.largest_q.max(dq[i].abs());
            e.largest_v = e.largest_v.max(dv[i].abs());
        }
    }
    e
}
