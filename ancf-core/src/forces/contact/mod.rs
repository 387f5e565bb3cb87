//! Penalty contact between the wire and rigid rods, with regularized
//! Coulomb friction (SPEC §7). Each rod names its law:
//!
//! * `Line` (default) and `Hertz`: contact on the centerline, integrated
//!   over the active zone (line.rs, zone.rs); `Hertz` is the line law with
//!   ε_L derived from the materials' E* (SPEC §7.3), resolved when the scene
//!   is read.
//! * `Surface`: fixed test points on the outer surface (surface.rs), the
//!   paper's method.
//!
//! Both apply the same point kernel (point.rs). The normal force derives
//! from a potential, so a frictionless impact conserves energy; the broad
//! phase skips elements whose centerline is far from every rod. Whether a
//! time step resolves a line-law contact is known before a run from ε_L and
//! the wire's ρA (resolution.rs).

mod hertz;
mod line;
mod point;
pub mod resolution;
mod surface;
pub mod zone;

pub use hertz::hertz_line_stiffness;
pub use resolution::{RESOLVED_STEP_FREQUENCY, UnresolvedContact, unresolved_contacts};
pub use surface::TestPoint;

use crate::element::{ElementMatrix, ElementVector, shape_functions};
use crate::math::quadrature::{Rule1d, gauss_legendre_unit};
use crate::math::vec3::dot;

/// How a rod's contact force is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactLaw {
    /// Centerline line contact over the active zone; stiffness ε_L in N/m².
    Line,
    /// The line law with ε_L = E* √(R_e / (2 R_s)) from the rod's and the
    /// wire's outer-layer materials (Hertz at a 90° crossing).
    Hertz,
    /// Surface test points; stiffness ε_N in N/m³.
    Surface,
}

impl ContactLaw {
    /// The name used in scene files and summaries.
    pub fn name(self) -> &'static str {
        match self {
            ContactLaw::Line => "line",
            ContactLaw::Hertz => "hertz",
            ContactLaw::Surface => "surface",
        }
    }

    /// The unit of the contact stiffness under this law.
    pub fn stiffness_unit(self) -> &'static str {
        match self {
            ContactLaw::Surface => "N/m^3",
            _ => "N/m^2",
        }
    }
}

/// A rigid cylinder.
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    /// A point on the axis, m.
    pub center: [f64; 3],
    /// Unit axis direction.
    pub axis: [f64; 3],
    /// Radius, m.
    pub radius: f64,
    /// Length, m, centred on `center`; `None` is infinite. The line laws
    /// treat the ends as spherical caps (distance to the axis segment), the
    /// surface law as open (no contact beyond the ends).
    pub length: Option<f64>,
    /// The contact law.
    pub law: ContactLaw,
    /// Penalty stiffness actually used: ε_L in N/m² (line, hertz) or ε_N in
    /// N/m³ (surface).
    pub contact_stiffness: f64,
    /// Coulomb coefficient μ; 0 = frictionless (no friction code runs).
    pub friction: f64,
    /// Contact damping with a coefficient of restitution; `None` (the
    /// default) = elastic contact (no damping code runs).
    pub damping: Option<ContactDamping>,
}

/// Hunt–Crossley contact damping: the normal force k δ becomes
/// k δ (1 + χ δ̇)⁺, δ̇ the rate of penetration, with χ = c(e) / v⁻ from the
/// coefficient of restitution e and the approach speed v⁻ of the contact
/// event (SPEC §7.3). The force starts and ends at zero like the elastic
/// one (a dashpot c δ̇ would jump at first touch).
///
/// Why c(e) can be exact: a single body hitting with this law obeys
/// m δ̇ dδ̇ = −k δⁿ (1 + χ δ̇) dδ; integrated from touch to release (δ = 0 at
/// both) the right side vanishes, so χ v⁻ − ln(1 + χ v⁻) = −χ v⁺ −
/// ln(1 − χ v⁺) for any m, k and n (Carvalho & Martins, Mech. Mach. Theory
/// 139, 2019). [`RestitutionModel::Exact`] solves it for the c that gives
/// v⁺/v⁻ = e; the classic closed forms approximate it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactDamping {
    restitution: f64,
    model: RestitutionModel,
    coefficient: f64,
}

/// How the damping factor follows from the coefficient of restitution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RestitutionModel {
    /// c solved from the closed-form rebound of the Hunt–Crossley law (see
    /// [`ContactDamping`]): a single body rebounds at exactly e.
    Exact,
    /// Flores et al. (Nonlinear Dyn. 65, 2011): c = 8 (1 − e) / (5 e);
    /// rebounds at 0.256 for e = 0.3, 0.470 for 0.5, 0.894 for 0.9.
    Flores,
    /// Lankarani & Nikravesh (J. Mech. Des. 112, 1990): c = 3 (1 − e²) / 4,
    /// from an energy balance for e → 1; rebounds at 0.684 for e = 0.3,
    /// 0.725 for 0.5, 0.913 for 0.9 (never below 0.64).
    LankaraniNikravesh,
}

