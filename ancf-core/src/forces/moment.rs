//! A moment load on a node, for any rotation of the node: its generalized
//! forces on the node's section gradients r_y, r_z and their derivatives,
//! the load stiffness of the Newton matrix.
//!
//! A moment M (N m) at a beam's end is a traction over its end face, σ₁₁ =
//! (M × x)·e₁ / I: its virtual work reaches the fully parameterized element
//! through the section gradients alone, as M · δθ with δθ the spin of the
//! section. For a section spanned by a = r_y and b = r_z (normal n = a × b
//! / |a × b|), a rigid rotation δθ moves them by δθ × a, δθ × b, and
//!
//! Q_a = (M' × a) / |a|²,  Q_b = (M' × b) / |b|²,  M' = M − ½ (M · n) n
//!
//! do the work Q_a · δa + Q_b · δb = M · δθ exactly (the two section
//! gradients see a torque about n twice, hence its half). Evaluated at the
//! node's current gradients, this is a moment of fixed direction in space
//! for any rotation (the roll-up's load); a force on r_x instead would
//! shear the end element, an error that grows as the elements shrink.
//! The load is not conservative in three dimensions (a moment of fixed
//! direction does work that depends on the path), so its work is summed
//! along the path ([`work_along`]) and its stiffness is not symmetric.
//!
//! A follower moment turns with the node: its components in the section's
//! frame (n, â, n × â) stay those it had in the reference, and its
//! stiffness adds the turning, ∂Q/∂M · ∂M/∂[a, b].

use crate::math::vec3::{cross, dot, scale, sub};

/// [a]×: the matrix of w ↦ a × w.
fn skew(a: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}

fn mul(x: &[[f64; 3]; 3], y: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| x[i][k] * y[k][j]).sum()))
}

/// The section's normal n = a × b / |a × b| and the moment M' that the two
/// gradients carry.
fn carried(m: [f64; 3], a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64, [f64; 3]) {
    let u = cross(a, b);
    let s = dot(u, u).sqrt();
    let n = scale(u, 1.0 / s);
    let mp = sub(m, scale(n, 0.5 * dot(m, n)));
    (n, s, mp)
}

/// The generalized forces [Q_a, Q_b] (N) of moment `m` (N m) on section
/// gradients `a` = r_y and `b` = r_z.
pub fn moment_forces(m: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 6] {
    let (_, _, mp) = carried(m, a, b);
    let qa = scale(cross(mp, a), 1.0 / dot(a, a));
    let qb = scale(cross(mp, b), 1.0 / dot(b, b));
    [qa[0], qa[1], qa[2], qb[0], qb[1], qb[2]]
}

/// ∂[Q_a, Q_b]/∂[a, b] (N), row-major 6 × 6: the load stiffness, which the
/// Newton matrix of Q_e − Q_ext holds with a minus sign.
pub fn moment_stiffness(m: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [[f64; 6]; 6] {
    let (n, s, mp) = carried(m, a, b);
    // dM' = C du, du = −[b]× da + [a]× db, C = −½ (n Mᵀ + (M·n) I)(I − n nᵀ) / s.
    let mn = dot(m, n);
    let c: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let projector = |k: usize, j: usize| f64::from(u8::from(k == j)) - n[k] * n[j];
            let left = |i: usize, k: usize| n[i] * m[k] + mn * f64::from(u8::from(i == k));
            -0.5 * (0..3).map(|k| left(i, k) * projector(k, j)).sum::<f64>() / s
        })
    });
    let (sa, sb, smp) = (skew(a), skew(b), skew(mp));
    let (aa, bb) = (dot(a, a), dot(b, b));
    let (ma, mb) = (cross(mp, a), cross(mp, b));
    let a_c = mul(&sa, &c);
    let b_c = mul(&sb, &c);
    let blocks: [[[[f64; 3]; 3]; 2]; 2] = [
        [
            // ∂Q_a/∂a = ([a]× C [b]× + [M']×)/|a|² − 2 (M' × a) aᵀ/|a|⁴
            std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    (mul(&a_c, &sb)[i][j] + smp[i][j]) / aa - 2.0 * ma[i] * a[j] / (aa * aa)
                })
            }),
            // ∂Q_a/∂b = −[a]× C [a]× / |a|²
            std::array::from_fn(|i| std::array::from_fn(|j| -mul(&a_c, &sa)[i][j] / aa)),
        ],
        [
            // ∂Q_b/∂a = [b]× C [b]× / |b|²
            std::array::from_fn(|i| std::array::from_fn(|j| mul(&b_c, &sb)[i][j] / bb)),
            // ∂Q_b/∂b = (−[b]× C [a]× + [M']×)/|b|² − 2 (M' × b) bᵀ/|b|⁴
            std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    (-mul(&b_c, &sa)[i][j] + smp[i][j]) / bb - 2.0 * mb[i] * b[j] / (bb * bb)
                })
            }),
        ],
    ];
    std::array::from_fn(|r| std::array::from_fn(|col| blocks[r / 3][col / 3][r % 3][col % 3]))
}

