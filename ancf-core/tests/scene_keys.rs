//! The scene keys' declaration (`ancf_core::scene::keys`) against what
//! uses it: the schema's fields, docs/scene.md's key tables, the value
//! checks (a value just outside a declared range is refused with its key
//! named), the declared defaults (a scene that writes one parses to the
//! scene that omits it), and the Python signatures and stub. Each test
//! fails on drift in either direction.

use ancf_core::scene::keys::{self, Absent, KEYS, Key, KeyType, Range};
use ancf_core::scene::{self as scene, Scene};
use serde::de::{self, Deserialize, Deserializer, Visitor};
use std::collections::BTreeSet;
use toml::Value;

/// The field names a derived `Deserialize` struct asks for.
fn fields<'de, T: Deserialize<'de>>() -> Vec<&'static str> {
    struct Capture<'a>(&'a mut Vec<&'static str>);
    #[derive(Debug)]
    struct Stop;
    impl std::fmt::Display for Stop {
        fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("stop")
        }
    }
    impl std::error::Error for Stop {}
    impl de::Error for Stop {
        fn custom<M: std::fmt::Display>(_: M) -> Self {
            Stop
        }
    }
    impl<'de> Deserializer<'de> for Capture<'_> {
        type Error = Stop;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
            Err(Stop)
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Stop> {
            self.0.extend_from_slice(fields);
            Err(Stop)
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
            bytes byte_buf option unit unit_struct newtype_struct seq tuple
            tuple_struct map enum identifier ignored_any
        }
    }
    let mut out = Vec::new();
    let _ = T::deserialize(Capture(&mut out));
    out
}

fn declared(tables: &[&str]) -> BTreeSet<&'static str> {
    KEYS.iter()
        .filter(|k| tables.contains(&k.table))
        .map(|k| k.name)
        .collect()
}

#[test]
fn the_schema_has_exactly_the_declared_keys() {
    let cases: Vec<(&[&str], Vec<&str>)> = vec![
        (&["analysis"], fields::<scene::AnalysisSpec>()),
        (&["gravity"], fields::<scene::GravitySpec>()),
        (&["material"], fields::<scene::MaterialSpec>()),
        (&["material.rate"], fields::<scene::RateSpec>()),
        (&["wire", "beam"], fields::<scene::WireSpec>()),
        (&["wire.layers"], fields::<scene::LayerSpec>()),
        (&["wire.rectangle"], fields::<scene::RectangleSpec>()),
        (&["wire.quadrature"], fields::<scene::QuadratureSpec>()),
        (&["wire.segments"], fields::<scene::SegmentSpec>()),
        (&["support"], fields::<scene::SupportSpec>()),
        (&["load"], fields::<scene::LoadSpec>()),
        (&["rod"], fields::<scene::RodSpec>()),
        (&["contact"], fields::<scene::ContactSpec>()),
        (&["damping"], fields::<scene::DampingSpec>()),
        (&["output"], fields::<scene::OutputSpec>()),
        (&["clearance"], fields::<scene::ClearanceSpec>()),
        (&["ground"], fields::<scene::GroundSpec>()),
    ];
    let mut tables_seen = BTreeSet::new();
    for (tables, schema) in cases {
        tables_seen.extend(tables.iter().copied());
        let schema: BTreeSet<&str> = schema.into_iter().collect();
        assert!(!schema.is_empty(), "{tables:?}: no fields read");
        assert_eq!(
            schema,
            declared(tables),
            "{tables:?}: schema vs declaration"
        );
    }
    let top: BTreeSet<&str> = fields::<scene::SceneFile>().into_iter().collect();
    for k in KEYS {
        assert!(
            tables_seen.contains(k.table),
            "{}: table not in the schema",
            k.path()
        );
        let head = k.table.split('.').next().unwrap();
        assert!(
            top.contains(head),
            "{}: no such table in a scene file",
            k.path()
        );
        assert!(!k.doc.is_empty(), "{}: no doc line", k.path());
    }
    let mut paths = BTreeSet::new();
    for k in KEYS {
        assert!(paths.insert(k.path()), "{} declared twice", k.path());
    }
}

