//! Quadrature rules: Gauss–Legendre along the beam axis and the paper's
//! disk/ring rule over a circular cross section (SPEC §2).
//!
//! All rules are computed once, when a model is built, by the Golub–Welsch
//! method (eigen-decomposition of the Jacobi matrix of the weight's
//! orthogonal polynomials), so any order is available; `build.rs` bakes the
//! axial rules of the compiled orders into constants as well.

use nalgebra::{DMatrix, SymmetricEigen};

/// A one-dimensional rule: nodes and weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Rule1d {
    /// Nodes on [0, 1].
    pub nodes: Vec<f64>,
    /// Weights (they sum to 1).
    pub weights: Vec<f64>,
}

/// One point of a cross-section rule: position (y, z) in m and area weight in m².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionPoint {
    /// Section coordinate y (m).
    pub y: f64,
    /// Section coordinate z (m).
    pub z: f64,
    /// Area weight (m²).
    pub weight: f64,
}

/// Nodes and weights of the Gauss rule whose Jacobi matrix has diagonal `a`
/// and off-diagonal `sqrt(b[1..])`, for a weight of total mass `b[0]`.
fn golub_welsch(a: &[f64], b: &[f64]) -> Rule1d {
    let n = a.len();
    let mut jacobi = DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        jacobi[(i, i)] = a[i];
        if i + 1 < n {
            let off = b[i + 1].sqrt();
            jacobi[(i, i + 1)] = off;
            jacobi[(i + 1, i)] = off;
        }
    }
    let eig = SymmetricEigen::new(jacobi);
    let mut pairs: Vec<(f64, f64)> = (0..n)
        .map(|i| (eig.eigenvalues[i], b[0] * eig.eigenvectors[(0, i)].powi(2)))
        .collect();
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
    Rule1d {
        nodes: pairs.iter().map(|p| p.0).collect(),
        weights: pairs.iter().map(|p| p.1).collect(),
    }
}

/// n-point Gauss–Legendre rule on [-1, 1] (exact for degree 2n − 1).
pub fn gauss_legendre(n: usize) -> Rule1d {
    assert!(n >= 1, "a Gauss–Legendre rule needs at least one point");
    let a = vec![0.0; n];
    let mut b = vec![2.0; n];
    for (k, bk) in b.iter_mut().enumerate().skip(1) {
        let k = k as f64;
        *bk = k * k / (4.0 * k * k - 1.0);
    }
    let mut rule = golub_welsch(&a, &b);
    // Symmetrize: removes the last bit of eigen-solver noise.
    for i in 0..n / 2 {
        let j = n - 1 - i;
        let x = 0.5 * (rule.nodes[j] - rule.nodes[i]);
        let w = 0.5 * (rule.weights[i] + rule.weights[j]);
        rule.nodes[i] = -x;
        rule.nodes[j] = x;
        rule.weights[i] = w;
        rule.weights[j] = w;
    }
    if n % 2 == 1 {
        rule.nodes[n / 2] = 0.0;
    }
    rule
}

/// n-point Gauss–Legendre rule mapped to [0, 1] (nodes ξ, weights sum to 1).
pub fn gauss_legendre_unit(n: usize) -> Rule1d {
    let r = gauss_legendre(n);
    Rule1d {
        nodes: r.nodes.iter().map(|x| 0.5 * (x + 1.0)).collect(),
        weights: r.weights.iter().map(|w| 0.5 * w).collect(),
    }
}

/// n-point Gauss rule for the weight |s| on [−r2, −r1] ∪ [r1, r2]
/// (the signed radius of SPEC §2), by the discretized Stieltjes procedure.
///
/// The weight is piecewise linear, so a Gauss–Legendre discretization with
/// `n + 2` points on each of the two intervals integrates every product the
/// procedure forms (degree ≤ 2n + 1 times |s|) exactly: the recurrence, and so
/// the rule, is exact up to round-off.
pub fn signed_radius_rule(n: usize, r1: f64, r2: f64) -> Rule1d {
    signed_radius_rule_weighted(n, &[(r1, r2, 1.0)])
}

