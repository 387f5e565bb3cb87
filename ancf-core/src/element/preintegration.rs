//! Pre-integration of linear (St. Venant–Kirchhoff) laws over the section.
//!
//! At an axial station the deformation gradient is affine in (y, z):
//! F(y, z) = [r₀ + y a + z b, r_y, r_z] with the five vectors
//! u = (r₀, a, b, r_y, r_z), each a linear combination of the element
//! coordinates. Every Green–Lagrange component is then linear in the 15 Gram
//! entries x_ij = u_i · u_j, with coefficients 1, y, z, y², yz, z², so the
//! energy of a linear law integrated over the section is
//!
//!   U(x) = ½ xᵀ A x + bᵀ x + U₀,
//!
//! with A, b built once from D and the section moments m₀ = ∫1, ∫y², ∫z²,
//! ∫y⁴, ∫z⁴, ∫y²z² (odd moments vanish on symmetric sections). Using the
//! point rule's own moments reproduces point quadrature exactly, at a cost
//! that does not depend on the number of section points or layers.

use crate::element::{ElementMatrix, ElementVector};
use crate::math::quadrature::SectionPoint;
use crate::math::simd::Arith;
use nalgebra::Vector3;
use nalgebra::{Matrix6, SMatrix, SVector};

type M15 = SMatrix<f64, 15, 15>;
type V15 = SVector<f64, 15>;
type M6x15 = SMatrix<f64, 6, 15>;

/// Index of the Gram entry (i, j) of the five vectors, i ≤ j.
const fn gram(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    // rows: (0,0..4)=0..4, (1,1..4)=5..8, (2,2..4)=9..11, (3,3..4)=12..13, (4,4)=14
    [0, 5, 9, 12, 14][i] + (j - i)
}

/// Section moments of a point rule: m₀, ∫y², ∫z², ∫y⁴, ∫z⁴, ∫y²z².
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    /// ∫ w dA (m²).
    pub m0: f64,
    /// ∫ w y² dA (m⁴).
    pub yy: f64,
    /// ∫ w z² dA (m⁴).
    pub zz: f64,
    /// ∫ w y⁴ dA (m⁶).
    pub y4: f64,
    /// ∫ w z⁴ dA (m⁶).
    pub z4: f64,
    /// ∫ w y² z² dA (m⁶).
    pub y2z2: f64,
}

impl Moments {
    /// The rule's moments, or `None` when an odd moment does not vanish
    /// (the rule is not symmetric and this form would not be exact).
    pub fn of(points: &[SectionPoint]) -> Option<Self> {
        let sum = |f: &dyn Fn(f64, f64) -> f64| {
            points.iter().map(|p| p.weight * f(p.y, p.z)).sum::<f64>()
        };
        let m = Moments {
            m0: sum(&|_, _| 1.0),
            yy: sum(&|y, _| y * y),
            zz: sum(&|_, z| z * z),
            y4: sum(&|y, _| y.powi(4)),
            z4: sum(&|_, z| z.powi(4)),
            y2z2: sum(&|y, z| y * y * z * z),
        };
        let r2 = m.yy.max(m.zz) / m.m0.max(f64::MIN_POSITIVE);
        let r = r2.sqrt();
        let odd = [
            sum(&|y, _| y) / r,
            sum(&|_, z| z) / r,
            sum(&|y, z| y * z) / r2,
            sum(&|y, _| y.powi(3)) / (r2 * r),
            sum(&|_, z| z.powi(3)) / (r2 * r),
            sum(&|y, z| y * y * z) / (r2 * r),
            sum(&|y, z| y * z * z) / (r2 * r),
            sum(&|y, z| y.powi(3) * z) / (r2 * r2),
            sum(&|y, z| y * z.powi(3)) / (r2 * r2),
        ];
        odd.iter().all(|v| v.abs() <= 1e-12 * m.m0).then_some(m)
    }
}

/// The strain pieces as linear maps of x: ε = c0 + C x at (0, 0); the y and
/// z coefficients P x, T x; and the quadratic (xx-only) coefficients α, β, γ
/// of y², yz, z² as linear forms.
fn strain_maps() -> (Vector6, M6x15, M6x15, M6x15, [V15; 3]) {
    let (r0, a, b, ry, rz) = (0, 1, 2, 3, 4);
    let c0 = Vector6::new(-0.5, -0.5, -0.5, 0.0, 0.0, 0.0);
    let mut c = M6x15::zeros();
    c[(0, gram(r0, r0))] = 0.5;
    c[(1, gram(ry, ry))] = 0.5;
    c[(2, gram(rz, rz))] = 0.5;
    c[(3, gram(ry, rz))] = 1.0;
    c[(4, gram(r0, rz))] = 1.0;
    c[(5, gram(r0, ry))] = 1.0;
    let mut p = M6x15::zeros();
    p[(0, gram(r0, a))] = 1.0;
    p[(4, gram(a, rz))] = 1.0;
    p[(5, gram(a, ry))] = 1.0;
    let mut t = M6x15::zeros();
    t[(0, gram(r0, b))] = 1.0;
    t[(4, gram(b, rz))] = 1.0;
    t[(5, gram(b, ry))] = 1.0;
    let mut alpha = V15::zeros();
    alpha[gram(a, a)] = 0.5;
    let mut beta = V15::zeros();
    beta[gram(a, b)] = 1.0;
    let mut gamma = V15::zeros();
    gamma[gram(b, b)] = 0.5;
    (c0, c, p, t, [alpha, beta, gamma])
}

type Vector6 = nalgebra::Vector6<f64>;

/// The energy of linear laws over a section (per unit axial length, J/m), in
/// strain-moment variables s = s₀ + J x: the strain at the centre (6), its
/// y- and z-slopes (the xx, xz, xy components, 3 + 3) and the coefficients
/// α, β, γ of y², yz, z² in E_xx. Then U = ½ sᵀ M s exactly: no constant or
/// linear term to cancel, so a stress-free state gives exactly zero (the
/// x-space form ½ xᵀAx + bᵀx + U₀ lost 1e-16 of E·V there — found by the
/// objectivity property test). A = Jᵀ M J is the Hessian in x.
///
/// The evaluation works on structures built once per element type: M by
/// its four non-zero blocks, and the Hessian blocks as 45 outer products
/// u_l u_rᵀ (of 15 × 25 possible) for an isotropic law, so that the
/// evaluation does only the products that are not zero.
#[derive(Clone, Debug)]
pub struct PreIntegrated {
    m: M15,
    j: M15,
    s0: V15,
    /// Jᵀ M J, the (constant) Hessian in x.
    a: M15,
    /// M by its blocks (`add_section` cannot fill anything else): the
    /// centre strains with α and γ (`CENTRE`, 8 × 8), the y-slopes and the
    /// z-slopes (3 × 3 each) and β alone — 83 products instead of 225.
    m_centre: [[f64; 8]; 8],
    m_slope_y: [[f64; 3]; 3],
    m_slope_z: [[f64; 3]; 3],
    m_beta: f64,
    /// The material part of the Hessian in u: block (i ≤ j) of the five
    /// vectors gets coef · u_l u_rᵀ for each (l, r, coef) in
    /// `hessian_terms[hessian_ranges[gram(i, j)]]` (grouped by block, so
    /// each block is summed in registers).
    hessian_terms: Vec<(usize, usize, f64)>,
    hessian_ranges: [(usize, usize); 15],
}

