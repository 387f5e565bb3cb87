//! The penalty and friction force at one contact point, shared by every
//! contact law: the surface law's test points and the line law's Gauss
//! points differ only in where the point sits, what gap offset applies and
//! what measure (area or length) its stiffness is multiplied by.

use super::ContactSample;
use crate::element::{ElementMatrix, ElementVector};
use crate::math::vec3::dot;
use crate::model::contact::Rod;

/// The vector from the rod's nearest axis point to `p` (m), and whether the
/// nearest point is inside the rod's length (`true`: the vector is normal to
/// the axis) or on an end (`false`: an end cap). `None` for `cap = false`
/// when `p` lies beyond the rod's ends (open ends: the surface law).
///
/// For a ground (a plane) the vector from its point to `p`, whose component
/// along the normal is the signed distance ([`LawInput::plane`]).
pub(crate) fn axis_offset(rod: &Rod, p: &[f64; 3], caps: bool) -> Option<([f64; 3], bool)> {
    let d = rod.axis;
    let rel = [
        p[0] - rod.center[0],
        p[1] - rod.center[1],
        p[2] - rod.center[2],
    ];
    if rod.is_ground() {
        return Some((rel, true));
    }
    let along = dot(rel, d);
    let (foot, inside) = match rod.length {
        Some(len) if along.abs() > 0.5 * len => {
            if !caps {
                return None;
            }
            (0.5 * len * along.signum(), false)
        }
        _ => (along, true),
    };
    Some((
        [
            rel[0] - foot * d[0],
            rel[1] - foot * d[1],
            rel[2] - foot * d[2],
        ],
        inside,
    ))
}

/// What contact adds to one element: the generalized force (N) and, when
/// asked, −∂Q/∂q and −∂Q/∂v; with the element's velocities (friction).
pub(crate) struct ElementOut<'a> {
    /// Element velocities (m/s and 1/s), read by friction and damping.
    pub v: &'a ElementVector,
    /// Contact damping factor χ (s/m) of this element and rod when the rod
    /// has damping (0 at an event's first step: the rate is only measured);
    /// `None` without.
    pub damping: Option<f64>,
    pub q: &'a mut ElementVector,
    pub kq: Option<&'a mut ElementMatrix>,
    pub kv: Option<&'a mut ElementMatrix>,
    /// Energy, normal force, friction power and resultant so far.
    pub sample: ContactSample,
}

/// One point of contact: where it is and how stiff it is.
pub(crate) struct PointInput<'a> {
    /// Shape functions of the point (its position is S e).
    pub s: &'a [f64; 8],
    /// Offset from the rod's nearest axis point to `p`, m.
    pub w: [f64; 3],
    /// `w` is normal to the axis (inside the rod's length), so the normal
    /// moves in the plane normal to the axis only.
    pub inside: bool,
    /// The gap is |w| − `offset` (m): the rod radius for surface points,
    /// rod + wire radius for centerline points.
    pub offset: f64,
    /// Stiffness times the point's measure: N/m of gap.
    pub stiffness: f64,
}

/// What one active point contributes.
pub(crate) struct PointResult {
    /// Penetration −g > 0, m.
    pub penetration: f64,
    /// Outward normal (from the rod to the wire).
    pub n: [f64; 3],
}

/// One contact point's law, wherever the point sits.
pub(crate) struct LawInput {
    /// Offset from the partner's nearest point to the point, m.
    pub w: [f64; 3],
    /// The gap is |w| − `offset` (m).
    pub offset: f64,
    /// Stiffness times the point's measure: N/m of gap.
    pub stiffness: f64,
    /// A rigid rod's axis when the nearest point is inside its length (the
    /// normal then turns in the plane normal to it); `None`: in every
    /// direction.
    pub axis: Option<[f64; 3]>,
    /// A plane's unit normal: then the gap is n · w − `offset`, signed, and
    /// the normal does not turn (`axis` is not read).
    pub plane: Option<[f64; 3]>,
    /// Coulomb μ (0: no friction).
    pub friction: f64,
    /// Friction's regularization velocity v_ε, m/s.
    pub slip_velocity: f64,
    /// Contact damping factor χ (s/m), `None` without damping.
    pub damping: Option<f64>,
    /// Velocity of the point relative to the partner, m/s (read with
    /// friction or damping only).
    pub velocity: [f64; 3],
}

