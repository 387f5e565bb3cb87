//! The Newton predictor of a step's end acceleration.

use super::State;
use crate::model::Model;

/// The Newton predictor for a₁ (full coordinates):
/// a₁ = (1 − ρ∞) a₀ + ρ∞ a₋₁, with a₋₁ the acceleration one step further
/// back, when that step had the same size h; else a₀.
///
/// Why: generalized-α (Chung–Hulbert) does not resolve the modes with
/// ω h ≫ 1 (axial and shear modes of short elements); all its amplification
/// eigenvalues for them tend to −ρ∞, so their acceleration goes
/// a₋₁ → −ρ∞ a₋₁ → ρ∞² a₋₁ over two steps. The weights above are the ones
/// that predict both that sequence and a constant acceleration exactly; a
/// smooth part changing at rate ȧ is off by (1 + ρ∞) h ȧ instead of h ȧ.
/// With ρ∞ = 1 (no numerical damping) those modes flip sign forever, and
/// the a₀ predictor is off by twice their amplitude: on the pendulum the flip
/// sits at the node next to the pin, and it sets the residual Newton starts
/// from, so that modified Newton needs more iterations and, on fine meshes,
/// refactorizations; this predictor removes it. Only unknowns are predicted; prescribed
/// coordinates keep a₀.
pub fn predict(model: &Model, s: &State, h: f64, spectral_radius: f64) -> Vec<f64> {
    let mut a1 = s.a.clone();
    let rho = spectral_radius;
    if let Some(prev) = s
        .previous
        .as_ref()
        .filter(|p| p.h == h && p.a.len() == a1.len() && rho > 0.0)
    {
        for run in model.free_coordinates() {
            let (a0, am1) = (&s.a[run.clone()], &prev.a[run.clone()]);
            for ((a1, a0), am1) in a1[run.clone()].iter_mut().zip(a0).zip(am1) {
                *a1 = (1.0 - rho) * a0 + rho * am1;
            }
        }
    }
    a1
}
