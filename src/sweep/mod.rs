//! `ancf sweep`: many variants of one scene ([`mod@file`]), run on this
//! machine's cores ([`local`]) or as a Slurm job array ([`slurm`]), gathered
//! into one table of design numbers ([`results`]).
//!
//! Every variant is an ordinary run in `DIR/runs/<id>/` (its scene as
//! `scene.toml`, then the run's own outputs and checkpoints), so that the
//! executors share nothing but the folder. A variant whose summary says
//! `completed` is done; one with a `checkpoint.json` is resumed from it;
//! any other starts over. Rerunning the same command therefore does only
//! what is missing.

pub mod file;
pub mod local;
pub mod quantiles;
pub mod results;
pub mod slurm;

use file::{Mode, Sweep};
use std::path::{Path, PathBuf};

/// Where the variants run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Executor {
    /// Child processes on this machine, `jobs` at a time.
    Local,
    /// One Slurm job array, one task per variant.
    Slurm,
}

/// Options of `ancf sweep`.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    pub out: PathBuf,
    pub executor: Executor,
    /// Local: variants at a time (default: the cores).
    pub jobs: usize,
    /// Slurm: submit and return without following the tasks.
    pub submit_only: bool,
    /// Slurm: `time`, `mem` and `max_parallel` given on the command line,
    /// over the sweep file's `[slurm]`.
    pub slurm: file::SlurmSpec,
    pub quiet: bool,
    /// Refuse variants with warnings before any runs (`--strict`).
    pub strict: bool,
    /// Cancelled (Ctrl-C, SIGTERM): local variants are stopped with a
    /// checkpoint, a Slurm job is no longer followed.
    pub cancel: ancf_core::solve::cancel::CancelToken,
}

/// `DIR/sweep.json`: what the folder holds, for reruns and `--collect`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    pub scene: PathBuf,
    pub mode: Mode,
    /// [`file::Sweep::ensemble`] (absent in a folder written before it
    /// existed: a grid).
    #[serde(default)]
    pub ensemble: bool,
    pub parameters: Vec<String>,
    /// (id, the values as the sweep file writes them).
    pub variants: Vec<(String, Vec<String>)>,
}

impl Manifest {
    fn of(sweep: &Sweep) -> Manifest {
        Manifest {
            scene: sweep.scene.clone(),
            mode: sweep.mode,
            ensemble: sweep.ensemble,
            parameters: sweep.parameters.clone(),
            variants: sweep
                .variants
                .iter()
                .map(|v| {
                    (
                        v.id.clone(),
                        v.values.iter().map(file::value_text).collect(),
                    )
                })
                .collect(),
        }
    }

    pub fn read(dir: &Path) -> Result<Manifest, String> {
        let path = dir.join("sweep.json");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "{}: {e} (is {} a sweep's output folder?)",
                path.display(),
                dir.display()
            )
        })?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// What the folder knows about one variant's run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RunState {
    /// summary.json says completed.
    Completed,
    /// Not completed, but a checkpoint to resume from.
    Resumable,
    /// Nothing usable: run from the start.
    Fresh,
}

/// The folder of variant `id`.
pub fn run_dir(out: &Path, id: &str) -> PathBuf {
    out.join("runs").join(id)
}

/// The state of variant `id`'s run in `out`.
pub fn run_state(out: &Path, id: &str) -> RunState {
    let dir = run_dir(out, id);
    let completed = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|s| s["status"] == "completed");
    if completed {
        RunState::Completed
    } else if dir.join("checkpoint.json").exists() {
        RunState::Resumable
    } else {
        RunState::Fresh
    }
}

/// Prepares `out` for `sweep`: writes sweep.json and each variant's
/// scene.toml, or, when `out` already holds this sweep, keeps everything.
/// A folder holding the same base scene and parameters with other values
/// is extended: a variant whose values it already holds keeps its id and
/// run (its scene must be the one the folder holds), new values get new
/// ids after the last, and completed variants the sweep no longer names
/// stay in the results. A folder holding another sweep is refused
/// (nothing is overwritten).
pub fn prepare(sweep: &mut Sweep, out: &Path) -> Result<(), String> {
    let mut manifest = Manifest::of(sweep);
    if out.join("sweep.json").exists() {
        let old = Manifest::read(out)?;
        if old != manifest {
            if old.scene != manifest.scene || old.parameters != manifest.parameters {
                return Err(format!(
                    "{} holds another sweep (its base scene or parameters differ); \
                     choose another --out or remove it",
                    out.display()
                ));
            }
            manifest = extend(&old, sweep, out)?;
        }
    }
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    std::fs::create_dir_all(out.join("runs")).map_err(io)?;
    for v in &sweep.variants {
        let dir = run_dir(out, &v.id);
        std::fs::create_dir_all(&dir).map_err(io)?;
        let path = dir.join("scene.toml");
        if std::fs::read_to_string(&path).ok().as_deref() != Some(v.scene_text.as_str()) {
            std::fs::write(&path, &v.scene_text).map_err(io)?;
        }
    }
    let text = serde_json::to_string_pretty(&manifest).expect("manifest serializes");
    std::fs::write(out.join("sweep.json"), text + "\n").map_err(io)
}

