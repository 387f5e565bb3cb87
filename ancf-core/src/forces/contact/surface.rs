//! The surface law (SPEC §7.1, the paper's method): fixed test points on the
//! deformed outer surface, `stations` Gauss points along ξ times `angles`
//! equally spaced angles φ, (y, z) = R_w (cos φ, sin φ). A point with gap
//! g = |w| − R_rod < 0 gets the force ε_N (−g) A n, A its reference surface
//! area (ε_N in N/m³). Kept for comparison and for sections whose squeeze
//! matters; its force jumps as test points enter the contact patch.

use super::point::{ElementOut, PointInput, axis_offset, point_contact};
use super::{ContactEvaluator, DeepestPoint, ElementGeometry};
use crate::element::{ElementVector, shape_functions};
use crate::math::quadrature::gauss_legendre_unit;
use crate::model::contact::Rod;

/// One surface test point, in material coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestPoint {
    /// Axial coordinate ξ = x/l.
    pub xi: f64,
    /// Section coordinates, m.
    pub y: f64,
    /// Section coordinates, m.
    pub z: f64,
    /// Reference surface area it stands for, m².
    pub area: f64,
    /// Shape functions at the point.
    pub s: [f64; 8],
}

/// The test points of one element: `stations` × `angles`.
pub fn test_points(stations: usize, angles: usize, wire_radius: f64, l: f64) -> Vec<TestPoint> {
    let rule = gauss_legendre_unit(stations);
    let dphi = 2.0 * std::f64::consts::PI / angles as f64;
    let mut points = Vec::new();
    for (xi, w) in rule.nodes.iter().zip(&rule.weights) {
        for j in 0..angles {
            let phi = j as f64 * dphi;
            let (y, z) = (wire_radius * phi.cos(), wire_radius * phi.sin());
            points.push(TestPoint {
                xi: *xi,
                y,
                z,
                area: w * l * wire_radius * dphi,
                s: shape_functions(*xi, y, z, l),
            });
        }
    }
    points
}

/// Surface contact of one element with `rod` (index `ri`): see
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
    for tp in &geometry.points {
        let p: [f64; 3] = std::array::from_fn(|c| (0..8).map(|i| tp.s[i] * e[3 * i + c]).sum());
        // Open ends: a point beyond the rod's length does not touch it.
        let Some((w, inside)) = axis_offset(rod, &p, false) else {
            continue;
        };
        let input = PointInput {
            s: &tp.s,
            w,
            inside,
            offset: rod.radius,
            stiffness: rod.contact_stiffness * tp.area,
        };
        let slip = contact.settings.slip_velocity;
        if let Some(r) = point_contact(&input, rod, slip, out)
            && deepest.is_none_or(|dp| r.penetration > dp.penetration)
        {
            deepest = Some(DeepestPoint {
                rod: ri,
                xi: tp.xi,
                y: tp.y,
                z: tp.z,
                penetration: r.penetration,
            });
        }
    }
    deepest
}
