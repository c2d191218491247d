//! Eq. 1: Euler's equations of the free rigid body with body-frame quaternion kinematics,
//! and the quantities the exact motion keeps.
//!
//! The paper prints `V' = ½ (W u + Q v + U w)`. With that sign `d|q|²/dt = 2 V W u ≠ 0`, so
//! `|q|` is not kept (on the paper's case 3a it grows to about 47 by t = 100). The correct
//! body-frame law is `q' = ½ q ⊗ (0, ω)`, which keeps `|q|` and the world-frame angular
//! momentum `L = M(q) · (Ix u, Iy v, Iz w)`. This module implements that law.

use nalgebra::{Quaternion, Vector3};

use crate::body::RigidBody;
use crate::error::Result;
use crate::float::RateScale;
use crate::kinematics::rotation_matrix;
use crate::ode::{power_of_two_scale, OdeSystem};

use super::kinds::Kinds;
use super::model::{Conserved, MidAxis, Model};

/// The state `[u, v, w, Q, U, V, W]`: body-frame angular velocity, then the body-to-world
/// quaternion, scalar first. A plain array: steppers loop over it, nalgebra views its parts.
pub type State = [f64; 7];

/// Builds a state from body-frame `omega` and a scalar-first quaternion `(Q, U, V, W)`.
pub fn state_from(omega_body: [f64; 3], q_body_to_world: [f64; 4]) -> State {
    let [u, v, w] = omega_body;
    let [q0, q1, q2, q3] = q_body_to_world;
    [u, v, w, q0, q1, q2, q3]
}

/// The body-frame angular velocity part of a state.
#[inline]
pub fn omega_body(x: &State) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

/// The quaternion part of a state (nalgebra's `Quaternion::new` takes the scalar first).
#[inline]
pub fn q_body_to_world(x: &State) -> Quaternion<f64> {
    Quaternion::new(x[3], x[4], x[5], x[6])
}

/// The free rigid body as an ODE system: eq. 1 with the body-frame quaternion law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeRigidBody {
    body: RigidBody,
    /// `((Iy - Iz)/Ix, (Iz - Ix)/Iy, (Ix - Iy)/Iz)`: Euler's equations as `u' = a v w`, etc.
    euler: Vector3<f64>,
    /// The intermediate axis, if the moments are distinct.
    mid: Option<usize>,
}

impl FreeRigidBody {
    pub fn new(body: RigidBody) -> Self {
        let i = body.inertia_body();
        let euler = Vector3::new((i.y - i.z) / i.x, (i.z - i.x) / i.y, (i.x - i.y) / i.z);
        Self {
            body,
            euler,
            mid: body.intermediate_axis(),
        }
    }

    pub fn body(&self) -> &RigidBody {
        &self.body
    }

    /// The coefficients `(a, b, c)` of Euler's equations `u' = a v w, v' = b u w, w' = c u v`.
    pub fn euler_coefficients(&self) -> Vector3<f64> {
        self.euler
    }
}

impl OdeSystem<7> for FreeRigidBody {
    #[inline(always)]
    fn increment(&self, _t: f64, x: &State, s: f64) -> State {
        scaled_increment([self.euler.x, self.euler.y, self.euler.z], x, s)
    }
}

impl Model<7> for FreeRigidBody {
    type Kept = FreeProjection;

    fn conserved(&self) -> Conserved {
        Conserved::FREE
    }

    fn kinds(&self) -> Kinds {
        Kinds::FREE
    }

    #[inline(always)]
    fn omega_body(&self, _t: f64, x: &State) -> Vector3<f64> {
        omega_body(x)
    }

    #[inline(always)]
    fn momentum_body(&self, _t: f64, x: &State) -> Vector3<f64> {
        self.body.inertia_body().component_mul(&omega_body(x))
    }

    fn energy(&self, _t: f64, x: &State) -> f64 {
        let omega = omega_body(x);
        0.5 * omega.dot(&self.body.inertia_body().component_mul(&omega))
    }

