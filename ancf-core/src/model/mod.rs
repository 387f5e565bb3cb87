//! The assembled model of one wire and any frame members ([`beam`]): their
//! elements, supports (eliminated coordinates), loads and the list of
//! effects it contains. Built from a
//! scene (or by hand); read by assembly and the solvers, never mutated by them.

mod alone;
pub mod beam;
mod builder;
pub mod clearance;
pub mod contact;
pub mod damping;
mod mass_product;
pub mod memory;
mod mesh;
pub mod spring;
pub use beam::{Beam, BeamLayout};
pub use builder::{BeamBuilder, WireBuilder, station_spacing};
pub use mesh::{ElementGroup, Segment};

use crate::element::{ElementIntegration, ElementMatrix, ElementVector, reference_coordinates};
use crate::math::vec3::{cross, dot, sub, unit};
use crate::section::Section;
use std::ops::Range;

/// Coordinates per node: r, r_x, r_y, r_z.
pub const NODE_DOFS: usize = 12;

/// The most elements a beam may have: a larger model needs more memory than
/// a workstation has (10⁵ elements take about 3 GB).
pub const MAX_ELEMENTS: usize = 1_000_000;

/// Axial Gauss points of an element unless said otherwise. 5 would
/// integrate an SVK element's energy exactly (degree 8 in ξ), but the
/// accuracy study (docs/accuracy) finds 3 points give the same
/// cantilever and pendulum errors to three digits at 60–70 % of the cost;
/// 2 points are 9× less accurate in dynamics.
pub const DEFAULT_AXIAL_ORDER: usize = 3;

/// Ring-rule order of a section unless said otherwise: 3 integrates an SVK
/// layer exactly (degree 4 in y, z).
pub const DEFAULT_SECTION_ORDER: usize = 3;

/// How a node is held (SPEC §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SupportKind {
    /// r, r_y, r_z and the two components of r_x normal to the wire axis
    /// fixed; the axial component of r_x is free, so the root section may
    /// stretch. Needs a wire axis along a coordinate direction.
    Clamp,
    /// All 12 coordinates fixed (zero axial strain at the node).
    Fixed,
    /// r fixed only: a spherical joint.
    Pin,
    /// r and the section gradient r_y fixed: the node turns about the
    /// section's y direction only (horizontal and normal to the axis for a
    /// horizontal beam, [`section_frame`]). A simply supported (fork) end of
    /// a frame member bending in its vertical plane: unlike a pin, it holds
    /// the member's twist and its sideways turn.
    Hinge,
    /// Nothing fixed: springs and a dashpot to fixed ground (a post's or a
    /// clamp's compliance), relaxed where the node starts.
    Spring(spring::Spring),
}

impl SupportKind {
    /// The scene file's name of the kind.
    pub fn name(&self) -> &'static str {
        match self {
            SupportKind::Clamp => "clamp",
            SupportKind::Fixed => "fixed",
            SupportKind::Pin => "pin",
            SupportKind::Hinge => "hinge",
            SupportKind::Spring(_) => "spring",
        }
    }
}

/// A support: which node, how it is held, where, and until when.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Support {
    /// The node held (0 … elements).
    pub node: usize,
    /// Which coordinates it holds.
    pub kind: SupportKind,
    /// Where the node is held (m); `None`: its reference position.
    pub position: Option<[f64; 3]>,
    /// Time (s) at which the support lets go (a broken conductor, a failed
    /// clamp); `None`: it holds for the whole run.
    pub release_time: Option<f64>,
}

impl Support {
    /// A support at the node's reference position that never releases.
    pub fn new(node: usize, kind: SupportKind) -> Self {
        Support {
            node,
            kind,
            position: None,
            release_time: None,
        }
    }
}

/// A constant force (N) at a node's position r and a constant moment
/// (N m) at the node. The moment keeps its direction in space as the node
/// turns, by any angle ([`crate::forces::moment`]: it acts on the node's
/// current section gradients, with its load stiffness).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointLoad {
    /// The loaded node.
    pub node: usize,
    /// The force (N).
    pub force: [f64; 3],
    /// The moment (N m); zero: none.
    pub moment: [f64; 3],
    /// Whether the moment turns with the node (a follower: `moment` is
    /// its direction in the reference, carried by the node's section
    /// frame); otherwise it keeps its direction in space.
    pub follower: bool,
}

impl PointLoad {
    /// Whether the load has a moment.
    pub fn has_moment(&self) -> bool {
        self.moment.iter().any(|m| *m != 0.0)
    }
}

/// A force contribution the model evaluates. The model holds exactly the
/// effects its scene names; code for an absent effect never runs.
// A model holds a handful of effects: the larger variants stay inline.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Effect {
    /// Elastic forces of the layers (always present).
    Elasticity {
        /// Whether a layer is Mooney–Rivlin (point-wise integration).
        mooney_rivlin: bool,
        /// Whether a layer has a centerline law (Poisson or ω split).
        centerline: bool,
    },
    /// Gravity: constant generalized force, full coordinates (N).
    Gravity {
        /// g (m/s²).
        acceleration: [f64; 3],
        /// The generalized gravity force, full coordinates (N).
        force: Vec<f64>,
    },
    /// Point loads.
    PointLoads(Vec<PointLoad>),
    /// Penalty contact with rigid rods (friction only where a rod has μ > 0).
    Contact(contact::Contact),
    /// Structural damping (Kelvin–Voigt or Rayleigh), each beam's own
    /// (index: beam; `None`: undamped); present when a beam is damped.
    Damping(Vec<Option<damping::Damping>>),
    /// Elastic supports: springs and dashpots at nodes.
    Springs(Vec<spring::SpringAt>),
}

/// Marks an element index between two beams in `Model::group_of`.
const GAP: u32 = u32::MAX;

