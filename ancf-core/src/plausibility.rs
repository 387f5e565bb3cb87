//! What real materials and wires look like: ranges that catch a slip of
//! units before a run, and strains that say after it where a law was used
//! outside the range it describes. These are warnings, not errors: a
//! scene may mean an unusual value (a rigid stand-in, a soft model
//! material), and `--strict` turns them into a failing exit code.

use crate::loads::strain_record::StrainRecord;
use crate::material::{Material, MaterialModel};
use crate::section::Section;
use std::ops::RangeInclusive;

/// Densities of solids (kg/m³): polymer foam (about 50) to osmium (22 590).
pub const DENSITY: RangeInclusive<f64> = 50.0..=23_000.0;

/// Young's moduli (Pa) of the materials St. Venant–Kirchhoff describes:
/// soft PVC insulation (about 1e7) to diamond (about 1.2e12). Rubber below
/// is Mooney–Rivlin's.
pub const SVK_YOUNGS_MODULUS: RangeInclusive<f64> = 1e7..=1.2e12;

/// Small-strain shear moduli 2 (μ10 + μ01) (Pa) of rubbers and elastomers:
/// soft gels (about 1e3) to hard polyurethane (about 1e8).
pub const MOONEY_RIVLIN_SHEAR_MODULUS: RangeInclusive<f64> = 1e3..=1e8;

/// The largest Mooney–Rivlin volume penalty κ (k2 = κ max(μ10, μ01)) worth
/// its cost: real rubbers resist volume change about 1e3–1e4 times more
/// than shear, and 1e7 is already the hard case. Beyond it the section's
/// volume modes are so stiff that steps which resolve the motion create
/// energy (the tutorial's drop cable with κ = 1e9 on its jacket: 12 751
/// rejected attempts in 8000 steps; 1e7: 325 in its first 3000; 1e3:
/// none), and nothing gets more accurate.
pub const MOONEY_RIVLIN_PENALTY_MAX: f64 = 1e7;

/// The largest plausible Kelvin–Voigt coefficient c (s): c damps a mode of
/// angular frequency ω at the ratio ζ = c ω / 2, so 1e-3 s already damps
/// a 100 Hz mode at 31 %, far above what metals and conductors show (a few
/// per cent at most). A larger value is most likely a damping ratio
/// written where a time belongs.
pub const KELVIN_VOIGT_MAX: f64 = 1e-3;

/// The strain beyond which St. Venant–Kirchhoff is used outside its range:
/// its uniaxial force departs from Hooke's by a factor λ(λ + 1)/2, 3 % at
/// 2 % strain (and metals yield near 0.2 %).
pub const SVK_STRAIN_LIMIT: f64 = 0.02;

/// The stretch of a metal wire (length / unstretched length − 1) beyond
/// which it is no longer a wire: steel and aluminium strands yield at
/// 0.2–0.9 % and break at a few per cent.
pub const STRETCH_LIMIT: f64 = 0.01;

/// What is implausible in `material` (named `field` in the scene, e.g.
/// `material[1]`): constants outside the ranges of real materials, most
/// often a slip of units.
pub fn material_warnings(field: &str, material: &Material) -> Vec<String> {
    let mut out = Vec::new();
    let mut outside = |key: &str, value: f64, range: &RangeInclusive<f64>, what: &str| {
        if !range.contains(&value) {
            out.push(format!(
                "{field}.{key} = {value:e} is outside {:e}–{:e}, the range of {what}: check the units",
                range.start(),
                range.end()
            ));
        }
    };
    outside(
        "density",
        material.density,
        &DENSITY,
        "solids (kg/m³, foam to osmium)",
    );
    match material.model {
        MaterialModel::StVenantKirchhoff { youngs_modulus, .. }
        | MaterialModel::ElasticPlastic { youngs_modulus, .. } => outside(
            "youngs_modulus",
            youngs_modulus,
            &SVK_YOUNGS_MODULUS,
            "St. Venant–Kirchhoff materials (Pa, soft PVC to diamond; rubber is Mooney–Rivlin's)",
        ),
        MaterialModel::MooneyRivlin {
            mu10,
            mu01,
            penalty,
        } => {
            outside(
                "mu10",
                2.0 * (mu10 + mu01),
                &MOONEY_RIVLIN_SHEAR_MODULUS,
                "rubbers' shear moduli 2 (μ10 + μ01) (Pa, soft gels to hard polyurethane)",
            );
            if penalty > MOONEY_RIVLIN_PENALTY_MAX {
                out.push(format!(
                    "{field}.penalty = {penalty:e} is above {MOONEY_RIVLIN_PENALTY_MAX:e}: \
                     the penalty is a multiple of the shear constants, not a modulus in Pa \
                     (rubbers resist volume change 1e3–1e4 times more than shear); a volume this \
                     stiff needs far smaller steps (expect step cuts) and gains no accuracy"
                ));
            }
        }
    }
    out
}

