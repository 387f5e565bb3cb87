//! Wire-to-beam contact: the line law of the rods (line.rs) with the gap
//! measured to a frame member's *deformed* centerline instead of a rod's
//! fixed axis, and both beams' coordinates in the force and its Jacobian.
//!
//! **Formulation.** Each Gauss point ξ of the wire's active zone is
//! projected onto the member's centerline (closest point η*, SPEC §9):
//! d = r_w(ξ) − r_m(η*), g = |d| − (R_w + R_m), the potential
//! V = ∫ ½ ε_L ⟨−g⟩² ds over the wire's reference length. This is the
//! point-to-line projection of Meier, Popp & Wall's line-to-line contact
//! (CMAME 2016). Its known weakness is the large crossing angle, where the
//! zone is short and a fixed set of Gauss points straddles it; here the
//! zone's ends are found exactly on the wire (zone.rs, over
//! `BeamGap`) and the Gauss points are placed inside it, so a 90°
//! crossing is integrated as accurately as a rod's and the force moves
//! smoothly as the crossing slides. Point-to-point contact (Wriggers &
//! Zavarise), which the all-angle method (Meier et al., CMAME 2017) blends
//! in at large angles, is therefore not needed; and unlike it, the
//! projection stays unique when the wire lies along the member.
//!
//! The projection crosses the member's element ends: the closest point is
//! sought on every member element within reach and the nearest taken; the
//! centerline is C¹ across nodes, so the gap and the force are continuous
//! when η* moves to the next element.
//!
//! **Linearization.** With t = ∂r_m/∂η and c = |t|² − d · ∂²r_m/∂η², the
//! projection's variation is δη* = [t · (S_w δe_w − S_m δe_m) + d · S_m′ δe_m] / c
//! (zero where η* sits on the member's free end), so
//! ∂d/∂e_w = S_w − t a_wᵀ and ∂d/∂e_m = −S_m − t a_mᵀ. The wire receives
//! S_wᵀ f, the member −S_mᵀ f(η*), whose derivative adds −S_m′ᵀ f δη*.
//! Friction and damping use the relative velocity S_w v_w − S_m v_m.

use super::capsule::{capsules_within, centerline_capsule};
use super::point::{LawInput, point_law};
use super::zone::{GapFunction, centerline, zones_of};
use super::{ContactEvaluator, ContactSample, DeepestPoint};
use crate::element::{ElementMatrix, ElementVector};
use crate::math::vec3::dot;
use crate::model::contact::MemberContact;

/// The nonzero centerline shape functions' indices (r and r_x of each node).
const CENTERLINE: [usize; 4] = [0, 1, 4, 5];

/// One element of a member, at the configuration being evaluated.
#[derive(Clone, Debug)]
pub struct MemberElement {
    /// Its index in the model.
    pub el: usize,
    /// Coordinates (m, –).
    pub e: ElementVector,
    /// Velocities (m/s, 1/s).
    pub v: ElementVector,
    /// Reference length, m.
    pub l: f64,
}

/// What contact with a member adds to one of the member's elements.
#[derive(Clone, Debug)]
pub struct MemberPart {
    /// The member element.
    pub el: usize,
    /// Generalized force on it, N.
    pub q: ElementVector,
    /// −∂Q_m/∂e_m (row-major 24 × 24).
    pub kq_mm: ElementMatrix,
    /// −∂Q_m/∂v_m.
    pub kv_mm: ElementMatrix,
    /// −∂Q_w/∂e_m: rows of the wire element, columns of this one.
    pub kq_wm: ElementMatrix,
    /// −∂Q_w/∂v_m.
    pub kv_wm: ElementMatrix,
    /// −∂Q_m/∂e_w: rows of this element, columns of the wire's.
    pub kq_mw: ElementMatrix,
    /// −∂Q_m/∂v_w.
    pub kv_mw: ElementMatrix,
}

