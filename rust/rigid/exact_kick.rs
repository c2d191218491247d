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
//!
//! **The invariants, carried.** A closed form rebuilt from each step's rounded end does not
//! keep the motion's invariants `|H|²` and `2E = Hᵀ I⁻¹ H` to round-off over the run: each
//! rebuild moves them by a fraction of an ulp, with a bias (with no torque, body (1, 1.7,
//! 2.3), ω₀ = (0.4, −0.9, 0.6), `dt = 0.1`: `E` rose by 5.6e-12 over 10⁶ steps of
//! `splitting_exact4`, linearly), and the frequency they set moves the phase by the integral
//! of that: an error growing as the square of the time (the attitude 1.6e-10, 1.6e-8 and
//! 1.6e-6 rad off the exact motion at T = 10³, 10⁴, 10⁵, almost all of it about `L`). So the
//! splitting carries both in double-double from step to step: a kick changes them by what it
//! did to `H` (exactly, from the float64 momenta before and after it), a free flow not at all,
//! and the momentum at the end of each free flow is moved onto them (one Newton step of the
//! two constraints, along their gradients `H` and `I⁻¹ H`: a move of a few ulps). With no
//! torque, the invariants then stay what the start gave them, to the round-off of a
//! compensated sum. With them the error grew linearly (1.7e-10 rad at T = 10⁵), by a bias of
//! the phase each rebuild takes from the rounded state; so the phase is carried too: a free
//! flow that starts where the last one ended (no kick in between moved the state: a zero
//! torque) goes on along the same closed form, its time summed in double-double, rather than
//! rebuilding it. With no torque the splitting is then the exact solution evaluated at the
//! step's time, and errs as little. The carried values live in the stepper (a run's steps are
//! taken in order, on one thread); a step from another state takes them afresh from it.

use std::cell::RefCell;

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::dynamics::model::{attitude, set_attitude};
use crate::dynamics::{GeneralModel, InertiaLaw, Model};
use crate::error::{Error, Result};
use crate::exact::compensated::{dd_add, dd_diff, squares, two_sum, weighted_squares, Dd};
use crate::exact::ExactMotion;
use crate::ode::Stepper;

/// The splitting (see the module doc), for a body of principal moments `moments`.
#[derive(Debug, Clone)]
pub struct ExactKick {
    body: RigidBody,
    /// `I⁻¹`'s diagonal, rounded once: the metric of the carried energy.
    inverse: [f64; 3],
    carry: RefCell<Carry>,
}

/// What a run's steps carry from one to the next (see the module doc).
#[derive(Debug, Clone, Default)]
struct Carry {
    /// The invariants, and the momentum the last step ended on.
    invariants: Option<(Invariants, [f64; 3])>,
    /// The last free motion, the time elapsed along it and the state it ended on.
    motion: Option<(ExactMotion, Dd, [f64; 7])>,
}

/// `|H|²` and `2E = Hᵀ I⁻¹ H` in double-double (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Invariants {
    momentum: Dd,
    energy: Dd,
}

impl Invariants {
    /// The invariants of the momentum `h` under the metric `inverse`.
    fn of(h: [f64; 3], inverse: [f64; 3]) -> Self {
        Self {
            momentum: squares(h),
            energy: weighted_squares(inverse, h),
        }
    }

    /// The change a kick from `before` to `after` made, added: `Σ w_k (2 b_k + d_k) d_k` for
    /// `d = a − b` (exact when the kick is smaller than the momentum, as in Fast2Sum), with
    /// `w = 1` for `|H|²` and `I⁻¹` for `2E`, each change rounded once and summed in
    /// double-double. Nothing for a zero torque.
    fn kicked(self, before: [f64; 3], after: [f64; 3], inverse: [f64; 3]) -> Self {
        if before == after {
            return self;
        }
        let (mut momentum, mut energy) = (0.0, 0.0);
        for k in 0..3 {
            let d = after[k] - before[k];
            let change = 2.0f64.mul_add(before[k], d) * d;
            momentum += change;
            energy = inverse[k].mul_add(change, energy);
        }
        Self {
            momentum: dd_add(self.momentum, (momentum, 0.0)),
            energy: dd_add(self.energy, (energy, 0.0)),
        }
    }
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
            inverse: [1.0 / d.x, 1.0 / d.y, 1.0 / d.z],
            carry: RefCell::new(Carry::default()),
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

