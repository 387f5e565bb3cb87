//! The study's report: errors against the reference, the Pareto front of
//! error against wall time, the cheapest setting reaching 1 %, 0.1 % and
//! 0.01 %, written as `report.md` with PNG plots and `runs.csv`.

use super::plan::{Family, FamilyKind, Level, Plan, Setting};
use super::reference::Analytic;
use super::{CONTACT_WINDOW, Outcome, Sample};
use crate::plot::{Series, pareto_plot};
use ancf_core::element::ElementIntegration;
use ancf_core::math::vec3::{norm, sub};
use ancf_core::scene::Scene;
use ancf_core::section::{Section, SectionShape};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The error levels every table answers for.
pub const THRESHOLDS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// Element kernel cost at one quadrature setting, µs per element.
#[derive(Clone, Debug)]
pub struct KernelCost {
    pub axial: usize,
    pub section: usize,
    /// Section points per axial station on the generated path.
    pub points: usize,
    pub preintegrated: bool,
    pub generated_force: f64,
    pub generated_jacobian: f64,
    pub generic_force: f64,
    pub generic_jacobian: f64,
}

/// The scene's section at another ring-rule order.
fn section_with_order(s: &Section, order: usize) -> Section {
    match &s.shape {
        SectionShape::Circular { radii } => {
            let layers: Vec<(f64, f64, ancf_core::material::Material)> = radii
                .iter()
                .zip(&s.layers)
                .map(|(&(a, b), l)| (a, b, l.material.clone()))
                .collect();
            Section::circular(&layers, order)
        }
        SectionShape::Rectangular { width, height } => {
            Section::rectangular(*width, *height, s.layers[0].material.clone(), order)
        }
    }
}

/// Element force and Jacobian cost against the quadrature orders, generated
/// kernel against the generic loop (single thread, medians of repeats).
pub fn kernel_costs(scene: &Scene) -> Vec<KernelCost> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let el = scene.model.element(0);
    let mut out = Vec::new();
    pool.install(|| {
        for section in 2..=5 {
            for axial in 2..=5 {
                let sec = section_with_order(&el.section, section);
                let gen_el = ElementIntegration::new(el.length, axial, sec);
                let generic = gen_el.clone().with_generic_kernel();
                let survey = crate::bench::Timing::SURVEY;
                let (gf, gj) = crate::bench::element_times_with(&gen_el, survey);
                let (nf, nj) = crate::bench::element_times_with(&generic, survey);
                out.push(KernelCost {
                    axial,
                    section,
                    points: gen_el.plan.points(),
                    preintegrated: gen_el.plan.is_preintegrated(),
                    generated_force: gf,
                    generated_jacobian: gj,
                    generic_force: nf,
                    generic_jacobian: nj,
                });
            }
        }
    });
    out
}

/// Everything the report is written from.
pub struct ReportInput<'a> {
    pub scene_path: &'a Path,
    pub scene: &'a Scene,
    pub plan: &'a Plan,
    pub outcomes: &'a [Vec<Outcome>],
    pub analytic: Option<&'a Analytic>,
    pub reference_run: Option<&'a Outcome>,
    pub kernels: Option<&'a [KernelCost]>,
    pub level: Level,
    pub jobs: usize,
    pub study_wall_s: f64,
}

/// Errors of one run against the reference (relative unless stated).
#[derive(Clone, Copy, Debug, Default)]
pub struct Errors {
    /// Static: tip displacement. Dynamic: tip trajectory, max over the
    /// sample times of |x − x_ref| over the largest tip excursion of the reference.
    pub tip: Option<f64>,
    /// Dynamic: the first sample time at which the tip is farther than 1 %
    /// of the excursion from the reference tip (None: never), s.
    pub divergence_time: Option<f64>,
    /// Dynamic: max |E + D − E(0)| over the reference's largest kinetic energy.
    pub energy: Option<f64>,
    /// Contact: the largest CFC-filtered rod peak.
    pub peak_force: Option<f64>,
    /// Contact: |t_peak − t_peak,ref|, s.
    pub peak_time: Option<f64>,
    /// Contact: impulse of the whole run over all rods.
    pub impulse: Option<f64>,
    /// Contact: the tip trajectory error until the reference's first
    /// contact + [`CONTACT_WINDOW`].
    pub tip_window: Option<f64>,
    /// Contact: the impulse in the first [`CONTACT_WINDOW`] after first contact.
    pub window_impulse: Option<f64>,
}

/// The reference a run is compared with.
struct Reference<'a> {
    tip: [f64; 3],
    samples: HashMap<i64, Sample>,
    interval: f64,
    excursion: f64,
    kinetic: f64,
    contact: Option<&'a Outcome>,
}

impl<'a> Reference<'a> {
    fn new(input: &'a ReportInput) -> Option<Self> {
        if let Some(a) = input.analytic {
            return Some(Reference {
                tip: a.displacement,
                samples: HashMap::new(),
                interval: 1.0,
                excursion: 0.0,
                kinetic: 0.0,
                contact: None,
            });
        }
        let r = input.reference_run.filter(|r| r.completed())?;
        let interval = input.plan.sample_interval.unwrap_or(1.0);
        let samples: HashMap<i64, Sample> = r
            .samples
            .iter()
            .map(|s| ((s.time / interval).round() as i64, *s))
            .collect();
        let first = r.samples.first().map_or([0.0; 3], |s| s.tip);
        Some(Reference {
            tip: r.tip,
            excursion: r
                .samples
                .iter()
                .map(|s| norm(sub(s.tip, first)))
                .fold(0.0, f64::max),
            kinetic: r.samples.iter().map(|s| s.kinetic).fold(0.0, f64::max),
            samples,
            interval,
            contact: r.peak_force.is_some().then_some(r),
        })
    }

