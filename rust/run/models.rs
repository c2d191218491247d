//! Runs of the models beyond the constant free body ([`crate::dynamics::Model`]: deployments,
//! damped bodies) over the frame grid, by the methods that can run them and the same drivers
//! as the free body ([`crate::run::fixed`], [`crate::run::adaptive`]).
//!
//! The methods' right to run a model is declared once, in the registry
//! ([`super::registry`], each method's `models`), and checked by [`Method::for_model`]:
//! RK4, RK4 projected onto the model's kept invariants (`|L|`, `L_world` and `|q|`; never the
//! energy, which these models change), DOPRI5 and DOP853. The closed form and the splittings
//! belong to the constant free body and refuse the others by name.
//!
//! Every frame records the body rates, the attitude, the total angular momentum in space
//! (`M(q) H_body`) and the total kinetic energy, plus the model's extra output.

use std::sync::atomic::AtomicBool;

use crate::dynamics::model::attitude;
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::rotation_matrix;
use crate::observe::models::ModelFlips;
use crate::observe::{Drift, Observer};
use crate::ode::controller::check_rtol;
use crate::ode::Stats;

use super::registry::run_model_method;
use super::{error_from_unit, method_and_grid, time_from_unit, to_unit, FrameGrid, Method};

/// A model run's frames, time-major, and its cost.
#[derive(Debug, Clone, Default)]
pub struct ModelOutput {
    /// `(frames, 3)` body rates.
    pub omega: Vec<f64>,
    /// `(frames, 4)` attitude quaternions, scalar first.
    pub q: Vec<f64>,
    /// `(frames, 3)` total angular momentum in space.
    pub momentum_world: Vec<f64>,
    /// `(frames, 3)` total angular momentum in body axes.
    pub momentum_body: Vec<f64>,
    /// `(frames,)` total kinetic energy.
    pub energy: Vec<f64>,
    /// `(frames, k)` the model's extra output (the damper's rates σ; empty for a deployment).
    pub extra: Vec<f64>,
    /// The flip times ([`crate::observe::models`]), if asked for and the model's principal
    /// axes are its body axes; `None` otherwise (not located, rather than none found).
    pub flip_times: Option<Vec<f64>>,
    /// The largest departure over the frames of what the model keeps (`|L|`, `L_world`,
    /// `|q|`, as [`Drift`] defines them) and of the energy, which the model's law changes (a
    /// deployment's work, a damper's loss): its entry is the largest relative change.
    pub drift: Drift,
    pub stats: Stats,
    /// The step taken; for an adaptive method, the mean accepted step.
    pub dt: f64,
}

impl ModelOutput {
    fn with_frames(frames: usize) -> Self {
        Self {
            omega: Vec::with_capacity(3 * frames),
            q: Vec::with_capacity(4 * frames),
            momentum_world: Vec::with_capacity(3 * frames),
            momentum_body: Vec::with_capacity(3 * frames),
            energy: Vec::with_capacity(frames),
            ..Self::default()
        }
    }

    /// The drift over the recorded frames, from values near 1 (the run's own units), so that
    /// no square under- or overflows.
    fn drift(&self) -> Drift {
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let l_world0 = &self.momentum_world[..3];
        let l0 = match norm(l_world0) {
            n if n > 0.0 => n,
            _ => 1.0,
        };
        let e0 = self.energy[0];
        let largest = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0, f64::max);
        Drift {
            energy: largest(&mut self.energy.iter().map(|e| match e0 {
                0.0 => (e - e0).abs(),
                _ => ((e - e0) / e0).abs(),
            })),
            momentum: largest(
                &mut self
                    .momentum_body
                    .chunks(3)
                    .map(|l| (norm(l) - l0).abs() / l0),
            ),
            momentum_world: largest(&mut self.momentum_world.chunks(3).map(|l| {
                let d: Vec<f64> = l.iter().zip(l_world0).map(|(a, b)| a - b).collect();
                norm(&d) / l0
            })),
            q_norm: largest(&mut self.q.chunks(4).map(|q| (norm(q) - 1.0).abs())),
        }
    }

    fn record<const N: usize, S: Model<N>>(&mut self, sys: &S, t: f64, x: &[f64; N]) {
        let omega = sys.omega_body(t, x);
        let q = attitude(x);
        let l_body = sys.momentum_body(t, x);
        let l_world = rotation_matrix(&q) * l_body;
        self.momentum_body.extend_from_slice(l_body.as_slice());
        self.omega.extend_from_slice(omega.as_slice());
        self.q.extend_from_slice(&[q.w, q.i, q.j, q.k]);
        self.momentum_world.extend_from_slice(l_world.as_slice());
        self.energy.push(sys.energy(t, x));
        sys.extra(x, &mut self.extra);
    }
}

