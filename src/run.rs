//! Running a validated scene: the solver loop and the outputs it writes.
//! Numerical failure ends the run with `status = "failed"` and a message
//! naming the step, the time and the likely cause; everything written up
//! to the last converged step stays on disk.

use crate::output::{
    ContactSummary, EnergySummary, Summary, TimeSeries, TipSummary, write_final_nodes,
};
use crate::plot::{Panel, Series, configurations_plot, line_plot, panels_plot};
use crate::vtk::VtkWriter;
use ancf_core::element::{deformation_gradient, green_lagrange, position, shape_gradients};
use ancf_core::forces::sum::{At, ForceSum};
use ancf_core::loads::rod_load::{Filtered, LoadHistory, RodLoad};
use ancf_core::math::vec3::norm;
use ancf_core::model::{Effect, Model};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::solve::dynamics::{Energies, State};
use ancf_core::solve::simulation::{Initial, Simulation, SimulationError, Snapshot};
use ancf_core::solve::statics::{StaticSettings, solve_static};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Set by the Ctrl-C handler (see `main.rs`); the run loop checks it each
/// step and ends with status "interrupted", keeping what it wrote.
pub static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

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
            Effect::Contact(c) if c.has_friction() => {
                format!("contact ({} rods, with friction)", c.rods.len())
            }
            Effect::Contact(c) => format!("contact ({} rods, frictionless)", c.rods.len()),
            Effect::Damping(d) => format!("damping ({d:?})"),
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
    let mut summary = new_summary(scene);
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
                    summary.contact = static_contact(model, &res.q);
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
        Analysis::Dynamic {
            settings,
            initial_static,
            load_steps,
        } => {
            summary.analysis = "dynamic".into();
            run_dynamic(
                scene,
                settings,
                *initial_static,
                *load_steps,
                opts,
                &mut summary,
                None,
            )?
        }
    };
    finish(scene, opts, summary, &final_q, start)
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

/// The material point that touched a rod first: element and (ξ, y, z).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct ContactPoint {
    element: usize,
    xi: f64,
    y: f64,
    z: f64,
}

/// History kept for the plots (written steps only).
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
struct History {
    time: Vec<f64>,
    energies: Vec<Energies>,
    /// Time, vertical displacement and E_xx, E_yy, E_zz of the first contact point.
    contact_point: Vec<[f64; 5]>,
    /// Centerline shapes (time, x–z points) at a few instants.
    shapes: Vec<(f64, Vec<(f64, f64)>)>,
}

/// Centerline in the x–z plane, 8 points per element.
fn centerline(model: &Model, q: &[f64]) -> Vec<(f64, f64)> {
    let mut pts = Vec::new();
    for el in 0..model.n_elements {
        let l = model.element(el).length;
        let e = model.element_coordinates(q, el);
        for k in usize::from(el > 0)..=8 {
            let p = position(&e, k as f64 / 8.0, 0.0, 0.0, l);
            pts.push((p[0], p[2]));
        }
    }
    pts
}

/// Position and E_xx, E_yy, E_zz of a material point.
fn point_state(model: &Model, q: &[f64], cp: &ContactPoint) -> ([f64; 3], [f64; 3]) {
    let l = model.element(cp.element).length;
    let e = model.element_coordinates(q, cp.element);
    let p = position(&e, cp.xi, cp.y, cp.z, l);
    let eps = green_lagrange(&deformation_gradient(
        &e,
        &shape_gradients(cp.xi, cp.y, cp.z, l),
    ));
    (p, [eps[0], eps[1], eps[2]])
}

/// What a run's outputs accumulate besides the simulation's own snapshot:
/// with it, what a checkpoint saves and a resumed run starts from.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
struct Progress {
    /// The simulation: step, phase, state, statistics, rod loads.
    sim: Snapshot,
    message: String,
    contact: Option<ContactSummary>,
    first_point: Option<ContactPoint>,
    history: History,
    max_drift: f64,
    e0: Energies,
    last: Energies,
    vtk_frames: Vec<(f64, String)>,
}

