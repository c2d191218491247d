//! Sweeps: many runs that each keep a few numbers — the flips counted, the largest tilt of
//! the spin axis, the invariants' drift, the exact flip period — and no frames, so that a
//! sweep's memory grows with its runs, never with their frames or steps.
//!
//! RK4 runs in SIMD lanes as a batch does ([`crate::ensemble::batch`]); other methods as single runs
//! on all cores. A row's numbers equal those of the single run of its inputs bit for bit
//! (its flips those of [`crate::run::simulate`], its tilt that of a [`crate::observe::tilt::TiltMonitor`] shown
//! every step), whatever the number of threads and however the rows are cut into blocks.

use std::sync::atomic::AtomicBool;

use rayon::prelude::*;

use crate::ensemble::batch::{
    needs_scaling, run_group, FlipTally, Options, Start, Stop, Watch, LANES,
};
use crate::error::{Error, Result};
use crate::exact::{flip_period, flip_period_of_rates, representable_period};
use crate::observe::Drift;
use crate::ode::Stats;
use crate::run::{simulate, FrameGrid, Keep, Method};

/// What one run of a sweep measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSummary {
    /// The flips: how many, the first and the last (see [`crate::observe::FlipDetector`]).
    pub flips: FlipTally,
    /// The largest tilt of the spin axis, radians in `[0, π]` (see [`crate::observe::tilt`]).
    pub tilt: f64,
    /// The exact flip period `2K(m)/λ` of the start ([`flip_period`]); `inf` for a motion
    /// that never flips.
    pub exact_period: f64,
    /// The invariants' largest drift over the frames.
    pub drift: Drift,
    pub stats: Stats,
    /// The step taken; for an adaptive method the mean accepted step, 0 for `exact`.
    pub dt: f64,
    /// Whether the run finished; if not, its numbers are NaN (its flip count 0), all but
    /// the exact period, which is the start's.
    pub status: RunStatus,
}

/// How a run of a sweep ended. A sweep keeps going past runs that did not finish.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum RunStatus {
    Ok = 0,
    /// The state stopped being finite (a step beyond the method's stability limit), or an
    /// adaptive step fell below round-off.
    Diverged = 1,
    /// An adaptive run needed more than `max_steps` step attempts.
    TooManySteps = 2,
    /// More flips than a run may return.
    TooManyFlips = 3,
}

impl RunStatus {
    /// Every status, by its code.
    pub const ALL: [RunStatus; 4] = [
        RunStatus::Ok,
        RunStatus::Diverged,
        RunStatus::TooManySteps,
        RunStatus::TooManyFlips,
    ];

    /// The status in words, as Python shows it.
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Ok => "ok",
            RunStatus::Diverged => "diverged",
            RunStatus::TooManySteps => "too many steps",
            RunStatus::TooManyFlips => "too many flips",
        }
    }

    /// The status of a run that failed with `error`; `None` for errors that stop the sweep
    /// (bad input, an interruption).
    fn of(error: &Error) -> Option<Self> {
        match error {
            Error::Row { error, .. } => Self::of(error),
            Error::Diverged { .. } | Error::EnergyGrew { .. } => Some(RunStatus::Diverged),
            Error::TooLarge { what, .. } if what.contains("flip") => Some(RunStatus::TooManyFlips),
            Error::TooLarge { .. } => Some(RunStatus::TooManySteps),
            Error::InvalidArgument { .. } | Error::Unsupported { .. } | Error::Interrupted => None,
        }
    }
}

impl RunSummary {
    /// The flips counted, or −1 for a run that did not finish: never mistaken for a stable
    /// one.
    pub fn flip_count(&self) -> i64 {
        match self.status {
            RunStatus::Ok => self.flips.count as i64,
            _ => -1,
        }
    }

    /// The summary of a run of `start` that ended with `status` before its end.
    fn failed(start: &Start, status: RunStatus) -> Result<Self> {
        Ok(Self {
            flips: FlipTally {
                count: 0,
                first: f64::NAN,
                last: f64::NAN,
            },
            tilt: f64::NAN,
            exact_period: exact_period(start)?,
            drift: Drift {
                energy: f64::NAN,
                momentum: f64::NAN,
                momentum_world: f64::NAN,
                q_norm: f64::NAN,
                jacobi: None,
                energy_balance: None,
                kept: crate::dynamics::Conserved::FREE,
            },
            stats: Stats::default(),
            dt: f64::NAN,
            status,
        })
    }
}

