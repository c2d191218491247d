//! Free rotation of a rigid body in weightlessness: the Dzhanibekov effect.
//!
//! The core integrates eq. 1 of Kutsenko & Zapolsky — Euler's equations for the body-frame
//! angular velocity `ω = (u, v, w)` together with the body-to-world unit quaternion
//! `q = (Q, U, V, W)` (scalar first) — and rotates point arrays by `q` without trigonometry.
//!
//! ```text
//! Ix u' = (Iy - Iz) v w      Q' = -½ (U u + V v + W w)
//! Iy v' = (Iz - Ix) u w      U' =  ½ (Q u + V w - W v)
//! Iz w' = (Ix - Iy) u v      V' =  ½ (Q v + W u - U w)
//!                            W' =  ½ (Q w + U v - V u)
//! ```
//!
//! The quaternion rows are the body-frame law `q' = ½ q ⊗ (0, ω)`; the paper's printed `V'`
//! row has a sign error (see [`dynamics`]).
//!
//! The crate is Python-free unless the `python` feature is on; then the `python` module
//! (rust/python/) holds the bindings and nothing else.
//!
//! The modules in layers, each using only the layers before it (tests/python/project/test_import_order.py
//! checks this line against the code): [`error`], [`isa`] → [`pool`], [`body`], [`buffer`],
//! [`ode`] → [`kinematics`], [`float`], [`mesh`], [`integrators`] → [`dynamics`] → [`exact`],
//! [`observe`] → [`rigid`] → [`run`] → [`ensemble`] → `python`.

pub mod body;
pub mod buffer;
pub mod dynamics;
pub mod ensemble;
pub mod error;
pub mod exact;
pub mod float;
pub mod integrators;
pub mod isa;
pub mod kinematics;
pub mod mesh;
pub mod observe;
pub mod ode;
pub mod pool;
pub mod rigid;
pub mod run;

#[cfg(feature = "python")]
mod python;

pub use body::RigidBody;
pub use dynamics::{FreeRigidBody, State};
pub use error::{Error, Result};
