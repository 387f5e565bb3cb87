//! Static equilibrium Q_e(q) = λ Q_ext by Newton–Raphson with load
//! increments and a backtracking line search (SPEC §5).

use crate::forces::plastic::{History, plastic_step};
use crate::forces::sum::{At, ForceSum};
use crate::linalg::linear_solver::SparseSolver;
use crate::material::beam_plasticity::PlasticState;
use crate::model::Model;
use crate::solve::cancel::CancelToken;
use crate::solve::reactions::support_forces;

/// Settings of the static solver.
#[derive(Clone, Debug)]
pub struct StaticSettings {
    /// Number of equal load increments (≥ 1). Default 1.
    pub load_steps: usize,
    /// Newton iterations allowed per increment. Default 50.
    pub max_iterations: usize,
    /// Relative residual tolerance, ‖R‖ / ‖Q_ext‖. Default 1e-10.
    pub residual_tolerance: f64,
    /// Relative increment tolerance, ‖Δq‖ / ‖q − q_ref‖. Default 1e-10.
    pub increment_tolerance: f64,
}

impl StaticSettings {
    /// Whether Newton can run with these settings: at least one load step
    /// and one iteration, relative tolerances in (0, 1).
    pub fn check(&self) -> Result<(), crate::check::ParameterError> {
        crate::check::count_in("load_steps", self.load_steps, 1..=1_000_000)?;
        crate::check::count_in("max_iterations", self.max_iterations, 1..=10_000)?;
        crate::check::relative_tolerance("tolerance", self.residual_tolerance)?;
        crate::check::relative_tolerance("tolerance", self.increment_tolerance)?;
        Ok(())
    }
}

impl Default for StaticSettings {
    fn default() -> Self {
        StaticSettings {
            load_steps: 1,
            max_iterations: 50,
            residual_tolerance: 1e-10,
            increment_tolerance: 1e-10,
        }
    }
}

/// A static equilibrium.
#[derive(Clone, Debug)]
pub struct StaticResult {
    /// Full coordinates at equilibrium.
    pub q: Vec<f64>,
    /// Newton iterations per load increment (increments are halved on failure).
    pub iterations: Vec<usize>,
    /// Per accepted increment, the relative residual ‖R‖ / scale before
    /// each iteration and at convergence (one more than its iterations):
    /// whether Newton converged quadratically, as the consistent tangent
    /// promises, or lost it (a contact or yield pattern that keeps
    /// changing, a tangent that is not the residual's derivative).
    pub residuals: Vec<Vec<f64>>,
    /// Strain energy at equilibrium (J).
    pub strain_energy: f64,
    /// Force each support exerts on the wire at its node's position r, N.
    pub reactions: Vec<(usize, [f64; 3])>,
    /// The contact at equilibrium (`None` without rods): each rod's force,
    /// the normal force and penetration, the deepest point.
    pub contact: Option<crate::forces::assembly::ContactForces>,
    /// The yielding points' states at equilibrium (see
    /// [`crate::forces::plastic::PlasticLayout`]); empty without a yielding
    /// layer.
    pub plastic: Vec<PlasticState>,
    /// Plastic work per beam over the load path (J); empty without a
    /// yielding layer.
    pub plastic_work: Vec<f64>,
}

/// A static solve that did not converge.
#[derive(Clone, Debug)]
pub struct StaticError {
    /// What failed, and the likely cause.
    pub message: String,
    /// The last converged state (the reference if none).
    pub last_converged: Vec<f64>,
    /// Newton iterations per load increment up to the failure.
    pub iterations: Vec<usize>,
    /// The load factor of `last_converged` (0: the reference): how much
    /// of the load the structure was found to carry.
    pub load_factor: f64,
    /// The solve was stopped by its cancel token (Ctrl-C, a termination
    /// signal), not a failure of Newton.
    pub interrupted: bool,
}

impl std::fmt::Display for StaticError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for StaticError {}

