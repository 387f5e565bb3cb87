//! Constitutive laws, written as energy → stress → tangent (each the
//! derivative of the one before, and tested that way).
//!
//! Voigt convention used throughout the crate:
//! strain ε = [E11, E22, E33, 2E23, 2E13, 2E12] (engineering shears),
//! stress σ = [S11, S22, S33, S23, S13, S12] (second Piola–Kirchhoff, Pa),
//! so that dW = σ · dε and the tangent D = ∂σ/∂ε is symmetric.

pub mod beam_plasticity;

use crate::check::{ParameterError, finite, positive, refuse};
use nalgebra::{Matrix3, Matrix6, Vector6};

/// Voigt index pairs (a, b) of the six strain/stress components.
pub const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// Green–Lagrange strain in Voigt form from the symmetric tensor E.
pub fn voigt_strain(e: &Matrix3<f64>) -> Vector6<f64> {
    Vector6::new(
        e[(0, 0)],
        e[(1, 1)],
        e[(2, 2)],
        2.0 * e[(1, 2)],
        2.0 * e[(0, 2)],
        2.0 * e[(0, 1)],
    )
}

/// Symmetric tensor from Voigt stress components.
pub fn tensor_from_stress(s: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2])
}

/// Symmetric tensor E from Voigt strain components (shears halved).
pub fn tensor_from_strain(e: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(
        e[0],
        0.5 * e[5],
        0.5 * e[4],
        0.5 * e[5],
        e[1],
        0.5 * e[3],
        0.5 * e[4],
        0.5 * e[3],
        e[2],
    )
}

/// Lamé parameters (λ, μ) in Pa from Young's modulus (Pa) and Poisson's ratio.
pub fn lame(youngs_modulus: f64, poisson_ratio: f64) -> (f64, f64) {
    let (e, nu) = (youngs_modulus, poisson_ratio);
    (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    )
}

/// Isotropic St. Venant–Kirchhoff elasticity matrix D (Pa) in Voigt form.
pub fn isotropic_elasticity(youngs_modulus: f64, poisson_ratio: f64) -> Matrix6<f64> {
    let (lambda, mu) = lame(youngs_modulus, poisson_ratio);
    let mut d = Matrix6::zeros();
    for a in 0..3 {
        for b in 0..3 {
            d[(a, b)] = lambda;
        }
        d[(a, a)] += 2.0 * mu;
        d[(a + 3, a + 3)] = mu;
    }
    d
}

/// A pointwise hyperelastic law: strain energy density W(ε) in J/m³.
/// (A few per model, read in the hot loop: kept inline, not boxed.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Law {
    /// W = ½ εᵀ D ε with a constant symmetric D (Pa): St. Venant–Kirchhoff
    /// and its parts (the weakened-bending split).
    Linear(Matrix6<f64>),
    /// Nearly incompressible Mooney–Rivlin (SPEC §3.2), all in Pa:
    /// W = μ10 (I1 − 3) + μ01 (I2 − 3) + k1 (I3 − 1) + k2 (I3 − 1)².
    MooneyRivlin {
        /// μ10 (Pa).
        mu10: f64,
        /// μ01 (Pa).
        mu01: f64,
        /// k1 (Pa), chosen so the reference is stress free.
        k1: f64,
        /// k2 (Pa), the volume penalty.
        k2: f64,
    },
    /// W = W_a − W_b: the centerline remainder of a locking split.
    Difference(Box<Law>, Box<Law>),
}

ancf_macros::mooney_rivlin_kernel! {
    /// Generated Mooney–Rivlin stress and tangent (Voigt), unrolled by
    /// `ancf_macros::mooney_rivlin_kernel!`; tested against
    /// [`Law::stress_tangent_generic`].
    pub fn mooney_rivlin_generated;
}

/// Stress and tangent of a law at one strain.
#[derive(Clone, Copy, Debug)]
pub struct StressTangent {
    /// Second Piola–Kirchhoff stress, Voigt (Pa).
    pub stress: Vector6<f64>,
    /// ∂S/∂E, Voigt (Pa).
    pub tangent: Matrix6<f64>,
}

