//! The user's own control law: a function called once per sample (not per stage) with what
//! the sensors measure, `f(t, q, omega, field, wheel_momentum) -> (torque, dipole)`, whose
//! torque three reaction wheels give the body ([`super::reaction`]) and whose dipole three
//! magnetorquers hold in the Earth's field (none without a field), both limited and held until
//! the next sample. The function sees the user's time, axes and units (a [`View`]): the
//! attitude measured by a star tracker (world-from-body, unit), the rates by a gyro, the field
//! by a magnetometer (body axes; zeros without a field), the wheels' momenta.
//!
//! **Failure.** A function that fails (the binding: raises, is interrupted, or returns what is
//! not six finite numbers) makes the held commands NaN; the wheels' momenta and the body's
//! rates stop being finite and the run stops at its next check with an error, which the
//! binding replaces by the function's own. Nothing is called again once it failed.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::error::Result;
use crate::float::RateScale;

use super::super::kinds::{Conserved, Traits};
use super::super::part::{
    Arg, Ctx, Dim, EnergyRole, Field, Fields, Function, MapFunction, ModelInfo, Param, ParamKind,
    Part, Sampling,
};
use super::common::{
    clip_dipole, field_from, gyro_from, limits, magnetometer_from, saturated, set_slot, slot,
    star_tracker_from, vector_or, view_hooks, with_field, Clock, View, Viewed, DIPOLE,
    GYRO_ANGLE_RANDOM_WALK, GYRO_BIAS, MAGNETOMETER_BIAS, MAGNETOMETER_NOISE, PERIOD, PHASE, SEED,
    STAR_TRACKER_NOISE,
};
use super::field::DipoleField;
use super::reaction::{self, ReactionWheels};
use super::sensors::{Gyro, Magnetometer, StarTracker};

/// The state: the wheels' two fields, then the held dipole and the saturation bits.
const DIPOLE_AT: usize = reaction::WIDTH;
const SATURATED_AT: usize = reaction::WIDTH + 3;

/// A control law of the user's (see the module doc).
#[derive(Clone)]
pub struct Controller {
    function: Arc<dyn Function>,
    clock: Clock,
    wheels: ReactionWheels,
    max_dipole: Vector3<f64>,
    /// The field as the user gave it and in the run's units, if there is one.
    field: Option<(DipoleField, DipoleField)>,
    magnetometer: Magnetometer,
    star_tracker: StarTracker,
    gyro: Gyro,
    view: View,
}

impl std::fmt::Debug for Controller {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Controller")
            .field("clock", &self.clock)
            .field("wheels", &self.wheels)
            .field("field", &self.field)
            .finish_non_exhaustive()
    }
}

/// The same function (the same object), the same actuators and sensors, seen the same way.
impl PartialEq for Controller {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.function, &other.function)
            && self.clock == other.clock
            && self.wheels == other.wheels
            && self.max_dipole == other.max_dipole
            && self.field == other.field
            && self.magnetometer == other.magnetometer
            && self.star_tracker == other.star_tracker
            && self.gyro == other.gyro
            && self.view == other.view
    }
}

impl Part for Controller {
    const INFO: ModelInfo = ModelInfo {
        name: "controller",
        about: "the user's law f(t, q, ω, B, h) -> (torque, dipole), called once per sample on \
                what the sensors measure; three reaction wheels give the torque, three \
                magnetorquers hold the dipole, each limited, held until the next sample",
        law: false,
        params: with_field!(optional;
            Param::new(
                "law",
                ParamKind::Function {
                    args: "t, q, omega, field, wheel_momentum",
                    returns: 6,
                },
                "the law: at time t, the measured attitude q (world-from-body, scalar first), \
                 body rates omega, field (body axes) and the wheels' momenta, the torque the \
                 wheels give the body (body axes) and the magnetorquers' dipole"
            ),
            PERIOD,
            PHASE,
            reaction::AXES,
            reaction::MOMENTUM,
            reaction::TORQUE_LIMIT,
            reaction::MOMENTUM_LIMIT,
            Param::new(
                "max_dipole",
                ParamKind::Vector,
                "each coil's largest dipole, body axes (default: no limit)"
            )
            .optional(),
            STAR_TRACKER_NOISE,
            GYRO_BIAS,
            GYRO_ANGLE_RANDOM_WALK,
            MAGNETOMETER_BIAS,
            MAGNETOMETER_NOISE,
            SEED,
        ),
        state: &[
            reaction::STATE[0],
            reaction::STATE[1],
            Field {
                name: "dipole",
                width: 3,
                body_vector: true,
                dim: DIPOLE,
                about: "the dipole held since the last sample (after saturation), body axes",
            },
            saturated(
                "bit k set where wheel k's torque limit, bit 3 + k where its momentum limit, \
                 bit 6 + k where coil k saturated at the last sample",
            ),
        ],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE
            .union(Traits::STORED_MOMENTUM)
            .union(Traits::PART_STATE)
            .union(Traits::SAMPLED),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        let field = match fields.get("orbit_rate") {
            None => None,
            Some(_) => {
                let f = field_from(fields)?;
                Some((f.clone(), f))
            }
        };
        Ok(Self {
            function: fields.function("law")?,
            clock: Clock::from_fields(fields)?,
            wheels: ReactionWheels::from_fields(fields)?,
            max_dipole: limits(
                "max_dipole",
                vector_or(fields, "max_dipole", [f64::INFINITY; 3])?,
            )?,
            field,
            magnetometer: magnetometer_from(fields)?,
            star_tracker: star_tracker_from(fields)?,
            gyro: gyro_from(fields)?,
            view: View::from_fields(fields)?,
        })
    }

