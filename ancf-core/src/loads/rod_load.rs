//! A rod's load as impact engineers report it (SPEC §7.5): the force the
//! wire puts on the rod at every time step, its raw peak, its CFC-filtered
//! peak, impulse and contact duration.

use crate::loads::cfc::{cfc_filter, corner_frequency};
use crate::math::vec3::norm;

/// Default channel frequency class: CFC 60 (−3 dB at 100 Hz), the class
/// SAE J211-1 gives barrier face forces — the load an impacting structure
/// puts on a rigid obstacle, as here. It keeps a pulse's impulse and the
/// frequencies a frame responds to. On the impact scene the CFC 60 peak
/// converges with the mesh where the CFC 600 peak does not: the penalty
/// contact's content above a few hundred Hz depends on how finely bending
/// waves are resolved (docs/accuracy/wire_rod_impact). Choose CFC 180 or 600
/// for a structure that responds above 100 Hz, with a mesh that resolves it.
pub const DEFAULT_CFC: f64 = 60.0;

/// A load history's CFC-filtered |F| on a uniform grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Filtered {
    /// The channel frequency class, Hz.
    pub cfc: f64,
    /// Grid times, s.
    pub time: Vec<f64>,
    /// |F| filtered, N.
    pub force: Vec<f64>,
}

impl Filtered {
    /// The filtered |F| at time `t` (s), linear between grid points,
    /// constant beyond the ends.
    pub fn at(&self, t: f64) -> f64 {
        let (xs, ys) = (&self.time, &self.force);
        match xs.partition_point(|&v| v <= t) {
            0 => ys.first().copied().unwrap_or(0.0),
            k if k >= xs.len() => ys.last().copied().unwrap_or(0.0),
            k => {
                let s = (t - xs[k - 1]) / (xs[k] - xs[k - 1]);
                (1.0 - s) * ys[k - 1] + s * ys[k]
            }
        }
    }
}

/// The force on one rod at every completed time step.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LoadHistory {
    /// Step end times, s.
    pub time: Vec<f64>,
    /// Resultant force on the rod (normal + friction), N.
    pub force: Vec<[f64; 3]>,
}

/// Summary of a load history.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RodLoad {
    /// Largest |F| over the steps, N.
    pub peak_force: f64,
    /// Its time, s.
    pub peak_time: f64,
    /// Largest |F| of the CFC-filtered force components, N.
    pub filtered_peak_force: f64,
    /// Its time, s.
    pub filtered_peak_time: f64,
    /// ∫ |F| dt, N s.
    pub impulse: f64,
    /// Time during which the rod carries a force, s.
    pub contact_duration: f64,
    /// The channel frequency class used, Hz.
    pub cfc: f64,
    /// When the rod is first touched, s (`None`: never).
    #[serde(default)]
    pub first_contact_time: Option<f64>,
    /// The first impact — the [`FIRST_IMPACT_WINDOW`] from the first
    /// contact — alone: its filtered peak |F| (N) …
    #[serde(default)]
    pub first_impact_filtered_peak: f64,
    /// … and its impulse ∫ |F| dt (N s). What a wire does after its first
    /// blow (bouncing, draping, a whipping free end) can depend on details
    /// a mesh or a time step resolves differently; the first blow converges
    /// first (docs/accuracy/span_break_frame).
    #[serde(default)]
    pub first_impact_impulse: f64,
}

/// The length of a rod's first impact in [`RodLoad`], s: from the first
/// contact on (the accuracy study's contact window too).
pub const FIRST_IMPACT_WINDOW: f64 = 0.1;

impl LoadHistory {
    /// Record the force `f` (N) at the end of a step ending at `t` (s).
    pub fn push(&mut self, t: f64, f: [f64; 3]) {
        self.time.push(t);
        self.force.push(f);
    }

    /// Drop the steps after time `t` (a resumed run continues from there).
    pub fn truncate_after(&mut self, t: f64) {
        let n = self.time.partition_point(|&x| x <= t);
        self.time.truncate(n);
        self.force.truncate(n);
    }

