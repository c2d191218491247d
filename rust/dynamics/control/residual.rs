//! A spacecraft's residual magnetic dipole: a constant dipole `m` fixed in the body (its
//! wiring, its magnets), on which the Earth's field acts, `τ = m × B` (body axes; Wertz,
//! *Spacecraft Attitude Determination and Control*, 1978, §17.2). An external torque: it keeps
//! nothing but `|q|`.

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::super::kinds::{Conserved, Traits};
use super::super::part::{Ctx, EnergyRole, Fields, ModelInfo, Param, ParamKind, Part};
use super::common::{field_from, with_field};
use super::field::DipoleField;

/// A residual dipole in the Earth's field (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ResidualDipole {
    /// The dipole in the run's body axes and units.
    dipole: Vector3<f64>,
    /// The field in the run's units.
    field: DipoleField,
}

impl ResidualDipole {
    /// A dipole `dipole` (body axes) in the field `field`.
    ///
    /// # Errors
    /// A dipole that is not three finite numbers.
    pub fn try_new(dipole: [f64; 3], field: DipoleField) -> Result<Self> {
        if !dipole.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "dipole",
                "must be three finite numbers",
                dipole,
            ));
        }
        Ok(Self {
            dipole: Vector3::from(dipole),
            field,
        })
    }
}

impl Part for ResidualDipole {
    const INFO: ModelInfo = ModelInfo {
        name: "residual_dipole",
        about: "a constant magnetic dipole m of the body in the Earth's dipole field along the \
                circular orbit: τ = m × B",
        law: false,
        params: with_field!(Param::new(
            "dipole",
            ParamKind::Vector,
            "the dipole, body axes (A·m² with the field in tesla)"
        )),
        state: &[],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE.union(Traits::KINKS),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(fields.vector("dipole")?, field_from(fields)?)
    }

    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        self.dipole.cross(&c.field_in_body(&self.field))
    }

    fn stage_field(&self) -> Option<DipoleField> {
        Some(self.field.clone())
    }

    /// The tabulated field's knots (none for the dipole).
    fn kinks(&self) -> Vec<f64> {
        self.field.kinks()
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            dipole: Vector3::from(to_axes(self.dipole.into())),
            ..self.clone()
        }
    }

    /// A torque is a moment times a rate squared; the field carries the rates, the dipole the
    /// moment.
    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            dipole: self.dipole.map(|v| ldexp(v, -m)),
            ..self.clone()
        })
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        Ok(Self {
            field: self.field.in_units(scale)?,
            ..self.clone()
        })
    }
}
