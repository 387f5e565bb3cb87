//! Running a validated scene: the solver loop, what it keeps in memory
//! ([`history`]) and the files it writes ([`files`], `plots`).
//! Numerical failure ends the run with `status = "failed"` and a message
//! naming the step, the time and the likely cause; everything written up
//! to the last converged step stays on disk.
//!
//! The loop drives `ancf_core`'s `Simulation`; a run without an output
//! directory ([`run_in_memory`], the study's) computes the same summary and
//! keeps its records in memory only.

pub mod files;
pub mod history;
pub mod observations;
mod plots;
mod progress;
pub mod supports;

use crate::output::{ContactSummary, EnergySummary, RunStatus, Summary, TipSummary};
use ancf_core::forces::assembly::ContactForces;
use ancf_core::loads::rod_load::{Filtered, LoadHistory, RodLoad};
use ancf_core::math::vec3::norm;
use ancf_core::model::{Effect, Model};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::cancel::CancelToken;
use ancf_core::solve::dynamics::{DynamicSettings, Energies};
use ancf_core::solve::simulation::{Initial, Simulation, SimulationError, Snapshot};
use ancf_core::solve::statics::{StaticSettings, solve_static_cancellable};
use files::{Checkpoint, Files, SupportLoads, io_err, write_final};
use history::History;
use observations::Observations;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output directory (created if absent).
    pub out: PathBuf,
    /// No progress bar.
    pub quiet: bool,
    /// The run checks it before every step and, once cancelled, ends with
    /// status "interrupted", keeping what it wrote.
    pub cancel: CancelToken,
}

/// A run kept in memory: its summary (as summary.json has it), its written
/// steps and the force on each rod at every step.
#[derive(Clone, Debug, Default)]
pub struct RunRecord {
    pub summary: Summary,
    /// Dynamic runs: the written steps (empty for a static run).
    pub history: History,
    /// Dynamic runs with rods: the force on each rod at every step, N.
    pub rod_loads: Vec<LoadHistory>,
    /// Dynamic runs with members: the wire's contact force on each member
    /// at every step, N.
    pub member_loads: Vec<LoadHistory>,
    /// Dynamic runs: the force each support exerts at every step, N.
    pub support_loads: Vec<LoadHistory>,
}

/// summary.json's `effects`: the model's effects by name.
pub fn effect_names(model: &Model) -> Vec<String> {
    model
        .effects
        .iter()
        .map(|e| match e {
            Effect::Elasticity {
                mooney_rivlin: true,
                ..
            } => "elasticity (with Mooney-Rivlin)".to_string(),
            Effect::Elasticity { .. } => "elasticity".to_string(),
            Effect::Gravity { .. } => "gravity".to_string(),
            Effect::PointLoads(l) => format!("point loads ({})", l.len()),
            Effect::Contact(c) if c.has_friction() => {
                format!("contact ({} rods, with friction)", c.rods.len())
            }
            Effect::Contact(c) => format!("contact ({} rods, frictionless)", c.rods.len()),
            Effect::Damping(_) => {
                let beams: Vec<String> = (model.dampings())
                    .map(|(b, d)| format!("{}: {d:?}", model.beams[b].name))
                    .collect();
                format!("damping ({})", beams.join(", "))
            }
            Effect::Springs(s) => format!("elastic supports ({})", s.len()),
        })
        .collect()
}

fn tip(model: &Model, q: &[f64]) -> TipSummary {
    let n = model.wire().last_node();
    let p = model.node_position(q, n);
    let p0 = model.node_position(&model.reference, n);
    TipSummary {
        position: p,
        displacement: [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]],
    }
}

/// Each beam's nodes, their twelve coordinates (position and gradients),
/// the wire first, with its name.
fn final_nodes(model: &Model, q: &[f64]) -> Vec<(String, Vec<[f64; 12]>)> {
    (model.beams.iter())
        .map(|b| {
            let nodes = (b.nodes.clone())
                .map(|n| std::array::from_fn(|k| q[ancf_core::model::NODE_DOFS * n + k]));
            (b.name.clone(), nodes.collect())
        })
        .collect()
}

