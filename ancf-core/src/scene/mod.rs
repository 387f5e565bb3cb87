//! Scene files (TOML): the public contract of what a simulation contains.
//! Parsing is strict (unknown keys are errors); validation names the field
//! at fault and runs before any work starts. Every key, its unit and its
//! default is documented in `docs/scene.md`.

use crate::element::ElementIntegration;
use crate::material::{Material, MaterialModel};
use crate::model::{Model, ModelError, PointLoad, Segment, Support, SupportKind};
use crate::section::Section;
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
    /// Dynamic: time step h (s).
    pub time_step: Option<f64>,
    /// Dynamic: generalized-α ρ∞.
    pub spectral_radius: Option<f64>,
    /// Static (and a static start): load increments.
    pub load_steps: Option<usize>,
    /// Dynamic: full or modified Newton.
    pub newton: Option<NewtonSpec>,
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
}

/// One concentric layer of `[wire] layers`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// Its material's name.
    pub material: String,
    /// Its outer radius (m).
    pub outer_radius: f64,
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
    /// Reference (unstretched) length (m).
    pub length: f64,
    /// Equal elements over the length (a uniform mesh); or `segments`.
    pub elements: Option<usize>,
    /// A graded mesh: regions from the first node on, each with its own
    /// element count; their lengths add up to `length`.
    pub segments: Option<Vec<SegmentSpec>>,
    /// Position of node 0 (m).
    pub origin: Option<[f64; 3]>,
    /// The wire's axis (normalised).
    pub direction: Option<[f64; 3]>,
    /// Concentric layers from the centre out.
    pub layers: Option<Vec<LayerSpec>>,
    /// A rectangular section instead of layers.
    pub rectangle: Option<RectangleSpec>,
    /// Quadrature orders.
    pub quadrature: Option<QuadratureSpec>,
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
    pub position: Option<[f64; 3]>,
    /// When it lets go (s); dynamic runs only.
    pub release_time: Option<f64>,
}

/// `[[load]]`: a constant force at a node.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// The node.
    pub node: NodeRef,
    /// The force (N).
    pub force: [f64; 3],
}

/// `[[rod]]`: a rigid cylinder the wire may touch.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// Its centre (m).
    pub center: [f64; 3],
    /// Its axis (normalised).
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
    /// Write PNG plots.
    pub plots: Option<bool>,
    /// Channel frequency class of the filtered rod forces (Hz).
    pub cfc: Option<f64>,
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
}

/// Defaults, documented in docs/scene.md.
pub mod defaults {
    /// Axial Gauss points (see [`crate::model::DEFAULT_AXIAL_ORDER`]).
    pub const AXIAL_ORDER: usize = crate::model::DEFAULT_AXIAL_ORDER;
    /// Ring-rule order (see [`crate::model::DEFAULT_SECTION_ORDER`]).
    pub const SECTION_ORDER: usize = crate::model::DEFAULT_SECTION_ORDER;
    /// ρ∞ = 0.9: damps the unresolved axial modes of a stiff wire a little;
    /// set 1 to conserve energy (the verification scenes do).
    pub const SPECTRAL_RADIUS: f64 = 0.9;
    /// Newton's relative residual tolerance.
    pub const TOLERANCE: f64 = 1e-10;
    /// Write every step.
    pub const OUTPUT_EVERY: usize = 1;
    /// The most time steps a scene may ask for (a run of this length takes days).
    pub const MAX_STEPS: f64 = 1e8;
    /// A checkpoint every 1000 steps: a few per typical run, negligible cost.
    pub const CHECKPOINT_EVERY: usize = 1000;
}

/// What a run does, after validation.
#[derive(Clone, Debug)]
pub enum Analysis {
    /// A static equilibrium.
    Static {
        /// Load increments.
        load_steps: usize,
        /// Newton's relative residual tolerance.
        tolerance: f64,
        /// Newton iterations per increment.
        max_iterations: usize,
    },
    /// `initial_static`: start from the static equilibrium (supports at
    /// their positions, release times ignored) at rest, solved in
    /// `load_steps` increments.
    Dynamic {
        /// The integrator's settings.
        settings: crate::solve::dynamics::DynamicSettings,
        /// Start from the static equilibrium.
        initial_static: bool,
        /// Its load increments.
        load_steps: usize,
    },
}

