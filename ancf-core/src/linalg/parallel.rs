//! Work sharing for the short parallel sections of a time step (assembly
//! chunks, the halves of the split band factorization).
//!
//! Each section lasts 0.05–10 ms and sits between serial stretches of
//! similar length, many times a Newton step. A thread that waits for work
//! by sleeping takes ≈ 40 µs to wake on a virtual machine (rayon's pool
//! threads sleep within a few µs of running out of work), which is as long
//! as the sections themselves: the force of a 1000-element wire, spread
//! over rayon's pool, took longer on two threads than on one. So the
//! helpers here wait by spinning, for up to [`SPIN`] after their last
//! section, and only then sleep: inside a Newton loop they are always
//! awake. The calling thread takes tasks too, and then spins until the
//! tasks the helpers took are done — at most one task's time.
//!
//! The helpers are `rayon::current_num_threads() − 1` threads of their
//! own, started at the first parallel section; one caller uses them at a
//! time (another runs its tasks itself). Which thread runs which task
//! varies; callers make the tasks write disjoint data, so results do not
//! depend on it.

use std::any::Any;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// How long a helper spins for the next section before it sleeps: longer
/// than the serial stretches of a Newton iteration (a refresh's
/// factorization on 1000 nodes is ≈ 3 ms), short against an output write
/// or the end of a run.
const SPIN: Duration = Duration::from_millis(5);

/// Run `run` on every task, on the calling thread and the helpers (as many
/// threads as the current rayon pool has), and return the results in task
/// order. With one thread, one task, or the helpers busy with another
/// caller's section, the tasks run in order on the calling thread.
pub fn run_tasks<T: Send, R: Send>(tasks: Vec<T>, run: impl Fn(T) -> R + Sync) -> Vec<R> {
    let n = tasks.len();
    let wanted = rayon::current_num_threads().min(n).saturating_sub(1);
    let pool = (wanted > 0).then(|| helpers(wanted)).flatten();
    let Some(mut pool) = pool else {
        return tasks.into_iter().map(run).collect();
    };
    let slots: Vec<Mutex<Option<T>>> = tasks.into_iter().map(|t| Mutex::new(Some(t))).collect();
    let results: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let take_tasks = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(slot) = slots.get(i) else { break };
            let task = slot
                .lock()
                .expect("task slot")
                .take()
                .expect("task taken once");
            let r = run(task);
            *results[i].lock().expect("result slot") = Some(r);
        }
    };
    pool.run(wanted, &take_tasks);
    results
        .into_iter()
        .map(|r| {
            r.into_inner()
                .expect("result slot")
                .expect("every task ran")
        })
        .collect()
}

/// The section the helpers work on, written by the caller that holds
/// [`Helpers`].
struct Section {
    epoch: usize,
    /// Helpers 0 … participants − 1 take part.
    participants: usize,
    /// The caller's `take_tasks`, valid until `active` is zero.
    job: Option<Job>,
}

/// A pointer to a section's work on the caller's stack.
#[derive(Clone, Copy)]
struct Job(*const (dyn Fn() + Sync + 'static));

// SAFETY: the pointee is `Sync`, and the caller keeps it alive (it waits
// for every participant to finish) while a helper may read it.
unsafe impl Send for Job {}

/// What the caller and its helpers share.
struct Shared {
    section: Mutex<Section>,
    /// `section.epoch`, for the helpers' spinning.
    epoch: AtomicUsize,
    /// Participants still inside the section.
    active: AtomicUsize,
    /// A panic inside a helper's part, passed on to the caller.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
    /// The number of sleeping helpers, and their wake-up.
    sleeping: Mutex<usize>,
    wake: Condvar,
}

/// The helper threads started so far; held by one caller at a time.
struct Helpers {
    shared: &'static Shared,
    started: usize,
}

/// Locks `m`, also after a panic elsewhere (the data stays consistent:
/// every write under these locks is a single assignment).
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// `wanted` helpers, started if need be, or `None` while another caller
/// holds them (or a thread could not be started).
fn helpers(wanted: usize) -> Option<std::sync::MutexGuard<'static, Helpers>> {
    static HELPERS: OnceLock<Mutex<Helpers>> = OnceLock::new();
    let helpers = HELPERS.get_or_init(|| {
        let shared = Box::leak(Box::new(Shared {
            section: Mutex::new(Section {
                epoch: 0,
                participants: 0,
                job: None,
            }),
            epoch: AtomicUsize::new(0),
            active: AtomicUsize::new(0),
            panic: Mutex::new(None),
            sleeping: Mutex::new(0),
            wake: Condvar::new(),
        }));
        Mutex::new(Helpers { shared, started: 0 })
    });
    // (Poisoned by a task's panic passed on to its caller: the helpers are
    // fine, every one of them finished that section.)
    let mut guard = match helpers.try_lock() {
        Ok(guard) => guard,
        Err(std::sync::TryLockError::Poisoned(poisoned)) => poisoned.into_inner(),
        Err(std::sync::TryLockError::WouldBlock) => return None,
    };
    while guard.started < wanted {
        let (shared, index) = (guard.shared, guard.started);
        let seen = shared.epoch.load(Ordering::Acquire);
        std::thread::Builder::new()
            .name(format!("ancf-helper-{index}"))
            .spawn(move || help(shared, index, seen))
            .ok()?;
        guard.started += 1;
    }
    Some(guard)
}

impl Helpers {
    /// Run `work` on the calling thread and on helpers 0 … `wanted` − 1,
    /// and return when all have finished it; a panic in any of them is
    /// passed on.
    fn run(&mut self, wanted: usize, work: &(dyn Fn() + Sync)) {
        let shared = self.shared;
        // SAFETY: only the lifetime is erased. The helpers read `work`
        // only between the epoch's bump below and their decrement of
        // `active`, and this function returns only after `active` is zero.
        let job = unsafe {
            std::mem::transmute::<*const (dyn Fn() + Sync + '_), *const (dyn Fn() + Sync + 'static)>(
                work,
            )
        };
        shared.active.store(wanted, Ordering::Relaxed);
        {
            let mut section = lock(&shared.section);
            section.epoch += 1;
            section.participants = wanted;
            section.job = Some(Job(job));
            shared.epoch.store(section.epoch, Ordering::SeqCst);
        }
        if *lock(&shared.sleeping) > 0 {
            shared.wake.notify_all();
        }
        let mine = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
        while shared.active.load(Ordering::Acquire) > 0 {
            std::hint::spin_loop();
        }
        lock(&shared.section).job = None;
        if let Err(payload) = mine {
            std::panic::resume_unwind(payload);
        }
        if let Some(payload) = lock(&shared.panic).take() {
            std::panic::resume_unwind(payload);
        }
    }
}

/// A helper's life: wait for a section newer than `seen`, take part if
/// its index is among the participants, repeat.
fn help(shared: &'static Shared, index: usize, mut seen: usize) {
    loop {
        wait_for_section(shared, seen);
        let (epoch, participants, job) = {
            let section = lock(&shared.section);
            (section.epoch, section.participants, section.job)
        };
        seen = epoch;
        let Some(Job(job)) = job.filter(|_| index < participants) else {
            continue;
        };
        // SAFETY: see `Helpers::run`: the caller waits for this part.
        let work = unsafe { &*job };
        if let Err(payload) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
            *lock(&shared.panic) = Some(payload);
        }
        shared.active.fetch_sub(1, Ordering::Release);
    }
}

