//! Driving an embedded Runge–Kutta pair with error control over the frame grid.
//!
//! Steps go where the error estimate lets them; frames stay exactly at `t_end · i /
//! (frames − 1)` and are read off the step's continuous extension (the step never has to
//! land on a frame, except the last step, which ends at `t_end`). Observers see every
//! accepted step, with the step's interpolant (flips are located on it), then the frames it
//! covers.
//!
//! **Error control** (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4): a step is accepted
//! when the root-mean-square of its error estimate over `atol_k + rtol · max(|x_k|, |x̃_k|)`
//! is at most 1. The rates' absolute tolerance is `atol · Ω`, with `Ω` the rate bound of
//! [`crate::run::step_size`], and the quaternion's is `atol`: both are then relative to the
//! motion's own scale, so a run is unchanged (bit for bit when `s` is a power of two) under
//! `(ω, t) → (s ω, t / s)`. The next step is `h · clamp(0.9 · err^(−α) · err_prev^β)`
//! (Gustafsson's PI controller in Hairer's form, `α = 1/(q+1) − 0.75 β` with `q` the
//! estimate's order; `β = 0.04` for DOPRI5 and 0 for DOP853, Hairer's defaults), never
//! growing right after a rejection.
//!
//! **Knots** ([`crate::dynamics::Model::knots`]): where the right-hand side is not smooth (a
//! deployment's knots, where the third derivative of the solution jumps) the error estimate,
//! which assumes the solution smooth to the pair's order, misjudges a step that straddles the
//! point (DOP853 at `rtol = 1e-11` let the energy error jump 24-fold past `rtol` across one
//! knot). A step that would pass a knot is shortened to end exactly on it (by the same 1.01
//! rule as the last step), and the integration restarts there as a new one would: the
//! right-hand side is evaluated afresh after the knot (one evaluation a knot, so that a jump
//! is taken from the side the next step integrates), the PI controller forgets the error
//! history of the smooth piece, and the next step is the one the controller wanted before
//! the knot shortened it (a rejection shrinks it if the new piece is rougher).
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};
use crate::observe::Observer;
use crate::ode::{DenseOutput, EmbeddedPair, EmbeddedStep, OdeSystem, Stats};
use crate::run::grid::FrameGrid;

pub use crate::ode::controller::{Adaptive, MIN_RTOL};

/// Accepted steps between two looks at the cancel flag and the state's finiteness.
const CHECK_EVERY: u64 = 1 << 10;

/// The most frames a step's interpolant is read at in a run that keeps none (see
/// [`crate::observe::Observer::keeps_frames`]): a step that spans more is read at its last
/// frame only. Below it, a run that keeps no frames (a summary, a sweep's row) measures its
/// drift at the frames as the run that keeps them does, bit for bit.
pub const FRAMES_READ_IN_A_STEP: usize = 64;

/// Frames (interpolated within one step) between two looks at the cancel flag.
const FRAMES_BETWEEN_CHECKS: u64 = 1 << 16;

/// The sizes a run's error is measured against: `rate`, a bound on the motion's rates (the
/// first step is taken from it), and each component's unit for the absolute tolerance —
/// `atol · size` on the first `rates` components (rates or momenta), `atol` on the rest (the
/// quaternion); `dims` of the `N` components are the system's (the others are padding, zero
/// throughout), and the error norm is their root-mean-square.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units<const N: usize> {
    pub rate: f64,
    pub weight: [f64; N],
    pub dims: usize,
}

impl<const N: usize> Units<N> {
    /// `size` on the first `rates` components, 1 on the others; a `size` that is zero or not
    /// finite counts as 1.
    pub fn new(rate: f64, size: f64, rates: usize) -> Self {
        let size = if size > 0.0 && size.is_finite() {
            size
        } else {
            1.0
        };
        Self {
            rate,
            weight: std::array::from_fn(|k| if k < rates { size } else { 1.0 }),
            dims: N,
        }
    }