/// Run a scene and write its outputs into `opts.out`. Returns the summary
/// (whose `status` says whether the run completed); `Err` only when the
/// outputs cannot be written at all.
pub fn run_scene(scene: &Scene, opts: &RunOptions) -> Result<Summary, String> {
    let _lock = crate::lock::OutputLock::acquire(&opts.out)?;
    clear_owned_outputs(&opts.out)?;
    execute(scene, Some(&opts.out), opts.quiet, &opts.cancel, None).map(|r| r.summary)
}

/// Run a scene without writing anything: the summary `run_scene` would
/// write, and the records in memory.
pub fn run_in_memory(scene: &Scene) -> RunRecord {
    execute(scene, None, true, &CancelToken::new(), None)
        .expect("a run without files has no I/O to fail")
}

/// The files and folders a run writes (and nothing else): a new run into a
/// folder removes these first, so no output of an earlier run is left
/// beside the new one's; other files in the folder are not touched.
pub const OWNED_OUTPUTS: &[&str] = &[
    "summary.json",
    "timeseries.csv",
    "timeseries.csv.tmp",
    "final_nodes.csv",
    "rod_forces.csv",
    "member_forces.csv",
    "supports.csv",
    "contact_point.csv",
    "checkpoint.json",
    "checkpoint.json.tmp",
    "energy.png",
    "configurations.png",
    "contact_point.png",
    "rod_forces.png",
    "member_loads.png",
    "vtk",
];

/// Remove `OWNED_OUTPUTS` and `final_nodes_*.csv` from `dir`.
fn clear_owned_outputs(dir: &Path) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| io_err(dir, e))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let owned = OWNED_OUTPUTS.contains(&name.as_ref())
            || (name.starts_with("final_nodes_") && name.ends_with(".csv"));
        if !owned {
            continue;
        }
        let path = entry.path();
        // Only `vtk` is a folder of ours; a folder under a file's name is
        // someone's, and is refused rather than deleted with its contents.
        let is_folder = entry.file_type().is_ok_and(|t| t.is_dir());
        let removed = match (is_folder, name.as_ref()) {
            (true, "vtk") => std::fs::remove_dir_all(&path),
            (true, _) => {
                return Err(format!(
                    "{} is a folder where the run writes a file; move or rename it (it is not \
                     deleted)",
                    path.display()
                ));
            }
            // Files, and links of any kind: the link goes, never its target.
            (false, _) => std::fs::remove_file(&path),
        };
        removed.map_err(|e| io_err(&path, e))?;
    }
    Ok(())
}

/// A run's total + dissipated energy may not rise by more than this
/// fraction of the largest energy in play (the scheme conserves or
/// dissipates; the integrator rejects such steps where there is contact).
pub const ENERGY_GAIN_WARNING: f64 = 0.01;

/// The warning of a run whose energy rose by `gain` J at its written steps
/// with `in_play` J in play at most (`None` within
/// [`ENERGY_GAIN_WARNING`]).
pub fn energy_gain_warning(gain: f64, in_play: f64) -> Option<String> {
    (gain > ENERGY_GAIN_WARNING * in_play + 1e-12).then(|| {
        format!(
            "energy: total + dissipated rose {gain:.4e} J above its start ({:.1} % of the {in_play:.4e} J in \
             play, more than {:.0} %): the energy balance is lost and the results are not to be \
             trusted; reduce analysis.time_step (or tighten analysis.tolerance)",
            100.0 * gain / in_play.max(f64::MIN_POSITIVE),
            100.0 * ENERGY_GAIN_WARNING
        )
    })
}

/// What a completed run's message says of its step cuts (`None` without
/// any): one step in a hundred or more cut means the guards, not the time
/// step, set the path (docs/scene.md).
pub fn step_cuts_note(step_cuts: usize, steps: usize) -> Option<String> {
    (step_cuts > 0).then(|| {
        let mut note = format!("{step_cuts} step attempt(s) rejected and cut in halves");
        if many_step_cuts(step_cuts, steps) {
            note.push_str(
                " (so many that the loads depend on which sub-steps passed: reduce \
                 analysis.time_step until the cuts stop)",
            );
        }
        note
    })
}

