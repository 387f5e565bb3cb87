//! What a run observes at every state besides the simulation's own records:
//! how close the wire came to each clearance zone, each frame member's
//! largest internal loads, and each beam's largest strains. The program's run and the Python `Simulation`
//! both keep one, so their summaries agree.

use crate::output::{BeamSummary, ClearanceSummary, StrainSummary, Summary};
use ancf_core::loads::clearance_record::ClearanceRecord;
use ancf_core::loads::member_load::MemberRecord;
use ancf_core::loads::strain_record::StrainRecord;
use ancf_core::model::Model;
use ancf_core::model::clearance::ClearanceZone;
use ancf_core::scene::Scene;
use ancf_core::solve::permanent_set::permanent_set;
use ancf_core::solve::statics::StaticSettings;

/// The records so far, one per clearance zone and one per frame member, in
/// the scene's order (in checkpoints under the keys `clearance` and
/// `members`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Observations {
    /// How close the wire came to each clearance zone.
    #[serde(default)]
    pub clearance: Vec<ClearanceRecord>,
    /// Each frame member's largest internal loads.
    #[serde(default)]
    pub members: Vec<MemberRecord>,
    /// When the wire first touched each frame member (s; `None`: not yet).
    #[serde(default)]
    pub member_first_contact: Vec<Option<f64>>,
    /// Each beam's largest strains, the wire first.
    #[serde(default)]
    pub strains: Vec<StrainRecord>,
    /// How deep the wire went into each ground (its plane as a
    /// half-space clearance zone), in the model's order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ground: Vec<ClearanceRecord>,
    /// Each frame member's largest bending moment at every observed state
    /// (time s, N m), in the model's member order: member_forces.csv's
    /// `NAME_moment`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub member_moments: Vec<Vec<(f64, f64)>>,
    /// Where the model's yielding points sit in a state's history (empty
    /// without any; rebuilt by `fit`, not checkpointed).
    #[serde(skip)]
    layout: PlasticLayout,
}

/// Each ground's plane as the half-space the wire must stay out of (the
/// side its normal points away from), in the model's order.
fn ground_zones(scene: &Scene) -> Vec<ClearanceZone> {
    scene.model.contact().map_or(Vec::new(), |c| {
        (c.rods.iter())
            .filter(|r| r.is_ground())
            .map(|g| ClearanceZone::HalfSpace {
                point: g.center,
                normal: g.axis,
            })
            .collect()
    })
}

use ancf_core::forces::plastic::{History, PlasticLayout};
use ancf_core::material::beam_plasticity::PlasticState;

impl Observations {
    /// Empty records for `scene`'s zones and members.
    pub fn new(scene: &Scene) -> Self {
        let mut o = Observations::default();
        o.fit(scene);
        o
    }

    /// One record per zone and member of `scene` (a checkpoint from before
    /// they were recorded records from here on).
    pub fn fit(&mut self, scene: &Scene) {
        self.clearance
            .resize(scene.clearance.len(), ClearanceRecord::default());
        self.members
            .resize(scene.model.beams.len() - 1, MemberRecord::default());
        self.member_first_contact
            .resize(scene.model.beams.len() - 1, None);
        self.strains
            .resize(scene.model.beams.len(), StrainRecord::default());
        self.ground
            .resize(ground_zones(scene).len(), ClearanceRecord::default());
        self.member_moments
            .resize(scene.model.beams.len() - 1, Vec::new());
        self.layout = PlasticLayout::of(&scene.model);
    }