/// Spin until the epoch moves past `seen`, for at most [`SPIN`]; then sleep
/// until it does.
fn wait_for_section(shared: &Shared, seen: usize) {
    let started = Instant::now();
    let mut spins = 0u32;
    while shared.epoch.load(Ordering::Acquire) == seen {
        spins = spins.wrapping_add(1);
        if spins.is_multiple_of(256) && started.elapsed() > SPIN {
            let mut sleeping = lock(&shared.sleeping);
            *sleeping += 1;
            while shared.epoch.load(Ordering::SeqCst) == seen {
                sleeping = shared
                    .wake
                    .wait(sleeping)
                    .unwrap_or_else(|poisoned| poisoned.into_inner());
            }
            *sleeping -= 1;
            return;
        }
        std::hint::spin_loop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_every_task_once_in_order_of_results() {
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let out = pool.install(|| run_tasks((0..37).collect(), |i: usize| i * i));
            assert_eq!(
                out,
                (0..37).map(|i| i * i).collect::<Vec<_>>(),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn tasks_may_hold_disjoint_mutable_windows() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut data = vec![0usize; 100];
        pool.install(|| {
            let tasks: Vec<(usize, &mut [usize])> = data.chunks_mut(7).enumerate().collect();
            run_tasks(tasks, |(k, w)| w.iter_mut().for_each(|x| *x = k));
        });
        assert!(data.iter().enumerate().all(|(i, &x)| x == i / 7));
    }

    #[test]
    fn a_panicking_task_panics_the_caller_instead_of_hanging() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| {
                run_tasks((0..8).collect(), |i: usize| {
                    assert!(i != 5, "task 5 fails");
                    i
                })
            })
        }));
        assert!(r.is_err());
    }

    /// Tasks that each take 5 ms: the helper, asleep after more than
    /// [`SPIN`] without work, wakes and takes some of them.
    #[test]
    fn a_sleeping_helper_wakes_for_the_next_section() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let section = || {
            pool.install(|| {
                run_tasks((0..4).collect(), |_: usize| {
                    std::thread::sleep(Duration::from_millis(5));
                    std::thread::current().id()
                })
            })
        };
        // (Other tests may hold the helpers for a while: a section then
        // runs on its caller alone; a few tries.)
        let woke = (0..20).any(|_| {
            let _ = section();
            std::thread::sleep(3 * SPIN);
            let threads: std::collections::HashSet<_> = section().into_iter().collect();
            threads.len() == 2
        });
        assert!(woke, "the helper took no task");
    }

    /// Callers on several threads at once (one holds the helpers, the
    /// others run their tasks themselves) all get every result.
    #[test]
    fn callers_at_the_same_time_get_their_own_results() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        std::thread::scope(|scope| {
            for caller in 0..4usize {
                let pool = &pool;
                scope.spawn(move || {
                    for round in 0..200usize {
                        let out = pool.install(|| {
                            run_tasks((0..9).collect(), |i: usize| caller * 1000 + round + i)
                        });
                        let expected: Vec<usize> =
                            (0..9).map(|i| caller * 1000 + round + i).collect();
                        assert_eq!(out, expected);
                    }
                });
            }
        });
    }
}
