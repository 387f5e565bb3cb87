//! Building a wire in code, without a scene file (issue 15): a few readable
//! lines give the same `Model` a scene would.
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

use super::contact::{ContactSettings, Rod};
use super::damping::Damping;
use super::{Model, ModelError, PointLoad, Segment, Support, SupportKind};
use crate::element::ElementIntegration;
use crate::material::Material;
use crate::section::Section;

/// A wire described in code; [`WireBuilder::build`] checks it and makes the [`Model`].
#[derive(Clone, Debug)]
pub struct WireBuilder {
    length: f64,
    elements: usize,
    /// A graded mesh (replaces `length` and `elements`).
    segments: Option<Vec<Segment>>,
    origin: [f64; 3],
    direction: [f64; 3],
    layers: Vec<(Material, f64)>,
    axial_order: usize,
    section_order: usize,
    supports: Vec<Support>,
    gravity: Option<[f64; 3]>,
    loads: Vec<PointLoad>,
    rods: Vec<Rod>,
    contact: ContactSettings,
    damping: Option<Damping>,
}

impl WireBuilder {
    /// A straight wire of `length` (m) in `elements` elements, along x from
    /// the origin, with the scene defaults (axial and section order 3).
    pub fn new(length: f64, elements: usize) -> Self {
        WireBuilder {
            length,
            elements,
            segments: None,
            origin: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            layers: Vec::new(),
            axial_order: super::DEFAULT_AXIAL_ORDER,
            section_order: super::DEFAULT_SECTION_ORDER,
            supports: Vec::new(),
            gravity: None,
            loads: Vec::new(),
            rods: Vec::new(),
            contact: ContactSettings::default(),
            damping: None,
        }
    }

    /// A graded mesh: the wire is the `segments` in order, each with its
    /// own element length (fine where the wire meets a rod, coarse
    /// elsewhere). Replaces the length and element count of [`WireBuilder::new`].
    pub fn graded(mut self, segments: &[Segment]) -> Self {
        self.length = segments.iter().map(|s| s.length).sum();
        self.elements = segments.iter().map(|s| s.elements).sum();
        self.segments = Some(segments.to_vec());
        self
    }

    /// Where the wire starts (m) and its direction (normalised).
    pub fn placed(mut self, origin: [f64; 3], direction: [f64; 3]) -> Self {
        self.origin = origin;
        self.direction = direction;
        self
    }

    /// The next concentric layer outward, up to `outer_radius` (m).
    pub fn layer(mut self, material: Material, outer_radius: f64) -> Self {
        self.layers.push((material, outer_radius));
        self
    }

    /// Gauss points along the element and the ring-rule order of the section.
    pub fn quadrature(mut self, axial: usize, section: usize) -> Self {
        self.axial_order = axial;
        self.section_order = section;
        self
    }

    /// A support at `node` (0 … elements) holding it in its reference place.
    pub fn support(mut self, node: usize, kind: SupportKind) -> Self {
        self.supports.push(Support::new(node, kind));
        self
    }

    /// A support given in full (position, release time).
    pub fn support_with(mut self, support: Support) -> Self {
        self.supports.push(support);
        self
    }

    /// Gravity acceleration, m/s².
    pub fn gravity(mut self, g: [f64; 3]) -> Self {
        self.gravity = Some(g);
        self
    }

    /// A constant force (N) at a node.
    pub fn load(mut self, node: usize, force: [f64; 3]) -> Self {
        self.loads.push(PointLoad { node, force });
        self
    }

    /// A rigid rod the wire may touch.
    pub fn rod(mut self, rod: Rod) -> Self {
        self.rods.push(rod);
        self
    }

    /// Contact integration and friction regularization (defaults as in scenes).
    pub fn contact_settings(mut self, settings: ContactSettings) -> Self {
        self.contact = settings;
        self
    }

    /// Kelvin–Voigt or Rayleigh damping.
    pub fn damping(mut self, damping: Damping) -> Self {
        self.damping = Some(damping);
        self
    }

    /// Checks the description and builds the model.
    pub fn build(self) -> Result<Model, ModelError> {
        let fail = |what: &str, message: String| {
            Err(ModelError::Wire {
                what: what.into(),
                message,
            })
        };
        if !(self.length.is_finite() && self.length > 0.0) {
            return fail("length", format!("must be > 0 m, got {}", self.length));
        }
        if self.elements == 0 {
            return fail("elements", "need at least one element".into());
        }
        if self.layers.is_empty() {
            return fail("layers", "a wire needs at least one layer".into());
        }
        let mut inner = 0.0;
        let mut section_layers = Vec::new();
        for (i, (material, outer)) in self.layers.into_iter().enumerate() {
            if !(outer.is_finite() && outer > inner) {
                return fail(
                    &format!("layer {i}"),
                    format!(
                        "outer radius {outer} m must exceed the layer's inner radius {inner} m"
                    ),
                );
            }
            section_layers.push((inner, outer, material));
            inner = outer;
        }
        for (i, rod) in self.rods.iter().enumerate() {
            let restitution_ok = rod
                .damping
                .is_none_or(|d| d.restitution() > 0.0 && d.restitution() <= 1.0);
            if !(rod.radius > 0.0
                && rod.contact_stiffness > 0.0
                && rod.friction >= 0.0
                && restitution_ok)
            {
                return fail(
                    &format!("rod {i}"),
                    format!(
                        "radius and stiffness must be > 0, friction ≥ 0 and restitution in (0, 1], got {rod:?}"
                    ),
                );
            }
        }
        let section = Section::circular(&section_layers, self.section_order);
        let element = ElementIntegration::new(
            self.length / self.elements as f64,
            self.axial_order,
            section,
        );
        let model = match &self.segments {
            Some(segments) => Model::graded(
                element,
                segments,
                self.origin,
                self.direction,
                self.supports,
                self.gravity,
                self.loads,
            ),
            None => Model::new(
                element,
                self.elements,
                self.origin,
                self.direction,
                self.supports,
                self.gravity,
                self.loads,
            ),
        };
        Ok(model?
            .with_rods(self.rods, self.contact)
            .with_damping(self.damping))
    }
}
