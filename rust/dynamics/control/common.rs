//! What the closed loop's parts share: the magnetic field's parameters, the sensors' and the
//! sample clock's, and the view from a run's axes and units back to the user's, in which every
//! law is evaluated (once a sample, so the conversion costs nothing per step).
//!
//! **Axes and units.** A run goes in its own body axes (principal axes where the user's tensor
//! is not diagonal), with moments over `2^m` and, at extreme rates, times and rates scaled by
//! `2^e` (see [`crate::float`]). A part keeps its parameters as the user gave them and a
//! [`View`]: the law sees the user's time, attitude, rates and field, and what it commands is
//! written back into the run's state in the run's axes and units. What a right-hand side
//! evaluates at every step (a magnetic torque `m × B`) reads only the run's own quantities.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::super::part::{Dim, Field, Fields, Param, ParamKind, Sampling, Value};
use super::field::DipoleField;
use super::noise::Noise;
use super::sensors::{Gyro, Magnetometer, StarTracker};

/// The IGRF-13 dipole at 2020.0: `B₀ R_E³` in T·m³ (see [`super::field`]).
pub const EARTH_MOMENT: f64 = 7.708e15;
/// The Earth's gravitational parameter `μ` in m³/s² (WGS 84).
pub const EARTH_MU: f64 = 3.986_004_418e14;

/// The magnetic field's parameters, the same in every magnetic part: its two required ones
/// first, its optional ones after the part's own (or all last and optional: `optional;`).
macro_rules! with_field {
    (@list [$($first:expr,)*] [$($param:expr,)*] $($last:expr),*) => {
        &[
            $($first,)*
            $($param,)*
            $($last,)*
            Param::new(
                "moment",
                ParamKind::Scalar,
                "the dipole's strength B₀ R_E³ (default 7.708e15 T·m³, IGRF-13 at 2020.0)",
            )
            .optional(),
            Param::new(
                "mu",
                ParamKind::Scalar,
                "the planet's gravitational parameter (default 3.986004418e14 m³/s²)",
            )
            .optional(),
            Param::new(
                "tilt",
                ParamKind::Scalar,
                "the dipole's tilt from the spin axis (radians; default 0)",
            )
            .optional(),
            Param::new(
                "earth_rate",
                ParamKind::Scalar,
                "the Earth's rate about its spin axis (default 0: at rest)",
            )
            .optional(),
            Param::new(
                "longitude",
                ParamKind::Scalar,
                "the dipole's longitude from the orbit's ascending node at t = 0 (radians; \
                 default 0)",
            )
            .optional(),
            Param::new(
                "field_times",
                ParamKind::Times,
                "knot times of a tabulated field that replaces the dipole's (with field_values)",
            )
            .optional(),
            Param::new(
                "field_values",
                ParamKind::Vectors,
                "the field in world axes at each of field_times (linear between, held outside)",
            )
            .optional(),
        ]
    };
    (optional; $($param:expr),* $(,)?) => {
        with_field!(@list [] [$($param,)*]
            Param::new("orbit_rate", ParamKind::Scalar, "the circular orbit's rate n (no field \
                       when not given)").optional(),
            Param::new("inclination", ParamKind::Scalar, "the orbit's inclination to the \
                       equator of the Earth's spin axis (radians)").optional()
        )
    };
    // the field's required parameters first: a part's optional ones follow its required ones
    ($($param:expr),* $(,)?) => {
        with_field!(@list [
            Param::new("orbit_rate", ParamKind::Scalar, "the circular orbit's rate n"),
            Param::new(
                "inclination",
                ParamKind::Scalar,
                "the orbit's inclination to the equator of the Earth's spin axis (radians; \
                 to the magnetic equator when the dipole is not tilted)",
            ),
        ] [$($param,)*])
    };
}
pub(crate) use with_field;

/// The number `name`, or `default` if it is not given.
///
/// # Errors
/// `name` given but not a number.
pub fn number_or(fields: &Fields, name: &'static str, default: f64) -> Result<f64> {
    match fields.get(name) {
        None => Ok(default),
        Some(Value::Number(v)) => Ok(*v),
        Some(_) => Err(Error::invalid(name, "must be a number", "something else")),
    }
}

