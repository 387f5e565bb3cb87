//! Wall time per time step of the flexible pendulum against the element
//! count, full and modified Newton (numbers in BENCHMARKS.md).
//! Each case runs after a 5-step warm-up, with the time step of the
//! 4-element scene (1e-3 s) and ρ∞ = 1, on the global rayon pool (all cores;
//! `ancf bench` measures single-threaded).
//! Run: `cargo run --release --example pendulum_scaling [max_elements]`

use ancf::bench::{pendulum, pendulum_step};
use ancf_core::solve::dynamics::NewtonKind;

fn main() {
    let max: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(4096);
    println!(
        "{:>8} {:>9} | {:>12} {:>8} {:>8} | {:>12} {:>8} {:>8} | {:>14}",
        "elements",
        "unknowns",
        "full ms/step",
        "its",
        "facts",
        "mod. ms/step",
        "its",
        "facts",
        "mod. µs/unk/step"
    );
    for n in [4usize, 16, 32, 64, 256, 1024, 4096]
        .into_iter()
        .filter(|n| *n <= max)
    {
        let m = pendulum(n);
        let steps = if n <= 64 {
            50
        } else if n <= 1024 {
            20
        } else {
            10
        };
        let (f, fi, ff) = pendulum_step(&m, NewtonKind::Full, steps);
        let (md, mi, mf) = pendulum_step(&m, NewtonKind::Modified, steps);
        println!(
            "{:>8} {:>9} | {:>12.3} {:>8.1} {:>8.1} | {:>12.3} {:>8.1} {:>8.2} | {:>14.2}",
            n,
            m.n_unknowns,
            f,
            fi,
            ff,
            md,
            mi,
            mf,
            md * 1e3 / m.n_unknowns as f64
        );
    }
}
