//! Global assembly, split as in fenris/diffsol: the sparsity pattern and
//! the map from element entries to value slots are computed once per model
//! ([`pattern`]); each Newton iteration only refills values in place
//! ([`assemble`]).

use super::plastic::{History, PlasticLayout};
use crate::element::ElementVector;
use crate::linalg::pattern::Pattern;
use crate::model::{Model, NODE_DOFS};
use std::ops::Range;

/// The pattern of `model`'s Newton matrix (once per phase).
pub fn pattern(model: &Model) -> Pattern {
    Pattern::new(&model.dof_map, model.n_unknowns, model.n_elements)
}

/// Elastic force (full coordinates), optionally its Jacobian (values in the
/// pattern's slots, written over `jacobian`'s), and the strain energy.
///
/// With enough element work ([`runs_in_parallel`]), the elements are split into
/// chunks that rayon evaluates in parallel, each writing straight into its
/// own windows of the force and of the Jacobian's values (see `Chunk`).
/// Every value receives its contributions in the serial loop's order, so
/// the result has the same bits as the serial loop with any number of
/// threads (tests: `chunked_assembly_equals_the_serial_loop` here,
/// `parallel_assembly_is_deterministic` in ancf-core/tests/pendulum.rs).
pub fn assemble(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    jacobian: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    let mut force = vec![0.0; q.len()];
    let mut energy = vec![0.0; model.n_elements];
    let u = assemble_into(model, pattern, q, jacobian, &mut force, &mut energy);
    (force, u)
}

/// [`assemble`] into `force` (full coordinates, overwritten) with
/// `energy` (one per element, overwritten) as workspace: what a Newton
/// loop calls every iteration without allocating. Returns the strain energy.
pub fn assemble_into(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    jacobian: Option<&mut [f64]>,
    force: &mut [f64],
    energy: &mut [f64],
) -> f64 {
    let virgin = History::default();
    assemble_into_with(model, pattern, q, virgin, jacobian, force, energy)
}

/// [`assemble_into`] with the yielding points evaluated from `plastic`
/// (their stored energy is the elastic part).
pub fn assemble_into_with(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    plastic: History<'_>,
    jacobian: Option<&mut [f64]>,
    force: &mut [f64],
    energy: &mut [f64],
) -> f64 {
    force.fill(0.0);
    // Per-element energies, summed in element order at the end.
    energy.fill(0.0);
    if !runs_in_parallel(model, jacobian.is_some()) || rayon::current_num_threads() == 1 {
        let mut values = jacobian.map(|v| {
            v.fill(0.0);
            (v, 0)
        });
        let all = 0..model.n_elements;
        let at = (q, plastic);
        add_whole_elements(model, pattern, at, all, 0, force, energy, values.as_mut());
    } else {
        assemble_chunks(model, pattern, (q, plastic), force, energy, jacobian);
    }
    energy.iter().sum()
}

