//! Work sharing for the short parallel sections of a time step: the
//! assembly's chunks, the block LU's two chains, the halves of the split
//! band factorization, of M x and of the generalized-α midpoint.
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
//! That holds while the run has the cores to itself. Where the machine has
//! more busy threads than cores (another program, two runs at once), a
//! helper loses its core for a time slice, inside a task the caller then
//! waits for, or while spinning for the next. So a waiting helper whose
//! yield lasted long sleeps at once, and the caller runs its sections
//! serially for a while when its waits exceed half its own work
//! ([`Backoff`]): two 2-thread runs at once then take the time of two
//! serial ones instead of 1.5× it.
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

/// Rounds of pure spinning (a few µs) before a waiting thread yields its
/// core at every round.
const PURE_SPINS: u32 = 2000;

/// Run `run` on every task, on the calling thread and the helpers (as many
/// threads as the current rayon pool has), and return the results in task
/// order. With one thread, one task, or the helpers busy with another
/// caller's section, the tasks run in order on the calling thread.
pub fn run_tasks<T: Send, R: Send>(tasks: Vec<T>, run: impl Fn(T) -> R + Sync) -> Vec<R> {
    let n = tasks.len();
    let wanted = rayon::current_num_threads().min(n).saturating_sub(1);
    let pool = (wanted > 0).then(|| helpers(wanted)).flatten();
    let Some(mut pool) = pool.filter(|p| !p.backoff.serial(Instant::now())) else {
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
    let (own, waited) = pool.run(wanted, &take_tasks);
    pool.backoff.record(own, waited, Instant::now());
    results
        .into_iter()
        .map(|r| {
            r.into_inner()
                .expect("result slot")
                .expect("every task ran")
        })
        .collect()
}

/// `f` inside a rayon pool of `threads` threads: the thread count its
/// parallel sections see (tests that compare thread counts).
#[cfg(test)]
pub(crate) fn with_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
    pool.expect("a thread pool").install(f)
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
    backoff: Backoff,
}

/// Sections run serially for a while after the helpers kept the caller
/// waiting. A helper is late when the machine has more busy threads than
/// cores (another program, another run): descheduled, it holds its task
/// for a time slice (ms) while the caller waits, and two 2-thread runs at
/// once took 1.5× the time of two serial ones. Over every [`Self::WINDOW`]
/// sections the caller's waits are compared with its own work: where they
/// exceed half of it the next sections run serially for a period, which
/// doubles (up to a second) while the waits stay long. Results do not
/// depend on it.
#[derive(Debug)]
struct Backoff {
    own: Duration,
    waited: Duration,
    sections: u32,
    serial_until: Option<Instant>,
    period: Duration,
}

impl Backoff {
    const WINDOW: u32 = 32;
    const FIRST_PERIOD: Duration = Duration::from_millis(50);
    const LONGEST_PERIOD: Duration = Duration::from_secs(1);

    fn new() -> Self {
        Backoff {
            own: Duration::ZERO,
            waited: Duration::ZERO,
            sections: 0,
            serial_until: None,
            period: Self::FIRST_PERIOD,
        }
    }

    /// Whether sections run serially at `now`.
    fn serial(&self, now: Instant) -> bool {
        self.serial_until.is_some_and(|until| now < until)
    }

    /// A section in which the caller worked `own` and then waited `waited`
    /// for the helpers.
    fn record(&mut self, own: Duration, waited: Duration, now: Instant) {
        self.own += own;
        self.waited += waited;
        self.sections += 1;
        if self.sections < Self::WINDOW {
            return;
        }
        if 2 * self.waited > self.own {
            self.serial_until = Some(now + self.period);
            self.period = (2 * self.period).min(Self::LONGEST_PERIOD);
        } else {
            self.period = Self::FIRST_PERIOD;
        }
        (self.own, self.waited, self.sections) = (Duration::ZERO, Duration::ZERO, 0);
    }
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
        Mutex::new(Helpers {
            shared,
            started: 0,
            backoff: Backoff::new(),
        })
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
    /// and return when all have finished it, with the time the caller
    /// worked and the time it then waited; a panic in any of them is passed
    /// on.
    fn run(&mut self, wanted: usize, work: &(dyn Fn() + Sync)) -> (Duration, Duration) {
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
        let started = Instant::now();
        let mine = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
        let worked = Instant::now();
        let mut spins = 0u32;
        while shared.active.load(Ordering::Acquire) > 0 {
            spins = spins.saturating_add(1);
            if spins > PURE_SPINS {
                // A helper that is not running (more busy threads than
                // cores) is waited for without taking its core.
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        lock(&shared.section).job = None;
        if let Err(payload) = mine {
            std::panic::resume_unwind(payload);
        }
        if let Some(payload) = lock(&shared.panic).take() {
            std::panic::resume_unwind(payload);
        }
        (worked - started, worked.elapsed())
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
/// until it does. After the first [`PURE_SPINS`] rounds each round yields
/// the core, and a yield that lasted [`CONTENDED`] — another thread ran on
/// this core meanwhile: more busy threads than cores — sends the helper to
/// sleep at once, so that a run sharing the machine with other work does
/// not take a core from it by spinning.
fn wait_for_section(shared: &Shared, seen: usize) {
    let started = Instant::now();
    let mut spins = 0u32;
    while shared.epoch.load(Ordering::Acquire) == seen {
        spins = spins.wrapping_add(1);
        let mut contended = false;
        if spins > PURE_SPINS {
            let yielded = Instant::now();
            std::thread::yield_now();
            contended = yielded.elapsed() > CONTENDED;
        }
        if contended || (spins.is_multiple_of(256) && started.elapsed() > SPIN) {
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

/// A yield that took this long gave the core to another thread.
const CONTENDED: Duration = Duration::from_micros(50);

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
        // (Other tests may hold the helpers for a while, or have made them
        // late into a serial period of up to a second: a section then runs
        // on its caller alone; tries for up to three seconds.)
        let woke = (0..200).any(|_| {
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

    /// Waits above half the caller's own work over a window start a serial
    /// period, which doubles while the waits stay long and falls back to
    /// its first length after a window without them.
    #[test]
    fn late_helpers_make_sections_serial_for_a_while() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let us = Duration::from_micros;
        let mut b = Backoff::new();
        let window = |b: &mut Backoff, waited: Duration, now: Instant| {
            for _ in 0..Backoff::WINDOW {
                b.record(us(100), waited, now);
            }
        };
        window(&mut b, us(40), t0);
        assert!(!b.serial(t0), "waits below half the work");
        window(&mut b, us(60), t0);
        assert!(b.serial(t0 + ms(49)) && !b.serial(t0 + ms(51)));
        let t1 = t0 + ms(60);
        window(&mut b, ms(3), t1);
        assert!(b.serial(t1 + ms(99)) && !b.serial(t1 + ms(101)));
        window(&mut b, us(5), t1 + ms(200));
        assert_eq!(b.period, Backoff::FIRST_PERIOD);
        assert!(!b.serial(t1 + ms(200)));
    }
}