    fn errors(&self, o: &Outcome) -> Errors {
        if !o.completed() {
            return Errors::default();
        }
        let mut e = Errors::default();
        if o.samples.is_empty() {
            e.tip = Some(norm(sub(o.tip, self.tip)) / norm(self.tip));
        } else {
            let mut worst: f64 = 0.0;
            let mut worst_window: f64 = 0.0;
            let window_end = self
                .contact
                .and_then(|r| r.first_contact)
                .map(|t| t + CONTACT_WINDOW);
            let mut matched = 0;
            for s in &o.samples {
                let k = (s.time / self.interval).round() as i64;
                if (s.time - k as f64 * self.interval).abs() > 1e-6 * self.interval {
                    continue;
                }
                if let Some(r) = self.samples.get(&k) {
                    let d = norm(sub(s.tip, r.tip));
                    if d > 0.01 * self.excursion && e.divergence_time.is_none() {
                        e.divergence_time = Some(s.time);
                    }
                    worst = worst.max(d);
                    if window_end.is_some_and(|t| s.time <= t + 1e-9) {
                        worst_window = worst_window.max(d);
                    }
                    matched += 1;
                }
            }
            if matched > 0 && self.excursion > 0.0 {
                e.tip = Some(worst / self.excursion);
                e.tip_window = window_end.map(|_| worst_window / self.excursion);
            }
            let e0 = o.samples[0].energy;
            if self.kinetic > 0.0 {
                e.energy = Some(
                    o.samples
                        .iter()
                        .map(|s| (s.energy - e0).abs())
                        .fold(0.0, f64::max)
                        / self.kinetic,
                );
            }
        }
        if let (Some(r), Some(f)) = (self.contact, o.peak_force) {
            let fr = r.peak_force.unwrap_or(0.0);
            if fr > 0.0 {
                e.peak_force = Some((f - fr).abs() / fr);
            }
            if let (Some(t), Some(tr)) = (o.peak_time, r.peak_time) {
                e.peak_time = Some((t - tr).abs());
            }
            if let (Some(i), Some(ir)) = (o.impulse, r.impulse) {
                e.impulse = Some((i - ir).abs() / ir.abs().max(1e-300));
            }
            if let (Some(i), Some(ir)) = (o.window_impulse, r.window_impulse) {
                e.window_impulse = Some((i - ir).abs() / ir.abs().max(1e-300));
            }
        }
        e
    }
}

/// A run joins the Pareto front only when it is more accurate than every
/// faster run by more than this fraction of their error: settings that give
/// the same result (section orders of pre-integrated layers) at timings
/// differing by noise are not a front.
const FRONT_MARGIN: f64 = 0.01;

/// Runs on the Pareto front of (wall time, error): no faster run is as accurate.
/// Returns indices sorted by wall time.
pub fn pareto_front(points: &[(f64, Option<f64>)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].1.is_some_and(f64::is_finite))
        .collect();
    idx.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.unwrap().total_cmp(&points[b].1.unwrap()))
    });
    let mut best = f64::INFINITY;
    let mut front = Vec::new();
    for i in idx {
        let e = points[i].1.unwrap();
        if e < best * (1.0 - FRONT_MARGIN) {
            best = e;
            front.push(i);
        }
    }
    front
}

/// The cheapest run whose error is at most `threshold`.
pub fn cheapest(points: &[(f64, Option<f64>)], threshold: f64) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].1.is_some_and(|e| e <= threshold))
        .min_by(|&a, &b| points[a].0.total_cmp(&points[b].0))
}

/// Runs within this fraction of the fastest qualifying run's wall time
/// count as equally fast (timing noise between runs sharing the cores).
const TIME_TIE: f64 = 0.10;

/// The cheapest run reaching `threshold`; among runs as fast within
/// `TIME_TIE`, the scene's own section and axial order first, then the
/// lowest orders, then fewest elements (a user should not pick section
/// order 5 over 3 because of timing noise when the results are the same).
pub fn cheapest_setting(
    base: &Setting,
    settings: &[Setting],
    points: &[(f64, Option<f64>)],
    threshold: f64,
) -> Option<usize> {
    let fastest = points[cheapest(points, threshold)?].0;
    (0..points.len())
        .filter(|&i| {
            points[i].1.is_some_and(|e| e <= threshold) && points[i].0 <= fastest * (1.0 + TIME_TIE)
        })
        .min_by_key(|&i| {
            let s = &settings[i];
            (
                s.section != base.section,
                s.axial != base.axial,
                s.section,
                s.axial,
                s.elements,
            )
        })
}

/// Seconds with three significant digits (static solves take microseconds).
fn secs(t: f64) -> String {
    if t >= 0.1 {
        format!("{t:.2}")
    } else {
        format!("{t:.2e}")
    }
}

fn pct(e: Option<f64>) -> String {
    match e {
        Some(e) if e.is_finite() => format!("{:.3e}", e * 100.0),
        _ => "–".into(),
    }
}

fn threshold_table(
    md: &mut String,
    base: &Setting,
    what: &str,
    settings: &[Setting],
    points: &[(f64, Option<f64>)],
) {
    let _ = writeln!(
        md,
        "\nCheapest setting whose {what} error is at most (runs within 10 % of the fastest count as equally fast; \
         the scene's own orders, else the lowest, are named among them):\n\n| error ≤ | setting | wall time (s) | error (%) |\n|---|---|---|---|"
    );
    for t in THRESHOLDS {
        match cheapest_setting(base, settings, points, t) {
            Some(i) => {
                let _ = writeln!(
                    md,
                    "| {} % | {} | {} | {} |",
                    t * 100.0,
                    settings[i].label(),
                    secs(points[i].0),
                    pct(points[i].1)
                );
            }
            None => {
                let _ = writeln!(md, "| {} % | not reached by any run | – | – |", t * 100.0);
            }
        }
    }
}

