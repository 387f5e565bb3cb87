//! `ancf study`: what accuracy costs in time, on the user's own scene.
//! The study sweeps the settings that matter for the scene
//! ([`plan`]), runs every setting with the ordinary run pipeline in memory
//! (each run single-threaded in its own one-thread rayon pool, runs in
//! parallel on worker threads; no files), measures its error
//! against an analytic value ([`mod@reference`]) or a finer reference run, and
//! writes a Markdown report with log–log error-against-time plots
//! ([`report`]).

pub mod plan;
pub mod reference;
pub mod report;

use crate::run::{RunRecord, run_in_memory};
use ancf_core::scene::{Scene, SceneFile};
use plan::{Level, Plan, Setting};
use std::path::{Path, PathBuf};

/// Contact scenes: the first impact is measured over this long after the
/// first contact, s (the trajectory until then, and the impulse in it) —
/// each rod's first impact in summary.json uses the same window.
/// Later, a frictional wrap and slide is sensitive to every setting (±4 % in
/// the impact scene's whole-run impulse) and is no convergence measure.
pub const CONTACT_WINDOW: f64 = ancf_core::loads::rod_load::FIRST_IMPACT_WINDOW;

/// Options of one study.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Report directory (created if absent).
    pub out: PathBuf,
    pub level: Level,
    /// Runs at the same time (each single-threaded). Default: the cores.
    pub jobs: usize,
    /// No progress lines on stderr.
    pub quiet: bool,
}

/// Tip position and energy at one sample time.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sample {
    /// s
    pub time: f64,
    /// Last node's position, m.
    pub tip: [f64; 3],
    /// Total mechanical energy plus friction dissipation, J.
    pub energy: f64,
    /// Kinetic energy, J.
    pub kinetic: f64,
}

/// One finished run of a study.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// "completed", "failed" or "refused" (the scene check refused it).
    pub status: String,
    pub message: String,
    /// Wall time of the run, s (the fastest of the repeats of short runs).
    pub wall_s: f64,
    /// Final tip displacement, m.
    pub tip: [f64; 3],
    /// Dynamic runs: the rows at the study's sample times.
    pub samples: Vec<Sample>,
    /// Contact runs: the largest CFC-filtered rod peak (N) and its time (s),
    /// and the largest penetration (m).
    pub peak_force: Option<f64>,
    pub peak_time: Option<f64>,
    pub max_penetration: Option<f64>,
    /// Contact runs: impulse over all rods (∫|F| dt, N s) and the first
    /// contact time (s).
    pub impulse: Option<f64>,
    pub first_contact: Option<f64>,
    /// Contact runs: impulse over all rods in the first
    /// [`CONTACT_WINDOW`] after first contact (N s).
    pub window_impulse: Option<f64>,
    /// Newton iterations per step (dynamic) or per load step (static),
    /// rejected attempts' included.
    pub iterations_per_step: f64,
    /// Dynamic runs: step attempts rejected and cut in halves.
    pub step_cuts: usize,
    /// Dynamic contact runs whose time step does not resolve a rod's
    /// line-law contact (known before they run,
    /// [`ancf_core::scene::Scene::resolving_step`]): the largest step
    /// that would, s.
    pub resolving_step: Option<f64>,
    /// Contact runs: each rod's loads, in the scene's rod order, then each
    /// frame member's.
    pub rods: Vec<RodOutcome>,
    /// The names of `rods`' entries: `rod 0`, …, `ground 0`, …, then the
    /// members' names.
    pub partners: Vec<String>,
    /// Each support's CFC-filtered peak force over the run (N), with what
    /// it holds (`wire node 0`); `None` for a dynamic run's support that
    /// held nothing (released at the start) and for static runs.
    pub supports: Vec<(String, Option<f64>)>,
}

/// One rod's loads in a run (summary.json's `contact.rods`).
#[derive(Clone, Copy, Debug, Default)]
pub struct RodOutcome {
    /// CFC-filtered peak over the run, N.
    pub filtered_peak: f64,
    /// Impulse over the run, N s.
    pub impulse: f64,
    /// Filtered peak in the rod's first impact, N.
    pub first_impact_peak: f64,
    /// Impulse of the rod's first impact, N s.
    pub first_impact_impulse: f64,
    /// A frame member's largest bending moment (N m) and von Mises stress
    /// (Pa) over the run; `None` for a rod.
    pub max_bending_moment: Option<f64>,
    pub max_von_mises: Option<f64>,
    /// A frame member's largest bending moment in its first impact, N m.
    pub first_impact_moment: Option<f64>,
    /// A frame member's design numbers (all `None` for a rod).
    pub design: MemberDesign,
}

