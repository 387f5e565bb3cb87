//! The active zone of the line law (SPEC §7.2): the intervals of ξ ∈ [0, 1]
//! where an element's centerline comes closer to a rod's axis than
//! R_s = R_wire + R_rod.
//!
//! D(ξ) = |w(ξ)|² − R_s², w the offset from the rod's nearest axis point, is
//! a polynomial of degree 6 along an infinite rod (the centerline is cubic).
//! It is sampled at 17 points; a sign change between samples is refined to
//! the root by safeguarded Newton, and where the samples' slopes show a
//! minimum (or maximum) between them, the extremum is found by Newton on D′
//! first, so a zone shorter than the sample spacing is not missed. The zone
//! ends are exact to round-off: the Gauss points placed between them then
//! integrate a smooth function, and a crossing that slides along the wire
//! moves the force smoothly.

use super::point::axis_offset;
use crate::element::ElementVector;
use crate::math::vec3::dot;
use crate::model::contact::Rod;

/// At most this many separate zones per element and rod (a cubic
/// centerline has at most three along an infinite rod).
pub const MAX_ZONES: usize = 4;

/// Sample intervals per element.
const SAMPLES: usize = 16;

/// The active intervals [ξ_a, ξ_b] of one element against one rod, in order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Zones {
    len: usize,
    bounds: [(f64, f64); MAX_ZONES],
}

impl Zones {
    /// The intervals, in increasing ξ.
    pub fn iter(&self) -> impl Iterator<Item = &(f64, f64)> {
        self.bounds[..self.len].iter()
    }

    /// Number of intervals.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.len
    }

    /// No active interval.
    #[cfg(test)]
    fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn push(&mut self, a: f64, b: f64) {
        if b > a && self.len < MAX_ZONES {
            self.bounds[self.len] = (a, b);
            self.len += 1;
        }
    }
}

/// Centerline position r(ξ) and its derivatives dr/dξ, d²r/dξ² (m), from
/// the cubic Hermite interpolation of r and r_x (element length `l`).
pub fn centerline(e: &ElementVector, xi: f64, l: f64) -> [[f64; 3]; 3] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let n = [
        [
            1.0 - 3.0 * x2 + 2.0 * x3,
            l * (xi - 2.0 * x2 + x3),
            3.0 * x2 - 2.0 * x3,
            l * (-x2 + x3),
        ],
        [
            -6.0 * xi + 6.0 * x2,
            l * (1.0 - 4.0 * xi + 3.0 * x2),
            6.0 * xi - 6.0 * x2,
            l * (-2.0 * xi + 3.0 * x2),
        ],
        [
            -6.0 + 12.0 * xi,
            l * (-4.0 + 6.0 * xi),
            6.0 - 12.0 * xi,
            l * (-2.0 + 6.0 * xi),
        ],
    ];
    std::array::from_fn(|k| {
        std::array::from_fn(|c| {
            n[k][0] * e[c] + n[k][1] * e[3 + c] + n[k][2] * e[12 + c] + n[k][3] * e[15 + c]
        })
    })
}

/// D(ξ) = |w|² − R_s² along one element's centerline against one rod.
struct RodGap<'a> {
    e: &'a ElementVector,
    l: f64,
    rod: &'a Rod,
    reach: f64,
}

impl GapFunction for RodGap<'_> {
    fn eval(&self, xi: f64) -> [f64; 3] {
        let [r, r1, r2] = centerline(self.e, xi, self.l);
        if self.rod.is_ground() {
            // A plane: the signed distance less the wire's radius, a cubic
            // in ξ (not squared: its sign is the side).
            let n = self.rod.axis;
            return [self.rod.height(&r) - self.reach, dot(r1, n), dot(r2, n)];
        }
        let (w, inside) = axis_offset(self.rod, &r, true).expect("caps always give an offset");
        // ∂w/∂ξ = Π r′ with Π = I − d dᵀ inside the rod's length, I on a cap.
        let d = self.rod.axis;
        let along = if inside { dot(r1, d) } else { 0.0 };
        let pr1 = [
            r1[0] - along * d[0],
            r1[1] - along * d[1],
            r1[2] - along * d[2],
        ];
        [
            dot(w, w) - self.reach * self.reach,
            2.0 * dot(w, pr1),
            2.0 * (dot(r1, pr1) + dot(w, r2)),
        ]
    }
}

/// A squared gap D(ξ) = |w(ξ)|² − R_s² along an element (w the offset from
/// the partner's nearest point), negative where the two overlap.
pub(crate) trait GapFunction {
    /// D, D′ and D″ at ξ.
    fn eval(&self, xi: f64) -> [f64; 3];

    /// A root of D in [a, b], where D(a) (= `fa`) and D(b) differ in sign.
    fn root(&self, a: f64, fa: f64, b: f64) -> f64 {
        self.refine(a, fa < 0.0, b, 0)
    }

    /// A root of D′ in [a, b], where D′(a) and D′(b) differ in sign.
    fn extremum(&self, a: f64, dfa: f64, b: f64) -> f64 {
        self.refine(a, dfa < 0.0, b, 1)
    }

