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
    /// The largest distance of its points from the centerline (m).
    pub reach: f64,
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

/// A point's force w Bᵀσ for a stress with only its beam components
/// (S₁₁, S₁₂, S₁₃), added to `q`: with S the symmetric 3 × 3 stress,
/// q_{3i+k} += w Σ_ab F_ka S_ab ∂s_i/∂x_b, (F S) formed once — what the
/// B-matrix form gives, at a fraction of its work.
fn add_beam_stress(
    f: &[[f64; 3]; 3],
    g: &[[f64; 3]; 8],
    w: f64,
    [s11, s12, s13]: [f64; 3],
    q: &mut ElementVector,
) {
    let fs: [[f64; 3]; 3] = std::array::from_fn(|k| {
        [
            f[k][0] * s11 + f[k][1] * s12 + f[k][2] * s13,
            f[k][0] * s12,
            f[k][0] * s13,
        ]
    });
    for (i, gi) in g.iter().enumerate() {
        for (k, row) in fs.iter().enumerate() {
            q[3 * i + k] += w * (row[0] * gi[0] + row[1] * gi[1] + row[2] * gi[2]);
        }
    }
}

/// Whether every point of `group` at a station with centerline gradient
/// a, x-derivatives b, c of r_y, r_z and section gradients r_y, r_z stays
/// inside the initial yield surface, by bounds over its disc ρ ≤ R: with
/// r_x = a + y b + z c,
/// |E₁₁| ≤ |½(|a|² − 1)| + R √((a·b)² + (a·c)²) + ½ R² (|b|² + |c|²)
/// and |γ₁₂| ≤ |a·r_y| + R √((b·r_y)² + (c·r_y)²) (γ₁₃ alike with r_z).
fn elastic_over_disc(
    group: &PlasticGroup,
    (a, b, c): ([f64; 3], [f64; 3], [f64; 3]),
    (ry, rz): ([f64; 3], [f64; 3]),
) -> bool {
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let r = group.reach;
    let axial = (0.5 * (dot(a, a) - 1.0)).abs()
        + r * dot(a, b).hypot(dot(a, c))
        + 0.5 * r * r * (dot(b, b) + dot(c, c));
    let shear = |s: [f64; 3]| dot(a, s).abs() + r * dot(b, s).hypot(dot(c, s));
    let [e, g, _] = group.law.beam_moduli();
    let (sigma, t2, t3) = (e * axial, g * shear(ry), g * shear(rz));
    sigma * sigma + 3.0 * (t2 * t2 + t3 * t3) <= group.law.yield_stress * group.law.yield_stress
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

    /// The yielding layers' share beyond their elastic law — which the plan
    /// pre-integrates with the other layers — at `e` from the history
    /// `input`: the force Σ w Bᵀ(σ − C ε) (added to `q`), its consistent
    /// tangent (added to `k`) and the potential's excess over ½ εᵀC ε (J),
    /// at the points where σ differs from C ε (only the beam stresses can).
    /// A point still virgin whose trial stress stays inside the yield
    /// surface adds nothing and costs its three beam strains.
    pub(crate) fn add_plastic(
        &self,
        e: &ElementVector,
        input: PlasticInput<'_>,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let virgin = PlasticState::default();
        let mut energy = 0.0;
        self.for_each_plastic_strain(
            e,
            Some(input.states),
            |index, _, (y, z), strain, w, group| {
                let old = input.states.get(index).unwrap_or(&virgin);
                if old.is_virgin() && group.law.is_elastic_from_virgin(strain) {
                    return;
                }
                let response = group.law.respond(strain, old, input.dt);
                let c = group.law.beam_moduli();
                let mut delta = Vector6::zeros();
                let mut d = Matrix6::zeros();
                for (a, &va) in BEAM_VOIGT.iter().enumerate() {
                    delta[va] = response.stress[a] - c[a] * strain[a];
                    for (b, &vb) in BEAM_VOIGT.iter().enumerate() {
                        let diagonal = if a == b { c[a] } else { 0.0 };
                        d[(va, vb)] = response.tangent[a][b] - diagonal;
                    }
                }
                let (xi, l) = (
                    self.axial.nodes[index / self.plastic_points_per_station()],
                    self.length,
                );
                let g = shape_gradients(xi, y, z, l);
                let f = deformation_gradient(e, &g);
                match k.as_deref_mut() {
                    Some(k) => add_point_stress(&f, &g, w, &delta, Some((&d, k)), q),
                    None => add_beam_stress(&f, &g, w, [delta[0], delta[5], delta[4]], q),
                }
                let elastic: f64 = (0..3).map(|i| 0.5 * c[i] * strain[i] * strain[i]).sum();
                let potential = group.law.incremental_energy(strain, old, &response.state);
                energy += w * (potential - elastic);
            },
        );
        energy
    }

    /// The yielding points at one axial station.
    pub(crate) fn plastic_points_per_station(&self) -> usize {
        self.plan.plastic.iter().map(|g| g.points.len()).sum()
    }

    /// Visit every yielding point with its index in the element's history,
    /// its ξ, its (y, z) (m), its beam strains (E₁₁, γ₁₂, γ₁₃) at `e`, its
    /// weight (m³) and its group. The strains come from the centerline's
    /// r_x = a, the x-derivatives b, c of r_y, r_z and r_y, r_z at the
    /// station: at (y, z), r_x = a + y b + z c, E₁₁ = ½(|r_x|² − 1),
    /// γ₁₂ = r_x · r_y, γ₁₃ = r_x · r_z — a few operations a point.
    ///
    /// With `skip_elastic`, the states of the last accepted step, a group's
    /// points at a station are not visited where all of them are virgin
    /// and a bound on their trial stress over the group's disc stays inside
    /// the yield surface: they would add nothing.
    fn for_each_plastic_strain(
        &self,
        e: &ElementVector,
        skip_elastic: Option<&[PlasticState]>,
        mut visit: impl FnMut(usize, f64, (f64, f64), [f64; 3], f64, &PlasticGroup),
    ) {
        let l = self.length;
        let v = |at: usize| [e[at], e[at + 1], e[at + 2]];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (ra, rxa, rya, rza) = (v(0), v(3), v(6), v(9));
        let (rb, rxb, ryb, rzb) = (v(12), v(15), v(18), v(21));
        let b: [f64; 3] = std::array::from_fn(|k| (ryb[k] - rya[k]) / l);
        let c: [f64; 3] = std::array::from_fn(|k| (rzb[k] - rza[k]) / l);
        let mut index = 0;
        for (xi, wx) in self.axial.nodes.iter().zip(&self.axial.weights) {
            let g = shape_gradients(*xi, 0.0, 0.0, l);
            let a: [f64; 3] = std::array::from_fn(|k| {
                g[0][0] * ra[k] + g[1][0] * rxa[k] + g[4][0] * rb[k] + g[5][0] * rxb[k]
            });
            let ry: [f64; 3] = std::array::from_fn(|k| (1.0 - xi) * rya[k] + xi * ryb[k]);
            let rz: [f64; 3] = std::array::from_fn(|k| (1.0 - xi) * rza[k] + xi * rzb[k]);
            for group in &self.plan.plastic {
                let points = index..index + group.points.len();
                if let Some(states) = skip_elastic {
                    let virgin = states
                        .get(points.clone())
                        .is_none_or(|s| s.iter().all(PlasticState::is_virgin));
                    if virgin && elastic_over_disc(group, (a, b, c), (ry, rz)) {
                        index = points.end;
                        continue;
                    }
                }
                for p in &group.points {
                    let rx: [f64; 3] = std::array::from_fn(|k| a[k] + p.y * b[k] + p.z * c[k]);
                    let strain = [0.5 * (dot(rx, rx) - 1.0), dot(rx, ry), dot(rx, rz)];
                    visit(index, *xi, (p.y, p.z), strain, wx * l * p.weight, group);
                    index += 1;
                }
            }
        }
    }

    /// The force, Jacobian and energy of the element with its yielding
    /// layers evaluated point by point from the history `input` — every
    /// other layer by the generic kernel — the reference the pre-integrated
    /// path with corrections ([`Self::evaluate_with`]) is tested against.
    pub fn evaluate_plastic_reference(
        &self,
        e: &ElementVector,
        input: PlasticInput<'_>,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let mut energy = 0.0;
        self.for_each_point_where(
            |layer| layer.laws.plastic.is_none(),
            |g, w, law| {
                energy += super::point_kernel_generic(e, g, w, law, q, k.as_deref_mut());
            },
        );
        energy + self.add_plastic_points(e, input, q, k)
    }

    /// The yielding layers' whole force, tangent and potential point by
    /// point, every stress from the return map: the reference
    /// [`Self::add_plastic`] is tested against (with the other layers by
    /// the generic kernel, see [`Self::evaluate_plastic_reference`]).
    fn add_plastic_points(
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
        self.for_each_plastic_strain(e, None, |index, xi, _, strain, w, group| {
            let old = input.states.get(index).unwrap_or(&virgin);
            if old.is_virgin() && group.law.is_elastic_from_virgin(strain) {
                // Still elastic: only the stress it is left at changes.
                let c = group.law.beam_moduli();
                out[index] = PlasticState {
                    stress: std::array::from_fn(|i| c[i] * strain[i]),
                    ..virgin
                };
                return;
            }
            let new = group.law.respond(strain, old, input.dt).state;
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
