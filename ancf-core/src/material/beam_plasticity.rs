//! Beam-type J2 plasticity at one point: the stresses a beam carries — the
//! axial stress σ = S₁₁ and the two transverse shears τ₂ = S₁₂, τ₃ = S₁₃ —
//! yield by von Mises, σ_eq² = σ² + 3 (τ₂² + τ₃²), while the section's
//! transverse normal stresses stay elastic. This is how OpenSees' fiber
//! sections and LS-DYNA's Hughes–Liu beam with *MAT_024 treat a beam, and
//! why it suits the fully parameterized element: plastic flow without the
//! transverse stresses cannot lock through plastic incompressibility.
//!
//! Strains are the Green–Lagrange E₁₁ and engineering shears γ₂ = 2 E₁₂,
//! γ₃ = 2 E₁₃, split additively into elastic and plastic parts (small
//! strain, large rotation: Sugiyama & Shabana; Gerstmayr). The elastic law
//! is the one the element's "centerline" locking remedy integrates over the
//! section: σ = E ε₁₁, τ = G γ, no Poisson coupling.
//!
//! Hardening is linear: isotropic (the yield stress grows with the
//! equivalent plastic strain ē) or kinematic (Prager's back stress, scaled
//! so that a bar in tension hardens at H in both cases); the Cowper–Symonds
//! rate law scales the yield stress by 1 + (ē̇ / D)^(1/q), ē̇ = Δē / Δt.
//!
//! The return map is the backward-Euler closest point. With
//! k_i = w_i C_i + H_kin, w = (1, 3, 3) and C = (E, G, G), the relative
//! stress ξ = σ − α follows from its trial value as
//! ξ_i = ξ_i^tr / (1 + k_i Δλ / Y), and the plastic multiplier Δλ = Δē
//! solves |ξ(Δλ)|_eq = Y(ē + Δλ), one monotone equation (safeguarded
//! Newton). Its consistent tangent differentiates that solution (the
//! implicit-function theorem on the four equations), so Newton on the
//! structure converges quadratically.
//!
//! The section's ring rule needs order 12 on a plastic layer to integrate
//! the moment of a yielding tube within 1 % (8 leaves it 1.1 % low at ten
//! times the yield curvature: the stress has kinks between the points);
//! `ancf-core/tests/beam_plasticity.rs` checks it against the closed form.

/// How the yield surface moves with plastic flow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hardening {
    /// The surface translates (Prager): the Bauschinger effect of cyclic
    /// bending. The default.
    #[default]
    Kinematic,
    /// The surface grows.
    Isotropic,
}

impl Hardening {
    /// The hardening a scene or a Python call names (`None`: the default,
    /// kinematic), or the message refusing an unknown name.
    pub fn from_name(name: Option<&str>) -> Result<Self, String> {
        match name {
            None | Some("kinematic") => Ok(Hardening::Kinematic),
            Some("isotropic") => Ok(Hardening::Isotropic),
            Some(other) => Err(format!(
                "unknown hardening \"{other}\" (use \"kinematic\" or \"isotropic\")"
            )),
        }
    }
}

/// The Cowper–Symonds rate law: the yield stress times 1 + (ē̇ / D)^(1/q).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CowperSymonds {
    /// D, 1/s (mild steel: 40.4, Jones, *Structural Impact*).
    pub d: f64,
    /// q (mild steel: 5).
    pub q: f64,
}

/// An elastic–plastic law for the stresses a beam carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamPlasticity {
    /// E, Pa.
    pub youngs_modulus: f64,
    /// G, Pa.
    pub shear_modulus: f64,
    /// f_y, Pa.
    pub yield_stress: f64,
    /// H, Pa (0: perfectly plastic).
    pub hardening_modulus: f64,
    /// How H acts.
    pub hardening: Hardening,
    /// The rate law (`None`: rate-independent).
    pub rate: Option<CowperSymonds>,
}

