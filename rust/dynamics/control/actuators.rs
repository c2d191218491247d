//! What actuators make of a command: magnetorquers' saturation, reaction wheels' torque and
//! momentum limits, and the share of a body torque each wheel is asked for.
//!
//! **Magnetorquers** are coils along the body's axes, each giving a dipole up to its limit:
//! a commanded dipole is clipped axis by axis (each coil saturates on its own; the direction
//! of the command is not kept), and the body feels `τ = m × B`.
//!
//! **Reaction wheels.** A wheel of axis `a` (body axes) stores the relative momentum `h`
//! (the gyrostat of [`crate::dynamics::Wheel`]); its motor is commanded the rate `ḣ = u`, and
//! the body feels `−u a` (an internal torque: the total momentum `H` does not change). The
//! motor gives at most `|u| ≤ u_max`, and the wheel spins up to `|h| ≤ h_max` (its speed
//! limit). A command is held for a sample period `T`, over which `h` moves on the line
//! `h + u (t − t_k)`; it is limited at the sample so that the line stays within the momentum
//! limit, `(−h_max − h) / T ≤ u ≤ (h_max − h) / T`, then to the torque limit (a wheel started
//! beyond its momentum limit is brought back at its torque limit). Over a hold the limited
//! wheel transfers exactly the momentum a wheel stopped at its limit would; within it, it
//! spreads it evenly.

use nalgebra::{DMatrix, Vector3};

use crate::error::{Error, Result};

/// `value` clipped to `±limit` (`limit ≥ 0`; infinite for none), and whether it was.
///
/// # Example
/// ```
/// use dzhanibekov::dynamics::control::clip;
/// assert_eq!(clip(-3.0, 2.0), (-2.0, true));
/// assert_eq!(clip(1.5, f64::INFINITY), (1.5, false));
/// ```
#[inline]
pub fn clip(value: f64, limit: f64) -> (f64, bool) {
    match value.abs() > limit {
        true => (limit.copysign(value), true),
        false => (value, false),
    }
}

/// A wheel's command after its limits (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelCommand {
    /// The momentum rate `u` the wheel is given over the hold.
    pub torque: f64,
    /// Whether the torque limit cut the command.
    pub torque_saturated: bool,
    /// Whether the momentum limit cut the command.
    pub momentum_saturated: bool,
}

/// The command `command` (a momentum rate) of a wheel holding `momentum`, limited for a hold
/// of `hold` by `torque_limit` and `momentum_limit` (each positive, infinite for none).
///
/// # Example
/// ```
/// use dzhanibekov::dynamics::control::limit_wheel;
/// // 0.1 short of its limit, a wheel asked for 1 over a hold of 1 is given 0.1
/// let c = limit_wheel(1.0, 0.9, 1.0, 5.0, 1.0);
/// assert!((c.torque - 0.1).abs() < 1e-15 && c.momentum_saturated && !c.torque_saturated);
/// ```
#[inline]
pub fn limit_wheel(
    command: f64,
    momentum: f64,
    hold: f64,
    torque_limit: f64,
    momentum_limit: f64,
) -> WheelCommand {
    let (low, high) = match momentum_limit.is_finite() {
        true => (
            (-momentum_limit - momentum) / hold,
            (momentum_limit - momentum) / hold,
        ),
        false => (f64::NEG_INFINITY, f64::INFINITY),
    };
    // max/min rather than clamp: never a panic, whatever the inputs
    let kept = command.max(low).min(high);
    let (torque, torque_saturated) = clip(kept, torque_limit);
    WheelCommand {
        torque,
        torque_saturated,
        momentum_saturated: kept != command,
    }
}

/// The minimum-norm share of a body torque among wheels: `u = −A⁺ τ`, with `A` the matrix of
/// the wheels' axes (columns, body axes) and `A⁺` its pseudo-inverse, so that the wheels give
/// the body `−A u = τ` when their axes span it (three or more independent axes), and the
/// torque's least-squares part along them otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelAllocation {
    /// `A⁺`, one row of three per wheel.
    rows: Vec<Vector3<f64>>,
}

/// The share of `torque` (body axes) each wheel is asked for, written into `out` (one a
/// wheel), by `allocation` (see [`WheelAllocation`]).
#[inline]
pub fn wheel_torques(allocation: &WheelAllocation, torque: &Vector3<f64>, out: &mut [f64]) {
    for (u, row) in out.iter_mut().zip(&allocation.rows) {
        *u = -row.dot(torque);
    }
}

impl WheelAllocation {
    /// The allocation among wheels of unit axes `axes` (body axes).
    ///
    /// # Errors
    /// No wheel, or an axis that is not a finite unit vector.
    pub fn try_new(axes: &[Vector3<f64>]) -> Result<Self> {
        if axes.is_empty() {
            return Err(Error::invalid("axes", "must hold at least one wheel", 0));
        }
        if let Some(a) = axes
            .iter()
            .find(|a| !(a.iter().all(|v| v.is_finite()) && (a.norm() - 1.0).abs() < 1e-12))
        {
            return Err(Error::invalid("axes", "must be unit vectors", a.as_slice()));
        }
        let a = DMatrix::from_fn(3, axes.len(), |i, j| axes[j][i]);
        let pinv = a
            .pseudo_inverse(1e-12)
            .map_err(|_| Error::invalid("axes", "must have a pseudo-inverse", axes.len()))?;
        Ok(Self {
            rows: (0..axes.len())
                .map(|i| Vector3::new(pinv[(i, 0)], pinv[(i, 1)], pinv[(i, 2)]))
                .collect(),
        })
    }

