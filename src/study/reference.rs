//! Analytic reference values a study can use instead of a reference run:
//! the cantilever cases of SPEC §8. A scene qualifies when it is
//! a straight cantilever — one clamp at node 0, one point load at the last
//! node, nothing else (no gravity, rods, damping) — with circular layers of
//! St. Venant–Kirchhoff material and ν = 0.

use ancf_core::material::MaterialModel;
use ancf_core::math::vec3::dot;
use ancf_core::model::{Effect, SupportKind};
use ancf_core::scene::{Analysis, Scene};
use ancf_core::section::SectionShape;

/// An analytic tip displacement and where it comes from.
#[derive(Clone, Debug)]
pub struct Analytic {
    /// Tip displacement, m.
    pub displacement: [f64; 3],
    /// What the value is, for the report.
    pub description: String,
}

/// Exact St. Venant–Kirchhoff bar (ν = 0): EA λ(λ² − 1)/2 = F; returns λ − 1.
pub fn svk_bar_strain(ea: f64, f: f64) -> f64 {
    let mut lam = 1.0 + f / ea;
    for _ in 0..60 {
        let g = ea * lam * (lam * lam - 1.0) / 2.0 - f;
        let dg = ea * (3.0 * lam * lam - 1.0) / 2.0;
        lam -= g / dg;
    }
    lam - 1.0
}

/// The analytic tip displacement of `scene`, if it is a cantilever case:
/// * a load along the axis: the exact SVK bar;
/// * a transverse load small enough that the response is linear (tip
///   deflection below 0.2 % of the length: geometric nonlinearity below
///   1e-5 relative): Timoshenko, F L³/(3 ω Σ E_k I_k) + F L/(Σ G_k A_k),
///   with the second-order axial shortening of the tip.
///   The shear term has no correction factor: the element's section field
///   is linear, so its shear strain is uniform over the section (κ = 1);
///   for the SPEC §8 section the term is 6e-4 of the deflection.
pub fn analytic(scene: &Scene) -> Option<Analytic> {
    let m = &scene.model;
    if !matches!(scene.analysis, Analysis::Static { .. }) {
        return None;
    }
    let [support] = m.supports.as_slice() else {
        return None;
    };
    if support.node != 0 || support.kind != SupportKind::Clamp || support.position.is_some() {
        return None;
    }
    let [load] = m.point_loads() else {
        return None;
    };
    if m.beams.len() > 1
        || load.node != m.n_elements
        || m.effects
            .iter()
            .any(|e| !matches!(e, Effect::Elasticity { .. } | Effect::PointLoads(_)))
    {
        return None;
    }
    let section = m.section();
    let SectionShape::Circular { .. } = section.shape else {
        return None;
    };
    let (mut ea, mut ei, mut ga) = (0.0, 0.0, 0.0);
    let mut omega = None;
    for layer in &section.layers {
        let MaterialModel::StVenantKirchhoff {
            youngs_modulus: e,
            poisson_ratio: nu,
            bending_factor: w,
        } = layer.material.model
        else {
            return None;
        };
        if nu != 0.0 || omega.is_some_and(|o| o != w) {
            return None;
        }
        omega = Some(w);
        ea += e * layer.area;
        ei += e * layer.second_moments[0];
        ga += e / 2.0 * layer.area;
    }
    let omega = omega?;
    let length = m.length();
    let axis = m.wire().axis;
    let f = load.force;
    let f_axial = dot(f, axis);
    let f_t = [
        f[0] - f_axial * axis[0],
        f[1] - f_axial * axis[1],
        f[2] - f_axial * axis[2],
    ];
    let f_t_norm = dot(f_t, f_t).sqrt();
    let scale = f_axial.abs().max(f_t_norm);
    if f_t_norm <= 1e-12 * scale {
        let d = svk_bar_strain(ea, f_axial) * length;
        return Some(Analytic {
            displacement: axis.map(|a| a * d),
            description: format!(
                "exact St. Venant–Kirchhoff bar: Σ E_k A_k λ(λ² − 1)/2 = F, elongation {d:.6e} m"
            ),
        });
    }
    if f_axial.abs() <= 1e-12 * scale {
        let bending = length.powi(3) / (3.0 * omega * ei);
        let shear = length / ga;
        let d = f_t_norm * (bending + shear);
        if d <= 2e-3 * length {
            // The tip also moves back along the axis by ½∫w′² dx = (3/5) δ²/L
            // (the cubic deflection curve): 8e-4 of δ for SPEC §8, larger than
            // the errors the study resolves.
            let shortening = 0.6 * d * d / length;
            let mut displacement = f_t.map(|x| x * (bending + shear));
            for (u, a) in displacement.iter_mut().zip(axis) {
                *u -= shortening * a;
            }
            return Some(Analytic {
                displacement,
                description: format!(
                    "Timoshenko beam: F L³/(3 ω Σ E_k I_k) + F L/(Σ G_k A_k) = {d:.6e} m \
                     (Euler–Bernoulli alone: {:.6e} m), and the tip's axial shortening (3/5) δ²/L = {shortening:.4e} m",
                    f_t_norm * bending
                ),
            });
        }
    }
    None
}
