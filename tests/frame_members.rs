//! Frame members in a scene file: `[[beam]]` tables beside `[wire]`,
//! supports and loads on a member by `beam = "NAME"`, each member's final
//! nodes in `final_nodes_NAME.csv`, its supports in summary.json by name.

use ancf::run::{RunOptions, run_scene};
use ancf_core::scene::Scene;

/// A static scene: a clamped 10 m wire (unloaded) and a 4 m steel tube
/// Ø 100 × 4 mm along y, clamped and pinned, with 1 kN at midspan.
fn scene(extra: &str) -> String {
    format!(
        r#"
[analysis]
kind = "static"

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3

[wire]
length = 10.0
elements = 20
layers = [{{ material = "steel", outer_radius = 0.01 }}]

[[beam]]
name = "tube"
length = 4.0
elements = 16
origin = [1.0, -2.0, -2.0]
direction = [0.0, 1.0, 0.0]
layers = [{{ material = "steel", inner_radius = 0.046, outer_radius = 0.05 }}]

[[support]]
node = 0
kind = "clamp"

[[support]]
beam = "tube"
node = 0
kind = "clamp"

[[support]]
beam = "tube"
node = "last"
kind = "pin"

[[load]]
beam = "tube"
node = 8
force = [0.0, 0.0, -1000.0]
{extra}
"#
    )
}

