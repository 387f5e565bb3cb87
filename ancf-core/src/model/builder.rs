//! Building a wire in code, without a scene file: a few readable lines give
//! the same `Model` a scene would. [`WireBuilder::build`] is where every
//! value of a wire is checked (a scene file and the Python package build
//! through it), with the rules each description holds (`Material::check`,
//! `Rod::check`, `ContactSettings::check`, `Damping::check`).
//!
//! ```
//! use ancf_core::model::contact::Rod;
//! use ancf_core::material::Material;
//! use ancf_core::model::{SupportKind, WireBuilder};
//! let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
//! let model = WireBuilder::new(2.0, 8)
//!     .layer(steel, 0.01)
//!     .support(0, SupportKind::Pin)
//!     .gravity([0.0, 0.0, -9.81])
//!     .rod(Rod::line([1.0, 0.0, -0.3], [0.0, 1.0, 0.0], 0.02, 5e7).with_friction(0.3))
//!     .build()
//!     .unwrap();
//! assert_eq!(model.n_elements, 8);
//! assert!(model.contact().is_some());
//! ```

use super::contact::{BeamContact, ContactLaw, ContactSettings, MemberContact, Rod};
use super::damping::Damping;
use super::{BeamLayout, Model, ModelError, PointLoad, Segment, Support, SupportKind};
use crate::check::{ParameterError, count_in, finite3, positive};
use crate::element::ElementIntegration;
use crate::material::Material;
use crate::section::Section;

/// The cross section a builder describes.
#[derive(Clone, Debug)]
enum SectionSpec {
    /// Concentric layers from the centre out: material and outer radius (m).
    Layers(Vec<(Material, f64)>),
    /// A rectangle: material, width along y and height along z (m).
    Rectangle(Material, f64, f64),
}

/// One beam's geometry and section described in code: the wire's (inside
/// a [`WireBuilder`]) or a frame member's ([`WireBuilder::member`]).
#[derive(Clone, Debug)]
pub struct BeamBuilder {
    name: String,
    length: f64,
    elements: usize,
    /// A graded mesh (replaces `length` and `elements`).
    segments: Option<Vec<Segment>>,
    origin: [f64; 3],
    direction: [f64; 3],
    section: SectionSpec,
    /// The first layer's inner radius (m): 0 for a solid section.
    bore: f64,
    axial_order: usize,
    section_order: usize,
    /// A member's contact with the wire (unused for the wire itself).
    contact: BeamContact,
}

impl BeamBuilder {
    /// A straight beam `name` of `length` (m) in `elements` elements, along
    /// x from the origin, with the scene defaults (axial and section order 3).
    pub fn new(name: &str, length: f64, elements: usize) -> Self {
        BeamBuilder {
            name: name.into(),
            length,
            elements,
            segments: None,
            origin: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            section: SectionSpec::Layers(Vec::new()),
            bore: 0.0,
            axial_order: super::DEFAULT_AXIAL_ORDER,
            section_order: super::DEFAULT_SECTION_ORDER,
            contact: BeamContact::default(),
        }
    }

    /// How the wire touches this member (default: the Hertz line law from
    /// the two outer materials, frictionless, elastic).
    pub fn contact(mut self, contact: BeamContact) -> Self {
        self.contact = contact;
        self
    }

    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// A graded mesh: the beam is the `segments` in order, each with its
    /// own element length (fine where the wire meets a rod, coarse
    /// elsewhere). Replaces the length and element count of [`BeamBuilder::new`].
    pub fn graded(mut self, segments: &[Segment]) -> Self {
        self.length = segments.iter().map(|s| s.length).sum();
        // Saturating: a count too large to add up is refused by `build`.
        self.elements = (segments.iter()).fold(0, |n: usize, s| n.saturating_add(s.elements));
        self.segments = Some(segments.to_vec());
        self
    }