impl RestitutionModel {
    /// The model named `name` in a scene file or a Python call, or what to
    /// tell the user.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "exact" => Ok(RestitutionModel::Exact),
            "flores" => Ok(RestitutionModel::Flores),
            "lankarani-nikravesh" => Ok(RestitutionModel::LankaraniNikravesh),
            other => Err(format!(
                "unknown model \"{other}\" (use \"exact\", \"flores\" or \"lankarani-nikravesh\")"
            )),
        }
    }

    /// The name used in scene files and summaries.
    pub fn name(self) -> &'static str {
        match self {
            RestitutionModel::Exact => "exact",
            RestitutionModel::Flores => "flores",
            RestitutionModel::LankaraniNikravesh => "lankarani-nikravesh",
        }
    }
}

impl ContactDamping {
    /// Damping for a coefficient of restitution `restitution` ∈ (0, 1) by
    /// `model`.
    pub fn new(restitution: f64, model: RestitutionModel) -> Self {
        let e = restitution;
        let coefficient = match model {
            RestitutionModel::Exact => exact_coefficient(e),
            RestitutionModel::Flores => 1.6 * (1.0 - e) / e,
            RestitutionModel::LankaraniNikravesh => 0.75 * (1.0 - e * e),
        };
        ContactDamping {
            restitution,
            model,
            coefficient,
        }
    }

    /// The coefficient of restitution asked for.
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// How c follows from it.
    pub fn model(&self) -> RestitutionModel {
        self.model
    }

    /// c(e): the damping factor is χ = c / v⁻ (s/m).
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }

    /// The damping factor χ (s/m) of an event that began at approach speed
    /// `impact_speed` (m/s; raised to `min_speed`).
    pub fn factor(&self, impact_speed: f64, min_speed: f64) -> f64 {
        self.coefficient / impact_speed.max(min_speed)
    }
}

/// The rebound ratio v⁺/v⁻ of a single body under Hunt–Crossley damping
/// with χ v⁻ = c: the root y ∈ (0, 1) of −y − ln(1 − y) = c − ln(1 + c),
/// divided by c (bisection; the left side increases with y).
pub fn hunt_crossley_rebound(c: f64) -> f64 {
    if c <= 0.0 {
        return 1.0;
    }
    let target = c - c.ln_1p();
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if -mid - (-mid).ln_1p() > target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi) / c
}

/// The c whose rebound ratio is `e` (bisection in ln c; the rebound
/// decreases from 1 at c = 0 towards 0).
fn exact_coefficient(e: f64) -> f64 {
    let (mut lo, mut hi) = ((1e-12_f64).ln(), (1e8_f64).ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if hunt_crossley_rebound(mid.exp()) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).exp()
}

impl Rod {
    /// An infinite, frictionless rod under the line law: a point on its axis
    /// and its direction, radius (m) and ε_L (N/m²).
    pub fn line(center: [f64; 3], axis: [f64; 3], radius: f64, stiffness: f64) -> Self {
        Rod {
            center,
            axis: crate::math::vec3::unit(axis),
            radius,
            length: None,
            law: ContactLaw::Line,
            contact_stiffness: stiffness,
            friction: 0.0,
            damping: None,
        }
    }

    /// The same rod with Coulomb friction μ.
    pub fn with_friction(self, friction: f64) -> Self {
        Rod { friction, ..self }
    }

    /// The same rod with contact damping of restitution `restitution` ∈ (0, 1)
    /// by `model`.
    pub fn with_restitution(self, restitution: f64, model: RestitutionModel) -> Self {
        Rod {
            damping: Some(ContactDamping::new(restitution, model)),
            ..self
        }
    }

    /// The same rod, `length` m long (centred on its point).
    pub fn with_length(self, length: f64) -> Self {
        Rod {
            length: Some(length),
            ..self
        }
    }
}

