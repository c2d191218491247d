//! Time steppers. Each method is a unit struct implementing [`Stepper`].

mod rk4;

pub use rk4::Rk4;

/// A first-order ODE system `x' = f(t, x)` of dimension `N`.
pub trait OdeSystem<const N: usize> {
    /// `s · f(t, x)`: the right-hand side times a step fraction. Steppers ask for scaled
    /// increments so that a system can fold `s` into its coefficients, which takes a
    /// multiplication off the critical path of every stage.
    fn increment(&self, t: f64, x: &[f64; N], s: f64) -> [f64; N];

    /// `f(t, x)`.
    fn rhs(&self, t: f64, x: &[f64; N]) -> [f64; N] {
        self.increment(t, x, 1.0)
    }
}

/// A one-step method with a fixed step.
pub trait Stepper<const N: usize, S: OdeSystem<N>> {
    /// The order of the global error.
    const ORDER: u32;
    /// Right-hand-side evaluations per step.
    const RHS_PER_STEP: u64;
    /// Advances `x` from `t` to `t + h`.
    fn step(&self, sys: &S, t: f64, h: f64, x: &mut [f64; N]);
}

/// What a run cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Right-hand-side evaluations.
    pub nfev: u64,
    /// Steps taken.
    pub n_steps: u64,
}

/// `x + k`, elementwise.
#[inline(always)]
pub(crate) fn add<const N: usize>(x: &[f64; N], k: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|j| x[j] + k[j])
}
