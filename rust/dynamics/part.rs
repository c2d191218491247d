//! What a part is: one trait ([`Part`]) every part of a system implements — a damper, a wheel,
//! an external torque — and the declaration ([`ModelInfo`]) it gives of itself once, which the
//! general model, the registry of methods, the binding, files and scenes read.
//!
//! **Declaration.** A part says its registry name, its parameters ([`Param`]: the binding
//! extracts each by its kind, the part checks its range in [`Part::from_fields`]), its state
//! ([`Field`]s: their width, physical dimension and whether they are body-axes vectors, turned
//! at the principal-axes edge), what a system with it still keeps, its energy role
//! ([`EnergyRole`]), whether it is an external torque, and what it asks of a method
//! ([`Traits`]).
//!
//! **Contributions** to the general model's equations ([`super::GeneralModel`]), each with a
//! default of nothing, in body axes:
//!
//! ```text
//! ω  = I(t)⁻¹ (H − Σ stored momenta)         Part::momentum (a wheel's h a, a damper's j σ)
//! H' = H × ω + Σ external torques             Part::torque
//! x' = Part::rates                            the part's own state
//! E  = ½ ωᵀ I ω + Σ Part::energy,   W' = Σ Part::dissipation  (the energy balance E + W)
//! ```
//!
//! A contribution that is constant over a run ([`Part::constant_momentum`],
//! [`Part::constant_torque`]) is folded once before the run, so the hot loop evaluates only
//! what changes. Unit scaling ([`Part::in_units`], [`Part::with_moments_scaled`]) and the
//! change to principal axes ([`Part::in_axes`]) are the part's too: it knows which of its
//! parameters carry a time, a moment or a body direction.

use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;

use super::general::InertiaLaw;
use super::kinds::{Conserved, Traits};
use super::multibody::{AloneSolve, Carried, Hub, PART_RATES};

/// The kind of value a parameter takes: what the binding extracts, and files and scenes store.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamKind {
    /// A number.
    Scalar,
    /// Three numbers (a vector).
    Vector,
    /// Knot times `(K,)`: finite, strictly increasing.
    Times,
    /// A number at each knot `(K,)`.
    Values,
    /// A vector at each knot `(K, 3)`.
    Vectors,
    /// One of these words.
    Choice(&'static [&'static str]),
    /// The user's function, called with `args` and giving `returns` numbers.
    Function { args: &'static str, returns: usize },
}

impl ParamKind {
    /// The kind's name, as the binding and files read it.
    pub const fn name(&self) -> &'static str {
        match self {
            ParamKind::Scalar => "scalar",
            ParamKind::Vector => "vector",
            ParamKind::Times => "times",
            ParamKind::Values => "values",
            ParamKind::Vectors => "vectors",
            ParamKind::Choice(_) => "choice",
            ParamKind::Function { .. } => "function",
        }
    }
}

/// A parameter of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param {
    pub name: &'static str,
    pub kind: ParamKind,
    /// Whether it may be left out (the part says what that means).
    pub optional: bool,
    /// One line for users.
    pub about: &'static str,
}

impl Param {
    pub const fn new(name: &'static str, kind: ParamKind, about: &'static str) -> Self {
        Self {
            name,
            kind,
            optional: false,
            about,
        }
    }

    /// The same parameter, optional.
    pub const fn optional(self) -> Self {
        Self {
            optional: true,
            ..self
        }
    }
}

/// The physical dimension of a state component, as powers of a rate (`1/T`) and of a moment
/// of inertia: what it is divided by when a run goes in its own units (see [`crate::float`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dim {
    pub rate: i32,
    pub moment: i32,
}

impl Dim {
    /// An angle, a length, a number.
    pub const NONE: Self = Self { rate: 0, moment: 0 };
    /// A rate (`1/T`).
    pub const RATE: Self = Self { rate: 1, moment: 0 };
    /// An angular momentum (moment × rate).
    pub const MOMENTUM: Self = Self { rate: 1, moment: 1 };
    /// A torque or an energy (moment × rate²).
    pub const TORQUE: Self = Self { rate: 2, moment: 1 };
}

/// A field of a part's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    /// How many numbers.
    pub width: usize,
    /// A vector in body axes (width 3), turned with the body's axes at the edge of a run.
    pub body_vector: bool,
    pub dim: Dim,
    /// One line for users.
    pub about: &'static str,
}