/// The vector `name`, or `default` if it is not given.
///
/// # Errors
/// `name` given but not a vector.
pub fn vector_or(fields: &Fields, name: &'static str, default: [f64; 3]) -> Result<[f64; 3]> {
    Ok(fields.optional_vector(name)?.unwrap_or(default))
}

/// The field the parameters of [`with_field`] describe.
///
/// # Errors
/// A parameter [`DipoleField`] refuses, naming it.
pub fn field_from(fields: &Fields) -> Result<DipoleField> {
    let dipole = DipoleField::try_new(
        fields.number("orbit_rate")?,
        fields.number("inclination")?,
        number_or(fields, "moment", EARTH_MOMENT)?,
        number_or(fields, "mu", EARTH_MU)?,
    )?
    .tilted(
        number_or(fields, "tilt", 0.0)?,
        number_or(fields, "earth_rate", 0.0)?,
        number_or(fields, "longitude", 0.0)?,
    )?;
    match (fields.get("field_times"), fields.get("field_values")) {
        (None, None) => Ok(dipole),
        (Some(_), Some(_)) => dipole.tabulated(
            fields.numbers("field_times")?,
            fields.vectors("field_values")?,
        ),
        (None, Some(_)) => Err(Error::invalid(
            "field_times",
            "must be given with field_values",
            "none",
        )),
        (Some(_), None) => Err(Error::invalid(
            "field_values",
            "must be given with field_times",
            "none",
        )),
    }
}

/// A sample clock in the user's time: samples at `phase + k · period`, `k = 0, 1, …`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    pub period: f64,
    pub phase: f64,
}

impl Clock {
    /// The clock of the parameters `period` and `phase` (default 0).
    ///
    /// # Errors
    /// A period that is not positive and finite, a phase that is negative or not finite.
    pub fn from_fields(fields: &Fields) -> Result<Self> {
        let period = fields.number("period")?;
        if !(period.is_finite() && period > 0.0) {
            return Err(Error::invalid(
                "period",
                "must be positive and finite",
                period,
            ));
        }
        let phase = number_or(fields, "phase", 0.0)?;
        if !(phase.is_finite() && phase >= 0.0) {
            return Err(Error::invalid(
                "phase",
                "must be finite and not negative",
                phase,
            ));
        }
        Ok(Self { period, phase })
    }

    /// The index of the sample at the user's time `t` (a sample time).
    #[inline]
    pub fn index(&self, t: f64) -> u64 {
        ((t - self.phase) / self.period).round().max(0.0) as u64
    }

    /// The clock in the run's time.
    pub fn in_run(&self, view: &View) -> Sampling {
        Sampling {
            period: view.scale.time_to_unit(self.period),
            phase: view.scale.time_to_unit(self.phase),
        }
    }
}

/// A standard deviation `name`, 0 if it is not given.
fn deviation_or_zero(fields: &Fields, name: &'static str) -> Result<f64> {
    number_or(fields, name, 0.0)
}

/// The magnetometer of the parameters `magnetometer_bias` and `magnetometer_noise` (each
/// default 0: noise-free).
///
/// # Errors
/// A parameter [`Magnetometer`] refuses.
pub fn magnetometer_from(fields: &Fields) -> Result<Magnetometer> {
    Magnetometer::try_new(
        vector_or(fields, "magnetometer_bias", [0.0; 3])?,
        deviation_or_zero(fields, "magnetometer_noise")?,
    )
    .map_err(|e| rename(e, "magnetometer_"))
}

/// The gyro of the parameters `gyro_bias` and `gyro_angle_random_walk` (each default 0).
///
/// # Errors
/// A parameter [`Gyro`] refuses.
pub fn gyro_from(fields: &Fields) -> Result<Gyro> {
    Gyro::try_new(
        vector_or(fields, "gyro_bias", [0.0; 3])?,
        deviation_or_zero(fields, "gyro_angle_random_walk")?,
    )
    .map_err(|e| rename(e, "gyro_"))
}

