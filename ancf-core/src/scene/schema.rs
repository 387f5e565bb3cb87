//! The scene file's schema: the TOML tables and keys as written, parsed
//! strictly (unknown keys are errors) with serde. No value is judged here;
//! `Scene::from_file` maps these onto the model builder and the settings.

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};

/// A node given as an index or as `"last"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeRef {
    /// Node index (0 … elements).
    Index(usize),
    /// The wire's last node.
    Last,
}

impl<'de> Deserialize<'de> for NodeRef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = NodeRef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a node index (0, 1, …) or \"last\"")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<NodeRef, E> {
                usize::try_from(v)
                    .map(NodeRef::Index)
                    .map_err(|_| E::custom(format!("node index {v} is negative")))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<NodeRef, E> {
                Ok(NodeRef::Index(v as usize))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<NodeRef, E> {
                if v == "last" {
                    Ok(NodeRef::Last)
                } else {
                    Err(E::custom(format!(
                        "unknown node \"{v}\" (use an index or \"last\")"
                    )))
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// `[analysis] time_step`: seconds, or `"auto"` (adaptive steps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeStepSpec {
    /// A fixed step (s).
    Fixed(f64),
    /// Steps chosen from a local error estimate.
    Auto,
}

impl<'de> Deserialize<'de> for TimeStepSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = TimeStepSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a time step in seconds or \"auto\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<TimeStepSpec, E> {
                Ok(TimeStepSpec::Fixed(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<TimeStepSpec, E> {
                Ok(TimeStepSpec::Fixed(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<TimeStepSpec, E> {
                Ok(TimeStepSpec::Fixed(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<TimeStepSpec, E> {
                if v == "auto" {
                    Ok(TimeStepSpec::Auto)
                } else {
                    Err(E::custom(format!(
                        "unknown time step \"{v}\" (use seconds or \"auto\")"
                    )))
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// `[analysis] kind`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum AnalysisKind {
    /// Static equilibrium (Newton, load steps).
    Static,
    /// Generalized-α time integration.
    Dynamic,
}

/// `[analysis] initial`: how a dynamic run starts.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum InitialSpec {
    /// The reference configuration (supports at their positions), at rest.
    Reference,
    /// The static equilibrium, at rest.
    Static,
}

/// `[damping]`: structural damping.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// `"kelvin-voigt"` or `"rayleigh"`.
    pub kind: String,
    /// Kelvin–Voigt c (s).
    pub strain_rate_coefficient: Option<f64>,
    /// Rayleigh mass factor (1/s).
    pub mass: Option<f64>,
    /// Rayleigh stiffness factor (s).
    pub stiffness: Option<f64>,
}

/// `[analysis] newton`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum NewtonSpec {
    /// A new Newton matrix every iteration.
    Full,
    /// The Newton matrix kept until convergence slows.
    Modified,
}

/// `[analysis]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// Static or dynamic.
    pub kind: AnalysisKind,
    /// Dynamic: the starting state (default: the reference).
    pub initial: Option<InitialSpec>,
    /// Dynamic: end time (s).
    pub end_time: Option<f64>,
    /// Dynamic: time step h (s), or `"auto"`.
    pub time_step: Option<TimeStepSpec>,
    /// Dynamic, adaptive: the position error (m) the run may accumulate.
    pub error_tolerance: Option<f64>,
    /// Dynamic, adaptive: the longest step (s).
    pub max_time_step: Option<f64>,
    /// Dynamic: generalized-α ρ∞.
    pub spectral_radius: Option<f64>,
    /// Static (and a static start): load increments.
    pub load_steps: Option<usize>,
    /// Dynamic: full or modified Newton.
    pub newton: Option<NewtonSpec>,
    /// Dynamic, modified Newton: Broyden's updates of the kept matrix.
    pub broyden: Option<bool>,
    /// Newton's relative residual tolerance.
    pub tolerance: Option<f64>,
    /// Newton iterations allowed per step or increment.
    pub max_iterations: Option<usize>,
}

/// `[gravity]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// g (m/s²).
    #[serde(deserialize_with = "vec3")]
    pub acceleration: [f64; 3],
}

/// `[[material]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Its name, as layers and rods refer to it.
    pub name: String,
    /// `"st-venant-kirchhoff"` or `"mooney-rivlin"`.
    pub model: String,
    /// ρ (kg/m³).
    pub density: f64,
    /// SVK: E (Pa).
    pub youngs_modulus: Option<f64>,
    /// SVK: ν.
    pub poisson_ratio: Option<f64>,
    /// SVK: ω, the weakened-bending coefficient.
    pub bending_factor: Option<f64>,
    /// The locking remedy: `"centerline"` or `"none"`.
    pub locking: Option<String>,
    /// Mooney–Rivlin: μ10 (Pa).
    pub mu10: Option<f64>,
    /// Mooney–Rivlin: μ01 (Pa).
    pub mu01: Option<f64>,
    /// Mooney–Rivlin: volume penalty κ.
    pub penalty: Option<f64>,
    /// SVK: the yield stress f_y (Pa), checked against (the law stays
    /// elastic); elastic–plastic: where it yields.
    pub yield_stress: Option<f64>,
    /// Elastic–plastic: the linear hardening modulus H (Pa).
    pub hardening_modulus: Option<f64>,
    /// Elastic–plastic: `"kinematic"` or `"isotropic"`.
    pub hardening: Option<String>,
    /// Elastic–plastic: the rate law.
    pub rate: Option<RateSpec>,
}

/// `[[material]] rate = { kind = "cowper-symonds", d, q }`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateSpec {
    /// `"cowper-symonds"`.
    pub kind: String,
    /// D (1/s).
    pub d: f64,
    /// q.
    pub q: f64,
}

/// One concentric layer of `[wire] layers`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// Its material's name.
    pub material: String,
    /// Its outer radius (m).
    pub outer_radius: f64,
    /// First layer only: its inner radius (m), a hollow section (a tube);
    /// absent, the first layer is solid.
    pub inner_radius: Option<f64>,
}

/// `[wire] rectangle`: a rectangular section.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RectangleSpec {
    /// Its material's name.
    pub material: String,
    /// Along y (m).
    pub width: f64,
    /// Along z (m).
    pub height: f64,
}

/// `[wire] quadrature`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadratureSpec {
    /// Gauss points along the element.
    pub axial: Option<usize>,
    /// Ring-rule order per layer.
    pub section: Option<usize>,
}

/// `[wire]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WireSpec {
    /// A `[[beam]]`'s name (unique, not "wire"); the wire has none.
    pub name: Option<String>,
    /// Reference (unstretched) length (m).
    pub length: f64,
    /// Equal elements over the length (a uniform mesh); or `segments`.
    pub elements: Option<usize>,
    /// A graded mesh: regions from the first node on, each with its own
    /// element count; their lengths add up to `length`.
    pub segments: Option<Vec<SegmentSpec>>,
    /// Position of node 0 (m).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub origin: Option<[f64; 3]>,
    /// The wire's axis (normalised).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub direction: Option<[f64; 3]>,
    /// Concentric layers from the centre out.
    pub layers: Option<Vec<LayerSpec>>,
    /// A rectangular section instead of layers.
    pub rectangle: Option<RectangleSpec>,
    /// Quadrature orders.
    pub quadrature: Option<QuadratureSpec>,
    /// A `[[beam]]`'s contact with the wire: `"hertz"` (default, from the
    /// two outer materials) or `"line"`.
    pub contact_law: Option<String>,
    /// A `[[beam]]`'s ε_L under the line law (N/m²).
    pub contact_stiffness: Option<f64>,
    /// A `[[beam]]`'s Coulomb μ against the wire.
    pub friction: Option<f64>,
    /// A `[[beam]]`'s coefficient of restitution e ∈ (0, 1] against the wire.
    pub restitution: Option<f64>,
    /// How the damping follows from `restitution` (as for rods).
    pub restitution_model: Option<String>,
    /// This beam's own structural damping, in place of `[damping]`'s.
    pub damping: Option<DampingSpec>,
}

/// One region of a graded mesh (`[wire] segments`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Reference length of the region, m.
    pub length: f64,
    /// Equal elements in it.
    pub elements: usize,
}