/// Invariants of C (I1, I2, I3) and its cofactor matrix (= I3 C⁻¹, defined
/// without an inverse, so an inverted element gives numbers, not NaN).
fn invariants_and_cofactor(c: &Matrix3<f64>) -> (f64, f64, f64, Matrix3<f64>) {
    let i1 = c.trace();
    let c2 = c * c;
    let i2 = 0.5 * (i1 * i1 - c2.trace());
    // Cayley–Hamilton: adj(C) = C² − I1 C + I2 I (= cof(C) for symmetric C).
    let cof = c2 - c * i1 + Matrix3::identity() * i2;
    let i3 = (c * cof).trace() / 3.0;
    (i1, i2, i3, cof)
}

impl Law {
    /// Mooney–Rivlin with k1 = −(μ10 + 2μ01) (stress-free reference) and
    /// k2 = κ · max(μ10, μ01).
    pub fn mooney_rivlin(mu10: f64, mu01: f64, penalty: f64) -> Self {
        Law::MooneyRivlin {
            mu10,
            mu01,
            k1: -(mu10 + 2.0 * mu01),
            k2: penalty * mu10.max(mu01),
        }
    }

    /// Whether this law is the Mooney–Rivlin kernel (used to prove that an
    /// all-SVK model never evaluates it).
    pub fn is_mooney_rivlin(&self) -> bool {
        match self {
            Law::MooneyRivlin { .. } => true,
            Law::Difference(a, b) => a.is_mooney_rivlin() || b.is_mooney_rivlin(),
            Law::Linear(_) => false,
        }
    }

    /// Strain energy density W (J/m³).
    pub fn energy(&self, eps: &Vector6<f64>) -> f64 {
        match self {
            Law::Linear(d) => 0.5 * eps.dot(&(d * eps)),
            Law::Difference(a, b) => a.energy(eps) - b.energy(eps),
            Law::MooneyRivlin { mu10, mu01, k1, k2 } => {
                let c = Matrix3::identity() + tensor_from_strain(eps) * 2.0;
                let (i1, i2, i3, _) = invariants_and_cofactor(&c);
                mu10 * (i1 - 3.0) + mu01 * (i2 - 3.0) + k1 * (i3 - 1.0) + k2 * (i3 - 1.0).powi(2)
            }
        }
    }

    /// Second Piola–Kirchhoff stress σ = ∂W/∂ε (Pa).
    pub fn stress(&self, eps: &Vector6<f64>) -> Vector6<f64> {
        match self {
            Law::Linear(d) => d * eps,
            Law::Difference(a, b) => a.stress(eps) - b.stress(eps),
            Law::MooneyRivlin { .. } => self.stress_tangent(eps).stress,
        }
    }

    /// Stress and tangent D = ∂σ/∂ε (Pa); Mooney–Rivlin through the generated kernel.
    pub fn stress_tangent(&self, eps: &Vector6<f64>) -> StressTangent {
        match self {
            Law::MooneyRivlin { mu10, mu01, k1, k2 } => {
                let (stress, tangent) = mooney_rivlin_generated(eps, *mu10, *mu01, *k1, *k2);
                StressTangent { stress, tangent }
            }
            Law::Difference(a, b) => {
                let (sa, sb) = (a.stress_tangent(eps), b.stress_tangent(eps));
                StressTangent {
                    stress: sa.stress - sb.stress,
                    tangent: sa.tangent - sb.tangent,
                }
            }
            Law::Linear(d) => StressTangent {
                stress: d * eps,
                tangent: *d,
            },
        }
    }

    /// The hand-written reference (3×3 matrix algebra, one directional
    /// derivative per column): what the generated kernel is tested against.
    pub fn stress_tangent_generic(&self, eps: &Vector6<f64>) -> StressTangent {
        match self {
            Law::Linear(_) | Law::Difference(..) => self.stress_tangent(eps),
            Law::MooneyRivlin { mu10, mu01, k1, k2 } => {
                let id = Matrix3::identity();
                let c = id + tensor_from_strain(eps) * 2.0;
                let (i1, _i2, i3, cof) = invariants_and_cofactor(&c);
                let p = k1 + 2.0 * k2 * (i3 - 1.0);
                // S = 2 [μ10 I + μ01 (I1 I − C) + p cof(C)]
                let s = (id * *mu10 + (id * i1 - c) * *mu01 + cof * p) * 2.0;
                let stress = Vector6::from_fn(|r, _| s[VOIGT[r]]);
                // dS = 2 [μ01 (tr H I − H) + 2 k2 (cof : H) cof + p dcof[H]], H = dC = 2 dE,
                // dcof[H] = CH + HC − tr H C − tr C H + (tr C tr H − tr(CH)) I.
                let mut tangent = Matrix6::zeros();
                for col in 0..6 {
                    let mut de = Vector6::zeros();
                    de[col] = 1.0;
                    let h = tensor_from_strain(&de) * 2.0;
                    let trh = h.trace();
                    let ch = c * h;
                    let dcof = ch + h * c - c * trh - h * i1 + id * (i1 * trh - ch.trace());
                    let cof_h = cof.component_mul(&h).sum();
                    let ds = ((id * trh - h) * *mu01 + cof * (2.0 * k2 * cof_h) + dcof * p) * 2.0;
                    for r in 0..6 {
                        tangent[(r, col)] = ds[VOIGT[r]];
                    }
                }
                StressTangent { stress, tangent }
            }
        }
    }
}

