//! The 24-DOF fully parameterized beam element (SPEC §1): shape functions,
//! elastic force and Jacobian, mass matrix and gravity force.
//!
//! Two kernels compute the same elastic force and Jacobian:
//! * the **generated** kernel ([`point_kernel`], written by
//!   `ancf_macros::structured_point_kernel!` from the sparsity of ∇s, with
//!   the axial loop specialised by `build.rs` for the compiled orders);
//! * the **generic** kernel (`point_kernel_generic`), the textbook
//!   B-matrix form with runtime loops, for any other order and as the
//!   reference the generated one is tested against.
//!
//! Which one runs for an element is reported by [`ElementIntegration::kernel_path`].

use crate::material::Law;
use crate::math::quadrature::{Rule1d, gauss_legendre_unit};
use crate::section::Section;
use nalgebra::{SMatrix, Vector6};

/// Element coordinates: [r_A, r_x^A, r_y^A, r_z^A, r_B, r_x^B, r_y^B, r_z^B], m and 1.
pub type ElementVector = [f64; 24];
/// A 24×24 element matrix, row-major.
pub type ElementMatrix = [f64; 576];

/// Signature of a whole-element kernel: adds the elastic force (N) to `q`
/// and, when asked, its Jacobian (N/m) to `k`; returns the strain energy (J).
pub(crate) type ElementKernelFn =
    fn(&ElementIntegration, &ElementVector, &mut ElementVector, Option<&mut ElementMatrix>) -> f64;

mod plastic;
pub(crate) mod preintegration;
mod twist;
pub use plastic::{PlasticGroup, PlasticInput, PlasticStep};

mod generated {
    include!(concat!(env!("OUT_DIR"), "/generated_kernels.rs"));
}
pub use generated::{COMPILED_AXIAL_ORDERS, axial_rule_for as compiled_axial_rule};

/// The axial factor of each shape function, N_i(ξ) (s_i = N_i · m_i(y, z)).
pub(crate) fn axial_factors(xi: f64, l: f64) -> [f64; 8] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        1.0 - xi,
        1.0 - xi,
        3.0 * x2 - 2.0 * x3,
        l * (-x2 + x3),
        xi,
        xi,
    ]
}

/// Which section factor m ∈ {1, y, z} (index 0, 1, 2) multiplies N_i.
pub(crate) const SECTION_FACTOR: [usize; 8] = [0, 0, 1, 2, 0, 0, 1, 2];

/// Shape functions s_i(ξ, y, z) (SPEC §1).
pub fn shape_functions(xi: f64, y: f64, z: f64, l: f64) -> [f64; 8] {
    let n = axial_factors(xi, l);
    let m = [1.0, y, z];
    std::array::from_fn(|i| n[i] * m[SECTION_FACTOR[i]])
}

/// Gradients ∇s_i = (∂/∂x, ∂/∂y, ∂/∂z) at (ξ = x/l, y, z), in 1/m and 1.
pub fn shape_gradients(xi: f64, y: f64, z: f64, l: f64) -> [[f64; 3]; 8] {
    let d1 = (-6.0 * xi + 6.0 * xi * xi) / l;
    [
        [d1, 0.0, 0.0],
        [1.0 - 4.0 * xi + 3.0 * xi * xi, 0.0, 0.0],
        [-y / l, 1.0 - xi, 0.0],
        [-z / l, 0.0, 1.0 - xi],
        [-d1, 0.0, 0.0],
        [-2.0 * xi + 3.0 * xi * xi, 0.0, 0.0],
        [y / l, xi, 0.0],
        [z / l, 0.0, xi],
    ]
}

/// Position r = S e of a material point (m).
pub fn position(e: &ElementVector, xi: f64, y: f64, z: f64, l: f64) -> [f64; 3] {
    let s = shape_functions(xi, y, z, l);
    std::array::from_fn(|k| (0..8).map(|i| s[i] * e[3 * i + k]).sum())
}

/// Deformation gradient F\[k\]\[a\] = Σ_i e\[3i+k\] ∂s_i/∂x_a.
pub fn deformation_gradient(e: &ElementVector, g: &[[f64; 3]; 8]) -> [[f64; 3]; 3] {
    std::array::from_fn(|k| std::array::from_fn(|a| (0..8).map(|i| e[3 * i + k] * g[i][a]).sum()))
}