/// The section's frame from its gradients a = r_y, b = r_z: the normal
/// n = a × b / |a × b|, â = a / |a| and n × â.
pub fn section_frame(a: [f64; 3], b: [f64; 3]) -> [[f64; 3]; 3] {
    let (n, _, _) = carried([0.0; 3], a, b);
    let ah = scale(a, 1.0 / dot(a, a).sqrt());
    [n, ah, cross(n, ah)]
}

/// A follower moment's direction in space: its components `c` (N m) in
/// the section's frame ([`section_frame`]) at gradients `a`, `b`.
pub fn follower_moment(c: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let f = section_frame(a, b);
    std::array::from_fn(|i| c[0] * f[0][i] + c[1] * f[1][i] + c[2] * f[2][i])
}

/// The forces of a follower moment of frame components `c`: those of the
/// moment it points to at `a`, `b` ([`moment_forces`]).
pub fn follower_forces(c: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 6] {
    moment_forces(follower_moment(c, a, b), a, b)
}

/// ∂[Q_a, Q_b]/∂[a, b] of a follower moment: the fixed moment's stiffness
/// at the current M plus ∂Q/∂M · ∂M/∂[a, b], M = c₁ n + c₂ â + c₃ n × â.
pub fn follower_stiffness(c: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [[f64; 6]; 6] {
    let m = follower_moment(c, a, b);
    let mut k = moment_stiffness(m, a, b);
    let [n, ah, _] = section_frame(a, b);
    let s = dot(cross(a, b), cross(a, b)).sqrt();
    let la = dot(a, a).sqrt();
    let eye = |i: usize, j: usize| f64::from(u8::from(i == j));
    let p: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| eye(i, j) - n[i] * n[j]));
    let pa: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| (eye(i, j) - ah[i] * ah[j]) / la));
    // dM = (c₁ I − c₃ [â]×) dn + (c₂ I + c₃ [n]×) dâ,
    // dn = P (−[b]× da + [a]× db) / s, dâ = (I − â âᵀ) da / |a|.
    let (sah, sn) = (skew(ah), skew(n));
    let on_n: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| c[0] * eye(i, j) - c[2] * sah[i][j]));
    let on_a: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| c[1] * eye(i, j) + c[2] * sn[i][j]));
    let dn_da = mul(&p, &skew(b)).map(|row| row.map(|v| -v / s));
    let dn_db = mul(&p, &skew(a)).map(|row| row.map(|v| v / s));
    let dm_da: [[f64; 3]; 3] = {
        let (x, y) = (mul(&on_n, &dn_da), mul(&on_a, &pa));
        std::array::from_fn(|i| std::array::from_fn(|j| x[i][j] + y[i][j]))
    };
    let dm_db = mul(&on_n, &dn_db);
    // ∂Q_a/∂M = −[a]× (I − ½ n nᵀ) / |a|², ∂Q_b/∂M likewise.
    let half: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| eye(i, j) - 0.5 * n[i] * n[j]));
    let dq_dm = [
        mul(&skew(a), &half).map(|row| row.map(|v| -v / dot(a, a))),
        mul(&skew(b), &half).map(|row| row.map(|v| -v / dot(b, b))),
    ];
    for (r, dq) in dq_dm.iter().enumerate() {
        for (col, dm) in [dm_da, dm_db].iter().enumerate() {
            let block = mul(dq, dm);
            for i in 0..3 {
                for j in 0..3 {
                    k[3 * r + i][3 * col + j] += block[i][j];
                }
            }
        }
    }
    k
}

/// A load's generalized forces [Q_{r_y}, Q_{r_z}] (N) at section
/// gradients `g` = [r_y, r_z] (`reference`: the node's in the reference,
/// where a follower's components are read), for moment `m` (N m).
fn load_at(m: [f64; 3], follower: bool, g: &[f64; 6], reference: &[f64; 6]) -> [f64; 6] {
    let (a, b) = ([g[0], g[1], g[2]], [g[3], g[4], g[5]]);
    match follower {
        false => moment_forces(m, a, b),
        true => follower_forces(components(m, reference), a, b),
    }
}