/// The Gauss rule for the weight c_k |s| on each piece r1_k ≤ |s| ≤ r2_k
/// (`pieces` = (r1, r2, c), non-overlapping, c > 0): concentric layers of
/// different stiffness integrated by one rule.
pub fn signed_radius_rule_weighted(n: usize, pieces: &[(f64, f64, f64)]) -> Rule1d {
    assert!(n >= 1 && !pieces.is_empty());
    let gl = gauss_legendre(n + 2);
    let mut xs = Vec::new();
    let mut ws = Vec::new();
    for &(r1, r2, c) in pieces {
        assert!(r1 >= 0.0 && r2 > r1 && c > 0.0);
        let (mid, half) = (0.5 * (r1 + r2), 0.5 * (r2 - r1));
        for (x, w) in gl.nodes.iter().zip(&gl.weights) {
            let s = mid + half * x;
            for sign in [-1.0, 1.0] {
                xs.push(sign * s);
                ws.push(c * w * half * s);
            }
        }
    }
    // Stieltjes: monic orthogonal polynomials evaluated on the discrete points.
    let m = xs.len();
    let mut p_prev = vec![0.0; m];
    let mut p = vec![1.0; m];
    let mut a = vec![0.0; n];
    let mut b = vec![0.0; n];
    let mut norm_prev = 1.0;
    for k in 0..n {
        let norm: f64 = (0..m).map(|i| ws[i] * p[i] * p[i]).sum();
        let xnorm: f64 = (0..m).map(|i| ws[i] * xs[i] * p[i] * p[i]).sum();
        a[k] = xnorm / norm;
        b[k] = if k == 0 { norm } else { norm / norm_prev };
        let next: Vec<f64> = (0..m)
            .map(|i| (xs[i] - a[k]) * p[i] - if k == 0 { 0.0 } else { b[k] * p_prev[i] })
            .collect();
        p_prev = std::mem::replace(&mut p, next);
        norm_prev = norm;
    }
    // The weight is even: the recurrence has a = 0 exactly.
    a.iter_mut().for_each(|x| *x = 0.0);
    let mut rule = golub_welsch(&a, &b);
    if n % 2 == 1 {
        rule.nodes[n / 2] = 0.0;
    }
    rule
}

/// The paper's product rule over the ring r1 ≤ ρ ≤ r2 (a disk when r1 = 0):
/// n angles θ_m = mπ/n over a half turn times the n-point signed-radius rule.
/// Exact for every monomial yᵃzᵇ with a + b ≤ 2n − 1. Points at the centre
/// (odd n) are merged into one, so a disk with odd n has n² − n + 1 points.
pub fn ring_rule(n: usize, r1: f64, r2: f64) -> Vec<SectionPoint> {
    ring_rule_weighted(n, &[(r1, r2, 1.0)])
}

/// The ring construction with `radial` signed-radius nodes and `angles`
/// angles over a half turn (2 × `angles` directions): exact for yᵃzᵇ with
/// a + b ≤ 2 min(radial, angles) − 1. A thin ring's stress varies little
/// through the wall and much around it (a yielding tube's stress has kinks
/// along its circumference): few radial nodes, many angles.
pub fn ring_rule_with(radial: usize, angles: usize, r1: f64, r2: f64) -> Vec<SectionPoint> {
    let rule = signed_radius_rule_weighted(radial, &[(r1, r2, 1.0)]);
    ring_of(&rule, angles)
}

/// The ring construction for the radial weight of [`signed_radius_rule_weighted`]:
/// ∫ f c(ρ) dA exact for f of degree ≤ 2n − 1.
pub fn ring_rule_weighted(n: usize, pieces: &[(f64, f64, f64)]) -> Vec<SectionPoint> {
    ring_of(&signed_radius_rule_weighted(n, pieces), n)
}