/// How the runs of a family are grouped in its plot.
fn group_key(kind: FamilyKind, s: &Setting, base: &Setting) -> String {
    match kind {
        FamilyKind::Static => format!("axial order {}", s.axial),
        FamilyKind::Contact => match (s.law, s.zone_points, s.stations) {
            (Some(law), _, _) => format!("{} law", law.name()),
            (None, Some(z), _) => format!("{z} zone points"),
            (None, None, n) => format!("{} stations", n.unwrap_or(0)),
        },
        FamilyKind::Dynamic => {
            if s.spectral_radius != base.spectral_radius {
                format!(
                    "{} el, ρ∞ = {}",
                    s.elements,
                    s.spectral_radius.unwrap_or(0.0)
                )
            } else if s.axial != base.axial {
                format!("{} el, axial order {}", s.elements, s.axial)
            } else if s.full_newton != base.full_newton {
                format!(
                    "{} el, {} Newton",
                    s.elements,
                    if s.full_newton == Some(true) {
                        "full"
                    } else {
                        "modified"
                    }
                )
            } else {
                format!("{} elements", s.elements)
            }
        }
    }
}

fn plot_family(
    path: &Path,
    title: &str,
    y_label: &str,
    kind: FamilyKind,
    settings: &[Setting],
    base: &Setting,
    points: &[(f64, Option<f64>)],
) -> Result<(), String> {
    let mut keys: Vec<String> = Vec::new();
    let mut groups: Vec<Vec<(f64, f64)>> = Vec::new();
    for (s, &(t, e)) in settings.iter().zip(points) {
        let Some(e) = e else { continue };
        let key = group_key(kind, s, base);
        let i = keys.iter().position(|k| *k == key).unwrap_or_else(|| {
            keys.push(key);
            groups.push(Vec::new());
            keys.len() - 1
        });
        groups[i].push((t, e * 100.0));
    }
    let series: Vec<Series> = keys
        .iter()
        .zip(groups)
        .map(|(k, points)| Series { label: k, points })
        .collect();
    let front: Vec<(f64, f64)> = pareto_front(points)
        .into_iter()
        .map(|i| (points[i].0, points[i].1.unwrap() * 100.0))
        .collect();
    pareto_plot(
        path,
        title,
        "wall time per run (s)",
        y_label,
        &series,
        &front,
    )
}

/// A scene's name in reports: its file name without extension.
pub fn scene_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into())
}

