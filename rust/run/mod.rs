//! Driving a fixed-step method over a frame grid, and the one entry point `simulate`.
//!
//! Frames fall exactly at `t_end · i / (frames − 1)`. Between two frames the run takes equal
//! substeps no longer than `dt`. Only frames reach the observers' storage, so the memory of a
//! run is set by `frames`, never by the step count.

pub mod adaptive;
pub mod step_size;

use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::{state_from, FreeRigidBody, State};
use crate::error::{Error, Result};
use crate::exact::ExactMotion;
use crate::float::RateScale;
use crate::integrators::{Dop853, Dopri5, Rk4};
use crate::observe::{Drift, DriftMonitor, FlipDetector, FrameRecorder, Observer};
use crate::ode::{Stats, Stepper};
use crate::rigid::{Rk4Projected, Splitting2, Splitting4};
use crate::run::adaptive::{integrate_adaptive, Adaptive};

mod models;

pub use models::{
    model_step, simulate_model, simulate_models, ModelMethod, ModelOutput, MODEL_METHODS,
};

/// What to do about a run that diverged.
pub(crate) const DIVERGED_HINT: &str =
    "the step is far beyond the method's stability limit; take a smaller dt";

/// Steps between two looks at the cancel flag and the state's finiteness (about 0.4 ms of RK4).
pub(crate) const CHECK_EVERY: u64 = 1 << 14;

/// The frame times of a run and the substeps between them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameGrid {
    t_end: f64,
    frames: usize,
    substeps: u64,
}

impl FrameGrid {
    /// `frames` frames over `[0, t_end]` with substeps no longer than `dt`.
    ///
    /// # Errors
    /// `t_end` and `dt` must be positive and finite, `frames` at least 2, and the run's total
    /// step count at most `max_steps`.
    ///
    /// # Example
    /// ```
    /// let grid = dzhanibekov::run::FrameGrid::try_new(100.0, 201, 1e-3, u64::MAX).unwrap();
    /// assert_eq!(grid.n_steps(), 100_000);
    /// assert_eq!(grid.time(200), 100.0);
    /// ```
    pub fn try_new(t_end: f64, frames: usize, dt: f64, max_steps: u64) -> Result<Self> {
        if !(t_end.is_finite() && t_end > 0.0) {
            return Err(Error::invalid(
                "t_end",
                "must be positive and finite",
                t_end,
            ));
        }
        if frames < 2 {
            return Err(Error::invalid("frames", "must be at least 2", frames));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid("dt", "must be positive and finite", dt));
        }
        let intervals = (frames - 1) as f64;
        let substeps = (t_end / intervals / dt).ceil().max(1.0);
        let total = substeps * intervals;
        if total.is_nan() || total > max_steps as f64 {
            return Err(Error::TooLarge {
                what: "the run",
                needed: format!("{total:.3e} steps (t_end / dt)"),
                limit: format!("max_steps = {max_steps}"),
                hint: "raise max_steps, or take a larger dt",
            });
        }
        Ok(Self {
            t_end,
            frames,
            substeps: substeps as u64,
        })
    }

    /// Frames only, for a method that takes no steps (`method = "exact"`).
    ///
    /// # Errors
    /// `t_end` must be positive and finite, and `frames` at least 2.
    pub fn try_frames(t_end: f64, frames: usize) -> Result<Self> {
        let mut grid = Self::try_new(t_end, frames, t_end, u64::MAX)?;
        grid.substeps = 0;
        Ok(grid)
    }

    /// The frames alone, for a method that chooses its own steps: one "substep" per frame.
    ///
    /// # Errors
    /// As [`FrameGrid::try_new`] for `t_end` and `frames`.
    pub fn frames_only(t_end: f64, frames: usize) -> Result<Self> {
        Self::try_new(t_end, frames, t_end.max(f64::MIN_POSITIVE), u64::MAX)
    }

    pub fn frames(&self) -> usize {
        self.frames
    }

    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Substeps between consecutive frames.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// Steps in the whole run.
    pub fn n_steps(&self) -> u64 {
        self.substeps * (self.frames as u64 - 1)
    }

    /// The time of frame `i`; exactly `t_end` for the last.
    pub fn time(&self, i: usize) -> f64 {
        self.t_end * (i as f64 / (self.frames - 1) as f64)
    }

    /// The step actually taken, at most the `dt` asked for; 0 for a grid without steps.
    pub fn step_size(&self) -> f64 {
        if self.substeps == 0 {
            return 0.0;
        }
        self.t_end / (self.frames - 1) as f64 / self.substeps as f64
    }
}

