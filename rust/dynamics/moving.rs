//! What the parts whose mass moves share (a spring–mass damper, a hinged appendage, slosh;
//! see [`super::multibody`]): their checks of input, what they keep, the hooks of
//! [`Part`](super::Part) such a part answers, written once ([`Mover`], [`mover_hooks`]), and
//! the spring, damper and start of a part with one coordinate ([`Coordinate`],
//! [`OneCoordinate`]).

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::kinds::{Conserved, Traits};
use super::multibody::{AloneSolve, Carried, Hub, PART_RATES};
use super::part::{EnergyRole, Field, Fields, ModelInfo, Param};

/// What a part whose mass moves is, besides its name, description, parameters and state: it
/// keeps the momenta and the energy balance, dissipates, and asks a method for state, stored
/// momentum and moving mass.
pub(crate) const fn moving_info(
    name: &'static str,
    about: &'static str,
    params: &'static [Param],
    state: &'static [Field],
) -> ModelInfo {
    ModelInfo {
        name,
        about,
        law: false,
        params,
        state,
        keeps: Conserved::MOMENTA.union(Conserved::ENERGY_BALANCE),
        defines: Conserved::NONE,
        energy: EnergyRole::Dissipates,
        external: false,
        unique: false,
        traits: Traits::PART_STATE
            .union(Traits::STORED_MOMENTUM)
            .union(Traits::MOVING_MASS),
    }
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

/// A part whose mass moves, as the general model asks of it: what the [`Part`](super::Part)
/// hooks of [`mover_hooks`] answer. Its state is its configuration and its conjugate momenta;
/// at the start it holds the configuration and the rates, whose momenta the model puts in.
pub(crate) trait Mover: Copy {
    /// How many rates it has (at most [`PART_RATES`]).
    const RATES: usize;
    /// The mass that moves.
    fn mover_mass(&self) -> f64;
    /// Its closed form alone on `hub`.
    fn lone(&self, hub: &Hub) -> AloneSolve;
    /// What it carries at its state `x`, and its momenta.
    fn carry(&self, x: &[f64]) -> (Carried, [f64; PART_RATES]);
    /// Its configuration and rates at the start, into `x`.
    fn begin(&self, x: &mut [f64]);
    /// The rates of a state `x` as [`Mover::begin`] left it.
    fn begin_rates(&self, x: &[f64]) -> [f64; PART_RATES];
    /// Its momenta `p` into its state `x`, in place of the rates.
    fn put_momenta(&self, x: &mut [f64], p: &[f64]);
}

/// The hooks of [`Part`](super::Part) of a part whose mass moves, from its [`Mover`]: written
/// inside each such part's `impl Part`.
macro_rules! mover_hooks {
    () => {
        #[inline(always)]
        fn carried(
            &self,
            x: &[f64],
        ) -> Option<(
            $crate::dynamics::multibody::Carried,
            [f64; $crate::dynamics::multibody::PART_RATES],
        )> {
            Some($crate::dynamics::moving::Mover::carry(self, x))
        }

        fn moving_rates(&self) -> usize {
            <Self as $crate::dynamics::moving::Mover>::RATES
        }

        fn alone(
            &self,
            hub: &$crate::dynamics::multibody::Hub,
        ) -> Option<$crate::dynamics::multibody::AloneSolve> {
            Some($crate::dynamics::moving::Mover::lone(self, hub))
        }

        fn moving_mass(&self) -> f64 {
            $crate::dynamics::moving::Mover::mover_mass(self)
        }

        fn start(&self, _omega0: &nalgebra::Vector3<f64>, x: &mut [f64]) {
            $crate::dynamics::moving::Mover::begin(self, x)
        }

        fn start_rates(&self, x: &[f64]) -> [f64; $crate::dynamics::multibody::PART_RATES] {
            $crate::dynamics::moving::Mover::begin_rates(self, x)
        }

        fn set_momenta(&self, x: &mut [f64], p: &[f64]) {
            $crate::dynamics::moving::Mover::put_momenta(self, x, p)
        }
    };
}
pub(crate) use mover_hooks;

/// The spring `k`, the damper `c` and the start `[q₀, q̇₀]` of a part with one coordinate `q`
/// (a displacement, a hinge angle): `V = ½ k q²`, the dissipated power `c q̇²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coordinate {
    pub stiffness: f64,
    pub damping: f64,
    pub start: [f64; 2],
}