/// How a layer's energy avoids the locking of the element's linear
/// transverse field (SPEC §3.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Locking {
    /// The paper's plain formulation: the whole law over the section.
    None,
    /// The default. SVK: the normal block without its Poisson coupling
    /// (E on the diagonal) and the true shear modulus G = E / 2(1 + ν) over
    /// the section, the normal block's remainder (λ's coupling, λ + 2μ − E
    /// on its diagonal) on the centerline — so torsion, whose shear strain
    /// vanishes on the centerline, sees G J. Mooney–Rivlin: a ν = 0 SVK law with the small-strain
    /// modulus E_c = 6(μ10 + μ01) over the section, W_MR − W_SVK on the
    /// centerline. Uniform states are unchanged (both parts integrate to the
    /// full law); bending sees E I instead of the locked stiffness.
    #[default]
    Centerline,
}

/// A material as a user describes it (one per layer), with its density.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Mass density, kg/m³.
    pub density: f64,
    /// The constitutive model and its constants.
    pub model: MaterialModel,
    /// The locking remedy (how the law is split between section and centerline).
    pub locking: Locking,
    /// The yield stress f_y (Pa) of an elastic material, when known: the
    /// law stays elastic, but a run warns where the stress passes it and
    /// reports a member's utilization against it. `None`: not checked.
    pub yield_stress: Option<f64>,
}

/// Poisson's ratio of a St. Venant–Kirchhoff material unless given: 0, the
/// value with which this element does not lock in bending (SPEC §3.3).
pub const DEFAULT_POISSON_RATIO: f64 = 0.0;

/// The weakened-bending coefficient ω unless given: 1, the plain continuum.
pub const DEFAULT_BENDING_FACTOR: f64 = 1.0;

impl Material {
    /// St. Venant–Kirchhoff: density (kg/m³), Young's modulus (Pa), Poisson's
    /// ratio and the weakened-bending coefficient ω (1: plain continuum);
    /// the default locking remedy.
    pub fn st_venant_kirchhoff(
        density: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
        bending_factor: f64,
    ) -> Self {
        Material {
            density,
            model: MaterialModel::StVenantKirchhoff {
                youngs_modulus,
                poisson_ratio,
                bending_factor,
            },
            locking: Default::default(),
            yield_stress: None,
        }
    }

    /// The same material with yield stress f_y (Pa): checked against, not
    /// modelled (the law stays elastic).
    pub fn with_yield_stress(self, yield_stress: f64) -> Self {
        Material {
            yield_stress: Some(yield_stress),
            ..self
        }
    }

    /// Nearly incompressible Mooney–Rivlin: density (kg/m³), μ10, μ01 (Pa)
    /// and the volume penalty κ; the default locking remedy.
    pub fn mooney_rivlin(density: f64, mu10: f64, mu01: f64, penalty: f64) -> Self {
        Material {
            density,
            model: MaterialModel::MooneyRivlin {
                mu10,
                mu01,
                penalty,
            },
            locking: Default::default(),
            yield_stress: None,
        }
    }

