//! Which settings a study sweeps for a scene: the choices a user
//! makes — elements, quadrature orders, time step, ρ∞, Newton kind, contact
//! stations and stiffness — each as a [`Setting`] applied to the scene file.

use ancf_core::model::contact::{ContactLaw, surface_stiffness_matching_line};
use ancf_core::model::station_spacing;
use ancf_core::scene::{
    Analysis, AnalysisKind, ContactSpec, NewtonSpec, OutputSpec, QuadratureSpec, Scene, SceneFile,
    TimeStepSpec,
};

/// How much to sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Level {
    /// A few runs per sweep (seconds): checks a scene and the report's shape.
    Quick,
    /// The full sweeps (minutes): what `docs/accuracy/` holds.
    Standard,
    /// Dynamic scenes: only the three refinements a result's error band
    /// needs — time step h, h/2, h/4; elements ½, 1, 2 ×; contact points
    /// ½, 1, 2 × — each at the scene's other settings, for scenes too costly
    /// for the standard sweeps (the span-break frame: minutes per run).
    Refinement,
}

/// One point of a sweep: every choice the study varies, resolved.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Setting {
    pub elements: usize,
    /// Gauss points along the element.
    pub axial: usize,
    /// Ring-rule order of the section.
    pub section: usize,
    /// Dynamic scenes: time step h, s (`None` with adaptive steps).
    pub time_step: Option<f64>,
    /// Dynamic scenes: adaptive steps with this error tolerance (m per
    /// step, `analysis.time_step = "auto"`).
    pub error_tolerance: Option<f64>,
    /// Dynamic scenes: generalized-α ρ∞.
    pub spectral_radius: Option<f64>,
    /// Dynamic scenes: full or modified Newton.
    pub full_newton: Option<bool>,
    /// Dynamic scenes: Newton's relative residual tolerance.
    pub tolerance: Option<f64>,
    /// Contact scenes with surface-law rods: test stations per element.
    pub stations: Option<usize>,
    /// Contact scenes with line-law (line, hertz) rods: Gauss points per active zone.
    pub zone_points: Option<usize>,
    /// Contact scenes: every rod's penalty stiffness ε_N times this factor.
    pub stiffness_factor: Option<f64>,
    /// Contact scenes with line-law rods: every rod switched to this law
    /// (`None`: the scene's own), see [`Setting::apply`].
    pub law: Option<ContactLaw>,
}

impl Setting {
    /// The scene's own setting.
    pub fn of_scene(scene: &Scene) -> Setting {
        let m = &scene.model;
        let (time_step, error_tolerance, spectral_radius, full_newton, tolerance) =
            match &scene.analysis {
                ancf_core::scene::Analysis::Dynamic { settings, .. } => (
                    settings
                        .step_control
                        .is_none()
                        .then_some(settings.time_step),
                    (settings.step_control.as_ref()).map(|c| c.tolerance),
                    Some(settings.spectral_radius),
                    Some(settings.newton == ancf_core::solve::dynamics::NewtonKind::Full),
                    Some(settings.tolerance),
                ),
                ancf_core::scene::Analysis::Static { .. } => (None, None, None, None, None),
            };
        Setting {
            elements: m.wire().elements.len(),
            axial: m.element(0).axial.nodes.len(),
            section: m.section().order,
            time_step,
            error_tolerance,
            spectral_radius,
            full_newton,
            tolerance,
            stations: m
                .contact()
                .filter(|c| c.rods.iter().any(|r| r.law == ContactLaw::Surface))
                .map(|c| c.settings.stations),
            zone_points: m
                .contact()
                .filter(|c| {
                    c.rods.iter().any(|r| r.law != ContactLaw::Surface) || !c.members.is_empty()
                })
                .map(|c| c.settings.zone_points),
            stiffness_factor: m.contact().map(|_| 1.0),
            law: None,
        }
    }