/// Resolution of the contact integration and the friction regularization.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSettings {
    /// Surface law: Gauss stations along each element. Default 8.
    pub stations: usize,
    /// Surface law: angles around the outer surface. Default 16.
    pub angles: usize,
    /// Line laws: Gauss points per active zone (per piece of at most half
    /// an element). Default 8: the 90° crossing's resultant to 1e-10 for a
    /// penetration up to 9 % of R_wire + R_rod (6 points: 6e-8).
    pub zone_points: usize,
    /// Regularization velocity v_ε of Coulomb friction, m/s. Default 1e-3:
    /// below it friction acts like a viscous damper.
    pub slip_velocity: f64,
    /// A time step whose deepest point penetrates a rod by more than this
    /// fraction of the wire radius is rejected and halved. Default 1: no
    /// physical state gets there, but a step too coarse for the contact
    /// does, and accepting it loses the wire through the rod.
    pub max_penetration: f64,
    /// Contact damping: the smallest approach speed v⁻ (m/s) the damping
    /// factor χ = c(e)/v⁻ is computed with. Default 0.1: a wire that slides
    /// or settles into contact (v⁻ → 0) would otherwise get an unbounded χ.
    pub min_impact_speed: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            stations: 8,
            angles: 16,
            zone_points: 8,
            slip_velocity: 1e-3,
            max_penetration: 1.0,
            min_impact_speed: 0.1,
        }
    }
}

/// The contact model of a wire: rods and the integration points.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The rods, in the scene's order.
    pub rods: Vec<Rod>,
    /// Integration and regularization settings.
    pub settings: ContactSettings,
    /// Gauss rule on [0, 1] for a piece of an active zone (line laws).
    pub zone_rule: Rule1d,
    /// Outer radius of the wire, m.
    pub wire_radius: f64,
    /// What depends on the element length, one per element group of the
    /// model (one for a uniform mesh).
    pub geometry: Vec<ElementGeometry>,
}

/// The contact quantities of elements of one length, computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementGeometry {
    /// Reference element length, m.
    pub length: f64,
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

impl Contact {
    /// The contact of a wire of outer radius `wire_radius` (m) with `rods`;
    /// `element_lengths` (m) are those of the model's element groups, in
    /// order (one for a uniform mesh).
    pub fn new(
        rods: Vec<Rod>,
        settings: ContactSettings,
        wire_radius: f64,
        element_lengths: &[f64],
    ) -> Self {
        let surface = rods.iter().any(|r| r.law == ContactLaw::Surface);
        let geometry = element_lengths
            .iter()
            .map(|&length| ElementGeometry {
                length,
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
        Contact {
            zone_rule: gauss_legendre_unit(settings.zone_points),
            rods,
            settings,
            wire_radius,
            geometry,
        }
    }

    /// Whether any rod has friction (then the Newton matrix is not symmetric).
    pub fn has_friction(&self) -> bool {
        self.rods.iter().any(|r| r.friction > 0.0)
    }

    /// Whether any rod has contact damping (then the force depends on the
    /// velocities, the Newton matrix is not symmetric, and the state keeps
    /// each contact event's approach speed).
    pub fn has_damping(&self) -> bool {
        self.rods.iter().any(|r| r.damping.is_some())
    }

    /// Whether the contact force depends on the velocities.
    pub fn velocity_dependent(&self) -> bool {
        self.has_friction() || self.has_damping()
    }

    /// Broad phase: can element `e` (of element group `group`) touch rod
    /// `rod`? The minimal distance between its cubic centerline (sampled at
    /// 9 stations) and the rod's axis, against R_w + R_rod plus a margin for
    /// the chord sag between samples and the section's deformation (R_w + l/8).
    pub fn may_touch(&self, group: usize, rod: &Rod, e: &ElementVector) -> bool {
        self.may_touch_within(group, rod, e, 0.0)
    }

    /// [`Contact::may_touch`] with `margin` (m) more reach: could the
    /// element touch the rod after its centerline moved by up to `margin`?
    pub fn may_touch_within(
        &self,
        group: usize,
        rod: &Rod,
        e: &ElementVector,
        margin: f64,
    ) -> bool {
        let geometry = &self.geometry[group];
        let l = geometry.length;
        let reach = rod.radius + 2.0 * self.wire_radius + l / 8.0 + margin;
        // First a sphere around the centerline's Bézier control points
        // r₁, r₁ + l/3 r₁ₓ, r₂ − l/3 r₂ₓ, r₂ (the cubic lies in their hull):
        // if even that is out of reach, so is every sample below (the same
        // answer, for a fraction of the work; the samples were 10 % of the
        // impact run, perf).
        let bezier: [[f64; 3]; 4] = std::array::from_fn(|k| {
            std::array::from_fn(|c| match k {
                0 => e[c],
                1 => e[c] + l / 3.0 * e[3 + c],
                2 => e[12 + c] - l / 3.0 * e[15 + c],
                _ => e[12 + c],
            })
        });
        let centre: [f64; 3] =
            std::array::from_fn(|c| 0.25 * bezier.iter().map(|b| b[c]).sum::<f64>());
        let radius = bezier
            .iter()
            .map(|b| {
                let d = [b[0] - centre[0], b[1] - centre[1], b[2] - centre[2]];
                dot(d, d)
            })
            .fold(0.0, f64::max)
            .sqrt();
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

    /// [`Contact::element`] for rod `ri` alone, in a contact event that
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
