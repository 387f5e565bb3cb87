//! What a model says about contact: the rigid rods, each with its law
//! (SPEC §7), stiffness, friction and restitution, and the settings of the
//! contact integration. Checked here once ([`Rod::check`],
//! [`ContactSettings::check`]); evaluated by `forces::contact`.
//!
//! * `Line` (default) and `Hertz`: contact on the centerline, integrated
//!   over the active zone; `Hertz` is the line law with ε_L derived from the
//!   materials' E* (hertz.rs).
//! * `Surface`: fixed test points on the outer surface, the paper's method.
//!
//! Whether a time step resolves a line-law contact is known from ε_L and
//! the wire's ρA alone (resolution.rs).

mod equivalent;
mod hertz;
pub mod resolution;

pub use equivalent::surface_stiffness_matching_line;
pub use hertz::hertz_line_stiffness;
pub use resolution::{RESOLVED_STEP_FREQUENCY, UnresolvedContact, unresolved_contacts};

use crate::check::{ParameterError, count_in, direction, finite3, non_negative, positive, refuse};

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

/// The shape of a rigid contact partner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RigidShape {
    /// A cylinder (a `[[rod]]`): the gap is the distance from its axis
    /// less both radii, the normal turns with the contact point.
    #[default]
    Cylinder,
    /// A plane (a `[[ground]]`): `center` is a point of it, `axis` its unit
    /// normal towards the side the wire belongs on; the gap is the signed
    /// distance n · (r − p) less the wire's radius, and the normal is fixed.
    /// A wire point that passes through the plane is still pushed back up.
    Plane,
}