    /// Safeguarded Newton on the `order`-th derivative of D: the bracket
    /// [a, b] shrinks every iteration, and a Newton step leaving it is
    /// replaced by bisection.
    fn refine(&self, mut a: f64, negative_at_a: bool, mut b: f64, order: usize) -> f64 {
        let mut x = 0.5 * (a + b);
        for _ in 0..100 {
            let v = self.eval(x);
            let (f, df) = (v[order], v[order + 1]);
            if f == 0.0 {
                return x;
            }
            if (f < 0.0) == negative_at_a {
                a = x;
            } else {
                b = x;
            }
            let newton = x - f / df;
            let next = if df != 0.0 && newton > a && newton < b {
                newton
            } else {
                0.5 * (a + b)
            };
            if (next - x).abs() <= 4.0 * f64::EPSILON || b - a <= 4.0 * f64::EPSILON {
                return next;
            }
            x = next;
        }
        x
    }
}

/// The intervals of ξ where element `e` (length `l`) has its centerline
/// within `reach` of the rod (distance to the axis segment: a finite rod's
/// ends are spherical caps), or of a ground's plane (on its side, or
/// through it).
pub fn active_zones(e: &ElementVector, l: f64, rod: &Rod, reach: f64) -> Zones {
    zones_of(&RodGap { e, l, rod, reach })
}

/// The intervals of ξ ∈ [0, 1] where `gap` is negative.
pub(crate) fn zones_of(gap: &impl GapFunction) -> Zones {
    let samples: [(f64, [f64; 3]); SAMPLES + 1] = std::array::from_fn(|k| {
        let xi = k as f64 / SAMPLES as f64;
        (xi, gap.eval(xi))
    });
    // Where D changes sign, in increasing ξ (at most two per sample interval).
    let mut crossings = [0.0; 2 * SAMPLES];
    let mut nc = 0;
    for pair in samples.windows(2) {
        let ((x0, d0), (x1, d1)) = (pair[0], pair[1]);
        let (neg0, neg1) = (d0[0] < 0.0, d1[0] < 0.0);
        if neg0 != neg1 {
            crossings[nc] = gap.root(x0, d0[0], x1);
            nc += 1;
        } else if if neg0 {
            d0[1] >= 0.0 && d1[1] < 0.0
        } else {
            d0[1] < 0.0 && d1[1] > 0.0
        } {
            // No sign change, but D turns between the samples toward zero
            // (a dip below zero when both are positive, a bump above zero
            // when both are negative): look at the extremum.
            let xm = gap.extremum(x0, d0[1], x1);
            let dm = gap.eval(xm)[0];
            if (dm < 0.0) != neg0 {
                crossings[nc] = gap.root(x0, d0[0], xm);
                crossings[nc + 1] = gap.root(xm, dm, x1);
                nc += 2;
            }
        }
    }
    let mut zones = Zones::default();
    let mut start = (samples[0].1[0] < 0.0).then_some(0.0);
    for &x in &crossings[..nc] {
        match start.take() {
            Some(a) => zones.push(a, x),
            None => start = Some(x),
        }
    }
    if let Some(a) = start {
        zones.push(a, 1.0);
    }
    zones
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::reference_coordinates;
    use crate::model::contact::ContactLaw;

    fn rod(x: f64, z: f64) -> Rod {
        Rod {
            center: [x, 0.0, z],
            axis: [0.0, 1.0, 0.0],
            radius: 0.02,
            shape: Default::default(),
            length: None,
            law: ContactLaw::Line,
            contact_stiffness: 1.0,
            friction: 0.0,
            damping: None,
        }
    }

    /// A crossing 0.1 µm deep is 0.16 mm wide, far narrower than the 7.8 mm
    /// between samples: found from the minimum between samples, with its
    /// ends at x_c ± √(R_s² − D²) to round-off.
    #[test]
    fn a_zone_narrower_than_the_samples_is_found_exactly() {
        let (l, reach, delta) = (0.125, 0.034, 1e-7);
        let e = reference_coordinates(
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            l,
        );
        let xc = 0.53 * l;
        let zones = active_zones(&e, l, &rod(xc, -(reach - delta)), reach);
        assert_eq!(zones.len(), 1);
        let (a, b) = *zones.iter().next().unwrap();
        let d = reach - delta;
        let s0 = (reach * reach - d * d).sqrt();
        assert!(
            (a * l - (xc - s0)).abs() < 1e-12 && (b * l - (xc + s0)).abs() < 1e-12,
            "{a} {b}"
        );
        // Just apart: nothing.
        assert!(active_zones(&e, l, &rod(xc, -(reach + 1e-9)), reach).is_empty());
    }

    /// A rod across the element's end covers [0, ξ_b]; a rod along the wire
    /// (touching everywhere) the whole element.
    #[test]
    fn zones_reach_the_element_ends() {
        let (l, reach) = (0.125, 0.034);
        let e = reference_coordinates(
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            l,
        );
        let zones = active_zones(&e, l, &rod(0.0, -(reach - 1e-3)), reach);
        let (a, b) = *zones.iter().next().unwrap();
        assert_eq!(a, 0.0);
        assert!(b > 0.0 && b < 1.0);
        let along = Rod {
            axis: [1.0, 0.0, 0.0],
            ..rod(0.0, -(reach - 1e-3))
        };
        let all: Vec<_> = active_zones(&e, l, &along, reach).iter().copied().collect();
        assert_eq!(all, vec![(0.0, 1.0)]);
    }
}