/// The steps' cost as this process ran them (summary.json `performance`);
/// the Python `Simulation` keeps one too.
#[derive(Clone, Debug, Default)]
pub struct Cost {
    steps: usize,
    /// Wall time spent in the steps, s.
    pub stepping: f64,
    iterations: usize,
    factorizations: usize,
    rejected: usize,
    force: (f64, usize),
    solve: (f64, usize),
    jacobian: (f64, usize),
    factorization: (f64, usize),
}

impl Cost {
    /// Count a step that took `info`.
    pub fn add(&mut self, info: &ancf_core::solve::dynamics::StepInfo) {
        self.steps += 1;
        self.iterations += info.iterations;
        self.factorizations += info.factorizations;
        self.rejected += info.rejected;
        self.force.0 += info.force_seconds;
        self.force.1 += info.force_evaluations;
        self.solve.0 += info.solve_seconds;
        self.solve.1 += info.solves;
        self.jacobian.0 += info.jacobian_seconds;
        self.jacobian.1 += info.jacobian_evaluations;
        self.factorization.0 += info.factorization_seconds;
        self.factorization.1 += info.factorizations;
    }

    /// summary.json's `performance` (`None` before a step with a solve).
    pub fn summary(&self) -> Option<crate::output::PerformanceSummary> {
        (self.steps > 0 && self.force.1 > 0 && self.solve.1 > 0).then(|| {
            let us = |(t, n): (f64, usize)| if n > 0 { 1e6 * t / n as f64 } else { 0.0 };
            let (step_us, force_us, solve_us) = (
                us((self.stepping, self.steps)),
                us(self.force),
                us(self.solve),
            );
            // The Newton method's own work per step: every force evaluation,
            // solve, Jacobian and factorization it made, at their times.
            let newton_us = 1e6
                * (self.force.0 + self.solve.0 + self.jacobian.0 + self.factorization.0)
                / self.steps as f64;
            crate::output::PerformanceSummary {
                step_us,
                force_us,
                solve_us,
                limit_ratio: step_us / (force_us + solve_us),
                newton_ratio: newton_us / (force_us + solve_us),
                iterations_per_step: self.iterations as f64 / self.steps as f64,
                evaluations_per_step: self.force.1 as f64 / self.steps as f64,
                jacobian_us: us(self.jacobian),
                factorization_us: us(self.factorization),
                factorizations: self.factorizations,
                rejected: self.rejected,
            }
        })
    }
}

/// configurations.png's extra shapes in the first impact, where the wire
/// changes most: at first contact and every 25 ms after, four in all.
const IMPACT_SNAPSHOTS: (usize, f64) = (4, 0.025);

/// Whether the step of size `h` (s) that ended `since` s after the first
/// contact is one of the [`IMPACT_SNAPSHOTS`].
fn impact_snapshot(since: f64, h: f64) -> bool {
    let (n, spacing) = IMPACT_SNAPSHOTS;
    (0..n).any(|j| {
        let at = j as f64 * spacing;
        since >= at - 1e-9 * h && since - h < at - 1e-9 * h
    })
}

/// How a dynamic run steps, for its summary's message: `N steps of h s`
/// (and the last one's length when `end_time` is no multiple of h: the run
/// ends on it), or the adaptive steps' tolerance and longest step.
pub fn stepping(settings: &DynamicSettings, n_steps: usize) -> String {
    match &settings.step_control {
        None => {
            let h = settings.time_step;
            let last = settings.end_time - n_steps.saturating_sub(1) as f64 * h;
            if n_steps > 1 && (last - h).abs() > 1e-6 * h {
                format!("{n_steps} steps of {h} s, the last {last:.3e} s")
            } else {
                format!("{n_steps} steps of {h} s")
            }
        }
        Some(c) => format!(
            "adaptive steps (error tolerance {:e} m per step, at most {:e} s)",
            c.tolerance, c.max_step
        ),
    }
}

/// Whether `step_cuts` rejected attempts in `steps` steps are so many (one
/// step in a hundred or more) that the guards, not the time step, set the
/// path.
pub fn many_step_cuts(step_cuts: usize, steps: usize) -> bool {
    step_cuts > 0 && 100 * step_cuts >= steps
}

