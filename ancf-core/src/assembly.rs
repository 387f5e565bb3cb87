//! Global assembly, split as in fenris/diffsol: the sparsity pattern and
//! the map from element entries to value slots are computed once per model
//! ([`Pattern::new`]); each Newton iteration only refills values in place
//! ([`assemble`]).

use crate::model::{Model, NODE_DOFS};
use faer::sparse::SymbolicSparseColMat;
use std::ops::Range;

/// Marks an element entry that touches an eliminated coordinate.
const NO_SLOT: u32 = u32::MAX;

/// The global matrix pattern over the unknowns (both triangles stored).
#[derive(Clone, Debug)]
pub struct Pattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// For element `el`, local entry (i, j): `slots[el * 576 + i * 24 + j]`
    /// is the index into the value array, or `NO_SLOT`.
    slots: Vec<u32>,
    /// For node k (0 … n_elements + 1): the first value slot of its columns
    /// (unknowns are numbered node by node, so a node range's columns are
    /// one contiguous window of the values).
    node_value_start: Vec<usize>,
}

impl Pattern {
    pub fn new(model: &Model) -> Self {
        let n = model.n_unknowns;
        // Column lists: for every element, the free coordinates it couples.
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for el in 0..model.n_elements {
            let free: Vec<usize> = (0..24)
                .filter_map(|i| model.dof_map[NODE_DOFS * el + i])
                .collect();
            for &c in &free {
                cols[c].extend_from_slice(&free);
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let mut slots = vec![NO_SLOT; model.n_elements * 576];
        for el in 0..model.n_elements {
            for i in 0..24 {
                let Some(r) = model.dof_map[NODE_DOFS * el + i] else {
                    continue;
                };
                for j in 0..24 {
                    let Some(c) = model.dof_map[NODE_DOFS * el + j] else {
                        continue;
                    };
                    let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                    let pos = rows.binary_search(&r).expect("entry in pattern");
                    slots[el * 576 + i * 24 + j] = (col_ptr[c] + pos) as u32;
                }
            }
        }
        // First unknown at or after each node's first coordinate; unknowns
        // increase with the coordinate (Model::dof_map).
        let n_nodes = model.dof_map.len() / NODE_DOFS;
        let node_value_start = (0..=n_nodes)
            .map(|k| {
                let first = model.dof_map[NODE_DOFS * k..]
                    .iter()
                    .find_map(|u| *u)
                    .unwrap_or(n);
                col_ptr[first]
            })
            .collect();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Pattern {
            symbolic,
            slots,
            node_value_start,
        }
    }

    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.nnz()]
    }

    /// y += scale · A x for the matrix with these `values` (x, y on the unknowns).
    pub fn mul_add(&self, values: &[f64], x: &[f64], scale: f64, y: &mut [f64]) {
        let col_ptr = self.symbolic.col_ptr();
        let rows = self.symbolic.row_idx();
        for (j, xj) in x.iter().enumerate() {
            for idx in col_ptr[j]..col_ptr[j + 1] {
                y[rows[idx]] += scale * values[idx] * xj;
            }
        }
    }

    /// The value slots of the columns of nodes `nodes`.
    pub fn node_values(&self, nodes: Range<usize>) -> Range<usize> {
        self.node_value_start[nodes.start]..self.node_value_start[nodes.end]
    }

    /// Add an element matrix (row-major 24×24) of element `el` to a window
    /// of the values that starts at slot `offset`.
    fn add_element_at(&self, values: &mut [f64], offset: usize, el: usize, m: &[f64; 576]) {
        let slots = &self.slots[el * 576..(el + 1) * 576];
        for (s, v) in slots.iter().zip(m.iter()) {
            if *s != NO_SLOT {
                values[*s as usize - offset] += v;
            }
        }
    }

    /// Add an element matrix (row-major 24×24) of element `el`, times `scale`.
    pub fn add_element(&self, values: &mut [f64], el: usize, m: &[f64; 576], scale: f64) {
        let slots = &self.slots[el * 576..(el + 1) * 576];
        for (s, v) in slots.iter().zip(m.iter()) {
            if *s != NO_SLOT {
                values[*s as usize] += scale * v;
            }
        }
    }
}