/// J row by row, (Gram column, coefficient) of its single non-zero: the
/// strain moments E_xx, E_yy, E_zz, 2E_yz, 2E_xz, 2E_xy at the centre, the
/// y-slopes and z-slopes of E_xx, 2E_xz, 2E_xy, and α, β, γ (checked against
/// `strain_maps` in `zero`). Each Gram entry appears once.
const STRAIN_MOMENTS: [(usize, f64); 15] = [
    (gram(0, 0), 0.5),
    (gram(3, 3), 0.5),
    (gram(4, 4), 0.5),
    (gram(3, 4), 1.0),
    (gram(0, 4), 1.0),
    (gram(0, 3), 1.0),
    (gram(0, 1), 1.0),
    (gram(1, 4), 1.0),
    (gram(1, 3), 1.0),
    (gram(0, 2), 1.0),
    (gram(2, 4), 1.0),
    (gram(2, 3), 1.0),
    (gram(1, 1), 0.5),
    (gram(1, 2), 1.0),
    (gram(2, 2), 0.5),
];

/// The strain moments that M couples with each other: the centre strains
/// and α, γ (E_xx's y² and z² terms multiply the centre's stresses).
const CENTRE: [usize; 8] = [0, 1, 2, 3, 4, 5, 12, 14];

/// The array `[e(0), e(1), …]` with `i` bound to each listed index in turn:
/// written out, so that every entry is computed in place (no zeroed array
/// filled by a loop) and each `i` is a constant inside `e`.
/// (`std::array::from_fn` in its place measured 15× slower in the kernels.)
macro_rules! unrolled {
    ($i:ident in [$($n:literal),*] => $e:expr) => {
        [$({
            let $i: usize = $n;
            $e
        }),*]
    };
}

// After `unrolled!`, which it uses.
mod kelvin_voigt;

/// Row of `m_centre` that each strain moment in [`CENTRE`] has (the others: unused).
const CENTRE_ROW: [usize; 15] = {
    let mut row = [usize::MAX; 15];
    let mut i = 0;
    while i < CENTRE.len() {
        row[CENTRE[i]] = i;
        i += 1;
    }
    row
};

/// The row of [`STRAIN_MOMENTS`] that names each Gram entry (each appears once).
const STRAIN_MOMENT_OF_GRAM: [usize; 15] = {
    let mut row = [usize::MAX; 15];
    let mut r = 0;
    while r < STRAIN_MOMENTS.len() {
        assert!(row[STRAIN_MOMENTS[r].0] == usize::MAX, "a Gram entry twice");
        row[STRAIN_MOMENTS[r].0] = r;
        r += 1;
    }
    row
};

/// Voigt rows that a y- or z-slope of the strain can have (xx, xz, xy).
const SLOPE_ROWS: [usize; 3] = [0, 4, 5];

/// The map u = T(ξ) e, entry by entry: the five vectors (r_x at the
/// centerline, a = ∂r_y/∂x, b = ∂r_z/∂x, r_y, r_z) are each a combination of
/// two or four of the element's eight nodal vectors (r, r_x, r_y, r_z at
/// node 1, then node 2). `T_VECTOR[p]`, `T_NODE[p]` name entry p; its
/// coefficient depends on ξ (`t_coefficients`).
const T_VECTOR: [usize; 12] = [0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4];
const T_NODE: [usize; 12] = [0, 1, 4, 5, 2, 6, 3, 7, 2, 6, 3, 7];

/// Coefficients of the twelve entries of T at ξ for an element of length l.
fn t_coefficients(xi: f64, l: f64) -> [f64; 12] {
    let d1 = (-6.0 * xi + 6.0 * xi * xi) / l;
    let h1 = 1.0 - 4.0 * xi + 3.0 * xi * xi;
    let h2 = -2.0 * xi + 3.0 * xi * xi;
    let il = 1.0 / l;
    [
        d1,
        h1,
        -d1,
        h2,
        -il,
        il,
        -il,
        il,
        1.0 - xi,
        xi,
        1.0 - xi,
        xi,
    ]
}

/// One of K's 36 upper node blocks (node a ≤ node b): the sum over the
/// pairs (p1, p2) of T entries at these nodes of T_p1 T_p2 H_ij, each term
/// (p1, p2, 5 i + j).
#[derive(Clone, Copy)]
struct NodeBlock {
    a: usize,
    b: usize,
    len: usize,
    terms: [(usize, usize, usize); 4],
}

/// The upper node blocks of K with their T-entry pairs (82 pairs in all:
/// a node carries one or two of T's entries).
const NODE_BLOCKS: [NodeBlock; 36] = {
    let mut out = [NodeBlock {
        a: 0,
        b: 0,
        len: 0,
        terms: [(0, 0, 0); 4],
    }; 36];
    let mut n = 0;
    let mut a = 0;
    while a < 8 {
        let mut b = a;
        while b < 8 {
            out[n].a = a;
            out[n].b = b;
            let mut p1 = 0;
            while p1 < 12 {
                let mut p2 = 0;
                while p2 < 12 {
                    if T_NODE[p1] == a && T_NODE[p2] == b {
                        let len = out[n].len;
                        out[n].terms[len] = (p1, p2, 5 * T_VECTOR[p1] + T_VECTOR[p2]);
                        out[n].len = len + 1;
                    }
                    p2 += 1;
                }
                p1 += 1;
            }
            n += 1;
            b += 1;
        }
        a += 1;
    }
    out
};

/// The pair (i, j), i ≤ j, of a Gram index.
const GRAM_PAIRS: [(usize, usize); 15] = [
    (0, 0),
    (0, 1),
    (0, 2),
    (0, 3),
    (0, 4),
    (1, 1),
    (1, 2),
    (1, 3),
    (1, 4),
    (2, 2),
    (2, 3),
    (2, 4),
    (3, 3),
    (3, 4),
    (4, 4),
];

impl PreIntegrated {
    /// No section yet: every tensor zero.
    pub fn zero() -> Self {
        let (c0, c, p, t, [al, be, ga]) = strain_maps();
        let mut j = M15::zeros();
        let mut s0 = V15::zeros();
        for r in 0..6 {
            j.set_row(r, &c.row(r));
            s0[r] = c0[r];
        }
        for (k, &r) in SLOPE_ROWS.iter().enumerate() {
            j.set_row(6 + k, &p.row(r));
            j.set_row(9 + k, &t.row(r));
        }
        j.set_row(12, &al.transpose());
        j.set_row(13, &be.transpose());
        j.set_row(14, &ga.transpose());
        for (r, &(col, coef)) in STRAIN_MOMENTS.iter().enumerate() {
            for c in 0..15 {
                let expect = if c == col { coef } else { 0.0 };
                assert_eq!(j[(r, c)], expect, "STRAIN_MOMENTS row {r} disagrees with J");
            }
        }
        PreIntegrated {
            m: M15::zeros(),
            j,
            s0,
            a: M15::zeros(),
            m_centre: [[0.0; 8]; 8],
            m_slope_y: [[0.0; 3]; 3],
            m_slope_z: [[0.0; 3]; 3],
            m_beta: 0.0,
            hessian_terms: Vec::new(),
            hessian_ranges: [(0, 0); 15],
        }
    }