/// A row of a docs key table: the keys it documents, and its cells by
/// column name.
type DocRow = (Vec<String>, Vec<(String, String)>);

/// docs/scene.md's key tables: section title → rows.
fn doc_tables() -> Vec<(String, Vec<DocRow>)> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/scene.md"))
        .expect("docs/scene.md");
    let mut out: Vec<(String, Vec<DocRow>)> = Vec::new();
    let mut header: Option<Vec<String>> = None;
    for line in text.lines() {
        if let Some(title) = line.strip_prefix("## ") {
            let table = title
                .split('`')
                .nth(1)
                .map(|t| t.trim_matches(|c| c == '[' || c == ']').to_string());
            out.push((table.unwrap_or_default(), Vec::new()));
            header = None;
            continue;
        }
        if !line.starts_with('|') {
            header = None;
            continue;
        }
        let cells = split_row(line);
        match &header {
            None if cells.first().map(String::as_str) == Some("key") => header = Some(cells),
            None => {}
            Some(_) if cells.iter().all(|c| c.chars().all(|ch| ch == '-')) => {}
            Some(h) => {
                let names: Vec<String> = cells[0]
                    .split('`')
                    .skip(1)
                    .step_by(2)
                    .map(str::to_string)
                    .collect();
                let named = h.iter().cloned().zip(cells.iter().cloned()).collect();
                if let Some(section) = out.last_mut() {
                    section.1.push((names, named));
                }
            }
        }
    }
    out
}

/// A table row's cells, `\|` kept inside a cell.
fn split_row(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    let mut cells = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cells.last_mut().unwrap().push('|');
                chars.next();
            }
            '|' => cells.push(String::new()),
            _ => cells.last_mut().unwrap().push(c),
        }
    }
    cells.into_iter().map(|c| c.trim().to_string()).collect()
}

