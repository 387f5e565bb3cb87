//! The sparsity pattern of a Newton matrix over the unknowns, and the map
//! from element entries to value slots, computed once (fenris's *pattern
//! once, values every iteration*): assembly adds element matrices into the
//! value array without searching.

use faer::sparse::SymbolicSparseColMat;
use std::ops::Range;

/// Coordinates per node: r, r_x, r_y, r_z.
const NODE_DOFS: usize = 12;

/// Marks an element entry that touches an eliminated coordinate.
const NO_SLOT: u32 = u32::MAX;

/// The global matrix pattern over the unknowns (both triangles stored).
#[derive(Clone, Debug)]
pub struct Pattern {
    /// The symbolic (structure-only) matrix the solvers factor.
    pub symbolic: SymbolicSparseColMat<usize>,
    /// For element `el`, local entry (i, j): `slots[el * 576 + i * 24 + j]`
    /// is the index into the value array, or `NO_SLOT`.
    slots: Vec<u32>,
    /// For element `el`, when every entry has a slot and column j's 24
    /// entries are 24 consecutive slots (rows are sorted and the element's
    /// two nodes adjacent: every element but those at a support): the
    /// first slot of each column. Its matrix is then added column by column
    /// to contiguous values, without a slot lookup per entry (the lookups
    /// and scattered stores were most of the Jacobian's assembly, perf).
    columns: Vec<Option<[u32; 24]>>,
    /// For node k (0 … n_elements + 1): the first value slot of its columns
    /// (unknowns are numbered node by node, so a node range's columns are
    /// one contiguous window of the values).
    node_value_start: Vec<usize>,
}

