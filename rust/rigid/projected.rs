//! RK4 projected onto the invariants; see [`Rk4Projected`].

use nalgebra::{Quaternion, Vector3};

use crate::body::RigidBody;
use crate::dynamics::model::MomentumProjection;
use crate::dynamics::{q_body_to_world, FreeRigidBody, Model, State};
use crate::kinematics::rotation_matrix;

use crate::integrators::Rk4;
use crate::ode::{power_of_two_scale, Stepper};

/// Below this `sin²` of the angle between `Iω` and `I²ω` the two constraints are treated as
/// one (the 2 × 2 system's determinant has lost half its digits).
const PARALLEL: f64 = 1e-8;

/// RK4 followed by a projection onto the invariants of the free motion.
///
/// After each RK4 step:
/// 1. the body rates are moved back onto the intersection of the energy ellipsoid
///    `ω·Iω = 2E₀` and the momentum sphere `|Iω|² = L₀²` (one Gauss–Newton step of the
///    minimum-norm correction along the two constraint gradients `Iω` and `I²ω`, which leaves
///    an error of the square of RK4's per-step drift);
/// 2. `q` is rescaled to unit norm;
/// 3. the attitude is turned, in space, by the smallest rotation that takes
///    `L_world = M(q) I ω` back onto its initial direction (`q ← δ ⊗ q`).
///
/// What this keeps: `|q|` and the direction of `L_world` to round-off at any step; `E` and
/// `|L|` to within the square of RK4's relative drift per step, `δ ≈ (hΩ)⁵/120` (one
/// Gauss–Newton step, not iterated), which is round-off for `hΩ ≲ 0.5` but not at steps
/// near RK4's stability limit: at `hΩ = 1.73` the energy still drifts by about 3e-9 over a
/// run (the run warns, `StepSizeWarning`). Within that, `ω` stays on the exact polhode (the
/// curve the rates trace in the body) and the body's angular momentum stays fixed in space. What no projection onto the invariants can restore is what they do
/// not determine: the position along the polhode (RK4's phase error, which moves the flip
/// times) and the body's angle about `L`; both keep RK4's O(h⁴) error. Near a principal
/// axis the two constraints on `ω` become parallel (both fix the spin rate); there only the
/// energy is projected, by scaling `ω`.
///
/// The projection works on rates and moments scaled by powers of two near `1/max|ω₀|` and
/// `1/max I` (exact, so runs keep the symmetry `(ω, t) → (sω, t/s)`), so that the fourth
/// powers of the rates it forms neither overflow nor underflow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4Projected {
    /// The moments times a power of two near `1 / max I`.
    inertia: Vector3<f64>,
    /// A power of two near `1 / max|ω₀|`: the projection sees `ω · omega_scale`.
    omega_scale: f64,
    /// `1 / omega_scale`, exactly.
    omega_unscale: f64,
    /// `2E₀ = ω₀ · I ω₀`, scaled.
    two_e0: f64,
    /// `L₀² = |I ω₀|²`, scaled.
    l0_sq: f64,
    /// `L_world` at the start, scaled.
    l_world0: Vector3<f64>,
}

impl Rk4Projected {
    /// RK4 projected onto the invariants of the initial state `x0` of `body`.
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        let inertia = body.inertia_body();
        let inertia = inertia * power_of_two_scale(inertia.max());
        let omega = Vector3::new(x0[0], x0[1], x0[2]);
        let omega_scale = power_of_two_scale(omega.amax());
        let omega = omega * omega_scale;
        let l = inertia.component_mul(&omega);
        Self {
            inertia,
            omega_scale,
            omega_unscale: 1.0 / omega_scale,
            two_e0: omega.dot(&l),
            l0_sq: l.norm_squared(),
            l_world0: rotation_matrix(&q_body_to_world(x0)) * l,
        }
    }

    /// Projects `x` onto the invariant set: `ω` onto `E = E₀, |L| = L₀`, `q` onto `|q| = 1`
    /// and `M(q) I ω = L_world(0)`.
    #[inline]
    pub fn project(&self, x: &mut State) {
        let w = Vector3::new(x[0], x[1], x[2]) * self.omega_scale;
        let p = self.inertia.component_mul(&w);
        let r = self.inertia.component_mul(&p);
        let (pp, pr, rr) = (p.dot(&p), p.dot(&r), r.dot(&r));
        let w_p = w.dot(&p);
        let det = pp * rr - pr * pr;
        let w = if det > PARALLEL * pp * rr {
            // g₁ = ω·Iω − 2E₀, g₂ = |Iω|² − L₀²; solve [pp pr; pr rr] (a, b) = −(g₁, g₂)/2
            let (g1, g2) = (w_p - self.two_e0, pp - self.l0_sq);
            let a = (g2 * pr - g1 * rr) / (2.0 * det);
            let b = (g1 * pr - g2 * pp) / (2.0 * det);
            w + p * a + r * b
        } else if w_p > 0.0 {
            w * (self.two_e0 / w_p).sqrt()
        } else {
            w
        };
        let mut q = q_body_to_world(x);
        if self.l0_sq > 0.0 {
            // δ ∝ (|a||b| + a·b, a × b) turns a = L_world onto b = L_world(0) (|a| = |b|)
            let a = rotation_matrix(&q) * self.inertia.component_mul(&w);
            let b = &self.l_world0;
            let delta = Quaternion::from_parts(self.l0_sq + a.dot(b), a.cross(b));
            q = delta * q;
        }
        let q = q / q.norm();
        let w = w * self.omega_unscale;
        *x = [w.x, w.y, w.z, q.w, q.i, q.j, q.k];
    }
}