    /// Short description for tables: what a user would write in the scene.
    pub fn label(&self) -> String {
        let mut s = format!(
            "{} el, axial {}, section {}",
            self.elements, self.axial, self.section
        );
        if let Some(h) = self.time_step {
            s += &format!(", h {h:.3e} s");
        }
        if let Some(t) = self.error_tolerance {
            s += &format!(", adaptive h (error ≤ {t:.0e} m/step)");
        }
        if let Some(r) = self.spectral_radius {
            s += &format!(", ρ∞ {r}");
        }
        if let Some(f) = self.full_newton {
            s += if f {
                ", full Newton"
            } else {
                ", modified Newton"
            };
        }
        if let Some(t) = self.tolerance {
            s += &format!(", tolerance {t:.0e}");
        }
        if let Some(n) = self.stations {
            s += &format!(", {n} stations");
        }
        if let Some(n) = self.zone_points {
            s += &format!(", {n} zone points");
        }
        if let Some(f) = self.stiffness_factor {
            s += &format!(", stiffness ×{f}");
        }
        if let Some(law) = self.law {
            s += &format!(", {} law", law.name());
        }
        s
    }

    /// The scene file with this setting, written only at multiples of
    /// `sample_interval` (dynamic), without VTK, plots or checkpoints.
    pub fn apply(&self, base: &SceneFile, sample_interval: Option<f64>) -> SceneFile {
        let mut f = base.clone();
        set_elements(&mut f, self.elements);
        f.wire.quadrature = Some(QuadratureSpec {
            axial: Some(self.axial),
            section: Some(self.section),
        });
        if let Some(h) = self.time_step {
            f.analysis.time_step = Some(TimeStepSpec::Fixed(h));
            f.analysis.error_tolerance = None;
            f.analysis.max_time_step = None;
        }
        if let Some(t) = self.error_tolerance {
            f.analysis.time_step = Some(TimeStepSpec::Auto);
            f.analysis.error_tolerance = Some(t);
        }
        if let Some(r) = self.spectral_radius {
            f.analysis.spectral_radius = Some(r);
        }
        if let Some(full) = self.full_newton {
            f.analysis.newton = Some(if full {
                NewtonSpec::Full
            } else {
                NewtonSpec::Modified
            });
        }
        if let Some(t) = self.tolerance {
            f.analysis.tolerance = Some(t);
        }
        if self.stations.is_some() || self.zone_points.is_some() {
            let c = f.contact.get_or_insert(ContactSpec {
                max_penetration: None,
                stations: None,
                angles: None,
                zone_points: None,
                slip_velocity: None,
                min_impact_speed: None,
            });
            c.stations = self.stations.or(c.stations);
            c.zone_points = self.zone_points.or(c.zone_points);
        }
        if let Some(k) = self.stiffness_factor {
            for r in &mut f.rod {
                r.contact_stiffness = r.contact_stiffness.map(|s| s * k);
            }
            for b in &mut f.beam {
                b.contact_stiffness = b.contact_stiffness.map(|s| s * k);
            }
        }
        if let Some(law) = self.law {
            let wire_radius = f
                .wire
                .layers
                .as_ref()
                .and_then(|l| l.last())
                .map_or(0.0, |l| l.outer_radius);
            for r in &mut f.rod {
                switch_law(r, law, wire_radius);
            }
        }
        let every = match (sample_interval, self.time_step) {
            (Some(dt), Some(h)) => Some(((dt / h).round() as usize).max(1)),
            _ => None,
        };
        f.output = Some(OutputSpec {
            every,
            checkpoint_every: Some(0),
            vtk: Some(false),
            vtk_every: None,
            plots: Some(false),
            cfc: base.output.as_ref().and_then(|o| o.cfc),
            response_frequencies: base
                .output
                .as_ref()
                .and_then(|o| o.response_frequencies.clone()),
            response_damping: base.output.as_ref().and_then(|o| o.response_damping),
        });
        f
    }
}

