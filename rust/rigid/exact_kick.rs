//! Strang's splitting on the exact free flow: a body under an external torque advanced by the
//! free rigid body's closed-form motion ([`crate::exact::ExactMotion`]) between half kicks
//! of the torque (the attitude held, the time held; the free flow carries the time):
//!
//! ```text
//! H ← H + ½ h τ_b(t, q);   (ω, q) ← exact free motion over h from (I⁻¹ H, q);   t ← t + h;
//! H ← H + ½ h τ_b(t, q)
//! ```
//!
//! Each sub-flow is exact and the composition symmetric, so the method is of order 2 (Hairer,
//! Lubich & Wanner, *Geometric Numerical Integration*, 2006, §II.5); with no torque it is the
//! exact solution. The free flow keeps `|q| = 1`, the kicks do not touch `q`: `|q|` is kept to
//! round-off. It runs a constant body under torques (no wheels, dampers or schedules: their free
//! part is not the elliptic motion). Each step builds the closed form from its start (the
//! elliptic functions' parameter, `K`, the phase), about the cost of a few dozen RK4
//! right-hand sides.

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::model::{attitude, set_attitude};
use crate::dynamics::{GeneralModel, InertiaLaw, Model};
use crate::error::{Error, Result};
use crate::exact::ExactMotion;
use crate::ode::Stepper;

/// The splitting (see the module doc), for a body of principal moments `moments`.
#[derive(Debug, Clone, Copy)]
pub struct ExactKick {
    body: RigidBody,
}

impl ExactKick {
    /// The splitting of `model`.
    ///
    /// # Errors
    /// A model whose body is not constant and diagonal, or that has wheels or a damper
    /// (refused before, by the registry).
    pub fn of<const N: usize>(model: &GeneralModel<N>) -> Result<Self> {
        let refuse = || {
            Error::invalid(
                "method",
                "'splitting_exact' runs a constant body in principal axes under torques alone",
                model.kinds().names(),
            )
        };
        if N != 7 || model.has_wheels() {
            return Err(refuse());
        }
        let InertiaLaw::Constant(c) = model.inertia() else {
            return Err(refuse());
        };
        let d = c.moments().ok_or_else(refuse)?;
        Ok(Self {
            body: RigidBody::try_new([d.x, d.y, d.z])?,
        })
    }

    #[inline(always)]
    fn kick<const N: usize>(sys: &GeneralModel<N>, t: f64, half: f64, x: &mut [f64; N]) {
        let tau = sys.torque(t, x) * half;
        x[0] += tau.x;
        x[1] += tau.y;
        x[2] += tau.z;
    }
}

impl<const N: usize> Stepper<N, GeneralModel<N>> for ExactKick {
    const ORDER: u32 = 2;
    /// Two torque evaluations (and one closed-form free motion).
    const RHS_PER_STEP: u64 = 2;

    fn step(&self, sys: &GeneralModel<N>, t: f64, h: f64, x: &mut [f64; N]) {
        Self::kick(sys, t, 0.5 * h, x);
        let moments = self.body.inertia_body();
        let h_body = Vector3::new(x[0], x[1], x[2]);
        let omega = h_body.component_div(&moments);
        let q = attitude(x);
        // a start the closed form refuses (not finite) leaves the state to the driver's
        // finiteness check
        let Ok(motion) = ExactMotion::try_new(&self.body, omega.into(), [q.w, q.i, q.j, q.k])
        else {
            x[0] = f64::NAN;
            return;
        };
        let s = motion.state_at(h);
        let h_new = Vector3::new(s[0], s[1], s[2]).component_mul(&moments);
        x[..3].copy_from_slice(h_new.as_slice());
        set_attitude(x, &nalgebra::Quaternion::new(s[3], s[4], s[5], s[6]));
        Self::kick(sys, t + h, 0.5 * h, x);
    }
}
