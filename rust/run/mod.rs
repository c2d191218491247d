//! Running a method: the one entry point [`simulate`], the drivers ([`fixed`], [`adaptive`])
//! over a frame grid ([`grid`]), the registry of methods ([`registry`]) and the step planner
//! ([`step_size`]).

pub mod adaptive;
pub mod evaluate;
pub mod fixed;
pub mod grid;
pub mod options;
pub mod progress;
pub mod registry;
pub mod step_size;
pub(crate) mod system;
pub mod watchdog;

use std::sync::atomic::AtomicBool;

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::{state_from, FreeRigidBody, Model};
use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::normalized;
use crate::observe::tilt::TiltMonitor;
use crate::observe::{
    Drift, DriftMonitor, End, FlatAxes, FlatSpin, FlipDetector, LastFrame, Observer, Recorder,
};
use crate::ode::controller::Adaptive;
use crate::ode::Stats;

pub use fixed::integrate;
pub(crate) use fixed::{CHECK_EVERY, DIVERGED_HINT};
pub(crate) use grid::max_steps_limit;
pub use grid::FrameGrid;
pub use registry::{Method, MethodInfo, Runs, METHODS};
pub use system::{plan_system, simulate_system, Edge, Planned};

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

/// The relative energy gain at a frame beyond which a fixed-step run of a model that only
/// loses energy (a damped body: [`Model::energy_never_grows`]) has diverged.
///
/// Inside its stability region RK4 damps every linear mode (`|R(z)| < 1` on both axes:
/// [`registry::Stability`]), so a stable run of a damped body loses energy, by the damper and
/// by the method: over 288 runs (four bodies, `dt · Ω` up to 1, far coarser than any step
/// planned for `rtol ≤ 1e-3`, and `hλ` up to 2.7) the energy rose above its start by at most
/// 4.9e-5 (at `dt · Ω = 1`, `hλ = 2.7`), elsewhere by round-off at most. Beyond the damper's
/// limit the slip grows geometrically (by `|R(−hλ)|` a step: 2.2 % at `hλ = 2.8`, 19 % at
/// 2.9), so the threshold moves the frame at which the run is stopped by a few steps only,
/// and RK4's growth can saturate: at `hλ = 2.8` a run ended finite with 614 times its
/// starting energy. 1 % is 200 times the largest gain of a stable run.
pub const ENERGY_GROWTH_TOL: f64 = 1e-2;

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
    /// `(frames, k)` the parts' state (a damper's σ); empty unless frames were kept.
    pub parts: Vec<f64>,
    /// The flip times; empty unless asked for.
    pub flip_times: Vec<f64>,
    /// The largest tilt of the spin axis from where it started, in radians; NaN unless kept.
    pub tilt: f64,
    /// The time the spin went flat ([`crate::observe::flat`]; NaN: not by the end), for a
    /// damped body of constant inertia; `None` for other runs.
    pub flat_time: Option<f64>,
    /// Where the run ended (kept whether or not the frames are).
    pub end: End,
    pub drift: Drift,
    pub stats: Stats,
    /// The step actually taken; for an adaptive method, the mean accepted step.
    pub dt: f64,
}

/// Simulates the free rotation of `body` (principal moments) from body rates `omega0` and
/// attitude `q0` (normalised here) over `grid`: the free body's run in its principal axes, as
/// a batch row or a sweep run takes it ([`simulate_system`] is the run in the user's axes).
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
    check_rates(omega0)?;
    let q0 = normalized(q0)?;
    let body = crate::float::unit_body(body).unwrap_or(*body);
    let sys = FreeRigidBody::new(body);
    let x0 = state_from(omega0, q0);
    // The tilt is watched at every step; without it the step loop stays bare.
    match keep.tilt {
        true => {
            let scale = RateScale::of(omega0);
            let omega = Vector3::from(omega0.map(|w| scale.rate_to_unit(w)));
            let tilt = TiltMonitor::new(&body, &omega);
            simulate_model_with(&sys, x0, grid, method, keep, tilt, cancel)
        }
        false => simulate_model_with(&sys, x0, grid, method, keep, NoTilt, cancel),
    }
}

