//! Evaluates penalty contact between the wire and rigid rods, with
//! regularized Coulomb friction (SPEC §7), from the model's description
//! ([`crate::model::contact`]). Each rod names its law:
//!
//! * `Line` (default) and `Hertz`: contact on the centerline, integrated
//!   over the active zone (line.rs, zone.rs).
//! * `Surface`: fixed test points on the outer surface (surface.rs), the
//!   paper's method.
//!
//! Both apply the same point kernel (point.rs). The normal force derives
//! from a potential, so a frictionless impact conserves energy; the broad
//! phase skips elements whose centerline is far from every rod.

pub mod beam;
pub mod capsule;
mod line;
mod point;
mod surface;
pub(crate) mod zone;

pub use surface::TestPoint;

use crate::element::{ElementMatrix, ElementVector, shape_functions};
use crate::math::quadrature::{Rule1d, gauss_legendre_unit};
use crate::math::vec3::dot;
use crate::model::contact::{Contact, ContactLaw, ContactSettings, MemberContact, Rod};

/// A model's contact, ready to evaluate: its rods and settings, the zone
/// rule and what depends on the element length, computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactEvaluator {
    /// The rods, in the scene's order.
    pub rods: Vec<Rod>,
    /// The frame members the wire may touch (partners after the rods).
    pub members: Vec<MemberContact>,
    /// Integration and regularization settings.
    pub settings: ContactSettings,
    /// Gauss rule on [0, 1] for a piece of an active zone (line laws).
    pub zone_rule: Rule1d,
    /// Outer radius of the wire, m.
    pub wire_radius: f64,
    /// What depends on the element length, one per element group of the
    /// model (one for a uniform mesh).
    pub geometry: Vec<ElementGeometry>,
    /// Whether any rod has contact damping ([`Contact::has_damping`]): then
    /// each contact event's approach speed is kept.
    pub damped: bool,
    /// The members that touch a ground besides the wire
    /// ([`Contact::grounded_members`]): (ground's rod index, beam), sorted.
    pub grounded_members: Vec<(usize, usize)>,
}

/// The contact quantities of elements of one length, computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementGeometry {
    /// Reference element length, m.
    pub length: f64,
    /// The outer radius of the elements' section, m: the wire's, or a
    /// member's where it touches a ground.
    pub radius: f64,
    /// Surface test points of one element (empty without surface-law rods).
    pub points: Vec<TestPoint>,
    /// Shape functions on the centerline at the 9 broad-phase stations
    /// (constant: computed once, not per element and step).
    broad_phase: [[f64; 8]; 9],
}

/// What contact does in one element (or summed over the wire).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSample {
    /// Penalty energy, J.
    pub energy: f64,
    /// Largest penetration −g, m (0 when apart).
    pub max_penetration: f64,
    /// Sum of normal force magnitudes, N.
    pub normal_force: f64,
    /// Friction power −Σ f_t · v_p ≥ 0, W.
    pub friction_power: f64,
    /// Power taken by contact damping ≥ 0, W.
    pub damping_power: f64,
    /// Largest rate of penetration δ̇ = −n · ṙ at an active point of a
    /// damped rod, m/s (0 otherwise): the approach speed of a new event.
    pub approach_speed: f64,
    /// Active integration points.
    pub active: usize,
    /// Resultant contact force on the wire (normal + friction), N; the rod
    /// carries its opposite.
    pub force: [f64; 3],
}

/// Where the deepest penetration of an element is, as a material point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeepestPoint {
    /// Rod index.
    pub rod: usize,
    /// Axial coordinate ξ.
    pub xi: f64,
    /// Section coordinate y of the surface point facing the rod, m.
    pub y: f64,
    /// Section coordinate z of the surface point facing the rod, m.
    pub z: f64,
    /// Penetration, m.
    pub penetration: f64,
}

impl ContactEvaluator {
    /// Rods and members: the contact partners (a pair is indexed
    /// `element × partners + partner`).
    pub fn partners(&self) -> usize {
        self.rods.len() + self.members.len()
    }

