//! Wall time per time step of the flexible pendulum against the element
//! count, full and modified Newton (issue 3; numbers in BENCHMARKS.md).
//! Each case runs 0.05 s of simulated time after a 5-step warm-up, with the
//! time step of the 4-element scene (1e-3 s) and ρ∞ = 1.
//! Run: `cargo run --release --example pendulum_scaling [max_elements]`

use ancf_core::dynamics::{DynamicSettings, Integrator, NewtonKind};
use ancf_core::element::ElementIntegration;
use ancf_core::material::{Material, MaterialModel};
use ancf_core::model::{Model, Support, SupportKind};
use ancf_core::section::Section;
use std::time::Instant;

fn model(n: usize) -> Model {
    let m = Material {
        locking: Default::default(),
        density: 7200.0,
        model: MaterialModel::StVenantKirchhoff {
            youngs_modulus: 2e9,
            poisson_ratio: 0.0,
            bending_factor: 1.0,
        },
    };
    let section = Section::circular(&[(0.0, 0.01, m.clone()), (0.01, 0.02, m)], 3);
    let el = ElementIntegration::new(1.0 / n as f64, 5, section);
    Model::new(
        el,
        n,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        vec![Support::new(0, SupportKind::Pin)],
        Some([0.0, 0.0, -9.81]),
        vec![],
    )
    .unwrap()
}

fn time_per_step(model: &Model, newton: NewtonKind, steps: usize) -> (f64, f64, f64) {
    let h = 1e-3;
    let settings = DynamicSettings {
        time_step: h,
        end_time: 1.0,
        spectral_radius: 1.0,
        newton,
        ..Default::default()
    };
    let mut integ = Integrator::new(model, settings).unwrap();
    let mut s = integ
        .initial_state(model.reference.clone(), vec![0.0; model.reference.len()])
        .unwrap();
    for _ in 0..5 {
        s = integ.step(&s, h).unwrap().0;
    }
    let (mut its, mut facs) = (0, 0);
    let t0 = Instant::now();
    for _ in 0..steps {
        let (next, info) = integ.step(&s, h).unwrap();
        its += info.iterations;
        facs += info.factorizations;
        s = next;
    }
    let dt = t0.elapsed().as_secs_f64() / steps as f64;
    (
        dt * 1e3,
        its as f64 / steps as f64,
        facs as f64 / steps as f64,
    )
}

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
        let m = model(n);
        let steps = if n <= 64 {
            50
        } else if n <= 1024 {
            20
        } else {
            10
        };
        let (f, fi, ff) = time_per_step(&m, NewtonKind::Full, steps);
        let (md, mi, mf) = time_per_step(&m, NewtonKind::Modified, steps);
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
