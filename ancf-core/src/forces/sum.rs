//! The one place where the forces of a model's effects are added up, for
//! every solver: static equilibrium, the integrator's residual, its initial
//! acceleration and the energy balance all ask a [`ForceSum`].
//!
//! The sum keeps three parts apart, because the solvers use them apart:
//!
//! * Q(q, v) = Q_e(q) − Q_c(q, v) on all coordinates (N): the elastic
//!   force less the contact force (a residual is scaled by ‖Q‖);
//! * Q_d(q, v) on the unknowns (N): damping, only with velocities;
//! * Q_ext on all coordinates (N): gravity and point loads, constant at a
//!   load factor λ (statics raises λ in increments, dynamics keeps λ = 1).
//!
//! Statics solves Q − λ Q_ext = 0, the integrator M a + Q + Q_d − Q_ext = 0.
//! An effect the model does not name is not evaluated (no zero vectors are
//! added). The parts are added in the order the solvers always added them,
//! so their results keep their bits.
//!
//! Evaluations write into buffers the sum owns (allocated once), and the
//! Jacobians into the caller's pattern-slot arrays: ∂(Q + Q_d)/∂q into `kq`
//! (overwritten), ∂(Q + Q_d)/∂v added to `kv`.

use super::assembly::{
    ContactForces, assemble, assemble_contact_reusing, assemble_into_with, mass_values, pattern,
    strain_energy_with,
};
use super::contact::ContactEvaluator;
use super::coupling::Coupling;
use super::damping::{KelvinVoigtWork, kelvin_voigt_force_into};
use super::plastic::{History, PlasticLayout};
use crate::linalg::pattern::Pattern;
use crate::material::beam_plasticity::PlasticState;
use crate::model::damping::Damping;
use crate::model::{Model, NODE_DOFS};

/// Where the forces are evaluated.
#[derive(Clone, Copy, Debug)]
pub struct At<'a> {
    /// Coordinates, all of them (m, –).
    pub q: &'a [f64],
    /// Velocities (m/s, 1/s); `None` in statics: no friction, no damping.
    pub v: Option<&'a [f64]>,
    /// The contact events' approach speeds per (element, rod) pair (m/s, see
    /// [`crate::solve::dynamics::State::contact_events`]); empty: none.
    pub events: &'a [f64],
    /// The (element, rod) pairs contact may visit (see
    /// [`super::assembly::contact_candidates`]); `None`: all.
    pub pairs: Option<&'a [usize]>,
    /// The yielding points' states at the last accepted step (see
    /// [`crate::forces::plastic::PlasticLayout`]); empty: virgin.
    pub plastic: &'a [PlasticState],
    /// The step being taken (s), for the rate law; `None`: statics.
    pub dt: Option<f64>,
}

impl<'a> At<'a> {
    /// At rest at `q`: statics.
    pub fn rest(q: &'a [f64]) -> Self {
        At {
            q,
            v: None,
            events: &[],
            pairs: None,
            plastic: &[],
            dt: None,
        }
    }

    /// At (q, v), outside any contact event, visiting every pair.
    pub fn moving(q: &'a [f64], v: &'a [f64]) -> Self {
        At {
            q,
            v: Some(v),
            events: &[],
            pairs: None,
            plastic: &[],
            dt: None,
        }
    }
}

/// The potential energies of the effects at a configuration (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Potentials {
    /// Strain energy.
    pub strain: f64,
    /// Gravity's potential (relative to the reference configuration).
    pub gravity: f64,
    /// The point loads' potential (relative to the reference configuration).
    pub loads: f64,
    /// Contact penalty energy.
    pub contact: f64,
}

