//! The same invalid value is refused for the same reason whichever way it
//! comes in: through a scene file (naming the file's field) and through the
//! builder and the solver settings in code (naming the model part and the
//! parameter). The cases are the table in tests/data/invalid_inputs.toml,
//! which the Python package's tests run through its API as well.

use ancf_core::material::Material;
use ancf_core::model::contact::{RestitutionModel, Rod};
use ancf_core::model::{ModelError, SupportKind, WireBuilder};
use ancf_core::scene::Scene;
use ancf_core::solve::dynamics::DynamicSettings;

/// One row of the table.
#[derive(Debug)]
struct Case {
    part: String,
    parameter: String,
    value: f64,
    reason: String,
}

fn cases() -> Vec<Case> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/invalid_inputs.toml"
    );
    let text = std::fs::read_to_string(path).expect("the table");
    let table: toml::Table = toml::from_str(&text).expect("valid TOML");
    table["case"]
        .as_array()
        .expect("[[case]]")
        .iter()
        .map(|c| Case {
            part: c["part"].as_str().expect("part").into(),
            parameter: c["parameter"].as_str().expect("parameter").into(),
            value: c["value"]
                .as_float()
                .or_else(|| c["value"].as_integer().map(|i| i as f64))
                .expect("value"),
            reason: c["reason"].as_str().expect("reason").into(),
        })
        .collect()
}

/// A valid scene: a pinned steel wire over a line-law rod.
const BASE: &str = r#"
[analysis]
kind = "dynamic"
end_time = 0.01
time_step = 1e-3

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3

[wire]
length = 1.0
elements = 4
layers = [{ material = "steel", outer_radius = 0.01 }]

[[support]]
node = 0
kind = "pin"

[[rod]]
center = [0.5, 0.0, -0.2]
axis = [0.0, 1.0, 0.0]
radius = 0.02
contact_law = "line"
contact_stiffness = 5e7
"#;

/// The base scene with the case's value, and the field it must be refused at.
fn scene_with(case: &Case) -> (String, String) {
    let mut doc: toml::Table = toml::from_str(BASE).expect("base scene");
    let value = toml::Value::Float(case.value);
    let p = case.parameter.clone();
    let (table, field) = match case.part.as_str() {
        "material" => (
            doc["material"].as_array_mut().unwrap()[0]
                .as_table_mut()
                .unwrap(),
            format!("material[0].{p}"),
        ),
        "layer" => (
            doc["wire"]["layers"].as_array_mut().unwrap()[0]
                .as_table_mut()
                .unwrap(),
            format!("wire.layers[0].{p}"),
        ),
        "rod" => (
            doc["rod"].as_array_mut().unwrap()[0]
                .as_table_mut()
                .unwrap(),
            format!("rod[0].{p}"),
        ),
        part => (doc[part].as_table_mut().unwrap(), format!("{part}.{p}")),
    };
    table.insert(p, value);
    (toml::to_string(&doc).expect("TOML"), field)
}

/// What the builder or the settings say of the case: the parameter named
/// and the message.
fn built_with(case: &Case) -> (String, String) {
    // The case's value for a material or rod parameter, the base's otherwise.
    let v = |name: &str, base: f64| {
        let ours = matches!(case.part.as_str(), "material" | "rod") && case.parameter == name;
        if ours { case.value } else { base }
    };
    if case.part == "analysis" {
        let mut s = DynamicSettings {
            time_step: 1e-3,
            end_time: 0.01,
            ..Default::default()
        };
        match case.parameter.as_str() {
            "time_step" => s.time_step = case.value,
            "end_time" => s.end_time = case.value,
            "spectral_radius" => s.spectral_radius = case.value,
            other => panic!("no settings parameter {other}"),
        }
        let Err(e) = s.check() else {
            panic!("{case:?} is accepted by the settings")
        };
        return (e.field, e.message);
    }
    let steel = Material::st_venant_kirchhoff(
        v("density", 7800.0),
        v("youngs_modulus", 2e11),
        v("poisson_ratio", 0.3),
        v("bending_factor", 1.0),
    );
    let mut rod = Rod::line(
        [0.5, 0.0, -0.2],
        [0.0, 1.0, 0.0],
        v("radius", 0.02),
        v("contact_stiffness", 5e7),
    )
    .with_friction(v("friction", 0.0));
    if case.part == "rod" && case.parameter == "length" {
        rod = rod.with_length(case.value);
    }
    if case.part == "rod" && case.parameter == "restitution" {
        rod = rod.with_restitution(case.value, RestitutionModel::Exact);
    }
    let length = if case.part == "wire" { case.value } else { 1.0 };
    let radius = if case.part == "layer" {
        case.value
    } else {
        0.01
    };
    let e = WireBuilder::new(length, 4)
        .layer(steel, radius)
        .support(0, SupportKind::Pin)
        .rod(rod)
        .build()
        .err()
        .unwrap_or_else(|| panic!("{case:?} is accepted by the builder"));
    let named = match &e {
        ModelError::Wire { what, .. } => what.clone(),
        ModelError::Layer { field, .. } | ModelError::Rod { field, .. } => field.clone(),
        other => panic!("{other} names another part"),
    };
    (named, e.message())
}

