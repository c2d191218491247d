//! Driving a fixed-step method over a frame grid.
//!
//! **Knots** ([`crate::dynamics::Model::knots`]): the equal substeps do not stop at a model's
//! knots, so a substep may straddle one. A method of order `p` keeps its order across a point
//! where the solution is `C^p`, and loses it there otherwise: one straddling step's local
//! error is `O(h^(m+1))` for a solution that is only `C^m` there. A deployment's law is `C²` in
//! time at its knots (the smootherstep), its solution `C³`: a straddling RK4 step errs by
//! `O(h⁴)`, the size of RK4's global error, so the run stays of order 4 (`rk4` and
//! `rk4_projected` are the fixed-step methods that run deployments). A right-hand side with a
//! jump at a knot would make the straddling step order 1 there (`O(h)` times the jump); the
//! adaptive methods end a step on every knot ([`crate::run::adaptive`]).
//!
//! **Kinks** ([`crate::dynamics::Model::kinks`]): where the right-hand side itself has a kink
//! or a jump (a tabulated torque, a wheel's schedule), [`integrate_across`] splits the substep
//! that straddles one into two, the first ending on it and the second starting one float64
//! after it (the side the table's law takes there, see [`crate::dynamics::Table`]): the run
//! keeps the method's order. Each split adds one step to the run's count. A system sampled at
//! some of its kinks ([`OdeSystem::sample`]: a controller's held command) is updated there,
//! between the step that ends on the kink and the next.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};
use crate::isa::Isa;
use crate::observe::Observer;
use crate::ode::{OdeSystem, Stats, Stepper};
use crate::run::grid::FrameGrid;

/// What to do about a run that diverged.
pub(crate) const DIVERGED_HINT: &str =
    "the step is far beyond the method's stability limit; take a smaller dt";

/// Steps between two looks at the cancel flag and the state's finiteness (about 0.4 ms of RK4).
pub(crate) const CHECK_EVERY: u64 = 1 << 14;

/// Integrates `sys` (any `N`-dimensional system: the free body, a model) from `x0` over
/// `grid` with a fixed-step method, showing frames (and steps, if asked) to `obs`. Returns the final state (in the method's own variables, see
/// [`Stepper::to_internal`]) and the run's cost.
///
/// # Errors
/// [`Error::Interrupted`] soon after `cancel` is set; [`Error::Diverged`] if the state stops
/// being finite.
pub fn integrate<const N: usize, S, M, O>(
    method: &M,
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    obs: &mut O,
    cancel: &AtomicBool,
) -> Result<([f64; N], Stats)>
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
{
    integrate_across(method, sys, x0, grid, &|_| f64::INFINITY, obs, cancel)
}

