//! The tilt of the spin axis: how far the body axis that starts nearest the angular momentum
//! swings away from it over a run.
//!
//! The *spin axis* is the body axis `e_k` nearest the angular momentum `L` at `t = 0` (the
//! largest `|L_k| = I_k |ω_k|`, the first on a tie), directed to `L`'s side: `s e_k`,
//! `s = sign L_k(0)`. Its tilt at time `t` is the angle between `L` and `s e_k`,
//! `cos θ(t) = s I_k ω_k(t) / |L|`, and since the motion keeps `|L|`, the largest tilt of a run
//! is `θ_max = arccos(min_t s I_k ω_k(t) / |L(0)|)`, the minimum taken over the initial state
//! and every step.
//!
//! Below 90° the spin axis only wobbles about `L`; above 90° it has turned over. It does so
//! for every start nearest the intermediate axis (whose rate changes sign on both sides of the
//! separatrix), and for a start nearest one stable axis whose motion, beyond the separatrix,
//! circulates the other; otherwise `θ_max` stays below 90°, approaching it near the
//! separatrix. A body at rest has no spin axis: its tilt is 0.

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::State;
use crate::observe::{component, Observer};

/// Watches the tilt of the spin axis (see the module docs) at every step and frame.
#[derive(Debug, Clone)]
pub struct TiltMonitor {
    axis: usize,
    sign: f64,
    /// `I_k / |L(0)|`, so that `cos θ = cos_per_rate · s ω_k` (computed on a scaled copy, as
    /// [`crate::observe::DriftMonitor`] does, so that nothing overflows).
    cos_per_rate: f64,
    /// The smallest `s ω_k` seen.
    lowest: f64,
}

impl TiltMonitor {
    /// A monitor for `body` starting from body rates `omega0`.
    pub fn new(body: &RigidBody, omega0: &Vector3<f64>) -> Self {
        let inertia = body.inertia_body();
        let largest = omega0.amax();
        let omega_scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
        let inertia_scaled = inertia / inertia.max();
        let l = inertia_scaled.component_mul(&(omega0 * omega_scale));
        let mut axis = 0;
        for k in 1..3 {
            if l[k].abs() > l[axis].abs() {
                axis = k;
            }
        }
        let norm = l.norm();
        Self {
            axis,
            sign: if l[axis] < 0.0 { -1.0 } else { 1.0 },
            cos_per_rate: if norm > 0.0 {
                inertia_scaled[axis] * omega_scale / norm
            } else {
                0.0
            },
            lowest: f64::INFINITY,
        }
    }

    /// The spin axis (0, 1, 2 for x, y, z) and its direction `s = ±1`.
    pub fn spin_axis(&self) -> (usize, f64) {
        (self.axis, self.sign)
    }

    /// The smallest `s ω_k` seen so far (`+∞` before the first frame).
    pub(crate) fn lowest(&self) -> f64 {
        self.lowest
    }

    /// Takes the smallest `s ω_k` that the SIMD lanes tracked for this run.
    pub(crate) fn set_lowest(&mut self, lowest: f64) {
        self.lowest = lowest;
    }

    /// The largest tilt seen, `θ_max` in radians, in `[0, π]`; 0 for a body at rest.
    pub fn tilt(&self) -> f64 {
        if self.cos_per_rate == 0.0 || !self.lowest.is_finite() {
            return 0.0;
        }
        (self.cos_per_rate * self.lowest).clamp(-1.0, 1.0).acos()
    }

    #[inline(always)]
    fn see(&mut self, x: &State) {
        self.lowest = self.lowest.min(self.sign * component(x, self.axis));
    }
}

impl Observer for TiltMonitor {
    const WANTS_STEPS: bool = true;

    #[inline(always)]
    fn frame(&mut self, _index: usize, _t: f64, x: &State) {
        self.see(x);
    }

    #[inline(always)]
    fn step(&mut self, _t0: f64, _x0: &State, _t1: f64, x1: &State) {
        self.see(x1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_spin_axis_is_the_axis_nearest_l() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        // L = (1, -4, 1.5): y is nearest, on its negative side
        let monitor = TiltMonitor::new(&body, &Vector3::new(1.0, -2.0, 0.5));
        assert_eq!(monitor.spin_axis(), (1, -1.0));
    }

    #[test]
    fn tilt_is_the_angle_between_l_and_the_axis() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let omega = Vector3::new(0.0, 0.3, 0.4); // L = (0, 0.6, 1.2)
        let mut monitor = TiltMonitor::new(&body, &omega);
        monitor.frame(0, 0.0, &[0.0, 0.3, 0.4, 1.0, 0.0, 0.0, 0.0]);
        assert_relative_eq!(monitor.tilt(), (0.6_f64).atan2(1.2), epsilon = 1e-15);
        // the axis swung to the other side of L: more than 90°
        monitor.step(0.0, &[0.0; 7], 1.0, &[0.0, 0.3, -0.2, 1.0, 0.0, 0.0, 0.0]);
        let expected = (-0.6 / 0.6_f64.hypot(1.2)).acos();
        assert!(expected > std::f64::consts::FRAC_PI_2);
        assert_relative_eq!(monitor.tilt(), expected, epsilon = 1e-15);
    }

    #[test]
    fn a_body_at_rest_does_not_tilt() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let mut monitor = TiltMonitor::new(&body, &Vector3::zeros());
        monitor.frame(0, 0.0, &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        assert_eq!(monitor.tilt(), 0.0);
    }
}
