//! Scene files (TOML): the public contract of what a simulation contains.
//! Parsing is strict (unknown keys are errors, schema.rs); the values are
//! then handed to the model builder and the solver settings, whose checks
//! are the only copy of each rule and each default, and an error they
//! return is mapped back to the file's field (`rod[0].contact_stiffness`).
//! Every key, its unit and its default is documented in `docs/scene.md`.

pub mod keys;
mod schema;
pub use schema::*;

use crate::check::ParameterError;
use crate::material::{Material, MaterialModel};
use crate::model::clearance::ClearanceZone;
use crate::model::contact::{BeamContact, ContactDamping, ContactLaw, ContactSettings, Rod};
use crate::model::damping::Damping;
use crate::model::spring::Spring;
use crate::model::{
    BeamBuilder, Model, ModelError, PointLoad, Segment, Support, SupportKind, WireBuilder,
};
use crate::solve::dynamics::{DynamicSettings, NewtonKind, StepControl};
use crate::solve::statics::StaticSettings;

/// The scene file's own defaults (those of the model and the solvers live
/// with them: `model::DEFAULT_AXIAL_ORDER`, `DynamicSettings::default`, …),
/// documented in docs/scene.md.
pub mod defaults {
    /// Write every step.
    pub const OUTPUT_EVERY: usize = 1;
    /// A checkpoint every 1000 steps: a few per typical run, negligible cost.
    pub const CHECKPOINT_EVERY: usize = 1000;
    /// The most elements a beam may have ([`crate::model::MAX_ELEMENTS`]).
    pub const MAX_ELEMENTS: usize = crate::model::MAX_ELEMENTS;
    /// The damping ratio of the supports' response oscillators: 2 %, a
    /// bolted steel structure's usual design value.
    pub const RESPONSE_DAMPING: f64 = 0.02;
}

