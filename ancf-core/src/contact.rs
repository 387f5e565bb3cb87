//! Penalty contact between the wire's deformed outer surface and rigid rods,
//! with regularized Coulomb friction (SPEC §7).
//!
//! Each element carries a fixed set of surface test points: `stations`
//! Gauss points along ξ times `angles` equally spaced angles φ on the outer
//! radius, (y, z) = R_w (cos φ, sin φ), so the surface follows the deformed
//! cross section. A point with gap g = |p⊥| − R_rod < 0 gets the normal force
//! ε_N (−g) w n, w its reference surface area (m²): ε_N is a pressure per
//! penetration (N/m³) and results converge as test points are refined.
//! The normal force derives from the potential V = Σ ½ ε_N g² w, so a
//! frictionless impact conserves energy. Fixed test points keep V smooth;
//! the broad phase only skips elements whose centerline is far from every rod.

use crate::element::{ElementMatrix, ElementVector, shape_functions};
use crate::quadrature::gauss_legendre_unit;

/// A rigid cylinder.
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    /// A point on the axis, m.
    pub center: [f64; 3],
    /// Unit axis direction.
    pub axis: [f64; 3],
    /// Radius, m.
    pub radius: f64,
    /// Length, m, centred on `center`; `None` is infinite.
    pub length: Option<f64>,
    /// Penalty ε_N, N/m³ (force per area per penetration).
    pub contact_stiffness: f64,
    /// Coulomb coefficient μ; 0 = frictionless (no friction code runs).
    pub friction: f64,
}

/// Resolution of the contact test points and the friction regularization.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSettings {
    /// Gauss stations along each element. Default 8.
    pub stations: usize,
    /// Angles around the outer surface. Default 16.
    pub angles: usize,
    /// Regularization velocity v_ε of Coulomb friction, m/s. Default 1e-3:
    /// below it friction acts like a viscous damper.
    pub slip_velocity: f64,
    /// A time step whose deepest test point penetrates a rod by more than
    /// this fraction of the wire radius is rejected and halved. Default 1:
    /// no physical state gets there (a soft penalty of 1e8 N/m³ penetrates
    /// half the radius in the impact scene), but a step too coarse for the
    /// contact does, and accepting it loses the wire through the rod.
    pub max_penetration: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            stations: 8,
            angles: 16,
            slip_velocity: 1e-3,
            max_penetration: 1.0,
        }
    }
}

/// One surface test point, in material coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestPoint {
    pub xi: f64,
    pub y: f64,
    pub z: f64,
    /// Reference surface area it stands for, m².
    pub area: f64,
    /// Shape functions at the point.
    pub s: [f64; 8],
}

/// The contact model of a wire: rods and the test points of one element.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    pub rods: Vec<Rod>,
    pub settings: ContactSettings,
    pub points: Vec<TestPoint>,
    /// Outer radius of the wire, m.
    pub wire_radius: f64,
    pub element_length: f64,
    /// Shape functions on the centerline at the 9 broad-phase stations
    /// (constant: computed once; recomputing them was 14 % of the impact run).
    broad_phase: [[f64; 8]; 9],
}

/// What contact does in one element (or summed over the wire).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSample {
    /// Penalty energy Σ ½ ε_N g² w, J.
    pub energy: f64,
    /// Largest penetration −g, m (0 when apart).
    pub max_penetration: f64,
    /// Sum of normal force magnitudes, N.
    pub normal_force: f64,
    /// Friction power −Σ f_t · v_p ≥ 0, W.
    pub friction_power: f64,
    /// Active test points.
    pub active: usize,
}

