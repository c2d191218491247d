//! The process's thread pool, which a child made by `fork()` rebuilds for itself.
//!
//! `fork()` copies only the calling thread: a child of a process that used rayon's global
//! pool inherits the pool's queues and sleeping-worker bookkeeping but none of its threads,
//! and its first parallel call waits forever for workers that do not exist (Python's
//! `multiprocessing` forks by default on Linux before 3.14). So the parallel work of the crate
//! runs on a pool tagged with the id of the process that built it; a process whose id differs
//! builds its own. The parent's pool is leaked in the child, never dropped: dropping it would
//! signal and join threads that are not there.

use std::sync::atomic::{AtomicPtr, Ordering};

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::{Error, Result};

struct ProcessPool {
    pid: u32,
    pool: ThreadPool,
}

static CURRENT: AtomicPtr<ProcessPool> = AtomicPtr::new(std::ptr::null_mut());

/// This process's pool (all cores, or `RAYON_NUM_THREADS`), built on first use in each
/// process.
///
/// # Errors
/// A pool that cannot be built (no threads to be had).
fn process_pool() -> Result<&'static ThreadPool> {
    let pid = std::process::id();
    let current = CURRENT.load(Ordering::Acquire);
    // SAFETY: a non-null pointer in CURRENT is a leaked Box, never freed.
    if let Some(p) = unsafe { current.as_ref() } {
        if p.pid == pid {
            return Ok(&p.pool);
        }
    }
    let pool = ThreadPoolBuilder::new()
        .build()
        .map_err(|e| Error::invalid("threads", "must give a thread pool", e.to_string()))?;
    let fresh = Box::into_raw(Box::new(ProcessPool { pid, pool }));
    match CURRENT.compare_exchange(current, fresh, Ordering::AcqRel, Ordering::Acquire) {
        // SAFETY: `fresh` was just leaked and is now published, never freed.
        Ok(_) => Ok(unsafe { &(*fresh).pool }),
        Err(other) => {
            // Another thread of this process published its pool first: use that one.
            // SAFETY: `fresh` was never published; `other` is a leaked Box, never freed.
            drop(unsafe { Box::from_raw(fresh) });
            match unsafe { other.as_ref() } {
                Some(p) if p.pid == pid => Ok(&p.pool),
                _ => process_pool(),
            }
        }
    }
}

/// Runs `work` on this process's pool (see the module's docs).
///
/// # Errors
/// A pool that cannot be built.
pub fn install<T: Send>(work: impl FnOnce() -> T + Send) -> Result<T> {
    Ok(process_pool()?.install(work))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn work_runs_on_one_pool_per_process() {
        let sum = install(|| (0..1000u64).into_par_iter().sum::<u64>()).unwrap();
        assert_eq!(sum, 999 * 1000 / 2);
        let a = process_pool().unwrap() as *const ThreadPool;
        let b = process_pool().unwrap() as *const ThreadPool;
        assert_eq!(a, b);
    }
}