    /// Where the beam starts (m) and its direction (normalised).
    pub fn placed(mut self, origin: [f64; 3], direction: [f64; 3]) -> Self {
        self.origin = origin;
        self.direction = direction;
        self
    }

    /// The next concentric layer outward, up to `outer_radius` (m)
    /// (replaces a rectangle).
    pub fn layer(mut self, material: Material, outer_radius: f64) -> Self {
        match &mut self.section {
            SectionSpec::Layers(layers) => layers.push((material, outer_radius)),
            SectionSpec::Rectangle(..) => {
                self.section = SectionSpec::Layers(vec![(material, outer_radius)])
            }
        }
        self
    }

    /// A hollow section: the first layer starts at `inner_radius` (m)
    /// instead of the centre — a tube, the paper's ring quadrature.
    pub fn bore(mut self, inner_radius: f64) -> Self {
        self.bore = inner_radius;
        self
    }

    /// A rectangular section of `width` along y and `height` along z (m),
    /// one material (replaces any layers).
    pub fn rectangle(mut self, material: Material, width: f64, height: f64) -> Self {
        self.section = SectionSpec::Rectangle(material, width, height);
        self
    }

    /// Gauss points along the element and the ring-rule order of the section.
    pub fn quadrature(mut self, axial: usize, section: usize) -> Self {
        self.axial_order = axial;
        self.section_order = section;
        self
    }

    /// The beam's length, elements, placement, quadrature, section and
    /// mesh checked (errors in the wire's terms: [`ModelError::Wire`],
    /// `Layer`, `Segment`), as the model's layout.
    fn layout(&self) -> Result<BeamLayout, ModelError> {
        let wire = |what: &str| {
            let what = what.to_string();
            move |e: ParameterError| ModelError::Wire {
                what: what.clone(),
                message: e.message,
            }
        };
        positive("length", self.length).map_err(wire("length"))?;
        if self.elements == 0 {
            return Err(ModelError::wire("elements", "need at least one element"));
        }
        if self.elements > super::MAX_ELEMENTS {
            return Err(ModelError::wire(
                if self.segments.is_some() {
                    "segments"
                } else {
                    "elements"
                },
                format!(
                    "{} elements is more than this code is meant for (≤ {:.0e})",
                    self.elements,
                    super::MAX_ELEMENTS as f64
                ),
            ));
        }
        let named = |e: ParameterError| ModelError::Wire {
            what: e.field,
            message: e.message,
        };
        finite3("origin", self.origin).map_err(named)?;
        crate::check::direction("direction", self.direction).map_err(named)?;
        count_in("axial", self.axial_order, 1..=16).map_err(wire("quadrature.axial"))?;
        count_in("section", self.section_order, 1..=16).map_err(wire("quadrature.section"))?;
        let section = self.section()?;
        let element = ElementIntegration::new(
            self.length / self.elements as f64,
            self.axial_order,
            section,
        );
        let groups = match &self.segments {
            Some(segments) => super::graded_groups(&element, segments)?,
            None => vec![(element, self.elements)],
        };
        Ok(BeamLayout {
            name: self.name.clone(),
            groups,
            origin: self.origin,
            direction: self.direction,
        })
    }