/// Green–Lagrange strain (Voigt) from F.
pub fn green_lagrange(f: &[[f64; 3]; 3]) -> Vector6<f64> {
    let c = |p: usize, q: usize| (0..3).map(|k| f[k][p] * f[k][q]).sum::<f64>();
    Vector6::new(
        0.5 * (c(0, 0) - 1.0),
        0.5 * (c(1, 1) - 1.0),
        0.5 * (c(2, 2) - 1.0),
        c(1, 2),
        c(0, 2),
        c(0, 1),
    )
}

ancf_macros::structured_point_kernel! {
    /// Generated point kernel: adds w·∂W/∂e to `q`, the upper triangle
    /// (row ≤ column) of w·∂²W/∂e² to `k` (the caller mirrors it), returns
    /// w·W, for the gradient sparsity of the 3243 beam.
    pub fn point_kernel;
    gradient_sparsity = [[x], [x], [x, y], [x, z], [x], [x], [x, y], [x, z]];
}

/// ∂ε/∂e (6×24, Voigt with engineering shears) built from a
/// deformation-gradient-like matrix `f`: with F it is the B matrix
/// (δε = B δe); with Ḟ it is the rate matrix of Kelvin–Voigt damping.
pub fn strain_matrix(f: &[[f64; 3]; 3], g: &[[f64; 3]; 8]) -> SMatrix<f64, 6, 24> {
    let mut b = SMatrix::<f64, 6, 24>::zeros();
    for i in 0..8 {
        for k in 0..3 {
            let col = 3 * i + k;
            let (fk, gi) = (&f[k], &g[i]);
            b[(0, col)] = fk[0] * gi[0];
            b[(1, col)] = fk[1] * gi[1];
            b[(2, col)] = fk[2] * gi[2];
            b[(3, col)] = fk[1] * gi[2] + fk[2] * gi[1];
            b[(4, col)] = fk[0] * gi[2] + fk[2] * gi[0];
            b[(5, col)] = fk[0] * gi[1] + fk[1] * gi[0];
        }
    }
    b
}

/// Generic point kernel, the textbook form: B = ∂ε/∂e (6×24),
/// q += w Bᵀσ, K += w (BᵀDB + geometric part).
pub(crate) fn point_kernel_generic(
    e: &ElementVector,
    g: &[[f64; 3]; 8],
    w: f64,
    law: &Law,
    q: &mut ElementVector,
    k: Option<&mut ElementMatrix>,
) -> f64 {
    let f = deformation_gradient(e, g);
    let eps = green_lagrange(&f);
    match k {
        Some(k) => {
            let st = law.stress_tangent(&eps);
            add_point_stress(&f, g, w, &st.stress, Some((&st.tangent, k)), q);
        }
        None => add_point_stress(&f, g, w, &law.stress(&eps), None, q),
    }
    w * law.energy(&eps)
}

/// A point's share of the force, w Bᵀσ, added to `q`, and with a tangent D
/// its share of the Jacobian, w (BᵀDB + geometric part), added to the
/// matrix beside it: what every law's point adds once it has its stress.
pub(crate) fn add_point_stress(
    f: &[[f64; 3]; 3],
    g: &[[f64; 3]; 8],
    w: f64,
    sigma: &Vector6<f64>,
    tangent: Option<(&nalgebra::Matrix6<f64>, &mut ElementMatrix)>,
    q: &mut ElementVector,
) {
    let b = strain_matrix(f, g);
    let force = b.transpose() * sigma;
    for (qi, fi) in q.iter_mut().zip(force.iter()) {
        *qi += w * fi;
    }
    if let Some((d, k)) = tangent {
        let kmat = b.transpose() * d * b;
        let s = crate::material::tensor_from_stress(sigma);
        for r in 0..24 {
            for c in 0..24 {
                let (i, kk, j, m) = (r / 3, r % 3, c / 3, c % 3);
                let mut v = kmat[(r, c)];
                if kk == m {
                    for a in 0..3 {
                        for bb in 0..3 {
                            v += g[i][a] * s[(a, bb)] * g[j][bb];
                        }
                    }
                }
                k[r * 24 + c] += w * v;
            }
        }
    }
}

/// Which element kernel a model runs: reported, never silent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelPath {
    /// Unrolled kernel generated for this axial order at compile time.
    /// The generated, unrolled kernel of this axial order.
    Generated {
        /// Gauss points along the element.
        axial_order: usize,
    },
    /// Loop-based kernel, any order.
    /// The generic loop kernel (an order without a generated one).
    Generic {
        /// Gauss points along the element.
        axial_order: usize,
    },
}