/// Write `report.md`, the plots and `runs.csv` into `out`; returns the report path.
pub fn write(input: &ReportInput, out: &Path) -> Result<PathBuf, String> {
    let name = scene_name(input.scene_path);
    let base = Setting::of_scene(input.scene);
    let reference = Reference::new(input);
    let mut md = String::new();
    let _ = writeln!(md, "# Accuracy and cost: `{name}`\n");
    let _ = writeln!(
        md,
        "Generated by `ancf study {} --out {}{}` ({} runs in {:.0} s on {} thread(s); each run single-threaded, \
         its wall time the fastest of up to 5 repeats when it takes under 0.5 s). Machine: {} logical cores. \
         Timings from runs sharing the cores are a little slower than a lone run; compare them with each other.\n",
        input.scene_path.display(),
        out.display(),
        match input.level {
            Level::Quick => " --level quick",
            Level::Standard => "",
            Level::Refinement => " --level refinement",
        },
        input.outcomes.iter().map(Vec::len).sum::<usize>(),
        input.study_wall_s,
        input.jobs,
        std::thread::available_parallelism().map_or(1, |n| n.get()),
    );
    let _ = writeln!(md, "The scene's own setting: {}.\n", base.label());
    match (input.analytic, input.reference_run) {
        (Some(a), _) => {
            let _ = writeln!(md, "**Reference**: analytic — {}.\n", a.description);
        }
        (None, Some(r)) => {
            let _ = writeln!(
                md,
                "**Reference**: a finer run computed by the study — {} ({}, {:.1} s). Errors much below the finest \
                 sweep run's are not resolved by it.\n",
                input.plan.reference.label(),
                r.status,
                r.wall_s
            );
        }
        (None, None) => {}
    }
    let Some(reference) = reference else {
        let why = input
            .reference_run
            .map_or("no reference".to_string(), |r| r.message.clone());
        let _ = writeln!(
            md,
            "**The reference run did not complete**: {why}. No errors against it can be given; \
             the refinements' convergence (which needs no reference) and every run follow.\n"
        );
        // What needs no reference: each family's convergence and its runs.
        let mut csv = String::new();
        for (fi, fam) in input.plan.families.iter().enumerate() {
            let outcomes = &input.outcomes[fi];
            let _ = writeln!(md, "## {}\n", fam.name);
            convergence_section(&mut md, fam, outcomes, &base);
            let errors = vec![Errors::default(); outcomes.len()];
            let slug: String = (fam.name.to_lowercase().chars())
                .map(|c| if c.is_alphanumeric() { c } else { '_' })
                .collect();
            let radius = input.scene.model.section().outer_radius();
            runs_table(&mut md, &mut csv, &slug, fam, outcomes, &errors, radius);
            md.push('\n');
        }
        let path = out.join("report.md");
        std::fs::write(&path, md).map_err(|e| format!("{}: {e}", path.display()))?;
        return Err(format!("the reference run did not complete: {why}"));
    };
    let _ = writeln!(
        md,
        "Errors: {}. Each table names the cheapest setting reaching 1 %, 0.1 % and 0.01 %; \
         the plots show every completed run, the Pareto front (no faster run is more accurate) as a black line.\n",
        match input.plan.sample_interval {
            None => "relative error of the tip displacement vector".to_string(),
            Some(dt) => format!(
                "tip trajectory — the largest distance from the reference tip over the samples every {dt:.3e} s, \
                 over the reference tip's largest excursion ({:.4} m); energy — the largest |E(t) + D(t) − E(0)| \
                 (total mechanical energy plus friction dissipation) over the reference's largest kinetic energy \
                 ({:.4e} J); \"trajectory off by 1 % from\" — the first sample time at which the tip is farther than 1 % \
                 of that excursion from the reference tip (never: it stays closer)",
                reference.excursion, reference.kinetic
            ),
        }
    );
    step_cuts_note(&mut md, input);
    unresolved_contact_note(&mut md, input);
    let mut csv = String::from(
        "family,elements,axial,section,time_step,spectral_radius,full_newton,stations,stiffness_factor,status,wall_s,\
         iterations_per_step,tip_error,divergence_time,energy_error,peak_force,peak_force_error,peak_time,peak_time_error,\
         max_penetration,impulse,impulse_error,first_contact,zone_points,window_tip_error,window_impulse,window_impulse_error,law,step_cuts,error_tolerance\n",
    );
    for (fi, fam) in input.plan.families.iter().enumerate() {
        let outcomes = &input.outcomes[fi];
        let errors: Vec<Errors> = outcomes.iter().map(|o| reference.errors(o)).collect();
        let slug: String = fam
            .name
            .to_lowercase()
            .chars()
            .map(|c| if c.is_alphanumeric() { c } else { '_' })
            .collect();
        let _ = writeln!(md, "## {}\n", fam.name);
        // (wall time, error) of every run for one error measure.
        let against_time = |metric: fn(&Errors) -> Option<f64>| -> Vec<(f64, Option<f64>)> {
            outcomes
                .iter()
                .zip(&errors)
                .map(|(o, e)| (o.wall_s, metric(e)))
                .collect()
        };
        let contact_scene = reference.contact.is_some();
        let primary = against_time(match (fam.kind, contact_scene) {
            (FamilyKind::Contact, _) => |e| e.peak_force,
            (_, true) => |e| e.tip_window,
            _ => |e| e.tip,
        });
        let (what, y_label) = match (fam.kind, input.plan.sample_interval, contact_scene) {
            (FamilyKind::Contact, _, _) => ("filtered peak force", "filtered peak force error (%)"),
            (_, None, _) => ("tip displacement", "tip displacement error (%)"),
            (_, _, true) => (
                "tip trajectory until 0.1 s after first contact",
                "tip trajectory error until first contact + 0.1 s (%)",
            ),
            _ => ("tip trajectory", "tip trajectory error (%)"),
        };
        let png = format!(
            "{slug}_{}.png",
            what.split(' ').take(2).collect::<Vec<_>>().join("_")
        );
        let title = format!("{name}: {what} error against wall time");
        plot_family(
            &out.join(&png),
            &title,
            y_label,
            fam.kind,
            &fam.settings,
            &base,
            &primary,
        )?;
        let _ = writeln!(md, "![{what} error against wall time]({png})");
        if fam.kind == FamilyKind::Static {
            section_order_note(&mut md, &fam.settings, &primary, &base);
        }
        threshold_table(&mut md, &base, what, &fam.settings, &primary);
        if outcomes.iter().any(|o| o.impulse.is_some()) {
            if fam.kind != FamilyKind::Contact {
                let peak = against_time(|e| e.peak_force);
                threshold_table(&mut md, &base, "filtered peak force", &fam.settings, &peak);
            }
            let window = against_time(|e| e.window_impulse);
            threshold_table(
                &mut md,
                &base,
                "impulse of the first 0.1 s of contact",
                &fam.settings,
                &window,
            );
            let impulse = against_time(|e| e.impulse);
            threshold_table(
                &mut md,
                &base,
                "impulse of the whole run",
                &fam.settings,
                &impulse,
            );
            convergence_section(&mut md, fam, outcomes, &base);
        }
        if fam.kind == FamilyKind::Dynamic {
            adaptive_section(&mut md, fam, outcomes, &errors, &base);
        }
        if fam.kind == FamilyKind::Contact {
            let _ = writeln!(
                md,
                "\nThe reference uses the scene's contact stiffness: for other values the error includes the \
                 change of the penalty model itself; the penetration column shows how close each is to rigid contact. \
                 A stiffness or law whose contact the scene's time step does not resolve (h √(ε_L / ρA) > 3, ρA the \
                 wire's mass per length) runs at the largest h/2ᵏ that does: its label gives the step, and its wall \
                 time includes the extra steps."
            );
        }
        if fam.kind == FamilyKind::Dynamic {
            let energy = against_time(|e| e.energy);
            if energy.iter().any(|p| p.1.is_some()) {
                let png = format!("{slug}_energy.png");
                plot_family(
                    &out.join(&png),
                    &format!("{name}: energy error against wall time"),
                    "energy error (% of max kinetic energy)",
                    fam.kind,
                    &fam.settings,
                    &base,
                    &energy,
                )?;
                let _ = writeln!(md, "\n![energy error against wall time]({png})");
                threshold_table(&mut md, &base, "energy", &fam.settings, &energy);
            }
        }
        let radius = input.scene.model.section().outer_radius();
        runs_table(&mut md, &mut csv, &slug, fam, outcomes, &errors, radius);
        md.push('\n');
    }
    if let Some(k) = input.kernels {
        kernel_section(&mut md, k);
    }
    let path = out.join("report.md");
    std::fs::write(&path, md).map_err(|e| format!("{}: {e}", path.display()))?;
    let runs = out.join("runs.csv");
    std::fs::write(&runs, csv).map_err(|e| format!("{}: {e}", runs.display()))?;
    Ok(path)
}

/// Observed order p = ln[(f₃ − f₂)/(f₂ − f₁)] / ln r of three levels
/// (f₃ coarsest, refinement ratio r) and the fine level's grid convergence
/// index GCI = 1.25 |f₂ − f₁| / (|f₁| (r^p − 1)) (Roache; SPEC §7.5).
/// `None` when the differences change sign (oscillatory convergence) or
/// grow (no convergence yet, or differences at the level of round-off and
/// solver tolerance): no order then.
pub fn richardson(coarse: f64, medium: f64, fine: f64, ratio: f64) -> Option<(f64, f64)> {
    let (d32, d21) = (coarse - medium, medium - fine);
    if d21 == 0.0 || d32 / d21 <= 1.0 {
        return None;
    }
    let p = (d32 / d21).ln() / ratio.ln();
    let gci = 1.25 * d21.abs() / (fine.abs() * (ratio.powf(p) - 1.0));
    Some((p, gci))
}

