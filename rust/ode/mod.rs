//! The ODE machinery under every method: the system and stepper traits, what a run cost.
//! Fixed-step methods implement [`Stepper`]; adaptive Runge–Kutta pairs implement
//! [`EmbeddedPair`] and are driven by [`crate::run::adaptive`].

pub mod controller;
pub(crate) mod embedded;

pub use embedded::{DenseOutput, EmbeddedPair, EmbeddedStep};

/// A stage time and what a system's right-hand side makes of it alone (an orbit's phase, a
/// field in world axes): made once for each distinct time of a step ([`OdeSystem::at_time`]),
/// read by every stage at that time ([`OdeSystem::increment_at`]). RK4's second and third
/// stages share `t + h/2`: three are made a step, not four. What `of_t` holds is the
/// system's own (see [`crate::dynamics::GeneralModel`]); a system that makes nothing of `t`
/// leaves it zero and the compiler drops it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageTime {
    pub t: f64,
    pub of_t: [f64; 5],
}

impl StageTime {
    /// `t`, with nothing made of it.
    #[inline(always)]
    pub fn bare(t: f64) -> Self {
        Self { t, of_t: [0.0; 5] }
    }
}

/// A first-order ODE system `x' = f(t, x)` of dimension `N`.
pub trait OdeSystem<const N: usize> {
    /// `s · f(t, x)`: the right-hand side times a step fraction. Steppers ask for scaled
    /// increments so that a system can fold `s` into its coefficients, which takes a
    /// multiplication off the critical path of every stage.
    fn increment(&self, t: f64, x: &[f64; N], s: f64) -> [f64; N];

    /// What the right-hand side makes of `t` alone (see [`StageTime`]); nothing by default.
    #[inline(always)]
    fn at_time(&self, t: f64) -> StageTime {
        StageTime::bare(t)
    }

    /// [`OdeSystem::increment`] at `at.t`, `at` made by [`OdeSystem::at_time`]: the same
    /// numbers, bit for bit, as `increment(at.t, x, s)`.
    #[inline(always)]
    fn increment_at(&self, at: &StageTime, x: &[f64; N], s: f64) -> [f64; N] {
        self.increment(at.t, x, s)
    }

    /// One whole RK4 step from `(t, x)` by `h` in the system's own code, if it has one (the
    /// same numbers, bit for bit, as [`crate::integrators::Rk4`]'s stages through
    /// [`OdeSystem::increment_at`]): `false`, and `x` untouched, if not. A system whose
    /// evaluation is out of line takes its four stages in one call so (a lone moving part,
    /// see [`crate::dynamics::GeneralModel`]); none by default.
    #[inline(always)]
    fn rk4_step(&self, _t: f64, _h: f64, _x: &mut [f64; N]) -> bool {
        false
    }

    /// What [`OdeSystem::at_time`] makes of RK4's three stage times `t`, `t + h/2`, `t + h`
    /// (`h/2` as `0.5 h`). A system may make the later two from the first (an orbit's phase
    /// turned by `n h/2`), at round-off from what `at_time` makes of them.
    #[inline(always)]
    fn stage_times(&self, t: f64, h: f64) -> [StageTime; 3] {
        let half = 0.5 * h;
        [self.at_time(t), self.at_time(t + half), self.at_time(t + h)]
    }

    /// `v` run on the system itself, or on a simpler system with the same right-hand side
    /// that it picked for its run (a kernel written out for a common case, see
    /// [`crate::dynamics::GeneralModel`]): a stepper that visits once a step tests what the
    /// system is once a step, not at each of its stages, and runs the kernel's code alone.
    #[inline(always)]
    fn specialised<V: Visit<N>>(&self, v: V) -> V::Out
    where
        Self: Sized,
    {
        v.visit(self)
    }

    /// `f(t, x)`.
    fn rhs(&self, t: f64, x: &[f64; N]) -> [f64; N] {
        self.increment(t, x, 1.0)
    }

    /// Whether the system has a discrete update at some of its kinks ([`OdeSystem::sample`]).
    fn is_sampled(&self) -> bool {
        false
    }

    /// The system's discrete update at its kink `t` (a controller's held command): the
    /// drivers call it once a step has ended on a kink, before the next starts.
    fn sample(&self, _t: f64, _x: &mut [f64; N]) {}
}

/// What a stepper runs on a system in the form the system picks ([`OdeSystem::specialised`]).
pub trait Visit<const N: usize> {
    type Out;
    fn visit<S: OdeSystem<N>>(self, sys: &S) -> Self::Out;
}

/// The first of the increasing `times` at or after `t`; infinity if none: a list of kinks
/// asked as the drivers ask a model ([`crate::dynamics::Model::next_kink`]).
#[inline]
pub fn first_from(times: &[f64], t: f64) -> f64 {
    times
        .get(times.partition_point(|&k| k < t))
        .copied()
        .unwrap_or(f64::INFINITY)
}

/// A one-step method with a fixed step.
pub trait Stepper<const N: usize, S: OdeSystem<N>> {
    /// The order of the global error.
    const ORDER: u32;
    /// Right-hand-side evaluations per step.
    const RHS_PER_STEP: u64;
    /// Advances `x` from `t` to `t + h`. `x` is in the method's own variables (see
    /// [`Stepper::to_internal`]).
    fn step(&self, sys: &S, t: f64, h: f64, x: &mut [f64; N]);

    /// The method's own variables from the system's state; the identity unless a method
    /// works on other variables (the splitting works on angular momentum, not rates).
    #[inline(always)]
    fn to_internal(&self, _sys: &S, x: &[f64; N]) -> [f64; N] {
        *x
    }

    /// The system's state from the method's own variables: what observers see.
    #[inline(always)]
    fn to_state(&self, _sys: &S, x: &[f64; N]) -> [f64; N] {
        *x
    }
}

/// What a run cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Right-hand-side evaluations.
    pub nfev: u64,
    /// Steps taken (accepted steps, for an adaptive method).
    pub n_steps: u64,
    /// Steps tried and rejected by an adaptive method's error control; 0 for a fixed step.
    pub n_rejected: u64,
}

/// `x + k`, elementwise.
#[inline(always)]
pub(crate) fn add<const N: usize>(x: &[f64; N], k: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|j| x[j] + k[j])
}

/// `2^−e` for `x = m · 2^e`, `1 ≤ m < 2`: a power of two at or below `1 / x`, read off the
/// exponent bits so that it follows exact scalings of `x` (1 for zero, subnormal or
/// non-finite `x`). Scaling by it is exact and keeps squares of `x` from overflowing.
pub(crate) fn power_of_two_scale(x: f64) -> f64 {
    if x.is_normal() {
        let e = ((x.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        2f64.powi(-e)
    } else {
        1.0
    }
}
