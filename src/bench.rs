//! `ancf bench`: the numbers users compare simulators by, measured
//! on this machine in one command. Element kernels, pendulum step times,
//! parallel speed-up and the impact scene's real-time factor. Single thread
//! unless stated (a 1-thread rayon pool); wall-clock medians of repeats.

use crate::run::{RunOptions, run_scene};
use ancf_core::element::{ElementIntegration, reference_coordinates};
use ancf_core::material::{Material, MaterialModel};
use ancf_core::model::{Model, Support, SupportKind};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::section::Section;
use ancf_core::solve::dynamics::{DynamicSettings, Integrator, NewtonKind};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

/// The benchmark's St. Venant–Kirchhoff material: E = 2 GPa, ρ = 7200 kg/m³.
pub fn svk(nu: f64) -> Material {
    Material {
        density: 7200.0,
        model: MaterialModel::StVenantKirchhoff {
            youngs_modulus: 2e9,
            poisson_ratio: nu,
            bending_factor: 1.0,
        },
        locking: Default::default(),
        yield_stress: None,
    }
}

/// The pendulum of `scenes/pendulum.toml` with `n` elements.
pub fn pendulum(n: usize) -> Model {
    pendulum_with(n, svk(0.0))
}

/// The same pendulum with another cover material.
pub fn pendulum_with(n: usize, cover: Material) -> Model {
    let section = Section::circular(&[(0.0, 0.01, svk(0.0)), (0.01, 0.02, cover)], 3);
    let el = ElementIntegration::new(1.0 / n as f64, 3, section);
    Model::new(
        el,
        n,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        vec![Support::new(0, SupportKind::Pin)],
        Some([0.0, 0.0, -9.81]),
        vec![],
    )
    .expect("valid pendulum")
}

/// Milliseconds per step, Newton iterations and factorizations per step,
/// over `steps` steps after 5 warm-up steps (h = 1e-3 s, ρ∞ = 1). The same
/// steps are timed five times from a fresh start and the median taken:
/// 50 four-element steps last half a millisecond, and one such timing
/// scattered by ±40 % on a shared host.
pub fn pendulum_step(model: &Model, newton: NewtonKind, steps: usize) -> (f64, f64, f64) {
    const REPEATS: usize = 5;
    let h = 1e-3;
    let settings = DynamicSettings {
        time_step: h,
        end_time: 1.0,
        spectral_radius: 1.0,
        newton,
        ..Default::default()
    };
    let model = std::sync::Arc::new(model.clone());
    let (mut its, mut facs) = (0, 0);
    let mut ms: Vec<f64> = (0..REPEATS)
        .map(|_| {
            let mut integ = Integrator::new(model.clone(), settings.clone()).expect("solver");
            let mut s = integ
                .initial_state(model.reference.clone(), vec![0.0; model.reference.len()])
                .expect("initial state");
            for _ in 0..5 {
                s = integ.step(&s, h).expect("step").0;
            }
            let t0 = Instant::now();
            for _ in 0..steps {
                let (next, info) = integ.step(&s, h).expect("step");
                its += info.iterations;
                facs += info.factorizations;
                s = next;
            }
            t0.elapsed().as_secs_f64() * 1e3 / steps as f64
        })
        .collect();
    ms.sort_by(f64::total_cmp);
    let n = (REPEATS * steps) as f64;
    (ms[REPEATS / 2], its as f64 / n, facs as f64 / n)
}

/// Time (µs) to assemble force and Jacobian (written over the previous
/// values) at a deformed state (the reference stretched by 1 %), as a
/// Newton iteration does, on the current rayon pool.
pub fn assembly_us(model: &Model) -> f64 {
    let pattern = ancf_core::forces::assembly::pattern(model);
    let q: Vec<f64> = model.reference.iter().map(|x| 1.01 * x).collect();
    let mut k = pattern.zeros();
    time_us(|| {
        std::hint::black_box(ancf_core::forces::assembly::assemble(
            model,
            &pattern,
            std::hint::black_box(&q),
            Some(&mut k),
        ));
    })
}