/// Non-finite body rates, refused.
pub(crate) fn check_rates(omega0: [f64; 3]) -> Result<()> {
    match omega0.iter().all(|w| w.is_finite()) {
        true => Ok(()),
        false => Err(Error::invalid(
            "omega0",
            "must be three finite body rates",
            omega0,
        )),
    }
}

/// Runs the model `sys` (in its own axes, its attitude already normalised) from `x0` at
/// `t = 0` over `grid` with `method`, keeping what `keep` asks (but the tilt, the free body's
/// alone): the one run of every model.
///
/// Rates far from 1 are integrated in the motion's own units (see [`crate::float`]): the
/// model's times ([`Model::in_units`]) and the state's rates scale, and the results back.
///
/// # Errors
/// A non-finite `x0`; a method that cannot run the model ([`Error::Unsupported`]);
/// [`Error::Interrupted`] soon after `cancel` is set; [`Error::Diverged`] if the state stops
/// being finite; [`Error::TooLarge`] beyond a step cap or memory.
pub fn simulate_model<const N: usize, S: Runs<N> + FlatAxes<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    simulate_model_with(sys, x0, grid, method, keep, NoTilt, cancel)
}

/// [`simulate_model`], with the tilt watched by `tilt` (given in the run's own units).
fn simulate_model_with<const N: usize, S: Runs<N> + FlatAxes<N>, T: TiltWatch<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    tilt: T,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    if !x0.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(
            "omega0",
            "must be finite body rates (and q0 a finite quaternion)",
            &x0[..N - 4],
        ));
    }
    method.for_kinds(sys.kinds())?;
    let omega0: [f64; 3] = sys.omega_body(0.0, &x0).into();
    let scale = RateScale::of(omega0);
    if scale.is_identity() {
        return simulate_unit(sys, x0, grid, method, keep, tilt, cancel);
    }
    let (unit_grid, unit_method) = to_unit(grid, method, omega0, scale)?;
    let unit = sys.in_units(scale)?;
    let x = sys.state_in_units(&x0, scale);
    let mut out = simulate_unit(&unit, x, &unit_grid, unit_method, keep, tilt, cancel)
        .map_err(|e| error_from_unit(e, scale, grid.t_end()))?;
    let end = &mut out.end;
    for w in out.omega.iter_mut().chain(end.omega.iter_mut()) {
        *w = scale.rate_from_unit(*w);
    }
    // the parts' state by its dimension (a rate once, a torque twice, an angle not at all)
    let dims = sys.parts_dims();
    if !dims.is_empty() {
        for v in [&mut out.parts, &mut end.parts] {
            for (x, d) in v.iter_mut().zip(dims.iter().cycle()) {
                *x = (0..d.rate).fold(*x, |x, _| scale.rate_from_unit(x));
            }
        }
    }
    // An integrator's frame 0 is the start as given: components below 2^-1074 of the largest
    // rate round in the run's own units (and move it by that much), the start itself does
    // not. (The exact method's frame 0 is its closed form at t = 0, scaled like the rest.)
    if let (Some(first), true) = (out.omega.get_mut(..3), method.info().takes_steps()) {
        first.copy_from_slice(&omega0);
    }
    let mut out = finite_frames(out, grid)?;
    for t in out.flip_times.iter_mut().chain(out.flat_time.as_mut()) {
        *t = time_from_unit(scale, *t, grid.t_end());
    }
    out.dt = scale.time_from_unit(out.dt);
    Ok(out)
}

/// What to say when a run's frames leave float64.
const NON_FINITE_HINT: &str = "its rates, attitude or parts' state left float64: the body \
                               rates `omega0` (or the moments times them) are too large";

/// `out`, or [`Error::Diverged`] at the first frame (or the end) whose rates, attitude or
/// parts' state float64 does not hold: no method returns a non-finite frame, whatever the
/// checks in its step loop saw (a state can be finite while the rates `I⁻¹ L` made from it
/// are not).
pub(crate) fn finite_frames(out: RunOutput, grid: &FrameGrid) -> Result<RunOutput> {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    let end = &out.end;
    if finite(&out.omega)
        && finite(&out.q)
        && finite(&out.parts)
        && finite(&end.omega)
        && finite(&end.q)
        && finite(&end.parts)
    {
        return Ok(out);
    }
    let first = |v: &[f64], width: usize| {
        v.chunks(width.max(1))
            .position(|f| !finite(f))
            .unwrap_or(usize::MAX)
    };
    let frames = out.omega.len() / 3;
    let width = match frames {
        0 => 1,
        n => out.parts.len() / n,
    };
    let frame = first(&out.omega, 3)
        .min(first(&out.q, 4))
        .min(first(&out.parts, width));
    let t = match frame < grid.frames() {
        true => grid.time(frame),
        false => grid.t_end(),
    };
    Err(Error::Diverged {
        t,
        hint: NON_FINITE_HINT,
    })
}

