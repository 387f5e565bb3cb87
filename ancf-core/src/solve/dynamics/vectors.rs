//! The integrator's vector loops: the generalized-α midpoint (dispatched
//! per SIMD path, plain arithmetic on every path), and norms.

use super::AlphaParameters;
use crate::linalg::parallel::run_tasks;
use crate::math::simd::{Arith, Plain, SimdPath, dot};
use std::ops::Range;

crate::simd_dispatch! {
    fn midpoint_on(params: &AlphaParameters, h: f64, state: [&[f64]; 4], out: [&mut [f64]; 3]) = midpoint_with;
}

/// From this many coordinates (≈ 680 elements) the midpoint is formed in
/// two halves on two threads (with more than one rayon thread): ≈ 35 µs
/// serially on the 1000-element span break, every Newton iteration. The
/// same bits either way (entry by entry).
const PARALLEL_MIN_COORDINATES: usize = 8192;

/// The generalized-α midpoint (see `midpoint_with`) on `path`.
pub(super) fn midpoint(
    path: SimdPath,
    params: &AlphaParameters,
    h: f64,
    state: [&[f64]; 4],
    [qm, vm, am]: [&mut [f64]; 3],
) {
    let n = qm.len();
    if n < PARALLEL_MIN_COORDINATES || rayon::current_num_threads() == 1 {
        return midpoint_on(path, params, h, state, [qm, vm, am]);
    }
    let half = n / 2;
    let [(q0, q1), (v0, v1), (a0, a1), (b0, b1)] = state.map(|v| v.split_at(half));
    let (low, high) = ([q0, v0, a0, b0], [q1, v1, a1, b1]);
    let (qm_low, qm_high) = qm.split_at_mut(half);
    let (vm_low, vm_high) = vm.split_at_mut(half);
    let (am_low, am_high) = am.split_at_mut(half);
    let halves = vec![
        (low, [qm_low, vm_low, am_low]),
        (high, [qm_high, vm_high, am_high]),
    ];
    run_tasks(halves, |(state, out)| {
        midpoint_on(path, params, h, state, out)
    });
}

/// The generalized-α midpoint (q_m, v_m, a_m) of the step from
/// `state` = (q, v, a) ending with acceleration a₁, over all coordinates.
/// Plain multiplications and additions on every path (no fused ones, so
/// the bits do not depend on the path); the AVX paths gain the wider
/// registers. Zipped, without indices, so that the loop vectorizes
/// (indexed, its bounds checks and spills made it ≈ 5 % of the span-break
/// scene).
// `F` unused: `simd_dispatch!` instantiates the loop per path, and this
// one computes with plain arithmetic on every path.
#[allow(clippy::extra_unused_type_parameters)]
#[inline(always)]
fn midpoint_with<F: Arith>(
    params: &AlphaParameters,
    h: f64,
    [q, v, a, a1]: [&[f64]; 4],
    [qm, vm, am]: [&mut [f64]; 3],
) {
    let (alpha_m, alpha_f) = (params.alpha_m, params.alpha_f);
    let state = q.iter().zip(v).zip(a).zip(a1);
    let midpoint = qm.iter_mut().zip(vm.iter_mut()).zip(am.iter_mut());
    for (((qm, vm), am), (((&q, &v), &a), &a1)) in midpoint.zip(state) {
        let (q1, v1) = params.newmark(h, q, v, a, a1);
        *qm = (1.0 - alpha_f) * q1 + alpha_f * q;
        *vm = (1.0 - alpha_f) * v1 + alpha_f * v;
        *am = (1.0 - alpha_m) * a1 + alpha_m * a;
    }
}

/// The residual M a + Q − F on the free coordinates `runs` (unknowns are
/// numbered run after run), written over `r`, with ‖M a‖² and ‖Q‖² over
/// the same entries: one pass instead of a pass for R and one per norm.
/// Each run's squares are summed as [`sum_of_squares`] sums that run's
/// slice (four partial sums from the run's start, the tail apart), so the
/// sums have the bits of the separate passes.
pub(super) fn balance(
    runs: &[Range<usize>],
    [ma, q, ext]: [&[f64]; 3],
    r: &mut Vec<f64>,
) -> (f64, f64) {
    let unknowns = runs.iter().map(|run| run.len()).sum();
    r.resize(unknowns, 0.0);
    let (mut ma2, mut q2) = (0.0, 0.0);
    let mut out = &mut r[..];
    for run in runs {
        let (head, rest) = out.split_at_mut(run.len());
        out = rest;
        let (ma, q, ext) = (&ma[run.clone()], &q[run.clone()], &ext[run.clone()]);
        let (mut sm, mut sq) = ([0.0f64; 4], [0.0f64; 4]);
        let (r4, ma4, q4, ext4) = (
            head.chunks_exact_mut(4),
            ma.chunks_exact(4),
            q.chunks_exact(4),
            ext.chunks_exact(4),
        );
        let tails = (ma4.remainder(), q4.remainder(), ext4.remainder());
        let chunks = r4.zip(ma4).zip(q4).zip(ext4);
        for (((r, ma), q), ext) in chunks {
            for k in 0..4 {
                r[k] = ma[k] + q[k] - ext[k];
                sm[k] += ma[k] * ma[k];
                sq[k] += q[k] * q[k];
            }
        }
        let (mut tm, mut tq) = (0.0, 0.0);
        let r_tail = head.chunks_exact_mut(4).into_remainder();
        for (((r, &ma), &q), &ext) in r_tail.iter_mut().zip(tails.0).zip(tails.1).zip(tails.2) {
            *r = ma + q - ext;
            tm += ma * ma;
            tq += q * q;
        }
        ma2 += (sm[0] + sm[1]) + (sm[2] + sm[3]) + tm;
        q2 += (sq[0] + sq[1]) + (sq[2] + sq[3]) + tq;
    }
    (ma2, q2)
}

/// Zero −∂Q/∂v where the last evaluation may have written it (`written`,
/// value slots; −∂Q/∂q is written over by `assemble`): with friction or
/// contact damping alone, the few elements in contact, not the 3.5 MB of a
/// 1000-element wire at every refresh (memset in perf).
pub(super) fn clear_velocity_jacobian(kv: &mut [f64], written: Range<usize>) {
    kv[written].fill(0.0);
}

pub(super) fn norm(v: &[f64]) -> f64 {
    sum_of_squares(v).sqrt()
}

/// Σ vᵢ² with `simd::dot`'s partial sums (one running sum waits on each
/// addition's latency at every entry; only the norms' last bits depend on
/// the order).
pub(super) fn sum_of_squares(v: &[f64]) -> f64 {
    dot::<Plain>(v, v)
}