/// What is implausible in the damping written at `field` (`damping`,
/// `beam[0].damping`, …): a Kelvin–Voigt coefficient above
/// [`KELVIN_VOIGT_MAX`].
pub fn damping_warnings(field: &str, damping: &crate::model::damping::Damping) -> Vec<String> {
    match *damping {
        crate::model::damping::Damping::KelvinVoigt { coefficient }
            if coefficient > KELVIN_VOIGT_MAX =>
        {
            let zeta = coefficient * 2.0 * std::f64::consts::PI * 100.0 / 2.0;
            vec![format!(
                "{field}.strain_rate_coefficient = {coefficient:e} s is above \
                 {KELVIN_VOIGT_MAX:e} s: it is a time, not a damping ratio, and damps a 100 Hz \
                 mode at ζ = c ω / 2 = {:.0} %; for a ratio ζ at a frequency f use c = ζ / (π f)",
                100.0 * zeta
            )]
        }
        _ => Vec::new(),
    }
}

/// [`material_warnings`] and [`damping_warnings`] for a model built in
/// code (no material names): each beam's layers, named `wire layer 0`,
/// `tube1 layer 0`, …, and its damping (`tube1 damping`).
pub fn model_warnings(model: &crate::model::Model) -> Vec<String> {
    let mut out = Vec::new();
    for beam in &model.beams {
        let section = &model.element(beam.elements.start).section;
        for (k, layer) in section.layers.iter().enumerate() {
            out.extend(material_warnings(
                &format!("{} layer {k}", beam.name),
                &layer.material,
            ));
        }
    }
    for (b, d) in model.dampings() {
        out.extend(damping_warnings(
            &format!("{} damping", model.beams[b].name),
            d,
        ));
    }
    out
}

/// The limit EN 1993-1-5 Annex C (C.8 (1)) sets on the principal strain of
/// a plastic design by finite elements.
pub const PLASTIC_DESIGN_STRAIN_LIMIT: f64 = 0.05;