/// `checkpoint.json`: the scene and the progress after a step.
#[derive(serde::Serialize, serde::Deserialize)]
struct Checkpoint {
    scene: String,
    progress: Progress,
}

fn write_checkpoint(out: &Path, scene: &Scene, p: &Progress) -> Result<(), String> {
    let text = serde_json::to_string(&Checkpoint {
        scene: scene.source.clone(),
        progress: p.clone(),
    })
    .map_err(|e| format!("checkpoint: {e}"))?;
    let tmp = out.join("checkpoint.json.tmp");
    std::fs::write(&tmp, text).map_err(|e| io_err(out, e))?;
    std::fs::rename(&tmp, out.join("checkpoint.json")).map_err(|e| io_err(out, e))
}

/// Keep the header and the rows of a CSV whose first column is ≤ `t`.
fn truncate_csv(path: &Path, t: f64) -> Result<(), String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(());
    };
    let mut kept = String::new();
    for (i, line) in text.lines().enumerate() {
        let time = line.split(',').next().and_then(|v| v.parse::<f64>().ok());
        if i == 0 || time.is_some_and(|x| x <= t + 1e-9 * t.abs().max(1e-300)) {
            kept.push_str(line);
            kept.push('\n');
        }
    }
    std::fs::write(path, kept).map_err(|e| io_err(path, e))
}