impl Coordinate {
    /// A spring `stiffness` and damper `damping`, starting at rest at `q = 0`.
    ///
    /// # Errors
    /// Either negative or not finite.
    pub fn try_new(stiffness: f64, damping: f64) -> Result<Self> {
        Ok(Self {
            stiffness: checked("stiffness", stiffness, false)?,
            damping: checked("damping", damping, false)?,
            start: [0.0; 2],
        })
    }

    /// The same with the start read from `fields`: the coordinate `name` and `rate0` (0 each).
    ///
    /// # Errors
    /// Either not a number or not finite.
    pub fn starting(mut self, fields: &Fields, name: &'static str) -> Result<Self> {
        self.start = [
            fields.optional_number(name)?.unwrap_or(0.0),
            fields.optional_number("rate0")?.unwrap_or(0.0),
        ];
        match self.start.iter().all(|v| v.is_finite()) {
            true => Ok(self),
            false => Err(Error::invalid(name, "and rate0 must be finite", self.start)),
        }
    }

    /// `k q + c q̇`: the spring's and damper's generalised force, less.
    #[inline(always)]
    pub fn force(&self, q: f64, rate: f64) -> f64 {
        self.stiffness * q + self.damping * rate
    }

    /// `½ k q²`.
    pub fn potential(&self, q: f64) -> f64 {
        0.5 * self.stiffness * q * q
    }

    /// The power the damping takes, `c q̇²`.
    #[inline(always)]
    pub fn dissipation(&self, rate: f64) -> f64 {
        self.damping * rate * rate
    }

    /// With the masses and moments scaled by `2⁻ᵐ` (the spring and damper with them).
    pub fn scaled(&self, m: i32) -> Self {
        Self {
            stiffness: ldexp(self.stiffness, -m),
            damping: ldexp(self.damping, -m),
            ..*self
        }
    }

    /// In the run's unit of rate.
    pub fn in_units(&self, scale: RateScale) -> Self {
        let rate = |v: f64| scale.rate_to_unit(v);
        Self {
            stiffness: rate(rate(self.stiffness)),
            damping: rate(self.damping),
            start: [self.start[0], rate(self.start[1])],
        }
    }
}

/// A part whose mass moves with one coordinate `q`: its state `[q, p]`, `p = ∂T/∂q̇`. It is
/// a [`Mover`] by what it carries at `q` and its [`Coordinate`].
pub(crate) trait OneCoordinate: Copy {
    fn coordinate(&self) -> &Coordinate;
    fn moved_mass(&self) -> f64;
    /// What it carries at `q`.
    fn carried_at(&self, q: f64) -> Carried;
    /// Its closed form alone on `hub`.
    fn lone_on(&self, hub: &Hub) -> AloneSolve;
}

impl<T: OneCoordinate> Mover for T {
    const RATES: usize = 1;

    fn mover_mass(&self) -> f64 {
        self.moved_mass()
    }

    fn lone(&self, hub: &Hub) -> AloneSolve {
        self.lone_on(hub)
    }

    #[inline(always)]
    fn carry(&self, x: &[f64]) -> (Carried, [f64; PART_RATES]) {
        (self.carried_at(x[0]), [x[1], 0.0, 0.0])
    }

    fn begin(&self, x: &mut [f64]) {
        x[..2].copy_from_slice(&self.coordinate().start);
    }

    fn begin_rates(&self, x: &[f64]) -> [f64; PART_RATES] {
        [x[1], 0.0, 0.0]
    }

    fn put_momenta(&self, x: &mut [f64], p: &[f64]) {
        x[1] = p[0];
    }
}

/// The hooks of [`Part`](super::Part) of a [`OneCoordinate`] part beyond [`mover_hooks`]: its
/// spring's energy, its damper's power, its units.
macro_rules! one_coordinate_hooks {
    () => {
        fn energy(&self, _t: f64, x: &[f64]) -> f64 {
            $crate::dynamics::moving::OneCoordinate::coordinate(self).potential(x[0])
        }

        #[inline(always)]
        fn dissipation(&self, c: &$crate::dynamics::part::Ctx<'_>, _x: &[f64]) -> f64 {
            let coordinate = $crate::dynamics::moving::OneCoordinate::coordinate(self);
            c.moving.map_or(0.0, |m| coordinate.dissipation(m.rates[0]))
        }

        fn in_units(&self, scale: $crate::float::RateScale) -> $crate::error::Result<Self> {
            let coordinate = $crate::dynamics::moving::OneCoordinate::coordinate(self);
            Ok(Self {
                coordinate: coordinate.in_units(scale),
                ..*self
            })
        }
    };
}
pub(crate) use one_coordinate_hooks;