/// A member's design numbers as a run's summary gives them (`None` where
/// the member has none): its utilization by EN 1993-1-1 over the run, …
#[derive(Clone, Copy, Debug, Default)]
pub struct MemberDesign {
    pub utilization: Option<f64>,
    /// … its plastic work (J) and largest equivalent plastic strain (a
    /// yielding member), …
    pub plastic_work: Option<f64>,
    pub max_plastic_strain: Option<f64>,
    /// … and its permanent set (m): its rest shape with the wire lifted
    /// off, after the run against before.
    pub permanent_set: Option<f64>,
}

impl Outcome {
    pub fn completed(&self) -> bool {
        self.status == "completed"
    }
}

/// `samples` (in time order) interpolated linearly at the multiples of
/// `dt` (s) within their span.
fn on_grid(samples: &[Sample], dt: f64) -> Vec<Sample> {
    let Some(last) = samples.last() else {
        return Vec::new();
    };
    let n = (last.time / dt + 1e-9).floor() as usize;
    (0..=n)
        .filter_map(|j| {
            let t = j as f64 * dt;
            let k = samples.partition_point(|s| s.time < t);
            let b = samples.get(k)?;
            let Some(a) = k.checked_sub(1).map(|i| &samples[i]) else {
                return Some(Sample { time: t, ..*b });
            };
            let w = ((t - a.time) / (b.time - a.time)).clamp(0.0, 1.0);
            let mix = |x: f64, y: f64| x + w * (y - x);
            Some(Sample {
                time: t,
                tip: std::array::from_fn(|c| mix(a.tip[c], b.tip[c])),
                energy: mix(a.energy, b.energy),
                kinetic: mix(a.kinetic, b.kinetic),
            })
        })
        .collect()
}

