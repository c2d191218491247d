//! The free body's run without steps: its frames taken from the closed form.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::body::RigidBody;
use crate::error::{Error, Result};
use crate::exact::ExactMotion;
use crate::observe::Observer;
use crate::run::fixed::CHECK_EVERY;
use crate::run::grid::FrameGrid;
use crate::run::progress;

/// The free body's frames evaluated from the closed form at the frame times: no steps, the
/// same observers, flip times from the solution by the detector's definition.
pub(crate) fn evaluate_exact<O: Observer<7>>(
    body: &RigidBody,
    x0: [f64; 7],
    grid: &FrameGrid,
    obs: &mut O,
    flips: bool,
    cancel: &AtomicBool,
) -> Result<Vec<f64>> {
    let omega0 = [x0[0], x0[1], x0[2]];
    let motion = ExactMotion::try_new(body, omega0, [x0[3], x0[4], x0[5], x0[6]])?;
    for i in 0..grid.frames() {
        let t = grid.time(i);
        if (i as u64).is_multiple_of(CHECK_EVERY) {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Interrupted);
            }
            progress::report(t, grid.t_end());
        }
        let x = motion.state_at(t);
        if !x.iter().all(|v| v.is_finite()) {
            return Err(Error::TooLarge {
                what: "the exact solution".into(),
                needed: format!("its phase at t = {t:.3e} (t_end · max|omega0| radians)"),
                limit: "what float64 holds".into(),
                hint: "take a shorter t_end",
            });
        }
        obs.frame(i, t, &x);
    }
    match flips {
        true => motion.flip_times(grid.t_end()),
        false => Ok(Vec::new()),
    }
}
