//! A rigid body carrying a spherical viscous nutation damper: a sphere of moment of inertia `j`
//! (about any axis through its centre) in a spherical cavity filled with viscous fluid, the
//! fluid exerting a torque `c (σ − ω)` on the body and its opposite on the sphere (Hughes,
//! *Spacecraft Attitude Dynamics*, 1986, the spherical nutation damper; Kaplan, *Modern
//! Spacecraft Dynamics and Control*, 1976, energy-sink analysis).
//!
//! **Variables** (body axes): the body rates `ω`, the sphere's absolute angular velocity `σ`
//! and the attitude `q`; the state is `[ω (3), σ (3), q (4)]`. `I` is the body's inertia
//! tensor with the sphere's mass counted as a point at its centre, so that the total angular
//! momentum is `H = I ω + j σ`.
//!
//! **Equations.** No external torque: `H` is fixed in space, `H' + ω × H = 0` in body axes,
//! i.e. `I ω' + j σ' + ω × (I ω + j σ) = 0`. The sphere alone, its angular momentum `j σ`
//! written in body axes, feels only the fluid's torque: `j (σ' + ω × σ) = −c (σ − ω)`.
//! Subtracting,
//!
//! ```text
//! I ω' = I ω × ω + c (σ − ω)
//! σ'   = σ × ω − (c / j) (σ − ω)
//! q'   = ½ q ⊗ (0, ω)
//! ```
//!
//! **Energy.** `T = ½ ωᵀ I ω + ½ j |σ|²`; with the equations above
//! `T' = c ω·(σ − ω) − c σ·(σ − ω) = −c |σ − ω|² ≤ 0`. At fixed `|H|` the least energy is a
//! spin about the major axis with the sphere co-rotating: the end of every motion with `c > 0`
//! (the major-axis rule of Explorer 1).

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::ode::OdeSystem;

use super::model::{quaternion_increment, Model};

/// The state `[ω (3), σ (3), q (4)]`.
pub type DamperState = [f64; 10];

/// A body with a spherical viscous damper (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedBody {
    inertia: Matrix3<f64>,
    inertia_inv: Matrix3<f64>,
    /// The principal moments when the tensor is diagonal: products by three multiplications.
    diagonal: Option<Vector3<f64>>,
    /// The sphere's moment `j`.
    sphere: f64,
    /// The damping coefficient `c`.
    damping: f64,
    /// `c / j`.
    rate: f64,
}

/// # Construction
impl DampedBody {
    /// A body of inertia tensor `inertia` (body axes) with a sphere of moment `sphere` and
    /// damping coefficient `damping`.
    ///
    /// # Errors
    /// A symmetric positive definite finite tensor, `sphere` positive and finite, `damping`
    /// non-negative and finite.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Matrix3;
    /// use dzhanibekov::dynamics::DampedBody;
    /// let body = Matrix3::from_diagonal(&[1.0, 2.0, 3.0].into());
    /// assert!(DampedBody::try_new(body, 0.1, 0.05).is_ok());
    /// assert!(DampedBody::try_new(body, 0.0, 0.05).is_err());
    /// ```
    pub fn try_new(inertia: Matrix3<f64>, sphere: f64, damping: f64) -> Result<Self> {
        let symmetric = (inertia - inertia.transpose()).amax() <= 1e-12 * inertia.amax();
        let inverse = inertia.try_inverse();
        let ok = inertia.iter().all(|v| v.is_finite())
            && symmetric
            && inertia.cholesky().is_some()
            && inverse.is_some_and(|m| m.iter().all(|v| v.is_finite()));
        let Some(inertia_inv) = inverse.filter(|_| ok) else {
            return Err(Error::invalid(
                "inertia",
                "must be a symmetric, positive definite, finite tensor (3 × 3)",
                inertia.as_slice(),
            ));
        };
        if !(sphere.is_finite() && sphere > 0.0) {
            return Err(Error::invalid(
                "damper inertia",
                "must be positive and finite",
                sphere,
            ));
        }
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(Error::invalid(
                "damping",
                "must be non-negative and finite",
                damping,
            ));
        }
        let rate = damping / sphere;
        if !rate.is_finite() {
            return Err(Error::invalid(
                "damping",
                "over the damper's inertia must be finite",
                (damping, sphere),
            ));
        }
        let inertia = (inertia + inertia.transpose()) * 0.5;
        let is_diagonal = (0..3).all(|i| (0..3).all(|j| i == j || inertia[(i, j)] == 0.0));
        Ok(Self {
            inertia,
            inertia_inv,
            diagonal: is_diagonal.then(|| inertia.diagonal()),
            sphere,
            damping,
            rate,
        })
    }

    /// The state from body rates `omega`, sphere rates `sigma` and attitude `q`.
    pub fn state_from(omega: [f64; 3], sigma: [f64; 3], q: [f64; 4]) -> DamperState {
        [
            omega[0], omega[1], omega[2], sigma[0], sigma[1], sigma[2], q[0], q[1], q[2], q[3],
        ]
    }
}

