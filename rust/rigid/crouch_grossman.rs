//! Crouch–Grossman of order 3 on the unit quaternions; see [`CrouchGrossman3`].

use crate::body::RigidBody;
use crate::dynamics::{FreeRigidBody, State};
use crate::ode::Stepper;

use super::lie::{exp, mul, rotate_back, scale_momentum, Norms};

/// The three-stage, third-order Crouch–Grossman method: a Runge–Kutta method whose stages and
/// step are products of exponentials of the frozen body rates (commutator-free), working on
/// `[L, q]` (observers see `[ω, q]`).
///
/// P. E. Crouch, R. Grossman, "Numerical integration of ordinary differential equations on
/// manifolds", J. Nonlinear Sci. 3 (1993) 1; B. Owren, A. Marthinsen, "Runge–Kutta methods
/// adapted to manifolds and based on rigid frames", BIT 39 (1999) 116 (the order conditions,
/// and these coefficients satisfying them); Hairer, Lubich & Wanner, *Geometric Numerical
/// Integration*, §IV.8.1.
///
/// ```text
/// c = (0, 3/4, 17/24),  a₂₁ = 3/4,  a₃₁ = 119/216,  a₃₂ = 17/108,
/// b = (13/51, −2/3, 24/17)
/// ```
///
/// With `Eᵢ = exp(h aᵢⱼ ωⱼ)` products (right-multiplied, as the body-frame law
/// `q' = ½ q ⊗ (0, ω)` is), the stages are `P₂ = exp(¾hω₁)`, `P₃ = exp(a₃₁hω₁) ⊗ exp(a₃₂hω₂)`,
/// the step `P = exp(b₁hω₁) ⊗ exp(b₂hω₂) ⊗ exp(b₃hω₃)`, with `ωᵢ = Lᵢ/I` and `Lᵢ = R(Pᵢ)ᵀ L₀`;
/// then `q ← q ⊗ P`, `L ← R(P)ᵀ L₀`. As for [`super::Rkmk4`], `L` turns against the attitude,
/// so `|L|`, `L_world` and `|q|` are kept to round-off (pulled back as the splitting's are),
/// and the energy drifts at O(h³) per unit time. Three evaluations of `ω(L)` a step and six
/// exponentials.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrouchGrossman3 {
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    norms: Norms,
}

/// Crouch & Grossman's order-3 coefficients (Owren & Marthinsen 1999, Table 1).
const A21: f64 = 3.0 / 4.0;
const A31: f64 = 119.0 / 216.0;
const A32: f64 = 17.0 / 108.0;
const B: [f64; 3] = [13.0 / 51.0, -2.0 / 3.0, 24.0 / 17.0];

impl CrouchGrossman3 {
    /// Crouch–Grossman 3 for `body` from state `x0` (`[ω, q]`).
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        let inertia: [f64; 3] = body.inertia_body().into();
        let l0 = [0, 1, 2].map(|k| inertia[k] * x0[k]);
        Self {
            inertia,
            inv_inertia: inertia.map(|i| 1.0 / i),
            norms: Norms::new(&l0),
        }
    }

    /// `h ω` of the momentum `l`.
    #[inline(always)]
    fn k(&self, h: f64, l: &[f64; 3]) -> [f64; 3] {
        let w = &self.inv_inertia;
        [h * w[0] * l[0], h * w[1] * l[1], h * w[2] * l[2]]
    }
}

impl Stepper<7, FreeRigidBody> for CrouchGrossman3 {
    const ORDER: u32 = 3;
    /// Three evaluations of `ω(L)`, with six exponentials and three turns of `L₀`.
    const RHS_PER_STEP: u64 = 3;

    #[inline]
    fn step(&self, _sys: &FreeRigidBody, _t: f64, h: f64, x: &mut State) {
        let l0 = [x[0], x[1], x[2]];
        let k1 = self.k(h, &l0);
        let p2 = exp(&k1.map(|k| A21 * k));
        let k2 = self.k(h, &rotate_back(&p2, &l0));
        let p3 = mul(&exp(&k1.map(|k| A31 * k)), &exp(&k2.map(|k| A32 * k)));
        let k3 = self.k(h, &rotate_back(&p3, &l0));
        let p = mul(
            &mul(&exp(&k1.map(|k| B[0] * k)), &exp(&k2.map(|k| B[1] * k))),
            &exp(&k3.map(|k| B[2] * k)),
        );
        self.norms.turn(x, &p, &l0);
    }

    /// `L = I ω`.
    #[inline(always)]
    fn to_internal(&self, _sys: &FreeRigidBody, x: &State) -> State {
        scale_momentum(&self.inertia, x)
    }

    /// `ω = L / I`.
    #[inline(always)]
    fn to_state(&self, _sys: &FreeRigidBody, x: &State) -> State {
        scale_momentum(&self.inv_inertia, x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The classical conditions to order 3 and Crouch & Grossman's extra one,
    /// `Σ bᵢ² cᵢ + 2 Σ_{i<j} bᵢ cᵢ bⱼ = 1/3` (Owren & Marthinsen 1999).
    #[test]
    fn the_coefficients_meet_the_order_conditions() {
        let c = [0.0, A21, A31 + A32];
        assert_relative_eq!(c[2], 17.0 / 24.0, epsilon = 1e-16);
        assert_relative_eq!(B.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
        assert_relative_eq!(
            (0..3).map(|i| B[i] * c[i]).sum::<f64>(),
            0.5,
            epsilon = 1e-15
        );
        assert_relative_eq!(
            (0..3).map(|i| B[i] * c[i] * c[i]).sum::<f64>(),
            1.0 / 3.0,
            epsilon = 1e-15
        );
        assert_relative_eq!(B[2] * A32 * c[1], 1.0 / 6.0, epsilon = 1e-15);
        let mut extra: f64 = (0..3).map(|i| B[i] * B[i] * c[i]).sum();
        for i in 0..3 {
            extra += 2.0 * B[i] * c[i] * B[i + 1..].iter().sum::<f64>();
        }
        assert_relative_eq!(extra, 1.0 / 3.0, epsilon = 1e-14);
    }
}
