//! The control laws, each a pure function of what the sensors measured at one sample.
//!
//! **B-dot** (Avanzini & Giulietti, "Magnetic detumbling of a rigid spacecraft", *J. Guidance,
//! Control, and Dynamics* 35(4), 2012; Markley & Crassidis, *Fundamentals of Spacecraft
//! Attitude Determination and Control*, 2014, §7.5.1): the dipole
//!
//! ```text
//! m = −(k / |B|) ḃ,      b = B / |B|,      ḃ ≈ (b_k − b_{k−1}) / T
//! ```
//!
//! from two successive magnetometer samples `T` apart (body axes). For a body turning fast
//! against the field's own motion `ḃ ≈ −ω × b`, so `m ≈ (k / |B|) ω × b` and the torque is
//! `m × B = −k (ω − (ω·b) b)`: the rates across the field decay, at `k` per unit of inertia.
//! Avanzini & Giulietti's gain `k* = 2 n (1 + sin ξ_m) J_min` ([`detumble_gain`]; `n` the
//! orbit's rate, `ξ_m` its inclination to the magnetic equator, `J_min` the least principal
//! moment) detumbles in about the least time.
//!
//! **Quaternion feedback** (Wie, Weiss & Arapostathis, "Quaternion feedback regulator for
//! spacecraft eigenaxis rotations", *J. Guidance* 12(3), 1989; Markley & Crassidis §7.2):
//!
//! ```text
//! τ = −K_p e − K_d (ω − ω_t),      e = 2 sgn(δq₀) δq_{1:3},      δq = q_t* ⊗ q
//! ```
//!
//! `δq` the body's attitude relative to the target's (target-from-body), its sign taken for
//! the shorter rotation, so `e = 2 sin(φ/2) ê` is the rotation vector `φ ê` to first order
//! (the same in body and target axes); `ω_t` the target's rate in body axes. About a principal
//! axis of moment `I` with scalar gains, small errors obey `I φ̈ + K_d φ̇ + K_p φ = 0`:
//! `ω_n = √(K_p / I)`, `ζ = K_d / (2 √(K_p I))`. (Wie's gain on `δq_{1:3}` is `2 K_p`.) The
//! target is fixed in space or in the orbiting frame (LVLH, see [`lvlh_attitude`]).
//!
//! **Momentum dumping** (Markley & Crassidis §7.6; Camillo & Markley, "Orbit-averaged
//! behavior of magnetic control laws for momentum unloading", *J. Guidance* 3(6), 1980):
//! `m = k (h × B) / |B|²`, `h` the wheels' momentum (body axes), gives the body the external
//! torque `m × B = −k (h − (h·b) b)`: the wheels' momentum across the field drains at `k`.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::dynamics::gravity::sin_cos;
use crate::kinematics::{rotation_matrix, world_to_body};

/// Avanzini & Giulietti's B-dot dipole (see the module doc) with gain `gain` from the field
/// `field` measured now and `previous` measured `period` before (body axes); zero when either
/// is zero.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use dzhanibekov::dynamics::control::bdot;
/// // the field turned from x toward y: the dipole opposes the turn
/// let m = bdot(1.0, &Vector3::new(0.99, 0.1, 0.0), &Vector3::x(), 1.0);
/// assert!(m.y < 0.0);
/// ```
#[inline]
pub fn bdot(gain: f64, field: &Vector3<f64>, previous: &Vector3<f64>, period: f64) -> Vector3<f64> {
    let (size, before) = (field.norm(), previous.norm());
    if size == 0.0 || before == 0.0 {
        return Vector3::zeros();
    }
    let rate = (field / size - previous / before) / period;
    rate * (-gain / size)
}

/// Avanzini & Giulietti's rate law, the dipole `m = (k / |B|) ω × b` from measured body rates
/// `omega` and field `field` (body axes): the torque is `m × B = −k (ω − (ω·b) b)` exactly,
/// the B-dot dipole's limit for fast rates (see the module doc); zero in no field.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use dzhanibekov::dynamics::control::rate_detumble;
/// let (w, b) = (Vector3::new(0.1, 0.2, 0.0), Vector3::new(0.0, 0.0, 3e-5));
/// let tau = rate_detumble(2.0, &w, &b).cross(&b);
/// assert!((tau + w * 2.0).amax() < 1e-15);      // all of ω is across the field
/// ```
#[inline]
pub fn rate_detumble(gain: f64, omega: &Vector3<f64>, field: &Vector3<f64>) -> Vector3<f64> {
    let size = field.norm();
    match size > 0.0 {
        true => omega.cross(field) * (gain / (size * size)),
        false => Vector3::zeros(),
    }
}