    /// The CFC-filtered |F| (class `cfc`, Hz). Each component is resampled
    /// linearly at a spacing that divides the time step and samples ≥ 10×
    /// the filter's −3 dB frequency, filtered, and recombined.
    pub fn filtered(&self, cfc: f64) -> Filtered {
        let n = self.time.len();
        if n < 2 {
            return Filtered {
                cfc,
                time: self.time.clone(),
                force: self.force.iter().map(|f| norm(*f)).collect(),
            };
        }
        let h = self
            .time
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|d| *d > 0.0)
            .fold(f64::INFINITY, f64::min);
        let sub = (h * 10.0 * corner_frequency(cfc)).ceil().max(1.0);
        let dt = h / sub;
        let (t0, t1) = (self.time[0], self.time[n - 1]);
        let m = ((t1 - t0) / dt + 1e-9).floor() as usize + 1;
        let grid: Vec<f64> = (0..m).map(|j| t0 + j as f64 * dt).collect();
        let mut k = 0;
        let resampled: Vec<[f64; 3]> = grid
            .iter()
            .map(|&t| {
                while k + 2 < n && self.time[k + 1] < t {
                    k += 1;
                }
                let (ta, tb) = (self.time[k], self.time[k + 1]);
                let s = ((t - ta) / (tb - ta)).clamp(0.0, 1.0);
                std::array::from_fn(|c| (1.0 - s) * self.force[k][c] + s * self.force[k + 1][c])
            })
            .collect();
        let comps: [Vec<f64>; 3] = std::array::from_fn(|c| {
            let x: Vec<f64> = resampled.iter().map(|f| f[c]).collect();
            cfc_filter(&x, dt, cfc)
        });
        let mags = (0..m)
            .map(|j| norm([comps[0][j], comps[1][j], comps[2][j]]))
            .collect();
        Filtered {
            cfc,
            time: grid,
            force: mags,
        }
    }

    /// ∫ |F| dt (N s) over the steps that end in [`from`, `to`] (s), each
    /// step's |F| at its end times its length (the first step, whose start
    /// is not recorded, is left out). From a first contact time on, the
    /// step that made the contact counts, as in a rod's first impact.
    pub fn impulse_between(&self, from: f64, to: f64) -> f64 {
        self.time
            .windows(2)
            .zip(&self.force[1..])
            .filter(|(t, _)| t[1] >= from && t[1] <= to)
            .map(|(t, f)| norm(*f) * (t[1] - t[0]))
            .sum()
    }

    /// Peaks, impulse and duration; the filtered peak from `filtered`, this
    /// history's [`LoadHistory::filtered`].
    pub fn summary(&self, filtered: &Filtered) -> RodLoad {
        let mut load = RodLoad {
            cfc: filtered.cfc,
            ..Default::default()
        };
        let mut prev = None;
        for (t, f) in self.time.iter().zip(&self.force) {
            let mag = norm(*f);
            if mag > load.peak_force {
                load.peak_force = mag;
                load.peak_time = *t;
            }
            // The step's length (the first step's is not known: it is the next one's).
            let dt = match prev {
                Some(p) => t - p,
                None => self.time.get(1).map_or(0.0, |t1| t1 - t),
            };
            load.impulse += mag * dt;
            if mag > 0.0 {
                load.contact_duration += dt;
                load.first_contact_time.get_or_insert(*t);
            }
            if let Some(t1) = load.first_contact_time
                && *t <= t1 + FIRST_IMPACT_WINDOW
            {
                load.first_impact_impulse += mag * dt;
            }
            prev = Some(*t);
        }
        for (t, m) in filtered.time.iter().zip(&filtered.force) {
            if *m > load.filtered_peak_force {
                load.filtered_peak_force = *m;
                load.filtered_peak_time = *t;
            }
            if let Some(t1) = load.first_contact_time
                && (t1..=t1 + FIRST_IMPACT_WINDOW).contains(t)
            {
                load.first_impact_filtered_peak = load.first_impact_filtered_peak.max(*m);
            }
        }
        load
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps `steps` (every 0.1 ms) of a 3 ms half-sine pulse of `peak` N
    /// along −z starting at `start` s, added to `h`.
    fn push_pulse(
        h: &mut LoadHistory,
        steps: std::ops::RangeInclusive<usize>,
        start: f64,
        peak: f64,
    ) {
        for k in steps {
            let t = k as f64 * 1e-4;
            let tau = t - start;
            let f = if (0.0..3e-3).contains(&tau) {
                peak * (std::f64::consts::PI * tau / 3e-3).sin()
            } else {
                0.0
            };
            h.push(t, [0.0, 0.0, -f]);
        }
    }

    #[test]
    fn impulse_between_two_times_is_the_pulse_inside_them() {
        // Two 3 ms pulses of 2 kN and 1 kN, at 10 ms and 30 ms.
        let mut h = LoadHistory::default();
        push_pulse(&mut h, 1..=250, 0.01, 2e3);
        let mut second = LoadHistory::default();
        push_pulse(&mut second, 251..=400, 0.03, 1e3);
        h.time.extend(second.time);
        h.force.extend(second.force);
        let pulse = |peak: f64| peak * 3e-3 * 2.0 / std::f64::consts::PI;
        let first = h.impulse_between(0.0, 0.02);
        assert!((first - pulse(2e3)).abs() < 2e-3 * pulse(2e3), "{first}");
        let later = h.impulse_between(0.02, 0.04);
        assert!((later - pulse(1e3)).abs() < 2e-3 * pulse(1e3), "{later}");
        let whole = h.summary(&h.filtered(600.0)).impulse;
        assert!((first + later - whole).abs() < 1e-12 * whole);
    }

    #[test]
    fn summary_of_a_half_sine_pulse() {
        // 3 ms half-sine of 2 kN along −z, sampled every 0.1 ms.
        let mut h = LoadHistory::default();
        push_pulse(&mut h, 1..=400, 0.01, 2e3);
        let s = h.summary(&h.filtered(600.0));
        let exact = 2e3 * 3e-3 * 2.0 / std::f64::consts::PI;
        assert!(
            (s.impulse - exact).abs() < 2e-3 * exact,
            "impulse {} vs {exact}",
            s.impulse
        );
        assert!((s.peak_force - 2e3).abs() < 1.0);
        assert!((s.peak_time - 0.0115).abs() < 1.1e-4);
        assert!(
            (s.contact_duration - 3e-3).abs() < 1.1e-4,
            "{}",
            s.contact_duration
        );
        // A smooth 3 ms pulse is far below the 1 kHz corner: the filter keeps its peak.
        assert!(
            (s.filtered_peak_force - 2e3).abs() < 0.02 * 2e3,
            "{}",
            s.filtered_peak_force
        );
        // One pulse: the first impact is all of it.
        assert_eq!(s.first_contact_time, Some(101.0 * 1e-4));
        assert_eq!(s.first_impact_impulse, s.impulse);
        assert!((s.first_impact_filtered_peak - s.filtered_peak_force).abs() < 1.0);
        // A second, larger blow 0.2 s later counts for the whole run only.
        let mut twice = h.clone();
        push_pulse(&mut twice, 401..=4000, 0.21, 4e3);
        let s2 = twice.summary(&twice.filtered(600.0));
        assert_eq!(s2.first_impact_impulse, s.impulse);
        assert!((s2.impulse - 3.0 * s.impulse).abs() < 2e-3 * s2.impulse);
        assert!((s2.first_impact_filtered_peak - s.filtered_peak_force).abs() < 1.0);
        assert!((s2.filtered_peak_force - 4e3).abs() < 0.02 * 4e3);
        h.truncate_after(0.0105);
        assert_eq!(h.time.len(), 105);
    }
}