    /// The momentum kick `H ← H + a τ_b(t, q)` (the attitude and the time held), its change
    /// of the invariants added to `carried`.
    #[inline(always)]
    pub(crate) fn kick<const N: usize, const H: bool>(
        &self,
        sys: &GeneralModel<N, H>,
        t: f64,
        a: f64,
        x: &mut [f64; N],
        carried: &mut Invariants,
    ) {
        let before = [x[0], x[1], x[2]];
        let tau = sys.torque(t, x) * a;
        x[0] += tau.x;
        x[1] += tau.y;
        x[2] += tau.z;
        *carried = carried.kicked(before, [x[0], x[1], x[2]], self.inverse);
    }

    /// The invariants carried to a step from `x`: the last step's, if it ended on `x`'s
    /// momentum, else `x`'s own.
    #[inline]
    pub(crate) fn carried_to<const N: usize>(&self, x: &[f64; N]) -> Invariants {
        let h = [x[0], x[1], x[2]];
        match self.carry.borrow().invariants {
            Some((carried, end)) if end == h => carried,
            _ => Invariants::of(h, self.inverse),
        }
    }

    /// Keeps `carried` for the next step, which starts from `x`.
    #[inline]
    pub(crate) fn carry<const N: usize>(&self, carried: Invariants, x: &[f64; N]) {
        self.carry.borrow_mut().invariants = Some((carried, [x[0], x[1], x[2]]));
    }

    /// The momentum of `x` moved onto the invariants `carried`: one Newton step of `|H|² =
    /// L²`, `Hᵀ I⁻¹ H = 2E` along their gradients `H` and `w = I⁻¹ H`, `δH = α H + β w`; along
    /// `H` alone where the two are parallel (a spin about a principal axis, where the one
    /// fixes the other). The residuals are of the order of round-off, and so is the move.
    #[inline]
    fn onto<const N: usize>(&self, carried: &Invariants, x: &mut [f64; N]) {
        let h = [x[0], x[1], x[2]];
        let now = Invariants::of(h, self.inverse);
        let r_l = dd_diff(now.momentum, carried.momentum);
        let r_e = dd_diff(now.energy, carried.energy);
        let hv = Vector3::from(h);
        let w = hv.component_mul(&Vector3::from(self.inverse));
        let (a, b, d) = (hv.dot(&hv), hv.dot(&w), w.dot(&w));
        let det = a.mul_add(d, -b * b);
        let (alpha, beta) = if det > 1e-24 * a * d {
            (
                (b * r_e - d * r_l) / (2.0 * det),
                (b * r_l - a * r_e) / (2.0 * det),
            )
        } else {
            (-r_l / (2.0 * a), 0.0)
        };
        let moved = hv + hv * alpha + w * beta;
        if moved.iter().all(|v| v.is_finite()) {
            x[..3].copy_from_slice(moved.as_slice());
        }
    }

