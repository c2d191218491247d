//! The registry of models: the inertia laws (the free body, a deployment) and one line per
//! part, [`parts!`], from which the enum the hot loop matches on ([`AnyPart`], no virtual
//! calls), the [`Kinds`] bits and the table [`MODELS`] follow. Adding a part: its file (a type
//! implementing [`Part`], with its [`ModelInfo`]) and its name in the list at the end of this
//! file. Nothing else names it: the general model, the methods' registry, the binding, files
//! and scenes read its declaration.

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;

use super::control::{BDot, Controller, MomentumDumping, QuaternionFeedback, ResidualDipole};
use super::kinds::{Conserved, Kinds, Traits};
use super::multibody::{AloneSolve, Carried, Hub, PART_RATES};
use super::part::{
    Ctx, EnergyRole, Field, Fields, Frame, Function, MapFunction, ModelInfo, Param, ParamKind,
    Part, Sampling,
};
use super::{
    CallableTorque, ConstantTorque, Damper, GravityGradient, Hinge, Slosh, SpringMass,
    TabulatedTorque, Wheel, WheelSchedule,
};

/// The constant free body (eq. 1): an inertia law, no part.
pub const FREE: ModelInfo = ModelInfo {
    name: "free",
    about: "the constant free rigid body (eq. 1)",
    law: true,
    params: &[Param::new(
        "inertia",
        ParamKind::Vectors,
        "the inertia tensor, body axes (L = T ω)",
    )],
    state: &[],
    keeps: Conserved::FREE,
    defines: Conserved::NONE,
    energy: EnergyRole::Neither,
    external: false,
    unique: true,
    traits: Traits::NONE,
};

/// A prescribed, smooth inertia tensor `I(t)` ([`super::Deployment`]): an inertia law.
pub const DEPLOYMENT: ModelInfo = ModelInfo {
    name: "deployment",
    about: "a prescribed, smooth inertia tensor I(t) (dL/dt = L × ω, ω = I(t)⁻¹ L)",
    law: true,
    params: &[
        Param::new("times", ParamKind::Times, "knot times"),
        Param::new(
            "tensors",
            ParamKind::Vectors,
            "the inertia tensor at each knot, body axes",
        ),
    ],
    state: &[],
    keeps: Conserved::MOMENTA,
    defines: Conserved::NONE,
    energy: EnergyRole::DoesWork,
    external: false,
    unique: true,
    traits: Traits::CHANGING_BODY,
};

/// The number of inertia laws before the parts in [`MODELS`].
const LAWS: usize = 2;

/// An unknown part's name, refused naming the parts there are.
fn unknown(name: &str) -> Error {
    let names: Vec<String> = MODELS
        .iter()
        .filter(|m| !m.law)
        .map(|m| format!("'{}'", m.name))
        .collect();
    Error::invalid("kind", format!("must be one of {}", names.join(", ")), name)
}