    /// The same units with the `k`-th component's (`k < N − 4`) of the dimension of a rate to
    /// the power `power(k)`: `size · rate^(p − 1)` (a momentum's `size` for rates and momenta,
    /// `size · rate` for an energy), 1 for `p = 0` (an angle, as the quaternion's). `size`
    /// and `rate` as given to [`Units::new`].
    pub fn with_powers(mut self, size: f64, power: impl Fn(usize) -> i32) -> Self {
        let size = if size > 0.0 && size.is_finite() {
            size
        } else {
            1.0
        };
        let rate = if self.rate > 0.0 && self.rate.is_finite() {
            self.rate
        } else {
            1.0
        };
        for k in 0..N.saturating_sub(4) {
            self.weight[k] = match power(k) {
                1 => size,
                p if p <= 0 => 1.0,
                p => (1..p).fold(size, |w, _| w * rate),
            };
        }
        self
    }

    /// The same units for a system of `dims` of the `N` components (see [`Units`]).
    pub fn with_dims(self, dims: usize) -> Self {
        Self {
            dims: dims.clamp(1, N),
            ..self
        }
    }
}

/// Integrates `sys` (the free body, a model) from `x0` over the frames of `grid` with the
/// pair `pair` under `settings`, its error measured in `units`, a step ending exactly at each
/// of the knots inside the run (see the module doc; `knots(t)` and `kinks(t)` are the first
/// at or after `t`, infinity if none, asked for as the run goes: see
/// [`crate::dynamics::Model::next_knot`]), showing every accepted step
/// and every frame to `obs`. Returns the final state and the run's cost.
///
/// # Errors
/// [`Error::Interrupted`] soon after `cancel` is set; [`Error::TooLarge`] when the run needs
/// more than `settings.max_steps` attempts; [`Error::Diverged`] if the state stops being
/// finite or the step shrinks below round-off.
#[allow(clippy::too_many_arguments)]
pub fn integrate_adaptive<const N: usize, S, P, O>(
    pair: &P,
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    settings: &Adaptive,
    units: &Units<N>,
    (knots, kinks): (&impl Fn(f64) -> f64, &impl Fn(f64) -> f64),
    obs: &mut O,
    cancel: &AtomicBool,
) -> Result<([f64; N], Stats)>
where
    S: OdeSystem<N>,
    P: EmbeddedPair<N, S>,
    O: Observer<N>,
{
    let t_end = grid.t_end();
    let atol: [f64; N] = std::array::from_fn(|k| settings.atol * units.weight[k]);
    let ctl = P::CONTROLLER;
    // the norms over N components, padding's zeros included, as over the system's own
    let padded = match units.dims == N {
        true => 1.0,
        false => (N as f64 / units.dims as f64).sqrt(),
    };

    obs.frame(0, 0.0, &x0);
    let keeps_frames = obs.keeps_frames();
    let (mut t, mut x) = (0.0, x0);
    if kinks(0.0) == 0.0 {
        // a kink at the start: the run integrates its far side, sampled there
        if sys.is_sampled() {
            sys.sample(t, &mut x);
        }
        t = crate::run::fixed::after(t);
    }
    let mut f = sys.rhs(t, &x);
    if !f.iter().all(|v| v.is_finite()) {
        return Err(Error::Diverged {
            t,
            hint: "the body rates `omega0` are too large for float64: their products overflow",
        });
    }
    let mut stats = Stats {
        nfev: 1,
        n_steps: 0,
        n_rejected: 0,
    };
    let mut h = settings.first_step_for(P::ERROR_ORDER, units.rate, t_end);
    let mut err_prev: f64 = 1e-4;
    let mut rejected = false;
    let mut next_frame = 1;
    // the next knot strictly inside the run (infinity for none)
    let inside = |k: f64| if k < t_end { k } else { f64::INFINITY };
    let mut next_knot = inside(knots(crate::run::fixed::after(0.0)));
    while next_frame < grid.frames() {
        // the step the controller wants, before a knot or the end shortens it
        let wanted = h;
        // Stretch a step that would stop just short of a knot or the end (Hairer's 1.01 rule).
        let knot = Some(next_knot).filter(|&k| t + 1.01 * h >= k);
        if let Some(k) = knot {
            h = k - t;
        }
        let last = knot.is_none() && t + 1.01 * h >= t_end;
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
                what: "the adaptive run".into(),
                needed: format!("more than {} step attempts (at t = {t:.6e})", stats.n_steps),
                limit: crate::run::grid::max_steps_limit(settings.max_steps),
                hint: "raise max_steps, or loosen rtol and atol",
            });
        }
        let step = pair.attempt(sys, t, h, &x, &f);
        stats.nfev += P::RHS_PER_STEP;
        let x1 = *step.x1();
        let scale: [f64; N] =
            std::array::from_fn(|k| atol[k] + settings.rtol * x[k].abs().max(x1[k].abs()));
        let err = step.error_norm(h, &scale) * padded;
        if err.is_nan() || err > 1.0 {
            // rejected (a NaN estimate, from an overflow, is rejected too)
            stats.n_rejected += 1;
            let factor = if err.is_finite() {
                (ctl.safety * err.powf(-ctl.alpha)).max(ctl.min_factor)
            } else {
                ctl.min_factor
            };
            h *= factor.min(1.0);
            rejected = true;
            if stats.n_rejected.is_multiple_of(CHECK_EVERY) {
                check(&x, t, t_end, cancel)?;
            }
            continue;
        }
        let t1 = match (last, knot) {
            (true, _) => t_end,
            (false, Some(k)) => k,
            (false, None) => t + h,
        };
        // The interpolant is built only if a frame or an observer (a flip) needs it.
        let mut dense: Option<P::Dense> = None;
        let mut dense_nfev = 0;
        let mut at = |theta: f64| {
            dense
                .get_or_insert_with(|| {
                    dense_nfev = P::RHS_PER_DENSE;
                    pair.dense(sys, t, h, &x, &step)
                })
                .at(theta)
        };
        if O::WANTS_STEPS {
            obs.step_dense(t, &x, t1, &x1, &mut at);
        }
        // One step can span millions of frames: a run that keeps none is shown, of more than
        // FRAMES_READ_IN_A_STEP, the last only (a sweep with frames = 2**31 read them all off
        // the interpolant, for hours; its drift is then measured at fewer of them)...
        if !keeps_frames && next_frame < grid.frames() && grid.time(next_frame) <= t1 {
            let last = grid.frame_at_or_before(t1);
            if last - next_frame >= FRAMES_READ_IN_A_STEP {
                next_frame = last;
            }
        }
        // ...and a run that keeps them reads the cancel flag between them too.
        while next_frame < grid.frames() && grid.time(next_frame) <= t1 {
            let tf = grid.time(next_frame);
            let xf = if tf == t1 { x1 } else { at((tf - t) / h) };
            obs.frame(next_frame, tf, &xf);
            next_frame += 1;
            if (next_frame as u64).is_multiple_of(FRAMES_BETWEEN_CHECKS) {
                check(&x, t, t_end, cancel)?;
            }
        }
        stats.nfev += dense_nfev;
        let mut factor = ctl.safety * err.powf(-ctl.alpha) * err_prev.powf(ctl.beta);
        factor = factor.clamp(ctl.min_factor, ctl.max_factor);
        if rejected {
            factor = factor.min(1.0);
        }
        err_prev = err.max(1e-4);
        rejected = false;
        (t, x, f) = (t1, x1, *step.f1());
        h *= factor;
        stats.n_steps += 1;
        if knot.is_some() {
            // a restart: the rhs from the new piece, no error history, the step not crippled
            // by the knot's shortening
            next_knot = inside(knots(crate::run::fixed::after(t)));
            if kinks(t) == t {
                // a kink or jump: the system sampled there, the next step starts one float64
                // after it, on its far side
                if sys.is_sampled() {
                    sys.sample(t, &mut x);
                }
                t = crate::run::fixed::after(t);
            }
            f = sys.rhs(t, &x);
            stats.nfev += 1;
            err_prev = 1e-4;
            h = h.max(wanted);
        }
        if stats.n_steps.is_multiple_of(CHECK_EVERY) {
            check(&x, t, t_end, cancel)?;
            check_pace(&stats, t, wanted.max(h), t_end, settings.max_steps)?;
        }
    }
    check(&x, t, t_end, cancel)?;
    Ok((x, stats))
}