/// The tightest Newton tolerance the study uses (the default's): the
/// reference runs with it whatever the scene's.
pub const NEWTON_TOLERANCE_FLOOR: f64 = 1e-10;

/// The penetration, as a fraction of the wire radius, at which the surface
/// law is matched to a line-law rod's crossing force.
pub const SURFACE_MATCH_PENETRATION: f64 = 0.1;

/// A line-law rod (`law = "line"`) under `law`: hertz takes the stiffness
/// from the rod's material (the run is refused when the rod names none);
/// the surface law gets the ε_N (N/m³) whose 90° crossing force equals the
/// line law's at a penetration δ* = 0.1 R_wire
/// ([`surface_stiffness_matching_line`]). Rods under other laws keep theirs.
fn switch_law(r: &mut ancf_core::scene::RodSpec, law: ContactLaw, wire_radius: f64) {
    if r.contact_law.as_deref() != Some("line") {
        return;
    }
    r.contact_law = Some(law.name().into());
    match law {
        ContactLaw::Line => {}
        ContactLaw::Hertz => r.contact_stiffness = None,
        ContactLaw::Surface => {
            let delta = SURFACE_MATCH_PENETRATION * wire_radius;
            r.contact_stiffness = r
                .contact_stiffness
                .map(|eps_l| surface_stiffness_matching_line(eps_l, wire_radius, r.radius, delta));
        }
    }
}

/// What a family of runs measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FamilyKind {
    /// Static: tip displacement.
    Static,
    /// Dynamic: tip trajectory and energy.
    Dynamic,
    /// Contact resolution: penetration, peak contact force and its time.
    Contact,
}

/// A sweep: a named list of settings shown in one table and one plot.
#[derive(Clone, Debug)]
pub struct Family {
    pub name: String,
    pub kind: FamilyKind,
    pub settings: Vec<Setting>,
}

/// Everything a study runs for one scene.
#[derive(Clone, Debug)]
pub struct Plan {
    pub families: Vec<Family>,
    /// The converged reference run (when no analytic value applies).
    pub reference: Setting,
    /// Dynamic scenes: the times at which trajectories are compared, s
    /// (the coarsest time step, so every run has a row there).
    pub sample_interval: Option<f64>,
}

fn push_unique(v: &mut Vec<Setting>, s: Setting) {
    if !v.contains(&s) {
        v.push(s);
    }
}

/// Stations per element that keep the scene's station spacing (m) on
/// `elements` elements (the validation requires spacing ≤ rod radius).
fn stations_for(base: &Setting, length: f64, elements: usize) -> Option<usize> {
    let s0 = base.stations?;
    let spacing = station_spacing(s0, length / base.elements as f64);
    Some(
        (1..=64)
            .find(|&n| station_spacing(n, length / elements as f64) <= spacing * (1.0 + 1e-12))
            .unwrap_or(64),
    )
}

/// `s` at the largest of h, h/2, h/4, … that resolves every rod's
/// line-law contact (h √(ε_L / ρA) ≤ 3,
/// [`ancf_core::model::contact::RESOLVED_STEP_FREQUENCY`]): the stiffness
/// and law families compare penalties and laws, which a step too coarse
/// for them does not (it goes on by rejecting steps, its loads set by which
/// sub-steps passed).
/// A setting the scene check refuses is left as is (its run says why).
fn resolved(file: &SceneFile, mut s: Setting) -> Setting {
    let Ok(scene) = Scene::from_file(&s.apply(file, None)) else {
        return s;
    };
    if let (Some(limit), Analysis::Dynamic { settings, .. }) =
        (scene.resolving_step(), &scene.analysis)
    {
        let mut h = settings.time_step;
        while h > limit {
            h /= 2.0;
        }
        s.time_step = Some(h);
    }
    s
}