    /// The section, each layer's radius and material checked.
    fn section(&self) -> Result<Section, ModelError> {
        let layer = |index: usize| {
            move |e: ParameterError| ModelError::Layer {
                index,
                field: e.field,
                message: e.message,
            }
        };
        match &self.section {
            SectionSpec::Layers(layers) => {
                if layers.is_empty() {
                    return Err(ModelError::wire(
                        "layers",
                        "a wire needs at least one layer",
                    ));
                }
                let mut inner =
                    crate::check::non_negative("inner_radius", self.bore).map_err(layer(0))?;
                let mut section_layers = Vec::new();
                for (i, (material, outer)) in layers.iter().enumerate() {
                    let outer = positive("outer_radius", *outer).map_err(layer(i))?;
                    if outer <= inner {
                        return Err(ModelError::Layer {
                            index: i,
                            field: "outer_radius".into(),
                            message: format!(
                                "{outer} m must exceed the layer's inner radius {inner} m ({})",
                                if i == 0 {
                                    "its inner_radius"
                                } else {
                                    "the previous outer radius"
                                }
                            ),
                        });
                    }
                    material.check().map_err(layer(i))?;
                    section_layers.push((inner, outer, material.clone()));
                    inner = outer;
                }
                Ok(Section::circular(&section_layers, self.section_order))
            }
            SectionSpec::Rectangle(material, width, height) => {
                let width = positive("width", *width).map_err(layer(0))?;
                let height = positive("height", *height).map_err(layer(0))?;
                material.check().map_err(layer(0))?;
                Ok(Section::rectangular(
                    width,
                    height,
                    material.clone(),
                    self.section_order,
                ))
            }
        }
    }
}

/// A wire described in code, with any frame members; [`WireBuilder::build`]
/// checks it and makes the [`Model`].
#[derive(Clone, Debug)]
pub struct WireBuilder {
    wire: BeamBuilder,
    members: Vec<BeamBuilder>,
    supports: Vec<Support>,
    /// Each support's beam by name (`None`: the wire), its node local to it.
    support_beams: Vec<Option<String>>,
    gravity: Option<[f64; 3]>,
    loads: Vec<PointLoad>,
    /// Each load's beam by name (`None`: the wire), its node local to it.
    load_beams: Vec<Option<String>>,
    rods: Vec<Rod>,
    /// The grounds (planes), listed after the rods in the model.
    grounds: Vec<Rod>,
    /// Each ground's `beams` list, by name (`None`: the wire only).
    ground_beams: Vec<Option<Vec<String>>>,
    contact: ContactSettings,
    /// The damping of every beam that names none of its own.
    damping: Option<Damping>,
    /// Beams' own damping, by beam name.
    beam_damping: Vec<(String, Damping)>,
}

impl WireBuilder {
    /// A straight wire of `length` (m) in `elements` elements, along x from
    /// the origin, with the scene defaults (axial and section order 3).
    pub fn new(length: f64, elements: usize) -> Self {
        WireBuilder {
            wire: BeamBuilder::new(super::WIRE, length, elements),
            members: Vec::new(),
            supports: Vec::new(),
            support_beams: Vec::new(),
            gravity: None,
            loads: Vec::new(),
            load_beams: Vec::new(),
            rods: Vec::new(),
            grounds: Vec::new(),
            ground_beams: Vec::new(),
            contact: ContactSettings::default(),
            damping: None,
            beam_damping: Vec::new(),
        }
    }

    /// A wire of the geometry and section `wire` describes (named "wire").
    pub fn from_beam(mut wire: BeamBuilder) -> Self {
        wire.name = super::WIRE.into();
        WireBuilder {
            wire,
            ..WireBuilder::new(0.0, 0)
        }
    }

    /// A graded mesh: the wire is the `segments` in order, each with its
    /// own element length (fine where the wire meets a rod, coarse
    /// elsewhere). Replaces the length and element count of [`WireBuilder::new`].
    pub fn graded(mut self, segments: &[Segment]) -> Self {
        self.wire = self.wire.graded(segments);
        self
    }

    /// Where the wire starts (m) and its direction (normalised).
    pub fn placed(mut self, origin: [f64; 3], direction: [f64; 3]) -> Self {
        self.wire = self.wire.placed(origin, direction);
        self
    }

    /// The next concentric layer outward, up to `outer_radius` (m)
    /// (replaces a rectangle).
    pub fn layer(mut self, material: Material, outer_radius: f64) -> Self {
        self.wire = self.wire.layer(material, outer_radius);
        self
    }