    /// Add a linear law D integrated with moments `m`:
    /// ∫ ½ εᵀDε with ε = ε_c + y ε_y + z ε_z + (α y² + β yz + γ z²) e₁.
    pub fn add_section(&mut self, d: &Matrix6<f64>, mo: &Moments) {
        let m = &mut self.m;
        for r in 0..6 {
            for c in 0..6 {
                m[(r, c)] += mo.m0 * d[(r, c)];
            }
        }
        for (a, &ra) in SLOPE_ROWS.iter().enumerate() {
            for (b, &rb) in SLOPE_ROWS.iter().enumerate() {
                m[(6 + a, 6 + b)] += mo.yy * d[(ra, rb)];
                m[(9 + a, 9 + b)] += mo.zz * d[(ra, rb)];
            }
        }
        // ∫ q (D ε_c)₀ with ∫ q = α ∫y² + γ ∫z².
        for c in 0..6 {
            m[(12, c)] += mo.yy * d[(0, c)];
            m[(c, 12)] += mo.yy * d[(0, c)];
            m[(14, c)] += mo.zz * d[(0, c)];
            m[(c, 14)] += mo.zz * d[(0, c)];
        }
        // ½ D₀₀ ∫ q² = ½ D₀₀ (α² ∫y⁴ + β² ∫y²z² + γ² ∫z⁴ + 2αγ ∫y²z²).
        let d00 = d[(0, 0)];
        m[(12, 12)] += d00 * mo.y4;
        m[(13, 13)] += d00 * mo.y2z2;
        m[(14, 14)] += d00 * mo.z4;
        m[(12, 14)] += d00 * mo.y2z2;
        m[(14, 12)] += d00 * mo.y2z2;
        self.a = self.j.transpose() * self.m * self.j;
        self.build_sparse_lists();
    }

    /// The non-zeros of M and the Hessian's outer-product terms, from M.
    fn build_sparse_lists(&mut self) {
        let m = &self.m;
        let block = |rows: &[usize], r: usize, c: usize| m[(rows[r], rows[c])];
        self.m_centre = std::array::from_fn(|r| std::array::from_fn(|c| block(&CENTRE, r, c)));
        self.m_slope_y = std::array::from_fn(|r| std::array::from_fn(|c| m[(6 + r, 6 + c)]));
        self.m_slope_z = std::array::from_fn(|r| std::array::from_fn(|c| m[(9 + r, 9 + c)]));
        self.m_beta = m[(13, 13)];
        let in_block = |r: usize, c: usize| {
            (CENTRE.contains(&r) && CENTRE.contains(&c))
                || ((6..9).contains(&r) && (6..9).contains(&c))
                || ((9..12).contains(&r) && (9..12).contains(&c))
                || (r == 13 && c == 13)
        };
        for r in 0..15 {
            for c in 0..15 {
                assert!(
                    in_block(r, c) || m[(r, c)] == 0.0,
                    "M({r}, {c}) outside its blocks"
                );
            }
        }
        // H_ij = Σ_(g1, g2) A_g1g2 (∂x_g1/∂u_i)(∂x_g2/∂u_j)ᵀ with
        // ∂x_(mn)/∂u_i = δ_im u_n + δ_in u_m: each non-zero of A adds
        // A · u_n u_qᵀ to block (m, p), and so on for the four index pairings.
        let mut terms: Vec<(usize, usize, usize, f64)> = Vec::new();
        for (g1, &(m, n)) in GRAM_PAIRS.iter().enumerate() {
            for (g2, &(p, q)) in GRAM_PAIRS.iter().enumerate() {
                let a = self.a[(g1, g2)];
                if a == 0.0 {
                    continue;
                }
                for (i, l) in [(m, n), (n, m)] {
                    for (j, r) in [(p, q), (q, p)] {
                        if i > j {
                            continue;
                        }
                        let block = gram(i, j);
                        match terms.iter_mut().find(|t| (t.0, t.1, t.2) == (block, l, r)) {
                            Some(t) => t.3 += a,
                            None => terms.push((block, l, r, a)),
                        }
                    }
                }
            }
        }
        self.hessian_terms.clear();
        for (g, range) in self.hessian_ranges.iter_mut().enumerate() {
            let start = self.hessian_terms.len();
            let of_block = terms.iter().filter(|t| t.0 == g);
            self.hessian_terms
                .extend(of_block.map(|&(_, l, r, coef)| (l, r, coef)));
            *range = (start, self.hessian_terms.len());
        }
    }

    /// Add a linear law D at the centerline with weight w (m²).
    pub fn add_centerline(&mut self, d: &Matrix6<f64>, w: f64) {
        self.add_section(
            d,
            &Moments {
                m0: w,
                ..Default::default()
            },
        );
    }

    /// Energy, force and Jacobian of the pre-integrated laws over the axial
    /// rule (`nodes` ξ ∈ [0, 1], `weights` summing to 1) of an element of
    /// length `l` (m), added to `q` and `k`: the lane kernel with one lane,
    /// so that an element alone and in a batch of four
    /// ([`jacobians_4`], [`forces_4`]) gets the same bits on every path.
    pub fn evaluate<const N: usize>(
        &self,
        nodes: &[f64; N],
        weights: &[f64; N],
        l: f64,
        e: &ElementVector,
        q: &mut ElementVector,
        k: Option<&mut ElementMatrix>,
    ) -> f64 {
        let path = crate::math::simd::path();
        match k {
            None => forces_1(path, self, nodes, weights, l, e, q),
            Some(k) => jacobians_1(path, self, nodes, weights, l, e, q, k),
        }
    }
}

/// The scalar form of the lane kernel, one element and one station at a
/// time: the readable statement of what [`jacobians_lanes`] computes, and
/// the tests' reference for it (bit for bit on the baseline path).
#[cfg(test)]
impl PreIntegrated {
    /// [`PreIntegrated::evaluate`] with a Jacobian, element by element: the
    /// stations' Hessian blocks first, then each node block of K summed
    /// over the stations and written once.
    fn evaluate_scalar(
        &self,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &ElementVector,
        q: &mut ElementVector,
        k: &mut ElementMatrix,
    ) -> f64 {
        let n = nodes.len();
        let mut energy = 0.0;
        let mut h = vec![[[0.0f64; 9]; 25]; n];
        let mut tc = vec![[0.0f64; 12]; n];
        let wx: Vec<f64> = weights.iter().map(|w| w * l).collect();
        for st in 0..n {
            let f = self.station(nodes[st], l, wx[st], e, q);
            energy += f.energy;
            tc[st] = f.tc;
            self.hessian_blocks(&f.u, &f.s, &mut h[st]);
        }
        for blk in &NODE_BLOCKS {
            let mut acc = [0.0f64; 9];
            for ((wx, tc), h) in wx.iter().zip(&tc).zip(&h) {
                for &(p1, p2, hi) in &blk.terms[..blk.len] {
                    let c = wx * tc[p1] * tc[p2];
                    for (x, hv) in acc.iter_mut().zip(&h[hi]) {
                        *x += c * hv;
                    }
                }
            }
            let (a, b) = (blk.a, blk.b);
            for r in 0..3 {
                for c in 0..3 {
                    k[(3 * a + r) * 24 + 3 * b + c] += acc[3 * r + c];
                    if a != b {
                        k[(3 * b + c) * 24 + 3 * a + r] += acc[3 * r + c];
                    }
                }
            }
        }
        energy
    }

