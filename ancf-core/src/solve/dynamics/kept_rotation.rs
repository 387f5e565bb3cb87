//! Modified Newton's kept matrix turned with the nodes.
//!
//! The elastic energy does not change when a body turns rigidly, so its
//! Hessian turns with it: K(R q) = T K(q) Tᵀ, with T rotating each node's
//! four vectors (r, r_x, r_y, r_z) by R, and the mass matrix (m ⊗ I₃)
//! commutes with T. So the whole Newton matrix A = (1 − α_m) M + c_k K
//! turns too, and since T is orthogonal, (T A Tᵀ)⁻¹ = T A⁻¹ Tᵀ: a kept
//! factorization serves a turned configuration through two rotations of
//! the vectors it solves for, at the cost of a vector pass each.
//!
//! A wire does not turn rigidly, but where it swings and whips its
//! elements mostly turn: the axial stiffness EA/l, tens of times the
//! inertia term of a 0.1 ms step, then points the wrong way in a kept
//! matrix after a step or two, and the iterations contract slowly
//! (BENCHMARKS.md, "why the kept matrix goes stale"). Turning each node's
//! part of the kept matrix by that node's own rotation since the matrix
//! was formed — the per-node "stiffness warping" of Müller et al., *Stable
//! real-time deformations*, SCA 2002, applied here to a factorization —
//! keeps that direction right: on the span break it removes most of the
//! refreshes. It is exact for one rotation of all nodes; where two
//! neighbouring nodes turned differently, their coupling blocks (the mass's
//! too) are turned by both, an error of the size of that difference,
//! which the refresh of a slowly contracting matrix bounds as before.
//!
//! A node's rotation is the one that takes its frame where the matrix was
//! formed to its frame now. A frame is the chord between the node's two
//! neighbours on its beam (its one neighbour at a beam's end) and the part
//! of r_y normal to it, made orthonormal (Gram–Schmidt), and their cross
//! product. The chord rather than r_x: the unresolved axial and bending
//! modes of short elements make a node's gradient jitter from step to
//! step, and turning the kept matrix by that jitter spoils it (a 1024-
//! element pendulum took 4 iterations a step instead of 3 with r_x; the
//! chord over two elements keeps 3). A vector of a node that the model
//! holds in part (a roller) stays unturned: T is then still orthogonal on
//! the unknowns.

use crate::linalg::parallel::run_tasks;
use crate::math::simd::{Arith, path};
use crate::math::vec3::dot;
use crate::model::{Model, NODE_DOFS};

/// A rotation or an orthonormal frame: `m[i]` is its i-th column (a
/// frame's i-th unit vector).
type Columns = [[f64; 3]; 3];

/// No rotation (and the frame of a node that has none).
const IDENTITY: Columns = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// The frames where the kept matrix was formed, the rotations to the
/// current iterate, and where the turned vectors lie among the unknowns.
#[derive(Clone, Debug, Default)]
pub(super) struct KeptRotation {
    /// Each node's frame where the kept matrix was formed (empty before
    /// the first factorization).
    formed: Vec<Columns>,
    /// Each node's rotation from there to the last iterate `turn` saw.
    now: Vec<Columns>,
    /// Each node's two neighbours on its beam, whose chord gives its frame
    /// (itself for a missing one, at a beam's end).
    neighbours: Vec<(usize, usize)>,
    /// The turned vectors, node by node: (node, its first turned vector's
    /// first unknown, how many vectors follow it among the unknowns). A
    /// vector is turned when its three coordinates are all unknowns.
    runs: Vec<(usize, usize, usize)>,
}

impl KeptRotation {
    pub(super) fn new(model: &Model) -> Self {
        let mut runs: Vec<(usize, usize, usize)> = Vec::new();
        for c in (0..model.dof_map.len()).step_by(3) {
            let [Some(u), Some(_), Some(_)] = model.dof_map[c..c + 3] else {
                continue;
            };
            let node = c / NODE_DOFS;
            match runs.last_mut() {
                Some((n, first, count)) if *n == node && *first + 3 * *count == u => *count += 1,
                _ => runs.push((node, u, 1)),
            }
        }
        let nodes = model.dof_map.len() / NODE_DOFS;
        let on_beam = |el: usize| el + 1 < nodes && !model.is_gap(el);
        let neighbours = (0..nodes)
            .map(|k| {
                let before = if k > 0 && on_beam(k - 1) { k - 1 } else { k };
                let after = if on_beam(k) { k + 1 } else { k };
                (before, after)
            })
            .collect();
        KeptRotation {
            formed: Vec::new(),
            now: Vec::new(),
            neighbours,
            runs,
        }
    }

