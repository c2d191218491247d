//! The models: the right-hand sides a run integrates. The constant free body
//! ([`FreeRigidBody`], eq. 1) and the general model ([`GeneralModel`]: an inertia law with its
//! parts) implement one trait ([`Model`]); what a user describes is a [`System`] (a body and
//! its parts in order: dampers, wheels, external torques, …), which the run turns into one of
//! them. Every part implements one trait ([`Part`]) and declares itself once
//! ([`ModelInfo`]); the registry ([`registry`]) lists them, one line each, and makes the enum
//! the hot loop matches on ([`AnyPart`]) and the table [`MODELS`] the methods' registry
//! ([`crate::run::registry`]), the binding, files and scenes read.

mod callable;
mod clocks;
pub mod control;
mod damper;
mod deployment;
mod free;
mod general;
pub mod gravity;
mod hinge;
mod kinds;
mod lone_step;
pub mod model;
pub(crate) mod moving;
pub mod multibody;
pub mod part;
pub mod registry;
mod slosh;
mod spring_mass;
mod system;
mod tabulated;
mod torques;
#[cfg(test)]
pub(crate) mod toy;
mod wheel;
mod wheel_schedule;

pub use callable::CallableTorque;
pub use clocks::Clocks;
pub use damper::Damper;
pub use deployment::Deployment;
pub use free::*;
pub use general::{
    ConstantInertia, GeneralModel, InertiaLaw, Movers, Moving, NoMoving, MAX_PARTS_STATE,
    STATE_SIZES,
};
pub use gravity::GravityGradient;
pub use hinge::{Hinge, LoneHinge, Pose};
pub use kinds::{Conserved, Kinds, Traits};
pub use model::{MidAxis, Model};
pub use part::{
    Arg, Ctx, Dim, EnergyRole, Field, Fields, Frame, Function, MapFunction, ModelInfo, Param,
    ParamKind, Part, Sampling, Value,
};
pub use registry::{AnyPart, MODELS};
pub use slosh::{LoneSlosh, Rod, Slosh, SloshRates};
pub use spring_mass::{LoneSpring, SpringMass};
pub use system::{System, SystemBody};
pub use tabulated::{Outside, Table, TabulatedTorque};
pub use torques::ConstantTorque;
pub use wheel::Wheel;
pub use wheel_schedule::WheelSchedule;
