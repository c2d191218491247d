//! Methods made for the free rigid body: RK4 with the invariants projected back, and the
//! splittings that keep them to round-off; and Strang's splitting of a body under torques
//! on the exact free flow.

mod exact_kick;
mod projected;
mod splitting;

pub use exact_kick::ExactKick;
pub use projected::Rk4Projected;
pub use splitting::{Splitting, Splitting2, Splitting4};
