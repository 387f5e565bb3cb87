//! A run's PNG plots: the energy balance, configurations, the first
//! contact point, and the force on each rod.

use super::history::History;
use crate::plot::{Panel, Series, configurations_plot, line_plot, panels_plot};
use ancf_core::loads::rod_load::{Filtered, LoadHistory, RodLoad};
use ancf_core::math::vec3::norm;
use ancf_core::model::Model;
use ancf_core::solve::dynamics::Energies;
use std::path::Path;

/// A plot still to be drawn: it writes its PNG when called.
pub type PlotJob<'a> = Box<dyn FnOnce() -> Result<(), String> + Send + 'a>;

/// Draws `jobs` at once on rayon's threads and returns the first error in
/// their order. Each plot is drawn supersampled and encoded on its own for
/// tens of ms, a noticeable part of a small run; a plot that panics is an
/// error, not the end of the run.
pub fn draw(jobs: Vec<PlotJob<'_>>) -> Result<(), String> {
    use rayon::prelude::*;
    let results: Vec<Result<(), String>> = jobs
        .into_par_iter()
        .map(|job| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
                .unwrap_or_else(|_| Err("a plot panicked".to_string()))
        })
        .collect();
    results.into_iter().collect()
}

/// `energy.png`, `configurations.png` and (with a contact point)
/// `contact_point.png`, as jobs for [`draw`].
pub fn dynamic_plots<'a>(out: &'a Path, model: &'a Model, h: &'a History) -> Vec<PlotJob<'a>> {
    let mut jobs: Vec<PlotJob<'a>> = vec![
        Box::new(move || plot_energy(out, model, h)),
        Box::new(move || plot_configurations(out, model, h)),
    ];
    if !h.contact_point.is_empty() {
        jobs.push(Box::new(move || plot_contact_point(out, h)));
    }
    jobs
}

/// `energy.png`: the energies and their total.
fn plot_energy(out: &Path, model: &Model, h: &History) -> Result<(), String> {
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
    )
}

/// `configurations.png`: the wire's shapes, with the rods and frame
/// members across the plane seen end-on.
fn plot_configurations(out: &Path, model: &Model, h: &History) -> Result<(), String> {
    let contact = model.contact();
    let mut rods: Vec<(f64, f64, f64)> = contact
        .map(|c| {
            c.rods
                .iter()
                .filter(|r| !r.is_ground() && r.axis[1].abs() > 0.99)
                .map(|r| (r.center[0], r.center[2], r.radius))
                .collect()
        })
        .unwrap_or_default();
    // Frame members across the plane (along y), seen end-on at their middle.
    for beam in model.beams.iter().skip(1) {
        if beam.axis[1].abs() > 0.99 {
            let (a, b) = (beam.nodes.start, beam.nodes.end - 1);
            let mid = |k: usize| 0.5 * (model.reference[12 * a + k] + model.reference[12 * b + k]);
            let radius = model.element(beam.elements.start).section.outer_radius();
            rods.push((mid(0), mid(2), radius));
        }
    }
    configurations_plot(&out.join("configurations.png"), &h.shapes, &rods)
}

/// `contact_point.png`: the first contact point's displacement and strains.
fn plot_contact_point(out: &Path, h: &History) -> Result<(), String> {
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
    )
}

/// `rod_forces.png`: per rod and ground (`names`: `rod0`, `ground0`, …),
/// the raw and the filtered force with both peaks marked.
pub fn plot_rod_forces(
    out: &Path,
    names: &[String],
    loads: &[LoadHistory],
    filtered: &[Filtered],
    rods: &[&crate::output::RodSummary],
) -> Result<(), String> {
    let titles: Vec<String> = (0..loads.len())
        .map(|i| {
            let name = names[i]
                .replacen("rod", "rod ", 1)
                .replacen("ground", "ground ", 1);
            format!("Force on {name} (CFC {:.0})", rods[i].load.cfc)
        })
        .collect();
    let summaries: Vec<&RodLoad> = rods.iter().map(|r| &r.load).collect();
    plot_forces(
        &out.join("rod_forces.png"),
        &titles,
        loads,
        filtered,
        &summaries,
    )
}