/// ∂[Q_{r_y}, Q_{r_z}]/∂[r_y, r_z] of a load, as [`load_at`].
fn load_stiffness(
    m: [f64; 3],
    follower: bool,
    g: &[f64; 6],
    reference: &[f64; 6],
) -> [[f64; 6]; 6] {
    let (a, b) = ([g[0], g[1], g[2]], [g[3], g[4], g[5]]);
    match follower {
        false => moment_stiffness(m, a, b),
        true => follower_stiffness(components(m, reference), a, b),
    }
}

/// `m`'s components in the section frame of gradients `g` = [r_y, r_z].
fn components(m: [f64; 3], g: &[f64; 6]) -> [f64; 3] {
    section_frame([g[0], g[1], g[2]], [g[3], g[4], g[5]]).map(|e| dot(e, m))
}

/// What a moment load needs at `q`: its moment at load factor `factor`
/// (N m), the node's section gradients [r_y, r_z] there and in the
/// reference (where a follower's components are read).
fn load_terms(
    model: &crate::model::Model,
    load: &crate::model::PointLoad,
    q: &[f64],
    factor: f64,
) -> ([f64; 3], [f64; 6], [f64; 6]) {
    (
        load.moment.map(|m| factor * m),
        model.section_gradients(q, load.node),
        model.section_gradients(&model.reference, load.node),
    )
}

/// A model's moment loads' generalized forces at `q` for load factor
/// `factor`: per loaded node, [Q_{r_y}, Q_{r_z}] (N) with the node.
pub fn load_forces(model: &crate::model::Model, q: &[f64], factor: f64) -> Vec<(usize, [f64; 6])> {
    (model.moment_loads())
        .map(|ld| {
            let (m, g, reference) = load_terms(model, ld, q, factor);
            (ld.node, load_at(m, ld.follower, &g, &reference))
        })
        .collect()
}

/// The load stiffness ∂[Q_{r_y}, Q_{r_z}]/∂[r_y, r_z] (N) of a model's
/// moment loads at `q` for load factor `factor`, per loaded node.
pub fn load_stiffnesses(
    model: &crate::model::Model,
    q: &[f64],
    factor: f64,
) -> Vec<(usize, [[f64; 6]; 6])> {
    (model.moment_loads())
        .map(|ld| {
            let (m, g, reference) = load_terms(model, ld, q, factor);
            (ld.node, load_stiffness(m, ld.follower, &g, &reference))
        })
        .collect()
}

