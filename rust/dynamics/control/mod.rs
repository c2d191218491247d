//! Closing the loop: the Earth's magnetic field along a circular orbit, the actuators a
//! controller drives (magnetorquers, wheels with torque and momentum limits), the control laws
//! (B-dot, quaternion feedback, momentum dumping), the sensors they read (gyro, magnetometer,
//! star tracker) and the counter-based noise those draw. Each is a pure function of its inputs,
//! so that a controller part only wires them together at its sample times (DESIGN.md §14: the
//! law is evaluated at sample times on what the sensors measure, its command held until the
//! next sample).
//!
//! Frames: the world is the orbit's inertial frame of [`super::Torques`] (the orbit in the
//! world `x–y` plane, the body at `r̂(t) = (cos nt, sin nt, 0)`, the orbit normal world `+z`);
//! vectors of the body are in body axes, attitudes world-from-body, scalar first.

pub mod actuators;
mod bdot;
mod common;
mod controller;
mod dumping;
pub mod field;
pub mod laws;
pub mod noise;
mod pointing;
mod reaction;
mod residual;
pub mod sensors;

pub use actuators::{clip, limit_wheel, wheel_torques, WheelAllocation, WheelCommand};
pub use bdot::BDot;
pub use common::{EARTH_MOMENT, EARTH_MU};
pub use controller::Controller;
pub use dumping::MomentumDumping;
pub use field::DipoleField;
pub use laws::{
    attitude_error, bdot, detumble_gain, lvlh_attitude, momentum_dump, pointing_angle,
    quaternion_feedback, rate_detumble, Target,
};
pub use noise::{philox4x64, Noise};
pub use pointing::QuaternionFeedback;
pub use residual::ResidualDipole;
pub use sensors::{Gyro, Magnetometer, StarTracker};