/// What a part does to the energy, read by the energy watchdog and by what a system keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnergyRole {
    /// Neither gives nor takes energy (a constant wheel).
    Neither,
    /// Does work on the body: the energy may rise (a torque, a deployment, a wheel spun up).
    DoesWork,
    /// Only takes energy ([`Part::dissipation`] says at what rate): a system whose parts only
    /// dissipate keeps its energy balance and may be checked for growth.
    Dissipates,
}

impl EnergyRole {
    pub const fn name(self) -> &'static str {
        match self {
            EnergyRole::Neither => "neither",
            EnergyRole::DoesWork => "does work",
            EnergyRole::Dissipates => "dissipates",
        }
    }
}

/// What is known about a model before it runs: an inertia law (the free body, a deployment) or
/// a part. The one declaration of a model; [`super::MODELS`] lists them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelInfo {
    /// The name users, files, scenes and the registry use.
    pub name: &'static str,
    /// One line for users.
    pub about: &'static str,
    /// Whether it is an inertia law (the free body, a deployment) rather than a part.
    pub law: bool,
    pub params: &'static [Param],
    /// Its own state, in order.
    pub state: &'static [Field],
    /// What a system made of it (and the free body) keeps; a system keeps what each of its
    /// models keeps (see [`super::Kinds::conserved`]).
    pub keeps: Conserved,
    /// An invariant it brings that the free body has not (the Jacobi integral of an orbit).
    pub defines: Conserved,
    pub energy: EnergyRole,
    /// An external torque (a system's `torques`), not an internal part.
    pub external: bool,
    /// At most one in a system (one orbit).
    pub unique: bool,
    /// What it asks of a method.
    pub traits: Traits,
}

impl ModelInfo {
    /// How many numbers of state it has.
    pub const fn width(&self) -> usize {
        let mut w = 0;
        let mut k = 0;
        while k < self.state.len() {
            w += self.state[k].width;
            k += 1;
        }
        w
    }
}

/// An argument of a user's function ([`Function`]).
#[derive(Debug, Clone, Copy)]
pub enum Arg<'a> {
    Number(f64),
    Vector(&'a [f64]),
}

/// A change of a part's functions (see [`Part::map_functions`]): each function to the one
/// called instead.
pub type MapFunction<'a> = dyn FnMut(&Arc<dyn Function>) -> Arc<dyn Function> + 'a;

/// A function of the user's code (in Python: a callable), as a part calls it. The core stays
/// free of Python: the binding implements this.
pub trait Function: Send + Sync {
    /// Calls the function with `args`, writing the numbers it gives into `out`; false if it
    /// failed (the implementation keeps why, and is not called again).
    fn call(&self, args: &[Arg<'_>], out: &mut [f64]) -> bool;

    /// The implementation, for the binding to read back why it failed.
    fn as_any(&self) -> &dyn Any;
}

/// A parameter's value, as the binding extracted it by its [`ParamKind`].
#[derive(Clone)]
pub enum Value {
    Number(f64),
    Vector([f64; 3]),
    Numbers(Vec<f64>),
    Vectors(Vec<[f64; 3]>),
    Text(String),
    Function(Arc<dyn Function>),
}

impl Debug for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Number(v) => write!(f, "{v:?}"),
            Value::Vector(v) => write!(f, "{v:?}"),
            Value::Numbers(v) => write!(f, "{} numbers", v.len()),
            Value::Vectors(v) => write!(f, "{} vectors", v.len()),
            Value::Text(v) => write!(f, "{v:?}"),
            Value::Function(_) => write!(f, "a function"),
        }
    }
}