/// Avanzini & Giulietti's gain `k* = 2 n (1 + sin ξ_m) J_min` for an orbit of rate
/// `orbit_rate` inclined by `inclination` to the magnetic equator and a body of least principal
/// moment `least_moment`.
///
/// # Example
/// ```
/// use dzhanibekov::dynamics::control::detumble_gain;
/// assert_eq!(detumble_gain(1e-3, std::f64::consts::FRAC_PI_2, 0.01), 4e-5);
/// ```
pub fn detumble_gain(orbit_rate: f64, inclination: f64, least_moment: f64) -> f64 {
    2.0 * orbit_rate * (1.0 + inclination.sin()) * least_moment
}

/// The orbiting frame's attitude at `t` (world-from-LVLH) for an orbit of rate `orbit_rate`:
/// its axes along-track `(−sin nt, cos nt, 0)`, minus the orbit normal `(0, 0, −1)` and nadir
/// `(−cos nt, −sin nt, 0)` (Hughes's `F_o`; `dzhanibekov.lvlh_frame`), `q_z(nt) ⊗ q_o(0)`.
#[inline]
pub fn lvlh_attitude(orbit_rate: f64, t: f64) -> Quaternion<f64> {
    let (s, c) = sin_cos(0.5 * orbit_rate * t);
    Quaternion::new(c, 0.0, 0.0, s) * Quaternion::new(0.5, -0.5, -0.5, 0.5)
}

/// Where a pointing law points the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// Fixed in space: the target's attitude (world-from-target).
    Inertial(Quaternion<f64>),
    /// Fixed in the orbiting frame of an orbit of rate `orbit_rate`: the target's attitude in
    /// it (LVLH-from-target).
    Lvlh {
        orbit_rate: f64,
        offset: Quaternion<f64>,
    },
}

impl Target {
    /// The target's attitude at `t` (world-from-target, unit) and its rate in its own axes.
    #[inline]
    pub fn at(&self, t: f64) -> (Quaternion<f64>, Vector3<f64>) {
        match *self {
            Target::Inertial(q) => (q / q.norm(), Vector3::zeros()),
            Target::Lvlh { orbit_rate, offset } => {
                let offset = offset / offset.norm();
                // the orbiting frame turns at n about minus its second axis
                let rate = world_to_body(&offset, &Vector3::new(0.0, -orbit_rate, 0.0));
                (lvlh_attitude(orbit_rate, t) * offset, rate)
            }
        }
    }
}

/// The error `e = 2 sgn(δq₀) δq_{1:3}` of a body at attitude `q` against a target at `target`
/// (both world-from-, unit), and `δq` itself (see the module doc).
#[inline]
pub fn attitude_error(
    q: &Quaternion<f64>,
    target: &Quaternion<f64>,
) -> (Vector3<f64>, Quaternion<f64>) {
    let dq = target.conjugate() * q;
    let sign = if dq.w < 0.0 { -2.0 } else { 2.0 };
    (dq.imag() * sign, dq)
}

/// The angle between a body at attitude `q` and a target at `target` (both world-from-,
/// unit), `0..=π`.
#[inline]
pub fn pointing_angle(q: &Quaternion<f64>, target: &Quaternion<f64>) -> f64 {
    let dq = target.conjugate() * q;
    // 2 atan2(|v|, |w|) keeps its accuracy near 0 and π alike
    2.0 * dq.imag().norm().atan2(dq.w.abs())
}