impl StaticError {
    /// What usually causes this failure and what to change (scene field
    /// names), for messages to a user.
    pub fn likely_cause(&self) -> &'static str {
        "supports too far from the wire's reach or a load too large; increase analysis.load_steps"
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Residual on the unknowns, R = Q(q) − λ Q_ext with Q = Q_e − Q_c − Q_m
/// (the sum's load factor is λ), and a scale for it: the largest of the
/// loads' size (‖λQ_ext‖ with the moments') and ‖Q‖ (so round-off in large opposing element forces is judged
/// relative to their size); with `k`, the Jacobian ∂Q/∂q written over it.
/// Returns R, the scale and the strain energy. Statics has normal contact
/// only (no velocities, so no friction and no damping).
fn residual(
    model: &Model,
    forces: &mut ForceSum,
    (q, plastic): (&[f64], &[PlasticState]),
    k: Option<&mut [f64]>,
) -> (Vec<f64>, f64, f64) {
    let at = At {
        plastic,
        ..At::rest(q)
    };
    forces.evaluate(model, at, k, None);
    let (internal, ext) = (forces.internal(), forces.external());
    let full: Vec<f64> = internal.iter().zip(ext).map(|(a, b)| a - b).collect();
    let r = model.gather(&full);
    let scale = forces.load_norm(model).max(norm(&model.gather(internal)));
    (r, scale, forces.strain_energy())
}

/// Solve for static equilibrium from the model's initial coordinates
/// (supports at their positions, see [`Model::initial_coordinates`]).
pub fn solve_static(model: &Model, settings: &StaticSettings) -> Result<StaticResult, StaticError> {
    solve_static_from(model, settings, model.initial_coordinates())
}

/// Newton at one load level from `q`: returns the relative residuals (one
/// per iteration and the converged one) and the strain energy, or a
/// message.
#[allow(clippy::too_many_arguments)]
fn newton(
    model: &Model,
    forces: &mut ForceSum,
    solver: &mut SparseSolver,
    (q, plastic): (&mut Vec<f64>, &[PlasticState]),
    settings: &StaticSettings,
    roundoff: &[f64],
    cancel: Option<&CancelToken>,
) -> Result<(Vec<f64>, f64), String> {
    let mut it = 0;
    let mut history = Vec::new();
    loop {
        if cancel.is_some_and(CancelToken::is_cancelled) {
            return Err("stopped".into());
        }
        let mut kv = forces.pattern().zeros();
        let (r, scale, u) = residual(model, forces, (q, plastic), Some(&mut kv));
        let rn = norm(&r);
        if !rn.is_finite() {
            return Err(
                "the residual is not finite (NaN or overflow in the element forces)".into(),
            );
        }
        history.push(rn / scale.max(f64::MIN_POSITIVE));
        let at_roundoff = super::at_roundoff(&r, roundoff);
        if it > 0 && (rn <= settings.residual_tolerance * scale || at_roundoff) {
            return Ok((history, u));
        }
        if it >= settings.max_iterations {
            return Err(format!(
                "Newton did not converge in {it} iterations (relative residual {:.2e})",
                rn / scale.max(f64::MIN_POSITIVE)
            ));
        }
        let mut coupling = Vec::new();
        forces.coupling().combined(model, 1.0, 0.0, &mut coupling);
        // Moment loads' stiffness is not symmetric (statics has no other
        // unsymmetric part: no friction, no damping).
        let symmetric = model.moment_loads().next().is_none();
        (solver.factorize_coupled(&kv, &coupling, symmetric)).map_err(|e| e.0)?;
        let mut dq = r.clone();
        solver.solve_in_place(&mut dq);
        dq.iter_mut().for_each(|v| *v = -*v);
        // Backtracking line search on the total potential energy
        // Π = U − Q_extᵀ(q − q_ref): a full Newton step on a stiff beam can
        // raise ‖R‖ (a linearized rotation stretches r_x) while Π falls, so
        // the residual norm alone is the wrong merit function here. With
        // yielding points U is the increment's potential (the return map's
        // incremental energy), whose gradient is the force all the same.
        let pi0 = u - forces.external_work(model, q);
        let slope: f64 = r.iter().zip(&dq).map(|(a, b)| a * b).sum();
        let mut alpha = 1.0;
        let mut trial = q.clone();
        for _ in 0..12 {
            trial.copy_from_slice(q);
            model.scatter_add(&dq, alpha, &mut trial);
            let (rt, _, ut) = residual(model, forces, (&trial, plastic), None);
            // A moment load has no potential: its work along the step.
            let moment_work =
                crate::forces::moment::work_along(model, q, &trial, forces.load_factor());
            let pit = ut - forces.external_work(model, &trial) - moment_work;
            let ok_energy =
                pit.is_finite() && pit <= pi0 + 1e-4 * alpha * slope.min(0.0) + 1e-12 * pi0.abs();
            if ok_energy || (norm(&rt).is_finite() && norm(&rt) < rn) || at_roundoff {
                break;
            }
            alpha *= 0.5;
        }
        *q = trial;
        it += 1;
    }
}

/// Solve for static equilibrium starting from the coordinates `q0`
/// (eliminated coordinates keep their values from `q0`). The load is
/// applied in `load_steps` increments; an increment that fails is halved
/// (down to 1/256 of the first) and the next one grows back.
pub fn solve_static_from(
    model: &Model,
    settings: &StaticSettings,
    q0: Vec<f64>,
) -> Result<StaticResult, StaticError> {
    solve_static_cancellable(model, settings, q0, None)
}

/// [`solve_static_from`] that `cancel` stops between Newton iterations
/// (Ctrl-C, a termination signal): the error then says so
/// ([`StaticError::interrupted`]) and keeps the last converged state.
pub fn solve_static_cancellable(
    model: &Model,
    settings: &StaticSettings,
    q0: Vec<f64>,
    cancel: Option<&CancelToken>,
) -> Result<StaticResult, StaticError> {
    solve_static_continuing(model, settings, (q0, Vec::new()), cancel)
}

/// [`solve_static_cancellable`] from coordinates and the yielding points'
/// states a path already reached (`start.1`: a [`StaticResult::plastic`];
/// empty: virgin): the load of `model` is applied from there, so an
/// unloading or a second load case continues the plastic history.
pub fn solve_static_continuing(
    model: &Model,
    settings: &StaticSettings,
    (q0, plastic0): (Vec<f64>, Vec<PlasticState>),
    cancel: Option<&CancelToken>,
) -> Result<StaticResult, StaticError> {
    if let Some(message) = model.static_holding_error() {
        return Err(StaticError {
            message,
            last_converged: q0,
            iterations: vec![],
            load_factor: 0.0,
            interrupted: false,
        });
    }
    let mut forces = ForceSum::new(model);
    let mut solver = SparseSolver::new(forces.pattern()).map_err(|e| StaticError {
        message: e.0,
        last_converged: q0.clone(),
        iterations: vec![],
        load_factor: 0.0,
        interrupted: false,
    })?;
    let roundoff = model.roundoff_forces();
    let mut q = q0;
    let mut iterations = Vec::new();
    let mut residuals = Vec::new();
    let base = 1.0 / settings.load_steps.max(1) as f64;
    let (mut lambda, mut dl) = (0.0f64, base);
    let mut energy = 0.0;
    let layout = forces.plastic_layout().clone();
    let mut plastic = match plastic0.len() {
        0 => layout.virgin(),
        n if n == layout.len() => plastic0,
        n => {
            return Err(StaticError {
                message: format!(
                    "the yielding points' states given are another model's ({n} states; this \
                     model has {})",
                    layout.len()
                ),
                last_converged: q,
                iterations: vec![],
                load_factor: 0.0,
                interrupted: false,
            });
        }
    };
    let mut plastic_work = vec![
        0.0;
        if layout.is_empty() {
            0
        } else {
            model.beams.len()
        }
    ];
    while lambda < 1.0 {
        // Equal increments that sum to 1 in round-off (ten of 0.1 make
        // 0.999…9) end at 1, not with an eleventh of 1e-16.
        let target = match lambda + dl {
            end if end > 1.0 - 1e-9 * dl => 1.0,
            end => end,
        };
        forces.set_load_factor(model, target);
        let mut trial = q.clone();
        let solved = newton(
            model,
            &mut forces,
            &mut solver,
            (&mut trial, &plastic),
            settings,
            &roundoff,
            cancel,
        );
        // An equilibrium in a member crushed through itself is none.
        let solved = solved.and_then(|found| match model.inverted_node(&trial) {
            Some(n) => Err(format!(
                "the equilibrium found has the element at node {n} crushed through itself \
                 (its gradients turned over): the load pushes a member past what it carries"
            )),
            None => Ok(found),
        });
        match solved {
            Ok((history, u)) => {
                iterations.push(history.len() - 1);
                residuals.push(history);
                q = trial;
                lambda = target;
                energy = u;
                dl = (1.5 * dl).min(base);
                if !layout.is_empty() {
                    // The increment is accepted: its points keep their states.
                    let history = History::of(&layout, &plastic, None);
                    let mut next = Vec::new();
                    let steps = plastic_step(model, &layout, &q, history, &mut next);
                    plastic = next;
                    for (w, step) in plastic_work.iter_mut().zip(&steps) {
                        *w += step.work;
                    }
                }
            }
            Err(_) if cancel.is_some_and(CancelToken::is_cancelled) => {
                return Err(StaticError {
                    message: format!(
                        "static solve stopped by Ctrl-C or a termination signal at load factor \
                         {lambda:.4} (the last converged)"
                    ),
                    last_converged: q,
                    iterations,
                    load_factor: lambda,
                    interrupted: true,
                });
            }
            Err(msg) if dl > base / 256.0 => {
                let _ = msg;
                dl *= 0.5;
            }
            Err(msg) => {
                let yielded = plastic.iter().any(|p| p.equivalent > 0.0);
                let mechanism = match yielded {
                    true => {
                        "; the structure had yielded, so the likely cause is a plastic \
                         mechanism: past its collapse load it has no equilibrium (the load \
                         exceeds what the yielding members carry)"
                    }
                    false => "",
                };
                return Err(StaticError {
                    message: format!(
                        "static solve at load factor {target:.4} (last converged {lambda:.4}, increment {dl:.2e}): {msg}{mechanism}"
                    ),
                    last_converged: q,
                    iterations,
                    load_factor: lambda,
                    interrupted: false,
                });
            }
        }
    }
    // Reactions: at equilibrium Q_e − Q_ext − Q_c is the support force on the held coordinates.
    forces.set_load_factor(model, 1.0);
    let at = At {
        plastic: &plastic,
        ..At::rest(&q)
    };
    forces.evaluate(model, at, None, None);
    let mut forces_on_body = Vec::new();
    let (qe, ext) = (forces.internal(), forces.external());
    support_forces(model, (&q, None), None, qe, ext, &mut forces_on_body);
    let nodes = model.supports.iter().map(|s| s.node);
    let reactions = nodes.zip(forces_on_body).collect();
    Ok(StaticResult {
        contact: forces.contact().cloned(),
        q,
        iterations,
        residuals,
        strain_energy: energy,
        reactions,
        plastic,
        plastic_work,
    })
}