    /// Record the nodes' frames at `q` (full coordinates), where the kept
    /// matrix was formed. Not checkpointed: a resumed run forms its matrix
    /// again where the checkpoint says, and these frames with it.
    pub(super) fn form(&mut self, q: &[f64]) {
        let nodes = q.as_chunks::<NODE_DOFS>().0;
        self.formed.clear();
        self.formed.resize(nodes.len(), IDENTITY);
        frames_on(path(), nodes, &self.neighbours, None, &mut self.formed);
    }

    /// Each node's rotation from where the kept matrix was formed to `q`;
    /// false (and nothing to turn) before a matrix was formed.
    pub(super) fn turn(&mut self, q: &[f64]) -> bool {
        if self.formed.is_empty() {
            return false;
        }
        let nodes = q.as_chunks::<NODE_DOFS>().0;
        self.now.clear();
        self.now.resize(nodes.len(), IDENTITY);
        let formed = Some(&self.formed[..]);
        frames_on(path(), nodes, &self.neighbours, formed, &mut self.now);
        true
    }

    /// x ← Tᵀ x: the unknowns' vectors turned back to where the kept matrix
    /// was formed.
    pub(super) fn to_formed(&self, x: &mut [f64]) {
        self.turn_vectors(x, |r| [r[0], r[1], r[2]]);
    }

    /// x ← T x: the inverse of [`KeptRotation::to_formed`].
    pub(super) fn to_current(&self, x: &mut [f64]) {
        self.turn_vectors(x, |r| std::array::from_fn(|i| [r[0][i], r[1][i], r[2][i]]));
    }

    /// Every turned vector of x times a matrix of its node's rotation (the
    /// rows that `rows` makes of it); from [`PARALLEL_MIN_UNKNOWNS`] on, in
    /// two halves on two threads (the same bits: vector by vector).
    fn turn_vectors(&self, x: &mut [f64], rows: impl Fn(&Columns) -> Columns + Sync) {
        let turn = |runs: &[(usize, usize, usize)], x: &mut [f64], offset: usize| {
            for &(node, first, count) in runs {
                let rows = rows(&self.now[node]);
                let first = first - offset;
                for v in x[first..first + 3 * count].as_chunks_mut::<3>().0 {
                    *v = turn_by(&rows, *v);
                }
            }
        };
        let serial = x.len() < PARALLEL_MIN_UNKNOWNS || self.runs.len() < 2;
        if serial || rayon::current_num_threads() == 1 {
            return turn(&self.runs, x, 0);
        }
        let (low, high) = self.runs.split_at(self.runs.len() / 2);
        let offset = high[0].1;
        let (x_low, x_high) = x.split_at_mut(offset);
        run_tasks(
            vec![(low, x_low, 0), (high, x_high, offset)],
            |(runs, x, offset)| turn(runs, x, offset),
        );
    }
}

/// From this many unknowns (≈ 680 elements) the vectors are turned in two
/// halves on two threads, as the integrator's midpoint.
const PARALLEL_MIN_UNKNOWNS: usize = 8192;

/// The matrix with rows `rows` times v.
#[inline(always)]
fn turn_by(rows: &Columns, v: [f64; 3]) -> [f64; 3] {
    rows.map(|row| dot(row, v))
}

crate::simd_dispatch! {
    fn frames_on(
        nodes: &[[f64; NODE_DOFS]],
        neighbours: &[(usize, usize)],
        formed: Option<&[Columns]>,
        out: &mut [Columns],
    ) = frames;
}

