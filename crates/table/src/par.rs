//! [`Par`]: how many threads a parallel library call may use, chosen by its caller.
//!
//! faer's way: the thread count is an argument of the call (here a field of the call's
//! settings), not a process-wide setting, so two callers in one process (two Python
//! estimators with different `n_jobs`, a test comparing 1 and 2 threads) each get what they
//! asked for. Only the CLI configures rayon's global pool (`--threads`).
use std::num::NonZeroUsize;

/// Where a parallel computation runs.
///
/// Results never depend on it: every parallel loop in hxai draws its random numbers from
/// generators seeded by structural indices and collects in index order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Par {
    /// The rayon pool of the calling thread: the global pool (all cores, or the CLI's
    /// `--threads`), or the pool the caller is already running in.
    #[default]
    Current,
    /// A pool of exactly this many threads, built for the call and dropped after it.
    Threads(NonZeroUsize),
}

impl Par {
    /// One thread: the computation runs sequentially (in a pool of one worker).
    pub const SEQUENTIAL: Par = Par::Threads(NonZeroUsize::MIN);

    /// `Threads(n)`, or `Current` for `n == 0`.
    pub fn threads(n: usize) -> Par {
        NonZeroUsize::new(n).map_or(Par::Current, Par::Threads)
    }

    /// Runs `f` with rayon's parallel iterators on the chosen pool (see [`Par::pool`]).
    pub fn run<R: Send>(self, f: impl FnOnce() -> R + Send) -> R {
        self.pool().install(f)
    }

    /// The pool to run in, for a call that enters it several times (between which it calls
    /// a progress callback, say): build it once, then [`Pool::install`] each parallel part.
    ///
    /// `Current` is the caller's pool. `Threads(n)` builds a pool of `n` threads, unless the
    /// calling thread already belongs to a pool of `n` threads (a nested call, which then
    /// stays where it is). If the operating system refuses the threads, the caller's pool
    /// is used instead: the thread count never changes a result, only the speed.
    pub fn pool(self) -> Pool {
        match self {
            Par::Current => Pool(None),
            Par::Threads(n) => {
                if rayon::current_thread_index().is_some()
                    && rayon::current_num_threads() == n.get()
                {
                    return Pool(None);
                }
                Pool(
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(n.get())
                        .build()
                        .ok(),
                )
            }
        }
    }
}

/// A pool chosen by [`Par::pool`]: its own threads, or the caller's pool.
#[derive(Debug)]
pub struct Pool(Option<rayon::ThreadPool>);

impl Pool {
    /// Runs `f` in this pool (rayon's parallel iterators inside `f` use its threads).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.0 {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threads_gives_that_many_workers() {
        assert_eq!(Par::threads(0), Par::Current);
        for n in [1, 2, 3] {
            let seen = Par::threads(n).run(rayon::current_num_threads);
            assert_eq!(seen, n);
        }
        assert_eq!(Par::SEQUENTIAL.run(rayon::current_num_threads), 1);
    }

    #[test]
    fn current_stays_in_the_callers_pool() {
        let inner = Par::threads(3).run(|| Par::Current.run(rayon::current_num_threads));
        assert_eq!(inner, 3);
    }
}