/// The force at one contact point and its derivatives.
pub(crate) struct PointForce {
    /// Force on the point (normal + friction), N.
    pub f: [f64; 3],
    /// ∂f/∂p: with respect to the point's position, N/m.
    pub dfdp: [[f64; 3]; 3],
    /// ∂f/∂ṗ: with respect to its relative velocity, N s/m (zero without
    /// friction and damping).
    pub dfdv: [[f64; 3]; 3],
    /// Penetration −g > 0, m.
    pub penetration: f64,
    /// Outward normal (from the partner to the point).
    pub n: [f64; 3],
}

/// The penalty, damping and friction law of [`point_contact`] at one point,
/// for any partner; adds energy, normal force, powers and the force to
/// `sample`. `None` when the point is apart.
pub(crate) fn point_law(pt: &LawInput, sample: &mut ContactSample) -> Option<PointForce> {
    let w = pt.w;
    let (dist, n) = match pt.plane {
        // A plane: the signed distance, the fixed normal.
        Some(normal) => (dot(w, normal), normal),
        None => {
            let dist = dot(w, w).sqrt();
            (dist, [w[0] / dist, w[1] / dist, w[2] / dist])
        }
    };
    let g = dist - pt.offset;
    if g >= 0.0 || (pt.plane.is_none() && dist == 0.0) {
        return None;
    }
    // Inside a rod's length the normal turns in the plane normal to the
    // axis (∂w/∂p = I − d dᵀ); on an end cap in every direction (∂w/∂p = I);
    // a plane's does not turn.
    let (d, dd) = match pt.axis {
        Some(d) => (d, 1.0),
        None => ([0.0; 3], 0.0),
    };
    let turns = if pt.plane.is_some() { 0.0 } else { 1.0 };
    let kn = pt.stiffness;
    let elastic = kn * (-g);
    // ∂n/∂p = (I − n nᵀ − d dᵀ) / |w| inside, (I − n nᵀ) / |w| on a cap, 0
    // on a plane
    let nmat = |a: usize, b: usize| {
        turns * ((a == b) as u8 as f64 - n[a] * n[b] - dd * d[a] * d[b]) / dist
    };
    let friction = pt.friction > 0.0;
    let damped = pt.damping.is_some();
    let vp = pt.velocity;
    // The normal force F and, with damping, its gradients ∂F/∂p and ∂F/∂ṙ.
    let (fnorm, grad_p, grad_v) = if damped {
        // Hunt–Crossley: F = k δ (1 + χ δ̇)⁺ with δ = −g, δ̇ = −n · ṙ;
        // ∂δ/∂p = −n, ∂δ̇/∂p = −(∂n/∂p) ṙ, ∂δ̇/∂ṙ = −n.
        let chi = pt.damping.unwrap_or(0.0);
        let rate = -dot(vp, n);
        let m = 1.0 + chi * rate;
        sample.approach_speed = sample.approach_speed.max(rate);
        if m > 0.0 {
            let fnorm = elastic * m;
            sample.damping_power += (fnorm - elastic) * rate;
            let nv: [f64; 3] = std::array::from_fn(|a| (0..3).map(|b| nmat(a, b) * vp[b]).sum());
            let grad_p = std::array::from_fn(|b| -kn * m * n[b] - elastic * chi * nv[b]);
            let grad_v = std::array::from_fn(|b| -elastic * chi * n[b]);
            (fnorm, grad_p, grad_v)
        } else {
            // Separating faster than 1/χ: the damping cancels the spring.
            sample.damping_power += -elastic * rate;
            (0.0, [0.0; 3], [0.0; 3])
        }
    } else {
        (elastic, [0.0; 3], [0.0; 3])
    };
    sample.energy += 0.5 * kn * g * g;
    sample.max_penetration = sample.max_penetration.max(-g);
    sample.normal_force += fnorm;
    sample.active += 1;
    let mut f = [fnorm * n[0], fnorm * n[1], fnorm * n[2]];
    // ∂f_n/∂p = n (∂F/∂p)ᵀ + F ∂n/∂p, ∂F/∂p = −kn n without damping
    let mut dfdp = [[0.0; 3]; 3];
    let mut dfdv = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            dfdp[a][b] = if damped {
                n[a] * grad_p[b] + fnorm * nmat(a, b)
            } else {
                -kn * n[a] * n[b] + fnorm * nmat(a, b)
            };
            if damped {
                dfdv[a][b] = n[a] * grad_v[b];
            }
        }
    }
    if friction {
        let vn = dot(vp, n);
        let vt = [vp[0] - vn * n[0], vp[1] - vn * n[1], vp[2] - vn * n[2]];
        let eps = pt.slip_velocity;
        let s = (dot(vt, vt) + eps * eps).sqrt();
        let t = [vt[0] / s, vt[1] / s, vt[2] / s];
        let mu = pt.friction;
        for c in 0..3 {
            f[c] -= mu * fnorm * t[c];
        }
        sample.friction_power += mu * fnorm * dot(vt, vt) / s;
        // A = ∂t/∂v_t = (I − v_t v_tᵀ / s²) / s
        let amat = |a: usize, b: usize| ((a == b) as u8 as f64 - vt[a] * vt[b] / (s * s)) / s;
        // ∂t/∂n = −A (n v_pᵀ + (v_p·n) I)
        let mut dtdn = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                dtdn[a][b] = -(0..3)
                    .map(|c| amat(a, c) * (n[c] * vp[b] + if c == b { vn } else { 0.0 }))
                    .sum::<f64>();
            }
        }
        for a in 0..3 {
            for b in 0..3 {
                // ∂f_t/∂p = −μ [ t (∂F_n/∂p) + F_n (∂t/∂n)(∂n/∂p) ]
                let dtdp: f64 = (0..3).map(|c| dtdn[a][c] * nmat(c, b)).sum();
                let dfn = if damped { grad_p[b] } else { -kn * n[b] };
                dfdp[a][b] += -mu * (t[a] * dfn + fnorm * dtdp);
                // ∂f_t/∂v_p = −μ [ t (∂F_n/∂ṙ) + F_n A P ], P = I − n nᵀ
                let ap: f64 = (0..3)
                    .map(|c| amat(a, c) * ((c == b) as u8 as f64 - n[c] * n[b]))
                    .sum();
                if damped {
                    dfdv[a][b] += -mu * (t[a] * grad_v[b] + fnorm * ap);
                } else {
                    dfdv[a][b] = -mu * fnorm * ap;
                }
            }
        }
    }
    for c in 0..3 {
        sample.force[c] += f[c];
    }
    Some(PointForce {
        f,
        dfdp,
        dfdv,
        penetration: -g,
        n,
    })
}