/// A straight wire of `n_elements` elements, in groups of equal length
/// (one group: a uniform mesh), and any frame members after it
/// ([`beam`]: one coordinate vector, a gap element between two beams).
#[derive(Clone, Debug)]
pub struct Model {
    /// The elements by length, beam after beam, covering every element but
    /// the gaps between beams.
    pub groups: Vec<ElementGroup>,
    /// Each element's group (`GAP` between beams).
    group_of: Vec<u32>,
    /// Number of element indices: the beams' elements and the gaps between
    /// them (nodes: one more).
    pub n_elements: usize,
    /// The beams: the wire (beam 0) and the members.
    pub beams: Vec<Beam>,
    /// Reference coordinates, 12 per node.
    pub reference: Vec<f64>,
    /// For each coordinate, its unknown index, or `None` when eliminated.
    /// Unknowns are numbered in coordinate order (0, 1, 2, … over the
    /// coordinates not held): the assembly pattern, `scatter_add` and the
    /// residual rely on it.
    pub dof_map: Vec<Option<usize>>,
    /// The coordinates not held, as runs of consecutive coordinates (from
    /// `dof_map`): the Newton loop's vector operations run over contiguous
    /// slices, which vectorize, instead of testing every coordinate.
    free: Vec<Range<usize>>,
    /// Number of unknowns (coordinates not held).
    pub n_unknowns: usize,
    /// The supports, in the scene's order.
    pub supports: Vec<Support>,
    /// The effects the model evaluates (only those its scene names).
    pub effects: Vec<Effect>,
}