/// The star tracker of the parameter `star_tracker_noise` (default 0).
///
/// # Errors
/// A parameter [`StarTracker`] refuses.
pub fn star_tracker_from(fields: &Fields) -> Result<StarTracker> {
    StarTracker::try_new(deviation_or_zero(fields, "star_tracker_noise")?)
        .map_err(|e| rename(e, "star_tracker_"))
}

/// A sensor's error, naming the part's parameter (`noise` → `magnetometer_noise`).
fn rename(e: Error, prefix: &'static str) -> Error {
    match e {
        Error::InvalidArgument { name, allowed, got } => {
            let full: &'static str = match (prefix, name) {
                ("magnetometer_", "bias") => "magnetometer_bias",
                ("magnetometer_", "noise") => "magnetometer_noise",
                ("gyro_", "bias") => "gyro_bias",
                ("gyro_", "angle_random_walk") => "gyro_angle_random_walk",
                ("star_tracker_", "noise") => "star_tracker_noise",
                _ => name,
            };
            Error::InvalidArgument {
                name: full,
                allowed,
                got,
            }
        }
        e => e,
    }
}

/// The sensors' parameters, listed in a part's own.
pub const MAGNETOMETER_BIAS: Param = Param::new(
    "magnetometer_bias",
    ParamKind::Vector,
    "the magnetometer's constant bias, body axes (default 0)",
)
.optional();
pub const MAGNETOMETER_NOISE: Param = Param::new(
    "magnetometer_noise",
    ParamKind::Scalar,
    "the magnetometer's white noise per axis, field units (default 0)",
)
.optional();
pub const GYRO_BIAS: Param = Param::new(
    "gyro_bias",
    ParamKind::Vector,
    "the gyro's constant bias, body axes (default 0)",
)
.optional();
pub const GYRO_ANGLE_RANDOM_WALK: Param = Param::new(
    "gyro_angle_random_walk",
    ParamKind::Scalar,
    "the gyro's angle random walk σ_v, rad/√time (default 0)",
)
.optional();
pub const STAR_TRACKER_NOISE: Param = Param::new(
    "star_tracker_noise",
    ParamKind::Scalar,
    "the star tracker's noise per axis, radians (default 0)",
)
.optional();
/// The sensors' seed (see [`View::from_fields`]).
pub const SEED: Param = Param::new(
    "seed",
    ParamKind::Scalar,
    "the sensors' noise seed, a whole number in [0, 2**53) (default 0); row i of a batch \
     draws as its single run seeded seed + i",
)
.optional();
/// The largest seed plus one: `2^53`, below which a float64 holds every whole number.
const MAX_SEED: f64 = 9_007_199_254_740_992.0;
/// The sample clock's parameters.
pub const PERIOD: Param = Param::new("period", ParamKind::Scalar, "the time between samples");
pub const PHASE: Param = Param::new(
    "phase",
    ParamKind::Scalar,
    "the first sample's time (default 0)",
)
.optional();

/// How a run's axes and units relate to the user's (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// `P`, taking a vector of the user's body axes into the run's, and `q_P` (the user's
    /// attitude is `q_run ⊗ q_P`), if the axes differ.
    axes: Option<(Matrix3<f64>, Quaternion<f64>)>,
    /// The run's moments are the user's over `2^moments`.
    moments: i32,
    /// The run's times and rates.
    pub scale: RateScale,
    /// The part's own seed (its parameter `seed`), the run's (added to it: a batch's row
    /// number) and the part's place among the system's parts.
    own: u64,
    seed: u64,
    index: u64,
}

impl Default for View {
    fn default() -> Self {
        Self {
            axes: None,
            moments: 0,
            scale: RateScale::of([1.0; 3]),
            own: 0,
            seed: 0,
            index: 0,
        }
    }
}

