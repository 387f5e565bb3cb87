//! The core's stages import one another in one direction only: no top-level
//! module of `ancf_core` (math, material, section, element, model, forces,
//! linalg, solve, loads, scene, error) imports a module that imports it back,
//! directly or through others. A stage's own unit tests (`#[cfg(test)]`,
//! the end of a file) may use a later stage to build their fixtures; they
//! are not part of the graph.
//!
//! The edges are read from the source: every `crate::NAME` path outside
//! comments and test modules, including grouped imports `crate::{a, b}`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file below `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source folder") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules that `code` names through `crate::`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name = ident(item.trim());
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            let name = ident(rest);
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

/// The code of a file without comments and without its test module.
fn code_of(text: &str) -> String {
    let mut code = String::new();
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("#[cfg(test)]") {
            break;
        }
        if t.starts_with("//") {
            continue;
        }
        let line = line.split(" // ").next().unwrap_or(line);
        code.push_str(line);
        code.push('\n');
    }
    code
}

/// Top-level module → the top-level modules it imports. `simd_dispatch!`
/// and `prelude` are defined at the crate root for `math` and `lib`.
fn module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let rel = file.strip_prefix(&root).expect("below src");
        let first = rel.components().next().expect("a path");
        let top = first
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if top == "lib" {
            continue;
        }
        let text = std::fs::read_to_string(&file).expect("readable source");
        let targets = graph.entry(top.clone()).or_default();
        for name in crate_paths(&code_of(&text)) {
            let name = match name.as_str() {
                "simd_dispatch" => "math".to_string(),
                "Error" => "error".to_string(),
                "prelude" => "lib".to_string(),
                _ => name,
            };
            if name != top {
                targets.insert(name);
            }
        }
    }
    graph
}

/// A cycle through `graph`, if any (depth-first search).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_string(), 1);
        stack.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            match state.get(next.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|n| n == next).expect("on stack");
                    let mut cycle = stack[start..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(next, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(node.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        if state.get(node.as_str()).copied().unwrap_or(0) == 0 {
            let mut stack = Vec::new();
            if let Some(c) = visit(node, graph, &mut state, &mut stack) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn the_reader_finds_grouped_and_plain_paths() {
    let code = code_of(
        "use crate::model::Model;\n// crate::solve in a comment\nuse crate::{forces::sum, linalg};\nfn f() { crate::math::vec3::dot(a, b) }\n#[cfg(test)]\nmod tests { use crate::scene; }\n",
    );
    let names: Vec<String> = crate_paths(&code).into_iter().collect();
    assert_eq!(names, ["forces", "linalg", "math", "model"]);
    let mut cyclic = BTreeMap::new();
    cyclic.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    cyclic.insert("b".to_string(), BTreeSet::from(["a".to_string()]));
    assert!(find_cycle(&cyclic).is_some());
}

#[test]
fn the_core_module_graph_has_no_cycle() {
    let graph = module_graph();
    assert!(graph.contains_key("model") && graph.contains_key("forces"));
    if let Some(cycle) = find_cycle(&graph) {
        panic!(
            "the modules import each other in a cycle: {}\nwhole graph: {graph:#?}",
            cycle.join(" → ")
        );
    }
    // The stages in an order where each imports only earlier ones: the
    // model describes, forces evaluate into linalg's containers, solvers
    // drive both, loads reduce what they return, plausibility judges
    // constants and strains, a scene maps a file onto the model and the
    // settings.
    let order = [
        "math",
        "check",
        "linalg",
        "material",
        "section",
        "element",
        "model",
        "forces",
        "loads",
        "solve",
        "plausibility",
        "scene",
        "error",
    ];
    let rank = |m: &str| order.iter().position(|o| *o == m);
    for (module, imports) in &graph {
        let at =
            rank(module).unwrap_or_else(|| panic!("module {module} has no place in the order"));
        for import in imports {
            let to = rank(import).unwrap_or_else(|| panic!("{module} imports unknown {import}"));
            assert!(to < at, "{module} imports {import}, a later stage");
        }
    }
}
