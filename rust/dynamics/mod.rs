//! The models: the right-hand sides a run integrates, one file per model. Each model has a
//! name here; the registry of methods ([`crate::run::registry`]) says which methods run it.

mod damper;
mod deployment;
mod free;
pub mod model;

pub use damper::{DampedBody, DamperState};
pub use deployment::{Deployment, DeploymentState};
pub use free::*;
pub use model::Model;

/// The constant free rigid body ([`FreeRigidBody`]).
pub const FREE: &str = "free";
/// A body whose inertia changes in a prescribed way ([`Deployment`]).
pub const DEPLOYMENT: &str = "deployment";
/// A body with a spherical viscous damper ([`DampedBody`]).
pub const DAMPER: &str = "damper";
