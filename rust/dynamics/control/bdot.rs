//! B-dot detumbling: three magnetorquers along the body's axes, commanded at each sample by
//! Avanzini & Giulietti's law from a magnetometer (`m = −(k / |B|) ḃ`, `ḃ` from this sample's
//! and the last one's unit field) or, with `rates = "gyro"`, from a gyro too
//! (`m = (k / |B|) ω̃ × b`); each coil clipped to its limit, the dipole held until the next
//! sample (see [`super::laws`], [`super::actuators`], [`super::sensors`]). The body feels
//! `τ = m × B` (body axes) from the Earth's dipole field along the orbit ([`super::field`]).
//! At the first sample there is no earlier field: the magnetometer law commands nothing.

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::RateScale;

use super::super::kinds::{Conserved, Traits};
use super::super::part::{
    Ctx, Dim, EnergyRole, Field, Fields, ModelInfo, Param, ParamKind, Part, Sampling,
};
use super::common::{
    clip_dipole, field_from, gyro_from, limits, magnetometer_from, saturated, set_slot, slot,
    vector_or, view_hooks, with_field, Clock, View, Viewed, DIPOLE, GYRO_ANGLE_RANDOM_WALK,
    GYRO_BIAS, MAGNETOMETER_BIAS, MAGNETOMETER_NOISE, PERIOD, PHASE, SEED,
};
use super::field::DipoleField;
use super::laws::{bdot, rate_detumble};
use super::sensors::{Gyro, Magnetometer};

/// A field (a torque per unit dipole): a rate squared.
const FIELD: Dim = Dim { rate: 2, moment: 0 };

/// Where the law reads the body's rates from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rates {
    /// The change of the measured field between samples (no gyro).
    Magnetometer,
    /// A gyro.
    Gyro,
}

impl std::str::FromStr for Rates {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "magnetometer" => Ok(Rates::Magnetometer),
            "gyro" => Ok(Rates::Gyro),
            _ => Err(Error::invalid(
                "rates",
                "must be 'magnetometer' or 'gyro'",
                s,
            )),
        }
    }
}

/// The state: the held dipole, the field measured at the last sample, the coils' saturation.
const DIPOLE_AT: usize = 0;
const FIELD_AT: usize = 3;
const SATURATED_AT: usize = 6;

/// B-dot detumbling by magnetorquers (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct BDot {
    gain: f64,
    clock: Clock,
    /// Each coil's limit (the user's body axes).
    max_dipole: Vector3<f64>,
    rates: Rates,
    magnetometer: Magnetometer,
    gyro: Gyro,
    /// The field as the user gave it (the law's) and in the run's units (the torque's).
    field: DipoleField,
    run_field: DipoleField,
    view: View,
}

impl Part for BDot {
    const INFO: ModelInfo = ModelInfo {
        name: "bdot",
        about: "B-dot detumbling: magnetorquers commanded m = −(k/|B|) db/dt from a \
                magnetometer (or (k/|B|) ω × b with a gyro) at each sample, clipped per coil, \
                held; τ = m × B in the Earth's dipole field",
        law: false,
        params: with_field!(
            Param::new(
                "gain",
                ParamKind::Scalar,
                "the gain k (a moment times a rate)"
            ),
            PERIOD,
            PHASE,
            Param::new(
                "max_dipole",
                ParamKind::Vector,
                "each coil's largest dipole, body axes (default: no limit)"
            )
            .optional(),
            Param::new(
                "rates",
                ParamKind::Choice(&["magnetometer", "gyro"]),
                "where the law reads the rates: the field's change (default) or a gyro"
            )
            .optional(),
            MAGNETOMETER_BIAS,
            MAGNETOMETER_NOISE,
            GYRO_BIAS,
            GYRO_ANGLE_RANDOM_WALK,
            SEED,
        ),
        state: &[
            Field {
                name: "dipole",
                width: 3,
                body_vector: true,
                dim: DIPOLE,
                about: "the dipole held since the last sample (after saturation), body axes",
            },
            Field {
                name: "field",
                width: 3,
                body_vector: true,
                dim: FIELD,
                about: "the field measured at the last sample, body axes",
            },
            saturated("bit k set where coil k saturated at the last sample"),
        ],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE
            .union(Traits::PART_STATE)
            .union(Traits::SAMPLED),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        let gain = fields.number("gain")?;
        if !(gain.is_finite() && gain >= 0.0) {
            return Err(Error::invalid(
                "gain",
                "must be finite and not negative",
                gain,
            ));
        }
        let field = field_from(fields)?;
        let rates = match fields.get("rates") {
            None => Rates::Magnetometer,
            Some(_) => fields.choice("rates")?,
        };
        Ok(Self {
            gain,
            clock: Clock::from_fields(fields)?,
            max_dipole: limits(
                "max_dipole",
                vector_or(fields, "max_dipole", [f64::INFINITY; 3])?,
            )?,
            rates,
            magnetometer: magnetometer_from(fields)?,
            gyro: gyro_from(fields)?,
            field: field.clone(),
            run_field: field,
            view: View::from_fields(fields)?,
        })
    }

    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, x: &[f64]) -> Vector3<f64> {
        slot(x, DIPOLE_AT).cross(&c.field_in_body(&self.run_field))
    }

    fn stage_field(&self) -> Option<DipoleField> {
        Some(self.run_field.clone())
    }

    /// The tabulated field's knots (none for the dipole).
    fn kinks(&self) -> Vec<f64> {
        self.run_field.kinks()
    }

    fn sampling(&self) -> Option<Sampling> {
        Some(self.clock.in_run(&self.view))
    }

    fn sample(&self, c: &Ctx<'_>, at: usize, x: &mut [f64]) {
        let v = &self.view;
        let own = &mut x[at..at + Self::INFO.width()];
        let t = v.time(c.t);
        let k = self.clock.index(t);
        let q = v.attitude(&c.q);
        let truth = self.field.body(t, &q);
        let measured = self.magnetometer.measure(&v.noise(0), k, &truth);
        let dipole = match self.rates {
            Rates::Magnetometer => {
                let before = v.as_user(&slot(own, FIELD_AT), FIELD, true);
                bdot(self.gain, &measured, &before, self.clock.period)
            }
            Rates::Gyro => {
                let omega = v.as_user(&c.omega, Dim::RATE, true);
                let rate = self.gyro.measure(&v.noise(1), k, self.clock.period, &omega);
                rate_detumble(self.gain, &rate, &measured)
            }
        };
        let (dipole, saturated) = clip_dipole(&dipole, &self.max_dipole);
        set_slot(own, DIPOLE_AT, &v.as_run(&dipole, DIPOLE, true));
        set_slot(own, FIELD_AT, &v.as_run(&measured, FIELD, true));
        own[SATURATED_AT] = f64::from(saturated);
    }

    view_hooks!();
}

impl Viewed for BDot {
    fn view_mut(&mut self) -> &mut View {
        &mut self.view
    }

    fn units_too(&mut self, scale: RateScale) -> Result<()> {
        self.run_field = self.field.in_units(scale)?;
        Ok(())
    }
}
