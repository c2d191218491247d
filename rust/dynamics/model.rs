//! What a run needs to know of a model beyond its right-hand side: where the attitude sits in
//! the state, the body rates, the total angular momentum and kinetic energy it reports, and
//! how the projected RK4 puts a state back onto the invariants that model keeps.
//!
//! Every model's state ends with the body-to-world quaternion `(Q, U, V, W)`, scalar first,
//! obeying the body-frame law `q' = ½ q ⊗ (0, ω)`.

use nalgebra::{Quaternion, Vector3};

use crate::error::Result;
use crate::float::RateScale;
use crate::kinematics::rotation_matrix;
use crate::ode::OdeSystem;

/// A model of a rotating body: an ODE system of dimension `N` whose last four components
/// are the attitude quaternion.
pub trait Model<const N: usize>: OdeSystem<N> + Sync {
    /// The model's name, as the method registry and error messages spell it.
    const NAME: &'static str;

    /// Body-frame angular velocity of the (main) body at `(t, x)`.
    fn omega_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64>;

    /// Total angular momentum at `(t, x)`, in body axes (body and any internal rotor).
    fn momentum_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64>;

    /// Total kinetic energy at `(t, x)`.
    fn energy(&self, t: f64, x: &[f64; N]) -> f64;

    /// Multiplies every rate of `x` by `factor`: the total angular momentum scales with it.
    fn scale_rates(&self, x: &mut [f64; N], factor: f64);

    /// A bound on the body rates over the run from `x0`, for the adaptive error control's
    /// absolute tolerance and the default step.
    fn rate_bound(&self, x0: &[f64; N]) -> f64;

    /// The principal moments at `t` when the principal axes are the body axes (every
    /// tensor of the model diagonal), where flips are located; `None` otherwise.
    fn principal_moments(&self, t: f64) -> Option<Vector3<f64>>;

    /// Extra per-frame output of the model (the damper's rates), appended to `out`.
    fn extra(&self, _x: &[f64; N], _out: &mut Vec<f64>) {}

    /// The same model with times in the units of `scale` (times multiplied by `2^e`, rates and
    /// momenta divided by it; see [`crate::float`]), so that a run from rates far from 1 is
    /// integrated in the motion's own units. What carries a time changes with them: a
    /// deployment's knot times, a damper's coefficient (a moment per unit time).
    ///
    /// # Errors
    /// [`crate::Error::TooLarge`] when such a time or coefficient leaves float64.
    fn in_units(&self, scale: RateScale) -> Result<Self>
    where
        Self: Sized;
}

/// The attitude part of a model's state (its last four components).
#[inline(always)]
pub fn attitude<const N: usize>(x: &[f64; N]) -> Quaternion<f64> {
    Quaternion::new(x[N - 4], x[N - 3], x[N - 2], x[N - 1])
}

/// `s · ½ q ⊗ (0, ω)`: the body-frame quaternion law, scaled.
#[inline(always)]
pub fn quaternion_increment(q: [f64; 4], omega: Vector3<f64>, s: f64) -> [f64; 4] {
    let [q0, q1, q2, q3] = q;
    let (u, v, w) = (omega.x, omega.y, omega.z);
    let half = 0.5 * s;
    [
        -half * (q1 * u + q2 * v + q3 * w),
        half * (q0 * u + q2 * w - q3 * v),
        half * (q0 * v + q3 * u - q1 * w),
        half * (q0 * w + q1 * v - q2 * u),
    ]
}

/// The invariants a model's exact motion keeps, taken at the start: the norm of the total
/// angular momentum and its direction in space (not the energy, which deployments change
/// and dampers dissipate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MomentumProjection {
    l0: f64,
    l_world0: Vector3<f64>,
}

impl MomentumProjection {
    /// The invariants of the state `x0` at `t0`.
    pub fn new<const N: usize, S: Model<N>>(sys: &S, t0: f64, x0: &[f64; N]) -> Self {
        let l = sys.momentum_body(t0, x0);
        Self {
            l0: l.norm(),
            l_world0: rotation_matrix(&attitude(x0)) * l,
        }
    }

    /// Puts `x` back onto `|L| = |L₀|`, `|q| = 1` and `M(q) L = L_world(0)`: the rates are
    /// scaled by `|L₀| / |L|`, `q` is normalised and then turned, in space, by the smallest
    /// rotation taking `L_world` onto its initial direction (`q ← δ ⊗ q`).
    #[inline]
    pub fn project<const N: usize, S: Model<N>>(&self, sys: &S, t: f64, x: &mut [f64; N]) {
        let l = sys.momentum_body(t, x);
        let n = l.norm();
        let mut q = attitude(x);
        if n > 0.0 && self.l0 > 0.0 {
            let factor = self.l0 / n;
            sys.scale_rates(x, factor);
            let a = rotation_matrix(&q) * (l * factor);
            let b = &self.l_world0;
            // δ ∝ (|a||b| + a·b, a × b) turns a onto b (|a| = |b|)
            let delta = Quaternion::from_parts(self.l0 * self.l0 + a.dot(b), a.cross(b));
            q = delta * q;
        }
        let q = q / q.norm();
        x[N - 4] = q.w;
        x[N - 3] = q.i;
        x[N - 2] = q.j;
        x[N - 1] = q.k;
    }
}
