//! A tube's cross-section check as a steel designer makes it (EN 1993-1-1
//! §6.2): the resistance of a circular hollow section (or a solid circle)
//! of yield stress f_y to bending with axial force, and the utilization
//! M_Ed / M_N,Rd of the internal loads a run computes.
//!
//! * Class (Table 5.2, tubes in bending and compression): d/t ≤ 50 ε² is
//!   class 1, ≤ 70 ε² class 2, ≤ 90 ε² class 3, ε² = 235 MPa / f_y; a
//!   solid circle is class 1.
//! * Class 1–2 (§6.2.5, §6.2.9.1): M_pl,Rd = W_pl f_y / γ_M0, W_pl =
//!   (D³ − d³) / 6, reduced for the axial force n = N_Ed / N_pl,Rd as
//!   M_N,Rd = M_pl,Rd (1 − n^1.7): the interaction for circular hollow
//!   sections that the UK National Annex and SCI P363 give with §6.2.9.1,
//!   within 2.1 % of M_pl of the exact fully plastic thin ring, M / M_pl =
//!   cos(π n / 2) (below it for n < 0.7, above by at most 0.8 % beyond).
//! * Class 3 (§6.2.9.2, with §6.2.1(7)'s linear sum): the elastic
//!   resistance, utilization N_Ed / N_pl,Rd + M_Ed / (W_el f_y).
//! * Class 4 sections (local buckling, EN 1993-1-6) are not checked.
//!
//! γ_M0 = 1.0 (the standard's recommended value). Shear and torsion are
//! left out: the wire's blows load a tube far below half its plastic shear
//! resistance, where §6.2.10 reduces nothing.

use std::f64::consts::PI;

/// γ_M0, the partial factor for the resistance of cross-sections.
pub const GAMMA_M0: f64 = 1.0;

/// A circular section's design resistances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularResistance {
    /// Its class (1 … 3).
    pub class: u8,
    /// N_pl,Rd = A f_y / γ_M0, N.
    pub axial: f64,
    /// M_pl,Rd (class 1–2) or M_el,Rd (class 3), N m.
    pub moment: f64,
}

impl CircularResistance {
    /// The resistances of a tube of outer diameter `d_outer` and inner
    /// diameter `d_inner` (0: a solid circle), m, of yield stress `fy` Pa;
    /// `None` for a class 4 tube (or a degenerate one).
    pub fn new(d_outer: f64, d_inner: f64, fy: f64) -> Option<Self> {
        if !(d_outer > d_inner && d_inner >= 0.0 && fy > 0.0) {
            return None;
        }
        let t = 0.5 * (d_outer - d_inner);
        let eps2 = 235e6 / fy;
        let slenderness = d_outer / t;
        let class = if d_inner == 0.0 || slenderness <= 50.0 * eps2 {
            1
        } else if slenderness <= 70.0 * eps2 {
            2
        } else if slenderness <= 90.0 * eps2 {
            3
        } else {
            return None;
        };
        let area = 0.25 * PI * (d_outer * d_outer - d_inner * d_inner);
        let modulus = if class <= 2 {
            (d_outer.powi(3) - d_inner.powi(3)) / 6.0
        } else {
            PI * (d_outer.powi(4) - d_inner.powi(4)) / (32.0 * d_outer)
        };
        Some(CircularResistance {
            class,
            axial: area * fy / GAMMA_M0,
            moment: modulus * fy / GAMMA_M0,
        })
    }

    /// The bending resistance under axial force `n_ed` (N, either sign):
    /// M_N,Rd, N m (0 once the axial force alone exhausts the section).
    pub fn moment_with_axial(&self, n_ed: f64) -> f64 {
        let n = (n_ed.abs() / self.axial).min(1.0);
        if self.class <= 2 {
            self.moment * (1.0 - n.powf(1.7))
        } else {
            self.moment * (1.0 - n)
        }
    }

    /// The utilization of bending moment `m_ed` (N m) with axial force
    /// `n_ed` (N): M_Ed / M_N,Rd (class 1–2) or N/N_Rd + M/M_Rd (class 3);
    /// ≤ 1 holds. Where the axial force alone exceeds the section, the
    /// linear sum, which is then above 1 whatever the moment.
    pub fn utilization(&self, n_ed: f64, m_ed: f64) -> f64 {
        let n = n_ed.abs() / self.axial;
        if self.class <= 2 && n < 1.0 {
            m_ed.abs() / self.moment_with_axial(n_ed)
        } else {
            n + m_ed.abs() / self.moment
        }
    }
}

/// The resistances of a beam's section when it is a single circular layer
/// (a tube or a solid circle) of a material with a yield stress; `None`
/// otherwise (layered conductors, rectangles, no f_y, class 4).
pub fn section_resistance(section: &crate::section::Section) -> Option<CircularResistance> {
    let crate::section::SectionShape::Circular { radii } = &section.shape else {
        return None;
    };
    let [(inner, outer)] = radii.as_slice() else {
        return None;
    };
    let fy = section.layers.first()?.material.yield_stress?;
    CircularResistance::new(2.0 * outer, 2.0 * inner, fy)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EN 39's scaffold tube Ø 48.3 × 4.0 mm in S235: W_pl = (D³ − d³) / 6
    /// = 7.871e-6 m³, M_pl,Rd = 1.850 kN m, class 1 (d/t = 12.1).
    #[test]
    fn the_scaffold_tube_has_its_handbook_resistance() {
        let r = CircularResistance::new(0.0483, 0.0403, 235e6).unwrap();
        assert_eq!(r.class, 1);
        assert!((r.moment - 1849.7).abs() < 0.5, "{}", r.moment);
        let area = 0.25 * PI * (0.0483f64.powi(2) - 0.0403f64.powi(2));
        assert!((r.axial - area * 235e6).abs() < 1e-6 * r.axial);
        assert_eq!(r.utilization(0.0, 0.5 * r.moment), 0.5);
    }

    /// The interaction follows the exact thin ring's cos(π n / 2) within
    /// 2.1 % of M_pl.
    #[test]
    fn the_axial_reduction_follows_the_thin_ring() {
        let r = CircularResistance::new(0.1, 0.098, 235e6 * 0.2).unwrap();
        assert!(r.class <= 2);
        for k in 0..=20 {
            let n = k as f64 / 20.0;
            let ours = r.moment_with_axial(n * r.axial) / r.moment;
            let exact = (0.5 * PI * n).cos();
            assert!((exact - ours).abs() < 0.021, "n = {n}: {ours} vs {exact}");
        }
    }

    #[test]
    fn classes_follow_the_slenderness_limits() {
        // D/t at f_y = 235 MPa: 50, 70, 90 are the class limits.
        let class = |dt: f64| CircularResistance::new(1.0, 1.0 - 2.0 / dt, 235e6).map(|r| r.class);
        assert_eq!(class(49.0), Some(1));
        assert_eq!(class(69.0), Some(2));
        assert_eq!(class(89.0), Some(3));
        assert_eq!(class(91.0), None);
        assert_eq!(CircularResistance::new(0.05, 0.0, 355e6).unwrap().class, 1);
        // Class 3: the elastic modulus π (D⁴ − d⁴) / 32 D.
        let r = CircularResistance::new(1.0, 1.0 - 2.0 / 80.0, 235e6).unwrap();
        let w_el = PI * (1.0 - (1.0f64 - 2.0 / 80.0).powi(4)) / 32.0;
        assert!((r.moment - w_el * 235e6).abs() < 1e-9 * r.moment);
        assert!((r.utilization(0.5 * r.axial, 0.25 * r.moment) - 0.75).abs() < 1e-12);
    }
}