    /// The Hessian blocks H_ij (index 5 i + j, row-major 3 × 3) of the
    /// section energy in the five vectors u, given the stress-like
    /// coefficients s: H_ij = S_ij I + Σ coef u_l u_rᵀ for i ≤ j, H_ji = H_ijᵀ
    /// (the lower blocks stored too: a transpose flag in the scatter loop
    /// cost more than the copies).
    fn hessian_blocks(&self, u: &[Vector3<f64>; 5], s: &[f64; 15], h: &mut [[f64; 9]; 25]) {
        for (g, &(i, j)) in GRAM_PAIRS.iter().enumerate() {
            let mut acc = [0.0f64; 9];
            acc[0] = s[g];
            acc[4] = s[g];
            acc[8] = s[g];
            let (start, end) = self.hessian_ranges[g];
            for &(l, r, coef) in &self.hessian_terms[start..end] {
                for a in 0..3 {
                    let ul = coef * u[l][a];
                    for b in 0..3 {
                        acc[3 * a + b] += ul * u[r][b];
                    }
                }
            }
            h[5 * i + j] = acc;
            if i != j {
                h[5 * j + i] = [
                    acc[0], acc[3], acc[6], acc[1], acc[4], acc[7], acc[2], acc[5], acc[8],
                ];
            }
        }
    }

    /// One axial station ξ with weight `wx` (m): adds the force to `q`.
    fn station(
        &self,
        xi: f64,
        l: f64,
        wx: f64,
        e: &ElementVector,
        q: &mut ElementVector,
    ) -> Station {
        let tc = t_coefficients(xi, l);
        let u = vectors(&tc, e);
        let x: [f64; 15] = std::array::from_fn(|g| u[GRAM_PAIRS[g].0].dot(&u[GRAM_PAIRS[g].1]));
        // s = s₀ + J x (J has one non-zero per row), then M s.
        let strain: [f64; 15] = std::array::from_fn(|r| {
            let (col, coef) = STRAIN_MOMENTS[r];
            self.s0[r] + coef * x[col]
        });
        let ms = self.m_times(&strain);
        let mut energy = 0.0;
        let mut sigma = [0.0f64; 15];
        for r in 0..15 {
            energy += strain[r] * ms[r];
            let (col, coef) = STRAIN_MOMENTS[r];
            sigma[col] = coef * ms[r];
        }
        // ∂U/∂u_i = Σ_j S_ij u_j with S_ii = 2σ_ii, S_ij = σ_ij (i ≠ j).
        let s: [f64; 15] = std::array::from_fn(|g| {
            let (i, j) = GRAM_PAIRS[g];
            if i == j { 2.0 * sigma[g] } else { sigma[g] }
        });
        add_force(&tc, wx, &u, &s, q);
        Station {
            energy: wx * 0.5 * energy,
            tc,
            u,
            s,
        }
    }
}

impl PreIntegrated {
    /// M y on M's non-zero blocks, row by row (each row's sum in a
    /// register: accumulating into memory made the loop wait on store
    /// forwarding).
    fn m_times(&self, y: &[f64; 15]) -> [f64; 15] {
        let mut my = [0.0f64; 15];
        for (r, row) in CENTRE.iter().zip(&self.m_centre) {
            my[*r] = row.iter().zip(&CENTRE).map(|(m, &c)| m * y[c]).sum();
        }
        for r in 0..3 {
            my[6 + r] = (0..3).map(|c| self.m_slope_y[r][c] * y[6 + c]).sum();
            my[9 + r] = (0..3).map(|c| self.m_slope_z[r][c] * y[9 + c]).sum();
        }
        my[13] = self.m_beta * y[13];
        my
    }
}

/// u = T e at one station: the five vectors (r_x at the centerline,
/// a = ∂r_y/∂x, b = ∂r_z/∂x, r_y, r_z) from the element's nodal vectors
/// (r, r_x, r_y, r_z at node 1, then node 2), T's entries `tc` written out.
fn vectors(tc: &[f64; 12], e: &ElementVector) -> [Vector3<f64>; 5] {
    let [d1, h1, _, h2, _, il, _, _, xi0, xi1, _, _] = *tc;
    let nv = |n: usize| Vector3::new(e[3 * n], e[3 * n + 1], e[3 * n + 2]);
    let (r1, r1x, r1y, r1z) = (nv(0), nv(1), nv(2), nv(3));
    let (r2, r2x, r2y, r2z) = (nv(4), nv(5), nv(6), nv(7));
    [
        (r1 - r2) * d1 + r1x * h1 + r2x * h2,
        (r2y - r1y) * il,
        (r2z - r1z) * il,
        r1y * xi0 + r2y * xi1,
        r1z * xi0 + r2z * xi1,
    ]
}

/// q += wx Tᵀ Q_u at one station, with Q_u,i = Σ_j S_ij u_j (S by Gram
/// index: S_ii = 2σ_ii, S_ij = σ_ij), written out.
fn add_force(tc: &[f64; 12], wx: f64, u: &[Vector3<f64>; 5], s: &[f64; 15], q: &mut ElementVector) {
    let [d1, h1, _, h2, _, il, _, _, xi0, xi1, _, _] = *tc;
    let gu: [Vector3<f64>; 5] =
        std::array::from_fn(|i| (0..5).fold(Vector3::zeros(), |acc, j| acc + u[j] * s[gram(i, j)]));
    let g0 = gu[0] * wx;
    let (ga, gb) = (gu[1] * (wx * il), gu[2] * (wx * il));
    let (gy, gz) = (gu[3] * wx, gu[4] * wx);
    let mut add = |n: usize, v: Vector3<f64>| {
        q[3 * n] += v.x;
        q[3 * n + 1] += v.y;
        q[3 * n + 2] += v.z;
    };
    add(0, g0 * d1);
    add(1, g0 * h1);
    add(2, gy * xi0 - ga);
    add(3, gz * xi0 - gb);
    add(4, -g0 * d1);
    add(5, g0 * h2);
    add(6, gy * xi1 + ga);
    add(7, gz * xi1 + gb);
}

