//! The beams of a model: the wire (beam 0) and any frame members, each a
//! chain of the same element with its own mesh, section and placement.
//!
//! All beams share one coordinate vector, node after node: beam 0's nodes
//! first, then each member's. Element `el` couples nodes `el` and `el + 1`
//! — the numbering every kernel, the pattern and the mass product rely on —
//! so between two beams one element index is a *gap*: it belongs to no
//! group, no kernel evaluates it, and its two nodes (the last of one beam,
//! the first of the next) are coupled by nothing. The Newton matrix stays
//! block tridiagonal by nodes (with zero blocks at the gaps): the wire's
//! band and block solvers run unchanged.

use crate::element::ElementIntegration;
use std::ops::Range;

/// One beam of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    /// Its name: "wire" for beam 0, a member's own otherwise.
    pub name: String,
    /// Its elements (indices into the model's elements).
    pub elements: Range<usize>,
    /// Its nodes (indices into the model's nodes; one more than elements).
    pub nodes: Range<usize>,
    /// Unit axis in the reference configuration.
    pub axis: [f64; 3],
    /// Section direction y in the reference configuration.
    pub section_y: [f64; 3],
    /// Section direction z in the reference configuration.
    pub section_z: [f64; 3],
}

impl Beam {
    /// The model's node of this beam's node `local` (0 … its elements).
    pub fn node(&self, local: usize) -> usize {
        self.nodes.start + local
    }

    /// Its last node (the model's index).
    pub fn last_node(&self) -> usize {
        self.nodes.end - 1
    }
}

/// A beam as the model is made from it: its elements by groups of equal
/// length (integration, count), where it starts and its direction.
#[derive(Clone, Debug)]
pub struct BeamLayout {
    /// Its name.
    pub name: String,
    /// Its element groups in order: integration (section, quadrature and
    /// element length) and element count.
    pub groups: Vec<(ElementIntegration, usize)>,
    /// Its first node (m).
    pub origin: [f64; 3],
    /// Its direction (any length but zero).
    pub direction: [f64; 3],
}
