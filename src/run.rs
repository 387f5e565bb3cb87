//! Running a validated scene: the solver loop and the outputs it writes.
//! Numerical failure ends the run with `status = "failed"` and a message
//! naming the step, the time and the likely cause; everything written up
//! to the last converged step stays on disk.

use crate::output::{EnergySummary, Summary, TimeSeries, TipSummary, write_final_nodes};
use crate::plot::{Series, line_plot};
use ancf_core::dynamics::{Energies, Integrator};
use ancf_core::model::{Effect, Model};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::statics::{StaticSettings, solve_static};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output directory (created if absent).
    pub out: PathBuf,
    /// No progress bar.
    pub quiet: bool,
}

fn effect_names(model: &Model) -> Vec<String> {
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
        })
        .collect()
}

fn tip(model: &Model, q: &[f64]) -> TipSummary {
    let n = model.n_elements;
    let p = model.node_position(q, n);
    let p0 = model.node_position(&model.reference, n);
    TipSummary {
        position: p,
        displacement: [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]],
    }
}

fn node_positions(model: &Model, q: &[f64]) -> Vec<[f64; 3]> {
    (0..model.n_nodes())
        .map(|n| model.node_position(q, n))
        .collect()
}

fn io_err(path: &Path, e: std::io::Error) -> String {
    format!("cannot write to {}: {e}", path.display())
}

/// Run a scene and write its outputs into `opts.out`. Returns the summary
/// (whose `status` says whether the run completed); `Err` only when the
/// outputs cannot be written at all.
pub fn run_scene(scene: &Scene, opts: &RunOptions) -> Result<Summary, String> {
    std::fs::create_dir_all(&opts.out).map_err(|e| io_err(&opts.out, e))?;
    let model = &scene.model;
    let mut summary = Summary {
        elements: model.n_elements,
        unknowns: model.n_unknowns,
        kernel: model.element.kernel_path().to_string(),
        effects: effect_names(model),
        ..Default::default()
    };
    let start = Instant::now();
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
            match solve_static(model, &settings) {
                Ok(res) => {
                    summary.status = "completed".into();
                    summary.message = format!(
                        "converged in {:?} Newton iterations per load step",
                        res.iterations
                    );
                    summary.steps = res.iterations.len();
                    summary.newton_iterations = res.iterations.iter().sum();
                    res.q
                }
                Err(e) => {
                    summary.status = "failed".into();
                    summary.message = format!(
                        "{}. Likely cause: a load too large for one step or an unstable configuration; \
                         increase analysis.load_steps",
                        e.message
                    );
                    summary.steps = e.iterations.len();
                    summary.newton_iterations = e.iterations.iter().sum();
                    e.last_converged
                }
            }
        }
        Analysis::Dynamic(settings) => {
            summary.analysis = "dynamic".into();
            run_dynamic(scene, settings, opts, &mut summary)?
        }
    };
    summary.tip = tip(model, &final_q);
    summary.wall_time_s = start.elapsed().as_secs_f64();
    write_final_nodes(&opts.out, &node_positions(model, &final_q))
        .map_err(|e| io_err(&opts.out, e))?;
    summary.write(&opts.out).map_err(|e| io_err(&opts.out, e))?;
    Ok(summary)
}

fn progress_bar(total: u64, quiet: bool) -> indicatif::ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} steps  t = {msg}  {per_sec}  ETA {eta}",
        )
        .expect("valid template"),
    );
    bar
}

/// History kept for the plots (written steps only).
#[derive(Default)]
struct History {
    time: Vec<f64>,
    energies: Vec<Energies>,
}

