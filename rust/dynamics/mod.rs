//! The models: the right-hand sides a run integrates, one file per model. Each model has a
//! name here; the registry of methods ([`crate::run::registry`]) says which methods run it.

mod free;

pub use free::*;

/// The constant free rigid body ([`FreeRigidBody`]).
pub const FREE: &str = "free";
