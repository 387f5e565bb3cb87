//! The Slurm executor: one `sbatch` job array with a task per variant that
//! still needs work, each task an ordinary `ancf run` (or `--resume`) into
//! the variant's folder on the shared file system. The sweep follows the
//! tasks with `squeue`, then records each task's final Slurm state (from
//! `scontrol`, or `sacct` where accounting runs) next to its run, so that
//! results.csv can say why a task left no summary (TIMEOUT, CANCELLED, …).
//! Rerunning the command submits only the variants still missing.

use super::file::SlurmSpec;
use super::run_dir;
use ancf_core::solve::cancel::CancelToken;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// How a Slurm sweep left this command.
pub enum Outcome {
    /// `--submit-only`: the array is queued.
    Submitted { job: String },
    /// Every task ended (or Ctrl-C stopped the following; tasks go on).
    Finished,
}

/// Runs `program` with `args`, returning its stdout, or an error naming it.
fn call(program: &str, args: &[&str]) -> Result<String, String> {
    let out = Command::new(program).args(args).output().map_err(|e| {
        format!(
            "{program}: {e}. The slurm executor needs Slurm's commands on PATH (a cluster's \
             login node; to try it on one machine: scripts/slurm-local.sh start)"
        )
    })?;
    if !out.status.success() {
        return Err(format!(
            "{program} {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// `s` as one word of a bash script, taken literally: in single quotes,
/// each `'` closed, escaped and reopened (`$(…)`, `` ` `` and `$` stay text).
fn shell_quoted(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// The job-array script for the variants `ids` of the sweep in `out`.
/// Paths go in single quotes; the caller refuses a path or a value with a
/// control character ([`script_safe`], [`SlurmSpec::check`]).
pub fn script(out: &Path, ids: &[String], spec: &SlurmSpec, exe: &Path) -> String {
    let mut s = String::from("#!/bin/bash\n");
    let _ = writeln!(s, "#SBATCH --job-name=ancf-sweep");
    let limit = spec.max_parallel.map_or(String::new(), |l| format!("%{l}"));
    let _ = writeln!(
        s,
        "#SBATCH --array=0-{}{limit}",
        ids.len().saturating_sub(1)
    );
    let _ = writeln!(s, "#SBATCH --ntasks=1");
    let _ = writeln!(s, "#SBATCH --cpus-per-task=1");
    if let Some(t) = &spec.time {
        let _ = writeln!(s, "#SBATCH --time={t}");
    }
    if let Some(m) = &spec.mem {
        let _ = writeln!(s, "#SBATCH --mem={m}");
    }
    if let Some(p) = &spec.partition {
        let _ = writeln!(s, "#SBATCH --partition={p}");
    }
    for o in spec.options.iter().flatten() {
        let _ = writeln!(s, "#SBATCH {o}");
    }
    // A minute before the time limit the run gets SIGINT: it stops after
    // its step and keeps its outputs; a rerun resumes it from its checkpoint.
    let _ = writeln!(s, "#SBATCH --signal=INT@60");
    let _ = writeln!(s, "#SBATCH --output={}/logs/slurm_%A_%a.out", out.display());
    let _ = writeln!(s, "set -u");
    let _ = writeln!(s, "export RAYON_NUM_THREADS=${{SLURM_CPUS_PER_TASK:-1}}");
    let _ = writeln!(s, "ids=({})", ids.join(" "));
    let _ = writeln!(s, "id=${{ids[$SLURM_ARRAY_TASK_ID]}}");
    let _ = writeln!(
        s,
        "dir={}\"/runs/$id\"",
        shell_quoted(&out.display().to_string())
    );
    // Resume when a checkpoint is there at the time the task starts (an
    // earlier attempt of the same variant), else start.
    let exe = shell_quoted(&exe.display().to_string());
    let _ = writeln!(
        s,
        "if [ -f \"$dir/checkpoint.json\" ]; then\n  exec {exe} run --resume \"$dir\" --quiet\nelse\n  exec {exe} run \"$dir/scene.toml\" --out \"$dir\" --quiet\nfi"
    );
    s
}

/// Whether `path` can be written into a job script: one line (a newline
/// would end the `#SBATCH --output` directive and start a command).
pub fn script_safe(what: &str, path: &Path) -> Result<(), String> {
    let text = path.display().to_string();
    if text.chars().any(char::is_control) {
        return Err(format!(
            "{what} \"{}\" holds a control character; the Slurm job script cannot name it",
            text.escape_debug()
        ));
    }
    Ok(())
}

/// Submits the variants `ids` (none: nothing to do) and, unless
/// `submit_only`, follows the array until every task has ended or `cancel`
/// is cancelled.
pub fn run(
    out: &Path,
    ids: &[String],
    spec: &SlurmSpec,
    submit_only: bool,
    quiet: bool,
    cancel: &CancelToken,
) -> Result<Outcome, String> {
    if ids.is_empty() {
        return Ok(Outcome::Finished);
    }
    let exe = std::env::current_exe().map_err(|e| format!("the ancf executable: {e}"))?;
    script_safe("--out", out)?;
    script_safe("the ancf executable", &exe)?;
    let dir = out.join("slurm");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::create_dir_all(out.join("logs")).map_err(|e| format!("{}: {e}", out.display()))?;
    // A task that left a stale state behind gets a fresh one.
    for id in ids {
        let _ = std::fs::remove_file(run_dir(out, id).join("slurm_state.txt"));
    }
    let n = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| e.file_name().to_string_lossy().ends_with(".sbatch"))
            })
            .count()
        })
        .unwrap_or(0);
    let path: PathBuf = dir.join(format!("array_{n}.sbatch"));
    std::fs::write(&path, script(out, ids, spec, &exe))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let job = call("sbatch", &["--parsable", &path.display().to_string()])?
        .trim()
        .split(';')
        .next()
        .unwrap_or("")
        .to_string();
    if job.is_empty() {
        return Err("sbatch printed no job id".into());
    }
    // jobs.txt: one line per submission, the job id and its tasks' variants.
    let mut jobs = std::fs::read_to_string(dir.join("jobs.txt")).unwrap_or_default();
    let _ = writeln!(jobs, "{job} {}", ids.join(" "));
    std::fs::write(dir.join("jobs.txt"), jobs).map_err(|e| format!("{}: {e}", dir.display()))?;
    if !quiet {
        eprintln!(
            "submitted job array {job}: {} tasks ({})",
            ids.len(),
            path.display()
        );
    }
    if submit_only {
        return Ok(Outcome::Submitted { job });
    }
    follow(&job, ids.len(), quiet, cancel);
    record_states(out, &job, ids);
    Ok(Outcome::Finished)
}