/// What a point remembers between steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlasticState {
    /// Plastic ε₁₁, γ₂, γ₃.
    pub plastic_strain: [f64; 3],
    /// Back stress (σ, τ₂, τ₃), Pa.
    pub back_stress: [f64; 3],
    /// Equivalent plastic strain ē.
    pub equivalent: f64,
    /// The stress (σ, τ₂, τ₃) it was left at, Pa: the start of the next
    /// step's plastic-work trapezoid.
    #[serde(default)]
    pub stress: [f64; 3],
}

impl PlasticState {
    /// Whether the point never flowed: ē = 0, which every plastic step
    /// raises (Δē = Δλ > 0), so that its plastic strain and back stress
    /// are zero too (the stress it was left at aside).
    #[inline]
    pub fn is_virgin(&self) -> bool {
        self.equivalent == 0.0
    }
}

/// The response of a point to a strain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointResponse {
    /// (σ, τ₂, τ₃), Pa.
    pub stress: [f64; 3],
    /// ∂ stress / ∂ (ε₁₁, γ₂, γ₃), the consistent tangent, Pa.
    pub tangent: [[f64; 3]; 3],
    /// The state after the step (to keep once the step is accepted).
    pub state: PlasticState,
    /// Whether the step flowed plastically.
    pub yielding: bool,
}

/// Weights of the equivalent stress: σ_eq² = Σ w_i ξ_i².
const W: [f64; 3] = [1.0, 3.0, 3.0];

impl BeamPlasticity {
    /// The incremental potential ψ (J/m³) of a step from `old` that the
    /// return map took to `new` at `strain`: the elastic energy
    /// ½ Σ C_i (ε_i − ε_i^p)², the kinematic hardening's stored energy
    /// ½ H_kin Σ (ε_i^p)² / w_i, and the work of the yield stress over the
    /// step, (f_y + H_iso ē) Δē + ½ H_iso Δē² (rate-independent part). The
    /// return map minimizes it over the plastic strain, so its derivative
    /// in the strain is the stress (Ortiz & Stainier's variational
    /// update): the static solver's line search descends on it. At a
    /// state the step left (Δē = 0) it is the stored energy.
    pub fn incremental_energy(
        &self,
        strain: [f64; 3],
        old: &PlasticState,
        new: &PlasticState,
    ) -> f64 {
        let c = self.moduli();
        let (h_iso, _) = self.split();
        let elastic: f64 = (0..3)
            .map(|i| 0.5 * c[i] * (strain[i] - new.plastic_strain[i]).powi(2))
            .sum();
        let dl = new.equivalent - old.equivalent;
        let yield_work = (self.yield_stress + h_iso * old.equivalent) * dl + 0.5 * h_iso * dl * dl;
        elastic + self.kinematic_energy(new) + yield_work
    }

    /// The kinematic hardening's stored energy ½ H_kin Σ (ε_i^p)² / w_i
    /// (J/m³): the back stress is α_i = H_kin ε_i^p / w_i.
    fn kinematic_energy(&self, state: &PlasticState) -> f64 {
        let (_, h_kin) = self.split();
        (0..3)
            .map(|i| 0.5 * h_kin * state.plastic_strain[i].powi(2) / W[i])
            .sum()
    }

    /// The work density dissipated by the step from `old` to `new`
    /// (J/m³): the trapezoid ½ (σ_old + σ_new) · Δε^p less what the
    /// kinematic hardening stored, so that the stored energy
    /// ([`Self::incremental_energy`] at Δē = 0) and this balance the
    /// stresses' trapezoid work ½ (σ_old + σ_new) · Δε.
    pub fn plastic_work(&self, old: &PlasticState, new: &PlasticState) -> f64 {
        let trapezoid: f64 = (0..3)
            .map(|i| {
                0.5 * (old.stress[i] + new.stress[i])
                    * (new.plastic_strain[i] - old.plastic_strain[i])
            })
            .sum();
        trapezoid - (self.kinematic_energy(new) - self.kinematic_energy(old))
    }

