//! Work sharing for the short parallel sections of a time step (assembly
//! chunks, the halves of the split band factorization).
//!
//! Each section lasts 0.1–10 ms and sits between serial stretches, and the
//! way rayon's own `join`/`par_iter` wait was measured to cost more than the
//! work on this kind of machine: a pool thread that runs out of work sleeps
//! within a few µs, and waking it takes ≈ 40 µs. Here every thread of the
//! pool takes the next task until none is left, and the calling thread then
//! spins (instead of sleeping) until the tasks the others took are done —
//! at most one task's time: a parallel section then takes the same time on
//! every call instead of sometimes the wake-up's more. Which thread runs
//! which task varies; callers make the tasks
//! write disjoint data, so results do not depend on it.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Run `run` on every task, on the threads of the current rayon pool, and
/// return the results in task order. With one thread (or one task) the
/// tasks run in order on the calling thread.
pub fn run_tasks<T: Send, R: Send>(tasks: Vec<T>, run: impl Fn(T) -> R + Sync) -> Vec<R> {
    let n = tasks.len();
    let helpers = rayon::current_num_threads().min(n).saturating_sub(1);
    if helpers == 0 {
        return tasks.into_iter().map(run).collect();
    }
    let slots: Vec<Mutex<Option<T>>> = tasks.into_iter().map(|t| Mutex::new(Some(t))).collect();
    let results: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let (next, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let take_tasks = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(slot) = slots.get(i) else { break };
            // Counted as done even if `run` panics, so that the caller stops
            // spinning and the scope passes the panic on.
            let _done = Done(&done);
            let task = slot
                .lock()
                .expect("task slot")
                .take()
                .expect("task taken once");
            let r = run(task);
            *results[i].lock().expect("result slot") = Some(r);
        }
    };
    rayon::scope(|scope| {
        for _ in 0..helpers {
            scope.spawn(|_| take_tasks());
        }
        take_tasks();
        while done.load(Ordering::Acquire) < n {
            std::hint::spin_loop();
        }
    });
    results
        .into_iter()
        .map(|r| {
            r.into_inner()
                .expect("result slot")
                .expect("every task ran")
        })
        .collect()
}

/// Marks one task done when dropped.
struct Done<'a>(&'a AtomicUsize);

impl Drop for Done<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
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
}