    /// The evaluator of `contact` on elements of `element_lengths` (m), those
    /// of the model's element groups in order (one for a uniform mesh).
    pub fn new(contact: &Contact, element_lengths: &[f64]) -> Self {
        let (settings, wire_radius) = (&contact.settings, contact.wire_radius);
        let surface = contact.rods.iter().any(|r| r.law == ContactLaw::Surface);
        let geometry = element_lengths
            .iter()
            .map(|&length| ElementGeometry {
                length,
                radius: wire_radius,
                points: if surface {
                    surface::test_points(settings.stations, settings.angles, wire_radius, length)
                } else {
                    Vec::new()
                },
                broad_phase: std::array::from_fn(|k| {
                    shape_functions(k as f64 / 8.0, 0.0, 0.0, length)
                }),
            })
            .collect();
        ContactEvaluator {
            zone_rule: gauss_legendre_unit(settings.zone_points),
            rods: contact.rods.clone(),
            members: contact.members.clone(),
            settings: settings.clone(),
            wire_radius,
            geometry,
            damped: contact.has_damping(),
            grounded_members: contact.grounded_members.clone(),
        }
    }

    /// The evaluator of `model`'s contact `contact`: each element group's
    /// length, and the outer radius of a member's groups (a member touches
    /// only the grounds that name it).
    pub fn for_model(contact: &Contact, model: &crate::model::Model) -> Self {
        let mut c = Self::new(contact, &model.element_lengths());
        let wire = model.wire().elements.clone();
        for (geometry, group) in c.geometry.iter_mut().zip(&model.groups) {
            if !wire.contains(&group.elements.start) {
                geometry.radius = group.integration.section.outer_radius();
            }
        }
        c
    }