/// Integrates `sys` from `x0` over `grid` with a fixed-step method, showing frames (and steps,
/// if asked) to `obs`. Returns the final state (in the method's own variables, see
/// [`Stepper::to_internal`]) and the run's cost.
///
/// # Errors
/// [`Error::Interrupted`] soon after `cancel` is set; [`Error::Diverged`] if the state stops
/// being finite.
pub fn integrate<M, O>(
    method: &M,
    sys: &FreeRigidBody,
    x0: State,
    grid: &FrameGrid,
    obs: &mut O,
    cancel: &AtomicBool,
) -> Result<(State, Stats)>
where
    M: Stepper<7, FreeRigidBody>,
    O: Observer,
{
    obs.frame(0, 0.0, &x0);
    let mut x = method.to_internal(sys, &x0);
    let n = grid.substeps();
    for i in 1..grid.frames() {
        let (ta, tb) = (grid.time(i - 1), grid.time(i));
        let h = (tb - ta) / n as f64;
        let mut done = 0;
        while done < n {
            let chunk = (n - done).min(CHECK_EVERY);
            x = advance(method, sys, obs, x, ta, h, done..done + chunk, (n, tb));
            done += chunk;
            check(&x, ta + done as f64 * h, cancel)?;
        }
        obs.frame(i, tb, &method.to_state(sys, &x));
    }
    let n_steps = grid.n_steps();
    Ok((
        x,
        Stats {
            nfev: n_steps * M::RHS_PER_STEP,
            n_steps,
            n_rejected: 0,
        },
    ))
}

/// Steps `range` of the `n` substeps from `ta` (the last lands exactly on `tb`). The state
/// goes in and out by value so that it lives in registers across the loop.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn advance<M, O>(
    method: &M,
    sys: &FreeRigidBody,
    obs: &mut O,
    mut x: State,
    ta: f64,
    h: f64,
    range: std::ops::Range<u64>,
    (n, tb): (u64, f64),
) -> State
where
    M: Stepper<7, FreeRigidBody>,
    O: Observer,
{
    for k in range {
        let t = ta + k as f64 * h;
        if O::WANTS_STEPS {
            let before = method.to_state(sys, &x);
            method.step(sys, t, h, &mut x);
            let t1 = if k + 1 == n { tb } else { t + h };
            obs.step(t, &before, t1, &method.to_state(sys, &x));
        } else {
            method.step(sys, t, h, &mut x);
        }
    }
    x
}

#[inline]
fn check(x: &State, t: f64, cancel: &AtomicBool) -> Result<()> {
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Interrupted);
    }
    if !x.iter().all(|v| v.is_finite()) {
        return Err(Error::Diverged {
            t,
            hint: DIVERGED_HINT,
        });
    }
    Ok(())
}

/// The integration methods on offer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Classic fixed-step fourth-order Runge–Kutta, the paper's method.
    Rk4,
    /// The closed-form solution ([`crate::exact`]): frames evaluated directly, no steps.
    Exact,
    /// RK4, each step projected back onto the energy, `|L|`, `L_world` and `|q| = 1`.
    Rk4Projected,
    /// Strang's splitting into exact rotations about the body axes (order 2).
    Splitting,
    /// Suzuki's composition of the splitting (order 4).
    Splitting4,
    /// Dormand–Prince 5(4) with error control and dense output.
    Dopri5(Adaptive),
    /// DOP853: Dormand–Prince 8(5,3) with error control and dense output.
    Dop853(Adaptive),
}

