//! The line law (SPEC §7.2): contact on the wire's centerline, integrated
//! over the active zone. The gap is g(ξ) = |w(ξ)| − R_s, R_s = R_wire +
//! R_rod, the line pressure p = ε_L ⟨−g⟩ (N/m per m of reference length,
//! ε_L in N/m²) and the potential V = ∫ ½ ε_L ⟨−g⟩² ds. The zone's ends are
//! found (zone.rs), and Gauss points placed between them integrate a smooth
//! integrand: refinement converges, and a crossing sliding along the wire
//! changes the force smoothly. p vanishes at the ends, so the moving ends
//! add nothing to the force's derivative: the tangent is the Gauss sum of
//! the pointwise tangents.

use super::point::{ElementOut, PointInput, axis_offset, point_contact};
use super::zone::active_zones;
use super::{ContactEvaluator, DeepestPoint, ElementGeometry};
use crate::element::{ElementVector, shape_functions};
use crate::math::vec3::dot;
use crate::model::contact::Rod;

/// A zone longer than this (in ξ) is split into pieces of at most this
/// length, each with its own Gauss points.
pub const MAX_PIECE: f64 = 0.5;

/// Line contact of one element with `rod` (index `ri`): see
/// [`ContactEvaluator::element_rod`].
pub(crate) fn element_rod(
    contact: &ContactEvaluator,
    geometry: &ElementGeometry,
    ri: usize,
    rod: &Rod,
    e: &ElementVector,
    out: &mut ElementOut,
) -> Option<DeepestPoint> {
    let mut deepest: Option<DeepestPoint> = None;
    let l = geometry.length;
    let reach = rod.radius + geometry.radius;
    let rule = &contact.zone_rule;
    for &(a, b) in active_zones(e, l, rod, reach).iter() {
        let pieces = ((b - a) / MAX_PIECE).ceil().max(1.0);
        let len = (b - a) / pieces;
        for piece in 0..pieces as usize {
            let start = a + piece as f64 * len;
            for (x, w) in rule.nodes.iter().zip(&rule.weights) {
                let xi = start + x * len;
                let s = shape_functions(xi, 0.0, 0.0, l);
                let r: [f64; 3] =
                    std::array::from_fn(|c| (0..8).map(|i| s[i] * e[3 * i + c]).sum());
                let (w_off, inside) =
                    axis_offset(rod, &r, true).expect("caps always give an offset");
                let input = PointInput {
                    s: &s,
                    w: w_off,
                    inside,
                    offset: reach,
                    stiffness: rod.contact_stiffness * w * len * l,
                };
                let slip = contact.settings.slip_velocity;
                if let Some(res) = point_contact(&input, rod, slip, out)
                    && deepest.is_none_or(|dp| res.penetration > dp.penetration)
                {
                    let (y, z) = facing_point(e, xi, &res.n, geometry.radius);
                    deepest = Some(DeepestPoint {
                        rod: ri,
                        xi,
                        y,
                        z,
                        penetration: res.penetration,
                    });
                }
            }
        }
    }
    deepest
}

/// Section coordinates (y, z) of the outer surface point at ξ that faces
/// the rod (deformed direction −n): y r_y + z r_z ∥ −n in the least-squares
/// sense, scaled to the wire radius.
pub(crate) fn facing_point(e: &ElementVector, xi: f64, n: &[f64; 3], radius: f64) -> (f64, f64) {
    let ry: [f64; 3] = std::array::from_fn(|c| (1.0 - xi) * e[6 + c] + xi * e[18 + c]);
    let rz: [f64; 3] = std::array::from_fn(|c| (1.0 - xi) * e[9 + c] + xi * e[21 + c]);
    let (a, b, c) = (dot(ry, ry), dot(ry, rz), dot(rz, rz));
    let (fy, fz) = (-dot(*n, ry), -dot(*n, rz));
    let det = a * c - b * b;
    let (y, z) = ((c * fy - b * fz) / det, (a * fz - b * fy) / det);
    let norm = (y * y + z * z).sqrt();
    if norm > 0.0 && norm.is_finite() {
        (radius * y / norm, radius * z / norm)
    } else {
        (0.0, -radius)
    }
}
