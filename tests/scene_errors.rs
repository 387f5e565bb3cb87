//! Bad input is refused before any work, with a message naming the field:
//! a table of malformed scenes, through the library and the CLI.

use ancf_core::scene::Scene;
use std::process::Command;

const BASE: &str = r#"
[analysis]
kind = "dynamic"
end_time = 0.01
time_step = 1e-3
spectral_radius = 1.0

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "core"
model = "st-venant-kirchhoff"
density = 7200.0
youngs_modulus = 2e9
poisson_ratio = 0.0
bending_factor = 1.0

[[material]]
name = "cover"
model = "mooney-rivlin"
density = 1100.0
mu10 = 5e5
mu01 = 1e5
penalty = 1e3

[wire]
length = 1.0
elements = 4
layers = [ { material = "core", outer_radius = 0.01 }, { material = "cover", outer_radius = 0.02 } ]
quadrature = { axial = 5, section = 3 }

[[support]]
node = 0
kind = "pin"

[[load]]
node = "last"
force = [0.0, 0.0, -1.0]
"#;

/// (what is wrong, replace this, with this, text the error must contain)
const CASES: &[(&str, &str, &str, &str)] = &[
    ("missing analysis kind", "kind = \"dynamic\"\n", "", "kind"),
    (
        "unknown key",
        "spectral_radius = 1.0",
        "spectral_radius = 1.0\nspectral_raduis = 0.5",
        "spectral_raduis",
    ),
    ("unknown table", "[gravity]", "[gravty]", "gravty"),
    (
        "wrong type",
        "elements = 4",
        "elements = \"four\"",
        "elements",
    ),
    (
        "negative radius",
        "outer_radius = 0.01 }",
        "outer_radius = -0.01 }",
        "wire.layers[0].outer_radius",
    ),
    (
        "zero radius",
        "outer_radius = 0.01 }",
        "outer_radius = 0.0 }",
        "wire.layers[0].outer_radius",
    ),
    (
        "inner radius ≥ outer",
        "outer_radius = 0.02 }",
        "outer_radius = 0.005 }",
        "wire.layers[1].outer_radius",
    ),
    ("zero length", "length = 1.0", "length = 0.0", "wire.length"),
    (
        "negative length",
        "length = 1.0",
        "length = -2.0",
        "wire.length",
    ),
    (
        "zero elements",
        "elements = 4",
        "elements = 0",
        "wire.elements",
    ),
    (
        "graded mesh and elements both given",
        "elements = 4",
        "elements = 4\nsegments = [ { length = 1.0, elements = 4 } ]",
        "wire.segments",
    ),
    (
        "neither elements nor segments",
        "elements = 4",
        "",
        "wire.elements",
    ),
    (
        "segments not adding up to the length",
        "elements = 4",
        "segments = [ { length = 0.5, elements = 2 }, { length = 0.4, elements = 8 } ]",
        "wire.segments",
    ),
    (
        "a segment without elements",
        "elements = 4",
        "segments = [ { length = 0.5, elements = 2 }, { length = 0.5, elements = 0 } ]",
        "wire.segments[1].elements",
    ),
    (
        "a segment of negative length",
        "elements = 4",
        "segments = [ { length = 1.5, elements = 2 }, { length = -0.5, elements = 3 } ]",
        "wire.segments[1].length",
    ),
    (
        "ω above 1",
        "bending_factor = 1.0",
        "bending_factor = 1.5",
        "material[0].bending_factor",
    ),
    (
        "ω below 0",
        "bending_factor = 1.0",
        "bending_factor = -0.1",
        "material[0].bending_factor",
    ),
    (
        "ν ≥ 0.5",
        "poisson_ratio = 0.0",
        "poisson_ratio = 0.5",
        "material[0].poisson_ratio",
    ),
    (
        "κ ≤ 0",
        "penalty = 1e3",
        "penalty = 0.0",
        "material[1].penalty",
    ),
    (
        "NaN modulus",
        "youngs_modulus = 2e9",
        "youngs_modulus = nan",
        "material[0].youngs_modulus",
    ),
    (
        "infinite density",
        "density = 7200.0",
        "density = inf",
        "material[0].density",
    ),
    (
        "unknown material name",
        "{ material = \"cover\"",
        "{ material = \"coverr\"",
        "wire.layers[1].material",
    ),
    (
        "support on a missing node",
        "node = 0\nkind = \"pin\"",
        "node = 9\nkind = \"pin\"",
        "support[0].node",
    ),
    (
        "unknown support kind",
        "kind = \"pin\"",
        "kind = \"swivel\"",
        "swivel",
    ),
    (
        "zero time step",
        "time_step = 1e-3",
        "time_step = 0.0",
        "analysis.time_step",
    ),
    (
        "negative time step",
        "time_step = 1e-3",
        "time_step = -1e-3",
        "analysis.time_step",
    ),
    (
        "absurdly small time step",
        "time_step = 1e-3",
        "time_step = 1e-300",
        "analysis.time_step",
    ),
    (
        "a time step that is neither seconds nor auto",
        "time_step = 1e-3",
        "time_step = \"fast\"",
        "analysis.time_step",
    ),
    (
        "adaptive steps without a tolerance",
        "time_step = 1e-3",
        "time_step = \"auto\"",
        "analysis.error_tolerance",
    ),
    (
        "a negative error tolerance",
        "time_step = 1e-3",
        "time_step = \"auto\"\nerror_tolerance = -1e-6",
        "analysis.error_tolerance",
    ),
    (
        "an error tolerance for fixed steps",
        "time_step = 1e-3",
        "time_step = 1e-3\nerror_tolerance = 1e-6",
        "analysis.error_tolerance",
    ),
    (
        "a longest step beyond the run",
        "time_step = 1e-3",
        "time_step = \"auto\"\nerror_tolerance = 1e-6\nmax_time_step = 1.0",
        "analysis.max_time_step",
    ),
    (
        "negative end time",
        "end_time = 0.01",
        "end_time = -1.0",
        "analysis.end_time",
    ),
    (
        "spectral radius above 1",
        "spectral_radius = 1.0",
        "spectral_radius = 1.2",
        "analysis.spectral_radius",
    ),
    (
        "Broyden updates with full Newton",
        "spectral_radius = 1.0",
        "spectral_radius = 1.0\nnewton = \"full\"\nbroyden = true",
        "analysis.broyden",
    ),
    (
        "Broyden updates in a static analysis",
        "kind = \"dynamic\"\nend_time = 0.01\ntime_step = 1e-3\nspectral_radius = 1.0",
        "kind = \"static\"\nbroyden = true",
        "analysis.broyden",
    ),
    ("malformed TOML", "[wire]", "[wire", "line"),
    (
        "SVK key on Mooney-Rivlin",
        "mu01 = 1e5",
        "mu01 = 1e5\nyoungs_modulus = 1e6",
        "material[1].youngs_modulus",
    ),
    (
        "unknown material model",
        "model = \"mooney-rivlin\"",
        "model = \"neo-hookean\"",
        "material[1].model",
    ),
    (
        "infinite gravity",
        "[0.0, 0.0, -9.81]",
        "[0.0, 0.0, -inf]",
        "gravity.acceleration[2]",
    ),
    (
        "load on a missing node",
        "node = \"last\"",
        "node = 12",
        "load[0].node",
    ),
    (
        "unknown node name",
        "node = \"last\"",
        "node = \"first\"",
        "first",
    ),
    (
        "zero axial quadrature",
        "axial = 5",
        "axial = 0",
        "wire.quadrature.axial",
    ),
    (
        "duplicate material",
        "name = \"cover\"",
        "name = \"core\"",
        "material[1].name",
    ),
    (
        "a follower without a moment",
        "force = [0.0, 0.0, -1.0]",
        "force = [0.0, 0.0, -1.0]\nfollower = true",
        "load[0].follower",
    ),
    (
        "static key in dynamic run",
        "spectral_radius = 1.0",
        "spectral_radius = 1.0\nload_steps = 3",
        "analysis.load_steps",
    ),
];

