use crate::ode::{add, OdeSystem, Stepper, Visit};

/// The classic fourth-order Runge–Kutta method (Kutta 1901), the paper's method.
///
/// Tableau: `c = (0, ½, ½, 1)`, `b = (1/6, 1/3, 1/3, 1/6)`, `A` with `½, ½, 1` on its
/// subdiagonal. The stages are taken as scaled increments `k₁ = (h/2) f(x)`, `k₂ = (h/2) f(x + k₁)`,
/// `k₃ = h f(x + k₂)`, `k₄ = (h/6) f(x + k₃)`, and `x + (k₁ + 2k₂ + k₃)/3` is formed while `k₄`
/// is computed: the same method, with a shorter chain of dependent floating-point operations.
/// What the system makes of `t` alone is made once for each of the step's three times `t`,
/// `t + h/2`, `t + h` ([`OdeSystem::stage_times`]), and the step runs on the system in the form
/// it picks ([`OdeSystem::specialised`]: a kernel written out for a common case).
#[derive(Debug, Clone, Copy, Default)]
pub struct Rk4;

impl<const N: usize, S: OdeSystem<N>> Stepper<N, S> for Rk4 {
    const ORDER: u32 = 4;
    const RHS_PER_STEP: u64 = 4;

    /// One step: the system's own whole step if it has one ([`OdeSystem::rk4_step`]), else
    /// the stages on the system in the form it picks ([`OdeSystem::specialised`]).
    #[inline(always)]
    fn step(&self, sys: &S, t: f64, h: f64, x: &mut [f64; N]) {
        if sys.rk4_step(t, h, x) {
            return;
        }
        sys.specialised(Rk4Step { t, h, x });
    }
}

/// One RK4 step from `t` over `h` on `x`, as a visit ([`crate::ode::Visit`]).
struct Rk4Step<'x, const N: usize> {
    t: f64,
    h: f64,
    x: &'x mut [f64; N],
}

impl<const N: usize> Visit<N> for Rk4Step<'_, N> {
    type Out = ();

    #[inline(always)]
    fn visit<S: OdeSystem<N>>(self, sys: &S) {
        let Self { t, h, x } = self;
        let half = 0.5 * h;
        // what the system makes of t alone, once for each of the step's three times
        let [start, middle, end] = sys.stage_times(t, h);
        let k1 = sys.increment_at(&start, x, half);
        let k2 = sys.increment_at(&middle, &add(x, &k1), half);
        let k3 = sys.increment_at(&middle, &add(x, &k2), h);
        let y4 = add(x, &k3);
        let partial: [f64; N] =
            std::array::from_fn(|j| x[j] + (k1[j] + 2.0 * k2[j] + k3[j]) * (1.0 / 3.0));
        let k4 = sys.increment_at(&end, &y4, h / 6.0);
        *x = add(&partial, &k4);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// x' = x: one step is the degree-4 Taylor polynomial of e^h.
    struct Growth;
    impl OdeSystem<1> for Growth {
        fn increment(&self, _t: f64, x: &[f64; 1], s: f64) -> [f64; 1] {
            [s * x[0]]
        }
    }

    /// x' = t³: RK4 integrates cubics in t exactly (Simpson's rule).
    struct Cubic;
    impl OdeSystem<1> for Cubic {
        fn increment(&self, t: f64, _x: &[f64; 1], s: f64) -> [f64; 1] {
            [s * t * t * t]
        }
    }

    #[test]
    fn one_step_is_the_taylor_polynomial() {
        let h: f64 = 0.1;
        let mut x = [1.0];
        Rk4.step(&Growth, 0.0, h, &mut x);
        let taylor = 1.0 + h + h * h / 2.0 + h.powi(3) / 6.0 + h.powi(4) / 24.0;
        assert_relative_eq!(x[0], taylor, epsilon = 1e-16);
    }

    #[test]
    fn quadrature_of_a_cubic_is_exact() {
        let mut x = [0.0];
        Rk4.step(&Cubic, 1.0, 1.0, &mut x);
        assert_relative_eq!(x[0], (16.0 - 1.0) / 4.0, epsilon = 1e-15);
    }
}
