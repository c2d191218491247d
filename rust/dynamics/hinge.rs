//! A hinged appendage: a rigid panel or rod on a one-axis hinge of the body, with a torsional
//! spring and damper — a deployed antenna or solar panel (Hughes, *Spacecraft Attitude
//! Dynamics*, 1986, ch. 8; Basilisk's hinged rigid bodies).
//!
//! **Geometry** (body axes, from the hub's mass centre): the hinge at `h`, its unit axis `e`;
//! at hinge angle `β` the panel is turned from its rest position by `A(β)`, the rotation by
//! `β` about `e`, so its mass centre is at `r = h + ℓ s(β)`, `s(β) = A(β) s₀ = s₀ cos β +
//! (e × s₀) sin β` (`s₀ ⊥ e` the arm's direction at rest, `ℓ` the distance from the hinge),
//! and its tensor about its own centre is `I_b = j_s s sᵀ + j_e e eᵀ + j_g g gᵀ`, `g = e × s`
//! (`j_s`, `j_e`, `j_g` its moments about the arm, the hinge axis and their normal).
//!
//! **State** `[β, p]`, `p = ∂T/∂β̇`. Its velocity relative to the hub is `ṙ = β̇ ℓ g` and its
//! angular velocity `Ω = ω + β̇ e`; with `u = ω × r + β̇ ℓ g`, `∂u/∂β = ω × ℓ g − β̇ ℓ s` and
//! `∂I_b/∂β = [e×] I_b − I_b [e×]` (so `∂(½ Ωᵀ I_b Ω)/∂β = e · (I_b Ω × Ω)`), Lagrange gives
//!
//! ```text
//! β' = β̇                                                   (from the joint solve)
//! p' = m (u − P/M) · (ω × ℓ g − β̇ ℓ s) + e · (I_b Ω × Ω) − k β − c β̇
//! ```
//!
//! `V = ½ k β²` (the spring is unloaded at rest), the dissipated power `c β̇²`.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};

use super::multibody::Carried;
use super::spring_mass::{checked, point, unit};

/// A hinged appendage (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hinge {
    mass: f64,
    /// `j_s`, `j_e`, `j_g`.
    moments: Vector3<f64>,
    hinge: Vector3<f64>,
    axis: Vector3<f64>,
    /// `s₀`.
    arm: Vector3<f64>,
    /// `e × s₀`.
    normal: Vector3<f64>,
    length: f64,
    stiffness: f64,
    damping: f64,
}

/// The panel at one hinge angle: its arm `s`, `g = e × s`, and tensor `I_b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub arm: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub inertia: Matrix3<f64>,
}

impl Hinge {
    /// A panel of mass `mass` and moments `moments` (about the arm, the hinge axis and their
    /// normal, through its own centre) hinged at `hinge` about `axis`, its centre at `length`
    /// from the hinge along `arm` at rest (`arm` is taken perpendicular to `axis`: its
    /// component along the axis is removed).
    ///
    /// # Errors
    /// A mass that is not positive; a moment, length, stiffness or damping that is negative
    /// (every one finite); moments that break the triangle inequality (no rigid body has
    /// them); a zero axis, or an arm along the axis.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Hinge;
    /// // a thin rod of length 2 hinged at (1, 0, 0), flapping about y
    /// let rod = Hinge::try_new(0.3, [0.0, 0.1, 0.1], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///                          [1.0, 0.0, 0.0], 1.0, 0.5, 0.01);
    /// assert!(rod.is_ok());
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn try_new(
        mass: f64,
        moments: [f64; 3],
        hinge: [f64; 3],
        axis: [f64; 3],
        arm: [f64; 3],
        length: f64,
        stiffness: f64,
        damping: f64,
    ) -> Result<Self> {
        let mass = checked("mass", mass, true)?;
        for j in moments {
            checked("moments", j, false)?;
        }
        let [js, je, jg] = moments;
        let slack = 1e-12 * (js + je + jg);
        if js > je + jg + slack || je > js + jg + slack || jg > js + je + slack {
            return Err(Error::invalid(
                "moments",
                "must meet the triangle inequality (each at most the sum of the other two)",
                moments,
            ));
        }
        let axis = unit("axis", axis)?;
        let raw = point("arm", arm)?;
        let along = raw - axis * axis.dot(&raw);
        let arm = match along.norm() > 1e-12 * raw.norm() {
            true => along.normalize(),
            false => {
                return Err(Error::invalid(
                    "arm",
                    "must not lie along the hinge axis",
                    raw.as_slice(),
                ))
            }
        };
        Ok(Self {
            mass,
            moments: Vector3::from(moments),
            hinge: point("hinge", hinge)?,
            axis,
            arm,
            normal: axis.cross(&arm),
            length: checked("length", length, false)?,
            stiffness: checked("stiffness", stiffness, false)?,
            damping: checked("damping", damping, false)?,
        })
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    pub fn moments(&self) -> Vector3<f64> {
        self.moments
    }

    pub fn hinge(&self) -> Vector3<f64> {
        self.hinge
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    pub fn arm(&self) -> Vector3<f64> {
        self.arm
    }

    pub fn length(&self) -> f64 {
        self.length
    }

    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// The panel at hinge angle `beta`.
    #[inline(always)]
    pub fn pose(&self, beta: f64) -> Pose {
        let (sin, cos) = super::gravity::sin_cos(beta);
        let arm = self.arm * cos + self.normal * sin;
        let normal = self.axis.cross(&arm);
        let [js, je, jg] = [self.moments.x, self.moments.y, self.moments.z];
        let inertia = arm * arm.transpose() * js
            + self.axis * self.axis.transpose() * je
            + normal * normal.transpose() * jg;
        Pose {
            arm,
            normal,
            inertia,
        }
    }

    /// What it carries in `pose`.
    #[inline(always)]
    pub fn carried(&self, pose: &Pose) -> Carried {
        Carried::point(
            self.mass,
            self.hinge + pose.arm * self.length,
            &[pose.normal * self.length],
        )
        .with_inertia(pose.inertia, &[self.axis])
    }

    /// `p'` in `pose` at angle `beta` and rate `rate`, the body rates `omega`, the panel's
    /// centre's velocity `velocity` in the frame of the mass centre and its angular velocity
    /// `spin`.
    #[inline(always)]
    pub fn momentum_rate(
        &self,
        pose: &Pose,
        beta: f64,
        rate: f64,
        omega: &Vector3<f64>,
        velocity: &Vector3<f64>,
        spin: &Vector3<f64>,
    ) -> f64 {
        let moved = omega.cross(&pose.normal) - pose.arm * rate;
        self.mass * self.length * velocity.dot(&moved)
            + self.axis.dot(&(pose.inertia * spin).cross(spin))
            - self.stiffness * beta
            - self.damping * rate
    }

    /// `½ k β²`.
    pub fn potential(&self, beta: f64) -> f64 {
        0.5 * self.stiffness * beta * beta
    }

    /// The power the damping takes, `c β̇²`.
    pub fn dissipation(&self, rate: f64) -> f64 {
        self.damping * rate * rate
    }
}