/// The largest scene file read: 16 MB, far above any scene (the span
/// break's is 5 kB; a 10⁵-node support list would be a few MB).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The text of the scene file at `path`: refused unread past
/// [`MAX_SCENE_BYTES`] (a scene is a few kB; `/dev/zero` would fill the
/// memory), and when it is not UTF-8.
pub fn read_scene_text(path: &std::path::Path) -> Result<String, SceneError> {
    use std::io::Read as _;
    let cannot = |e: std::io::Error| err("", format!("cannot read {}: {e}", path.display()));
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(cannot)?
        .take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(err(
            "",
            format!(
                "{} is larger than a scene file may be ({} MB)",
                path.display(),
                MAX_SCENE_BYTES >> 20
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|_| {
        err(
            "",
            format!("{} is not UTF-8 text: no scene file", path.display()),
        )
    })
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
    /// A ParaView frame every N steps (a multiple of `every`); `None`: at
    /// most [`VTK_FRAMES`] frames over the run ([`Self::vtk_interval`]).
    pub vtk_every: Option<usize>,
    /// Write PNG plots.
    pub plots: bool,
    /// Channel frequency class of the filtered rod forces, Hz (SAE J211).
    pub cfc: f64,
    /// Frequencies (Hz) of the oscillators each support's force drives
    /// ([`crate::loads::response`]); empty: none is computed.
    pub response_frequencies: Vec<f64>,
    /// Their damping ratio ζ.
    pub response_damping: f64,
}

/// The ParaView frames a run writes unless `output.vtk_every` says
/// otherwise: enough to watch the motion, a few tens of MB on the shipped
/// scenes (a frame of the 64-element impact is 0.43 MB).
pub const VTK_FRAMES: usize = 50;

impl OutputSettings {
    /// Steps between ParaView frames in a run of `steps` steps:
    /// `vtk_every`, else the smallest multiple of `every` that writes at
    /// most [`VTK_FRAMES`] frames (the first and last state are written
    /// too).
    pub fn vtk_interval(&self, steps: usize) -> usize {
        self.vtk_every.unwrap_or_else(|| {
            let rows = steps.div_ceil(self.every);
            self.every * rows.div_ceil(VTK_FRAMES).max(1)
        })
    }

    /// An adaptive run's ParaView frames: one each time the run passes a
    /// multiple of this period (s), `end_time` / [`VTK_FRAMES`], since its
    /// step count is not known ahead (the first and last state are written
    /// too). `None` for fixed steps, or when `vtk_every` asks for frames
    /// by steps.
    pub fn vtk_period(&self, adaptive: bool, end_time: f64) -> Option<f64> {
        (adaptive && self.vtk_every.is_none()).then(|| end_time / VTK_FRAMES as f64)
    }
}

impl Default for OutputSettings {
    /// Every step written, a checkpoint every 1000 steps, ParaView files and
    /// plots, CFC 60 rod loads.
    fn default() -> Self {
        OutputSettings {
            every: defaults::OUTPUT_EVERY,
            checkpoint_every: defaults::CHECKPOINT_EVERY,
            vtk: true,
            vtk_every: None,
            plots: true,
            cfc: crate::loads::rod_load::DEFAULT_CFC,
            response_frequencies: Vec::new(),
            response_damping: defaults::RESPONSE_DAMPING,
        }
    }
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
    /// Regions the wire must stay out of (`[[clearance]]`): a run reports
    /// how close it came to each.
    pub clearance: Vec<ClearanceZone>,
    /// Constants outside the ranges of real materials, by field
    /// ([`crate::plausibility::material_warnings`]).
    pub implausible: Vec<String>,
}

/// A scene that cannot be run, with the field at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// Dotted path of the field, e.g. `material[1].poisson_ratio`; for an
    /// error of TOML syntax or type, the key or table on its line (empty
    /// when there is none).
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

impl SceneFile {
    /// Parse TOML text (syntax, types and unknown keys; no validation).
    pub fn from_toml(text: &str) -> Result<SceneFile, SceneError> {
        toml::from_str(text).map_err(|e| {
            let field = error_field(text, &e);
            let mut message = e.to_string().trim_end().to_string();
            if let Some(words) = whole_number_error(&field, e.message()) {
                message = message.replace(e.message().trim_end(), &words);
            }
            SceneError { field, message }
        })
    }
}

/// A count or index that is not a whole number ≥ 0, in the user's words
/// instead of the parser's ("invalid value: integer `-4`, expected
/// usize"): what the key `field` accepts (its declared range) and what was
/// given. `None` for any other parse error.
fn whole_number_error(field: &str, message: &str) -> Option<String> {
    let unsigned = ["usize", "u64", "u32", "u16", "u8"];
    let expected = message.rsplit("expected ").next()?.trim();
    if !unsigned.contains(&expected) {
        return None;
    }
    let got = message.split('`').nth(1)?;
    let (table, name) = field.rsplit_once('.')?;
    let table: String = (table.split('.'))
        .map(|part| part.split('[').next().unwrap_or(part))
        .collect::<Vec<_>>()
        .join(".");
    let accepted = match keys::find(&table, name).map(|k| k.range) {
        Some(keys::Range::Count { min, max }) if max < u64::MAX => {
            format!("a whole number from {min} to {max}")
        }
        Some(keys::Range::Count { min, .. }) => format!("a whole number ≥ {min}"),
        _ => "a whole number ≥ 0".to_string(),
    };
    Some(format!("must be {accepted}, got {got}"))
}

/// The key a "missing field `key`" parse error names.
fn missing_field(message: &str) -> Option<&str> {
    message
        .strip_prefix("missing field `")?
        .split('`')
        .next()
        .filter(|key| !key.is_empty())
}

/// The dotted field a TOML parse error of `text` is about (empty when the
/// error has no place). A missing key is reported at the table that lacks
/// it (an empty span at the start: the file itself), so its name is joined
/// to that table's.
pub fn error_field(text: &str, e: &toml::de::Error) -> String {
    let Some(span) = e.span() else {
        return String::new();
    };
    let at = field_at(text, span.start);
    match missing_field(e.message()) {
        Some(key) if span.is_empty() && span.start == 0 => key.to_string(),
        Some(key) if !at.is_empty() => format!("{at}.{key}"),
        Some(key) => key.to_string(),
        None => at,
    }
}

/// The dotted field (`wire.elements`, `rod[1].center`, or the table
/// `rod[1]` itself) at byte `at` of the TOML `text`: the table header last
/// opened before it, and the key on its line.
pub fn field_at(text: &str, at: usize) -> String {
    let upto = &text[..at.min(text.len())];
    let line_start = upto.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[line_start..]
        .find('\n')
        .map_or(text.len(), |i| line_start + i);
    let mut table = String::new();
    let mut counts: Vec<(String, usize)> = Vec::new();
    for line in text[..line_end].lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            let name = name.trim().to_string();
            let n = match counts.iter_mut().find(|(k, _)| *k == name) {
                Some((_, n)) => {
                    *n += 1;
                    *n
                }
                None => {
                    counts.push((name.clone(), 0));
                    0
                }
            };
            table = format!("{name}[{n}]");
        } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.split(']').next()) {
            table = name.trim().to_string();
        }
    }
    let line = text[line_start..line_end].trim();
    let key = (!line.starts_with('['))
        .then(|| line.split('=').next().map(str::trim))
        .flatten()
        .filter(|k| {
            let bare = |c: char| c.is_ascii_alphanumeric() || "_-.\"".contains(c);
            !k.is_empty() && k.chars().all(bare) && line.contains('=')
        });
    match key {
        Some(k) if table.is_empty() => k.to_string(),
        Some(k) => format!("{table}.{k}"),
        None => table,
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

    /// Whether a dynamic run starts from the static equilibrium
    /// (`initial = "static"`), where the supports' forces at t = 0 are
    /// static loads to compare peaks with.
    pub fn starts_from_equilibrium(&self) -> bool {
        matches!(
            self.analysis,
            Analysis::Dynamic {
                initial_static: true,
                ..
            }
        )
    }

    /// The rods whose line-law contact `analysis.time_step` does not
    /// resolve ([`Model::unresolved_contacts`]); none for a static analysis
    /// or adaptive steps (which stay below the limit near a rod).
    pub fn unresolved_contacts(&self) -> Vec<crate::model::contact::UnresolvedContact> {
        match &self.analysis {
            Analysis::Dynamic { settings, .. } if settings.step_control.is_none() => {
                self.model.unresolved_contacts(settings.time_step)
            }
            Analysis::Dynamic { .. } | Analysis::Static { .. } => Vec::new(),
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

    /// What a valid scene will likely do badly, said before it runs:
    /// material constants outside the ranges of real materials, and each
    /// contact the time step does not resolve, with the step that would.
    pub fn warnings(&self) -> Vec<String> {
        let unresolved = self.unresolved_contacts();
        (self.implausible.iter().cloned())
            .chain(unresolved.iter().map(ToString::to_string))
            .collect()
    }

    /// Read, parse and validate a scene file.
    /// A file larger than [`MAX_SCENE_BYTES`] is refused unread
    /// ([`read_scene_text`]).
    pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
        let text = read_scene_text(path)?;
        Scene::from_toml(&text).map_err(|mut e| {
            e.message = format!("{} (in {})", e.message, path.display());
            e
        })
    }

    /// Validate a parsed scene and build its model: the file's own rules
    /// (which keys go together, names of materials and laws, nodes given as
    /// `"last"`) are checked here, every value by the model builder and the
    /// solver settings; errors name the file's field.
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

        let (wire, layer_materials, outer_material, n_elements) =
            beam_description(&f.wire, "wire", crate::model::WIRE, &find)?;
        let mut builder = WireBuilder::from_beam(wire);
        // Frame members: their descriptions, and each one's node count by name.
        let mut beam_nodes = vec![(crate::model::WIRE.to_string(), n_elements + 1)];
        if f.wire.name.is_some() {
            return Err(err(
                "wire.name",
                "the wire is named \"wire\"; names are for [[beam]] tables",
            ));
        }
        for (key, given) in [
            ("contact_law", f.wire.contact_law.is_some()),
            ("contact_stiffness", f.wire.contact_stiffness.is_some()),
            ("friction", f.wire.friction.is_some()),
            ("restitution", f.wire.restitution.is_some()),
            ("restitution_model", f.wire.restitution_model.is_some()),
        ] {
            if given {
                return Err(err(
                    format!("wire.{key}"),
                    "a contact key of a [[beam]] (how the wire touches that member) or a [[rod]]",
                ));
            }
        }
        let mut dampings: Vec<(String, Damping)> = Vec::new();
        for (i, b) in f.beam.iter().enumerate() {
            let table = format!("beam[{i}]");
            let Some(name) = &b.name else {
                return Err(err(
                    format!("{table}.name"),
                    "missing: a member needs a name",
                ));
            };
            crate::model::beam::check_member_name(name)
                .map_err(|message| err(format!("{table}.name"), message))?;
            if beam_nodes.iter().any(|(n, _)| n == name) {
                return Err(err(
                    format!("{table}.name"),
                    format!("\"{name}\" names two members: names are unique"),
                ));
            }
            let (member, _, _, elements) = beam_description(b, &table, name, &find)?;
            builder = builder.member(member.contact(beam_contact(b, &table)?));
            let field = format!("{table}.damping");
            if let Some(d) = damping(b.damping.as_ref(), &field)? {
                builder = builder.damping_on(name, d.clone());
                dampings.push((field, d));
            }
            beam_nodes.push((name.clone(), elements + 1));
        }
        // A node of the wire or of the member named `beam`: its index on that beam.
        let node =
            |table: String, beam: &Option<String>, n: NodeRef| -> Result<usize, SceneError> {
                let name = beam.as_deref().unwrap_or(crate::model::WIRE);
                let Some((_, n_nodes)) = beam_nodes.iter().find(|(b, _)| b == name) else {
                    let known: Vec<&str> = beam_nodes.iter().map(|(b, _)| b.as_str()).collect();
                    return Err(err(
                        format!("{table}.beam"),
                        format!("unknown beam \"{name}\" (defined: {known:?})"),
                    ));
                };
                let whose = if beam.is_none() {
                    "the wire".to_string()
                } else {
                    format!("beam \"{name}\"")
                };
                match n {
                    NodeRef::Last => Ok(n_nodes - 1),
                    NodeRef::Index(i) if i < *n_nodes => Ok(i),
                    NodeRef::Index(i) => Err(err(
                        format!("{table}.node"),
                        format!(
                            "node {i} does not exist ({whose} has nodes 0..={}, or \"last\")",
                            n_nodes - 1
                        ),
                    )),
                }
            };
        for (i, s) in f.support.iter().enumerate() {
            let kind = match s.kind {
                SupportKindSpec::Clamp => SupportKind::Clamp,
                SupportKindSpec::Fixed => SupportKind::Fixed,
                SupportKindSpec::Pin => SupportKind::Pin,
                SupportKindSpec::Hinge => SupportKind::Hinge,
                SupportKindSpec::Spring => SupportKind::Spring(Spring {
                    stiffness: s.stiffness.ok_or_else(|| {
                        err(
                            format!("support[{i}].stiffness"),
                            "missing: a spring support needs stiffness = [kx, ky, kz] (N/m)",
                        )
                    })?,
                    rotational_stiffness: s.rotational_stiffness.unwrap_or(0.0),
                    torsional_stiffness: s.torsional_stiffness.unwrap_or(0.0),
                    damping: s.damping.unwrap_or(0.0),
                }),
            };
            if s.kind != SupportKindSpec::Spring {
                let given = [
                    ("stiffness", s.stiffness.is_some()),
                    ("rotational_stiffness", s.rotational_stiffness.is_some()),
                    ("torsional_stiffness", s.torsional_stiffness.is_some()),
                    ("damping", s.damping.is_some()),
                ];
                if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
                    return Err(err(
                        format!("support[{i}].{key}"),
                        format!(
                            "only a kind = \"spring\" support has it (this one is \"{}\")",
                            kind.name()
                        ),
                    ));
                }
            }
            if s.release_time.is_some() && f.analysis.kind == AnalysisKind::Static {
                return Err(err(
                    format!("support[{i}].release_time"),
                    "a release time needs kind = \"dynamic\"",
                ));
            }
            let support = Support {
                node: node(format!("support[{i}]"), &s.beam, s.node)?,
                kind,
                position: s.position,
                release_time: s.release_time,
            };
            builder = match &s.beam {
                Some(beam) => builder.support_on(beam, support),
                None => builder.support_with(support),
            };
        }
        for (i, l) in f.load.iter().enumerate() {
            if l.force.is_none() && l.moment.is_none() {
                return Err(err(
                    format!("load[{i}].force"),
                    "missing: give a force (N), a moment (N m) or both",
                ));
            }
            if l.follower && l.moment.is_none() {
                return Err(err(
                    format!("load[{i}].follower"),
                    "a follower needs a moment (N m) to turn with the node",
                ));
            }
            let load = PointLoad {
                node: node(format!("load[{i}]"), &l.beam, l.node)?,
                force: l.force.unwrap_or_default(),
                moment: l.moment.unwrap_or_default(),
                follower: l.follower,
            };
            builder = match &l.beam {
                Some(beam) => builder.load_on(beam, load),
                None => builder.load_with(load),
            };
        }
        if let Some(g) = &f.gravity {
            builder = builder.gravity(g.acceleration);
        }
        if f.contact.is_some() && f.rod.is_empty() && f.beam.is_empty() && f.ground.is_empty() {
            return Err(err(
                "contact",
                "contact settings without any [[rod]] or [[beam]] to touch",
            ));
        }
        let w = &f.wire;
        let wire_radius = match &w.rectangle {
            Some(r) => crate::section::rectangle_outer_radius(r.width, r.height),
            None => w
                .layers
                .as_ref()
                .and_then(|l| l.last())
                .map_or(0.0, |l| l.outer_radius),
        };
        for rod in rods(&f.rod, wire_radius, &outer_material, &find)? {
            builder = builder.rod(rod);
        }
        for (ground, beams) in grounds(&f.ground)? {
            builder = match beams {
                Some(beams) => builder.ground_touching(ground, &beams),
                None => builder.ground(ground),
            };
        }
        builder = builder.contact_settings(contact_settings(f.contact.as_ref()));
        if let Some(d) = damping(f.damping.as_ref(), "damping")? {
            builder = builder.damping(d.clone());
            dampings.push(("damping".into(), d));
        }
        if let Some(d) = damping(f.wire.damping.as_ref(), "wire.damping")? {
            builder = builder.damping_on(crate::model::WIRE, d.clone());
            dampings.push(("wire.damping".into(), d));
        }
        let analysis = analysis(&f.analysis)?;
        let output = output(f.output.as_ref())?;
        let cfc_given = f.output.as_ref().is_some_and(|o| o.cfc.is_some());
        output_resolved(&output, &analysis, cfc_given)?;
        let model = builder
            .build()
            .map_err(|e| model_error(&e, &layer_materials, &f.material))?;
        let solves_statics = match analysis {
            Analysis::Static { .. } => true,
            Analysis::Dynamic { initial_static, .. } => initial_static,
        };
        if solves_statics && let Some(message) = model.static_holding_error() {
            return Err(err("support", message));
        }
        // A static solve pushes the wire out of a shallow overlap; a run
        // from the starting shape would begin with the whole overlap as its
        // force, and a rod through the wire's centerline has no side to
        // push it to in either.
        let wire_radius = model.contact().map_or(0.0, |c| c.wire_radius);
        let overlap = (model.rod_overlap_at_start())
            .filter(|&(_, depth, _)| !solves_statics || depth > wire_radius);
        if let Some((i, depth, p)) = overlap {
            let (name, what, key) = match model.contact() {
                Some(c) if c.rods[i].is_ground() => (c.rigid_name(i), "ground", "point"),
                _ => (format!("rod[{i}]"), "rod", "center"),
            };
            return Err(err(
                format!("{name}.{key}"),
                format!(
                    "the {what} overlaps the wire where the run starts: the wire's surface is {:.2} mm \
                     inside it near [{:.3}, {:.3}, {:.3}] m{}; move the {what} or the wire (the geometry is \
                     at fault, not the contact)",
                    1e3 * depth,
                    p[0],
                    p[1],
                    p[2],
                    match solves_statics {
                        true => ", its centerline too: a static solve has no side to push it to",
                        false => "",
                    }
                ),
            ));
        }
        let clearance = clearance_zones(&f.clearance, &f.ground)?;
        let implausible = (materials.iter().enumerate())
            .flat_map(|(i, (_, m))| {
                crate::plausibility::material_warnings(&format!("material[{i}]"), m)
            })
            .chain(
                (dampings.iter())
                    .flat_map(|(field, d)| crate::plausibility::damping_warnings(field, d)),
            )
            .collect();
        Ok(Scene {
            source: String::new(),
            model,
            analysis,
            output,
            clearance,
            implausible,
        })
    }
}