    /// `Ω` ([`rate_bound`]), times [`frequency_factor`] for moments that break the triangle
    /// inequality (their precession is faster).
    fn rate_bound(&self, x0: &State) -> f64 {
        rate_bound(&self.body, [x0[0], x0[1], x0[2]]) * frequency_factor(&self.body)
    }

    fn state_size(&self, x0: &State) -> f64 {
        rate_bound(&self.body, [x0[0], x0[1], x0[2]])
    }

    #[inline(always)]
    fn intermediate_axis(&self, _t: f64) -> MidAxis {
        match self.mid {
            Some(k) => MidAxis::Body(k),
            None => MidAxis::None,
        }
    }

    fn kept(&self, _t0: f64, x0: &State) -> FreeProjection {
        FreeProjection::new(&self.body, x0)
    }

    #[inline]
    fn project(&self, kept: &FreeProjection, _t: f64, x: &mut State) {
        kept.project(x);
    }

    fn in_units(&self, _scale: RateScale) -> Result<Self> {
        Ok(*self) // nothing carries a time
    }
}

/// Below this `sin²` of the angle between `Iω` and `I²ω` the two constraints are treated as
/// one (the 2 × 2 system's determinant has lost half its digits).
const PARALLEL: f64 = 1e-8;

/// The free body's projection onto its invariants (what `rk4_projected` restores after each
/// step):
/// 1. the body rates are moved back onto the intersection of the energy ellipsoid
///    `ω·Iω = 2E₀` and the momentum sphere `|Iω|² = L₀²` (one Gauss–Newton step of the
///    minimum-norm correction along the two constraint gradients `Iω` and `I²ω`, which leaves
///    an error of the square of RK4's per-step drift);
/// 2. `q` is rescaled to unit norm;
/// 3. the attitude is turned, in space, by the smallest rotation that takes
///    `L_world = M(q) I ω` back onto its initial direction (`q ← δ ⊗ q`).
///
/// What this keeps: `|q|` and the direction of `L_world` to round-off at any step; `E` and
/// `|L|` to within the square of RK4's relative energy change per step, `δ ≤ (hΩ)⁵/120`
/// (one Gauss–Newton step, not iterated), which is round-off for `hΩ ≲ 0.25` but not at
/// larger steps: at `hΩ = 1.73` the energy drifts by 1e-8 to 2e-6 depending on the orbit
/// (the run warns, `StepSizeWarning`; measured in `docs/work_precision.md`). Within that, `ω`
/// stays on the exact polhode (the curve the rates trace in the body) and the body's angular
/// momentum stays fixed in space. What no projection onto the invariants can restore is what
/// they do not determine: the position along the polhode (RK4's phase error, which moves the
/// flip times) and the body's angle about `L`; both keep RK4's O(h⁴) error. Near a principal
/// axis the two constraints on `ω` become parallel (both fix the spin rate); there only the
/// energy is projected, by scaling `ω`.
///
/// The projection works on rates and moments scaled by powers of two near `1/max|ω₀|` and
/// `1/max I` (exact, so runs keep the symmetry `(ω, t) → (sω, t/s)`), so that the fourth
/// powers of the rates it forms neither overflow nor underflow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeProjection {
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

impl FreeProjection {
    /// The invariants of the initial state `x0` of `body`.
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

/// `s · f(x)` of eq. 1 for the Euler coefficients `euler` (see
/// [`FreeRigidBody::euler_coefficients`]). The one definition of the right-hand side: the
/// single run and the SIMD lanes of a batch ([`crate::ensemble::lanes`]) both call it, so that a batch
/// row performs the same floating-point operations in the same order as a single run.
#[inline(always)]
pub fn scaled_increment(euler: [f64; 3], x: &State, s: f64) -> State {
    increment_scaled([s * euler[0], s * euler[1], s * euler[2]], 0.5 * s, x)
}

/// [`scaled_increment`] with its factors formed: `scaled = s · euler`, `half = s / 2` (the
/// batch's lanes form them once for many steps; the arithmetic is the same).
#[inline(always)]
pub fn increment_scaled(scaled: [f64; 3], half: f64, x: &State) -> State {
    let [u, v, w, q0, q1, q2, q3] = *x;
    [
        scaled[0] * (v * w),
        scaled[1] * (u * w),
        scaled[2] * (u * v),
        -half * (q1 * u + q2 * v + q3 * w),
        half * (q0 * u + q2 * w - q3 * v),
        half * (q0 * v + q3 * u - q1 * w),
        half * (q0 * w + q1 * v - q2 * u),
    ]
}

/// The quantities the exact free motion keeps, evaluated at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants {
    /// Kinetic energy `½ ω · I ω`.
    pub energy: f64,
    /// Body-frame angular momentum `I ω`; its norm is kept.
    pub l_body: Vector3<f64>,
    /// World-frame angular momentum `M(q) I ω`, kept as a vector.
    pub l_world: Vector3<f64>,
    /// `|q|`, kept at 1.
    pub q_norm: f64,
}