/// The parts of the dynamic Newton matrix (1 − α_m) M + (1 − α_f) β h² K
/// of `model` (ρ∞ = 1, h = 1e-4 s, K at the reference stretched by 1 %),
/// M's and K's values over the pattern (see [`newton_sum`]), and a block
/// LU for it: what a modified-Newton refresh of the impact scene factors.
pub fn newton_parts(
    model: &Model,
) -> (
    Vec<f64>,
    Vec<f64>,
    ancf_core::linalg::block_tridiagonal::BlockTridiagonalLu,
) {
    use ancf_core::forces::assembly::{assemble, mass_values, pattern};
    use ancf_core::linalg::block_tridiagonal::BlockTridiagonalLu;
    let pattern = pattern(model);
    let q: Vec<f64> = model.reference.iter().map(|x| 1.01 * x).collect();
    let mut k = pattern.zeros();
    assemble(model, &pattern, &q, Some(&mut k));
    let mass = mass_values(model, &pattern);
    let sym = pattern.symbolic.as_ref();
    let lu = BlockTridiagonalLu::new(sym.nrows(), sym.col_ptr(), sym.row_idx())
        .expect("a wire's matrix has node blocks");
    (mass, k, lu)
}

/// The Newton matrix of [`newton_parts`] as the sum its factorization reads.
pub fn newton_sum<'a>(mass: &'a [f64], k: &'a [f64]) -> ancf_core::linalg::value_sum::ValueSum<'a> {
    ancf_core::linalg::value_sum::ValueSum {
        parts: [mass, k, k],
        weights: [0.5, 0.5 * 0.25 * 1e-8, 0.0],
        third_slots: 0..0,
    }
}

/// Time (µs) to factor, and to solve with, the block-tridiagonal LU of
/// [`newton_parts`] (the sum read from M and K where each block is
/// loaded, as a modified-Newton refresh does; each solve as an iteration
/// of the impact scene's solver; kept in single precision, as modified
/// Newton keeps it).
pub fn block_lu_us(model: &Model) -> (f64, f64) {
    use ancf_core::linalg::block_tridiagonal::Precision;
    let (mass, k, mut lu) = newton_parts(model);
    let sum = newton_sum(&mass, &k);
    let factor = time_us(|| {
        lu.factorize_sum(std::hint::black_box(&sum), Precision::Single)
            .expect("a mass-dominated matrix is regular");
    });
    let b: Vec<f64> = (0..model.n_unknowns).map(|i| (i as f64).sin()).collect();
    let mut x = b.clone();
    let solve = time_us(|| {
        x.copy_from_slice(&b);
        lu.solve_in_place(std::hint::black_box(&mut x));
    });
    (factor, solve)
}

/// How long a timing measures: batches of at least `batch_s` seconds (the
/// batch size doubled until one lasts that long), the median of `samples`.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    /// Shortest batch (s).
    pub batch_s: f64,
    /// Batches timed; the median is reported.
    pub samples: usize,
}

impl Timing {
    /// `ancf bench`'s: nine batches of ≥ 20 ms (0.2–0.4 s a timing).
    pub const BENCH: Timing = Timing {
        batch_s: 0.02,
        samples: 9,
    };
    /// The study's table of element cost against quadrature order (64
    /// timings): five batches of ≥ 4 ms, 0.03–0.05 s a timing (with
    /// `BENCH` the table took 22 s, a quarter of the impact study).
    pub const SURVEY: Timing = Timing {
        batch_s: 0.004,
        samples: 5,
    };
}

/// Median time (µs) of `f` over repeated batches ([`Timing::BENCH`]).
fn time_us(f: impl FnMut()) -> f64 {
    time_us_with(Timing::BENCH, f)
}