/// A model's effects, summed: the pattern their Jacobians live in, the
/// constant parts (external force, Rayleigh matrix) and the buffers of the
/// last evaluation. Made once per model; every method takes that model.
pub struct ForceSum {
    pattern: Pattern,
    /// λ Q_ext, all coordinates (N).
    external: Vec<f64>,
    /// λ: the moment loads' factor, as `external`'s.
    load_factor: f64,
    /// The moment loads' forces of the last evaluation, per loaded node
    /// [Q_{r_y}, Q_{r_z}] (N; [`crate::forces::moment`]).
    moments: Vec<(usize, [f64; 6])>,
    /// Rayleigh damping matrix α M + β K₀ in pattern slots, each beam's
    /// own factors in its slots (empty when no beam has Rayleigh damping).
    rayleigh: Vec<f64>,
    /// Each group's Kelvin–Voigt coefficient c (s; `None`: its beam has
    /// none); empty when no beam has Kelvin–Voigt damping.
    strain_rate: Vec<Option<f64>>,
    /// Kelvin–Voigt's buffers, kept between evaluations.
    kelvin_voigt_work: KelvinVoigtWork,
    /// Q = Q_e − Q_c of the last evaluation (all coordinates, N).
    internal: Vec<f64>,
    /// Per-element strain energies (workspace) and their sum (J).
    element_energy: Vec<f64>,
    strain_energy: f64,
    /// The model's contact, ready to evaluate (`None` without rods).
    evaluator: Option<ContactEvaluator>,
    /// The last evaluation's contact (its force vector is reused).
    contact: Option<ContactForces>,
    /// The blocks coupling two beams of the last evaluation with `kq`.
    coupling: Coupling,
    /// Q_d on the unknowns (N) and its power Q_d · v (W) of the last
    /// evaluation with velocities; empty without damping.
    damping: Vec<f64>,
    damping_power: f64,
    /// The force vector and its nonzero nodes that the contact energy's
    /// evaluation ([`ForceSum::potentials_visiting`], once a step) reuses,
    /// instead of allocating and clearing a whole force vector each time.
    energy_buffer: std::sync::Mutex<(Vec<f64>, Vec<usize>)>,
    /// Where the yielding points' states sit (empty without any).
    plastic: PlasticLayout,
}

impl ForceSum {
    /// The sum of `model`'s effects at load factor 1.
    pub fn new(model: &Model) -> Self {
        let pattern = pattern(model);
        let rayleigh = rayleigh_values(model, &pattern);
        let strain_rate: Vec<Option<f64>> = (0..model.groups.len())
            .map(|g| match model.beam_damping(model.group_beam(g)) {
                Some(&Damping::KelvinVoigt { coefficient }) => Some(coefficient),
                _ => None,
            })
            .collect();
        let strain_rate = match strain_rate.iter().any(Option::is_some) {
            true => strain_rate,
            false => Vec::new(),
        };
        let n = model.reference.len();
        ForceSum {
            pattern,
            external: model.external_force(1.0),
            load_factor: 1.0,
            moments: Vec::new(),
            rayleigh,
            strain_rate,
            kelvin_voigt_work: KelvinVoigtWork::default(),
            internal: vec![0.0; n],
            element_energy: vec![0.0; model.n_elements],
            strain_energy: 0.0,
            evaluator: model
                .contact()
                .map(|c| ContactEvaluator::for_model(c, model)),
            contact: model.contact().map(|_| ContactForces::default()),
            coupling: Coupling::default(),
            damping: Vec::new(),
            damping_power: 0.0,
            energy_buffer: Default::default(),
            plastic: PlasticLayout::of(model),
        }
    }