/// [`integrate`], with every step ending on the kinks inside the run (see the module doc):
/// `kinks(t)` is the first at or after `t` (infinity if none), asked for as the run goes
/// ([`crate::dynamics::Model::next_kink`]), so that a clock's kinks need no list.
///
/// # Errors
/// Those of [`integrate`].
pub fn integrate_across<const N: usize, S, M, O>(
    method: &M,
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    kinks: &impl Fn(f64) -> f64,
    obs: &mut O,
    cancel: &AtomicBool,
) -> Result<([f64; N], Stats)>
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
{
    obs.frame(0, 0.0, &x0);
    let mut x = method.to_internal(sys, &x0);
    let n = grid.substeps();
    let mut splits = 0;
    for i in 1..grid.frames() {
        let (ta, tb) = (grid.time(i - 1), grid.time(i));
        let h = (tb - ta) / n as f64;
        // the first kink in this frame's interval, its start included (the step from a kink
        // starts just after it; the step onto the interval's end ends on it)
        let first = kinks(ta);
        if first < tb {
            let extra;
            (x, extra) = advance_across_widest(
                method,
                sys,
                obs,
                x,
                ta,
                h,
                (n, tb),
                (first, kinks),
                (grid.t_end(), cancel),
            )?;
            splits += extra;
            check(&x, tb, grid.t_end(), cancel)?;
            obs.frame(i, tb, &method.to_state(sys, &x));
            continue;
        }
        let mut done = 0;
        while done < n {
            let chunk = (n - done).min(CHECK_EVERY);
            x = advance_widest(method, sys, obs, x, ta, h, done..done + chunk, (n, tb));
            done += chunk;
            check(&x, ta + done as f64 * h, grid.t_end(), cancel)?;
        }
        obs.frame(i, tb, &method.to_state(sys, &x));
    }
    let n_steps = grid.n_steps() + splits;
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
fn advance<const N: usize, S, M, O>(
    method: &M,
    sys: &S,
    obs: &mut O,
    mut x: [f64; N],
    ta: f64,
    h: f64,
    range: std::ops::Range<u64>,
    (n, tb): (u64, f64),
) -> [f64; N]
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
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

/// [`advance`], compiled for AVX-512 and run where the CPU has it: the same operations in the
/// same order (see [`crate::isa`] for the bits), with 32 vector registers instead of 16, in
/// which RK4's stages of a 7-state system spill less to the stack (AMD EPYC, CPU time: the
/// free body's RK4 step 23.5 -> 21.0 ns; AVX2's encoding alone gained nothing, 23.8 ns).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn advance_widest<const N: usize, S, M, O>(
    method: &M,
    sys: &S,
    obs: &mut O,
    x: [f64; N],
    ta: f64,
    h: f64,
    range: std::ops::Range<u64>,
    end: (u64, f64),
) -> [f64; N]
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
{
    #[cfg(target_arch = "x86_64")]
    {
        #[target_feature(enable = "avx512f")]
        #[allow(clippy::too_many_arguments)]
        fn avx512<const N: usize, S, M, O>(
            method: &M,
            sys: &S,
            obs: &mut O,
            x: [f64; N],
            ta: f64,
            h: f64,
            range: std::ops::Range<u64>,
            end: (u64, f64),
        ) -> [f64; N]
        where
            S: OdeSystem<N>,
            M: Stepper<N, S>,
            O: Observer<N>,
        {
            advance(method, sys, obs, x, ta, h, range, end)
        }
        if Isa::detect() == Isa::Avx512 {
            // SAFETY: the CPU has AVX-512F (checked just now).
            return unsafe { avx512(method, sys, obs, x, ta, h, range, end) };
        }
    }
    advance(method, sys, obs, x, ta, h, range, end)
}

/// [`advance_across`], compiled for AVX-512 and run where the CPU has it, as
/// [`advance_widest`]: a run sampled in every frame (a controller) goes here, not there, and
/// its larger states (14 numbers with a controller's) spill less with 32 registers.
#[allow(clippy::too_many_arguments)]
fn advance_across_widest<const N: usize, S, M, O, K>(
    method: &M,
    sys: &S,
    obs: &mut O,
    x: [f64; N],
    ta: f64,
    h: f64,
    end: (u64, f64),
    kinks: (f64, &K),
    stop: (f64, &AtomicBool),
) -> Result<([f64; N], u64)>
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
    K: Fn(f64) -> f64,
{
    #[cfg(target_arch = "x86_64")]
    {
        #[target_feature(enable = "avx512f")]
        #[allow(clippy::too_many_arguments)]
        fn avx512<const N: usize, S, M, O, K>(
            method: &M,
            sys: &S,
            obs: &mut O,
            x: [f64; N],
            ta: f64,
            h: f64,
            end: (u64, f64),
            kinks: (f64, &K),
            stop: (f64, &AtomicBool),
        ) -> Result<([f64; N], u64)>
        where
            S: OdeSystem<N>,
            M: Stepper<N, S>,
            O: Observer<N>,
            K: Fn(f64) -> f64,
        {
            advance_across(method, sys, obs, x, ta, h, end, kinks, stop)
        }
        if Isa::detect() == Isa::Avx512 {
            // SAFETY: the CPU has AVX-512F (checked just now).
            return unsafe { avx512(method, sys, obs, x, ta, h, end, kinks, stop) };
        }
    }
    advance_across(method, sys, obs, x, ta, h, end, kinks, stop)
}

