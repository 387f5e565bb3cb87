//! The instruction set the hot loops run on, chosen once at run time.
//!
//! The binary is built for baseline x86-64 (SSE2), so that one build runs on
//! every CPU a user has. Loops that pay for it are written once, generic
//! over [`Arith`] (`a · b + c` as two roundings, [`Plain`], or one fused
//! multiply-add, [`Fused`]), and [`crate::simd_dispatch!`] compiles each of them
//! three times: baseline, AVX2 + FMA, and AVX-512. Which one runs is decided
//! at the first call ([`path`]) from the CPU, unless the `ANCF_SIMD`
//! environment variable (`baseline`, `avx2`, `avx512`) or [`force`] picks one
//! the CPU supports.
//!
//! The paths round differently (a fused multiply-add rounds once), so their
//! results agree to round-off, not bit for bit; a given path on a given CPU
//! and thread count is deterministic.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction-set path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimdPath {
    /// SSE2, what every x86-64 CPU has (and every other architecture).
    Baseline,
    /// AVX2 with fused multiply-add (x86-64-v3: Intel since 2013, AMD since 2015).
    Avx2,
    /// AVX-512 F + VL with fused multiply-add (x86-64-v4).
    Avx512,
}

impl SimdPath {
    /// Every path, slowest first.
    pub const ALL: [SimdPath; 3] = [SimdPath::Baseline, SimdPath::Avx2, SimdPath::Avx512];

    /// The name used by `ANCF_SIMD`, `--simd` and the benchmark output.
    pub fn name(self) -> &'static str {
        match self {
            SimdPath::Baseline => "baseline",
            SimdPath::Avx2 => "avx2",
            SimdPath::Avx512 => "avx512",
        }
    }

    /// The path named `name` (see [`SimdPath::name`]).
    pub fn from_name(name: &str) -> Option<SimdPath> {
        SimdPath::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Whether this CPU can run the path.
    pub fn supported(self) -> bool {
        match self {
            SimdPath::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => {
                SimdPath::Avx2.supported()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The fastest path this CPU supports.
    pub fn detect() -> SimdPath {
        *SimdPath::ALL
            .iter()
            .rev()
            .find(|p| p.supported())
            .unwrap_or(&SimdPath::Baseline)
    }
}

const UNSET: u8 = u8::MAX;
static CHOSEN: AtomicU8 = AtomicU8::new(UNSET);

/// The path the dispatched loops take (chosen at the first call).
pub fn path() -> SimdPath {
    match CHOSEN.load(Ordering::Relaxed) {
        UNSET => {
            let chosen = from_environment().unwrap_or_else(SimdPath::detect);
            CHOSEN.store(chosen as u8, Ordering::Relaxed);
            chosen
        }
        v => SimdPath::ALL[v as usize],
    }
}

/// Run the dispatched loops on `path` from now on (for side-by-side
/// measurements and tests). Refused when the CPU lacks the instructions.
pub fn force(path: SimdPath) -> Result<(), String> {
    if !path.supported() {
        return Err(format!(
            "this CPU cannot run the {} path (it supports up to {})",
            path.name(),
            SimdPath::detect().name()
        ));
    }
    CHOSEN.store(path as u8, Ordering::Relaxed);
    Ok(())
}

/// `ANCF_SIMD`, if it names a path this CPU supports (otherwise a warning
/// on stderr, once, and the detected path).
fn from_environment() -> Option<SimdPath> {
    let value = std::env::var("ANCF_SIMD").ok()?;
    match SimdPath::from_name(value.trim()) {
        Some(p) if p.supported() => Some(p),
        Some(p) => {
            eprintln!(
                "warning: ANCF_SIMD={value}: this CPU cannot run the {} path; using {}",
                p.name(),
                SimdPath::detect().name()
            );
            None
        }
        None => {
            eprintln!(
                "warning: ANCF_SIMD={value} is not one of baseline, avx2, avx512; using {}",
                SimdPath::detect().name()
            );
            None
        }
    }
}

/// Multiply-add as the path computes it.
pub trait Arith {
    /// a · b + c.
    fn mul_add(a: f64, b: f64, c: f64) -> f64;
}

/// Two roundings: what the baseline path computes (a software fused
/// multiply-add would be a library call per operation there).
pub struct Plain;

/// One rounding, one instruction on CPUs with FMA.
pub struct Fused;

impl Arith for Plain {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

impl Arith for Fused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// Σ a_k b_k with four partial sums (one running sum waits on each
/// addition's latency: the band factorization was 4× slower that way, perf).
/// On the AVX2 path the four sums are one vector register and one FMA per
/// four products.
#[inline(always)]
pub fn dot<F: Arith>(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail = a4
        .remainder()
        .iter()
        .zip(b4.remainder())
        .fold(0.0, |s, (x, y)| F::mul_add(*x, *y, s));
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] = F::mul_add(x[k], y[k], acc[k]);
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Defines `fn $name(path: SimdPath, args…)` that calls the generic
/// `$generic::<F: Arith>(args…)` compiled for `path`: baseline with
/// [`Plain`], AVX2 + FMA and AVX-512 with [`Fused`]. Callers pass
/// [`path()`]; tests pass each supported path to compare them. `$generic`
/// must be `#[inline(always)]` (and so must what its hot loop calls, with
/// no closures that might stay out of line), so that its body is compiled
/// inside each path's `#[target_feature]` function.
///
/// # Panics
/// When `path` is not supported by the CPU.
#[macro_export]
#[doc(hidden)]
macro_rules! simd_dispatch {
    ($(#[$attr:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? = $generic:ident;) => {
        $(#[$attr])*
        $vis fn $name(path: $crate::math::simd::SimdPath, $($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                fn avx2($($arg: $ty),*) $(-> $ret)? {
                    $generic::<$crate::math::simd::Fused>($($arg),*)
                }
                #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
                fn avx512($($arg: $ty),*) $(-> $ret)? {
                    $generic::<$crate::math::simd::Fused>($($arg),*)
                }
                if path != $crate::math::simd::SimdPath::Baseline {
                    assert!(path.supported(), "the {} path needs CPU features this CPU lacks", path.name());
                }
                match path {
                    // SAFETY: checked above that the CPU has the path's features.
                    $crate::math::simd::SimdPath::Avx512 => return unsafe { avx512($($arg),*) },
                    $crate::math::simd::SimdPath::Avx2 => return unsafe { avx2($($arg),*) },
                    $crate::math::simd::SimdPath::Baseline => {}
                }
            }
            $generic::<$crate::math::simd::Plain>($($arg),*)
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_detection_is_supported() {
        for p in SimdPath::ALL {
            assert_eq!(SimdPath::from_name(p.name()), Some(p));
        }
        assert_eq!(SimdPath::from_name("sse9"), None);
        assert!(SimdPath::detect().supported());
        assert!(SimdPath::Baseline.supported());
    }

    #[test]
    fn fused_and_plain_dots_agree_to_round_off() {
        for n in [0, 1, 3, 4, 7, 22, 23, 46] {
            let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos()).collect();
            let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let (plain, fused) = (dot::<Plain>(&a, &b), dot::<Fused>(&a, &b));
            let size: f64 = a.iter().zip(&b).map(|(x, y)| (x * y).abs()).sum();
            assert!((plain - exact).abs() <= 1e-15 * size.max(1.0), "{n}");
            assert!((fused - exact).abs() <= 1e-15 * size.max(1.0), "{n}");
        }
    }
}
