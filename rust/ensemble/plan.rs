//! One step for all the runs of a batch or sweep, planned before they start.
//!
//! The runs of a batch share one frame grid and so one step. With `dt` given it is that
//! step; with `dt = None` a fixed-step method takes the smallest of the steps its runs would
//! pick alone (so no run is less accurate than alone), and an adaptive method leaves each run
//! to pick its own first step, as alone. The plan also names the run that RK4 threatens most
//! (the largest predicted drift of `|q|`, see [`crate::run::step_size`]), for one warning.

use crate::ensemble::batch::{plan_rows, Start};
use crate::error::Result;
use crate::ode::controller::check_rtol;
use crate::run::registry::Method;
use crate::run::step_size::StepPlan;

/// The step shared by the runs of a batch, and its worst run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchPlan {
    /// The step every run is given; `None` for an adaptive method without `dt`, whose runs
    /// each pick their own first step.
    pub dt: Option<f64>,
    /// The run with the largest predicted drift (the first of equals) and its plan at `dt`;
    /// `None` without runs or without a shared step.
    pub worst: Option<(usize, StepPlan)>,
}

/// Plans the step of every run of `starts` (see the module docs); each run's inputs are
/// checked as its single run checks them, errors naming the row.
///
/// # Errors
/// A bad `rtol` (even without runs), and what [`plan_rows`] refuses.
pub fn plan_batch(
    starts: &[Start],
    t_end: f64,
    frames: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
) -> Result<BatchPlan> {
    check_rtol(rtol)?;
    if dt.is_none() && method.is_adaptive() {
        plan_rows(starts, t_end, frames, method, dt, rtol)?;
        return Ok(BatchPlan {
            dt: None,
            worst: None,
        });
    }
    if starts.is_empty() {
        return Ok(BatchPlan {
            dt: Some(dt.unwrap_or(1.0)),
            worst: None,
        });
    }
    let mut plans = plan_rows(starts, t_end, frames, method, dt, rtol)?;
    let step = plans.iter().map(|p| p.dt).fold(f64::INFINITY, f64::min);
    if dt.is_none() && plans.iter().any(|p| p.dt != step) {
        plans = plan_rows(starts, t_end, frames, method, Some(step), rtol)?;
    }
    let mut worst = 0;
    for (i, p) in plans.iter().enumerate() {
        if p.predicted_drift > plans[worst].predicted_drift {
            worst = i;
        }
    }
    Ok(BatchPlan {
        dt: Some(step),
        worst: Some((worst, plans[worst])),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start(omega0: [f64; 3]) -> Start {
        Start::try_new([1.0, 2.0, 3.0], omega0, [1.0, 0.0, 0.0, 0.0]).unwrap()
    }

    #[test]
    fn the_batch_takes_the_smallest_step_and_names_the_fastest_run() {
        let starts = [
            start([0.1, 0.2, 0.3]),
            start([1.0, 2.0, 3.0]),
            start([0.5, 0.5, 0.5]),
        ];
        let rk4: Method = "rk4".parse().unwrap();
        let p = plan_batch(&starts, 100.0, 201, rk4, None, 1e-9).unwrap();
        let alone: Vec<f64> = starts
            .iter()
            .map(|s| plan_batch(std::slice::from_ref(s), 100.0, 201, rk4, None, 1e-9))
            .map(|p| p.unwrap().dt.unwrap())
            .collect();
        assert_eq!(
            p.dt,
            Some(alone.iter().cloned().fold(f64::INFINITY, f64::min))
        );
        // at one shared coarse step the fastest run loses the most of |q|
        let coarse = plan_batch(&starts, 100.0, 201, rk4, Some(0.2), 1e-9).unwrap();
        assert_eq!(coarse.dt, Some(0.2));
        let (row, worst) = coarse.worst.unwrap();
        assert_eq!(row, 1);
        assert!(worst.predicted_drift > 0.0);
    }

    #[test]
    fn an_adaptive_batch_leaves_the_step_to_each_run_and_a_bad_rtol_is_refused() {
        let dopri5: Method = "dopri5".parse().unwrap();
        let p = plan_batch(&[start([0.1, 0.2, 0.3])], 10.0, 11, dopri5, None, 1e-9).unwrap();
        assert_eq!(p.dt, None);
        assert!(plan_batch(&[], 10.0, 11, dopri5, None, 1e-20).is_err());
    }
}
