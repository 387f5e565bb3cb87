//! The physically based contact stiffness (SPEC §7.3, Johnson, *Contact
//! Mechanics*, 1985, §4.2): two elastic cylinders crossing at 90° touch
//! like a sphere of radius R_e = √(R_1 R_2) on a plane, F = (4/3) E* √R_e
//! δ^{3/2}, with E* = [(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂]⁻¹.
//!
//! The line law's resultant at a 90° crossing is, for small δ,
//! F ≈ (4/3) ε_L √(2 R_s) δ^{3/2} (R_s = R_wire + R_rod; exact form in
//! SPEC §7.2.4), so ε_L = E* √(R_e / (2 R_s)) reproduces Hertz there. The
//! line law is used rather than a point law at the deepest point because it
//! stays meaningful when the wire wraps the rod (a point law has no
//! equivalent radius for a wrap) and keeps the force a smooth function of
//! the configuration. At other crossing angles Hertz's contact ellipse
//! changes R_e by a factor that stays within ≈ ±15 % from 90° down to 30°
//! (Johnson, Fig. 4.5); the line law's own angle dependence is not matched.
//! A stranded conductor is softer than solid metal, so E* from the wire's
//! smeared modulus is an upper bound on the stiffness.

/// ε_L (N/m²) matching Hertz at a 90° crossing, from (E, ν) of the rod and
/// of the wire's outer layer and their radii (m).
pub fn hertz_line_stiffness(
    rod: (f64, f64),
    wire: (f64, f64),
    wire_radius: f64,
    rod_radius: f64,
) -> f64 {
    let compliance = |(e, nu): (f64, f64)| (1.0 - nu * nu) / e;
    let e_star = 1.0 / (compliance(rod) + compliance(wire));
    let r_e = (wire_radius * rod_radius).sqrt();
    e_star * (r_e / (2.0 * (wire_radius + rod_radius))).sqrt()
}
