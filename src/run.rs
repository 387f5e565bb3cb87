//! Running a validated scene: the solver loop and the outputs it writes.
//! Numerical failure ends the run with `status = "failed"` and a message
//! naming the step, the time and the likely cause; everything written up
//! to the last converged step stays on disk.

use crate::output::{
    ContactSummary, EnergySummary, Summary, TimeSeries, TipSummary, write_final_nodes,
};
use crate::plot::{Panel, Series, configurations_plot, line_plot, panels_plot};
use crate::vtk::VtkWriter;
use ancf_core::dynamics::{Energies, Integrator, State};
use ancf_core::element::{deformation_gradient, green_lagrange, position, shape_gradients};
use ancf_core::model::{Effect, Model};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::statics::{StaticSettings, solve_static};
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
            )?
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

/// The material point that touched a rod first: element and (ξ, y, z).
#[derive(Clone, Copy, Debug)]
struct ContactPoint {
    element: usize,
    xi: f64,
    y: f64,
    z: f64,
}

/// History kept for the plots (written steps only).
#[derive(Default)]
struct History {
    time: Vec<f64>,
    energies: Vec<Energies>,
    /// Time, vertical displacement and E_xx, E_yy, E_zz of the first contact point.
    contact_point: Vec<[f64; 5]>,
    /// Centerline shapes (time, x–z points) at a few instants.
    shapes: Vec<(f64, Vec<(f64, f64)>)>,
    /// Time and each rod's normal force, N.
    rod_forces: Vec<Vec<f64>>,
}