/// What a run writes.
#[derive(Clone, Debug)]
pub struct OutputSettings {
    /// Write every N-th step (≥ 1).
    pub every: usize,
    /// Write `checkpoint.json` every N steps (0: never). Default 1000.
    pub checkpoint_every: usize,
    /// Write ParaView files.
    pub vtk: bool,
    /// Write PNG plots.
    pub plots: bool,
    /// Channel frequency class of the filtered rod forces, Hz (SAE J211).
    pub cfc: f64,
}

/// A validated scene, ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The TOML text it was read from (kept in checkpoints; empty when built otherwise).
    pub source: String,
    /// The model to simulate.
    pub model: Model,
    /// How to run it.
    pub analysis: Analysis,
    /// What to write.
    pub output: OutputSettings,
}

/// A scene that cannot be run, with the field at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// Dotted path of the field, e.g. `material[1].poisson_ratio` (empty for syntax errors).
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.field, self.message)
        }
    }
}
impl std::error::Error for SceneError {}

fn err(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError {
        field: field.into(),
        message: message.into(),
    }
}

fn finite(field: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(field, format!("must be a finite number, got {v}")))
    }
}

fn positive(field: &str, v: f64) -> Result<f64, SceneError> {
    finite(field, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(err(field, format!("must be > 0, got {v}")))
    }
}

fn finite3(field: &str, v: [f64; 3]) -> Result<[f64; 3], SceneError> {
    for (i, x) in v.iter().enumerate() {
        finite(&format!("{field}[{i}]"), *x)?;
    }
    Ok(v)
}

impl SceneFile {
    /// Parse TOML text (syntax, types and unknown keys; no validation).
    pub fn from_toml(text: &str) -> Result<SceneFile, SceneError> {
        toml::from_str(text).map_err(|e| SceneError {
            field: String::new(),
            message: e.to_string().trim_end().to_string(),
        })
    }
}

impl Scene {
    /// Parse and validate a scene from TOML text.
    pub fn from_toml(text: &str) -> Result<Scene, SceneError> {
        let file = SceneFile::from_toml(text)?;
        let mut scene = Scene::from_file(&file)?;
        scene.source = text.to_string();
        Ok(scene)
    }

    /// The rods whose line-law contact `analysis.time_step` does not
    /// resolve ([`Model::unresolved_contacts`]); none for a static analysis.
    pub fn unresolved_contacts(&self) -> Vec<crate::model::contact::UnresolvedContact> {
        match &self.analysis {
            Analysis::Dynamic { settings, .. } => {
                self.model.unresolved_contacts(settings.time_step)
            }
            Analysis::Static { .. } => Vec::new(),
        }
    }

    /// The largest time step (s) that resolves every rod's line-law contact
    /// ([`crate::model::contact::UnresolvedContact::resolving_step`]), when
    /// `analysis.time_step` does not; `None` when it does.
    pub fn resolving_step(&self) -> Option<f64> {
        self.unresolved_contacts()
            .iter()
            .map(|u| u.resolving_step())
            .reduce(f64::min)
    }