/// The sweeps for `scene` (whose file is `file`).
pub fn plan(file: &SceneFile, scene: &Scene, level: Level) -> Plan {
    let base = Setting::of_scene(scene);
    let length = file.wire.length;
    let quick = level == Level::Quick;
    if file.analysis.kind == AnalysisKind::Static {
        let elements: &[usize] = if quick {
            &[1, 2, 4]
        } else {
            &[1, 2, 4, 8, 16, 32, 64]
        };
        let axial: &[usize] = if quick { &[3, 5] } else { &[2, 3, 4, 5] };
        let section: &[usize] = if quick { &[3] } else { &[2, 3, 4, 5] };
        let mut settings = Vec::new();
        for &s in section {
            for &a in axial {
                for &n in elements {
                    settings.push(Setting {
                        elements: n,
                        axial: a,
                        section: s,
                        ..base.clone()
                    });
                }
            }
        }
        let reference = Setting {
            elements: 2 * elements.last().unwrap(),
            axial: 5,
            section: 5,
            ..base.clone()
        };
        return Plan {
            families: vec![Family {
                name: "Mesh and quadrature".into(),
                kind: FamilyKind::Static,
                settings,
            }],
            reference,
            sample_interval: None,
        };
    }

    // Dynamic: time step × elements at the scene's ρ∞ and Newton kind, then
    // ρ∞ and the other Newton kind at the scene's element count.
    let h0 = fixed_step(scene, &base);
    let contact = base.stations.is_some() || base.zone_points.is_some();
    if level == Level::Refinement {
        return refinement_plan(&base, h0, length);
    }
    let h_factors: &[f64] = if quick {
        &[2.0, 1.0]
    } else if contact {
        &[2.0, 1.0, 0.5, 0.25]
    } else {
        &[4.0, 2.0, 1.0, 0.5, 0.25]
    };
    // ρ∞, Newton kind and axial order are varied at these step factors
    // (contact runs cost seconds each: two steps say enough there).
    let variant_factors: &[f64] = if contact { &[1.0, 0.5] } else { h_factors };
    let n_factors: &[f64] = if quick {
        &[1.0, 2.0]
    } else if contact {
        &[0.5, 1.0, 2.0]
    } else {
        &[0.5, 1.0, 2.0, 4.0]
    };
    let at = |h: f64, n: usize| at_step_and_mesh(&base, length, h, n);
    let element_counts: Vec<usize> = {
        let mut v: Vec<usize> = n_factors
            .iter()
            .map(|f| ((base.elements as f64 * f).round() as usize).max(1))
            .collect();
        v.dedup();
        v
    };
    let mut stepping = Vec::new();
    for &n in &element_counts {
        for &hf in h_factors {
            push_unique(&mut stepping, at(h0 * hf, n));
        }
    }
    if !quick {
        let rho0 = base.spectral_radius.unwrap_or(1.0);
        for rho in [1.0, 0.9, 0.8] {
            if rho != rho0 {
                for &hf in variant_factors {
                    push_unique(
                        &mut stepping,
                        Setting {
                            spectral_radius: Some(rho),
                            ..at(h0 * hf, base.elements)
                        },
                    );
                }
            }
        }
        for &hf in variant_factors {
            push_unique(
                &mut stepping,
                Setting {
                    full_newton: base.full_newton.map(|f| !f),
                    ..at(h0 * hf, base.elements)
                },
            );
        }
        // Newton's tolerance, tightened (a scene may stop Newton early
        // where that moves nothing it reports: shown here, not assumed).
        let t0 = base.tolerance.unwrap_or(NEWTON_TOLERANCE_FLOOR);
        for t in [1e-6, 1e-8, NEWTON_TOLERANCE_FLOOR] {
            if t < t0 {
                push_unique(
                    &mut stepping,
                    Setting {
                        tolerance: Some(t),
                        ..at(h0, base.elements)
                    },
                );
            }
        }
        for axial in 2..=5 {
            if axial != base.axial {
                for &hf in variant_factors {
                    push_unique(
                        &mut stepping,
                        Setting {
                            axial,
                            ..at(h0 * hf, base.elements)
                        },
                    );
                }
            }
        }
    }
    // Adaptive steps beside the fixed ones, at the scene's mesh, error
    // tolerances 1e-4 … 1e-7 m per step: the
    // tables and plots then compare them at equal accuracy.
    let tolerances: &[f64] = if quick {
        &[1e-6]
    } else {
        &[1e-4, 1e-5, 1e-6, 1e-7]
    };
    for &t in tolerances {
        push_unique(
            &mut stepping,
            Setting {
                time_step: None,
                error_tolerance: Some(t),
                ..base.clone()
            },
        );
    }
    let h_min = h0 * h_factors.iter().copied().fold(f64::INFINITY, f64::min);
    let h_max = h0 * h_factors.iter().copied().fold(0.0, f64::max);
    let n_max = *element_counts.iter().max().unwrap();
    let mut families = vec![Family {
        name: "Time stepping and mesh".into(),
        kind: FamilyKind::Dynamic,
        settings: stepping,
    }];
    if base.stations.is_some() || base.zone_points.is_some() {
        // The contact integration refined (stations of the surface law,
        // zone points of the line laws) against the stiffness.
        let refine = |k: usize| -> Setting {
            Setting {
                stations: base.stations.map(|s0| (s0 << k).min(64)),
                zone_points: base.zone_points.map(|z0| (z0 << k).min(32)),
                ..base.clone()
            }
        };
        let levels: Vec<Setting> = if quick {
            vec![refine(0)]
        } else if base.zone_points.is_some() {
            // ½, 1 and 2 × the scene's zone points: three levels for an order.
            let half = Setting {
                zone_points: base.zone_points.map(|z0| (z0 / 2).max(1)),
                ..base.clone()
            };
            vec![half, refine(0), refine(1)]
        } else {
            vec![refine(0), refine(1), refine(2)]
        };
        let factors: &[f64] = if quick {
            &[0.1, 1.0]
        } else {
            &[0.01, 0.1, 1.0, 10.0, 100.0]
        };
        let mut contact = Vec::new();
        for level in &levels {
            for &k in factors {
                push_unique(
                    &mut contact,
                    resolved(
                        file,
                        Setting {
                            stiffness_factor: Some(k),
                            ..level.clone()
                        },
                    ),
                );
            }
        }
        families.push(Family {
            name: "Contact resolution".into(),
            kind: FamilyKind::Contact,
            settings: contact,
        });
        // The laws side by side on line-law scenes (the scene's own first).
        if base.zone_points.is_some() && !quick {
            let laws = [ContactLaw::Line, ContactLaw::Hertz, ContactLaw::Surface];
            families.push(Family {
                name: "Contact law".into(),
                kind: FamilyKind::Contact,
                settings: laws
                    .iter()
                    .map(|&law| {
                        resolved(
                            file,
                            Setting {
                                law: (law != ContactLaw::Line).then_some(law),
                                ..base.clone()
                            },
                        )
                    })
                    .collect(),
            });
        }
    }
    let reference = Setting {
        elements: 2 * n_max,
        axial: reference_axial(scene, &base),
        section: base.section,
        // Contact runs: h_min/2 (a contact reference at h_min/4 and twice
        // the elements takes ten minutes; the contact errors are far larger
        // than what the factor 2 leaves).
        time_step: Some(if contact { h_min / 2.0 } else { h_min / 4.0 }),
        error_tolerance: None,
        spectral_radius: Some(1.0),
        // Modified Newton: the tolerance, not the Newton kind, sets how
        // close the reference is to its converged solution (on the impact
        // scene's reference the two kinds agree to 1.1e-6 relative, far
        // under the errors the study measures, and modified Newton costs a
        // third).
        full_newton: Some(false),
        tolerance: Some(NEWTON_TOLERANCE_FLOOR),
        stations: stations_for(&base, length, 2 * n_max).map(|s| (2 * s).min(64)),
        zone_points: base.zone_points.map(|z| (2 * z).min(32)),
        stiffness_factor: base.stiffness_factor,
        law: None,
    };
    Plan {
        families,
        reference,
        sample_interval: Some(h_max),
    }
}

