//! Runge–Kutta–Munthe-Kaas of order 4 on the unit quaternions; see [`Rkmk4`].

use crate::body::RigidBody;
use crate::dynamics::{FreeRigidBody, State};
use crate::ode::Stepper;

use super::lie::{cross, exp, rotate_back, scale_momentum, Norms};

/// The classical fourth-order Runge–Kutta method lifted to the rotation group by Munthe-Kaas's
/// construction (RKMK4), explicit, working on `[L, q]` (observers see `[ω, q]`).
///
/// H. Munthe-Kaas, "High order Runge–Kutta methods on manifolds", Appl. Numer. Math. 29 (1999)
/// 115; A. Iserles, H. Munthe-Kaas, S. P. Nørsett, A. Zanna, "Lie-group methods", Acta
/// Numerica 9 (2000) 215, §5 (the order-4 scheme with two commutators used here); Hairer,
/// Lubich & Wanner, *Geometric Numerical Integration*, §IV.8.2.
///
/// The whole state is the image of one rotation: over a step the attitude turns
/// `q = q₀ ⊗ exp(σ)` and the body angular momentum the other way, `L = R(exp σ)ᵀ L₀`, so that
/// `L_world = M(q) L` stays put. The rotation vector `σ` obeys
/// `σ' = dexp⁻¹_{−σ}(ω(L)) = ω + ½ σ × ω + (1/12) σ × (σ × ω) + …`, which RK4 integrates
/// from `σ = 0` with the commutators it needs for order 4 folded into two cross products
/// (`kᵢ = h ω(Lᵢ)`, rotation vectors):
///
/// ```text
/// σ₂ = k₁/2,  σ₃ = k₂/2 + (1/8) k₁ × k₂,  σ₄ = k₃,
/// σ  = (k₁ + 2k₂ + 2k₃ + k₄)/6 + (1/12) k₁ × k₄.
/// ```
///
/// (The signs of the cross products are those of a body-frame, right-multiplied law
/// `q' = ½ q ⊗ (0, ω)`; Iserles et al. write the left-multiplied one.) Each stage is one
/// evaluation of `ω = L / I` (the right-hand side on the group) plus an exponential and a
/// turn of `L₀`, and the step one more exponential; the exponentials of angles up to 1 radian
/// are polynomials in `θ²`. What it keeps: `|L|`, `L_world` and `|q|` to round-off (pulled
/// back as the splitting's are); the energy drifts at O(h⁴) per unit time, as RK4's does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rkmk4 {
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    norms: Norms,
}

impl Rkmk4 {
    /// RKMK4 for `body` from state `x0` (`[ω, q]`).
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        let inertia: [f64; 3] = body.inertia_body().into();
        let l0 = [0, 1, 2].map(|k| inertia[k] * x0[k]);
        Self {
            inertia,
            inv_inertia: inertia.map(|i| 1.0 / i),
            norms: Norms::new(&l0),
        }
    }

    /// `h ω` of the momentum `R(exp σ)ᵀ L₀`.
    #[inline(always)]
    fn k(&self, h: f64, l0: &[f64; 3], sigma: &[f64; 3]) -> [f64; 3] {
        let l = rotate_back(&exp(sigma), l0);
        let w = &self.inv_inertia;
        [h * w[0] * l[0], h * w[1] * l[1], h * w[2] * l[2]]
    }
}

impl Stepper<7, FreeRigidBody> for Rkmk4 {
    const ORDER: u32 = 4;
    /// Four evaluations of `ω(L)`, each with an exponential and a turn of `L₀`, and a fifth
    /// exponential for the step.
    const RHS_PER_STEP: u64 = 4;

    #[inline]
    fn step(&self, _sys: &FreeRigidBody, _t: f64, h: f64, x: &mut State) {
        let l0 = [x[0], x[1], x[2]];
        let w = &self.inv_inertia;
        let k1 = [h * w[0] * l0[0], h * w[1] * l0[1], h * w[2] * l0[2]];
        let k2 = self.k(h, &l0, &k1.map(|k| 0.5 * k));
        let c12 = cross(&k1, &k2);
        let k3 = self.k(
            h,
            &l0,
            &[
                0.5 * k2[0] + 0.125 * c12[0],
                0.5 * k2[1] + 0.125 * c12[1],
                0.5 * k2[2] + 0.125 * c12[2],
            ],
        );
        let k4 = self.k(h, &l0, &k3);
        let c14 = cross(&k1, &k4);
        let sigma: [f64; 3] = std::array::from_fn(|j| {
            (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]) * (1.0 / 6.0) + c14[j] * (1.0 / 12.0)
        });
        let p = exp(&sigma);
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