    /// What a valid scene will likely do badly, said before it runs: each
    /// rod whose line-law contact the time step does not resolve, with the
    /// step that would.
    pub fn warnings(&self) -> Vec<String> {
        self.unresolved_contacts()
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    /// Read, parse and validate a scene file.
    pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| err("", format!("cannot read {}: {e}", path.display())))?;
        Scene::from_toml(&text).map_err(|mut e| {
            e.message = format!("{} (in {})", e.message, path.display());
            e
        })
    }

    /// Validate a parsed scene and build its model.
    pub fn from_file(f: &SceneFile) -> Result<Scene, SceneError> {
        let materials = validate_materials(&f.material)?;
        let find = |field: &str, name: &str| -> Result<Material, SceneError> {
            materials
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, m)| m.clone())
                .ok_or_else(|| {
                    let known: Vec<&str> = materials.iter().map(|(n, _)| n.as_str()).collect();
                    err(
                        field,
                        format!("unknown material \"{name}\" (defined: {known:?})"),
                    )
                })
        };

        let w = &f.wire;
        let length = positive("wire.length", w.length)?;
        let segments = mesh_segments(w, length)?;
        let n_elements: usize = segments.iter().map(|s| s.elements).sum();
        if n_elements > 1_000_000 {
            return Err(err(
                if w.segments.is_some() {
                    "wire.segments"
                } else {
                    "wire.elements"
                },
                format!("{n_elements} elements is more than this code is meant for (≤ 1e6)"),
            ));
        }
        let origin = finite3("wire.origin", w.origin.unwrap_or([0.0; 3]))?;
        let direction = finite3("wire.direction", w.direction.unwrap_or([1.0, 0.0, 0.0]))?;
        if direction.iter().all(|v| *v == 0.0) {
            return Err(err("wire.direction", "must not be the zero vector"));
        }
        let q = w.quadrature.clone().unwrap_or(QuadratureSpec {
            axial: None,
            section: None,
        });
        let axial = q.axial.unwrap_or(defaults::AXIAL_ORDER);
        let section_order = q.section.unwrap_or(defaults::SECTION_ORDER);
        if !(1..=16).contains(&axial) {
            return Err(err(
                "wire.quadrature.axial",
                format!("must be 1..=16, got {axial}"),
            ));
        }
        if !(1..=16).contains(&section_order) {
            return Err(err(
                "wire.quadrature.section",
                format!("must be 1..=16, got {section_order}"),
            ));
        }
        let (section, outer_material) = match (&w.layers, &w.rectangle) {
            (Some(_), Some(_)) => {
                return Err(err("wire", "give either `layers` or `rectangle`, not both"));
            }
            (None, None) => {
                return Err(err(
                    "wire.layers",
                    "missing: the cross section (layers or rectangle)",
                ));
            }
            (Some(layers), None) => {
                if layers.is_empty() {
                    return Err(err("wire.layers", "needs at least one layer"));
                }
                let mut inner = 0.0;
                let mut out = Vec::new();
                for (i, l) in layers.iter().enumerate() {
                    let field = format!("wire.layers[{i}].outer_radius");
                    let r = positive(&field, l.outer_radius)?;
                    if r <= inner {
                        return Err(err(
                            field,
                            format!(
                                "{r} m must exceed the layer's inner radius {inner} m (the previous outer radius)"
                            ),
                        ));
                    }
                    out.push((
                        inner,
                        r,
                        find(&format!("wire.layers[{i}].material"), &l.material)?,
                    ));
                    inner = r;
                }
                let outer = out.last().expect("at least one layer").2.clone();
                (Section::circular(&out, section_order), outer)
            }
            (None, Some(r)) => {
                let width = positive("wire.rectangle.width", r.width)?;
                let height = positive("wire.rectangle.height", r.height)?;
                let material = find("wire.rectangle.material", &r.material)?;
                (
                    Section::rectangular(width, height, material.clone(), section_order),
                    material,
                )
            }
        };
        let n_nodes = n_elements + 1;
        let node = |field: String, n: NodeRef| -> Result<usize, SceneError> {
            match n {
                NodeRef::Last => Ok(n_nodes - 1),
                NodeRef::Index(i) if i < n_nodes => Ok(i),
                NodeRef::Index(i) => Err(err(
                    field,
                    format!(
                        "node {i} does not exist (the wire has nodes 0..={}, or \"last\")",
                        n_nodes - 1
                    ),
                )),
            }
        };
        let mut supports = Vec::new();
        for (i, s) in f.support.iter().enumerate() {
            let kind = match s.kind {
                SupportKindSpec::Clamp => SupportKind::Clamp,
                SupportKindSpec::Fixed => SupportKind::Fixed,
                SupportKindSpec::Pin => SupportKind::Pin,
            };
            let position = match s.position {
                Some(p) => Some(finite3(&format!("support[{i}].position"), p)?),
                None => None,
            };
            let release_time = match s.release_time {
                Some(t) => {
                    let t = finite(&format!("support[{i}].release_time"), t)?;
                    if t < 0.0 {
                        return Err(err(
                            format!("support[{i}].release_time"),
                            format!("must be ≥ 0 s, got {t}"),
                        ));
                    }
                    Some(t)
                }
                None => None,
            };
            supports.push(Support {
                node: node(format!("support[{i}].node"), s.node)?,
                kind,
                position,
                release_time,
            });
        }
        let mut loads = Vec::new();
        for (i, l) in f.load.iter().enumerate() {
            let force = finite3(&format!("load[{i}].force"), l.force)?;
            loads.push(PointLoad {
                node: node(format!("load[{i}].node"), l.node)?,
                force,
            });
        }
        let gravity = match &f.gravity {
            Some(g) => Some(finite3("gravity.acceleration", g.acceleration)?),
            None => None,
        };

        let a = &f.analysis;
        let analysis = match a.kind {
            AnalysisKind::Static => {
                for (name, given) in [
                    ("end_time", a.end_time.is_some()),
                    ("time_step", a.time_step.is_some()),
                    ("spectral_radius", a.spectral_radius.is_some()),
                    ("newton", a.newton.is_some()),
                    ("initial", a.initial.is_some()),
                ] {
                    if given {
                        return Err(err(
                            format!("analysis.{name}"),
                            "only for kind = \"dynamic\"",
                        ));
                    }
                }
                let load_steps = a.load_steps.unwrap_or(1);
                if load_steps == 0 {
                    return Err(err("analysis.load_steps", "must be at least 1"));
                }
                Analysis::Static {
                    load_steps,
                    tolerance: tolerance(a)?,
                    max_iterations: a.max_iterations.unwrap_or(50).max(1),
                }
            }
            AnalysisKind::Dynamic => {
                let initial_static = a.initial == Some(InitialSpec::Static);
                if a.load_steps == Some(0) {
                    return Err(err("analysis.load_steps", "must be at least 1"));
                }
                if a.load_steps.is_some() && !initial_static {
                    return Err(err("analysis.load_steps", "only for kind = \"static\""));
                }
                let end_time = a.end_time.ok_or_else(|| {
                    err(
                        "analysis.end_time",
                        "missing (s), required for a dynamic run",
                    )
                })?;
                let end_time = positive("analysis.end_time", end_time)?;
                let h = a.time_step.ok_or_else(|| {
                    err(
                        "analysis.time_step",
                        "missing (s), required for a dynamic run",
                    )
                })?;
                let h = positive("analysis.time_step", h)?;
                if h > end_time {
                    return Err(err(
                        "analysis.time_step",
                        format!("{h} s is longer than end_time {end_time} s"),
                    ));
                }
                // A step so small that the run could never finish is a typo, not a plan.
                let steps = end_time / h;
                if steps > defaults::MAX_STEPS {
                    return Err(err(
                        "analysis.time_step",
                        format!(
                            "{h} s makes {steps:.3e} steps to end_time {end_time} s (more than {:.0e}); check the units",
                            defaults::MAX_STEPS
                        ),
                    ));
                }
                let rho = finite(
                    "analysis.spectral_radius",
                    a.spectral_radius.unwrap_or(defaults::SPECTRAL_RADIUS),
                )?;
                if !(0.0..=1.0).contains(&rho) {
                    return Err(err(
                        "analysis.spectral_radius",
                        format!("must be in [0, 1], got {rho}"),
                    ));
                }
                let settings = crate::solve::dynamics::DynamicSettings {
                    time_step: h,
                    end_time,
                    spectral_radius: rho,
                    newton: match a.newton.unwrap_or(NewtonSpec::Modified) {
                        NewtonSpec::Full => crate::solve::dynamics::NewtonKind::Full,
                        NewtonSpec::Modified => crate::solve::dynamics::NewtonKind::Modified,
                    },
                    tolerance: tolerance(a)?,
                    max_iterations: a.max_iterations.unwrap_or(25).max(1),
                    ..Default::default()
                };
                Analysis::Dynamic {
                    settings,
                    initial_static,
                    load_steps: a.load_steps.unwrap_or(1),
                }
            }
        };
        let output = match &f.output {
            Some(o) => {
                let every = o.every.unwrap_or(defaults::OUTPUT_EVERY);
                if every == 0 {
                    return Err(err("output.every", "must be at least 1"));
                }
                OutputSettings {
                    every,
                    checkpoint_every: o.checkpoint_every.unwrap_or(defaults::CHECKPOINT_EVERY),
                    vtk: o.vtk.unwrap_or(true),
                    plots: o.plots.unwrap_or(true),
                    cfc: positive(
                        "output.cfc",
                        o.cfc.unwrap_or(crate::loads::rod_load::DEFAULT_CFC),
                    )?,
                }
            }
            None => OutputSettings {
                every: defaults::OUTPUT_EVERY,
                checkpoint_every: defaults::CHECKPOINT_EVERY,
                vtk: true,
                plots: true,
                cfc: crate::loads::rod_load::DEFAULT_CFC,
            },
        };

        let longest = segments
            .iter()
            .map(|s| s.length / s.elements as f64)
            .fold(0.0, f64::max);
        let element = ElementIntegration::new(
            segments[0].length / segments[0].elements as f64,
            axial,
            section,
        );
        let wire_radius = element.section.outer_radius();
        let (rods, contact_settings) = validate_rods(
            &f.rod,
            f.contact.as_ref(),
            longest,
            wire_radius,
            &outer_material,
            &find,
        )?;
        let damping = validate_damping(f.damping.as_ref())?;
        if let Some(i) = supports.iter().position(|s| s.release_time.is_some())
            && a.kind == AnalysisKind::Static
        {
            return Err(err(
                format!("support[{i}].release_time"),
                "a release time needs kind = \"dynamic\"",
            ));
        }
        let model = if w.segments.is_some() {
            Model::graded(
                element, &segments, origin, direction, supports, gravity, loads,
            )
        } else {
            Model::new(
                element, n_elements, origin, direction, supports, gravity, loads,
            )
        }
        .map_err(|e| model_error(&e))?
        .with_rods(rods, contact_settings)
        .with_damping(damping);
        if model.n_unknowns == 0 {
            return Err(err(
                "support",
                "every coordinate is fixed: nothing to solve",
            ));
        }
        Ok(Scene {
            source: String::new(),
            model,
            analysis,
            output,
        })
    }
}