#[test]
fn docs_scene_md_lists_each_declared_key_with_its_default_and_unit() {
    let docs = doc_tables();
    let mut problems = Vec::new();
    for (table, rows) in &docs {
        if rows.is_empty() || keys::keys_of(table).next().is_none() {
            continue;
        }
        let documented: BTreeSet<&str> = rows
            .iter()
            .flat_map(|(names, _)| names.iter().map(String::as_str))
            .collect();
        let want = declared(&[table.as_str()]);
        if documented != want {
            problems.push(format!(
                "[{table}]: documented {documented:?}, declared {want:?}"
            ));
        }
        for (names, cells) in rows {
            for name in names {
                let Some(k) = keys::find(table, name) else {
                    continue;
                };
                for (column, cell) in cells {
                    let cell = cell.replace('`', "");
                    let want = match column.as_str() {
                        "default" => k.default.doc_text().replace('`', ""),
                        "unit" => k.unit.to_string(),
                        _ => continue,
                    };
                    if cell != want {
                        problems.push(format!(
                            "{}: docs' {column} \"{cell}\", declared \"{want}\"",
                            k.path()
                        ));
                    }
                }
            }
        }
    }
    for head in [
        "analysis", "material", "wire", "beam", "rod", "contact", "output",
    ] {
        assert!(
            docs.iter().any(|(t, rows)| t == head && !rows.is_empty()),
            "docs/scene.md has no key table for [{head}]"
        );
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A scene with every table, each key absent unless the scene needs it.
const BASE: &str = r#"
[analysis]
kind = "dynamic"
end_time = 0.002
time_step = 0.001

[gravity]
acceleration = [0.0, 0.0, -9.81]

[[material]]
name = "steel"
model = "st-venant-kirchhoff"
density = 7850.0
youngs_modulus = 2e11

[[material]]
name = "rubber"
model = "mooney-rivlin"
density = 1100.0
mu10 = 1e5
mu01 = 2e4
penalty = 1e3

[[material]]
name = "s235"
model = "elastic-plastic"
density = 7850.0
youngs_modulus = 2.1e11
yield_stress = 2.35e8

[wire]
length = 1.0
elements = 4
layers = [{ material = "steel", outer_radius = 0.01 }]

[[beam]]
name = "tube"
length = 1.0
elements = 2
origin = [0.5, -0.5, -1.0]
direction = [0.0, 1.0, 0.0]
layers = [{ material = "steel", inner_radius = 0.04, outer_radius = 0.05 }]

[[support]]
node = 0
kind = "pin"

[[support]]
node = "last"
kind = "spring"
stiffness = [1e3, 1e3, 1e3]

[[support]]
beam = "tube"
node = 0
kind = "clamp"

[[load]]
node = 2
force = [0.0, 0.0, -1.0]

[[rod]]
center = [0.5, 0.0, -0.5]
axis = [0.0, 1.0, 0.0]
radius = 0.02
contact_stiffness = 1e7
contact_law = "line"

[[ground]]
point = [0.0, 0.0, -2.0]
normal = [0.0, 0.0, 1.0]
contact_stiffness = 1e7

[contact]

[damping]
kind = "rayleigh"
mass = 0.1

[[clearance]]
kind = "half-space"
point = [0.0, 0.0, -5.0]
normal = [0.0, 0.0, 1.0]

[output]
vtk = false
"#;

/// The base scene's table that `table` names (its first entry for a
/// `[[table]]`; the rubber for Mooney–Rivlin's keys, the spring for a
/// spring's), made ready for
/// `name` to take a value: keys it goes with are set.
fn place<'a>(doc: &'a mut Value, k: &Key) -> &'a mut toml::Table {
    let root = doc.as_table_mut().unwrap();
    let mut parts = k.table.split('.');
    let head = parts.next().unwrap();
    if k.table == "damping" && k.name == "strain_rate_coefficient" {
        root.insert(
            "damping".into(),
            Value::Table(toml::toml! { kind = "kelvin-voigt" }),
        );
    }
    if k.table == "analysis" && ["max_time_step", "error_tolerance"].contains(&k.name) {
        let analysis = root["analysis"].as_table_mut().unwrap();
        analysis.insert("time_step".into(), "auto".into());
        analysis.insert("error_tolerance".into(), 1e-4.into());
    }
    if k.table == "analysis" && k.name == "load_steps" {
        root["analysis"]
            .as_table_mut()
            .unwrap()
            .insert("initial".into(), "static".into());
    }
    if k.table == "output" && k.name == "response_damping" {
        root["output"].as_table_mut().unwrap().insert(
            "response_frequencies".into(),
            Value::Array(vec![10.0.into()]),
        );
    }
    let second = match head {
        "material" => ["mu10", "mu01", "penalty"].as_slice(),
        "support" => [
            "stiffness",
            "rotational_stiffness",
            "torsional_stiffness",
            "damping",
        ]
        .as_slice(),
        _ => &[],
    };
    let plastic = head == "material"
        && (["hardening_modulus", "hardening", "rate"].contains(&k.name)
            || k.table == "material.rate");
    let index = match plastic {
        true => 2,
        false => usize::from(second.contains(&k.name)),
    };
    let table = match root.get_mut(head).unwrap() {
        Value::Array(items) => items[index].as_table_mut().unwrap(),
        other => other.as_table_mut().unwrap(),
    };
    if head == "beam" {
        if k.name == "contact_stiffness" {
            table.insert("contact_law".into(), "line".into());
        }
        if k.name == "restitution_model" {
            table.insert("restitution".into(), 0.5.into());
        }
    }
    if (head == "rod" || head == "ground") && k.name == "restitution_model" {
        table.insert("restitution".into(), 0.5.into());
    }
    match parts.next() {
        None => table,
        Some("layers") => table["layers"].as_array_mut().unwrap()[0]
            .as_table_mut()
            .unwrap(),
        Some("quadrature") => table
            .entry("quadrature")
            .or_insert(Value::Table(toml::Table::new()))
            .as_table_mut()
            .unwrap(),
        Some("segments") => {
            table.remove("elements");
            table.insert(
                "segments".into(),
                Value::Array(vec![Value::Table(toml::toml! { length = 1.0
                elements = 4 })]),
            );
            table["segments"].as_array_mut().unwrap()[0]
                .as_table_mut()
                .unwrap()
        }
        Some("rectangle") => {
            table.remove("layers");
            table.insert(
                "rectangle".into(),
                Value::Table(toml::toml! { material = "steel"
                width = 0.02
                height = 0.02 }),
            );
            table["rectangle"].as_table_mut().unwrap()
        }
        Some("rate") => {
            table.insert(
                "rate".into(),
                Value::Table(toml::toml! { kind = "cowper-symonds"
                d = 40.4
                q = 5.0 }),
            );
            table["rate"].as_table_mut().unwrap()
        }
        Some(other) => panic!("no place for {other}"),
    }
}

