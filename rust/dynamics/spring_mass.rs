//! A spring–mass damper: a point mass `m` sliding along a line of the body, `r = a + x d`
//! (`a` the spring's rest point from the hub's mass centre, `d` a unit direction, body axes),
//! on a spring of stiffness `k` with viscous damping `c` — the classic nutation damper
//! (Hughes, *Spacecraft Attitude Dynamics*, 1986, §8; Kaplan, *Modern Spacecraft Dynamics and
//! Control*, 1976, §5).
//!
//! **State** `[x, p]`: the displacement from the rest point and its conjugate momentum
//! `p = ∂T/∂ẋ = m (u − P/M) · d` (see [`super::multibody`]). With `u = ω × r + ẋ d`,
//! `∂u/∂x = ω × d`, Lagrange's equation is
//!
//! ```text
//! x' = ẋ                                        (from the joint solve)
//! p' = m (u − P/M) · (ω × d) − k x − c ẋ
//! ```
//!
//! `V = ½ k x²`, the dissipated power `c ẋ²`.

use nalgebra::Vector3;

use crate::error::{Error, Result};

use super::multibody::Carried;

/// A spring–mass damper (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringMass {
    mass: f64,
    anchor: Vector3<f64>,
    direction: Vector3<f64>,
    stiffness: f64,
    damping: f64,
}

/// `value` if it is finite and at least `low` (or above it, `strict`).
pub(crate) fn checked(name: &'static str, value: f64, strict: bool) -> Result<f64> {
    let ok = value.is_finite() && if strict { value > 0.0 } else { value >= 0.0 };
    match ok {
        true => Ok(value),
        false => Err(Error::invalid(
            name,
            match strict {
                true => "must be positive and finite",
                false => "must be non-negative and finite",
            },
            value,
        )),
    }
}

/// `v` as a unit vector.
///
/// # Errors
/// A vector that is not finite or is zero.
pub(crate) fn unit(name: &'static str, v: [f64; 3]) -> Result<Vector3<f64>> {
    let v = Vector3::from(v);
    let n = v.norm();
    match v.iter().all(|c| c.is_finite()) && n > 0.0 && n.is_finite() {
        true => Ok(v / n),
        false => Err(Error::invalid(
            name,
            "must be a non-zero, finite direction",
            v.as_slice(),
        )),
    }
}

/// `v` as a finite point.
pub(crate) fn point(name: &'static str, v: [f64; 3]) -> Result<Vector3<f64>> {
    match v.iter().all(|c| c.is_finite()) {
        true => Ok(Vector3::from(v)),
        false => Err(Error::invalid(name, "must be three finite numbers", v)),
    }
}

impl SpringMass {
    /// A mass `mass` at rest at `anchor`, sliding along `direction` (normalised here).
    ///
    /// # Errors
    /// A mass that is not positive, a stiffness or damping that is negative, any of them or
    /// of the vectors not finite, a zero direction.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::SpringMass;
    /// assert!(SpringMass::try_new(0.1, [1.0, 0.0, 0.0], [0.0, 0.0, 2.0], 5.0, 0.1).is_ok());
    /// assert!(SpringMass::try_new(0.1, [1.0, 0.0, 0.0], [0.0; 3], 5.0, 0.1).is_err());
    /// ```
    pub fn try_new(
        mass: f64,
        anchor: [f64; 3],
        direction: [f64; 3],
        stiffness: f64,
        damping: f64,
    ) -> Result<Self> {
        Ok(Self {
            mass: checked("mass", mass, true)?,
            anchor: point("anchor", anchor)?,
            direction: unit("direction", direction)?,
            stiffness: checked("stiffness", stiffness, false)?,
            damping: checked("damping", damping, false)?,
        })
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    pub fn anchor(&self) -> Vector3<f64> {
        self.anchor
    }

    pub fn direction(&self) -> Vector3<f64> {
        self.direction
    }

    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// What it carries at displacement `x`.
    #[inline(always)]
    pub fn carried(&self, x: f64) -> Carried {
        Carried::point(
            self.mass,
            self.anchor + self.direction * x,
            &[self.direction],
        )
    }

    /// `p'` at displacement `x` and rate `rate`, the body rates `omega` and the mass's
    /// velocity `velocity` in the frame of the mass centre.
    #[inline(always)]
    pub fn momentum_rate(
        &self,
        x: f64,
        rate: f64,
        omega: &Vector3<f64>,
        velocity: &Vector3<f64>,
    ) -> f64 {
        self.mass * velocity.dot(&omega.cross(&self.direction))
            - self.stiffness * x
            - self.damping * rate
    }

    /// `½ k x²`.
    pub fn potential(&self, x: f64) -> f64 {
        0.5 * self.stiffness * x * x
    }

    /// The power the damping takes, `c ẋ²`.
    pub fn dissipation(&self, rate: f64) -> f64 {
        self.damping * rate * rate
    }
}