/// `[[support]] kind`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SupportKindSpec {
    /// r, r_y, r_z and the normal part of r_x held.
    Clamp,
    /// All 12 coordinates held.
    Fixed,
    /// r held (a spherical joint).
    Pin,
    /// r and r_y held (turns about the section's y direction only).
    Hinge,
    /// Springs and a dashpot to fixed ground.
    Spring,
}

/// `[[support]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// The node held.
    pub node: NodeRef,
    /// How it is held.
    pub kind: SupportKindSpec,
    /// Where it is held (m); default its reference position.
    #[serde(default, deserialize_with = "optional_vec3")]
    pub position: Option<[f64; 3]>,
    /// When it lets go (s); dynamic runs only.
    pub release_time: Option<f64>,
    /// The `[[beam]]` it holds, by name (absent: the wire).
    pub beam: Option<String>,
    /// `kind = "spring"`: translational stiffness along x, y, z (N/m).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub stiffness: Option<[f64; 3]>,
    /// `kind = "spring"`: rotational stiffness of the tangent, bending
    /// (N m/rad); default 0.
    pub rotational_stiffness: Option<f64>,
    /// `kind = "spring"`: torsional stiffness about the axis (N m/rad);
    /// default 0.
    pub torsional_stiffness: Option<f64>,
    /// `kind = "spring"`: dashpot on the position (N s/m); default 0.
    pub damping: Option<f64>,
}