    /// Whether the constants describe a real material: ρ > 0; SVK: E > 0,
    /// ν ∈ (−1, 0.5) (the bounds of a stable isotropic solid), ω ∈ [0, 1];
    /// Mooney–Rivlin: μ10, μ01 ≥ 0 with μ10 + μ01 > 0, κ > 0; a yield
    /// stress > 0, for SVK only.
    pub fn check(&self) -> Result<(), ParameterError> {
        positive("density", self.density)?;
        if let Some(fy) = self.yield_stress {
            positive("yield_stress", fy)?;
            if matches!(self.model, MaterialModel::MooneyRivlin { .. }) {
                return refuse(
                    "yield_stress",
                    "a Mooney–Rivlin material does not yield: yield_stress is for steel and \
                     aluminium (st-venant-kirchhoff, elastic-plastic)",
                );
            }
        }
        match self.model {
            MaterialModel::StVenantKirchhoff {
                youngs_modulus,
                poisson_ratio,
                bending_factor,
            } => {
                check_elasticity(youngs_modulus, poisson_ratio)?;
                let omega = finite("bending_factor", bending_factor)?;
                if !(0.0..=1.0).contains(&omega) {
                    return refuse(
                        "bending_factor",
                        format!("ω must lie in [0, 1], got {omega}"),
                    );
                }
            }
            MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio,
                hardening_modulus,
                rate,
                ..
            } => {
                check_elasticity(youngs_modulus, poisson_ratio)?;
                if self.locking == Locking::None {
                    return refuse(
                        "locking",
                        "an elastic-plastic layer needs the centerline split (its beam stresses \
                         yield, its transverse stresses stay elastic on the section's diagonal \
                         law): leave locking at its default",
                    );
                }
                let Some(fy) = self.yield_stress else {
                    return refuse(
                        "yield_stress",
                        "an elastic-plastic material needs its yield stress (Pa)",
                    );
                };
                let h = finite("hardening_modulus", hardening_modulus)?;
                if !(0.0..youngs_modulus).contains(&h) {
                    return refuse(
                        "hardening_modulus",
                        format!("must lie in [0, E) = [0, {youngs_modulus:e}) Pa, got {h}"),
                    );
                }
                if fy >= youngs_modulus {
                    return refuse(
                        "yield_stress",
                        format!("must be below Young's modulus {youngs_modulus:e} Pa, got {fy}"),
                    );
                }
                if let Some(r) = rate {
                    positive("rate.d", r.d)?;
                    positive("rate.q", r.q)?;
                }
            }
            MaterialModel::MooneyRivlin {
                mu10,
                mu01,
                penalty,
            } => {
                let (mu10, mu01) = (finite("mu10", mu10)?, finite("mu01", mu01)?);
                if mu10 < 0.0 || mu01 < 0.0 || mu10 + mu01 <= 0.0 {
                    return refuse(
                        if mu10 >= 0.0 && mu01 < 0.0 {
                            "mu01"
                        } else {
                            "mu10"
                        },
                        format!("need μ10 ≥ 0, μ01 ≥ 0 and μ10 + μ01 > 0, got {mu10}, {mu01}"),
                    );
                }
                positive("penalty", penalty)?;
            }
        }
        Ok(())
    }

    /// How this layer integrates its energy (see [`MaterialModel::layer_laws`]).
    pub fn layer_laws(&self) -> LayerLaws {
        let mut laws = self.model.layer_laws(self.locking);
        laws.plastic = self.plasticity();
        laws
    }

    /// The beam plasticity of an elastic–plastic material (`None` for the
    /// others, and for one without its yield stress, which `check` refuses).
    pub fn plasticity(&self) -> Option<beam_plasticity::BeamPlasticity> {
        match self.model {
            MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio,
                hardening_modulus,
                hardening,
                rate,
            } => Some(beam_plasticity::BeamPlasticity {
                youngs_modulus,
                shear_modulus: lame(youngs_modulus, poisson_ratio).1,
                yield_stress: self.yield_stress?,
                hardening_modulus,
                hardening,
                rate,
            }),
            _ => None,
        }
    }

    /// Elastic–plastic (beam-type J2 in the beam stresses): density (kg/m³),
    /// Young's modulus E (Pa), Poisson's ratio, yield stress f_y (Pa) and
    /// linear hardening modulus H (Pa, 0: perfectly plastic), kinematic;
    /// rate-independent.
    pub fn elastic_plastic(
        density: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
        yield_stress: f64,
        hardening_modulus: f64,
    ) -> Self {
        Material {
            density,
            model: MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio,
                hardening_modulus,
                hardening: Default::default(),
                rate: None,
            },
            locking: Default::default(),
            yield_stress: Some(yield_stress),
        }
    }

    /// Whether its beam stresses yield (an elastic–plastic material).
    pub fn is_plastic(&self) -> bool {
        matches!(self.model, MaterialModel::ElasticPlastic { .. })
    }
}