impl std::fmt::Display for KernelPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KernelPath::Generated { axial_order } => {
                write!(f, "generated kernel (axial order {axial_order})")
            }
            KernelPath::Generic { axial_order } => write!(
                f,
                "generic kernel (axial order {axial_order} not compiled; compiled: {:?}, set ANCF_KERNEL_ORDERS)",
                COMPILED_AXIAL_ORDERS
            ),
        }
    }
}

/// Everything needed to integrate one element: its length, the axial rule
/// and the section (layers with their points and laws).
#[derive(Clone, Debug)]
pub struct ElementIntegration {
    /// Element length l, m.
    pub length: f64,
    /// Axial Gauss–Legendre rule on ξ ∈ [0, 1] (weights sum to 1).
    pub axial: Rule1d,
    /// The cross section (layers, laws, quadrature points).
    pub section: Section,
    /// The points the generated kernel integrates (see [`IntegrationPlan`]).
    pub plan: IntegrationPlan,
    kernel: Option<ElementKernelFn>,
    /// A rectangle's Saint-Venant torsion ([`twist`]); `None` for circles.
    twist: Option<twist::TwistCorrection>,
}

/// A ring r1 ≤ ρ ≤ r2 (m) with a stiffness factor c relative to its group's law.
type RadialPiece = (f64, f64, f64);

/// Section points sharing one law.
#[derive(Clone, Debug)]
pub struct PointGroup {
    /// The group's section points (y, z, weight).
    pub points: Vec<crate::math::quadrature::SectionPoint>,
    /// The law all of them share.
    pub law: Law,
}

/// How the generated kernel integrates a section, exactly as the per-layer
/// rule does, with fewer points:
/// * circular layers whose section laws are linear and proportional
///   (D_k = c_k D̂: the default ν = 0 split with a common ω) share one ring
///   rule of order 3 for the piecewise weight c(ρ) — exact, since an SVK
///   integrand is a polynomial of degree 4 in (y, z) — whatever the
///   section order (≥ 3) asked for: two layers cost 7 points instead of 14;
/// * linear centerline laws are summed into one centerline law.
///
/// Other layers (Mooney–Rivlin, order < 3, rectangles) keep their points.
#[derive(Clone, Debug)]
pub struct IntegrationPlan {
    /// Linear laws, pre-integrated over the section (see `preintegration.rs`).
    pub(crate) preintegrated: Option<crate::element::preintegration::PreIntegrated>,
    /// Section points integrated point by point, grouped by law.
    pub groups: Vec<PointGroup>,
    /// Centerline laws with their weights (m²).
    pub centerline: Vec<(Law, f64)>,
    /// The layers whose beam stresses yield, point by point with their
    /// history (see `plastic.rs`).
    pub plastic: Vec<PlasticGroup>,
}