/// Centerline in the x–z plane, 8 points per element.
fn centerline(model: &Model, q: &[f64]) -> Vec<(f64, f64)> {
    let l = model.element.length;
    let mut pts = Vec::new();
    for el in 0..model.n_elements {
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
    let l = model.element.length;
    let e = model.element_coordinates(q, cp.element);
    let p = position(&e, cp.xi, cp.y, cp.z, l);
    let eps = green_lagrange(&deformation_gradient(
        &e,
        &shape_gradients(cp.xi, cp.y, cp.z, l),
    ));
    (p, [eps[0], eps[1], eps[2]])
}

/// Per-rod statistics (issue 8): peak normal force, its time, impulse.
#[derive(Clone, Debug, Default)]
struct RodStats {
    peak_force: f64,
    peak_time: f64,
    impulse: f64,
}

fn run_dynamic(
    scene: &Scene,
    settings: &ancf_core::dynamics::DynamicSettings,
    initial_static: bool,
    load_steps: usize,
    opts: &RunOptions,
    summary: &mut Summary,
) -> Result<Vec<f64>, String> {
    let model = &scene.model;
    let out = &opts.out;
    let contact = model.contact();
    let n_rods = contact.map_or(0, |c| c.rods.len());
    let mut series = TimeSeries::create(out, contact.is_some()).map_err(|e| io_err(out, e))?;
    let mut rod_csv = if n_rods > 0 {
        let header: Vec<String> = (0..n_rods).map(|i| format!("rod{i}_force")).collect();
        Some(
            crate::output::Table::create(
                &out.join("rod_forces.csv"),
                &format!("time,{}", header.join(",")),
            )
            .map_err(|e| io_err(out, e))?,
        )
    } else {
        None
    };
    let mut vtk = if scene.output.vtk {
        Some(VtkWriter::new(&out.join("vtk"), model).map_err(|e| io_err(out, e))?)
    } else {
        None
    };
    // Phases: the model with the supports still holding, between release times.
    let releases: Vec<f64> = model
        .release_times()
        .into_iter()
        .filter(|t| *t < settings.end_time)
        .collect();
    let mut phase_starts = vec![0.0];
    phase_starts.extend(releases.iter().copied().filter(|t| *t > 0.0));
    let phases: Vec<Model> = phase_starts.iter().map(|t| model.holding_at(*t)).collect();

    // Initial coordinates: static equilibrium with every support holding, or the supports' positions.
    let q0 = if initial_static {
        let st = StaticSettings {
            load_steps,
            ..Default::default()
        };
        match solve_static(model, &st) {
            Ok(res) => {
                summary.message = format!(
                    "initial static equilibrium in {:?} iterations; ",
                    res.iterations
                );
                res.q
            }
            Err(e) => {
                summary.status = "failed".into();
                summary.message = format!(
                    "initial static equilibrium: {}. Likely cause: supports too far from the wire's \
                     reach or a load too large; increase analysis.load_steps",
                    e.message
                );
                return Ok(e.last_converged);
            }
        }
    } else {
        model.initial_coordinates()
    };
    let fail_setup = |summary: &mut Summary, what: &str, msg: String| {
        summary.status = "failed".into();
        summary.message = format!("{what}: {msg}");
    };
    let mut phase = 0;
    let mut integ = match Integrator::new(&phases[0], settings.clone()) {
        Ok(i) => i,
        Err(e) => {
            fail_setup(summary, "setting up the solver", e.message);
            return Ok(q0);
        }
    };
    let mut state = match integ.initial_state(q0.clone(), vec![0.0; q0.len()]) {
        Ok(s) => s,
        Err(e) => {
            fail_setup(summary, "initial acceleration", e.message);
            return Ok(q0);
        }
    };
    summary.unknowns = phases[0].n_unknowns;
    let h = settings.time_step;
    let n_steps = (settings.end_time / h - 1e-9).ceil() as usize;
    let bar = progress_bar(n_steps as u64, opts.quiet);
    let mut history = History::default();
    let e0 = integ.energies(&state);
    let mut contact_summary = contact.map(|_| ContactSummary::default());
    let mut rod_stats = vec![RodStats::default(); n_rods];
    let mut first_point: Option<ContactPoint> = None;
    let snapshot_every = (n_steps / 8).max(1);
    let write = |series: &mut TimeSeries,
                 vtk: &mut Option<VtkWriter>,
                 history: &mut History,
                 s: &State,
                 e: &Energies,
                 its: usize,
                 c: Option<&ancf_core::contact::ContactSample>|
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
            v.frame(model, s.time, &s.q, &s.v)?;
        }
        history.time.push(s.time);
        history.energies.push(*e);
        Ok(())
    };
    let no_contact = ancf_core::contact::ContactSample::default();
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
    let mut max_drift: f64 = 0.0;
    let mut last = e0;
    let mut released = 0;
    summary.status = "completed".into();
    summary
        .message
        .push_str(&format!("{n_steps} steps of {h} s"));
    for k in 1..=n_steps {
        // A release inside this step: switch to the next phase at its start.
        while phase + 1 < phases.len() && phase_starts[phase + 1] <= state.time + 1e-12 * h {
            phase += 1;
            let dissipated = state.dissipated;
            integ = match Integrator::new(&phases[phase], settings.clone()) {
                Ok(i) => i,
                Err(e) => {
                    fail_setup(summary, "setting up the solver after a release", e.message);
                    break;
                }
            };
            match integ.initial_state(state.q.clone(), state.v.clone()) {
                Ok(mut s) => {
                    s.time = state.time;
                    s.dissipated = dissipated;
                    integ.set_energy_reference(&s);
                    state = s;
                    released += 1;
                }
                Err(e) => {
                    fail_setup(summary, "acceleration after a release", e.message);
                    break;
                }
            }
        }
        if summary.status == "failed" {
            break;
        }
        if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            summary.status = "interrupted".into();
            summary.message = format!(
                "interrupted (Ctrl-C) before step {k} at t = {:.6} s; output up to the last written step is kept",
                state.time
            );
            break;
        }
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
                if let (Some(cs), Some(c)) = (contact_summary.as_mut(), contact) {
                    let sample = &info.contact;
                    if sample.active > 0 && cs.first_time.is_none() {
                        cs.first_time = Some(state.time);
                        if let Some((el, dp)) = info.deepest {
                            let tp = &c.points[dp.point];
                            first_point = Some(ContactPoint {
                                element: el,
                                xi: tp.xi,
                                y: tp.y,
                                z: tp.z,
                            });
                        }
                    }
                    cs.max_normal_force = cs.max_normal_force.max(sample.normal_force);
                    cs.max_penetration = cs.max_penetration.max(sample.max_penetration);
                    for (r, f) in rod_stats.iter_mut().zip(&info.rod_forces) {
                        r.impulse += f * hk;
                        if *f > r.peak_force {
                            r.peak_force = *f;
                            r.peak_time = state.time;
                        }
                    }
                }
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
                    max_drift = max_drift.max((e.total() + e.dissipated - e0.total()).abs());
                    last = e;
                    write(
                        &mut series,
                        &mut vtk,
                        &mut history,
                        &state,
                        &e,
                        info.iterations,
                        contact.map(|_| &info.contact),
                    )
                    .map_err(|e| io_err(out, e))?;
                    if let Some(t) = rod_csv.as_mut() {
                        let mut row = vec![state.time];
                        row.extend(
                            info.rod_forces
                                .iter()
                                .copied()
                                .chain(std::iter::repeat(0.0))
                                .take(n_rods),
                        );
                        t.row(&row).map_err(|e| io_err(out, e))?;
                        history.rod_forces.push(row);
                    }
                    if let Some(cp) = &first_point {
                        let (p, strains) = point_state(model, &state.q, cp);
                        let (p0, _) = point_state(model, &model.reference, cp);
                        history.contact_point.push([
                            state.time,
                            p[2] - p0[2],
                            strains[0],
                            strains[1],
                            strains[2],
                        ]);
                    }
                }
                if k % snapshot_every == 0 || k == n_steps {
                    history
                        .shapes
                        .push((state.time, centerline(model, &state.q)));
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
    if released > 0 && summary.status == "completed" {
        summary
            .message
            .push_str(&format!("; {released} support release(s)"));
    }
    summary.time = state.time;
    summary.energy = Some(EnergySummary {
        kinetic: last.kinetic,
        strain: last.strain,
        gravity: last.gravity,
        loads: last.loads,
        contact: last.contact,
        dissipated: last.dissipated,
        total: last.total(),
        max_drift,
    });
    if let Some(cs) = contact_summary.as_mut() {
        cs.rods = rod_stats
            .iter()
            .map(|r| crate::output::RodSummary {
                peak_force: r.peak_force,
                peak_time: r.peak_time,
                impulse: r.impulse,
            })
            .collect();
    }
    summary.contact = contact_summary;
    if scene.output.plots {
        plot_dynamic(out, model, &history)?;
    }
    if !history.contact_point.is_empty() {
        write_contact_point(out, &history).map_err(|e| io_err(out, e))?;
    }
    Ok(state.q)
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
    if let Some(first) = h.rod_forces.first()
        && first.len() > 2
    {
        let labels: Vec<String> = (1..first.len()).map(|i| format!("rod {}", i - 1)).collect();
        let series: Vec<Series> = labels
            .iter()
            .enumerate()
            .map(|(i, l)| Series {
                label: l,
                points: h.rod_forces.iter().map(|r| (r[0], r[i + 1])).collect(),
            })
            .collect();
        line_plot(
            &out.join("rod_forces.png"),
            "Normal force on each rod",
            "time t (s)",
            "normal force (N)",
            &series,
        )?;
    }
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
            &[
                Panel {
                    title: "First contact point: vertical displacement",
                    x_label: "t (s)",
                    y_label: "Δz (m)",
                    series: vec![Series {
                        label: "Δz",
                        points: col(1),
                    }],
                },
                Panel {
                    title: "Normal strain E_xx",
                    x_label: "t (s)",
                    y_label: "E_xx (-)",
                    series: vec![Series {
                        label: "E_xx",
                        points: col(2),
                    }],
                },
                Panel {
                    title: "Normal strain E_yy",
                    x_label: "t (s)",
                    y_label: "E_yy (-)",
                    series: vec![Series {
                        label: "E_yy",
                        points: col(3),
                    }],
                },
                Panel {
                    title: "Normal strain E_zz",
                    x_label: "t (s)",
                    y_label: "E_zz (-)",
                    series: vec![Series {
                        label: "E_zz",
                        points: col(4),
                    }],
                },
            ],
        )?;
    }
    Ok(())
}