    /// A hollow section: the first layer starts at `inner_radius` (m)
    /// instead of the centre — a tube, the paper's ring quadrature.
    pub fn bore(mut self, inner_radius: f64) -> Self {
        self.wire = self.wire.bore(inner_radius);
        self
    }

    /// A rectangular section of `width` along y and `height` along z (m),
    /// one material (replaces any layers).
    pub fn rectangle(mut self, material: Material, width: f64, height: f64) -> Self {
        self.wire = self.wire.rectangle(material, width, height);
        self
    }

    /// Gauss points along the element and the ring-rule order of the section.
    pub fn quadrature(mut self, axial: usize, section: usize) -> Self {
        self.wire = self.wire.quadrature(axial, section);
        self
    }

    /// A frame member: another beam of the same element, after the wire
    /// and the members before it. Its supports and loads are given with
    /// [`WireBuilder::support_on`] and [`WireBuilder::load_on`].
    pub fn member(mut self, member: BeamBuilder) -> Self {
        self.members.push(member);
        self
    }

    /// Whether a member named `name` has been added.
    pub fn has_member(&self, name: &str) -> bool {
        self.members.iter().any(|m| m.name == name)
    }

    /// A support on beam `beam` (a member's name, or "wire"), its `node`
    /// counted on that beam.
    pub fn support_on(mut self, beam: &str, support: Support) -> Self {
        self.supports.push(support);
        self.support_beams.push(Some(beam.into()));
        self
    }

    /// A load on beam `beam` (a member's name, or "wire"), its `node`
    /// counted on that beam.
    pub fn load_on(mut self, beam: &str, load: PointLoad) -> Self {
        self.loads.push(load);
        self.load_beams.push(Some(beam.into()));
        self
    }

    /// A support at `node` (0 … elements) holding it in its reference place.
    pub fn support(self, node: usize, kind: SupportKind) -> Self {
        self.support_with(Support::new(node, kind))
    }

    /// An elastic support at `node`: `spring`'s springs and dashpot, relaxed
    /// where the node starts.
    pub fn spring(self, node: usize, spring: super::spring::Spring) -> Self {
        self.support(node, SupportKind::Spring(spring))
    }

    /// A support given in full (position, release time).
    pub fn support_with(mut self, support: Support) -> Self {
        self.supports.push(support);
        self.support_beams.push(None);
        self
    }

    /// Gravity acceleration, m/s².
    pub fn gravity(mut self, g: [f64; 3]) -> Self {
        self.gravity = Some(g);
        self
    }

    /// A constant force (N) at a node.
    pub fn load(self, node: usize, force: [f64; 3]) -> Self {
        self.load_with(PointLoad {
            node,
            force,
            ..Default::default()
        })
    }

    /// A constant moment (N m) at a node, of fixed direction in space for
    /// any rotation of the node ([`crate::forces::moment`]).
    pub fn moment(self, node: usize, moment: [f64; 3]) -> Self {
        self.load_with(PointLoad {
            node,
            moment,
            ..Default::default()
        })
    }

    /// A load given in full (force and moment).
    pub fn load_with(mut self, load: PointLoad) -> Self {
        self.loads.push(load);
        self.load_beams.push(None);
        self
    }

    /// A rigid rod the wire may touch (a plane, [`Rod::plane`], is a
    /// ground: [`WireBuilder::ground`]).
    pub fn rod(mut self, rod: Rod) -> Self {
        if rod.is_ground() {
            self.grounds.push(rod);
            self.ground_beams.push(None);
        } else {
            self.rods.push(rod);
        }
        self
    }

    /// The ground under the wire: a plane ([`Rod::plane`]) it may touch but
    /// not pass. A cylinder given here is a rod ([`WireBuilder::rod`]).
    /// The model lists the grounds after the rods.
    pub fn ground(self, ground: Rod) -> Self {
        self.rod(ground)
    }