/// The mesh of `[wire]`: `elements` equal elements, or the `segments` of a
/// graded mesh (each checked, their lengths adding up to `length`).
fn mesh_segments(w: &WireSpec, length: f64) -> Result<Vec<Segment>, SceneError> {
    match (w.elements, &w.segments) {
        (Some(_), Some(_)) => Err(err(
            "wire.segments",
            "give either wire.elements (equal elements) or wire.segments (a graded mesh), not both",
        )),
        (None, None) => Err(err(
            "wire.elements",
            "missing: give the number of elements (or wire.segments for a graded mesh)",
        )),
        (Some(0), None) => Err(err("wire.elements", "must be at least 1")),
        (Some(n), None) => Ok(vec![Segment {
            length,
            elements: n,
        }]),
        (None, Some(list)) => {
            if list.is_empty() {
                return Err(err("wire.segments", "name at least one segment"));
            }
            let mut out = Vec::new();
            for (i, s) in list.iter().enumerate() {
                let l = positive(&format!("wire.segments[{i}].length"), s.length)?;
                if s.elements == 0 {
                    return Err(err(
                        format!("wire.segments[{i}].elements"),
                        "must be at least 1",
                    ));
                }
                out.push(Segment {
                    length: l,
                    elements: s.elements,
                });
            }
            let sum: f64 = out.iter().map(|s| s.length).sum();
            if (sum - length).abs() > 1e-9 * length {
                return Err(err(
                    "wire.segments",
                    format!(
                        "the segments' lengths add up to {sum} m, but wire.length is {length} m"
                    ),
                ));
            }
            Ok(out)
        }
    }
}

