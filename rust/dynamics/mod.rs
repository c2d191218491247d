//! The models: the right-hand sides a run integrates, one file per model.

mod damper;
mod deployment;
mod free;
pub mod model;

pub use damper::{DampedBody, DamperState};
pub use deployment::{Deployment, DeploymentState};
pub use free::*;
pub use model::Model;
