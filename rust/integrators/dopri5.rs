use crate::ode::controller::Controller;
use crate::ode::embedded::{combine, stages, weighted, DenseOutput, EmbeddedPair, EmbeddedStep};
use crate::ode::OdeSystem;

/// The Dormand–Prince 5(4) pair (J. R. Dormand, P. J. Prince, "A family of embedded
/// Runge–Kutta formulae", J. Comput. Appl. Math. 6 (1980) 19–26), as in Hairer's DOPRI5:
/// seven stages, the last evaluated at the new point and reused as the next step's first
/// (FSAL), fifth-order propagation with a fourth-order error estimate, and Hairer's
/// fourth-order continuous extension (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed.,
/// §II.6, with Shampine's coefficients).
#[derive(Debug, Clone, Copy, Default)]
pub struct Dopri5;

/// The nodes `c` of the first six stages; the seventh is at `c = 1` (the new point).
const C: [f64; 6] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0];

/// The coupling coefficients `A` of the first six stages (row `i`: stage `i`).
const A: [[f64; 6]; 6] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
];

/// The fifth-order weights; also the seventh stage's row of `A` (FSAL).
const B: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];

/// `b − b̂`: the fifth-order weights minus the embedded fourth-order ones, over all seven
/// stages (`b̂ = (5179/57600, 0, 7571/16695, 393/640, −92097/339200, 187/2100, 1/40)`).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Hairer's dense-output coefficients `d` over the seven stages (DOPRI5, `CONTD5`).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// An attempted Dormand–Prince step: its seven stages (the last at the new point) and the
/// new state.
#[derive(Debug, Clone, Copy)]
pub struct Dopri5Step<const N: usize> {
    k: [[f64; N]; 7],
    x1: [f64; N],
}

impl<const N: usize> EmbeddedStep<N> for Dopri5Step<N> {
    fn x1(&self) -> &[f64; N] {
        &self.x1
    }

    fn f1(&self) -> &[f64; N] {
        &self.k[6]
    }

    fn error_norm(&self, h: f64, scale: &[f64; N]) -> f64 {
        let err = weighted(&E, &self.k);
        let sum: f64 = (0..N).map(|n| (h * err[n] / scale[n]).powi(2)).sum();
        (sum / N as f64).sqrt()
    }
}

/// Hairer's quartic interpolant of one step:
/// `x(θ) = r₁ + θ (r₂ + (1−θ) (r₃ + θ (r₄ + (1−θ) r₅)))`.
#[derive(Debug, Clone, Copy)]
pub struct Dopri5Dense<const N: usize> {
    r: [[f64; N]; 5],
}

impl<const N: usize> DenseOutput<N> for Dopri5Dense<N> {
    fn at(&self, theta: f64) -> [f64; N] {
        let [r1, r2, r3, r4, r5] = &self.r;
        let s = 1.0 - theta;
        std::array::from_fn(|n| r1[n] + theta * (r2[n] + s * (r3[n] + theta * (r4[n] + s * r5[n]))))
    }
}

impl<const N: usize, S: OdeSystem<N>> EmbeddedPair<N, S> for Dopri5 {
    const ORDER: u32 = 5;
    const ERROR_ORDER: u32 = 4;
    const RHS_PER_STEP: u64 = 6;
    const RHS_PER_DENSE: u64 = 0;
    /// Hairer's `DOPRI5` defaults: β = 0.04, factors in [0.2, 10].
    const CONTROLLER: Controller = Controller::pi(4, 0.04, 0.2, 10.0);
    type Step = Dopri5Step<N>;
    type Dense = Dopri5Dense<N>;

    #[inline]
    fn attempt(&self, sys: &S, t: f64, h: f64, x: &[f64; N], f0: &[f64; N]) -> Dopri5Step<N> {
        let k6 = stages(sys, &A, &C, t, h, x, f0);
        let x1 = combine(x, h, &B, &k6);
        let mut k = [[0.0; N]; 7];
        k[..6].copy_from_slice(&k6);
        k[6] = sys.rhs(t + h, &x1);
        Dopri5Step { k, x1 }
    }

    fn dense(&self, _sys: &S, _t: f64, h: f64, x: &[f64; N], step: &Dopri5Step<N>) -> Self::Dense {
        let k = &step.k;
        let d = weighted(&D, k);
        let r2: [f64; N] = std::array::from_fn(|n| step.x1[n] - x[n]);
        let r3: [f64; N] = std::array::from_fn(|n| h * k[0][n] - r2[n]);
        let r4: [f64; N] = std::array::from_fn(|n| r2[n] - h * k[6][n] - r3[n]);
        let r5: [f64; N] = std::array::from_fn(|n| h * d[n]);
        Dopri5Dense {
            r: [*x, r2, r3, r4, r5],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ode::embedded::check_tableau;

    #[test]
    fn tableau_is_consistent_and_fifth_order_for_quadrature() {
        check_tableau(&A, &B, &C, 5);
        // the embedded weights b̂ = b − e also sum to 1 and integrate quartics exactly
        let c7 = [C[0], C[1], C[2], C[3], C[4], C[5], 1.0];
        let b7 = [B[0], B[1], B[2], B[3], B[4], B[5], 0.0];
        let bhat: Vec<f64> = (0..7).map(|i| b7[i] - E[i]).collect();
        assert!((bhat.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        for k in 0..4 {
            let q: f64 = (0..7).map(|i| bhat[i] * c7[i].powi(k)).sum();
            assert!((q - 1.0 / (k + 1) as f64).abs() < 1e-14, "k = {k}: {q}");
        }
    }

    #[test]
    fn dense_coefficients_sum_to_zero() {
        // the interpolant's θ²(1−θ)² term vanishes for a constant right-hand side
        assert!(D.iter().sum::<f64>().abs() < 1e-13);
    }
}
