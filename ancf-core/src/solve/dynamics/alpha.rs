//! Generalized-α (Chung–Hulbert) parameters and Newmark's update.

use super::State;

/// Generalized-α parameters from ρ∞.
#[derive(Clone, Copy, Debug)]
pub struct AlphaParameters {
    /// α_m.
    pub alpha_m: f64,
    /// α_f.
    pub alpha_f: f64,
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
}

impl AlphaParameters {
    /// One coordinate's q₁ and v₁ for a step of size h from (q, v, a) that
    /// ends with acceleration a₁ (Newmark's update, SPEC §6).
    #[inline(always)]
    pub(super) fn newmark(&self, h: f64, q: f64, v: f64, a: f64, a1: f64) -> (f64, f64) {
        let (beta, gamma) = (self.beta, self.gamma);
        let q1 = q + h * v + h * h * ((0.5 - beta) * a + beta * a1);
        let v1 = v + h * ((1.0 - gamma) * a + gamma * a1);
        (q1, v1)
    }

    /// The state's coordinates with a₁, for Newmark's update: (q, v, a, a₁).
    pub(super) fn coordinates<'a>(
        s: &'a State,
        a1: &'a [f64],
    ) -> impl Iterator<Item = (f64, f64, f64, f64)> + 'a {
        (s.q.iter().zip(&s.v).zip(&s.a).zip(a1)).map(|(((&q, &v), &a), &a1)| (q, v, a, a1))
    }

    /// The parameters of Chung & Hulbert for spectral radius ρ∞ ∈ [0, 1].
    pub fn new(rho_inf: f64) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (1.0 - alpha_m + alpha_f).powi(2);
        AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        }
    }
}
