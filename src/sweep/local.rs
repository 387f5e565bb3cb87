//! The local executor: each variant is an `ancf run` child process (so a
//! crash or a panic in one does not take the others down), `jobs` at a
//! time, each with `cores / jobs` threads, under one progress bar.
//!
//! Ctrl-C: the children get the interrupt too (same terminal, or forwarded
//! here), stop after their current step with a checkpoint, and their
//! outputs are kept; no new child starts. Rerunning resumes them. A child
//! whose parent dies (killed, not interrupted) gets SIGTERM and stops the
//! same way (Linux), so a rerun never races an orphan; each run also locks
//! its folder (`ancf_output::lock`).

use super::run_command;
use ancf_core::solve::cancel::CancelToken;
use std::io::IsTerminal;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// Runs the variants `ids` of the sweep in `out`; true when interrupted.
pub fn run(
    out: &Path,
    ids: &[String],
    jobs: usize,
    quiet: bool,
    cancel: &CancelToken,
) -> Result<bool, String> {
    let exe = std::env::current_exe().map_err(|e| format!("the ancf executable: {e}"))?;
    let jobs = jobs.max(1);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = (cores / jobs).max(1);
    let bar = if quiet || !std::io::stderr().is_terminal() {
        indicatif::ProgressBar::hidden()
    } else {
        let bar = indicatif::ProgressBar::new(ids.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} variants  {msg}  ETA {eta}",
            )
            .expect("valid template"),
        );
        bar
    };
    std::fs::create_dir_all(out.join("logs")).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut queue = ids.iter();
    let mut running: Vec<(String, Child)> = Vec::new();
    let mut forwarded = false;
    loop {
        let interrupted = cancel.is_cancelled();
        if interrupted && !forwarded {
            // Children started by this process get the interrupt as well
            // (a terminal's Ctrl-C reaches them anyway; a `kill -INT` of
            // this process alone does not).
            for (_, child) in &running {
                let _ = Command::new("kill")
                    .args(["-INT", &child.id().to_string()])
                    .status();
            }
            forwarded = true;
        }
        while !interrupted && running.len() < jobs {
            let Some(id) = queue.next() else { break };
            let mut cmd = Command::new(&exe);
            if let Ok(simd) = std::env::var("ANCF_SIMD") {
                cmd.env("ANCF_SIMD", simd);
            }
            // The child's messages (a panic's among them): DIR/logs/<id>.log.
            let log_path = out.join("logs").join(format!("{id}.log"));
            let log = std::fs::File::create(&log_path)
                .map_err(|e| format!("{}: {e}", log_path.display()))?;
            let log2 = log
                .try_clone()
                .map_err(|e| format!("{}: {e}", log_path.display()))?;
            stop_with_this_process(&mut cmd);
            let child = cmd
                .args(run_command(out, id))
                .env("RAYON_NUM_THREADS", threads.to_string())
                .stdin(Stdio::null())
                .stdout(Stdio::from(log))
                .stderr(Stdio::from(log2))
                .spawn()
                .map_err(|e| format!("{}: {e}", exe.display()))?;
            running.push((id.clone(), child));
        }
        if running.is_empty() {
            break;
        }
        let mut k = 0;
        while k < running.len() {
            match running[k].1.try_wait() {
                Ok(Some(_)) => {
                    let (id, _) = running.remove(k);
                    bar.inc(1);
                    bar.set_message(format!("{id} done"));
                }
                Ok(None) => k += 1,
                Err(e) => return Err(format!("waiting for variant {}: {e}", running[k].0)),
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    bar.finish_and_clear();
    Ok(cancel.is_cancelled())
}

/// The child `cmd` starts gets SIGTERM when this process dies (Linux:
/// prctl PR_SET_PDEATHSIG; its SIGTERM handler checkpoints and stops, as on
/// Ctrl-C). A child whose parent is already gone when it starts exits.
fn stop_with_this_process(cmd: &mut Command) {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        let parent = std::process::id() as libc::pid_t;
        // SAFETY: between fork and exec only async-signal-safe calls are
        // made (prctl, getppid), and nothing is allocated.
        unsafe {
            cmd.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                if libc::getppid() != parent {
                    return Err(std::io::Error::other(
                        "the sweep ended before its run started",
                    ));
                }
                Ok(())
            });
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = cmd;
}
