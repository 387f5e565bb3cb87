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
use crate::quadrature::SectionPoint;
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
    pub m0: f64,
    pub yy: f64,
    pub zz: f64,
    pub y4: f64,
    pub z4: f64,
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
#[derive(Clone, Debug)]
pub struct PreIntegrated {
    m: M15,
    j: M15,
    s0: V15,
    /// Jᵀ M J, the (constant) Hessian in x.
    pub a: M15,
    /// J row by row: (column, coefficient) of its single non-zero.
    jmap: [(usize, f64); 15],
}

/// Voigt rows that a y- or z-slope of the strain can have (xx, xz, xy).
const SLOPE_ROWS: [usize; 3] = [0, 4, 5];

impl PreIntegrated {
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
        let jmap = std::array::from_fn(|r| {
            let nz: Vec<(usize, f64)> = (0..15)
                .filter(|&c| j[(r, c)] != 0.0)
                .map(|c| (c, j[(r, c)]))
                .collect();
            assert_eq!(
                nz.len(),
                1,
                "each strain moment is one Gram entry times a constant"
            );
            nz[0]
        });
        PreIntegrated {
            m: M15::zeros(),
            j,
            s0,
            a: M15::zeros(),
            jmap,
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

    /// Energy, force and Jacobian of the pre-integrated laws at the axial
    /// station ξ with weight `wx` (m), added to `q` and `k`.
    pub fn evaluate(
        &self,
        xi: f64,
        l: f64,
        wx: f64,
        e: &ElementVector,
        q: &mut ElementVector,
        k: Option<&mut ElementMatrix>,
    ) -> f64 {
        // u = T e: (node, coefficient) pairs for each of the five vectors.
        let d1 = (-6.0 * xi + 6.0 * xi * xi) / l;
        let t: [[(usize, f64); 4]; 5] = [
            [
                (0, d1),
                (1, 1.0 - 4.0 * xi + 3.0 * xi * xi),
                (4, -d1),
                (5, -2.0 * xi + 3.0 * xi * xi),
            ],
            [(2, -1.0 / l), (6, 1.0 / l), (0, 0.0), (0, 0.0)],
            [(3, -1.0 / l), (7, 1.0 / l), (0, 0.0), (0, 0.0)],
            [(2, 1.0 - xi), (6, xi), (0, 0.0), (0, 0.0)],
            [(3, 1.0 - xi), (7, xi), (0, 0.0), (0, 0.0)],
        ];
        let mut u = [[0.0f64; 3]; 5];
        for (i, row) in t.iter().enumerate() {
            for &(node, c) in row {
                for k in 0..3 {
                    u[i][k] += c * e[3 * node + k];
                }
            }
        }
        let dot = |i: usize, j: usize| u[i][0] * u[j][0] + u[i][1] * u[j][1] + u[i][2] * u[j][2];
        let mut x = V15::zeros();
        for i in 0..5 {
            for j in i..5 {
                x[gram(i, j)] = dot(i, j);
            }
        }
        // J has one non-zero per row: apply it as a map.
        let mut strain = self.s0;
        for (r, &(col, coef)) in self.jmap.iter().enumerate() {
            strain[r] += coef * x[col];
        }
        let ms = self.m * strain;
        let mut sigma = V15::zeros();
        for (r, &(col, coef)) in self.jmap.iter().enumerate() {
            sigma[col] += coef * ms[r];
        }
        let energy = wx * 0.5 * strain.dot(&ms);
        // ∂U/∂u_i = Σ_j S_ij u_j with S_ii = 2σ_ii, S_ij = σ_ij.
        let s = |i: usize, j: usize| {
            if i == j {
                2.0 * sigma[gram(i, i)]
            } else {
                sigma[gram(i, j)]
            }
        };
        let mut gu = [[0.0f64; 3]; 5];
        for i in 0..5 {
            for j in 0..5 {
                let sij = s(i, j);
                for k in 0..3 {
                    gu[i][k] += sij * u[j][k];
                }
            }
        }
        for (i, row) in t.iter().enumerate() {
            for &(node, c) in row {
                for k in 0..3 {
                    q[3 * node + k] += wx * c * gu[i][k];
                }
            }
        }
        let Some(kmat) = k else { return energy };
        // ∂x_(mn)/∂u_i = δ_im u_n + δ_in u_m (2u_i for m = n = i).
        // H_ij = S_ij I + Σ_(mn),(pq) A_(mn)(pq) (∂x_mn/∂u_i)(∂x_pq/∂u_j)ᵀ.
        // J[i] lists (gram index, vector index l, factor): ∂x/∂u_i = factor · u_l.
        let mut jac: [[(usize, usize, f64); 5]; 5] = [[(0, 0, 0.0); 5]; 5];
        for (i, ji) in jac.iter_mut().enumerate() {
            for (l, slot) in ji.iter_mut().enumerate() {
                *slot = (gram(i, l), l, if i == l { 2.0 } else { 1.0 });
            }
        }
        let mut h = [[[[0.0f64; 3]; 3]; 5]; 5];
        for i in 0..5 {
            for j in i..5 {
                let mut blk = [[0.0f64; 3]; 3];
                for &(gi, l, fi) in &jac[i] {
                    for &(gj, n, fj) in &jac[j] {
                        let c = self.a[(gi, gj)] * fi * fj;
                        if c == 0.0 {
                            continue;
                        }
                        for r in 0..3 {
                            for cc in 0..3 {
                                blk[r][cc] += c * u[l][r] * u[n][cc];
                            }
                        }
                    }
                }
                let sij = s(i, j);
                for r in 0..3 {
                    blk[r][r] += sij;
                }
                h[i][j] = blk;
                if i != j {
                    for r in 0..3 {
                        for cc in 0..3 {
                            h[j][i][cc][r] = blk[r][cc];
                        }
                    }
                }
            }
        }
        for (i, ti) in t.iter().enumerate() {
            for &(ni, ci) in ti {
                if ci == 0.0 {
                    continue;
                }
                for (j, tj) in t.iter().enumerate() {
                    for &(nj, cj) in tj {
                        if cj == 0.0 {
                            continue;
                        }
                        let c = wx * ci * cj;
                        for r in 0..3 {
                            for cc in 0..3 {
                                kmat[(3 * ni + r) * 24 + 3 * nj + cc] += c * h[i][j][r][cc];
                            }
                        }
                    }
                }
            }
        }
        energy
    }
}