impl Pattern {
    /// The pattern of a wire's Newton matrix: element `el` couples the 24
    /// coordinates from `NODE_DOFS · el` on (its two nodes); `dof_map` gives
    /// each coordinate's unknown (`None`: held), numbered in coordinate
    /// order, `n_unknowns` of them.
    pub fn new(dof_map: &[Option<usize>], n_unknowns: usize, n_elements: usize) -> Self {
        let n = n_unknowns;
        // Column lists: for every element, the free coordinates it couples.
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for el in 0..n_elements {
            let free: Vec<usize> = (0..24)
                .filter_map(|i| dof_map[NODE_DOFS * el + i])
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
        let mut slots = vec![NO_SLOT; n_elements * 576];
        for el in 0..n_elements {
            for i in 0..24 {
                let Some(r) = dof_map[NODE_DOFS * el + i] else {
                    continue;
                };
                for j in 0..24 {
                    let Some(c) = dof_map[NODE_DOFS * el + j] else {
                        continue;
                    };
                    let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                    let pos = rows.binary_search(&r).expect("entry in pattern");
                    slots[el * 576 + i * 24 + j] = (col_ptr[c] + pos) as u32;
                }
            }
        }
        let columns = slots
            .chunks_exact(576)
            .map(|el| {
                let first: [u32; 24] = std::array::from_fn(|j| el[j]);
                let contiguous = (0..24).all(|i| {
                    (0..24).all(|j| first[j] != NO_SLOT && el[i * 24 + j] == first[j] + i as u32)
                });
                contiguous.then_some(first)
            })
            .collect();
        // First unknown at or after each node's first coordinate; unknowns
        // increase with the coordinate (Model::dof_map).
        let n_nodes = dof_map.len() / NODE_DOFS;
        let node_value_start = (0..=n_nodes)
            .map(|k| {
                let first = dof_map[NODE_DOFS * k..]
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
            columns,
            node_value_start,
        }
    }

    /// The value slot of entry (`row`, `col`) of the unknowns, `None` when
    /// it is not in the pattern (two unknowns no element couples).
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let col_ptr = self.symbolic.col_ptr();
        let rows = &self.symbolic.row_idx()[col_ptr[col]..col_ptr[col + 1]];
        rows.binary_search(&row).ok().map(|p| col_ptr[col] + p)
    }

    /// Structural non-zeros.
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// A zero value for every slot.
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

    /// Add the columns `cols` (local, 0…24) of an element matrix (row-major
    /// 24×24) of element `el` to a window of the values that starts at slot
    /// `offset`.
    pub(crate) fn add_element_columns(
        &self,
        values: &mut [f64],
        offset: usize,
        el: usize,
        m: &[f64; 576],
        cols: Range<usize>,
    ) {
        let slots = &self.slots[el * 576..(el + 1) * 576];
        if cols == (0..24) {
            match &self.columns[el] {
                Some(first) => add_to_columns(values, offset, first, |e| m[e]),
                None => add_to_slots(values, offset, slots, m.iter().copied()),
            }
        } else {
            for (row_slots, row) in slots.chunks_exact(24).zip(m.chunks_exact(24)) {
                let row = row[cols.clone()].iter().copied();
                add_to_slots(values, offset, &row_slots[cols.clone()], row);
            }
        }
    }

    /// Add lane `lane` of four element matrices stored entry-major
    /// (`m[i * 24 + j][lane]`, as `jacobians_x4` writes them) as the matrix
    /// of element `el`, to a window of the values that starts at slot
    /// `offset`: [`Self::add_element_columns`] over all columns.
    pub(crate) fn add_lane_columns(
        &self,
        values: &mut [f64],
        offset: usize,
        el: usize,
        m: &[[f64; 4]; 576],
        lane: usize,
    ) {
        match &self.columns[el] {
            Some(first) => add_to_columns(values, offset, first, |e| m[e][lane]),
            None => {
                let slots = &self.slots[el * 576..(el + 1) * 576];
                add_to_slots(values, offset, slots, m.iter().map(|v| v[lane]));
            }
        }
    }

    /// Add an element matrix (row-major 24×24) of element `el`.
    pub fn add_element(&self, values: &mut [f64], el: usize, m: &[f64; 576]) {
        self.add_element_columns(values, 0, el, m, 0..24);
    }
}

/// Add element entries to their value slots (`NO_SLOT`: an entry on an
/// eliminated coordinate, skipped) in a window of the values that starts
/// at slot `offset`.
fn add_to_slots(values: &mut [f64], offset: usize, slots: &[u32], m: impl Iterator<Item = f64>) {
    for (s, v) in slots.iter().zip(m) {
        if *s != NO_SLOT {
            values[*s as usize - offset] += v;
        }
    }
}

/// Add the element entries `m(i * 24 + j)` column by column to the 24
/// consecutive values from slot `first[j]` (see `Pattern::columns`), in a
/// window of the values that starts at slot `offset`.
#[inline(always)]
fn add_to_columns(values: &mut [f64], offset: usize, first: &[u32; 24], m: impl Fn(usize) -> f64) {
    for (j, &s) in first.iter().enumerate() {
        let column = &mut values[s as usize - offset..][..24];
        for (i, v) in column.iter_mut().enumerate() {
            *v += m(i * 24 + j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Element matrices added column by column (`Pattern::columns`) land
    /// in the slots the entry-by-entry map gives, bit for bit; an element
    /// at a clamp (entries without a slot) takes the map.
    #[test]
    fn column_adds_equal_the_slot_map() {
        // Six elements, node 0 clamped along x: all but the axial r_x held.
        let n_elements = 6;
        let mut dof_map = vec![None; NODE_DOFS * (n_elements + 1)];
        let mut n_unknowns = 0;
        for (c, u) in dof_map.iter_mut().enumerate() {
            if c == 3 || c >= NODE_DOFS {
                *u = Some(n_unknowns);
                n_unknowns += 1;
            }
        }
        let pattern = Pattern::new(&dof_map, n_unknowns, n_elements);
        assert!(pattern.columns[0].is_none());
        assert!(pattern.columns[1..].iter().all(|c| c.is_some()));
        let (mut by_columns, mut by_slots) = (pattern.zeros(), pattern.zeros());
        for el in 0..n_elements {
            let m: [f64; 576] = std::array::from_fn(|e| ((e * 7919 + el * 31) as f64).sin());
            pattern.add_element(&mut by_columns, el, &m);
            let slots = &pattern.slots[el * 576..(el + 1) * 576];
            add_to_slots(&mut by_slots, 0, slots, m.iter().copied());
        }
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&by_columns), bits(&by_slots));
        assert!(by_columns.iter().all(|v| *v != 0.0));
    }
}
