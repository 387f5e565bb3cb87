//! How far a beam was strained over a run: the largest axial strain of its
//! centerline, of each layer's outermost fibres, and the largest stretch
//! of the whole beam — what says whether a law was used inside the range
//! it describes (St. Venant–Kirchhoff: small strains), and whether a wire
//! stretched as no real conductor can.
//!
//! The fibre strain is the Green strain E_xx along the beam at distance
//! (y, z) from the centerline. With r_x(y, z) = a + y b + z c (a the
//! centerline's r_x, b and c the x-derivatives of r_y and r_z, constant in
//! an element),
//!
//! E_xx = ½(|a|² − 1) + y a·b + z a·c + ½|y b + z c|²,
//!
//! bounded on a circle of radius R by |E₀| + R √((a·b)² + (a·c)²) +
//! ½ R² (|b|² + |c|²), which is exact to first order in the bending.
//! It is taken at each element's ends and middle, the stretch from
//! Simpson's rule on |a|.

use crate::element::ElementVector;
use crate::model::{Beam, Model};
use crate::section::{Section, SectionShape};

/// One peak: the largest |E_xx| (−), its time (s) and its place (m from
/// the beam's first node, along it unstretched).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PeakStrain {
    /// The largest |E_xx| (−).
    pub max_strain: f64,
    /// Its time (s).
    pub time: f64,
    /// Its place (m from the beam's first node).
    pub at: f64,
}

impl PeakStrain {
    fn visit(&mut self, strain: f64, time: f64, at: f64) {
        if strain > self.max_strain {
            *self = PeakStrain {
                max_strain: strain,
                time,
                at,
            };
        }
    }
}

/// A beam's largest strains so far.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StrainRecord {
    /// The centerline's largest |E_xx| (stretch or shortening).
    pub axial: PeakStrain,
    /// Each layer's outermost fibres (axial and bending), from the centre out.
    pub layers: Vec<PeakStrain>,
    /// The largest length / unstretched length − 1 of the whole beam (−) …
    pub max_stretch: f64,
    /// … and its time (s).
    pub max_stretch_time: f64,
    /// A beam with a yielding layer: its largest equivalent plastic strain
    /// (−) with time and place (at an axial Gauss point); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_plastic_strain: Option<PeakStrain>,
    /// … and the plastic work done on it since t = 0 (J).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plastic_work: Option<f64>,
}

impl StrainRecord {
    /// Observe the yielding points' `states` of `beam` (the model's
    /// history, placed by `layout`) and its plastic work `work` (J) at time
    /// `t` (s); nothing for a beam without a yielding layer.
    pub fn observe_plastic(
        &mut self,
        model: &Model,
        beam: &Beam,
        (layout, states): (
            &crate::forces::plastic::PlasticLayout,
            &[crate::material::beam_plasticity::PlasticState],
        ),
        work: f64,
        t: f64,
    ) {
        let mut peak = self.max_plastic_strain.unwrap_or_default();
        let mut any = false;
        for el in beam.elements.clone() {
            let points = layout.element(states, el);
            if points.is_empty() {
                continue;
            }
            any = true;
            let ei = model.element(el);
            let per_station = points.len() / ei.axial.nodes.len();
            for (i, p) in points.iter().enumerate() {
                let xi = ei.axial.nodes[i / per_station];
                let at = model.node_arc(el) - model.node_arc(beam.nodes.start) + xi * ei.length;
                peak.visit(p.equivalent, t, at);
            }
        }
        if any {
            self.max_plastic_strain = Some(peak);
            self.plastic_work = Some(work);
        }
    }
}

/// The centerline's gradient a = r_x at ξ = 0, ½ and 1 of element
/// coordinates `e` of length `l` (m): Σ e_i ∂s_i/∂x with the shape
/// gradients' values there written out (at the ends a node's own r_x), so
/// that the three points take no division; the same sums, in the same
/// order, as over [`crate::element::shape_gradients`] (its other terms
/// are zeros).
fn centerline_gradients(e: &ElementVector, l: f64) -> [[f64; 3]; 3] {
    // (−6ξ + 6ξ²)/l and 1 − 4ξ + 3ξ² = −2ξ + 3ξ² = −¼ at ξ = ½.
    let d1 = -1.5 / l;
    let middle = std::array::from_fn(|k| {
        ((e[k] * d1 + e[3 + k] * -0.25) + e[12 + k] * -d1) + e[15 + k] * -0.25
    });
    let node = |i: usize| std::array::from_fn(|k| e[3 * i + k]);
    [node(1), middle, node(5)]
}

/// The x-derivatives b of r_y and c of r_z, constant in an element of
/// coordinates `e` and length `l` (m).
fn section_gradients(e: &ElementVector, l: f64) -> ([f64; 3], [f64; 3]) {
    let b = std::array::from_fn(|k| (e[18 + k] - e[6 + k]) / l);
    let c = std::array::from_fn(|k| (e[21 + k] - e[9 + k]) / l);
    (b, c)
}