    /// How many wheels it shares among.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether it has no wheel (never: [`WheelAllocation::try_new`] refuses it).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn a_wheel_within_its_limits_is_given_its_command() {
        let c = limit_wheel(0.3, 0.5, 1.0, 1.0, 2.0);
        assert_eq!(
            c,
            WheelCommand {
                torque: 0.3,
                torque_saturated: false,
                momentum_saturated: false
            }
        );
        let free = limit_wheel(-7.0, 1e6, 0.1, f64::INFINITY, f64::INFINITY);
        assert_eq!(free.torque, -7.0);
    }

    #[test]
    fn the_torque_limit_cuts_a_command_either_way() {
        for (command, expected) in [(3.0, 0.5), (-3.0, -0.5)] {
            let c = limit_wheel(command, 0.0, 1.0, 0.5, 100.0);
            assert_eq!(c.torque, expected);
            assert!(c.torque_saturated && !c.momentum_saturated);
        }
    }

    #[test]
    fn a_held_command_brings_the_wheel_exactly_to_its_momentum_limit() {
        // h + u T lands on ±h_max, not beyond
        let (h, hold, limit) = (0.7, 0.25, 1.0);
        let up = limit_wheel(10.0, h, hold, f64::INFINITY, limit);
        assert_relative_eq!(h + up.torque * hold, limit, epsilon = 1e-15);
        let down = limit_wheel(-10.0, h, hold, f64::INFINITY, limit);
        assert_relative_eq!(h + down.torque * hold, -limit, epsilon = 1e-15);
        assert!(up.momentum_saturated && down.momentum_saturated);
        // at the limit a wheel keeps its speed, and may always spin down
        let held = limit_wheel(1.0, limit, hold, f64::INFINITY, limit);
        assert_eq!(held.torque, 0.0);
        assert_eq!(limit_wheel(-0.1, limit, hold, 1.0, limit).torque, -0.1);
    }

    #[test]
    fn a_wheel_beyond_its_limit_is_brought_back_at_its_torque_limit() {
        let c = limit_wheel(0.0, 1.5, 0.1, 0.2, 1.0);
        assert_eq!(c.torque, -0.2);
        assert!(c.torque_saturated && c.momentum_saturated);
        let c = limit_wheel(0.0, -1.5, 0.1, 0.2, 1.0);
        assert_eq!(c.torque, 0.2);
    }

    #[test]
    fn three_orthogonal_wheels_each_take_their_axis_share() {
        let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
        let a = WheelAllocation::try_new(&axes).unwrap();
        let tau = Vector3::new(0.3, -0.2, 0.5);
        let mut u = [0.0; 3];
        wheel_torques(&a, &tau, &mut u);
        assert_relative_eq!(Vector3::from(u), -tau, epsilon = 1e-15);
    }

    #[test]
    fn a_pyramid_of_four_wheels_gives_the_torque_at_the_least_norm() {
        // four wheels at 54.74° from z (NASA's standard pyramid): the null space is
        // (1, −1, 1, −1) in this order
        let c = 1.0 / 3.0_f64.sqrt();
        let axes = [
            Vector3::new(c, c, c),
            Vector3::new(-c, c, c),
            Vector3::new(-c, -c, c),
            Vector3::new(c, -c, c),
        ];
        let a = WheelAllocation::try_new(&axes).unwrap();
        let tau = Vector3::new(0.3, -0.2, 0.5);
        let mut u = [0.0; 4];
        wheel_torques(&a, &tau, &mut u);
        let given: Vector3<f64> = axes.iter().zip(&u).map(|(a, u)| -a * *u).sum();
        assert_relative_eq!(given, tau, epsilon = 1e-14);
        assert!((u[0] - u[1] + u[2] - u[3]).abs() < 1e-14, "{u:?}");
    }

    #[test]
    fn one_wheel_takes_the_torques_part_along_its_axis() {
        let axis = Vector3::new(0.6, 0.8, 0.0);
        let a = WheelAllocation::try_new(&[axis]).unwrap();
        let mut u = [0.0];
        wheel_torques(&a, &Vector3::new(1.0, 2.0, 3.0), &mut u);
        assert_relative_eq!(u[0], -(0.6 + 1.6), epsilon = 1e-14);
    }

    #[test]
    fn axes_that_are_not_unit_vectors_are_refused() {
        assert!(WheelAllocation::try_new(&[]).is_err());
        assert!(WheelAllocation::try_new(&[Vector3::new(1.0, 1.0, 0.0)]).is_err());
        assert!(WheelAllocation::try_new(&[Vector3::new(f64::NAN, 0.0, 0.0)]).is_err());
    }
}