/// What `record`, beam `name`'s strains over a run with `section`, says
/// was outside the range of its laws: a stretch of an all-metal
/// (St. Venant–Kirchhoff) beam beyond [`STRETCH_LIMIT`], else a centerline
/// strain beyond [`SVK_STRAIN_LIMIT`]; and a solid St. Venant–Kirchhoff
/// layer's fibre strain beyond it. (A stranded layer, ω < 1, bends by its
/// strands sliding: its fibre strain is no material strain.)
/// An elastic-plastic layer's outer-fibre strain beyond
/// [`PLASTIC_DESIGN_STRAIN_LIMIT`] is a warning too.
pub fn strain_warnings(name: &str, record: &StrainRecord, section: &Section) -> Vec<String> {
    let svk = |m: &Material| matches!(m.model, MaterialModel::StVenantKirchhoff { .. });
    let all_svk = section.layers.iter().all(|l| svk(&l.material));
    let mut out = Vec::new();
    if all_svk && record.max_stretch > STRETCH_LIMIT {
        out.push(format!(
            "{name} stretched by {:.1} % of its length at t = {:.4} s: no metal wire stretches \
             {:.0} % and stays elastic; check the moduli (Pa) and the loads",
            100.0 * record.max_stretch,
            record.max_stretch_time,
            100.0 * STRETCH_LIMIT
        ));
    } else if section.layers.iter().any(|l| svk(&l.material))
        && record.axial.max_strain > SVK_STRAIN_LIMIT
    {
        out.push(format!(
            "{name}'s centerline strained by {:.1} % at t = {:.4} s, {:.2} m from its start: \
             St. Venant–Kirchhoff describes strains below {:.0} %",
            100.0 * record.axial.max_strain,
            record.axial.time,
            record.axial.at,
            100.0 * SVK_STRAIN_LIMIT
        ));
    }
    for (k, (layer, peak)) in section.layers.iter().zip(&record.layers).enumerate() {
        if layer.material.is_plastic() && peak.max_strain > PLASTIC_DESIGN_STRAIN_LIMIT {
            out.push(format!(
                "{name}'s layer {k} strained by {:.1} % in its outer fibres at t = {:.4} s, \
                 {:.2} m from its start: past the 5 % principal strain EN 1993-1-5 Annex C \
                 (C.8) allows for plastic design by finite elements (the member has failed by \
                 that rule)",
                100.0 * peak.max_strain,
                peak.time,
                peak.at,
            ));
        }
        let solid = matches!(
            layer.material.model,
            MaterialModel::StVenantKirchhoff { bending_factor, .. } if bending_factor == 1.0
        );
        if solid && peak.max_strain > SVK_STRAIN_LIMIT {
            out.push(format!(
                "{name}'s layer {k} strained by {:.1} % in its outer fibres at t = {:.4} s, \
                 {:.2} m from its start: St. Venant–Kirchhoff describes strains below {:.0} %",
                100.0 * peak.max_strain,
                peak.time,
                peak.at,
                100.0 * SVK_STRAIN_LIMIT
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slip_of_units_is_named() {
        let steel = Material::st_venant_kirchhoff(7850.0, 2e11, 0.3, 1.0);
        assert!(material_warnings("material[0]", &steel).is_empty());
        let kilopascal = Material::st_venant_kirchhoff(7850.0, 2e5, 0.3, 1.0);
        let w = material_warnings("material[0]", &kilopascal);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("material[0].youngs_modulus = 2e5"),
            "{w:?}"
        );
        let tonnes = Material::st_venant_kirchhoff(7.85, 2e11, 0.3, 1.0);
        assert!(material_warnings("m", &tonnes)[0].contains("m.density"));
        let rubber = Material::mooney_rivlin(1100.0, 4e5, 1e5, 100.0);
        assert!(material_warnings("m", &rubber).is_empty());
        let rubber_in_gpa = Material::mooney_rivlin(1100.0, 4e14, 1e14, 100.0);
        assert_eq!(material_warnings("m", &rubber_in_gpa).len(), 1);
        let hard_case = Material::mooney_rivlin(1100.0, 4e5, 1e5, 1e7);
        assert!(material_warnings("m", &hard_case).is_empty());
        let bulk_in_pa = Material::mooney_rivlin(1100.0, 4e5, 1e5, 2e9);
        let w = material_warnings("m", &bulk_in_pa);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("m.penalty = 2e9"), "{w:?}");
    }

    #[test]
    fn a_yielding_layer_past_five_percent_is_named() {
        use crate::loads::strain_record::PeakStrain;
        let s235 = Material::elastic_plastic(7850.0, 210e9, 0.3, 235e6, 21e6);
        let tube = Section::circular(&[(0.02015, 0.02415, s235)], 3);
        let peak = |max_strain| PeakStrain {
            max_strain,
            time: 1.5,
            at: 2.0,
        };
        let mut record = StrainRecord {
            layers: vec![peak(0.049)],
            ..Default::default()
        };
        assert!(strain_warnings("tube0", &record, &tube).is_empty());
        record.layers = vec![peak(0.051)];
        let w = strain_warnings("tube0", &record, &tube);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("5 %") && w[0].contains("EN 1993-1-5"),
            "{w:?}"
        );
        // An elastic layer at the same strain is St. Venant–Kirchhoff's warning.
        let elastic = Section::circular(
            &[(
                0.02015,
                0.02415,
                Material::st_venant_kirchhoff(7850.0, 210e9, 0.3, 1.0),
            )],
            3,
        );
        assert!(!strain_warnings("tube0", &record, &elastic)[0].contains("EN 1993-1-5"));
    }

    #[test]
    fn a_damping_ratio_written_as_a_time_is_named() {
        use crate::model::damping::Damping;
        let conductor = Damping::KelvinVoigt { coefficient: 1e-5 };
        assert!(damping_warnings("damping", &conductor).is_empty());
        let rayleigh = Damping::Rayleigh {
            mass: 0.5,
            stiffness: 1e-2,
        };
        assert!(damping_warnings("damping", &rayleigh).is_empty());
        // "2 %" written as c: a 100 Hz mode damped at 628 %.
        let ratio = Damping::KelvinVoigt { coefficient: 0.02 };
        let w = damping_warnings("damping", &ratio);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("damping.strain_rate_coefficient = 2e-2 s"),
            "{w:?}"
        );
        assert!(w[0].contains("= 628 %"), "{w:?}");
    }
}