impl MemberPart {
    fn new(el: usize) -> Self {
        MemberPart {
            el,
            q: [0.0; 24],
            kq_mm: [0.0; 576],
            kv_mm: [0.0; 576],
            kq_wm: [0.0; 576],
            kv_wm: [0.0; 576],
            kq_mw: [0.0; 576],
            kv_mw: [0.0; 576],
        }
    }
}

/// What contact with one member adds to one wire element and to the
/// member's elements it touches.
#[derive(Clone, Debug)]
pub struct BeamContactOut {
    /// Generalized force on the wire element, N.
    pub q: ElementVector,
    /// −∂Q_w/∂e_w.
    pub kq: ElementMatrix,
    /// −∂Q_w/∂v_w.
    pub kv: ElementMatrix,
    /// The member elements touched, each with its force and blocks.
    pub parts: Vec<MemberPart>,
    /// Energy, forces and counts.
    pub sample: ContactSample,
    /// The deepest point on the wire element.
    pub deepest: Option<DeepestPoint>,
}

impl Default for BeamContactOut {
    fn default() -> Self {
        BeamContactOut {
            q: [0.0; 24],
            kq: [0.0; 576],
            kv: [0.0; 576],
            parts: Vec::new(),
            sample: ContactSample::default(),
            deepest: None,
        }
    }
}

impl BeamContactOut {
    /// Cleared for the next wire element (the allocation kept).
    pub fn clear(&mut self) {
        self.q = [0.0; 24];
        self.kq.fill(0.0);
        self.kv.fill(0.0);
        self.parts.clear();
        self.sample = ContactSample::default();
        self.deepest = None;
    }

    fn part(&mut self, el: usize) -> &mut MemberPart {
        let k = match self.parts.iter().position(|p| p.el == el) {
            Some(k) => k,
            None => {
                self.parts.push(MemberPart::new(el));
                self.parts.len() - 1
            }
        };
        &mut self.parts[k]
    }
}

/// The centerline shape functions at ξ of an element of length `l` (m):
/// values and their first and second derivatives in ξ (the position is
/// Σ s_i e_i; only r and r_x of the two nodes enter).
pub fn centerline_shapes(xi: f64, l: f64) -> [[f64; 8]; 3] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        [
            1.0 - 3.0 * x2 + 2.0 * x3,
            l * (xi - 2.0 * x2 + x3),
            0.0,
            0.0,
            3.0 * x2 - 2.0 * x3,
            l * (-x2 + x3),
            0.0,
            0.0,
        ],
        [
            -6.0 * xi + 6.0 * x2,
            l * (1.0 - 4.0 * xi + 3.0 * x2),
            0.0,
            0.0,
            6.0 * xi - 6.0 * x2,
            l * (-2.0 * xi + 3.0 * x2),
            0.0,
            0.0,
        ],
        [
            -6.0 + 12.0 * xi,
            l * (-4.0 + 6.0 * xi),
            0.0,
            0.0,
            6.0 - 12.0 * xi,
            l * (-2.0 + 6.0 * xi),
            0.0,
            0.0,
        ],
    ]
}

/// The point of a member's centerline nearest to a point p.
#[derive(Clone, Copy, Debug)]
pub struct Closest {
    /// Index into the member elements searched.
    pub k: usize,
    /// Its coordinate η ∈ [0, 1] on that element.
    pub eta: f64,
    /// Position r_m(η) and ∂r_m/∂η, ∂²r_m/∂η² there (m).
    pub r: [[f64; 3]; 3],
    /// Whether η sits on the member's free end with the minimum beyond
    /// it (then d is not normal to the centerline and δη = 0).
    pub clamped: bool,
}