/// `[[load]]`: a constant force at a node.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// The node.
    pub node: NodeRef,
    /// The `[[beam]]` it loads, by name (absent: the wire).
    pub beam: Option<String>,
    /// The force (N).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub force: Option<[f64; 3]>,
    /// The moment (N m), of fixed direction in space for any rotation of
    /// the node (`crate::forces::moment`).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub moment: Option<[f64; 3]>,
    /// Whether the moment turns with the node (default: fixed in space).
    #[serde(default)]
    pub follower: bool,
}

/// `[[rod]]`: a rigid cylinder the wire may touch.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// Its centre (m).
    #[serde(deserialize_with = "vec3")]
    pub center: [f64; 3],
    /// Its axis (normalised).
    #[serde(deserialize_with = "vec3")]
    pub axis: [f64; 3],
    /// Its radius (m).
    pub radius: f64,
    /// Its length (m); absent: infinite.
    pub length: Option<f64>,
    /// `"line"`, `"hertz"` or `"surface"`.
    pub contact_law: Option<String>,
    /// Penalty: ε_L (N/m², line) or ε_N (N/m³, surface).
    pub contact_stiffness: Option<f64>,
    /// Its material's name (required by hertz).
    pub material: Option<String>,
    /// Coulomb μ.
    pub friction: Option<f64>,
    /// Coefficient of restitution e ∈ (0, 1): contact damping (absent: none).
    pub restitution: Option<f64>,
    /// `"exact"` (default), `"flores"` or `"lankarani-nikravesh"`: how the
    /// damping follows from `restitution`.
    pub restitution_model: Option<String>,
}

/// `[contact]`: integration and regularization.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The largest penetration tolerated before a step is cut (m).
    pub max_penetration: Option<f64>,
    /// Surface law: Gauss stations per element.
    pub stations: Option<usize>,
    /// Surface law: angles around the wire.
    pub angles: Option<usize>,
    /// Line laws: Gauss points per active zone.
    pub zone_points: Option<usize>,
    /// Friction regularization velocity (m/s).
    pub slip_velocity: Option<f64>,
    /// Contact damping: the smallest approach speed its factor uses (m/s).
    pub min_impact_speed: Option<f64>,
}

