//! A spherical viscous nutation damper, a part of a body: a sphere of moment of inertia `j`
//! (about any axis through its centre) in a spherical cavity filled with viscous fluid, the
//! fluid exerting a torque `c (σ − ω)` on the body and its opposite on the sphere (Hughes,
//! *Spacecraft Attitude Dynamics*, 1986, the spherical nutation damper; Kaplan, *Modern
//! Spacecraft Dynamics and Control*, 1976, energy-sink analysis).
//!
//! **Variables** (body axes): the sphere's absolute angular velocity `σ` is the part's state.
//! The body's tensor `I` counts the sphere's mass as a point at its centre, so that the total
//! angular momentum is `H = I ω + j σ`.
//!
//! **Equations.** No external torque: `H' = H × ω` in body axes. The sphere alone, its angular
//! momentum `j σ` written in body axes, feels only the fluid's torque:
//! `j (σ' + ω × σ) = −c (σ − ω)`, so
//!
//! ```text
//! σ' = σ × ω − (c / j) (σ − ω),    ω = I⁻¹ (H − j σ)
//! ```
//!
//! **Energy.** `T = ½ ωᵀ I ω + ½ j |σ|²`; with the equations above
//! `T' = c ω·(σ − ω) − c σ·(σ − ω) = −c |σ − ω|² ≤ 0`. At fixed `|H|` the least energy is a
//! spin about the major axis with the sphere co-rotating: the end of every motion with `c > 0`
//! (the major-axis rule of Explorer 1).

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::RateScale;

/// A spherical viscous damper (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    /// The sphere's moment `j`.
    sphere: f64,
    /// The damping coefficient `c`.
    damping: f64,
    /// `c / j`.
    rate: f64,
}

impl Damper {
    /// A sphere of moment `sphere` with damping coefficient `damping`.
    ///
    /// # Errors
    /// `sphere` positive and finite, `damping` non-negative and finite, their ratio finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Damper;
    /// assert!(Damper::try_new(0.1, 0.05).is_ok());
    /// assert!(Damper::try_new(0.0, 0.05).is_err());
    /// ```
    pub fn try_new(sphere: f64, damping: f64) -> Result<Self> {
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
        Ok(Self {
            sphere,
            damping,
            rate,
        })
    }

    pub fn sphere(&self) -> f64 {
        self.sphere
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// `σ'` at rates `omega` of the body and `sigma` of the sphere.
    #[inline(always)]
    pub fn sigma_rate(&self, omega: &Vector3<f64>, sigma: &Vector3<f64>) -> Vector3<f64> {
        sigma.cross(omega) - (sigma - omega) * self.rate
    }

    /// The decay rate of the slip `σ − ω`, `c (1/j + 1/I_min)`, for a body whose least
    /// principal moment is `least`: the damper's stiffness.
    pub fn slip_rate(&self, least: f64) -> f64 {
        self.damping / self.sphere + self.damping / least
    }

    /// The same damper with moments over `2^m` (see [`crate::float`]).
    pub fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Self::try_new(
            crate::float::ldexp(self.sphere, -m),
            crate::float::ldexp(self.damping, -m),
        )
    }

    /// The same damper with times in the units of `scale`: the torque `c (σ − ω)` is over
    /// `2^(2e)` in the run's units and the rates over `2^e`, so `c` is over `2^e`.
    pub(crate) fn in_units(&self, scale: RateScale) -> Result<Self> {
        Self::try_new(self.sphere, scale.rate_to_unit(self.damping))
    }
}