/// `sweep` over the folder `out` that holds `old` (same scene and
/// parameters): `sweep`'s variants take the ids of the old ones with their
/// values, new ones the ids after the last; the manifest of both.
fn extend(old: &Manifest, sweep: &mut Sweep, out: &Path) -> Result<Manifest, String> {
    let next = old
        .variants
        .iter()
        .filter_map(|(id, _)| id.strip_prefix('v')?.parse::<usize>().ok())
        .max()
        .map_or(0, |n| n + 1);
    let total = next + sweep.variants.len();
    let width = total.saturating_sub(1).to_string().len().max(3);
    let mut fresh = next;
    let mut ids = Vec::new();
    for v in &sweep.variants {
        let values: Vec<String> = v.values.iter().map(file::value_text).collect();
        match old.variants.iter().find(|(_, vals)| *vals == values) {
            Some((id, _)) => {
                let held = std::fs::read_to_string(run_dir(out, id).join("scene.toml")).ok();
                if held.as_deref().is_some_and(|t| t != v.scene_text) {
                    return Err(format!(
                        "{}: variant {id} ({}) holds another scene than this sweep makes for \
                         those values (the base scene changed); choose another --out",
                        out.display(),
                        values.join(", ")
                    ));
                }
                ids.push(id.clone());
            }
            None => {
                ids.push(format!("v{fresh:0width$}"));
                fresh += 1;
            }
        }
    }
    for (v, id) in sweep.variants.iter_mut().zip(ids) {
        v.id = id;
    }
    let mut manifest = Manifest::of(sweep);
    // Completed variants of the folder that this sweep no longer names.
    let kept: Vec<(String, Vec<String>)> = (old.variants.iter())
        .filter(|(id, _)| !manifest.variants.iter().any(|(n, _)| n == id))
        .filter(|(id, _)| run_state(out, id) == RunState::Completed)
        .cloned()
        .collect();
    manifest.variants.splice(0..0, kept);
    let number = |id: &str| {
        id.trim_start_matches('v')
            .parse::<usize>()
            .unwrap_or(usize::MAX)
    };
    manifest.variants.sort_by_key(|(id, _)| number(id));
    Ok(manifest)
}

/// The command line that runs (or resumes) variant `id` with this `ancf`.
pub fn run_command(out: &Path, id: &str) -> Vec<String> {
    let dir = run_dir(out, id);
    let dir_s = dir.display().to_string();
    match run_state(out, id) {
        RunState::Resumable => vec!["run".into(), "--resume".into(), dir_s, "--quiet".into()],
        _ => vec![
            "run".into(),
            dir.join("scene.toml").display().to_string(),
            "--out".into(),
            dir_s,
            "--quiet".into(),
        ],
    }
}

/// How a sweep ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SweepEnd {
    /// Every variant completed; `warned` of them with warnings or many
    /// step cuts.
    Completed { warned: usize },
    /// `--strict`: some variants have warnings; nothing was run.
    Refused { warned: usize },
    /// Some variants failed or are missing (their status is in results.csv).
    Incomplete { failed: usize, missing: usize },
    /// Ctrl-C: finished runs kept, interrupted ones checkpointed.
    Interrupted,
    /// Slurm, `--submit-only`: submitted, not followed.
    Submitted { job: String, tasks: usize },
}

/// `ancf sweep SWEEP.toml`: checks every variant, runs what is missing and
/// writes results.csv and report.md.
pub fn run(sweep_path: &Path, opts: &SweepOptions) -> Result<SweepEnd, String> {
    let mut sweep = file::load(sweep_path).map_err(|e| e.to_string())?;
    // One sweep in a folder at a time (each variant's run locks its own).
    let _lock = ancf_output::lock::OutputLock::acquire(&opts.out)?;
    prepare(&mut sweep, &opts.out)?;
    let out = std::path::absolute(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    let todo: Vec<String> = sweep
        .variants
        .iter()
        .filter(|v| run_state(&out, &v.id) != RunState::Completed)
        .map(|v| v.id.clone())
        .collect();
    if !opts.quiet {
        eprintln!(
            "ancf sweep: {} variants ({} done already), {} executor",
            sweep.variants.len(),
            sweep.variants.len() - todo.len(),
            match opts.executor {
                Executor::Local => "local",
                Executor::Slurm => "slurm",
            }
        );
    }
    // Before the work starts, whether quiet or not.
    let mut warned = 0;
    for v in sweep.variants.iter().filter(|v| todo.contains(&v.id)) {
        for w in &v.warnings {
            eprintln!("warning: {}: {w}", v.id);
        }
        warned += usize::from(!v.warnings.is_empty());
    }
    if opts.strict && warned > 0 {
        return Ok(SweepEnd::Refused { warned });
    }
    let interrupted = match opts.executor {
        Executor::Local => local::run(&out, &todo, opts.jobs, opts.quiet, &opts.cancel)?,
        Executor::Slurm => {
            let o = &opts.slurm;
            let spec = file::SlurmSpec {
                time: o.time.clone().or(sweep.slurm.time.clone()),
                mem: o.mem.clone().or(sweep.slurm.mem.clone()),
                max_parallel: o.max_parallel.or(sweep.slurm.max_parallel),
                ..sweep.slurm.clone()
            };
            match slurm::run(
                &out,
                &todo,
                &spec,
                opts.submit_only,
                opts.quiet,
                &opts.cancel,
            )? {
                slurm::Outcome::Submitted { job } => {
                    return Ok(SweepEnd::Submitted {
                        job,
                        tasks: todo.len(),
                    });
                }
                slurm::Outcome::Finished => false,
            }
        }
    };
    let end = results::collect(&out)?;
    Ok(if interrupted {
        SweepEnd::Interrupted
    } else {
        end
    })
}