impl View {
    /// The view of a part whose parameter `seed` (default 0) seeds its sensors' noise.
    ///
    /// # Errors
    /// A seed that is not a whole number in `[0, 2^53)`.
    pub fn from_fields(fields: &Fields) -> Result<Self> {
        let seed = number_or(fields, "seed", 0.0)?;
        if !((0.0..MAX_SEED).contains(&seed) && seed.fract() == 0.0) {
            return Err(Error::invalid(
                "seed",
                "must be a whole number in [0, 2**53)",
                seed,
            ));
        }
        Ok(Self {
            own: seed as u64,
            ..Self::default()
        })
    }

    /// The same view with the body axes mapped by `to_axes` (see [`super::super::Part::in_axes`]).
    pub fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        let p = Matrix3::from_columns(&[
            Vector3::from(to_axes([1.0, 0.0, 0.0])),
            Vector3::from(to_axes([0.0, 1.0, 0.0])),
            Vector3::from(to_axes([0.0, 0.0, 1.0])),
        ]);
        let p = match self.axes {
            Some((before, _)) => p * before,
            None => p,
        };
        let axes =
            (p != Matrix3::identity()).then(|| (p, UnitQuaternion::from_matrix(&p).into_inner()));
        Self { axes, ..*self }
    }

    /// The same view with moments over another `2^m`.
    pub fn with_moments_scaled(&self, m: i32) -> Self {
        Self {
            moments: self.moments + m,
            ..*self
        }
    }

    /// The same view in the units of `scale`.
    pub fn in_units(&self, scale: RateScale) -> Self {
        Self { scale, ..*self }
    }

    /// The same view for the run seeded with `seed` (added to the part's own: row `i` of a
    /// batch is seeded `i`), the part at `index`.
    pub fn seeded(&self, seed: u64, index: usize) -> Self {
        Self {
            seed,
            index: index as u64,
            ..*self
        }
    }

    /// The noise stream of the part's sensor `sensor` (0, 1, 2, …): keyed by the part's seed
    /// plus the run's, so that row `i` of a batch draws as its single run with the part's
    /// seed plus `i`.
    pub fn noise(&self, sensor: u64) -> Noise {
        Noise::new(self.own.wrapping_add(self.seed), self.index * 8 + sensor)
    }

    /// The user's time of the run's `t`.
    #[inline]
    pub fn time(&self, t: f64) -> f64 {
        self.scale.time_from_unit(t)
    }

    /// The user's attitude (unit) of the run's `q`.
    #[inline]
    pub fn attitude(&self, q: &Quaternion<f64>) -> Quaternion<f64> {
        let q = match &self.axes {
            Some((_, qp)) => q * qp,
            None => *q,
        };
        q / q.norm()
    }

    /// A quantity of dimension `dim` of the run's, in the user's units (a body-axes vector if
    /// `body`).
    #[inline]
    pub fn as_user(&self, v: &Vector3<f64>, dim: Dim, body: bool) -> Vector3<f64> {
        let mut v = match (&self.axes, body) {
            (Some((p, _)), true) => p.tr_mul(v),
            _ => *v,
        };
        for _ in 0..dim.rate {
            v = v.map(|c| self.scale.rate_from_unit(c));
        }
        v.map(|c| ldexp(c, self.moments * dim.moment))
    }

    /// A quantity of dimension `dim` of the user's, in the run's units (and axes if `body`).
    #[inline]
    pub fn as_run(&self, v: &Vector3<f64>, dim: Dim, body: bool) -> Vector3<f64> {
        let mut v = v.map(|c| ldexp(c, -self.moments * dim.moment));
        for _ in 0..dim.rate {
            v = v.map(|c| self.scale.rate_to_unit(c));
        }
        match (&self.axes, body) {
            (Some((p, _)), true) => p * v,
            _ => v,
        }
    }
}

/// A part that sees the run through a [`View`]: the four hooks of [`super::super::Part`]
/// that change the run's axes, units and seed pass through to the view ([`view_hooks`]), and
/// a part says here what else they change.
pub trait Viewed: Clone {
    /// The part's view.
    fn view_mut(&mut self) -> &mut View;