/// Penalty force F n, F = k ⟨−g⟩ (times (1 + χ δ̇)⁺ with contact damping,
/// δ̇ = −n · ṙ the rate of penetration), and regularized Coulomb friction
/// −μ F v_t / √(|v_t|² + v_ε²) at one point; scatters them into the
/// element force `out.q` and their derivatives −∂f/∂q into `out.kq`,
/// −∂f/∂v into `out.kv`, and adds energy ½ k g², normal force, friction and
/// damping power and the force to `out.sample`. `None` when the point is
/// apart (g ≥ 0).
pub(crate) fn point_contact(
    pt: &PointInput,
    rod: &Rod,
    slip_velocity: f64,
    out: &mut ElementOut,
) -> Option<PointResult> {
    let v = out.v;
    let vp: [f64; 3] = if rod.friction > 0.0 || out.damping.is_some() {
        std::array::from_fn(|c| (0..8).map(|i| pt.s[i] * v[3 * i + c]).sum())
    } else {
        [0.0; 3]
    };
    let law = LawInput {
        w: pt.w,
        offset: pt.offset,
        stiffness: pt.stiffness,
        axis: pt.inside.then_some(rod.axis),
        plane: rod.is_ground().then_some(rod.axis),
        friction: rod.friction,
        slip_velocity,
        damping: out.damping,
        velocity: vp,
    };
    let PointForce {
        f,
        dfdp,
        dfdv,
        penetration,
        n,
    } = point_law(&law, &mut out.sample)?;
    let friction = rod.friction > 0.0;
    let damped = out.damping.is_some();
    let s = pt.s;
    for i in 0..8 {
        for c in 0..3 {
            out.q[3 * i + c] += s[i] * f[c];
        }
    }
    let add = |m: &mut ElementMatrix, blk: &[[f64; 3]; 3]| {
        for i in 0..8 {
            for j in 0..8 {
                let sij = s[i] * s[j];
                if sij == 0.0 {
                    continue;
                }
                for a in 0..3 {
                    for b in 0..3 {
                        m[(3 * i + a) * 24 + 3 * j + b] -= sij * blk[a][b];
                    }
                }
            }
        }
    };
    if let Some(k) = out.kq.as_deref_mut() {
        add(k, &dfdp);
    }
    if (friction || damped)
        && let Some(k) = out.kv.as_deref_mut()
    {
        add(k, &dfdv);
    }
    Some(PointResult { penetration, n })
}