/// What `--strict` fails a completed run for: each warning of its summary
/// (before and after the run) and many step cuts ([`many_step_cuts`]).
pub fn strict_findings(summary: &Summary) -> Vec<String> {
    let mut findings = summary.warnings.clone();
    if many_step_cuts(summary.step_cuts, summary.steps) {
        findings.push(format!(
            "{} step attempts rejected in {} steps: reduce analysis.time_step until the cuts stop",
            summary.step_cuts, summary.steps
        ));
    }
    findings
}

/// Continue the run checkpointed in `dir` (`ancf run --resume DIR`): the
/// outputs are cut back to the checkpoint and continued; the result equals
/// an uninterrupted run bit for bit. `cancel` stops it as in [`run_scene`].
pub fn resume(dir: &Path, quiet: bool, cancel: &CancelToken) -> Result<Summary, String> {
    let _lock = crate::lock::OutputLock::acquire(dir)?;
    let path = dir.join("checkpoint.json");
    let ck = Checkpoint::read(&path)?;
    let scene = Scene::from_toml(&ck.scene).map_err(|e| format!("the checkpoint's scene: {e}"))?;
    if !matches!(scene.analysis, Analysis::Dynamic { .. }) {
        return Err("only dynamic runs have checkpoints".into());
    }
    execute(&scene, Some(dir), quiet, cancel, Some(ck.progress)).map(|r| r.summary)
}

/// The run: static or dynamic, with files in `out` or in memory only,
/// from the start or from a checkpoint's progress.
fn execute(
    scene: &Scene,
    out: Option<&Path>,
    quiet: bool,
    cancel: &CancelToken,
    resume: Option<Progress>,
) -> Result<RunRecord, String> {
    let model = &scene.model;
    let mut summary = new_summary(scene);
    let start = Instant::now();
    let mut record = RunRecord::default();
    let final_q = match &scene.analysis {
        Analysis::Static {
            load_steps,
            tolerance,
            max_iterations,
        } => {
            summary.analysis = "static".into();
            let settings = StaticSettings {
                load_steps: *load_steps,
                max_iterations: *max_iterations,
                residual_tolerance: *tolerance,
                increment_tolerance: *tolerance,
            };
            match solve_static_cancellable(
                model,
                &settings,
                model.initial_coordinates(),
                Some(cancel),
            ) {
                Ok(res) => {
                    summary.status = RunStatus::Completed;
                    summary.message = format!(
                        "converged in {:?} Newton iterations per load step",
                        res.iterations
                    );
                    summary.steps = res.iterations.len();
                    summary.newton_iterations = res.iterations.iter().sum();
                    summary.supports = supports::static_supports(model, &res.reactions, &res.q);
                    let mut observed = Observations::new(scene);
                    let forces = res
                        .contact
                        .as_ref()
                        .map_or(&[][..], |c| &c.member_forces[..]);
                    observed.observe(scene, (&res.q, &res.plastic), 0.0, forces);
                    observed.observe_plastic(scene, &res.plastic, &res.plastic_work, 0.0);
                    observed.fill(scene, &mut summary);
                    let end = (&res.q[..], None, &res.plastic[..]);
                    Observations::fill_permanent_set(model, end, &mut summary);
                    summary.contact = res
                        .contact
                        .as_ref()
                        .and_then(|cf| static_contact(model, cf, &observed));
                    if let Some(cf) = &res.contact {
                        for (beam, f) in summary.beams.iter_mut().zip(&cf.member_forces) {
                            let force = norm(*f);
                            beam.contact.peak_force = force;
                            beam.contact.filtered_peak_force = force;
                        }
                    }
                    res.q
                }
                Err(e) if e.interrupted => {
                    summary.status = RunStatus::Interrupted;
                    summary.message = format!("{}; the last converged state is kept", e.message);
                    summary.steps = e.iterations.len();
                    summary.newton_iterations = e.iterations.iter().sum();
                    e.last_converged
                }
                Err(e) => {
                    summary.status = RunStatus::Failed;
                    summary.message = match model.ill_conditioning() {
                        Some(note) => format!("{}. Likely cause: {note}", e.message),
                        None => format!(
                            "{}. Likely cause: a load too large for one step or an unstable \
                             configuration; increase analysis.load_steps",
                            e.message
                        ),
                    };
                    summary.steps = e.iterations.len();
                    summary.newton_iterations = e.iterations.iter().sum();
                    e.last_converged
                }
            }
        }
        Analysis::Dynamic {
            settings,
            initial_static,
            load_steps,
        } => {
            summary.analysis = "dynamic".into();
            let initial = match (*initial_static, resume.is_some()) {
                (true, false) => Initial::Static {
                    load_steps: *load_steps,
                },
                _ => Initial::Reference,
            };
            let watch = Watch { quiet, cancel };
            let (q, history) = run_dynamic(
                scene,
                settings,
                initial,
                out,
                &watch,
                &mut summary,
                resume,
                &mut record,
            )?;
            record.history = history;
            q
        }
    };
    summary.tip = tip(model, &final_q);
    summary.wall_time_s = start.elapsed().as_secs_f64();
    if let Some(dir) = out {
        write_final(dir, &final_nodes(model, &final_q), &summary)?;
    }
    record.summary = summary;
    Ok(record)
}

