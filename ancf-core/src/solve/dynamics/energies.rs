//! The energies of a state.

/// Energies of a state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Energies {
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Strain energy (J).
    pub strain: f64,
    /// Potential of gravity (J).
    pub gravity: f64,
    /// Potential of the point loads (J).
    pub loads: f64,
    /// Contact penalty energy.
    pub contact: f64,
    /// Dissipated by friction and damping since t = 0 (not part of `total`).
    pub dissipated: f64,
    /// Plastic work since t = 0 (not part of `total`; written only where
    /// a layer yields).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub plastic: f64,
}

impl Energies {
    /// What the balance keeps: the mechanical energy plus what friction,
    /// damping and plastic flow took out of it (J).
    pub fn balance(&self) -> f64 {
        self.total() + self.dissipated + self.plastic
    }

    /// Mechanical energy: kinetic + strain + potentials + contact penalty.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.gravity + self.loads + self.contact
    }

    /// The energy in play, every term counted positive (J): the energy
    /// guard's scale (the potentials may be negative).
    pub fn in_play(&self) -> f64 {
        self.kinetic + self.strain + self.gravity.abs() + self.loads.abs() + self.contact
    }
}

/// Whether an energy is exactly zero (one nothing contributed to).
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