impl Method {
    /// The method's name, as `FromStr` reads it.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 => "rk4",
            Method::Exact => "exact",
            Method::Rk4Projected => "rk4_projected",
            Method::Splitting => "splitting",
            Method::Splitting4 => "splitting4",
            Method::Dopri5(_) => "dopri5",
            Method::Dop853(_) => "dop853",
        }
    }

    /// Whether the method chooses its own steps (then `dt` is only the first one tried).
    pub fn is_adaptive(&self) -> bool {
        matches!(self, Method::Dopri5(_) | Method::Dop853(_))
    }

    /// The same method with adaptive `settings` (unchanged for a fixed-step method).
    pub fn with_adaptive(self, settings: Adaptive) -> Self {
        match self {
            Method::Dopri5(_) => Method::Dopri5(settings),
            Method::Dop853(_) => Method::Dop853(settings),
            fixed => fixed,
        }
    }

    /// The order of the method's global error (`u32::MAX` for the exact solution, which has
    /// no truncation error).
    pub fn order(&self) -> u32 {
        match self {
            Method::Rk4 | Method::Rk4Projected | Method::Splitting4 => 4,
            Method::Splitting => 2,
            Method::Dopri5(_) => 5,
            Method::Dop853(_) => 8,
            Method::Exact => u32::MAX,
        }
    }
}

impl FromStr for Method {
    type Err = Error;

    /// The method of the given name, adaptive ones with default tolerances.
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "rk4" => Ok(Method::Rk4),
            "exact" => Ok(Method::Exact),
            "rk4_projected" => Ok(Method::Rk4Projected),
            "splitting" => Ok(Method::Splitting),
            "splitting4" => Ok(Method::Splitting4),
            "dopri5" => Ok(Method::Dopri5(Adaptive::default())),
            "dop853" => Ok(Method::Dop853(Adaptive::default())),
            other => Err(Error::invalid(
                "method",
                "must be one of 'rk4', 'rk4_projected', 'splitting', 'splitting4', 'dopri5', \
                 'dop853', 'exact'",
                other,
            )),
        }
    }
}

/// What a run should keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Keep {
    /// ω and q at every frame.
    pub frames: bool,
    /// The flip times.
    pub flips: bool,
}

/// A run's output: only what [`Keep`] asked for is filled.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// `(frames, 3)` body rates, time-major; empty unless frames were kept.
    pub omega: Vec<f64>,
    /// `(frames, 4)` quaternions, scalar first; empty unless frames were kept.
    pub q: Vec<f64>,
    pub flip_times: Vec<f64>,
    pub drift: Drift,
    pub stats: Stats,
    /// The step actually taken; for an adaptive method, the mean accepted step.
    pub dt: f64,
}

/// Simulates the free rotation of `body` from body rates `omega0` and attitude `q0`
/// (normalised here) over `grid`.
///
/// Rates of any size are integrated in the motion's own units (see [`crate::float`]), so
/// that rates of 1e-300 or 1e300 neither underflow nor overflow in Euler's products; moments
/// likewise, over a power of two near the largest.
///
/// # Errors
/// Non-finite `omega0`, a zero or non-finite `q0`, a span `t_end · max|ω₀|` beyond float64,
/// and the errors of [`integrate`].
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
/// let body = dzhanibekov::RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
/// let grid = FrameGrid::try_new(100.0, 201, 1e-3, u64::MAX).unwrap();
/// let keep = Keep { frames: true, flips: true };
/// let out = simulate(&body, [0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0], &grid, Method::Rk4, keep,
///                    &AtomicBool::new(false)).unwrap();
/// assert_eq!(out.q.len(), 201 * 4);
/// assert!(out.drift.q_norm < 1e-9);
/// assert!(!out.flip_times.is_empty());
/// ```
pub fn simulate(
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    if !omega0.iter().all(|w| w.is_finite()) {
        return Err(Error::invalid(
            "omega0",
            "must be three finite body rates",
            omega0,
        ));
    }
    if let Some(unit) = crate::float::unit_body(body) {
        return simulate(&unit, omega0, q0, grid, method, keep, cancel);
    }
    let scale = RateScale::of(omega0);
    if !scale.is_identity() {
        normalized(q0)?; // refused before anything else, as unscaled; normalised once, inside
        return simulate_scaled(body, omega0, q0, grid, method, keep, cancel, scale);
    }
    let q0 = normalized(q0)?;
    let sys = FreeRigidBody::new(*body);
    let omega = Vector3::from(omega0);
    let recorder = match keep.frames {
        true => Some(FrameRecorder::with_frames(grid.frames())?),
        false => None,
    };
    let mut obs = (DriftMonitor::new(body, &omega), recorder);
    if matches!(method, Method::Exact) {
        return simulate_exact(body, omega0, q0, grid, keep, obs, cancel);
    }
    let x0 = state_from(omega0, q0);
    // Flip detection looks at every step; without it the step loop stays bare.
    let (stats, flip_times) = if keep.flips {
        let mut flips = FlipDetector::new(body, &sys.euler_coefficients(), &omega);
        let stats = run_method(method, &sys, x0, grid, &mut (&mut obs, &mut flips), cancel)?;
        (stats, flips.flip_times)
    } else {
        (
            run_method(method, &sys, x0, grid, &mut obs, cancel)?,
            Vec::new(),
        )
    };
    let dt = if method.is_adaptive() {
        grid.t_end() / stats.n_steps.max(1) as f64
    } else {
        grid.step_size()
    };
    finished(obs, flip_times, stats, dt, grid)
}