fn parse(doc: &Value) -> Result<Scene, ancf_core::SceneError> {
    Scene::from_toml(&toml::to_string(doc).unwrap())
}

fn base() -> Value {
    toml::from_str(BASE).unwrap()
}

#[test]
fn the_base_scene_of_these_tests_is_valid() {
    parse(&base()).expect("base scene");
}

/// Values just outside a declared range, each with what it violates.
fn outside(range: Range) -> Vec<Value> {
    match range {
        Range::Any => vec![],
        Range::Positive => vec![
            Value::Float(0.0),
            Value::Float(-1.0),
            Value::Float(f64::NAN),
        ],
        Range::NonNegative => vec![Value::Float(-1e-9), Value::Float(f64::INFINITY)],
        Range::Interval {
            low,
            low_open,
            high,
            high_open,
        } => {
            let below = if low_open { low } else { low - 1e-9 };
            let above = if high_open { high } else { high + 1e-9 };
            vec![Value::Float(below), Value::Float(above)]
        }
        Range::Count { min, max } => {
            let mut v = Vec::new();
            if max < i64::MAX as u64 {
                v.push(Value::Integer(max as i64 + 1));
            }
            if min > 0 {
                v.push(Value::Integer(min as i64 - 1));
            }
            v
        }
    }
}

/// Values at a declared range's ends and inside, which it accepts.
fn inside(range: Range) -> Vec<Value> {
    match range {
        Range::Interval {
            low,
            low_open,
            high,
            high_open,
        } => {
            let mut v = vec![Value::Float(0.5 * (low + high))];
            if !low_open {
                v.push(Value::Float(low));
            }
            if !high_open {
                v.push(Value::Float(high));
            }
            v
        }
        _ => vec![],
    }
}