/// E > 0 and ν in (−1, 0.5), the bounds of a stable isotropic solid: the
/// elasticity of St. Venant–Kirchhoff and of the elastic-plastic model.
fn check_elasticity(youngs_modulus: f64, poisson_ratio: f64) -> Result<(), ParameterError> {
    positive("youngs_modulus", youngs_modulus)?;
    let nu = finite("poisson_ratio", poisson_ratio)?;
    if !(nu > -1.0 && nu < 0.5) {
        return refuse("poisson_ratio", format!("must lie in (−1, 0.5), got {nu}"));
    }
    Ok(())
}

/// A constitutive model with its constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MaterialModel {
    /// St. Venant–Kirchhoff: Young's modulus (Pa), Poisson's ratio, and the
    /// weakened-bending coefficient ω ∈ [0, 1] (fraction of the continuum
    /// bending stiffness kept; 1 = plain continuum).
    StVenantKirchhoff {
        /// E (Pa).
        youngs_modulus: f64,
        /// ν.
        poisson_ratio: f64,
        /// ω, the weakened-bending coefficient (1: none).
        bending_factor: f64,
    },
    /// Nearly incompressible Mooney–Rivlin: μ10, μ01 (Pa) and the
    /// dimensionless volume penalty κ (k2 = κ max(μ10, μ01)).
    MooneyRivlin {
        /// μ10 (Pa).
        mu10: f64,
        /// μ01 (Pa).
        mu01: f64,
        /// κ (dimensionless).
        penalty: f64,
    },
    /// St. Venant–Kirchhoff's elasticity (ω = 1) whose beam stresses yield
    /// at the material's `yield_stress` (beam-type J2, see
    /// [`beam_plasticity`]): Young's modulus (Pa), Poisson's ratio, the
    /// linear hardening modulus H (Pa, 0: perfectly plastic), how it acts,
    /// and the rate law.
    ElasticPlastic {
        /// E (Pa).
        youngs_modulus: f64,
        /// ν.
        poisson_ratio: f64,
        /// H (Pa).
        hardening_modulus: f64,
        /// Kinematic or isotropic.
        hardening: beam_plasticity::Hardening,
        /// Cowper–Symonds (`None`: rate-independent).
        rate: Option<beam_plasticity::CowperSymonds>,
    },
}

/// How one layer's energy is integrated: a law over the section points and,
/// only when the layer needs it, a law on the centerline weighted by the
/// layer's area.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerLaws {
    /// The law integrated over the section points.
    pub section: Law,
    /// The law integrated on the centerline (weighted by the layer's area), if any.
    pub centerline: Option<Law>,
    /// The plasticity of the section points' beam stresses (`section` is
    /// then their elastic law, which the transverse stresses keep), if any.
    pub plastic: Option<beam_plasticity::BeamPlasticity>,
}

