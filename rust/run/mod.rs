//! Running a method: the one entry point [`simulate`], the drivers ([`fixed`], [`adaptive`])
//! over a frame grid ([`grid`]), the registry of methods ([`registry`]) and the step planner
//! ([`step_size`]).

pub mod adaptive;
pub mod fixed;
pub mod grid;
pub mod registry;
pub mod step_size;
pub mod watchdog;

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::{state_from, FreeRigidBody};
use crate::error::{Error, Result};
use crate::exact::ExactMotion;
use crate::float::RateScale;
use crate::kinematics::normalized;
use crate::observe::tilt::TiltMonitor;
use crate::observe::{Drift, DriftMonitor, FlipDetector, FrameRecorder, Observer};
use crate::ode::controller::Adaptive;
use crate::ode::Stats;

mod models;

pub use fixed::integrate;
pub(crate) use fixed::{CHECK_EVERY, DIVERGED_HINT};
pub(crate) use grid::max_steps_limit;
pub use grid::FrameGrid;
pub use models::{
    model_method_and_grid, model_step, rows_method_and_grid, simulate_model, simulate_models,
    ModelOutput,
};
pub(crate) use registry::run_method;
pub use registry::{Method, MethodInfo, METHODS};

/// The method named `name` and the frame grid of its run: tolerances `rtol`, `atol`, first
/// step `dt` (`None`: picked in the run, for each run of a batch or sweep as alone) and a cap
/// of `max_steps` attempts for an adaptive method; substeps no longer than `dt` and at most
/// `max_steps` of them for a fixed-step one, which needs a `dt`.
///
/// # Errors
/// An unknown name, bad tolerances, no `dt` for a fixed-step method, and the errors of
/// [`FrameGrid::for_method`].
pub fn method_and_grid(
    name: &str,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    max_steps: u64,
    rtol: f64,
    atol: f64,
) -> Result<(Method, FrameGrid)> {
    let method = Method::named(name, rtol, atol, dt)?;
    let dt = match (dt, method.info().step_rule) {
        (Some(dt), _) => dt,
        (None, registry::StepRule::Accuracy { .. }) => {
            return Err(Error::invalid(
                "dt",
                "must be given for a fixed-step method (plan it first)",
                "None",
            ))
        }
        (None, _) => t_end, // not used: no steps, or the method picks them
    };
    let grid = FrameGrid::for_method(&method, t_end, frames, dt, max_steps)?;
    Ok((method.with_max_steps(max_steps), grid))
}

/// What a run should keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Keep {
    /// ω and q at every frame.
    pub frames: bool,
    /// The flip times.
    pub flips: bool,
    /// The largest tilt of the spin axis ([`TiltMonitor`]).
    pub tilt: bool,
}

/// A run's output: only what [`Keep`] asked for is filled.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// `(frames, 3)` body rates, time-major; empty unless frames were kept.
    pub omega: Vec<f64>,
    /// `(frames, 4)` quaternions, scalar first; empty unless frames were kept.
    pub q: Vec<f64>,
    pub flip_times: Vec<f64>,
    /// The largest tilt of the spin axis from where it started, in radians; NaN unless kept.
    pub tilt: f64,
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
/// let keep = Keep { frames: true, flips: true, tilt: false };
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
    // The tilt is watched at every step; without it the step loop stays bare.
    match keep.tilt {
        true => {
            let tilt = TiltMonitor::new(body, &Vector3::from(omega0));
            simulate_unit(body, omega0, q0, grid, method, keep, tilt, cancel)
        }
        false => simulate_unit(body, omega0, q0, grid, method, keep, NoTilt, cancel),
    }
}

/// What a run watches beside the drift and frames: the tilt, or nothing.
trait TiltWatch: Observer {
    fn tilt(&self) -> f64;
}

/// No tilt watched: a bare step loop.
struct NoTilt;

impl Observer for NoTilt {}

impl TiltWatch for NoTilt {
    fn tilt(&self) -> f64 {
        f64::NAN
    }
}