/// The work (J) of a model's moment loads (factor `factor`) along the
/// straight path from `q0` to `q1` in coordinates, by 8-point Gauss: a
/// Newton step's, for the line search of statics, and a time step's. In
/// the plane, where the moment has a potential, it is M · Δθ to the rule's
/// accuracy for any step that keeps the section gradients well away from
/// zero (a step turning a section by a right angle: 1.2e-6 relative).
pub fn work_along(model: &crate::model::Model, q0: &[f64], q1: &[f64], factor: f64) -> f64 {
    let rule = crate::math::quadrature::gauss_legendre_unit(8);
    (model.moment_loads())
        .map(|ld| {
            let (m, g0, reference) = load_terms(model, ld, q0, factor);
            let g1 = model.section_gradients(q1, ld.node);
            (rule.nodes.iter().zip(&rule.weights))
                .map(|(s, w)| {
                    let g: [f64; 6] = std::array::from_fn(|k| g0[k] + s * (g1[k] - g0[k]));
                    let f = load_at(m, ld.follower, &g, &reference);
                    w * (0..6).map(|k| f[k] * (g1[k] - g0[k])).sum::<f64>()
                })
                .sum::<f64>()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotate(axis: [f64; 3], angle: f64, v: [f64; 3]) -> [f64; 3] {
        let k = scale(axis, 1.0 / dot(axis, axis).sqrt());
        let (c, s) = (angle.cos(), angle.sin());
        let kv = cross(k, v);
        std::array::from_fn(|i| v[i] * c + kv[i] * s + k[i] * dot(k, v) * (1.0 - c))
    }

    /// For any section turned anywhere, a small rigid rotation δθ of the
    /// node takes Q · δg = M · δθ of work: the moment is M at every
    /// rotation, not only at the reference.
    #[test]
    fn the_forces_do_the_moments_work_in_any_rotation() {
        let m = [3.0, -7.0, 11.0];
        for (axis, angle) in [
            ([0.0, 1.0, 0.0], 0.0),
            ([0.3, 1.0, -0.2], 2.0),
            ([1.0, 0.5, 0.7], 4.0),
        ] {
            let (a, b) = (
                rotate(axis, angle, [0.0, 1.1, 0.0]),
                rotate(axis, angle, [0.0, 0.0, 0.9]),
            );
            let q = moment_forces(m, a, b);
            for dtheta in [[1e-7, 0.0, 0.0], [0.0, 1e-7, 0.0], [0.0, 0.0, 1e-7]] {
                let (da, db) = (cross(dtheta, a), cross(dtheta, b));
                let work: f64 = (0..3).map(|k| q[k] * da[k] + q[3 + k] * db[k]).sum();
                let expected = dot(m, dtheta);
                assert!(
                    (work - expected).abs() < 1e-12 * 20.0,
                    "{work} vs {expected}"
                );
            }
        }
    }

    /// In the plane the moment has a potential: the work along a straight
    /// path in the gradients between two sections turned by Δθ is M Δθ.
    #[test]
    fn the_work_in_the_plane_is_the_moment_times_the_turn() {
        let m = 5.0;
        let (a, theta0, theta1) = ([0.0, 1.0, 0.0], 0.3, 0.3 + 0.5 * std::f64::consts::PI);
        let b = |t: f64| rotate([0.0, 1.0, 0.0], t, [0.0, 0.0, 1.0]);
        let (b0, b1) = (b(theta0), b(theta1));
        let rule = crate::math::quadrature::gauss_legendre_unit(8);
        let work: f64 = (rule.nodes.iter().zip(&rule.weights))
            .map(|(s, w)| {
                let g: [f64; 3] = std::array::from_fn(|k| b0[k] + s * (b1[k] - b0[k]));
                let f = moment_forces([0.0, m, 0.0], a, g);
                w * (0..3).map(|k| f[3 + k] * (b1[k] - b0[k])).sum::<f64>()
            })
            .sum();
        let exact = m * (theta1 - theta0);
        assert!((work / exact - 1.0).abs() < 1e-5, "{work} against {exact}");
    }

    /// A follower moment turns with the section: the forces at a turned
    /// section do the work of the turned moment, and its stiffness is the
    /// derivative of its forces.
    #[test]
    fn a_follower_moment_turns_with_the_section() {
        let c = [3.0, -7.0, 11.0];
        let (a0, b0) = ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        let (axis, angle) = ([0.3, 1.0, -0.2], 2.0);
        let (a, b) = (rotate(axis, angle, a0), rotate(axis, angle, b0));
        let turned = rotate(axis, angle, follower_moment(c, a0, b0));
        let m = follower_moment(c, a, b);
        assert!((0..3).all(|k| (m[k] - turned[k]).abs() < 1e-12));
        let q = follower_forces(c, a, b);
        let dtheta = [0.0, 1e-7, 0.0];
        let (da, db) = (cross(dtheta, a), cross(dtheta, b));
        let work: f64 = (0..3).map(|k| q[k] * da[k] + q[3 + k] * db[k]).sum();
        assert!((work - dot(turned, dtheta)).abs() < 1e-11);

        assert_derivative(
            |a, b| follower_forces(c, a, b),
            |a, b| follower_stiffness(c, a, b),
        );
    }

    /// The load stiffness is the derivative of the forces (central
    /// differences), for stretched and sheared sections too.
    #[test]
    fn the_stiffness_is_the_derivative_of_the_forces() {
        let m = [3.0, -7.0, 11.0];
        assert_derivative(
            |a, b| moment_forces(m, a, b),
            |a, b| moment_stiffness(m, a, b),
        );
    }

    /// `stiffness` is the derivative of `forces` by central differences at
    /// a stretched and sheared section.
    fn assert_derivative(
        forces: impl Fn([f64; 3], [f64; 3]) -> [f64; 6],
        stiffness: impl Fn([f64; 3], [f64; 3]) -> [[f64; 6]; 6],
    ) {
        let (a, b) = ([0.1, 1.2, -0.3], [0.2, 0.25, 0.8]);
        let k = stiffness(a, b);
        let g = [a[0], a[1], a[2], b[0], b[1], b[2]];
        let at = |g: [f64; 6]| forces([g[0], g[1], g[2]], [g[3], g[4], g[5]]);
        let h = 1e-6;
        for j in 0..6 {
            let (mut gp, mut gm) = (g, g);
            gp[j] += h;
            gm[j] -= h;
            let (fp, fm) = (at(gp), at(gm));
            for i in 0..6 {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                assert!(
                    (k[i][j] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "({i}, {j}): {} vs {fd}",
                    k[i][j]
                );
            }
        }
    }
}