/// Continue the run checkpointed in `dir` (`ancf run --resume DIR`): the
/// outputs are cut back to the checkpoint and continued; the result equals
/// an uninterrupted run bit for bit.
pub fn resume(dir: &Path, quiet: bool) -> Result<Summary, String> {
    let path = dir.join("checkpoint.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let ck: Checkpoint =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let scene = Scene::from_toml(&ck.scene).map_err(|e| format!("the checkpoint's scene: {e}"))?;
    let Analysis::Dynamic { settings, .. } = &scene.analysis else {
        return Err("only dynamic runs have checkpoints".into());
    };
    let t = ck.progress.sim.state.time;
    truncate_csv(&dir.join("timeseries.csv"), t)?;
    let opts = RunOptions {
        out: dir.to_path_buf(),
        quiet,
    };
    let mut summary = new_summary(&scene);
    summary.analysis = "dynamic".into();
    let start = Instant::now();
    let q = run_dynamic(
        &scene,
        settings,
        false,
        1,
        &opts,
        &mut summary,
        Some(ck.progress),
    )?;
    finish(&scene, &opts, summary, &q, start)
}

fn new_summary(scene: &Scene) -> Summary {
    let model = &scene.model;
    Summary {
        elements: model.n_elements,
        unknowns: model.n_unknowns,
        kernel: model.element(0).kernel_path().to_string(),
        simd: ancf_core::math::simd::path().name().into(),
        effects: effect_names(model),
        ..Default::default()
    }
}

fn finish(
    scene: &Scene,
    opts: &RunOptions,
    mut summary: Summary,
    final_q: &[f64],
    start: Instant,
) -> Result<Summary, String> {
    let model = &scene.model;
    summary.tip = tip(model, final_q);
    summary.wall_time_s = start.elapsed().as_secs_f64();
    write_final_nodes(&opts.out, &node_positions(model, final_q))
        .map_err(|e| io_err(&opts.out, e))?;
    summary.write(&opts.out).map_err(|e| io_err(&opts.out, e))?;
    Ok(summary)
}

#[allow(clippy::too_many_arguments)]
fn run_dynamic(
    scene: &Scene,
    settings: &ancf_core::solve::dynamics::DynamicSettings,
    initial_static: bool,
    load_steps: usize,
    opts: &RunOptions,
    summary: &mut Summary,
    resume: Option<Progress>,
) -> Result<Vec<f64>, String> {
    let model = &scene.model;
    let out = &opts.out;
    let contact = model.contact();
    let resuming = resume.is_some();
    let mut series = if resuming {
        TimeSeries::append(out)
    } else {
        TimeSeries::create(out, contact.is_some())
    }
    .map_err(|e| io_err(out, e))?;
    let h = settings.time_step;
    let write = |series: &mut TimeSeries,
                 vtk: &mut Option<VtkWriter>,
                 history: &mut History,
                 s: &State,
                 e: &Energies,
                 its: usize,
                 c: Option<&ancf_core::forces::contact::ContactSample>|
     -> std::io::Result<()> {
        let p = model.node_position(&s.q, model.n_elements);
        let mut row = vec![
            s.time,
            p[0],
            p[1],
            p[2],
            e.kinetic,
            e.strain,
            e.gravity,
            e.total(),
            e.loads,
            its as f64,
        ];
        if let Some(c) = c {
            row.extend([c.normal_force, c.max_penetration, e.contact, e.dissipated]);
        }
        series.row(&row)?;
        if let Some(v) = vtk.as_mut() {
            v.frame(s.time, &s.q, &s.v)?;
        }
        history.time.push(s.time);
        history.energies.push(*e);
        Ok(())
    };

    let (mut p, mut sim, mut vtk) = match resume {
        Some(p) => {
            let sim = Simulation::resume(model, settings.clone(), p.sim.clone())
                .map_err(|e| e.to_string())?;
            let vtk = if scene.output.vtk {
                Some(
                    VtkWriter::resume(&out.join("vtk"), model, p.vtk_frames.clone())
                        .map_err(|e| io_err(out, e))?,
                )
            } else {
                None
            };
            (p, sim, vtk)
        }
        None => {
            let mut vtk = if scene.output.vtk {
                Some(VtkWriter::new(&out.join("vtk"), model).map_err(|e| io_err(out, e))?)
            } else {
                None
            };
            // Initial coordinates: static equilibrium with every support holding, or the supports' positions.
            let initial = if initial_static {
                Initial::Static { load_steps }
            } else {
                Initial::Reference
            };
            let sim = match Simulation::new(model, settings.clone(), initial) {
                Ok(sim) => sim,
                Err(SimulationError::Static(e)) => {
                    summary.status = "failed".into();
                    summary.message = format!(
                        "initial static equilibrium: {}. Likely cause: {}",
                        e.message,
                        e.likely_cause()
                    );
                    return Ok(e.last_converged);
                }
                Err(e) => {
                    summary.status = "failed".into();
                    summary.message = e.to_string();
                    return Ok(model.initial_coordinates());
                }
            };
            let message = if initial_static {
                format!(
                    "initial static equilibrium in {:?} iterations; ",
                    sim.static_iterations
                )
            } else {
                String::new()
            };
            let state = sim.state().clone();
            let e0 = sim.energies();
            let mut history = History::default();
            let no_contact = ancf_core::forces::contact::ContactSample::default();
            write(
                &mut series,
                &mut vtk,
                &mut history,
                &state,
                &e0,
                0,
                contact.map(|_| &no_contact),
            )
            .map_err(|e| io_err(out, e))?;
            history.shapes.push((0.0, centerline(model, &state.q)));
            let p = Progress {
                sim: sim.snapshot(),
                message,
                contact: contact.map(|_| ContactSummary::default()),
                first_point: None,
                history,
                max_drift: 0.0,
                e0,
                last: e0,
                vtk_frames: Vec::new(),
            };
            (p, sim, vtk)
        }
    };
    let (done, n_steps) = sim.steps();
    summary.unknowns = model.holding_at(0.0).n_unknowns;
    let bar = progress_bar(n_steps as u64, opts.quiet);
    bar.set_position(done as u64);
    let snapshot_every = (n_steps / 8).max(1);
    summary.status = "completed".into();
    summary.message = format!("{}{n_steps} steps of {h} s", p.message);
    while !sim.is_finished() {
        let k = sim.steps().0 + 1;
        if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            summary.status = "interrupted".into();
            summary.message = format!(
                "interrupted (Ctrl-C or a termination signal) before step {k} at t = {:.6} s; output up to the last written step is kept{}",
                sim.state().time,
                if scene.output.checkpoint_every > 0 {
                    "; continue with `ancf run --resume DIR`"
                } else {
                    ""
                }
            );
            break;
        }
        let t_before = sim.state().time;
        let info = match sim.step() {
            Ok(info) => info,
            Err(e @ SimulationError::Step { .. }) => {
                summary.status = "failed".into();
                summary.message = format!(
                    "{e}. Likely cause: {}. Output up to t = {t_before:.6} s is kept",
                    e.likely_cause()
                );
                break;
            }
            Err(e) => {
                summary.status = "failed".into();
                summary.message = e.to_string();
                break;
            }
        };
        let state = sim.state();
        if let Some(cs) = p.contact.as_mut() {
            let sample = &info.contact;
            if sample.active > 0 && cs.first_time.is_none() {
                cs.first_time = Some(state.time);
                if let Some((el, dp)) = info.deepest {
                    p.first_point = Some(ContactPoint {
                        element: el,
                        xi: dp.xi,
                        y: dp.y,
                        z: dp.z,
                    });
                }
            }
            cs.max_normal_force = cs.max_normal_force.max(sample.normal_force);
            cs.max_penetration = cs.max_penetration.max(sample.max_penetration);
        }
        if k % scene.output.every == 0 || k == n_steps {
            let e = sim.energies();
            if !e.total().is_finite() {
                summary.status = "failed".into();
                summary.message = format!(
                    "step {k} at t = {:.6} s: the energy is not finite. Likely cause: an inverted \
                     element or a time step too large; reduce analysis.time_step",
                    state.time
                );
                break;
            }
            p.max_drift = p
                .max_drift
                .max((e.total() + e.dissipated - p.e0.total()).abs());
            p.last = e;
            write(
                &mut series,
                &mut vtk,
                &mut p.history,
                state,
                &e,
                info.iterations,
                contact.map(|_| &info.contact),
            )
            .map_err(|e| io_err(out, e))?;
            if let Some(cp) = &p.first_point {
                let (pos, strains) = point_state(model, &state.q, cp);
                let (p0, _) = point_state(model, &model.reference, cp);
                p.history.contact_point.push([
                    state.time,
                    pos[2] - p0[2],
                    strains[0],
                    strains[1],
                    strains[2],
                ]);
            }
        }
        if k % snapshot_every == 0 || k == n_steps {
            p.history
                .shapes
                .push((state.time, centerline(model, &state.q)));
        }
        let time = state.time;
        let every = scene.output.checkpoint_every;
        if every > 0 && k % every == 0 && k < n_steps {
            p.sim = sim.snapshot();
            // The checkpoint names the frames: they must be on disk first.
            if let Some(v) = vtk.as_mut() {
                v.sync().map_err(|e| io_err(out, e))?;
            }
            p.vtk_frames = vtk
                .as_ref()
                .map(|v| v.frames().to_vec())
                .unwrap_or_default();
            write_checkpoint(out, scene, &p)?;
            // The resumed run starts without a factorization: so does this one.
            sim.refresh_factorization();
        }
        bar.set_position(k as u64);
        bar.set_message(format!("{time:.4} s"));
    }
    bar.finish_and_clear();
    if let Some(v) = vtk.as_mut() {
        v.finish().map_err(|e| io_err(out, e))?;
    }
    let progress = sim.progress();
    if progress.released > 0 && summary.status == "completed" {
        summary
            .message
            .push_str(&format!("; {} support release(s)", progress.released));
    }
    summary.steps = progress.step;
    summary.newton_iterations = progress.newton_iterations;
    summary.factorizations = progress.factorizations;
    summary.time = progress.state.time;
    summary.energy = Some(EnergySummary {
        last: p.last,
        total: p.last.total(),
        max_drift: p.max_drift,
    });
    if let (Some(cs), Some(c)) = (p.contact.as_mut(), contact) {
        let cfc = scene.output.cfc;
        // Filtered once per rod, for the summary, the CSV and the plot.
        let filtered: Vec<Filtered> = sim.rod_loads().iter().map(|h| h.filtered(cfc)).collect();
        cs.rods = c
            .rods
            .iter()
            .zip(sim.rod_loads())
            .zip(&filtered)
            .map(|((rod, h), f)| rod_summary(rod, h.summary(f)))
            .collect();
        write_rod_forces(out, sim.rod_loads(), &filtered).map_err(|e| io_err(out, e))?;
        if scene.output.plots {
            plot_rod_forces(out, sim.rod_loads(), &filtered, &cs.rods)?;
        }
    }
    summary.contact = p.contact.clone();
    if scene.output.plots {
        plot_dynamic(out, model, &p.history)?;
    }
    if !p.history.contact_point.is_empty() {
        write_contact_point(out, &p.history).map_err(|e| io_err(out, e))?;
    }
    Ok(sim.state().q.clone())
}