    #[inline]
    fn momentum(&self, _t: f64, x: &[f64]) -> Vector3<f64> {
        self.wheels.stored(x, 0)
    }

    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, x: &[f64]) -> Vector3<f64> {
        match &self.field {
            Some((_, run)) => slot(x, DIPOLE_AT).cross(&c.field_in_body(run)),
            None => Vector3::zeros(),
        }
    }

    fn stage_field(&self) -> Option<DipoleField> {
        self.field.as_ref().map(|(_, run)| run.clone())
    }

    /// The tabulated field's knots (none for the dipole).
    fn kinks(&self) -> Vec<f64> {
        self.field
            .as_ref()
            .map_or_else(Vec::new, |(_, run)| run.kinks())
    }

    #[inline]
    fn rates(&self, _c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        self.wheels.rates(x, 0, dx);
    }

    fn start(&self, _omega0: &Vector3<f64>, x: &mut [f64]) {
        self.wheels.start(&self.view, x, 0);
    }

    fn largest_momentum(&self) -> f64 {
        self.wheels.largest()
    }

    fn sampling(&self) -> Option<Sampling> {
        Some(self.clock.in_run(&self.view))
    }

    fn sample(&self, c: &Ctx<'_>, at: usize, x: &mut [f64]) {
        let v = &self.view;
        let own = &mut x[at..at + Self::INFO.width()];
        let t = v.time(c.t);
        let k = self.clock.index(t);
        let period = self.clock.period;
        let truth = v.attitude(&c.q);
        let q = self.star_tracker.measure(&v.noise(2), k, &truth);
        let omega = self.gyro.measure(
            &v.noise(1),
            k,
            period,
            &v.as_user(&c.omega, Dim::RATE, true),
        );
        let field = match &self.field {
            Some((user, _)) => self
                .magnetometer
                .measure(&v.noise(0), k, &user.body(t, &truth)),
            None => Vector3::zeros(),
        };
        let momenta = self.wheels.momenta(v, own, 0);
        let q = [q.w, q.i, q.j, q.k];
        let args = [
            Arg::Number(t),
            Arg::Vector(&q),
            Arg::Vector(omega.as_slice()),
            Arg::Vector(field.as_slice()),
            Arg::Vector(momenta.as_slice()),
        ];
        let mut out = [0.0; 6];
        if !self.function.call(&args, &mut out) {
            out = [f64::NAN; 6];
        }
        let torque = Vector3::new(out[0], out[1], out[2]);
        let wheels = self.wheels.command(v, &torque, period, own, 0);
        let dipole = match self.field {
            Some(_) => Vector3::new(out[3], out[4], out[5]),
            None => Vector3::zeros(),
        };
        let (dipole, saturated) = clip_dipole(&dipole, &self.max_dipole);
        set_slot(own, DIPOLE_AT, &v.as_run(&dipole, DIPOLE, true));
        own[SATURATED_AT] = f64::from(wheels | saturated << 6);
        if out.iter().any(|c| c.is_nan()) {
            // a failed call: the held commands stop being finite, so do the wheels' momenta
            // and the body's rates after the next step, and the run stops with its error (a
            // NaN dipole alone would stay in its slot without a field)
            own.fill(f64::NAN);
        }
    }

    view_hooks!();

    fn heap_bytes(&self) -> usize {
        self.wheels.heap_bytes()
    }

    fn functions(&self) -> Vec<&Arc<dyn Function>> {
        vec![&self.function]
    }

    fn map_functions(&self, f: &mut MapFunction<'_>) -> Self {
        Self {
            function: f(&self.function),
            ..self.clone()
        }
    }
}

impl Viewed for Controller {
    fn view_mut(&mut self) -> &mut View {
        &mut self.view
    }

    fn axes_too(&mut self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) {
        self.wheels = self.wheels.in_axes(to_axes);
    }

    fn units_too(&mut self, scale: RateScale) -> Result<()> {
        if let Some((user, _)) = self.field.take() {
            let run = user.in_units(scale)?;
            self.field = Some((user, run));
        }
        Ok(())
    }
}
