//! What a dynamic run keeps in memory of its written steps: the samples a
//! study or a plot reads (time, tip, energies), the first contact point's
//! motion and strains, and a few centerline shapes.

use ancf_core::element::{deformation_gradient, green_lagrange, position, shape_gradients};
use ancf_core::loads::contact_record::ContactPoint;
use ancf_core::model::Model;
use ancf_core::solve::dynamics::{Energies, State};

/// The written steps of a run (every `output.every`-th step and the last).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct History {
    /// Times, s.
    pub time: Vec<f64>,
    /// Energies, J.
    pub energies: Vec<Energies>,
    /// The last node's position, m.
    #[serde(default)]
    pub tip: Vec<[f64; 3]>,
    /// Time, vertical displacement and E_xx, E_yy, E_zz of the first contact point.
    pub contact_point: Vec<[f64; 5]>,
    /// Centerline shapes (time, x–z points) at a few instants.
    pub shapes: Vec<(f64, Vec<(f64, f64)>)>,
}

impl History {
    /// Record a written step.
    pub fn push(&mut self, model: &Model, s: &State, e: &Energies) {
        self.time.push(s.time);
        self.energies.push(*e);
        self.tip
            .push(model.node_position(&s.q, model.wire().last_node()));
    }

    /// Record the first contact point's displacement and strains at `s`.
    pub fn push_contact_point(&mut self, model: &Model, s: &State, cp: &ContactPoint) {
        let (pos, strains) = point_state(model, &s.q, cp);
        let (p0, _) = point_state(model, &model.reference, cp);
        self.contact_point
            .push([s.time, pos[2] - p0[2], strains[0], strains[1], strains[2]]);
    }

    /// Record the centerline's shape at `s` (once per instant).
    pub fn push_shape(&mut self, model: &Model, s: &State) {
        if self.shapes.last().is_none_or(|(t, _)| *t != s.time) {
            self.shapes.push((s.time, centerline(model, &s.q)));
        }
    }
}

/// The wire's centerline in the x–z plane, 8 points per element.
fn centerline(model: &Model, q: &[f64]) -> Vec<(f64, f64)> {
    let mut pts = Vec::new();
    for el in model.wire().elements.clone() {
        let l = model.element(el).length;
        let e = model.element_coordinates(q, el);
        for k in usize::from(el > 0)..=8 {
            let p = position(&e, k as f64 / 8.0, 0.0, 0.0, l);
            pts.push((p[0], p[2]));
        }
    }
    pts
}

/// Position and E_xx, E_yy, E_zz of a material point.
fn point_state(model: &Model, q: &[f64], cp: &ContactPoint) -> ([f64; 3], [f64; 3]) {
    let l = model.element(cp.element).length;
    let e = model.element_coordinates(q, cp.element);
    let p = position(&e, cp.xi, cp.y, cp.z, l);
    let eps = green_lagrange(&deformation_gradient(
        &e,
        &shape_gradients(cp.xi, cp.y, cp.z, l),
    ));
    (p, [eps[0], eps[1], eps[2]])
}