/// A quantity a refinement is judged by: its name and how to read it from a run.
type Quantity = (String, Box<dyn Fn(&Outcome) -> Option<f64>>);

/// The quantities of a contact run: the filtered peak, the first impact's
/// impulse and the tip at first contact + 0.1 s; with several rods or
/// members (`partners`, their names), each one's first impact (filtered
/// peak, impulse) and its whole-run filtered peak, and a member's largest
/// bending moment and von Mises stress; each support's (`supports`: what
/// each holds) filtered peak force over the run.
fn quantities(partners: &[String], supports: &[String]) -> Vec<Quantity> {
    let rods = partners.len();
    // Interpolated linearly between the samples around the time (the
    // nearest sample was ambiguous: with samples every 2 steps the time
    // often falls midway, and round-off in the sample times picked a side).
    let tip_z = |o: &Outcome| -> Option<f64> {
        let t = o.first_contact? + CONTACT_WINDOW;
        let k = o.samples.partition_point(|s| s.time < t);
        let (a, b) = (o.samples.get(k.checked_sub(1)?)?, o.samples.get(k)?);
        let w = ((t - a.time) / (b.time - a.time)).clamp(0.0, 1.0);
        Some(a.tip[2] + w * (b.tip[2] - a.tip[2]))
    };
    let mut q: Vec<Quantity> = vec![
        ("filtered peak force (N)".into(), Box::new(|o| o.peak_force)),
        (
            "impulse, first 0.1 s of contact (N s)".into(),
            Box::new(|o| o.window_impulse),
        ),
        ("tip z at first contact + 0.1 s (m)".into(), Box::new(tip_z)),
    ];
    if rods > 1 {
        for (k, name) in partners.iter().enumerate() {
            let rod = move |o: &Outcome| o.rods.get(k).copied();
            q.push((
                format!("{name}: first impact, filtered peak (N)"),
                Box::new(move |o| rod(o).map(|r| r.first_impact_peak)),
            ));
            q.push((
                format!("{name}: first impact, impulse (N s)"),
                Box::new(move |o| rod(o).map(|r| r.first_impact_impulse)),
            ));
            q.push((
                format!("{name}: filtered peak, whole run (N)"),
                Box::new(move |o| rod(o).map(|r| r.filtered_peak)),
            ));
            if !name.starts_with("rod ") && !name.starts_with("ground ") {
                q.push((
                    format!("{name}: first impact, max bending moment (N m)"),
                    Box::new(move |o| rod(o).and_then(|r| r.first_impact_moment)),
                ));
                q.push((
                    format!("{name}: max bending moment, whole run (N m)"),
                    Box::new(move |o| rod(o).and_then(|r| r.max_bending_moment)),
                ));
                q.push((
                    format!("{name}: max von Mises stress, whole run (Pa)"),
                    Box::new(move |o| rod(o).and_then(|r| r.max_von_mises)),
                ));
                // Design numbers, where the member has them (a yield
                // stress; a yielding material for the plastic ones).
                q.push((
                    format!("{name}: utilization, whole run"),
                    Box::new(move |o| rod(o).and_then(|r| r.design.utilization)),
                ));
                q.push((
                    format!("{name}: plastic work (J)"),
                    Box::new(move |o| rod(o).and_then(|r| r.design.plastic_work)),
                ));
                q.push((
                    format!("{name}: largest equivalent plastic strain"),
                    Box::new(move |o| rod(o).and_then(|r| r.design.max_plastic_strain)),
                ));
                q.push((
                    format!("{name}: permanent set (m)"),
                    Box::new(move |o| rod(o).and_then(|r| r.design.permanent_set)),
                ));
            }
        }
    }
    for (k, label) in supports.iter().enumerate() {
        q.push((
            format!("support {k} ({label}): filtered peak force (N)"),
            Box::new(move |o| o.supports.get(k).and_then(|s| s.1)),
        ));
    }
    q
}

/// How one quantity behaves under one refinement.
struct Convergence {
    /// The three finest levels' values, coarsest first.
    values: [f64; 3],
    /// Observed order and GCI of the finest, when the differences shrink.
    order_gci: Option<(f64, f64)>,
}

impl Convergence {
    /// The spread of the three values relative to the finest.
    fn spread(&self) -> f64 {
        let [a, b, c] = self.values;
        (a.max(b).max(c) - a.min(b).min(c)) / c.abs()
    }

    /// An error band for the value `at` (the scene's setting) of this
    /// refinement: its distance from the finest level plus the finest's GCI
    /// when the values converge, else the spread of the three levels.
    fn band(&self, at: f64) -> f64 {
        let fine = self.values[2];
        match self.order_gci {
            Some((_, gci)) => (at - fine).abs() / fine.abs() + gci,
            None => self.spread(),
        }
    }
}