/// Why a model cannot be built. Each kind names the part at fault in the
/// model's own terms (layer 1, rod 0, support 2) and the parameter by its
/// scene-file key; a scene maps it to the field of its file (`scene`), the
/// Python package to its own arguments.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelError {
    /// A property of the wire as a whole: `what` is "length", "elements",
    /// "direction", "segments", "layers", "quadrature.axial" or
    /// "quadrature.section".
    Wire {
        /// The property at fault.
        what: String,
        /// What is wrong with it.
        message: String,
    },
    /// Layer `index` of the section (0 from the centre out; the rectangle is
    /// layer 0): `field` is "outer_radius", "width", "height" or a parameter
    /// of its material ("poisson_ratio", …).
    Layer {
        /// The layer (0-based).
        index: usize,
        /// Its parameter at fault.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// Segment `index` of a graded mesh: `what` is "length" or "elements".
    Segment {
        /// The segment (0-based).
        index: usize,
        /// Its property at fault.
        what: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// Support `index`: `what` is "node", "kind", "position" or "release_time".
    Support {
        /// The support (0-based).
        index: usize,
        /// Its property at fault.
        what: String,
        /// What is wrong with it.
        message: String,
    },
    /// Every coordinate is held: there is nothing to solve.
    NothingToSolve,
    /// Frame member `index` (0-based, in the order given), named `name`:
    /// `error` is about its own geometry or section, in the wire's terms
    /// (`Wire { what: "length" }`, `Layer`, `Segment`).
    Member {
        /// The member (0-based).
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong with it.
        error: Box<ModelError>,
    },
    /// Point load `index`: `what` is "node" or "force".
    Load {
        /// The load (0-based).
        index: usize,
        /// Its property at fault.
        what: String,
        /// What is wrong with it.
        message: String,
    },
    /// The gravitational acceleration.
    Gravity {
        /// The component at fault (`acceleration[2]`).
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// Rod `index`: `field` is one of [`contact::Rod::check`]'s parameters.
    Rod {
        /// The rod (0-based).
        index: usize,
        /// Its parameter at fault.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// Ground `index`: `field` is one of [`contact::Rod::check`]'s
    /// parameters for a plane.
    Ground {
        /// The ground (0-based, among the grounds).
        index: usize,
        /// Its parameter at fault.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The contact settings: `field` is one of [`contact::ContactSettings::check`]'s.
    Contact {
        /// The setting at fault.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The structural damping: `field` is one of [`damping::Damping::check`]'s.
    Damping {
        /// The factor at fault.
        field: String,
        /// What is wrong with it.
        message: String,
    },
}

impl ModelError {
    fn wire(what: &str, message: impl Into<String>) -> Self {
        ModelError::Wire {
            what: what.into(),
            message: message.into(),
        }
    }

    /// What is wrong, without the part's name.
    pub fn message(&self) -> String {
        match self {
            ModelError::Wire { message, .. }
            | ModelError::Layer { message, .. }
            | ModelError::Segment { message, .. }
            | ModelError::Support { message, .. }
            | ModelError::Load { message, .. }
            | ModelError::Gravity { message, .. }
            | ModelError::Rod { message, .. }
            | ModelError::Ground { message, .. }
            | ModelError::Contact { message, .. }
            | ModelError::Damping { message, .. } => message.clone(),
            ModelError::NothingToSolve => "every coordinate is fixed: nothing to solve".into(),
            ModelError::Member { error, .. } => error.message(),
        }
    }
}

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let m = self.message();
        match self {
            ModelError::Wire { what, .. } => write!(f, "wire {what}: {m}"),
            ModelError::Layer { index, field, .. } => write!(f, "layer {index}, {field}: {m}"),
            ModelError::Segment { index, what, .. } => write!(f, "segment {index}, {what}: {m}"),
            ModelError::Support { index, what, .. } => write!(f, "support {index}, {what}: {m}"),
            ModelError::NothingToSolve => write!(f, "supports: {m}"),
            ModelError::Load { index, what, .. } => write!(f, "load {index}, {what}: {m}"),
            ModelError::Gravity { field, .. } => write!(f, "gravity {field}: {m}"),
            ModelError::Rod { index, field, .. } => write!(f, "rod {index}, {field}: {m}"),
            ModelError::Ground { index, field, .. } => write!(f, "ground {index}, {field}: {m}"),
            ModelError::Contact { field, .. } => write!(f, "contact {field}: {m}"),
            ModelError::Damping { field, .. } => write!(f, "damping {field}: {m}"),
            ModelError::Member { name, error, .. } => match &**error {
                ModelError::Wire { what, .. } => write!(f, "member \"{name}\" {what}: {m}"),
                inner => write!(f, "member \"{name}\", {inner}"),
            },
        }
    }
}
impl std::error::Error for ModelError {}

/// The unknown numbering: every coordinate not held by an active support
/// (`active(support)`), in order. Errors name the support at fault.
fn eliminate(
    n_nodes: usize,
    supports: &[Support],
    beams: &[Beam],
    active: impl Fn(&Support) -> bool,
) -> Result<(Vec<Option<usize>>, usize), ModelError> {
    let mut fixed = vec![false; NODE_DOFS * n_nodes];
    for (i, s) in supports.iter().enumerate() {
        if s.node >= n_nodes {
            return Err(ModelError::Support {
                index: i,
                what: "node".into(),
                message: format!(
                    "node {} does not exist (the wire has nodes 0..={})",
                    s.node,
                    n_nodes - 1
                ),
            });
        }
        if !active(s) {
            continue;
        }
        let base = NODE_DOFS * s.node;
        let mut fix = |c: usize| fixed[base + c] = true;
        match s.kind {
            SupportKind::Fixed => (0..12).for_each(&mut fix),
            SupportKind::Pin => (0..3).for_each(&mut fix),
            SupportKind::Hinge => (0..3).chain(6..9).for_each(&mut fix),
            SupportKind::Spring(_) => {}
            SupportKind::Clamp => {
                let axis = beams
                    .iter()
                    .find(|b| b.nodes.contains(&s.node))
                    .map_or([1.0, 0.0, 0.0], |b| b.axis);
                let Some(along) = (0..3).find(|&k| (axis[k].abs() - 1.0).abs() < 1e-12) else {
                    return Err(ModelError::Support {
                        index: i,
                        what: "kind".into(),
                        message: format!(
                            "a clamp needs a wire along a coordinate axis (its direction is {axis:?}); use a fixed support"
                        ),
                    });
                };
                (0..3).chain(6..12).for_each(&mut fix);
                (0..3).filter(|&k| k != along).for_each(|k| fix(3 + k));
            }
        }
    }
    let mut dof_map = vec![None; fixed.len()];
    let mut n_unknowns = 0;
    for (c, f) in fixed.iter().enumerate() {
        if !f {
            dof_map[c] = Some(n_unknowns);
            n_unknowns += 1;
        }
    }
    Ok((dof_map, n_unknowns))
}

/// The runs of consecutive coordinates that are unknowns.
fn free_runs(dof_map: &[Option<usize>]) -> Vec<Range<usize>> {
    let mut runs: Vec<Range<usize>> = Vec::new();
    for (c, u) in dof_map.iter().enumerate() {
        if u.is_some() {
            match runs.last_mut() {
                Some(run) if run.end == c => run.end = c + 1,
                _ => runs.push(c..c + 1),
            }
        }
    }
    runs
}

/// Rotate v by the smallest rotation taking unit `from` to unit `to` (Rodrigues).
fn rotate_between(from: [f64; 3], to: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let k = cross(from, to);
    let s = dot(k, k).sqrt();
    let c = dot(from, to);
    if s < 1e-14 {
        return if c > 0.0 { v } else { v.map(|x| -x) };
    }
    let k = k.map(|x| x / s);
    let kv = cross(k, v);
    let kkv = dot(k, v);
    std::array::from_fn(|i| v[i] * c + kv[i] * s + k[i] * kkv * (1.0 - c))
}

/// The wire's name as a beam.
pub const WIRE: &str = "wire";

/// The element groups of a graded mesh: each segment's elements at its own
/// length, with `element`'s section and quadrature.
pub fn graded_groups(
    element: &ElementIntegration,
    segments: &[Segment],
) -> Result<Vec<(ElementIntegration, usize)>, ModelError> {
    if segments.is_empty() {
        return Err(ModelError::wire("segments", "name at least one segment"));
    }
    let mut groups = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        if s.elements == 0 {
            return Err(ModelError::Segment {
                index: i,
                what: "elements",
                message: "need at least one element".into(),
            });
        }
        if !(s.length.is_finite() && s.length > 0.0) {
            return Err(ModelError::Segment {
                index: i,
                what: "length",
                message: format!("must be > 0 m, got {}", s.length),
            });
        }
        groups.push((
            element.with_length(s.length / s.elements as f64),
            s.elements,
        ));
    }
    Ok(groups)
}

/// Two unit vectors completing `axis` to a right-handed frame; for the
/// default axis x they are y and z.
pub fn section_frame(axis: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    // z-direction of the section: global z projected off the axis, unless the axis is vertical.
    let up = if axis[2].abs() < 0.9 {
        [0.0, 0.0, 1.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let ny = unit(cross(up, axis));
    let nz = cross(axis, ny);
    (ny, nz)
}

impl Model {
    /// A straight wire of `n_elements` equal elements (each `element.length`
    /// long) from `origin` along `direction` (normalised here).
    pub fn new(
        element: ElementIntegration,
        n_elements: usize,
        origin: [f64; 3],
        direction: [f64; 3],
        supports: Vec<Support>,
        gravity: Option<[f64; 3]>,
        loads: Vec<PointLoad>,
    ) -> Result<Self, ModelError> {
        if n_elements == 0 {
            return Err(ModelError::wire("elements", "need at least one element"));
        }
        let wire = BeamLayout {
            name: WIRE.into(),
            groups: vec![(element, n_elements)],
            origin,
            direction,
        };
        Self::from_beams(vec![wire], supports, gravity, loads)
    }

    /// A straight wire meshed by `segments` in order (a graded mesh: each
    /// region has its own element length); `element` gives the section and
    /// the quadrature, its length is ignored.
    pub fn graded(
        element: ElementIntegration,
        segments: &[Segment],
        origin: [f64; 3],
        direction: [f64; 3],
        supports: Vec<Support>,
        gravity: Option<[f64; 3]>,
        loads: Vec<PointLoad>,
    ) -> Result<Self, ModelError> {
        let groups = graded_groups(&element, segments)?;
        let wire = BeamLayout {
            name: WIRE.into(),
            groups,
            origin,
            direction,
        };
        Self::from_beams(vec![wire], supports, gravity, loads)
    }

    /// A model of several beams: the wire first (`beams[0]`), then the
    /// members, in order. Supports and loads name the model's nodes (a
    /// member's node `k` is `model.beams[i].node(k)`); a model built this
    /// way is checked only as far as [`Model::new`] checks (the builder
    /// checks everything).
    pub fn from_beams(
        layouts: Vec<BeamLayout>,
        supports: Vec<Support>,
        gravity: Option<[f64; 3]>,
        loads: Vec<PointLoad>,
    ) -> Result<Self, ModelError> {
        let firsts = beam::first_nodes(&layouts);
        let mut groups: Vec<ElementGroup> = Vec::new();
        let mut group_of = Vec::new();
        let mut beams = Vec::new();
        let mut reference = Vec::new();
        for (b, layout) in layouts.into_iter().enumerate() {
            let direction = layout.direction;
            let dn = (direction.iter().map(|v| v * v).sum::<f64>()).sqrt();
            if !(dn > 0.0 && dn.is_finite()) {
                return Err(ModelError::wire(
                    "direction",
                    "must be a non-zero finite vector",
                ));
            }
            let axis = direction.map(|v| v / dn);
            let (ny, nz) = section_frame(axis);
            // The gap between this beam and the previous one.
            let first_element = firsts[b];
            group_of.resize(first_element, GAP);
            let first_group = groups.len();
            for (integration, count) in layout.groups {
                let (first, start) = match groups.last() {
                    Some(p) if groups.len() > first_group => {
                        (p.elements.end, p.arc(p.elements.len()))
                    }
                    _ => (group_of.len(), 0.0),
                };
                let g = groups.len() as u32;
                groups.push(ElementGroup::new(integration, first..first + count, start));
                group_of.extend(std::iter::repeat_n(g, count));
            }
            let elements = first_element..group_of.len();
            let nodes = first_element..group_of.len() + 1;
            reference.resize(NODE_DOFS * nodes.end, 0.0);
            let origin = layout.origin;
            for g in &groups[first_group..] {
                let l = g.integration.length;
                for (j, el) in g.elements.clone().enumerate() {
                    // A beam's first group keeps the uniform mesh's product
                    // order (axis · l · j), so a uniform wire's bits do not
                    // change.
                    let start = std::array::from_fn(|k| {
                        if g.start == 0.0 {
                            origin[k] + axis[k] * l * j as f64
                        } else {
                            origin[k] + axis[k] * g.arc(j)
                        }
                    });
                    let e = reference_coordinates(start, axis, ny, nz, l);
                    reference[NODE_DOFS * el..NODE_DOFS * el + 24].copy_from_slice(&e);
                }
            }
            beams.push(Beam {
                name: layout.name,
                elements,
                nodes,
                axis,
                section_y: ny,
                section_z: nz,
            });
        }
        let n_elements = group_of.len();
        let n_nodes = n_elements + 1;
        let (dof_map, n_unknowns) = eliminate(n_nodes, &supports, &beams, |_| true)?;
        for (i, ld) in loads.iter().enumerate() {
            if ld.node >= n_nodes {
                return Err(ModelError::Load {
                    index: i,
                    what: "node".into(),
                    message: format!(
                        "node {} does not exist (the wire has nodes 0..={})",
                        ld.node,
                        n_nodes - 1
                    ),
                });
            }
        }
        let sections = || groups.iter().map(|g| &g.integration.section);
        let mut effects = vec![Effect::Elasticity {
            mooney_rivlin: sections().any(|s| s.has_mooney_rivlin()),
            centerline: sections().any(|s| s.layers.iter().any(|l| l.laws.centerline.is_some())),
        }];
        if let Some(g) = gravity {
            let mut force = vec![0.0; reference.len()];
            for group in &groups {
                let qe = group.integration.gravity_force(g);
                for el in group.elements.clone() {
                    for (i, v) in qe.iter().enumerate() {
                        force[NODE_DOFS * el + i] += v;
                    }
                }
            }
            effects.push(Effect::Gravity {
                acceleration: g,
                force,
            });
        }
        if !loads.is_empty() {
            effects.push(Effect::PointLoads(loads));
        }
        let mut model = Model {
            groups,
            group_of,
            n_elements,
            beams,
            reference,
            free: free_runs(&dof_map),
            dof_map,
            n_unknowns,
            supports,
            effects,
        };
        // Elastic supports relax where their nodes start.
        let start = model.initial_coordinates();
        let springs: Vec<spring::SpringAt> = (model.supports.iter().enumerate())
            .filter_map(|(i, s)| match s.kind {
                SupportKind::Spring(k) => {
                    let base = NODE_DOFS * s.node;
                    let rest = &start[base..base + NODE_DOFS];
                    Some(spring::SpringAt::new(i, s.node, k, rest))
                }
                _ => None,
            })
            .collect();
        if !springs.is_empty() {
            model.effects.push(Effect::Springs(springs));
        }
        Ok(model)
    }

    /// The integration of element `el` (its length is the element's; not
    /// a gap, see [`Model::is_gap`]).
    pub fn element(&self, el: usize) -> &ElementIntegration {
        &self.groups[self.group_of[el] as usize].integration
    }

    /// Whether element index `el` is the gap between two beams (no element).
    pub fn is_gap(&self, el: usize) -> bool {
        self.group_of[el] == GAP
    }

    /// The wire: beam 0.
    pub fn wire(&self) -> &Beam {
        &self.beams[0]
    }

    /// The beams no support holds (any kind, springs included): a static
    /// solution of such a beam is singular — it has rigid-body motions.
    /// A beam whose coordinates are all held ([`Model::alone`]'s others) is
    /// held.
    pub fn unheld_beams(&self) -> Vec<&Beam> {
        (self.beams.iter().enumerate())
            .filter(|(i, b)| {
                !self.fully_held(*i) && !self.supports.iter().any(|s| b.nodes.contains(&s.node))
            })
            .map(|(_, b)| b)
            .collect()
    }

    /// What a static solution needs that `self` lacks, said to a user:
    /// `None` when every beam is held.
    pub fn static_holding_error(&self) -> Option<String> {
        let unheld = self.unheld_beams();
        let names: Vec<String> = (unheld.iter())
            .map(|b| {
                if b.name == WIRE {
                    "the wire".to_string()
                } else {
                    format!("member \"{}\"", b.name)
                }
            })
            .collect();
        (!names.is_empty()).then(|| {
            format!(
                "{} not held: a static solution needs a support (pin, clamp, fixed or spring) on \
                 every beam, or it can move as a rigid body",
                names.join(" and ") + if names.len() > 1 { " are" } else { " is" }
            )
        })
    }

    /// The beam named `name`, with its index.
    pub fn beam(&self, name: &str) -> Option<(usize, &Beam)> {
        self.beams.iter().enumerate().find(|(_, b)| b.name == name)
    }

    /// The beam holding node `n` and the node's index in it.
    pub fn beam_of_node(&self, n: usize) -> Option<(usize, usize)> {
        (self.beams.iter().enumerate())
            .find(|(_, b)| b.nodes.contains(&n))
            .map(|(i, b)| (i, n - b.nodes.start))
    }

    /// The group of element `el` (an index into [`Model::groups`]).
    pub fn group(&self, el: usize) -> usize {
        self.group_of[el] as usize
    }

    /// The mass matrix of element `el` (kg), row-major 24×24.
    pub fn element_mass(&self, el: usize) -> &ElementMatrix {
        &self.groups[self.group_of[el] as usize].mass
    }

    /// The cross section (the same for every element).
    pub fn section(&self) -> &Section {
        &self.groups[0].integration.section
    }

    /// The element lengths (m), one per group.
    pub fn element_lengths(&self) -> Vec<f64> {
        self.groups.iter().map(|g| g.integration.length).collect()
    }

    /// Reference (unstretched) arc length of node `n` from node 0 (m).
    pub fn node_arc(&self, n: usize) -> f64 {
        // A node between two groups of one beam has the same arc in both.
        let g = (self.groups.iter())
            .find(|g| g.elements.start <= n && n <= g.elements.end)
            .expect("every node belongs to a group");
        g.arc(n - g.elements.start)
    }

    /// Reference arc length between nodes `a` ≤ `b` (m); within one group
    /// the product of the element length and the element count.
    pub fn arc_between(&self, a: usize, b: usize) -> f64 {
        let el = a.min(self.n_elements - 1);
        if !self.is_gap(el) {
            let g = &self.groups[self.group_of[el] as usize];
            if b <= g.elements.end {
                return (b - a) as f64 * g.integration.length;
            }
        }
        self.node_arc(b) - self.node_arc(a)
    }

    /// The wire's reference (unstretched) length (m).
    pub fn length(&self) -> f64 {
        self.node_arc(self.wire().last_node())
    }

    /// What in this model makes Newton's work hard, when something does:
    /// a beam so slender (L / R above 1e4) that its bending stiffness is a
    /// vanishing fraction of its axial one, or a Mooney–Rivlin layer whose
    /// volume penalty κ exceeds 1e7 (nearly incompressible beyond what the
    /// element resolves: it locks). A failed solve's message adds it to its
    /// likely cause.
    pub fn ill_conditioning(&self) -> Option<String> {
        let mut notes = Vec::new();
        for beam in &self.beams {
            let length = self.node_arc(beam.last_node()) - self.node_arc(beam.nodes.start);
            let radius = self.element(beam.elements.start).section.outer_radius();
            let slenderness = length / radius;
            if slenderness > 1e4 {
                notes.push(format!(
                    "{} \"{}\" is very slender (L / R = {slenderness:.1e}): its bending stiffness is \
                     about {:.0e} of its axial one, so Newton meets a nearly singular matrix; start \
                     it near its shape (a support's position starts a span on its sag parabola), \
                     take more load steps, or model it coarser",
                    if beam.name == WIRE { "the beam" } else { "member" },
                    beam.name,
                    1.0 / (slenderness * slenderness)
                ));
            }
        }
        for group in &self.groups {
            for layer in &group.integration.section.layers {
                if let crate::material::MaterialModel::MooneyRivlin { penalty, .. } =
                    layer.material.model
                    && penalty > 1e7
                {
                    notes.push(format!(
                        "the Mooney–Rivlin volume penalty κ = {penalty:.1e} is beyond 1e7: the \
                         layer is so nearly incompressible that the element locks and Newton \
                         stalls; κ = 1e3 … 1e7 keeps ν within about 5e-4 … 5e-8 of 0.5"
                    ));
                    break;
                }
            }
        }
        notes.dedup();
        (!notes.is_empty()).then(|| notes.join("; "))
    }

    /// The model with only the supports still holding at time `t` (those
    /// without a release time, or released later): a release phase. The
    /// coordinates a released support held become unknowns.
    pub fn holding_at(&self, t: f64) -> Model {
        let (dof_map, n_unknowns) = eliminate(self.n_nodes(), &self.supports, &self.beams, |s| {
            s.release_time.is_none_or(|r| r > t)
        })
        .expect("supports were validated when the model was built");
        Model {
            free: free_runs(&dof_map),
            dof_map,
            n_unknowns,
            ..self.clone()
        }
    }

    /// The release times of the supports, sorted, without duplicates.
    pub fn release_times(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self
            .supports
            .iter()
            .filter_map(|s| s.release_time)
            .collect();
        t.sort_by(f64::total_cmp);
        t.dedup();
        t
    }

    /// Starting coordinates: the reference, with every support at its
    /// `position`. When supports move, the nodes between two consecutive
    /// supported nodes are laid on a parabola in the vertical plane through
    /// them (sagging along gravity, or −z) whose arc length equals their
    /// unstretched length — a hanging conductor's shape to within a few per
    /// cent — or on the straight chord when it is longer than the wire
    /// (taut). A straight, compressed start would buckle the static solve of
    /// a slack span; this one is already in tension. Nodes beyond the end
    /// supports move rigidly with them.
    pub fn initial_coordinates(&self) -> Vec<f64> {
        let mut q = self.reference.clone();
        for beam in &self.beams {
            self.lay_beam(beam, &mut q);
        }
        q
    }

    /// [`Model::initial_coordinates`] of one beam: its nodes between its
    /// supports.
    fn lay_beam(&self, beam: &Beam, q: &mut [f64]) {
        let on_beam = |s: &&Support| beam.nodes.contains(&s.node);
        let moved: Vec<(usize, [f64; 3])> = self
            .supports
            .iter()
            .filter(on_beam)
            .filter_map(|s| s.position.map(|p| (s.node, p)))
            .collect();
        if moved.iter().all(|(n, p)| {
            let r = self.node_position(&self.reference, *n);
            dot(sub(*p, r), sub(*p, r)) == 0.0
        }) {
            return;
        }
        // Every supported node with its target position, by node index.
        let mut held: Vec<(usize, [f64; 3])> = self
            .supports
            .iter()
            .filter(on_beam)
            .map(|s| {
                (
                    s.node,
                    s.position
                        .unwrap_or_else(|| self.node_position(&self.reference, s.node)),
                )
            })
            .collect();
        held.sort_by_key(|h| h.0);
        held.dedup_by_key(|h| h.0);
        let down = {
            let g = self.gravity_acceleration().unwrap_or([0.0, 0.0, -1.0]);
            let n = dot(g, g).sqrt();
            g.map(|x| x / n)
        };
        let set_node = |q: &mut [f64], n: usize, p: [f64; 3], tangent: [f64; 3], stretch: f64| {
            let base = NODE_DOFS * n;
            let ny = rotate_between(beam.axis, tangent, beam.section_y);
            let nz = rotate_between(beam.axis, tangent, beam.section_z);
            for k in 0..3 {
                q[base + k] = p[k];
                q[base + 3 + k] = stretch * tangent[k];
                q[base + 6 + k] = ny[k];
                q[base + 9 + k] = nz[k];
            }
        };
        // Rigid shifts beyond the first and last held nodes.
        let shift = |q: &mut [f64], nodes: std::ops::Range<usize>, by: [f64; 3]| {
            for n in nodes {
                for k in 0..3 {
                    q[NODE_DOFS * n + k] += by[k];
                }
            }
        };
        let (first, last) = (held[0], held[held.len() - 1]);
        shift(
            q,
            beam.nodes.start..first.0 + 1,
            sub(first.1, self.node_position(&self.reference, first.0)),
        );
        shift(
            q,
            last.0..beam.nodes.end,
            sub(last.1, self.node_position(&self.reference, last.0)),
        );
        for pair in held.windows(2) {
            let ((na, pa), (nb, pb)) = (pair[0], pair[1]);
            let chord = sub(pb, pa);
            let c = dot(chord, chord).sqrt();
            let s_len = self.arc_between(na, nb);
            if c == 0.0 || nb == na {
                continue;
            }
            let u = chord.map(|x| x / c);
            if s_len <= c {
                for n in na..=nb {
                    let f = (n - na) as f64 / (nb - na) as f64;
                    set_node(
                        q,
                        n,
                        std::array::from_fn(|k| pa[k] + f * chord[k]),
                        u,
                        c / s_len,
                    );
                }
                continue;
            }
            // Sag direction: `down` with its chord component removed.
            let mut w = sub(down, u.map(|x| x * dot(down, u)));
            let wn = dot(w, w).sqrt();
            if wn < 1e-9 {
                w = beam.section_y;
            } else {
                w = w.map(|x| x / wn);
            }
            // p(τ) = pa + τ c u + 4 f τ(1 − τ) w; arc length by 200-point midpoint sums.
            let arc = |f: f64, upto: f64| -> f64 {
                let m = 200;
                (0..m)
                    .map(|i| {
                        let t = upto * (i as f64 + 0.5) / m as f64;
                        (c * c + (4.0 * f * (1.0 - 2.0 * t)).powi(2)).sqrt() * upto / m as f64
                    })
                    .sum()
            };
            let (mut lo, mut hi) = (0.0, s_len);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if arc(mid, 1.0) < s_len {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let f = 0.5 * (lo + hi);
            for n in na..=nb {
                let target = self.arc_between(na, n);
                let (mut a, mut b) = (0.0, 1.0);
                for _ in 0..60 {
                    let mid = 0.5 * (a + b);
                    if arc(f, mid) < target {
                        a = mid
                    } else {
                        b = mid
                    }
                }
                let t = 0.5 * (a + b);
                let p =
                    std::array::from_fn(|k| pa[k] + t * c * u[k] + 4.0 * f * t * (1.0 - t) * w[k]);
                let d: [f64; 3] =
                    std::array::from_fn(|k| c * u[k] + 4.0 * f * (1.0 - 2.0 * t) * w[k]);
                let dn = dot(d, d).sqrt();
                set_node(q, n, p, d.map(|x| x / dn), 1.0);
            }
        }
    }

    /// Number of elements, every beam's (the gaps between beams not counted).
    pub fn element_count(&self) -> usize {
        self.groups.iter().map(|g| g.elements.len()).sum()
    }

    /// Number of nodes (element indices + 1: every beam's nodes).
    pub fn n_nodes(&self) -> usize {
        self.n_elements + 1
    }

    /// Coordinates of element `el` out of a full coordinate vector.
    pub fn element_coordinates(&self, q: &[f64], el: usize) -> ElementVector {
        q[NODE_DOFS * el..NODE_DOFS * el + 24].try_into().unwrap()
    }

    /// The unknown of each of element `el`'s 24 coordinates (`None`: held).
    pub fn element_unknowns(&self, el: usize) -> [Option<usize>; 24] {
        std::array::from_fn(|i| self.dof_map[NODE_DOFS * el + i])
    }

    /// The gravitational acceleration (m/s²), when the model has gravity.
    pub fn gravity_acceleration(&self) -> Option<[f64; 3]> {
        self.effects.iter().find_map(|e| match e {
            Effect::Gravity { acceleration, .. } => Some(*acceleration),
            _ => None,
        })
    }

    /// The gravity force (full coordinates), when the model has gravity.
    pub fn gravity_force(&self) -> Option<&[f64]> {
        self.effects.iter().find_map(|e| match e {
            Effect::Gravity { force, .. } => Some(force.as_slice()),
            _ => None,
        })
    }

    /// The contact effect, when the scene has rods.
    pub fn contact(&self) -> Option<&contact::Contact> {
        self.effects.iter().find_map(|e| match e {
            Effect::Contact(c) => Some(c),
            _ => None,
        })
    }

    /// The rods and members whose line-law contact a time step of `h` s
    /// does not resolve on this wire (h ω_c above
    /// [`contact::RESOLVED_STEP_FREQUENCY`], see [`contact::resolution`]);
    /// empty without contact.
    pub fn unresolved_contacts(&self, h: f64) -> Vec<contact::UnresolvedContact> {
        self.contact().map_or_else(Vec::new, |c| {
            let members: Vec<(String, f64)> = (c.members.iter())
                .map(|m| {
                    let beam = &self.beams[m.beam];
                    let group = self.group(beam.elements.start);
                    let mass = self.groups[group].integration.section.mass_per_length();
                    (beam.name.clone(), mass)
                })
                .collect();
            contact::unresolved_contacts(c, self.section().mass_per_length(), &members, h)
        })
    }

    /// The longest step (s) that resolves every line-law contact of the
    /// model (h ω_c ≤ [`contact::RESOLVED_STEP_FREQUENCY`]): an adaptive
    /// run's steps near a rod or member stay below it. `None` without a
    /// line-law contact.
    pub fn contact_step_limit(&self) -> Option<f64> {
        (self.unresolved_contacts(f64::INFINITY).iter())
            .map(|u| u.resolving_step())
            .reduce(f64::min)
    }

    /// The elastic supports (empty without any).
    pub fn springs(&self) -> &[spring::SpringAt] {
        self.effects
            .iter()
            .find_map(|e| match e {
                Effect::Springs(s) => Some(&s[..]),
                _ => None,
            })
            .unwrap_or(&[])
    }

    /// Support `i`'s spring when it carries a moment (a rotational or a
    /// torsional spring).
    pub fn moment_spring(&self, i: usize) -> Option<&spring::SpringAt> {
        (self.springs().iter()).find(|s| s.support == i && s.carries_moment())
    }

    /// The elastic supports' energy at coordinates `q` (J), which counts as
    /// strain energy.
    pub fn spring_energy(&self, q: &[f64]) -> f64 {
        self.springs().iter().map(|s| s.energy(q)).sum()
    }

    /// Whether an elastic support has a dashpot.
    pub fn has_spring_damping(&self) -> bool {
        self.springs().iter().any(|s| s.spring.damping > 0.0)
    }

    /// Beam `beam`'s structural damping, when it has one.
    pub fn beam_damping(&self, beam: usize) -> Option<&damping::Damping> {
        self.effects.iter().find_map(|e| match e {
            Effect::Damping(per_beam) => per_beam.get(beam).and_then(Option::as_ref),
            _ => None,
        })
    }

    /// The damped beams (index) with their damping.
    pub fn dampings(&self) -> impl Iterator<Item = (usize, &damping::Damping)> {
        (0..self.beams.len()).filter_map(|b| self.beam_damping(b).map(|d| (b, d)))
    }

    /// Whether any beam is damped.
    pub fn is_damped(&self) -> bool {
        self.dampings().next().is_some()
    }

    /// The beam of group `g` (its elements lie in one beam).
    pub fn group_beam(&self, g: usize) -> usize {
        let first = self.groups[g].elements.start;
        (self.beams.iter())
            .position(|b| b.elements.contains(&first))
            .expect("a group's elements belong to a beam")
    }

    /// Add each beam's damping (index: beam) as one of the model's effects
    /// (none when no beam is damped).
    pub fn with_damping(mut self, per_beam: Vec<Option<damping::Damping>>) -> Self {
        if per_beam.iter().any(Option::is_some) {
            self.effects.push(Effect::Damping(per_beam));
        }
        self
    }

    /// Add rods: contact becomes one of the model's effects.
    pub fn with_rods(self, rods: Vec<contact::Rod>, settings: contact::ContactSettings) -> Self {
        self.with_contact(rods, (Vec::new(), Vec::new()), settings)
    }

    /// The model with contact between the wire and `rods` and `members`
    /// (none without either).
    pub fn with_contact(
        mut self,
        rods: Vec<contact::Rod>,
        (members, grounded): (Vec<contact::MemberContact>, Vec<(usize, usize)>),
        settings: contact::ContactSettings,
    ) -> Self {
        if !rods.is_empty() || !members.is_empty() {
            let c = contact::Contact::new(rods, settings, self.section().outer_radius())
                .with_members(members)
                .with_grounded_members(grounded);
            self.effects.push(Effect::Contact(c));
        }
        self
    }

    /// The point loads (empty without them).
    pub fn point_loads(&self) -> &[PointLoad] {
        self.effects
            .iter()
            .find_map(|e| match e {
                Effect::PointLoads(l) => Some(l.as_slice()),
                _ => None,
            })
            .unwrap_or(&[])
    }

    /// Constant external force (gravity + point loads), full coordinates, scaled by `factor`.
    pub fn external_force(&self, factor: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.reference.len()];
        for effect in &self.effects {
            match effect {
                Effect::Gravity { force, .. } => {
                    f.iter_mut().zip(force).for_each(|(a, b)| *a += factor * b)
                }
                Effect::PointLoads(loads) => {
                    for ld in loads {
                        let base = NODE_DOFS * ld.node;
                        for k in 0..3 {
                            f[base + k] += factor * ld.force[k];
                        }
                    }
                }
                Effect::Elasticity { .. }
                | Effect::Contact(_)
                | Effect::Damping(_)
                | Effect::Springs(_) => {}
            }
        }
        f
    }

    /// Potential energy of the external forces, −Q_extᵀ (q − q_ref) (J).
    pub fn external_potential(&self, q: &[f64]) -> (f64, f64) {
        let mut gravity = 0.0;
        let mut loads = 0.0;
        if let Some(g) = self.gravity_force() {
            gravity = -g
                .iter()
                .zip(q.iter().zip(&self.reference))
                .map(|(f, (a, b))| f * (a - b))
                .sum::<f64>();
        }
        for ld in self.point_loads() {
            for k in 0..3 {
                let c = NODE_DOFS * ld.node + k;
                loads -= ld.force[k] * (q[c] - self.reference[c]);
            }
        }
        (gravity, loads)
    }

    /// The point loads that carry a moment (their work depends on the
    /// path: [`crate::forces::moment`]).
    pub fn moment_loads(&self) -> impl Iterator<Item = &PointLoad> {
        self.point_loads().iter().filter(|l| l.has_moment())
    }

    /// The section gradients [r_y, r_z] of node `n` in `q`, as one array.
    pub fn section_gradients(&self, q: &[f64], n: usize) -> [f64; 6] {
        std::array::from_fn(|k| q[NODE_DOFS * n + 6 + k])
    }

    /// M x for a full coordinate vector x (fixed entries included as given).
    /// The element mass matrix is an 8×8 scalar matrix times I₃ (SPEC §1:
    /// S = [s₁I, …, s₈I]), so each element costs 8·8·3 products, not 24².
    pub fn mass_times(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        self.mass_times_into(x, &mut out);
        out
    }

    /// `out` = M x (full coordinates), without allocating.
    pub fn mass_times_into(&self, x: &[f64], out: &mut [f64]) {
        mass_product::mass_times_into(&self.groups, x, out)
    }

    /// Add the unknowns' entries of a full vector to `out` (unknowns).
    pub fn gather_add(&self, full: &[f64], out: &mut [f64]) {
        for (x, u) in full.iter().zip(&self.dof_map) {
            if let Some(u) = u {
                out[*u] += x;
            }
        }
    }

    /// Gather the unknowns out of a full vector.
    pub fn gather(&self, full: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_unknowns];
        for (c, m) in self.dof_map.iter().enumerate() {
            if let Some(u) = m {
                out[*u] = full[c];
            }
        }
        out
    }

    /// Add `scale · x` (unknowns) into a full vector.
    pub fn scatter_add(&self, x: &[f64], scale: f64, full: &mut [f64]) {
        let mut x = x;
        for run in self.free_coordinates() {
            let (part, rest) = x.split_at(run.len());
            x = rest;
            for (f, x) in full[run.clone()].iter_mut().zip(part) {
                *f += scale * x;
            }
        }
    }

    /// `full` ← `base` + `scale · x` on the coordinates not held (x over the
    /// unknowns), the held ones of `full` left as they are: a
    /// [`Model::scatter_add`] onto a copy of `base` without the copy, with
    /// its bits, where `full` already holds `base`'s held coordinates.
    pub fn scatter_add_to(&self, base: &[f64], x: &[f64], scale: f64, full: &mut [f64]) {
        let mut x = x;
        for run in self.free_coordinates() {
            let (part, rest) = x.split_at(run.len());
            x = rest;
            let (base, full) = (&base[run.clone()], &mut full[run.clone()]);
            for ((f, b), x) in full.iter_mut().zip(base).zip(part) {
                *f = b + scale * x;
            }
        }
    }

    /// The coordinates not held, as runs of consecutive coordinates in
    /// order. Unknowns are numbered in coordinate order, so a vector over
    /// the unknowns holds the runs one after another: loops over the runs
    /// and the matching slices of such a vector are contiguous and
    /// vectorize (testing `dof_map` at every coordinate does not).
    pub fn free_coordinates(&self) -> &[Range<usize>] {
        &self.free
    }

    /// The first node of `q` whose gradients [r_x r_y r_z] have turned
    /// over, their determinant's sign no longer the reference's: the
    /// element there was crushed through itself (its material turned
    /// inside out). Green–Lagrange strain cannot see it: r_x → −r_x
    /// strains nothing, so a dead load pushing a member past what it
    /// carries finds an "equilibrium" in the inverted member, which no
    /// solid reaches. `None` when every node keeps its handedness.
    pub fn inverted_node(&self, q: &[f64]) -> Option<usize> {
        let det = |q: &[f64], n: usize| {
            let g =
                |k: usize| -> [f64; 3] { std::array::from_fn(|i| q[NODE_DOFS * n + 3 * k + i]) };
            let [a, b, c] = [g(1), g(2), g(3)];
            crate::math::vec3::dot(a, crate::math::vec3::cross(b, c))
        };
        (0..self.n_nodes()).find(|&n| det(q, n) * det(&self.reference, n) <= 0.0)
    }

    /// The gradients [r_x, r_y, r_z] of node `n` in `q`, one after the
    /// other: the section's orientation and stretch (dimensionless).
    pub fn node_gradients(&self, q: &[f64], n: usize) -> [f64; 9] {
        std::array::from_fn(|k| q[NODE_DOFS * n + 3 + k])
    }

    /// The twist (rad) of node `n`'s section in `q` about its centerline,
    /// from the reference ([`crate::math::twist`]).
    pub fn node_twist(&self, q: &[f64], n: usize) -> f64 {
        let (g, g0) = (
            self.node_gradients(q, n),
            self.node_gradients(&self.reference, n),
        );
        let v = |g: &[f64; 9], k: usize| -> [f64; 3] { [g[3 * k], g[3 * k + 1], g[3 * k + 2]] };
        crate::math::twist::twist(v(&g0, 0), v(&g0, 1), v(&g, 0), v(&g, 1))
    }

    /// Position of node `n` in a full coordinate vector.
    pub fn node_position(&self, q: &[f64], n: usize) -> [f64; 3] {
        std::array::from_fn(|k| q[NODE_DOFS * n + k])
    }

    /// The size of round-off in each assembled force entry (N), one value
    /// per unknown: strains carry an absolute error of about ε_machine, so
    /// forces carry about ε · (largest element stiffness) · (coordinate
    /// size). Newton accepts a residual whose entries are all below 100
    /// times this: no iteration can reduce it further (measured: the
    /// pendulum's residual stagnates at 3e-9 N with 16 elements, where
    /// ε · EA / l_e = 9e-9 N). The stiffness is each beam's own: a stiff
    /// frame member's round-off is far above a soft wire's whole residual
    /// (measured: tubes with E × 1e4 set it to 11 N, and the span break's
    /// wire was then accepted unconverged from the first step).
    pub fn roundoff_forces(&self) -> Vec<f64> {
        let qmax = self.reference.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let mut full = vec![0.0; self.reference.len()];
        for beam in &self.beams {
            // The shortest elements are the stiffest.
            let mut kmax = 0.0f64;
            let groups = self.groups.iter().filter(|g| {
                g.elements.start < beam.elements.end && beam.elements.start < g.elements.end
            });
            for g in groups {
                let e = self.element_coordinates(&self.reference, g.elements.start);
                let mut q = [0.0; 24];
                let mut k = [0.0; 576];
                g.integration.evaluate(&e, &mut q, Some(&mut k));
                kmax = (0..24).fold(kmax, |m, i| m.max(k[i * 24 + i].abs()));
            }
            let size = 100.0 * f64::EPSILON * kmax * qmax;
            full[NODE_DOFS * beam.nodes.start..NODE_DOFS * beam.nodes.end].fill(size);
        }
        self.gather(&full)
    }

    /// Total mass (kg), every beam's.
    pub fn total_mass(&self) -> f64 {
        self.groups
            .iter()
            .map(|g| {
                let m = g.integration.section.mass_per_length();
                m * g.integration.length * g.elements.len() as f64
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use crate::material::Material;
    use crate::model::WireBuilder;

    /// M x from the non-zero couplings equals the dense element matrices'
    /// product to round-off, for a one- and a two-layer section.
    #[test]
    fn mass_product_equals_the_dense_element_product() {
        let steel = Material::st_venant_kirchhoff(7850.0, 2e11, 0.3, 1.0);
        let alu = Material::st_venant_kirchhoff(2700.0, 7e10, 0.33, 0.2);
        for layers in [
            vec![(steel.clone(), 0.01)],
            vec![(steel, 0.005), (alu, 0.014)],
        ] {
            let mut b = WireBuilder::new(2.0, 5);
            for (m, r) in layers {
                b = b.layer(m, r);
            }
            let model = b.build().expect("valid wire");
            let n = model.reference.len();
            let x: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) as f64).sin()).collect();
            let mut dense = vec![0.0; n];
            for el in 0..model.n_elements {
                let base = super::NODE_DOFS * el;
                for a in 0..24 {
                    for b in 0..24 {
                        dense[base + a] += model.element_mass(el)[a * 24 + b] * x[base + b];
                    }
                }
            }
            let fast = model.mass_times(&x);
            for (f, d) in fast.iter().zip(&dense) {
                assert!((f - d).abs() <= 1e-14 * d.abs().max(1e-3), "{f} vs {d}");
            }
        }
    }
}