/// The `n` substeps of `h` from `ta` to `tb`, each straddling one of the kinks (the first at
/// or after `ta` is `first`, each next one `kinks(t)`, see [`integrate_across`]) split on it:
/// the first piece ends on the kink, the second starts one float64 after it (a substep
/// starting on a kink starts one float64 after it). Returns the state and the steps taken
/// beyond the `n`. The cancel flag and the state's finiteness are checked every
/// [`CHECK_EVERY`] substeps, as between kinks (a controller sampled at every step puts kinks
/// in every frame), and every [`CHECK_EVERY`] kinks (a clock far faster than the step puts
/// many in one substep).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn advance_across<const N: usize, S, M, O>(
    method: &M,
    sys: &S,
    obs: &mut O,
    mut x: [f64; N],
    ta: f64,
    h: f64,
    (n, tb): (u64, f64),
    (first, kinks): (f64, &impl Fn(f64) -> f64),
    (t_end, cancel): (f64, &AtomicBool),
) -> Result<([f64; N], u64)>
where
    S: OdeSystem<N>,
    M: Stepper<N, S>,
    O: Observer<N>,
{
    let (mut next, mut seen) = (first, 0_u64);
    let mut pieces: u64 = 0;
    // (a function, not a closure: a closure is compiled apart from its caller, without the
    // caller's AVX-512, see `advance_across_widest`)
    #[inline(always)]
    fn piece<const N: usize, S, M, O>(
        (method, sys, obs): (&M, &S, &mut O),
        x: &mut [f64; N],
        t: f64,
        t1: f64,
    ) where
        S: OdeSystem<N>,
        M: Stepper<N, S>,
        O: Observer<N>,
    {
        if O::WANTS_STEPS {
            let before = method.to_state(sys, x);
            method.step(sys, t, t1 - t, x);
            obs.step(t, &before, t1, &method.to_state(sys, x));
        } else {
            method.step(sys, t, t1 - t, x);
        }
    }
    for k in 0..n {
        let mut t = ta + k as f64 * h;
        let t1 = if k + 1 == n { tb } else { t + h };
        while next < t1 {
            let kink = next;
            next = kinks(after(kink));
            if kink > t {
                piece((method, sys, &mut *obs), &mut x, t, kink);
                pieces += 1;
            }
            if sys.is_sampled() {
                let mut state = method.to_state(sys, &x);
                sys.sample(kink, &mut state);
                x = method.to_internal(sys, &state);
            }
            // on the kink's far side (also when the substep starts on it)
            t = after(kink).max(t);
            seen += 1;
            if seen % CHECK_EVERY == 0 {
                check(&x, t, t_end, cancel)?;
            }
        }
        if t1 > t {
            piece((method, sys, &mut *obs), &mut x, t, t1);
            pieces += 1;
        }
        if (k + 1) % CHECK_EVERY == 0 {
            check(&x, t1, t_end, cancel)?;
        }
    }
    Ok((x, pieces.saturating_sub(n)))
}

/// The float64 just after `t` (the next step's start after a kink at `t`).
#[inline]
pub(crate) fn after(t: f64) -> f64 {
    t.next_up()
}

/// Stops on the cancel flag or a state that is not finite; reports the progress (see
/// [`crate::run::progress`]).
#[inline]
fn check<const N: usize>(x: &[f64; N], t: f64, t_end: f64, cancel: &AtomicBool) -> Result<()> {
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Interrupted);
    }
    crate::run::progress::report(t, t_end);
    if !x.iter().all(|v| v.is_finite()) {
        return Err(Error::Diverged {
            t,
            hint: DIVERGED_HINT,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RigidBody;
    use crate::dynamics::{state_from, FreeRigidBody};
    use crate::integrators::Rk4;
    use crate::rigid::Rk4Projected;

    /// The steps of `method` from `x0`, by the baseline build of [`advance`] and by the one
    /// this CPU runs ([`advance_widest`]: AVX-512 where there is one).
    fn both<M: Stepper<7, FreeRigidBody>>(method: &M, sys: &FreeRigidBody) -> [[u64; 7]; 2] {
        let x0 = method.to_internal(sys, &state_from([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.5]));
        let (n, h) = (2000, 1e-3);
        let plain = advance(method, sys, &mut (), x0, 0.0, h, 0..n, (n, 2.0));
        let widest = advance_widest(method, sys, &mut (), x0, 0.0, h, 0..n, (n, 2.0));
        [plain.map(f64::to_bits), widest.map(f64::to_bits)]
    }

    #[test]
    fn the_widest_build_gives_the_baselines_bits() {
        // the same IEEE operations, however encoded: RK4's products and sums, the
        // projection's square roots and divisions (a step that calls the C library's sin and
        // cos may not: LLVM joins the two into one `sincos` call in one build of a loop and
        // not in another, and glibc's answers can differ in the last bit)
        let body = RigidBody::try_new([1.0, 1.7, 2.3]).unwrap();
        let sys = FreeRigidBody::new(body);
        let x0 = state_from([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.5]);
        let [a, b] = both(&Rk4, &sys);
        assert_eq!(a, b, "rk4");
        assert_ne!(a, x0.map(f64::to_bits), "the state moved");
        let [a, b] = both(&Rk4Projected::new(&sys, &x0), &sys);
        assert_eq!(a, b, "rk4_projected");
    }
}
