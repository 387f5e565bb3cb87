//! The supports' loads as a frame or tower designer reads them: the static
//! force, the peak over the run (raw and CFC-filtered) and their ratio to
//! the static force (the wire's supports) or to the member's own limit (a
//! frame member's), and what a structure with one mode at a given
//! frequency feels from it.

use crate::output::{SupportResponse, SupportSummary};
use ancf_core::loads::design_check::{CircularResistance, section_resistance};
use ancf_core::loads::response::{peak_response, peak_response_magnitude};
use ancf_core::loads::rod_load::{Filtered, LoadHistory};
use ancf_core::math::vec3::norm;
use ancf_core::model::Model;

/// A static run's supports: the reaction at equilibrium alone.
/// `reactions` are `StaticResult::reactions` (node, force), in the model's
/// support order.
/// `q` the equilibrium's coordinates (a spring's moment is read there).
pub fn static_supports(
    model: &Model,
    reactions: &[(usize, [f64; 3])],
    q: &[f64],
) -> Vec<SupportSummary> {
    reactions
        .iter()
        .enumerate()
        .map(|(i, (node, f))| {
            let limit = member_resistance(model, *node);
            let (beam, node) = beam_and_node(model, *node);
            let moment = model.moment_spring(i).map(|s| norm(s.moment_on_body(q)));
            SupportSummary {
                beam,
                node,
                static_force: *f,
                peak_moment: moment,
                limit_force: limit.map(|r| r.axial),
                ratio_to_limit: limit.map(|r| norm(*f) / r.axial),
                limit_moment: limit.map(|r| r.moment),
                moment_ratio_to_limit: limit.zip(moment).map(|(r, m)| m / r.moment),
                ..Default::default()
            }
        })
        .collect()
}

/// Into `supports` (a dynamic run's, model order): each spring support's
/// largest moment over `moments` (the simulation's histories, empty when no
/// support carries one).
pub fn add_peak_moments(model: &Model, supports: &mut [SupportSummary], moments: &[LoadHistory]) {
    for (i, (summary, h)) in supports.iter_mut().zip(moments).enumerate() {
        if model.moment_spring(i).is_none() {
            continue;
        }
        let peak = (h.time.iter().zip(&h.force))
            .map(|(t, m)| (*t, norm(*m)))
            .fold(None, |best: Option<(f64, f64)>, (t, m)| match best {
                Some((_, b)) if b >= m => best,
                _ => Some((t, m)),
            });
        if let Some((t, m)) = peak {
            summary.peak_moment = Some(m);
            summary.peak_moment_time = Some(t);
            summary.moment_ratio_to_limit = summary.limit_moment.map(|limit| m / limit);
        }
    }
}

/// The design resistance of the frame member that holds the model's node
/// `n`, read from the section of the element at the node: `None` for the
/// wire and for a section without one (no f_y, layered, rectangular).
fn member_resistance(model: &Model, n: usize) -> Option<CircularResistance> {
    let (b, local) = model.beam_of_node(n)?;
    let elements = &model.beams[b].elements;
    let el = (elements.start + local).min(elements.end.checked_sub(1)?);
    (b > 0).then(|| section_resistance(&model.element(el).section))?
}

/// The beam holding the model's node `n` (its name) and the node's index on it.
fn beam_and_node(model: &Model, n: usize) -> (String, usize) {
    let (b, local) = model
        .beam_of_node(n)
        .expect("a support's node is on a beam");
    (model.beams[b].name.clone(), local)
}

/// A dynamic run's supports: `initial` is each support's force at t = 0
/// (`Simulation::initial_support_forces`; missing entries count as zero),
/// `loads` and `filtered` their histories and CFC-filtered magnitudes,
/// and the oscillators of each of `frequencies` (Hz) with ratio `damping`
/// driven by each component of the force (none when empty).
/// The peaks are compared with the force at t = 0 only when the run starts
/// from the static equilibrium (`from_equilibrium`): a run that starts at
/// rest in the unloaded shape has, at t = 0, only the share of gravity the
/// mass coupling leaves to the supports, no static load to compare with.
pub fn dynamic_supports(
    model: &Model,
    initial: &[[f64; 3]],
    from_equilibrium: bool,
    loads: &[LoadHistory],
    filtered: &[Filtered],
    (frequencies, damping): (&[f64], f64),
) -> Vec<SupportSummary> {
    model
        .supports
        .iter()
        .zip(loads)
        .zip(filtered)
        .enumerate()
        .map(|(i, ((s, h), f))| {
            let static_force = initial.get(i).copied().unwrap_or([0.0; 3]);
            let load = h.summary(f);
            let reference = norm(static_force);
            let of_wire = model.beam_of_node(s.node).is_some_and(|(b, _)| b == 0);
            let ratio = |peak: f64| {
                (of_wire && from_equilibrium && reference > 0.0).then(|| peak / reference)
            };
            let limit = member_resistance(model, s.node);
            let to_limit = |peak: f64| limit.map(|r| peak / r.axial);
            let (beam, node) = beam_and_node(model, s.node);
            // The force at t = 0, then the steps' (built only when asked for).
            let series = (!frequencies.is_empty()).then(|| {
                let time: Vec<f64> = std::iter::once(0.0).chain(h.time.iter().copied()).collect();
                let components: [Vec<f64>; 3] = std::array::from_fn(|c| {
                    let steps = h.force.iter().map(|f| f[c]);
                    std::iter::once(static_force[c]).chain(steps).collect()
                });
                (time, components)
            });
            SupportSummary {
                beam,
                node,
                static_force,
                peak_force: Some(load.peak_force),
                peak_time: Some(load.peak_time),
                filtered_peak_force: Some(load.filtered_peak_force),
                ratio_to_static: ratio(load.peak_force),
                filtered_ratio_to_static: ratio(load.filtered_peak_force),
                limit_force: limit.map(|r| r.axial),
                ratio_to_limit: to_limit(load.peak_force),
                filtered_ratio_to_limit: to_limit(load.filtered_peak_force),
                limit_moment: limit.map(|r| r.moment),
                response: (series.iter())
                    .flat_map(|(time, components)| {
                        frequencies.iter().map(move |&f| (time, components, f))
                    })
                    .map(|(time, components, frequency)| {
                        let peak: [f64; 3] = std::array::from_fn(|c| {
                            peak_response(time, &components[c], frequency, damping)
                        });
                        let vector = components.each_ref().map(Vec::as_slice);
                        let magnitude = peak_response_magnitude(time, vector, frequency, damping);
                        SupportResponse {
                            frequency,
                            damping,
                            peak,
                            peak_magnitude: magnitude,
                            ratio_to_static: ratio(magnitude),
                            ratio_to_limit: to_limit(magnitude),
                        }
                    })
                    .collect(),
                ..Default::default()
            }
        })
        .collect()
}