/// `run`, or the summary of a run that ended early with a status the sweep records and
/// goes on (naming the row for errors that stop it).
fn kept(start: &Start, row: usize, run: Result<RunSummary>) -> Result<RunSummary> {
    match run {
        Ok(run) => Ok(run),
        Err(e) => match RunStatus::of(&e) {
            Some(status) => RunSummary::failed(start, status).map_err(|e| e.in_row(row)),
            None => Err(e.in_row(row)),
        },
    }
}

/// Runs every start over `grid` and summarises each run, on all cores.
///
/// The frames of `grid` only set the substeps (and where the drift is measured); none are
/// kept. With `method = Exact` the tilt is measured at the frames, the only states it
/// evaluates.
///
/// A run that diverges or needs too many steps does not stop the others: its summary has
/// NaN numbers and a [`RunStatus`] saying why.
///
/// # Errors
/// A row's invalid input, naming the row ([`Error::Row`]); [`Error::Interrupted`] soon
/// after `cancel` is set.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use dzhanibekov::ensemble::batch::{Options, Start};
/// use dzhanibekov::run::{FrameGrid, Method};
/// use dzhanibekov::ensemble::sweep::sweep;
/// let grid = FrameGrid::try_new(100.0, 2, 1e-3, u64::MAX).unwrap();
/// let paper = [52.0833, 27.0833, 41.6666];
/// let starts = [Start::try_new(paper, [0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]).unwrap()];
/// let runs = sweep(&starts, &grid, Method::Rk4, &Options::default(), &AtomicBool::new(false)).unwrap();
/// assert_eq!(runs[0].flips.count, 2);
/// assert!((runs[0].flips.last - runs[0].flips.first - runs[0].exact_period).abs() < 1e-3);
/// assert!(runs[0].tilt > 3.0); // the spin axis turned over
/// ```
pub fn sweep(
    starts: &[Start],
    grid: &FrameGrid,
    method: Method,
    options: &Options,
    cancel: &AtomicBool,
) -> Result<Vec<RunSummary>> {
    let isa = options.isa()?;
    // the summaries, held twice (per block, then in order), and the columns made from them
    let per_run = 2 * std::mem::size_of::<RunSummary>() + 16 * std::mem::size_of::<f64>();
    crate::buffer::ensure_room(
        starts.len() as f64 * per_run as f64,
        "the sweep's results",
        "sweep fewer starts at a time",
    )?;
    let stop = Stop::new(cancel);
    let m = starts.len();
    options.install(m, || {
        let parts: Vec<Result<Vec<RunSummary>>> = if method.info().batch {
            starts
                .par_chunks(LANES)
                .enumerate()
                .map(|(g, group)| {
                    stop.watch(lane_group(isa, method, group, g * LANES, grid, &stop))
                })
                .collect()
        } else {
            starts
                .par_iter()
                .enumerate()
                .map(|(i, start)| {
                    stop.check()?;
                    let run = kept(start, i, single(start, grid, method, cancel));
                    stop.watch(run.map(|r| vec![r]))
                })
                .collect()
        };
        let parts = stop.gather(parts)?;
        crate::buffer::try_collect(
            parts.into_iter().flatten(),
            m,
            "the runs' results",
            "run fewer starts at a time",
        )
    })
}

fn lane_group(
    isa: crate::ensemble::lanes::Isa,
    method: Method,
    group: &[Start],
    first_row: usize,
    grid: &FrameGrid,
    stop: &Stop,
) -> Result<Vec<RunSummary>> {
    let watch = Watch {
        flips: true,
        tilt: true,
        count_only: true,
    };
    let alone = || {
        group
            .iter()
            .enumerate()
            .map(|(l, start)| {
                stop.check()?;
                let run = single(start, grid, method, stop.cancel);
                stop.watch(kept(start, first_row + l, run))
            })
            .collect()
    };
    if group.iter().any(needs_scaling) {
        // as a batch does: such rows run alone, in their own units
        return alone();
    }
    let runs = match run_group(isa, group, first_row, grid, watch, None, stop) {
        Ok(runs) => runs,
        // A run of the group failed: each runs alone (bit for bit its lane), so that the
        // others keep their numbers and the failed one gets its status.
        Err(e) if RunStatus::of(&e).is_some() => return alone(),
        Err(e) => return Err(e),
    };
    let n_steps = grid.n_steps();
    group
        .iter()
        .zip(runs)
        .enumerate()
        .map(|(l, (start, run))| {
            Ok(RunSummary {
                flips: run.flips,
                tilt: run.tilt,
                exact_period: exact_period(start).map_err(|e| e.in_row(first_row + l))?,
                drift: run.drift,
                stats: Stats {
                    nfev: method.info().rhs_per_step * n_steps,
                    n_steps,
                    n_rejected: 0,
                },
                dt: grid.step_size(),
                status: RunStatus::Ok,
            })
        })
        .collect()
}

