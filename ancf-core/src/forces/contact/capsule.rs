//! A capsule holding an element's centerline: its chord and a radius, the
//! farthest of the cubic's inner Bézier control points from the chord.
//!
//! Why: the wire-to-member contact (beam.rs) finds an element's active
//! zone from 17 samples of the gap, each a closest-point search on the
//! member's nearby elements, and the broad phase's spheres let through
//! every wire element within a member element's half length: on the
//! elastic frame nine in ten such searches found no zone. Two capsules
//! whose chords lie farther apart than their radii plus the contact
//! distance cannot touch; the search is then skipped. For the nearly
//! straight elements of a wire and a tube the radius is a small fraction
//! of the sphere's, so the bound is close to the true distance.

use crate::element::ElementVector;
use crate::math::vec3::{dot, norm, sub};

/// A chord from `a` to `b` (m) and a radius (m): every point of the
/// centerline lies within `radius` of the chord.
#[derive(Clone, Copy, Debug)]
pub struct Capsule {
    /// The chord's start: the element's first node (m).
    pub a: [f64; 3],
    /// The chord's end: the element's second node (m).
    pub b: [f64; 3],
    /// The largest distance of the centerline from the chord (m).
    pub radius: f64,
}

/// The capsule of an element's centerline (coordinates `e`, length `l`,
/// m): the cubic lies in the hull of its Bézier control points r₁,
/// r₁ + l/3 r₁ₓ, r₂ − l/3 r₂ₓ, r₂, and that hull within the largest
/// distance of the two inner points from the chord r₁ r₂ (the set of
/// points within a distance of a segment is convex).
pub fn centerline_capsule(e: &ElementVector, l: f64) -> Capsule {
    let a = [e[0], e[1], e[2]];
    let b = [e[12], e[13], e[14]];
    let inner = [
        std::array::from_fn(|c| e[c] + l / 3.0 * e[3 + c]),
        std::array::from_fn(|c| e[12 + c] - l / 3.0 * e[15 + c]),
    ];
    let radius = inner
        .iter()
        .map(|p| norm(sub(*p, closest_on_segment(*p, a, b))))
        .fold(0.0, f64::max);
    Capsule { a, b, radius }
}

/// Whether two capsules may come within `reach` (m) of each other: false
/// only when their chords lie farther apart than their radii plus
/// `reach`, with a margin for the rounding of the chords' distance.
pub fn capsules_within(p: &Capsule, q: &Capsule, reach: f64) -> bool {
    let lengths = norm(sub(p.b, p.a)) + norm(sub(q.b, q.a));
    let margin = 1e-9 * (lengths + reach) + 1e-15;
    segment_distance(p, q) <= p.radius + q.radius + reach + margin
}