/// Run one setting in memory, as `ancf run` would (call it inside a
/// one-thread rayon pool for a single-threaded timing).
/// Short runs are repeated (up to 5 times, 0.5 s in all) and the fastest
/// time kept: the timings of millisecond-scale static solves are otherwise
/// noise.
pub fn run_setting(file: &SceneFile, setting: &Setting, sample_interval: Option<f64>) -> Outcome {
    let variant = setting.apply(file, sample_interval);
    let scene = match Scene::from_file(&variant) {
        Ok(s) => s,
        Err(e) => {
            return Outcome {
                status: "refused".into(),
                message: e.to_string(),
                ..Default::default()
            };
        }
    };
    let mut best: Option<RunRecord> = None;
    let mut total = 0.0;
    for _ in 0..5 {
        let run = run_in_memory(&scene);
        total += run.summary.wall_time_s;
        let done = run.summary.status != crate::output::RunStatus::Completed || total > 0.5;
        if best
            .as_ref()
            .is_none_or(|b| run.summary.wall_time_s < b.summary.wall_time_s)
        {
            best = Some(run);
        }
        if done {
            break;
        }
    }
    let RunRecord {
        summary,
        history,
        rod_loads,
        member_loads,
        ..
    } = best.expect("at least one run");
    let samples: Vec<Sample> = (0..history.time.len())
        .map(|k| Sample {
            time: history.time[k],
            tip: history.tip[k],
            energy: history.energies[k].total() + history.energies[k].dissipated,
            kinetic: history.energies[k].kinetic,
        })
        .collect();
    // Adaptive steps do not land on the sample times: their rows (every
    // step) are interpolated there.
    let samples = match (setting.error_tolerance, sample_interval) {
        (Some(_), Some(dt)) => on_grid(&samples, dt),
        _ => samples,
    };
    let first = summary.contact.as_ref().and_then(|c| c.first_time);
    let window_impulse = first.filter(|_| summary.analysis == "dynamic").map(|t| {
        (rod_loads.iter().chain(&member_loads))
            .map(|h| h.impulse_between(t, t + CONTACT_WINDOW))
            .sum()
    });
    // Contact runs: the rod with the largest filtered peak (SAE J211, the
    // load a designer uses; the raw peak of a penalty contact is not a result).
    let contact = summary.contact.as_ref();
    // Rods, grounds, then members: each one's load, and a member's moments and
    // stress (whole run, whole run, first impact).
    type Member = Option<(f64, f64, f64, MemberDesign)>;
    let loads: Vec<(String, &ancf_core::loads::rod_load::RodLoad, Member)> = contact
        .map(|c| {
            let rods =
                (c.rods.iter().enumerate()).map(|(i, r)| (format!("rod {i}"), &r.load, None));
            let grounds = (c.ground.iter().enumerate())
                .map(|(i, g)| (format!("ground {i}"), &g.contact.load, None));
            let members = summary.beams.iter().map(|b| {
                let r = &b.record;
                let strain = (summary.strains.iter())
                    .find(|s| s.beam == b.name)
                    .map(|s| &s.record);
                let design = MemberDesign {
                    utilization: r.utilization,
                    plastic_work: strain.and_then(|s| s.plastic_work),
                    max_plastic_strain: (strain.and_then(|s| s.max_plastic_strain.as_ref()))
                        .map(|p| p.max_strain),
                    permanent_set: b.permanent_set,
                };
                let m = (
                    r.max_bending_moment,
                    r.max_von_mises,
                    r.first_impact_max_bending_moment,
                    design,
                );
                (b.name.clone(), &b.contact, Some(m))
            });
            rods.chain(grounds).chain(members).collect()
        })
        .unwrap_or_default();
    // The ground's blow is not the frame's load: the peak is the rods' and
    // the members'.
    let peak_rod = loads
        .iter()
        .filter(|(name, _, _)| !name.starts_with("ground"))
        .map(|(_, l, _)| *l)
        .max_by(|a, b| a.filtered_peak_force.total_cmp(&b.filtered_peak_force));
    Outcome {
        status: summary.status.to_string(),
        message: summary.message.clone(),
        wall_s: summary.wall_time_s,
        tip: summary.tip.displacement,
        samples,
        peak_force: peak_rod.map(|r| r.filtered_peak_force),
        peak_time: peak_rod.map(|r| r.filtered_peak_time),
        max_penetration: contact.map(|c| c.max_penetration),
        impulse: contact.map(|_| loads.iter().map(|(_, l, _)| l.impulse).sum()),
        first_contact: contact.and_then(|c| c.first_time),
        window_impulse,
        iterations_per_step: summary.newton_iterations as f64 / summary.steps.max(1) as f64,
        step_cuts: summary.step_cuts,
        resolving_step: scene.resolving_step(),
        rods: loads
            .iter()
            .map(|(_, l, member)| RodOutcome {
                filtered_peak: l.filtered_peak_force,
                impulse: l.impulse,
                first_impact_peak: l.first_impact_filtered_peak,
                first_impact_impulse: l.first_impact_impulse,
                max_bending_moment: member.map(|m| m.0),
                max_von_mises: member.map(|m| m.1),
                first_impact_moment: member.map(|m| m.2),
                design: member.map(|m| m.3).unwrap_or_default(),
            })
            .collect(),
        partners: loads.iter().map(|(name, ..)| name.clone()).collect(),
        supports: summary
            .supports
            .iter()
            .map(|p| {
                let label = format!("{} node {}", p.beam, p.node);
                (label, p.filtered_peak_force.filter(|f| *f > 0.0))
            })
            .collect(),
    }
}

/// The distinct settings of `plan`'s families (and its reference, slot
/// (families, 0), when run), each with the (family, index) slots it fills:
/// a setting that several families share runs once.
fn distinct_settings(plan: &Plan, with_reference: bool) -> Vec<(&Setting, Vec<(usize, usize)>)> {
    let mut jobs: Vec<(&Setting, Vec<(usize, usize)>)> = Vec::new();
    let reference = (plan.families.len(), 0);
    let all = plan
        .families
        .iter()
        .enumerate()
        .flat_map(|(fi, f)| {
            f.settings
                .iter()
                .enumerate()
                .map(move |(si, s)| ((fi, si), s))
        })
        .chain(with_reference.then_some((reference, &plan.reference)));
    for (slot, s) in all {
        match jobs.iter_mut().find(|(t, _)| *t == s) {
            Some((_, slots)) => slots.push(slot),
            None => jobs.push((s, vec![slot])),
        }
    }
    jobs
}