impl IntegrationPlan {
    /// The plan for `section`: linear laws pre-integrated, the rest by points.
    pub fn new(section: &Section) -> Self {
        let mut groups: Vec<PointGroup> = Vec::new();
        let mut plastic = Vec::new();
        // Proportional linear circular layers: (D̂, pieces (r1, r2, c)).
        let mut merged: Vec<(nalgebra::Matrix6<f64>, Vec<RadialPiece>)> = Vec::new();
        let radii = match &section.shape {
            crate::section::SectionShape::Circular { radii } if section.order >= 3 => Some(radii),
            _ => None,
        };
        for (i, layer) in section.layers.iter().enumerate() {
            // A yielding layer: its elastic law integrated as any layer's,
            // its points kept for the plastic corrections.
            if let Some(law) = layer.laws.plastic {
                let reach = (layer.points.iter()).fold(0.0f64, |m, p| m.max(p.y.hypot(p.z)));
                plastic.push(PlasticGroup {
                    points: layer.points.clone(),
                    law,
                    elastic: layer.laws.section.clone(),
                    reach,
                });
            }
            match (&layer.laws.section, radii) {
                (Law::Linear(d), Some(radii)) => {
                    let (r1, r2) = radii[i];
                    let scale = |a: &nalgebra::Matrix6<f64>, b: &nalgebra::Matrix6<f64>| {
                        let c = a.dot(b) / b.dot(b);
                        ((a - b * c).norm() <= 1e-12 * a.norm()).then_some(c)
                    };
                    match merged
                        .iter_mut()
                        .find_map(|(dh, pieces)| scale(d, dh).map(|c| (pieces, c)))
                    {
                        Some((pieces, c)) if c > 0.0 => pieces.push((r1, r2, c)),
                        _ => merged.push((*d, vec![(r1, r2, 1.0)])),
                    }
                }
                _ => groups.push(PointGroup {
                    points: layer.points.clone(),
                    law: layer.laws.section.clone(),
                }),
            }
        }
        for (d, pieces) in merged {
            groups.push(PointGroup {
                points: crate::math::quadrature::ring_rule_weighted(3, &pieces),
                law: Law::Linear(d),
            });
        }
        // Linear laws on symmetric rules: pre-integrated (their own moments, so
        // the result equals the point rule's exactly).
        let mut pre = crate::element::preintegration::PreIntegrated::zero();
        let mut any = false;
        groups.retain(|g| {
            match (
                &g.law,
                crate::element::preintegration::Moments::of(&g.points),
            ) {
                (Law::Linear(d), Some(m)) => {
                    pre.add_section(d, &m);
                    any = true;
                    false
                }
                _ => true,
            }
        });
        let mut centerline = Vec::new();
        for layer in &section.layers {
            match &layer.laws.centerline {
                Some(Law::Linear(d)) => {
                    pre.add_centerline(d, layer.area);
                    any = true;
                }
                Some(other) => centerline.push((other.clone(), layer.area)),
                None => {}
            }
        }
        IntegrationPlan {
            preintegrated: any.then_some(pre),
            groups,
            centerline,
            plastic,
        }
    }

    /// Whether linear laws are pre-integrated.
    pub fn is_preintegrated(&self) -> bool {
        self.preintegrated.is_some()
    }

    /// Whether every law is pre-integrated (no section or centerline
    /// points left): what the lane kernels need.
    pub fn is_preintegrated_only(&self) -> bool {
        self.is_preintegrated() && self.points() == 0
    }

    /// Points per axial station (the yielding layers' included).
    pub fn points(&self) -> usize {
        self.groups.iter().map(|g| g.points.len()).sum::<usize>()
            + self.plastic.iter().map(|g| g.points.len()).sum::<usize>()
            + self.centerline.len()
    }

    /// Whether a layer yields (its points carry a history).
    pub fn is_plastic(&self) -> bool {
        !self.plastic.is_empty()
    }
}

impl ElementIntegration {
    /// Elements of `length` (m) with `axial_order` Gauss points along them.
    pub fn new(length: f64, axial_order: usize, section: Section) -> Self {
        ElementIntegration {
            length,
            axial: gauss_legendre_unit(axial_order),
            plan: IntegrationPlan::new(&section),
            twist: twist::TwistCorrection::of(&section),
            section,
            kernel: generated::element_kernel_for(axial_order),
        }
    }

    /// The same integration for elements of length `length` (m): the
    /// pre-integrated section tensors do not depend on it.
    pub fn with_length(&self, length: f64) -> Self {
        ElementIntegration {
            length,
            ..self.clone()
        }
    }

    /// Force the generic path (for comparisons and benchmarks).
    pub fn with_generic_kernel(mut self) -> Self {
        self.kernel = None;
        self
    }

    /// Which kernel evaluates the element (generated or generic).
    pub fn kernel_path(&self) -> KernelPath {
        let axial_order = self.axial.nodes.len();
        match self.kernel {
            Some(_) => KernelPath::Generated { axial_order },
            None => KernelPath::Generic { axial_order },
        }
    }

    /// Elastic force (added to `q`), Jacobian (added to `k` when given) and
    /// strain energy of one element with coordinates `e`; a yielding layer
    /// from its virgin state (see [`Self::evaluate_with`]).
    pub fn evaluate(
        &self,
        e: &ElementVector,
        q: &mut ElementVector,
        k: Option<&mut ElementMatrix>,
    ) -> f64 {
        self.evaluate_with(e, PlasticInput::default(), q, k)
    }

