//! Time of one factorization of the block-tridiagonal LU on the dynamic
//! Newton matrix of an n-element pendulum wire (the sum (1 − α_m) M +
//! c_k K read where each block is loaded, kept in single precision, as a
//! modified-Newton refresh does): warm (factorizations one after the
//! other, the matrix in cache as far as it fits) and cold (64 MB written
//! between two factorizations, as a run's force evaluations and solves do
//! between two refreshes); the best of seven batches each, and a hash of
//! one solve's bits (equal hashes: the same arithmetic).
//! Run: `cargo run --release --example block_lu_timing [elements] [factorizations per batch]`

use ancf::bench::{newton_parts, newton_sum, pendulum};
use ancf_core::linalg::block_tridiagonal::Precision;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let reps: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(100);
    let model = pendulum(n);
    let (mass, k, mut lu) = newton_parts(&model);
    let sum = newton_sum(&mass, &k);
    let mut other = vec![0.0f64; 8 << 20];
    let mut best = [f64::INFINITY; 2];
    for _ in 0..7 {
        for (cold, best) in best.iter_mut().enumerate() {
            let mut seconds = 0.0;
            for r in 0..reps {
                if cold == 1 {
                    other.iter_mut().for_each(|x| *x += r as f64);
                }
                let started = std::time::Instant::now();
                lu.factorize_sum(std::hint::black_box(&sum), Precision::Single)
                    .expect("a mass-dominated matrix is regular");
                seconds += started.elapsed().as_secs_f64();
            }
            *best = best.min(seconds / reps as f64 * 1e6);
        }
    }
    std::hint::black_box(&other);
    let mut x: Vec<f64> = (0..model.n_unknowns).map(|i| (i as f64).sin()).collect();
    lu.solve_in_place(&mut x);
    let hash = x
        .iter()
        .fold(0u64, |h, v| h.wrapping_mul(31).wrapping_add(v.to_bits()));
    let [warm, cold] = best;
    println!(
        "{n} elements: factorization {warm:.1} µs warm, {cold:.1} µs cold (best of 7 batches of {reps}); solution bits {hash:016x}"
    );
}
