//! A section's twist about its centerline: how far its r_y turned about
//! the tangent, beyond what the swing of the tangent itself carries.
//!
//! The swing is the smallest rotation taking the reference tangent t₀ to
//! the current t (about t₀ × t): it carries the reference r_y to a
//! direction normal to t. The twist is the angle from that carried
//! direction to the current r_y (its part normal to t), positive about t.
//! A rigid rotation about the tangent is all twist; a bend in a plane
//! containing r_y or normal to it is none. It is undefined where the
//! tangent has turned right round (t = −t₀), where any swing axis serves.

use super::vec3::{cross, dot, scale, sub, unit};

/// The twist (rad, in (−π, π]) of a section whose tangent and r_y are
/// `t`, `y` now and `t0`, `y0` in the reference (any lengths).
pub fn twist(t0: [f64; 3], y0: [f64; 3], t: [f64; 3], y: [f64; 3]) -> f64 {
    let (t0, t) = (unit(t0), unit(t));
    let normal = |v: [f64; 3], t: [f64; 3]| unit(sub(v, scale(t, dot(v, t))));
    let y0 = normal(y0, t0);
    // Rodrigues' rotation about t₀ × t by the angle between them, in the
    // form without the axis's normalization: v cos + (k × v) + k (k·v) / (1 + cos).
    let (k, c) = (cross(t0, t), dot(t0, t));
    let kv = cross(k, y0);
    let carried: [f64; 3] =
        std::array::from_fn(|i| y0[i] * c + kv[i] + k[i] * dot(k, y0) / (1.0 + c));
    let y = normal(y, t);
    dot(cross(carried, y), t).atan2(dot(carried, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotate(axis: [f64; 3], angle: f64, v: [f64; 3]) -> [f64; 3] {
        let k = unit(axis);
        let (c, s) = (angle.cos(), angle.sin());
        let kv = cross(k, v);
        std::array::from_fn(|i| v[i] * c + kv[i] * s + k[i] * dot(k, v) * (1.0 - c))
    }

    /// A turn about the tangent is twist, a bend is none, and a bend after
    /// a twist keeps the twist.
    #[test]
    fn twist_is_the_turn_about_the_tangent_beyond_the_swing() {
        let (t0, y0) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let twisted = rotate(t0, 0.7, y0);
        assert!((twist(t0, y0, t0, twisted) - 0.7).abs() < 1e-14);
        for axis in [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.6, -0.8]] {
            let (t, y) = (rotate(axis, 1.2, t0), rotate(axis, 1.2, y0));
            assert!(twist(t0, y0, t, y).abs() < 1e-14, "bent about {axis:?}");
            let (t, y) = (rotate(axis, 1.2, t0), rotate(axis, 1.2, twisted));
            assert!((twist(t0, y0, t, y) - 0.7).abs() < 1e-14, "{axis:?}");
        }
        // Lengths do not matter.
        assert!((twist(scale(t0, 2.0), y0, t0, scale(twisted, 0.5)) - 0.7).abs() < 1e-14);
    }
}
