//! One law's stiffness that matches another's force at a 90° crossing, so
//! that runs under different laws compare like with like (the accuracy
//! study switches a line-law rod to the surface law with it).

/// The surface law's ε_N (N/m³) whose 90° crossing force equals the line
/// law's with ε_L (N/m²) at a penetration δ* (m), for a wire of radius R_w
/// on a rod of radius R_r (m): for small δ the surface patch carries
/// F ≈ π ε_N √(R_w R_r) δ² and the line F ≈ (4/3) ε_L √(2 R_s) δ^{3/2}
/// (R_s = R_w + R_r, SPEC §7.2), so
/// ε_N = (4/3) ε_L √(2 R_s) / (π √(R_w R_r) √δ*).
pub fn surface_stiffness_matching_line(
    line_stiffness: f64,
    wire_radius: f64,
    rod_radius: f64,
    penetration: f64,
) -> f64 {
    let (rw, rr) = (wire_radius, rod_radius);
    4.0 / 3.0 * line_stiffness * (2.0 * (rw + rr)).sqrt()
        / (std::f64::consts::PI * (rw * rr).sqrt() * penetration.sqrt())
}
