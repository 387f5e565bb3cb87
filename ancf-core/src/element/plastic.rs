//! The element's yielding layers: the section points of a layer whose
//! material is elastic–plastic, integrated one by one with the history
//! each point carries.
//!
//! **Formulation.** Beam-type J2 (see
//! [`crate::material::beam_plasticity`]) in the stresses a beam carries: at
//! each point the Green–Lagrange strain's E₁₁ and engineering shears
//! γ₁₂ = 2E₁₂, γ₁₃ = 2E₁₃ are split additively into elastic and plastic
//! parts (small strain, large rotation: Sugiyama & Shabana, Gerstmayr),
//! the second Piola–Kirchhoff S₁₁, S₁₂, S₁₃ come from the return map, and
//! the transverse S₂₂, S₃₃, S₂₃ stay elastic with the layer's section law
//! (the diagonal E, E, G of the centerline split, see
//! [`crate::material::Locking::Centerline`]). Plastic flow therefore never
//! meets the element's linear transverse field: the fully parameterized
//! element cannot lock through plastic incompressibility, which a full
//! J2 on all six stresses would invite. The layer's centerline remainder
//! (Poisson's coupling) stays elastic: in uniaxial stress it carries no
//! axial force, yielding or not, since the transverse strains it ties to
//! the axial one keep the ratio −ν.
//!
//! **History.** A point's [`PlasticState`] is read, never written, while a
//! step iterates: the force and its consistent tangent come from the
//! return map at the iterate from the state of the last accepted step.
//! [`plastic_step`] computes the states to keep once a step is accepted,
//! with the plastic work of the step (trapezoid rule, so that elastic
//! energy plus plastic work balance the stresses' work).
//!
//! **Cost.** Elastic layers keep their pre-integrated kernels; only the
//! yielding layers' points are visited here, at the ring order
//! [`crate::section::PLASTIC_LAYER_ORDER`] at least.

use super::{
    ElementIntegration, ElementMatrix, ElementVector, add_point_stress, deformation_gradient,
    green_lagrange, shape_gradients,
};
use crate::material::Law;
use crate::material::beam_plasticity::{BeamPlasticity, PlasticState, PointResponse};
use crate::math::quadrature::SectionPoint;
use nalgebra::{Matrix6, Vector6};

/// Section points of a layer whose beam stresses yield.
#[derive(Clone, Debug)]
pub struct PlasticGroup {
    /// The layer's points (y, z, weight), m and m².
    pub points: Vec<SectionPoint>,
    /// Its plasticity.
    pub law: BeamPlasticity,
    /// Its elastic section law: the transverse stresses' (its diagonal),
    /// and Kelvin–Voigt damping's.
    pub elastic: Law,
}

/// The history a yielding element's points are evaluated from, and the
/// step it is evaluated for.
#[derive(Clone, Copy, Debug, Default)]
pub struct PlasticInput<'a> {
    /// One state per yielding point — axial station after station, group
    /// after group, point after point (see
    /// [`ElementIntegration::plastic_points`]); empty: the virgin state.
    pub states: &'a [PlasticState],
    /// The step (s), for the rate law; `None`: rate-independent (statics).
    pub dt: Option<f64>,
}

/// What an accepted step did at an element's yielding points.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlasticStep {
    /// The step's plastic work, J.
    pub work: f64,
    /// The largest equivalent plastic strain after it …
    pub max_equivalent: f64,
    /// … and the axial coordinate ξ ∈ [0, 1] of its point.
    pub max_at: f64,
}

/// The elastic diagonal (E₂₂, E₃₃, G₂₃) of a layer's section law, Pa.
fn transverse_moduli(elastic: &Law) -> [f64; 3] {
    match elastic {
        Law::Linear(d) => [d[(1, 1)], d[(2, 2)], d[(3, 3)]],
        _ => unreachable!("an elastic-plastic layer's section law is linear"),
    }
}

/// The beam strains (E₁₁, γ₁₂, γ₁₃) of a Voigt strain (11, 22, 33, 23, 13, 12).
fn beam_strain(eps: &Vector6<f64>) -> [f64; 3] {
    [eps[0], eps[5], eps[4]]
}