fn write_contact_point(out: &Path, h: &History) -> std::io::Result<()> {
    let mut s = String::from("time,dz,exx,eyy,ezz\n");
    for r in &h.contact_point {
        s.push_str(&format!(
            "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            r[0], r[1], r[2], r[3], r[4]
        ));
    }
    std::fs::write(out.join("contact_point.csv"), s)
}

fn plot_dynamic(out: &Path, model: &Model, h: &History) -> Result<(), String> {
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
    let contact = model.contact();
    if contact.is_some() {
        series.push(Series {
            label: "contact (penalty)",
            points: pick(|e| e.contact),
        });
        series.push(Series {
            label: "friction dissipated",
            points: pick(|e| e.dissipated),
        });
    }
    series.push(Series {
        label: "total",
        points: pick(|e| e.total()),
    });
    if contact.is_some_and(|c| c.has_friction()) {
        series.push(Series {
            label: "total + dissipated",
            points: pick(|e| e.total() + e.dissipated),
        });
    }
    line_plot(
        &out.join("energy.png"),
        "Energy balance",
        "time t (s)",
        "energy (J)",
        &series,
    )?;
    let rods: Vec<(f64, f64, f64)> = contact
        .map(|c| {
            c.rods
                .iter()
                .filter(|r| r.axis[1].abs() > 0.99)
                .map(|r| (r.center[0], r.center[2], r.radius))
                .collect()
        })
        .unwrap_or_default();
    configurations_plot(&out.join("configurations.png"), &h.shapes, &rods)?;
    if !h.contact_point.is_empty() {
        let col = |i: usize| {
            h.contact_point
                .iter()
                .map(|r| (r[0], r[i]))
                .collect::<Vec<_>>()
        };
        panels_plot(
            &out.join("contact_point.png"),
            2,
            2,
            (560, 420),
            &[
                Panel {
                    title: "First contact point: vertical displacement",
                    x_label: "t (s)",
                    y_label: "Δz (m)",
                    series: vec![Series {
                        label: "Δz",
                        points: col(1),
                    }],
                    ..Default::default()
                },
                Panel {
                    title: "Normal strain E_xx",
                    x_label: "t (s)",
                    y_label: "E_xx (-)",
                    series: vec![Series {
                        label: "E_xx",
                        points: col(2),
                    }],
                    ..Default::default()
                },
                Panel {
                    title: "Normal strain E_yy",
                    x_label: "t (s)",
                    y_label: "E_yy (-)",
                    series: vec![Series {
                        label: "E_yy",
                        points: col(3),
                    }],
                    ..Default::default()
                },
                Panel {
                    title: "Normal strain E_zz",
                    x_label: "t (s)",
                    y_label: "E_zz (-)",
                    series: vec![Series {
                        label: "E_zz",
                        points: col(4),
                    }],
                    ..Default::default()
                },
            ],
        )?;
    }
    Ok(())
}