/// How many times the steps `max_steps` leaves a run may fall short of what it needs at its
/// present step before it is refused: a run is refused only when its step has shrunk far
/// below what the rest of the run could take (a torque spinning the body up without bound),
/// never for a short stretch of small steps.
pub const PACE_MARGIN: f64 = 16.0;

/// Refuses a run whose present step `h` (at `t`) would take more than [`PACE_MARGIN`] times
/// the attempts `max_steps` leaves to reach `t_end`: a torque of 1e15 spun the body up until
/// its steps ran toward `max_steps = 1e10` for hours; now it is refused within milliseconds
/// of its steps shrinking so.
fn check_pace(stats: &Stats, t: f64, h: f64, t_end: f64, max_steps: u64) -> Result<()> {
    let left = max_steps.saturating_sub(stats.n_steps + stats.n_rejected) as f64;
    let needed = (t_end - t) / h;
    if needed.is_nan() || needed <= PACE_MARGIN * left {
        return Ok(());
    }
    Err(Error::TooLarge {
        what: "the adaptive run".into(),
        needed: format!(
            "about {needed:.3e} more steps at its present step ({h:.3e} at t = {t:.6e}, after \
             {} steps)",
            stats.n_steps
        ),
        limit: crate::run::grid::max_steps_limit(max_steps),
        hint: "take a shorter t_end, raise max_steps, or loosen rtol and atol (a torque \
               that spins the body up without bound needs ever smaller steps)",
    })
}

