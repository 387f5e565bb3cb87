//! The sweep file (docs/sweep.md): a base scene, the parameters to vary as
//! dotted scene paths with a list of values each, combined as a full grid
//! or zipped; and the variants it expands to, each a complete scene checked
//! by the same validation as `ancf check` before anything runs.

use ancf_core::scene::Scene;
use std::path::{Path, PathBuf};

/// How the parameters' value lists combine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Every combination (the last parameter varies fastest).
    Grid,
    /// The k-th values of every list together (equal lengths).
    Zip,
}

/// `[slurm]`: what each array task asks the scheduler for.
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct SlurmSpec {
    /// Wall-time limit per task, Slurm's format (e.g. "00:30:00").
    pub time: Option<String>,
    /// Memory per task (e.g. "2G").
    pub mem: Option<String>,
    /// Tasks running at once (`%N` of `--array`: Slurm's array throttle).
    #[serde(alias = "limit")]
    pub max_parallel: Option<usize>,
    /// Partition (`--partition`).
    pub partition: Option<String>,
    /// Further `#SBATCH` lines, verbatim (e.g. "--account=myproject").
    pub options: Option<Vec<String>>,
}

impl SlurmSpec {
    /// Whether each value can go into the job script as it is: one line
    /// each (a newline would start a shell command of its own), and
    /// `time`, `mem` and `partition` of the characters Slurm's values use.
    pub fn check(&self) -> Result<(), String> {
        let plain = |field: &str, v: &Option<String>| match v {
            Some(v)
                if v.is_empty()
                    || !v
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "_-:.,+".contains(c)) =>
            {
                Err(format!(
                    "slurm.{field}: \"{}\" is not a Slurm value (letters, digits and _-:.,+ only)",
                    v.escape_debug()
                ))
            }
            _ => Ok(()),
        };
        plain("time", &self.time)?;
        plain("mem", &self.mem)?;
        plain("partition", &self.partition)?;
        for (i, o) in self.options.iter().flatten().enumerate() {
            if o.chars().any(char::is_control) {
                return Err(format!(
                    "slurm.options[{i}]: \"{}\" holds a control character; each option is one #SBATCH line",
                    o.escape_debug()
                ));
            }
        }
        Ok(())
    }
}

#[derive(Clone, Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepSpec {
    scene: PathBuf,
    mode: Option<Mode>,
    ensemble: Option<bool>,
    parameters: toml::Table,
    slurm: Option<SlurmSpec>,
}

/// A checked sweep: the base scene, the parameters (in the file's order) and
/// every variant's scene text.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The base scene file, resolved against the sweep file's folder.
    pub scene: PathBuf,
    pub mode: Mode,
    /// Whether the variants sample what is not known (a sag, a length
    /// within its tolerance; `ensemble = true`): only then does the report
    /// give quantiles with their confidence intervals. A grid over chosen
    /// values is no sample, and gets its extremes and where they are.
    pub ensemble: bool,
    /// Parameter paths, in the order of the columns of results.csv.
    pub parameters: Vec<String>,
    pub variants: Vec<Variant>,
    pub slurm: SlurmSpec,
}

/// One combination of parameter values.
#[derive(Clone, Debug)]
pub struct Variant {
    /// `v000`, `v001`, … in expansion order.
    pub id: String,
    /// One value per parameter, in [`Sweep::parameters`] order.
    pub values: Vec<toml::Value>,
    /// The complete scene file of this variant.
    pub scene_text: String,
    /// What its scene will likely do badly ([`Scene::warnings`]): said
    /// before the sweep runs.
    pub warnings: Vec<String>,
}

/// The most variants one sweep takes: each is a folder with a scene, a
/// run and its outputs.
pub const MAX_VARIANTS: usize = 100_000;

/// A sweep-file error, naming where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepError(pub String);

impl std::fmt::Display for SweepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SweepError {}

fn err<T>(msg: impl Into<String>) -> Result<T, SweepError> {
    Err(SweepError(msg.into()))
}

/// A value as the sweep file writes it (results.csv, report.md).
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(value_text).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// The scene paths of a parameter name: one, or several joined by `&`
/// that change together (`"wire.length & support[1].position"`, each value
/// a list with one entry per path).
fn linked_paths(name: &str) -> Vec<&str> {
    name.split('&').map(str::trim).collect()
}