#[cfg(test)]
/// What one axial station leaves for the Jacobian: its energy (J), T's
/// coefficients, the five vectors and S (S_ii = 2σ_ii, S_ij = σ_ij).
struct Station {
    energy: f64,
    tc: [f64; 12],
    u: [Vector3<f64>; 5],
    s: [f64; 15],
}

/// Several elements' forces at once, lane by lane (structure of arrays:
/// `e[i]` holds coordinate i of each element). Each lane performs the
/// operations of [`PreIntegrated::station`] in the same order, with the
/// multiply-adds of `F`: with [`crate::math::simd::Plain`] a lane has the
/// bits of the scalar station; on the AVX2 and AVX-512 paths four elements
/// fill one register and every multiply-add is one instruction (a single
/// element's station is a chain of short dependent steps that leaves the
/// vector units idle). Plain operators on a lane array, no closures: the
/// closures of a first version were not inlined into the SIMD paths'
/// functions and ran without their instruction set (perf: `fma` called as
/// a library function).
#[derive(Clone, Copy)]
struct Lanes<const W: usize>([f64; W]);

impl<const W: usize> Lanes<W> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Lanes([x; W])
    }

    /// self · b + c with the multiply-add of F.
    #[inline(always)]
    fn mul_add<F: Arith>(self, b: Self, c: Self) -> Self {
        let mut out = c;
        for k in 0..W {
            out.0[k] = F::mul_add(self.0[k], b.0[k], c.0[k]);
        }
        out
    }

    /// self · s + c with the multiply-add of F.
    #[inline(always)]
    fn mul_add_s<F: Arith>(self, s: f64, c: Self) -> Self {
        let mut out = c;
        for k in 0..W {
            out.0[k] = F::mul_add(self.0[k], s, c.0[k]);
        }
        out
    }
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const W: usize> std::ops::$tr for Lanes<W> {
            type Output = Self;
            #[inline(always)]
            fn $f(mut self, b: Self) -> Self {
                for k in 0..W {
                    self.0[k] $op b.0[k];
                }
                self
            }
        }
        impl<const W: usize> std::ops::$tr<f64> for Lanes<W> {
            type Output = Self;
            #[inline(always)]
            fn $f(mut self, b: f64) -> Self {
                for k in 0..W {
                    self.0[k] $op b;
                }
                self
            }
        }
    };
}
lane_op!(Add, add, +=);
lane_op!(Sub, sub, -=);
lane_op!(Mul, mul, *=);

impl<const W: usize> std::ops::Neg for Lanes<W> {
    type Output = Self;
    #[inline(always)]
    fn neg(mut self) -> Self {
        for k in 0..W {
            self.0[k] = -self.0[k];
        }
        self
    }
}

/// The force (added to `q`) and the energy of W elements, summed over the
/// axial rule (`nodes`, `weights` on [0, 1]) of elements of length `l`.
#[inline(always)]
fn forces_lanes<F: Arith, const W: usize, const FORCE: bool>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[Lanes<W>; 24],
    q: &mut [Lanes<W>; 24],
) -> Lanes<W> {
    let mut energy = Lanes::splat(0.0);
    for (&xi, &w) in nodes.iter().zip(weights) {
        energy = energy + station_lanes::<F, W, FORCE>(pre, xi, l, w * l, e, q).energy;
    }
    energy
}

/// What a lane station leaves for the Jacobian (as [`Station`] does for
/// one element): its energy (J), the five vectors by components and S.
struct LaneStation<const W: usize> {
    energy: Lanes<W>,
    u: [[Lanes<W>; 3]; 5],
    /// S (S_ii = 2σ_ii, S_ij = σ_ij); an energy-only station stops before
    /// S and leaves σ here, which no caller reads.
    s: [Lanes<W>; 15],
}

/// Force, energy and Jacobian of W elements, in [`PreIntegrated::evaluate`]'s
/// order of operations: each station's Hessian blocks (as
/// `hessian_blocks`), then K's 36 upper node blocks summed over the stations
/// term by term (`NODE_BLOCKS`). The blocks' sums are kept apart from `k`
/// until the end and added once, so that with [`crate::math::simd::Plain`]
/// every lane has the scalar path's bits. One element's Jacobian is a
/// chain of 3 × 3 outer products that leaves the vector units idle; W
/// elements fill the registers (the force kernel's reason, see [`Lanes`]).
#[inline(always)]
fn jacobians_lanes<F: Arith, const W: usize>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[Lanes<W>; 24],
    q: &mut [Lanes<W>; 24],
    k: &mut [[Lanes<W>; 9]; 36],
) -> Lanes<W> {
    let zero = Lanes::<W>::splat(0.0);
    *k = [[zero; 9]; 36];
    let mut energy = zero;
    // The station's 25 Hessian blocks: every one is written at every
    // station (a pair and its transpose), so the array is zeroed once a
    // call, not once a station (a 7 KB memset each, perf).
    let mut h = [[zero; 9]; 25];
    for (&xi, &w) in nodes.iter().zip(weights) {
        let wx = w * l;
        let st = station_lanes::<F, W, true>(pre, xi, l, wx, e, q);
        energy = energy + st.energy;
        let tc = t_coefficients(xi, l);
        for (g, &(i, j)) in GRAM_PAIRS.iter().enumerate() {
            let mut acc = [zero; 9];
            acc[0] = st.s[g];
            acc[4] = st.s[g];
            acc[8] = st.s[g];
            let (start, end) = pre.hessian_ranges[g];
            for &(vl, vr, coef) in &pre.hessian_terms[start..end] {
                for a in 0..3 {
                    let ul = st.u[vl][a] * coef;
                    for b in 0..3 {
                        acc[3 * a + b] = ul.mul_add::<F>(st.u[vr][b], acc[3 * a + b]);
                    }
                }
            }
            h[5 * i + j] = acc;
            if i != j {
                h[5 * j + i] = [
                    acc[0], acc[3], acc[6], acc[1], acc[4], acc[7], acc[2], acc[5], acc[8],
                ];
            }
        }
        for (blk, kb) in NODE_BLOCKS.iter().zip(k.iter_mut()) {
            // The block's sum in registers over its terms (accumulating in
            // memory term by term waited on store forwarding, perf).
            let mut acc = *kb;
            for &(p1, p2, hi) in &blk.terms[..blk.len] {
                let c = wx * tc[p1] * tc[p2];
                for (x, hv) in acc.iter_mut().zip(&h[hi]) {
                    *x = hv.mul_add_s::<F>(c, *x);
                }
            }
            *kb = acc;
        }
    }
    energy
}

/// u = T e of W elements by components (u[v][c]: component c of vector v),
/// T's entries `tc` written out as in [`PreIntegrated::station`].
#[inline(always)]
fn vectors_lanes<F: Arith, const W: usize>(
    tc: &[f64; 12],
    e: &[Lanes<W>; 24],
) -> [[Lanes<W>; 3]; 5] {
    let [d1, h1, _, h2, _, il, _, _, xi0, xi1, _, _] = *tc;
    unrolled!(v in [0, 1, 2, 3, 4] => unrolled!(c in [0, 1, 2] => {
        let (r1, r1x, r1y, r1z) = (e[c], e[3 + c], e[6 + c], e[9 + c]);
        let (r2, r2x, r2y, r2z) = (e[12 + c], e[15 + c], e[18 + c], e[21 + c]);
        match v {
            0 => r2x.mul_add_s::<F>(h2, r1x.mul_add_s::<F>(h1, (r1 - r2) * d1)),
            1 => (r2y - r1y) * il,
            2 => (r2z - r1z) * il,
            3 => r2y.mul_add_s::<F>(xi1, r1y * xi0),
            _ => r2z.mul_add_s::<F>(xi1, r1z * xi0),
        }
    }))
}