/// The point of the segment [a, b] nearest to `p`.
fn closest_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let d = sub(b, a);
    let dd = dot(d, d);
    let s = if dd > 0.0 {
        (dot(sub(p, a), d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    std::array::from_fn(|c| a[c] + s * d[c])
}

/// The distance (m) between two capsules' chords: the closest points of
/// two segments (Ericson, *Real-Time Collision Detection*, 2005, § 5.1.9).
fn segment_distance(p: &Capsule, q: &Capsule) -> f64 {
    let (d1, d2, r) = (sub(p.b, p.a), sub(q.b, q.a), sub(p.a, q.a));
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let (s, t) = if a <= 0.0 && e <= 0.0 {
        (0.0, 0.0)
    } else if a <= 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = dot(d1, r);
        if e <= 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = dot(d1, d2);
            let denom = a * e - b * b;
            let s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    let c1: [f64; 3] = std::array::from_fn(|k| p.a[k] + s * d1[k]);
    let c2: [f64; 3] = std::array::from_fn(|k| q.a[k] + t * d2[k]);
    norm(sub(c1, c2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::contact::zone::centerline;

    /// A bent, twisted element of length `l` from `seed`: its nodes and
    /// slopes varied, as a deformed wire's or tube's.
    fn element(seed: usize, l: f64, at: [f64; 3]) -> ElementVector {
        let v = |k: usize| ((seed * 7919 + k * 104_729) % 1000) as f64 / 1000.0 - 0.5;
        let mut e = [0.0; 24];
        for c in 0..3 {
            e[c] = at[c] + 0.1 * l * v(c);
            e[12 + c] = at[c] + if c == 0 { l } else { 0.0 } + 0.1 * l * v(3 + c);
            e[3 + c] = if c == 0 { 1.0 } else { 0.0 } + 0.6 * v(6 + c);
            e[15 + c] = if c == 0 { 1.0 } else { 0.0 } + 0.6 * v(9 + c);
        }
        e
    }

    /// Every centerline point lies in the capsule.
    #[test]
    fn the_capsule_holds_the_centerline() {
        for seed in 0..200 {
            let l = 0.05 + 0.01 * (seed % 30) as f64;
            let e = element(seed, l, [0.0; 3]);
            let cap = centerline_capsule(&e, l);
            for k in 0..=100 {
                let r = centerline(&e, k as f64 / 100.0, l)[0];
                let off = norm(sub(r, closest_on_segment(r, cap.a, cap.b)));
                assert!(
                    off <= cap.radius * (1.0 + 1e-12) + 1e-15,
                    "{seed}: {off} > {}",
                    cap.radius
                );
            }
        }
    }

    /// The chords' distance is the least over points of both segments
    /// (against a fine search), in general position, parallel and crossing.
    #[test]
    fn segment_distance_is_the_least_distance() {
        let brute = |p: &Capsule, q: &Capsule| {
            let mut best = f64::INFINITY;
            for i in 0..=200 {
                for j in 0..=200 {
                    let (s, t) = (i as f64 / 200.0, j as f64 / 200.0);
                    let x: [f64; 3] = std::array::from_fn(|k| p.a[k] + s * (p.b[k] - p.a[k]));
                    let y: [f64; 3] = std::array::from_fn(|k| q.a[k] + t * (q.b[k] - q.a[k]));
                    best = best.min(norm(sub(x, y)));
                }
            }
            best
        };
        let cap = |a: [f64; 3], b: [f64; 3]| Capsule { a, b, radius: 0.0 };
        let cases = [
            (
                cap([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
                cap([0.5, -1.0, 0.3], [0.5, 1.0, 0.3]),
            ),
            (
                cap([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
                cap([0.2, 0.1, 0.0], [1.4, 0.1, 0.0]),
            ),
            (
                cap([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
                cap([2.0, 0.5, 0.1], [3.0, -0.2, 0.4]),
            ),
            (
                cap([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
                cap([0.3, 0.4, 0.0], [0.3, -0.4, 0.0]),
            ),
            (
                cap([0.1, 0.2, 0.3], [0.4, -0.5, 0.9]),
                cap([-0.3, 0.3, 0.2], [0.6, 0.1, -0.2]),
            ),
        ];
        for (p, q) in &cases {
            let (fast, slow) = (segment_distance(p, q), brute(p, q));
            assert!(fast <= slow + 1e-12, "{fast} > {slow}");
            assert!(slow - fast < 1e-2, "{fast} far below {slow}");
        }
    }

    /// Two elements whose capsules are apart have centerlines apart by
    /// more than the reach; some near pairs are tested as well.
    #[test]
    fn capsules_apart_means_centerlines_apart() {
        let reach = 0.064;
        let (mut apart, mut near) = (0, 0);
        for seed in 0..400 {
            let wire = element(seed, 0.05, [0.0; 3]);
            // Tubes beside the wire, 0 … 16 cm away.
            let offset = [-0.1, 0.0, 0.002 * (seed % 80) as f64];
            let tube = element(seed + 1000, 0.25, offset);
            let (p, q) = (
                centerline_capsule(&wire, 0.05),
                centerline_capsule(&tube, 0.25),
            );
            let mut least = f64::INFINITY;
            for i in 0..=60 {
                let x = centerline(&wire, i as f64 / 60.0, 0.05)[0];
                for j in 0..=60 {
                    let y = centerline(&tube, j as f64 / 60.0, 0.25)[0];
                    least = least.min(norm(sub(x, y)));
                }
            }
            if capsules_within(&p, &q, reach) {
                near += 1;
            } else {
                apart += 1;
                assert!(least > reach, "{seed}: apart, yet {least} ≤ {reach}");
            }
        }
        assert!(apart > 50 && near > 50, "{apart} apart, {near} near");
    }
}