/// Where the deepest penetration of an element is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeepestPoint {
    pub point: usize,
    pub rod: usize,
    pub penetration: f64,
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Contact {
    pub fn new(
        rods: Vec<Rod>,
        settings: ContactSettings,
        wire_radius: f64,
        element_length: f64,
    ) -> Self {
        let rule = gauss_legendre_unit(settings.stations);
        let dphi = 2.0 * std::f64::consts::PI / settings.angles as f64;
        let mut points = Vec::new();
        for (xi, w) in rule.nodes.iter().zip(&rule.weights) {
            for j in 0..settings.angles {
                let phi = j as f64 * dphi;
                let (y, z) = (wire_radius * phi.cos(), wire_radius * phi.sin());
                points.push(TestPoint {
                    xi: *xi,
                    y,
                    z,
                    area: w * element_length * wire_radius * dphi,
                    s: shape_functions(*xi, y, z, element_length),
                });
            }
        }
        Contact {
            rods,
            settings,
            points,
            wire_radius,
            element_length,
            broad_phase: std::array::from_fn(|k| {
                shape_functions(k as f64 / 8.0, 0.0, 0.0, element_length)
            }),
        }
    }

    pub fn has_friction(&self) -> bool {
        self.rods.iter().any(|r| r.friction > 0.0)
    }

    /// Broad phase: can element `e` touch rod `rod`? The minimal distance
    /// between its cubic centerline (sampled at 9 stations) and the rod's
    /// axis, against R_w + R_rod plus a margin for the chord sag between
    /// samples and the section's deformation (R_w + l/8).
    pub fn may_touch(&self, rod: &Rod, e: &ElementVector) -> bool {
        let l = self.element_length;
        let reach = rod.radius + 2.0 * self.wire_radius + l / 8.0;
        // First a sphere around the centerline's Bézier control points
        // r₁, r₁ + l/3 r₁ₓ, r₂ − l/3 r₂ₓ, r₂ (the cubic lies in their hull):
        // if even that is out of reach, so is every sample below (the same
        // answer, for a fraction of the work; the samples were 10 % of the
        // impact run, perf).
        let bezier: [[f64; 3]; 4] = std::array::from_fn(|k| {
            std::array::from_fn(|c| match k {
                0 => e[c],
                1 => e[c] + l / 3.0 * e[3 + c],
                2 => e[12 + c] - l / 3.0 * e[15 + c],
                _ => e[12 + c],
            })
        });
        let centre: [f64; 3] =
            std::array::from_fn(|c| 0.25 * bezier.iter().map(|b| b[c]).sum::<f64>());
        let radius = bezier
            .iter()
            .map(|b| {
                let d = [b[0] - centre[0], b[1] - centre[1], b[2] - centre[2]];
                dot(&d, &d)
            })
            .fold(0.0, f64::max)
            .sqrt();
        // A point's coordinate along the rod's axis from its centre and its
        // distance from the axis (m).
        let axis_coordinates = |p: &[f64; 3]| {
            let rel = [
                p[0] - rod.center[0],
                p[1] - rod.center[1],
                p[2] - rod.center[2],
            ];
            let along = dot(&rel, &rod.axis);
            let perp = [
                rel[0] - along * rod.axis[0],
                rel[1] - along * rod.axis[1],
                rel[2] - along * rod.axis[2],
            ];
            (along, dot(&perp, &perp).sqrt())
        };
        let (along, distance) = axis_coordinates(&centre);
        if distance > reach + radius
            || rod
                .length
                .is_some_and(|len| along.abs() > 0.5 * len + reach + radius)
        {
            return false;
        }
        self.broad_phase.iter().any(|s| {
            let p: [f64; 3] = std::array::from_fn(|c| (0..8).map(|i| s[i] * e[3 * i + c]).sum());
            let (along, distance) = axis_coordinates(&p);
            if let Some(len) = rod.length
                && along.abs() > 0.5 * len + reach
            {
                return false;
            }
            distance < reach
        })
    }

    /// Contact force on one element (added to `q`, N), −∂Q/∂q (added to
    /// `kq`) and −∂Q/∂v (added to `kv`), with coordinates `e` and velocities
    /// `v`. Returns the sample and the deepest point.
    pub fn element(
        &self,
        e: &ElementVector,
        v: &ElementVector,
        q: &mut ElementVector,
        mut kq: Option<&mut ElementMatrix>,
        mut kv: Option<&mut ElementMatrix>,
    ) -> (ContactSample, Option<DeepestPoint>) {
        let mut sample = ContactSample::default();
        let mut deepest: Option<DeepestPoint> = None;
        for ri in 0..self.rods.len() {
            let (s, dp) = self.element_rod(ri, e, v, q, kq.as_deref_mut(), kv.as_deref_mut());
            sample.accumulate(&s);
            if let Some(dp) = dp
                && deepest.is_none_or(|d| dp.penetration > d.penetration)
            {
                deepest = Some(dp);
            }
        }
        (sample, deepest)
    }

    /// [`Contact::element`] for rod `ri` alone.
    pub fn element_rod(
        &self,
        ri: usize,
        e: &ElementVector,
        v: &ElementVector,
        q: &mut ElementVector,
        mut kq: Option<&mut ElementMatrix>,
        mut kv: Option<&mut ElementMatrix>,
    ) -> (ContactSample, Option<DeepestPoint>) {
        let mut sample = ContactSample::default();
        let mut deepest: Option<DeepestPoint> = None;
        let rod = &self.rods[ri];
        if !self.may_touch(rod, e) {
            return (sample, None);
        }
        let d = rod.axis;
        for (pi, tp) in self.points.iter().enumerate() {
            let p: [f64; 3] = std::array::from_fn(|c| (0..8).map(|i| tp.s[i] * e[3 * i + c]).sum());
            let rel = [
                p[0] - rod.center[0],
                p[1] - rod.center[1],
                p[2] - rod.center[2],
            ];
            let along = dot(&rel, &d);
            if let Some(len) = rod.length
                && along.abs() > 0.5 * len
            {
                continue;
            }
            let perp = [
                rel[0] - along * d[0],
                rel[1] - along * d[1],
                rel[2] - along * d[2],
            ];
            let dist = dot(&perp, &perp).sqrt();
            let g = dist - rod.radius;
            if g >= 0.0 || dist == 0.0 {
                continue;
            }
            let n = [perp[0] / dist, perp[1] / dist, perp[2] / dist];
            let kn = rod.contact_stiffness * tp.area;
            let fnorm = kn * (-g);
            sample.energy += 0.5 * kn * g * g;
            sample.max_penetration = sample.max_penetration.max(-g);
            sample.normal_force += fnorm;
            sample.active += 1;
            if deepest.is_none_or(|dp| -g > dp.penetration) {
                deepest = Some(DeepestPoint {
                    point: pi,
                    rod: ri,
                    penetration: -g,
                });
            }
            let mut f = [fnorm * n[0], fnorm * n[1], fnorm * n[2]];
            // ∂n/∂p = (I − n nᵀ − d dᵀ) / |p⊥|
            let nmat =
                |a: usize, b: usize| ((a == b) as u8 as f64 - n[a] * n[b] - d[a] * d[b]) / dist;
            // −∂f_n/∂p = kn (n nᵀ − (−g) ∂n/∂p)
            let mut dfdp = [[0.0; 3]; 3]; // ∂f/∂p
            for a in 0..3 {
                for b in 0..3 {
                    dfdp[a][b] = -kn * n[a] * n[b] + fnorm * nmat(a, b);
                }
            }
            let mut dfdv = [[0.0; 3]; 3];
            if rod.friction > 0.0 {
                let vp: [f64; 3] =
                    std::array::from_fn(|c| (0..8).map(|i| tp.s[i] * v[3 * i + c]).sum());
                let vn = dot(&vp, &n);
                let vt = [vp[0] - vn * n[0], vp[1] - vn * n[1], vp[2] - vn * n[2]];
                let eps = self.settings.slip_velocity;
                let s = (dot(&vt, &vt) + eps * eps).sqrt();
                let t = [vt[0] / s, vt[1] / s, vt[2] / s];
                let mu = rod.friction;
                for c in 0..3 {
                    f[c] -= mu * fnorm * t[c];
                }
                sample.friction_power += mu * fnorm * dot(&vt, &vt) / s;
                // A = ∂t/∂v_t = (I − v_t v_tᵀ / s²) / s
                let amat =
                    |a: usize, b: usize| ((a == b) as u8 as f64 - vt[a] * vt[b] / (s * s)) / s;
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
                        // ∂f_t/∂p = −μ [ t (∂F_n/∂p) + F_n (∂t/∂n)(∂n/∂p) ], ∂F_n/∂p = −kn nᵀ
                        let dtdp: f64 = (0..3).map(|c| dtdn[a][c] * nmat(c, b)).sum();
                        dfdp[a][b] += -mu * (t[a] * (-kn * n[b]) + fnorm * dtdp);
                        // ∂f_t/∂v_p = −μ F_n A P, P = I − n nᵀ
                        let ap: f64 = (0..3)
                            .map(|c| amat(a, c) * ((c == b) as u8 as f64 - n[c] * n[b]))
                            .sum();
                        dfdv[a][b] = -mu * fnorm * ap;
                    }
                }
            }
            for i in 0..8 {
                for c in 0..3 {
                    q[3 * i + c] += tp.s[i] * f[c];
                }
            }
            let add = |m: &mut ElementMatrix, blk: &[[f64; 3]; 3]| {
                for i in 0..8 {
                    for j in 0..8 {
                        let sij = tp.s[i] * tp.s[j];
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
            if let Some(k) = kq.as_deref_mut() {
                add(k, &dfdp);
            }
            if rod.friction > 0.0
                && let Some(k) = kv.as_deref_mut()
            {
                add(k, &dfdv);
            }
        }
        (sample, deepest)
    }
}

impl ContactSample {
    pub fn accumulate(&mut self, o: &ContactSample) {
        self.energy += o.energy;
        self.max_penetration = self.max_penetration.max(o.max_penetration);
        self.normal_force += o.normal_force;
        self.friction_power += o.friction_power;
        self.active += o.active;
    }
}