    /// A ground ([`WireBuilder::ground`]) that the beams named in `beams`
    /// touch: the wire (`"wire"`, which touches every ground and must be
    /// named) and frame members, each by the line law with its own outer
    /// radius (a post that falls, a tube pressed down onto it). The names
    /// are checked when the model is built.
    pub fn ground_touching(mut self, ground: Rod, beams: &[&str]) -> Self {
        self = self.ground(ground);
        if let Some(names) = self.ground_beams.last_mut() {
            *names = Some(beams.iter().map(|b| b.to_string()).collect());
        }
        self
    }

    /// Contact integration and friction regularization (defaults as in scenes).
    pub fn contact_settings(mut self, settings: ContactSettings) -> Self {
        self.contact = settings;
        self
    }

    /// Kelvin–Voigt or Rayleigh damping of the wire and every member that
    /// has none of its own ([`WireBuilder::damping_on`]).
    pub fn damping(mut self, damping: Damping) -> Self {
        self.damping = Some(damping);
        self
    }

    /// Beam `beam`'s own damping (a member's name, or "wire"), in place of
    /// [`WireBuilder::damping`]'s: a conductor and the steel of a frame
    /// dissipate differently. Without any, a beam is undamped.
    pub fn damping_on(mut self, beam: &str, damping: Damping) -> Self {
        self.beam_damping.retain(|(name, _)| name != beam);
        self.beam_damping.push((beam.into(), damping));
        self
    }

