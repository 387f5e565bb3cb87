//! `ancf`: run, check and inspect ANCF wire simulations.

use ancf::run::{RunOptions, run_scene};
use ancf_core::math::quadrature::ring_rule;
use ancf_core::math::simd::SimdPath;
use ancf_core::scene::Scene;
use ancf_core::solve::cancel::CancelToken;
use clap::{CommandFactory, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "ancf",
    version = ancf::build_info::version_line(),
    about = "ANCF beam simulator for electrical wires and cables"
)]
struct Cli {
    /// Instruction set of the hot loops: auto (the fastest this CPU has),
    /// baseline, avx2 or avx512. Results agree to round-off across paths.
    #[arg(long, global = true, value_enum, default_value = "auto")]
    simd: SimdChoice,
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SimdChoice {
    Auto,
    Baseline,
    Avx2,
    Avx512,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Csv,
    Table,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write its outputs (summary.json, timeseries.csv, plots) into --out.
    Run {
        /// The scene file (not needed with --resume).
        #[arg(required_unless_present = "resume")]
        scene: Option<PathBuf>,
        /// Output directory (default: out/<the scene file's name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Continue the run whose outputs (and checkpoint.json) are in DIR.
        #[arg(long, value_name = "DIR", conflicts_with = "scene")]
        resume: Option<PathBuf>,
        /// Fail (exit code 3) on any warning, before the run or after it,
        /// and on many step cuts.
        #[arg(long)]
        strict: bool,
    },
    /// Validate a scene without running it.
    Check {
        scene: PathBuf,
        /// Fail (exit code 3) when the scene has warnings.
        #[arg(long)]
        strict: bool,
    },
    /// Measure element kernels, time steps, parallel speed-up and the impact
    /// scene's real-time factor (release build; run from the repository root).
    Bench {
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Smaller meshes and a short impact run (seconds instead of a minute).
        #[arg(long)]
        quick: bool,
    },
    /// What accuracy costs in time: sweep a scene's settings (elements,
    /// quadrature, time step, ρ∞, Newton kind, contact resolution), measure
    /// error and wall time, write report.md with plots into --out. Several
    /// scenes: one subdirectory each and an index (README.md).
    Study {
        /// The scene file(s).
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// Report directory.
        #[arg(long, default_value = "study")]
        out: PathBuf,
        /// quick: a few runs per sweep (seconds); standard: the full sweeps (minutes); refinement: h, elements and
        /// contact points refined three levels each (error bands of costly dynamic scenes).
        #[arg(long, value_enum, default_value = "standard")]
        level: ancf::study::plan::Level,
        /// Runs at the same time, each single-threaded (default: the cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// No progress lines.
        #[arg(long)]
        quiet: bool,
    },
    /// Run many variants of a scene (docs/sweep.md): the parameters of
    /// SWEEP (dotted scene paths with lists of values) as a grid or zipped,
    /// every variant checked first, run here or as a Slurm job array, and
    /// gathered into DIR/results.csv and DIR/report.md. Rerunning skips
    /// finished variants and resumes interrupted ones.
    Sweep {
        /// The sweep file (not needed with --collect).
        #[arg(required_unless_present = "collect")]
        sweep: Option<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "sweep")]
        out: PathBuf,
        /// Where the variants run.
        #[arg(long, value_enum, default_value = "local")]
        executor: ancf::sweep::Executor,
        /// Local: variants at a time (default: the cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Slurm: submit the job array and return.
        #[arg(long)]
        submit_only: bool,
        /// Slurm: wall-time limit per task (e.g. 00:30:00), over the sweep file's [slurm] time.
        #[arg(long)]
        time: Option<String>,
        /// Slurm: memory per task (e.g. 2G), over the sweep file's [slurm] mem.
        #[arg(long)]
        mem: Option<String>,
        /// Slurm: tasks running at once, over the sweep file's [slurm] max_parallel.
        #[arg(long)]
        max_parallel: Option<usize>,
        /// Gather the results of the sweep in DIR (after --submit-only).
        #[arg(long, value_name = "DIR", conflicts_with = "sweep")]
        collect: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Refuse to start when a variant has warnings; fail (exit code 3)
        /// when a variant ends with warnings or many step cuts.
        #[arg(long)]
        strict: bool,
    },
    /// Print a completion script for SHELL (bash, zsh, fish, elvish,
    /// powershell), e.g. `ancf completions bash >
    /// ~/.local/share/bash-completion/completions/ancf`.
    Completions {
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff) of ancf or of one of its commands, e.g.
    /// `ancf man run > ancf-run.1 && man ./ancf-run.1`.
    Man {
        /// The command (run, check, sweep, …); none: ancf's own page.
        command: Option<String>,
    },
    /// Print the ring/disk quadrature rule over inner ≤ ρ ≤ outer (Lan, Tian & Yu 2020, Tables 1–2).
    Quadrature {
        /// Inner radius, m (0 for a disk).
        #[arg(long, default_value_t = 0.0)]
        inner: f64,
        /// Outer radius, m.
        #[arg(long, default_value_t = 1.0)]
        outer: f64,
        /// Order n (exact for polynomials of degree ≤ 2n − 1).
        #[arg(long, default_value_t = 3)]
        order: usize,
        #[arg(long, value_enum, default_value = "table")]
        format: Format,
    },
}