    /// Observe `scene`'s model at coordinates `q` with the yielding points'
    /// states `plastic` (empty: none or virgin), time `t` (s), the wire's
    /// contact force on each member that may touch it being
    /// `member_forces` (N, model's member order; empty: none).
    pub fn observe(
        &mut self,
        scene: &Scene,
        (q, plastic): (&[f64], &[PlasticState]),
        t: f64,
        member_forces: &[[f64; 3]],
    ) {
        let model = &scene.model;
        if self.layout.is_empty() && !plastic.is_empty() {
            self.layout = PlasticLayout::of(model);
        }
        let yielding = History::of(&self.layout, plastic, None);
        for (zone, record) in scene.clearance.iter().zip(&mut self.clearance) {
            record.observe(zone, model, q, t);
        }
        for (zone, record) in ground_zones(scene).iter().zip(&mut self.ground) {
            record.observe(zone, model, q, t);
        }
        // Members that may touch the wire, in order, and their forces.
        let touching = model.contact().map_or(&[][..], |c| &c.members[..]);
        for (contact, force) in touching.iter().zip(member_forces) {
            let first = &mut self.member_first_contact[contact.beam - 1];
            if first.is_none() && force.iter().any(|f| *f != 0.0) {
                *first = Some(t);
            }
        }
        let members = model.beams.iter().skip(1).zip(&mut self.members);
        let histories = members
            .zip(&self.member_first_contact)
            .zip(&mut self.member_moments);
        for (((beam, record), first), history) in histories {
            let m = record.observe(model, beam, (q, yielding), t, *first);
            history.push((t, m));
        }
        for (beam, record) in model.beams.iter().zip(&mut self.strains) {
            record.observe(model, beam, q, t);
        }
    }

    /// Observe the yielding points of a state (`states`, `work` per beam:
    /// [`ancf_core::solve::dynamics::State::plastic`], `plastic_work`) at
    /// time `t` (s): each beam's largest plastic strain and its plastic work.
    pub fn observe_plastic(
        &mut self,
        scene: &Scene,
        states: &[PlasticState],
        work: &[f64],
        t: f64,
    ) {
        if states.is_empty() {
            return;
        }
        if self.layout.is_empty() {
            self.layout = PlasticLayout::of(&scene.model);
        }
        let beams = scene.model.beams.iter().zip(&mut self.strains);
        for (b, (beam, record)) in beams.enumerate() {
            let w = work.get(b).copied().unwrap_or(0.0);
            record.observe_plastic(&scene.model, beam, (&self.layout, states), w, t);
        }
    }

    /// summary.json's `strains`: each beam's name and largest strains.
    pub fn strain_summary(&self, scene: &Scene) -> Vec<StrainSummary> {
        (scene.model.beams.iter())
            .zip(&self.strains)
            .map(|(beam, record)| StrainSummary {
                beam: beam.name.clone(),
                record: record.clone(),
                layer_strains: StrainSummary::layer_kinds(
                    &scene.model.element(beam.elements.start).section,
                ),
            })
            .collect()
    }

    /// What the strains say was outside the range of the beams' laws
    /// ([`ancf_core::plausibility::strain_warnings`]).
    pub fn strain_warnings(&self, scene: &Scene) -> Vec<String> {
        let model = &scene.model;
        (model.beams.iter())
            .zip(&self.strains)
            .flat_map(|(beam, record)| {
                let section = &model.element(beam.elements.start).section;
                ancf_core::plausibility::strain_warnings(&beam.name, record, section)
            })
            .collect()
    }

    /// Each frame member whose outer-fiber von Mises stress passed its
    /// material's yield stress: the elastic result is not valid past it.
    pub fn yield_warnings(&self, scene: &Scene) -> Vec<String> {
        let model = &scene.model;
        (model.beams.iter().skip(1))
            .zip(&self.members)
            .filter_map(|(beam, r)| {
                let material = &model.element(beam.elements.start).section.layers.last()?.material;
                // A yielding material models what the warning is about.
                if material.is_plastic() {
                    return None;
                }
                let fy = material.yield_stress?;
                (r.max_von_mises > fy).then(|| {
                    format!(
                        "beam \"{}\": its outer fiber's von Mises stress reached {:.0} MPa at t = {:.4} s, \
                         {:.2} m from its first node, past its material's yield stress {:.0} MPa; the \
                         material law is elastic, so the run's results past that moment are not the \
                         member's (it would bend for good)",
                        beam.name,
                        1e-6 * r.max_von_mises,
                        r.max_von_mises_time,
                        r.max_von_mises_at,
                        1e-6 * fy
                    )
                })
            })
            .collect()
    }

    /// summary.json's `clearance`: each zone's kind and record.
    pub fn clearance_summary(&self, scene: &Scene) -> Vec<ClearanceSummary> {
        (scene.clearance.iter())
            .zip(&self.clearance)
            .map(|(zone, record)| ClearanceSummary {
                kind: zone.kind().into(),
                record: *record,
            })
            .collect()
    }

