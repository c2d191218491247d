//! Runs of the models beyond the constant free body ([`crate::dynamics::Model`]: deployments,
//! damped bodies) over the frame grid, by the methods that can run them.
//!
//! The methods' right to run a model is declared once, in the registry
//! ([`super::registry`], each method's `models`), and read by [`ModelMethod::for_model`]:
//! RK4, RK4 projected onto the model's kept invariants (`|L|`, `L_world` and `|q|`; never the
//! energy, which these models change), DOPRI5 and DOP853. The closed form and the splittings
//! belong to the constant free body and refuse the others by name.
//!
//! Every frame records the body rates, the attitude, the total angular momentum in space
//! (`M(q) H_body`) and the total kinetic energy, plus the model's extra output.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::dynamics::model::{attitude, MomentumProjection};
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::integrators::{Dop853, Dopri5, Rk4};
use crate::kinematics::rotation_matrix;
use crate::ode::controller::Adaptive;
use crate::ode::{DenseOutput, EmbeddedPair, EmbeddedStep, Stats, Stepper};

use super::{FrameGrid, Method, CHECK_EVERY, DIVERGED_HINT, METHODS};

/// A method able to run a [`Model`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelMethod {
    Rk4,
    Rk4Projected,
    Dopri5(Adaptive),
    Dop853(Adaptive),
}