/// The family's adaptive runs beside the scene's fixed step: wall time and
/// the errors that the tables above judge, as ratios of cost at the
/// accuracy each reaches (nothing when the family has no adaptive run).
fn adaptive_section(
    md: &mut String,
    fam: &Family,
    outcomes: &[Outcome],
    errors: &[Errors],
    base: &Setting,
) {
    let runs: Vec<usize> = (0..fam.settings.len())
        .filter(|&i| fam.settings[i].error_tolerance.is_some() || fam.settings[i] == *base)
        .collect();
    if !runs
        .iter()
        .any(|&i| fam.settings[i].error_tolerance.is_some())
    {
        return;
    }
    let base_wall = runs
        .iter()
        .find(|&&i| fam.settings[i] == *base && outcomes[i].completed())
        .map(|&i| outcomes[i].wall_s);
    let pct = |v: Option<f64>| v.map_or("–".into(), |v| format!("{:.3}", 100.0 * v));
    let _ = writeln!(
        md,
        "
Fixed and adaptive steps side by side (`analysis.time_step = \"auto\"`, the \
         tolerance bounding each step's position error; wall time relative to the scene's own \
         setting, errors in %):\n"
    );
    let _ = writeln!(
        md,
        "| setting | wall time (s) | × the scene's | trajectory | energy | filtered peak | impulse, first 0.1 s | impulse, whole run |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for i in runs {
        let (s, o, e) = (&fam.settings[i], &outcomes[i], &errors[i]);
        if !o.completed() {
            let _ = writeln!(md, "| {} | {} | | | | | | |", s.label(), o.status);
            continue;
        }
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            s.label(),
            secs(o.wall_s),
            base_wall.map_or("–".into(), |b| format!("{:.2}", o.wall_s / b)),
            pct(e.tip),
            pct(e.energy),
            pct(e.peak_force),
            pct(e.window_impulse),
            pct(e.impulse),
        );
    }
}

/// Per refinement direction of a family (time step, elements, contact
/// integration), the three finest runs that differ from the scene's setting
/// only in it: the values of the filtered peak, the first impact's impulse
/// and the tip position at first contact + 0.1 s (with several rods, each
/// rod's first impact and whole-run peak), observed orders and GCIs; with
/// several rods, a table of design loads with their bands.
fn convergence_section(md: &mut String, fam: &Family, outcomes: &[Outcome], base: &Setting) {
    type Key = fn(&Setting) -> f64;
    let directions: [(&str, Key, Key); 3] = [
        (
            "time step h",
            |s| s.time_step.unwrap_or(0.0),
            |s| -s.time_step.unwrap_or(0.0),
        ),
        ("elements", |s| s.elements as f64, |s| s.elements as f64),
        (
            "contact integration points",
            |s| s.zone_points.or(s.stations).unwrap_or(0) as f64,
            |s| s.zone_points.or(s.stations).unwrap_or(0) as f64,
        ),
    ];
    let base_run = fam
        .settings
        .iter()
        .zip(outcomes)
        .find(|(s, o)| *s == base && o.completed())
        .map(|(_, o)| o);
    let partners = outcomes
        .iter()
        .map(|o| &o.partners)
        .max_by_key(|p| p.len())
        .cloned()
        .unwrap_or_default();
    let supports: Vec<String> = outcomes
        .iter()
        .map(|o| &o.supports)
        .max_by_key(|s| s.len())
        .map(|s| s.iter().map(|(label, _)| label.clone()).collect())
        .unwrap_or_default();
    let rods = partners.len();
    let quantities = quantities(&partners, &supports);
    // Per quantity: the largest band over the directions, and whether any
    // direction oscillated.
    let mut bands: Vec<(f64, bool)> = vec![(0.0, false); quantities.len()];
    let mut rows = String::new();
    for (name, value, fineness) in directions {
        // Runs equal to the scene's setting but for this direction (and the
        // stations the mesh implies).
        let same_but = |s: &Setting| {
            let mut t = s.clone();
            match name {
                "time step h" => t.time_step = base.time_step,
                "elements" => {
                    t.elements = base.elements;
                    t.stations = base.stations;
                }
                _ => {
                    t.stations = base.stations;
                    t.zone_points = base.zone_points;
                }
            }
            t == *base
        };
        let mut runs: Vec<(&Setting, &Outcome)> = fam
            .settings
            .iter()
            .zip(outcomes)
            .filter(|(s, o)| same_but(s) && o.completed())
            .collect();
        runs.sort_by(|a, b| fineness(a.0).total_cmp(&fineness(b.0)));
        runs.dedup_by(|a, b| value(a.0) == value(b.0));
        if runs.len() < 3 {
            continue;
        }
        let last = &runs[runs.len() - 3..];
        let ratio = (value(last[0].0) / value(last[1].0)).max(value(last[1].0) / value(last[0].0));
        let levels = last
            .iter()
            .map(|(s, _)| format!("{}", value(s)))
            .collect::<Vec<_>>()
            .join(" → ");
        for (qi, (qname, get)) in quantities.iter().enumerate() {
            let f: Vec<Option<f64>> = last.iter().map(|(_, o)| get(o)).collect();
            let [Some(f3), Some(f2), Some(f1)] = [f[0], f[1], f[2]] else {
                continue;
            };
            let c = Convergence {
                values: [f3, f2, f1],
                order_gci: richardson(f3, f2, f1, ratio),
            };
            let (order, gci) = match c.order_gci {
                Some((p, g)) => (format!("{p:.2}"), format!("{:.2} %", 100.0 * g)),
                None => (
                    if (f3 - f2) * (f2 - f1) < 0.0 {
                        "oscillating"
                    } else {
                        "not shrinking"
                    }
                    .into(),
                    format!("spread {:.2} %", 100.0 * c.spread()),
                ),
            };
            if let Some(at) = base_run.and_then(get) {
                let band = &mut bands[qi];
                band.0 = band.0.max(c.band(at));
                band.1 |= c.order_gci.is_none();
            }
            let _ = writeln!(
                rows,
                "| {name} | {levels} | {qname} | {f3:.5} → {f2:.5} → {f1:.5} | {order} | {gci} |"
            );
        }
    }
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "\nConvergence (Richardson, the three finest levels of each refinement at the scene's other settings; \
         GCI of the finest with safety factor 1.25):\n\n| refined | levels | quantity | values | observed order | GCI |\n\
         |---|---|---|---|---|---|\n{rows}"
    );
    let Some(at) = base_run.filter(|_| rods > 1) else {
        return;
    };
    let _ = writeln!(
        md,
        "\n**Loads at the scene's setting** ({}, {:.0} s wall, single-threaded) with their band: the largest over \
         the refinements of |value − finest level| + the finest level's GCI where the values converge, or the \
         spread of the three levels where they do not converge (marked ~).\n\n| quantity | value | band |\n|---|---|---|",
        base.label(),
        at.wall_s
    );
    for ((qname, get), (band, oscillating)) in quantities.iter().zip(&bands).skip(3) {
        if let Some(v) = get(at) {
            let _ = writeln!(
                md,
                "| {qname} | {v:.4} | ±{:.1} %{} |",
                100.0 * band,
                if *oscillating { " ~" } else { "" }
            );
        }
    }
}