/// A model error as the scene file's field: the model names its parts
/// (segment 1, support 2), the scene knows where they are written.
fn model_error(e: &ModelError) -> SceneError {
    let (field, message) = match e {
        ModelError::Wire { what, message } => (format!("wire.{what}"), message.clone()),
        ModelError::Segment {
            index,
            what,
            message,
        } => (format!("wire.segments[{index}].{what}"), message.clone()),
        ModelError::Support {
            index,
            what,
            message,
        } => (format!("support[{index}].{what}"), message.clone()),
        ModelError::LoadNode { index, node } => (
            format!("load[{index}].node"),
            format!("node {node} does not exist"),
        ),
    };
    err(field, message)
}

fn tolerance(a: &AnalysisSpec) -> Result<f64, SceneError> {
    let t = positive(
        "analysis.tolerance",
        a.tolerance.unwrap_or(defaults::TOLERANCE),
    )?;
    if t >= 1.0 {
        return Err(err(
            "analysis.tolerance",
            format!("a relative tolerance must be < 1, got {t}"),
        ));
    }
    Ok(t)
}

fn validate_damping(
    spec: Option<&DampingSpec>,
) -> Result<Option<crate::model::damping::Damping>, SceneError> {
    let Some(d) = spec else { return Ok(None) };
    let reject = |pairs: &[(&str, bool)]| -> Result<(), SceneError> {
        for (k, given) in pairs {
            if *given {
                return Err(err(
                    format!("damping.{k}"),
                    format!("not a parameter of kind \"{}\"", d.kind),
                ));
            }
        }
        Ok(())
    };
    match d.kind.as_str() {
        "kelvin-voigt" => {
            reject(&[
                ("mass", d.mass.is_some()),
                ("stiffness", d.stiffness.is_some()),
            ])?;
            let c = d.strain_rate_coefficient.ok_or_else(|| {
                err(
                    "damping.strain_rate_coefficient",
                    "missing (s), required for kelvin-voigt",
                )
            })?;
            let c = positive("damping.strain_rate_coefficient", c)?;
            Ok(Some(crate::model::damping::Damping::KelvinVoigt {
                coefficient: c,
            }))
        }
        "rayleigh" => {
            reject(&[(
                "strain_rate_coefficient",
                d.strain_rate_coefficient.is_some(),
            )])?;
            let alpha = finite("damping.mass", d.mass.unwrap_or(0.0))?;
            let beta = finite("damping.stiffness", d.stiffness.unwrap_or(0.0))?;
            if alpha < 0.0 || beta < 0.0 || alpha + beta == 0.0 {
                return Err(err(
                    "damping.mass",
                    format!("need mass ≥ 0, stiffness ≥ 0, not both 0; got {alpha}, {beta}"),
                ));
            }
            Ok(Some(crate::model::damping::Damping::Rayleigh {
                mass: alpha,
                stiffness: beta,
            }))
        }
        other => Err(err(
            "damping.kind",
            format!("unknown kind \"{other}\" (use \"kelvin-voigt\" or \"rayleigh\")"),
        )),
    }
}

