//! Keeping the pool's other threads awake through a step.
//!
//! A step hands work to the thread pool dozens of times (each pass over the colours,
//! each integration, each energy sum), with short stretches of work on one thread in
//! between (the colouring, the prefix sums). A rayon thread that finds no work for a
//! few dozen rounds goes to sleep, and waking it is slow on a virtual machine: on the
//! 2-core machine of 2026-12-03 (a probe of 400 joins of two 50 µs halves, each after
//! a pause), a join took 120–240 µs on average once the other thread had time to fall
//! asleep, and 70 µs when it had not.
//!
//! So for a step big enough to share out, every other thread of the pool is given a
//! job that keeps asking the pool for work until the step is over: the threads never
//! sleep between the step's stages, and each stage finds them ready. Which thread does
//! which work changes nothing in the results (every stage gives the same bits on any
//! number of threads), only the time. On an 8,000-sphere pile on 2 threads (three
//! runs of 300 steps each), a step took 6.7–7.3 ms with the threads kept awake and
//! 7.3–8.4 ms without.
//!
//! A waiting job gives up after [`IDLE_LIMIT`] without work, so a thread is never held
//! for long by a step that no longer needs it, and two steps run at once on one pool
//! (tests do that) cannot hold each other's threads for more than that.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use std::time::Duration;

use web_time::Instant;

/// How long a waiting thread asks for work without finding any before it stops
/// waiting (then rayon puts it to sleep as usual).
const IDLE_LIMIT: Duration = Duration::from_millis(4);

/// Idle rounds between two looks at the clock.
const ROUNDS_PER_CLOCK: u32 = 64;

/// Runs `body` with every other thread of the current pool kept awake, asking for
/// work, until `body` returns (see the module's note). With one thread, just `body`.
pub(crate) fn keep_pool_awake<R>(body: impl FnOnce() -> R) -> R {
    if rayon::current_num_threads() < 2 {
        return body();
    }
    let done = Arc::new(AtomicBool::new(false));
    let (flag, owner) = (Arc::clone(&done), rayon::current_thread_index());
    rayon::spawn_broadcast(move |context| {
        if Some(context.index()) != owner {
            wait_for_work(&flag);
        }
    });
    let result = body();
    done.store(true, Ordering::Release);
    result
}

/// Executes the pool's work as it comes until `done`, or until none has come for
/// [`IDLE_LIMIT`].
fn wait_for_work(done: &AtomicBool) {
    let mut last_work = Instant::now();
    let mut idle_rounds = 0u32;
    while !done.load(Ordering::Acquire) {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            idle_rounds = 0;
            last_work = Instant::now();
            continue;
        }
        idle_rounds += 1;
        if idle_rounds.is_multiple_of(ROUNDS_PER_CLOCK) && last_work.elapsed() > IDLE_LIMIT {
            return;
        }
        std::hint::spin_loop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    /// The body's parallel work is done (by whichever threads), its result comes back,
    /// and the waiting jobs let go of the threads: the pool then still runs a job on
    /// every thread.
    #[test]
    #[cfg_attr(miri, ignore = "too slow to interpret, and no unsafe code")]
    fn the_body_runs_with_the_pool_and_the_pool_is_free_after() {
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            let sum = pool.install(|| keep_pool_awake(|| (0..100_000u64).into_par_iter().sum::<u64>()));
            assert_eq!(sum, 100_000 * 99_999 / 2);
            assert_eq!(pool.broadcast(|context| context.index()), (0..threads).collect::<Vec<_>>());
        }
    }

    /// Steps started at once from several threads on one pool (as tests do) all
    /// finish, each with its own result, though each keeps the pool's other threads.
    #[test]
    #[cfg_attr(miri, ignore = "too slow to interpret, and no unsafe code")]
    fn several_bodies_at_once_on_one_pool_all_finish() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
        let pool = &pool;
        std::thread::scope(|scope| {
            let runs: Vec<_> = (0..4u64)
                .map(|k| {
                    scope.spawn(move || {
                        pool.install(|| {
                            keep_pool_awake(|| (0..200_000u64).into_par_iter().map(|x| x * k).sum::<u64>())
                        })
                    })
                })
                .collect();
            for (k, run) in runs.into_iter().enumerate() {
                assert_eq!(run.join().expect("no panic"), k as u64 * 200_000 * 199_999 / 2);
            }
        });
    }
}