/// The exact flip period of a start, from its rates alone where that decides it.
fn exact_period(start: &Start) -> Result<f64> {
    match flip_period_of_rates(&start.body, start.omega0) {
        Some(period) => representable_period(period, start.omega0),
        None => flip_period(&start.body, start.omega0),
    }
}

/// One run alone, by the one driver ([`crate::run::simulate`]: in the motion's own units for
/// rates far from 1), keeping its flips and tilt.
fn single(
    start: &Start,
    grid: &FrameGrid,
    method: Method,
    cancel: &AtomicBool,
) -> Result<RunSummary> {
    let exact_period = exact_period(start)?;
    let keep = Keep {
        frames: false,
        flips: true,
        tilt: true,
    };
    let run = simulate(
        &start.body,
        start.omega0,
        start.q0,
        grid,
        method,
        keep,
        cancel,
    )?;
    let mut flips = FlipTally::default();
    flips.absorb(&run.flip_times);
    Ok(RunSummary {
        flips,
        tilt: run.tilt,
        exact_period,
        drift: run.drift,
        stats: run.stats,
        dt: run.dt,
        status: RunStatus::Ok,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{state_from, FreeRigidBody};
    use crate::integrators::Rk4;
    use crate::kinematics::normalized;
    use crate::observe::tilt::TiltMonitor;
    use crate::run::integrate;
    use nalgebra::Vector3;

    #[test]
    fn a_run_that_diverges_gets_its_status_and_the_others_their_numbers() {
        let paper = [52.0833, 27.0833, 41.6666];
        let rates = [[0.0, 0.1, 1.0], [0.0, 1e3, 1.0], [0.1, 0.0, 1.0]];
        let starts: Vec<Start> = rates
            .iter()
            .map(|w| Start::try_new(paper, *w, [1.0, 0.0, 0.0, 0.0]).unwrap())
            .collect();
        // dt = 0.5 is far beyond RK4's stability limit for |ω| = 1000 only
        let grid = FrameGrid::try_new(100.0, 2, 0.5, u64::MAX).unwrap();
        let cancel = AtomicBool::new(false);
        let runs = sweep(&starts, &grid, Method::Rk4, &Options::default(), &cancel).unwrap();
        let status: Vec<_> = runs.iter().map(|r| r.status).collect();
        assert_eq!(
            status,
            [RunStatus::Ok, RunStatus::Diverged, RunStatus::Ok],
            "{runs:?}"
        );
        assert!(runs[1].tilt.is_nan() && runs[1].drift.energy.is_nan() && runs[1].dt.is_nan());
        for i in [0, 2] {
            let alone = sweep(
                &starts[i..=i],
                &grid,
                Method::Rk4,
                &Options::default(),
                &cancel,
            );
            assert_eq!(alone.unwrap()[0], runs[i]);
        }
    }

    #[test]
    fn tilt_in_lanes_is_that_of_a_monitor_shown_every_step() {
        let bodies = [
            [52.0833, 27.0833, 41.6666],
            [1.0, 2.0, 3.0],
            [3.0, 1.0, 2.5],
        ];
        let starts: Vec<Start> = (0..21)
            .map(|i| {
                let f = i as f64;
                let omega = [0.4 * (1.1 * f).sin(), 0.6 * (0.5 * f).cos(), 1.0 - 0.03 * f];
                Start::try_new(bodies[i % 3], omega, [1.0, 0.1 * f, 0.0, -0.2]).unwrap()
            })
            .collect();
        let grid = FrameGrid::try_new(50.0, 3, 5e-3, u64::MAX).unwrap();
        let cancel = AtomicBool::new(false);
        let runs = sweep(&starts, &grid, Method::Rk4, &Options::default(), &cancel).unwrap();
        let mut turned = 0;
        for (s, run) in starts.iter().zip(&runs) {
            let sys = FreeRigidBody::new(s.body);
            let mut tilt = TiltMonitor::new(&s.body, &Vector3::from(s.omega0));
            let x0 = state_from(s.omega0, normalized(s.q0).unwrap());
            integrate(&Rk4, &sys, x0, &grid, &mut tilt, &cancel).unwrap();
            assert_eq!(run.tilt.to_bits(), tilt.tilt().to_bits(), "{s:?}");
            turned += usize::from(run.tilt > std::f64::consts::FRAC_PI_2);
        }
        assert!(
            (3..18).contains(&turned),
            "both kinds should be seen, {turned} turned over"
        );
    }
}