impl TiltWatch for TiltMonitor {
    fn tilt(&self) -> f64 {
        TiltMonitor::tilt(self)
    }
}

/// [`simulate`] of a start in the motion's own units (rates and moments near 1).
#[allow(clippy::too_many_arguments)]
fn simulate_unit<T: TiltWatch>(
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    tilt: T,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    let sys = FreeRigidBody::new(*body);
    let omega = Vector3::from(omega0);
    let recorder = match keep.frames {
        true => Some(FrameRecorder::with_frames(grid.frames())?),
        false => None,
    };
    let mut obs = (DriftMonitor::new(body, &omega), (recorder, tilt));
    if !method.info().takes_steps() {
        return simulate_exact(body, omega0, q0, grid, keep, obs, cancel);
    }
    let x0 = state_from(omega0, q0);
    // Flip detection looks at every step; without it the step loop stays bare.
    let (stats, flip_times) = if keep.flips {
        let mut flips = FlipDetector::new(body, &sys.euler_coefficients(), &omega);
        let stats = run_method(method, &sys, x0, grid, &mut (&mut obs, &mut flips), cancel)?;
        (stats, flips.into_flip_times()?)
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
    let t_end = scale.time_to_unit(grid.t_end());
    if !t_end.is_finite() {
        return Err(Error::TooLarge {
            what: "the run",
            needed: format!(
                "t_end · max|omega0| = {:.3e} · {:.3e} radians",
                grid.t_end(),
                omega0.iter().fold(0.0_f64, |m, w| m.max(w.abs()))
            ),
            limit: "what float64 holds".into(),
            hint: "take a shorter t_end",
        });
    }
    // A span that underflows is one in which nothing moves that float64 can show.
    let unit_grid = grid.with_t_end(t_end.max(f64::from_bits(1)));
    // an adaptive method's first step is a time too
    let method = match method.adaptive_settings() {
        Some(a) => method.with_adaptive(Adaptive {
            first_step: a
                .first_step
                .map(|h| scale.time_to_unit(h))
                .filter(|h| h.is_finite() && *h > 0.0),
            ..a
        }),
        None => method,
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

/// `error` of a run integrated in the units of `scale`, with a divergence time back in the
/// user's units (within the user's span).
pub(crate) fn error_from_unit(error: Error, scale: RateScale, t_end: f64) -> Error {
    match error {
        Error::Diverged { t, hint } => Error::Diverged {
            t: time_from_unit(scale, t, t_end),
            hint,
        },
        other => other,
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
    )
    .map_err(|e| error_from_unit(e, scale, grid.t_end()))?;
    for w in &mut out.omega {
        *w = scale.rate_from_unit(*w);
    }
    // An integrator's frame 0 is the start as given: components below 2^-1074 of the largest
    // rate round in the run's own units (and move it by that much), the start itself does
    // not. (The exact method's frame 0 is its closed form at t = 0, scaled like the rest.)
    if let (Some(first), false) = (out.omega.get_mut(..3), !method.info().takes_steps()) {
        first.copy_from_slice(&omega0);
    }
    if !out.omega.iter().all(|w| w.is_finite()) {
        return Err(Error::Diverged {
            t: grid.t_end(),
            hint: "the body rates `omega0` are too large for float64",
        });
    }
    for t in &mut out.flip_times {
        *t = time_from_unit(scale, *t, grid.t_end());
    }
    out.dt = scale.time_from_unit(out.dt);
    Ok(out)
}

/// Frames evaluated from the closed form at the frame times: no steps, the same observers,
/// flip times from the solution by the detector's definition.
fn simulate_exact<T: TiltWatch>(
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    keep: Keep,
    mut obs: Watched<T>,
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
fn finished<T: TiltWatch>(
    (drift, (frames, tilt)): Watched<T>,
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
        tilt: tilt.tilt(),
        drift,
        stats,
        dt,
    })
}

/// The observers of every run: the drift, the frames if kept, the tilt if watched.
type Watched<T> = (DriftMonitor, (Option<FrameRecorder>, T));