/// Median time (µs) of `f` over repeated batches as `timing` says.
fn time_us_with(timing: Timing, mut f: impl FnMut()) -> f64 {
    let mut batch = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..batch {
            f();
        }
        if t.elapsed().as_secs_f64() > timing.batch_s {
            break;
        }
        batch *= 2;
    }
    let mut samples: Vec<f64> = (0..timing.samples.max(1))
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                f();
            }
            t.elapsed().as_secs_f64() * 1e6 / batch as f64
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// The benchmark's Mooney–Rivlin rubber (plain formulation, κ = 1e3).
pub fn rubber() -> Material {
    Material {
        density: 1100.0,
        model: MaterialModel::MooneyRivlin {
            mu10: 5e5,
            mu01: 1e5,
            penalty: 1e3,
        },
        locking: ancf_core::material::Locking::None,
        yield_stress: None,
    }
}

/// A straight element of length `l` (m) with a fixed, deterministic
/// perturbation of every coordinate: a deformed state for kernel timings.
pub fn deformed_element(l: f64) -> [f64; 24] {
    let mut e = reference_coordinates(
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        l,
    );
    for (i, v) in e.iter_mut().enumerate() {
        *v += 0.01 * ((i * 7919 % 23) as f64 / 23.0 - 0.5);
    }
    e
}

/// Floating-point operations of one pre-integrated SVK element force with a
/// 3-point axial rule, counted in `station_lanes` (preintegration.rs): per
/// station u = T e 48, Gram entries 75, strain moments 30, M s 151, energy
/// and stresses 50, ∂U/∂u 150, Tᵀ(·) into q 78 — 582 (a multiply-add
/// counts 2), times 3 stations.
pub const FORCE_FLOPS: f64 = 3.0 * 582.0;

/// Force time (µs per element) of 32 elements evaluated eight at a time, as
/// the force-only assembly does (`ElementIntegration::forces_x8`); `NaN`
/// when the element has no batched kernel.
pub fn batched_force_us(el: &ElementIntegration) -> f64 {
    let e = deformed_element(el.length);
    let scale = [1.0, 1.0001, 0.9999, 1.0, 1.0002, 0.9998, 1.0003, 0.9997];
    let lanes: [[f64; 8]; 24] = std::array::from_fn(|i| scale.map(|s| e[i] * s));
    if el.forces_x8(&lanes, &mut [[0.0; 8]; 24]).is_none() {
        return f64::NAN;
    }
    time_us(|| {
        for _ in 0..4 {
            let mut q = [[0.0; 8]; 24];
            std::hint::black_box(el.forces_x8(std::hint::black_box(&lanes), &mut q));
        }
    }) / 32.0
}

/// Floating-point operations of one pre-integrated SVK element force and
/// Jacobian with a 3-point axial rule, counted in `jacobians_lanes`
/// (preintegration.rs): per station the force's 582, the Hessian blocks'
/// 45 outer products of an isotropic law at 21 each (3 scalings, 9
/// multiply-adds) and K's 82 node-block terms at 20 each (2 products of
/// T's coefficients, 9 multiply-adds) — 3167, times 3 stations — plus the
/// 576 additions into the element matrix.
pub const JACOBIAN_FLOPS: f64 = 3.0 * (582.0 + 45.0 * 21.0 + 82.0 * 20.0) + 576.0;

/// Force + Jacobian time (µs per element) of 32 elements evaluated four at
/// a time, as the Jacobian assembly does
/// (`ElementIntegration::jacobians_x4`); `NaN` when the element has no
/// batched kernel.
pub fn batched_jacobian_us(el: &ElementIntegration) -> f64 {
    let e = deformed_element(el.length);
    let lanes: [[f64; 4]; 24] = std::array::from_fn(|i| [e[i], e[i] * 1.0001, e[i] * 0.9999, e[i]]);
    let mut k = Box::new([[0.0; 4]; 576]);
    if el
        .jacobians_x4(&lanes, &mut [[0.0; 4]; 24], &mut k)
        .is_none()
    {
        return f64::NAN;
    }
    time_us(|| {
        for _ in 0..8 {
            let mut q = [[0.0; 4]; 24];
            std::hint::black_box(el.jacobians_x4(std::hint::black_box(&lanes), &mut q, &mut k));
        }
    }) / 32.0
}

