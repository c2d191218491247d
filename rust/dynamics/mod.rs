//! The models: the right-hand sides a run integrates. The constant free body
//! ([`FreeRigidBody`], eq. 1) and the general model ([`GeneralModel`]: a constant or
//! scheduled body with parts) implement one trait ([`Model`]); what a user describes is a
//! [`System`] (a body, its parts — dampers, wheels — and its external torques), which the run turns into one of them. Each model the registry knows has an
//! entry in [`MODELS`]; the registry of methods ([`crate::run::registry`]) says which methods
//! run which.

mod callable;
mod damper;
mod deployment;
mod free;
mod general;
pub mod gravity;
mod hinge;
mod kinds;
pub mod model;
pub mod multibody;
mod slosh;
mod spring_mass;
mod system;
mod tabulated;
mod torques;
mod wheel;
mod wheel_schedule;

pub use callable::{CallableTorque, TorqueFunction};
pub use damper::Damper;
pub use deployment::Deployment;
pub use free::*;
pub use general::{ConstantInertia, GeneralModel, InertiaLaw};
pub use hinge::{Hinge, LoneHinge, Pose};
pub use kinds::{Kinds, ModelInfo, MODELS};
pub use model::{Conserved, MidAxis, Model};
pub use slosh::{LoneSlosh, Rod, Slosh, SloshRates};
pub use spring_mass::{LoneSpring, SpringMass};
pub use system::{Part, System, SystemBody};
pub use tabulated::{Outside, Table, TabulatedTorque};
pub use torques::{Frame, Torque, Torques};
pub use wheel::Wheel;
pub use wheel_schedule::WheelSchedule;
