//! Stopping long work from outside: the work runs on a helper thread and looks at a cancel
//! flag, while the calling thread asks, every [`POLL`], whether to stop (Ctrl-C in Python).
//! Short work is not worth a thread: [`is_long`] and the `LONG_*` sizes say which is which.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use crate::error::Result;
use crate::run::grid::FrameGrid;
use crate::run::registry::Method;

/// How often the calling thread asks whether to stop.
pub const POLL: Duration = Duration::from_millis(50);

/// Steps above which a run is long (about 5 ms of RK4).
pub const LONG_RUN_STEPS: u64 = 200_000;
/// Frames of the exact solution above which its evaluation is long (about 5 ms).
pub const LONG_EXACT_FRAMES: usize = 5_000;
/// Point-frames above which rotating points is long.
pub const LONG_ROTATION: usize = 1 << 24;
/// Rows above which computing invariants is long.
pub const LONG_INVARIANTS: usize = 1 << 22;
/// Cells above which building a mesh is long.
pub const LONG_MESH: usize = 1 << 20;

/// Whether `runs` runs of `method` over `grid` are long enough to watch on a helper thread
/// (an adaptive method's step count is not known before it runs: always).
pub fn is_long(method: &Method, grid: &FrameGrid, runs: usize) -> bool {
    let runs = runs as u64;
    if !method.info().takes_steps() {
        return runs.saturating_mul(grid.frames() as u64) > LONG_EXACT_FRAMES as u64;
    }
    let work = runs.saturating_mul(grid.n_steps().max(grid.frames() as u64));
    method.is_adaptive() || work > LONG_RUN_STEPS
}

/// The address space a helper thread takes as it starts: its stack (Rust's 2 MiB) and, on
/// its first use of a thread-local of this library, a block glibc allocates for them, whose
/// failure aborts the process ("cannot allocate memory for thread-local data"), with room to
/// spare for the allocator's own bookkeeping.
const THREAD_ROOM: f64 = (4 << 20) as f64;

/// Runs `work` on a scoped helper thread while this thread calls `stop()` every [`POLL`];
/// once `stop()` returns true, `work`'s cancel flag is set (and `stop` no longer called), so
/// that it returns soon after. Returns what `work` returned, or `Err` with the panic's payload
/// if it panicked.
///
/// A thread that cannot be had is [`crate::Error::TooLarge`], not an abort: under an
/// address-space limit nearly reached (by the caller's own allocations) the helper's start
/// is checked first.
pub fn watch<T: Send>(
    work: impl FnOnce(&AtomicBool) -> Result<T> + Send,
    mut stop: impl FnMut() -> bool,
) -> std::thread::Result<Result<T>> {
    const HINT: &str = "free some memory, or ask for less";
    if let Err(e) = crate::buffer::ensure_room(THREAD_ROOM, "a helper thread", HINT) {
        return Ok(Err(e));
    }
    let cancel = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let (done_tx, done_rx) = mpsc::channel::<()>();
        let cancel = &cancel;
        let spawned = std::thread::Builder::new().spawn_scoped(scope, move || {
            let result = work(cancel);
            let _ = done_tx.send(());
            result
        });
        let handle = match spawned {
            Ok(handle) => handle,
            Err(e) => {
                return Ok(Err(crate::Error::TooLarge {
                    what: "starting a helper thread".into(),
                    needed: format!("a thread ({e})"),
                    limit: "what this process can start".into(),
                    hint: HINT,
                }))
            }
        };
        let mut stopped = false;
        while let Err(mpsc::RecvTimeoutError::Timeout) = done_rx.recv_timeout(POLL) {
            if !stopped && stop() {
                stopped = true;
                cancel.store(true, Ordering::Relaxed);
            }
        }
        handle.join()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    #[test]
    fn work_stops_soon_after_it_is_asked_to() {
        let mut asked = 0;
        let out = watch(
            |cancel| loop {
                if cancel.load(Ordering::Relaxed) {
                    return Err::<(), _>(Error::Interrupted);
                }
                std::thread::sleep(Duration::from_millis(1));
            },
            || {
                asked += 1;
                asked == 2
            },
        );
        assert!(matches!(out, Ok(Err(Error::Interrupted))));
        assert_eq!(asked, 2, "not asked again once stopping");
    }

    #[test]
    fn a_panic_in_the_work_is_returned_not_raised() {
        let out = watch(|_| -> Result<()> { panic!("boom") }, || false);
        assert!(out.is_err());
    }
}