/// The `[[clearance]]` zones, each with its own shape's keys, checked.
fn clearance_zones(
    specs: &[ClearanceSpec],
    grounds: &[GroundSpec],
) -> Result<Vec<ClearanceZone>, SceneError> {
    specs
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let field = |key: &str| format!("clearance[{i}].{key}");
            let need = |key: &str, v: Option<[f64; 3]>| {
                v.ok_or_else(|| err(field(key), "missing: this kind of zone needs it"))
            };
            let refuse_extra = |keys: &[(&str, bool)], kind: &str| match keys.iter().find(|k| k.1) {
                Some((key, _)) => Err(err(
                    field(key),
                    format!("a kind = \"{kind}\" zone has no {key}"),
                )),
                None => Ok(()),
            };
            let zone = match c.kind {
                ClearanceKindSpec::Box => {
                    refuse_extra(
                        &[
                            ("point", c.point.is_some()),
                            ("normal", c.normal.is_some()),
                            ("ground", c.ground.is_some()),
                        ],
                        "box",
                    )?;
                    ClearanceZone::Box {
                        min: need("min", c.min)?,
                        max: need("max", c.max)?,
                    }
                }
                ClearanceKindSpec::HalfSpace => {
                    refuse_extra(
                        &[
                            ("min", c.min.is_some()),
                            ("max", c.max.is_some()),
                            ("ground", c.ground.is_some()),
                        ],
                        "half-space",
                    )?;
                    ClearanceZone::HalfSpace {
                        point: need("point", c.point)?,
                        normal: need("normal", c.normal)?,
                    }
                }
                ClearanceKindSpec::Ground => {
                    refuse_extra(
                        &[
                            ("min", c.min.is_some()),
                            ("max", c.max.is_some()),
                            ("point", c.point.is_some()),
                            ("normal", c.normal.is_some()),
                        ],
                        "ground",
                    )?;
                    let index = c
                        .ground
                        .ok_or_else(|| err(field("ground"), "missing: the [[ground]]'s index"))?;
                    let g = grounds.get(index).ok_or_else(|| {
                        err(
                            field("ground"),
                            format!(
                                "no ground[{index}]: the scene has {} [[ground]] table(s)",
                                grounds.len()
                            ),
                        )
                    })?;
                    ClearanceZone::HalfSpace {
                        point: g.point,
                        normal: g.normal,
                    }
                }
            };
            zone.check().map_err(|e| err(field(&e.field), e.message))?;
            Ok(zone)
        })
        .collect()
}

