//! Structural damping as a model names it (SPEC §6); evaluated by
//! `forces::damping`.

/// Damping named by a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Damping {
    /// Q_d = (mass · M + stiffness · K₀) v; `mass` in 1/s, `stiffness` in s.
    Rayleigh {
        /// Mass-proportional factor (1/s).
        mass: f64,
        /// Stiffness-proportional factor (s).
        stiffness: f64,
    },
    /// σ_v = c D₀ Ė; `coefficient` c in s.
    KelvinVoigt {
        /// c (s).
        coefficient: f64,
    },
}