/// Declares the parts: `parts! { Damper, Wheel, … }` makes [`AnyPart`] (one variant each),
/// [`MODELS`] (the laws, then the parts in this order) and each part's `KIND` bit.
macro_rules! parts {
    ($($ty:ident),* $(,)?; test: $($test:ident),* $(,)?) => {
        #[cfg(not(test))]
        parts!(@registry $($ty),*);
        #[cfg(test)]
        parts!(@registry $($ty,)* $($test),*);
    };
    (@registry $($ty:ident),* $(,)?) => {
        /// A part of any kind (see the module doc): what a system holds and the general model
        /// evaluates, each call one `match` the compiler inlines.
        #[derive(Debug, Clone, PartialEq)]
        pub enum AnyPart {
            $($ty($ty),)*
        }

        /// The parts' places in the registry.
        #[allow(dead_code)]
        #[derive(Clone, Copy)]
        enum Index {
            $($ty,)*
        }

        $(
            impl $ty {
                /// The part's bit in a set of models.
                pub const KIND: Kinds = Kinds::at(LAWS + Index::$ty as usize);
            }

            impl From<$ty> for AnyPart {
                fn from(part: $ty) -> Self {
                    AnyPart::$ty(part)
                }
            }
        )*

        /// Every model's declaration, in the order users see them: the inertia laws, then the
        /// parts in the registry's order. Bit `k` of [`Kinds`] is `MODELS[k]`.
        pub const MODELS: &[&ModelInfo] = &[&FREE, &DEPLOYMENT, $(&<$ty as Part>::INFO,)*];

        /// # Declaration
        impl AnyPart {
            /// The part of kind `name` (a registry name) from its parameters.
            ///
            /// # Errors
            /// An unknown kind, naming those there are; a parameter the part refuses.
            pub fn build(name: &str, fields: &Fields) -> Result<Self> {
                $(
                    if name == <$ty as Part>::INFO.name {
                        return Ok(AnyPart::$ty(<$ty as Part>::from_fields(fields)?));
                    }
                )*
                Err(unknown(name))
            }

            /// The part's declaration.
            pub fn info(&self) -> &'static ModelInfo {
                match self { $(AnyPart::$ty(_) => &<$ty as Part>::INFO,)* }
            }

            /// The part's bit in a set of models.
            pub fn kind(&self) -> Kinds {
                match self { $(AnyPart::$ty(_) => <$ty>::KIND,)* }
            }
        }

        /// # Contributions (see [`Part`])
        impl AnyPart {
            #[inline(always)]
            pub fn momentum(&self, t: f64, x: &[f64]) -> Vector3<f64> {
                match self { $(AnyPart::$ty(p) => Part::momentum(p, t, x),)* }
            }

            pub fn constant_momentum(&self) -> Option<Vector3<f64>> {
                match self { $(AnyPart::$ty(p) => Part::constant_momentum(p),)* }
            }

            #[inline(always)]
            pub fn torque(&self, c: &Ctx<'_>, x: &[f64]) -> Vector3<f64> {
                match self { $(AnyPart::$ty(p) => Part::torque(p, c, x),)* }
            }

            pub fn constant_torque(&self) -> Option<(Vector3<f64>, Frame)> {
                match self { $(AnyPart::$ty(p) => Part::constant_torque(p),)* }
            }

            #[inline(always)]
            pub fn rates(&self, c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
                match self { $(AnyPart::$ty(p) => Part::rates(p, c, x, dx),)* }
            }

            pub fn start(&self, omega0: &Vector3<f64>, x: &mut [f64]) {
                match self { $(AnyPart::$ty(p) => Part::start(p, omega0, x),)* }
            }

            pub fn energy(&self, t: f64, x: &[f64]) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::energy(p, t, x),)* }
            }

            #[inline(always)]
            pub fn dissipation(&self, c: &Ctx<'_>, x: &[f64]) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::dissipation(p, c, x),)* }
            }

            #[inline(always)]
            pub fn carried(&self, x: &[f64]) -> Option<(Carried, [f64; PART_RATES])> {
                match self { $(AnyPart::$ty(p) => Part::carried(p, x),)* }
            }

            pub fn moving_rates(&self) -> usize {
                match self { $(AnyPart::$ty(p) => Part::moving_rates(p),)* }
            }

            pub fn moving_mass(&self) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::moving_mass(p),)* }
            }

            pub fn start_rates(&self, x: &[f64]) -> [f64; PART_RATES] {
                match self { $(AnyPart::$ty(p) => Part::start_rates(p, x),)* }
            }

            pub fn set_momenta(&self, x: &mut [f64], p_: &[f64]) {
                match self { $(AnyPart::$ty(p) => Part::set_momenta(p, x, p_),)* }
            }

            pub fn alone(&self, hub: &Hub) -> Option<AloneSolve> {
                match self { $(AnyPart::$ty(p) => Part::alone(p, hub),)* }
            }

            pub fn frequency(&self, rate: f64) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::frequency(p, rate),)* }
            }

            pub fn largest_momentum(&self) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::largest_momentum(p),)* }
            }

            pub fn kinks(&self) -> Vec<f64> {
                match self { $(AnyPart::$ty(p) => Part::kinks(p),)* }
            }

            pub fn stiffness(&self, least: f64) -> f64 {
                match self { $(AnyPart::$ty(p) => Part::stiffness(p, least),)* }
            }

            pub fn integral(
                &self,
                t: f64,
                q: &Quaternion<f64>,
                tensor: &Matrix3<f64>,
                energy: f64,
                momentum: &Vector3<f64>,
            ) -> Option<f64> {
                match self {
                    $(AnyPart::$ty(p) => Part::integral(p, t, q, tensor, energy, momentum),)*
                }
            }

            pub fn rate_bound(
                &self,
                least: f64,
                largest: f64,
                integral: f64,
                stored: f64,
            ) -> Option<f64> {
                match self {
                    $(AnyPart::$ty(p) => Part::rate_bound(p, least, largest, integral, stored),)*
                }
            }

            pub fn stage_field(&self) -> Option<crate::dynamics::control::DipoleField> {
                match self { $(AnyPart::$ty(p) => Part::stage_field(p),)* }
            }

            pub fn sampling(&self) -> Option<Sampling> {
                match self { $(AnyPart::$ty(p) => Part::sampling(p),)* }
            }

            pub fn sample(&self, c: &Ctx<'_>, at: usize, x: &mut [f64]) {
                match self { $(AnyPart::$ty(p) => Part::sample(p, c, at, x),)* }
            }
        }

        /// The parts the right-hand side evaluates inline, in one column per kind (see
        /// [`super::GeneralModel`]): parts without state, and the first part with state (its
        /// state starts at the state's index 3). Each column's loop is monomorphic, and a
        /// kind that makes no such contribution compiles to no loop at all.
        #[allow(non_snake_case)]
        #[derive(Debug, Clone, PartialEq, Default)]
        pub struct Columns {
            $(pub $ty: Vec<$ty>,)*
            /// The first part with state, in the slot of its kind.
            first: First,
            /// A part without state of a kind a system holds at most one of.
            single: First,
            /// The kinds present, one bit each (in [`Index`]' order): a right-hand side tests
            /// a bit, not each column's length.
            present: u64,
        }

        /// The first part with state: one slot per kind, at most one of them filled (a chain
        /// of checks the compiler lays out straight, where a `match` would jump through a
        /// table).
        #[allow(non_snake_case)]
        #[derive(Debug, Clone, PartialEq, Default)]
        struct First {
            $($ty: Option<$ty>,)*
        }

        impl Columns {
            /// Puts `part` in its kind's column, or, with state, as the first part with state.
            pub fn push(&mut self, part: &AnyPart) {
                match part {
                    $(AnyPart::$ty(p) => match <$ty as Part>::INFO.width() {
                        0 if <$ty as Part>::INFO.unique => self.single.$ty = Some(p.clone()),
                        0 => self.$ty.push(p.clone()),
                        _ => self.first.$ty = Some(p.clone()),
                    },)*
                }
                self.present |= 1 << Self::index(part);
            }

            fn index(part: &AnyPart) -> usize {
                match part { $(AnyPart::$ty(_) => Index::$ty as usize,)* }
            }

            pub fn is_empty(&self) -> bool {
                self.present == 0
            }

            /// `h` less the momenta the columns' parts store (taken from `h` one by one: no
            /// sum formed first, one addition less on the chain every evaluation waits on).
            #[inline(always)]
            pub fn less_momentum<const N: usize>(
                &self,
                t: f64,
                x: &[f64; N],
                mut h: Vector3<f64>,
            ) -> Vector3<f64> {
                $(
                    if <$ty as Part>::INFO.traits.contains(Traits::STORED_MOMENTUM)
                        && self.present & (1 << Index::$ty as usize) != 0
                    {
                        const W: usize = <$ty as Part>::INFO.width();
                        if W == 0 && <$ty as Part>::INFO.unique {
                            if let Some(p) = &self.single.$ty {
                                h -= Part::momentum(p, t, &[]);
                            }
                        } else if W == 0 {
                            for p in &self.$ty {
                                h -= Part::momentum(p, t, &[]);
                            }
                        } else if let (Some(p), true) = (&self.first.$ty, 3 + W + 4 <= N) {
                            h -= Part::momentum(p, t, &x[3..3 + W]);
                        }
                    }
                )*
                h
            }

            /// `tau` plus the torques of the columns' parts.
            #[inline(always)]
            pub fn plus_torque<const N: usize>(
                &self,
                c: &Ctx<'_>,
                x: &[f64; N],
                mut tau: Vector3<f64>,
            ) -> Vector3<f64> {
                $(
                    if <$ty as Part>::INFO.external
                        && self.present & (1 << Index::$ty as usize) != 0
                    {
                        const W: usize = <$ty as Part>::INFO.width();
                        if W == 0 && <$ty as Part>::INFO.unique {
                            // at most one in a system: no loop
                            if let Some(p) = &self.single.$ty {
                                tau += Part::torque(p, c, &[]);
                            }
                        } else if W == 0 {
                            for p in &self.$ty {
                                tau += Part::torque(p, c, &[]);
                            }
                        } else if let (Some(p), true) = (&self.first.$ty, 3 + W + 4 <= N) {
                            tau += Part::torque(p, c, &x[3..3 + W]);
                        }
                    }
                )*
                tau
            }

            /// The rates of the first part with state (times `s`, into `dx[3..]`) and the
            /// power it dissipates.
            #[inline(always)]
            pub fn rates<const N: usize>(
                &self,
                c: &Ctx<'_>,
                x: &[f64; N],
                s: f64,
                dx: &mut [f64; N],
            ) -> f64 {
                let mut power = 0.0;
                $(
                    if <$ty as Part>::INFO.width() > 0
                        && self.present & (1 << Index::$ty as usize) != 0
                    {
                        const W: usize = <$ty as Part>::INFO.width();
                        if let (Some(p), true) = (&self.first.$ty, 3 + W + 4 <= N) {
                            let mut d = [0.0; W];
                            Part::rates(p, c, &x[3..3 + W], &mut d);
                            for (k, v) in d.iter().enumerate() {
                                dx[3 + k] = v * s;
                            }
                            if <$ty as Part>::INFO.energy == EnergyRole::Dissipates {
                                power += Part::dissipation(p, c, &x[3..3 + W]);
                            }
                        }
                    }
                )*
                power
            }
        }

        /// # Axes, units, runs
        impl AnyPart {
            pub fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
                match self { $(AnyPart::$ty(p) => AnyPart::$ty(Part::in_axes(p, to_axes)),)* }
            }

            /// # Errors
            /// See [`Part::with_moments_scaled`].
            pub fn with_moments_scaled(&self, m: i32) -> Result<Self> {
                Ok(match self {
                    $(AnyPart::$ty(p) => AnyPart::$ty(Part::with_moments_scaled(p, m)?),)*
                })
            }

            /// # Errors
            /// See [`Part::in_units`].
            pub fn in_units(&self, scale: RateScale) -> Result<Self> {
                Ok(match self { $(AnyPart::$ty(p) => AnyPart::$ty(Part::in_units(p, scale)?),)* })
            }

            pub fn seeded(&self, seed: u64, index: usize) -> Self {
                match self { $(AnyPart::$ty(p) => AnyPart::$ty(Part::seeded(p, seed, index)),)* }
            }

            pub fn heap_bytes(&self) -> usize {
                match self { $(AnyPart::$ty(p) => Part::heap_bytes(p),)* }
            }

            pub fn model_bytes(&self) -> usize {
                match self { $(AnyPart::$ty(p) => Part::model_bytes(p),)* }
            }

            pub fn largest_rate(&self, least: f64) -> Option<(&'static str, f64, f64)> {
                match self { $(AnyPart::$ty(p) => Part::largest_rate(p, least),)* }
            }

            pub fn functions(&self) -> Vec<&Arc<dyn Function>> {
                match self { $(AnyPart::$ty(p) => Part::functions(p),)* }
            }

            pub fn map_functions(&self, f: &mut MapFunction<'_>) -> Self {
                match self { $(AnyPart::$ty(p) => AnyPart::$ty(Part::map_functions(p, f)),)* }
            }
        }
    };
}