/// The point of the centerlines of `elements` (one member's) nearest to
/// `p`: on each element the safeguarded Newton iteration on
/// (r(η) − p) · r′(η) = 0 from the best of five samples, clamped to
/// [0, 1]; the nearest over the elements. `None` without elements.
pub fn closest_point(p: [f64; 3], elements: &[MemberElement]) -> Option<(Closest, f64)> {
    let mut best: Option<(Closest, f64)> = None;
    for (k, m) in elements.iter().enumerate() {
        let dist2 = |eta: f64| {
            let r = centerline(&m.e, eta, m.l)[0];
            let d = [p[0] - r[0], p[1] - r[1], p[2] - r[2]];
            dot(d, d)
        };
        let mut eta = [0.0, 0.25, 0.5, 0.75, 1.0]
            .into_iter()
            .map(|x| (x, dist2(x)))
            .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a })
            .0;
        let mut clamped = false;
        for _ in 0..50 {
            let [r, r1, r2] = centerline(&m.e, eta, m.l);
            let d = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
            let f = dot(d, r1);
            let df = dot(r1, r1) + dot(d, r2);
            let step = if df > 0.0 { f / df } else { f.signum() * 0.1 };
            let next = (eta - step).clamp(0.0, 1.0);
            clamped = (next == 0.0 && f > 0.0) || (next == 1.0 && f < 0.0);
            let done = (next - eta).abs() <= 4.0 * f64::EPSILON;
            eta = next;
            if done {
                break;
            }
        }
        let r = centerline(&m.e, eta, m.l);
        let d = [p[0] - r[0][0], p[1] - r[0][1], p[2] - r[0][2]];
        let d2 = dot(d, d);
        if best.is_none_or(|(_, b)| d2 < b) {
            best = Some((Closest { k, eta, r, clamped }, d2));
        }
    }
    // An end of one element is clamped although the next element carries
    // the centerline on: only the member's own ends count as clamped.
    best.map(|(mut c, d2)| {
        if c.clamped {
            let el = elements[c.k].el;
            let continues = if c.eta == 0.0 {
                elements.iter().any(|m| m.el + 1 == el)
            } else {
                elements.iter().any(|m| m.el == el + 1)
            };
            c.clamped = !continues;
        }
        (c, d2)
    })
}

/// D(ξ) = |d|² − R_s² along a wire element against a member: the gap
/// function whose negative intervals are the active zones.
pub(crate) struct BeamGap<'a> {
    pub e: &'a ElementVector,
    pub l: f64,
    pub elements: &'a [MemberElement],
    pub reach: f64,
}

impl GapFunction for BeamGap<'_> {
    fn eval(&self, xi: f64) -> [f64; 3] {
        let [p, p1, p2] = centerline(self.e, xi, self.l);
        let Some((c, _)) = closest_point(p, self.elements) else {
            return [1.0, 0.0, 0.0];
        };
        let [r, r1, r2] = c.r;
        let d = [p[0] - r[0], p[1] - r[1], p[2] - r[2]];
        // dd/dξ = p′ − t η′, η′ = (t · p′) / c (zero on a free end).
        let projected = if c.clamped {
            0.0
        } else {
            let t1 = dot(r1, p1);
            t1 * t1 / (dot(r1, r1) - dot(d, r2))
        };
        [
            dot(d, d) - self.reach * self.reach,
            2.0 * dot(d, p1),
            2.0 * (dot(p1, p1) - projected + dot(d, p2)),
        ]
    }
}