/// A rigid contact partner of the wire: a cylinder (a rod) or, with
/// [`RigidShape::Plane`], the ground. Both share the line law, friction,
/// restitution and the load report; only the gap's geometry differs.
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    /// A point on the axis (a plane: a point of it), m.
    pub center: [f64; 3],
    /// Unit axis direction (a plane: its unit normal).
    pub axis: [f64; 3],
    /// Radius, m (a plane: 0).
    pub radius: f64,
    /// A cylinder or a plane.
    pub shape: RigidShape,
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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RestitutionModel {
    /// c solved from the closed-form rebound of the Hunt–Crossley law (see
    /// [`ContactDamping`]): a single body rebounds at exactly e. The default.
    #[default]
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
    /// The damping that a contact's `restitution` and `restitution_model`
    /// keys ask for, the one rule every way in (scene, builder, Python)
    /// follows: the model needs the coefficient, the model's name must be
    /// known, and e = 1 (elastic) or no coefficient asks for none. The
    /// coefficient's range is [`Rod::check`]'s.
    pub fn from_keys(
        restitution: Option<f64>,
        model: Option<&str>,
    ) -> Result<Option<ContactDamping>, ParameterError> {
        let kind = match model {
            Some(name) => RestitutionModel::from_name(name)
                .or_else(|message| refuse("restitution_model", message))?,
            None => RestitutionModel::default(),
        };
        Ok(match restitution {
            None if model.is_some() => {
                return refuse(
                    "restitution",
                    "missing: restitution_model is set but the coefficient of restitution is not",
                );
            }
            None | Some(1.0) => None,
            Some(e) => Some(ContactDamping::new(e, kind)),
        })
    }

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
        // An axis without a finite, non-zero length stays as given, for
        // `check` to name it.
        let n = crate::math::vec3::norm(axis);
        let axis = if n > 0.0 && n.is_finite() {
            axis.map(|a| a / n)
        } else {
            axis
        };
        Rod {
            center,
            axis,
            radius,
            shape: RigidShape::Cylinder,
            length: None,
            law: ContactLaw::Line,
            contact_stiffness: stiffness,
            friction: 0.0,
            damping: None,
        }
    }

    /// The ground: a frictionless plane through `point` (m) with `normal`
    /// (towards the wire's side, normalised) under the line law of ε_L
    /// `stiffness` (N/m²).
    pub fn plane(point: [f64; 3], normal: [f64; 3], stiffness: f64) -> Self {
        Rod {
            radius: 0.0,
            shape: RigidShape::Plane,
            ..Rod::line(point, normal, 0.0, stiffness)
        }
    }

    /// Whether this partner is the ground (a plane).
    pub fn is_ground(&self) -> bool {
        self.shape == RigidShape::Plane
    }

    /// A plane's signed distance to `p` (m): along its normal from its
    /// point, negative below it.
    pub fn height(&self, p: &[f64; 3]) -> f64 {
        let rel = std::array::from_fn(|k| p[k] - self.center[k]);
        crate::math::vec3::dot(rel, self.axis)
    }

    /// Whether the rod can be built: a finite centre, a non-zero axis,
    /// radius, length and stiffness > 0, friction μ ≥ 0 and restitution in
    /// (0, 1].
    /// A plane's point and normal are checked as `point` and `normal`, and
    /// it takes the line law only.
    pub fn check(&self) -> Result<(), ParameterError> {
        match self.shape {
            RigidShape::Cylinder => {
                finite3("center", self.center)?;
                direction("axis", self.axis)?;
                positive("radius", self.radius)?;
                if let Some(l) = self.length {
                    positive("length", l)?;
                }
            }
            RigidShape::Plane => {
                finite3("point", self.center)?;
                direction("normal", self.axis)?;
                if self.law != ContactLaw::Line || self.length.is_some() || self.radius != 0.0 {
                    return refuse(
                        "contact_law",
                        "the ground takes the line law only (no length, no radius)",
                    );
                }
            }
        }
        positive("contact_stiffness", self.contact_stiffness)?;
        non_negative("friction", self.friction)?;
        if let Some(d) = self.damping {
            let e = d.restitution();
            if !(e > 0.0 && e <= 1.0) {
                return refuse(
                    "restitution",
                    format!("must be in (0, 1] (1 = elastic, no damping), got {e}"),
                );
            }
        }
        Ok(())
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

/// How the scene names rigid partner `i` of `rods` (the grounds after the
/// rods): `rod[k]` or `ground[k]`, k counted among its own kind.
pub fn rigid_name(rods: &[Rod], i: usize) -> String {
    let kind = rods[i].shape;
    let k = rods[..i].iter().filter(|r| r.shape == kind).count();
    match kind {
        RigidShape::Cylinder => format!("rod[{k}]"),
        RigidShape::Plane => format!("ground[{k}]"),
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

impl ContactSettings {
    /// Whether the settings can be used: stations 1..=64, angles 3..=256,
    /// zone points 1..=32, the penetration limit, slip velocity and least
    /// impact speed > 0.
    pub fn check(&self) -> Result<(), ParameterError> {
        count_in("stations", self.stations, 1..=64)?;
        count_in("angles", self.angles, 3..=256)?;
        count_in("zone_points", self.zone_points, 1..=32)?;
        positive("max_penetration", self.max_penetration)?;
        positive("slip_velocity", self.slip_velocity)?;
        positive("min_impact_speed", self.min_impact_speed)?;
        Ok(())
    }
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

/// How a frame member and the wire touch: the line law against the
/// member's deformed centerline (`forces::contact::beam`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamContact {
    /// `Line`: ε_L is `contact_stiffness`; `Hertz` (the default): ε_L from
    /// the member's and the wire's outer-layer materials at a 90° crossing.
    pub law: ContactLaw,
    /// ε_L (N/m²) under the line law.
    pub contact_stiffness: Option<f64>,
    /// Coulomb coefficient μ; 0 = frictionless.
    pub friction: f64,
    /// Contact damping with a coefficient of restitution; `None`: elastic.
    pub damping: Option<ContactDamping>,
}

impl Default for BeamContact {
    fn default() -> Self {
        BeamContact {
            law: ContactLaw::Hertz,
            contact_stiffness: None,
            friction: 0.0,
            damping: None,
        }
    }
}

impl BeamContact {
    /// The contact a member's keys ask for, the one rule every way in
    /// (scene, Python) follows: `contact_law` is `"hertz"` (the default) or
    /// `"line"`; `contact_stiffness` goes with the line law, which needs
    /// it, and the Hertz law refuses it (its stiffness comes from the two
    /// materials); `friction` defaults to 0; the damping is
    /// [`ContactDamping::from_keys`]'s. The values' ranges are
    /// [`MemberContact::check`]'s.
    pub fn from_keys(
        law: Option<&str>,
        contact_stiffness: Option<f64>,
        friction: Option<f64>,
        (restitution, restitution_model): (Option<f64>, Option<&str>),
    ) -> Result<BeamContact, ParameterError> {
        let law = match (law, contact_stiffness) {
            (None, Some(_)) => {
                return refuse(
                    "contact_law",
                    "missing: contact_stiffness (N/m^2) goes with contact_law = \"line\"; \
                     without a law the Hertz stiffness of the two materials is used",
                );
            }
            (None | Some("hertz"), _) => ContactLaw::Hertz,
            (Some("line"), _) => ContactLaw::Line,
            (Some(other), _) => {
                return refuse(
                    "contact_law",
                    format!(
                        "unknown law \"{other}\" for a member (use \"hertz\", the default, or \
                         \"line\")"
                    ),
                );
            }
        };
        let contact = BeamContact {
            law,
            contact_stiffness,
            friction: friction.unwrap_or(0.0),
            damping: ContactDamping::from_keys(restitution, restitution_model)?,
        };
        contact.check_law()?;
        Ok(contact)
    }

    /// Whether the law and the stiffness go together (the builder's check
    /// too): the line law needs `contact_stiffness`, the Hertz law refuses
    /// one (its stiffness comes from the two materials), and the surface
    /// law is for rigid rods only.
    pub fn check_law(&self) -> Result<(), ParameterError> {
        match (self.law, self.contact_stiffness) {
            (ContactLaw::Line, Some(_)) | (ContactLaw::Hertz, None) => Ok(()),
            (ContactLaw::Line, None) => refuse(
                "contact_stiffness",
                "missing: contact_law = \"line\" needs the line law's ε_L (N/m^2)",
            ),
            (ContactLaw::Hertz, Some(_)) => refuse(
                "contact_stiffness",
                "not used by contact_law = \"hertz\", whose stiffness comes from the two \
                 materials; give contact_law = \"line\" to use it",
            ),
            (ContactLaw::Surface, _) => refuse(
                "contact_law",
                "a member touches the wire by the line law (\"line\" or \"hertz\"); surface \
                 test points are for rigid rods",
            ),
        }
    }
}

/// Whether a ground's `beams` list can be: it names the wire, which
/// touches every ground (the rule a scene, the builder and Python follow;
/// the members' names are the model's to check).
pub fn check_ground_beams<S: AsRef<str> + std::fmt::Debug>(
    beams: &[S],
) -> Result<(), ParameterError> {
    if beams.iter().any(|b| b.as_ref() == crate::model::WIRE) {
        return Ok(());
    }
    refuse(
        "beams",
        format!(
            "{beams:?} leaves out the wire, which touches every ground: list \"wire\" with the \
             members that touch it too"
        ),
    )
}

/// A frame member's contact with the wire, as the model evaluates it.
#[derive(Clone, Debug, PartialEq)]
pub struct MemberContact {
    /// The member's beam (index into the model's beams; the wire is 0).
    pub beam: usize,
    /// Outer radius of the member's section, m.
    pub radius: f64,
    /// ε_L actually used, N/m² (per metre of the wire's reference length).
    pub contact_stiffness: f64,
    /// Coulomb coefficient μ; 0 = frictionless.
    pub friction: f64,
    /// Contact damping; `None`: elastic.
    pub damping: Option<ContactDamping>,
}

impl MemberContact {
    /// Whether the contact can be built: stiffness > 0, μ ≥ 0, restitution
    /// in (0, 1] (a rod's rules).
    pub fn check(&self) -> Result<(), ParameterError> {
        let rod = Rod {
            contact_stiffness: self.contact_stiffness,
            friction: self.friction,
            damping: self.damping,
            ..Rod::line([0.0; 3], [1.0, 0.0, 0.0], self.radius, 1.0)
        };
        rod.check()
    }
}

/// The contact of a wire with its rods and frame members, as the model
/// describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The rods, in the scene's order.
    pub rods: Vec<Rod>,
    /// The frame members the wire may touch, in the scene's order. A
    /// contact partner is a rod (indices 0 … rods) or a member (after them).
    pub members: Vec<MemberContact>,
    /// Integration and regularization settings.
    pub settings: ContactSettings,
    /// Outer radius of the wire, m.
    pub wire_radius: f64,
    /// The frame members that touch a ground besides the wire: (the
    /// ground's index among the rods, the member's beam), sorted. The wire
    /// touches every ground; a member only those listed here, by the same
    /// line law with its own outer radius.
    pub grounded_members: Vec<(usize, usize)>,
}

impl Contact {
    /// The contact of a wire of outer radius `wire_radius` (m) with `rods`.
    pub fn new(rods: Vec<Rod>, settings: ContactSettings, wire_radius: f64) -> Self {
        Contact {
            rods,
            members: Vec::new(),
            settings,
            wire_radius,
            grounded_members: Vec::new(),
        }
    }

    /// The same contact with the wire also touching `members`.
    pub fn with_members(self, members: Vec<MemberContact>) -> Self {
        Contact { members, ..self }
    }

    /// The same contact with frame members touching grounds: (the ground's
    /// index among the rods, the member's beam) pairs.
    pub fn with_grounded_members(self, mut pairs: Vec<(usize, usize)>) -> Self {
        pairs.sort_unstable();
        pairs.dedup();
        Contact {
            grounded_members: pairs,
            ..self
        }
    }

    /// Rods and members: the contact partners.
    pub fn partners(&self) -> usize {
        self.rods.len() + self.members.len()
    }

    /// How the scene names rigid partner `i` (an index into `rods`, where
    /// the grounds follow the rods): `rod[k]` or `ground[k]`.
    pub fn rigid_name(&self, i: usize) -> String {
        rigid_name(&self.rods, i)
    }

    /// Whether any rod or member has friction (then the Newton matrix is
    /// not symmetric).
    pub fn has_friction(&self) -> bool {
        self.rods.iter().any(|r| r.friction > 0.0) || self.members.iter().any(|m| m.friction > 0.0)
    }

    /// Whether any rod or member has contact damping (then the force
    /// depends on the velocities, the Newton matrix is not symmetric, and
    /// the state keeps each contact event's approach speed).
    pub fn has_damping(&self) -> bool {
        self.rods.iter().any(|r| r.damping.is_some())
            || self.members.iter().any(|m| m.damping.is_some())
    }

    /// Whether the contact force depends on the velocities.
    pub fn velocity_dependent(&self) -> bool {
        self.has_friction() || self.has_damping()
    }
}