    /// The sparsity pattern of the Jacobians (the model's element blocks).
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Scale the external force to load factor `lambda` (statics' increments).
    pub fn set_load_factor(&mut self, model: &Model, lambda: f64) {
        self.external = model.external_force(lambda);
        self.load_factor = lambda;
    }

    /// λ, the load factor of `external` and the moment loads.
    pub fn load_factor(&self) -> f64 {
        self.load_factor
    }

    /// The moment loads' forces of the last evaluation: per loaded node,
    /// [Q_{r_y}, Q_{r_z}] (N).
    pub fn moments(&self) -> &[(usize, [f64; 6])] {
        &self.moments
    }

    /// ‖λ Q_ext‖ with the moment loads' forces of the last evaluation
    /// added (N): the size of what loads the model, which a residual is
    /// judged against (the moments sit in `internal`, not `external`).
    pub fn load_norm(&self, model: &Model) -> f64 {
        let ext = model.gather(&self.external);
        let ext2: f64 = ext.iter().map(|v| v * v).sum();
        let moments2: f64 = (self.moments.iter())
            .flat_map(|(_, f)| f)
            .map(|v| v * v)
            .sum();
        (ext2 + moments2).sqrt()
    }

    /// λ Q_ext, all coordinates (N).
    pub fn external(&self) -> &[f64] {
        &self.external
    }

    /// The work of λ Q_ext from the reference to `q`, λ Q_extᵀ(q − q_ref) (J).
    pub fn external_work(&self, model: &Model, q: &[f64]) -> f64 {
        (self.external.iter())
            .zip(q.iter().zip(&model.reference))
            .map(|(f, (a, b))| f * (a - b))
            .sum::<f64>()
    }

    /// Whether the forces depend on the velocities (friction, contact
    /// damping, structural damping): then the Newton matrix has a
    /// velocity part.
    pub fn velocity_dependent(model: &Model) -> bool {
        model.contact().is_some_and(|c| c.velocity_dependent())
            || model.is_damped()
            || model.has_spring_damping()
    }

    /// The value slots of ∂(Q + Q_d)/∂v the last evaluation with a `kv`
    /// may have written: every slot with structural damping (Rayleigh,
    /// Kelvin–Voigt) or support dashpots, else the columns of the wire
    /// elements contact wrote (none when nothing touched), so that a
    /// caller can clear and combine only those.
    pub fn velocity_jacobian_slots(&self, model: &Model) -> std::ops::Range<usize> {
        if model.is_damped() || model.has_spring_damping() {
            return 0..self.pattern.nnz();
        }
        match self.contact.as_ref().and_then(|c| c.velocity_elements) {
            Some((first, last)) => self.pattern.node_values(first..last + 2),
            None => 0..0,
        }
    }

    /// Whether the Jacobian is symmetric: not with friction, contact
    /// damping, Kelvin–Voigt damping (Rayleigh's constant matrix is) or
    /// moment loads (their load stiffness).
    pub fn symmetric(model: &Model) -> bool {
        !model.contact().is_some_and(|c| c.velocity_dependent())
            && !(model.dampings()).any(|(_, d)| matches!(d, Damping::KelvinVoigt { .. }))
            && model.moment_loads().next().is_none()
    }

    /// Evaluate the forces at `at` into the sum's buffers; with `kq`, write
    /// ∂(Q + Q_d)/∂q over it, with `kv` add ∂(Q + Q_d)/∂v to it (pattern
    /// slots; the velocity parts only where they exist).
    pub fn evaluate(
        &mut self,
        model: &Model,
        at: At<'_>,
        mut kq: Option<&mut [f64]>,
        mut kv: Option<&mut [f64]>,
    ) {
        self.strain_energy = assemble_into_with(
            model,
            &self.pattern,
            at.q,
            History::of(&self.plastic, at.plastic, at.dt),
            kq.as_deref_mut(),
            &mut self.internal,
            &mut self.element_energy,
        );
        let springs = model.springs();
        if !springs.is_empty() {
            self.strain_energy += add_springs(
                model,
                &self.pattern,
                at.q,
                &mut self.internal,
                kq.as_deref_mut(),
            );
        }
        if model.moment_loads().next().is_some() {
            self.moments = crate::forces::moment::load_forces(model, at.q, self.load_factor);
            add_moment_loads(
                model,
                &self.pattern,
                (at.q, self.load_factor),
                &self.moments,
                &mut self.internal,
                kq.as_deref_mut(),
            );
        }
        if let (Some(c), Some(ev)) = (model.contact(), &self.evaluator) {
            let kvc = if c.velocity_dependent() {
                kv.as_deref_mut()
            } else {
                None
            };
            let buffer = (self.contact.take())
                .map(|c| (c.force, c.force_nodes))
                .unwrap_or_default();
            let rest;
            let v = match at.v {
                Some(v) => v,
                None => {
                    rest = vec![0.0; at.q.len()];
                    &rest
                }
            };
            let coupling = kq.is_some().then_some(&mut self.coupling);
            let cf = assemble_contact_reusing(
                model,
                ev,
                &self.pattern,
                at.q,
                v,
                at.events,
                at.pairs,
                (kq.as_deref_mut(), kvc, coupling),
                buffer,
            );
            // The contact force is zero outside its nodes' rows.
            for &n in &cf.force_nodes {
                let rows = NODE_DOFS * n..NODE_DOFS * (n + 1);
                let (a, b) = (&mut self.internal[rows.clone()], &cf.force[rows]);
                a.iter_mut().zip(b).for_each(|(a, b)| *a -= b);
            }
            self.contact = Some(cf);
        }
        let Some(v) = at.v else {
            self.damping.clear();
            return;
        };
        self.damping.clear();
        self.damping_power = 0.0;
        if !model.is_damped() && !model.has_spring_damping() {
            return;
        }
        self.damping.resize(model.n_unknowns, 0.0);
        if !self.rayleigh.is_empty() {
            let vu = model.gather(v);
            self.pattern
                .mul_add(&self.rayleigh, &vu, 1.0, &mut self.damping);
            if let Some(kv) = kv.as_deref_mut() {
                kv.iter_mut().zip(&self.rayleigh).for_each(|(a, b)| *a += b);
            }
            self.damping_power = self.damping.iter().zip(&vu).map(|(a, b)| a * b).sum();
        }
        if !self.strain_rate.is_empty() {
            self.damping_power += kelvin_voigt_force_into(
                model,
                &self.pattern,
                &self.strain_rate,
                (at.q, v),
                (kq, kv.as_deref_mut()),
                &mut self.kelvin_voigt_work,
                &mut self.damping,
            );
        }
        if model.has_spring_damping() {
            self.damping_power += add_dashpots(model, &self.pattern, v, &mut self.damping, kv);
        }
    }

    /// Where the yielding points' states sit (empty without any).
    pub fn plastic_layout(&self) -> &PlasticLayout {
        &self.plastic
    }

    /// The history the forces read: `states` placed by the layout, over
    /// a step `dt`.
    pub fn history<'a>(&'a self, states: &'a [PlasticState], dt: Option<f64>) -> History<'a> {
        History::of(&self.plastic, states, dt)
    }

    /// Q = Q_e − Q_c of the last evaluation (all coordinates, N).
    pub fn internal(&self) -> &[f64] {
        &self.internal
    }

    /// Strain energy of the last evaluation (J).
    pub fn strain_energy(&self) -> f64 {
        self.strain_energy
    }

    /// The model's contact, ready to evaluate (`None` without rods).
    pub fn contact_evaluator(&self) -> Option<&ContactEvaluator> {
        self.evaluator.as_ref()
    }

    /// Contact of the last evaluation (`None` without contact).
    pub fn contact(&self) -> Option<&ContactForces> {
        self.contact.as_ref()
    }

    /// The blocks coupling two beams (wire and member in contact) of the
    /// last evaluation with a Jacobian: −∂Q/∂q and −∂Q/∂v outside the
    /// pattern (empty without such contact).
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// Q_d on the unknowns (N) and its power (W) of the last evaluation;
    /// `None` without damping or without velocities (statics).
    pub fn damping(&self) -> Option<(&[f64], f64)> {
        (!self.damping.is_empty()).then_some((&self.damping[..], self.damping_power))
    }

    /// The effects' potential energies at (q, v) (contact outside any
    /// event). Leaves the last evaluation's buffers alone.
    pub fn potentials(&self, model: &Model, q: &[f64], v: &[f64]) -> Potentials {
        self.potentials_visiting(model, q, v, None, &[])
    }

    /// [`ForceSum::potentials`] with the contact energy summed over the
    /// (element, rod) pairs `pairs` only (see
    /// [`crate::forces::assembly::contact_candidates`]; `None`: all pairs).
    /// With candidates that hold at `q`, the same sum: a pair outside them
    /// cannot touch and adds nothing. The yielding points' elastic energy is
    /// taken from `plastic`, the states accepted at `q`.
    pub fn potentials_visiting(
        &self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        pairs: Option<&[usize]>,
        plastic: &[PlasticState],
    ) -> Potentials {
        let history = self.history(plastic, None);
        let strain = strain_energy_with(model, q, history) + model.spring_energy(q);
        let (gravity, loads) = model.external_potential(q);
        let contact = self.evaluator.as_ref().map_or(0.0, |c| {
            let mut kept = self.energy_buffer.lock().unwrap_or_else(|p| p.into_inner());
            let (events, buffer) = (&[], std::mem::take(&mut *kept));
            let cf = assemble_contact_reusing(
                model,
                c,
                &self.pattern,
                q,
                v,
                events,
                pairs,
                (None, None, None),
                buffer,
            );
            let energy = cf.total.energy;
            *kept = (cf.force, cf.force_nodes);
            energy
        });
        Potentials {
            strain,
            gravity,
            loads,
            contact,
        }
    }
}

/// The elastic supports' forces added to `internal` (all coordinates) and
/// their stiffness — K on the position, the rotational spring's 3 × 3 block
/// on r_x, the torsional spring's 6 × 6 on r_y, r_z — to `kq` (pattern slots, unknowns only); returns their energy
/// (J), which counts as strain energy.
fn add_springs(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    internal: &mut [f64],
    kq: Option<&mut [f64]>,
) -> f64 {
    let springs = model.springs();
    springs.iter().for_each(|s| s.add_force(q, internal));
    if let Some(kq) = kq {
        // Every unknown of one node is coupled with the others by its
        // elements: the slots exist.
        let mut add = |a: usize, b: usize, v: f64| {
            if let (Some(r), Some(c)) = (model.dof_map[a], model.dof_map[b]) {
                kq[pattern
                    .slot(r, c)
                    .expect("a node's block is in the pattern")] += v;
            }
        };
        for s in springs {
            let base = s.first_coordinate();
            for (k, stiffness) in s.spring.stiffness.iter().enumerate() {
                add(base + k, base + k, *stiffness);
            }
            if s.spring.rotational_stiffness != 0.0 {
                let h = s.rotational_jacobian(q);
                for (i, row) in h.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        add(base + 3 + i, base + 3 + j, *v);
                    }
                }
            }
            if s.spring.torsional_stiffness != 0.0 {
                let h = s.torsional_jacobian();
                for (i, row) in h.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        add(base + 6 + i, base + 6 + j, *v);
                    }
                }
            }
        }
    }
    model.spring_energy(q)
}