/// Elastic force (full coordinates), optionally its Jacobian (values in the
/// pattern's slots, written over `jacobian`'s), and the strain energy.
///
/// From [`PARALLEL_MIN_ELEMENTS`] elements on, the elements are split into
/// chunks that rayon evaluates in parallel, each writing straight into its
/// own windows of the force and of the Jacobian's values (see [`Chunks`]).
/// The split depends on the model only, never on the thread count, so every
/// value receives its contributions in the same order with any number of
/// threads: the same bits with 1 or 2 threads (tests/pendulum.rs). Each
/// chunk also zeroes its own window of the Jacobian first: zeroed by the
/// calling thread, the values had to travel to the other core's cache, and
/// 2 threads assembled 256 elements only 1.16× faster than one.
pub fn assemble(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    jacobian: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    let mut force = vec![0.0; q.len()];
    // Per-element energies, summed in element order at the end (the serial
    // loop's order, whatever the split).
    let mut energy = vec![0.0; model.n_elements];
    let n = model.n_elements;
    if n < PARALLEL_MIN_ELEMENTS {
        let values = jacobian.map(|v| {
            v.fill(0.0);
            (v, 0)
        });
        assemble_elements(model, pattern, q, 0..n, &mut force, &mut energy, values);
    } else {
        let chunks = Chunks::new(n);
        let mut values = jacobian;
        // The interiors' windows cover every value: they are zeroed there.
        let phases = [(chunks.interiors(), true), (chunks.boundaries(), false)];
        for (tasks, zero) in phases {
            let values = values.as_deref_mut();
            assemble_phase(
                model,
                pattern,
                q,
                &tasks,
                zero,
                &mut force,
                &mut energy,
                values,
            );
        }
    }
    (force, energy.iter().sum())
}

/// Below this many elements the serial loop is used (one chunk's work).
pub const PARALLEL_MIN_ELEMENTS: usize = 64;

/// Elements per chunk: 16 chunks at 256 elements, so that rayon can balance
/// two busy cores; the boundary elements (1 in 16) run as a second phase.
const CHUNK_ELEMENTS: usize = 16;

/// The parallel split of a chain of elements. Element `e` touches nodes `e`
/// and `e + 1`. Chunk c holds elements [c s, (c + 1) s − 1): it touches
/// nodes [c s, (c + 1) s), disjoint from every other chunk's, so chunks
/// write disjoint windows of the force (node-major) and of the matrix
/// values (column-major, columns numbered node by node). The element
/// between two chunks, (c + 1) s − 1, is a boundary element: boundaries
/// touch disjoint node pairs too and run as a second parallel phase.
struct Chunks {
    n: usize,
    s: usize,
}

impl Chunks {
    fn new(n: usize) -> Self {
        Chunks {
            n,
            s: CHUNK_ELEMENTS,
        }
    }

    fn count(&self) -> usize {
        self.n.div_ceil(self.s)
    }

    /// Element ranges of the chunks' interiors.
    fn interiors(&self) -> Vec<Range<usize>> {
        (0..self.count())
            .map(|c| {
                let start = c * self.s;
                let end = ((c + 1) * self.s - 1).min(self.n);
                // The last chunk has no boundary after it.
                let end = if c + 1 == self.count() { self.n } else { end };
                start..end
            })
            .collect()
    }

    /// The boundary elements, one range each.
    fn boundaries(&self) -> Vec<Range<usize>> {
        (0..self.count() - 1)
            .map(|c| (c + 1) * self.s - 1..(c + 1) * self.s)
            .collect()
    }
}