/// The mesh of `[wire]`: `elements` equal elements, or the `segments` of a
/// graded mesh (each checked, their lengths adding up to `length`).
fn mesh_segments(w: &WireSpec, length: f64, table: &str) -> Result<Vec<Segment>, SceneError> {
    match (w.elements, &w.segments) {
        (Some(_), Some(_)) => Err(err(
            format!("{table}.segments"),
            format!(
                "give either {table}.elements (equal elements) or {table}.segments (a graded mesh), not both"
            ),
        )),
        (None, None) => Err(err(
            format!("{table}.elements"),
            format!("missing: give the number of elements (or {table}.segments for a graded mesh)"),
        )),
        (Some(0), None) => Err(err(format!("{table}.elements"), "must be at least 1")),
        (Some(n), None) => Ok(vec![Segment {
            length,
            elements: n,
        }]),
        (None, Some(list)) => {
            if list.is_empty() {
                return Err(err(
                    format!("{table}.segments"),
                    "name at least one segment",
                ));
            }
            let mut out = Vec::new();
            for (i, s) in list.iter().enumerate() {
                let l = positive(&format!("{table}.segments[{i}].length"), s.length)?;
                if s.elements == 0 || s.elements > defaults::MAX_ELEMENTS {
                    return Err(err(
                        format!("{table}.segments[{i}].elements"),
                        format!(
                            "must be a whole number from 1 to {:.0e}, got {}",
                            defaults::MAX_ELEMENTS as f64,
                            s.elements
                        ),
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
                    format!("{table}.segments"),
                    format!(
                        "the segments' lengths add up to {sum} m, but {table}.length is {length} m"
                    ),
                ));
            }
            Ok(out)
        }
    }
}

/// A model error as the scene file's field: the model names its parts
/// (layer 1, rod 0, support 2), the scene knows where they are written.
/// A layer's material parameter is the field of its `[[material]]` table.
fn model_error(
    e: &ModelError,
    layer_materials: &[String],
    materials: &[MaterialSpec],
) -> SceneError {
    let field = match e {
        ModelError::Wire { what, .. } => format!("wire.{what}"),
        ModelError::Layer { index, field, .. } => match field.as_str() {
            "outer_radius" | "inner_radius" => format!("wire.layers[{index}].{field}"),
            "width" | "height" => format!("wire.rectangle.{field}"),
            parameter => {
                let name = layer_materials.get(*index);
                match materials.iter().position(|m| Some(&m.name) == name) {
                    Some(m) => format!("material[{m}].{parameter}"),
                    None => format!("wire.layers[{index}].material"),
                }
            }
        },
        ModelError::Segment { index, what, .. } => format!("wire.segments[{index}].{what}"),
        ModelError::Support { index, what, .. } => format!("support[{index}].{what}"),
        ModelError::NothingToSolve => "support".into(),
        ModelError::Load { index, what, .. } => format!("load[{index}].{what}"),
        ModelError::Gravity { field, .. } => format!("gravity.{field}"),
        ModelError::Rod { index, field, .. } => format!("rod[{index}].{field}"),
        ModelError::Ground { index, field, .. } => format!("ground[{index}].{field}"),
        ModelError::Contact { field, .. } => format!("contact.{field}"),
        ModelError::Damping { field, .. } => format!("damping.{field}"),
        ModelError::Member { index, error, .. } => {
            let inner = model_error(error, layer_materials, materials).field;
            inner.replacen("wire.", &format!("beam[{index}]."), 1)
        }
    };
    err(field, e.message())
}

/// A settings error as the field of `[table]`.
fn in_table(table: &str) -> impl Fn(ParameterError) -> SceneError + '_ {
    move |e| err(format!("{table}.{}", e.field), e.message)
}