/// Waits until `squeue` no longer lists job `job` (or Ctrl-C).
fn follow(job: &str, tasks: usize, quiet: bool, cancel: &CancelToken) {
    let bar = if quiet || !std::io::stderr().is_terminal() {
        indicatif::ProgressBar::hidden()
    } else {
        let bar = indicatif::ProgressBar::new(tasks as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} tasks ended  {msg}")
                .expect("valid template"),
        );
        bar
    };
    loop {
        if cancel.is_cancelled() {
            eprintln!(
                "stopped following job {job}; its tasks go on. Collect later with `ancf sweep --collect DIR`"
            );
            break;
        }
        let listed = match call("squeue", &["-h", "-r", "-j", job, "-o", "%i %T"]) {
            Ok(text) => text.lines().filter(|l| !l.trim().is_empty()).count(),
            // squeue refuses a job id it has forgotten: the array is over.
            Err(_) => 0,
        };
        bar.set_position(tasks.saturating_sub(listed) as u64);
        if listed == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    bar.finish_and_clear();
}

/// Final state of each task of `job` (index → state), from scontrol (no
/// accounting needed) or sacct.
fn task_states(job: &str) -> Vec<(usize, String)> {
    let mut states = Vec::new();
    if let Ok(text) = call("scontrol", &["show", "job", "-o", job]) {
        for line in text.lines() {
            let field = |k: &str| {
                line.split_whitespace()
                    .find_map(|w| w.strip_prefix(k).map(str::to_string))
            };
            if let (Some(task), Some(state)) = (field("ArrayTaskId="), field("JobState="))
                && let Ok(t) = task.parse::<usize>()
            {
                states.push((t, state));
            }
        }
    }
    if states.is_empty()
        && let Ok(text) = call("sacct", &["-j", job, "-n", "-P", "-X", "-o", "JobID,State"])
    {
        for line in text.lines() {
            let mut parts = line.split('|');
            if let (Some(id), Some(state)) = (parts.next(), parts.next())
                && let Some(t) = id.split('_').nth(1).and_then(|t| t.parse::<usize>().ok())
            {
                states.push((
                    t,
                    state.split_whitespace().next().unwrap_or(state).to_string(),
                ));
            }
        }
    }
    states
}