/// The parameters a part is built from, by name (see [`Part::from_fields`]).
#[derive(Debug, Clone, Default)]
pub struct Fields(Vec<(&'static str, Value)>);

impl Fields {
    pub fn new() -> Self {
        Self(Vec::new())
    }

    /// The same fields with `name` set to `value`.
    pub fn with(mut self, name: &'static str, value: Value) -> Self {
        self.set(name, value);
        self
    }

    pub fn set(&mut self, name: &'static str, value: Value) {
        self.0.retain(|(n, _)| *n != name);
        self.0.push((name, value));
    }

    pub fn get(&self, name: &str) -> Option<&Value> {
        self.0.iter().find(|(n, _)| *n == name).map(|(_, v)| v)
    }

    fn missing(name: &'static str, kind: &str) -> Error {
        Error::invalid(name, format!("must be given ({kind})"), "nothing")
    }

    /// The number `name`.
    ///
    /// # Errors
    /// `name` missing, or not a number.
    pub fn number(&self, name: &'static str) -> Result<f64> {
        match self.get(name) {
            Some(Value::Number(v)) => Ok(*v),
            _ => Err(Self::missing(name, "a number")),
        }
    }

    /// The number `name`, if given.
    ///
    /// # Errors
    /// `name` given but not a number.
    pub fn optional_number(&self, name: &'static str) -> Result<Option<f64>> {
        match self.get(name) {
            None => Ok(None),
            Some(Value::Number(v)) => Ok(Some(*v)),
            Some(_) => Err(Self::missing(name, "a number")),
        }
    }

    /// The vector `name`, if given.
    ///
    /// # Errors
    /// `name` given but not a vector.
    pub fn optional_vector(&self, name: &'static str) -> Result<Option<[f64; 3]>> {
        match self.get(name) {
            None => Ok(None),
            Some(Value::Vector(v)) => Ok(Some(*v)),
            Some(_) => Err(Self::missing(name, "three numbers")),
        }
    }

    /// The vector `name`.
    ///
    /// # Errors
    /// `name` missing, or not a vector.
    pub fn vector(&self, name: &'static str) -> Result<[f64; 3]> {
        self.optional_vector(name)?
            .ok_or_else(|| Self::missing(name, "three numbers"))
    }

    /// The numbers `name` (knot times or values).
    ///
    /// # Errors
    /// `name` missing, or not numbers.
    pub fn numbers(&self, name: &'static str) -> Result<Vec<f64>> {
        match self.get(name) {
            Some(Value::Numbers(v)) => Ok(v.clone()),
            _ => Err(Self::missing(name, "numbers")),
        }
    }

    /// The vectors `name` (a vector at each knot).
    ///
    /// # Errors
    /// `name` missing, or not vectors.
    pub fn vectors(&self, name: &'static str) -> Result<Vec<[f64; 3]>> {
        match self.get(name) {
            Some(Value::Vectors(v)) => Ok(v.clone()),
            _ => Err(Self::missing(name, "vectors")),
        }
    }

    /// The word `name`, parsed.
    ///
    /// # Errors
    /// `name` missing, or not a word `T` parses.
    pub fn choice<T: std::str::FromStr<Err = Error>>(&self, name: &'static str) -> Result<T> {
        match self.get(name) {
            Some(Value::Text(v)) => v.parse(),
            _ => Err(Self::missing(name, "a word")),
        }
    }

    /// The function `name`.
    ///
    /// # Errors
    /// `name` missing, or not a function.
    pub fn function(&self, name: &'static str) -> Result<Arc<dyn Function>> {
        match self.get(name) {
            Some(Value::Function(f)) => Ok(f.clone()),
            _ => Err(Self::missing(name, "a function")),
        }
    }
}

/// What a part's contributions see at one evaluation, in the run's axes and units: the time,
/// the attitude (world-from-body, not normalised), the body rates and the body's inertia law.
#[derive(Debug, Clone, Copy)]
pub struct Ctx<'a> {
    pub t: f64,
    pub q: Quaternion<f64>,
    pub omega: Vector3<f64>,
    pub inertia: &'a InertiaLaw,
    /// For a part whose mass moves in the body: what the joint solve found for it.
    pub moving: Option<Moved<'a>>,
    /// What the model made of `t` alone, once for every stage at `t` (see [`Timed`]).
    pub timed: Timed,
}

/// What a general model makes of a stage time alone, once for every stage at that time (see
/// [`crate::ode::StageTime`]), for the parts that read it at every stage: each `None` where
/// the model did not make it (the part then evaluates it itself, to the same numbers).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timed {
    /// `(sin nt, cos nt)` of the gravity gradient's orbit phase.
    pub orbit: Option<(f64, f64)>,
    /// The field every magnetic part of the system reads ([`Part::stage_field`]), in world
    /// axes at `t`.
    pub field: Option<Vector3<f64>>,
}

/// What the joint solve of a body carrying moving mass gives one such part (see
/// [`super::multibody`]): its rates, its mass element's velocity in the frame of the system's
/// mass centre and its angular velocity (body axes), and what it carries at this state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moved<'a> {
    pub rates: [f64; PART_RATES],
    pub velocity: Vector3<f64>,
    pub spin: Vector3<f64>,
    pub carried: &'a Carried,
}