/// The elements `els` whole — force and, with `values`, Jacobian columns —
/// into a force window that starts at node `node0`, their energies into
/// `energy` (from `els.start` on). Several at a time where the kernel
/// allows: forces eight and then four at a time
/// ([`crate::element::ElementIntegration::forces_x8`], `forces_x4`),
/// Jacobians four at a time (`jacobians_x4`); the same bits per element as
/// one by one, added in the same order, and faster with SIMD.
#[allow(clippy::too_many_arguments)]
fn add_whole_elements(
    model: &Model,
    pattern: &Pattern,
    (q, plastic): (&[f64], History<'_>),
    els: Range<usize>,
    node0: usize,
    force: &mut [f64],
    energy: &mut [f64],
    mut values: Option<&mut (&mut [f64], usize)>,
) {
    let e0 = els.start;
    // The Jacobian lane kernel writes every entry of `k4`: zeroed at the
    // first batch of a call that assembles a Jacobian, not at every batch
    // (18 KB a batch showed as memset, perf).
    let mut k4: Option<[[f64; 4]; 576]> = None;
    for group in &model.groups {
        let end = group.elements.end.min(els.end);
        let mut first = group.elements.start.max(els.start);
        // A yielding layer's elements: the pre-integrated laws eight or four
        // at a time, then each element's corrections where it yields.
        let yielding = group.integration.plan.is_plastic();
        while values.is_none() && first + 8 <= end {
            let mut q8 = [[0.0; 8]; 24];
            let e8 = lanes(model, q, first);
            let u = match yielding {
                true => group.integration.forces_x8_before_plastic(&e8, &mut q8),
                false => group.integration.forces_x8(&e8, &mut q8),
            };
            let Some(u) = u else {
                break;
            };
            match yielding {
                true => add_lanes_yielding(
                    model,
                    (q, plastic),
                    first,
                    (&u, &q8),
                    (e0, node0),
                    force,
                    energy,
                ),
                false => add_lanes(&u, &q8, first - e0, first - node0, force, energy),
            }
            first += 8;
        }
        while yielding && values.is_none() && first + 4 <= end {
            let mut q4 = [[0.0; 4]; 24];
            let e4 = lanes(model, q, first);
            let Some(u) = group.integration.forces_x4_before_plastic(&e4, &mut q4) else {
                break;
            };
            add_lanes_yielding(
                model,
                (q, plastic),
                first,
                (&u, &q4),
                (e0, node0),
                force,
                energy,
            );
            first += 4;
        }
        while yielding && first + 4 <= end {
            let Some((v, offset)) = values.as_mut() else {
                break;
            };
            let e4 = lanes(model, q, first);
            let mut q4 = [[0.0; 4]; 24];
            #[allow(clippy::unnecessary_lazy_evaluations)]
            let k4 = k4.get_or_insert_with(|| [[0.0; 4]; 576]);
            let ei = &group.integration;
            let Some(u) = ei.jacobians_x4_before_plastic(&e4, &mut q4, k4) else {
                break;
            };
            // Each element's lane with its corrections, as one by one.
            for k in 0..4 {
                let el = first + k;
                let e = model.element_coordinates(q, el);
                let mut qe: [f64; 24] = std::array::from_fn(|i| q4[i][k]);
                let mut ke: [f64; 576] = std::array::from_fn(|i| k4[i][k]);
                let input = plastic.element(el);
                let correction = ei.add_plastic(&e, input, &mut qe, Some(&mut ke));
                pattern.add_element_columns(v, *offset, el, &ke, 0..24);
                energy[el - e0] = u[k] + correction;
                let base = NODE_DOFS * (el - node0);
                for (f, x) in force[base..base + 24].iter_mut().zip(&qe) {
                    *f += x;
                }
            }
            first += 4;
        }
        while first + 4 <= end {
            let e4 = lanes(model, q, first);
            let mut q4 = [[0.0; 4]; 24];
            let u = match values.as_mut() {
                Some((v, offset)) => {
                    // Lazy on purpose: `get_or_insert` would zero 18 KB at every batch.
                    #[allow(clippy::unnecessary_lazy_evaluations)]
                    let k4 = k4.get_or_insert_with(|| [[0.0; 4]; 576]);
                    let Some(u) = group.integration.jacobians_x4(&e4, &mut q4, k4) else {
                        break;
                    };
                    for k in 0..4 {
                        pattern.add_lane_columns(v, *offset, first + k, k4, k);
                    }
                    u
                }
                None => {
                    let Some(u) = group.integration.forces_x4(&e4, &mut q4) else {
                        break;
                    };
                    u
                }
            };
            add_lanes(&u, &q4, first - e0, first - node0, force, energy);
            first += 4;
        }
        for el in first..end {
            let part = Part::Whole;
            energy[el - e0] = add_element_window(
                model,
                pattern,
                (q, plastic),
                el,
                part,
                node0,
                force,
                values.as_deref_mut(),
            );
        }
    }
}

/// [`add_lanes`] for elements with a yielding layer: each element's lane
/// of the pre-integrated laws (`u`, `q`) gets its yielding layer's
/// corrections ([`crate::element::ElementIntegration::add_plastic`]) before
/// it is added — the sums, in the order, of
/// [`crate::element::ElementIntegration::evaluate_with`] one by one, so the
/// bits do not depend on how the elements were batched or chunked.
fn add_lanes_yielding<const W: usize>(
    model: &Model,
    (q, plastic): (&[f64], History<'_>),
    first: usize,
    (u, lanes): (&[f64; W], &[[f64; W]; 24]),
    (e0, node0): (usize, usize),
    force: &mut [f64],
    energy: &mut [f64],
) {
    for k in 0..W {
        let el = first + k;
        let e = model.element_coordinates(q, el);
        let mut qe: [f64; 24] = std::array::from_fn(|i| lanes[i][k]);
        let correction = model
            .element(el)
            .add_plastic(&e, plastic.element(el), &mut qe, None);
        energy[el - e0] = u[k] + correction;
        let base = NODE_DOFS * (el - node0);
        for (f, v) in force[base..base + 24].iter_mut().zip(&qe) {
            *f += v;
        }
    }
}

/// Coordinate i of elements `first`..`first + W` as lanes: `[i][k]`.
pub(crate) fn lanes<const W: usize>(model: &Model, q: &[f64], first: usize) -> [[f64; W]; 24] {
    let e: [ElementVector; W] = std::array::from_fn(|k| model.element_coordinates(q, first + k));
    std::array::from_fn(|i| std::array::from_fn(|k| e[k][i]))
}

/// A batch's energies into `energy` from index `at` and its forces
/// (`q[i][k]`: coordinate i of the k-th element) into `force` from node
/// `node`, element after element.
fn add_lanes<const W: usize>(
    u: &[f64; W],
    q: &[[f64; W]; 24],
    at: usize,
    node: usize,
    force: &mut [f64],
    energy: &mut [f64],
) {
    for k in 0..W {
        energy[at + k] = u[k];
        let base = NODE_DOFS * (node + k);
        for i in 0..24 {
            force[base + i] += q[i][k];
        }
    }
}

/// The strain energy (J) at `q` without the forces (what the energy
/// balance needs): the elements eight and four at a time where
/// [`assemble_into`] takes them so, at half the work, summed in the same order — its bits.
/// A group whose energies are worth it is split in halves
/// (`per_element_in_halves`): the same bits.
pub fn strain_energy(model: &Model, q: &[f64]) -> f64 {
    strain_energy_with(model, q, History::default())
}

/// [`strain_energy`] with the yielding points' elastic energy from `plastic`.
pub fn strain_energy_with(model: &Model, q: &[f64], plastic: History<'_>) -> f64 {
    let mut energy = vec![0.0; model.n_elements];
    per_element_in_halves(model, &mut energy, |group, els, out| {
        group_energies(model, group, (q, plastic), els, out)
    });
    energy.iter().sum()
}

/// Fills `out` (one entry per element index of the model) group by group
/// with `fill(group, elements, window)`. A group whose element work is
/// worth it (as a force alone is, see [`runs_in_parallel`]) goes in two
/// windows on two threads, the second starting a multiple of eight
/// elements after the group's first, so that every element is batched as
/// in one loop: the same bits on any number of threads.
pub(crate) fn per_element_in_halves<T: Send>(
    model: &Model,
    out: &mut [T],
    fill: impl Fn(&crate::model::ElementGroup, Range<usize>, &mut [T]) + Sync,
) {
    let threads = rayon::current_num_threads();
    for group in &model.groups {
        let elements = group.elements.clone();
        let window = &mut out[elements.clone()];
        let split = elements.start + 8 * (elements.len() / 16);
        if threads > 1 && worth_splitting(elements.len(), FORCE_PER_ELEMENT_US) {
            let (low, high) = window.split_at_mut(split - elements.start);
            let halves = vec![(elements.start..split, low), (split..elements.end, high)];
            crate::linalg::parallel::run_tasks(halves, |(els, out)| fill(group, els, out));
        } else {
            fill(group, elements, window);
        }
    }
}

/// The energies of `group`'s elements `els` into `out` (one per element),
/// eight and four at a time where the kernel allows.
fn group_energies(
    model: &Model,
    group: &crate::model::ElementGroup,
    (q, plastic): (&[f64], History<'_>),
    els: Range<usize>,
    out: &mut [f64],
) {
    let (mut first, end) = (els.start, els.end);
    let at = |el: usize| el - els.start;
    while first + 8 <= end {
        let Some(u) = group.integration.energies_x8(&lanes(model, q, first)) else {
            break;
        };
        out[at(first)..at(first) + 8].copy_from_slice(&u);
        first += 8;
    }
    while first + 4 <= end {
        let Some(u) = group.integration.energies_x4(&lanes(model, q, first)) else {
            break;
        };
        out[at(first)..at(first) + 4].copy_from_slice(&u);
        first += 4;
    }
    for el in first..end {
        let e = model.element_coordinates(q, el);
        let input = plastic.element(el);
        out[at(el)] = (group.integration).evaluate_with(&e, input, &mut [0.0; 24], None);
    }
}

/// Whether [`assemble`] splits the elements into parallel chunks (with more
/// than one rayon thread): when the estimated element work — a force and
/// Jacobian, or a force alone (every modified-Newton iteration) — reaches
/// [`PARALLEL_MIN_WORK_US`]. Results do not depend on it (the chunks equal
/// the serial loop bit for bit); only the speed does.
pub fn runs_in_parallel(model: &Model, with_jacobian: bool) -> bool {
    let element = model.element(0);
    let points = (element.axial.nodes.len() * element.plan.points()) as f64;
    // µs of force + Jacobian per element: pre-integrated
    // SVK 0.75 four at a time, plus ≈ 0.3 per section point.
    let per_element = 0.75 + 0.3 * points;
    let work = if with_jacobian {
        per_element
    } else {
        FORCE_PER_ELEMENT_US
    };
    worth_splitting(model.n_elements, work)
}

/// Whether `elements` elements of `per_element_us` µs of work each are
/// worth a parallel section (at least two chunks, and
/// [`PARALLEL_MIN_WORK_US`]).
fn worth_splitting(elements: usize, per_element_us: f64) -> bool {
    elements >= 2 * CHUNK_ELEMENTS && elements as f64 * per_element_us >= PARALLEL_MIN_WORK_US
}

/// µs of a force alone per element (the eight-wide kernel, pre-integrated
/// SVK): the 1000-element span break's forces (≈ 150 µs) gain on two
/// threads, the 64-element impact's (≈ 10 µs) would not.
const FORCE_PER_ELEMENT_US: f64 = 0.15;

/// A force alone goes in this many chunks (two per thread on two cores),
/// of at least [`FORCE_CHUNK_MIN`] elements: each chunk evaluates its two
/// boundary elements one by one, outside the eight-wide batches, so a force
/// is split into few large chunks; a Jacobian (five times the work per
/// element) into many of [`CHUNK_ELEMENTS`].
const FORCE_CHUNKS: usize = 4;
const FORCE_CHUNK_MIN: usize = 64;

/// Element work (µs) below which the serial loop is used: a section costs
/// its hand-off to the helper thread, and the force rows and Jacobian
/// columns the helper wrote must travel back to the core that goes on with
/// them. The 64-element impact scene (77 µs of Jacobian work) ran 1.2×
/// slower with a parallel Jacobian; 128 elements and more gain.
pub const PARALLEL_MIN_WORK_US: f64 = 100.0;

/// Nodes per chunk: about 8 chunks at 256 elements, so that rayon can
/// balance two cores, and 1 extra element evaluation in 33 (16 per chunk
/// measured the same on 2 threads, with twice the extra work). 33, so that
/// a chunk's 32 interior elements go four at a time through the Jacobian
/// kernel: with 32 nodes, 3 of its 31 went one by one, at 3.3 times a
/// batched element's cost each (perf, the span-break scene's contact phase).
const CHUNK_ELEMENTS: usize = 33;

/// One chunk of the parallel split of the chain (element `e` touches nodes
/// `e` and `e + 1`). Chunk c owns the nodes [c s, (c + 1) s): it writes the
/// force rows and the Jacobian columns of those nodes only (columns are
/// numbered node by node, so they are one window of the values), disjoint
/// from every other chunk's. Its interior elements [c s, (c + 1) s − 1)
/// touch only its nodes. The element between two chunks touches one node
/// of each: both chunks evaluate it and each adds the half that lands on
/// its own node — the chunk before it after its interior, the chunk after
/// it first — which is exactly the serial loop's order for every value.
/// The cost is one extra element evaluation per chunk (1 in 32); the price
/// of the alternatives, measured at 256 elements: a second parallel phase
/// for the boundary elements (another wake-up of the other thread in a
/// Newton step) or buffering them for a serial scatter (1.67× instead of
/// 1.85× for the assembly).
struct Chunk {
    /// The boundary element before the chunk, whose second node is ours.
    lead: Option<usize>,
    interior: Range<usize>,
    /// The boundary element after the chunk, whose first node is ours.
    trail: Option<usize>,
    /// The chunk's nodes.
    nodes: Range<usize>,
}

fn chunks(n: usize, s: usize) -> Vec<Chunk> {
    let starts: Vec<usize> = (0..n.div_ceil(s)).map(|c| c * s).collect();
    chunks_from(n, &starts)
}

/// The chunks of `n` elements whose first nodes are `starts` (increasing,
/// from 0, at least two elements apart).
fn chunks_from(n: usize, starts: &[usize]) -> Vec<Chunk> {
    (starts.iter().enumerate())
        .map(|(c, &start)| {
            let next = starts.get(c + 1).copied();
            let end = next.map_or(n, |b| b - 1);
            Chunk {
                lead: (c > 0).then(|| start - 1),
                interior: start..end,
                trail: next.map(|_| end),
                nodes: start..next.unwrap_or(n + 1),
            }
        })
        .collect()
}

/// A yielding point's share of an element's force, in elastic elements:
/// its strains, trial stress and return map against the eight-wide
/// pre-integrated kernel's ≈ 0.08 µs an element (perf of the plastic
/// span break: 48 elements of 192 points added 70 µs to a 84 µs force).
const PLASTIC_POINT_WEIGHT: f64 = 0.1;

/// The first nodes of `parts` force chunks of about equal work, where
/// yielding layers make some elements cost many times the others (a
/// frame's members, all at the end): `None` without any (`layout` empty),
/// where [`chunks`]' equal sizes are equal work.
fn weighted_starts(layout: &PlasticLayout, parts: usize) -> Option<Vec<usize>> {
    if layout.is_empty() {
        return None;
    }
    let n = layout.elements();
    let weight = |el: usize| 1.0 + PLASTIC_POINT_WEIGHT * layout.points(el) as f64;
    let total: f64 = (0..n).map(weight).sum();
    let mut starts = vec![0];
    let mut done = 0.0;
    for el in 0..n {
        let next = starts.len() as f64 * total / parts as f64;
        let last = *starts.last().expect("starts at 0");
        if starts.len() < parts && done >= next && el >= last + 2 && n >= el + 2 {
            starts.push(el);
        }
        done += weight(el);
    }
    Some(starts)
}

/// Which of an element's two nodes receive its force and Jacobian columns.
#[derive(Clone, Copy, PartialEq)]
enum Part {
    Whole,
    FirstNode,
    SecondNode,
}

impl Part {
    fn local(self) -> Range<usize> {
        match self {
            Part::Whole => 0..24,
            Part::FirstNode => 0..12,
            Part::SecondNode => 12..24,
        }
    }
}

/// The chunks in parallel ([`crate::linalg::parallel::run_tasks`]), each zeroing
/// its window of the Jacobian first
/// (zeroed by the calling thread, the values had to travel to the other
/// core's cache: 1.16× at 256 elements instead of 1.87×).
fn assemble_chunks(
    model: &Model,
    pattern: &Pattern,
    at: (&[f64], History<'_>),
    force: &mut [f64],
    energy: &mut [f64],
    values: Option<&mut [f64]>,
) {
    let weighted = at.1.layout.and_then(|l| weighted_starts(l, FORCE_CHUNKS));
    let chunks = match (&values, weighted) {
        (Some(_), _) => chunks(model.n_elements, CHUNK_ELEMENTS),
        (None, Some(starts)) => chunks_from(model.n_elements, &starts),
        (None, None) => {
            let size = FORCE_CHUNK_MIN.max(model.n_elements.div_ceil(FORCE_CHUNKS));
            chunks(model.n_elements, size)
        }
    };
    let force_w = windows_mut(
        force,
        chunks
            .iter()
            .map(|c| NODE_DOFS * c.nodes.start..NODE_DOFS * c.nodes.end),
    );
    // Energies of the interior and the trailing boundary element.
    let energy_w = windows_mut(
        energy,
        chunks
            .iter()
            .map(|c| c.interior.start..c.trail.map_or(c.interior.end, |t| t + 1)),
    );
    let values_w: Vec<Option<(&mut [f64], usize)>> = match values {
        Some(v) => {
            let ranges: Vec<Range<usize>> = chunks
                .iter()
                .map(|c| pattern.node_values(c.nodes.clone()))
                .collect();
            let starts: Vec<usize> = ranges.iter().map(|r| r.start).collect();
            windows_mut(v, ranges.into_iter())
                .into_iter()
                .zip(starts)
                .map(Some)
                .collect()
        }
        None => chunks.iter().map(|_| None).collect(),
    };
    let tasks: Vec<ChunkTask> = chunks
        .iter()
        .zip(force_w)
        .zip(energy_w)
        .zip(values_w)
        .map(|(((c, f), e), v)| (c, f, e, v))
        .collect();
    crate::linalg::parallel::run_tasks(tasks, |(c, f, e, mut v): ChunkTask| {
        if let Some((v, _)) = v.as_mut() {
            v.fill(0.0);
        }
        let (node0, el0) = (c.nodes.start, c.interior.start);
        // Window-relative: force rows from our first node on.
        if let Some(b) = c.lead {
            add_element_window(
                model,
                pattern,
                at,
                b,
                Part::SecondNode,
                node0,
                f,
                v.as_mut(),
            );
        }
        let interior = c.interior.clone();
        add_whole_elements(model, pattern, at, interior, node0, f, e, v.as_mut());
        if let Some(b) = c.trail {
            let part = Part::FirstNode;
            e[b - el0] = add_element_window(model, pattern, at, b, part, node0, f, v.as_mut());
        }
    });
}

/// A chunk and its windows of the force, the energies and the values.
type ChunkTask<'c, 'w> = (
    &'c Chunk,
    &'w mut [f64],
    &'w mut [f64],
    Option<(&'w mut [f64], usize)>,
);

/// Evaluate element `el` at `q` and add the `part` of its force and
/// Jacobian columns to a force window that starts at node `node0` and to
/// `values` (slots from the given offset on); returns its strain energy.
#[allow(clippy::too_many_arguments)]
fn add_element_window(
    model: &Model,
    pattern: &Pattern,
    (q, plastic): (&[f64], History<'_>),
    el: usize,
    part: Part,
    node0: usize,
    force: &mut [f64],
    values: Option<&mut (&mut [f64], usize)>,
) -> f64 {
    // The gap between two beams is no element.
    if model.is_gap(el) {
        return 0.0;
    }
    let e = model.element_coordinates(q, el);
    let input = plastic.element(el);
    let mut qe = [0.0; 24];
    let local = part.local();
    let u = match values {
        Some((values, offset)) => {
            let mut ke = [0.0; 576];
            let u = (model.element(el)).evaluate_with(&e, input, &mut qe, Some(&mut ke));
            pattern.add_element_columns(values, *offset, el, &ke, local.clone());
            u
        }
        None => model.element(el).evaluate_with(&e, input, &mut qe, None),
    };
    // Row i of element el is coordinate 12 el + i; the window starts at
    // 12 node0, which the lead element (el = node0 − 1, rows 12..24)
    // precedes: subtract last, so no step goes below zero.
    let (base, window) = (NODE_DOFS * el, NODE_DOFS * node0);
    for i in local {
        force[base + i - window] += qe[i];
    }
    u
}

/// Disjoint mutable windows of `data` at the sorted, non-overlapping `ranges`.
fn windows_mut<T>(mut data: &mut [T], ranges: impl Iterator<Item = Range<usize>>) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    let mut consumed = 0;
    for r in ranges {
        let rest = std::mem::take(&mut data);
        let (_, rest) = rest.split_at_mut(r.start - consumed);
        let (window, rest) = rest.split_at_mut(r.end - r.start);
        out.push(window);
        data = rest;
        consumed = r.end;
    }
    out
}

/// The mass matrix values in the pattern's slots.
pub fn mass_values(model: &Model, pattern: &Pattern) -> Vec<f64> {
    let mut v = pattern.zeros();
    for group in &model.groups {
        for el in group.elements.clone() {
            pattern.add_element(&mut v, el, &group.mass);
        }
    }
    v
}

/// Contact forces of the whole wire at (q, v).
#[derive(Clone, Debug, Default)]
pub struct ContactForces {
    /// Generalized contact force, full coordinates (N).
    pub force: Vec<f64>,
    /// The nodes whose rows of `force` this evaluation added to
    /// (increasing, each once); every other row is zero. A wire touches
    /// the rods and members over a few elements of its thousand, so the
    /// force is added to the internal force, and cleared for the next
    /// evaluation, over these rows only: not two passes over the whole
    /// vector in every force evaluation.
    pub force_nodes: Vec<usize>,
    /// Summed over rods.
    pub total: crate::forces::contact::ContactSample,
    /// Resultant contact force (normal + friction) the wire puts on each
    /// rod (N), in the scene's rod order.
    pub rod_forces: Vec<[f64; 3]>,
    /// Resultant contact force (normal + friction) the wire puts on each
    /// frame member it may touch (N), in the scene's member order.
    pub member_forces: Vec<[f64; 3]>,
    /// Deepest penetrating point: (element, point).
    pub deepest: Option<(usize, crate::forces::contact::DeepestPoint)>,
    /// With contact damping, per (element, partner) pair (index
    /// `element × partners + partner`, partners the rods then the members):
    /// `Some(largest rate of penetration, m/s)` where the pair touches,
    /// else `None`. Empty without contact damping.
    pub touching: Vec<Option<f64>>,
    /// The elements whose −∂Q/∂v blocks this evaluation added to (first
    /// to last, ends included), when it was asked for one and any pair
    /// touched: what a caller that zeroes only the written part of that
    /// Jacobian must clear next time.
    pub velocity_elements: Option<(usize, usize)>,
}

impl ContactForces {
    /// Widen [`ContactForces::velocity_elements`] to element `el`.
    fn wrote_velocity_jacobian(&mut self, el: usize) {
        self.velocity_elements = Some(match self.velocity_elements {
            Some((first, last)) => (first.min(el), last.max(el)),
            None => (el, el),
        });
    }

    /// What a wire element's contact with one partner (pair `pair`) adds:
    /// the pair touching (with its approach speed), the sample's totals,
    /// the deepest point, and the element force `qe` at element `el`.
    fn record(
        &mut self,
        pair: usize,
        el: usize,
        sample: &crate::forces::contact::ContactSample,
        deepest: Option<crate::forces::contact::DeepestPoint>,
        qe: &[f64; 24],
    ) {
        if let Some(t) = self.touching.get_mut(pair) {
            *t = Some(sample.approach_speed);
        }
        self.total.accumulate(sample);
        if let Some(dp) = deepest
            && self
                .deepest
                .is_none_or(|(_, d)| dp.penetration > d.penetration)
        {
            self.deepest = Some((el, dp));
        }
        self.add_element_force(el, qe);
    }

    /// `qe` added to element `el`'s rows of the force.
    fn add_element_force(&mut self, el: usize, qe: &[f64; 24]) {
        let base = NODE_DOFS * el;
        for i in 0..24 {
            self.force[base + i] += qe[i];
        }
        self.force_nodes.extend([el, el + 1]);
    }
}

/// Contact at (q, v): the forces, −∂Q/∂q added to `jac_q` and −∂Q/∂v added
/// to `jac_v` (pattern slots).
pub fn assemble_contact(
    model: &Model,
    contact: &crate::forces::contact::ContactEvaluator,
    pattern: &Pattern,
    q: &[f64],
    v: &[f64],
    jac_q: Option<&mut [f64]>,
    jac_v: Option<&mut [f64]>,
) -> ContactForces {
    assemble_contact_reusing(
        model,
        contact,
        pattern,
        q,
        v,
        &[],
        None,
        (jac_q, jac_v, None),
        Default::default(),
    )
}

/// The Jacobians contact adds to: −∂Q/∂q and −∂Q/∂v in pattern slots, and
/// the blocks coupling two beams (wire and member in contact).
pub type ContactJacobians<'a> = (
    Option<&'a mut [f64]>,
    Option<&'a mut [f64]>,
    Option<&'a mut crate::forces::coupling::Coupling>,
);

/// [`assemble_contact`] whose force vector reuses the allocation of
/// `buffer`, a force and its nonzero nodes (see
/// [`ContactForces::force_nodes`]; a Newton loop hands back the previous
/// iteration's, and only those rows are cleared), within the contact
/// events `events` (per (element, partner) pair, the approach speed in m/s
/// at which the pair's contact began, 0 = none; empty = no events: contact
/// damping acts only within an event, see [`crate::solve::dynamics::State`]),
/// visiting only the (element, partner) pairs `pairs` (index `element ×
/// partners + partner`, increasing; see [`contact_candidates`]) or, with
/// `None`, all. The Jacobians go to `jacobians` (the coupling blocks are
/// cleared first).
#[allow(clippy::too_many_arguments)]
pub fn assemble_contact_reusing(
    model: &Model,
    contact: &crate::forces::contact::ContactEvaluator,
    pattern: &Pattern,
    q: &[f64],
    v: &[f64],
    events: &[f64],
    pairs: Option<&[usize]>,
    jacobians: ContactJacobians<'_>,
    buffer: (Vec<f64>, Vec<usize>),
) -> ContactForces {
    let (mut jac_q, mut jac_v, mut coupling) = jacobians;
    if let Some(c) = coupling.as_deref_mut() {
        c.clear();
    }
    let (mut force, mut force_nodes) = buffer;
    if force.len() == q.len() {
        for &n in &force_nodes {
            force[NODE_DOFS * n..NODE_DOFS * (n + 1)].fill(0.0);
        }
    } else {
        force.clear();
        force.resize(q.len(), 0.0);
    }
    force_nodes.clear();
    let mut out = ContactForces {
        force,
        force_nodes,
        rod_forces: vec![[0.0; 3]; contact.rods.len()],
        member_forces: vec![[0.0; 3]; contact.members.len()],
        touching: if contact.damped {
            vec![None; model.n_elements * contact.partners()]
        } else {
            Vec::new()
        },
        ..Default::default()
    };
    let (rods, partners) = (contact.rods.len(), contact.partners());
    let mut beam_out = crate::forces::contact::beam::BeamContactOut::default();
    let mut spheres = None;
    // Element Jacobian workspaces only when a Jacobian is asked for (most
    // calls are residuals: zeroing 9 KB each was memset in perf).
    let mut kq = jac_q.as_ref().map(|_| [0.0; 576]);
    let mut kv = jac_v.as_ref().map(|_| [0.0; 576]);
    // The wire's elements touch the rods (they come first, from 0 on);
    // a grounded member's elements touch their grounds.
    let visit: Box<dyn Iterator<Item = usize>> = match pairs {
        Some(p) => Box::new(p.iter().copied()),
        None => Box::new(
            (0..model.wire().elements.end * partners).chain(grounded_pairs(model, contact)),
        ),
    };
    let wire_end = model.wire().elements.end;
    // The coordinates of the element last visited (pairs come element by element).
    let (mut loaded, mut e, mut ve) = (None, [0.0; 24], [0.0; 24]);
    for pair in visit {
        let (el, ri) = (pair / partners, pair % partners);
        if loaded != Some(el) {
            e = model.element_coordinates(q, el);
            ve = model.element_coordinates(v, el);
            loaded = Some(el);
        }
        if ri >= rods {
            let mi = ri - rods;
            let jac = (jac_q.is_some(), jac_v.is_some());
            beam_out.clear();
            let spheres = spheres.get_or_insert_with(|| MemberSpheres::new(model, contact, q));
            member_contact(
                model,
                contact,
                (q, v),
                (el, &e, &ve),
                (mi, spheres),
                events.get(pair).copied().unwrap_or(0.0),
                jac.0 || jac.1,
                &mut beam_out,
            );
            let sample = beam_out.sample;
            if sample.active == 0 {
                continue;
            }
            out.record(pair, el, &sample, beam_out.deepest, &beam_out.q);
            for c in 0..3 {
                // The member carries the opposite of the force on the wire.
                out.member_forces[mi][c] -= sample.force[c];
            }
            for part in &beam_out.parts {
                out.add_element_force(part.el, &part.q);
            }
            if let Some(values) = jac_q.as_deref_mut() {
                pattern.add_element(values, el, &beam_out.kq);
                for part in &beam_out.parts {
                    pattern.add_element(values, part.el, &part.kq_mm);
                }
            }
            if let Some(values) = jac_v.as_deref_mut() {
                pattern.add_element(values, el, &beam_out.kv);
                out.wrote_velocity_jacobian(el);
                for part in &beam_out.parts {
                    pattern.add_element(values, part.el, &part.kv_mm);
                    out.wrote_velocity_jacobian(part.el);
                }
            }
            if let Some(c) = coupling.as_deref_mut() {
                let v = jac.1;
                for part in &beam_out.parts {
                    c.add(
                        el,
                        part.el,
                        jac.0.then_some(&part.kq_wm),
                        v.then_some(&part.kv_wm),
                    );
                    c.add(
                        part.el,
                        el,
                        jac.0.then_some(&part.kq_mw),
                        v.then_some(&part.kv_mw),
                    );
                }
            }
            continue;
        }
        // kq and kv stay zero between elements: an element away from the
        // rods writes nothing, and they are cleared after one that touched
        // (clearing them for every element was 26 % of the impact run's
        // instructions, callgrind).
        let mut qe = [0.0; 24];
        let (sample, dp) = contact.element_rod(
            model.group(el),
            ri,
            &e,
            &ve,
            events.get(pair).copied().unwrap_or(0.0),
            &mut qe,
            kq.as_mut(),
            kv.as_mut(),
        );
        if sample.active == 0 {
            continue;
        }
        // The deepest point is the wire's (a point along it, for its plots).
        let dp = dp.filter(|_| el < wire_end);
        out.record(pair, el, &sample, dp, &qe);
        for c in 0..3 {
            // The rod carries the opposite of the force on the wire.
            out.rod_forces[ri][c] -= sample.force[c];
        }
        if let (Some(values), Some(k)) = (jac_q.as_deref_mut(), kq.as_mut()) {
            pattern.add_element(values, el, k);
            k.fill(0.0);
        }
        if let (Some(values), Some(k)) = (jac_v.as_deref_mut(), kv.as_mut()) {
            pattern.add_element(values, el, k);
            k.fill(0.0);
            out.wrote_velocity_jacobian(el);
        }
    }
    out.force_nodes.sort_unstable();
    out.force_nodes.dedup();
    out
}

/// Every (element, ground) pair of the members that touch a ground
/// (`element × partners + ground`), increasing.
fn grounded_pairs<'a>(
    model: &'a Model,
    contact: &'a crate::forces::contact::ContactEvaluator,
) -> impl Iterator<Item = usize> + 'a {
    let partners = contact.partners();
    (1..model.beams.len()).flat_map(move |beam| {
        (model.beams[beam].elements.clone())
            .flat_map(move |el| contact.grounds_of(beam).map(move |ri| el * partners + ri))
    })
}

/// Contact of wire element `el` (coordinates and velocities `e`, `ve`)
/// with member `mi` (its elements' centerline spheres `spheres`) at
/// (q, v), into `out`: the member's elements within reach are gathered,
/// then [`crate::forces::contact::beam`] evaluates.
#[allow(clippy::too_many_arguments)]
fn member_contact(
    model: &Model,
    contact: &crate::forces::contact::ContactEvaluator,
    (q, v): (&[f64], &[f64]),
    (el, e, ve): (usize, &[f64; 24], &[f64; 24]),
    (mi, spheres): (usize, &MemberSpheres),
    impact_speed: f64,
    jacobians: bool,
    out: &mut crate::forces::contact::beam::BeamContactOut,
) {
    use crate::forces::contact::beam::{MemberElement, element_member};
    let member = &contact.members[mi];
    let l = contact.geometry[model.group(el)].length;
    let elements: Vec<MemberElement> = spheres
        .within(contact, mi, e, l, 0.0)
        .map(|m| MemberElement {
            el: m,
            e: model.element_coordinates(q, m),
            v: model.element_coordinates(v, m),
            l: contact.geometry[model.group(m)].length,
        })
        .collect();
    let partner = contact.rods.len() + mi;
    element_member(
        contact,
        partner,
        member,
        e,
        ve,
        l,
        &elements,
        impact_speed,
        jacobians,
        out,
    );
}

/// Every member's elements with the spheres holding their centerlines at
/// one configuration, and a sphere holding each whole member: computed
/// once per pass over the wire, not per wire element.
pub(crate) struct MemberSpheres {
    /// Per member: (element, centre, radius) of each element.
    elements: Vec<Vec<(usize, [f64; 3], f64)>>,
    /// Per member: a sphere holding all its elements' spheres.
    whole: Vec<([f64; 3], f64)>,
}

impl MemberSpheres {
    fn new(model: &Model, contact: &crate::forces::contact::ContactEvaluator, q: &[f64]) -> Self {
        use crate::forces::contact::beam::centerline_sphere;
        let elements: Vec<Vec<(usize, [f64; 3], f64)>> = (contact.members.iter())
            .map(|m| {
                (model.beams[m.beam].elements.clone())
                    .map(|el| {
                        let l = contact.geometry[model.group(el)].length;
                        let (c, r) = centerline_sphere(&model.element_coordinates(q, el), l);
                        (el, c, r)
                    })
                    .collect()
            })
            .collect();
        let whole = elements
            .iter()
            .map(|els| {
                let n = els.len().max(1) as f64;
                let c: [f64; 3] =
                    std::array::from_fn(|k| els.iter().map(|e| e.1[k]).sum::<f64>() / n);
                let r = els
                    .iter()
                    .map(|e| crate::math::vec3::norm(crate::math::vec3::sub(e.1, c)) + e.2)
                    .fold(0.0, f64::max);
                (c, r)
            })
            .collect();
        MemberSpheres { elements, whole }
    }

    /// The elements of member `mi` whose centerline can come within the
    /// contact distance (plus `margin`, m) of a wire element's (coordinates
    /// `e`, length `l`).
    fn within<'a>(
        &'a self,
        contact: &crate::forces::contact::ContactEvaluator,
        mi: usize,
        e: &[f64; 24],
        l: f64,
        margin: f64,
    ) -> impl Iterator<Item = usize> + 'a {
        use crate::forces::contact::beam::{centerline_sphere, spheres_within};
        let wire = centerline_sphere(e, l);
        let reach = contact.members[mi].radius + contact.wire_radius + margin;
        let near = spheres_within(wire, self.whole[mi], reach);
        (self.elements[mi].iter())
            .filter(move |(_, c, r)| near && spheres_within(wire, (*c, *r), reach))
            .map(|(el, ..)| *el)
    }
}