/// The moment loads' `forces` (at `q`, factor λ) taken from `internal`
/// (Q = Q_e − Q_m) and their stiffness −∂Q_m/∂q added to `kq` (pattern
/// slots, unknowns only): the loaded nodes' section-gradient blocks.
fn add_moment_loads(
    model: &Model,
    pattern: &Pattern,
    (q, factor): (&[f64], f64),
    forces: &[(usize, [f64; 6])],
    internal: &mut [f64],
    kq: Option<&mut [f64]>,
) {
    for (node, f) in forces {
        let base = NODE_DOFS * node + 6;
        internal[base..base + 6]
            .iter_mut()
            .zip(f)
            .for_each(|(a, b)| *a -= b);
    }
    let Some(kq) = kq else {
        return;
    };
    for (node, k) in crate::forces::moment::load_stiffnesses(model, q, factor) {
        let base = NODE_DOFS * node + 6;
        for (i, row) in k.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if let (Some(r), Some(c)) = (model.dof_map[base + i], model.dof_map[base + j]) {
                    kq[pattern
                        .slot(r, c)
                        .expect("a node's block is in the pattern")] -= v;
                }
            }
        }
    }
}

/// The Rayleigh matrix α M + β K₀ in pattern slots, each Rayleigh-damped
/// beam's own factors in its nodes' columns (beams share no slot: a gap
/// element lies between two); empty when no beam has Rayleigh damping.
fn rayleigh_values(model: &Model, pattern: &Pattern) -> Vec<f64> {
    let rayleigh: Vec<(usize, f64, f64)> = (model.dampings())
        .filter_map(|(b, d)| match *d {
            Damping::Rayleigh { mass, stiffness } => Some((b, mass, stiffness)),
            Damping::KelvinVoigt { .. } => None,
        })
        .collect();
    if rayleigh.is_empty() {
        return Vec::new();
    }
    let mut k0 = pattern.zeros();
    assemble(model, pattern, &model.reference, Some(&mut k0));
    let m = mass_values(model, pattern);
    let mut values = pattern.zeros();
    for (b, alpha, beta) in rayleigh {
        for slot in pattern.node_values(model.beams[b].nodes.clone()) {
            values[slot] = alpha * m[slot] + beta * k0[slot];
        }
    }
    values
}

/// The elastic supports' dashpots c ṙ added to `qd` (unknowns) and c to
/// `kv`'s diagonal; returns their power (W).
fn add_dashpots(
    model: &Model,
    pattern: &Pattern,
    v: &[f64],
    qd: &mut [f64],
    mut kv: Option<&mut [f64]>,
) -> f64 {
    let mut power = 0.0;
    for s in model.springs() {
        let c = s.spring.damping;
        for k in 0..3 {
            let coord = s.first_coordinate() + k;
            if let Some(u) = model.dof_map[coord] {
                qd[u] += c * v[coord];
                power += c * v[coord] * v[coord];
                if let Some(kv) = kv.as_deref_mut() {
                    kv[pattern.slot(u, u).expect("a diagonal is in the pattern")] += c;
                }
            }
        }
    }
    power
}