/// Who watches a dynamic run: a progress bar unless quiet, and the token
/// that stops it.
struct Watch<'a> {
    quiet: bool,
    cancel: &'a CancelToken,
}

/// What a run accumulates besides the simulation's own snapshot: with it,
/// what a checkpoint saves and a resumed run starts from.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Progress {
    /// The simulation: step, phase, state, statistics, rod loads, contact.
    sim: Snapshot,
    message: String,
    history: History,
    max_drift: f64,
    /// The largest rise of total + dissipated energy above its start, and
    /// the largest energy in play, over the written steps (J).
    #[serde(default)]
    max_gain: f64,
    #[serde(default)]
    max_in_play: f64,
    e0: Energies,
    last: Energies,
    vtk_frames: Vec<(f64, String)>,
    /// The clearance zones' and the frame members' records so far.
    #[serde(flatten)]
    observed: Observations,
}

fn new_summary(scene: &Scene) -> Summary {
    let model = &scene.model;
    Summary {
        elements: model.element_count(),
        unknowns: model.n_unknowns,
        kernel: model.element(0).kernel_path().to_string(),
        simd: ancf_core::math::simd::path().name().into(),
        effects: effect_names(model),
        warnings: scene.warnings(),
        ..Default::default()
    }
}

/// The dynamic run's loop: steps the simulation, writes every
/// `output.every`-th step (and the last) to the history and the files,
/// checkpoints. Returns the final coordinates and the history; the rod and
/// support loads go to `record`.
#[allow(clippy::too_many_arguments)]
fn run_dynamic(
    scene: &Scene,
    settings: &DynamicSettings,
    initial: Initial,
    out: Option<&Path>,
    watch: &Watch<'_>,
    summary: &mut Summary,
    resume: Option<Progress>,
    record: &mut RunRecord,
) -> Result<(Vec<f64>, History), String> {
    let model = &scene.model;
    let contact = model.contact();
    let (mut p, mut sim, mut files) = match resume {
        Some(p) => {
            let sim = Simulation::resume(model, settings.clone(), p.sim.clone())
                .map_err(|e| e.to_string())?;
            let files = out
                .map(|dir| Files::open(dir, scene, Some(&p)))
                .transpose()?;
            (p, sim, files)
        }
        None => {
            let mut files = out.map(|dir| Files::open(dir, scene, None)).transpose()?;
            let from_static = matches!(initial, Initial::Static { .. });
            let sim = match Simulation::new_cancellable(
                model,
                settings.clone(),
                initial,
                Some(watch.cancel),
            ) {
                Ok(sim) => sim,
                Err(SimulationError::Static(e)) if e.interrupted => {
                    summary.status = RunStatus::Interrupted;
                    summary.message = format!(
                        "initial static equilibrium: {}; nothing was stepped",
                        e.message
                    );
                    return Ok((e.last_converged, History::default()));
                }
                Err(SimulationError::Static(e)) => {
                    summary.status = RunStatus::Failed;
                    summary.message = format!(
                        "initial static equilibrium: {}. Likely cause: {}",
                        e.message,
                        model
                            .ill_conditioning()
                            .unwrap_or_else(|| e.likely_cause().to_string())
                    );
                    return Ok((e.last_converged, History::default()));
                }
                Err(e) => {
                    summary.status = RunStatus::Failed;
                    summary.message = e.to_string();
                    return Ok((model.initial_coordinates(), History::default()));
                }
            };
            let message = if from_static {
                format!(
                    "initial static equilibrium in {:?} iterations; ",
                    sim.static_iterations
                )
            } else {
                String::new()
            };
            let state = sim.state();
            let e0 = sim.energies();
            let mut history = History::default();
            let no_contact = ancf_core::forces::contact::ContactSample::default();
            if let Some(f) = files.as_mut() {
                f.row(model, state, &e0, 0, contact.map(|_| &no_contact), true)?;
            }
            history.push(model, state, &e0);
            history.push_shape(model, state);
            let mut observed = Observations::new(scene);
            observed.observe(scene, (&state.q, &state.plastic), state.time, &[]);
            let p = Progress {
                sim: sim.snapshot(),
                message,
                history,
                max_drift: 0.0,
                max_gain: 0.0,
                max_in_play: e0.in_play(),
                e0,
                last: e0,
                vtk_frames: Vec::new(),
                observed,
            };
            (p, sim, files)
        }
    };
    p.observed.fit(scene);
    let (done, n_steps) = sim.steps();
    summary.unknowns = model.holding_at(0.0).n_unknowns;
    let (quiet, cancel) = (watch.quiet, watch.cancel);
    let bar = progress::Bar::new(n_steps as u64, quiet || !std::io::stderr().is_terminal());
    bar.set_position(done as u64);
    let snapshot_every = (n_steps / 8).max(1);
    let mut cost = Cost::default();
    let vtk_every = scene.output.vtk_interval(n_steps);
    let vtk_period = (scene.output).vtk_period(settings.step_control.is_some(), settings.end_time);
    // A checkpoint carries where the kept factorization was formed, so a
    // resumed run refactors there and results do not depend on how often
    // a run checkpoints.
    let checkpoint_every = scene.output.checkpoint_every;
    summary.status = RunStatus::Completed;
    summary.message = format!("{}{}", p.message, stepping(settings, n_steps));
    while !sim.is_finished() {
        let k = sim.steps().0 + 1;
        if cancel.is_cancelled() {
            summary.status = RunStatus::Interrupted;
            summary.message = format!(
                "stopped by Ctrl-C or a termination signal before step {k} at t = {:.6} s; output up \
                 to the last written step is kept{}",
                sim.state().time,
                match out {
                    Some(dir) if checkpoint_every > 0 => {
                        format!("; continue with `ancf run --resume {}`", dir.display())
                    }
                    _ => String::new(),
                }
            );
            break;
        }
        let t_before = sim.state().time;
        let started = std::time::Instant::now();
        let stepped = sim.step();
        cost.stepping += started.elapsed().as_secs_f64();
        let info = match stepped {
            Ok(info) => {
                cost.add(&info);
                info
            }
            Err(e @ SimulationError::Step { .. }) => {
                summary.status = RunStatus::Failed;
                let newton_failed = matches!(
                    &e,
                    SimulationError::Step {
                        error: ancf_core::solve::dynamics::StepError::Halved { .. }
                            | ancf_core::solve::dynamics::StepError::NotConverged { .. },
                        ..
                    }
                );
                // Newton's own settings first, then the model's conditioning.
                let cause = match (
                    newton_failed,
                    settings.newton_note(),
                    model.ill_conditioning(),
                ) {
                    (true, Some(note), _) | (true, None, Some(note)) => note,
                    _ => e.likely_cause().to_string(),
                };
                summary.message =
                    format!("{e}. Likely cause: {cause}. Output up to t = {t_before:.6} s is kept");
                break;
            }
            Err(e) => {
                summary.status = RunStatus::Failed;
                summary.message = e.to_string();
                break;
            }
        };
        let state = sim.state();
        p.observed.observe(
            scene,
            (&state.q, &state.plastic),
            state.time,
            &info.member_forces,
        );
        p.observed
            .observe_plastic(scene, &state.plastic, &state.plastic_work, state.time);
        let last = sim.is_finished();
        // A ParaView frame is due, with a row (every `vtk_every`-th step is
        // a row already).
        let frame_due = match vtk_period {
            Some(period) => (state.time / period).floor() > (t_before / period).floor(),
            None => k % vtk_every == 0,
        };
        if k % scene.output.every == 0 || last || frame_due {
            let e = sim.energies();
            if !e.total().is_finite() {
                summary.status = RunStatus::Failed;
                summary.message = format!(
                    "step {k} at t = {:.6} s: the energy is not finite. Likely cause: an inverted \
                     element or a time step too large; reduce analysis.time_step",
                    state.time
                );
                break;
            }
            // Plastic work leaves the mechanical energy as friction does.
            let kept = e.total() + e.dissipated + e.plastic;
            p.max_drift = p.max_drift.max((kept - p.e0.total()).abs());
            p.max_gain = p.max_gain.max(kept - p.e0.total());
            p.max_in_play = p.max_in_play.max(e.in_play());
            p.last = e;
            if let Some(f) = files.as_mut() {
                let frame = frame_due || last;
                f.row(
                    model,
                    state,
                    &e,
                    info.iterations,
                    contact.map(|_| &info.contact),
                    frame,
                )?;
            }
            p.history.push(model, state, &e);
            if let Some(cp) = sim.contact().and_then(|c| c.first_point) {
                p.history.push_contact_point(model, state, &cp);
            }
        }
        let in_first_impact = sim
            .contact()
            .and_then(|c| c.first_time)
            .is_some_and(|t1| impact_snapshot(state.time - t1, state.time - t_before));
        if k % snapshot_every == 0 || last || in_first_impact {
            p.history.push_shape(model, state);
        }
        let time = state.time;
        if checkpoint_every > 0 && k % checkpoint_every == 0 && !last {
            p.sim = sim.checkpoint();
            if let Some(f) = files.as_mut() {
                f.checkpoint(scene, &mut p)?;
            }
        }
        bar.set_position(k as u64);
        bar.set_message(format!("{time:.4} s"));
    }
    bar.finish_and_clear();
    let progress = sim.progress();
    if progress.released > 0 && summary.status == RunStatus::Completed {
        summary
            .message
            .push_str(&format!("; {} support release(s)", progress.released));
    }
    summary.steps = progress.step;
    summary.newton_iterations = progress.newton_iterations;
    summary.factorizations = progress.factorizations;
    summary.step_cuts = progress.step_cuts;
    summary.performance = cost.summary();
    summary.time_steps = crate::output::TimeStepSummary::of(progress);
    if let Some(note) = step_cuts_note(progress.step_cuts, progress.step)
        && summary.status == RunStatus::Completed
    {
        summary.message.push_str(&format!("; {note}"));
    }
    summary.time = progress.state.time;
    if let Some(w) = energy_gain_warning(p.max_gain, p.max_in_play) {
        summary.message.push_str(&format!("; warning: {w}"));
        summary.warnings.push(w);
    }
    p.observed.fill(scene, summary);
    Observations::fill_member_contact(summary, sim.member_loads(), scene.output.cfc);
    let end = sim.state();
    let holding = scene.model.holding_at(end.time);
    Observations::fill_permanent_set(&holding, (&end.q, Some(&end.v), &end.plastic), summary);
    summary.energy = Some(EnergySummary {
        last: p.last,
        total: p.last.total(),
        max_drift: p.max_drift,
    });
    // Filtered once per rod, for the summary, the CSV and the plot.
    let cfc = scene.output.cfc;
    let filtered: Vec<Filtered> = sim.rod_loads().iter().map(|h| h.filtered(cfc)).collect();
    if let (Some(c), Some(record)) = (contact, sim.contact()) {
        let loads: Vec<RodLoad> = (sim.rod_loads().iter())
            .zip(&filtered)
            .map(|(h, f)| h.summary(f))
            .collect();
        summary.contact = Some(contact_summary(
            c,
            record.first_time,
            record.max_normal_force,
            record.max_penetration,
            loads,
            &p.observed,
        ));
    }
    let supports = SupportLoads {
        initial: sim.initial_support_forces(),
        loads: sim.support_loads(),
        moments: sim.support_moments(),
    };
    let support_filtered: Vec<Filtered> = supports.loads.iter().map(|h| h.filtered(cfc)).collect();
    summary.supports = supports::dynamic_supports(
        model,
        supports.initial,
        scene.starts_from_equilibrium(),
        supports.loads,
        &support_filtered,
        (
            &scene.output.response_frequencies,
            scene.output.response_damping,
        ),
    );
    supports::add_peak_moments(model, &mut summary.supports, supports.moments);
    let member_filtered: Vec<Filtered> =
        sim.member_loads().iter().map(|h| h.filtered(cfc)).collect();
    if let Some(f) = files.as_mut() {
        summary.warnings.extend(f.lost());
        let finished = f.finish(
            scene,
            &p.history,
            sim.rod_loads(),
            &filtered,
            (
                sim.member_loads(),
                &member_filtered,
                &p.observed.member_moments,
            ),
            supports,
            summary,
        );
        // An output that cannot be written fails the run, and the summary
        // (written after) keeps what it computed and says which file.
        if let Err(message) = finished {
            summary.status = RunStatus::Failed;
            summary.message = format!(
                "{message}; the run computed to its end: summary.json and final_nodes.csv keep \
                 its results, the files written before it its histories"
            );
        }
    }
    record.rod_loads = sim.rod_loads().to_vec();
    record.member_loads = sim.member_loads().to_vec();
    record.support_loads = sim.support_loads().to_vec();
    Ok((sim.state().q.clone(), p.history))
}