/// What a run watches beside the drift and frames: the tilt, or nothing.
pub(crate) trait TiltWatch<const N: usize>: Observer<N> {
    fn tilt(&self) -> f64;
}

/// No tilt watched: a bare step loop.
pub(crate) struct NoTilt;

impl<const N: usize> Observer<N> for NoTilt {}

impl<const N: usize> TiltWatch<N> for NoTilt {
    fn tilt(&self) -> f64 {
        f64::NAN
    }
}

impl TiltWatch<7> for TiltMonitor {
    fn tilt(&self) -> f64 {
        TiltMonitor::tilt(self)
    }
}

/// [`simulate_model`] of a start in the motion's own units (rates near 1).
fn simulate_unit<const N: usize, S: Runs<N> + FlatAxes<N>, T: TiltWatch<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    tilt: T,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    let recorder = match keep.frames {
        true => Some(Recorder::with_frames(sys, grid.frames())?),
        false => None,
    };
    // A fixed step can be past the stability limit of a damper; an adaptive one shrinks
    // until it is stable, and its error follows its (possibly loose) tolerance.
    let drift = match method.is_adaptive() {
        true => DriftMonitor::new(sys),
        false => DriftMonitor::new(sys).watching_growth(ENERGY_GROWTH_TOL),
    };
    if let Some(settings) = method.adaptive_settings() {
        check_least_steps(sys, &x0, grid, &settings)?;
    }
    let mut obs = (drift, ((recorder, LastFrame::new(sys)), tilt));
    if !method.info().takes_steps() {
        let flip_times = sys.run_exact(x0, grid, &mut obs, keep.flips, cancel)?;
        return finished(obs, flip_times, Stats::default(), 0.0, grid);
    }
    // Flip detection looks at every step, and so does the watch for a damped body's flat
    // spin; without them the step loop stays bare.
    let flat = sys.flat_axes().map(|major| FlatSpin::new(sys, major));
    let (stats, flip_times, flat_time) = match (keep.flips, flat) {
        (true, Some(mut flat)) => {
            let mut flips = FlipDetector::new(sys, 0.0, &x0);
            let mut watch = (&mut obs, (&mut flips, &mut flat));
            let stats = sys.run_method(method, x0, grid, &mut watch, cancel)?;
            (stats, flips.into_flip_times()?, Some(flat.time()))
        }
        (true, None) => {
            let mut flips = FlipDetector::new(sys, 0.0, &x0);
            let stats = sys.run_method(method, x0, grid, &mut (&mut obs, &mut flips), cancel)?;
            (stats, flips.into_flip_times()?, None)
        }
        (false, Some(mut flat)) => {
            let stats = sys.run_method(method, x0, grid, &mut (&mut obs, &mut flat), cancel)?;
            (stats, Vec::new(), Some(flat.time()))
        }
        (false, None) => (
            sys.run_method(method, x0, grid, &mut obs, cancel)?,
            Vec::new(),
            None,
        ),
    };
    let dt = if method.is_adaptive() {
        grid.t_end() / stats.n_steps.max(1) as f64
    } else {
        grid.step_size()
    };
    let mut out = finished(obs, flip_times, stats, dt, grid)?;
    out.flat_time = flat_time;
    Ok(out)
}

/// The most an accepted step of an adaptive pair turns the attitude, `h |ω|` in radians, with
/// `rtol` at most [`MEASURED_RTOL`] and `atol` below [`MEASURED_ATOL`]: far beyond what the
/// pairs' error estimates accept there (the largest measured by tests/adaptive_bounds.rs is
/// 12.4 radians, dop853 about a principal axis at `atol` 0.099).
pub const MAX_TURN_PER_STEP: f64 = 100.0;

