//! The models: the right-hand sides a run integrates, one file per model.

mod free;

pub use free::*;