/// # Derived from the declaration
impl AnyPart {
    /// The registry name.
    pub fn name(&self) -> &'static str {
        self.info().name
    }

    /// How many numbers of state it has.
    pub fn width(&self) -> usize {
        self.info().width()
    }

    /// Its state's fields.
    pub fn state(&self) -> &'static [Field] {
        self.info().state
    }
}

/// The kinds of a system with `parts` whose inertia law changes (`changing`) or not: the one
/// place a system's set of models is made (its [`super::System`] and its run's model read it).
pub fn kinds_of(changing: bool, parts: &[AnyPart]) -> Kinds {
    let body = match changing {
        true => Kinds::DEPLOYMENT,
        false => Kinds::NONE,
    };
    match parts.iter().fold(body, |k, p| k.union(p.kind())) {
        Kinds::NONE => Kinds::FREE,
        kinds => kinds,
    }
}

#[cfg(test)]
use super::toy::Counter;

parts! {
    Damper,
    Wheel,
    WheelSchedule,
    GravityGradient,
    ConstantTorque,
    TabulatedTorque,
    CallableTorque,
    ResidualDipole,
    BDot,
    QuaternionFeedback,
    MomentumDumping,
    Controller,
    SpringMass,
    Hinge,
    Slosh;
    // parts that exist only to test the seam
    test: Counter,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_has_one_name_and_one_bit() {
        for (k, m) in MODELS.iter().enumerate() {
            assert_eq!(Kinds::named(m.name), Some(Kinds::at(k)), "{}", m.name);
            assert_eq!(MODELS.iter().filter(|o| o.name == m.name).count(), 1);
            // a part's state widths add up, an inertia law has none
            assert!(!m.law || m.state.is_empty());
            // an external torque keeps neither |L| nor L in space
            assert!(!m.external || !m.keeps.contains(Conserved::MOMENTUM_WORLD));
            assert_eq!(m.external, m.traits.contains(Traits::EXTERNAL_TORQUE));
            assert_eq!(m.width() > 0, m.traits.contains(Traits::PART_STATE));
        }
        assert_eq!(Damper::KIND, Kinds::named("damper").unwrap());
        let e = AnyPart::build("flywheel", &Fields::new()).unwrap_err();
        assert!(e.to_string().contains("'damper'"), "{e}");
    }
}