/// The quaternion-feedback torque (body axes; see the module doc) on a body at attitude `q`
/// turning at `omega` (body axes), toward a target at `target` (world-from-target, unit)
/// turning at `target_rate` (its own axes), with gain matrices `kp`, `kd` (body axes).
///
/// # Example
/// ```
/// use nalgebra::{Matrix3, Quaternion, Vector3};
/// use dzhanibekov::dynamics::control::quaternion_feedback;
/// // turned a little about z past the target, the body is pushed back about −z
/// let q = Quaternion::new(0.01_f64.cos(), 0.0, 0.0, 0.01_f64.sin());
/// let k = Matrix3::identity();
/// let tau = quaternion_feedback(&q, &Vector3::zeros(), &Quaternion::identity(),
///                               &Vector3::zeros(), &k, &k);
/// assert!((tau.z + 0.02).abs() < 1e-5 && tau.x == 0.0);
/// ```
#[inline]
pub fn quaternion_feedback(
    q: &Quaternion<f64>,
    omega: &Vector3<f64>,
    target: &Quaternion<f64>,
    target_rate: &Vector3<f64>,
    kp: &Matrix3<f64>,
    kd: &Matrix3<f64>,
) -> Vector3<f64> {
    let (e, dq) = attitude_error(q, target);
    // δq is target-from-body: its matrix takes body axes to the target's
    let target_rate_body = rotation_matrix(&dq).transpose() * target_rate;
    -(kp * e) - kd * (omega - target_rate_body)
}

