//! Explicit Runge–Kutta pairs with an error estimate and a continuous extension ("dense
//! output"), the building blocks of [`crate::run::adaptive`].

use super::controller::Controller;
use super::OdeSystem;

/// An embedded explicit Runge–Kutta pair: a step of order [`EmbeddedPair::ORDER`] (local
/// extrapolation: the higher-order solution is propagated), an estimate of its local error,
/// and an interpolant of the step for output between step ends.
pub trait EmbeddedPair<const N: usize, S: OdeSystem<N>> {
    /// Order of the propagated solution.
    const ORDER: u32;
    /// Order of the error estimate; the step-size controller's exponent is
    /// `1 / (ERROR_ORDER + 1)`.
    const ERROR_ORDER: u32;
    /// New right-hand-side evaluations per attempted step. The first stage of a step is the
    /// last of the previous one ("first same as last"), so it is not counted again.
    const RHS_PER_STEP: u64;
    /// Extra right-hand-side evaluations to build the interpolant of one step.
    const RHS_PER_DENSE: u64;
    /// The step-size controller the pair is tuned for.
    const CONTROLLER: Controller;

    /// What an attempted step leaves behind.
    type Step: EmbeddedStep<N>;
    /// The interpolant of an accepted step.
    type Dense: DenseOutput<N>;

    /// One step of size `h` from `(t, x)`, where `f0 = f(t, x)`.
    fn attempt(&self, sys: &S, t: f64, h: f64, x: &[f64; N], f0: &[f64; N]) -> Self::Step;

    /// The interpolant over the accepted step `step`, taken from `(t, x)` with size `h`.
    fn dense(&self, sys: &S, t: f64, h: f64, x: &[f64; N], step: &Self::Step) -> Self::Dense;
}

/// The result of one attempted step.
pub trait EmbeddedStep<const N: usize> {
    /// The new state.
    fn x1(&self) -> &[f64; N];
    /// `f(t + h, x1)`: the first stage of the next step.
    fn f1(&self) -> &[f64; N];
    /// The root-mean-square of the local error estimate divided, component by component,
    /// by `scale` (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4, eq. 4.11). The step
    /// is accepted when this is at most 1.
    fn error_norm(&self, h: f64, scale: &[f64; N]) -> f64;
}

/// A continuous extension of one step.
pub trait DenseOutput<const N: usize> {
    /// The state at the fraction `theta ∈ [0, 1]` of the step.
    fn at(&self, theta: f64) -> [f64; N];
}

/// The stages `k_i = f(t + c_i h, x + h Σ_j a_ij k_j)` of an explicit tableau, with
/// `k_0 = f0` given; `a` is strictly lower triangular. Zero entries are skipped.
#[inline(always)]
pub(crate) fn stages<const N: usize, const S: usize, Sys: OdeSystem<N>>(
    sys: &Sys,
    a: &[[f64; S]; S],
    c: &[f64; S],
    t: f64,
    h: f64,
    x: &[f64; N],
    f0: &[f64; N],
) -> [[f64; N]; S] {
    let mut k = [[0.0; N]; S];
    k[0] = *f0;
    for i in 1..S {
        let y = combine(x, h, &a[i][..i], &k[..i]);
        k[i] = sys.rhs(t + c[i] * h, &y);
    }
    k
}

/// `x + h Σ_j w_j k_j` (zero weights skipped).
#[inline(always)]
pub(crate) fn combine<const N: usize>(x: &[f64; N], h: f64, w: &[f64], k: &[[f64; N]]) -> [f64; N] {
    let mut dy = [0.0; N];
    for (wj, kj) in w.iter().zip(k) {
        if *wj != 0.0 {
            for n in 0..N {
                dy[n] += wj * kj[n];
            }
        }
    }
    std::array::from_fn(|n| x[n] + h * dy[n])
}

/// `Σ_j w_j k_j` (zero weights skipped).
#[inline(always)]
pub(crate) fn weighted<const N: usize>(w: &[f64], k: &[[f64; N]]) -> [f64; N] {
    combine(&[0.0; N], 1.0, w, k)
}

/// Checks shared by the tableau tests: consistency (`Σ b = 1`), rows of `A` summing to `c`,
/// and the quadrature conditions `Σ b_i c_i^k = 1/(k+1)` up to `order − 1`.
#[cfg(test)]
pub(crate) fn check_tableau<const S: usize>(
    a: &[[f64; S]; S],
    b: &[f64; S],
    c: &[f64; S],
    order: u32,
) {
    let sum_b: f64 = b.iter().sum();
    assert!((sum_b - 1.0).abs() < 1e-14, "sum b = {sum_b}");
    for i in 0..S {
        let row: f64 = a[i].iter().sum();
        assert!((row - c[i]).abs() < 1e-13, "row {i}: {row} vs c = {}", c[i]);
        assert!(a[i][i..].iter().all(|&v| v == 0.0), "row {i} not explicit");
    }
    for k in 0..order as i32 {
        let q: f64 = b.iter().zip(c).map(|(bi, ci)| bi * ci.powi(k)).sum();
        let want = 1.0 / (k + 1) as f64;
        assert!((q - want).abs() < 1e-13, "Σ b c^{k} = {q}, want {want}");
    }
}
