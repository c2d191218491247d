//! One step for all the runs of a batch or sweep, planned before they start.
//!
//! The runs of a batch share one frame grid and so one step. With `dt` given it is that
//! step; with `dt = None` a fixed-step method takes the smallest of the steps its runs would
//! pick alone (so no run is less accurate than alone), and an adaptive method leaves each run
//! to pick its own first step, as alone. The plan also names the run that RK4 threatens most
//! (the largest predicted drift of `|q|`, see [`crate::run::step_size`]), for one warning.

use crate::buffer::try_with_capacity;
use crate::dynamics::System;
use crate::ensemble::batch::{plan_rows, Start};
use crate::error::Result;
use crate::ode::controller::check_rtol;
use crate::run::options::RunOptions;
use crate::run::plan_system;
use crate::run::registry::Method;
use crate::run::step_size::StepPlan;

/// What to ask for when the plans of a batch's rows do not fit.
const PLANS_HINT: &str = "plan fewer starts at a time";

/// The step shared by the runs of a batch, and its worst run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchPlan {
    /// The step every run is given; `None` for an adaptive method without `dt`, whose runs
    /// each pick their own first step.
    pub dt: Option<f64>,
    /// The run with the largest predicted drift (the first of equals) and its plan at `dt`;
    /// `None` without runs.
    pub worst: Option<(usize, StepPlan)>,
    /// The run whose model is stiffest relative to its rates (a damper's slip rate over the
    /// rate bound), and its plan; `None` without runs.
    pub stiffest: Option<(usize, StepPlan)>,
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
    shared_step(starts.len(), method, dt, rtol, |dt| {
        plan_rows(starts, t_end, frames, method, dt, rtol)
    })
}

/// Plans the step of every run of `systems` from `omega0[i]`, `q0[i]` (one row each), as
/// [`plan_batch`] plans the free body's.
///
/// # Errors
/// As [`plan_batch`], naming the row.
pub fn plan_systems(
    systems: &[System],
    omega0: &[[f64; 3]],
    q0: &[[f64; 4]],
    options: &RunOptions,
) -> Result<BatchPlan> {
    let o = options;
    shared_step(systems.len(), o.method, o.dt, o.rtol, |dt| {
        // allocated at once, fallibly (a collect's doubling asked for 32768 plans' room for
        // 20000 rows, beyond what the caller checked, and aborted under a memory limit)
        let mut plans = try_with_capacity(systems.len(), "the step plans", PLANS_HINT)?;
        for i in 0..systems.len() {
            plans.push(
                plan_system(
                    &systems[i],
                    omega0[i],
                    q0[i],
                    o.t_end,
                    o.frames,
                    o.method,
                    dt,
                    o.rtol,
                )
                .map_err(|e| e.in_row(i))?,
            );
        }
        Ok(plans)
    })
}

/// The shared step of `runs` runs whose plans at a step `dt` (`None`: each its own) `plans`
/// makes (see the module docs).
fn shared_step(
    runs: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
    plan_at: impl Fn(Option<f64>) -> Result<Vec<StepPlan>>,
) -> Result<BatchPlan> {
    check_rtol(rtol)?;
    if !method.info().takes_steps() || (dt.is_none() && method.is_adaptive()) {
        let plans = plan_at(dt)?;
        return Ok(BatchPlan {
            dt,
            worst: worst(&plans),
            stiffest: stiffest(&plans),
        });
    }
    if runs == 0 {
        return Ok(BatchPlan {
            dt: Some(dt.unwrap_or(1.0)),
            worst: None,
            stiffest: None,
        });
    }
    let mut plans = plan_at(dt)?;
    let step = plans
        .iter()
        .filter_map(|p| p.dt)
        .fold(f64::INFINITY, f64::min);
    if dt.is_none() && plans.iter().any(|p| p.dt != Some(step)) {
        plans = plan_at(Some(step))?;
    }
    Ok(BatchPlan {
        dt: Some(step),
        worst: worst(&plans),
        stiffest: stiffest(&plans),
    })
}

/// The run with the largest predicted drift (the first of equals) and its plan.
fn worst(plans: &[StepPlan]) -> Option<(usize, StepPlan)> {
    largest(plans, |p| p.predicted_drift)
}

/// The run with the stiffest model (the first of equals) and its plan.
fn stiffest(plans: &[StepPlan]) -> Option<(usize, StepPlan)> {
    largest(plans, |p| p.stiffness / p.rate_bound.max(f64::MIN_POSITIVE))
}

fn largest(plans: &[StepPlan], key: impl Fn(&StepPlan) -> f64) -> Option<(usize, StepPlan)> {
    let mut best: Option<(usize, StepPlan)> = None;
    for (i, p) in plans.iter().enumerate() {
        if best.is_none_or(|(_, b)| key(p) > key(&b)) {
            best = Some((i, *p));
        }
    }
    best
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