    /// (E, G, G), Pa: the moduli of (E₁₁, γ₁₂, γ₁₃).
    pub fn beam_moduli(&self) -> [f64; 3] {
        self.moduli()
    }

    /// Whether a point with no history stays elastic at `strain`: its
    /// trial stress inside the initial yield surface.
    #[inline]
    pub fn is_elastic_from_virgin(&self, strain: [f64; 3]) -> bool {
        // The rate law scales the yield stress only once the point flows
        // (Δē > 0), so the initial surface is f_y's.
        let (e, g) = (self.youngs_modulus, self.shear_modulus);
        let (s, t2, t3) = (e * strain[0], g * strain[1], g * strain[2]);
        s * s + 3.0 * (t2 * t2 + t3 * t3) <= self.yield_stress * self.yield_stress
    }

    fn moduli(&self) -> [f64; 3] {
        [self.youngs_modulus, self.shear_modulus, self.shear_modulus]
    }

    /// The isotropic part of the hardening modulus, and the kinematic.
    fn split(&self) -> (f64, f64) {
        match self.hardening {
            Hardening::Isotropic => (self.hardening_modulus, 0.0),
            Hardening::Kinematic => (0.0, self.hardening_modulus),
        }
    }

    /// The yield stress after a plastic step Δλ from ē over `dt` s, and
    /// its derivative in Δλ.
    fn yield_after(&self, equivalent: f64, dl: f64, dt: Option<f64>) -> (f64, f64) {
        let (h_iso, _) = self.split();
        let base = self.yield_stress + h_iso * (equivalent + dl);
        match (self.rate, dt) {
            (Some(r), Some(dt)) if dt > 0.0 && dl > 0.0 => {
                let x = dl / (dt * r.d);
                let factor = 1.0 + x.powf(1.0 / r.q);
                let dfactor = x.powf(1.0 / r.q - 1.0) / (r.q * dt * r.d);
                (base * factor, h_iso * factor + base * dfactor)
            }
            _ => (base, h_iso),
        }
    }