/// Where the beam stresses and their tangent sit in Voigt order.
const BEAM_VOIGT: [usize; 3] = [0, 5, 4];

/// The Voigt stress and tangent at a point from its beam response and the
/// transverse moduli.
fn point_stress(
    eps: &Vector6<f64>,
    response: &PointResponse,
    transverse: [f64; 3],
) -> (Vector6<f64>, Matrix6<f64>) {
    let mut sigma = Vector6::zeros();
    let mut d = Matrix6::zeros();
    for (a, &va) in BEAM_VOIGT.iter().enumerate() {
        sigma[va] = response.stress[a];
        for (b, &vb) in BEAM_VOIGT.iter().enumerate() {
            d[(va, vb)] = response.tangent[a][b];
        }
    }
    for (i, c) in transverse.iter().enumerate() {
        sigma[i + 1] = c * eps[i + 1];
        d[(i + 1, i + 1)] = *c;
    }
    (sigma, d)
}

impl ElementIntegration {
    /// The yielding points of one element: axial stations times the
    /// plastic groups' points (0 without a yielding layer).
    pub fn plastic_points(&self) -> usize {
        self.axial.nodes.len()
            * self
                .plan
                .plastic
                .iter()
                .map(|g| g.points.len())
                .sum::<usize>()
    }

    /// Visit every yielding point — its index in the element's history,
    /// its axial coordinate ξ, the shape gradients there, its weight (m³)
    /// and its group.
    fn for_each_plastic_point(
        &self,
        mut visit: impl FnMut(usize, f64, &[[f64; 3]; 8], f64, &PlasticGroup),
    ) {
        let l = self.length;
        let mut index = 0;
        for (xi, wx) in self.axial.nodes.iter().zip(&self.axial.weights) {
            for group in &self.plan.plastic {
                for p in &group.points {
                    let g = shape_gradients(*xi, p.y, p.z, l);
                    visit(index, *xi, &g, wx * l * p.weight, group);
                    index += 1;
                }
            }
        }
    }

    /// The yielding layers' force (added to `q`), consistent tangent (added
    /// to `k`) and incremental potential (J, see
    /// [`BeamPlasticity::incremental_energy`]; the stored energy at the
    /// states of an accepted step) at `e` from the history `input`.
    pub(crate) fn add_plastic(
        &self,
        e: &ElementVector,
        input: PlasticInput<'_>,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let virgin = PlasticState::default();
        let mut energy = 0.0;
        self.for_each_plastic_point(|index, _, g, w, group| {
            let old = input.states.get(index).unwrap_or(&virgin);
            let f = deformation_gradient(e, g);
            let eps = green_lagrange(&f);
            let strain = beam_strain(&eps);
            let response = group.law.respond(strain, old, input.dt);
            let transverse = transverse_moduli(&group.elastic);
            let (sigma, d) = point_stress(&eps, &response, transverse);
            add_point_stress(&f, g, w, &sigma, k.as_deref_mut().map(|k| (&d, k)), q);
            let elastic_transverse: f64 = (0..3)
                .map(|i| 0.5 * transverse[i] * eps[i + 1] * eps[i + 1])
                .sum();
            let potential = group.law.incremental_energy(strain, old, &response.state);
            energy += w * (potential + elastic_transverse);
        });
        energy
    }

    /// The states the yielding points of an element at `e` keep once a step
    /// from `input` is accepted, written over `out` (one per point), and
    /// what the step did there.
    pub fn plastic_step(
        &self,
        e: &ElementVector,
        input: PlasticInput<'_>,
        out: &mut [PlasticState],
    ) -> PlasticStep {
        let virgin = PlasticState::default();
        let mut step = PlasticStep::default();
        self.for_each_plastic_point(|index, xi, g, w, group| {
            let old = input.states.get(index).unwrap_or(&virgin);
            let eps = green_lagrange(&deformation_gradient(e, g));
            let new = group.law.respond(beam_strain(&eps), old, input.dt).state;
            step.work += w * group.law.plastic_work(old, &new);
            if new.equivalent > step.max_equivalent {
                step.max_equivalent = new.equivalent;
                step.max_at = xi;
            }
            out[index] = new;
        });
        step
    }
}