impl Ctx<'_> {
    /// `field` at this stage, in body axes: from the world field the model made once for the
    /// stage's time ([`Timed::field`], when `field` is the one it made), else made here.
    #[inline(always)]
    pub fn field_in_body(&self, field: &crate::dynamics::control::DipoleField) -> Vector3<f64> {
        match self.timed.field {
            Some(world) => crate::kinematics::world_to_body(&self.q, &world),
            None => field.body(self.t, &self.q),
        }
    }

    /// `I(t) v`.
    #[inline(always)]
    pub fn inertia_times(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.inertia.apply(self.t, v)
    }
}

/// The axes a vector is fixed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    Body,
    World,
}

impl std::str::FromStr for Frame {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "body" => Ok(Frame::Body),
            "world" => Ok(Frame::World),
            _ => Err(Error::invalid("frame", "must be 'body' or 'world'", s)),
        }
    }
}

/// When a sampled part is evaluated: at `phase + k · period`, `k = 0, 1, …` (see
/// [`Part::sample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    pub period: f64,
    pub phase: f64,
}

/// A part of a system (see the module doc). Every contribution defaults to nothing, so a part
/// states only what it does.
pub trait Part: Clone + Debug + PartialEq + Send + Sync + Sized {
    /// The part's declaration.
    const INFO: ModelInfo;

    /// The part from its parameters, each checked.
    ///
    /// # Errors
    /// A parameter out of its range, naming it.
    fn from_fields(fields: &Fields) -> Result<Self>;

    /// The angular momentum stored in the part (body axes) at `t` with state `x`: `H` counts
    /// it, the body's rates do not.
    #[inline(always)]
    fn momentum(&self, _t: f64, _x: &[f64]) -> Vector3<f64> {
        Vector3::zeros()
    }

    /// The stored momentum if it is constant over a run (folded once before it).
    fn constant_momentum(&self) -> Option<Vector3<f64>> {
        None
    }

    /// The external torque on the body, in body axes.
    #[inline(always)]
    fn torque(&self, _c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        Vector3::zeros()
    }

    /// The torque if it is a constant vector in body or world axes (folded once before a run).
    fn constant_torque(&self) -> Option<(Vector3<f64>, Frame)> {
        None
    }