/// The product of a signed-radius rule with `angles` angles θ_m = mπ/angles
/// over a half turn; its nodes at the centre are merged into one point.
fn ring_of(radial: &Rule1d, angles: usize) -> Vec<SectionPoint> {
    let dtheta = std::f64::consts::PI / angles as f64;
    let mut points = Vec::with_capacity(radial.nodes.len() * angles);
    let mut centre_weight = 0.0;
    for (s, w) in radial.nodes.iter().zip(&radial.weights) {
        if *s == 0.0 {
            centre_weight += dtheta * w * angles as f64;
            continue;
        }
        for m in 0..angles {
            let theta = m as f64 * dtheta;
            points.push(SectionPoint {
                y: s * theta.cos(),
                z: s * theta.sin(),
                weight: dtheta * w,
            });
        }
    }
    if centre_weight > 0.0 {
        points.push(SectionPoint {
            y: 0.0,
            z: 0.0,
            weight: centre_weight,
        });
    }
    points
}

/// Gauss–Legendre product rule over the rectangle |y| ≤ width/2, |z| ≤ height/2.
pub fn rectangle_rule(ny: usize, nz: usize, width: f64, height: f64) -> Vec<SectionPoint> {
    let gy = gauss_legendre(ny);
    let gz = gauss_legendre(nz);
    let mut points = Vec::with_capacity(ny * nz);
    for (y, wy) in gy.nodes.iter().zip(&gy.weights) {
        for (z, wz) in gz.nodes.iter().zip(&gz.weights) {
            points.push(SectionPoint {
                y: 0.5 * width * y,
                z: 0.5 * height * z,
                weight: 0.25 * width * height * wy * wz,
            });
        }
    }
    points
}

/// ∫ yᵃ zᵇ dA over the ring r1 ≤ ρ ≤ r2, in closed form:
/// ∫ρ^{a+b+1}dρ · ∫cosᵃθ sinᵇθ dθ, the angular integral by the Beta function
/// (zero unless a and b are both even).
pub fn ring_monomial_integral(a: u32, b: u32, r1: f64, r2: f64) -> f64 {
    if a % 2 == 1 || b % 2 == 1 {
        return 0.0;
    }
    let p = (a + b + 2) as i32;
    let radial = (r2.powi(p) - r1.powi(p)) / p as f64;
    // ∫_0^{2π} cos^a sin^b = 2 Γ((a+1)/2) Γ((b+1)/2) / Γ((a+b+2)/2), via double factorials:
    // = 2π (a−1)!! (b−1)!! / (a+b)!!
    let df = |k: i64| -> f64 {
        let mut r = 1.0;
        let mut i = k;
        while i > 1 {
            r *= i as f64;
            i -= 2;
        }
        r
    };
    let angular =
        2.0 * std::f64::consts::PI * df(a as i64 - 1) * df(b as i64 - 1) / df((a + b) as i64);
    radial * angular
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_degree_2n_minus_1() {
        for n in 1..=10 {
            let r = gauss_legendre(n);
            let integrate = |d: usize| -> f64 {
                (r.nodes.iter().zip(&r.weights))
                    .map(|(x, w)| w * x.powi(d as i32))
                    .sum()
            };
            for d in 0..=(2 * n - 1) {
                let q = integrate(d);
                let exact = if d % 2 == 1 {
                    0.0
                } else {
                    2.0 / (d as f64 + 1.0)
                };
                assert!((q - exact).abs() < 1e-14, "n={n} d={d}: {q} vs {exact}");
            }
            let d = 2 * n;
            let q = integrate(d);
            assert!(
                (q - 2.0 / (d as f64 + 1.0)).abs() > 1e-8,
                "n={n} must not be exact at degree 2n"
            );
        }
    }

    #[test]
    fn three_point_gauss_legendre_matches_textbook() {
        let r = gauss_legendre(3);
        assert!((r.nodes[2] - (0.6f64).sqrt()).abs() < 1e-15);
        assert!((r.weights[0] - 5.0 / 9.0).abs() < 1e-15);
        assert!((r.weights[1] - 8.0 / 9.0).abs() < 1e-15);
    }
}
