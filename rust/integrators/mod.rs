//! General-purpose time steppers on the machinery of [`crate::ode`]: RK4 with a fixed step
//! and the Dormand–Prince pairs with error control.

mod dop853;
mod dopri5;
mod rk4;

pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use rk4::Rk4;