/// (E₀, the fibre strain's bound per layer) at a point of centerline
/// gradient `a` in an element of section gradients `b`, `c` and
/// `section`; also |a| (for the stretch).
fn point_strains(
    a: [f64; 3],
    (b, c): ([f64; 3], [f64; 3]),
    section: &Section,
    layers: &mut [f64],
) -> (f64, f64) {
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let aa = dot(a, a);
    let e0 = 0.5 * (aa - 1.0);
    let (p, q) = (dot(a, b), dot(a, c));
    let quad = 0.5 * (dot(b, b) + dot(c, c));
    // √(p² + q²) once a point, not once a layer (libm's hypot is slow).
    let bending = p.hypot(q);
    for (k, out) in layers.iter_mut().enumerate() {
        let (linear, r2) = match &section.shape {
            SectionShape::Circular { radii } => {
                let r = radii[k].1;
                (r * bending, r * r)
            }
            SectionShape::Rectangular { width, height } => (
                0.5 * (p.abs() * width + q.abs() * height),
                0.25 * (width * width + height * height),
            ),
        };
        *out = e0.abs() + linear + quad * r2;
    }
    (e0.abs(), aa.sqrt())
}

impl StrainRecord {
    /// Observe beam `beam` of `model` at coordinates `q` and time `t` (s).
    /// A beam of [`PARALLEL_MIN_ELEMENTS`] or more is observed in two
    /// halves on two threads (with more than one rayon thread), merged so
    /// that the result has the bits of one loop: each half keeps the first
    /// strictly largest of its points, the second half's replaces the
    /// first's only when strictly larger, and the stretch's per-element
    /// terms are summed in element order.
    pub fn observe(&mut self, model: &Model, beam: &Beam, q: &[f64], t: f64) {
        let start = model.node_arc(beam.nodes.start);
        let elements = beam.elements.clone();
        let parallel = rayon::current_num_threads() > 1 && elements.len() >= PARALLEL_MIN_ELEMENTS;
        let halves = if parallel {
            let mid = elements.start + elements.len() / 2;
            vec![elements.start..mid, mid..elements.end]
        } else {
            vec![elements]
        };
        let observe_half = |els: std::ops::Range<usize>| {
            let mut part = self.clone();
            let lengths = part.observe_elements(model, q, t, start, els);
            (part, lengths)
        };
        let parts = crate::linalg::parallel::run_tasks(halves, observe_half);
        let mut length = 0.0;
        for (part, lengths) in parts {
            self.axial
                .visit(part.axial.max_strain, part.axial.time, part.axial.at);
            self.layers.resize(part.layers.len(), PeakStrain::default());
            for (record, p) in self.layers.iter_mut().zip(&part.layers) {
                record.visit(p.max_strain, p.time, p.at);
            }
            for l in lengths {
                length += l;
            }
        }
        let unstretched = model.node_arc(beam.last_node()) - start;
        let stretch = length / unstretched - 1.0;
        if stretch > self.max_stretch {
            self.max_stretch = stretch;
            self.max_stretch_time = t;
        }
    }

    /// Visit the points of elements `els` (three each) into this record,
    /// and return each element's stretched length (m), in element order.
    fn observe_elements(
        &mut self,
        model: &Model,
        q: &[f64],
        t: f64,
        start: f64,
        els: std::ops::Range<usize>,
    ) -> Vec<f64> {
        let mut fibres = [0.0; 8];
        let mut lengths = Vec::with_capacity(els.len());
        for el in els {
            let integration = model.element(el);
            let (l, section) = (integration.length, &integration.section);
            let n_layers = section.layers.len().min(fibres.len());
            self.layers.resize(n_layers, PeakStrain::default());
            let e = model.element_coordinates(q, el);
            let at0 = model.node_arc(el) - start;
            let mut stretch = [0.0; 3];
            let bc = section_gradients(&e, l);
            let gradients = centerline_gradients(&e, l);
            for (j, (xi, a)) in [0.0, 0.5, 1.0].into_iter().zip(gradients).enumerate() {
                let (axial, a) = point_strains(a, bc, section, &mut fibres[..n_layers]);
                let at = at0 + xi * l;
                self.axial.visit(axial, t, at);
                for (record, &f) in self.layers.iter_mut().zip(&fibres[..n_layers]) {
                    record.visit(f, t, at);
                }
                stretch[j] = a;
            }
            lengths.push(l / 6.0 * (stretch[0] + 4.0 * stretch[1] + stretch[2]));
        }
        lengths
    }
}