    /// Checks the description and builds the model. The first value at
    /// fault is named: the wire's length, elements and quadrature, each
    /// layer (its radius and material), the supports, loads and gravity,
    /// each rod, the contact settings and the damping.
    pub fn build(self) -> Result<Model, ModelError> {
        let mut layouts = vec![self.wire.layout()?];
        for (i, m) in self.members.iter().enumerate() {
            let member = |error: ModelError| ModelError::Member {
                index: i,
                name: m.name.clone(),
                error: Box::new(error),
            };
            if let Err(message) = super::beam::check_member_name(&m.name) {
                return Err(member(ModelError::wire("name", message)));
            }
            if self.members[..i].iter().any(|o| o.name == m.name) {
                return Err(member(ModelError::wire(
                    "name",
                    format!("\"{}\" names two members: names are unique", m.name),
                )));
            }
            layouts.push(m.layout().map_err(member)?);
        }
        // Refused before any work: a model the machine cannot hold (the
        // estimate is read only where it could matter).
        let elements = layouts
            .iter()
            .fold(0usize, |n, l| n.saturating_add(l.element_count()));
        if super::memory::needed_bytes(elements) > 1 << 30
            && let Some(available) = super::memory::available_bytes()
            && let Some(message) = super::memory::shortfall(elements, available)
        {
            let what = if self.wire.segments.is_some() {
                "segments"
            } else {
                "elements"
            };
            return Err(ModelError::wire(what, message));
        }
        for (index, s) in self.supports.iter().enumerate() {
            let at = |e: ParameterError| ModelError::Support {
                index,
                what: e.field,
                message: e.message,
            };
            if let Some(p) = s.position {
                finite3("position", p).map_err(at)?;
            }
            if let Some(t) = s.release_time {
                crate::check::non_negative("release_time", t).map_err(at)?;
            }
            if let SupportKind::Spring(spring) = s.kind {
                spring.check().map_err(at)?;
                if s.release_time.is_some() {
                    return Err(at(ParameterError {
                        field: "release_time".into(),
                        message: "a spring support holds for the whole run; release_time is for \
                                  pin, clamp and fixed supports"
                            .into(),
                    }));
                }
            }
        }
        for (index, l) in self.loads.iter().enumerate() {
            let at = |e: ParameterError| ModelError::Load {
                index,
                what: e.field,
                message: e.message,
            };
            finite3("force", l.force).map_err(at)?;
            finite3("moment", l.moment).map_err(at)?;
        }
        if let Some(g) = self.gravity {
            finite3("acceleration", g).map_err(|e| ModelError::Gravity {
                field: e.field,
                message: e.message,
            })?;
        }
        for (index, rod) in self.rods.iter().enumerate() {
            rod.check().map_err(|e| ModelError::Rod {
                index,
                field: e.field,
                message: e.message,
            })?;
        }
        for (index, ground) in self.grounds.iter().enumerate() {
            ground.check().map_err(|e| ModelError::Ground {
                index,
                field: e.field,
                message: e.message,
            })?;
        }
        let contact = |e: ParameterError| ModelError::Contact {
            field: e.field,
            message: e.message,
        };
        self.contact.check().map_err(contact)?;
        let damping = self.beam_dampings(&layouts)?;
        // Each beam's name, first node and element count.
        let starts: Vec<(&str, usize, usize)> = (layouts.iter())
            .zip(super::beam::first_nodes(&layouts))
            .map(|(l, first)| (l.name.as_str(), first, l.element_count()))
            .collect();
        let place = |beam: &Option<String>, node: usize| -> Result<usize, (&'static str, String)> {
            let name = beam.as_deref().unwrap_or(super::WIRE);
            let Some(&(_, start, elements)) = starts.iter().find(|(n, ..)| *n == name) else {
                let names: Vec<&str> = starts.iter().map(|s| s.0).collect();
                return Err((
                    "beam",
                    format!("no beam is named \"{name}\" (there are {names:?})"),
                ));
            };
            if node > elements {
                let whose = if name == super::WIRE {
                    "the wire".to_string()
                } else {
                    format!("member \"{name}\"")
                };
                return Err((
                    "node",
                    format!("node {node} does not exist ({whose} has nodes 0..={elements})"),
                ));
            }
            Ok(start + node)
        };
        let mut supports = self.supports.clone();
        for (index, (s, beam)) in supports.iter_mut().zip(&self.support_beams).enumerate() {
            s.node = place(beam, s.node).map_err(|(what, message)| ModelError::Support {
                index,
                what: what.into(),
                message,
            })?;
        }
        let mut loads = self.loads.clone();
        for (index, (l, beam)) in loads.iter_mut().zip(&self.load_beams).enumerate() {
            l.node = place(beam, l.node).map_err(|(what, message)| ModelError::Load {
                index,
                what: what.into(),
                message,
            })?;
        }
        let model = Model::from_beams(layouts, supports, self.gravity, loads)?;
        members_clear_of_the_wire(&model)?;
        surface_stations_resolve_rods(&self.rods, &self.contact, &model).map_err(contact)?;
        if model.n_unknowns == 0 {
            return Err(ModelError::NothingToSolve);
        }
        let members = member_contacts(&self.members, &model)?;
        let mut grounded = Vec::new();
        for (index, names) in self.ground_beams.iter().enumerate() {
            let Some(names) = names else { continue };
            super::contact::check_ground_beams(names).map_err(|e| ModelError::Ground {
                index,
                field: e.field,
                message: e.message,
            })?;
            for name in names.iter().filter(|n| *n != super::WIRE) {
                let beam = (model.beam(name).map(|(b, _)| b))
                    .filter(|&b| b > 0)
                    .ok_or_else(|| ModelError::Ground {
                        index,
                        field: "beams".into(),
                        message: format!(
                            "no frame member is named \"{name}\" (there are {:?})",
                            model.beams[1..].iter().map(|b| &b.name).collect::<Vec<_>>()
                        ),
                    })?;
                grounded.push((self.rods.len() + index, beam));
            }
        }
        let mut rigid = self.rods;
        rigid.extend(self.grounds);
        Ok(model
            .with_contact(rigid, (members, grounded), self.contact)
            .with_damping(damping))
    }

