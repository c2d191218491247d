//! A momentum wheel, a part of a body (a gyrostat): a symmetric rotor spinning about an axis
//! `a` fixed in the body, carrying the angular momentum `h a` relative to the body (Hughes,
//! *Spacecraft Attitude Dynamics*, 1986, ch. 6, the gyrostat).
//!
//! **Variables** (body axes): the body's tensor `I` counts the rotor as a rigid part; its
//! relative momentum `h` is held constant (a motor keeps the rotor's spin relative to the
//! body). The total angular momentum is `H = I ω + Σ h a`, so that
//!
//! ```text
//! ω  = I⁻¹ (H − Σ h a)
//! H' = H × ω (+ τ_b)        I ω' = (I ω + Σ h a) × ω (+ τ_b)
//! ```
//!
//! Without an external torque `H` is fixed in space and, `h` being constant, the body's
//! kinetic energy `½ ωᵀ I ω` is kept too (`ω · (H × ω) = 0`). A wheel has no state of its
//! own: its momentum is a parameter of the model.

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::kinds::{Conserved, Traits};
use super::part::{EnergyRole, Fields, ModelInfo, Param, ParamKind, Part};

/// A momentum wheel (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wheel {
    /// The unit spin axis in body axes.
    axis: Vector3<f64>,
    /// The relative angular momentum `h` along it.
    momentum: f64,
}

/// A spin axis: three finite numbers, not all zero, normalised.
///
/// # Errors
/// An axis that is not that, named `axis`.
pub(crate) fn unit_axis(axis: [f64; 3]) -> Result<Vector3<f64>> {
    let a = Vector3::from(axis);
    let norm = a.norm();
    if !(a.iter().all(|v| v.is_finite()) && norm > 0.0 && norm.is_finite()) {
        return Err(Error::invalid(
            "axis",
            "must be three finite numbers, not all zero",
            axis,
        ));
    }
    Ok(a / norm)
}

impl Wheel {
    /// A wheel spinning about `axis` (body axes, any non-zero length: normalised here) with
    /// relative angular momentum `momentum`.
    ///
    /// # Errors
    /// An `axis` that is not finite or has zero length; a `momentum` that is not finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Wheel;
    /// let w = Wheel::try_new([0.0, 2.0, 0.0], 0.5).unwrap();
    /// assert_eq!(w.momentum_body().y, 0.5);
    /// assert!(Wheel::try_new([0.0, 0.0, 0.0], 0.5).is_err());
    /// ```
    pub fn try_new(axis: [f64; 3], momentum: f64) -> Result<Self> {
        let axis = unit_axis(axis)?;
        if !momentum.is_finite() {
            return Err(Error::invalid("momentum", "must be finite", momentum));
        }
        Ok(Self { axis, momentum })
    }

    /// The unit spin axis in body axes.
    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    /// The relative angular momentum along the axis.
    pub fn momentum(&self) -> f64 {
        self.momentum
    }

    /// `h a`, in body axes.
    pub fn momentum_body(&self) -> Vector3<f64> {
        self.axis * self.momentum
    }

    fn with_momentum(&self, momentum: f64) -> Result<Self> {
        match momentum.is_finite() && ((momentum == 0.0) == (self.momentum == 0.0)) {
            true => Ok(Self { momentum, ..*self }),
            false => Err(Error::invalid(
                "momentum",
                "must stay within float64 in the run's units (moments and rates scaled)",
                self.momentum,
            )),
        }
    }
}

impl Part for Wheel {
    const INFO: ModelInfo = ModelInfo {
        name: "wheel",
        about: "a momentum wheel of constant relative momentum (a gyrostat: I ω' = (I ω + Σ h a) \
                × ω)",
        law: false,
        params: &[
            Param::new(
                "axis",
                ParamKind::Vector,
                "the spin axis, body axes (normalised)",
            ),
            Param::new(
                "momentum",
                ParamKind::Scalar,
                "the rotor's angular momentum relative to the body along the axis",
            ),
        ],
        state: &[],
        // with a gravity gradient too, the Jacobi integral stays kept; with a damper, the
        // energy balance (a constant wheel does no work)
        keeps: Conserved::MOMENTA
            .union(Conserved::JACOBI)
            .union(Conserved::ENERGY_BALANCE),
        defines: Conserved::NONE,
        energy: EnergyRole::Neither,
        external: false,
        unique: false,
        traits: Traits::STORED_MOMENTUM,
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(fields.vector("axis")?, fields.number("momentum")?)
    }

    fn largest_rate(&self, least: f64) -> Option<(&'static str, f64, f64)> {
        Some(("momentum", self.momentum, self.momentum.abs() / least))
    }

    #[inline(always)]
    fn momentum(&self, _t: f64, _x: &[f64]) -> Vector3<f64> {
        self.momentum_body()
    }

    fn constant_momentum(&self) -> Option<Vector3<f64>> {
        Some(self.momentum_body())
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            axis: Vector3::from(to_axes(self.axis.into())),
            ..*self
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        self.with_momentum(ldexp(self.momentum, -m))
    }

    /// A momentum is a moment times a rate.
    fn in_units(&self, scale: RateScale) -> Result<Self> {
        self.with_momentum(scale.rate_to_unit(self.momentum))
    }
}
