//! Properties over random states and random scene files.

#[path = "../ancf-core/tests/common/mod.rs"]
mod common;
use ancf::output::RunStatus;
use ancf_core::scene::Scene;
use common::*;
use proptest::prelude::*;

fn element_vector(values: &[f64], amplitude: f64, l: f64) -> [f64; 24] {
    let mut e = reference(l);
    for (i, v) in e.iter_mut().enumerate() {
        let scale = if (i / 3) % 4 == 0 { l } else { 1.0 };
        *v += amplitude * scale * values[i];
    }
    e
}

fn sections() -> Vec<ancf_core::section::Section> {
    vec![
        two_layer(svk(2e9, 0.3, 0.5), svk(1e9, 0.0, 1.0), 3),
        two_layer(svk(2e9, 0.0, 1.0), mooney_rivlin(1e3), 3),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Objectivity: the energy does not change under a rigid rotation and translation.
    #[test]
    fn energy_is_objective(values in proptest::collection::vec(-1.0f64..1.0, 24), rot in proptest::array::uniform3(-3.0f64..3.0), amp in 0.0f64..0.3) {
        prop_assume!(rot.iter().map(|x| x * x).sum::<f64>() > 1e-6);
        let e = element_vector(&values, amp, 0.5);
        for s in sections() {
            let el = element(s, 0.5, 3);
            let u = el.energy(&e);
            let moved = rigid_motion(&e, &rotation(rot), [1.0, -2.0, 0.5]);
            let um = el.energy(&moved);
            prop_assert!((u - um).abs() <= 1e-9 * u.abs().max(1e-9), "{} vs {}", u, um);
        }
    }

    /// Force = gradient of the energy, Jacobian symmetric, at random states.
    #[test]
    fn force_is_energy_gradient_and_tangent_symmetric(values in proptest::collection::vec(-1.0f64..1.0, 24), amp in 0.01f64..0.2, j in 0usize..24) {
        let e = element_vector(&values, amp, 0.5);
        for s in sections() {
            let el = element(s, 0.5, 3);
            let mut q = [0.0; 24];
            let mut k = [0.0; 576];
            el.evaluate(&e, &mut q, Some(&mut k));
            let h = 1e-6;
            let (mut ep, mut em) = (e, e);
            ep[j] += h;
            em[j] -= h;
            let fd = (el.energy(&ep) - el.energy(&em)) / (2.0 * h);
            let qn = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            prop_assert!((fd - q[j]).abs() <= 1e-6 * qn, "dU/de[{}] {} vs {}", j, fd, q[j]);
            let kn = k.iter().map(|x| x * x).sum::<f64>().sqrt();
            for i in 0..24 {
                prop_assert!((k[i * 24 + j] - k[j * 24 + i]).abs() <= 1e-12 * kn);
            }
        }
    }

    /// Random text never panics the parser.
    #[test]
    fn random_text_never_panics_the_parser(text in "\\PC{0,400}") {
        let _ = Scene::from_toml(&text);
    }

    /// Mutated scene files never panic the parser, and the valid ones run a few steps without panicking.
    #[test]
    fn mutated_scenes_never_panic(pos in 0usize..10_000, replacement in prop_oneof![
        Just("-1".to_string()), Just("0".to_string()), Just("nan".to_string()), Just("inf".to_string()),
        Just("1e308".to_string()), Just("\"x\"".to_string()), Just("[]".to_string()), Just("".to_string()),
        Just("{".to_string()), Just("2".to_string()), Just("0.5".to_string()), Just("1e-300".to_string()),
    ]) {
        let base = std::fs::read_to_string("scenes/pendulum.toml").unwrap()
            .replace("end_time = 1.0", "end_time = 0.003");
        // Replace the number (or word) that starts after the pos-th '=' sign.
        let eqs: Vec<usize> = base.match_indices('=').map(|(i, _)| i).collect();
        let at = eqs[pos % eqs.len()] + 1;
        let end = base[at..].find(['\n', '#', ',', ']', '}']).map_or(base.len(), |k| at + k);
        let text = format!("{} {}{}", &base[..at], replacement, &base[end..]);
        if let Ok(scene) = Scene::from_toml(&text)
            && scene.model.n_elements <= 64
            && match &scene.analysis {
                // Bounded runs only: a valid scene may still ask for millions of steps.
                ancf_core::scene::Analysis::Dynamic { settings, .. } => settings.end_time / settings.time_step <= 1000.0,
                ancf_core::scene::Analysis::Static { .. } => true,
            }
        {
            {
                let dir = std::env::temp_dir().join(format!("ancf-prop-{}-{}", std::process::id(), pos));
                let summary = ancf::run::run_scene(&scene, &ancf::run::RunOptions { out: dir.clone(), quiet: true, cancel: Default::default() });
                let _ = std::fs::remove_dir_all(&dir);
                if let Ok(s) = summary {
                    prop_assert!(matches!(s.status, RunStatus::Completed | RunStatus::Failed));
                    if let Some(e) = s.energy {
                        prop_assert!(s.status == RunStatus::Failed || e.total.is_finite(), "a completed run with non-finite energy");
                    }
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Every shipped scene, one value mutated: the scene is refused naming
    /// its field (or, for broken TOML, the line), or it runs — a few
    /// hundred steps at most — to `completed` or `failed`, without a
    /// panic. Large scenes are only parsed.
    #[test]
    fn mutated_shipped_scenes_are_refused_by_field_or_run_cleanly(
        which in 0usize..10,
        pos in 0usize..10_000,
        replacement in prop_oneof![
            Just("-1".to_string()), Just("0".to_string()), Just("nan".to_string()),
            Just("1e308".to_string()), Just("\"x\"".to_string()), Just("[]".to_string()),
            Just("2".to_string()), Just("1e-300".to_string()), Just("[1.0, 2.0]".to_string()),
            Just("[1.0, 2.0, 3.0, 4.0]".to_string()), Just("\"last\"".to_string()),
        ],
    ) {
        // The shipped scenes, and the design keys (ground under a member,
        // plasticity, springs, responses, a release) in a scene small
        // enough to step, at a fixed and at an adaptive step.
        let paths = [
            "scenes/pendulum.toml", "scenes/wire_rod_impact.toml",
            "scenes/cantilever_large_deflection.toml", "scenes/two_layer_cantilever.toml",
            "scenes/span_break_frame.toml", "scenes/span_break_elastic_frame.toml",
            "scenes/span_break_plastic_frame.toml", "tests/data/fuzz_design.toml",
            "tests/data/fuzz_design.toml", "tests/data/fuzz_design.toml",
        ];
        let mut base = std::fs::read_to_string(paths[which]).unwrap();
        if which == 9 {
            base = base.replace("time_step = 1e-4", "time_step = \"auto\"\nerror_tolerance = 1e-6");
        }
        let eqs: Vec<usize> = base.match_indices(" = ").map(|(i, _)| i + 2).collect();
        let at = eqs[pos % eqs.len()] + 1;
        let end = base[at..].find(['\n', '#']).map_or(base.len(), |k| at + k);
        let text = format!("{}{}{}", &base[..at], replacement, &base[end..]);
        match Scene::from_toml(&text) {
            Err(e) => prop_assert!(
                !e.field.is_empty() || e.message.contains("line"),
                "a refusal names neither a field nor a line: {e}"
            ),
            Ok(mut scene) if scene.model.element_count() <= 64 => {
                if let ancf_core::scene::Analysis::Dynamic { settings, .. } = &mut scene.analysis {
                    // A bounded run: at most 300 steps of the scene's own step.
                    settings.end_time = settings.end_time.min(300.0 * settings.time_step);
                }
                let dir = std::env::temp_dir()
                    .join(format!("ancf-fuzz-{}-{which}-{pos}", std::process::id()));
                let summary = ancf::run::run_scene(&scene, &ancf::run::RunOptions {
                    out: dir.clone(),
                    quiet: true,
                    cancel: Default::default(),
                });
                let _ = std::fs::remove_dir_all(&dir);
                if let Ok(s) = summary {
                    prop_assert!(matches!(s.status, RunStatus::Completed | RunStatus::Failed));
                    if let Some(e) = s.energy {
                        prop_assert!(
                            s.status == RunStatus::Failed || e.total.is_finite(),
                            "a completed run with non-finite energy"
                        );
                    }
                }
            }
            Ok(_) => {}
        }
    }

    /// Every shipped sweep file, one value mutated: it is loaded (every
    /// variant a valid scene) or refused with a message, without a panic.
    #[test]
    fn mutated_sweep_files_load_or_are_refused_cleanly(
        which in 0usize..5,
        pos in 0usize..10_000,
        replacement in prop_oneof![
            Just("-1".to_string()), Just("0".to_string()), Just("nan".to_string()),
            Just("1e308".to_string()), Just("\"x\"".to_string()), Just("[]".to_string()),
            Just("[[]]".to_string()), Just("[1, \"a\"]".to_string()), Just("\"grid\"".to_string()),
            Just("\"zip\"".to_string()), Just("{}".to_string()), Just("\"a\\nb\"".to_string()),
        ],
    ) {
        let names = [
            "span_break_frame", "span_break_damping", "span_break_elastic_damping",
            "span_break_ensemble", "span_break_plastic_damping",
        ];
        let root = std::env::current_dir().unwrap();
        let base = std::fs::read_to_string(format!("sweeps/{}.toml", names[which]))
            .unwrap()
            .replace("\"../scenes/", &format!("\"{}/scenes/", root.display()));
        let eqs: Vec<usize> = base.match_indices(" = ").map(|(i, _)| i + 2).collect();
        let at = eqs[pos % eqs.len()] + 1;
        let end = base[at..].find(['\n', '#']).map_or(base.len(), |k| at + k);
        let text = format!("{}{}{}", &base[..at], replacement, &base[end..]);
        let dir = std::env::temp_dir()
            .join(format!("ancf-sweep-fuzz-{}-{which}-{pos}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sweep.toml");
        std::fs::write(&path, &text).unwrap();
        let loaded = ancf::sweep::file::load(&path);
        let _ = std::fs::remove_dir_all(&dir);
        match loaded {
            Ok(sweep) => {
                // load() checked every variant; the first, again, here.
                let first = sweep.variants.first();
                prop_assert!(first.is_some_and(|v| Scene::from_toml(&v.scene_text).is_ok()));
            }
            Err(e) => prop_assert!(!e.0.trim().is_empty()),
        }
    }
}
