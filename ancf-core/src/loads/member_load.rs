//! A frame member's internal loads over a run, as a designer sizes a tube:
//! the largest bending moment and the largest von Mises stress at its
//! outer fiber, where along it and when.
//!
//! They are taken where a finite-element program takes member forces: at
//! the element ends, from each element's generalized internal forces — the
//! resultants that hold its nodes in equilibrium, which converge with the
//! nodal values. (The centerline's curvature κ = |r_x × r_xx| / |r_x|³ is
//! no measure of this element's moment: on a propped tube it drifted from
//! −7 % to +32 % of beam theory's clamp moment as 16 elements became 128,
//! where the end resultants stay within 0.1 %.) Stresses follow beam
//! theory at the outer radius, small strains.

use crate::forces::plastic::History;
use crate::math::vec3::{cross, dot, norm};
use crate::model::{Beam, Model};

/// A member's largest internal loads so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MemberRecord {
    /// The largest bending moment (N m) …
    pub max_bending_moment: f64,
    /// … its time (s) …
    pub max_bending_moment_time: f64,
    /// … and where: the distance from the member's first node (m, along
    /// it unstretched).
    pub max_bending_moment_at: f64,
    /// The largest von Mises stress at the outer fiber (Pa) …
    pub max_von_mises: f64,
    /// … its time (s) …
    pub max_von_mises_time: f64,
    /// … and where (m from the member's first node).
    pub max_von_mises_at: f64,
    /// The largest bending moment (N m) and von Mises stress (Pa) in the
    /// first impact: the [`crate::loads::rod_load::FIRST_IMPACT_WINDOW`]
    /// from the wire's first contact with the member (0: never touched).
    /// What a wire does after its first blow can depend on details a mesh
    /// or a time step resolves differently; the first blow converges.
    #[serde(default)]
    pub first_impact_max_bending_moment: f64,
    /// (The first impact's von Mises stress, Pa.)
    #[serde(default)]
    pub first_impact_max_von_mises: f64,
    /// The largest utilization M_Ed / M_N,Rd of the member's section by
    /// EN 1993-1-1 ([`crate::loads::design_check`]; ≤ 1 holds), for a tube
    /// or solid circle whose material gives a yield stress (`None`
    /// otherwise) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub utilization: Option<f64>,
    /// … its time (s) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub utilization_time: Option<f64>,
    /// … and where (m from the member's first node).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub utilization_at: Option<f64>,
}

/// The resultants element `el` carries at its end `end` (0: first node,
/// 1: second) at coordinates `q` (a yielding layer's stresses from the
/// history `plastic`): axial force N (N), bending moment |M|
/// (N m) and torque T (N m), from its generalized internal forces (what
/// the element exerts on the node): a rotation δθ of the node's triad moves
/// each gradient r_i by δθ × r_i, so the node's moment is Σ_i r_i × Q_{r_i}
/// and its force the Q on r; split along and across the unit tangent.
pub fn end_resultants(
    model: &Model,
    el: usize,
    end: usize,
    q: &[f64],
    plastic: History<'_>,
) -> (f64, f64, f64) {
    let e = model.element_coordinates(q, el);
    let mut qe = [0.0; 24];
    (model.element(el)).evaluate_with(&e, plastic.element(el), &mut qe, None);
    let base = 12 * end;
    let v = |x: &[f64], at: usize| [x[at], x[at + 1], x[at + 2]];
    let force = v(&qe, base);
    let mut moment = [0.0; 3];
    for i in 0..3 {
        let r = v(&e, base + 3 + 3 * i);
        let m = cross(r, v(&qe, base + 3 + 3 * i));
        moment = std::array::from_fn(|k| moment[k] + m[k]);
    }
    let rx = v(&e, base + 3);
    let t = rx.map(|x| x / norm(rx));
    let torque = dot(moment, t);
    let bending: [f64; 3] = std::array::from_fn(|k| moment[k] - torque * t[k]);
    (dot(force, t).abs(), norm(bending), torque.abs())
}

/// The outer fiber's von Mises stress (Pa) under axial force `n` (N),
/// bending moment `m` and torque `t` (N m) in `section`: σ = E_o (N / EA +
/// M R / EI), τ = G_o T R / GJ, √(σ² + 3τ²), E_o and G_o the outer layer's.
pub fn von_mises(section: &crate::section::Section, n: f64, m: f64, t: f64) -> f64 {
    let gj: f64 = (section.layers.iter())
        .map(|l| {
            l.material.model.small_strain_shear_modulus()
                * (l.second_moments[0] + l.second_moments[1])
        })
        .sum();
    let outer = section.layers.last().expect("a section has a layer");
    let model = &outer.material.model;
    let (e, g) = (
        model.small_strain_youngs_modulus(),
        model.small_strain_shear_modulus(),
    );
    let r = section.outer_radius();
    let sigma = e * (n / section.axial_stiffness() + m * r / section.bending_stiffness());
    let tau = g * t * r / gj;
    (sigma * sigma + 3.0 * tau * tau).sqrt()
}

impl MemberRecord {
    /// Observe member `beam` of `model` at coordinates `q`, time `t` (s),
    /// the wire having first touched it at `first_contact` (s; `None`:
    /// not yet).
    ///
    /// Returns the member's largest bending moment at this state (N m).
    pub fn observe(
        &mut self,
        model: &Model,
        beam: &Beam,
        (q, plastic): (&[f64], History<'_>),
        t: f64,
        first_contact: Option<f64>,
    ) -> f64 {
        let mut largest: f64 = 0.0;
        let start = model.node_arc(beam.nodes.start);
        let resistance = crate::loads::design_check::section_resistance(
            &model.element(beam.elements.start).section,
        );
        let first_impact = first_contact
            .is_some_and(|t1| (t1..=t1 + crate::loads::rod_load::FIRST_IMPACT_WINDOW).contains(&t));
        for el in beam.elements.clone() {
            let section = &model.element(el).section;
            for end in 0..2 {
                let (n, m, torque) = end_resultants(model, el, end, q, plastic);
                largest = largest.max(m);
                let stress = von_mises(section, n, m, torque);
                let at = model.node_arc(el + end) - start;
                if m > self.max_bending_moment {
                    self.max_bending_moment = m;
                    self.max_bending_moment_time = t;
                    self.max_bending_moment_at = at;
                }
                if stress > self.max_von_mises {
                    self.max_von_mises = stress;
                    self.max_von_mises_time = t;
                    self.max_von_mises_at = at;
                }
                if let Some(r) = resistance {
                    let u = r.utilization(n, m);
                    if self.utilization.is_none_or(|max| u > max) {
                        self.utilization = Some(u);
                        self.utilization_time = Some(t);
                        self.utilization_at = Some(at);
                    }
                }
                if first_impact {
                    self.first_impact_max_bending_moment =
                        self.first_impact_max_bending_moment.max(m);
                    self.first_impact_max_von_mises = self.first_impact_max_von_mises.max(stress);
                }
            }
        }
        largest
    }
}