/// Shows each frame of a model run to its [`ModelOutput`].
struct ModelRecorder<'a, S> {
    sys: &'a S,
    out: ModelOutput,
}

impl<const N: usize, S: Model<N>> Observer<N> for ModelRecorder<'_, S> {
    fn frame(&mut self, _index: usize, t: f64, x: &[f64; N]) {
        self.out.record(self.sys, t, x);
    }
}

/// Integrates the model `sys` from `x0` (at t = 0) over `grid` with `method`.
///
/// Fixed-step methods take `grid.substeps()` equal steps between frames; adaptive ones choose
/// their steps under the tolerances (absolute tolerance relative to the size of the rates, or
/// momenta, at the start) and read the frames off their dense output.
///
/// # Errors
/// Non-finite `x0`; a method that cannot run the model ([`Error::Unsupported`]);
/// [`Error::Interrupted`] soon after `cancel` is set; [`Error::Diverged`] if the state stops
/// being finite; [`Error::TooLarge`] beyond an adaptive run's step cap.
pub fn simulate_model<const N: usize, S: Model<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: Method,
    flips: bool,
    cancel: &AtomicBool,
) -> Result<ModelOutput> {
    if !x0.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(
            "omega0",
            "must be finite body rates (and q0 a finite quaternion)",
            x0.as_slice(),
        ));
    }
    let omega0: [f64; 3] = sys.omega_body(0.0, &x0).into();
    let scale = RateScale::of(omega0);
    if !scale.is_identity() {
        return simulate_scaled(sys, x0, grid, method, flips, cancel, scale);
    }
    let mut recorder = ModelRecorder {
        sys,
        out: ModelOutput::with_frames(grid.frames()),
    };
    // Flip location looks at every step; without it the step loop stays bare.
    let (stats, flip_times) = match flips && sys.principal_moments(0.0).is_some() {
        true => {
            let mut flips = ModelFlips::new(sys);
            let obs = &mut (&mut recorder, &mut flips);
            let stats = run_model_method(method, sys, x0, grid, obs, cancel)?;
            (stats, Some(flips.into_flip_times()?))
        }
        false => (
            run_model_method(method, sys, x0, grid, &mut recorder, cancel)?,
            None,
        ),
    };
    let mut out = recorder.out;
    out.flip_times = flip_times;
    out.drift = out.drift();
    out.dt = if method.is_adaptive() {
        grid.t_end() / stats.n_steps.max(1) as f64
    } else {
        grid.step_size()
    };
    out.stats = stats;
    Ok(out)
}

/// [`simulate_model`] in the motion's own units (see [`crate::float`]): rates and momenta over
/// `2^e`, times (the span, the model's own times) times `2^e`, and back, so that Euler's
/// products of rates of 1e-300 or 1e300 neither underflow nor overflow.
fn simulate_scaled<const N: usize, S: Model<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: Method,
    flips: bool,
    cancel: &AtomicBool,
    scale: RateScale,
) -> Result<ModelOutput> {
    let omega0: [f64; 3] = sys.omega_body(0.0, &x0).into();
    let (unit_grid, unit_method) = to_unit(grid, method, omega0, scale)?;
    let unit = sys.in_units(scale)?;
    let x = state_to_unit(&x0, scale);
    let mut out = simulate_model(&unit, x, &unit_grid, unit_method, flips, cancel)
        .map_err(|e| error_from_unit(e, scale, grid.t_end()))?;
    let rates = [
        &mut out.omega,
        &mut out.momentum_world,
        &mut out.momentum_body,
        &mut out.extra,
    ];
    for v in rates.into_iter().flatten() {
        *v = scale.rate_from_unit(*v);
    }
    // an energy is a moment times a rate squared
    for e in &mut out.energy {
        *e = scale.rate_from_unit(scale.rate_from_unit(*e));
    }
    for t in out.flip_times.iter_mut().flatten() {
        *t = time_from_unit(scale, *t, grid.t_end());
    }
    out.dt = scale.time_from_unit(out.dt);
    if !out.omega.iter().all(|w| w.is_finite()) {
        return Err(Error::Diverged {
            t: grid.t_end(),
            hint: "the body rates `omega0` are too large for float64",
        });
    }
    Ok(out)
}