/// The core's multiply-add peak on the chosen path (GFLOP/s): 12
/// independent chains of fused multiply-adds of the path's full width
/// (8 lanes on AVX-512, where the force kernel runs eight elements a
/// register; 4 on AVX2), of 2-lane multiplies and adds on the baseline;
/// written with intrinsics so that the compiler cannot serialize them (an
/// auto-vectorized loop came out scalar).
pub fn fma_peak_gflops() -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        use ancf_core::math::simd::{SimdPath, path};
        use std::arch::x86_64::*;
        const CHAINS: usize = 12;
        #[target_feature(enable = "avx2,fma")]
        fn fused(n: usize) -> f64 {
            let a = _mm256_set1_pd(std::hint::black_box(0.999_999_9));
            let b = _mm256_set1_pd(std::hint::black_box(1e-7));
            let mut acc = [_mm256_set1_pd(1.0); CHAINS];
            for _ in 0..n {
                for x in acc.iter_mut() {
                    *x = _mm256_fmadd_pd(*x, a, b);
                }
            }
            let mut out = [0.0; 4];
            let sum = acc
                .iter()
                .fold(_mm256_setzero_pd(), |s, x| _mm256_add_pd(s, *x));
            // SAFETY: `out` holds four f64.
            unsafe { _mm256_storeu_pd(out.as_mut_ptr(), sum) };
            out.iter().sum()
        }
        #[target_feature(enable = "avx512f")]
        fn fused512(n: usize) -> f64 {
            let a = _mm512_set1_pd(std::hint::black_box(0.999_999_9));
            let b = _mm512_set1_pd(std::hint::black_box(1e-7));
            let mut acc = [_mm512_set1_pd(1.0); CHAINS];
            for _ in 0..n {
                for x in acc.iter_mut() {
                    *x = _mm512_fmadd_pd(*x, a, b);
                }
            }
            let sum = acc
                .iter()
                .fold(_mm512_setzero_pd(), |s, x| _mm512_add_pd(s, *x));
            _mm512_reduce_add_pd(sum)
        }
        #[target_feature(enable = "sse2")]
        fn plain(n: usize) -> f64 {
            let a = _mm_set1_pd(std::hint::black_box(0.999_999_9));
            let b = _mm_set1_pd(std::hint::black_box(1e-7));
            let mut acc = [_mm_set1_pd(1.0); CHAINS];
            for _ in 0..n {
                for x in acc.iter_mut() {
                    *x = _mm_add_pd(_mm_mul_pd(*x, a), b);
                }
            }
            let mut out = [0.0; 2];
            let sum = acc.iter().fold(_mm_setzero_pd(), |s, x| _mm_add_pd(s, *x));
            // SAFETY: `out` holds two f64.
            unsafe { _mm_storeu_pd(out.as_mut_ptr(), sum) };
            out.iter().sum()
        }
        let n = 20_000;
        let p = path();
        let us = time_us(|| {
            let n = std::hint::black_box(n);
            // SAFETY: `path` is a path the CPU supports (AVX2 + FMA on the
            // AVX2 path, AVX-512 F on the AVX-512 one).
            let r = unsafe {
                match p {
                    SimdPath::Baseline => plain(n),
                    SimdPath::Avx2 => fused(n),
                    SimdPath::Avx512 => fused512(n),
                }
            };
            std::hint::black_box(r);
        });
        let lanes = match p {
            SimdPath::Baseline => 2.0,
            SimdPath::Avx2 => 4.0,
            SimdPath::Avx512 => 8.0,
        };
        n as f64 * CHAINS as f64 * lanes * 2.0 / us / 1e3
    }
    #[cfg(not(target_arch = "x86_64"))]
    f64::NAN
}

/// The CPU's model name (Linux: /proc/cpuinfo), or "unknown".
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Force and Jacobian time (µs) of one element.
pub fn element_times(el: &ElementIntegration) -> (f64, f64) {
    element_times_with(el, Timing::BENCH)
}