/// The momentum-dumping dipole `k (h × B) / |B|²` (see the module doc) for wheels of total
/// momentum `momentum` in a field `field` (body axes); zero in no field.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use dzhanibekov::dynamics::control::momentum_dump;
/// let (h, b) = (Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 2.0));
/// let m = momentum_dump(0.5, &h, &b);
/// assert_eq!(m.cross(&b), -h * 0.5);     // the torque drains h across the field
/// ```
#[inline]
pub fn momentum_dump(gain: f64, momentum: &Vector3<f64>, field: &Vector3<f64>) -> Vector3<f64> {
    let size2 = field.norm_squared();
    match size2 > 0.0 {
        true => momentum.cross(field) * (gain / size2),
        false => Vector3::zeros(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Unit, UnitQuaternion};
    use std::f64::consts::PI;

    /// The attitude after turning at the constant body rate `omega` for `t` from `q0`.
    fn turned(q0: &Quaternion<f64>, omega: &Vector3<f64>, t: f64) -> Quaternion<f64> {
        q0 * UnitQuaternion::from_scaled_axis(omega * t).into_inner()
    }

    #[test]
    fn bdot_tends_to_the_rate_law_and_damps_the_rates_across_the_field() {
        // a body turning at constant ω in a field fixed in space: as T → 0 the dipole tends to
        // (k/|B|) ω × b and the torque to −k ω⊥; the backward difference errs by O(T)
        let (k, omega) = (0.7, Vector3::new(0.1, -0.25, 0.2));
        let b_world = Vector3::new(2e-5, -1e-5, 3e-5);
        let q0 = Quaternion::new(0.9, 0.1, -0.3, 0.2).normalize();
        let t = 3.0;
        let b_now = world_to_body(&turned(&q0, &omega, t), &b_world);
        let unit = b_now.normalize();
        let limit = omega.cross(&unit) * (k / b_now.norm());
        let mut errors = vec![];
        for period in [1e-2, 1e-3, 1e-4] {
            let before = world_to_body(&turned(&q0, &omega, t - period), &b_world);
            let m = bdot(k, &b_now, &before, period);
            errors.push((m - limit).norm() / limit.norm());
            let tau = m.cross(&b_now);
            assert!(omega.dot(&tau) < 0.0, "the torque takes energy out");
        }
        assert!(errors[2] < 1e-4, "{errors:?}");
        assert_relative_eq!(errors[0] / errors[1], 10.0, max_relative = 0.05);
        let tau = limit.cross(&b_now);
        assert_relative_eq!(tau, -(omega - unit * omega.dot(&unit)) * k, epsilon = 1e-15);
        assert_eq!(bdot(k, &Vector3::zeros(), &b_now, 1.0), Vector3::zeros());
        // the gyro's form of the law is that limit itself, and nothing in no field
        assert_relative_eq!(
            rate_detumble(k, &omega, &b_now),
            limit,
            max_relative = 1e-14
        );
        assert_eq!(
            rate_detumble(k, &omega, &Vector3::zeros()),
            Vector3::zeros()
        );
    }

    #[test]
    fn the_lvlh_frame_has_the_orbit_frames_axes() {
        let n = 0.37;
        for t in [0.0, 1.0, 7.5, -3.0] {
            let m = rotation_matrix(&lvlh_attitude(n, t));
            let (s, c) = (n * t).sin_cos();
            assert_relative_eq!(
                m.column(0).into_owned(),
                Vector3::new(-s, c, 0.0),
                epsilon = 1e-15
            );
            assert_relative_eq!(
                m.column(1).into_owned(),
                Vector3::new(0.0, 0.0, -1.0),
                epsilon = 1e-15
            );
            assert_relative_eq!(
                m.column(2).into_owned(),
                Vector3::new(-c, -s, 0.0),
                epsilon = 1e-15
            );
        }
    }

    #[test]
    fn the_error_is_the_rotation_vector_to_first_order_and_the_shorter_way() {
        let target = Quaternion::new(0.3, -0.5, 0.7, 0.2).normalize();
        let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5));
        for angle in [1e-6, 0.01, 1.0, 3.0, 3.5, 2.0 * PI - 0.2] {
            let q = target * UnitQuaternion::from_axis_angle(&axis, angle).into_inner();
            let (e, _) = attitude_error(&q, &target);
            // the shorter rotation: an angle beyond π is the other way round by 2π − angle
            let (phi, sign) = match angle > PI {
                true => (2.0 * PI - angle, -1.0),
                false => (angle, 1.0),
            };
            assert_relative_eq!(
                e,
                axis.into_inner() * (2.0 * (phi / 2.0).sin() * sign),
                epsilon = 1e-12
            );
            assert_relative_eq!(pointing_angle(&q, &target), phi, epsilon = 1e-12);
            // q and −q are one attitude
            assert_eq!(attitude_error(&(-q), &target).0, e);
        }
    }

    #[test]
    fn a_body_at_rest_in_the_orbiting_frame_feels_no_feedback() {
        // aligned with LVLH and turning with it, ω = (0, −n, 0) in its axes
        let n = 1.1e-3;
        let k = Matrix3::from_diagonal(&Vector3::new(0.2, 0.3, 0.4));
        let offset = Quaternion::new(0.8, 0.1, -0.3, 0.5).normalize();
        let target = Target::Lvlh {
            orbit_rate: n,
            offset,
        };
        for t in [0.0, 1000.0, 4321.0] {
            let (q_t, rate) = target.at(t);
            // the body is the target frame itself: its rate is the frame's, in its axes
            let omega = rate;
            let tau = quaternion_feedback(&q_t, &omega, &q_t, &rate, &k, &k);
            assert!(tau.amax() < 1e-15, "{tau}");
            // and that rate is the orbit's: n about minus the orbit normal, in world axes
            let world = rotation_matrix(&q_t) * omega;
            assert_relative_eq!(world, Vector3::new(0.0, 0.0, n), epsilon = 1e-15);
        }
        // a body at rest in space, aligned with the frame at t, is pushed to turn with it
        let (q_t, rate) = Target::Lvlh {
            orbit_rate: n,
            offset: Quaternion::identity(),
        }
        .at(0.0);
        let tau = quaternion_feedback(&q_t, &Vector3::zeros(), &q_t, &rate, &k, &k);
        assert_relative_eq!(tau, Vector3::new(0.0, -0.3 * n, 0.0), epsilon = 1e-18);
    }

    #[test]
    fn the_feedback_is_proportional_and_derivative_about_a_principal_axis() {
        // turned by φ about z and turning at φ̇: τ_z = −K_p 2 sin(φ/2) − K_d φ̇
        let (kp, kd) = (0.4, 1.3);
        let (phi, rate) = (0.3, -0.05);
        let q = Quaternion::new((phi / 2.0_f64).cos(), 0.0, 0.0, (phi / 2.0_f64).sin());
        let tau = quaternion_feedback(
            &q,
            &Vector3::new(0.0, 0.0, rate),
            &Quaternion::identity(),
            &Vector3::zeros(),
            &(Matrix3::identity() * kp),
            &(Matrix3::identity() * kd),
        );
        assert_relative_eq!(
            tau,
            Vector3::new(0.0, 0.0, -kp * 2.0 * (phi / 2.0).sin() - kd * rate),
            epsilon = 1e-16
        );
    }

    #[test]
    fn dumping_drains_the_momentum_across_the_field_only() {
        let b = Vector3::new(1e-5, -2e-5, 2.5e-5);
        let unit = b.normalize();
        let h = Vector3::new(0.02, 0.01, -0.03);
        let tau = momentum_dump(0.1, &h, &b).cross(&b);
        assert_relative_eq!(tau, -(h - unit * h.dot(&unit)) * 0.1, epsilon = 1e-15);
        assert!(momentum_dump(0.1, &(unit * 0.3), &b).cross(&b).amax() < 1e-17);
        assert_eq!(momentum_dump(0.1, &h, &Vector3::zeros()), Vector3::zeros());
    }
}