/// Stops on the cancel flag or a state that is not finite; reports the progress (see
/// [`crate::run::progress`]).
fn check<const N: usize>(x: &[f64; N], t: f64, t_end: f64, cancel: &AtomicBool) -> Result<()> {
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Interrupted);
    }
    crate::run::progress::report(t, t_end);
    if !x.iter().all(|v| v.is_finite()) {
        return Err(Error::Diverged {
            t,
            hint: "the state overflowed; the body rates `omega0` are too large for float64",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{Dop853, Dopri5};

    /// `x' = max(0, t − 1)`: a kink at `t = 1`, and `x(t) = ½ (t − 1)²` after it, a
    /// polynomial each pair integrates exactly on either side.
    struct Kink;

    impl OdeSystem<1> for Kink {
        fn increment(&self, t: f64, _x: &[f64; 1], s: f64) -> [f64; 1] {
            [s * (t - 1.0).max(0.0)]
        }
    }

    /// The end of every accepted step.
    #[derive(Default)]
    struct StepEnds(Vec<f64>);

    impl Observer<1> for StepEnds {
        const WANTS_STEPS: bool = true;
        fn step(&mut self, _t0: f64, _x0: &[f64; 1], t1: f64, _x1: &[f64; 1]) {
            self.0.push(t1);
        }
    }

    fn run<P: EmbeddedPair<1, Kink>>(pair: &P, knots: &[f64]) -> (f64, Vec<f64>, Stats) {
        let grid = FrameGrid::frames_only(3.0, 4).unwrap();
        let settings = Adaptive::try_new(1e-6, 1e-9).unwrap();
        let units = Units::new(1.0, 1.0, 1);
        let mut ends = StepEnds::default();
        let cancel = AtomicBool::new(false);
        let (x, stats) = integrate_adaptive(
            pair,
            &Kink,
            [0.0],
            &grid,
            &settings,
            &units,
            (&|t| crate::ode::first_from(knots, t), &|_| f64::INFINITY),
            &mut ends,
            &cancel,
        )
        .unwrap();
        (x[0], ends.0, stats)
    }

    #[test]
    fn a_step_ends_exactly_at_each_knot_and_the_kink_costs_nothing() {
        for (x, ends, _) in [run(&Dopri5, &[1.0]), run(&Dop853, &[1.0])] {
            assert!(ends.contains(&1.0), "{ends:?}");
            // each piece is a polynomial the pair integrates exactly: x(3) = 2 to round-off
            assert!((x - 2.0).abs() < 1e-14, "{x}");
        }
        // knots outside the run (before, at its start, at or after its end) change nothing
        let (x, ends, stats) = run(&Dop853, &[-1.0, 0.0, 1.0, 3.0, 7.0]);
        assert_eq!((x, ends, stats), run(&Dop853, &[1.0]));
    }

    #[test]
    fn without_the_knot_a_step_straddles_the_kink_and_errs() {
        // the error control sees no error on either polynomial piece and lets the step grow
        // over the kink: the estimate misses the error there (the DOP853 jump)
        for (x, ends, _) in [run(&Dopri5, &[]), run(&Dop853, &[])] {
            assert!(!ends.contains(&1.0), "{ends:?}");
            assert!((x - 2.0).abs() > 1e-12, "{x}");
        }
    }
}