/// Every node's frame (see [`frame_lanes`]), four nodes at a time; with
/// `formed`, the rotation R = E Eₒᵀ from each node's frame Eₒ there to
/// its frame E here instead.
// `F` unused: `simd_dispatch!` instantiates the loop per path.
#[allow(clippy::extra_unused_type_parameters)]
#[inline(always)]
fn frames<F: Arith>(
    nodes: &[[f64; NODE_DOFS]],
    neighbours: &[(usize, usize)],
    formed: Option<&[Columns]>,
    out: &mut [Columns],
) {
    let rotation = |now: &Columns, formed: &Columns| -> Columns {
        // Column j is Σₖ E[k] Eₒ[k][j].
        std::array::from_fn(|j| {
            std::array::from_fn(|i| {
                now[0][i] * formed[0][j] + now[1][i] * formed[1][j] + now[2][i] * formed[2][j]
            })
        })
    };
    let (chunks, rest) = out.as_chunks_mut::<4>();
    for (c, out) in chunks.iter_mut().enumerate() {
        let ks: [usize; 4] = std::array::from_fn(|l| 4 * c + l);
        let f = frame_lanes(nodes, ks, neighbours);
        *out = match formed {
            Some(formed) => std::array::from_fn(|l| rotation(&f[l], &formed[ks[l]])),
            None => f,
        };
    }
    let done = 4 * chunks.len();
    for (l, out) in rest.iter_mut().enumerate() {
        let k = done + l;
        let [f] = frame_lanes(nodes, [k], neighbours);
        *out = match formed {
            Some(formed) => rotation(&f, &formed[k]),
            None => f,
        };
    }
}

/// Node k's frame (see [`frame_lanes`]), for the tests.
#[cfg(test)]
fn frame(nodes: &[[f64; NODE_DOFS]], k: usize, neighbours: (usize, usize)) -> Columns {
    let mut all = vec![(k, k); nodes.len()];
    all[k] = neighbours;
    frame_lanes(nodes, [k], &all)[0]
}

/// Three coordinates of L nodes, one lane per node.
type Lanes<const L: usize> = [[f64; L]; 3];

/// Lanes with coordinate c of lane l from `f(c, l)`.
#[inline(always)]
fn lanes<const L: usize>(f: impl Fn(usize, usize) -> f64) -> Lanes<L> {
    std::array::from_fn(|c| std::array::from_fn(|l| f(c, l)))
}

/// a · b lane by lane.
#[inline(always)]
fn dot_lanes<const L: usize>(a: &Lanes<L>, b: &Lanes<L>) -> [f64; L] {
    std::array::from_fn(|l| a[0][l] * b[0][l] + a[1][l] * b[1][l] + a[2][l] * b[2][l])
}