/// A rod's entry in the summary: its law and stiffness, and its load.
fn rod_summary(rod: &ancf_core::model::contact::Rod, load: RodLoad) -> crate::output::RodSummary {
    crate::output::RodSummary {
        law: rod.law.name().into(),
        contact_stiffness: rod.contact_stiffness,
        stiffness_unit: rod.law.stiffness_unit().into(),
        restitution: rod.damping.map(|d| d.restitution()),
        restitution_model: rod.damping.map(|d| d.model().name().into()),
        load,
    }
}

/// summary.json's `contact`: the rods' and the grounds' entries from each
/// rigid partner's `loads` (model order: the rods, then the grounds), the
/// grounds' depths from `observed`. Python's summary is built by it too.
pub fn contact_summary(
    c: &ancf_core::model::contact::Contact,
    first_time: Option<f64>,
    max_normal_force: f64,
    max_penetration: f64,
    loads: Vec<RodLoad>,
    observed: &Observations,
) -> ContactSummary {
    let (mut rods, mut ground) = (Vec::new(), Vec::new());
    let mut depths = observed.ground.iter();
    for (rod, load) in c.rods.iter().zip(loads) {
        let entry = rod_summary(rod, load);
        if rod.is_ground() {
            let d = depths.next().copied().unwrap_or_default();
            ground.push(crate::output::GroundSummary {
                contact: entry,
                max_depth: (-d.min_distance.unwrap_or(0.0)).max(0.0),
                max_depth_time: d.time,
                max_depth_at: d.position,
            });
        } else {
            rods.push(entry);
        }
    }
    ContactSummary {
        first_time,
        max_normal_force,
        max_penetration,
        rods,
        ground,
    }
}

/// Contact in a static equilibrium: each rod's final force is its peak
/// (no impulse, no duration, nothing to filter).
fn static_contact(
    model: &Model,
    cf: &ContactForces,
    observed: &Observations,
) -> Option<ContactSummary> {
    let c = model.contact()?;
    let loads = (cf.rod_forces.iter())
        .map(|f| {
            let force = norm(*f);
            RodLoad {
                peak_force: force,
                filtered_peak_force: force,
                ..Default::default()
            }
        })
        .collect();
    Some(contact_summary(
        c,
        (cf.total.active > 0).then_some(0.0),
        cf.total.normal_force,
        cf.total.max_penetration,
        loads,
        observed,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The message names the steps' length, and the last step's when the
    /// end time is no multiple of it.
    #[test]
    fn stepping_names_a_short_last_step() {
        let settings = |end_time: f64| DynamicSettings {
            time_step: 1e-4,
            end_time,
            ..Default::default()
        };
        assert_eq!(stepping(&settings(1.0), 10_000), "10000 steps of 0.0001 s");
        assert_eq!(
            stepping(&settings(0.00105), 11),
            "11 steps of 0.0001 s, the last 5.000e-5 s"
        );
    }
}
