//! Clearance zones: a region the wire must stay out of — the road, the
//! track or the line under a protective frame. They exert no force; a run
//! measures how close the wire's surface comes to each (see
//! [`crate::loads::clearance_record`]).

use crate::check::{ParameterError, direction, finite3};
use crate::math::vec3::{dot, norm, sub};

/// A region the wire must not enter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClearanceZone {
    /// An axis-aligned box between two corners (m).
    Box {
        /// The corner of least x, y, z.
        min: [f64; 3],
        /// The corner of largest x, y, z.
        max: [f64; 3],
    },
    /// Everything on one side of a plane through `point` (m): the side
    /// `normal` points away from (so `normal` points to where the wire may
    /// be; a road surface at z = 0 is point [0, 0, 0], normal [0, 0, 1]).
    HalfSpace {
        /// A point of the plane.
        point: [f64; 3],
        /// The plane's normal, out of the zone (any length but zero).
        normal: [f64; 3],
    },
}

impl ClearanceZone {
    /// The zone's name in the scene file.
    pub fn kind(&self) -> &'static str {
        match self {
            ClearanceZone::Box { .. } => "box",
            ClearanceZone::HalfSpace { .. } => "half-space",
        }
    }

    /// Corners finite and ordered (`max[i]` > `min[i]`); a half-space's
    /// point finite and its normal a direction.
    pub fn check(&self) -> Result<(), ParameterError> {
        match self {
            ClearanceZone::Box { min, max } => {
                finite3("min", *min)?;
                finite3("max", *max)?;
                if let Some(i) = (0..3).find(|&i| max[i] <= min[i]) {
                    return Err(ParameterError {
                        field: format!("max[{i}]"),
                        message: format!("must exceed min[{i}] = {}, got {}", min[i], max[i]),
                    });
                }
            }
            ClearanceZone::HalfSpace { point, normal } => {
                finite3("point", *point)?;
                direction("normal", *normal)?;
            }
        }
        Ok(())
    }

    /// The signed distance of point `p` from the zone (m): positive
    /// outside, the depth inside as a negative number.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        match self {
            ClearanceZone::Box { min, max } => {
                let d: [f64; 3] = std::array::from_fn(|i| (min[i] - p[i]).max(p[i] - max[i]));
                let outside = norm(d.map(|x| x.max(0.0)));
                let inside = d[0].max(d[1]).max(d[2]).min(0.0);
                outside + inside
            }
            ClearanceZone::HalfSpace { point, normal } => {
                dot(sub(p, *point), *normal) / norm(*normal)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_distances() {
        let b = ClearanceZone::Box {
            min: [0.0, 0.0, 0.0],
            max: [2.0, 1.0, 1.0],
        };
        assert_eq!(b.distance([1.0, 0.5, 3.0]), 2.0);
        assert_eq!(b.distance([5.0, 5.0, 0.5]), 5.0);
        assert_eq!(b.distance([1.0, 0.5, 0.9]), -0.09999999999999998);
        let h = ClearanceZone::HalfSpace {
            point: [0.0, 0.0, 1.0],
            normal: [0.0, 0.0, 2.0],
        };
        assert_eq!(h.distance([7.0, -3.0, 4.0]), 3.0);
        assert_eq!(h.distance([0.0, 0.0, 0.5]), -0.5);
    }

    #[test]
    fn bad_zones_name_the_field() {
        let b = ClearanceZone::Box {
            min: [0.0; 3],
            max: [1.0, 0.0, 1.0],
        };
        assert_eq!(b.check().unwrap_err().field, "max[1]");
        let h = ClearanceZone::HalfSpace {
            point: [0.0; 3],
            normal: [0.0; 3],
        };
        assert_eq!(h.check().unwrap_err().field, "normal");
    }
}
