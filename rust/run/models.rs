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
use crate::kinematics::rotation_matrix;
use crate::observe::Observer;
use crate::ode::controller::check_rtol;
use crate::ode::Stats;

use super::registry::run_model_method;
use super::{FrameGrid, Method};

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
    cancel: &AtomicBool,
) -> Result<ModelOutput> {
    if !x0.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(
            "omega0",
            "must be finite body rates (and q0 a finite quaternion)",
            x0.as_slice(),
        ));
    }
    let mut recorder = ModelRecorder {
        sys,
        out: ModelOutput::with_frames(grid.frames()),
    };
    let stats = run_model_method(method, sys, x0, grid, &mut recorder, cancel)?;
    let mut out = recorder.out;
    out.dt = if method.is_adaptive() {
        grid.t_end() / stats.n_steps.max(1) as f64
    } else {
        grid.step_size()
    };
    out.stats = stats;
    Ok(out)
}

/// The method named `name` for the model `sys` from `x0` and its frame grid: `dt = None`
/// picks [`model_step`] for a fixed-step method; an adaptive one is capped at `max_steps`
/// attempts.
///
/// # Errors
/// An unknown name, a method that cannot run the model, bad tolerances, and the errors of
/// [`FrameGrid::try_new`].
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
    let grid = if method.is_adaptive() {
        FrameGrid::frames_only(t_end, frames)?
    } else {
        let dt = match dt {
            Some(dt) => dt,
            None => model_step(sys, x0, t_end, check_rtol(rtol)?),
        };
        FrameGrid::try_new(t_end, frames, dt, max_steps)?
    };
    Ok((method.with_max_steps(max_steps), grid))
}

/// The fixed step for accuracy `rtol` over `[0, t_end]` from `x0`: `h` with
/// `Ω t_end (hΩ)⁴ = rtol` and `hΩ ≤ 0.5`, `Ω` the model's rate bound — the free body's
/// rule for RK4 ([`crate::step_size`]) with its constant taken as 1. A model's phase error
/// is not bounded by it near a separatrix (a deployment that tumbles crosses one).
pub fn model_step<const N: usize, S: Model<N>>(
    sys: &S,
    x0: &[f64; N],
    t_end: f64,
    rtol: f64,
) -> f64 {
    let rate = sys.rate_bound(x0);
    if !(rate > 0.0 && rate.is_finite()) {
        return t_end;
    }
    let span = (rate * t_end).max(1.0);
    let h_omega = (rtol / span).powf(0.25).min(0.5);
    h_omega / rate
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
    cancel: &AtomicBool,
) -> Result<Vec<ModelOutput>> {
    use rayon::prelude::*;
    systems
        .par_iter()
        .zip(x0s.par_iter())
        .enumerate()
        .map(|(row, (sys, x0))| {
            simulate_model(sys, *x0, grid, method, cancel).map_err(|e| e.in_row(row))
        })
        .collect()
}