/// [`element_times`] measured as `timing` says.
pub fn element_times_with(el: &ElementIntegration, timing: Timing) -> (f64, f64) {
    let e = deformed_element(el.length);
    let force = time_us_with(timing, || {
        let mut q = [0.0; 24];
        std::hint::black_box(el.evaluate(std::hint::black_box(&e), &mut q, None));
    });
    let mut k = [0.0; 576];
    let jac = time_us_with(timing, || {
        let mut q = [0.0; 24];
        k.fill(0.0);
        std::hint::black_box(el.evaluate(std::hint::black_box(&e), &mut q, Some(&mut k)));
    });
    (force, jac)
}

#[derive(Debug, Serialize)]
pub struct BenchReport {
    /// CPU model name.
    pub cpu: String,
    /// The instruction-set path the kernels ran (`ancf --simd` forces one).
    pub simd: String,
    /// Circular two-layer SVK section, 3 axial points, ring rule n = 3: one
    /// element at a time.
    pub force_us: f64,
    /// The same force, eight elements at a time as the assembly evaluates
    /// them (µs per element).
    pub force_batch_us: f64,
    /// Floating-point operations of that force ([`FORCE_FLOPS`]), the rate
    /// achieved in the batched form (GFLOP/s), the measured multiply-add
    /// peak of one core on this path (GFLOP/s) and the fraction reached.
    pub force_flops: f64,
    pub force_gflops: f64,
    pub fma_peak_gflops: f64,
    pub force_peak_fraction: f64,
    pub jacobian_us: f64,
    /// The same force + Jacobian, four elements at a time as the Jacobian
    /// assembly evaluates them (µs per element), its operations
    /// ([`JACOBIAN_FLOPS`]) and their rate (GFLOP/s).
    pub jacobian_batch_us: f64,
    pub jacobian_flops: f64,
    pub jacobian_gflops: f64,
    pub jacobian_peak_fraction: f64,
    /// Rectangle 3 axial × 2×2 SVK (Chrono's ChElementBeamANCF_3243 case).
    pub rect_force_us: f64,
    /// The rectangle's force eight elements at a time (µs per element).
    pub rect_force_batch_us: f64,
    pub rect_jacobian_us: f64,
    /// The rectangle's force + Jacobian four elements at a time (µs per element).
    pub rect_jacobian_batch_us: f64,
    /// Mooney–Rivlin Jacobian per section point (plain formulation).
    pub mooney_rivlin_jacobian_us_per_point: f64,
    pub step_ms_32_full_newton: f64,
    /// The block-tridiagonal LU of the 64-element pendulum's dynamic Newton
    /// matrix ([`block_lu_us`]): one factorization and one solve (µs).
    pub block_lu_factor_us: f64,
    pub block_lu_solve_us: f64,
    /// Modified Newton, ms per step, keyed by element count.
    pub step_ms: BTreeMap<String, f64>,
    /// Full Newton, ms per step, keyed by element count.
    pub step_ms_full_newton: BTreeMap<String, f64>,
    /// Parallel assembly at 256 elements (SVK pendulum): the time to
    /// assemble force and Jacobian, 1 thread over 2 threads (median of 5
    /// alternating pairs; the step ratios below: of 3).
    pub parallel_speedup_256: f64,
    /// The same at 256, 1024 and 4096 elements, keyed by element count.
    pub parallel_assembly_speedup: BTreeMap<String, f64>,
    /// Whole full-Newton steps at 256 elements, 1 thread over 2 threads.
    pub parallel_step_speedup_256: f64,
    /// Whole steps, 1 thread over 2 threads, keyed by element count (256,
    /// 1024, 4096): (full Newton, modified Newton).
    pub parallel_step_speedup: BTreeMap<String, (f64, f64)>,
    /// Whole full-Newton steps at 256 elements with a plain Mooney–Rivlin
    /// cover (section points: the element work dominates).
    pub parallel_speedup_256_mooney_rivlin: f64,
    /// Simulated seconds per wall second for scenes/wire_rod_impact.toml, one thread.
    pub impact_realtime_factor: f64,
    /// The same run's limit ratio: wall time per step over one force
    /// evaluation plus one solve (summary.json `performance`).
    pub impact_limit_ratio: f64,
    /// The part of it the Newton method's own work takes (summary.json
    /// `performance.newton_ratio`): the ratio with every other cost removed.
    pub impact_newton_ratio: f64,
    /// scenes/span_break_frame.toml's limit ratio up to 0.85 s (its three
    /// first impacts), one thread.
    pub span_break_limit_ratio: f64,
    /// Its Newton ratio.
    pub span_break_newton_ratio: f64,
    pub threads_available: usize,
}