/// `member_loads.png`: per frame member a row, the wire's contact force on
/// it (raw and filtered, both peaks marked) beside its largest bending
/// moment over time (`moments`: time s, N m, each member's, as
/// member_forces.csv's `NAME_moment`) with its section's bending
/// resistance (`limits`: M_pl,Rd, N m, where the section has one), so a
/// designer sees when and how often the blows take it to its limit; the
/// largest moment, von Mises stress and utilization in the titles.
pub fn plot_member_loads(
    out: &Path,
    (loads, filtered, moments): super::files::MemberLoads<'_>,
    limits: &[Option<f64>],
    beams: &[crate::output::BeamSummary],
) -> Result<(), String> {
    let force_titles: Vec<String> = (beams.iter())
        .map(|b| format!("Contact force on {} (CFC {:.0})", b.name, b.contact.cfc))
        .collect();
    let moment_titles: Vec<String> = (beams.iter())
        .map(|b| {
            let utilization =
                (b.record.utilization).map_or(String::new(), |u| format!(", utilization {u:.2}"));
            format!(
                "Largest moment in {}: {:.3} kN m, von Mises {:.1} MPa{utilization}",
                b.name,
                b.record.max_bending_moment / 1e3,
                b.record.max_von_mises / 1e6
            )
        })
        .collect();
    let mut panels = Vec::with_capacity(2 * beams.len());
    for (i, b) in beams.iter().enumerate() {
        let (Some(h), Some(f)) = (loads.get(i), filtered.get(i)) else {
            break;
        };
        panels.push(force_panel(&force_titles[i], h, f, &b.contact));
        let moment = moments.get(i).map_or(&[][..], Vec::as_slice);
        let kilo: Vec<(f64, f64)> = moment.iter().map(|&(t, m)| (t, m / 1e3)).collect();
        let mut series = vec![Series {
            label: "largest |M| along the member",
            points: kilo,
        }];
        if let (Some(limit), Some(first), Some(last)) = (
            limits.get(i).copied().flatten(),
            moment.first(),
            moment.last(),
        ) {
            series.push(Series {
                label: "M_pl,Rd = W_pl f_y",
                points: vec![(first.0, limit / 1e3), (last.0, limit / 1e3)],
            });
        }
        let peak = (b.record.max_bending_moment > 0.0).then(|| {
            let m = b.record.max_bending_moment;
            (
                b.record.max_bending_moment_time,
                m / 1e3,
                format!("max {:.2} kN m", m / 1e3),
            )
        });
        panels.push(Panel {
            title: &moment_titles[i],
            x_label: "time t (s)",
            y_label: "bending moment (kN m)",
            series,
            marks: peak.into_iter().collect(),
            markers: false,
        });
    }
    if panels
        .iter()
        .step_by(2)
        .all(|p| p.series[0].points.is_empty())
    {
        return Ok(());
    }
    panels_plot(
        &out.join("member_loads.png"),
        panels.len() / 2,
        2,
        (960, 480),
        &panels,
    )
}

/// Panels of forces: per load, its raw and filtered |F| with both peaks.
fn plot_forces(
    path: &Path,
    titles: &[String],
    loads: &[LoadHistory],
    filtered: &[Filtered],
    summaries: &[&RodLoad],
) -> Result<(), String> {
    let panels: Vec<Panel> = (loads.iter().zip(filtered).zip(summaries).zip(titles))
        .map(|(((h, f), load), title)| force_panel(title, h, f, load))
        .collect();
    if panels.iter().all(|p| p.series[0].points.is_empty()) {
        return Ok(());
    }
    panels_plot(path, panels.len(), 1, (960, 480), &panels)
}

/// One load's panel: its raw and filtered |F| (N) over time, the filtered
/// drawn over the raw, with both peaks of `load` marked.
fn force_panel<'a>(title: &'a str, h: &LoadHistory, f: &Filtered, load: &RodLoad) -> Panel<'a> {
    let raw = (h.time.iter().zip(&h.force))
        .map(|(t, v)| (*t, norm(*v)))
        .collect();
    Panel {
        title,
        x_label: "time t (s)",
        y_label: "force (N)",
        series: vec![
            Series {
                label: "raw, every step (with the wire's axial ringing)",
                points: raw,
            },
            Series {
                label: "CFC filtered: the design value, as impact tests report",
                points: (f.time.iter().copied())
                    .zip(f.force.iter().copied())
                    .collect(),
            },
        ],
        marks: vec![
            (
                load.peak_time,
                load.peak_force,
                format!("raw peak {:.0} N", load.peak_force),
            ),
            (
                load.filtered_peak_time,
                load.filtered_peak_force,
                format!("filtered peak {:.0} N", load.filtered_peak_force),
            ),
        ],
        markers: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn every_job_runs_and_the_first_error_is_returned() {
        let ran = AtomicUsize::new(0);
        let job = |fail: Option<&'static str>| -> PlotJob<'_> {
            let ran = &ran;
            Box::new(move || {
                ran.fetch_add(1, Ordering::SeqCst);
                fail.map_or(Ok(()), |m| Err(m.to_string()))
            })
        };
        assert_eq!(draw(Vec::new()), Ok(()));
        assert_eq!(draw(vec![job(None), job(None), job(None)]), Ok(()));
        assert_eq!(ran.swap(0, Ordering::SeqCst), 3);
        let r = draw(vec![job(None), job(Some("second")), job(Some("third"))]);
        assert_eq!(r, Err("second".to_string()));
        assert_eq!(ran.load(Ordering::SeqCst), 3);
    }

    #[test]
    fn a_panicking_plot_is_an_error_and_the_others_are_drawn() {
        let ran = AtomicUsize::new(0);
        let count = || {
            ran.fetch_add(1, Ordering::SeqCst);
            Ok(())
        };
        let jobs: Vec<PlotJob<'_>> = vec![
            Box::new(|| panic!("no font")),
            Box::new(count),
            Box::new(|| Ok(())),
            Box::new(count),
        ];
        assert_eq!(draw(jobs), Err("a plot panicked".to_string()));
        assert_eq!(ran.load(Ordering::SeqCst), 2);
    }
}