/// From this many elements a beam's strains are observed on two threads
/// (≈ 4 % of the 1000-element span break's main thread, every step).
pub const PARALLEL_MIN_ELEMENTS: usize = 512;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::model::WireBuilder;

    /// The written-out gradients are the shape-gradient sums, value for
    /// value, on elements of unrelated coordinates and lengths.
    #[test]
    fn centerline_gradients_are_the_shape_gradient_sums() {
        for seed in 1..50u32 {
            let x = |i: u32| ((seed * 7919 + i * 104_729) % 1000) as f64 / 137.0 - 3.5;
            let e: ElementVector = std::array::from_fn(|i| x(i as u32));
            let l = 0.013 + 0.37 * x(99).abs();
            let written = centerline_gradients(&e, l);
            for (xi, a) in [0.0, 0.5, 1.0].into_iter().zip(written) {
                let g = crate::element::shape_gradients(xi, 0.0, 0.0, l);
                let sum: [f64; 3] =
                    std::array::from_fn(|k| (0..8).map(|i| e[3 * i + k] * g[i][0]).sum());
                assert_eq!(a, sum, "ξ = {xi}, l = {l}");
            }
        }
    }

    fn wire() -> Model {
        WireBuilder::new(2.0, 4)
            .layer(Material::st_venant_kirchhoff(7800.0, 2e11, 0.0, 1.0), 0.01)
            .layer(Material::st_venant_kirchhoff(2700.0, 7e10, 0.0, 1.0), 0.02)
            .build()
            .unwrap()
    }

    /// A uniform stretch λ: every fibre at ½(λ² − 1), the length λ L.
    #[test]
    fn a_uniform_stretch_is_everywhere() {
        let model = wire();
        let lambda = 1.03;
        let mut q = model.reference.clone();
        for node in 0..5 {
            q[12 * node] *= lambda;
            q[12 * node + 3] = lambda;
        }
        let mut r = StrainRecord::default();
        r.observe(&model, model.wire(), &q, 0.5);
        let e = 0.5 * (lambda * lambda - 1.0);
        assert!((r.axial.max_strain - e).abs() < 1e-14);
        assert_eq!(r.layers.len(), 2);
        for l in &r.layers {
            assert!((l.max_strain - e).abs() < 1e-14, "{l:?}");
            assert_eq!(l.time, 0.5);
        }
        assert!((r.max_stretch - (lambda - 1.0)).abs() < 1e-14);
    }

    /// Bent into an arc of radius ρ (the nodes on it, gradients rotated):
    /// a fibre at R from the centerline strains by about R / ρ, the
    /// centerline by little; the outer layer's more than the core's.
    #[test]
    fn bending_strains_the_outer_fibres() {
        let model = wire();
        let rho = 5.0;
        let mut q = model.reference.clone();
        for node in 0..5 {
            let s = 0.5 * node as f64;
            let phi = s / rho;
            let b = 12 * node;
            q[b] = rho * phi.sin();
            q[b + 2] = rho * (1.0 - phi.cos());
            q[b + 3..b + 6].copy_from_slice(&[phi.cos(), 0.0, phi.sin()]);
            q[b + 9..b + 12].copy_from_slice(&[-phi.sin(), 0.0, phi.cos()]);
        }
        let mut r = StrainRecord::default();
        r.observe(&model, model.wire(), &q, 0.0);
        assert!(r.axial.max_strain < 1e-4, "{:?}", r.axial);
        for (layer, radius) in r.layers.iter().zip([0.01, 0.02]) {
            let expected = radius / rho;
            assert!(
                (layer.max_strain / expected - 1.0).abs() < 0.02,
                "{} against {expected}",
                layer.max_strain
            );
        }
    }

    /// A beam long enough for two halves: over a few observations, with
    /// ties and a prior record, two threads give one thread's record bit
    /// for bit.
    #[test]
    fn two_halves_keep_the_record_of_one_loop() {
        let n = PARALLEL_MIN_ELEMENTS + 7;
        let model = WireBuilder::new(50.0, n)
            .layer(Material::st_venant_kirchhoff(7800.0, 2e11, 0.0, 1.0), 0.01)
            .build()
            .unwrap();
        let observe = |threads: usize| {
            crate::linalg::parallel::with_threads(threads, || {
                let mut r = StrainRecord::default();
                for step in 0..4 {
                    // A wave whose crest moves along the wire, and a flat
                    // stretch (equal strains at many points: ties).
                    let mut q = model.reference.clone();
                    for node in 0..=n {
                        let x = model.reference[12 * node];
                        let bump = 1e-3 * (0.3 * x - step as f64).sin().max(0.0);
                        q[12 * node] *= 1.0 + 1e-4 * step as f64;
                        q[12 * node + 3] = 1.0 + 1e-4 * step as f64;
                        q[12 * node + 2] = bump;
                    }
                    r.observe(&model, model.wire(), &q, 0.1 * step as f64);
                }
                r
            })
        };
        let (one, two) = (observe(1), observe(2));
        assert_eq!(one, two);
        assert_eq!(one.max_stretch.to_bits(), two.max_stretch.to_bits());
        // The stretch grows with the steps: the last one holds the peaks.
        assert!((one.axial.time - 0.3).abs() < 1e-12, "{:?}", one.axial);
        assert!(one.axial.max_strain > 0.0 && one.max_stretch > 0.0);
    }
}
