//! Methods made for the free rigid body: RK4 with the invariants projected back, and the
//! splittings that keep them to round-off.

mod projected;
mod splitting;

pub use projected::Rk4Projected;
pub use splitting::{Splitting, Splitting2, Splitting4};
