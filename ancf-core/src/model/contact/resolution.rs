//! Whether a time step resolves a rod's or a frame member's line-law
//! contact, known before a run starts.
//!
//! Where the wire lies on a rod, the line law (and hertz, the line law with
//! ε_L from E*) is an elastic foundation of ε_L N/m² under a beam of ρA
//! kg/m: the wire vibrates against it at no less than ω_c = √(ε_L / ρA).
//! A step that samples that oscillation too coarsely (h ω_c above about 3)
//! is rejected and cut again and again, and the loads then depend on which
//! sub-steps passed; below it the impact and span-break contacts, at every
//! stiffness and law tried, run without a cut. Resolving the contact is
//! necessary, not sufficient: a Newton tolerance too loose for a very
//! small step adds up an energy error, and a contact too soft for the blow
//! meets the penetration limit whatever the step. The surface law's ε_N
//! (N/m³) has no foundation stiffness per length; it is not judged. A
//! frame member moves too: wire and member oscillate against each other at
//! ω_c = √(ε_L (1/ρA_w + 1/ρA_m)), higher than against a rigid rod.

use super::{Contact, ContactLaw};

/// The largest h ω_c at which a line-law contact is resolved (see the
/// module's measurements).
pub const RESOLVED_STEP_FREQUENCY: f64 = 3.0;

/// A rod or member whose line-law contact a time step does not resolve.
#[derive(Clone, Debug, PartialEq)]
pub struct UnresolvedContact {
    /// The contact partner's index: the rods in the scene's order, then
    /// the members.
    pub rod: usize,
    /// The partner as a message names it: `rod 0`, `ground 0`,
    /// `member "tube"`.
    pub partner: String,
    /// Its law.
    pub law: ContactLaw,
    /// Its penalty ε_L, N/m².
    pub stiffness: f64,
    /// The mass per length the contact oscillates, kg/m: the wire's ρA
    /// against a rod, the reduced 1 / (1/ρA_w + 1/ρA_m) against a member.
    pub mass_per_length: f64,
    /// ω_c = √(ε_L / ρA), rad/s.
    pub frequency: f64,
    /// The time step judged, s.
    pub time_step: f64,
}

impl UnresolvedContact {
    /// The largest time step that resolves the contact, s.
    pub fn resolving_step(&self) -> f64 {
        RESOLVED_STEP_FREQUENCY / self.frequency
    }
}

impl std::fmt::Display for UnresolvedContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "analysis.time_step = {:e} s does not resolve {}'s {} contact: h ω_c = {:.1} > {} \
             (ω_c = √(ε_L / ρA) = {:.3e} rad/s, ε_L = {:.3e} N/m² on {:.4} kg/m); expect step cuts \
             and loads that depend on them; a time step ≤ {:.2e} s resolves it",
            self.time_step,
            self.partner,
            self.law.name(),
            self.time_step * self.frequency,
            RESOLVED_STEP_FREQUENCY,
            self.frequency,
            self.stiffness,
            self.mass_per_length,
            self.resolving_step(),
        )
    }
}

/// The rods and members of `contact` whose line-law contact a step of
/// `time_step` s does not resolve on a wire of `mass_per_length` kg/m, the
/// members named and of `member_masses` kg/m (in member order), in
/// partner order; then each member on a ground that names it.
pub fn unresolved_contacts(
    contact: &Contact,
    mass_per_length: f64,
    members: &[(String, f64)],
    time_step: f64,
) -> Vec<UnresolvedContact> {
    let rods = (contact.rods.iter().enumerate())
        .filter(|(_, rod)| rod.law != ContactLaw::Surface)
        .map(|(i, rod)| UnresolvedContact {
            rod: i,
            partner: contact.rigid_name(i).replace('[', " ").replace(']', ""),
            law: rod.law,
            stiffness: rod.contact_stiffness,
            mass_per_length,
            frequency: (rod.contact_stiffness / mass_per_length).sqrt(),
            time_step,
        });
    let wire_members =
        contact
            .members
            .iter()
            .zip(members)
            .enumerate()
            .map(|(i, (m, (name, mass)))| {
                let reduced = 1.0 / (1.0 / mass_per_length + 1.0 / mass);
                UnresolvedContact {
                    rod: contact.rods.len() + i,
                    partner: format!("member \"{name}\""),
                    law: ContactLaw::Line,
                    stiffness: m.contact_stiffness,
                    mass_per_length: reduced,
                    frequency: (m.contact_stiffness / reduced).sqrt(),
                    time_step,
                }
            });
    // A member on a ground: the member's own mass against the plane.
    let grounded = (contact.grounded_members.iter())
        .filter_map(|&(ri, beam)| members.get(beam - 1).map(|m| (ri, m)))
        .map(|(ri, (name, mass))| UnresolvedContact {
            rod: ri,
            partner: format!(
                "{} under member \"{name}\"",
                contact.rigid_name(ri).replace('[', " ").replace(']', "")
            ),
            law: ContactLaw::Line,
            stiffness: contact.rods[ri].contact_stiffness,
            mass_per_length: *mass,
            frequency: (contact.rods[ri].contact_stiffness / mass).sqrt(),
            time_step,
        });
    rods.chain(wire_members)
        .chain(grounded)
        .filter(|u| u.time_step * u.frequency > RESOLVED_STEP_FREQUENCY)
        .collect()
}