#[test]
fn the_base_scene_is_valid() {
    Scene::from_toml(BASE).expect("base scene");
}

#[test]
fn malformed_scenes_are_refused_naming_the_field() {
    assert!(CASES.len() >= 20);
    for (what, from, to, expect) in CASES {
        assert!(
            BASE.contains(from),
            "{what}: the base scene has no `{from}`"
        );
        let text = BASE.replacen(from, to, 1);
        let err = Scene::from_toml(&text)
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"));
        let msg = err.to_string();
        assert!(
            msg.contains(expect),
            "{what}: message `{msg}` does not mention `{expect}`"
        );
    }
}

#[test]
fn cli_refuses_bad_scenes_without_leaving_output() {
    let dir = std::env::temp_dir().join(format!("ancf-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, (what, from, to, expect)) in CASES.iter().enumerate().step_by(4) {
        let path = dir.join(format!("bad{i}.toml"));
        std::fs::write(&path, BASE.replacen(from, to, 1)).unwrap();
        let out_dir = dir.join(format!("out{i}"));
        let out = Command::new(env!("CARGO_BIN_EXE_ancf"))
            .args([
                "run",
                path.to_str().unwrap(),
                "--out",
                out_dir.to_str().unwrap(),
                "--quiet",
            ])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{what}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(expect), "{what}: {stderr}");
        assert!(
            !out_dir.exists(),
            "{what}: output directory created for a refused scene"
        );
        let check = Command::new(env!("CARGO_BIN_EXE_ancf"))
            .args(["check", path.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(check.status.code(), Some(2), "{what} (check)");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Regression: 10 cm tubes slipped between contact test stations
/// 12.5 cm apart and the wire fell through the frame. A rod thinner than the
/// station spacing is refused, naming the field and the stations needed.
#[test]
fn rod_thinner_than_station_spacing_is_refused() {
    let rod = "\n[[rod]]\ncenter = [0.5, 0.0, -0.3]\naxis = [0.0, 1.0, 0.0]\nradius = 0.01\ncontact_law = \"surface\"\ncontact_stiffness = 1e10\n";
    let err = Scene::from_toml(&(BASE.to_string() + rod)).expect_err("refused");
    assert_eq!(err.field, "contact.stations");
    assert!(err.message.contains("use stations = "), "{}", err.message);
    let fine = BASE.to_string() + rod + "\n[contact]\nstations = 40\n";
    Scene::from_toml(&fine).expect("enough stations");
}

/// Contact laws. A stiffness without a law (the old N/m³ meaning)
/// is refused naming `contact_law`; each law's bad values (and an unknown
/// rod material under any law, and bad contact damping) name their field;
/// the line law needs no station rule, and hertz derives its stiffness.
#[test]
fn contact_laws_are_validated_naming_the_field() {
    let rod = |body: &str| {
        format!(
            "{BASE}\n[[material]]\nname = \"rod-steel\"\nmodel = \"st-venant-kirchhoff\"\ndensity = 7850.0\n\
             youngs_modulus = 2e11\npoisson_ratio = 0.3\n\n[[rod]]\ncenter = [0.5, 0.0, -0.3]\n\
             axis = [0.0, 1.0, 0.0]\nradius = 0.01\n{body}"
        )
    };
    let cases = [
        ("contact_stiffness = 1e10\n", "rod[0].contact_law"),
        (
            "contact_law = \"point\"\ncontact_stiffness = 1e10\n",
            "rod[0].contact_law",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = -5e7\n",
            "rod[0].contact_stiffness",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = nan\n",
            "rod[0].contact_stiffness",
        ),
        ("contact_law = \"line\"\n", "rod[0].contact_stiffness"),
        ("contact_law = \"hertz\"\n", "rod[0].material"),
        (
            "contact_law = \"hertz\"\nmaterial = \"unobtainium\"\n",
            "rod[0].material",
        ),
        (
            "contact_law = \"hertz\"\nmaterial = \"rod-steel\"\ncontact_stiffness = 1e9\n",
            "rod[0].contact_stiffness",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nmaterial = \"rod-stel\"\n",
            "rod[0].material",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\n[contact]\nzone_points = 0\n",
            "contact.zone_points",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 0.0\n",
            "rod[0].restitution",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 1.5\n",
            "rod[0].restitution",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution_model = \"flores\"\n",
            "rod[0].restitution",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 0.5\nrestitution_model = \"newton\"\n",
            "rod[0].restitution_model",
        ),
        (
            "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 0.5\n[contact]\nmin_impact_speed = 0.0\n",
            "contact.min_impact_speed",
        ),
    ];
    for (body, field) in cases {
        let err = Scene::from_toml(&rod(body)).expect_err(body);
        assert_eq!(err.field, field, "{body}: {}", err.message);
    }
    // The line law has no station-spacing rule (the thin rod above is fine);
    // a line rod may name its material (compared with hertz by the study).
    let line = Scene::from_toml(&rod(
        "contact_law = \"line\"\ncontact_stiffness = 5e7\nmaterial = \"rod-steel\"\n",
    ))
    .expect("line");
    assert_eq!(line.model.contact().unwrap().rods[0].contact_stiffness, 5e7);
    assert_eq!(line.model.contact().unwrap().rods[0].damping, None);
    // Contact damping: the exact model by default; e = 1 builds none.
    let damped = Scene::from_toml(&rod(
        "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 0.4\n",
    ))
    .expect("damped");
    let d = damped.model.contact().unwrap().rods[0]
        .damping
        .expect("damping");
    assert_eq!((d.restitution(), d.model().name()), (0.4, "exact"));
    let elastic = Scene::from_toml(&rod(
        "contact_law = \"line\"\ncontact_stiffness = 5e7\nrestitution = 1.0\n",
    ))
    .expect("e = 1");
    assert_eq!(elastic.model.contact().unwrap().rods[0].damping, None);
    // Hertz: ε_L = E* √(R_e / (2 R_s)), E* from the rod and the wire's outer layer.
    let hertz = Scene::from_toml(&rod("contact_law = \"hertz\"\nmaterial = \"rod-steel\"\n"))
        .expect("hertz");
    let c = hertz.model.contact().unwrap();
    let (rw, rr) = (c.wire_radius, 0.01);
    // The base scene's cover is Mooney–Rivlin (μ10 = 5e5, μ01 = 1e5 Pa):
    // small-strain E = 6 (μ10 + μ01), ν = 0.5.
    let (e_wire, nu_wire) = (6.0 * (5e5 + 1e5), 0.5);
    let e_star = 1.0 / ((1.0 - 0.09) / 2e11 + (1.0 - nu_wire * nu_wire) / e_wire);
    let expected = e_star * ((rw * rr).sqrt() / (2.0 * (rw + rr))).sqrt();
    let got = c.rods[0].contact_stiffness;
    assert!(
        (got - expected).abs() < 1e-12 * expected,
        "{got} vs {expected}"
    );
}

/// A missing key is named by its full field, the table it belongs to
/// included; a missing table by its own name.
#[test]
fn missing_keys_are_named_with_their_table() {
    let wire = BASE
        .split("[wire]")
        .nth(1)
        .and_then(|rest| rest.split("[[support]]").next())
        .unwrap();
    let cases = [
        (format!("[wire]{wire}"), String::new(), "wire"),
        ("length = 1.0\n".to_string(), String::new(), "wire.length"),
        (
            "kind = \"dynamic\"\n".to_string(),
            String::new(),
            "analysis.kind",
        ),
        (
            "{ material = \"core\", outer_radius = 0.01 }".to_string(),
            "{ material = \"core\" }".to_string(),
            "wire.layers.outer_radius",
        ),
        (
            "name = \"cover\"\n".to_string(),
            String::new(),
            "material[1].name",
        ),
    ];
    for (from, to, field) in cases {
        assert!(BASE.contains(&from), "the base scene has no `{from}`");
        let err = Scene::from_toml(&BASE.replacen(&from, &to, 1))
            .err()
            .unwrap_or_else(|| panic!("{field} missing: accepted"));
        assert_eq!(err.field, field, "{}", err.message);
    }
}