/// A rod's entry in the summary: its law and stiffness, and its load.
fn rod_summary(rod: &ancf_core::forces::contact::Rod, load: RodLoad) -> crate::output::RodSummary {
    crate::output::RodSummary {
        law: rod.law.name().into(),
        contact_stiffness: rod.contact_stiffness,
        stiffness_unit: rod.law.stiffness_unit().into(),
        restitution: rod.damping.map(|d| d.restitution()),
        restitution_model: rod.damping.map(|d| d.model().name().into()),
        load,
    }
}

/// `rod_forces.csv`: every step's force on each rod, |F| raw and CFC
/// filtered (interpolated from the filter's grid to the step times), and
/// the components.
fn write_rod_forces(
    out: &Path,
    loads: &[LoadHistory],
    filtered: &[Filtered],
) -> std::io::Result<()> {
    let mut s = String::from("time");
    for i in 0..loads.len() {
        s += &format!(",rod{i}_force,rod{i}_filtered,rod{i}_fx,rod{i}_fy,rod{i}_fz");
    }
    s.push('\n');
    let steps = loads.first().map_or(0, |h| h.time.len());
    for k in 0..steps {
        let t = loads[0].time[k];
        s += &format!("{t:.9e}");
        for (h, f) in loads.iter().zip(filtered) {
            let v = h.force[k];
            let mag = norm(v);
            s += &format!(
                ",{mag:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
                f.at(t),
                v[0],
                v[1],
                v[2]
            );
        }
        s.push('\n');
    }
    std::fs::write(out.join("rod_forces.csv"), s)
}