/// One step of a dotted scene path: a key or an index into an array of tables.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// `rod[1].center` → Key(rod), Index(1), Key(center).
fn parse_path(path: &str) -> Result<Vec<Step>, String> {
    let mut steps = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("'{part}' is not a scene key (letters, digits, _)"));
        }
        steps.push(Step::Key(key.to_string()));
        while !rest.is_empty() {
            let close = rest
                .find(']')
                .ok_or_else(|| format!("'{part}': missing ']'"))?;
            let index = rest[1..close]
                .parse::<usize>()
                .map_err(|_| format!("'{part}': the index must be a whole number ≥ 0"))?;
            steps.push(Step::Index(index));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(format!("'{part}': unexpected '{rest}'"));
            }
        }
    }
    Ok(steps)
}

/// Sets `path` in the scene `table` to `value`; missing tables and the
/// last key are created (validation then decides whether the key exists in
/// the schema), array indices must exist.
fn set_path(table: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), String> {
    let steps = parse_path(path)?;
    let mut here = toml::Value::Table(std::mem::take(table));
    let result = set_in(&mut here, &steps, value, path);
    if let toml::Value::Table(t) = here {
        *table = t;
    }
    result
}

fn set_in(
    at: &mut toml::Value,
    steps: &[Step],
    value: toml::Value,
    path: &str,
) -> Result<(), String> {
    let Some((step, rest)) = steps.split_first() else {
        *at = value;
        return Ok(());
    };
    match step {
        Step::Key(k) => {
            let toml::Value::Table(t) = at else {
                return Err(format!(
                    "{path}: '{k}' is inside a value that is not a table"
                ));
            };
            if !t.contains_key(k) && matches!(rest.first(), Some(Step::Index(_))) {
                return Err(format!(
                    "{path}: the scene has no [[{k}]] table (add one to the scene, or drop this parameter)"
                ));
            }
            let next = t.entry(k.clone()).or_insert_with(|| {
                if rest.is_empty() {
                    toml::Value::Boolean(false)
                } else {
                    toml::Value::Table(toml::Table::new())
                }
            });
            set_in(next, rest, value, path)
        }
        Step::Index(i) => {
            let toml::Value::Array(a) = at else {
                return Err(format!("{path}: [{i}] indexes a value that is not a list"));
            };
            let n = a.len();
            let Some(next) = a.get_mut(*i) else {
                return Err(format!("{path}: index {i} is past the scene's {n} entries"));
            };
            set_in(next, rest, value, path)
        }
    }
}

/// Reads and checks a sweep file: every variant is a valid scene, or the
/// sweep is refused naming the variant, its values and the field.
pub fn load(path: &Path) -> Result<Sweep, SweepError> {
    let text = ancf_core::scene::read_scene_text(path).map_err(|e| SweepError(e.message))?;
    let spec: SweepSpec = toml::from_str(&text).map_err(|e| located(path, &text, &e))?;
    if spec
        .slurm
        .as_ref()
        .is_some_and(|s| s.max_parallel == Some(0))
    {
        return err(format!(
            "{}: slurm.max_parallel: must be at least 1",
            path.display()
        ));
    }
    if let Some(slurm) = &spec.slurm {
        slurm
            .check()
            .map_err(|e| SweepError(format!("{}: {e}", path.display())))?;
    }
    let folder = path.parent().unwrap_or(Path::new("."));
    let scene = folder.join(&spec.scene);
    let scene = std::fs::canonicalize(&scene).unwrap_or(scene);
    let base_text = ancf_core::scene::read_scene_text(&scene).map_err(|e| {
        SweepError(format!(
            "scene = \"{}\": {}",
            spec.scene.display(),
            e.message
        ))
    })?;
    let base: toml::Table =
        toml::from_str(&base_text).map_err(|e| located(&scene, &base_text, &e))?;
    let sweep = expand(
        scene,
        base,
        spec.mode.unwrap_or(Mode::Grid),
        &spec.parameters,
        spec.slurm.unwrap_or_default(),
    )
    .map_err(|e| match parameter_line(&text, &e.0) {
        Some(line) => SweepError(format!("{}:{line}: {}", path.display(), e.0)),
        None => SweepError(format!("{}: {}", path.display(), e.0)),
    })?;
    Ok(Sweep {
        ensemble: spec.ensemble.unwrap_or(false),
        ..sweep
    })
}

/// A TOML error of `text` (the file `path`) as `path:line: field: message`.
fn located(path: &Path, text: &str, e: &toml::de::Error) -> SweepError {
    match e.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            let field = ancf_core::scene::error_field(text, e);
            let field = if field.is_empty() {
                String::new()
            } else {
                format!("{field}: ")
            };
            SweepError(format!("{}:{line}: {field}{}", path.display(), e.message()))
        }
        None => SweepError(format!("{}: {}", path.display(), e.message())),
    }
}