/// The orthonormal frames of nodes `ks`, one lane per node (the same
/// operations in every lane, which the vector units run side by side):
/// node k's chord from its neighbour `before` to `after`, the part of its
/// r_y normal to it, and their cross product — the identity when chord
/// and r_y are parallel, zero or not finite, or the node has no
/// neighbour: no rotation is then taken.
#[inline(always)]
fn frame_lanes<const L: usize>(
    nodes: &[[f64; NODE_DOFS]],
    ks: [usize; L],
    neighbours: &[(usize, usize)],
) -> [Columns; L] {
    let chord: Lanes<L> = lanes(|c, l| {
        let (before, after) = neighbours[ks[l]];
        nodes[after][c] - nodes[before][c]
    });
    let ry: Lanes<L> = lanes(|c, l| nodes[ks[l]][6 + c]);
    let lx = dot_lanes(&chord, &chord).map(f64::sqrt);
    let e1: Lanes<L> = lanes(|c, l| chord[c][l] * (1.0 / lx[l]));
    let p = dot_lanes(&ry, &e1);
    let y: Lanes<L> = lanes(|c, l| ry[c][l] - p[l] * e1[c][l]);
    let ly = dot_lanes(&y, &y).map(f64::sqrt);
    let e2: Lanes<L> = lanes(|c, l| y[c][l] * (1.0 / ly[l]));
    let e3: Lanes<L> = lanes(|c, l| {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        e1[a][l] * e2[b][l] - e1[b][l] * e2[a][l]
    });
    std::array::from_fn(|l| {
        let f = [e1, e2, e3].map(|e| [e[0][l], e[1][l], e[2][l]]);
        if f.as_flattened().iter().all(|x| x.is_finite()) && ly[l] > 1e-12 * lx[l] {
            f
        } else {
            IDENTITY
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rotation about `axis` (unit) by `angle`, as columns.
    fn rotation(axis: [f64; 3], angle: f64) -> Columns {
        let (s, c) = angle.sin_cos();
        let [x, y, z] = axis;
        let m = [
            [
                c + x * x * (1.0 - c),
                x * y * (1.0 - c) - z * s,
                x * z * (1.0 - c) + y * s,
            ],
            [
                y * x * (1.0 - c) + z * s,
                c + y * y * (1.0 - c),
                y * z * (1.0 - c) - x * s,
            ],
            [
                z * x * (1.0 - c) - y * s,
                z * y * (1.0 - c) + x * s,
                c + z * z * (1.0 - c),
            ],
        ];
        // Rows above; columns here.
        std::array::from_fn(|j| std::array::from_fn(|i| m[i][j]))
    }

    fn apply(r: &Columns, v: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|k| r[k][i] * v[k]).sum())
    }

    /// Two nodes of a slightly stretched, sheared and bent element.
    fn nodes() -> [[f64; NODE_DOFS]; 2] {
        [
            [
                0.3, -0.2, 1.0, 1.01, 0.02, -0.01, 0.03, 0.98, 0.01, 0.0, -0.02, 1.0,
            ],
            [
                0.8, -0.15, 1.02, 0.99, 0.05, 0.02, -0.02, 1.01, 0.03, 0.01, 0.0, 0.99,
            ],
        ]
    }

    /// Each vector of `node` turned by `r`, the position also moved by `t`.
    fn moved(node: &[f64; NODE_DOFS], r: &Columns, t: [f64; 3]) -> [f64; NODE_DOFS] {
        let mut out = [0.0; NODE_DOFS];
        for v in 0..4 {
            let x = apply(r, [node[3 * v], node[3 * v + 1], node[3 * v + 2]]);
            out[3 * v..3 * v + 3].copy_from_slice(&x);
        }
        for i in 0..3 {
            out[i] += t[i];
        }
        out
    }

    #[test]
    fn rigidly_moved_nodes_give_their_rotation() {
        let r = rotation([1.0 / 3f64.sqrt(); 3], 0.7);
        let a = nodes();
        let b = a.map(|n| moved(&n, &r, [2.0, -1.0, 0.5]));
        let mut k = KeptRotation {
            formed: Vec::new(),
            now: Vec::new(),
            neighbours: vec![(0, 1), (0, 1)],
            runs: vec![(0, 0, 4), (1, 12, 4)],
        };
        k.form(a.as_flattened());
        assert!(k.turn(b.as_flattened()));
        for now in &k.now {
            for (got, want) in now.as_flattened().iter().zip(r.as_flattened()) {
                assert!((got - want).abs() < 1e-14, "{now:?} against {r:?}");
            }
        }
        // Tᵀ takes the moved nodes' vectors back, T turns them again (the
        // positions' translation aside).
        let mut x = b.as_flattened().to_vec();
        for n in 0..2 {
            for i in 0..3 {
                x[NODE_DOFS * n + i] -= [2.0, -1.0, 0.5][i];
            }
        }
        let moved_back = x.clone();
        k.to_formed(&mut x);
        for (got, want) in x.iter().zip(a.as_flattened()) {
            assert!((got - want).abs() < 1e-14);
        }
        k.to_current(&mut x);
        for (got, want) in x.iter().zip(&moved_back) {
            assert!((got - want).abs() < 1e-14);
        }
    }

    /// The reason for the rotation: a kept matrix turned by T solves the
    /// turned system exactly, (T A Tᵀ)⁻¹ b = T A⁻¹ Tᵀ b, for any A.
    #[test]
    fn turning_the_solve_solves_the_turned_matrix() {
        let r = rotation([0.0, 0.6, 0.8], -1.1);
        let n = NODE_DOFS;
        // A symmetric positive definite A on one node.
        let a: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                let off = 0.1 / (1.0 + (i + 2 * j) as f64) + 0.1 / (1.0 + (j + 2 * i) as f64);
                if i == j { 4.0 + i as f64 } else { off }
            })
            .collect();
        let t: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                if i / 3 == j / 3 { r[j % 3][i % 3] } else { 0.0 }
            })
            .collect();
        let mul = |x: &[f64], y: &[f64], tx: bool, ty: bool| -> Vec<f64> {
            (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    (0..n)
                        .map(|l| {
                            let a = if tx { x[l * n + i] } else { x[i * n + l] };
                            let b = if ty { y[j * n + l] } else { y[l * n + j] };
                            a * b
                        })
                        .sum()
                })
                .collect()
        };
        let turned = mul(&mul(&t, &a, false, false), &t, false, true);
        let solve = |m: &[f64], b: &[f64]| -> Vec<f64> {
            let m = nalgebra::DMatrix::from_row_slice(n, n, m);
            let b = nalgebra::DVector::from_column_slice(b);
            m.lu().solve(&b).unwrap().as_slice().to_vec()
        };
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let direct = solve(&turned, &b);
        let k = KeptRotation {
            formed: vec![IDENTITY],
            now: vec![r],
            neighbours: vec![(0, 0)],
            runs: vec![(0, 0, 4)],
        };
        let mut x = b.clone();
        k.to_formed(&mut x);
        let mut x = solve(&a, &x);
        k.to_current(&mut x);
        for (got, want) in x.iter().zip(&direct) {
            assert!(
                (got - want).abs() < 1e-13 * want.abs().max(1.0),
                "{x:?} against {direct:?}"
            );
        }
    }

    /// Frames formed four nodes at a time, one per lane, are each node's
    /// own frame and rotation bit for bit, on every path this CPU has (the
    /// lanes only run side by side what one node at a time computes).
    #[test]
    fn frames_in_lanes_equal_frames_one_by_one() {
        let nodes: Vec<[f64; NODE_DOFS]> = (0..9)
            .map(|k| {
                std::array::from_fn(|i| {
                    ((k * NODE_DOFS + i) as f64 * 0.731).sin() + (i % 4 == 0) as u8 as f64
                })
            })
            .collect();
        let neighbours: Vec<(usize, usize)> = (0..9)
            .map(|k: usize| (k.saturating_sub(1), (k + 1).min(8)))
            .collect();
        let formed: Vec<Columns> = (0..9)
            .map(|k| rotation([0.0, 0.6, 0.8], 0.1 * k as f64))
            .collect();
        for path in crate::math::simd::SimdPath::ALL
            .into_iter()
            .filter(|p| p.supported())
        {
            let mut frames = vec![IDENTITY; 9];
            frames_on(path, &nodes, &neighbours, None, &mut frames);
            let mut turned = vec![IDENTITY; 9];
            frames_on(path, &nodes, &neighbours, Some(&formed), &mut turned);
            for k in 0..9 {
                let f = frame(&nodes, k, neighbours[k]);
                assert_ne!(f, IDENTITY);
                assert_eq!(frames[k], f, "{} node {k}", path.name());
                let r: Columns = std::array::from_fn(|j| {
                    std::array::from_fn(|i| (0..3).map(|m| f[m][i] * formed[k][m][j]).sum())
                });
                assert_eq!(turned[k], r, "{} node {k}", path.name());
            }
        }
    }

    /// A vector long enough to be turned in two halves on two threads is
    /// turned as vector by vector on one: the same bits.
    #[test]
    fn halves_turn_as_one_pass() {
        let nodes = PARALLEL_MIN_UNKNOWNS / NODE_DOFS + 3;
        let k = KeptRotation {
            formed: vec![IDENTITY; nodes],
            now: (0..nodes)
                .map(|n| rotation([0.6, 0.0, 0.8], 0.01 * n as f64))
                .collect(),
            neighbours: vec![(0, 0); nodes],
            runs: (0..nodes).map(|n| (n, NODE_DOFS * n, 4)).collect(),
        };
        let x: Vec<f64> = (0..NODE_DOFS * nodes)
            .map(|i| (i as f64 * 0.37).sin())
            .collect();
        let one_by_one = |back: bool| -> Vec<f64> {
            let mut y = x.clone();
            for (n, v) in y.as_chunks_mut::<3>().0.iter_mut().enumerate() {
                let r = &k.now[n / 4];
                let rows = if back {
                    *r
                } else {
                    std::array::from_fn(|i| [r[0][i], r[1][i], r[2][i]])
                };
                *v = turn_by(&rows, *v);
            }
            y
        };
        let (mut formed, mut current) = (x.clone(), x.clone());
        k.to_formed(&mut formed);
        k.to_current(&mut current);
        assert_eq!(formed, one_by_one(true));
        assert_eq!(current, one_by_one(false));
    }

    #[test]
    fn a_node_without_neighbours_or_with_r_y_along_its_chord_takes_no_rotation() {
        let n = nodes();
        assert_eq!(frame(&n, 0, (0, 0)), IDENTITY);
        let mut p = n;
        // r_y of node 0 along the chord from node 0 to node 1.
        let chord: [f64; 3] = std::array::from_fn(|i| 2.0 * (n[1][i] - n[0][i]));
        p[0][6..9].copy_from_slice(&chord);
        assert_eq!(frame(&p, 0, (0, 1)), IDENTITY);
        assert_ne!(frame(&n, 0, (0, 1)), IDENTITY);
    }
}
