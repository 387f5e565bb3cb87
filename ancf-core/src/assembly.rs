//! Global assembly, split as in fenris/diffsol: the sparsity pattern and
//! the map from element entries to value slots are computed once per model
//! ([`Pattern::new`]); each Newton iteration only refills values in place
//! ([`assemble`]).

use crate::model::{Model, NODE_DOFS};
use faer::sparse::SymbolicSparseColMat;

/// Marks an element entry that touches an eliminated coordinate.
const NO_SLOT: u32 = u32::MAX;

/// The global matrix pattern over the unknowns (both triangles stored).
#[derive(Clone, Debug)]
pub struct Pattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// For element `el`, local entry (i, j): `slots[el * 576 + i * 24 + j]`
    /// is the index into the value array, or `NO_SLOT`.
    slots: Vec<u32>,
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
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Pattern { symbolic, slots }
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
/// pattern's slots, added to `jacobian`), and the strain energy.
pub fn assemble(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    jacobian: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    if uses_parallel_assembly(model) && rayon::current_num_threads() > 1 {
        assemble_parallel(model, pattern, q, jacobian)
    } else {
        assemble_serial(model, pattern, q, jacobian)
    }
}

/// Below this many elements the serial loop is faster than splitting work.
pub const PARALLEL_MIN_ELEMENTS: usize = 64;

/// Whether elements are evaluated in parallel: only when they carry point
/// work (Mooney–Rivlin layers, non-linear centerline laws). A fully
/// pre-integrated element (1.2 µs for force and Jacobian) is cheaper than
/// the parallel path's per-element buffer and serial scatter: with it, two
/// threads were slower than one (0.73–0.97× at 256 elements, 0.80 → 0.97 s
/// for 8 full-Newton steps at 4096; BENCHMARKS.md, issue 7).
pub fn uses_parallel_assembly(model: &Model) -> bool {
    let plan = &model.element.plan;
    model.n_elements >= PARALLEL_MIN_ELEMENTS && (plan.points() > 0)
}

fn assemble_serial(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    mut jacobian: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    let mut force = vec![0.0; q.len()];
    let mut energy = 0.0;
    let mut ke = [0.0; 576];
    for el in 0..model.n_elements {
        let e = model.element_coordinates(q, el);
        let mut qe = [0.0; 24];
        match jacobian.as_deref_mut() {
            Some(values) => {
                ke.fill(0.0);
                energy += model.element.evaluate(&e, &mut qe, Some(&mut ke));
                pattern.add_element(values, el, &ke, 1.0);
            }
            None => energy += model.element.evaluate(&e, &mut qe, None),
        }
        let base = NODE_DOFS * el;
        for i in 0..24 {
            force[base + i] += qe[i];
        }
    }
    (force, energy)
}

/// One element's strain energy, force and (when asked) Jacobian.
type ElementContribution = (f64, [f64; 24], Option<Box<[f64; 576]>>);

/// Elements evaluated in parallel (rayon), then scattered serially in
/// element order: the sums happen in the same order as in the serial loop,
/// so the result has the same bits with any number of threads.
fn assemble_parallel(
    model: &Model,
    pattern: &Pattern,
    q: &[f64],
    jacobian: Option<&mut [f64]>,
) -> (Vec<f64>, f64) {
    use rayon::prelude::*;
    let want_k = jacobian.is_some();
    let per_element: Vec<ElementContribution> = (0..model.n_elements)
        .into_par_iter()
        .map(|el| {
            let e = model.element_coordinates(q, el);
            let mut qe = [0.0; 24];
            if want_k {
                let mut ke = Box::new([0.0; 576]);
                let u = model.element.evaluate(&e, &mut qe, Some(&mut ke));
                (u, qe, Some(ke))
            } else {
                (model.element.evaluate(&e, &mut qe, None), qe, None)
            }
        })
        .collect();
    let mut force = vec![0.0; q.len()];
    let mut energy = 0.0;
    let mut jacobian = jacobian;
    for (el, (u, qe, ke)) in per_element.iter().enumerate() {
        energy += u;
        let base = NODE_DOFS * el;
        for i in 0..24 {
            force[base + i] += qe[i];
        }
        if let (Some(values), Some(ke)) = (jacobian.as_deref_mut(), ke) {
            pattern.add_element(values, el, ke, 1.0);
        }
    }
    (force, energy)
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
