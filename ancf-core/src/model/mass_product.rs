//! M x for the whole wire (the generalized-α residual's M a, every Newton
//! iteration): element by element over the element mass's non-zero node
//! couplings (M_e = m ⊗ I₃, 24 of m's 64 entries are non-zero), four
//! elements per vector register as the force kernel does. Each element's
//! rows are summed in the same order as one at a time, so the baseline path
//! has the bits of the scalar loop.

use std::ops::Range;

use crate::math::simd::{Arith, path};
use crate::model::{ElementGroup, NODE_DOFS};

/// `out` = M x over the wire's element groups, each with its element
/// mass's non-zeros `(i, j, m_ij)` (node vectors i, j ∈ 0..8, sorted by i).
pub(crate) fn mass_times_into(groups: &[ElementGroup], x: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for g in groups {
        product(path(), &g.mass_nonzeros, g.elements.clone(), x, out)
    }
}

crate::simd_dispatch! {
    fn product(nonzeros: &[(usize, usize, f64)], range: Range<usize>, x: &[f64], out: &mut [f64]) = product_with;
}

/// Adds M x of the elements in `range` to `out`.
#[inline(always)]
fn product_with<F: Arith>(
    nonzeros: &[(usize, usize, f64)],
    range: Range<usize>,
    x: &[f64],
    out: &mut [f64],
) {
    let mut el = range.start;
    while el + 4 <= range.end {
        elements::<F, 4>(nonzeros, el, x, out);
        el += 4;
    }
    while el < range.end {
        elements::<F, 1>(nonzeros, el, x, out);
        el += 1;
    }
}

/// Adds M_e x_e of the W elements from `first` to `out`, in element order.
#[inline(always)]
fn elements<F: Arith, const W: usize>(
    nonzeros: &[(usize, usize, f64)],
    first: usize,
    x: &[f64],
    out: &mut [f64],
) {
    let mut xl = [[0.0f64; W]; 24];
    for lane in 0..W {
        let base = NODE_DOFS * (first + lane);
        for (c, v) in xl.iter_mut().enumerate() {
            v[lane] = x[base + c];
        }
    }
    let mut yl = [[0.0f64; W]; 24];
    let mut acc = [[0.0f64; W]; 3];
    let mut row = usize::MAX;
    for &(i, j, m) in nonzeros {
        if i != row {
            if row != usize::MAX {
                yl[3 * row..3 * row + 3].copy_from_slice(&acc);
            }
            acc = [[0.0; W]; 3];
            row = i;
        }
        for k in 0..3 {
            for l in 0..W {
                acc[k][l] = F::mul_add(m, xl[3 * j + k][l], acc[k][l]);
            }
        }
    }
    if row != usize::MAX {
        yl[3 * row..3 * row + 3].copy_from_slice(&acc);
    }
    for lane in 0..W {
        let base = NODE_DOFS * (first + lane);
        for (c, y) in yl.iter().enumerate() {
            out[base + c] += y[lane];
        }
    }
}