fn load(path: &std::path::Path) -> Result<Scene, ExitCode> {
    Scene::load(path).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

/// What a valid scene will likely do badly ([`Scene::warnings`]), on
/// stderr; how many. Under `--strict` a scene with warnings is not run:
/// exit code 3.
fn print_warnings(scene: &Scene, strict: bool) -> Result<usize, ExitCode> {
    let warnings = scene.warnings();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let n = warnings.len();
    if strict && n > 0 {
        eprintln!("error: --strict: the scene has {n} warning(s) above");
        return Err(ExitCode::from(3));
    }
    Ok(n)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let forced = match cli.simd {
        SimdChoice::Auto => None,
        SimdChoice::Baseline => Some(SimdPath::Baseline),
        SimdChoice::Avx2 => Some(SimdPath::Avx2),
        SimdChoice::Avx512 => Some(SimdPath::Avx512),
    };
    if let Some(path) = forced
        && let Err(e) = ancf_core::math::simd::force(path)
    {
        eprintln!("error: --simd {}: {e}", path.name());
        return ExitCode::from(2);
    }
    match cli.command {
        Command::Check { scene, strict } => match load(&scene) {
            // The warnings first, then the verdict with their count: the
            // line a reader sees last says whether there is more to read.
            Ok(s) => match print_warnings(&s, strict) {
                Ok(n) => {
                    println!(
                        "{}: valid, {n} warning{} ({} elements, {} unknowns, {})",
                        scene.display(),
                        if n == 1 { "" } else { "s" },
                        s.model.element_count(),
                        s.model.n_unknowns,
                        s.model.element(0).kernel_path()
                    );
                    ExitCode::SUCCESS
                }
                Err(code) => code,
            },
            Err(code) => code,
        },
        Command::Run {
            scene,
            out,
            quiet,
            resume,
            strict,
        } => {
            // Ctrl-C ends the run after the current step, keeping everything written so far.
            let cancel = stop_on_interrupt("an interrupt will stop the run without a summary");
            let mut printed = 0;
            let (result, out) = match (resume, scene) {
                (Some(dir), _) => {
                    if !quiet {
                        eprintln!("ancf: resuming the run in {}", dir.display());
                    }
                    (ancf::run::resume(&dir, quiet, &cancel), dir)
                }
                (None, Some(scene)) => {
                    let out = out.unwrap_or_else(|| {
                        let stem = scene.file_stem().unwrap_or_default();
                        std::path::Path::new("out").join(stem)
                    });
                    let s = match load(&scene) {
                        Ok(s) => s,
                        Err(code) => return code,
                    };
                    if !quiet {
                        eprintln!(
                            "ancf: {} — {}",
                            scene.display(),
                            s.model.element(0).kernel_path()
                        );
                    }
                    // Before the work starts, whether quiet or not.
                    printed = match print_warnings(&s, strict) {
                        Ok(n) => n,
                        Err(code) => return code,
                    };
                    (
                        run_scene(
                            &s,
                            &RunOptions {
                                out: out.clone(),
                                quiet,
                                cancel,
                            },
                        ),
                        out,
                    )
                }
                (None, None) => unreachable!("clap requires a scene without --resume"),
            };
            match result {
                Ok(summary) if summary.status == ancf::output::RunStatus::Completed => {
                    println!(
                        "completed: {} steps, {} Newton iterations, {:.2} s wall; outputs in {}",
                        summary.steps,
                        summary.newton_iterations,
                        summary.wall_time_s,
                        out.display()
                    );
                    // A completed run can still have been held together by
                    // rejected steps: say so where the user looks.
                    if let Some(note) = ancf::run::step_cuts_note(summary.step_cuts, summary.steps)
                    {
                        eprintln!("note: {note}");
                    }
                    let findings = ancf::run::strict_findings(&summary);
                    // Those found by the run (the scene's own were printed before it).
                    for w in summary.warnings.iter().skip(printed) {
                        eprintln!("warning: {w}");
                    }
                    if strict && !findings.is_empty() {
                        eprintln!(
                            "error: --strict: the run completed with {} finding(s) above; outputs in {}",
                            findings.len(),
                            out.display()
                        );
                        return ExitCode::from(3);
                    }
                    ExitCode::SUCCESS
                }
                Ok(summary) => {
                    eprintln!("error: run {}: {}", summary.status, summary.message);
                    eprintln!("outputs so far are in {}", out.display());
                    ExitCode::from(if summary.status == ancf::output::RunStatus::Interrupted {
                        130
                    } else {
                        1
                    })
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(1)
                }
            }
        }
        Command::Bench { json, quick } => {
            if cfg!(debug_assertions) {
                eprintln!(
                    "warning: a debug build; benchmark numbers need `cargo run --release -- bench`"
                );
            }
            match ancf::bench::run(quick) {
                Ok(report) => {
                    if json {
                        println!(
                            "{}",
                            serde_json::to_string_pretty(&report).expect("report serializes")
                        );
                    } else {
                        print!("{}", ancf::bench::table(&report));
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(1)
                }
            }
        }
        Command::Study {
            scenes,
            out,
            level,
            jobs,
            quiet,
        } => study(&scenes, &out, level, jobs, quiet),
        Command::Sweep {
            sweep,
            out,
            executor,
            jobs,
            submit_only,
            time,
            mem,
            max_parallel,
            collect,
            quiet,
            strict,
        } => sweep_command(
            sweep,
            out,
            executor,
            jobs,
            submit_only,
            ancf::sweep::file::SlurmSpec {
                time,
                mem,
                max_parallel,
                ..Default::default()
            },
            collect,
            quiet,
            strict,
        ),
        Command::Completions { shell } => {
            let mut cmd = Cli::command();
            clap_complete::generate(shell, &mut cmd, "ancf", &mut std::io::stdout());
            ExitCode::SUCCESS
        }
        Command::Man { command } => {
            let cli = Cli::command();
            let man = match &command {
                None => clap_mangen::Man::new(cli),
                Some(name) => match cli.find_subcommand(name) {
                    Some(sub) => clap_mangen::Man::new(sub.clone()).title(format!("ancf-{name}")),
                    None => {
                        let names: Vec<&str> =
                            cli.get_subcommands().map(|c| c.get_name()).collect();
                        eprintln!("error: man: no command \"{name}\" (one of {names:?})");
                        return ExitCode::from(2);
                    }
                },
            };
            let mut page = Vec::new();
            match man.render(&mut page) {
                Ok(()) => {
                    use std::io::Write;
                    let _ = std::io::stdout().write_all(&page);
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: the manual page: {e}");
                    ExitCode::from(1)
                }
            }
        }
        Command::Quadrature {
            inner,
            outer,
            order,
            format,
        } => {
            if !(inner >= 0.0 && outer > inner && outer.is_finite()) {
                eprintln!("error: --inner/--outer: need 0 ≤ inner < outer, got {inner}, {outer}");
                return ExitCode::from(2);
            }
            if !(1..=64).contains(&order) {
                eprintln!("error: --order: must be 1..=64, got {order}");
                return ExitCode::from(2);
            }
            let points = ring_rule(order, inner, outer);
            match format {
                Format::Csv => {
                    println!("y,z,weight");
                    for p in &points {
                        println!("{:.16e},{:.16e},{:.16e}", p.y, p.z, p.weight);
                    }
                }
                Format::Table => {
                    println!(
                        "ring rule, order {order}, {inner} ≤ ρ ≤ {outer}: {} points",
                        points.len()
                    );
                    println!("{:>4} {:>22} {:>22} {:>22}", "k", "y", "z", "weight");
                    for (k, p) in points.iter().enumerate() {
                        println!(
                            "{:>4} {:>22.15} {:>22.15} {:>22.15}",
                            k + 1,
                            p.y,
                            p.z,
                            p.weight
                        );
                    }
                    let area: f64 = points.iter().map(|p| p.weight).sum();
                    println!(
                        "sum of weights {area:.15} (area π(R2² − R1²) = {:.15})",
                        std::f64::consts::PI * (outer * outer - inner * inner)
                    );
                }
            }
            ExitCode::SUCCESS
        }
    }
}

/// `ancf study`: every scene is checked before any run starts.
fn study(
    scenes: &[PathBuf],
    out: &std::path::Path,
    level: ancf::study::plan::Level,
    jobs: Option<usize>,
    quiet: bool,
) -> ExitCode {
    if cfg!(debug_assertions) {
        eprintln!("warning: a debug build; study timings need `cargo run --release -- study`");
    }
    for scene in scenes {
        if let Err(code) = load(scene) {
            return code;
        }
    }
    if jobs == Some(0) {
        eprintln!("error: --jobs: must be at least 1");
        return ExitCode::from(2);
    }
    let jobs = jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let several = scenes.len() > 1;
    let mut index = String::from(
        "# Accuracy and cost\n\nReports of `ancf study` (error against wall time for the settings users choose):\n\n",
    );
    for scene in scenes {
        let stem = ancf::study::report::scene_name(scene);
        let dir = if several {
            out.join(&stem)
        } else {
            out.to_path_buf()
        };
        let opts = ancf::study::StudyOptions {
            out: dir.clone(),
            level,
            jobs,
            quiet,
        };
        match ancf::study::study(scene, &opts) {
            Ok(report) => {
                println!("{}: report in {}", scene.display(), report.display());
                index.push_str(&format!("* [{stem}]({stem}/report.md)\n"));
            }
            Err(e) => {
                eprintln!("error: {}: {e}", scene.display());
                return ExitCode::from(1);
            }
        }
    }
    if several {
        let path = out.join("README.md");
        if let Err(e) = std::fs::write(&path, index) {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(1);
        }
    }
    ExitCode::SUCCESS
}

#[allow(clippy::too_many_arguments)]
fn sweep_command(
    sweep: Option<PathBuf>,
    out: PathBuf,
    executor: ancf::sweep::Executor,
    jobs: Option<usize>,
    submit_only: bool,
    slurm: ancf::sweep::file::SlurmSpec,
    collect: Option<PathBuf>,
    quiet: bool,
    strict: bool,
) -> ExitCode {
    use ancf::sweep::{Executor, SweepEnd, SweepOptions};
    if jobs == Some(0) {
        eprintln!("error: --jobs: must be at least 1");
        return ExitCode::from(2);
    }
    if executor != Executor::Slurm {
        for (given, flag) in [
            (submit_only, "--submit-only"),
            (slurm.time.is_some(), "--time"),
            (slurm.mem.is_some(), "--mem"),
            (slurm.max_parallel.is_some(), "--max-parallel"),
        ] {
            if given {
                eprintln!("error: {flag}: only with --executor slurm");
                return ExitCode::from(2);
            }
        }
    }
    if slurm.max_parallel == Some(0) {
        eprintln!("error: --max-parallel: must be at least 1");
        return ExitCode::from(2);
    }
    if let Some(dir) = collect {
        ancf::sweep::slurm::refresh_states(&dir);
        return match ancf::sweep::results::collect(&dir) {
            Ok(end) => sweep_exit(&dir, end, strict),
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        };
    }
    // Ctrl-C: finished variants are kept, running ones stop with a checkpoint.
    let cancel = stop_on_interrupt("an interrupt will stop the sweep without results.csv");
    let opts = SweepOptions {
        cancel,
        out: out.clone(),
        executor,
        jobs: jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        submit_only,
        slurm,
        quiet,
        strict,
    };
    let sweep = sweep.expect("clap requires a sweep file without --collect");
    match ancf::sweep::run(&sweep, &opts) {
        Ok(SweepEnd::Submitted { job, tasks }) => {
            println!(
                "submitted job array {job} ({tasks} tasks); gather the results with `ancf sweep --collect {}`",
                out.display()
            );
            ExitCode::SUCCESS
        }
        Ok(end) => sweep_exit(&out, end, strict),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn sweep_exit(out: &std::path::Path, end: ancf::sweep::SweepEnd, strict: bool) -> ExitCode {
    use ancf::sweep::SweepEnd;
    let table = out.join("results.csv");
    match end {
        SweepEnd::Completed { warned } => {
            println!("completed: every variant; results in {}", table.display());
            if warned > 0 {
                eprintln!(
                    "warning: {warned} variant(s) ended with warnings or many step cuts (column warnings and step_cuts of {})",
                    table.display()
                );
                if strict {
                    eprintln!("error: --strict: {warned} variant(s) with findings");
                    return ExitCode::from(3);
                }
            }
            ExitCode::SUCCESS
        }
        SweepEnd::Refused { warned } => {
            eprintln!(
                "error: --strict: {warned} variant(s) have warnings (above); nothing was run"
            );
            ExitCode::from(3)
        }
        SweepEnd::Incomplete { failed, missing } => {
            eprintln!(
                "error: {failed} variant(s) failed, {missing} not run; their status is in {} (rerun the same command to retry only those)",
                table.display()
            );
            ExitCode::from(1)
        }
        SweepEnd::Interrupted => {
            eprintln!(
                "interrupted: finished variants kept, running ones checkpointed; rerun the same command to go on ({})",
                table.display()
            );
            ExitCode::from(130)
        }
        SweepEnd::Submitted { .. } => ExitCode::SUCCESS,
    }
}

/// A token that Ctrl-C or SIGTERM cancels; runs and sweeps check it
/// between steps. `without` says what is lost when no handler can be set.
fn stop_on_interrupt(without: &str) -> CancelToken {
    let token = CancelToken::new();
    let handler = token.clone();
    if let Err(e) = ctrlc::set_handler(move || handler.cancel()) {
        eprintln!("warning: no Ctrl-C handler ({e}); {without}");
    }
    token
}