/// The line (from 1) of the sweep file where the parameter an error
/// names (`parameters."NAME": …`) is given.
fn parameter_line(text: &str, message: &str) -> Option<usize> {
    let name = message.strip_prefix("parameters.\"")?.split("\":").next()?;
    let quoted = format!("\"{name}\"");
    text.lines()
        .position(|l| l.trim_start().starts_with(&quoted))
        .map(|i| i + 1)
}

/// The variants of `parameters` (name → list of values) over `base`.
pub fn expand(
    scene: PathBuf,
    base: toml::Table,
    mode: Mode,
    parameters: &toml::Table,
    slurm: SlurmSpec,
) -> Result<Sweep, SweepError> {
    if parameters.is_empty() {
        return err(
            "[parameters]: name at least one scene path to vary, e.g. \"wire.length\" = [40.0, 50.0]",
        );
    }
    let mut names = Vec::new();
    let mut lists = Vec::new();
    // Each scene path once over all parameters (trimmed: " wire.elements "
    // is wire.elements): a second setting would silently win.
    let mut seen: Vec<(String, &str)> = Vec::new();
    for (name, values) in parameters {
        for path in linked_paths(name) {
            parse_path(path).map_err(|e| SweepError(format!("parameters.\"{name}\": {e}")))?;
            if let Some((_, other)) = seen.iter().find(|(p, _)| p == path) {
                return err(if other == name {
                    format!("parameters.\"{name}\": the scene path '{path}' is named twice")
                } else {
                    format!(
                        "parameters.\"{name}\": the scene path '{path}' is also set by \
                         parameters.\"{other}\"; name each path once"
                    )
                });
            }
            seen.push((path.to_string(), name));
        }
        let toml::Value::Array(values) = values else {
            return err(format!(
                "parameters.\"{name}\": a list of values, e.g. [1.0, 2.0]"
            ));
        };
        if values.is_empty() {
            return err(format!(
                "parameters.\"{name}\": the list of values is empty"
            ));
        }
        let k = linked_paths(name).len();
        if k > 1
            && let Some(bad) = values
                .iter()
                .find(|v| v.as_array().is_none_or(|a| a.len() != k))
        {
            return err(format!(
                "parameters.\"{name}\": {k} linked paths take lists of {k} values each, got {}",
                value_text(bad)
            ));
        }
        names.push(name.clone());
        lists.push(values.clone());
    }
    // Refused before anything is built: a grid of 10⁶ variants took
    // gigabytes and minutes to check, then wrote a folder per variant.
    let count = match mode {
        Mode::Zip => lists[0].len(),
        Mode::Grid => lists.iter().fold(1usize, |n, l| n.saturating_mul(l.len())),
    };
    if count > MAX_VARIANTS {
        return err(format!(
            "[parameters]: {count} variants, more than a sweep takes ({MAX_VARIANTS}); split it \
             into several sweeps"
        ));
    }
    let combos: Vec<Vec<usize>> = match mode {
        Mode::Zip => {
            let n = lists[0].len();
            if let Some(k) = lists.iter().position(|l| l.len() != n) {
                return err(format!(
                    "mode = \"zip\" needs lists of equal length: \"{}\" has {n} values, \"{}\" {}",
                    names[0],
                    names[k],
                    lists[k].len()
                ));
            }
            (0..n).map(|i| vec![i; lists.len()]).collect()
        }
        Mode::Grid => {
            let mut combos = vec![Vec::new()];
            for l in &lists {
                combos = combos
                    .into_iter()
                    .flat_map(|c| {
                        (0..l.len()).map(move |i| {
                            let mut c = c.clone();
                            c.push(i);
                            c
                        })
                    })
                    .collect();
            }
            combos
        }
    };
    let width = combos.len().saturating_sub(1).to_string().len().max(3);
    let mut variants = Vec::new();
    for (k, combo) in combos.iter().enumerate() {
        let id = format!("v{k:0width$}");
        let values: Vec<toml::Value> = combo
            .iter()
            .zip(&lists)
            .map(|(&i, l)| l[i].clone())
            .collect();
        let describe = || {
            let parts: Vec<String> = names
                .iter()
                .zip(&values)
                .map(|(n, v)| format!("{n} = {}", value_text(v)))
                .collect();
            format!("variant {id} ({})", parts.join(", "))
        };
        let mut table = base.clone();
        // A sweep is for its numbers: no ParaView frames (hundreds of
        // variants would write GB) unless a parameter asks for them.
        set_path(&mut table, "output.vtk", toml::Value::Boolean(false))
            .map_err(|e| SweepError(format!("{}: {e}", describe())))?;
        for (name, value) in names.iter().zip(&values) {
            let paths = linked_paths(name);
            let parts = match value {
                toml::Value::Array(a) if paths.len() > 1 => a.clone(),
                v => vec![v.clone()],
            };
            for (path, part) in paths.iter().zip(parts) {
                set_path(&mut table, path, part)
                    .map_err(|e| SweepError(format!("parameters.\"{name}\": {e}")))?;
            }
        }
        let scene_text =
            toml::to_string(&table).map_err(|e| SweepError(format!("{}: {e}", describe())))?;
        let scene = Scene::from_toml(&scene_text).map_err(|e| {
            // The parameter that set the field at fault, when one did; the
            // complaint without the generated text's line.
            let culprit = names.iter().zip(&values).find(|(n, _)| {
                linked_paths(n).iter().any(|p| {
                    !e.field.is_empty() && (e.field.starts_with(p) || p.starts_with(&e.field))
                })
            });
            let complaint = e.message.lines().last().unwrap_or("").trim();
            let field = if e.field.is_empty() {
                String::new()
            } else {
                format!("{}: ", e.field)
            };
            match culprit {
                Some((n, v)) => SweepError(format!(
                    "parameters.\"{n}\": the value {} makes {} an invalid scene: {field}{complaint}",
                    value_text(v),
                    describe()
                )),
                None => SweepError(format!("{}: {field}{complaint}", describe())),
            }
        })?;
        variants.push(Variant {
            id,
            values,
            scene_text,
            warnings: scene.warnings(),
        });
    }
    Ok(Sweep {
        scene,
        mode,
        ensemble: false,
        parameters: names,
        variants,
        slurm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> toml::Table {
        toml::from_str(
            r#"
            [analysis]
            kind = "dynamic"
            end_time = 0.01
            time_step = 1e-3
            [[material]]
            name = "m"
            model = "st-venant-kirchhoff"
            density = 7000.0
            youngs_modulus = 2e9
            [wire]
            length = 1.0
            elements = 2
            layers = [ { material = "m", outer_radius = 0.01 } ]
            [[support]]
            node = 0
            kind = "pin"
            [[rod]]
            center = [0.5, 0.0, -0.3]
            axis = [0.0, 1.0, 0.0]
            radius = 0.02
            contact_law = "line"
            contact_stiffness = 1e7
            "#,
        )
        .unwrap()
    }

    fn params(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    /// `expand` over the test scene with the parameters of `text`.
    fn sweep(mode: Mode, text: &str) -> Result<Sweep, SweepError> {
        expand(
            "s.toml".into(),
            base(),
            mode,
            &params(text),
            SlurmSpec::default(),
        )
    }

    /// A key missing from the sweep file is named, at the file or in its
    /// table.
    #[test]
    fn a_missing_key_is_named() {
        let message = |text: &str| {
            let e = toml::from_str::<SweepSpec>(text).unwrap_err();
            located(Path::new("s.toml"), text, &e).0
        };
        let no_scene = message("mode = \"grid\"\n[parameters]\n\"wire.length\" = [1.0]\n");
        assert!(no_scene.starts_with("s.toml:1: scene: "), "{no_scene}");
        let no_parameters = message("scene = \"a.toml\"\n");
        assert!(
            no_parameters.starts_with("s.toml:1: parameters: "),
            "{no_parameters}"
        );
    }

    #[test]
    fn paths_parse_keys_and_indices() {
        assert_eq!(
            parse_path("rod[1].center").unwrap(),
            vec![
                Step::Key("rod".into()),
                Step::Index(1),
                Step::Key("center".into())
            ]
        );
        assert!(parse_path("rod[x].center").is_err());
        assert!(parse_path("wire..length").is_err());
        assert!(parse_path("rod[1").is_err());
    }

    #[test]
    fn grid_and_zip_expand_in_order() {
        let grid = sweep(
            Mode::Grid,
            "\"wire.length\" = [1.0, 2.0]\n\"rod[0].center\" = [[0.5, 0.0, -0.3], [0.6, 0.0, -0.3], [0.7, 0.0, -0.3]]",
        )
        .unwrap();
        assert_eq!(grid.variants.len(), 6);
        // The file's order; the last parameter varies fastest.
        assert_eq!(grid.parameters, vec!["wire.length", "rod[0].center"]);
        assert_eq!(value_text(&grid.variants[1].values[1]), "[0.6, 0.0, -0.3]");
        assert_eq!(value_text(&grid.variants[3].values[0]), "2.0");
        let scene = Scene::from_toml(&grid.variants[5].scene_text).unwrap();
        assert_eq!(scene.model.n_elements, 2);
        assert!(
            (scene.model.element(0).length - 1.0).abs() < 1e-12,
            "wire.length = 2 over 2 elements"
        );
        let zip = sweep(
            Mode::Zip,
            "\"wire.length\" = [1.0, 2.0]\n\"wire.elements\" = [2, 4]",
        )
        .unwrap();
        assert_eq!(zip.variants.len(), 2);
        assert_eq!(zip.variants[1].id, "v001");
        let mismatched = sweep(
            Mode::Zip,
            "\"wire.length\" = [1.0, 2.0]\n\"wire.elements\" = [2]",
        );
        assert!(mismatched.unwrap_err().0.contains("equal length"));
    }

    /// A grid beyond [`MAX_VARIANTS`] is refused before it is built.
    #[test]
    fn a_sweep_has_at_most_max_variants() {
        let base: toml::Table = toml::from_str("[wire]\nlength = 1.0\nelements = 2\n").unwrap();
        let many: Vec<String> = (0..1000).map(|i| format!("{}.0", i + 1)).collect();
        let list = format!("[{}]", many.join(", "));
        let parameters: toml::Table = toml::from_str(&format!(
            "\"wire.length\" = {list}\n\"wire.origin[0]\" = {list}"
        ))
        .unwrap();
        let e = expand(
            PathBuf::from("s.toml"),
            base,
            Mode::Grid,
            &parameters,
            SlurmSpec::default(),
        )
        .expect_err("10^6 variants");
        assert!(e.0.contains("1000000 variants"), "{}", e.0);
    }

    /// A path named twice, within one parameter or across two (spaces
    /// aside), is refused: one of the settings would silently win.
    #[test]
    fn a_scene_path_is_set_by_one_parameter_only() {
        let base: toml::Table = toml::from_str("[wire]\nlength = 1.0\nelements = 2\n").unwrap();
        for params in [
            "\"wire.elements\" = [2]\n\" wire.elements \" = [4]",
            "\"wire.length & wire.length\" = [[1.0, 2.0]]",
        ] {
            let parameters: toml::Table = toml::from_str(params).unwrap();
            let e = expand(
                PathBuf::from("s.toml"),
                base.clone(),
                Mode::Grid,
                &parameters,
                SlurmSpec::default(),
            )
            .expect_err(params);
            assert!(e.0.contains("wire."), "{params}: {}", e.0);
        }
    }

    #[test]
    fn linked_paths_change_together() {
        let linked = sweep(
            Mode::Grid,
            "\"wire.length & wire.elements\" = [[1.0, 2], [2.0, 4]]\n\"rod[0].radius\" = [0.02, 0.03]",
        )
        .unwrap();
        assert_eq!(linked.variants.len(), 4);
        let last = Scene::from_toml(&linked.variants[3].scene_text).unwrap();
        assert_eq!(last.model.n_elements, 4);
        assert!((last.model.element(0).length - 0.5).abs() < 1e-12);
        let e = sweep(
            Mode::Grid,
            "\"wire.length & wire.elements\" = [[1.0, 2], [2.0]]",
        )
        .unwrap_err();
        assert!(e.0.contains("2 linked paths take lists of 2 values"), "{e}");
    }

    /// One bad variant refuses the whole sweep, naming it, its values and the field.
    #[test]
    fn a_bad_variant_is_named_with_its_field() {
        let e = sweep(Mode::Grid, "\"wire.length\" = [1.0, -2.0]").unwrap_err();
        assert!(
            e.0.contains("variant v001 (wire.length = -2.0)") && e.0.contains("wire.length"),
            "{e}"
        );
        let e = sweep(Mode::Grid, "\"wire.lenght\" = [1.0]").unwrap_err();
        assert!(e.0.contains("lenght"), "{e}");
        let e = sweep(Mode::Grid, "\"rod[3].radius\" = [0.1]").unwrap_err();
        assert!(e.0.contains("index 3 is past the scene's 1 entries"), "{e}");
        let e = sweep(Mode::Grid, "\"wire.length\" = 1.0").unwrap_err();
        assert!(e.0.contains("a list of values"), "{e}");
        let e = sweep(Mode::Grid, "\"rod[0].contact_stiffness\" = [\"stiff\"]").unwrap_err();
        assert!(
            e.0.contains("rod[0].contact_stiffness") || e.0.contains("contact_stiffness"),
            "{e}"
        );
    }
}