/// `[analysis]`: the file's rules (which keys go with which kind), then the
/// solver settings' own check.
fn analysis(a: &AnalysisSpec) -> Result<Analysis, SceneError> {
    match a.kind {
        AnalysisKind::Static => {
            for (name, given) in [
                ("end_time", a.end_time.is_some()),
                ("time_step", a.time_step.is_some()),
                ("error_tolerance", a.error_tolerance.is_some()),
                ("max_time_step", a.max_time_step.is_some()),
                ("spectral_radius", a.spectral_radius.is_some()),
                ("newton", a.newton.is_some()),
                ("broyden", a.broyden.is_some()),
                ("initial", a.initial.is_some()),
            ] {
                if given {
                    return Err(err(
                        format!("analysis.{name}"),
                        "only for kind = \"dynamic\"",
                    ));
                }
            }
            let d = StaticSettings::default();
            let tolerance = a.tolerance.unwrap_or(d.residual_tolerance);
            let settings = StaticSettings {
                load_steps: a.load_steps.unwrap_or(d.load_steps),
                max_iterations: a.max_iterations.unwrap_or(d.max_iterations),
                residual_tolerance: tolerance,
                increment_tolerance: tolerance,
            };
            settings.check().map_err(in_table("analysis"))?;
            Ok(Analysis::Static {
                load_steps: settings.load_steps,
                tolerance,
                max_iterations: settings.max_iterations,
            })
        }
        AnalysisKind::Dynamic => {
            let initial_static = a.initial == Some(InitialSpec::Static);
            if a.load_steps.is_some() && !initial_static {
                return Err(err(
                    "analysis.load_steps",
                    "only for kind = \"static\" or a dynamic run with initial = \"static\" (its \
                     starting equilibrium's increments)",
                ));
            }
            // The static start's increments: the static solve's own bounds.
            if let Some(n) = a.load_steps {
                let start = StaticSettings {
                    load_steps: n,
                    ..Default::default()
                };
                start.check().map_err(in_table("analysis"))?;
            }
            let end_time = a.end_time.ok_or_else(|| {
                err(
                    "analysis.end_time",
                    "missing (s), required for a dynamic run",
                )
            })?;
            let time_step = a.time_step.ok_or_else(|| {
                err(
                    "analysis.time_step",
                    "missing (s), required for a dynamic run",
                )
            })?;
            let fixed = match time_step {
                TimeStepSpec::Fixed(h) => Some(h),
                TimeStepSpec::Auto => None,
            };
            let (time_step, step_control) =
                StepControl::from_keys(fixed, end_time, a.error_tolerance, a.max_time_step)
                    .map_err(in_table("analysis"))?;
            let d = DynamicSettings::default();
            let settings = DynamicSettings {
                time_step,
                step_control,
                end_time,
                spectral_radius: a.spectral_radius.unwrap_or(d.spectral_radius),
                newton: match a.newton {
                    Some(NewtonSpec::Full) => NewtonKind::Full,
                    Some(NewtonSpec::Modified) => NewtonKind::Modified,
                    None => d.newton,
                },
                broyden: a.broyden.unwrap_or(d.broyden),
                tolerance: a.tolerance.unwrap_or(d.tolerance),
                max_iterations: a.max_iterations.unwrap_or(d.max_iterations),
                ..d
            };
            settings.check().map_err(in_table("analysis"))?;
            Ok(Analysis::Dynamic {
                settings,
                initial_static,
                load_steps: a.load_steps.unwrap_or(1),
            })
        }
    }
}