/// Largest distance (m) between consecutive contact stations along the
/// wire: Gauss nodes inside an element and across element ends.
pub fn station_spacing(stations: usize, element_length: f64) -> f64 {
    let x = crate::math::quadrature::gauss_legendre_unit(stations).nodes;
    let inner = x.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    inner.max(2.0 * x[0]) * element_length
}

fn validate_rods(
    specs: &[RodSpec],
    contact: Option<&ContactSpec>,
    element_length: f64,
    wire_radius: f64,
    wire_material: &Material,
    find: &dyn Fn(&str, &str) -> Result<Material, SceneError>,
) -> Result<
    (
        Vec<crate::model::contact::Rod>,
        crate::model::contact::ContactSettings,
    ),
    SceneError,
> {
    use crate::model::contact::{ContactDamping, ContactLaw, RestitutionModel};
    let mut rods = Vec::new();
    for (i, r) in specs.iter().enumerate() {
        let at = |k: &str| format!("rod[{i}].{k}");
        let center = finite3(&at("center"), r.center)?;
        let axis = finite3(&at("axis"), r.axis)?;
        let n = axis.iter().map(|v| v * v).sum::<f64>().sqrt();
        if n == 0.0 {
            return Err(err(at("axis"), "must not be the zero vector"));
        }
        let radius = positive(&at("radius"), r.radius)?;
        let length = match r.length {
            Some(l) => Some(positive(&at("length"), l)?),
            None => None,
        };
        let law = match r.contact_law.as_deref() {
            Some("line") => ContactLaw::Line,
            Some("hertz") => ContactLaw::Hertz,
            Some("surface") => ContactLaw::Surface,
            Some(other) => {
                return Err(err(
                    at("contact_law"),
                    format!("unknown law \"{other}\" (use \"line\", \"hertz\" or \"surface\")"),
                ));
            }
            // contact_stiffness was ε_N in N/m³ (surface test points) before
            // the line law became the default; its unit now depends on the
            // law, so a stiffness without a law is refused, not reinterpreted.
            None if r.contact_stiffness.is_some() => {
                return Err(err(
                    at("contact_law"),
                    "missing: contact_stiffness is in N/m² for contact_law = \"line\" (the default) and \
                     in N/m³ for \"surface\" (the paper's test points, the meaning in scenes written \
                     before the line law); name the law",
                ));
            }
            None => ContactLaw::Line,
        };
        // The rod's material: checked whenever named (a typo is an error
        // under every law), used by the hertz law.
        let rod_material = match &r.material {
            Some(name) => Some(find(&at("material"), name)?),
            None => None,
        };
        let contact_stiffness = match (law, r.contact_stiffness, rod_material) {
            (ContactLaw::Hertz, Some(_), _) => {
                return Err(err(
                    at("contact_stiffness"),
                    "not used by contact_law = \"hertz\" (the stiffness follows from the materials)",
                ));
            }
            (ContactLaw::Hertz, None, None) => {
                return Err(err(
                    at("material"),
                    "missing: contact_law = \"hertz\" needs the rod's material (E and ν)",
                ));
            }
            (ContactLaw::Hertz, None, Some(m)) => crate::model::contact::hertz_line_stiffness(
                m.model.elastic_constants(),
                wire_material.model.elastic_constants(),
                wire_radius,
                radius,
            ),
            (_, None, _) => {
                return Err(err(
                    at("contact_stiffness"),
                    format!(
                        "missing ({}), required for contact_law = \"{}\"",
                        law.stiffness_unit(),
                        law.name()
                    ),
                ));
            }
            (_, Some(k), _) => positive(&at("contact_stiffness"), k)?,
        };
        let friction = finite(&at("friction"), r.friction.unwrap_or(0.0))?;
        if friction < 0.0 {
            return Err(err(at("friction"), format!("must be ≥ 0, got {friction}")));
        }
        let model = r
            .restitution_model
            .as_deref()
            .map_or(Ok(RestitutionModel::Exact), RestitutionModel::from_name)
            .map_err(|message| err(at("restitution_model"), message))?;
        let damping = match r.restitution {
            None if r.restitution_model.is_some() => {
                return Err(err(
                    at("restitution"),
                    "missing: restitution_model is set but the coefficient of restitution is not",
                ));
            }
            None => None,
            Some(e) => {
                let e = finite(&at("restitution"), e)?;
                if !(e > 0.0 && e <= 1.0) {
                    return Err(err(
                        at("restitution"),
                        format!("must be in (0, 1] (1 = elastic, no damping), got {e}"),
                    ));
                }
                // e = 1 asks for no damping: none is built.
                (e < 1.0).then(|| ContactDamping::new(e, model))
            }
        };
        rods.push(crate::model::contact::Rod {
            center,
            axis: axis.map(|v| v / n),
            radius,
            length,
            law,
            contact_stiffness,
            friction,
            damping,
        });
    }
    let mut settings = crate::model::contact::ContactSettings::default();
    if let Some(c) = contact {
        if rods.is_empty() {
            return Err(err("contact", "contact settings without any [[rod]]"));
        }
        if let Some(s) = c.stations {
            if !(1..=64).contains(&s) {
                return Err(err("contact.stations", format!("must be 1..=64, got {s}")));
            }
            settings.stations = s;
        }
        if let Some(a) = c.angles {
            if !(3..=256).contains(&a) {
                return Err(err("contact.angles", format!("must be 3..=256, got {a}")));
            }
            settings.angles = a;
        }
        if let Some(z) = c.zone_points {
            if !(1..=32).contains(&z) {
                return Err(err(
                    "contact.zone_points",
                    format!("must be 1..=32, got {z}"),
                ));
            }
            settings.zone_points = z;
        }
        if let Some(m) = c.max_penetration {
            settings.max_penetration = positive("contact.max_penetration", m)?;
        }
        if let Some(v) = c.slip_velocity {
            settings.slip_velocity = positive("contact.slip_velocity", v)?;
        }
        if let Some(v) = c.min_impact_speed {
            settings.min_impact_speed = positive("contact.min_impact_speed", v)?;
        }
    }
    // A rod thinner than the gap between surface test stations can pass
    // between them (measured: 10 cm tubes slipped through 1 m elements with
    // 8 stations). Require at least two stations across a rod's diameter.
    // The line laws find their active zone and need no such rule.
    let spacing = station_spacing(settings.stations, element_length);
    if let Some((i, r)) = rods
        .iter()
        .enumerate()
        .find(|(_, r)| r.law == ContactLaw::Surface && spacing > r.radius)
    {
        let needed =
            (settings.stations..=64).find(|&n| station_spacing(n, element_length) <= r.radius);
        let advice = match needed {
            Some(n) => format!("use stations = {n} or more"),
            None => "use shorter elements (more wire.elements)".to_string(),
        };
        return Err(err(
            "contact.stations",
            format!(
                "test points {spacing:.3} m apart along the wire exceed rod[{i}].radius = {} m, so the rod \
                 could pass between them; {advice}",
                r.radius
            ),
        ));
    }
    Ok((rods, settings))
}

