//! Cross sections: concentric circular layers (solid core and rings), each
//! with its own material, or the classical rectangle. A section owns its
//! quadrature points, the laws each layer integrates, and the density
//! moments the mass matrix needs.

use crate::material::{LayerLaws, Material};
use crate::math::quadrature::{SectionPoint, rectangle_rule, ring_rule, ring_rule_with};
use std::f64::consts::PI;

/// One layer of a section, ready for integration.
#[derive(Clone, Debug)]
pub struct SectionLayer {
    /// Quadrature points of this layer (m, m²).
    pub points: Vec<SectionPoint>,
    /// Area of the layer, m².
    pub area: f64,
    /// ∫ y² dA and ∫ z² dA over the layer, m⁴.
    pub second_moments: [f64; 2],
    /// The layer's material.
    pub material: Material,
    /// Its laws on the section points and on the centerline.
    pub laws: LayerLaws,
}

/// Shape of a section, as given by the user.
#[derive(Clone, Debug, PartialEq)]
pub enum SectionShape {
    /// Concentric layers listed from the centre out: (inner radius, outer
    /// radius) in m; the first inner radius is 0 for a solid core.
    Circular {
        /// (inner, outer) radius of each layer, m.
        radii: Vec<(f64, f64)>,
    },
    /// Width (along y) and height (along z), m.
    Rectangular {
        /// Along y, m.
        width: f64,
        /// Along z, m.
        height: f64,
    },
}

/// Saint-Venant's torsion constant J (m⁴) of a `width` × `height`
/// rectangle: J = β b h³, b ≥ h, with the exact series β = (1/3)(1 − (192
/// h / π⁵ b) Σ_{n odd} tanh(n π b / 2h) / n⁵) (Timoshenko & Goodier,
/// *Theory of Elasticity*, §109), summed until its terms fall below 1e-16
/// (the square: J = 0.1406 a⁴).
pub fn saint_venant_torsion(width: f64, height: f64) -> f64 {
    let (b, h) = if width >= height {
        (width, height)
    } else {
        (height, width)
    };
    let pi = std::f64::consts::PI;
    let mut sum = 0.0;
    let mut n = 1.0f64;
    loop {
        let term = (n * pi * b / (2.0 * h)).tanh() / n.powi(5);
        sum += term;
        if term < 1e-16 {
            break;
        }
        n += 2.0;
    }
    (1.0 - 192.0 * h / (pi.powi(5) * b) * sum) / 3.0 * b * h.powi(3)
}

/// A cross section with its quadrature.
#[derive(Clone, Debug)]
pub struct Section {
    /// Circular layers or a rectangle.
    pub shape: SectionShape,
    /// The layers, from the centre out.
    pub layers: Vec<SectionLayer>,
    /// Ring-rule order n per layer (circular) or points per direction (rectangular).
    pub order: usize,
}

/// Density moments of a section, the mass matrix's section factors:
/// The outer radius of a `width` × `height` rectangle (m): its half diagonal.
pub fn rectangle_outer_radius(width: f64, height: f64) -> f64 {
    0.5 * width.hypot(height)
}

/// `m[a][b] = Σ ρ_k ∫ m_a m_b dA` with m = (1, y, z), in kg/m, kg, kg·m.
pub type DensityMoments = [[f64; 3]; 3];

/// The ring-rule order (or points per direction) of a solid circle or
/// rectangle whose material yields, at least: a yielding section's stress
/// has kinks between the points, and order 8 leaves a solid circle's moment
/// 1.1 % low at ten times the yield curvature where 12 is within 0.5 %
/// (`ancf-core/tests/beam_plasticity.rs`).
pub const PLASTIC_LAYER_ORDER: usize = 12;

/// The angles over a half turn of a yielding ring (a tube's wall), at
/// least, with [`PLASTIC_RING_RADIAL`] nodes through the wall: its stress
/// varies little through a wall and has kinks around it. 16 angles keep a
/// tube's moment within 0.4 % of the closed form at any curvature, with
/// 64 points where the order-12 rule takes 144 for 0.55 %.
pub const PLASTIC_RING_ANGLES: usize = 16;

/// Signed-radius nodes of a yielding ring: two through each side's wall.
pub const PLASTIC_RING_RADIAL: usize = 4;