/// M y on M's non-zero blocks, lane by lane, each row's sum in a register.
#[inline(always)]
fn m_times_lanes<F: Arith, const W: usize>(
    pre: &PreIntegrated,
    y: &[Lanes<W>; 15],
) -> [Lanes<W>; 15] {
    unrolled!(r in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => match r {
        6..=8 => {
            let my = &pre.m_slope_y[r - 6];
            y[8].mul_add_s::<F>(my[2], y[7].mul_add_s::<F>(my[1], y[6] * my[0]))
        }
        9..=11 => {
            let mz = &pre.m_slope_z[r - 9];
            y[11].mul_add_s::<F>(mz[2], y[10].mul_add_s::<F>(mz[1], y[9] * mz[0]))
        }
        13 => y[13] * pre.m_beta,
        _ => {
            let row = &pre.m_centre[CENTRE_ROW[r]];
            let mut acc = y[CENTRE[0]] * row[0];
            for c in 1..8 {
                acc = y[CENTRE[c]].mul_add_s::<F>(row[c], acc);
            }
            acc
        }
    })
}

/// q += wx Tᵀ Q_u with Q_u,i = Σ_j S_ij u_j (S by Gram index), as in
/// [`PreIntegrated::station`].
#[inline(always)]
fn add_force_lanes<F: Arith, const W: usize>(
    tc: &[f64; 12],
    wx: f64,
    u: &[[Lanes<W>; 3]; 5],
    s: &[Lanes<W>; 15],
    q: &mut [Lanes<W>; 24],
) {
    let [d1, h1, _, h2, _, il, _, _, xi0, xi1, _, _] = *tc;
    let zero = Lanes::<W>::splat(0.0);
    let gu: [[Lanes<W>; 3]; 5] = unrolled!(i in [0, 1, 2, 3, 4] => unrolled!(c in [0, 1, 2] => {
        let mut acc = zero;
        for j in 0..5 {
            acc = u[j][c].mul_add::<F>(s[gram(i, j)], acc);
        }
        acc
    }));
    let wil = wx * il;
    for c in 0..3 {
        let g0 = gu[0][c] * wx;
        let (ga, gb) = (gu[1][c] * wil, gu[2][c] * wil);
        let (gy, gz) = (gu[3][c] * wx, gu[4][c] * wx);
        q[c] = q[c] + g0 * d1;
        q[3 + c] = q[3 + c] + g0 * h1;
        q[6 + c] = q[6 + c] + gy.mul_add_s::<F>(xi0, -ga);
        q[9 + c] = q[9 + c] + gz.mul_add_s::<F>(xi0, -gb);
        q[12 + c] = q[12 + c] + -g0 * d1;
        q[15 + c] = q[15 + c] + g0 * h2;
        q[18 + c] = q[18 + c] + gy.mul_add_s::<F>(xi1, ga);
        q[21 + c] = q[21 + c] + gz.mul_add_s::<F>(xi1, gb);
    }
}

/// [`PreIntegrated::station`]'s force and energy for W elements; without
/// `FORCE` the energy alone (its bits are the same: the force is computed
/// from the energy's terms after them).
#[inline(always)]
fn station_lanes<F: Arith, const W: usize, const FORCE: bool>(
    pre: &PreIntegrated,
    xi: f64,
    l: f64,
    wx: f64,
    e: &[Lanes<W>; 24],
    q: &mut [Lanes<W>; 24],
) -> LaneStation<W> {
    let tc = t_coefficients(xi, l);
    let zero = Lanes::<W>::splat(0.0);
    // Every array below is built entry by entry (`unrolled!`), never zeroed
    // first: a zeroed array filled by a loop compiles to a call to memset
    // (four a station, about a tenth of the force kernel's time, perf).
    let u = vectors_lanes::<F, W>(&tc, e);
    let x: [Lanes<W>; 15] = unrolled!(g in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
        let (a, b) = (&u[GRAM_PAIRS[g].0], &u[GRAM_PAIRS[g].1]);
        a[2].mul_add::<F>(b[2], a[1].mul_add::<F>(b[1], a[0] * b[0]))
    });
    let strain: [Lanes<W>; 15] = unrolled!(r in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
        let (col, coef) = STRAIN_MOMENTS[r];
        x[col].mul_add_s::<F>(coef, Lanes::splat(pre.s0[r]))
    });
    let ms = m_times_lanes::<F, W>(pre, &strain);
    let mut energy = zero;
    for r in 0..15 {
        energy = strain[r].mul_add::<F>(ms[r], energy);
    }
    let sigma: [Lanes<W>; 15] = unrolled!(g in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14] => {
        let r = STRAIN_MOMENT_OF_GRAM[g];
        ms[r] * STRAIN_MOMENTS[r].1
    });
    if !FORCE {
        return LaneStation {
            energy: energy * (wx * 0.5),
            u,
            s: sigma,
        };
    }
    let mut s = sigma;
    for (g, &(i, j)) in GRAM_PAIRS.iter().enumerate() {
        if i == j {
            s[g] = sigma[g] * 2.0;
        }
    }
    add_force_lanes::<F, W>(&tc, wx, &u, &s, q);
    LaneStation {
        energy: energy * (wx * 0.5),
        u,
        s,
    }
}

/// The lane kernel on plain arrays (`e[i][k]`: coordinate i of element k).
#[inline(always)]
fn forces_arrays<F: Arith, const W: usize, const FORCE: bool>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; W]; 24],
    q: &mut [[f64; W]; 24],
) -> [f64; W] {
    let mut el = [Lanes([0.0; W]); 24];
    let mut ql = [Lanes([0.0; W]); 24];
    for i in 0..24 {
        (el[i], ql[i]) = (Lanes(e[i]), Lanes(q[i]));
    }
    let energy = forces_lanes::<F, W, FORCE>(pre, nodes, weights, l, &el, &mut ql);
    for (qi, v) in q.iter_mut().zip(&ql) {
        *qi = v.0;
    }
    energy.0
}

/// Write K's upper node blocks (as [`jacobians_lanes`] leaves them) and
/// their mirror images through `k(i * 24 + j, entry)`: each entry of the
/// 24 × 24 matrix is visited once.
#[inline(always)]
fn node_blocks_to_matrix<const W: usize>(
    blocks: &[[Lanes<W>; 9]; 36],
    mut k: impl FnMut(usize, Lanes<W>),
) {
    for (blk, acc) in NODE_BLOCKS.iter().zip(blocks) {
        let (a, b) = (blk.a, blk.b);
        for r in 0..3 {
            for c in 0..3 {
                let v = acc[3 * r + c];
                k((3 * a + r) * 24 + 3 * b + c, v);
                if a != b {
                    k((3 * b + c) * 24 + 3 * a + r, v);
                }
            }
        }
    }
}