#[test]
fn a_value_outside_a_declared_range_is_refused_naming_its_key() {
    let mut problems = Vec::new();
    for k in KEYS.iter().filter(|k| k.range != Range::Any) {
        for v in outside(k.range) {
            let mut doc = base();
            place(&mut doc, k).insert(k.name.into(), v.clone());
            match parse(&doc) {
                Ok(_) => problems.push(format!("{} = {v}: accepted", k.path())),
                Err(e) if !e.field.ends_with(k.name) => problems.push(format!(
                    "{} = {v}: refused as \"{e}\", naming another field",
                    k.path()
                )),
                Err(_) => {}
            }
        }
        for v in inside(k.range) {
            let mut doc = base();
            place(&mut doc, k).insert(k.name.into(), v.clone());
            if let Err(e) = parse(&doc)
                && e.field.ends_with(k.name)
            {
                problems.push(format!(
                    "{} = {v}: inside its range, refused: {e}",
                    k.path()
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A scene as compared: everything but the text it came from.
fn scene_without_source(s: Scene) -> String {
    format!(
        "{:?}",
        Scene {
            source: String::new(),
            ..s
        }
    )
}

#[test]
fn a_declared_default_written_out_gives_the_scene_that_omits_it() {
    let mut checked = 0;
    for k in KEYS {
        let Absent::Literal(literal) = k.default else {
            continue;
        };
        let value: Value = toml::from_str::<toml::Table>(&format!("v = {literal}"))
            .unwrap_or_else(|e| panic!("{}: default {literal} is no TOML value: {e}", k.path()))
            .remove("v")
            .unwrap();
        let mut without = base();
        place(&mut without, k).remove(k.name);
        let mut with = without.clone();
        place(&mut with, k).insert(k.name.into(), value);
        let (a, b) = (parse(&without), parse(&with));
        let (a, b) = (
            a.unwrap_or_else(|e| panic!("{} absent: {e}", k.path())),
            b.unwrap_or_else(|e| panic!("{} = {literal}: {e}", k.path())),
        );
        assert_eq!(
            scene_without_source(a),
            scene_without_source(b),
            "{} = {literal} is not what its absence means",
            k.path()
        );
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} defaults checked");
}

/// The top-level comma-separated parts of `s` (brackets nest).
fn top_level_parts(s: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0i32, 0, Vec::new());
    for (i, c) in s.char_indices() {
        match c {
            '[' | '(' | '<' | '{' => depth += 1,
            ']' | ')' | '>' | '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

/// The text between the parenthesis opening at `open` and its match.
fn parenthesized(s: &str, open: usize) -> Option<&str> {
    let mut depth = 0;
    for (i, c) in s[open..].char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(&s[open + 1..open + i]);
                }
            }
            _ => {}
        }
    }
    None
}

/// The argument names of `def method(` in the stub's `class Class:` (or of
/// `__init__` for `Class(…)`).
fn stub_arguments(stub: &str, class: &str, method: &str) -> Option<BTreeSet<String>> {
    let body = stub.split(&format!("class {class}:")).nth(1)?;
    let body = body.split("\nclass ").next()?;
    let open = body.find(&format!("def {method}("))? + "def (".len() + method.len() - 1;
    Some(
        top_level_parts(parenthesized(body, open)?)
            .into_iter()
            .filter_map(|a| a.split(':').next())
            .map(|a| a.trim().to_string())
            .filter(|a| !a.is_empty() && a != "self")
            .collect(),
    )
}

/// The Python argument names of `fn method(` in the binding's
/// `#[pymethods] impl Class`: the Rust parameters, which PyO3 exposes by
/// name (the receiver and the `Python` token aside).
fn binding_arguments(src: &str, class: &str, method: &str) -> Option<BTreeSet<String>> {
    let body = src
        .split(&format!("#[pymethods]\nimpl {class} {{"))
        .nth(1)?;
    let body = body.split("\n}\n").next()?;
    let open = body.find(&format!("fn {method}("))? + "fn (".len() + method.len() - 1;
    Some(
        top_level_parts(parenthesized(body, open)?)
            .into_iter()
            .filter_map(|a| a.split(':').next())
            .map(|a| a.trim().to_string())
            .filter(|a| !a.is_empty() && !a.contains("self") && a != "py")
            .collect(),
    )
}

#[test]
fn each_declared_python_argument_is_in_the_stub_and_the_binding() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../ancf-python");
    let stub = std::fs::read_to_string(format!("{root}/python/ancf/__init__.pyi")).unwrap();
    let src = std::fs::read_to_string(format!("{root}/src/lib.rs")).unwrap();
    let mut problems = Vec::new();
    let mut checked = 0;
    for k in KEYS {
        for p in k.python {
            let (call, arg) = p.trim_end_matches(')').split_once('(').unwrap();
            let (class, method) = call.split_once('.').unwrap_or((call, "__init__"));
            let rust_method = if method == "__init__" { "new" } else { method };
            match stub_arguments(&stub, class, method) {
                Some(args) if args.contains(arg) => {}
                other => problems.push(format!("{}: {p} not in the stub ({other:?})", k.path())),
            }
            match binding_arguments(&src, class, rust_method) {
                Some(args) if args.contains(arg) => {}
                other => problems.push(format!(
                    "{}: {p} not in the binding's signature ({other:?})",
                    k.path()
                )),
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} Python arguments checked");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn choices_are_refused_outside_their_list_naming_the_key() {
    for k in KEYS {
        let KeyType::Choice(names) = k.ty else {
            continue;
        };
        assert!(!names.is_empty());
        let mut doc = base();
        place(&mut doc, k).insert(k.name.into(), "no-such-choice".into());
        let e = parse(&doc).expect_err(k.name);
        assert!(
            e.field.ends_with(k.name) || e.message.contains(k.name),
            "{}: refused as \"{e}\"",
            k.path()
        );
    }
}