/// The grid and method of a run from `omega0` in the units of `scale` (see [`crate::float`]):
/// times (the span, an adaptive method's first step) multiplied by `2^e`.
///
/// # Errors
/// A span `t_end · max|ω₀|` that float64 cannot hold.
pub(crate) fn to_unit(
    grid: &FrameGrid,
    method: Method,
    omega0: [f64; 3],
    scale: RateScale,
) -> Result<(FrameGrid, Method)> {
    let t_end = scale.time_to_unit(grid.t_end);
    if !t_end.is_finite() {
        return Err(Error::TooLarge {
            what: "the run",
            needed: format!(
                "t_end · max|omega0| = {:.3e} · {:.3e} radians",
                grid.t_end,
                omega0.iter().fold(0.0_f64, |m, w| m.max(w.abs()))
            ),
            limit: "what float64 holds".into(),
            hint: "take a shorter t_end",
        });
    }
    // A span that underflows is one in which nothing moves that float64 can show.
    let unit_grid = FrameGrid {
        t_end: t_end.max(f64::from_bits(1)),
        ..*grid
    };
    // an adaptive method's first step is a time too
    let method = match method {
        Method::Dopri5(a) | Method::Dop853(a) => method.with_adaptive(Adaptive {
            first_step: a
                .first_step
                .map(|h| scale.time_to_unit(h))
                .filter(|h| h.is_finite() && *h > 0.0),
            ..a
        }),
        fixed => fixed,
    };
    Ok((unit_grid, method))
}

/// `drift`, or [`Error::Diverged`] at `t_end` when an invariant overflowed: past the
/// stability limit a short run can end finite but so large that its energy is not, and that
/// run diverged, whatever the cheap checks in the step loop saw.
pub(crate) fn finite_drift(drift: Drift, t_end: f64) -> Result<Drift> {
    match [
        drift.energy,
        drift.momentum,
        drift.momentum_world,
        drift.q_norm,
    ]
    .iter()
    .all(|v| v.is_finite())
    {
        true => Ok(drift),
        false => Err(Error::Diverged {
            t: t_end,
            hint: DIVERGED_HINT,
        }),
    }
}

/// A time of a run in the units of `scale` back in the user's, within the user's span (NaN,
/// "no such time", stays NaN).
pub(crate) fn time_from_unit(scale: RateScale, t: f64, t_end: f64) -> f64 {
    match t.is_nan() {
        true => t,
        false => scale.time_from_unit(t).min(t_end),
    }
}

/// [`simulate`] in the motion's own units: rates over `2^e`, times times `2^e`, and back.
#[allow(clippy::too_many_arguments)]
fn simulate_scaled(
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
    scale: RateScale,
) -> Result<RunOutput> {
    let (unit_grid, method) = to_unit(grid, method, omega0, scale)?;
    let mut out = simulate(
        body,
        omega0.map(|w| scale.rate_to_unit(w)),
        q0,
        &unit_grid,
        method,
        keep,
        cancel,
    )?;
    for w in &mut out.omega {
        *w = scale.rate_from_unit(*w);
    }
    // An integrator's frame 0 is the start as given: components below 2^-1074 of the largest
    // rate round in the run's own units (and move it by that much), the start itself does
    // not. (The exact method's frame 0 is its closed form at t = 0, scaled like the rest.)
    if let (Some(first), false) = (out.omega.get_mut(..3), matches!(method, Method::Exact)) {
        first.copy_from_slice(&omega0);
    }
    if !out.omega.iter().all(|w| w.is_finite()) {
        return Err(Error::Diverged {
            t: grid.t_end,
            hint: "the body rates `omega0` are too large for float64",
        });
    }
    for t in &mut out.flip_times {
        *t = time_from_unit(scale, *t, grid.t_end);
    }
    out.dt = scale.time_from_unit(out.dt);
    Ok(out)
}