/// Run every setting of `plan` and the reference, `jobs` at a time, and
/// `tail` on the first worker that finds no run left (while the others
/// finish theirs: the element-cost table, which had left a core idle for
/// its 3 s after the runs). Returns the outcomes per family (in the plan's
/// order), the reference's, and `tail`'s result.
fn execute<T: Send>(
    file: &SceneFile,
    plan: &Plan,
    need_reference_run: bool,
    opts: &StudyOptions,
    tail: impl FnOnce() -> T + Send,
) -> (Vec<Vec<Outcome>>, Option<Outcome>, T) {
    let reference_index = plan.families.len();
    let mut jobs = distinct_settings(plan, need_reference_run);
    // Longest first (a rough cost model: elements × steps), so the reference
    // run does not start last.
    let cost = |s: &Setting| s.elements as f64 / s.time_step.unwrap_or(1.0) * s.axial as f64;
    jobs.sort_by(|a, b| cost(b.0).total_cmp(&cost(a.0)));
    // Worker threads pull jobs from a shared counter. Each worker runs its
    // jobs inside its own one-thread rayon pool, so a run's assembly stays
    // serial and exactly `jobs` runs share the cores. (A rayon `par_iter`
    // over the jobs would not do: a rayon worker waiting on another pool
    // keeps stealing jobs, and more runs than cores would share the clock.)
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let total = jobs.len();
    let results = std::sync::Mutex::new(Vec::with_capacity(total));
    let tail = std::sync::Mutex::new(Some(tail));
    let tail_out = std::sync::Mutex::new(None);
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.max(1).min(total.max(1)) {
            scope.spawn(|| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .expect("a one-thread pool");
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some((s, slots)) = jobs.get(k) else {
                        let task = tail.lock().expect("no panics while held").take();
                        if let Some(task) = task {
                            *tail_out.lock().expect("no panics while held") = Some(task());
                        }
                        break;
                    };
                    let o = pool.install(|| run_setting(file, s, plan.sample_interval));
                    let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                    if !opts.quiet {
                        eprintln!(
                            "  [{n}/{total}] {:<9} {:>8.2} s  {}",
                            o.status,
                            o.wall_s,
                            s.label()
                        );
                    }
                    results
                        .lock()
                        .expect("no panics while held")
                        .push((slots, o));
                }
            });
        }
    });
    let results = results.into_inner().expect("workers finished");
    let mut families: Vec<Vec<Outcome>> = plan
        .families
        .iter()
        .map(|f| vec![Outcome::default(); f.settings.len()])
        .collect();
    let mut reference = None;
    for (slots, o) in results {
        for &(fi, si) in slots {
            if fi == reference_index {
                reference = Some(o.clone());
            } else {
                families[fi][si] = o.clone();
            }
        }
    }
    let tail_out = tail_out
        .into_inner()
        .expect("workers finished")
        .expect("the first idle worker ran the tail");
    (families, reference, tail_out)
}

