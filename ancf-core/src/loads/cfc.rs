//! The channel frequency class (CFC) filter of SAE J211-1 / ISO 6487, with
//! which crash and impact tests report forces (SPEC §7.5): a 2-pole
//! Butterworth low-pass run forward and then backward, so the result has no
//! phase shift and 4 poles; −3 dB at 5/3 · CFC Hz (CFC 600: 1000 Hz), unit
//! gain at DC, so a filtered pulse keeps its impulse.

/// The −3 dB frequency of a channel class, Hz.
pub fn corner_frequency(cfc: f64) -> f64 {
    5.0 / 3.0 * cfc
}

/// Filters samples taken every `dt` seconds with class `cfc` (Hz).
///
/// Each pass starts from the steady state of its first sample (the
/// standard's zero padding when the signal starts at zero, as a contact
/// force does, and no start-up transient when it does not).
pub fn cfc_filter(samples: &[f64], dt: f64, cfc: f64) -> Vec<f64> {
    let wd = 2.0 * std::f64::consts::PI * cfc * 2.0775;
    let wa = (wd * dt / 2.0).tan();
    let s2 = std::f64::consts::SQRT_2;
    let d = 1.0 + s2 * wa + wa * wa;
    let a0 = wa * wa / d;
    let (a1, a2) = (2.0 * a0, a0);
    let b1 = -2.0 * (wa * wa - 1.0) / d;
    let b2 = (-1.0 + s2 * wa - wa * wa) / d;
    let pass = |x: &mut dyn Iterator<Item = f64>| -> Vec<f64> {
        let mut out = Vec::with_capacity(samples.len());
        let (mut x1, mut x2, mut y1, mut y2) = (f64::NAN, 0.0, 0.0, 0.0);
        for xt in x {
            if x1.is_nan() {
                (x1, x2, y1, y2) = (xt, xt, xt, xt);
            }
            let yt = a0 * xt + a1 * x1 + a2 * x2 + b1 * y1 + b2 * y2;
            (x2, x1, y2, y1) = (x1, xt, y1, yt);
            out.push(yt);
        }
        out
    };
    let forward = pass(&mut samples.iter().copied());
    let mut backward = pass(&mut forward.iter().rev().copied());
    backward.reverse();
    backward
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gain of the filter at frequency f (Hz), measured on a long sine.
    fn gain(f: f64, dt: f64, cfc: f64) -> f64 {
        let n = (20.0 / (f * dt)) as usize;
        let x: Vec<f64> = (0..n)
            .map(|k| (2.0 * std::f64::consts::PI * f * k as f64 * dt).sin())
            .collect();
        let y = cfc_filter(&x, dt, cfc);
        // Amplitude in the middle, away from both ends.
        let mid = &y[n / 4..3 * n / 4];
        let xm = &x[n / 4..3 * n / 4];
        let rms = |v: &[f64]| (v.iter().map(|a| a * a).sum::<f64>() / v.len() as f64).sqrt();
        rms(mid) / rms(xm)
    }

    #[test]
    fn unit_gain_at_dc_and_minus_3_db_at_the_corner() {
        let (dt, cfc) = (1e-5, 600.0);
        let y = cfc_filter(&vec![3.5; 1000], dt, cfc);
        assert!(y.iter().all(|v| (v - 3.5).abs() < 1e-12), "DC gain is 1");
        let g = gain(corner_frequency(cfc), dt, cfc);
        let db = 20.0 * g.log10();
        assert!((db + 3.0).abs() < 0.3, "−3 dB at 5/3 CFC: {db:.3} dB");
        assert!(gain(100.0, dt, cfc) > 0.995, "passes the band");
        assert!(gain(10_000.0, dt, cfc) < 0.02, "stops far above the corner");
    }

    #[test]
    fn a_pulse_keeps_its_impulse_and_loses_its_spike() {
        let dt = 1e-5;
        // A 2 ms half-sine pulse of 1 kN with a one-sample 5 kN spike on top.
        let mut x: Vec<f64> = (0..2000)
            .map(|k| {
                let t = k as f64 * dt - 5e-3;
                if (0.0..2e-3).contains(&t) {
                    1e3 * (std::f64::consts::PI * t / 2e-3).sin()
                } else {
                    0.0
                }
            })
            .collect();
        x[600] += 5e3;
        let y = cfc_filter(&x, dt, 600.0);
        let (ix, iy): (f64, f64) = (x.iter().sum::<f64>() * dt, y.iter().sum::<f64>() * dt);
        assert!((ix - iy).abs() < 1e-9 * ix, "impulse {ix} vs {iy}");
        let peak = y.iter().cloned().fold(0.0, f64::max);
        assert!(
            peak < 1.2e3 && peak > 0.9e3,
            "spike removed, pulse kept: {peak}"
        );
    }
}
