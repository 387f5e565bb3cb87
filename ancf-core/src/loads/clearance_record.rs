//! How close the wire came to a clearance zone over a run: the smallest
//! distance of its surface, when and where, and whether it entered.

use crate::element::position;
use crate::model::Model;
use crate::model::clearance::ClearanceZone;

/// Points sampled per element (at ξ = 0, ¼, ½, ¾; the last node closes the
/// wire): a quarter element apart, a few cm on the meshes that resolve a
/// falling span.
pub const SAMPLES_PER_ELEMENT: usize = 4;

/// A zone's record so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClearanceRecord {
    /// The smallest distance (m) between the wire's surface (centerline
    /// less the outer radius) and the zone; negative: the depth it entered
    /// (`None` before the first observation).
    pub min_distance: Option<f64>,
    /// Its time (s).
    pub time: f64,
    /// The centerline point it was measured at (m).
    pub position: [f64; 3],
    /// Whether the wire's surface was ever inside the zone.
    pub entered: bool,
}

impl ClearanceRecord {
    /// Observe the wire of `model` at coordinates `q` and time `time` (s).
    pub fn observe(&mut self, zone: &ClearanceZone, model: &Model, q: &[f64], time: f64) {
        let radius = model.section().outer_radius();
        let mut visit = |p: [f64; 3]| {
            let d = zone.distance(p) - radius;
            if self.min_distance.is_none_or(|m| d < m) {
                self.min_distance = Some(d);
                self.time = time;
                self.position = p;
            }
            self.entered |= d < 0.0;
        };
        let wire = model.wire();
        for el in wire.elements.clone() {
            let e = model.element_coordinates(q, el);
            let l = model.element(el).length;
            for k in 0..SAMPLES_PER_ELEMENT {
                visit(position(
                    &e,
                    k as f64 / SAMPLES_PER_ELEMENT as f64,
                    0.0,
                    0.0,
                    l,
                ));
            }
        }
        visit(model.node_position(q, wire.last_node()));
    }
}