/// Frames evaluated from the closed form at the frame times: no steps, the same observers,
/// flip times from the solution by the detector's definition.
fn simulate_exact(
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    keep: Keep,
    mut obs: (DriftMonitor, Option<FrameRecorder>),
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    let motion = ExactMotion::try_new(body, omega0, q0)?;
    for i in 0..grid.frames() {
        if (i as u64).is_multiple_of(CHECK_EVERY) && cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        let t = grid.time(i);
        let x = motion.state_at(t);
        if !x.iter().all(|v| v.is_finite()) {
            return Err(Error::TooLarge {
                what: "the exact solution",
                needed: format!("its phase at t = {t:.3e} (t_end · max|omega0| radians)"),
                limit: "what float64 holds".into(),
                hint: "take a shorter t_end",
            });
        }
        obs.frame(i, t, &x);
    }
    let flip_times = match keep.flips {
        true => motion.flip_times(grid.t_end())?,
        false => Vec::new(),
    };
    finished(obs, flip_times, Stats::default(), 0.0, grid)
}

/// The output of a run from what its observers saw.
///
/// # Errors
/// Invariants that overflowed (see [`finite_drift`]).
fn finished(
    (drift, frames): (DriftMonitor, Option<FrameRecorder>),
    flip_times: Vec<f64>,
    stats: Stats,
    dt: f64,
    grid: &FrameGrid,
) -> Result<RunOutput> {
    let drift = finite_drift(drift.drift, grid.t_end())?;
    let frames = frames.unwrap_or_default();
    Ok(RunOutput {
        omega: frames.omega,
        q: frames.q,
        flip_times,
        drift,
        stats,
        dt,
    })
}

/// Runs `method` over `grid` from `x0`, showing frames (and steps, if asked) to `obs`.
pub(crate) fn run_method<O: Observer>(
    method: Method,
    sys: &FreeRigidBody,
    x0: State,
    grid: &FrameGrid,
    obs: &mut O,
    cancel: &AtomicBool,
) -> Result<Stats> {
    let body = sys.body();
    let (_, stats) = match method {
        Method::Rk4 => integrate(&Rk4, sys, x0, grid, obs, cancel)?,
        // `simulate` evaluates the exact solution before it gets here: nothing to step.
        Method::Exact => (x0, Stats::default()),
        Method::Rk4Projected => {
            integrate(&Rk4Projected::new(body, &x0), sys, x0, grid, obs, cancel)?
        }
        Method::Splitting => integrate(&Splitting2::new(body, &x0), sys, x0, grid, obs, cancel)?,
        Method::Splitting4 => integrate(&Splitting4::new(body, &x0), sys, x0, grid, obs, cancel)?,
        Method::Dopri5(a) => integrate_adaptive(&Dopri5, sys, x0, grid, &a, obs, cancel)?,
        Method::Dop853(a) => integrate_adaptive(&Dop853, sys, x0, grid, &a, obs, cancel)?,
    };
    Ok(stats)
}

/// `q / |q|`.
///
/// # Errors
/// A zero or non-finite quaternion.
pub fn normalized(q: [f64; 4]) -> Result<[f64; 4]> {
    let largest = q.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(largest.is_finite() && largest > 0.0) {
        return Err(Error::invalid(
            "q0",
            "must be a finite, non-zero quaternion (Q, U, V, W)",
            q,
        ));
    }
    // Scale first so that the norm neither overflows nor underflows.
    let s = q.map(|c| c / largest);
    let n = s.iter().map(|c| c * c).sum::<f64>().sqrt();
    Ok(s.map(|c| c / n))
}