    /// The rates of the part's own state `x`, written into `dx` (as long as `x`).
    #[inline(always)]
    fn rates(&self, _c: &Ctx<'_>, _x: &[f64], _dx: &mut [f64]) {}

    /// The part's state at the start of a run from the body rates `omega0` (the part's axes),
    /// written into `x`.
    fn start(&self, _omega0: &Vector3<f64>, _x: &mut [f64]) {}

    /// For a part whose mass moves in the body ([`Traits::MOVING_MASS`]): what it carries at
    /// state `x` (see [`super::multibody`]) and its momenta conjugate to its rates.
    #[inline(always)]
    fn carried(&self, _x: &[f64]) -> Option<(Carried, [f64; PART_RATES])> {
        None
    }

    /// How many rates it has in the joint solve.
    fn moving_rates(&self) -> usize {
        0
    }

    /// The mass it moves in the body (constant).
    fn moving_mass(&self) -> f64 {
        0.0
    }

    /// Its rates at the start, from the state [`Part::start`] wrote.
    fn start_rates(&self, _x: &[f64]) -> [f64; PART_RATES] {
        [0.0; PART_RATES]
    }

    /// Writes the momenta `p` (the start's, from the mass matrix) into its state.
    fn set_momenta(&self, _x: &mut [f64], _p: &[f64]) {}

    /// Its closed form alone on `hub` (the system's only part), if it has one: the run then
    /// takes it instead of the general joint solve.
    fn alone(&self, _hub: &Hub) -> Option<AloneSolve> {
        None
    }

    /// A bound on the frequency of its own oscillation on a body turning at up to `rate`.
    fn frequency(&self, _rate: f64) -> f64 {
        0.0
    }

    /// The part's own kinetic (and potential) energy at `t` with state `x`; a part whose mass
    /// moves gives its potential alone (the kinetic energy is the whole system's).
    fn energy(&self, _t: f64, _x: &[f64]) -> f64 {
        0.0
    }

    /// The power the part dissipates (non-negative), for a part that does.
    #[inline(always)]
    fn dissipation(&self, _c: &Ctx<'_>, _x: &[f64]) -> f64 {
        0.0
    }

    /// The largest `|stored momentum|` over a run (for the rate bound).
    fn largest_momentum(&self) -> f64 {
        self.constant_momentum().map_or(0.0, |h| h.norm())
    }

    /// The times (increasing) where the part's law has a kink or a jump: every step ends on
    /// them.
    fn kinks(&self) -> Vec<f64> {
        Vec::new()
    }

    /// The decay rate of the part's fastest own mode for a body of least moment `least` (a
    /// damper's slip): an explicit method's step times it must stay within its real-axis
    /// stability limit.
    fn stiffness(&self, _least: f64) -> f64 {
        0.0
    }

    /// An integral the part brings to the motion (the Jacobi integral of an orbit) at `t`,
    /// attitude `q`, for a body of tensor `tensor` with kinetic energy `energy` and total
    /// momentum `momentum` (body axes).
    fn integral(
        &self,
        _t: f64,
        _q: &Quaternion<f64>,
        _tensor: &Matrix3<f64>,
        _energy: f64,
        _momentum: &Vector3<f64>,
    ) -> Option<f64> {
        None
    }

    /// A bound on the body rates from the part's [`Part::integral`] `integral`, for a body of
    /// least and largest moments `least` and `largest` with stored momenta of at most `stored`.
    fn rate_bound(&self, _least: f64, _largest: f64, _integral: f64, _stored: f64) -> Option<f64> {
        None
    }

    /// The magnetic field the part's torque reads at every stage, if it does: a model whose
    /// magnetic parts all read one field makes it once per stage time (in [`Ctx::timed`]).
    fn stage_field(&self) -> Option<crate::dynamics::control::DipoleField> {
        None
    }

    /// When the part is sampled, if it is (see [`Part::sample`]).
    fn sampling(&self) -> Option<Sampling> {
        None
    }

    /// At a sample time `c.t` of the part, with the run as it is then (`c`): its discrete
    /// update of the run's state `x` (the whole
    /// state `[H, parts…, q]`; the part's own state starts at `at`), e.g. a controller's held
    /// command. Every method ends a step on the sample times, and the run calls this there.
    fn sample(&self, _c: &Ctx<'_>, _at: usize, _x: &mut [f64]) {}

    /// The same part with its body-axes vectors mapped by `to_axes` (a change of body axes).
    fn in_axes(&self, _to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        self.clone()
    }

    /// The same part for moments over `2^m` (see [`crate::float`]).
    ///
    /// # Errors
    /// A parameter that float64 no longer holds.
    fn with_moments_scaled(&self, _m: i32) -> Result<Self> {
        Ok(self.clone())
    }

    /// The same part with times in the units of `scale` (see [`crate::float`]).
    ///
    /// # Errors
    /// A parameter that float64 no longer holds.
    fn in_units(&self, _scale: RateScale) -> Result<Self> {
        Ok(self.clone())
    }

    /// The same part for the run of seed `seed` (a sensor's noise), `index` its place among
    /// the system's parts (two parts draw different streams).
    fn seeded(&self, _seed: u64, _index: usize) -> Self {
        self.clone()
    }

    /// About how many bytes a copy of the part holds on the heap (a table shared by the
    /// copies counts nothing).
    fn heap_bytes(&self) -> usize {
        0
    }

    /// About the most bytes a run's model holds for the part while it is built (its tables
    /// copied into the run's axes and units, the kinks they add): what a run checks it has
    /// room for before it starts.
    fn model_bytes(&self) -> usize {
        0
    }

    /// The largest rate the part brings to a body of least moment `least` (a wheel's
    /// momentum over it, an orbit's rate), with the parameter that sets it and that
    /// parameter's value: what a rate bound float64 cannot hold is blamed on.
    fn largest_rate(&self, _least: f64) -> Option<(&'static str, f64, f64)> {
        None
    }

    /// The user's functions the part calls (the binding readies and stops them).
    fn functions(&self) -> Vec<&Arc<dyn Function>> {
        Vec::new()
    }

    /// The same part calling `f` of each of its functions instead (a run's own view of the
    /// user's function).
    fn map_functions(&self, _f: &mut MapFunction<'_>) -> Self {
        self.clone()
    }
}

/// The heap bytes of a vector of `n` values of `T`, with the allocator's header.
pub(crate) fn block<T>(n: usize) -> usize {
    let bytes = n * std::mem::size_of::<T>();
    if bytes == 0 {
        0
    } else {
        bytes.max(16) + 16
    }
}