    /// Each beam's damping (index: beam): its own, else the model's; each
    /// checked, a beam's own named as its scene field (`damping.…` of the
    /// wire or of the member).
    fn beam_dampings(&self, layouts: &[BeamLayout]) -> Result<Vec<Option<Damping>>, ModelError> {
        if let Some(d) = &self.damping {
            d.check().map_err(|e| ModelError::Damping {
                field: e.field,
                message: e.message,
            })?;
        }
        let mut out = vec![self.damping.clone(); layouts.len()];
        for (name, d) in &self.beam_damping {
            let Some(beam) = layouts.iter().position(|l| &l.name == name) else {
                let names: Vec<&str> = layouts.iter().map(|l| l.name.as_str()).collect();
                return Err(ModelError::Damping {
                    field: "beam".into(),
                    message: format!("no beam is named \"{name}\" (there are {names:?})"),
                });
            };
            d.check().map_err(|e| {
                let own = ModelError::wire(&format!("damping.{}", e.field), e.message);
                match beam {
                    0 => own,
                    _ => ModelError::Member {
                        index: beam - 1,
                        name: name.clone(),
                        error: Box::new(own),
                    },
                }
            })?;
            out[beam] = Some(d.clone());
        }
        Ok(out)
    }
}

/// Each member's contact with the wire, its stiffness resolved (the Hertz
/// law's from the member's and the wire's outer materials) and checked.
fn member_contacts(
    members: &[BeamBuilder],
    model: &Model,
) -> Result<Vec<MemberContact>, ModelError> {
    let outer = |beam: usize| {
        let el = model.beams[beam].elements.start;
        let section = &model.groups[model.group(el)].integration.section;
        let material = &section
            .layers
            .last()
            .expect("a section has layers")
            .material;
        (section.outer_radius(), material.model.elastic_constants())
    };
    let (wire_radius, wire_constants) = outer(0);
    let mut out = Vec::new();
    for (i, m) in members.iter().enumerate() {
        let at = |field: &str, message: String| ModelError::Member {
            index: i,
            name: m.name.clone(),
            error: Box::new(ModelError::wire(field, message)),
        };
        let (radius, constants) = outer(i + 1);
        let c = m.contact;
        c.check_law().map_err(|e| at(&e.field, e.message))?;
        let contact_stiffness = c.contact_stiffness.unwrap_or_else(|| {
            crate::model::contact::hertz_line_stiffness(
                constants,
                wire_constants,
                wire_radius,
                radius,
            )
        });
        let contact = MemberContact {
            beam: i + 1,
            radius,
            contact_stiffness,
            friction: c.friction,
            damping: c.damping,
        };
        contact.check().map_err(|e| at(&e.field, e.message))?;
        out.push(contact);
    }
    Ok(out)
}

/// Largest distance (m) between consecutive surface-law stations along the
/// wire: Gauss nodes inside an element and across element ends.
pub fn station_spacing(stations: usize, element_length: f64) -> f64 {
    let x = crate::math::quadrature::gauss_legendre_unit(stations).nodes;
    let inner = x.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    inner.max(2.0 * x[0]) * element_length
}

/// A rod thinner than the gap between surface test stations can pass
/// between them (measured: 10 cm tubes slipped through 1 m elements with 8
/// stations): at least two stations across a surface-law rod's diameter.
/// The line laws find their active zone and need no such rule.
fn surface_stations_resolve_rods(
    rods: &[Rod],
    settings: &ContactSettings,
    model: &Model,
) -> Result<(), ParameterError> {
    let longest = model.element_lengths().into_iter().fold(0.0, f64::max);
    let spacing = station_spacing(settings.stations, longest);
    let Some((i, r)) = rods
        .iter()
        .enumerate()
        .find(|(_, r)| r.law == ContactLaw::Surface && spacing > r.radius)
    else {
        return Ok(());
    };
    let needed = (settings.stations..=64).find(|&n| station_spacing(n, longest) <= r.radius);
    let advice = match needed {
        Some(n) => format!("use stations = {n} or more"),
        None => "use shorter elements (more wire.elements)".to_string(),
    };
    crate::check::refuse(
        "stations",
        format!(
            "test points {spacing:.3} m apart along the wire exceed rod[{i}].radius = {} m, so the rod \
             could pass between them; {advice}",
            r.radius
        ),
    )
}