/// Whether `squeue` still lists tasks of `job`.
fn queued(job: &str) -> bool {
    call("squeue", &["-h", "-r", "-j", job, "-o", "%i"]).is_ok_and(|t| !t.trim().is_empty())
}

/// Writes each task's final Slurm state into its run folder. Once the job
/// has left the queue, a task Slurm no longer lists (cancelled before it
/// started, or forgotten after MinJobAge without accounting) is recorded
/// as UNKNOWN, so that results.csv does not call it "not run yet".
fn record_states(out: &Path, job: &str, ids: &[String]) {
    let states = task_states(job);
    let over = !queued(job);
    for (task, id) in ids.iter().enumerate() {
        let path = run_dir(out, id).join("slurm_state.txt");
        match states.iter().find(|(t, _)| *t == task) {
            Some((_, state)) => {
                let _ = std::fs::write(&path, format!("{state}\n"));
            }
            None if over && !path.exists() => {
                let _ = std::fs::write(&path, "UNKNOWN\n");
            }
            None => {}
        }
    }
}

/// `--collect`: refresh the states of every job submitted from `out` that
/// Slurm still knows (best effort; results come from the runs' summaries).
pub fn refresh_states(out: &Path) {
    let Ok(jobs) = std::fs::read_to_string(out.join("slurm").join("jobs.txt")) else {
        return;
    };
    for line in jobs.lines() {
        let mut words = line.split_whitespace();
        if let Some(job) = words.next() {
            let ids: Vec<String> = words.map(str::to_string).collect();
            record_states(out, job, &ids);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_array_script_maps_task_indices_to_variants() {
        let spec = SlurmSpec {
            time: Some("00:10:00".into()),
            mem: Some("1G".into()),
            max_parallel: Some(4),
            partition: None,
            options: Some(vec!["--account=wires".into()]),
        };
        let ids = vec!["v001".to_string(), "v004".to_string()];
        let s = script(
            Path::new("/shared/sweep"),
            &ids,
            &spec,
            Path::new("/opt/ancf"),
        );
        for line in [
            "#SBATCH --array=0-1%4",
            "#SBATCH --time=00:10:00",
            "#SBATCH --mem=1G",
            "#SBATCH --account=wires",
            "#SBATCH --signal=INT@60",
            "ids=(v001 v004)",
            "dir='/shared/sweep'\"/runs/$id\"",
            "exec '/opt/ancf' run --resume \"$dir\" --quiet",
        ] {
            assert!(
                s.lines().any(|l| l.trim() == line),
                "missing {line:?} in\n{s}"
            );
        }
    }

    /// A path with `$(…)`, backquotes and a quote stays text: bash, given
    /// the script's `dir=` line, sets dir to the path itself.
    #[test]
    fn paths_in_the_script_are_not_expanded_by_the_shell() {
        let hostile = "/tmp/a $(touch pwned) `id` it's";
        let s = script(
            Path::new(hostile),
            &["v001".to_string()],
            &SlurmSpec::default(),
            Path::new("/opt/ancf"),
        );
        let line = s.lines().find(|l| l.starts_with("dir=")).unwrap();
        let out = Command::new("bash")
            .arg("-c")
            .arg(format!("id=v001; {line}; printf %s \"$dir\""))
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            format!("{hostile}/runs/v001")
        );
        assert!(script_safe("--out", Path::new("/tmp/a\nb")).is_err());
        let bad = SlurmSpec {
            partition: Some("debug\nrm -rf ~".into()),
            ..Default::default()
        };
        assert!(bad.check().unwrap_err().contains("slurm.partition"));
        let bad = SlurmSpec {
            options: Some(vec!["--account=x\ntouch pwned".into()]),
            ..Default::default()
        };
        assert!(bad.check().unwrap_err().contains("slurm.options[0]"));
    }
}
