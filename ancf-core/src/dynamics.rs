//! Implicit generalized-α time integration (Chung–Hulbert, SPEC §6), Newton
//! on the accelerations, with full or modified Newton and step cutting.

use crate::assembly::{Pattern, assemble, mass_values};
use crate::linear_solver::SparseSolver;
use crate::model::Model;

/// How often the Newton matrix is refactorized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonKind {
    /// Fresh Jacobian and factorization every iteration.
    Full,
    /// Keep the factorization across iterations and steps while Newton
    /// converges well (contraction ≤ 0.25 per iteration, ≤ 6 iterations);
    /// refactor otherwise. The default: on the pendulum it needs the same
    /// steps at a fraction of the factorizations.
    Modified,
}

/// Settings of the dynamic solver.
#[derive(Clone, Debug)]
pub struct DynamicSettings {
    /// Time step h, s.
    pub time_step: f64,
    /// End time, s.
    pub end_time: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1]; 1 = no numerical damping.
    pub spectral_radius: f64,
    pub newton: NewtonKind,
    /// Newton iterations allowed per step before the step is cut. Default 25.
    pub max_iterations: usize,
    /// Relative residual tolerance. Default 1e-10.
    pub tolerance: f64,
    /// How many times a step may be halved before the run fails. Default 10.
    pub max_cuts: usize,
}

impl Default for DynamicSettings {
    fn default() -> Self {
        DynamicSettings {
            time_step: 1e-3,
            end_time: 1.0,
            spectral_radius: 1.0,
            newton: NewtonKind::Modified,
            max_iterations: 25,
            tolerance: 1e-10,
            max_cuts: 10,
        }
    }
}

/// Generalized-α parameters from ρ∞.
#[derive(Clone, Copy, Debug)]
pub struct AlphaParameters {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl AlphaParameters {
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

/// State in full coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub time: f64,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// Energies of a state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    pub kinetic: f64,
    pub strain: f64,
    pub gravity: f64,
    pub loads: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.gravity + self.loads
    }
}

/// Statistics of one completed step.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepInfo {
    pub iterations: usize,
    pub factorizations: usize,
    /// Sub-steps used (1 when no cut was needed).
    pub substeps: usize,
}

#[derive(Clone, Debug)]
pub struct StepError {
    pub message: String,
}

/// The integrator: owns the pattern, the symbolic factorization and the
/// constant mass values, computed once per model.
pub struct Integrator<'m> {
    pub model: &'m Model,
    pub settings: DynamicSettings,
    params: AlphaParameters,
    pattern: Pattern,
    mass: Vec<f64>,
    solver: SparseSolver,
    /// Step size of the current factorization, if it is valid for reuse.
    factored_for: Option<f64>,
    ext: Vec<f64>,
    /// Residual entries below this are round-off (N), see [`Model::roundoff_force`].
    roundoff: f64,
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

impl<'m> Integrator<'m> {
    pub fn new(model: &'m Model, settings: DynamicSettings) -> Result<Self, StepError> {
        let pattern = Pattern::new(model);
        let solver = SparseSolver::new(&pattern).map_err(|e| StepError { message: e.0 })?;
        let mass = mass_values(model, &pattern);
        Ok(Integrator {
            params: AlphaParameters::new(settings.spectral_radius),
            model,
            settings,
            mass,
            solver,
            factored_for: None,
            ext: model.external_force(1.0),
            roundoff: model.roundoff_force(),
            pattern,
        })
    }

    /// Initial state at rest at `q0`, with the consistent initial
    /// acceleration M a₀ = Q_ext − Q_e(q₀).
    pub fn initial_state(&mut self, q0: Vec<f64>, v0: Vec<f64>) -> Result<State, StepError> {
        let (qe, _) = assemble(self.model, &self.pattern, &q0, None);
        let rhs_full: Vec<f64> = self.ext.iter().zip(&qe).map(|(a, b)| a - b).collect();
        let mut a = self.model.gather(&rhs_full);
        // Subtract the mass coupling to prescribed velocities' rates (zero: supports are fixed).
        self.solver.factorize(&self.mass).map_err(|e| StepError {
            message: format!("mass matrix: {}", e.0),
        })?;
        self.factored_for = None;
        self.solver.solve_in_place(&mut a);
        let mut a_full = vec![0.0; q0.len()];
        self.model.scatter_add(&a, 1.0, &mut a_full);
        Ok(State {
            time: 0.0,
            q: q0,
            v: v0,
            a: a_full,
        })
    }

    /// Energies of a state.
    pub fn energies(&self, s: &State) -> Energies {
        let (_, strain) = assemble(self.model, &self.pattern, &s.q, None);
        let mv = self.model.mass_times(&s.v);
        let kinetic = 0.5 * s.v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
        let (gravity, loads) = self.model.external_potential(&s.q);
        Energies {
            kinetic,
            strain,
            gravity,
            loads,
        }
    }