/// A shipped scene run to `end_time` (s; its own when `None`) without
/// output but its summary: (simulated s per wall s, limit ratio, Newton
/// ratio).
fn scene_performance(path: &str, end_time: Option<f64>) -> Result<(f64, f64, f64), String> {
    let mut scene = Scene::load(std::path::Path::new(path))
        .map_err(|e| format!("{path} (run from the repository root): {e}"))?;
    if let (Some(end), Analysis::Dynamic { settings, .. }) = (end_time, &mut scene.analysis) {
        settings.end_time = end;
    }
    scene.output.every = 1_000_000;
    scene.output.vtk = false;
    scene.output.plots = false;
    let dir = std::env::temp_dir().join(format!("ancf-bench-{}", std::process::id()));
    let t = Instant::now();
    let s = run_scene(
        &scene,
        &RunOptions {
            out: dir.clone(),
            quiet: true,
            cancel: Default::default(),
        },
    )?;
    let wall = t.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&dir);
    let (ratio, newton) = s
        .performance
        .as_ref()
        .map_or((f64::NAN, f64::NAN), |p| (p.limit_ratio, p.newton_ratio));
    Ok((s.time / wall, ratio, newton))
}

/// Run every measurement. `quick` trims the largest meshes (for tests).
pub fn run(quick: bool) -> Result<BenchReport, String> {
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| e.to_string())?;
    let (force_us, jacobian_us, rect_force_us, rect_jacobian_us, mr, batch) =
        single.install(|| {
            let circle = ElementIntegration::new(
                0.25,
                3,
                Section::circular(&[(0.0, 0.01, svk(0.3)), (0.01, 0.02, svk(0.3))], 3),
            );
            let rect =
                ElementIntegration::new(0.25, 3, Section::rectangular(0.02, 0.02, svk(0.3), 2));
            let mr =
                ElementIntegration::new(0.25, 3, Section::circular(&[(0.0, 0.02, rubber())], 3));
            let points = 3 * mr.section.layers[0].points.len();
            let (f, j) = element_times(&circle);
            let (rf, rj) = element_times(&rect);
            let (_, mj) = element_times(&mr);
            let batch = (
                batched_force_us(&circle),
                batched_force_us(&rect),
                batched_jacobian_us(&circle),
                batched_jacobian_us(&rect),
            );
            (f, j, rf, rj, mj / points as f64, batch)
        });
    let peak = fma_peak_gflops();
    let force_gflops = FORCE_FLOPS / batch.0 / 1e3;
    let sizes: &[usize] = if quick {
        &[4, 16, 32]
    } else {
        &[4, 16, 32, 64, 256, 1024, 4096]
    };
    let mut step_ms = BTreeMap::new();
    let mut step_full = BTreeMap::new();
    single.install(|| {
        for &n in sizes {
            let m = pendulum(n);
            let steps = if n <= 64 {
                50
            } else if n <= 1024 {
                10
            } else {
                3
            };
            step_full.insert(n.to_string(), pendulum_step(&m, NewtonKind::Full, steps).0);
            step_ms.insert(
                n.to_string(),
                pendulum_step(&m, NewtonKind::Modified, steps).0,
            );
        }
    });
    let block_lu = single.install(|| block_lu_us(&pendulum(64)));
    let n_par = if quick { 64 } else { 256 };
    let two_pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .map_err(|e| e.to_string())?;
    let assembly_sizes: &[usize] = if quick { &[64] } else { &[256, 1024, 4096] };
    let mut parallel_assembly_speedup = BTreeMap::new();
    let mut parallel_step_speedup = BTreeMap::new();
    // Ratios of 1-thread to 2-thread times, measured in alternation: the
    // median of several pairs (single pairs on this shared 2-vCPU machine
    // ranged from 1.15 to 2.1 for the same 4096-element assembly).
    let paired = |pairs: usize, time: &(dyn Fn() -> f64 + Sync)| {
        let mut r: Vec<f64> = (0..pairs)
            .map(|_| single.install(time) / two_pool.install(time))
            .collect();
        r.sort_by(f64::total_cmp);
        r[pairs / 2]
    };
    for &n in assembly_sizes {
        let m = pendulum(n);
        let asm = || assembly_us(&m);
        parallel_assembly_speedup.insert(n.to_string(), paired(5, &asm));
        let steps = (2560 / n).max(3);
        let full = || pendulum_step(&m, NewtonKind::Full, steps).0;
        let modified = || pendulum_step(&m, NewtonKind::Modified, steps).0;
        parallel_step_speedup.insert(n.to_string(), (paired(3, &full), paired(3, &modified)));
    }
    let cover = pendulum_with(n_par, rubber());
    let cover_step = || pendulum_step(&cover, NewtonKind::Full, 5).0;
    let parallel_speedup_256_mooney_rivlin = paired(3, &cover_step);
    // The impact whole (0.05 s with --quick); the span break to 0.85 s,
    // past its three first impacts (0.02 s with --quick: the plumbing).
    let (impact_realtime_factor, impact_limit_ratio, impact_newton_ratio) = single
        .install(|| scene_performance("scenes/wire_rod_impact.toml", quick.then_some(0.05)))?;
    let (_, span_break_limit_ratio, span_break_newton_ratio) = single.install(|| {
        scene_performance(
            "scenes/span_break_frame.toml",
            Some(if quick { 0.02 } else { 0.85 }),
        )
    })?;
    Ok(BenchReport {
        cpu: cpu_model(),
        simd: ancf_core::math::simd::path().name().into(),
        force_us,
        force_batch_us: batch.0,
        jacobian_batch_us: batch.2,
        jacobian_flops: JACOBIAN_FLOPS,
        jacobian_gflops: JACOBIAN_FLOPS / batch.2 / 1e3,
        jacobian_peak_fraction: JACOBIAN_FLOPS / batch.2 / 1e3 / peak,
        force_flops: FORCE_FLOPS,
        force_gflops,
        fma_peak_gflops: peak,
        force_peak_fraction: force_gflops / peak,
        jacobian_us,
        rect_force_us,
        rect_force_batch_us: batch.1,
        rect_jacobian_batch_us: batch.3,
        rect_jacobian_us,
        mooney_rivlin_jacobian_us_per_point: mr,
        step_ms_32_full_newton: step_full.get("32").copied().unwrap_or(f64::NAN),
        block_lu_factor_us: block_lu.0,
        block_lu_solve_us: block_lu.1,
        step_ms,
        step_ms_full_newton: step_full,
        parallel_speedup_256: parallel_assembly_speedup
            .get(&n_par.to_string())
            .copied()
            .unwrap_or(f64::NAN),
        parallel_assembly_speedup,
        parallel_step_speedup_256: parallel_step_speedup
            .get(&n_par.to_string())
            .map_or(f64::NAN, |s| s.0),
        parallel_step_speedup,
        parallel_speedup_256_mooney_rivlin,
        impact_realtime_factor,
        impact_limit_ratio,
        impact_newton_ratio,
        span_break_limit_ratio,
        span_break_newton_ratio,
        threads_available: std::thread::available_parallelism().map_or(1, |n| n.get()),
    })
}