/// Up to this `rtol` and below [`MEASURED_ATOL`] the steps are bounded by
/// [`MAX_TURN_PER_STEP`] (at `rtol` 0.5 and 0.9 steps of 30 and 50 radians were accepted).
pub const MEASURED_RTOL: f64 = 0.1;

/// Below this `atol` a step's error is measured at all (the quaternion is of size 1: an
/// `atol` near 1 accepts any attitude, and any step).
pub const MEASURED_ATOL: f64 = 0.1;

/// The fewest steps an adaptive run of the free body needs, from what its motion keeps: the
/// rates never fall below `2E / |L|` (`ω·L = 2E` and Cauchy–Schwarz), so the attitude turns
/// at least `t_end · 2E / |L|` radians, and no step turns it more than
/// [`MAX_TURN_PER_STEP`]. `None` for other models (their pace is watched as they run) and
/// for tolerances that accept anything.
pub fn least_adaptive_steps<const N: usize, S: Model<N>>(
    sys: &S,
    x0: &[f64; N],
    t_end: f64,
    settings: &Adaptive,
) -> Option<(f64, f64)> {
    use crate::dynamics::Kinds;
    if sys.kinds() != Kinds::FREE || settings.atol >= MEASURED_ATOL || settings.rtol > MEASURED_RTOL
    {
        return None;
    }
    let (energy, momentum) = (sys.energy(0.0, x0), sys.momentum_body(0.0, x0).norm());
    if !(energy > 0.0 && momentum > 0.0) {
        return None;
    }
    let turns = t_end * (2.0 * energy / momentum);
    Some((turns / MAX_TURN_PER_STEP, turns))
}

/// Refuses up front an adaptive run that needs more steps than `max_steps` allows (see
/// [`least_adaptive_steps`]): rates of 1e20 or 1e300, or `t_end = 1e300`, ran toward
/// `max_steps` for hours, where RK4 is refused by its planned step.
fn check_least_steps<const N: usize, S: Model<N>>(
    sys: &S,
    x0: &[f64; N],
    grid: &FrameGrid,
    settings: &Adaptive,
) -> Result<()> {
    let Some((least, turns)) = least_adaptive_steps(sys, x0, grid.t_end(), settings) else {
        return Ok(());
    };
    if least <= settings.max_steps as f64 {
        return Ok(());
    }
    let needed = match least.is_finite() {
        true => format!(
            "at least {least:.3e} steps (its attitude turns {turns:.3e} radians, at most \
             {MAX_TURN_PER_STEP} in a step)"
        ),
        false => "more steps than float64 counts (its attitude turns more radians than \
                  float64 holds)"
            .into(),
    };
    Err(Error::TooLarge {
        what: "the adaptive run".into(),
        needed,
        limit: max_steps_limit(settings.max_steps),
        hint: "take a shorter t_end, or raise max_steps",
    })
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
            what: "the run".into(),
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
    match drift.is_finite() {
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
        Error::EnergyGrew { t, ratio } => Error::EnergyGrew {
            t: time_from_unit(scale, t, t_end),
            ratio,
        },
        other => other,
    }
}

/// The observers of every run: the drift, the frames if kept, the tilt if watched.
type Watched<'a, const N: usize, S, T> = (
    DriftMonitor<'a, S>,
    ((Option<Recorder<'a, N, S>>, LastFrame<'a, N, S>), T),
);

/// The output of a run from what its observers saw.
///
/// # Errors
/// Invariants that overflowed (see [`finite_drift`]).
fn finished<const N: usize, S: Model<N>, T: TiltWatch<N>>(
    (drift, ((frames, last), tilt)): Watched<'_, N, S, T>,
    flip_times: Vec<f64>,
    stats: Stats,
    dt: f64,
    grid: &FrameGrid,
) -> Result<RunOutput> {
    if let Some((t, ratio)) = drift.grew {
        return Err(Error::EnergyGrew { t, ratio });
    }
    let drift = finite_drift(drift.drift, grid.t_end())?;
    let (omega, q, parts) = frames.map(Recorder::into_frames).unwrap_or_default();
    finite_frames(
        RunOutput {
            omega,
            q,
            parts,
            flip_times,
            tilt: tilt.tilt(),
            flat_time: None,
            end: last.end(),
            drift,
            stats,
            dt,
        },
        grid,
    )
}