/// The table of every run of a family (Markdown) and its rows of `runs.csv`.
fn runs_table(
    md: &mut String,
    csv: &mut String,
    slug: &str,
    fam: &Family,
    outcomes: &[Outcome],
    errors: &[Errors],
    radius: f64,
) {
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6e}"));
    let contact = outcomes.iter().any(|o| o.peak_force.is_some());
    let _ = write!(
        md,
        "\nAll runs:\n\n| setting | status | wall time (s) | Newton its/step | {} error (%) |",
        if fam.kind == FamilyKind::Static {
            "tip"
        } else {
            "trajectory"
        }
    );
    if fam.kind != FamilyKind::Static {
        md.push_str(" energy error (%) | trajectory off by 1 % from (s) |");
    }
    if contact {
        md.push_str(
            " trajectory error until first contact + 0.1 s (%) | first contact (s) | filtered peak force (N) | peak force error (%) | peak time error (ms) | impulse (N s) | \
             impulse error (%) | first 0.1 s impulse (N s) | its error (%) | penetration / wire radius |",
        );
    }
    md.push('\n');
    let columns =
        5 + 2 * usize::from(fam.kind != FamilyKind::Static) + if contact { 10 } else { 0 };
    md.push_str(&"|---".repeat(columns));
    md.push_str("|\n");
    for ((s, o), e) in fam.settings.iter().zip(outcomes).zip(errors) {
        let status = if o.completed() && o.step_cuts > 0 {
            format!("completed, {} step cuts", o.step_cuts)
        } else if o.completed() {
            "completed".to_string()
        } else {
            format!("{}: {}", o.status, o.message.replace('|', "/"))
        };
        let _ = write!(
            md,
            "| {} | {} | {} | {:.1} | {} |",
            s.label(),
            status,
            secs(o.wall_s),
            o.iterations_per_step,
            pct(e.tip)
        );
        if fam.kind != FamilyKind::Static {
            let _ = write!(
                md,
                " {} | {} |",
                pct(e.energy),
                match (o.completed(), e.divergence_time) {
                    (false, _) => "–".to_string(),
                    (true, None) => "never".to_string(),
                    (true, Some(t)) => format!("{t:.4}"),
                }
            );
        }
        if contact {
            let _ = write!(
                md,
                " {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                pct(e.tip_window),
                o.first_contact.map_or("–".into(), |t| format!("{t:.4}")),
                o.peak_force.map_or("–".into(), |f| format!("{f:.1}")),
                pct(e.peak_force),
                e.peak_time
                    .map_or("–".into(), |t| format!("{:.2}", t * 1e3)),
                o.impulse.map_or("–".into(), |i| format!("{i:.3}")),
                pct(e.impulse),
                o.window_impulse.map_or("–".into(), |i| format!("{i:.3}")),
                pct(e.window_impulse),
                o.max_penetration
                    .filter(|_| o.completed())
                    .map_or("–".into(), |p| format!("{:.3}", p / radius)),
            );
        }
        md.push('\n');
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{:.6e},{:.3},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            slug,
            s.elements,
            s.axial,
            s.section,
            opt(s.time_step),
            opt(s.spectral_radius),
            s.full_newton.map_or(String::new(), |f| f.to_string()),
            s.stations.map_or(String::new(), |n| n.to_string()),
            opt(s.stiffness_factor),
            o.status,
            o.wall_s,
            o.iterations_per_step,
            opt(e.tip),
            opt(e.divergence_time),
            opt(e.energy),
            opt(o.peak_force),
            opt(e.peak_force),
            opt(o.peak_time),
            opt(e.peak_time),
            opt(o.max_penetration),
            opt(o.impulse),
            opt(e.impulse),
            opt(o.first_contact),
            s.zone_points.map_or(String::new(), |n| n.to_string()),
            opt(e.tip_window),
            opt(o.window_impulse),
            opt(e.window_impulse),
            s.law.map_or("", |l| l.name()),
            o.step_cuts,
            opt(s.error_tolerance),
        );
    }
}

/// Which runs had step cuts, and what that says about their numbers.
fn step_cuts_note(md: &mut String, input: &ReportInput) {
    let cut: Vec<(&Setting, &Outcome)> = input
        .plan
        .families
        .iter()
        .zip(input.outcomes.iter())
        .flat_map(|(f, o)| f.settings.iter().zip(o))
        .filter(|(_, o)| o.completed() && o.step_cuts > 0)
        .collect();
    let Some((most, worst)) = cut.iter().max_by_key(|(_, o)| o.step_cuts) else {
        return;
    };
    let _ = writeln!(
        md,
        "**Step cuts**: {} completed runs had them (most: {}, {} cuts). A cut rejects a step attempt — \
         Newton failed, or the converged step would raise total + dissipated energy more than 1 % of the energy in \
         play above its start (the energy guard) or push the wire past the penetration limit — and redoes it in \
         halves. Many cuts mean the run used up its energy budget and went on by rejecting the steps that add \
         energy: its loads then depend on which sub-steps passed (a change of the sub-step policy alone can move \
         a filtered peak by several per cent), so they are not converged samples; a smaller time step is what resolves them.\n",
        cut.len(),
        most.label(),
        worst.step_cuts,
    );
}