    /// What else turns with the body axes (the wheels' axes); nothing by default.
    fn axes_too(&mut self, _to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) {}

    /// What else goes into the units of `scale` (the field the torque reads); nothing by
    /// default.
    ///
    /// # Errors
    /// A parameter that float64 no longer holds.
    fn units_too(&mut self, _scale: RateScale) -> Result<()> {
        Ok(())
    }
}

/// The hooks of [`super::super::Part`] of a [`Viewed`] part: written inside its `impl Part`.
macro_rules! view_hooks {
    () => {
        fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
            let mut part = self.clone();
            let view = part.view_mut();
            *view = view.in_axes(to_axes);
            $crate::dynamics::control::common::Viewed::axes_too(&mut part, to_axes);
            part
        }

        fn with_moments_scaled(&self, m: i32) -> $crate::error::Result<Self> {
            let mut part = self.clone();
            let view = part.view_mut();
            *view = view.with_moments_scaled(m);
            Ok(part)
        }

        fn in_units(&self, scale: $crate::float::RateScale) -> $crate::error::Result<Self> {
            let mut part = self.clone();
            let view = part.view_mut();
            *view = view.in_units(scale);
            $crate::dynamics::control::common::Viewed::units_too(&mut part, scale)?;
            Ok(part)
        }

        fn seeded(&self, seed: u64, index: usize) -> Self {
            let mut part = self.clone();
            let view = part.view_mut();
            *view = view.seeded(seed, index);
            part
        }
    };
}
pub(crate) use view_hooks;

/// A magnetic dipole (its torque in a field is a torque): a moment, no rate.
pub const DIPOLE: Dim = Dim { rate: 0, moment: 1 };

/// Three numbers of a state slice starting at `at`.
#[inline]
pub fn slot(x: &[f64], at: usize) -> Vector3<f64> {
    Vector3::new(x[at], x[at + 1], x[at + 2])
}

/// Writes `v` into three numbers of a state slice starting at `at`.
#[inline]
pub fn set_slot(x: &mut [f64], at: usize, v: &Vector3<f64>) {
    x[at..at + 3].copy_from_slice(v.as_slice());
}

/// `dipole` clipped per coil to `limit` (user's axes), and which coils saturated (bit `k`
/// for coil `k`).
#[inline]
pub fn clip_dipole(dipole: &Vector3<f64>, limit: &Vector3<f64>) -> (Vector3<f64>, u32) {
    let mut out = Vector3::zeros();
    let mut bits = 0;
    for k in 0..3 {
        let (v, s) = super::actuators::clip(dipole[k], limit[k]);
        out[k] = v;
        bits |= u32::from(s) << k;
    }
    (out, bits)
}

/// The state field of a part's saturation bits (see each part for their meaning).
pub const fn saturated(about: &'static str) -> Field {
    Field {
        name: "saturated",
        width: 1,
        body_vector: false,
        dim: Dim::NONE,
        about,
    }
}