/// Run the study of the scene in `path` and write its report into `opts.out`.
/// Returns the report's path.
pub fn study(path: &Path, opts: &StudyOptions) -> Result<PathBuf, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file = SceneFile::from_toml(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let scene = Scene::from_file(&file).map_err(|e| format!("{}: {e}", path.display()))?;
    let plan = plan::plan(&file, &scene, opts.level);
    let analytic = reference::analytic(&scene);
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    let runs: usize = plan.families.iter().map(|f| f.settings.len()).sum();
    if !opts.quiet {
        eprintln!(
            "study of {}: {runs} runs{} on {} threads",
            path.display(),
            if analytic.is_none() {
                " + a reference run"
            } else {
                ""
            },
            opts.jobs
        );
    }
    let start = std::time::Instant::now();
    let (outcomes, reference_run, kernels) =
        execute(&file, &plan, analytic.is_none(), opts, || {
            match opts.level {
                Level::Standard => Some(report::kernel_costs(&scene)),
                Level::Quick | Level::Refinement => None,
            }
        });
    let input = report::ReportInput {
        scene_path: path,
        scene: &scene,
        plan: &plan,
        outcomes: &outcomes,
        analytic: analytic.as_ref(),
        reference_run: reference_run.as_ref(),
        kernels: kernels.as_deref(),
        level: opts.level,
        jobs: opts.jobs,
        study_wall_s: start.elapsed().as_secs_f64(),
    };
    report::write(&input, &opts.out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The impact scene's file and its standard-level plan.
    fn impact_plan() -> (SceneFile, Plan) {
        let text = std::fs::read_to_string("scenes/wire_rod_impact.toml").unwrap();
        let file = SceneFile::from_toml(&text).unwrap();
        let scene = Scene::from_file(&file).unwrap();
        let plan = plan::plan(&file, &scene, Level::Standard);
        (file, plan)
    }

    /// The impact study's plan repeats the scene's own setting in three
    /// families: it runs once and fills every slot.
    #[test]
    fn a_setting_shared_by_families_runs_once() {
        let (_, plan) = impact_plan();
        let slots: usize = plan.families.iter().map(|f| f.settings.len()).sum();
        let jobs = distinct_settings(&plan, true);
        let filled: Vec<(usize, usize)> = jobs.iter().flat_map(|(_, s)| s.clone()).collect();
        assert_eq!(
            filled.len(),
            slots + 1,
            "every slot and the reference, once"
        );
        let mut unique = filled.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), filled.len());
        for (s, slots) in &jobs {
            for &(fi, si) in slots {
                let planned = plan
                    .families
                    .get(fi)
                    .map_or(&plan.reference, |f| &f.settings[si]);
                assert_eq!(planned, *s);
            }
        }
        let shared = jobs.iter().filter(|(_, slots)| slots.len() > 1).count();
        assert!(
            shared >= 1,
            "the scene's own setting is in several families"
        );
        assert!(jobs.len() < slots + 1);
        // Without the reference run, no job fills its slot.
        assert!(
            distinct_settings(&plan, false)
                .iter()
                .all(|(_, s)| s.iter().all(|&(fi, _)| fi < plan.families.len()))
        );
    }

    /// The reference integrates axially with three points when every law is
    /// pre-integrated (the impact scene), with five when one is not.
    #[test]
    fn the_reference_axial_order_follows_the_laws() {
        let svk = std::fs::read_to_string("scenes/wire_rod_impact.toml").unwrap();
        let rubber = svk.replace(
            "name = \"aluminium-strands\"\nmodel = \"st-venant-kirchhoff\"\ndensity = 2026.0\nyoungs_modulus = 51.7e9\npoisson_ratio = 0.0\nbending_factor = 0.1",
            "name = \"aluminium-strands\"\nmodel = \"mooney-rivlin\"\ndensity = 2026.0\nmu10 = 5e5\nmu01 = 1e5\npenalty = 1e3",
        );
        assert_ne!(rubber, svk, "the outer layer became Mooney–Rivlin");
        for (text, axial) in [(svk, 3), (rubber, 5)] {
            let file = SceneFile::from_toml(&text).unwrap();
            let scene = Scene::from_file(&file).unwrap();
            assert_eq!(
                plan::plan(&file, &scene, Level::Standard).reference.axial,
                axial
            );
        }
    }

    /// The stiffness and law families run each contact at a step that
    /// resolves it: on the impact scene (h = 0.1 ms) ×100 at 50 µs and hertz
    /// at 25 µs, everything else at the scene's step.
    #[test]
    fn contact_settings_run_at_a_step_that_resolves_them() {
        let (file, plan) = impact_plan();
        let mut checked = 0;
        for fam in plan
            .families
            .iter()
            .filter(|f| f.name.starts_with("Contact"))
        {
            for s in &fam.settings {
                let expected = match (s.stiffness_factor, s.law) {
                    (_, Some(ancf_core::model::contact::ContactLaw::Hertz)) => 2.5e-5,
                    (Some(k), _) if k > 10.0 => 5e-5,
                    _ => 1e-4,
                };
                assert_eq!(s.time_step, Some(expected), "{}", s.label());
                let run = Scene::from_file(&s.apply(&file, None)).unwrap();
                assert!(
                    run.warnings().is_empty(),
                    "{}: {:?}",
                    s.label(),
                    run.warnings()
                );
                checked += 1;
            }
        }
        assert_eq!(checked, 18, "15 stiffness × zone-point settings and 3 laws");
    }
}