    /// [`Self::evaluate`] with the yielding layers' points evaluated from
    /// the history `plastic` (their stored energy is the elastic part).
    pub fn evaluate_with(
        &self,
        e: &ElementVector,
        plastic: PlasticInput<'_>,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let mut u = match self.kernel {
            Some(kernel) => kernel(self, e, q, k.as_deref_mut()),
            None => self.evaluate_generic(e, q, k.as_deref_mut()),
        };
        if let Some(t) = &self.twist {
            let rule = (&self.axial.nodes[..], &self.axial.weights[..], self.length);
            u += t.add(rule, e, q, k.as_deref_mut());
        }
        match self.plan.is_plastic() {
            true => u + self.add_plastic(e, plastic, q, k),
            false => u,
        }
    }

    /// Elastic forces (added to `q`) and strain energies of four elements
    /// at once, `e[i][k]` being coordinate i of the k-th: the SIMD-friendly
    /// form of [`ElementIntegration::evaluate`] without a Jacobian, with the
    /// same bits per element. `None` when this element is not integrated by
    /// pre-integration alone with a generated axial rule (then evaluate one
    /// by one).
    pub fn forces_x4(&self, e: &[[f64; 4]; 24], q: &mut [[f64; 4]; 24]) -> Option<[f64; 4]> {
        if !self.plan.is_preintegrated_only() {
            return None;
        }
        self.forces_x4_before_plastic(e, q)
    }

    /// [`Self::forces_x4`] for eight elements at once (the same bits per
    /// element; faster on the AVX-512 path).
    pub fn forces_x8(&self, e: &[[f64; 8]; 24], q: &mut [[f64; 8]; 24]) -> Option<[f64; 8]> {
        if !self.plan.is_preintegrated_only() {
            return None;
        }
        self.forces_x8_before_plastic(e, q)
    }

    /// [`Self::forces_x8`] of the pre-integrated laws alone, also for
    /// elements with a yielding layer, whose corrections the caller adds
    /// element by element ([`Self::add_plastic`]).
    pub(crate) fn forces_x8_before_plastic(
        &self,
        e: &[[f64; 8]; 24],
        q: &mut [[f64; 8]; 24],
    ) -> Option<[f64; 8]> {
        let (pre, nodes, weights) = self.lane_kernel_data_before_plastic()?;
        let path = crate::math::simd::path();
        Some(preintegration::forces_8(
            path,
            pre,
            nodes,
            weights,
            self.length,
            e,
            q,
        ))
    }

    /// [`Self::forces_x4`] of the pre-integrated laws alone (see
    /// [`Self::forces_x8_before_plastic`]).
    pub(crate) fn forces_x4_before_plastic(
        &self,
        e: &[[f64; 4]; 24],
        q: &mut [[f64; 4]; 24],
    ) -> Option<[f64; 4]> {
        let (pre, nodes, weights) = self.lane_kernel_data_before_plastic()?;
        let path = crate::math::simd::path();
        Some(preintegration::forces_4(
            path,
            pre,
            nodes,
            weights,
            self.length,
            e,
            q,
        ))
    }

    /// [`Self::jacobians_x4`] of the pre-integrated laws alone (see
    /// [`Self::forces_x8_before_plastic`]).
    pub(crate) fn jacobians_x4_before_plastic(
        &self,
        e: &[[f64; 4]; 24],
        q: &mut [[f64; 4]; 24],
        k: &mut [[f64; 4]; 576],
    ) -> Option<[f64; 4]> {
        let (pre, nodes, weights) = self.lane_kernel_data_before_plastic()?;
        let path = crate::math::simd::path();
        Some(preintegration::jacobians_4(
            path,
            pre,
            nodes,
            weights,
            self.length,
            e,
            q,
            k,
        ))
    }

    /// [`Self::energies_x4`] for eight elements at once.
    pub fn energies_x8(&self, e: &[[f64; 8]; 24]) -> Option<[f64; 8]> {
        let (pre, nodes, weights) = self.lane_kernel_data()?;
        let path = crate::math::simd::path();
        Some(preintegration::energies_8(
            path,
            pre,
            nodes,
            weights,
            self.length,
            e,
        ))
    }

    /// Forces (added to `q`), strain energies and Jacobians (written over
    /// `k`: `k[i * 24 + j][m]` is entry (i, j) of the m-th element) of four
    /// elements at once: the SIMD-friendly form of
    /// [`ElementIntegration::evaluate`] with a Jacobian, the same bits per
    /// element. `None` where [`Self::forces_x4`] is.
    pub fn jacobians_x4(
        &self,
        e: &[[f64; 4]; 24],
        q: &mut [[f64; 4]; 24],
        k: &mut [[f64; 4]; 576],
    ) -> Option<[f64; 4]> {
        if !self.plan.is_preintegrated_only() {
            return None;
        }
        self.jacobians_x4_before_plastic(e, q, k)
    }

    /// What the lane kernel needs — the pre-integrated section and the
    /// generated axial rule — when this element is integrated by
    /// pre-integration alone with a generated rule.
    fn lane_kernel_data(
        &self,
    ) -> Option<(
        &preintegration::PreIntegrated,
        &'static [f64],
        &'static [f64],
    )> {
        if !self.plan.is_preintegrated_only() {
            return None;
        }
        self.lane_kernel_data_before_plastic()
    }

    /// [`Self::lane_kernel_data`] for an element whose only points besides
    /// the pre-integrated laws are a yielding layer's corrections (the
    /// caller adds them, [`Self::add_plastic`]).
    fn lane_kernel_data_before_plastic(
        &self,
    ) -> Option<(
        &preintegration::PreIntegrated,
        &'static [f64],
        &'static [f64],
    )> {
        let others = self.plan.points() - self.plastic_points_per_station();
        // A rectangle's twist is added element by element (evaluate_with).
        if self.kernel.is_none() || others != 0 || self.twist.is_some() {
            return None;
        }
        let pre = self.plan.preintegrated.as_ref()?;
        let (nodes, weights) = generated::axial_rule_for(self.axial.nodes.len())?;
        Some((pre, nodes, weights))
    }

    /// Strain energies of four elements at once (as [`Self::forces_x4`]
    /// gives them, bit for bit) without their forces; `None` where
    /// `forces_x4` is.
    pub fn energies_x4(&self, e: &[[f64; 4]; 24]) -> Option<[f64; 4]> {
        let (pre, nodes, weights) = self.lane_kernel_data()?;
        Some(preintegration::energies_4(
            crate::math::simd::path(),
            pre,
            nodes,
            weights,
            self.length,
            e,
        ))
    }

    /// Strain energy only (J).
    pub fn energy(&self, e: &ElementVector) -> f64 {
        self.evaluate(e, &mut [0.0; 24], None)
    }

    /// The generic loop-based path.
    pub fn evaluate_generic(
        &self,
        e: &ElementVector,
        q: &mut ElementVector,
        mut k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let mut energy = 0.0;
        self.for_each_point(|g, w, law| {
            energy += point_kernel_generic(e, g, w, law, q, k.as_deref_mut())
        });
        energy
    }

    /// Visit every integration point with the shape gradients there, its
    /// weight (m³) and its law: the section points of each layer and, where a
    /// layer has one, its centerline point (weighted by the layer's area).
    /// A yielding layer's section points are visited with its elastic law.
    pub fn for_each_point(&self, visit: impl FnMut(&[[f64; 3]; 8], f64, &Law)) {
        self.for_each_point_where(|_| true, visit);
    }

    /// [`Self::for_each_point`], the section points of the layers `take`
    /// accepts only (every centerline point is visited).
    pub(crate) fn for_each_point_where(
        &self,
        take: impl Fn(&crate::section::SectionLayer) -> bool,
        mut visit: impl FnMut(&[[f64; 3]; 8], f64, &Law),
    ) {
        let l = self.length;
        for (xi, wx) in self.axial.nodes.iter().zip(&self.axial.weights) {
            let wx = wx * l;
            for layer in &self.section.layers {
                for p in layer.points.iter().filter(|_| take(layer)) {
                    visit(
                        &shape_gradients(*xi, p.y, p.z, l),
                        wx * p.weight,
                        &layer.laws.section,
                    );
                }
                if let Some(cl) = &layer.laws.centerline {
                    visit(&shape_gradients(*xi, 0.0, 0.0, l), wx * layer.area, cl);
                }
            }
        }
    }

    /// Visit the points the integration plan takes one by one — each
    /// group's section points, then the centerline laws (the rest is
    /// pre-integrated) — at the axial rule `nodes`, `weights` on [0, 1],
    /// with the shape gradients there, the weight (m³) and the law. The
    /// elastic force and the Kelvin–Voigt damping both integrate so.
    #[inline(always)]
    pub fn for_each_plan_point(
        &self,
        nodes: &[f64],
        weights: &[f64],
        mut visit: impl FnMut(&[[f64; 3]; 8], f64, &Law),
    ) {
        let (l, plan) = (self.length, &self.plan);
        for (xi, w) in nodes.iter().zip(weights) {
            let wx = w * l;
            for group in &plan.groups {
                for p in &group.points {
                    visit(
                        &shape_gradients(*xi, p.y, p.z, l),
                        wx * p.weight,
                        &group.law,
                    );
                }
            }
            if !plan.centerline.is_empty() {
                let g = shape_gradients(*xi, 0.0, 0.0, l);
                for (law, area) in &plan.centerline {
                    visit(&g, wx * area, law);
                }
            }
        }
    }

    /// Element mass matrix (kg), row-major 24×24: M = Σ ρ ∫ SᵀS dV, exact
    /// (5-point axial rule, degree 6 integrand; section moments in closed form).
    pub fn mass_matrix(&self) -> ElementMatrix {
        let l = self.length;
        let mom = self.section.density_moments();
        let rule = gauss_legendre_unit(5);
        let mut m = [0.0; 576];
        for (xi, w) in rule.nodes.iter().zip(&rule.weights) {
            let n = axial_factors(*xi, l);
            for i in 0..8 {
                for j in 0..8 {
                    let v = w * l * n[i] * n[j] * mom[SECTION_FACTOR[i]][SECTION_FACTOR[j]];
                    for kk in 0..3 {
                        m[(3 * i + kk) * 24 + 3 * j + kk] += v;
                    }
                }
            }
        }
        m
    }

    /// Generalized gravity force (N) for the acceleration `g` (m/s²): Σ ρ ∫ Sᵀg dV.
    pub fn gravity_force(&self, g: [f64; 3]) -> ElementVector {
        let l = self.length;
        let mom = self.section.density_moments();
        let rule = gauss_legendre_unit(3);
        let mut q = [0.0; 24];
        for (xi, w) in rule.nodes.iter().zip(&rule.weights) {
            let n = axial_factors(*xi, l);
            for i in 0..8 {
                // ∫ρ m_i dA: only m = 1 survives on symmetric sections.
                let v = w * l * n[i] * mom[0][SECTION_FACTOR[i]];
                for kk in 0..3 {
                    q[3 * i + kk] += v * g[kk];
                }
            }
        }
        q
    }
}