/// The filter and the oscillators need frequencies the steps sample:
/// CFC's −3 dB corner (5/3 CFC) and every response frequency below the
/// Nyquist frequency 1 / (2 h) of the longest step (fixed h, or an
/// adaptive run's `max_time_step`). Above it the steps carry no such
/// content, and the numbers would be the unfiltered force or the starting
/// one, not what was asked. The default class is not judged (`cfc_given`
/// false): a coarse run without contact does not ask for it.
fn output_resolved(
    output: &OutputSettings,
    analysis: &Analysis,
    cfc_given: bool,
) -> Result<(), SceneError> {
    let Analysis::Dynamic { settings, .. } = analysis else {
        return Ok(());
    };
    let h = settings
        .step_control
        .as_ref()
        .map_or(settings.time_step, |c| c.max_step);
    let nyquist = 0.5 / h;
    let corner = crate::loads::cfc::corner_frequency(output.cfc);
    if cfc_given && corner >= nyquist {
        return Err(err(
            "output.cfc",
            format!(
                "CFC {} has its −3 dB corner at {corner:.4e} Hz, at or above the steps' Nyquist \
                 frequency 1/(2h) = {nyquist:.4e} Hz (h = {h:e} s): the filter would pass \
                 everything the steps carry; use a class below {:.4e}, or a shorter step",
                output.cfc,
                0.6 * nyquist
            ),
        ));
    }
    for (i, &f) in output.response_frequencies.iter().enumerate() {
        if f >= nyquist {
            return Err(err(
                format!("output.response_frequencies[{i}]"),
                format!(
                    "{f:e} Hz is at or above the steps' Nyquist frequency 1/(2h) = {nyquist:.4e} Hz \
                     (h = {h:e} s): an oscillator that fast is not resolved; use a shorter step"
                ),
            ));
        }
    }
    Ok(())
}

/// `[output]` over the defaults.
fn output(o: Option<&OutputSpec>) -> Result<OutputSettings, SceneError> {
    let d = OutputSettings::default();
    let Some(o) = o else { return Ok(d) };
    let every = o.every.unwrap_or(d.every);
    if every == 0 {
        return Err(err("output.every", "must be at least 1"));
    }
    let vtk_every = match o.vtk_every {
        Some(n) if n == 0 || n % every != 0 => {
            return Err(err(
                "output.vtk_every",
                format!("must be a positive multiple of output.every ({every}), got {n}"),
            ));
        }
        n => n,
    };
    let response_frequencies = o.response_frequencies.clone().unwrap_or_default();
    for (i, &f) in response_frequencies.iter().enumerate() {
        positive(&format!("output.response_frequencies[{i}]"), f)?;
    }
    let response_damping = match o.response_damping {
        Some(_) if response_frequencies.is_empty() => {
            return Err(err(
                "output.response_damping",
                "the oscillators' damping needs output.response_frequencies",
            ));
        }
        Some(z) if !(0.0..1.0).contains(&z) => {
            return Err(err(
                "output.response_damping",
                format!("a damping ratio in [0, 1) (0.02 is 2 %), got {z}"),
            ));
        }
        z => z.unwrap_or(d.response_damping),
    };
    Ok(OutputSettings {
        every,
        checkpoint_every: o.checkpoint_every.unwrap_or(d.checkpoint_every),
        vtk: o.vtk.unwrap_or(d.vtk),
        vtk_every,
        plots: o.plots.unwrap_or(d.plots),
        cfc: positive("output.cfc", o.cfc.unwrap_or(d.cfc))?,
        response_frequencies,
        response_damping,
    })
}