    /// The exact free motion over `h` (any sign) from `x`: along the last free motion if it
    /// ended on `x`, else along a new one whose end is moved onto the invariants `carried`
    /// (see the module doc).
    #[inline]
    ///
    /// `h` is a double-double: the sub-steps of [`super::ExactKick4`] then sum to its step to
    /// round-off along a motion that goes on (their float64 weights sum to 1 within an ulp,
    /// which over 10⁶ steps gathers 1e-11 of phase).
    pub(crate) fn free_flow<const N: usize>(&self, h: Dd, x: &mut [f64; N], carried: &Invariants) {
        let carry = &mut *self.carry.borrow_mut();
        if let Some((motion, elapsed, end)) = carry.motion.as_mut() {
            if end[..] == x[..] {
                *elapsed = dd_add(*elapsed, h);
                let s = motion.state_at(elapsed.0 + elapsed.1);
                self.set_state(x, &s);
                end.copy_from_slice(&x[..7]);
                return;
            }
        }
        let (omega, q) = self.rates_and_attitude(x);
        // a start the closed form refuses (not finite) leaves the state to the driver's
        // finiteness check
        let Ok(motion) = ExactMotion::try_new_for_step(&self.body, omega, q) else {
            x[0] = f64::NAN;
            carry.motion = None;
            return;
        };
        let s = motion.state_at(h.0 + h.1);
        self.set_state(x, &s);
        self.onto(carried, x);
        let mut end = [0.0; 7];
        end.copy_from_slice(&x[..7]);
        carry.motion = Some((motion, two_sum(h.0, h.1), end));
    }

    /// `x` from a state `[ω, q]` of the free motion: `H = I ω` and `q`.
    #[inline]
    fn set_state<const N: usize>(&self, x: &mut [f64; N], s: &[f64; 7]) {
        let h_new = Vector3::new(s[0], s[1], s[2]).component_mul(&self.body.inertia_body());
        x[..3].copy_from_slice(h_new.as_slice());
        set_attitude(x, &nalgebra::Quaternion::new(s[3], s[4], s[5], s[6]));
    }
}

impl<const N: usize, const H: bool> Stepper<N, GeneralModel<N, H>> for ExactKick {
    const ORDER: u32 = 2;
    /// Two torque evaluations (and one closed-form free motion).
    const RHS_PER_STEP: u64 = 2;

    fn step(&self, sys: &GeneralModel<N, H>, t: f64, h: f64, x: &mut [f64; N]) {
        let mut carried = self.carried_to(x);
        self.kick(sys, t, 0.5 * h, x, &mut carried);
        self.free_flow((h, 0.0), x, &carried);
        self.kick(sys, t + h, 0.5 * h, x, &mut carried);
        self.carry(carried, x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{ConstantInertia, ConstantTorque, Frame};
    use nalgebra::Matrix3;

    /// `(|H|², 2E)` of `x` in plain float64, and the attitude's norm.
    fn invariants(x: &[f64; 7], moments: [f64; 3]) -> (f64, f64) {
        let l2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        let e2 = (0..3).map(|k| x[k] * x[k] / moments[k]).sum();
        (l2, e2)
    }

    #[test]
    fn rebuilt_free_flows_keep_the_invariants_they_carry() {
        // the issue's body and start, with no torque; each flow rebuilt (the carried motion
        // forgotten), as under a torque: without the move onto the carried invariants |H|²
        // and 2E drift by up to 2.3e-13 (relative) over these 2·10⁴ flows
        let moments = [1.0, 1.7, 2.3];
        let inertia = ConstantInertia::try_new(Matrix3::from_diagonal(&moments.into())).unwrap();
        let zero = ConstantTorque::try_new([0.0; 3], Frame::Body)
            .unwrap()
            .into();
        let model = GeneralModel::<7>::try_new(InertiaLaw::Constant(inertia), vec![zero]).unwrap();
        let mut x = model.state_from(0.0, [0.4, -0.9, 0.6], [1.0, 0.0, 0.0, 0.0]);
        let (l0, e0) = invariants(&x, moments);
        let kick = ExactKick::of(&model, &x).unwrap();
        let carried = kick.carried_to(&x);
        let mut worst: f64 = 0.0;
        for _ in 0..20_000 {
            kick.carry.borrow_mut().motion = None;
            kick.free_flow((0.1, 0.0), &mut x, &carried);
            let (l2, e2) = invariants(&x, moments);
            worst = worst
                .max(((l2 - l0) / l0).abs())
                .max(((e2 - e0) / e0).abs());
        }
        // what float64 evaluation of the invariants can tell: a few ulps
        assert!(worst < 8.0 * f64::EPSILON, "{worst:e}");
    }
}