    /// The stress, consistent tangent and new state at strain (ε₁₁, γ₂,
    /// γ₃) from `old`, over a step of `dt` s (the rate law's; `None`:
    /// rate-independent).
    pub fn respond(&self, strain: [f64; 3], old: &PlasticState, dt: Option<f64>) -> PointResponse {
        let c = self.moduli();
        let (_, h_kin) = self.split();
        let trial: [f64; 3] = std::array::from_fn(|i| {
            c[i] * (strain[i] - old.plastic_strain[i]) - old.back_stress[i]
        });
        let eq = |x: &[f64; 3]| (0..3).map(|i| W[i] * x[i] * x[i]).sum::<f64>().sqrt();
        let (y0, _) = self.yield_after(old.equivalent, 0.0, dt);
        if eq(&trial) <= y0 {
            let stress = std::array::from_fn(|i| trial[i] + old.back_stress[i]);
            let mut tangent = [[0.0; 3]; 3];
            for i in 0..3 {
                tangent[i][i] = c[i];
            }
            return PointResponse {
                stress,
                tangent,
                state: PlasticState { stress, ..*old },
                yielding: false,
            };
        }
        let k: [f64; 3] = std::array::from_fn(|i| W[i] * c[i] + h_kin);
        // ξ(Δλ) for the multiplier and the yield stress it meets.
        let xi_at = |dl: f64, y: f64| -> [f64; 3] {
            std::array::from_fn(|i| trial[i] / (1.0 + k[i] * dl / y))
        };
        let residual = |dl: f64| {
            let (y, dy) = self.yield_after(old.equivalent, dl, dt);
            let xi = xi_at(dl, y);
            let q = eq(&xi);
            // dq/dΔλ through ξ_i = t_i / (1 + k_i Δλ / Y(Δλ)).
            let dq: f64 = (0..3)
                .map(|i| {
                    let d = 1.0 + k[i] * dl / y;
                    let dd = k[i] / y - k[i] * dl * dy / (y * y);
                    W[i] * xi[i] * (-trial[i] * dd / (d * d))
                })
                .sum::<f64>()
                / q;
            (q - y, dq - dy)
        };
        // Bracket: φ(0) > 0; φ falls monotonically and is negative once
        // Δλ passes the elastic trial's distance over the smallest k.
        let (mut lo, mut hi) = (
            0.0,
            2.0 * eq(&trial) / k.iter().fold(f64::MAX, |a, &b| a.min(b)),
        );
        while residual(hi).0 > 0.0 {
            hi *= 2.0;
        }
        let mut dl = 0.5 * (lo + hi);
        for _ in 0..200 {
            let (f, df) = residual(dl);
            if f > 0.0 {
                lo = dl;
            } else {
                hi = dl;
            }
            let newton = dl - f / df;
            let next = if df < 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            let done = (next - dl).abs() <= 1e-15 * next.abs().max(1e-300) || hi - lo <= 1e-16 * hi;
            dl = next;
            if done {
                break;
            }
        }
        let (y, dy) = self.yield_after(old.equivalent, dl, dt);
        let xi = xi_at(dl, y);
        let q = eq(&xi);
        let n: [f64; 3] = std::array::from_fn(|i| W[i] * xi[i] / q);
        let mut state = *old;
        for i in 0..3 {
            state.plastic_strain[i] += dl * n[i];
            state.back_stress[i] += h_kin * dl * xi[i] / q;
        }
        state.equivalent += dl;
        let stress: [f64; 3] = std::array::from_fn(|i| xi[i] + state.back_stress[i]);
        state.stress = stress;
        // Consistent tangent: the equations F_i = ξ_i − t_i + k_i Δλ ξ_i / q
        // = 0 and G = q − Y(Δλ) = 0 in (ξ, Δλ), with ∂t_i/∂ε_j = C_i δ_ij.
        let mut j = [[0.0; 4]; 4];
        for a in 0..3 {
            for b in 0..3 {
                let dq_db = W[b] * xi[b] / q;
                j[a][b] = if a == b { 1.0 + k[a] * dl / q } else { 0.0 }
                    - k[a] * dl * xi[a] * dq_db / (q * q);
            }
            j[a][3] = k[a] * xi[a] / q;
            j[3][a] = W[a] * xi[a] / q;
        }
        j[3][3] = -dy;
        let inv = invert4(&j);
        // d(ξ, Δλ)/dε_m = J⁻¹ (C_m e_m).
        let mut dx = [[0.0; 3]; 4];
        for (row, d) in dx.iter_mut().enumerate() {
            for m in 0..3 {
                d[m] = inv[row][m] * c[m];
            }
        }
        // σ_i = ξ_i + α_i^n + H_kin Δλ ξ_i / q.
        let mut tangent = [[0.0; 3]; 3];
        for i in 0..3 {
            for m in 0..3 {
                let dq: f64 = (0..3).map(|b| W[b] * xi[b] / q * dx[b][m]).sum();
                let d_ratio = xi[i] / q * dx[3][m] + dl / q * dx[i][m] - dl * xi[i] / (q * q) * dq;
                tangent[i][m] = dx[i][m] + h_kin * d_ratio;
            }
        }
        PointResponse {
            stress,
            tangent,
            state,
            yielding: true,
        }
    }
}

/// The inverse of a 4 × 4 matrix by Gauss–Jordan with partial pivoting.
fn invert4(a: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut m = *a;
    let mut inv = [[0.0; 4]; 4];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..4 {
        let p = (col..4)
            .max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))
            .unwrap_or(col);
        m.swap(col, p);
        inv.swap(col, p);
        let d = m[col][col];
        for k in 0..4 {
            m[col][k] /= d;
            inv[col][k] /= d;
        }
        for r in 0..4 {
            if r != col {
                let f = m[r][col];
                for k in 0..4 {
                    m[r][k] -= f * m[col][k];
                    inv[r][k] -= f * inv[col][k];
                }
            }
        }
    }
    inv
}