/// # Properties
impl DampedBody {
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }

    pub fn sphere(&self) -> f64 {
        self.sphere
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }
}

#[inline(always)]
fn omega_of(x: &DamperState) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

#[inline(always)]
fn sigma_of(x: &DamperState) -> Vector3<f64> {
    Vector3::new(x[3], x[4], x[5])
}

impl OdeSystem<10> for DampedBody {
    #[inline(always)]
    fn increment(&self, _t: f64, x: &DamperState, s: f64) -> DamperState {
        let omega = omega_of(x);
        let sigma = sigma_of(x);
        let relative = sigma - omega;
        let domega = match self.diagonal {
            Some(d) => {
                let l = d.component_mul(&omega);
                (l.cross(&omega) + relative * self.damping).component_div(&d) * s
            }
            None => {
                let l = self.inertia * omega;
                self.inertia_inv * (l.cross(&omega) + relative * self.damping) * s
            }
        };
        let dsigma = (sigma.cross(&omega) - relative * self.rate) * s;
        let dq = quaternion_increment([x[6], x[7], x[8], x[9]], omega, s);
        [
            domega.x, domega.y, domega.z, dsigma.x, dsigma.y, dsigma.z, dq[0], dq[1], dq[2], dq[3],
        ]
    }
}

impl Model<10> for DampedBody {
    const NAME: &'static str = "damper";

    fn omega_body(&self, _t: f64, x: &DamperState) -> Vector3<f64> {
        omega_of(x)
    }

    fn momentum_body(&self, _t: f64, x: &DamperState) -> Vector3<f64> {
        self.inertia * omega_of(x) + sigma_of(x) * self.sphere
    }

    fn energy(&self, _t: f64, x: &DamperState) -> f64 {
        let omega = omega_of(x);
        0.5 * (omega.dot(&(self.inertia * omega)) + self.sphere * sigma_of(x).norm_squared())
    }

    fn scale_rates(&self, x: &mut DamperState, factor: f64) {
        for v in &mut x[..6] {
            *v *= factor;
        }
    }

    /// `√(2 T / λ_min(I))` bounds `|ω|` (T never rises) and `√(2T / j)` bounds `|σ|`.
    fn principal_moments(&self, _t: f64) -> Option<Vector3<f64>> {
        self.diagonal
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        // torque c (σ − ω): over 2^(2e) in the run's units, rates over 2^e, so c over 2^e
        Self::try_new(self.inertia, self.sphere, scale.rate_to_unit(self.damping))
    }

    fn rate_bound(&self, x0: &DamperState) -> f64 {
        let two_t = 2.0 * self.energy(0.0, x0);
        let lambda_min = self.inertia.symmetric_eigenvalues().min();
        (two_t / lambda_min.min(self.sphere)).sqrt()
    }

    fn extra(&self, x: &DamperState, out: &mut Vec<f64>) {
        out.extend_from_slice(&x[3..6]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn damped() -> DampedBody {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        DampedBody::try_new(i, 0.2, 0.05).unwrap()
    }

    #[test]
    fn energy_falls_at_c_times_the_relative_rate_squared() {
        let d = damped();
        let x = DampedBody::state_from([0.3, -0.7, 1.1], [0.2, 0.1, 0.9], [1.0, 0.0, 0.0, 0.0]);
        let dx = d.rhs(0.0, &x);
        let omega = omega_of(&x);
        let de =
            omega.dot(&(d.inertia * omega_of(&dx))) + d.sphere * sigma_of(&x).dot(&sigma_of(&dx));
        let rel = sigma_of(&x) - omega;
        assert_relative_eq!(de, -d.damping * rel.norm_squared(), max_relative = 1e-13);
    }

    #[test]
    fn total_momentum_obeys_euler_in_body_axes() {
        // H' + ω × H = 0
        let d = damped();
        let x = DampedBody::state_from([0.3, -0.7, 1.1], [0.2, 0.1, 0.9], [1.0, 0.0, 0.0, 0.0]);
        let dx = d.rhs(0.0, &x);
        let dh = d.inertia * omega_of(&dx) + sigma_of(&dx) * d.sphere;
        let h = d.momentum_body(0.0, &x);
        assert!((dh + omega_of(&x).cross(&h)).amax() < 1e-14);
    }
}
