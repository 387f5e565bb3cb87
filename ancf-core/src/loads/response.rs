//! What a structure with one mode feels from a load history: the largest
//! response of an oscillator of frequency f and damping ratio ζ driven by
//! the force, as an equivalent static force (the shock response spectrum
//! with which structural engineers judge pulse loads).
//!
//! A support's force after a conductor breaks is a train of short pulses
//! (axial waves running along the span) on top of a slowly changing
//! tension. Its peak, raw or CFC-filtered, depends on how the pulses are
//! resolved and scatters between nearly equal runs; what a tower whose
//! first mode lies at f takes from them does not: far below the pulses'
//! frequencies it feels their impulse, near them it resonates. The
//! oscillator
//!
//! u'' + 2ζω u' + ω² u = ω² F(t),  ω = 2π f,
//!
//! starts in static equilibrium with the first sample (u = F(t₀), at rest),
//! so u is the force a spring of the structure's stiffness carries: a
//! constant F gives u = F, a suddenly applied F (from rest at zero) up to
//! 2F when undamped.

/// The largest |u| (N) of the oscillator of `frequency` (Hz) and damping
/// ratio `damping` driven by the samples `force` (N) at `time` (s),
/// linear between samples. Newmark's average acceleration (unconditionally
/// stable): its period errs by (ω h)²/12 at a sample spacing h, 0.01 % at
/// 50 Hz with h = 0.1 ms.
pub fn peak_response(time: &[f64], force: &[f64], frequency: f64, damping: f64) -> f64 {
    response(time, force, frequency, damping).fold(0.0, |peak, u| peak.max(u.abs()))
}

/// The largest |u| (N) of the vector oscillator driven by a force's three
/// components `force` (N, each sampled at `time`, s): the oscillators of
/// the components run side by side and their outputs make one vector, so
/// its peak is a magnitude, comparable with a force's |F|.
pub fn peak_response_magnitude(
    time: &[f64],
    force: [&[f64]; 3],
    frequency: f64,
    damping: f64,
) -> f64 {
    let [x, y, z] = force.map(|f| response(time, f, frequency, damping));
    (x.zip(y).zip(z))
        .map(|((x, y), z)| (x * x + y * y + z * z).sqrt())
        .fold(0.0, f64::max)
}

/// The oscillator's u (N) at each sample of `time`, as [`peak_response`]
/// describes (empty when `force` is).
fn response<'a>(
    time: &'a [f64],
    force: &'a [f64],
    frequency: f64,
    damping: f64,
) -> impl Iterator<Item = f64> + 'a {
    let w = 2.0 * std::f64::consts::PI * frequency;
    let (w2, c) = (w * w, 2.0 * damping * w);
    let f0 = force.first().copied();
    let (mut u, mut v, mut a) = (f0.unwrap_or(0.0), 0.0, 0.0);
    let steps = (time.windows(2).zip(force.get(1..).unwrap_or(&[]))).map(move |(t, f)| {
        let h = t[1] - t[0];
        let (up, vp) = (u + h * v + 0.25 * h * h * a, v + 0.5 * h * a);
        a = (w2 * (f - up) - c * vp) / (1.0 + 0.5 * h * c + 0.25 * h * h * w2);
        (u, v) = (up + 0.25 * h * h * a, vp + 0.5 * h * a);
        u
    });
    f0.into_iter().chain(steps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn grid(h: f64, end: f64) -> Vec<f64> {
        (0..=(end / h).round() as usize)
            .map(|k| k as f64 * h)
            .collect()
    }

    #[test]
    fn a_constant_force_is_carried_as_it_is() {
        let t = grid(1e-3, 1.0);
        let f = vec![-4.4e3; t.len()];
        assert_eq!(peak_response(&t, &f, 7.0, 0.02), 4.4e3);
        assert_eq!(peak_response(&[], &[], 7.0, 0.02), 0.0);
    }

    /// A force applied suddenly from zero: 2F undamped, 1 + exp(−ζπ/√(1−ζ²))
    /// times F with damping (the first overshoot), to the integrator's
    /// (ω h)² error.
    #[test]
    fn a_suddenly_applied_force_overshoots_as_the_oscillator_does() {
        let (h, f_hz) = (1e-4, 10.0);
        let t = grid(h, 0.5);
        let mut f = vec![1e3; t.len()];
        f[0] = 0.0;
        // The ramp over the first sample shortens the rise by h/2 (ω h ≪ 1).
        for zeta in [0.0, 0.05, 0.2] {
            let exact = 1e3 * (1.0 + (-zeta * PI / (1.0 - zeta * zeta).sqrt()).exp());
            let got = peak_response(&t, &f, f_hz, zeta);
            assert!(
                (got / exact - 1.0).abs() < 1e-4,
                "ζ = {zeta}: {got} against {exact}"
            );
        }
    }

    /// At resonance the steady amplitude is F/(2ζ); a short pulse of
    /// impulse I far above the frequency gives ω I (the impulse, not the
    /// peak, is what the oscillator feels).
    #[test]
    fn resonance_and_a_short_pulse_give_their_closed_forms() {
        let (h, f_hz, zeta) = (1e-4, 5.0, 0.02);
        let w = 2.0 * PI * f_hz;
        // 40 time constants 1/(ζω): the build-up 1 − e^(−ζωt) is complete.
        let t = grid(h, 40.0 / (zeta * w));
        let f: Vec<f64> = t.iter().map(|t| 100.0 * (w * t).sin()).collect();
        let got = peak_response(&t, &f, f_hz, zeta);
        let exact = 100.0 / (2.0 * zeta);
        assert!((got / exact - 1.0).abs() < 2e-3, "{got} against {exact}");

        // A 1 ms half sine of 1 kN peak (I = 2/π N s) on a 1 Hz oscillator,
        // undamped: ω I.
        let t = grid(1e-5, 1.0);
        let f: Vec<f64> = (t.iter())
            .map(|&t| {
                if t < 1e-3 {
                    1e3 * (PI * t / 1e-3).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let impulse = 2.0 / PI;
        let got = peak_response(&t, &f, 1.0, 0.0);
        let exact = 2.0 * PI * impulse;
        assert!((got / exact - 1.0).abs() < 1e-3, "{got} against {exact}");
    }

    /// The vector oscillator's peak is a magnitude: the same for a force
    /// along an axis and along a diagonal, where the largest component's
    /// peak is only 1/√3 of it.
    #[test]
    fn the_vector_peak_does_not_depend_on_the_force_direction() {
        let t = grid(1e-4, 0.5);
        let mut along: Vec<f64> = vec![1e3; t.len()];
        along[0] = 0.0;
        let zero = vec![0.0; t.len()];
        let axis = peak_response_magnitude(&t, [&along, &zero, &zero], 10.0, 0.05);
        assert_eq!(axis, peak_response(&t, &along, 10.0, 0.05));
        let third: Vec<f64> = along.iter().map(|f| f / 3f64.sqrt()).collect();
        let diagonal = peak_response_magnitude(&t, [&third, &third, &third], 10.0, 0.05);
        assert!(
            (diagonal / axis - 1.0).abs() < 1e-12,
            "{diagonal} against {axis}"
        );
        let component = peak_response(&t, &third, 10.0, 0.05);
        assert!((component * 3f64.sqrt() / axis - 1.0).abs() < 1e-12);
    }
}