/// Whole-element kernel with the axial rule fixed at compile time (`N`
/// points), calling the generated point kernel. `build.rs` instantiates it
/// for each compiled order with the rule's nodes and weights as constants.
pub(crate) fn structured_element<const N: usize>(
    nodes: &[f64; N],
    weights: &[f64; N],
    ei: &ElementIntegration,
    e: &ElementVector,
    q: &mut ElementVector,
    mut k: Option<&mut ElementMatrix>,
) -> f64 {
    let l = ei.length;
    let mut energy = 0.0;
    if let Some(pre) = &ei.plan.preintegrated {
        energy += pre.evaluate(nodes, weights, l, e, q, k.as_deref_mut());
    }
    if ei.plan.points() == 0 {
        return energy;
    }
    // The point kernel writes K's upper triangle: summed over the points
    // here, mirrored into k once.
    let mut upper = k.as_ref().map(|_| [0.0; 576]);
    ei.for_each_plan_point(nodes, weights, |g, w, law| {
        energy += point_kernel(e, g, w, law, q, upper.as_mut());
    });
    if let (Some(k), Some(upper)) = (k, upper) {
        for r in 0..24 {
            k[r * 24 + r] += upper[r * 24 + r];
            for c in r + 1..24 {
                let v = upper[r * 24 + c];
                k[r * 24 + c] += v;
                k[c * 24 + r] += v;
            }
        }
    }
    energy
}

/// Reference (undeformed) element coordinates of a straight element from
/// `start` along the unit `axis`, with section directions `ny`, `nz`.
pub fn reference_coordinates(
    start: [f64; 3],
    axis: [f64; 3],
    ny: [f64; 3],
    nz: [f64; 3],
    l: f64,
) -> ElementVector {
    let mut e = [0.0; 24];
    for k in 0..3 {
        e[k] = start[k];
        e[3 + k] = axis[k];
        e[6 + k] = ny[k];
        e[9 + k] = nz[k];
        e[12 + k] = start[k] + l * axis[k];
        e[15 + k] = axis[k];
        e[18 + k] = ny[k];
        e[21 + k] = nz[k];
    }
    e
}