/// Assemble the element ranges `tasks` (touching pairwise disjoint nodes)
/// in parallel, each into its windows of `force`, `energy` and `values`
/// (zeroing its window of `values` first when `zero`).
#[allow(clippy::too_many_arguments)]
fn assemble_phase(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    tasks: &[Range<usize>],
    zero: bool,
    force: &mut [f64],
    energy: &mut [f64],
    values: Option<&mut [f64]>,
) {
    use rayon::prelude::*;
    // Nodes touched by elements [a, b): [a, b + 1).
    let nodes = |r: &Range<usize>| r.start..r.end + 1;
    let force_w = windows_mut(
        force,
        tasks.iter().map(|r| {
            let nd = nodes(r);
            NODE_DOFS * nd.start..NODE_DOFS * nd.end
        }),
    );
    let energy_w = windows_mut(energy, tasks.iter().cloned());
    let values_w: Vec<Option<(&mut [f64], usize)>> = match values {
        Some(v) => {
            let ranges: Vec<Range<usize>> = tasks
                .iter()
                .map(|r| pattern.node_values(nodes(r)))
                .collect();
            let starts = ranges.iter().map(|r| r.start);
            windows_mut(v, ranges.iter().cloned())
                .into_iter()
                .zip(starts.collect::<Vec<_>>())
                .map(Some)
                .collect()
        }
        None => tasks.iter().map(|_| None).collect(),
    };
    tasks
        .iter()
        .zip(force_w)
        .zip(energy_w)
        .zip(values_w)
        .collect::<Vec<_>>()
        .into_par_iter()
        .for_each(|(((r, f), e), mut v)| {
            if let (true, Some((v, _))) = (zero, v.as_mut()) {
                v.fill(0.0);
            }
            assemble_elements(model, pattern, q, r.clone(), f, e, v);
        });
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

/// The element loop: elements `elements`, force into `force` (full
/// coordinates from node `elements.start` on), energies into `energy`
/// (from element `elements.start` on), Jacobian entries into `values`
/// (the pattern's value slots from the given offset on).
fn assemble_elements(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    elements: Range<usize>,
    force: &mut [f64],
    energy: &mut [f64],
    mut values: Option<(&mut [f64], usize)>,
) {
    let mut ke = [0.0; 576];
    let first = elements.start;
    for el in elements {
        let e = model.element_coordinates(q, el);
        let mut qe = [0.0; 24];
        energy[el - first] = match values.as_mut() {
            Some((values, offset)) => {
                ke.fill(0.0);
                let u = model.element.evaluate(&e, &mut qe, Some(&mut ke));
                pattern.add_element_at(values, *offset, el, &ke);
                u
            }
            None => model.element.evaluate(&e, &mut qe, None),
        };
        let base = NODE_DOFS * (el - first);
        for i in 0..24 {
            force[base + i] += qe[i];
        }
    }
}

/// The mass matrix values in the pattern's slots.
pub fn mass_values(model: &Model, pattern: &Pattern) -> Vec<f64> {
    let mut v = pattern.zeros();
    for el in 0..model.n_elements {
        pattern.add_element(&mut v, el, &model.element_mass, 1.0);
    }
    v
}

/// Contact forces of the whole wire at (q, v).
#[derive(Clone, Debug, Default)]
pub struct ContactForces {
    /// Generalized contact force, full coordinates (N).
    pub force: Vec<f64>,
    /// Summed over rods.
    pub total: crate::contact::ContactSample,
    /// Normal force on each rod (N), in the scene's rod order.
    pub rod_forces: Vec<f64>,
    /// Deepest penetrating test point: (element, point).
    pub deepest: Option<(usize, crate::contact::DeepestPoint)>,
}

/// Contact at (q, v): the forces, −∂Q/∂q added to `jac_q` and −∂Q/∂v added
/// to `jac_v` (pattern slots).
pub fn assemble_contact(
    model: &Model,
    contact: &crate::contact::Contact,
    pattern: &Pattern,
    q: &[f64],
    v: &[f64],
    mut jac_q: Option<&mut [f64]>,
    mut jac_v: Option<&mut [f64]>,
) -> ContactForces {
    let mut out = ContactForces {
        force: vec![0.0; q.len()],
        rod_forces: vec![0.0; contact.rods.len()],
        ..Default::default()
    };
    let mut kq = [0.0; 576];
    let mut kv = [0.0; 576];
    for el in 0..model.n_elements {
        let e = model.element_coordinates(q, el);
        let ve = model.element_coordinates(v, el);
        for ri in 0..contact.rods.len() {
            // kq and kv stay zero between elements: an element away from the
            // rods writes nothing, and they are cleared after one that touched
            // (clearing them for every element was 26 % of the impact run's
            // instructions, callgrind).
            let mut qe = [0.0; 24];
            let (sample, dp) = contact.element_rod(
                ri,
                &e,
                &ve,
                &mut qe,
                jac_q.is_some().then_some(&mut kq),
                jac_v.is_some().then_some(&mut kv),
            );
            if sample.active == 0 {
                continue;
            }
            out.total.accumulate(&sample);
            out.rod_forces[ri] += sample.normal_force;
            if let Some(dp) = dp
                && out
                    .deepest
                    .is_none_or(|(_, d)| dp.penetration > d.penetration)
            {
                out.deepest = Some((el, crate::contact::DeepestPoint { rod: ri, ..dp }));
            }
            let base = NODE_DOFS * el;
            for i in 0..24 {
                out.force[base + i] += qe[i];
            }
            if let Some(values) = jac_q.as_deref_mut() {
                pattern.add_element(values, el, &kq, 1.0);
            }
            if let Some(values) = jac_v.as_deref_mut() {
                pattern.add_element(values, el, &kv, 1.0);
            }
            kq.fill(0.0);
            kv.fill(0.0);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementIntegration;
    use crate::material::{Material, MaterialModel};
    use crate::model::{Support, SupportKind};
    use crate::section::Section;

    /// The chunked assembly writes the same force, energy and Jacobian bits
    /// as one serial loop over all elements, for element counts that do and
    /// do not fill the last chunk, with a clamped end (eliminated columns)
    /// and a Mooney–Rivlin cover (point work) on a bent, stretched wire.
    #[test]
    fn chunked_assembly_equals_the_serial_loop() {
        let steel = Material {
            density: 7800.0,
            model: MaterialModel::StVenantKirchhoff {
                youngs_modulus: 2e11,
                poisson_ratio: 0.3,
                bending_factor: 1.0,
            },
            locking: Default::default(),
        };
        let rubber = Material {
            density: 1100.0,
            model: MaterialModel::MooneyRivlin {
                mu10: 5e5,
                mu01: 1e5,
                penalty: 1e3,
            },
            locking: crate::material::Locking::None,
        };
        for (n, cover) in [(64, steel.clone()), (71, rubber), (130, steel.clone())] {
            let section = Section::circular(&[(0.0, 0.01, steel.clone()), (0.01, 0.02, cover)], 3);
            let model = Model::new(
                ElementIntegration::new(1.0 / n as f64, 3, section),
                n,
                [0.0; 3],
                [1.0, 0.0, 0.0],
                vec![Support::new(0, SupportKind::Clamp)],
                None,
                vec![],
            )
            .unwrap();
            let pattern = Pattern::new(&model);
            let q: Vec<f64> = model
                .reference
                .iter()
                .enumerate()
                .map(|(i, x)| x * 1.01 + 1e-3 * ((i * 7919 % 31) as f64 / 31.0 - 0.5))
                .collect();
            // Written over, not added to.
            let mut k_chunked = vec![1.0; pattern.nnz()];
            let (f_chunked, u_chunked) = assemble(&model, &pattern, &q, Some(&mut k_chunked));
            let mut k_serial = pattern.zeros();
            let mut f_serial = vec![0.0; q.len()];
            let mut u_serial = vec![0.0; n];
            let all = Some((&mut k_serial[..], 0));
            assemble_elements(
                &model,
                &pattern,
                &q,
                0..n,
                &mut f_serial,
                &mut u_serial,
                all,
            );
            let same =
                |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same(&f_chunked, &f_serial), "n = {n}: force differs");
            assert!(same(&k_chunked, &k_serial), "n = {n}: Jacobian differs");
            assert_eq!(u_chunked.to_bits(), u_serial.iter().sum::<f64>().to_bits());
            assert!(k_serial.iter().all(|v| v.is_finite()) && u_chunked > 0.0);
        }
    }
}
