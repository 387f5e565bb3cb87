//! Structural damping as a model names it (SPEC §6); evaluated by
//! `forces::damping`.

use crate::check::{ParameterError, finite, positive, refuse};

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

impl Damping {
    /// Whether the factors can be used: Kelvin–Voigt c > 0; Rayleigh
    /// α, β ≥ 0, not both 0.
    pub fn check(&self) -> Result<(), ParameterError> {
        match *self {
            Damping::KelvinVoigt { coefficient } => {
                positive("strain_rate_coefficient", coefficient)?;
            }
            Damping::Rayleigh { mass, stiffness } => {
                let (alpha, beta) = (finite("mass", mass)?, finite("stiffness", stiffness)?);
                if alpha < 0.0 || beta < 0.0 || alpha + beta == 0.0 {
                    return refuse(
                        if alpha >= 0.0 && beta < 0.0 {
                            "stiffness"
                        } else {
                            "mass"
                        },
                        format!("need mass ≥ 0, stiffness ≥ 0, not both 0; got {alpha}, {beta}"),
                    );
                }
            }
        }
        Ok(())
    }
}
