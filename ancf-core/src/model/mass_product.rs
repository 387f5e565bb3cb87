//! M x for the whole wire (the generalized-α residual's M a, every Newton
//! iteration): element by element over the element mass's non-zero node
//! couplings (M_e = m ⊗ I₃, 24 of m's 64 entries are non-zero).
//!
//! For a section symmetric about its centre (every section the crate
//! builds) m couples a node's r and r_x with both nodes' r and r_x, r_y
//! only with r_y and r_z only with r_z. A node's twelve rows then take four
//! twelve-wide multiply-adds per element node, of the tiles
//! [r, r, r_y, r_z] and [r_x, r_x, 0, 0] (`paired`): a node's coordinates
//! stay where they are in memory. Any other mass runs `product`, four elements
//! per vector register with the coordinates transposed into lanes (six
//! times the instructions). Both sum every row over its non-zeros in
//! ascending column order, the zero coefficients adding exact zeros, so
//! they give the same bits.

use std::ops::Range;

use crate::math::simd::{Arith, path};
use crate::model::{ElementGroup, NODE_DOFS};

/// `out` = M x over the wire's element groups, each with its element
/// mass's non-zeros `(i, j, m_ij)` (node vectors i, j ∈ 0..8, sorted by i).
/// A paired group of [`PARALLEL_MIN_ELEMENTS`] or more runs in two halves
/// on two threads (with more than one rayon thread), with the same bits.
pub(crate) fn mass_times_into(groups: &[ElementGroup], x: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    let threads = rayon::current_num_threads();
    for g in groups {
        match &g.paired_mass {
            Some(m) if threads > 1 && g.elements.len() >= PARALLEL_MIN_ELEMENTS => {
                paired_in_halves(m, g.elements.clone(), x, out)
            }
            Some(m) => paired(path(), m, None, g.elements.clone(), None, x, out, 0),
            None => product(path(), &g.mass_nonzeros, g.elements.clone(), x, out),
        }
    }
}

/// From this many elements a group's M x (≈ 25 µs serially at 1000
/// elements, every Newton iteration) is split over two threads.
pub(crate) const PARALLEL_MIN_ELEMENTS: usize = 512;

/// The paired product in two halves of the group's nodes, split at the
/// middle element s: the first half takes its elements and element s − 1's
/// rows on node s − 1, the second element s − 1's rows on node s and then
/// its elements; every row is summed in the serial loop's order.
fn paired_in_halves(mass: &PairedMass, elements: Range<usize>, x: &[f64], out: &mut [f64]) {
    let s = elements.start + elements.len() / 2;
    let (low, high) = out.split_at_mut(NODE_DOFS * s);
    let halves = [
        (None, elements.start..s - 1, Some(s - 1), low, 0),
        (Some(s - 1), s..elements.end, None, high, s),
    ];
    let path = path();
    crate::linalg::parallel::run_tasks(Vec::from(halves), |(lead, range, trail, out, node0)| {
        paired(path, mass, lead, range, trail, x, out, node0)
    });
}

crate::simd_dispatch! {
    fn product(nonzeros: &[(usize, usize, f64)], range: Range<usize>, x: &[f64], out: &mut [f64]) = product_with;
}

crate::simd_dispatch! {
    #[allow(clippy::too_many_arguments)]
    fn paired(mass: &PairedMass, lead: Option<usize>, range: Range<usize>, trail: Option<usize>, x: &[f64], out: &mut [f64], node0: usize) = paired_with;
}

/// A node's twelve coordinates.
type NodeVector = [f64; NODE_DOFS];

/// The element mass as the coefficients of `paired`'s four multiply-adds
/// per element node: `coefficients[a][s]` multiplies tile s (0: node 0's
/// [r, r, r_y, r_z], 1: its [r_x, r_x, 0, 0], 2 and 3: node 1's) into node
/// a's rows — the order of ascending columns for every row.
#[derive(Clone, Debug)]
pub(crate) struct PairedMass {
    coefficients: [[NodeVector; 4]; 2],
}

impl PairedMass {
    /// The coefficients, or `None` when the mass couples anything else
    /// (r_y with r, r_y with r_z: a section off its centre).
    pub(crate) fn new(nonzeros: &[(usize, usize, f64)]) -> Option<Self> {
        let mut coefficients = [[[0.0; NODE_DOFS]; 4]; 2];
        for &(i, j, m) in nonzeros {
            let (a, t) = (i / 4, i % 4);
            let (b, u) = (j / 4, j % 4);
            // The tile holding column j in row type t's lanes.
            let tile = match (t, u) {
                (0 | 1, 0) | (2, 2) | (3, 3) => 0,
                (0 | 1, 1) => 1,
                _ => return None,
            };
            coefficients[a][2 * b + tile][3 * t..3 * t + 3].fill(m);
        }
        Some(PairedMass { coefficients })
    }
}

/// Node n's two tiles: [r, r, r_y, r_z] and [r_x, r_x, 0, 0].
#[inline(always)]
fn tiles(x: &[f64], n: usize) -> [NodeVector; 2] {
    let v: &NodeVector = x[NODE_DOFS * n..NODE_DOFS * (n + 1)]
        .try_into()
        .expect("twelve coordinates a node");
    let mut first = *v;
    first[3..6].copy_from_slice(&v[0..3]);
    let mut second = [0.0; NODE_DOFS];
    second[0..3].copy_from_slice(&v[3..6]);
    second[3..6].copy_from_slice(&v[3..6]);
    [first, second]
}