impl Stepper<7, FreeRigidBody> for Rk4Projected {
    const ORDER: u32 = 4;
    const RHS_PER_STEP: u64 = 4;

    #[inline]
    fn step(&self, sys: &FreeRigidBody, t: f64, h: f64, x: &mut State) {
        Rk4.step(sys, t, h, x);
        self.project(x);
    }
}

/// RK4 on a model beyond the free body (a deployment, a damped body), each step followed by
/// the projection onto what that model keeps ([`MomentumProjection`]: `|L|`, `L_world`,
/// `|q|`; never the energy, which the model's law changes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelRk4Projected {
    projection: MomentumProjection,
}

impl ModelRk4Projected {
    /// Projected RK4 keeping the invariants of `sys` at `(t0, x0)`.
    pub fn new<const N: usize, S: Model<N>>(sys: &S, t0: f64, x0: &[f64; N]) -> Self {
        Self {
            projection: MomentumProjection::new(sys, t0, x0),
        }
    }
}

impl<const N: usize, S: Model<N>> Stepper<N, S> for ModelRk4Projected {
    const ORDER: u32 = 4;
    const RHS_PER_STEP: u64 = 4;

    #[inline]
    fn step(&self, sys: &S, t: f64, h: f64, x: &mut [f64; N]) {
        Stepper::<N, S>::step(&Rk4, sys, t, h, x);
        self.projection.project(sys, t + h, x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn projection_lands_on_both_invariants() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let x0 = [0.3, -0.4, 0.5, 1.0, 0.0, 0.0, 0.0];
        let p = Rk4Projected::new(&body, &x0);
        // an RK4-sized departure: one Gauss–Newton step leaves its square
        let mut x = [
            0.3 * (1.0 + 1e-6),
            -0.4 * (1.0 - 1e-6),
            0.5 + 1e-6,
            1.01,
            0.02,
            0.0,
            0.0,
        ];
        p.project(&mut x);
        let i = body.inertia_body();
        let energy = |x: &State| (0..3).map(|k| i[k] * x[k] * x[k]).sum::<f64>();
        let momentum = |x: &State| (0..3).map(|k| (i[k] * x[k]).powi(2)).sum::<f64>();
        let world = |x: &State| {
            rotation_matrix(&q_body_to_world(x)) * Vector3::new(i.x * x[0], i.y * x[1], i.z * x[2])
        };
        assert_relative_eq!(energy(&x), energy(&x0), max_relative = 1e-11);
        assert_relative_eq!(momentum(&x), momentum(&x0), max_relative = 1e-11);
        let q_norm = (3..7).map(|k| x[k] * x[k]).sum::<f64>().sqrt();
        assert_relative_eq!(q_norm, 1.0, epsilon = 1e-15);
        assert!((world(&x) - world(&x0)).norm() < 1e-11 * world(&x0).norm());
    }

    #[test]
    fn huge_and_tiny_rates_are_projected_without_overflow() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        for s in [1e150, 1e-150] {
            let x0 = [0.3 * s, -0.4 * s, 0.5 * s, 1.0, 0.0, 0.0, 0.0];
            let p = Rk4Projected::new(&body, &x0);
            let mut x = [
                0.3 * s * (1.0 + 1e-9),
                -0.4 * s,
                0.5 * s,
                1.0,
                0.0,
                0.0,
                0.0,
            ];
            p.project(&mut x);
            assert!(x.iter().all(|v| v.is_finite()));
            assert_relative_eq!(x[1], x0[1], max_relative = 1e-8);
        }
    }

    #[test]
    fn spin_about_an_axis_is_rescaled() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let x0 = [0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0];
        let p = Rk4Projected::new(&body, &x0);
        let mut x = [0.0, 0.0, 2.002, 1.0, 0.0, 0.0, 0.0];
        p.project(&mut x);
        assert_relative_eq!(x[2], 2.0, epsilon = 1e-15);
    }
}
