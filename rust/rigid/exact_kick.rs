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
//! round-off. It runs a constant body under torques of time and attitude (no wheels, dampers or
//! other parts: their free part is not the elliptic motion; steps end on a tabulated torque's
//! knots). Each step builds the closed form from its start (the
//! elliptic functions' parameter, `K`, the phase: [`ExactMotion::try_new_for_step`]), about
//! the cost of ten RK4 steps under the gravity gradient. [`super::ExactKick4`] composes it to
//! fourth order.

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
    /// The splitting of `model` from the start `x0`.
    ///
    /// # Errors
    /// A model whose body is not constant and diagonal, or that has wheels or a damper
    /// (refused before, by the registry); a start whose closed form does not start there
    /// ([`ExactMotion::try_new`]: moments it cannot resolve), checked once here so that each
    /// step builds the lighter [`ExactMotion::try_new_for_step`].
    pub fn of<const N: usize, const H: bool>(
        model: &GeneralModel<N, H>,
        x0: &[f64; N],
    ) -> Result<Self> {
        let refuse = || {
            Error::invalid(
                "method",
                "'splitting_exact' and 'splitting_exact4' run a constant body in principal axes \
                 under torques alone",
                model.kinds().names(),
            )
        };
        if N != 7 || model.has_parts_inside() {
            return Err(refuse());
        }
        let InertiaLaw::Constant(c) = model.inertia() else {
            return Err(refuse());
        };
        let d = c.moments().ok_or_else(refuse)?;
        let out = Self {
            body: RigidBody::try_new([d.x, d.y, d.z])?,
        };
        let (omega, q) = out.rates_and_attitude(x0);
        ExactMotion::try_new(&out.body, omega, q)?;
        Ok(out)
    }

    /// The body rates and the attitude of a state `[H, q]`.
    #[inline(always)]
    fn rates_and_attitude<const N: usize>(&self, x: &[f64; N]) -> ([f64; 3], [f64; 4]) {
        let h_body = Vector3::new(x[0], x[1], x[2]);
        let omega = h_body.component_div(&self.body.inertia_body());
        let q = attitude(x);
        (omega.into(), [q.w, q.i, q.j, q.k])
    }

    /// The momentum kick `H ← H + a τ_b(t, q)` (the attitude and the time held).
    #[inline(always)]
    pub(crate) fn kick<const N: usize, const H: bool>(
        sys: &GeneralModel<N, H>,
        t: f64,
        a: f64,
        x: &mut [f64; N],
    ) {
        let tau = sys.torque(t, x) * a;
        x[0] += tau.x;
        x[1] += tau.y;
        x[2] += tau.z;
    }

    /// The exact free motion over `h` (any sign) from `x`.
    #[inline]
    pub(crate) fn free_flow<const N: usize>(&self, h: f64, x: &mut [f64; N]) {
        let moments = self.body.inertia_body();
        let (omega, q) = self.rates_and_attitude(x);
        // a start the closed form refuses (not finite) leaves the state to the driver's
        // finiteness check
        let Ok(motion) = ExactMotion::try_new_for_step(&self.body, omega, q) else {
            x[0] = f64::NAN;
            return;
        };
        let s = motion.state_at(h);
        let h_new = Vector3::new(s[0], s[1], s[2]).component_mul(&moments);
        x[..3].copy_from_slice(h_new.as_slice());
        set_attitude(x, &nalgebra::Quaternion::new(s[3], s[4], s[5], s[6]));
    }
}

impl<const N: usize, const H: bool> Stepper<N, GeneralModel<N, H>> for ExactKick {
    const ORDER: u32 = 2;
    /// Two torque evaluations (and one closed-form free motion).
    const RHS_PER_STEP: u64 = 2;

    fn step(&self, sys: &GeneralModel<N, H>, t: f64, h: f64, x: &mut [f64; N]) {
        Self::kick(sys, t, 0.5 * h, x);
        self.free_flow(h, x);
        Self::kick(sys, t + h, 0.5 * h, x);
    }
}