/// One element's force, energy and Jacobian (added to `q` and `k`)
/// through the lane kernel: the bits of a batch of four's lane.
#[inline(always)]
fn jacobians_1_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &ElementVector,
    q: &mut ElementVector,
    k: &mut ElementMatrix,
) -> f64 {
    let el: [Lanes<1>; 24] = std::array::from_fn(|i| Lanes([e[i]]));
    let mut ql: [Lanes<1>; 24] = std::array::from_fn(|i| Lanes([q[i]]));
    let mut blocks = [[Lanes([0.0]); 9]; 36];
    let energy = jacobians_lanes::<F, 1>(pre, nodes, weights, l, &el, &mut ql, &mut blocks);
    for (qi, v) in q.iter_mut().zip(&ql) {
        *qi = v.0[0];
    }
    node_blocks_to_matrix(&blocks, |i, v| k[i] += v.0[0]);
    energy.0[0]
}

/// Four elements' forces (added to `q`), energies and Jacobians (written
/// over `k` by lanes: `k[i * 24 + j][m]` is entry (i, j) of element m, one
/// vector store per entry).
#[inline(always)]
fn jacobians_4_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; 4]; 24],
    q: &mut [[f64; 4]; 24],
    k: &mut [[f64; 4]; 576],
) -> [f64; 4] {
    let el: [Lanes<4>; 24] = std::array::from_fn(|i| Lanes(e[i]));
    let mut ql: [Lanes<4>; 24] = std::array::from_fn(|i| Lanes(q[i]));
    let mut blocks = [[Lanes([0.0; 4]); 9]; 36];
    let energy = jacobians_lanes::<F, 4>(pre, nodes, weights, l, &el, &mut ql, &mut blocks);
    for (qi, v) in q.iter_mut().zip(&ql) {
        *qi = v.0;
    }
    node_blocks_to_matrix(&blocks, |i, v| k[i] = v.0);
    energy.0
}

/// One element's force through the lane kernel (so that a lone element and
/// a batch of four give the same bits on every path).
#[inline(always)]
fn forces_1_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &ElementVector,
    q: &mut ElementVector,
) -> f64 {
    let mut e1 = [[0.0]; 24];
    let mut q1 = [[0.0]; 24];
    for i in 0..24 {
        (e1[i], q1[i]) = ([e[i]], [q[i]]);
    }
    let energy = forces_arrays::<F, 1, true>(pre, nodes, weights, l, &e1, &mut q1);
    for (qi, v) in q.iter_mut().zip(&q1) {
        *qi = v[0];
    }
    energy[0]
}

/// Four elements' forces at once (see [`Lanes`]).
#[inline(always)]
fn forces_4_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; 4]; 24],
    q: &mut [[f64; 4]; 24],
) -> [f64; 4] {
    forces_arrays::<F, 4, true>(pre, nodes, weights, l, e, q)
}

/// Eight elements' forces at once: on the AVX-512 path one 512-bit
/// register a lane operation, faster than four lanes; on the other paths
/// no slower. Each lane has the bits it has in any other
/// batch.
#[inline(always)]
fn forces_8_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; 8]; 24],
    q: &mut [[f64; 8]; 24],
) -> [f64; 8] {
    forces_arrays::<F, 8, true>(pre, nodes, weights, l, e, q)
}

/// Eight elements' strain energies at once, without their forces.
#[inline(always)]
fn energies_8_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; 8]; 24],
) -> [f64; 8] {
    forces_arrays::<F, 8, false>(pre, nodes, weights, l, e, &mut [[0.0; 8]; 24])
}

/// Four elements' strain energies at once, without their forces.
#[inline(always)]
fn energies_4_with<F: Arith>(
    pre: &PreIntegrated,
    nodes: &[f64],
    weights: &[f64],
    l: f64,
    e: &[[f64; 4]; 24],
) -> [f64; 4] {
    forces_arrays::<F, 4, false>(pre, nodes, weights, l, e, &mut [[0.0; 4]; 24])
}

crate::simd_dispatch! {
    fn forces_1(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &ElementVector,
        q: &mut ElementVector,
    ) -> f64 = forces_1_with;
}

crate::simd_dispatch! {
    /// Forces (added to `q`) and energies of four elements given by lanes.
    pub(crate) fn forces_4(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &[[f64; 4]; 24],
        q: &mut [[f64; 4]; 24],
    ) -> [f64; 4] = forces_4_with;
}

crate::simd_dispatch! {
    // The path plus the lane kernel's arguments: the kernel's data as it
    // comes, as forces_1 takes it.
    #[allow(clippy::too_many_arguments)]
    fn jacobians_1(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &ElementVector,
        q: &mut ElementVector,
        k: &mut ElementMatrix,
    ) -> f64 = jacobians_1_with;
}

crate::simd_dispatch! {
    /// Forces (added to `q`), energies and Jacobians (written over `k`,
    /// entry-major with the elements as lanes) of four elements given by
    /// lanes: each element's bits as it gets them alone from
    /// [`PreIntegrated::evaluate`] (into a zero matrix).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn jacobians_4(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &[[f64; 4]; 24],
        q: &mut [[f64; 4]; 24],
        k: &mut [[f64; 4]; 576],
    ) -> [f64; 4] = jacobians_4_with;
}

crate::simd_dispatch! {
    /// Forces (added to `q`) and energies of eight elements given by lanes.
    pub(crate) fn forces_8(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &[[f64; 8]; 24],
        q: &mut [[f64; 8]; 24],
    ) -> [f64; 8] = forces_8_with;
}

crate::simd_dispatch! {
    /// Strain energies of eight elements given by lanes: [`forces_8`]'s,
    /// bit for bit.
    pub(crate) fn energies_8(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &[[f64; 8]; 24],
    ) -> [f64; 8] = energies_8_with;
}