    /// The grounds (rod indices, increasing) that the elements of beam
    /// `beam` touch besides the wire: none for the wire (which touches every
    /// rod) or an ungrounded member.
    pub fn grounds_of(&self, beam: usize) -> impl Iterator<Item = usize> + '_ {
        (self.grounded_members.iter())
            .filter(move |&&(_, b)| b == beam)
            .map(|&(ri, _)| ri)
    }

    /// Broad phase: can element `e` (of element group `group`) touch rod
    /// `rod`? The minimal distance between its cubic centerline (sampled at
    /// 9 stations) and the rod's axis, against R_w + R_rod plus a margin for
    /// the chord sag between samples and the section's deformation (R_w + l/8).
    pub fn may_touch(&self, group: usize, rod: &Rod, e: &ElementVector) -> bool {
        self.may_touch_within(group, rod, e, 0.0)
    }

    /// [`ContactEvaluator::may_touch`] with `margin` (m) more reach: could the
    /// element touch the rod after its centerline moved by up to `margin`?
    pub fn may_touch_within(
        &self,
        group: usize,
        rod: &Rod,
        e: &ElementVector,
        margin: f64,
    ) -> bool {
        let sphere = self.centerline_sphere(group, e);
        self.may_touch_around(group, rod, e, sphere, margin)
    }

    /// A sphere (centre, radius; m) holding the centerline of element `e`
    /// of element group `group`, for [`ContactEvaluator::may_touch_around`].
    pub fn centerline_sphere(&self, group: usize, e: &ElementVector) -> ([f64; 3], f64) {
        beam::centerline_sphere(e, self.geometry[group].length)
    }

    /// [`ContactEvaluator::may_touch_within`] with the element's
    /// [`ContactEvaluator::centerline_sphere`] given, so that a broad
    /// phase over several rods computes it once an element.
    pub fn may_touch_around(
        &self,
        group: usize,
        rod: &Rod,
        e: &ElementVector,
        (centre, radius): ([f64; 3], f64),
        margin: f64,
    ) -> bool {
        let geometry = &self.geometry[group];
        let l = geometry.length;
        let reach = rod.radius + 2.0 * geometry.radius + l / 8.0 + margin;
        if rod.is_ground() {
            // A plane: the signed distance of the sphere, then of the samples.
            if rod.height(&centre) > reach + radius {
                return false;
            }
            return geometry.broad_phase.iter().any(|s| {
                let p: [f64; 3] =
                    std::array::from_fn(|c| (0..8).map(|i| s[i] * e[3 * i + c]).sum());
                rod.height(&p) < reach
            });
        }
        // First the sphere holding the centerline: if even that is out of
        // reach, so is every sample below (the same answer, for a fraction
        // of the work; the samples were 10 % of the impact run, perf).
        // A point's coordinate along the rod's axis from its centre and its
        // distance from the axis (m).
        let axis_coordinates = |p: &[f64; 3]| {
            let rel = [
                p[0] - rod.center[0],
                p[1] - rod.center[1],
                p[2] - rod.center[2],
            ];
            let along = dot(rel, rod.axis);
            let perp = [
                rel[0] - along * rod.axis[0],
                rel[1] - along * rod.axis[1],
                rel[2] - along * rod.axis[2],
            ];
            (along, dot(perp, perp).sqrt())
        };
        let (along, distance) = axis_coordinates(&centre);
        if distance > reach + radius
            || rod
                .length
                .is_some_and(|len| along.abs() > 0.5 * len + reach + radius)
        {
            return false;
        }
        geometry.broad_phase.iter().any(|s| {
            let p: [f64; 3] = std::array::from_fn(|c| (0..8).map(|i| s[i] * e[3 * i + c]).sum());
            let (along, distance) = axis_coordinates(&p);
            if let Some(len) = rod.length
                && along.abs() > 0.5 * len + reach
            {
                return false;
            }
            distance < reach
        })
    }

    /// Contact force on one element of element group `group` (added to
    /// `q`, N), −∂Q/∂q (added to `kq`) and −∂Q/∂v (added to `kv`), with
    /// coordinates `e` and velocities `v`. Returns the sample and the
    /// deepest point.
    pub fn element(
        &self,
        group: usize,
        e: &ElementVector,
        v: &ElementVector,
        q: &mut ElementVector,
        mut kq: Option<&mut ElementMatrix>,
        mut kv: Option<&mut ElementMatrix>,
    ) -> (ContactSample, Option<DeepestPoint>) {
        let mut sample = ContactSample::default();
        let mut deepest: Option<DeepestPoint> = None;
        for ri in 0..self.rods.len() {
            let (s, dp) = self.element_rod(
                group,
                ri,
                e,
                v,
                0.0,
                q,
                kq.as_deref_mut(),
                kv.as_deref_mut(),
            );
            sample.accumulate(&s);
            if let Some(dp) = dp
                && deepest.is_none_or(|d| dp.penetration > d.penetration)
            {
                deepest = Some(dp);
            }
        }
        (sample, deepest)
    }

    /// [`ContactEvaluator::element`] for rod `ri` alone, in a contact event that
    /// began at approach speed `impact_speed` (m/s; 0: none yet, the
    /// event's first step, undamped).
    #[allow(clippy::too_many_arguments)]
    pub fn element_rod(
        &self,
        group: usize,
        ri: usize,
        e: &ElementVector,
        v: &ElementVector,
        impact_speed: f64,
        q: &mut ElementVector,
        kq: Option<&mut ElementMatrix>,
        kv: Option<&mut ElementMatrix>,
    ) -> (ContactSample, Option<DeepestPoint>) {
        let rod = &self.rods[ri];
        if !self.may_touch(group, rod, e) {
            return (ContactSample::default(), None);
        }
        // Within an event χ; at its first step 0 (the approach speed is
        // still to be measured).
        let damping = rod.damping.map(|d| {
            if impact_speed > 0.0 {
                d.factor(impact_speed, self.settings.min_impact_speed)
            } else {
                0.0
            }
        });
        let mut out = point::ElementOut {
            v,
            damping,
            q,
            kq,
            kv,
            sample: ContactSample::default(),
        };
        let geometry = &self.geometry[group];
        let deepest = match rod.law {
            ContactLaw::Surface => surface::element_rod(self, geometry, ri, rod, e, &mut out),
            ContactLaw::Line | ContactLaw::Hertz => {
                line::element_rod(self, geometry, ri, rod, e, &mut out)
            }
        };
        (out.sample, deepest)
    }
}

impl ContactSample {
    /// Add another sample's energy, forces and counts; keep the larger penetration.
    pub fn accumulate(&mut self, o: &ContactSample) {
        self.energy += o.energy;
        self.max_penetration = self.max_penetration.max(o.max_penetration);
        self.normal_force += o.normal_force;
        self.friction_power += o.friction_power;
        self.damping_power += o.damping_power;
        self.approach_speed = self.approach_speed.max(o.approach_speed);
        self.active += o.active;
        for c in 0..3 {
            self.force[c] += o.force[c];
        }
    }
}