impl Invariants {
    /// The invariants of state `x` for a body with principal moments `inertia_body`.
    pub fn of(inertia_body: &Vector3<f64>, x: &State) -> Self {
        let omega = omega_body(x);
        let l_body = inertia_body.component_mul(&omega);
        let q = q_body_to_world(x);
        Self {
            energy: 0.5 * omega.dot(&l_body),
            l_body,
            l_world: rotation_matrix(&q) * l_body,
            q_norm: q.norm(),
        }
    }
}

/// `Ω = √(2E / I_min)`: an upper bound of `|ω(t)|` over the whole motion from `omega0`.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// let body = dzhanibekov::RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
/// // spin about the axis of least inertia: the bound is the spin rate itself
/// assert_relative_eq!(dzhanibekov::dynamics::rate_bound(&body, [4.0, 0.0, 0.0]), 4.0);
/// ```
pub fn rate_bound(body: &RigidBody, omega0: [f64; 3]) -> f64 {
    let i = body.inertia_body();
    let i_min = i.min();
    // Σ (I_k / I_min) ω_k², with the largest |ω_k| factored out so that nothing overflows.
    let big = omega0.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
    if big == 0.0 || !big.is_finite() {
        return big;
    }
    let s: f64 = (0..3)
        .map(|k| i[k] / i_min * (omega0[k] / big).powi(2))
        .sum();
    big * s.sqrt()
}

/// `max(1, |I_j − I_k| / I_i)` over the axes: the motion's frequencies are at most this times
/// [`rate_bound`]. It is 1 for every body that meets the triangle inequality; moments that no
/// body has, such as `(1, 1, 10)`, precess faster than `Ω` (9 times, there).
pub fn frequency_factor(body: &RigidBody) -> f64 {
    let i = body.inertia_body();
    (0..3).fold(1.0_f64, |m, k| {
        m.max((i[(k + 1) % 3] - i[(k + 2) % 3]).abs() / i[k])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn paper_body() -> FreeRigidBody {
        FreeRigidBody::new(RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap())
    }

    #[test]
    fn energy_and_q_norm_are_stationary_under_the_rhs() {
        // dE/dt = ω · I ω' and d|q|²/dt = 2 q · q' vanish identically for eq. 1.
        let sys = paper_body();
        let x = state_from([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
        let dx = sys.rhs(0.0, &x);
        let i = sys.body().inertia_body();
        let de = omega_body(&x).dot(&i.component_mul(&omega_body(&dx)));
        let dq = (0..4).map(|k| x[3 + k] * dx[3 + k]).sum::<f64>();
        assert_relative_eq!(de, 0.0, epsilon = 1e-14);
        assert_relative_eq!(dq, 0.0, epsilon = 1e-15);
    }

    #[test]
    fn rhs_is_half_q_times_pure_omega() {
        let sys = paper_body();
        let x = state_from([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
        let dx = sys.rhs(0.0, &x);
        let expected = q_body_to_world(&x) * Quaternion::from_imag(omega_body(&x)) * 0.5;
        assert_relative_eq!(dx[3], expected.w, epsilon = 1e-15);
        assert_relative_eq!(dx[4], expected.i, epsilon = 1e-15);
        assert_relative_eq!(dx[5], expected.j, epsilon = 1e-15);
        assert_relative_eq!(dx[6], expected.k, epsilon = 1e-15);
    }
}