/// Centerline points an element is sampled at when members are checked
/// against the wire.
const OVERLAP_SAMPLES: usize = 8;

/// The closest approach of two polylines (points in order), and the point
/// of `wire` that starts the segment where it happens: (distance m, point).
fn closest_approach(wire: &[[f64; 3]], line: &[[f64; 3]]) -> Option<(f64, [f64; 3])> {
    wire.windows(2)
        .flat_map(|w| {
            line.windows(2)
                .map(move |m| (super::beam::segment_distance(w[0], w[1], m[0], m[1]), w[0]))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

impl Model {
    /// The wire's centerline at the starting coordinates `q`, sampled for
    /// the overlap checks, and its outer radius (m).
    fn starting_wire(&self, q: &[f64]) -> (Vec<[f64; 3]>, f64) {
        let points = super::beam::centerline_points(self, self.wire(), q, OVERLAP_SAMPLES);
        let radius = (self.element(self.wire().elements.start).section).outer_radius();
        (points, radius)
    }

    /// The first rod whose surface the wire's surface enters, in the
    /// wire's starting shape, by more than a tenth of the wire's radius:
    /// (rod index, depth in m, the wire's centerline point there). A run
    /// that starts so begins with a contact force of the whole overlap —
    /// the geometry is at fault, not the contact law.
    ///
    /// A ground: the wire's surface below its plane by more than a tenth
    /// of the radius.
    pub fn rod_overlap_at_start(&self) -> Option<(usize, f64, [f64; 3])> {
        let contact = self.contact()?;
        let (wire, wire_radius) = self.starting_wire(&self.initial_coordinates());
        contact.rods.iter().enumerate().find_map(|(i, rod)| {
            if rod.is_ground() {
                let p = *wire
                    .iter()
                    .min_by(|a, b| rod.height(a).total_cmp(&rod.height(b)))?;
                let depth = wire_radius - rod.height(&p);
                return (depth > 0.1 * wire_radius).then_some((i, depth, p));
            }
            // An endless rod: a segment far beyond the wire on both sides.
            let half = rod.length.map_or(1e6, |l| 0.5 * l);
            let end = |s: f64| std::array::from_fn(|k| rod.center[k] + s * half * rod.axis[k]);
            let (d, p) = closest_approach(&wire, &[end(-1.0), end(1.0)])?;
            let depth = wire_radius + rod.radius - d;
            (depth > 0.1 * wire_radius).then_some((i, depth, p))
        })
    }
}

/// Every member clear of the wire where both start (their starting
/// shapes): a member whose surface overlaps the wire's would start in deep
/// contact, or inside it.
fn members_clear_of_the_wire(model: &Model) -> Result<(), ModelError> {
    if model.beams.len() < 2 {
        return Ok(());
    }
    let q = model.initial_coordinates();
    let (wire, wire_radius) = model.starting_wire(&q);
    for (i, member) in model.beams.iter().enumerate().skip(1) {
        let line = super::beam::centerline_points(model, member, &q, OVERLAP_SAMPLES);
        let clearance = wire_radius + model.element(member.elements.start).section.outer_radius();
        if let Some((d, p)) = closest_approach(&wire, &line)
            && d < clearance
        {
            return Err(ModelError::Member {
                index: i - 1,
                name: member.name.clone(),
                error: Box::new(ModelError::wire(
                    "origin",
                    format!(
                        "the member overlaps the wire where they start: their centerlines come {d:.4} m \
                         apart near [{:.3}, {:.3}, {:.3}] m, less than their radii's sum {clearance:.4} m",
                        p[0], p[1], p[2]
                    ),
                )),
            });
        }
    }
    Ok(())
}
