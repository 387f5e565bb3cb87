//! What a run's contact did as a whole, step by step: when and where the
//! wire first touched a rod, the largest normal force and penetration. The
//! rods' own force histories are [`super::rod_load::LoadHistory`].

use crate::forces::contact::{ContactSample, DeepestPoint};

/// The material point that touched a rod first.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactPoint {
    /// Element index.
    pub element: usize,
    /// Axial coordinate ξ ∈ [0, 1].
    pub xi: f64,
    /// Section coordinates of the surface point facing the rod, m.
    pub y: f64,
    /// See `y`, m.
    pub z: f64,
}

/// Contact over a run so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactRecord {
    /// End time of the first step with any contact, s (`None`: never touched).
    pub first_time: Option<f64>,
    /// The deepest point of that step.
    pub first_point: Option<ContactPoint>,
    /// Largest total normal force of any step, N.
    pub max_normal_force: f64,
    /// Largest penetration of any step, m.
    pub max_penetration: f64,
}

impl ContactRecord {
    /// Record the step that ended at `time` with contact `sample` and its
    /// deepest point `deepest` (element, point).
    pub fn push(
        &mut self,
        time: f64,
        sample: &ContactSample,
        deepest: Option<(usize, DeepestPoint)>,
    ) {
        if sample.active > 0 && self.first_time.is_none() {
            self.first_time = Some(time);
            self.first_point = deepest.map(|(element, p)| ContactPoint {
                element,
                xi: p.xi,
                y: p.y,
                z: p.z,
            });
        }
        self.max_normal_force = self.max_normal_force.max(sample.normal_force);
        self.max_penetration = self.max_penetration.max(sample.max_penetration);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_touch_is_kept_and_the_largest_values_grow() {
        let mut r = ContactRecord::default();
        r.push(0.1, &ContactSample::default(), None);
        assert_eq!(r.first_time, None);
        let point = DeepestPoint {
            rod: 0,
            xi: 0.25,
            y: 0.0,
            z: -0.01,
            penetration: 1e-4,
        };
        let touch = ContactSample {
            active: 2,
            normal_force: 50.0,
            max_penetration: 1e-4,
            ..Default::default()
        };
        r.push(0.2, &touch, Some((3, point)));
        let later = ContactSample {
            active: 1,
            normal_force: 20.0,
            max_penetration: 3e-4,
            ..Default::default()
        };
        r.push(0.3, &later, Some((5, point)));
        assert_eq!(r.first_time, Some(0.2));
        assert_eq!(r.first_point.map(|p| (p.element, p.xi)), Some((3, 0.25)));
        assert_eq!((r.max_normal_force, r.max_penetration), (50.0, 3e-4));
    }
}