/// Line contact of one wire element (coordinates `e`, velocities `v`,
/// length `l`) with one member (`member`, partner index `partner`, its
/// elements within reach `elements`), in a contact event that began at
/// `impact_speed` (m/s; 0: none yet). Adds to `out`; with `jacobians`, the
/// blocks too.
#[allow(clippy::too_many_arguments)]
pub(crate) fn element_member(
    contact: &ContactEvaluator,
    partner: usize,
    member: &MemberContact,
    e: &ElementVector,
    v: &ElementVector,
    l: f64,
    elements: &[MemberElement],
    impact_speed: f64,
    jacobians: bool,
    out: &mut BeamContactOut,
) {
    let reach = member.radius + contact.wire_radius;
    // No zone where no member element's capsule comes within reach (most
    // of the elements the broad phase's spheres let through): the search
    // below would sample the gap and find it positive everywhere.
    let wire = centerline_capsule(e, l);
    let near = |m: &MemberElement| capsules_within(&wire, &centerline_capsule(&m.e, m.l), reach);
    if !elements.iter().any(near) {
        return;
    }
    let damping = member.damping.map(|d| {
        if impact_speed > 0.0 {
            d.factor(impact_speed, contact.settings.min_impact_speed)
        } else {
            0.0
        }
    });
    let moving = member.friction > 0.0 || damping.is_some();
    let rule = &contact.zone_rule;
    let gap = BeamGap {
        e,
        l,
        elements,
        reach,
    };
    for &(a, b) in zones_of(&gap).iter() {
        let pieces = ((b - a) / super::line::MAX_PIECE).ceil().max(1.0);
        let len = (b - a) / pieces;
        for piece in 0..pieces as usize {
            let start = a + piece as f64 * len;
            for (x, w) in rule.nodes.iter().zip(&rule.weights) {
                let xi = start + x * len;
                let sw = centerline_shapes(xi, l)[0];
                let p: [f64; 3] =
                    std::array::from_fn(|c| CENTERLINE.iter().map(|&i| sw[i] * e[3 * i + c]).sum());
                let Some((cp, _)) = closest_point(p, elements) else {
                    continue;
                };
                let m = &elements[cp.k];
                let [sm, sm1, _] = centerline_shapes(cp.eta, m.l);
                let [r, t, r2] = cp.r;
                let d = [p[0] - r[0], p[1] - r[1], p[2] - r[2]];
                let interp = |s: &[f64; 8], x: &ElementVector| -> [f64; 3] {
                    std::array::from_fn(|c| CENTERLINE.iter().map(|&i| s[i] * x[3 * i + c]).sum())
                };
                let velocity = if moving {
                    let (vw, vm) = (interp(&sw, v), interp(&sm, &m.v));
                    [vw[0] - vm[0], vw[1] - vm[1], vw[2] - vm[2]]
                } else {
                    [0.0; 3]
                };
                let law = LawInput {
                    w: d,
                    offset: reach,
                    stiffness: member.contact_stiffness * w * len * l,
                    axis: None,
                    plane: None,
                    friction: member.friction,
                    slip_velocity: contact.settings.slip_velocity,
                    damping,
                    velocity,
                };
                let Some(pf) = point_law(&law, &mut out.sample) else {
                    continue;
                };
                if out.deepest.is_none_or(|dp| pf.penetration > dp.penetration) {
                    let (y, z) = super::line::facing_point(e, xi, &pf.n, contact.wire_radius);
                    out.deepest = Some(DeepestPoint {
                        rod: partner,
                        xi,
                        y,
                        z,
                        penetration: pf.penetration,
                    });
                }
                let f = pf.f;
                for &i in &CENTERLINE {
                    for c in 0..3 {
                        out.q[3 * i + c] += sw[i] * f[c];
                    }
                }
                let part = out.part(m.el);
                for &i in &CENTERLINE {
                    for c in 0..3 {
                        part.q[3 * i + c] -= sm[i] * f[c];
                    }
                }
                if !jacobians {
                    continue;
                }
                // δη = a_w · δe_w + a_m · δe_m (zero on a free end).
                let (mut aw, mut am) = ([0.0; 24], [0.0; 24]);
                if !cp.clamped {
                    let c = dot(t, t) - dot(d, r2);
                    for &i in &CENTERLINE {
                        for k in 0..3 {
                            aw[3 * i + k] = sw[i] * t[k] / c;
                            am[3 * i + k] = (-sm[i] * t[k] + sm1[i] * d[k]) / c;
                        }
                    }
                }
                // ∂v_rel/∂η = −S_m′ v_m.
                let vm1 = if moving { interp(&sm1, &m.v) } else { [0.0; 3] };
                // ∂f/∂e = (∂f/∂d)(∂d/∂e) + (∂f/∂v_rel)(−v_m′ aᵀ), 3 × 24 each.
                let df = |s: &[f64; 8], sign: f64, a: &[f64; 24]| -> [[f64; 24]; 3] {
                    let mut out = [[0.0; 24]; 3];
                    for (row, o) in out.iter_mut().enumerate() {
                        // (∂f/∂d) t and (∂f/∂v) v_m′: the columns that multiply aᵀ.
                        let dt: f64 = (0..3).map(|k| pf.dfdp[row][k] * t[k]).sum();
                        let dv: f64 = (0..3).map(|k| pf.dfdv[row][k] * vm1[k]).sum();
                        for j in 0..24 {
                            o[j] = -(dt + dv) * a[j];
                        }
                        for &i in &CENTERLINE {
                            for k in 0..3 {
                                o[3 * i + k] += sign * s[i] * pf.dfdp[row][k];
                            }
                        }
                    }
                    out
                };
                let (fw, fm) = (df(&sw, 1.0, &aw), df(&sm, -1.0, &am));
                for &i in &CENTERLINE {
                    for row in 0..3 {
                        let (rw, rm) = (sw[i], sm[i]);
                        let (m1f, r) = (sm1[i] * f[row], 3 * i + row);
                        for j in 0..24 {
                            out.kq[r * 24 + j] -= rw * fw[row][j];
                        }
                        let part = out.part(m.el);
                        for j in 0..24 {
                            part.kq_wm[r * 24 + j] -= rw * fm[row][j];
                            part.kq_mw[r * 24 + j] += rm * fw[row][j] + m1f * aw[j];
                            part.kq_mm[r * 24 + j] += rm * fm[row][j] + m1f * am[j];
                        }
                    }
                }
                if moving {
                    for &i in &CENTERLINE {
                        for &jn in &CENTERLINE {
                            for a in 0..3 {
                                for b in 0..3 {
                                    let g = pf.dfdv[a][b];
                                    let (r, col) = ((3 * i + a) * 24, 3 * jn + b);
                                    out.kv[r + col] -= sw[i] * g * sw[jn];
                                    let part = out.part(m.el);
                                    part.kv_wm[r + col] += sw[i] * g * sm[jn];
                                    part.kv_mw[r + col] += sm[i] * g * sw[jn];
                                    part.kv_mm[r + col] -= sm[i] * g * sm[jn];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The centre and radius (m) of a sphere holding an element's centerline:
/// around the Bézier control points r₁, r₁ + l/3 r₁ₓ, r₂ − l/3 r₂ₓ, r₂
/// (the cubic lies in their hull).
pub fn centerline_sphere(e: &ElementVector, l: f64) -> ([f64; 3], f64) {
    let bezier: [[f64; 3]; 4] = std::array::from_fn(|k| {
        std::array::from_fn(|c| match k {
            0 => e[c],
            1 => e[c] + l / 3.0 * e[3 + c],
            2 => e[12 + c] - l / 3.0 * e[15 + c],
            _ => e[12 + c],
        })
    });
    let centre: [f64; 3] = std::array::from_fn(|c| 0.25 * bezier.iter().map(|b| b[c]).sum::<f64>());
    let radius = bezier
        .iter()
        .map(|b| {
            let d = [b[0] - centre[0], b[1] - centre[1], b[2] - centre[2]];
            dot(d, d)
        })
        .fold(0.0, f64::max)
        .sqrt();
    (centre, radius)
}

/// Whether two centerline spheres are within `reach` (m) of each other.
pub fn spheres_within(a: ([f64; 3], f64), b: ([f64; 3], f64), reach: f64) -> bool {
    let d = [a.0[0] - b.0[0], a.0[1] - b.0[1], a.0[2] - b.0[2]];
    dot(d, d).sqrt() <= a.1 + b.1 + reach
}