#[test]
fn a_member_in_a_scene_bends_and_reports_by_name() {
    let scene = Scene::from_toml(&scene("")).unwrap();
    assert_eq!(scene.model.element_count(), 36);
    let dir = std::env::temp_dir().join(format!("ancf-members-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = RunOptions {
        out: dir.clone(),
        quiet: true,
        cancel: Default::default(),
    };
    let summary = run_scene(&scene, &opts).unwrap();
    assert_eq!(summary.elements, 36);
    // The wire's file has the wire's 21 nodes, the tube's its 17.
    let rows = |f: &str| -> Vec<Vec<f64>> {
        std::fs::read_to_string(dir.join(f))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect()
    };
    let (wire, tube) = (rows("final_nodes.csv"), rows("final_nodes_tube.csv"));
    assert_eq!((wire.len(), tube.len()), (21, 17));
    assert!(wire.iter().all(|r| r[3] == 0.0), "the wire does not move");
    let i = std::f64::consts::PI * (0.05_f64.powi(4) - 0.046_f64.powi(4)) / 4.0;
    let theory = 7.0 * 1000.0 * 4.0_f64.powi(3) / (768.0 * 2e11 * i);
    let delta = 2.0 + tube[8][3];
    assert!(
        (delta / -theory - 1.0).abs() < 0.01,
        "{delta} m against {theory} m"
    );
    let s = &summary.supports;
    let names: Vec<(&str, usize)> = s.iter().map(|s| (s.beam.as_str(), s.node)).collect();
    assert_eq!(names, [("wire", 0), ("tube", 0), ("tube", 16)]);
    let lifted: f64 = s.iter().map(|s| s.static_force[2]).sum();
    assert!((lifted - 1000.0).abs() < 1e-6, "{lifted}");
    // The member's largest moment: the clamp's 3 P L / 16 = 750 N m.
    let [beam] = &summary.beams[..] else {
        panic!("{:?}", summary.beams)
    };
    assert_eq!(beam.name, "tube");
    let r = beam.record;
    assert!((r.max_bending_moment / 750.0 - 1.0).abs() < 0.005, "{r:?}");
    assert_eq!(r.max_bending_moment_at, 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn members_are_checked_naming_the_field() {
    let error = |text: String| Scene::from_toml(&text).unwrap_err().to_string();
    let e = error(scene(
        "[[support]]\nbeam = \"post\"\nnode = 0\nkind = \"pin\"",
    ));
    assert!(
        e.starts_with("support[3].beam: unknown beam \"post\""),
        "{e}"
    );
    let e = error(scene(
        "[[load]]\nbeam = \"tube\"\nnode = 17\nforce = [0.0, 0.0, 1.0]",
    ));
    assert!(
        e.starts_with("load[1].node: node 17 does not exist (beam \"tube\" has nodes 0..=16"),
        "{e}"
    );
    let twin = "[[beam]]\nname = \"tube\"\nlength = 1.0\nelements = 2\nlayers = [{ material = \"steel\", outer_radius = 0.01 }]";
    let e = error(scene(twin));
    assert!(e.starts_with("beam[1].name"), "{e}");
    let empty = scene("").replace("length = 4.0", "length = 0.0");
    let e = error(empty);
    assert!(e.starts_with("beam[0].length"), "{e}");
    let e = error(scene("").replace("name = \"tube\"", "name = \"wire\""));
    assert!(e.starts_with("beam[0].name"), "{e}");
}

/// Gravity switched on at once on a clamped tube member (a cantilever at
/// rest, released): its root moment swings to about twice the static
/// w L² / 2 (one mode: exactly twice; ρ∞ = 1 keeps it) and the summary says
/// when.
#[test]
fn a_suddenly_loaded_member_peaks_at_twice_its_static_moment() {
    let text = scene("")
        .replace(
            "kind = \"static\"",
            "kind = \"dynamic\"\nend_time = 0.1\ntime_step = 2e-4\nspectral_radius = 1.0",
        )
        .replace(
            "[[support]]\nbeam = \"tube\"\nnode = \"last\"\nkind = \"pin\"\n",
            "",
        )
        .replace(
            "[[load]]\nbeam = \"tube\"\nnode = 8\nforce = [0.0, 0.0, -1000.0]\n",
            "",
        )
        + "[gravity]\nacceleration = [0.0, 0.0, -9.81]\n[output]\nvtk = false\nplots = false\n";
    let scene = Scene::from_toml(&text).unwrap();
    let run = ancf::run::run_in_memory(&scene);
    let w = 7800.0 * std::f64::consts::PI * (0.05_f64.powi(2) - 0.046_f64.powi(2)) * 9.81;
    let static_moment = w * 4.0 * 4.0 / 2.0;
    let r = run.summary.beams[0].record;
    let ratio = r.max_bending_moment / static_moment;
    assert!((1.8..2.1).contains(&ratio), "{ratio}: {r:?}");
    assert_eq!(r.max_bending_moment_at, 0.0);
    assert!(r.max_bending_moment_time > 0.01, "{r:?}");
}

/// ParaView shows the members as tubes beside the wire: one frame holds
/// both surfaces (16 points around each of 4 stations an element, and the
/// last), their quads apart.
#[test]
fn the_vtk_frames_draw_the_members() {
    let text = scene("").replace(
        "kind = \"static\"",
        "kind = \"dynamic\"\nend_time = 2e-3\ntime_step = 1e-3",
    ) + "[output]\nplots = false\n";
    let scene = Scene::from_toml(&text).unwrap();
    let dir = std::env::temp_dir().join(format!("ancf-members-vtk-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = RunOptions {
        out: dir.clone(),
        quiet: true,
        cancel: Default::default(),
    };
    run_scene(&scene, &opts).unwrap();
    let frame = std::fs::read_to_string(dir.join("vtk/wire_000000.vtu")).unwrap();
    let rings = (20 * 4 + 1) + (16 * 4 + 1);
    let cells = 16 * (20 * 4) + 16 * (16 * 4);
    assert!(
        frame.contains(&format!(
            "NumberOfPoints=\"{}\" NumberOfCells=\"{cells}\"",
            16 * rings
        )),
        "{}",
        &frame[..300]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A static scene with a beam no support holds is refused before work,
/// naming the beam: its static solution has rigid-body motions (it used to
/// end, after the Newton iterations, in "increase analysis.load_steps").
#[test]
fn an_unheld_beam_is_refused_for_statics() {
    let free_tube = scene("")
        .replace(
            "[[support]]\nbeam = \"tube\"\nnode = 0\nkind = \"clamp\"\n",
            "",
        )
        .replace(
            "[[support]]\nbeam = \"tube\"\nnode = \"last\"\nkind = \"pin\"\n",
            "",
        )
        .replace(
            "[[load]]\nbeam = \"tube\"\nnode = 8\nforce = [0.0, 0.0, -1000.0]\n",
            "",
        );
    let e = Scene::from_toml(&free_tube).unwrap_err().to_string();
    assert!(e.starts_with("support: member \"tube\" is not held"), "{e}");
    let free_wire = scene("").replace("[[support]]\nnode = 0\nkind = \"clamp\"\n", "");
    let e = Scene::from_toml(&free_wire).unwrap_err().to_string();
    assert!(e.starts_with("support: the wire is not held"), "{e}");
    // The same through the core's solver, for a model built in code.
    let steel = ancf_core::material::Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let model = ancf_core::model::WireBuilder::new(1.0, 4)
        .layer(steel, 0.01)
        .load(4, [0.0, 0.0, -1.0])
        .build()
        .unwrap();
    let e = ancf_core::solve::statics::solve_static(&model, &Default::default()).unwrap_err();
    assert!(
        e.message.starts_with("the wire is not held"),
        "{}",
        e.message
    );
    assert!(e.iterations.is_empty());
}

/// A member on a post: its far end on an elastic support (a spring of k
/// along z) instead of a pin. The spring takes its share of the load as
/// −k δ, and the supports still carry the load together.
#[test]
fn a_member_on_an_elastic_post_shares_the_load() {
    let k = 2e5;
    let text = scene("").replace(
        "[[support]]\nbeam = \"tube\"\nnode = \"last\"\nkind = \"pin\"\n",
        &format!(
            "[[support]]\nbeam = \"tube\"\nnode = \"last\"\nkind = \"spring\"\nstiffness = [1e8, 1e8, {k}]\n"
        ),
    );
    let scene = Scene::from_toml(&text).unwrap();
    assert_eq!(scene.model.springs().len(), 1);
    let run = ancf::run::run_in_memory(&scene);
    let post = &run.summary.supports[2];
    assert_eq!((post.beam.as_str(), post.node), ("tube", 16));
    // A cantilever on a spring prop: the prop's force R closes the gap
    // between the free tip's deflection under P at midspan, 5 P L³ / 48 EI,
    // and what R lifts back, R (L³ / 3 EI + 1 / k).
    let (p, l) = (1000.0, 4.0_f64);
    let ei = 2e11 * std::f64::consts::PI * (0.05_f64.powi(4) - 0.046_f64.powi(4)) / 4.0;
    let r = (5.0 * p * l.powi(3) / (48.0 * ei)) / (l.powi(3) / (3.0 * ei) + 1.0 / k);
    let held = post.static_force[2];
    assert!((held / r - 1.0).abs() < 0.01, "{held} N against {r} N");
    assert!(held < 5.0 / 16.0 * p, "a soft prop carries less than a pin");
    let lifted: f64 = run.summary.supports.iter().map(|s| s.static_force[2]).sum();
    assert!((lifted - 1000.0).abs() < 1e-6, "{lifted}");
}