/// The keys of a map keyed by element count, in numeric order (the map
/// orders them as strings).
fn by_element_count<V>(map: &BTreeMap<String, V>) -> Vec<&String> {
    let mut sizes: Vec<&String> = map.keys().collect();
    sizes.sort_by_key(|n| n.parse::<usize>().unwrap_or(0));
    sizes
}

/// The report as a table.
pub fn table(r: &BenchReport) -> String {
    let mut s = format!("CPU: {}; SIMD path: {}\n", r.cpu, r.simd);
    s += "Element kernels (single thread, µs per element)\n";
    s += &format!(
        "  SVK circle, 2 layers, 3 axial × ring n=3   force {:8.3}   Jacobian {:8.3}\n",
        r.force_us, r.jacobian_us
    );
    s += &format!(
        "  SVK rectangle 3 × 2×2                      force {:8.3}   Jacobian {:8.3}\n",
        r.rect_force_us, r.rect_jacobian_us
    );
    s += &format!(
        "  batched as the assembly runs them (forces 8, Jacobians 4 at a time): \
         circle force {:.3}, rectangle force {:.3}; circle Jacobian {:.3}, rectangle Jacobian {:.3}\n",
        r.force_batch_us, r.rect_force_batch_us, r.jacobian_batch_us, r.rect_jacobian_batch_us
    );
    s += &format!(
        "  circle force: {:.0} flops, {:.1} GFLOP/s of a {:.1} GFLOP/s multiply-add peak ({:.0} %)\n",
        r.force_flops,
        r.force_gflops,
        r.fma_peak_gflops,
        100.0 * r.force_peak_fraction
    );
    s += &format!(
        "  circle force + Jacobian: {:.0} flops, {:.1} GFLOP/s ({:.0} % of the peak)\n",
        r.jacobian_flops,
        r.jacobian_gflops,
        100.0 * r.jacobian_peak_fraction
    );
    s += &format!(
        "  Mooney–Rivlin Jacobian per section point   {:8.3} µs\n",
        r.mooney_rivlin_jacobian_us_per_point
    );
    s += &format!(
        "Block LU, 64-element dynamic Newton matrix: factorization {:.1} µs, solve {:.2} µs\n",
        r.block_lu_factor_us, r.block_lu_solve_us
    );
    s += "Pendulum time step (single thread, ms per step)\n";
    s += "  elements   full Newton   modified Newton\n";
    let sizes = by_element_count(&r.step_ms_full_newton);
    for n in sizes {
        let full = r.step_ms_full_newton[n];
        s += &format!("  {:>8}   {:>11.3}   {:>15.3}\n", n, full, r.step_ms[n]);
    }
    s += "Parallel speed-up, 1 → 2 threads\n";
    let sizes = by_element_count(&r.parallel_assembly_speedup);
    s += "  elements   assembly (force + Jacobian)   full-Newton step   modified-Newton step\n";
    for n in sizes {
        let (full, modified) = r.parallel_step_speedup[n];
        s += &format!(
            "  {:>8}   {:>26.2}×   {:>15.2}×   {:>19.2}×\n",
            n, r.parallel_assembly_speedup[n], full, modified
        );
    }
    s += &format!(
        "  full-Newton step with a Mooney–Rivlin cover (256 elements; 64 with --quick): {:.2}×\n",
        r.parallel_speedup_256_mooney_rivlin
    );
    s += &format!(
        "Impact scene real-time factor (simulated s per wall s, 1 thread): {:.3}\n",
        r.impact_realtime_factor
    );
    s += &format!(
        "Impact scene limit ratio (wall time per step / one force evaluation + one solve): {:.2} \
         (the Newton method's own work: {:.2})\n",
        r.impact_limit_ratio, r.impact_newton_ratio
    );
    s += &format!(
        "Span-break scene limit ratio (to 0.85 s, its first impacts): {:.2} (Newton: {:.2})\n",
        r.span_break_limit_ratio, r.span_break_newton_ratio
    );
    s
}