    /// Advance by one step of size `h`, cutting it in halves on failure.
    pub fn step(&mut self, s: &State, h: f64) -> Result<(State, StepInfo), StepError> {
        self.step_cut(s, h, 0)
    }

    fn step_cut(
        &mut self,
        s: &State,
        h: f64,
        depth: usize,
    ) -> Result<(State, StepInfo), StepError> {
        match self.try_step(s, h) {
            Ok((next, mut info)) => {
                info.substeps = 1;
                Ok((next, info))
            }
            Err(e) if depth < self.settings.max_cuts => {
                let _ = e;
                self.factored_for = None;
                let (mid, i1) = self.step_cut(s, 0.5 * h, depth + 1)?;
                let (end, i2) = self.step_cut(&mid, 0.5 * h, depth + 1)?;
                Ok((
                    end,
                    StepInfo {
                        iterations: i1.iterations + i2.iterations,
                        factorizations: i1.factorizations + i2.factorizations,
                        substeps: i1.substeps + i2.substeps,
                    },
                ))
            }
            Err(e) => Err(StepError {
                message: format!(
                    "{} (after halving the step {} times, h = {:.3e} s)",
                    e.message, depth, h
                ),
            }),
        }
    }

    /// One generalized-α step of size h without cutting.
    fn try_step(&mut self, s: &State, h: f64) -> Result<(State, StepInfo), StepError> {
        let AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.params;
        let model = self.model;
        let n = s.q.len();
        // Predictor: a₁ = a₀.
        let mut a1 = s.a.clone();
        let mut q1 = vec![0.0; n];
        let mut v1 = vec![0.0; n];
        let mut info = StepInfo::default();
        let c_k = (1.0 - alpha_f) * beta * h * h;
        let mut prev_rn = f64::INFINITY;
        let mut kv = self.pattern.zeros();
        for it in 0..=self.settings.max_iterations {
            for c in 0..n {
                q1[c] = s.q[c] + h * s.v[c] + h * h * ((0.5 - beta) * s.a[c] + beta * a1[c]);
                v1[c] = s.v[c] + h * ((1.0 - gamma) * s.a[c] + gamma * a1[c]);
            }
            let qm: Vec<f64> = (0..n)
                .map(|c| (1.0 - alpha_f) * q1[c] + alpha_f * s.q[c])
                .collect();
            let am: Vec<f64> = (0..n)
                .map(|c| (1.0 - alpha_m) * a1[c] + alpha_m * s.a[c])
                .collect();
            let need_k = match self.settings.newton {
                NewtonKind::Full => true,
                NewtonKind::Modified => self.factored_for != Some(h),
            };
            if need_k {
                kv.fill(0.0);
            }
            let (qe, _) = assemble(
                model,
                &self.pattern,
                &qm,
                if need_k { Some(&mut kv) } else { None },
            );
            let ma = model.mass_times(&am);
            let r_full: Vec<f64> = (0..n).map(|c| ma[c] + qe[c] - self.ext[c]).collect();
            let r = model.gather(&r_full);
            let rn = norm(&r);
            let scale = norm(&model.gather(&ma))
                .max(norm(&model.gather(&self.ext)))
                .max(norm(&model.gather(&qe)));
            if !rn.is_finite() {
                self.factored_for = None;
                return Err(StepError {
                    message: "non-finite residual (NaN or overflow)".into(),
                });
            }
            if it > 0 && (rn <= self.settings.tolerance * scale || norm_inf(&r) <= self.roundoff) {
                info.iterations = it;
                if self.settings.newton == NewtonKind::Modified && it > 6 {
                    self.factored_for = None;
                }
                let time = s.time + h;
                return Ok((
                    State {
                        time,
                        q: q1,
                        v: v1,
                        a: a1,
                    },
                    info,
                ));
            }
            if it == self.settings.max_iterations {
                break;
            }
            // Modified Newton: refresh a factorization that contracts too slowly.
            if self.settings.newton == NewtonKind::Modified && it > 1 && rn > 0.25 * prev_rn {
                self.factored_for = None;
                kv.fill(0.0);
                assemble(model, &self.pattern, &qm, Some(&mut kv));
            }
            prev_rn = rn;
            if self.factored_for != Some(h) || self.settings.newton == NewtonKind::Full {
                let a_mat: Vec<f64> = self
                    .mass
                    .iter()
                    .zip(&kv)
                    .map(|(m, k)| (1.0 - alpha_m) * m + c_k * k)
                    .collect();
                self.solver
                    .factorize(&a_mat)
                    .map_err(|e| StepError { message: e.0 })?;
                info.factorizations += 1;
                self.factored_for = Some(h);
            }
            let mut da = r;
            self.solver.solve_in_place(&mut da);
            model.scatter_add(&da, -1.0, &mut a1);
        }
        self.factored_for = None;
        Err(StepError {
            message: format!(
                "Newton did not converge in {} iterations",
                self.settings.max_iterations
            ),
        })
    }
}