/// `[output]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write every N-th step.
    pub every: Option<usize>,
    /// Checkpoint every N steps (0: never).
    pub checkpoint_every: Option<usize>,
    /// Write ParaView files.
    pub vtk: Option<bool>,
    /// A ParaView frame every N steps.
    pub vtk_every: Option<usize>,
    /// Write PNG plots.
    pub plots: Option<bool>,
    /// Channel frequency class of the filtered rod forces (Hz).
    pub cfc: Option<f64>,
    /// Frequencies of the oscillators the supports' forces drive (Hz).
    pub response_frequencies: Option<Vec<f64>>,
    /// Their damping ratio.
    pub response_damping: Option<f64>,
}

/// The scene file as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// `[analysis]`.
    pub analysis: AnalysisSpec,
    /// `[gravity]`.
    pub gravity: Option<GravitySpec>,
    #[serde(default)]
    /// `[[material]]`.
    pub material: Vec<MaterialSpec>,
    /// `[wire]`.
    pub wire: WireSpec,
    #[serde(default)]
    /// `[[beam]]`: frame members, each with the keys of `[wire]` and a name.
    pub beam: Vec<WireSpec>,
    #[serde(default)]
    /// `[[support]]`.
    pub support: Vec<SupportSpec>,
    #[serde(default)]
    /// `[[load]]`.
    pub load: Vec<LoadSpec>,
    #[serde(default)]
    /// `[[rod]]`.
    pub rod: Vec<RodSpec>,
    /// `[contact]`.
    pub contact: Option<ContactSpec>,
    /// `[damping]`.
    pub damping: Option<DampingSpec>,
    /// `[output]`.
    pub output: Option<OutputSpec>,
    #[serde(default)]
    /// `[[clearance]]`.
    pub clearance: Vec<ClearanceSpec>,
    #[serde(default)]
    /// `[[ground]]`.
    pub ground: Vec<GroundSpec>,
}

/// `[[ground]]`: a plane the wire touches and does not pass.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    /// A point of the plane (m).
    #[serde(deserialize_with = "vec3")]
    pub point: [f64; 3],
    /// Its normal, towards the side the wire belongs on (normalised).
    #[serde(deserialize_with = "vec3")]
    pub normal: [f64; 3],
    /// ε_L (N/m²), the line law's.
    pub contact_stiffness: f64,
    /// Coulomb μ.
    pub friction: Option<f64>,
    /// Coefficient of restitution e ∈ (0, 1]: contact damping (absent: none).
    pub restitution: Option<f64>,
    /// How the damping follows from `restitution` (as for rods).
    pub restitution_model: Option<String>,
    /// The beams that touch it (default: the wire only).
    pub beams: Option<Vec<String>>,
}

/// `[[clearance]] kind`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ClearanceKindSpec {
    /// An axis-aligned box: `min`, `max`.
    Box,
    /// A half-space: `point`, `normal` (out of the zone).
    HalfSpace,
    /// The half-space under a `[[ground]]`: `ground`, its index.
    Ground,
}

/// `[[clearance]]`: a region the wire must stay out of.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClearanceSpec {
    /// Which shape.
    pub kind: ClearanceKindSpec,
    /// Box: the corner of least x, y, z (m).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub min: Option<[f64; 3]>,
    /// Box: the corner of largest x, y, z (m).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub max: Option<[f64; 3]>,
    /// Half-space: a point of its plane (m).
    #[serde(default, deserialize_with = "optional_vec3")]
    pub point: Option<[f64; 3]>,
    /// Half-space: the plane's normal, out of the zone.
    #[serde(default, deserialize_with = "optional_vec3")]
    pub normal: Option<[f64; 3]>,
    /// Ground: the `[[ground]]`'s index (0, 1, …).
    pub ground: Option<usize>,
}

/// A vector of exactly three numbers: a longer array is refused, not cut
/// (`[0, 0, -1, 12345]` is no force), a shorter one too.
fn vec3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    let v: Vec<f64> = Vec::deserialize(d)?;
    <[f64; 3]>::try_from(v.as_slice())
        .map_err(|_| de::Error::invalid_length(v.len(), &"exactly 3 numbers"))
}

/// [`vec3`], when given.
fn optional_vec3<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    vec3(d).map(Some)
}