fn run_dynamic(
    scene: &Scene,
    settings: &ancf_core::dynamics::DynamicSettings,
    opts: &RunOptions,
    summary: &mut Summary,
) -> Result<Vec<f64>, String> {
    let model = &scene.model;
    let out = &opts.out;
    let mut series = TimeSeries::create(out).map_err(|e| io_err(out, e))?;
    let fail_setup = |summary: &mut Summary, msg: String| {
        summary.status = "failed".into();
        summary.message = msg;
    };
    let mut integ = match Integrator::new(model, settings.clone()) {
        Ok(i) => i,
        Err(e) => {
            fail_setup(summary, format!("setting up the solver: {}", e.message));
            return Ok(model.reference.clone());
        }
    };
    let mut state =
        match integ.initial_state(model.reference.clone(), vec![0.0; model.reference.len()]) {
            Ok(s) => s,
            Err(e) => {
                fail_setup(summary, format!("initial acceleration: {}", e.message));
                return Ok(model.reference.clone());
            }
        };
    let h = settings.time_step;
    let n_steps = (settings.end_time / h - 1e-9).ceil() as usize;
    let bar = progress_bar(n_steps as u64, opts.quiet);
    let mut history = History::default();
    let e0 = integ.energies(&state);
    let write_row = |series: &mut TimeSeries, t: f64, q: &[f64], e: &Energies, its: usize| {
        let p = model.node_position(q, model.n_elements);
        series.row(&[
            t,
            p[0],
            p[1],
            p[2],
            e.kinetic,
            e.strain,
            e.gravity,
            e.total(),
            e.loads,
            its as f64,
        ])
    };
    write_row(&mut series, 0.0, &state.q, &e0, 0).map_err(|e| io_err(out, e))?;
    history.time.push(0.0);
    history.energies.push(e0);
    let mut max_drift: f64 = 0.0;
    let mut last = e0;
    summary.status = "completed".into();
    summary.message = format!("{n_steps} steps of {h} s");
    for k in 1..=n_steps {
        let hk = if k == n_steps {
            settings.end_time - state.time
        } else {
            h
        };
        match integ.step(&state, hk) {
            Ok((next, info)) => {
                state = next;
                summary.steps = k;
                summary.newton_iterations += info.iterations;
                summary.factorizations += info.factorizations;
                if k % scene.output.every == 0 || k == n_steps {
                    let e = integ.energies(&state);
                    if !e.total().is_finite() {
                        summary.status = "failed".into();
                        summary.message = format!(
                            "step {k} at t = {:.6} s: the energy is not finite. Likely cause: an inverted \
                             element or a time step too large; reduce analysis.time_step",
                            state.time
                        );
                        break;
                    }
                    max_drift = max_drift.max((e.total() - e0.total()).abs());
                    last = e;
                    write_row(&mut series, state.time, &state.q, &e, info.iterations)
                        .map_err(|e| io_err(out, e))?;
                    history.time.push(state.time);
                    history.energies.push(e);
                }
                bar.set_position(k as u64);
                bar.set_message(format!("{:.4} s", state.time));
            }
            Err(e) => {
                summary.status = "failed".into();
                summary.message = format!(
                    "step {k} at t = {:.6} s: {}. Likely cause: a time step too large for the stiffness \
                     (material penalty, contact) or an unstable configuration; reduce analysis.time_step. \
                     Output up to t = {:.6} s is kept",
                    state.time + hk,
                    e.message,
                    state.time
                );
                break;
            }
        }
    }
    bar.finish_and_clear();
    summary.time = state.time;
    summary.energy = Some(EnergySummary {
        kinetic: last.kinetic,
        strain: last.strain,
        gravity: last.gravity,
        loads: last.loads,
        total: last.total(),
        max_drift,
    });
    if scene.output.plots {
        plot_energies(out, &history)?;
    }
    Ok(state.q)
}

fn plot_energies(out: &Path, h: &History) -> Result<(), String> {
    let pick = |f: fn(&Energies) -> f64| {
        h.time
            .iter()
            .zip(&h.energies)
            .map(|(t, e)| (*t, f(e)))
            .collect::<Vec<_>>()
    };
    let mut series = vec![
        Series {
            label: "kinetic",
            points: pick(|e| e.kinetic),
        },
        Series {
            label: "strain",
            points: pick(|e| e.strain),
        },
        Series {
            label: "gravity potential",
            points: pick(|e| e.gravity),
        },
    ];
    if h.energies.iter().any(|e| e.loads != 0.0) {
        series.push(Series {
            label: "load potential",
            points: pick(|e| e.loads),
        });
    }
    series.push(Series {
        label: "total",
        points: pick(|e| e.total()),
    });
    line_plot(
        &out.join("energy.png"),
        "Energy balance",
        "time t (s)",
        "energy (J)",
        &series,
    )
}
