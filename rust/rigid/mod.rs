//! Methods made for the free rigid body: RK4 with the invariants projected back, the
//! splittings that keep them to round-off, and the classic geometric integrators of the
//! atlas: the implicit midpoint rule, the discrete Moser–Veselov algorithm (plain and with
//! modified moments), Runge–Kutta–Munthe-Kaas and Crouch–Grossman on the unit quaternions;
//! and the splittings of a body under torques on the exact free flow (Strang's, and Suzuki's
//! fourth-order composition of it).

mod crouch_grossman;
mod dmv;
mod exact_kick;
mod exact_kick4;
mod implicit_midpoint;
mod lie;
mod projected;
mod rkmk;
mod splitting;

pub use crouch_grossman::CrouchGrossman3;
pub use dmv::{DiscreteMoserVeselov, Dmv, DmvModified};
pub use exact_kick::ExactKick;
pub use exact_kick4::ExactKick4;
pub use implicit_midpoint::ImplicitMidpoint;
pub use projected::Rk4Projected;
pub use rkmk::Rkmk4;
pub use splitting::{Splitting, Splitting2, Splitting4, Splitting6};