    /// summary.json's `beams`: each member's name and largest loads.
    pub fn member_summary(&self, scene: &Scene) -> Vec<BeamSummary> {
        (scene.model.beams.iter().skip(1))
            .zip(&self.members)
            .map(|(beam, record)| BeamSummary {
                name: beam.name.clone(),
                record: *record,
                contact: Default::default(),
                permanent_set: None,
                permanent_set_at: None,
                end_displacement: None,
                end_speed: None,
            })
            .collect()
    }

    /// What a run's message adds for the zones the wire entered (`None`:
    /// none).
    pub fn clearance_note(&self) -> Option<String> {
        let entered: Vec<String> = (self.clearance.iter().enumerate())
            .filter(|(_, r)| r.entered)
            .map(|(i, r)| {
                format!(
                    "clearance[{i}] ({:.3} m deep at t = {:.4} s, at [{:.2}, {:.2}, {:.2}] m)",
                    -r.min_distance.unwrap_or(0.0),
                    r.time,
                    r.position[0],
                    r.position[1],
                    r.position[2]
                )
            })
            .collect();
        (!entered.is_empty()).then(|| format!("the wire entered {}", entered.join(", ")))
    }

    /// Into `summary.beams`: each member's contact load, from the force the
    /// wire put on it at every step (`loads`, model's member order),
    /// filtered at `cfc` Hz.
    pub fn fill_member_contact(
        summary: &mut Summary,
        loads: &[ancf_core::loads::rod_load::LoadHistory],
        cfc: f64,
    ) {
        for (beam, h) in summary.beams.iter_mut().zip(loads) {
            beam.contact = h.summary(&h.filtered(cfc));
        }
    }

    /// Into `summary.beams`: each member with an elastic-plastic layer's
    /// permanent set from the run's end (coordinates `q`, velocities `v`,
    /// none for a static run, and the yielding points' states), and its
    /// displacement and speed then. `model` is the one holding at the end
    /// ([`ancf_core::model::Model::holding_at`] after a release). A member
    /// without a rest shape (not held on its own, no equilibrium) gets
    /// none, and a warning in `summary` says why.
    pub fn fill_permanent_set(
        model: &Model,
        (q, v, plastic): (&[f64], Option<&[f64]>, &[PlasticState]),
        summary: &mut Summary,
    ) {
        let members = (model.beams.iter().enumerate().skip(1)).zip(summary.beams.iter_mut());
        let mut warnings = Vec::new();
        for ((index, beam), out) in members {
            let section = &model.element(beam.elements.start).section;
            if !section.layers.iter().any(|l| l.material.is_plastic()) {
                continue;
            }
            use ancf_core::math::vec3::{norm, sub};
            let (mut moved, mut speed) = (0.0f64, 0.0f64);
            for n in beam.nodes.clone() {
                let r = model.node_position(q, n);
                moved = moved.max(norm(sub(r, model.node_position(&model.reference, n))));
                if let Some(v) = v {
                    speed = speed.max(norm(model.node_position(v, n)));
                }
            }
            out.end_displacement = Some(moved);
            out.end_speed = v.map(|_| speed);
            let settings = StaticSettings::default();
            match permanent_set(model, index, (q, plastic), &settings) {
                Ok(set) => {
                    out.permanent_set = Some(set.set);
                    out.permanent_set_at = Some(set.at);
                }
                Err(e) => warnings.push(format!(
                    "member \"{}\" has no permanent set: its rest shape without the wire was \
                     not found ({})",
                    beam.name, e.message
                )),
            }
        }
        for w in warnings {
            summary.message.push_str(&format!("; warning: {w}"));
            summary.warnings.push(w);
        }
    }

    /// Into `summary`: its `clearance`, `beams` and `strains`, and the note
    /// on entered zones at the end of its message.
    /// Strains beyond a law's range are warnings, added to the message too.
    pub fn fill(&self, scene: &Scene, summary: &mut Summary) {
        summary.clearance = self.clearance_summary(scene);
        summary.beams = self.member_summary(scene);
        summary.strains = self.strain_summary(scene);
        if let Some(note) = self.clearance_note() {
            summary.message.push_str(&format!("; {note}"));
        }
        for w in self
            .strain_warnings(scene)
            .into_iter()
            .chain(self.yield_warnings(scene))
        {
            summary.message.push_str(&format!("; warning: {w}"));
            summary.warnings.push(w);
        }
    }
}