fn validate_materials(specs: &[MaterialSpec]) -> Result<Vec<(String, Material)>, SceneError> {
    let mut out: Vec<(String, Material)> = Vec::new();
    for (i, m) in specs.iter().enumerate() {
        let at = |k: &str| format!("material[{i}].{k}");
        if m.name.trim().is_empty() {
            return Err(err(at("name"), "must not be empty"));
        }
        if out.iter().any(|(n, _)| *n == m.name) {
            return Err(err(at("name"), format!("\"{}\" is defined twice", m.name)));
        }
        let density = positive(&at("density"), m.density)?;
        let locking = match m.locking.as_deref() {
            None | Some("centerline") => crate::material::Locking::Centerline,
            Some("none") => crate::material::Locking::None,
            Some(other) => {
                return Err(err(
                    at("locking"),
                    format!("unknown treatment \"{other}\" (use \"centerline\" or \"none\")"),
                ));
            }
        };
        let reject = |pairs: &[(&str, bool)], model: &str| -> Result<(), SceneError> {
            for (k, given) in pairs {
                if *given {
                    return Err(err(at(k), format!("not a parameter of model \"{model}\"")));
                }
            }
            Ok(())
        };
        let model = match m.model.as_str() {
            "st-venant-kirchhoff" => {
                reject(
                    &[
                        ("mu10", m.mu10.is_some()),
                        ("mu01", m.mu01.is_some()),
                        ("penalty", m.penalty.is_some()),
                    ],
                    &m.model,
                )?;
                let e = positive(
                    &at("youngs_modulus"),
                    m.youngs_modulus
                        .ok_or_else(|| err(at("youngs_modulus"), "missing (Pa)"))?,
                )?;
                let nu = finite(&at("poisson_ratio"), m.poisson_ratio.unwrap_or(0.0))?;
                if !(nu > -1.0 && nu < 0.5) {
                    return Err(err(
                        at("poisson_ratio"),
                        format!("must lie in (−1, 0.5), got {nu}"),
                    ));
                }
                let omega = finite(&at("bending_factor"), m.bending_factor.unwrap_or(1.0))?;
                if !(0.0..=1.0).contains(&omega) {
                    return Err(err(
                        at("bending_factor"),
                        format!("ω must lie in [0, 1], got {omega}"),
                    ));
                }
                MaterialModel::StVenantKirchhoff {
                    youngs_modulus: e,
                    poisson_ratio: nu,
                    bending_factor: omega,
                }
            }
            "mooney-rivlin" => {
                reject(
                    &[
                        ("youngs_modulus", m.youngs_modulus.is_some()),
                        ("poisson_ratio", m.poisson_ratio.is_some()),
                        ("bending_factor", m.bending_factor.is_some()),
                    ],
                    &m.model,
                )?;
                let mu10 = finite(
                    &at("mu10"),
                    m.mu10.ok_or_else(|| err(at("mu10"), "missing (Pa)"))?,
                )?;
                let mu01 = finite(
                    &at("mu01"),
                    m.mu01.ok_or_else(|| err(at("mu01"), "missing (Pa)"))?,
                )?;
                if mu10 < 0.0 || mu01 < 0.0 || mu10 + mu01 <= 0.0 {
                    return Err(err(
                        at("mu10"),
                        format!("need μ10 ≥ 0, μ01 ≥ 0 and μ10 + μ01 > 0, got {mu10}, {mu01}"),
                    ));
                }
                let penalty = positive(
                    &at("penalty"),
                    m.penalty
                        .ok_or_else(|| err(at("penalty"), "missing (κ, e.g. 1e3)"))?,
                )?;
                MaterialModel::MooneyRivlin {
                    mu10,
                    mu01,
                    penalty,
                }
            }
            other => {
                return Err(err(
                    at("model"),
                    format!(
                        "unknown model \"{other}\" (use \"st-venant-kirchhoff\" or \"mooney-rivlin\")"
                    ),
                ));
            }
        };
        out.push((
            m.name.clone(),
            Material {
                density,
                model,
                locking,
            },
        ));
    }
    Ok(out)
}