crate::simd_dispatch! {
    /// Strain energies of four elements given by lanes: [`forces_4`]'s
    /// energies, bit for bit, at about half its work.
    pub(crate) fn energies_4(
        pre: &PreIntegrated,
        nodes: &[f64],
        weights: &[f64],
        l: f64,
        e: &[[f64; 4]; 24],
    ) -> [f64; 4] = energies_4_with;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::math::simd::SimdPath;
    use crate::model::WireBuilder;

    /// The Gauss–Legendre rule of order 3 on [0, 1].
    const RULE_NODES: [f64; 3] = [0.1127016653792583, 0.5, 0.8872983346207417];
    const RULE_WEIGHTS: [f64; 3] = [5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0];

    /// The impact scene's two-layer conductor (ν = 0.3 in the cover, so
    /// that every block of M is filled), 8 elements.
    fn two_layer_wire() -> crate::model::Model {
        let core = Material::st_venant_kirchhoff(5990.0, 1.54e11, 0.0, 0.1);
        let cover = Material::st_venant_kirchhoff(2026.0, 5.17e10, 0.3, 0.1);
        WireBuilder::new(2.0, 8)
            .layer(core, 0.0052)
            .layer(cover, 0.01407)
            .build()
            .unwrap()
    }

    /// The wire's pre-integrated section and element length (m).
    fn preintegrated(model: &crate::model::Model) -> (&PreIntegrated, f64) {
        let element = model.element(0);
        let pre = element.plan.preintegrated.as_ref();
        (pre.expect("SVK is pre-integrated"), element.length)
    }

    /// Four of its elements, each perturbed differently (a deformed state).
    fn perturbed_elements(model: &crate::model::Model) -> [ElementVector; 4] {
        std::array::from_fn(|k| {
            let mut e = model.element_coordinates(&model.reference, k);
            for (i, v) in e.iter_mut().enumerate() {
                *v += 0.02 * (((i * 7919 + 31 * k) % 23) as f64 / 23.0 - 0.5);
            }
            e
        })
    }

    /// The lane kernel against the scalar station (the Jacobian path's): on
    /// the baseline path bit for bit, on the fused paths to round-off; and
    /// four or eight elements at once give each element the bits it gets
    /// alone, on every path this CPU runs.
    #[test]
    fn lane_kernel_equals_the_scalar_station_on_every_path() {
        let model = two_layer_wire();
        let (pre, l) = preintegrated(&model);
        let (nodes, weights) = (&RULE_NODES, &RULE_WEIGHTS);
        let elements = perturbed_elements(&model);
        for path in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
            let mut lanes_in = [[0.0; 4]; 24];
            for (k, e) in elements.iter().enumerate() {
                for i in 0..24 {
                    lanes_in[i][k] = e[i];
                }
            }
            let mut lanes_out = [[0.0; 4]; 24];
            let energies = forces_4(path, pre, nodes, weights, l, &lanes_in, &mut lanes_out);
            // The energy-only kernel gives the same energies, bit for bit.
            let alone_energies = energies_4(path, pre, nodes, weights, l, &lanes_in);
            for k in 0..4 {
                assert_eq!(
                    alone_energies[k].to_bits(),
                    energies[k].to_bits(),
                    "{}",
                    path.name()
                );
            }
            // Eight at a time (the four twice): each lane the bits of four's.
            let lanes8: [[f64; 8]; 24] =
                std::array::from_fn(|i| std::array::from_fn(|k| lanes_in[i][k % 4]));
            let mut out8 = [[0.0; 8]; 24];
            let energies8 = forces_8(path, pre, nodes, weights, l, &lanes8, &mut out8);
            let alone8 = energies_8(path, pre, nodes, weights, l, &lanes8);
            for k in 0..8 {
                let name = path.name();
                assert_eq!(energies8[k].to_bits(), energies[k % 4].to_bits(), "{name}");
                assert_eq!(alone8[k].to_bits(), energies[k % 4].to_bits(), "{name}");
                for i in 0..24 {
                    assert_eq!(
                        out8[i][k].to_bits(),
                        lanes_out[i][k % 4].to_bits(),
                        "{name}"
                    );
                }
            }
            for (k, e) in elements.iter().enumerate() {
                let mut alone = [0.0; 24];
                let energy = forces_1(path, pre, nodes, weights, l, e, &mut alone);
                assert_eq!(energy.to_bits(), energies[k].to_bits(), "{}", path.name());
                for i in 0..24 {
                    assert_eq!(
                        alone[i].to_bits(),
                        lanes_out[i][k].to_bits(),
                        "{}",
                        path.name()
                    );
                }
                // The scalar station, as the Jacobian path runs it.
                let mut scalar = [0.0; 24];
                let mut scalar_energy = 0.0;
                for (&xi, &w) in nodes.iter().zip(weights) {
                    scalar_energy += pre.station(xi, l, w * l, e, &mut scalar).energy;
                }
                let size = scalar.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..24 {
                    let diff = (alone[i] - scalar[i]).abs();
                    match path {
                        SimdPath::Baseline => assert_eq!(alone[i].to_bits(), scalar[i].to_bits()),
                        _ => assert!(
                            diff <= 1e-12 * size,
                            "{}: {diff:e} of {size:e}",
                            path.name()
                        ),
                    }
                }
                assert!((energy - scalar_energy).abs() <= 1e-12 * scalar_energy.abs());
            }
        }
    }

    /// The Jacobian lane kernel against the scalar form: bit for bit on the
    /// baseline path (force, energy and all 576 entries), to round-off on
    /// the fused paths; four elements at once give each the bits it gets
    /// alone ([`PreIntegrated::evaluate`]), on every path this CPU runs;
    /// and the force of a Jacobian evaluation is the force-only kernel's.
    #[test]
    fn jacobian_lane_kernel_equals_the_scalar_form_on_every_path() {
        let model = two_layer_wire();
        let (pre, l) = preintegrated(&model);
        let (nodes, weights) = (&RULE_NODES, &RULE_WEIGHTS);
        let elements = perturbed_elements(&model);
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for path in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
            let lanes_in: [[f64; 4]; 24] =
                std::array::from_fn(|i| std::array::from_fn(|k| elements[k][i]));
            let mut q4 = [[0.0; 4]; 24];
            let mut k4 = [[f64::NAN; 4]; 576];
            let u4 = jacobians_4(path, pre, nodes, weights, l, &lanes_in, &mut q4, &mut k4);
            for (k, e) in elements.iter().enumerate() {
                let (mut q1, mut k1) = ([0.0; 24], [0.0; 576]);
                let u1 = jacobians_1(path, pre, nodes, weights, l, e, &mut q1, &mut k1);
                let q_lane: Vec<f64> = (0..24).map(|i| q4[i][k]).collect();
                assert_eq!(u1.to_bits(), u4[k].to_bits(), "{}", path.name());
                assert_eq!(bits(&q1), bits(&q_lane), "{}", path.name());
                let k_lane: Vec<f64> = (0..576).map(|i| k4[i][k]).collect();
                assert_eq!(bits(&k1), bits(&k_lane), "{}", path.name());
                let mut q_force = [0.0; 24];
                forces_1(path, pre, nodes, weights, l, e, &mut q_force);
                assert_eq!(bits(&q1), bits(&q_force), "{}", path.name());
                let (mut qs, mut ks) = ([0.0; 24], [0.0; 576]);
                let us = pre.evaluate_scalar(nodes, weights, l, e, &mut qs, &mut ks);
                let size = ks.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(size > 0.0);
                if path == SimdPath::Baseline {
                    assert_eq!(us.to_bits(), u1.to_bits());
                    assert_eq!(bits(&qs), bits(&q1));
                    assert_eq!(bits(&ks), bits(&k1));
                } else {
                    for (a, b) in ks.iter().zip(&k1) {
                        assert!(
                            (a - b).abs() <= 1e-12 * size,
                            "{}: {a:e} against {b:e}",
                            path.name()
                        );
                    }
                    assert!((us - u1).abs() <= 1e-12 * us.abs());
                }
            }
        }
    }
}