/// A model's state in the units of `scale`: its rates (or momenta) over `2^e`, its attitude
/// (the last four components) as it is.
fn state_to_unit<const N: usize>(x: &[f64; N], scale: RateScale) -> [f64; N] {
    std::array::from_fn(|k| match k < N - 4 {
        true => scale.rate_to_unit(x[k]),
        false => x[k],
    })
}

/// The method named `name` for the model `sys` from `x0` and its frame grid, as
/// [`method_and_grid`] makes them for the free body; `dt = None` picks [`model_step`] for a
/// fixed-step method.
///
/// # Errors
/// A method that cannot run the model, and the errors of [`method_and_grid`].
#[allow(clippy::too_many_arguments)]
pub fn model_method_and_grid<const N: usize, S: Model<N>>(
    sys: &S,
    x0: &[f64; N],
    name: &str,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    max_steps: u64,
    rtol: f64,
    atol: f64,
) -> Result<(Method, FrameGrid)> {
    let method = Method::named(name, rtol, atol, dt)?.for_model(S::NAME)?;
    let dt = match dt {
        None if !method.is_adaptive() => Some(model_step(sys, x0, t_end, check_rtol(rtol)?)?),
        dt => dt,
    };
    method_and_grid(name, t_end, frames, dt, max_steps, rtol, atol)
}

/// The method named `name` and the one frame grid of a batch of model runs, as
/// [`model_method_and_grid`] makes them for one: with `dt = None` a fixed-step method takes
/// the smallest of the steps its runs would pick alone; an adaptive one lets each run pick
/// its own first step, as alone.
///
/// # Errors
/// No runs, and the errors of [`model_method_and_grid`] and [`model_step`].
#[allow(clippy::too_many_arguments)]
pub fn rows_method_and_grid<const N: usize, S: Model<N>>(
    systems: &[S],
    x0s: &[[f64; N]],
    name: &str,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    max_steps: u64,
    rtol: f64,
    atol: f64,
) -> Result<(Method, FrameGrid)> {
    let (Some(sys), Some(x0)) = (systems.first(), x0s.first()) else {
        return Err(Error::invalid("omega0", "must give at least one run", 0));
    };
    let plan = |dt| model_method_and_grid(sys, x0, name, t_end, frames, dt, max_steps, rtol, atol);
    let (method, grid) = plan(dt)?;
    if dt.is_some() || method.is_adaptive() {
        return Ok((method, grid));
    }
    let mut step = f64::INFINITY;
    for (s, x) in systems.iter().zip(x0s) {
        step = step.min(model_step(s, x, t_end, rtol)?);
    }
    plan(Some(step))
}

/// The fixed step for accuracy `rtol` over `[0, t_end]` from `x0`: `h` with
/// `Ω t_end (hΩ)⁴ = rtol` and `hΩ ≤ 0.5`, `Ω` the model's rate bound — the free body's
/// rule for RK4 ([`crate::step_size`]) with its constant taken as 1. A model's phase error
/// is not bounded by it near a separatrix (a deployment that tumbles crosses one). The bound
/// is taken in the motion's own units (see [`crate::float`]), where its squares stay in
/// float64.
///
/// # Errors
/// A model whose times leave float64 in those units ([`Model::in_units`]).
pub fn model_step<const N: usize, S: Model<N>>(
    sys: &S,
    x0: &[f64; N],
    t_end: f64,
    rtol: f64,
) -> Result<f64> {
    let scale = RateScale::of(sys.omega_body(0.0, x0).into());
    let rate = match scale.is_identity() {
        true => sys.rate_bound(x0),
        false => {
            let x = state_to_unit(x0, scale);
            scale.rate_from_unit(sys.in_units(scale)?.rate_bound(&x))
        }
    };
    if !(rate > 0.0 && rate.is_finite()) {
        return Ok(t_end);
    }
    let span = (rate * t_end).max(1.0);
    let h_omega = (rtol / span).powf(0.25).min(0.5);
    Ok(h_omega / rate)
}

/// Runs `systems[i]` from `x0s[i]` on all cores (rayon), each over `grid` with `method`.
///
/// # Errors
/// The first failing run's error, naming its row ([`Error::Row`]).
pub fn simulate_models<const N: usize, S: Model<N>>(
    systems: &[S],
    x0s: &[[f64; N]],
    grid: &FrameGrid,
    method: Method,
    flips: bool,
    cancel: &AtomicBool,
) -> Result<Vec<ModelOutput>> {
    use rayon::prelude::*;
    systems
        .par_iter()
        .zip(x0s.par_iter())
        .enumerate()
        .map(|(row, (sys, x0))| {
            simulate_model(sys, *x0, grid, method, flips, cancel).map_err(|e| e.in_row(row))
        })
        .collect()
}