impl MaterialModel {
    /// Small-strain Young's modulus (Pa) and Poisson's ratio, for contact
    /// stiffness: SVK as given; Mooney–Rivlin E = 6 (μ10 + μ01), ν = 0.5
    /// (shear modulus 2 (μ10 + μ01), incompressible).
    pub fn elastic_constants(&self) -> (f64, f64) {
        match *self {
            MaterialModel::StVenantKirchhoff {
                youngs_modulus,
                poisson_ratio,
                ..
            }
            | MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio,
                ..
            } => (youngs_modulus, poisson_ratio),
            MaterialModel::MooneyRivlin { mu10, mu01, .. } => (6.0 * (mu10 + mu01), 0.5),
        }
    }

    /// Section and centerline laws of a layer. Weakened bending (SPEC
    /// §3.1): the axial term ½ D₁₁ E_xx² of the section law is kept with
    /// weight ω, and (1 − ω) of it moves to the centerline. The locking
    /// treatment is described at [`Locking`]. A layer needing no centerline
    /// term (ω = 1 and no remainder) gets none.
    pub fn layer_laws(&self, locking: Locking) -> LayerLaws {
        if let MaterialModel::ElasticPlastic {
            youngs_modulus,
            poisson_ratio,
            ..
        } = *self
        {
            // Its elasticity is St. Venant–Kirchhoff's, split alike.
            let svk = MaterialModel::StVenantKirchhoff {
                youngs_modulus,
                poisson_ratio,
                bending_factor: 1.0,
            };
            return svk.layer_laws(locking);
        }
        let (mut section, mut centerline) = match (*self, locking) {
            (
                MaterialModel::StVenantKirchhoff {
                    youngs_modulus,
                    poisson_ratio,
                    ..
                },
                Locking::None,
            ) => (
                isotropic_elasticity(youngs_modulus, poisson_ratio),
                Matrix6::zeros(),
            ),
            (
                MaterialModel::StVenantKirchhoff {
                    youngs_modulus,
                    poisson_ratio,
                    ..
                },
                Locking::Centerline,
            ) => {
                // The section keeps E on the normal strains without their
                // Poisson coupling, and the true shear modulus G (torsion
                // and the varying part of transverse shear live only off
                // the centerline); the centerline takes the rest of the
                // normal block: λ's coupling and the diagonal's λ + 2μ − E.
                let full = isotropic_elasticity(youngs_modulus, poisson_ratio);
                let mut d0 = isotropic_elasticity(youngs_modulus, 0.0);
                for k in 3..6 {
                    d0[(k, k)] = full[(k, k)];
                }
                (d0, full - d0)
            }
            (
                MaterialModel::MooneyRivlin {
                    mu10,
                    mu01,
                    penalty,
                },
                Locking::None,
            ) => {
                return LayerLaws {
                    section: Law::mooney_rivlin(mu10, mu01, penalty),
                    centerline: None,
                    plastic: None,
                };
            }
            (
                MaterialModel::MooneyRivlin {
                    mu10,
                    mu01,
                    penalty,
                },
                Locking::Centerline,
            ) => {
                let svk = Law::Linear(isotropic_elasticity(6.0 * (mu10 + mu01), 0.0));
                return LayerLaws {
                    section: svk.clone(),
                    centerline: Some(Law::Difference(
                        Box::new(Law::mooney_rivlin(mu10, mu01, penalty)),
                        Box::new(svk),
                    )),
                    plastic: None,
                };
            }
            (MaterialModel::ElasticPlastic { .. }, _) => {
                unreachable!("elastic-plastic returned above")
            }
        };
        let MaterialModel::StVenantKirchhoff { bending_factor, .. } = *self else {
            unreachable!("Mooney–Rivlin and elastic–plastic returned above")
        };
        if bending_factor != 1.0 {
            let axial = section[(0, 0)];
            section[(0, 0)] = bending_factor * axial;
            centerline[(0, 0)] += (1.0 - bending_factor) * axial;
        }
        let centerline = if centerline.iter().all(|v| *v == 0.0) {
            None
        } else {
            Some(Law::Linear(centerline))
        };
        LayerLaws {
            section: Law::Linear(section),
            centerline,
            plastic: None,
        }
    }

    /// Small-strain Young's modulus (Pa): E for SVK, 6(μ10 + μ01) for Mooney–Rivlin.
    pub fn small_strain_youngs_modulus(&self) -> f64 {
        match *self {
            MaterialModel::StVenantKirchhoff { youngs_modulus, .. }
            | MaterialModel::ElasticPlastic { youngs_modulus, .. } => youngs_modulus,
            MaterialModel::MooneyRivlin { mu10, mu01, .. } => 6.0 * (mu10 + mu01),
        }
    }

    /// Small-strain shear modulus (Pa): Lamé's μ for SVK, 2(μ10 + μ01) for
    /// Mooney–Rivlin.
    pub fn small_strain_shear_modulus(&self) -> f64 {
        match *self {
            MaterialModel::StVenantKirchhoff {
                youngs_modulus,
                poisson_ratio,
                ..
            }
            | MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio,
                ..
            } => lame(youngs_modulus, poisson_ratio).1,
            MaterialModel::MooneyRivlin { mu10, mu01, .. } => 2.0 * (mu10 + mu01),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_strain() -> Vector6<f64> {
        Vector6::new(0.12, -0.05, 0.08, 0.07, -0.11, 0.04)
    }

    fn laws() -> Vec<Law> {
        vec![
            Law::Linear(isotropic_elasticity(2e9, 0.3)),
            Law::mooney_rivlin(5e5, 1e5, 1e3),
            Law::mooney_rivlin(3e5, 4e5, 10.0),
        ]
    }

    #[test]
    fn stress_is_derivative_of_energy_and_tangent_of_stress() {
        let eps = sample_strain();
        for law in laws() {
            let st = law.stress_tangent(&eps);
            let h = 1e-6;
            for j in 0..6 {
                let mut ep = eps;
                let mut em = eps;
                ep[j] += h;
                em[j] -= h;
                let fd = (law.energy(&ep) - law.energy(&em)) / (2.0 * h);
                let scale = st.stress.norm();
                assert!(
                    (fd - st.stress[j]).abs() < 1e-7 * scale,
                    "{law:?} stress {j}: {fd} vs {}",
                    st.stress[j]
                );
                let dfd = (law.stress(&ep) - law.stress(&em)) / (2.0 * h);
                let scale = st.tangent.norm();
                for i in 0..6 {
                    assert!(
                        (dfd[i] - st.tangent[(i, j)]).abs() < 1e-7 * scale,
                        "{law:?} tangent ({i},{j}): {} vs {}",
                        dfd[i],
                        st.tangent[(i, j)]
                    );
                }
            }
            assert!((st.tangent - st.tangent.transpose()).norm() < 1e-12 * st.tangent.norm());
        }
    }

    #[test]
    fn mooney_rivlin_reference_is_stress_free_with_small_strain_modulus() {
        let law = Law::mooney_rivlin(5e5, 1e5, 1e3);
        let st = law.stress_tangent(&Vector6::zeros());
        assert!(st.stress.norm() < 1e-6);
        assert_eq!(law.energy(&Vector6::zeros()), 0.0);
        // Shear modulus 2(μ10 + μ01): D_44 (S23 per engineering γ23) = μ.
        assert!((st.tangent[(3, 3)] - 2.0 * (5e5 + 1e5)).abs() < 1e-6 * 1.2e6);
    }

    #[test]
    fn weakened_bending_split_sums_to_the_continuum_law() {
        let m = MaterialModel::StVenantKirchhoff {
            youngs_modulus: 1e9,
            poisson_ratio: 0.25,
            bending_factor: 0.3,
        };
        for locking in [Locking::None, Locking::Centerline] {
            let laws = m.layer_laws(locking);
            let (Law::Linear(ds), Some(Law::Linear(dc))) = (&laws.section, &laws.centerline) else {
                panic!("expected a linear section law and a centerline law")
            };
            assert!((ds + dc - isotropic_elasticity(1e9, 0.25)).norm() < 1e-3);
            // ω scales the section's axial term only.
            assert!(
                (ds[(0, 0)]
                    - 0.3
                        * if locking == Locking::None {
                            isotropic_elasticity(1e9, 0.25)[(0, 0)]
                        } else {
                            1e9
                        })
                .abs()
                    < 1e-3
            );
        }
        let plain = MaterialModel::StVenantKirchhoff {
            youngs_modulus: 1e9,
            poisson_ratio: 0.0,
            bending_factor: 1.0,
        };
        // ν = 0 and ω = 1: nothing on the centerline with either treatment.
        assert!(plain.layer_laws(Locking::None).centerline.is_none());
        assert!(plain.layer_laws(Locking::Centerline).centerline.is_none());
    }
}

#[cfg(test)]
mod generated_tests {
    use super::*;

    /// The generated Mooney–Rivlin kernel equals the hand-written reference.
    #[test]
    fn generated_mooney_rivlin_equals_generic() {
        let strains = [
            Vector6::zeros(),
            Vector6::new(0.12, -0.05, 0.08, 0.07, -0.11, 0.04),
            Vector6::new(-0.3, 0.25, 0.1, -0.2, 0.15, 0.3),
        ];
        for law in [
            Law::mooney_rivlin(5e5, 1e5, 1e3),
            Law::mooney_rivlin(3e5, 4e5, 1e7),
        ] {
            for eps in &strains {
                let g = law.stress_tangent(eps);
                let r = law.stress_tangent_generic(eps);
                let ds = (g.stress - r.stress).norm() / r.stress.norm().max(1.0);
                let dt = (g.tangent - r.tangent).norm() / r.tangent.norm();
                assert!(
                    ds < 1e-12 && dt < 1e-12,
                    "{law:?} at {eps:?}: stress {ds:e}, tangent {dt:e}"
                );
            }
        }
    }
}
