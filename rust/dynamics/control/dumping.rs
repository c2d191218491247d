//! Momentum dumping: three magnetorquers commanded at each sample `m = k (h × B̃) / |B̃|²` from
//! the momentum `h` the system's parts store (its wheels', read from their tachometers: the
//! total momentum less the body's own, `H − I ω`) and a magnetometer's field, clipped per
//! coil and held (see [`super::laws`]). The body feels `τ = m × B = −k h⊥`: the wheels'
//! momentum across the field drains into the Earth's field while a pointing law holds the body.

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::RateScale;

use super::super::kinds::{Conserved, Traits};
use super::super::part::{
    Ctx, Dim, EnergyRole, Field, Fields, ModelInfo, Param, ParamKind, Part, Sampling,
};
use super::common::{
    clip_dipole, field_from, limits, magnetometer_from, saturated, set_slot, slot, vector_or,
    view_hooks, with_field, Clock, View, Viewed, DIPOLE, MAGNETOMETER_BIAS, MAGNETOMETER_NOISE,
    PERIOD, PHASE, SEED,
};
use super::field::DipoleField;
use super::laws::momentum_dump;
use super::sensors::Magnetometer;

const DIPOLE_AT: usize = 0;
const SATURATED_AT: usize = 3;

/// Momentum dumping by magnetorquers (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct MomentumDumping {
    gain: f64,
    clock: Clock,
    max_dipole: Vector3<f64>,
    magnetometer: Magnetometer,
    field: DipoleField,
    run_field: DipoleField,
    view: View,
}

impl Part for MomentumDumping {
    const INFO: ModelInfo = ModelInfo {
        name: "momentum_dumping",
        about: "momentum dumping: magnetorquers commanded m = k (h × B)/|B|² from the momentum \
                the parts store at each sample, clipped per coil, held; τ = m × B",
        law: false,
        params: with_field!(
            Param::new("gain", ParamKind::Scalar, "the gain k (a rate)"),
            PERIOD,
            PHASE,
            Param::new(
                "max_dipole",
                ParamKind::Vector,
                "each coil's largest dipole, body axes (default: no limit)"
            )
            .optional(),
            MAGNETOMETER_BIAS,
            MAGNETOMETER_NOISE,
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
        Ok(Self {
            gain,
            clock: Clock::from_fields(fields)?,
            max_dipole: limits(
                "max_dipole",
                vector_or(fields, "max_dipole", [f64::INFINITY; 3])?,
            )?,
            magnetometer: magnetometer_from(fields)?,
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
        // what the parts store: the total momentum less the body's own
        let total = Vector3::new(x[0], x[1], x[2]);
        let stored = v.as_user(&(total - c.inertia_times(&c.omega)), Dim::MOMENTUM, true);
        let own = &mut x[at..at + Self::INFO.width()];
        let t = v.time(c.t);
        let k = self.clock.index(t);
        let truth = self.field.body(t, &v.attitude(&c.q));
        let measured = self.magnetometer.measure(&v.noise(0), k, &truth);
        let dipole = momentum_dump(self.gain, &stored, &measured);
        let (dipole, saturated) = clip_dipole(&dipole, &self.max_dipole);
        set_slot(own, DIPOLE_AT, &v.as_run(&dipole, DIPOLE, true));
        own[SATURATED_AT] = f64::from(saturated);
    }

    view_hooks!();
}

impl Viewed for MomentumDumping {
    fn view_mut(&mut self) -> &mut View {
        &mut self.view
    }

    fn units_too(&mut self, scale: RateScale) -> Result<()> {
        self.run_field = self.field.in_units(scale)?;
        Ok(())
    }
}
