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

use crate::element::{ElementIntegration, position};
use crate::math::vec3::{dot, sub};
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

impl BeamLayout {
    /// Its element count, every group's.
    pub fn element_count(&self) -> usize {
        self.groups.iter().map(|g| g.1).sum()
    }
}

/// The longest name a member may have, in bytes.
pub const MAX_NAME_LEN: usize = 64;

/// Whether `name` may name a frame member: it becomes part of file names
/// (`final_nodes_NAME.csv`) and CSV headers, so only letters, digits, `_`
/// and `-`, 1 to [`MAX_NAME_LEN`] of them, and not "wire" (the wire's own).
/// `Err` says what is wrong, the name quoted with control characters
/// escaped.
pub fn check_member_name(name: &str) -> Result<(), String> {
    let shown = name.escape_debug().to_string();
    if name.is_empty() {
        return Err("a member's name must not be empty".into());
    }
    if name == super::WIRE {
        return Err("\"wire\" is the wire's own name; name the member otherwise".into());
    }
    if name.len() > MAX_NAME_LEN {
        return Err(format!(
            "\"{}…\" is {} bytes long; a member's name has at most {MAX_NAME_LEN}",
            shown.chars().take(32).collect::<String>(),
            name.len()
        ));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(format!(
            "\"{shown}\" holds {:?}: a member's name becomes part of file names and CSV \
             headers, so it takes only letters, digits, '_' and '-'",
            c
        ));
    }
    Ok(())
}

/// Each beam's first node (and first element) in the model: one past the
/// previous beam's last node, the index between them being its gap.
pub fn first_nodes(layouts: &[BeamLayout]) -> Vec<usize> {
    let mut next = 0;
    (layouts.iter())
        .map(|l| {
            let first = next;
            next += l.element_count() + 1;
            first
        })
        .collect()
}

/// Points along beam `beam`'s centerline at coordinates `q`, `per_element`
/// to an element (from each element's first node on) and its last node.
pub fn centerline_points(
    model: &super::Model,
    beam: &Beam,
    q: &[f64],
    per_element: usize,
) -> Vec<[f64; 3]> {
    let mut points = Vec::new();
    for el in beam.elements.clone() {
        let e = model.element_coordinates(q, el);
        let l = model.element(el).length;
        for k in 0..per_element {
            points.push(position(&e, k as f64 / per_element as f64, 0.0, 0.0, l));
        }
    }
    points.push(model.node_position(q, beam.last_node()));
    points
}

/// The distance (m) between the segments from `p0` to `p1` and from `q0`
/// to `q1` (closest points clamped to both segments).
pub fn segment_distance(p0: [f64; 3], p1: [f64; 3], q0: [f64; 3], q1: [f64; 3]) -> f64 {
    let (d1, d2, r) = (sub(p1, p0), sub(q1, q0), sub(p0, q0));
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let (c, b) = (dot(d1, r), dot(d1, d2));
    let denom = a * e - b * b;
    // The closest point on the first segment's line to the second's, clamped.
    let mut s = if a > 0.0 && denom > 1e-14 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = if e > 0.0 { (b * s + f) / e } else { 0.0 };
    if t < 0.0 {
        t = 0.0;
        s = if a > 0.0 {
            (-c / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    } else if t > 1.0 {
        t = 1.0;
        s = if a > 0.0 {
            ((b - c) / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    }
    let d: [f64; 3] = std::array::from_fn(|k| p0[k] + s * d1[k] - q0[k] - t * d2[k]);
    dot(d, d).sqrt()
}