/// The points of a layer r1 ≤ ρ ≤ r2 of `material` when the section asks
/// for `order`: the ring rule, or for a yielding layer the rules above.
fn layer_points(material: &Material, order: usize, r1: f64, r2: f64) -> Vec<SectionPoint> {
    match (material.is_plastic(), r1 > 0.0) {
        (false, _) => ring_rule(order, r1, r2),
        (true, true) => ring_rule_with(PLASTIC_RING_RADIAL, order.max(PLASTIC_RING_ANGLES), r1, r2),
        (true, false) => ring_rule(order.max(PLASTIC_LAYER_ORDER), r1, r2),
    }
}

/// The points per direction of a rectangle of `material`.
fn layer_order(material: &Material, order: usize) -> usize {
    match material.is_plastic() {
        true => order.max(PLASTIC_LAYER_ORDER),
        false => order,
    }
}

impl Section {
    /// Concentric circular layers, each `(inner, outer, material)`, integrated
    /// with the ring rule of order `order` (exact to degree 2·order − 1).
    pub fn circular(layers: &[(f64, f64, Material)], order: usize) -> Self {
        let layers_out = layers
            .iter()
            .map(|(r1, r2, m)| {
                let i = PI * (r2.powi(4) - r1.powi(4)) / 4.0;
                SectionLayer {
                    points: layer_points(m, order, *r1, *r2),
                    area: PI * (r2 * r2 - r1 * r1),
                    second_moments: [i, i],
                    laws: m.layer_laws(),
                    material: m.clone(),
                }
            })
            .collect();
        Section {
            shape: SectionShape::Circular {
                radii: layers.iter().map(|(a, b, _)| (*a, *b)).collect(),
            },
            layers: layers_out,
            order,
        }
    }

    /// A rectangle of one material with `order × order` Gauss–Legendre points.
    pub fn rectangular(width: f64, height: f64, material: Material, order: usize) -> Self {
        let layer = SectionLayer {
            points: {
                let n = layer_order(&material, order);
                rectangle_rule(n, n, width, height)
            },
            area: width * height,
            second_moments: [height * width.powi(3) / 12.0, width * height.powi(3) / 12.0],
            laws: material.layer_laws(),
            material,
        };
        Section {
            shape: SectionShape::Rectangular { width, height },
            layers: vec![layer],
            order,
        }
    }

    /// Outer radius (circular) or half diagonal (rectangular), m.
    pub fn outer_radius(&self) -> f64 {
        match &self.shape {
            SectionShape::Circular { radii } => radii.last().map_or(0.0, |r| r.1),
            SectionShape::Rectangular { width, height } => rectangle_outer_radius(*width, *height),
        }
    }

    /// Σ ρ_k ∫ m_a m_b dA with m = (1, y, z). Both shapes are symmetric about
    /// y and z, so only the diagonal remains.
    pub fn density_moments(&self) -> DensityMoments {
        let mut m = [[0.0; 3]; 3];
        for l in &self.layers {
            let rho = l.material.density;
            m[0][0] += rho * l.area;
            m[1][1] += rho * l.second_moments[0];
            m[2][2] += rho * l.second_moments[1];
        }
        m
    }

    /// Axial stiffness EA = Σ E_k A_k (N), small-strain.
    pub fn axial_stiffness(&self) -> f64 {
        self.layers
            .iter()
            .map(|l| l.material.model.small_strain_youngs_modulus() * l.area)
            .sum()
    }

    /// Bending stiffness about y: EI = Σ E_k ∫z² dA (N m²), small-strain.
    pub fn bending_stiffness(&self) -> f64 {
        self.layers
            .iter()
            .map(|l| l.material.model.small_strain_youngs_modulus() * l.second_moments[1])
            .sum()
    }

    /// Mass per unit length, kg/m.
    pub fn mass_per_length(&self) -> f64 {
        self.density_moments()[0][0]
    }

    /// Whether any layer uses the Mooney–Rivlin law.
    /// Whether any layer evaluates the Mooney–Rivlin law, over the section
    /// or on the centerline (the locking remedy's remainder).
    pub fn has_mooney_rivlin(&self) -> bool {
        self.layers.iter().any(|l| {
            l.laws.section.is_mooney_rivlin()
                || l.laws
                    .centerline
                    .as_ref()
                    .is_some_and(|c| c.is_mooney_rivlin())
        })
    }
}