#[test]
fn every_invalid_value_is_refused_for_the_same_reason_by_scene_and_builder() {
    let cases = cases();
    assert!(cases.len() >= 15, "the table has its cases");
    for case in &cases {
        let what = format!("{} {} = {}", case.part, case.parameter, case.value);
        let (text, field) = scene_with(case);
        let Err(scene) = Scene::from_toml(&text) else {
            panic!("{what}: the scene is accepted");
        };
        assert_eq!(scene.field, field, "{what}: the scene names the field");
        assert!(
            scene.message.contains(&case.reason),
            "{what}: scene says `{}`, not `{}`",
            scene.message,
            case.reason
        );
        let (named, message) = built_with(case);
        assert_eq!(
            named, case.parameter,
            "{what}: the builder names the parameter"
        );
        assert_eq!(
            message, scene.message,
            "{what}: the builder and the scene give one reason"
        );
    }
}

#[test]
fn the_base_of_the_table_is_valid() {
    Scene::from_toml(BASE).expect("the base scene is valid");
}

/// A vector is three numbers: a longer one is refused, not cut short (a
/// fourth entry of a force would otherwise be dropped without a word), and
/// a shorter one too.
#[test]
fn vectors_of_three_numbers_only() {
    let pendulum = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/pendulum.toml"
    ))
    .unwrap();
    for (from, to) in [
        (
            "direction = [1.0, 0.0, 0.0]",
            "direction = [1.0, 0.0, 0.0, 0.0]",
        ),
        ("direction = [1.0, 0.0, 0.0]", "direction = [1.0, 0.0]"),
        (
            "acceleration = [0.0, 0.0, -9.81]",
            "acceleration = [0.0, 0.0, -9.81, 12345.0]",
        ),
        (
            "origin = [0.0, 0.0, 0.0]",
            "origin = [0.0, 0.0, 0.0, \"junk\", true]",
        ),
    ] {
        let text = pendulum.replace(from, to);
        assert_ne!(text, pendulum, "{from}");
        let e = ancf_core::scene::Scene::from_toml(&text)
            .unwrap_err()
            .to_string();
        assert!(e.contains(to.split(" =").next().unwrap()), "{to}: {e}");
    }
    let force = pendulum + "\n[[load]]\nnode = \"last\"\nforce = [0, 0, -1, 12345]\n";
    let e = ancf_core::scene::Scene::from_toml(&force)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("invalid length 4, expected exactly 3 numbers"),
        "{e}"
    );
}

/// An error of TOML syntax or type names the key (or table) on its line,
/// with the table's index for arrays of tables; the message keeps toml's
/// line and column.
#[test]
fn syntax_and_type_errors_name_their_field() {
    for (text, field, line) in [
        (
            "[wire]\nlength = 1.0\nelements = \"x\"\n",
            "wire.elements",
            3,
        ),
        (
            "[[rod]]\ncenter = [0, 0, 0]\naxis = [0, 1, 0]\nradius = 0.1\n[[rod]]\naxis = [0, 1, 0]\nradius = 0.1\ncenter = [1, 2, \"a\"]\n",
            "rod[1].center",
            8,
        ),
        ("[wire\nlength = 1.0\n", "wire", 1),
        (
            "[wire]\nlayers = [ { material = \"a\", outer_radius = 0.01 },\n  { material = 3 } ]\n",
            "wire",
            3,
        ),
    ] {
        let e = Scene::from_toml(text).unwrap_err();
        assert_eq!(e.field, field, "{e}");
        assert!(
            e.message.contains(&format!("at line {line}, column")),
            "{e}"
        );
    }
}

/// A count that is not a whole number ≥ 0 is answered in the user's words,
/// with the range its key accepts, not the parser's ("expected usize").
#[test]
fn counts_that_are_not_whole_numbers_say_what_is_accepted() {
    let max = ancf_core::model::MAX_ELEMENTS;
    for (from, to, field, says) in [
        (
            "elements = 4",
            "elements = -4",
            "wire.elements",
            format!("must be a whole number from 1 to {max}, got -4"),
        ),
        (
            "elements = 4",
            "elements = 2.5",
            "wire.elements",
            format!("must be a whole number from 1 to {max}, got 2.5"),
        ),
        (
            "time_step = 1e-3",
            "time_step = 1e-3\nload_steps = -1",
            "analysis.load_steps",
            "must be a whole number from 1 to".into(),
        ),
    ] {
        let e = Scene::from_toml(&BASE.replace(from, to)).unwrap_err();
        assert_eq!(e.field, field, "{e}");
        assert!(e.message.contains(&says), "{e}");
        assert!(!e.message.contains("usize"), "{e}");
        assert!(e.message.contains("at line"), "the place is kept: {e}");
    }
}