/// `rod_forces.png`: per rod, the raw and the filtered force with both peaks marked.
fn plot_rod_forces(
    out: &Path,
    loads: &[LoadHistory],
    filtered: &[Filtered],
    rods: &[crate::output::RodSummary],
) -> Result<(), String> {
    let titles: Vec<String> = (0..loads.len())
        .map(|i| format!("Force on rod {i} (CFC {:.0})", rods[i].load.cfc))
        .collect();
    let panels: Vec<Panel> = loads
        .iter()
        .zip(filtered)
        .zip(rods)
        .zip(&titles)
        .map(|(((h, f), r), title)| {
            let raw = h
                .time
                .iter()
                .zip(&h.force)
                .map(|(t, v)| (*t, norm(*v)))
                .collect();
            Panel {
                title,
                x_label: "time t (s)",
                y_label: "force (N)",
                // The filtered force drawn over the raw one.
                series: vec![
                    Series {
                        label: "raw (every step)",
                        points: raw,
                    },
                    Series {
                        label: "CFC filtered",
                        points: f
                            .time
                            .iter()
                            .copied()
                            .zip(f.force.iter().copied())
                            .collect(),
                    },
                ],
                marks: vec![
                    (
                        r.load.peak_time,
                        r.load.peak_force,
                        format!("raw peak {:.0} N", r.load.peak_force),
                    ),
                    (
                        r.load.filtered_peak_time,
                        r.load.filtered_peak_force,
                        format!("filtered peak {:.0} N", r.load.filtered_peak_force),
                    ),
                ],
            }
        })
        .collect();
    if panels.iter().all(|p| p.series[0].points.is_empty()) {
        return Ok(());
    }
    panels_plot(
        &out.join("rod_forces.png"),
        panels.len(),
        1,
        (960, 480),
        &panels,
    )
}

/// Contact in a static equilibrium: each rod's final force is its peak
/// (no impulse, no duration, nothing to filter).
fn static_contact(model: &Model, q: &[f64]) -> Option<ContactSummary> {
    let c = model.contact()?;
    let mut forces = ForceSum::new(model);
    forces.evaluate(model, At::rest(q), None, None);
    let cf = forces.contact()?;
    let rods = c
        .rods
        .iter()
        .zip(&cf.rod_forces)
        .map(|(rod, f)| {
            let force = norm(*f);
            rod_summary(
                rod,
                RodLoad {
                    peak_force: force,
                    filtered_peak_force: force,
                    ..Default::default()
                },
            )
        })
        .collect();
    Some(ContactSummary {
        first_time: (cf.total.active > 0).then_some(0.0),
        max_normal_force: cf.total.normal_force,
        max_penetration: cf.total.max_penetration,
        rods,
    })
}