/// The (element, partner) pairs (index `element × partners + partner`,
/// increasing; partners are the rods, then the members) that the broad
/// phase lets through at `q` with `margin` (m) more reach: every pair that
/// can touch in a configuration whose centerline is within `margin` of
/// this one ([`centerline_shift`]). A time step computes them once and its
/// Newton iterations visit only them, so the broad phase's cost per
/// iteration does not grow with the elements far from every partner.
pub fn contact_candidates(
    model: &Model,
    contact: &crate::forces::contact::ContactEvaluator,
    q: &[f64],
    margin: f64,
    out: &mut Vec<usize>,
) {
    out.clear();
    let (rods, partners) = (contact.rods.len(), contact.partners());
    let mut spheres = None;
    for el in model.wire().elements.clone() {
        let e = model.element_coordinates(q, el);
        let group = model.group(el);
        if rods > 0 {
            let sphere = contact.centerline_sphere(group, &e);
            for (ri, rod) in contact.rods.iter().enumerate() {
                if contact.may_touch_around(group, rod, &e, sphere, margin) {
                    out.push(el * partners + ri);
                }
            }
        }
        let l = contact.geometry[group].length;
        for mi in 0..contact.members.len() {
            let spheres = spheres.get_or_insert_with(|| MemberSpheres::new(model, contact, q));
            if spheres.within(contact, mi, &e, l, margin).next().is_some() {
                out.push(el * partners + rods + mi);
            }
        }
    }
    // A grounded member's elements and their grounds, after the wire's.
    for beam in 1..model.beams.len() {
        if contact.grounds_of(beam).next().is_none() {
            continue;
        }
        for el in model.beams[beam].elements.clone() {
            let e = model.element_coordinates(q, el);
            let group = model.group(el);
            let sphere = contact.centerline_sphere(group, &e);
            for ri in contact.grounds_of(beam) {
                let ground = &contact.rods[ri];
                if contact.may_touch_around(group, ground, &e, sphere, margin) {
                    out.push(el * partners + ri);
                }
            }
        }
    }
}