/// Which runs' time step does not resolve their contact (h √(ε_L / ρA) > 3,
/// known before they ran), with the step that would.
fn unresolved_contact_note(md: &mut String, input: &ReportInput) {
    let mut runs: Vec<(String, f64)> = input
        .plan
        .families
        .iter()
        .zip(input.outcomes.iter())
        .flat_map(|(f, o)| f.settings.iter().zip(o))
        .filter_map(|(s, o)| o.resolving_step.map(|h| (s.label(), h)))
        .collect();
    // A setting several families share is listed once.
    runs.sort_by(|a, b| a.0.cmp(&b.0));
    runs.dedup_by(|a, b| a.0 == b.0);
    if runs.is_empty() {
        return;
    }
    let list: Vec<String> = runs
        .iter()
        .map(|(label, h)| format!("{label} (h ≤ {h:.2e} s would)"))
        .collect();
    let _ = writeln!(
        md,
        "**Unresolved contact**: the time step of {} run(s) does not resolve their contact — h √(ε_L / ρA) > {} \
         for a rod, the wire's frequency on the rod's penalty (ancf warns of it before a run): {}. Their loads \
         are not converged samples of the law or stiffness they stand for; compare them at the step named.\n",
        runs.len(),
        ancf_core::model::contact::RESOLVED_STEP_FREQUENCY,
        list.join("; "),
    );
}

/// How much the section order changes the result, per order, against the
/// scene's own order (pre-integrated St. Venant–Kirchhoff layers: nothing
/// from order 3 on; order 2 is not exact for them).
fn section_order_note(
    md: &mut String,
    settings: &[Setting],
    points: &[(f64, Option<f64>)],
    base: &Setting,
) {
    let mut orders: Vec<usize> = settings.iter().map(|s| s.section).collect();
    orders.sort_unstable();
    orders.dedup();
    let mut parts = Vec::new();
    for &order in orders.iter().filter(|&&o| o != base.section) {
        let mut largest: Option<f64> = None;
        for (i, a) in settings
            .iter()
            .enumerate()
            .filter(|(_, a)| a.section == order)
        {
            let twin = settings.iter().position(|b| {
                b.section == base.section && b.elements == a.elements && b.axial == a.axial
            });
            if let (Some(x), Some(Some(y))) = (points[i].1, twin.map(|j| points[j].1)) {
                let d = (x - y).abs() / x.abs().max(y.abs()).max(1e-300);
                largest = Some(largest.map_or(d, |l: f64| l.max(d)));
            }
        }
        if let Some(l) = largest {
            parts.push(format!("order {order}: {l:.1e}"));
        }
    }
    if !parts.is_empty() {
        let _ = writeln!(
            md,
            "\nLargest relative change of the error against section order {} at the same elements and axial order: {}. \
             (St. Venant–Kirchhoff layers are pre-integrated exactly from order 3 on: there the section order \
             changes neither result nor cost, and timing differences between such runs are noise.)",
            base.section,
            parts.join(", ")
        );
    }
}

fn kernel_section(md: &mut String, k: &[KernelCost]) {
    let _ = writeln!(
        md,
        "## Element cost against quadrature order\n\n\
         One element of this scene's section, force alone and force with Jacobian, µs per evaluation \
         (single thread, medians; timed while the study's last runs finish on the other cores). *Generated*: the kernel `build.rs` unrolls for the axial order (St. \
         Venant–Kirchhoff layers pre-integrated over the section, so independent of the section order); \
         *generic*: the loop over every quadrature point.\n\n\
         | axial | section | points per station (generated) | pre-integrated | generated force | generated Jacobian | generic force | generic Jacobian | Jacobian speed-up |\n\
         |---|---|---|---|---|---|---|---|---|"
    );
    for c in k {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1}× |",
            c.axial,
            c.section,
            c.points,
            if c.preintegrated { "yes" } else { "no" },
            c.generated_force,
            c.generated_jacobian,
            c.generic_force,
            c.generic_jacobian,
            c.generic_jacobian / c.generated_jacobian
        );
    }
    md.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Second-order data f = 1 + h² at h = 4, 2, 1: p = 2, GCI = 1.25 · 3 / (2 · 3).
    #[test]
    fn richardson_recovers_the_order_and_the_error_band() {
        let f = |h: f64| 1.0 + h * h;
        let (p, gci) = richardson(f(4.0), f(2.0), f(1.0), 2.0).unwrap();
        assert!((p - 2.0).abs() < 1e-12, "{p}");
        assert!((gci - 1.25 * 3.0 / (2.0 * 3.0)).abs() < 1e-12, "{gci}");
        // The fine value's true error is h² = 1: the band (1.25 · 1 · 2 = 1.25 relative to 2) covers it.
        assert!(gci * f(1.0) >= 1.0);
        assert!(
            richardson(1.0, 2.0, 1.5, 2.0).is_none(),
            "oscillating: no order"
        );
    }

    #[test]
    fn pareto_front_keeps_only_runs_more_accurate_than_every_faster_one() {
        // (wall time, error): the 2nd is slower and worse than the 1st, the
        // 4th ties the 3rd within the margin, the 5th failed.
        let pts = [
            (1.0, Some(1e-1)),
            (2.0, Some(2e-1)),
            (3.0, Some(1e-2)),
            (4.0, Some(0.999e-2)),
            (5.0, None),
            (6.0, Some(1e-3)),
        ];
        assert_eq!(pareto_front(&pts), vec![0, 2, 5]);
    }

    #[test]
    fn cheapest_run_per_threshold() {
        let pts = [
            (3.0, Some(5e-3)),
            (1.0, Some(2e-2)),
            (2.0, Some(8e-3)),
            (0.5, None),
        ];
        assert_eq!(cheapest(&pts, 1e-2), Some(2));
        assert_eq!(cheapest(&pts, 1e-1), Some(1));
        assert_eq!(cheapest(&pts, 1e-3), None);
    }
}