/// A limit per coil: three numbers, each positive (infinite for none).
///
/// # Errors
/// A limit that is not positive, named `name`.
pub fn limits(name: &'static str, v: [f64; 3]) -> Result<Vector3<f64>> {
    match v.iter().all(|c| *c > 0.0) {
        true => Ok(Vector3::from(v)),
        false => Err(Error::invalid(
            name,
            "must be positive (infinite for no limit)",
            v,
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A view of run axes turned from the user's by 90° about z, moments over 2^5, rates
    /// over 2^69.
    fn turned() -> View {
        let turn = |v: [f64; 3]| [-v[1], v[0], v[2]];
        View::default()
            .in_axes(&turn)
            .with_moments_scaled(5)
            .in_units(RateScale::of([1e21, 0.0, 0.0]))
    }

    #[test]
    fn quantities_go_to_the_run_and_back_unchanged() {
        let v = turned();
        let x = Vector3::new(0.3, -1.2, 2.5);
        for dim in [
            Dim::NONE,
            Dim::RATE,
            Dim::MOMENTUM,
            Dim::TORQUE,
            DIPOLE,
            Dim { rate: 2, moment: 0 }, // a field: a torque per unit dipole
        ] {
            for body in [false, true] {
                let back = v.as_user(&v.as_run(&x, dim, body), dim, body);
                assert_relative_eq!(back, x, max_relative = 1e-15);
            }
        }
        // a body vector turns with the axes; a torque is a moment times a rate squared
        let run = v.as_run(&Vector3::x(), Dim::TORQUE, true);
        let e = 70; // RateScale::of(1e21): 2^69 ≤ 1e21 < 2^70
        assert_relative_eq!(
            run,
            Vector3::y() * 2f64.powi(-5 - 2 * e),
            max_relative = 1e-15
        );
    }

    #[test]
    fn the_users_attitude_is_the_runs_turned_back() {
        // a body vector's image in space is the same seen either way: M(q_run) P v = M(q_user) v
        let v = turned();
        let q_run = Quaternion::new(0.9, 0.1, -0.3, 0.2).normalize();
        let q_user = v.attitude(&q_run);
        let x = Vector3::new(0.3, -1.2, 2.5);
        let run = v.as_run(&x, Dim::NONE, true);
        let m = crate::kinematics::rotation_matrix;
        assert_relative_eq!(m(&q_run) * run, m(&q_user) * x, epsilon = 1e-15);
    }

    #[test]
    fn a_clock_counts_its_samples_from_its_phase() {
        let c = Clock {
            period: 0.25,
            phase: 1.0,
        };
        assert_eq!(c.index(1.0), 0);
        assert_eq!(c.index(3.5), 10);
        assert_eq!(c.index(1.0 + 0.25 * 1e6), 1_000_000);
        let s = c.in_run(&View::default().in_units(RateScale::of([1e21, 0.0, 0.0])));
        assert_eq!(s.period, 0.25 * 2f64.powi(69));
    }

    #[test]
    fn coils_saturate_one_by_one_and_say_which() {
        let (m, bits) = clip_dipole(
            &Vector3::new(0.3, -0.05, -2.0),
            &Vector3::new(0.2, 0.1, 1.0),
        );
        assert_eq!(m, Vector3::new(0.2, -0.05, -1.0));
        assert_eq!(bits, 0b101);
    }

    fn seeded(seed: f64) -> Result<View> {
        View::from_fields(&Fields::new().with("seed", Value::Number(seed)))
    }

    /// A part's noise is keyed by its seed plus the run's (a batch's row): row `i` of a batch
    /// draws as the part seeded `seed + i` alone; the rows and the parts draw apart.
    #[test]
    fn the_noise_is_keyed_by_the_parts_seed_plus_the_runs() {
        let draw = |v: View, sensor| v.noise(sensor).normals(3, 0);
        let row_two = seeded(5.0).unwrap().seeded(2, 1);
        assert_eq!(draw(row_two, 0), draw(seeded(7.0).unwrap().seeded(0, 1), 0));
        assert_ne!(draw(row_two, 0), draw(seeded(5.0).unwrap().seeded(0, 1), 0));
        // another part, another sensor: other streams
        assert_ne!(draw(row_two, 0), draw(seeded(5.0).unwrap().seeded(2, 0), 0));
        assert_ne!(draw(row_two, 0), draw(row_two, 1));
        // left out, the seed is 0
        assert_eq!(
            View::from_fields(&Fields::new()).unwrap(),
            seeded(0.0).unwrap()
        );
    }

    #[test]
    fn a_seed_that_is_not_a_whole_number_below_two_to_the_53_is_refused_by_name() {
        for bad in [-1.0, 0.5, 9_007_199_254_740_992.0, f64::NAN, f64::INFINITY] {
            match seeded(bad) {
                Err(Error::InvalidArgument { name, .. }) => assert_eq!(name, "seed"),
                other => panic!("{bad}: {other:?}"),
            }
        }
        assert!(seeded(9_007_199_254_740_991.0).is_ok());
    }
}
