//! The wire's elements as groups of equal length: a uniform mesh is one
//! group, a graded mesh (fine where the wire meets a rod, coarse elsewhere)
//! one group per region. Everything that depends on the element length — the
//! integration, the mass matrix and its non-zeros — is computed once per
//! group; the pre-integrated section tensors are the same for all of them.

use std::ops::Range;

use crate::element::{ElementIntegration, ElementMatrix};
use crate::model::mass_product::PairedMass;

/// Consecutive elements of one length.
#[derive(Clone, Debug)]
pub struct ElementGroup {
    /// The elements of the group (indices into the model's elements).
    pub elements: Range<usize>,
    /// Their integration (its `length` is the group's element length, m).
    pub integration: ElementIntegration,
    /// Their element mass matrix (kg), row-major 24×24.
    pub mass: ElementMatrix,
    /// The element mass matrix's non-zero node-vector couplings (i, j, m_ij),
    /// i, j ∈ 0..8 (the matrix is m ⊗ I₃). For a section symmetric about its
    /// centre 40 of the 64 are exactly zero (∫y dA = 0 couples r_y with
    /// nothing but r_y), so M x skips them.
    pub(crate) mass_nonzeros: Vec<(usize, usize, f64)>,
    /// The same as the node-tile product's coefficients, when the section
    /// is symmetric about its centre (see `mass_product`), built once here
    /// rather than at every product.
    pub(crate) paired_mass: Option<PairedMass>,
    /// Arc length (m, reference configuration) from its beam's first node
    /// to the group's first node.
    pub start: f64,
}

impl ElementGroup {
    pub(crate) fn new(integration: ElementIntegration, elements: Range<usize>, start: f64) -> Self {
        let mass = integration.mass_matrix();
        let mass_nonzeros: Vec<_> = (0..8)
            .flat_map(|i| (0..8).map(move |j| (i, j)))
            .map(|(i, j)| (i, j, mass[(3 * i) * 24 + 3 * j]))
            .filter(|&(_, _, m)| m != 0.0)
            .collect();
        let paired_mass = PairedMass::new(&mass_nonzeros);
        ElementGroup {
            elements,
            integration,
            mass,
            paired_mass,
            mass_nonzeros,
            start,
        }
    }

    /// Reference arc length (m) of the group's node `k` (0 = its first).
    pub fn arc(&self, k: usize) -> f64 {
        self.start + self.integration.length * k as f64
    }
}

/// One region of a graded mesh: `elements` equal elements over `length` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Reference length of the region (m).
    pub length: f64,
    /// Number of elements in it.
    pub elements: usize,
}