/// A bound (m) on how far any point of the wire's centerline moved from `a`
/// to `b` (full coordinates): the cubic Hermite centerline moves by at most
/// max |Δr| + 2 · (4/27) · l · max |Δr_x| (the shape functions of r_x peak at
/// 4/27 of the element length l).
pub fn centerline_shift(model: &Model, a: &[f64], b: &[f64]) -> f64 {
    let l = model
        .groups
        .iter()
        .map(|g| g.integration.length)
        .fold(0.0, f64::max);
    // The largest squares, one root each at the end: the root is
    // monotonic and correctly rounded, so this is the largest root, bit
    // for bit, without a root per node.
    // Node by node as fixed-size arrays, so that no index is checked.
    let n = NODE_DOFS * model.n_nodes();
    let (a, _) = a[..n].as_chunks::<NODE_DOFS>();
    let (b, _) = b[..n].as_chunks::<NODE_DOFS>();
    let (mut dr2, mut drx2) = (0.0f64, 0.0f64);
    for (a, b) in a.iter().zip(b) {
        let d2 = |k: usize| {
            let v = [b[k] - a[k], b[k + 1] - a[k + 1], b[k + 2] - a[k + 2]];
            v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
        };
        dr2 = dr2.max(d2(0));
        drx2 = drx2.max(d2(3));
    }
    dr2.sqrt() + 8.0 / 27.0 * l * drx2.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementIntegration;
    use crate::material::{Material, MaterialModel};
    use crate::model::{Support, SupportKind};
    use crate::section::Section;

    /// A straight wire of `n` elements of `length` (m) along x, clamped at
    /// node 0 (eliminated rows and columns at the first element).
    /// A steel core's and a rubber cover's materials (the cover's
    /// Mooney–Rivlin law works per point, not pre-integrated).
    fn steel_and_rubber() -> (Material, Material) {
        let steel = Material {
            density: 7800.0,
            model: MaterialModel::StVenantKirchhoff {
                youngs_modulus: 2e11,
                poisson_ratio: 0.3,
                bending_factor: 1.0,
            },
            locking: Default::default(),
            yield_stress: None,
        };
        let rubber = Material {
            density: 1100.0,
            model: MaterialModel::MooneyRivlin {
                mu10: 5e5,
                mu01: 1e5,
                penalty: 1e3,
            },
            locking: crate::material::Locking::None,
            yield_stress: None,
        };
        (steel, rubber)
    }

    /// The reference coordinates stretched by 1 % and perturbed (bent).
    fn bent_stretched(model: &Model) -> Vec<f64> {
        (model.reference.iter().enumerate())
            .map(|(i, x)| x * 1.01 + 1e-3 * ((i * 7919 % 31) as f64 / 31.0 - 0.5))
            .collect()
    }

    /// A wire of 300 elastic elements with a yielding tube of 16 after it:
    /// the force's chunks split the work, not the elements, evenly (the
    /// tube's chunk is short), and write the serial loop's bits all the
    /// same, yielding points and all.
    #[test]
    fn force_chunks_weigh_yielding_elements_and_keep_the_serial_bits() {
        use crate::material::beam_plasticity::PlasticState;
        use crate::model::{BeamBuilder, WireBuilder};
        let steel = Material::st_venant_kirchhoff(7850.0, 2.1e11, 0.3, 1.0);
        let s235 = Material::elastic_plastic(7850.0, 2.1e11, 0.3, 2.35e8, 0.0);
        let model = WireBuilder::new(3.0, 300)
            .layer(steel, 0.01)
            .support(0, SupportKind::Clamp)
            .member(
                BeamBuilder::new("tube", 1.0, 16)
                    .placed([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
                    .layer(s235, 0.05)
                    .bore(0.046),
            )
            .support_on("tube", Support::new(0, SupportKind::Clamp))
            .build()
            .unwrap();
        let layout = crate::forces::plastic::PlasticLayout::of(&model);
        let starts = weighted_starts(&layout, FORCE_CHUNKS).expect("a yielding layer");
        assert_eq!(starts.len(), FORCE_CHUNKS, "{starts:?}");
        let tube = model.beams[1].elements.clone();
        let last = *starts.last().unwrap();
        assert!(
            last > tube.start - 100,
            "the tube's chunk is short: {starts:?}"
        );
        assert!(
            weighted_starts(
                &crate::forces::plastic::PlasticLayout::of(&clamped_wire(
                    Section::circular(
                        &[(
                            0.0,
                            0.01,
                            Material::st_venant_kirchhoff(7850.0, 2.1e11, 0.3, 1.0)
                        )],
                        3
                    ),
                    300,
                    0.01
                )),
                FORCE_CHUNKS
            )
            .is_none()
        );
        // Every tube point yielded: their states, not the virgin bound, decide.
        let layout = crate::forces::plastic::PlasticLayout::of(&model);
        let mut yielded = layout.virgin();
        for (i, p) in yielded.iter_mut().enumerate() {
            *p = PlasticState {
                equivalent: 1e-3,
                plastic_strain: [1e-3 * ((i % 7) as f64 - 3.0), 0.0, 0.0],
                ..*p
            };
        }
        let history = History::of(&layout, &yielded, None);
        let pattern = pattern(&model);
        let q = bent_stretched(&model);
        let n = model.n_elements;
        let mut f_chunked = vec![0.0; q.len()];
        let mut u = vec![0.0; n];
        assemble_chunks(
            &model,
            &pattern,
            (&q, history),
            &mut f_chunked,
            &mut u,
            None,
        );
        let mut f_serial = vec![0.0; q.len()];
        for el in 0..n {
            add_element_window(
                &model,
                &pattern,
                (&q, history),
                el,
                Part::Whole,
                0,
                &mut f_serial,
                None,
            );
        }
        assert!(
            f_chunked
                .iter()
                .zip(&f_serial)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        assert!(f_serial[12 * tube.start..].iter().any(|v| *v != 0.0));
    }

    fn clamped_wire(section: Section, n: usize, length: f64) -> Model {
        let element = ElementIntegration::new(length, 3, section);
        let clamp = vec![Support::new(0, SupportKind::Clamp)];
        Model::new(element, n, [0.0; 3], [1.0, 0.0, 0.0], clamp, None, vec![]).unwrap()
    }

    /// The chunked assembly writes the same force, energy and Jacobian bits
    /// as one serial loop over all elements, for element counts that do and
    /// do not fill the last chunk, with a clamped end (eliminated columns)
    /// and a Mooney–Rivlin cover (point work) on a bent, stretched wire;
    /// and `strain_energy` equals the force-only assembly's energy.
    #[test]
    fn chunked_assembly_equals_the_serial_loop() {
        let (steel, rubber) = steel_and_rubber();
        for (n, cover) in [
            (64, steel.clone()),
            (71, rubber),
            (130, steel.clone()),
            (97, steel.clone()),
        ] {
            let section = Section::circular(&[(0.0, 0.01, steel.clone()), (0.01, 0.02, cover)], 3);
            let model = clamped_wire(section, n, 1.0 / n as f64);
            let pattern = pattern(&model);
            let q = bent_stretched(&model);
            // The chunks, called directly (assemble() takes the serial loop
            // on a one-thread pool); the Jacobian is written over, not added to.
            let mut k_chunked = vec![1.0; pattern.nnz()];
            let mut f_chunked = vec![0.0; q.len()];
            let mut u = vec![0.0; n];
            let k = Some(&mut k_chunked[..]);
            assemble_chunks(
                &model,
                &pattern,
                (&q, History::default()),
                &mut f_chunked,
                &mut u,
                k,
            );
            let u_chunked: f64 = u.iter().sum();
            let mut k_serial = pattern.zeros();
            let mut f_serial = vec![0.0; q.len()];
            let mut u_serial = vec![0.0; n];
            let mut all = (&mut k_serial[..], 0);
            for el in 0..n {
                let f = &mut f_serial;
                let whole = Part::Whole;
                u_serial[el] = add_element_window(
                    &model,
                    &pattern,
                    (&q, History::default()),
                    el,
                    whole,
                    0,
                    f,
                    Some(&mut all),
                );
            }
            let same =
                |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same(&f_chunked, &f_serial), "n = {n}: force differs");
            assert!(same(&k_chunked, &k_serial), "n = {n}: Jacobian differs");
            assert_eq!(u_chunked.to_bits(), u_serial.iter().sum::<f64>().to_bits());
            assert!(k_serial.iter().all(|v| v.is_finite()) && u_chunked > 0.0);
            // The force alone, in its own (larger) chunks.
            let mut f_alone = vec![0.0; q.len()];
            assemble_chunks(
                &model,
                &pattern,
                (&q, History::default()),
                &mut f_alone,
                &mut u,
                None,
            );
            assert!(same(&f_alone, &f_serial), "n = {n}: force alone differs");
            assert_eq!(u.iter().sum::<f64>().to_bits(), u_chunked.to_bits());
            // The energy alone (the energy balance's) has the force-only
            // assembly's bits, batched or not (the Mooney–Rivlin cover is not).
            let (_, u_forces) = assemble(&model, &pattern, &q, None);
            assert_eq!(
                strain_energy(&model, &q).to_bits(),
                u_forces.to_bits(),
                "n = {n}: the energy alone differs"
            );
        }
    }

    /// A wire long enough for parallel forces: its strain energy on two
    /// threads (two windows) has the bits of one thread, and the force
    /// alone in four chunks equals the serial loop, with a Mooney–Rivlin
    /// cover (whose batched energies differ from one-by-one ones).
    #[test]
    fn long_wire_energy_and_force_on_two_threads_have_one_threads_bits() {
        let (steel, rubber) = steel_and_rubber();
        let n = 701;
        let section = Section::circular(&[(0.0, 0.01, steel), (0.01, 0.02, rubber)], 3);
        let model = clamped_wire(section, n, 1.0 / n as f64);
        assert!(runs_in_parallel(&model, false));
        let pattern = pattern(&model);
        let q = bent_stretched(&model);
        let run = |threads: usize| {
            crate::linalg::parallel::with_threads(threads, || {
                let (force, u) = assemble(&model, &pattern, &q, None);
                let bits: Vec<u64> = force.iter().map(|f| f.to_bits()).collect();
                (bits, u.to_bits(), strain_energy(&model, &q).to_bits())
            })
        };
        let (one, two) = (run(1), run(2));
        assert!(one == two);
        assert!(f64::from_bits(one.2) > 0.0);
    }
}