/// The axial order of a dynamic scene's reference run. Five points
/// integrate a St. Venant–Kirchhoff element exactly (its energy density is
/// of degree 8 in ξ); when every law of the section is pre-integrated, three
/// (or the scene's own, if higher) moved the impact study's reference by
/// 5e-8 of the tip excursion, 1e-8 of the filtered peak and 6e-8 of the
/// impulse at 256 elements — 1/2000 of the finest threshold the study
/// reports — at 3/4 of its cost. Other laws keep five.
fn reference_axial(scene: &Scene, base: &Setting) -> usize {
    let all_preintegrated = scene.model.element(0).plan.is_preintegrated_only();
    base.axial.max(if all_preintegrated { 3 } else { 5 })
}

/// The fixed step the study refines: the scene's, or a tenth of an adaptive
/// scene's longest step.
fn fixed_step(scene: &Scene, base: &Setting) -> f64 {
    match (&scene.analysis, base.time_step) {
        (_, Some(h)) => h,
        (Analysis::Dynamic { settings, .. }, None) => {
            (settings.step_control.as_ref()).map_or(settings.time_step, |c| c.max_step / 10.0)
        }
        (Analysis::Static { .. }, None) => unreachable!("a static scene has no time step"),
    }
}

/// `base` at time step `h` (s) on `n` elements, with the surface-law
/// stations that mesh needs.
fn at_step_and_mesh(base: &Setting, length: f64, h: f64, n: usize) -> Setting {
    Setting {
        elements: n,
        time_step: Some(h),
        error_tolerance: None,
        stations: stations_for(base, length, n),
        ..base.clone()
    }
}