/// `[damping]` or a beam's own `damping` (at `table`): which factors go
/// with which kind; their values are the model's to check.
fn damping(spec: Option<&DampingSpec>, table: &str) -> Result<Option<Damping>, SceneError> {
    let Some(d) = spec else { return Ok(None) };
    let reject = |pairs: &[(&str, bool)]| -> Result<(), SceneError> {
        for (k, given) in pairs {
            if *given {
                return Err(err(
                    format!("{table}.{k}"),
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
            let coefficient = d.strain_rate_coefficient.ok_or_else(|| {
                err(
                    format!("{table}.strain_rate_coefficient"),
                    "missing (s), required for kelvin-voigt",
                )
            })?;
            Ok(Some(Damping::KelvinVoigt { coefficient }))
        }
        "rayleigh" => {
            reject(&[(
                "strain_rate_coefficient",
                d.strain_rate_coefficient.is_some(),
            )])?;
            Ok(Some(Damping::Rayleigh {
                mass: d.mass.unwrap_or(0.0),
                stiffness: d.stiffness.unwrap_or(0.0),
            }))
        }
        other => Err(err(
            format!("{table}.kind"),
            format!("unknown kind \"{other}\" (use \"kelvin-voigt\" or \"rayleigh\")"),
        )),
    }
}

/// `[contact]` over the defaults; the values are the model's to check.
fn contact_settings(spec: Option<&ContactSpec>) -> ContactSettings {
    let d = ContactSettings::default();
    let Some(c) = spec else { return d };
    ContactSettings {
        stations: c.stations.unwrap_or(d.stations),
        angles: c.angles.unwrap_or(d.angles),
        zone_points: c.zone_points.unwrap_or(d.zone_points),
        slip_velocity: c.slip_velocity.unwrap_or(d.slip_velocity),
        max_penetration: c.max_penetration.unwrap_or(d.max_penetration),
        min_impact_speed: c.min_impact_speed.unwrap_or(d.min_impact_speed),
    }
}

/// A contact's damping from its `restitution` and `restitution_model`
/// (a rod's, a member's, a ground's) by [`ContactDamping::from_keys`];
/// `at` names a key of the table.
fn contact_damping(
    restitution: Option<f64>,
    model: Option<&str>,
    at: &dyn Fn(&str) -> String,
) -> Result<Option<ContactDamping>, SceneError> {
    ContactDamping::from_keys(restitution, model).map_err(|e| err(at(&e.field), e.message))
}

/// A ground and the beams its `beams` names (`None`: the wire only).
type GroundTouching<'a> = (Rod, Option<Vec<&'a str>>);

/// `[[ground]]`: planes under the line law, each with its stiffness,
/// friction and restitution, and its `beams` (absent: the wire only); the
/// values and the names are the model's to check.
fn grounds(specs: &[GroundSpec]) -> Result<Vec<GroundTouching<'_>>, SceneError> {
    let mut out = Vec::new();
    for (i, g) in specs.iter().enumerate() {
        let at = |k: &str| format!("ground[{i}].{k}");
        let damping = contact_damping(g.restitution, g.restitution_model.as_deref(), &at)?;
        let plane = Rod::plane(g.point, g.normal, g.contact_stiffness);
        let ground = Rod {
            friction: g.friction.unwrap_or(plane.friction),
            damping,
            ..plane
        };
        let beams = (g.beams.as_ref()).map(|b| b.iter().map(String::as_str).collect());
        out.push((ground, beams));
    }
    Ok(out)
}

/// `[[rod]]`: the law and what it needs (a stiffness, or for hertz the
/// rod's material), the restitution model's name; the values are the
/// model's to check.
fn rods(
    specs: &[RodSpec],
    wire_radius: f64,
    wire_material: &Material,
    find: &dyn Fn(&str, &str) -> Result<Material, SceneError>,
) -> Result<Vec<Rod>, SceneError> {
    let mut rods = Vec::new();
    for (i, r) in specs.iter().enumerate() {
        let at = |k: &str| format!("rod[{i}].{k}");
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
            // A stiffness's unit depends on the law (N/m² for the line
            // laws, N/m³ for surface test points): one without a law is
            // refused, not guessed.
            None if r.contact_stiffness.is_some() => {
                return Err(err(
                    at("contact_law"),
                    "missing: contact_stiffness is in N/m² for contact_law = \"line\" and in N/m³ \
                     for \"surface\" (the paper's test points); name the law",
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
                r.radius,
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
            (_, Some(k), _) => k,
        };
        let damping = contact_damping(r.restitution, r.restitution_model.as_deref(), &at)?;
        let line = Rod::line(r.center, r.axis, r.radius, contact_stiffness);
        rods.push(Rod {
            length: r.length,
            law,
            friction: r.friction.unwrap_or(line.friction),
            damping,
            ..line
        });
    }
    Ok(rods)
}

/// A `[[beam]]`'s contact keys: the law (`"hertz"` by default, `"line"`
/// with its stiffness), friction and restitution; the values are the
/// model's to check.
fn beam_contact(b: &WireSpec, table: &str) -> Result<BeamContact, SceneError> {
    let damping = (b.restitution, b.restitution_model.as_deref());
    BeamContact::from_keys(
        b.contact_law.as_deref(),
        b.contact_stiffness,
        b.friction,
        damping,
    )
    .map_err(|e| err(format!("{table}.{}", e.field), e.message))
}

/// `[[material]]`: names, the model's name and which constants go with
/// it; the constants are checked by [`Material::check`].
fn validate_materials(specs: &[MaterialSpec]) -> Result<Vec<(String, Material)>, SceneError> {
    use crate::material::beam_plasticity::{CowperSymonds, Hardening};
    let mut out: Vec<(String, Material)> = Vec::new();
    for (i, m) in specs.iter().enumerate() {
        let at = |k: &str| format!("material[{i}].{k}");
        if m.name.trim().is_empty() {
            return Err(err(at("name"), "must not be empty"));
        }
        if out.iter().any(|(n, _)| *n == m.name) {
            return Err(err(at("name"), format!("\"{}\" is defined twice", m.name)));
        }
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
        let plastic_keys = [
            ("hardening_modulus", m.hardening_modulus.is_some()),
            ("hardening", m.hardening.is_some()),
            ("rate", m.rate.is_some()),
        ];
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
                reject(&plastic_keys, &m.model)?;
                MaterialModel::StVenantKirchhoff {
                    youngs_modulus: m
                        .youngs_modulus
                        .ok_or_else(|| err(at("youngs_modulus"), "missing (Pa)"))?,
                    poisson_ratio: m
                        .poisson_ratio
                        .unwrap_or(crate::material::DEFAULT_POISSON_RATIO),
                    bending_factor: m
                        .bending_factor
                        .unwrap_or(crate::material::DEFAULT_BENDING_FACTOR),
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
                reject(&plastic_keys, &m.model)?;
                MaterialModel::MooneyRivlin {
                    mu10: m.mu10.ok_or_else(|| err(at("mu10"), "missing (Pa)"))?,
                    mu01: m.mu01.ok_or_else(|| err(at("mu01"), "missing (Pa)"))?,
                    penalty: m
                        .penalty
                        .ok_or_else(|| err(at("penalty"), "missing (κ, e.g. 1e3)"))?,
                }
            }
            "elastic-plastic" => {
                reject(
                    &[
                        ("mu10", m.mu10.is_some()),
                        ("mu01", m.mu01.is_some()),
                        ("penalty", m.penalty.is_some()),
                        ("bending_factor", m.bending_factor.is_some()),
                    ],
                    &m.model,
                )?;
                if m.yield_stress.is_none() {
                    return Err(err(at("yield_stress"), "missing (Pa), e.g. 235e6 for S235"));
                }
                let hardening = Hardening::from_name(m.hardening.as_deref())
                    .map_err(|message| err(at("hardening"), message))?;
                let rate = match &m.rate {
                    None => None,
                    Some(r) if r.kind == "cowper-symonds" => Some(CowperSymonds { d: r.d, q: r.q }),
                    Some(r) => {
                        return Err(err(
                            at("rate.kind"),
                            format!("unknown rate law \"{}\" (use \"cowper-symonds\")", r.kind),
                        ));
                    }
                };
                MaterialModel::ElasticPlastic {
                    youngs_modulus: m
                        .youngs_modulus
                        .ok_or_else(|| err(at("youngs_modulus"), "missing (Pa)"))?,
                    poisson_ratio: m
                        .poisson_ratio
                        .unwrap_or(crate::material::DEFAULT_POISSON_RATIO),
                    hardening_modulus: m.hardening_modulus.unwrap_or(0.0),
                    hardening,
                    rate,
                }
            }
            other => {
                return Err(err(
                    at("model"),
                    format!(
                        "unknown model \"{other}\" (use \"st-venant-kirchhoff\", \"mooney-rivlin\" or \"elastic-plastic\")"
                    ),
                ));
            }
        };
        let material = Material {
            density: m.density,
            model,
            locking,
            yield_stress: m.yield_stress,
        };
        material.check().map_err(|e| err(at(&e.field), e.message))?;
        out.push((m.name.clone(), material));
    }
    Ok(out)
}

/// A beam's geometry and section as the file gives it (`[wire]` or a
/// `[[beam]]`, `table` naming it in errors): its description, the
/// materials of its layers by layer (to map errors back), the material of
/// its outer surface and its element count.
fn beam_description(
    w: &WireSpec,
    table: &str,
    name: &str,
    find: &dyn Fn(&str, &str) -> Result<Material, SceneError>,
) -> Result<(BeamBuilder, Vec<String>, Material, usize), SceneError> {
    let length = positive(&format!("{table}.length"), w.length)?;
    let segments = mesh_segments(w, length, table)?;
    let n_elements: usize = segments.iter().map(|s| s.elements).sum();
    if n_elements > defaults::MAX_ELEMENTS {
        return Err(err(
            format!(
                "{table}.{}",
                if w.segments.is_some() {
                    "segments"
                } else {
                    "elements"
                }
            ),
            format!(
                "{n_elements} elements is more than this code is meant for (≤ {:.0e})",
                defaults::MAX_ELEMENTS as f64
            ),
        ));
    }
    let mut builder = BeamBuilder::new(name, length, n_elements)
        .placed(
            w.origin.unwrap_or([0.0; 3]),
            w.direction.unwrap_or([1.0, 0.0, 0.0]),
        )
        .quadrature(
            w.quadrature
                .as_ref()
                .and_then(|q| q.axial)
                .unwrap_or(crate::model::DEFAULT_AXIAL_ORDER),
            w.quadrature
                .as_ref()
                .and_then(|q| q.section)
                .unwrap_or(crate::model::DEFAULT_SECTION_ORDER),
        );
    if w.segments.is_some() {
        builder = builder.graded(&segments);
    }
    // The materials of the layers, by layer, for mapping errors back.
    let mut layer_materials = Vec::new();
    let outer_material = match (&w.layers, &w.rectangle) {
        (Some(_), Some(_)) => {
            return Err(err(table, "give either `layers` or `rectangle`, not both"));
        }
        (None, None) => {
            return Err(err(
                format!("{table}.layers"),
                "missing: the cross section (layers or rectangle)",
            ));
        }
        (Some(layers), None) => {
            if layers.is_empty() {
                return Err(err(format!("{table}.layers"), "needs at least one layer"));
            }
            for (i, l) in layers.iter().enumerate() {
                match (i, l.inner_radius) {
                    (0, Some(r)) => builder = builder.bore(r),
                    (_, Some(_)) => {
                        return Err(err(
                            format!("{table}.layers[{i}].inner_radius"),
                            "only the first layer has one: each other layer starts at the previous \
                                 outer radius",
                        ));
                    }
                    (_, None) => {}
                }
                let m = find(&format!("{table}.layers[{i}].material"), &l.material)?;
                builder = builder.layer(m, l.outer_radius);
                layer_materials.push(l.material.clone());
            }
            let last = &layers[layers.len() - 1].material;
            find(&format!("{table}.layers"), last)?
        }
        (None, Some(r)) => {
            let m = find(&format!("{table}.rectangle.material"), &r.material)?;
            builder = builder.rectangle(m.clone(), r.width, r.height);
            layer_materials.push(r.material.clone());
            m
        }
    };
    Ok((builder, layer_materials, outer_material, n_elements))
}
