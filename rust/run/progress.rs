//! How far a single run has got, for a progress bar: the drivers report the share of the span
//! they have reached each time they look at their cancel flag (every [`super::CHECK_EVERY`]
//! fixed steps, every 1024 adaptive ones, every [`super::CHECK_EVERY`] frames of the closed
//! form), into a meter the caller set for the thread the run is on ([`metered`]); a watcher
//! on another thread reads it. With no meter set (a batch's rows, a sweep, a run in Rust) a
//! report is one look at a thread-local and nothing else.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;

/// How many meters are set, on any thread: while none is, a report is one load of it.
static METERED: AtomicUsize = AtomicUsize::new(0);

/// The share of the span a run has reached, as the bits of an `f64` in `[0, 1]`.
#[derive(Debug, Default)]
pub struct Meter(AtomicU64);

impl Meter {
    /// A meter at 0.
    pub fn new() -> Self {
        Self(AtomicU64::new(0.0f64.to_bits()))
    }

    /// The share last reported, in `[0, 1]`.
    pub fn share(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }

    fn set(&self, share: f64) {
        self.0.store(share.to_bits(), Ordering::Relaxed);
    }
}

thread_local! {
    static METER: RefCell<Option<Arc<Meter>>> = const { RefCell::new(None) };
}

/// Runs `work` with `meter` receiving this thread's reports.
pub fn metered<T>(meter: Arc<Meter>, work: impl FnOnce() -> T) -> T {
    let previous = METER.with(|m| m.replace(Some(meter)));
    METERED.fetch_add(1, Ordering::Relaxed);
    let out = work();
    METERED.fetch_sub(1, Ordering::Relaxed);
    METER.with(|m| *m.borrow_mut() = previous);
    out
}

/// Reports that the run on this thread has reached `t` of `t_end` (a share clamped to
/// `[0, 1]`; NaN is ignored). With no meter set anywhere it is one relaxed load: a call in
/// the drivers' step loops (the thread-local's access), even once in 16384 steps, changed
/// how the loop was compiled and cost RK4 3.5% a step.
#[inline(always)]
pub fn report(t: f64, t_end: f64) {
    if METERED.load(Ordering::Relaxed) > 0 {
        report_metered(t, t_end);
    }
}

#[cold]
#[inline(never)]
fn report_metered(t: f64, t_end: f64) {
    METER.with(|m| {
        if let Some(meter) = m.borrow().as_ref() {
            let share = t / t_end;
            if share.is_finite() {
                meter.set(share.clamp(0.0, 1.0));
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_reach_the_meter_of_their_thread_only() {
        let meter = Arc::new(Meter::new());
        report(0.5, 1.0); // no meter: nothing
        metered(meter.clone(), || {
            report(0.25, 1.0);
            assert_eq!(meter.share(), 0.25);
            // another thread's reports do not reach it
            std::thread::scope(|s| {
                s.spawn(|| report(0.75, 1.0));
            });
            report(3.0, 2.0);
        });
        assert_eq!(meter.share(), 1.0);
        report(0.1, 1.0); // the meter is gone with the run
        assert_eq!(meter.share(), 1.0);
    }
}