/// A rod that the wire starts inside is the geometry's fault, and is
/// refused before any work naming the rod (a run would begin with the
/// whole overlap as its contact force); touching it is fine. A static
/// start pushes the wire out of a shallow overlap, but a rod through the
/// wire's centerline is refused there too: it has no side to push to.
#[test]
fn a_rod_overlapping_the_wire_at_the_start_is_refused() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/wire_rod_impact.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let rod = "center = [1.0, 0.0, -0.3]";
    assert!(text.contains(rod));
    let inside = text.replace(rod, "center = [1.0, 0.0, -0.02]");
    let e = Scene::from_toml(&inside).unwrap_err();
    assert_eq!(e.field, "rod[0].center", "{e}");
    assert!(e.message.contains("the geometry is at fault"), "{e}");
    // Touching: the wire (radius 14.07 mm) on the rod (20 mm) at 34.07 mm.
    let touching = text.replace(rod, "center = [1.0, 0.0, -0.03407]");
    assert!(Scene::from_toml(&touching).is_ok());
    let kind = "kind = \"dynamic\"";
    assert!(text.contains(kind));
    let static_start = |t: &str| t.replace(kind, "kind = \"dynamic\"\ninitial = \"static\"");
    let e = Scene::from_toml(&static_start(&inside)).unwrap_err();
    assert_eq!(e.field, "rod[0].center", "{e}");
    assert!(e.message.contains("no side to push it to"), "{e}");
    // Less than the wire's radius deep: the static solve pushes it out.
    let shallow = text.replace(rod, "center = [1.0, 0.0, -0.025]");
    assert!(Scene::from_toml(&shallow).is_err());
    assert!(Scene::from_toml(&static_start(&shallow)).is_ok());
}

/// A member's name becomes part of file names and CSV headers: only an
/// identifier is taken, by the scene and the builder alike.
#[test]
fn a_member_name_must_be_an_identifier() {
    let scene = |name: &str| {
        format!(
            "{BASE}\n[[beam]]\nname = \"{}\"\nlength = 1.0\nelements = 2\norigin = [0.0, 5.0, 0.0]\n\
             layers = [{{ material = \"steel\", outer_radius = 0.01 }}]\n[[support]]\nbeam = \"{}\"\n\
             node = 0\nkind = \"fixed\"\n",
            toml_escaped(name),
            toml_escaped(name)
        )
    };
    let long = "a".repeat(240);
    for bad in [
        "../../x",
        "/abs",
        "a\u{0}b",
        long.as_str(),
        "a,b\nc",
        "wire",
        "",
        "tube 1",
    ] {
        let e = Scene::from_toml(&scene(bad)).expect_err(bad);
        assert_eq!(e.field, "beam[0].name", "{bad:?}: {e}");
        let built = WireBuilder::new(1.0, 2)
            .layer(Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0), 0.01)
            .support(0, SupportKind::Fixed)
            .member(
                ancf_core::model::BeamBuilder::new(bad, 1.0, 2)
                    .placed([0.0, 5.0, 0.0], [1.0, 0.0, 0.0])
                    .layer(Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0), 0.01),
            )
            .build();
        assert!(
            matches!(built, Err(ModelError::Member { .. })),
            "{bad:?}: the builder took it"
        );
    }
    for good in ["tube0", "post_1-a", "A"] {
        Scene::from_toml(&scene(good)).unwrap_or_else(|e| panic!("{good}: {e}"));
    }
}

/// `s` as the inside of a TOML basic string.
fn toml_escaped(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '"' => "\\\"".to_string(),
            '\\' => "\\\\".to_string(),
            c if (c as u32) < 0x20 => format!("\\u{:04X}", c as u32),
            c => c.to_string(),
        })
        .collect()
}

/// Counts and frequencies have bounds before any work: the filter's class
/// and the oscillators below the steps' Nyquist frequency (1/(2h) = 500 Hz
/// here), the static start's increments as a static solve's.
#[test]
fn counts_and_frequencies_are_bounded_before_work() {
    let with = |extra: &str| Scene::from_toml(&format!("{BASE}\n{extra}\n"));
    for (extra, field) in [
        ("[output]\ncfc = 1e9", "output.cfc"),
        ("[output]\ncfc = 1e300", "output.cfc"),
        ("[output]\ncfc = 300.0", "output.cfc"),
        (
            "[output]\nresponse_frequencies = [2e153]",
            "output.response_frequencies[0]",
        ),
        (
            "[output]\nresponse_frequencies = [10.0, 500.0]",
            "output.response_frequencies[1]",
        ),
    ] {
        let e = with(extra).expect_err(extra);
        assert_eq!(e.field, field, "{extra}: {e}");
    }
    with("[output]\ncfc = 180.0\nresponse_frequencies = [10.0, 400.0]").expect("below Nyquist");
    let scene = |analysis: &str| Scene::from_toml(&BASE.replace("kind = \"dynamic\"", analysis));
    let e = scene("kind = \"dynamic\"\ninitial = \"static\"\nload_steps = 1099511627776")
        .expect_err("2^40 increments");
    assert_eq!(e.field, "analysis.load_steps", "{e}");
    let e = scene("kind = \"dynamic\"\nload_steps = 4").expect_err("no static start");
    assert!(e.message.contains("initial = \"static\""), "{e}");
}