/// [`Level::Refinement`] of a dynamic scene: one family, the scene's
/// setting refined in h, in the elements and in the contact points, three
/// levels each; the reference run is the finest mesh at the finest step.
fn refinement_plan(base: &Setting, h0: f64, length: f64) -> Plan {
    let at = |h: f64, n: usize| at_step_and_mesh(base, length, h, n);
    let half = (base.elements / 2).max(1);
    let mut settings = Vec::new();
    for s in [
        at(h0, half),
        at(h0, base.elements),
        at(h0, 2 * base.elements),
        at(h0 / 2.0, base.elements),
        at(h0 / 4.0, base.elements),
    ] {
        push_unique(&mut settings, s);
    }
    if base.zone_points.is_some() || base.stations.is_some() {
        for k in [0.5, 2.0] {
            push_unique(
                &mut settings,
                Setting {
                    stations: base
                        .stations
                        .map(|s| ((s as f64 * k) as usize).clamp(1, 64)),
                    zone_points: base
                        .zone_points
                        .map(|z| ((z as f64 * k) as usize).clamp(1, 32)),
                    ..base.clone()
                },
            );
        }
    }
    Plan {
        families: vec![Family {
            name: "Refinement".into(),
            kind: FamilyKind::Dynamic,
            settings,
        }],
        reference: Setting {
            tolerance: Some(base.tolerance.unwrap_or(1.0).min(1e-8)),
            ..at(h0 / 4.0, 2 * base.elements)
        },
        sample_interval: Some(h0),
    }
}

/// Sets the scene's element count to `n`: a uniform mesh gets `n` elements,
/// a graded one keeps its proportions (each segment's count scaled by
/// n / total, rounded, at least 1).
fn set_elements(f: &mut SceneFile, n: usize) {
    match &mut f.wire.segments {
        Some(segments) => {
            let total: usize = segments.iter().map(|s| s.elements).sum();
            let factor = n as f64 / total as f64;
            for s in segments {
                s.elements = ((s.elements as f64 * factor).round() as usize).max(1);
            }
        }
        None => f.wire.elements = Some(n),
    }
}