/// Adds M x of the elements in `range` to `out`, element by element, after
/// the rows of element `lead` on its second node and before those of
/// element `trail` on its first; `out` starts at node `node0`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn paired_with<F: Arith>(
    mass: &PairedMass,
    lead: Option<usize>,
    range: Range<usize>,
    trail: Option<usize>,
    x: &[f64],
    out: &mut [f64],
    node0: usize,
) {
    if let Some(el) = lead {
        let (left, right) = (tiles(x, el), tiles(x, el + 1));
        let y = node_rows::<F>(&mass.coefficients[1], [&left, &right]);
        add_rows(out, el + 1 - node0, y);
    }
    if !range.is_empty() {
        let mut left = tiles(x, range.start);
        for el in range {
            let right = tiles(x, el + 1);
            for (a, c) in mass.coefficients.iter().enumerate() {
                add_rows(out, el + a - node0, node_rows::<F>(c, [&left, &right]));
            }
            left = right;
        }
    }
    if let Some(el) = trail {
        let (left, right) = (tiles(x, el), tiles(x, el + 1));
        let y = node_rows::<F>(&mass.coefficients[0], [&left, &right]);
        add_rows(out, el - node0, y);
    }
}

/// `out`'s rows of node `node` += y.
#[inline(always)]
fn add_rows(out: &mut [f64], node: usize, y: NodeVector) {
    let row = &mut out[NODE_DOFS * node..NODE_DOFS * (node + 1)];
    for (o, y) in row.iter_mut().zip(y) {
        *o += y;
    }
}

/// An element's rows on one of its nodes, from its coefficients for that
/// node and the tiles of its two nodes.
#[inline(always)]
fn node_rows<F: Arith>(
    coefficients: &[NodeVector; 4],
    [left, right]: [&[NodeVector; 2]; 2],
) -> NodeVector {
    let sources = [&left[0], &left[1], &right[0], &right[1]];
    let mut y = [0.0; NODE_DOFS];
    for (c, t) in coefficients.iter().zip(sources) {
        for l in 0..NODE_DOFS {
            y[l] = F::mul_add(c[l], t[l], y[l]);
        }
    }
    y
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementIntegration;
    use crate::material::Material;
    use crate::math::simd::SimdPath;
    use crate::model::{Model, WireBuilder};
    use crate::section::Section;

    /// The paired form gives the lane form's bits on every path this CPU
    /// has, for a one- and a two-layer circle and a rectangle.
    #[test]
    fn paired_product_equals_the_lane_product_bit_for_bit() {
        let steel = Material::st_venant_kirchhoff(7850.0, 2e11, 0.3, 1.0);
        let alu = Material::st_venant_kirchhoff(2700.0, 7e10, 0.33, 0.2);
        let rectangle =
            ElementIntegration::new(0.2, 3, Section::rectangular(0.02, 0.01, steel.clone(), 3));
        let models = [
            WireBuilder::new(2.0, 7).layer(steel.clone(), 0.01).build(),
            WireBuilder::new(2.0, 9)
                .layer(steel, 0.005)
                .layer(alu, 0.014)
                .build(),
            Model::new(
                rectangle,
                6,
                [0.0; 3],
                [1.0, 0.0, 0.0],
                vec![],
                None,
                vec![],
            ),
        ];
        for model in models {
            let model = model.expect("valid wire");
            let g = &model.groups[0];
            let paired_mass = g.paired_mass.as_ref().expect("a symmetric section");
            let n = model.reference.len();
            let x: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) as f64).sin() * 1e3).collect();
            for p in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
                let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
                paired(
                    p,
                    paired_mass,
                    None,
                    g.elements.clone(),
                    None,
                    &x,
                    &mut a,
                    0,
                );
                product(p, &g.mass_nonzeros, g.elements.clone(), &x, &mut b);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&a), bits(&b), "{}", p.name());
            }
        }
    }

    /// A mass coupling r_y with r (a section off its centre) is not paired.
    #[test]
    fn an_off_centre_mass_takes_the_lane_form() {
        assert!(PairedMass::new(&[(0, 0, 1.0), (2, 2, 1.0), (3, 3, 1.0)]).is_some());
        assert!(PairedMass::new(&[(0, 0, 1.0), (2, 0, 0.1)]).is_none());
        assert!(PairedMass::new(&[(2, 3, 0.1)]).is_none());
    }

    /// The product in two halves (the parallel split) gives the serial
    /// loop's bits, for an even and an odd number of elements.
    #[test]
    fn halves_equal_the_serial_product_bit_for_bit() {
        let steel = Material::st_venant_kirchhoff(7850.0, 2e11, 0.3, 1.0);
        for n in [8, 13] {
            let model = WireBuilder::new(2.0, n)
                .layer(steel.clone(), 0.01)
                .build()
                .unwrap();
            let g = &model.groups[0];
            let mass = g.paired_mass.as_ref().expect("a symmetric section");
            let x: Vec<f64> = (0..model.reference.len())
                .map(|i| ((i * 7 + 3) as f64).sin() * 1e3)
                .collect();
            let mut serial = vec![0.0; x.len()];
            paired(
                path(),
                mass,
                None,
                g.elements.clone(),
                None,
                &x,
                &mut serial,
                0,
            );
            let mut halves = vec![0.0; x.len()];
            crate::linalg::parallel::with_threads(2, || {
                paired_in_halves(mass, g.elements.clone(), &x, &mut halves)
            });
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&serial), bits(&halves), "{n} elements");
            assert!(serial.iter().all(|v| *v != 0.0));
        }
    }
}