impl ModelMethod {
    /// `method` for the model named `model`.
    ///
    /// # Errors
    /// [`Error::Unsupported`], naming both, for the exact solution and the splittings, which
    /// are built on the constant free body.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::run::{Method, ModelMethod};
    /// let e = ModelMethod::for_model(Method::Exact, "deployment").unwrap_err();
    /// assert!(e.to_string().starts_with("method 'exact' cannot run model 'deployment'"));
    /// ```
    pub fn for_model(method: Method, model: &'static str) -> Result<Self> {
        let runs = method.info().models.contains(&model);
        match method {
            Method::Rk4 if runs => Ok(Self::Rk4),
            Method::Rk4Projected if runs => Ok(Self::Rk4Projected),
            Method::Dopri5(a) if runs => Ok(Self::Dopri5(a)),
            Method::Dop853(a) if runs => Ok(Self::Dop853(a)),
            _ => Err(Error::Unsupported {
                method: method.name(),
                model,
                supported: METHODS
                    .iter()
                    .filter(|m| m.models.contains(&model))
                    .map(|m| format!("'{}'", m.name))
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    pub fn is_adaptive(&self) -> bool {
        matches!(self, Self::Dopri5(_) | Self::Dop853(_))
    }
}

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

/// Integrates the model `sys` from `x0` (at t = 0) over `grid` with `method`.
///
/// Fixed-step methods take `grid.substeps()` equal steps between frames; adaptive ones choose
/// their steps under the tolerances (absolute tolerance relative to the size of the rates, or
/// momenta, at the start) and read the frames off their dense output.
///
/// # Errors
/// Non-finite `x0`; [`Error::Interrupted`] soon after `cancel` is set; [`Error::Diverged`]
/// if the state stops being finite; [`Error::TooLarge`] beyond an adaptive run's step cap.
pub fn simulate_model<const N: usize, S: Model<N>>(
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    method: ModelMethod,
    cancel: &AtomicBool,
) -> Result<ModelOutput> {
    if !x0.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(
            "omega0",
            "must be finite body rates (and q0 a finite quaternion)",
            x0.as_slice(),
        ));
    }
    let mut out = ModelOutput::with_frames(grid.frames());
    out.record(sys, 0.0, &x0);
    let stats = match method {
        ModelMethod::Rk4 => fixed(sys, x0, grid, &mut out, cancel, |_, _| {})?,
        ModelMethod::Rk4Projected => {
            let projection = MomentumProjection::new(sys, 0.0, &x0);
            fixed(sys, x0, grid, &mut out, cancel, |t, x| {
                projection.project(sys, t, x)
            })?
        }
        ModelMethod::Dopri5(a) => adaptive(&Dopri5, sys, x0, grid, &a, &mut out, cancel)?,
        ModelMethod::Dop853(a) => adaptive(&Dop853, sys, x0, grid, &a, &mut out, cancel)?,
    };
    out.dt = if method.is_adaptive() {
        grid.t_end() / stats.n_steps.max(1) as f64
    } else {
        grid.step_size()
    };
    out.stats = stats;
    Ok(out)
}

/// RK4 over the grid, `after(t, x)` applied after every step.
fn fixed<const N: usize, S: Model<N>>(
    sys: &S,
    mut x: [f64; N],
    grid: &FrameGrid,
    out: &mut ModelOutput,
    cancel: &AtomicBool,
    after: impl Fn(f64, &mut [f64; N]),
) -> Result<Stats> {
    let n = grid.substeps();
    for i in 1..grid.frames() {
        let (ta, tb) = (grid.time(i - 1), grid.time(i));
        let h = (tb - ta) / n as f64;
        for k in 0..n {
            let t = ta + k as f64 * h;
            Stepper::<N, S>::step(&Rk4, sys, t, h, &mut x);
            after(t + h, &mut x);
            if (k + 1).is_multiple_of(CHECK_EVERY) {
                check(&x, t + h, cancel)?;
            }
        }
        check(&x, tb, cancel)?;
        out.record(sys, tb, &x);
    }
    let n_steps = grid.n_steps();
    Ok(Stats {
        nfev: 4 * n_steps,
        n_steps,
        n_rejected: 0,
    })
}

/// An embedded pair over the grid with error control (the controller of
/// [`crate::run::adaptive`]: Hairer's PI control, his defaults per pair).
fn adaptive<const N: usize, S: Model<N>, P: EmbeddedPair<N, S>>(
    pair: &P,
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    settings: &Adaptive,
    out: &mut ModelOutput,
    cancel: &AtomicBool,
) -> Result<Stats> {
    let t_end = grid.t_end();
    // absolute tolerance: `atol` on q, `atol` times the largest rate (or momentum) elsewhere
    let size = x0[..N - 4].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let size = if size > 0.0 { size } else { 1.0 };
    let atol: [f64; N] =
        std::array::from_fn(|k| settings.atol * if k < N - 4 { size } else { 1.0 });
    let (beta, min_factor, max_factor) = if P::ERROR_ORDER < 6 {
        (0.04, 0.2, 10.0)
    } else {
        (0.0, 1.0 / 3.0, 6.0)
    };
    let alpha = 1.0 / (P::ERROR_ORDER + 1) as f64 - 0.75 * beta;
    let (mut t, mut x) = (0.0, x0);
    let mut f = sys.rhs(t, &x);
    let mut stats = Stats {
        nfev: 1,
        ..Stats::default()
    };
    let mut h = settings.first_step_for(P::ERROR_ORDER, sys.rate_bound(&x0), t_end);
    let mut err_prev: f64 = 1e-4;
    let mut rejected = false;
    let mut next_frame = 1;
    while next_frame < grid.frames() {
        let last = t + 1.01 * h >= t_end;
        if last {
            h = t_end - t;
        }
        if h <= 4.0 * f64::EPSILON * t.abs() || h == 0.0 {
            return Err(Error::Diverged {
                t,
                hint: "the adaptive step fell below round-off; `rtol` and `atol` cannot be \
                       met in float64 here",
            });
        }
        if stats.n_steps + stats.n_rejected >= settings.max_steps {
            return Err(Error::TooLarge {
                what: "the adaptive run",
                needed: format!("more than {} step attempts (at t = {t:.6e})", stats.n_steps),
                limit: format!("max_steps = {}", settings.max_steps),
                hint: "raise max_steps, or loosen rtol and atol",
            });
        }
        let step = pair.attempt(sys, t, h, &x, &f);
        stats.nfev += P::RHS_PER_STEP;
        let x1 = *step.x1();
        let scale: [f64; N] =
            std::array::from_fn(|k| atol[k] + settings.rtol * x[k].abs().max(x1[k].abs()));
        let err = step.error_norm(h, &scale);
        if err.is_nan() || err > 1.0 {
            stats.n_rejected += 1;
            let factor = if err.is_finite() {
                (0.9 * err.powf(-alpha)).max(min_factor)
            } else {
                min_factor
            };
            h *= factor.min(1.0);
            rejected = true;
            continue;
        }
        let t1 = if last { t_end } else { t + h };
        let mut dense: Option<P::Dense> = None;
        while next_frame < grid.frames() && grid.time(next_frame) <= t1 {
            let tf = grid.time(next_frame);
            let xf = if tf == t1 {
                x1
            } else {
                if dense.is_none() {
                    stats.nfev += P::RHS_PER_DENSE;
                }
                dense
                    .get_or_insert_with(|| pair.dense(sys, t, h, &x, &step))
                    .at((tf - t) / h)
            };
            out.record(sys, tf, &xf);
            next_frame += 1;
        }
        let mut factor =
            (0.9 * err.powf(-alpha) * err_prev.powf(beta)).clamp(min_factor, max_factor);
        if rejected {
            factor = factor.min(1.0);
        }
        err_prev = err.max(1e-4);
        rejected = false;
        (t, x, f) = (t1, x1, *step.f1());
        h *= factor;
        stats.n_steps += 1;
        if stats.n_steps.is_multiple_of(1 << 10) {
            check(&x, t, cancel)?;
        }
    }
    check(&x, t, cancel)?;
    Ok(stats)
}

#[inline]
fn check<const N: usize>(x: &[f64; N], t: f64, cancel: &AtomicBool) -> Result<()> {
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
    method: ModelMethod,
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
