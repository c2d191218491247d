//! The general model: a body whose inertia is constant or prescribed ([`Deployment`]), with
//! its parts in the user's order ([`AnyPart`]: dampers, wheels, external torques, …), in the
//! total angular momentum. Each part contributes what it declares (see [`super::Part`]); the
//! model adds them up, folding what is constant over a run once before it.
//!
//! **State** `[H (3), the parts' states…, padding, W (1, if a part dissipates), q (4)]`: `H`
//! the total angular momentum in body axes, each part's own state in the parts' order, zeros
//! up to the state size `N` the run was given (see [`crate::run::simulate_system`]: a few
//! sizes are compiled), `W` the work the parts dissipated since the start, `q` the attitude.
//! With `I(t)` the body's tensor (a part's mass counted as the body's),
//!
//! ```text
//! ω  = I(t)⁻¹ (H − Σ h_k)              h_k the momentum part k stores (a wheel's h a, j σ)
//! H' = H × ω + Σ τ_k                   τ_k part k's external torque, body axes
//! x_k' = part k's rates                (a damper: σ' = σ × ω − (c / j) (σ − ω))
//! W' = Σ P_k                           P_k ≥ 0 the power part k dissipates
//! q' = ½ q ⊗ (0, ω)
//! ```
//!
//! `ω` is made in one place ([`GeneralModel::omega_body`]). With parts whose mass moves in the
//! body ([`Traits::MOVING_MASS`]: a spring–mass damper, a hinged appendage, slosh) it is solved
//! there jointly with their rates, from the mass matrix of the hub and those parts about the
//! system's mass centre ([`super::multibody`]; the body's mass is then needed): `H` is their
//! total angular momentum, each such part's state holds its conjugate momenta, and each gets
//! its rates and its element's velocity through [`Ctx::moving`]. A deployment alone is
//! `L' = L × ω, ω = I(t)⁻¹ L` (see [`Deployment`]); a damped body alone is Hughes's spherical
//! damper; constant wheels make a gyrostat. Without external torques every such model keeps
//! `|H|` and `H` in space exactly; with a gravity gradient alone (and constant wheels) the
//! Jacobi integral ([`Model::jacobi`]). The energy `E = ½ ωᵀ I ω + Σ E_k` of a system whose
//! parts only dissipate falls by exactly `W`: its energy balance `E + W` is kept, and its drift
//! measures the run's error as the free body's energy drift does.

use std::fmt::Debug;

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::world_to_body;
use crate::ode::{OdeSystem, StageTime, Visit};

use super::control::DipoleField;
use super::damper::DamperKernel;
use super::gravity::{sin_cos, OrbitKernel};
use super::kinds::{Conserved, Kinds, Traits};
use super::model::{
    attitude, mid_axis_of, quaternion_increment, set_attitude, MidAxis, Model, MomentumProjection,
};
use super::multibody::{self, Alone, AloneSolve, Carried, Hub, MassMatrix, MAX_RATES, PART_RATES};
use super::part::Moved;
use super::part::{Ctx, Dim, EnergyRole, Frame, Timed};
use super::registry::{kinds_of, AnyPart, Columns};
use super::{Clocks, Deployment};

/// A constant tensor, its inverse, and what the runs read of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantInertia {
    tensor: Matrix3<f64>,
    inverse: Matrix3<f64>,
    /// The principal moments when the tensor is diagonal, and their reciprocals: `I⁻¹ L` is
    /// then three multiplications (within round-off of three divisions, and off the critical
    /// path of a right-hand side).
    diagonal: Option<(Vector3<f64>, Vector3<f64>)>,
    mid: MidAxis,
    least: f64,
}

impl ConstantInertia {
    /// A symmetric, positive definite, finite tensor.
    ///
    /// # Errors
    /// A tensor that is not that, or whose inverse float64 cannot hold.
    pub fn try_new(tensor: Matrix3<f64>) -> Result<Self> {
        let symmetric = (tensor - tensor.transpose()).amax() <= 1e-12 * tensor.amax();
        let inverse = tensor.try_inverse();
        let unit = tensor * crate::ode::power_of_two_scale(tensor.amax());
        let ok = tensor.iter().all(|v| v.is_finite())
            && symmetric
            && unit.cholesky().is_some()
            && inverse.is_some_and(|m| m.iter().all(|v| v.is_finite()));
        let Some(inverse) = inverse.filter(|_| ok) else {
            return Err(Error::invalid(
                "inertia",
                "must be a symmetric, positive definite, finite tensor (3 × 3)",
                tensor.as_slice(),
            ));
        };
        // halves first: a moment near the largest float64 would overflow in `m + mᵀ`
        let tensor = tensor * 0.5 + tensor.transpose() * 0.5;
        let is_diagonal = (0..3).all(|i| (0..3).all(|j| i == j || tensor[(i, j)] == 0.0));
        let mid = mid_axis_of(&tensor, is_diagonal);
        Ok(Self {
            tensor,
            inverse,
            diagonal: is_diagonal.then(|| {
                let d = tensor.diagonal();
                (d, d.map(|v| 1.0 / v))
            }),
            mid,
            least: tensor.symmetric_eigenvalues().min(),
        })
    }

    /// The principal moments, when the tensor is diagonal.
    pub fn moments(&self) -> Option<Vector3<f64>> {
        self.diagonal.map(|(d, _)| d)
    }

    #[inline(always)]
    fn apply(&self, v: &Vector3<f64>) -> Vector3<f64> {
        match self.diagonal {
            Some((d, _)) => v.component_mul(&d),
            None => self.tensor * v,
        }
    }

    #[inline(always)]
    fn solve(&self, l: &Vector3<f64>) -> Vector3<f64> {
        match self.diagonal {
            Some((_, r)) => l.component_mul(&r),
            None => self.inverse * l,
        }
    }
}

/// How the body's inertia goes over a run.
#[derive(Debug, Clone, PartialEq)]
pub enum InertiaLaw {
    Constant(ConstantInertia),
    Schedule(Deployment),
}

impl InertiaLaw {
    /// `ω = I(t)⁻¹ l`.
    #[inline(always)]
    pub fn omega_from(&self, t: f64, l: &Vector3<f64>) -> Vector3<f64> {
        match self {
            InertiaLaw::Constant(c) => c.solve(l),
            InertiaLaw::Schedule(d) => d.omega_from_momentum(t, l),
        }
    }

    /// `I(t) v`.
    #[inline(always)]
    pub fn apply(&self, t: f64, v: &Vector3<f64>) -> Vector3<f64> {
        match self {
            InertiaLaw::Constant(c) => c.apply(v),
            InertiaLaw::Schedule(d) => d.inertia_at(t) * v,
        }
    }

    /// `I(t)`.
    pub fn tensor_at(&self, t: f64) -> Matrix3<f64> {
        match self {
            InertiaLaw::Constant(c) => c.tensor,
            InertiaLaw::Schedule(d) => d.inertia_at(t),
        }
    }

    /// The least principal moment over the run.
    fn least(&self) -> f64 {
        match self {
            InertiaLaw::Constant(c) => c.least,
            InertiaLaw::Schedule(d) => d.least_moment(),
        }
    }
}

/// The state sizes the general model is compiled for: a run takes the least that holds its
/// parts' state (and the dissipated work), the rest padded with zeros whose rates are 0 (the
/// adaptive error norm and the drift read the model's own numbers alone). Each size compiles
/// the drivers, methods and observers once more.
pub const STATE_SIZES: [usize; 8] = [7, 8, 10, 11, 12, 14, 16, 24];

/// The most numbers of state a system's parts may have together (with the dissipated work).
pub const MAX_PARTS_STATE: usize = STATE_SIZES[STATE_SIZES.len() - 1] - 7;

/// A part placed in the state: where its own state starts, and how many numbers it has.
#[derive(Debug, Clone, PartialEq)]
struct Placed {
    part: AnyPart,
    at: usize,
    width: usize,
}

impl Placed {
    #[inline(always)]
    fn of<'x>(&self, x: &'x [f64]) -> &'x [f64] {
        &x[self.at..self.at + self.width]
    }
}

/// The parts as the right-hand side evaluates them. Its arrays are indexed at fixed places
/// only, so that the compiler keeps a step's states in registers (an index known at run time
/// would keep them in memory, and cost a system without parts as much as one with them): the
/// parts without state and the first part with state (its state starts at index 3) inline,
/// one monomorphic loop per kind ([`Columns`]); the other parts with state out of line on a
/// copy of the state.
#[derive(Debug, Clone, PartialEq, Default)]
struct Hot {
    /// Parts evaluated inline: without state and with a changing stored momentum or torque,
    /// and the first part with state.
    columns: Columns,
    /// Whether the inline parts store momentum, give a torque, have state.
    stores: bool,
    torques: bool,
    states: bool,
    /// The other parts with state.
    rest: Vec<Placed>,
}

impl Hot {
    fn of(parts: &[Placed]) -> Self {
        let mut hot = Self::default();
        for p in parts {
            let info = p.part.info();
            let stores = info.traits.contains(Traits::STORED_MOMENTUM)
                && p.part.constant_momentum().is_none();
            let torques = info.external && p.part.constant_torque().is_none();
            let inline = match p.width {
                0 => stores || torques,
                _ => !hot.states,
            };
            if !inline {
                if p.width > 0 {
                    hot.rest.push(p.clone());
                }
                continue;
            }
            hot.columns.push(&p.part);
            hot.stores |= stores;
            hot.torques |= torques;
            hot.states |= p.width > 0;
        }
        hot
    }
}

/// What the right-hand side makes of `t` alone, once for each distinct stage time (see
/// [`StageTime`]; its `of_t` holds `[sin nt, cos nt, B_world]`): the gravity gradient's orbit
/// phase, and the magnetic field in world axes when every magnetic part reads the same one
/// (else each part makes its own at every stage). A system without either makes nothing.
#[derive(Debug, Clone, PartialEq, Default)]
struct TimeOnly {
    orbit_rate: Option<f64>,
    field: Option<DipoleField>,
}

impl TimeOnly {
    fn of(parts: &[AnyPart]) -> Self {
        let orbit_rate = parts.iter().find_map(|p| match p {
            AnyPart::GravityGradient(g) => Some(g.orbit_rate()),
            _ => None,
        });
        let fields: Vec<DipoleField> = parts.iter().filter_map(AnyPart::stage_field).collect();
        let field = fields
            .first()
            .cloned()
            .filter(|f| fields.iter().all(|g| g == f));
        Self { orbit_rate, field }
    }

    #[inline(always)]
    fn at(&self, t: f64) -> StageTime {
        let mut at = StageTime::bare(t);
        if let Some(n) = self.orbit_rate {
            (at.of_t[0], at.of_t[1]) = sin_cos(n * t);
        }
        if let Some(f) = &self.field {
            at.of_t[2..].copy_from_slice(f.world(t).as_slice());
        }
        at
    }

    /// What the parts read of `at` (made by [`TimeOnly::at`]).
    #[inline(always)]
    fn timed(&self, at: &StageTime) -> Timed {
        let v = &at.of_t;
        Timed {
            orbit: self.orbit_rate.map(|_| (v[0], v[1])),
            field: self.field.as_ref().map(|_| Vector3::new(v[2], v[3], v[4])),
        }
    }
}

/// A right-hand side written out for a common system (see [`OrbitKernel`], [`DamperKernel`]):
/// a body of constant principal moments with the gravity gradient alone (and constant
/// wheels), or with one damper alone. Every other system takes the parts in turn.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kernel {
    None,
    Orbit(OrbitKernel),
    Damper(DamperKernel),
}

impl Kernel {
    fn of(
        inertia: &InertiaLaw,
        parts: &[AnyPart],
        folded: bool,
        stored: Option<Vector3<f64>>,
    ) -> Self {
        let InertiaLaw::Constant(ConstantInertia {
            diagonal: Some((d, r)),
            ..
        }) = inertia
        else {
            return Kernel::None;
        };
        let changing = |p: &&AnyPart| !GeneralModel::<7>::is_lean(std::slice::from_ref(p));
        let mut hot = parts.iter().filter(changing);
        match (hot.next(), hot.next(), folded) {
            (Some(AnyPart::GravityGradient(g)), None, false) => {
                Kernel::Orbit(OrbitKernel::new(g, *d, *r, stored.unwrap_or_default()))
            }
            (Some(AnyPart::Damper(p)), None, false) if parts.len() == 1 => {
                Kernel::Damper(DamperKernel::new(p, *r))
            }
            _ => Kernel::None,
        }
    }
}

/// A general model whose right-hand side is the orbit kernel's ([`OrbitKernel`]): what a
/// step runs ([`OdeSystem::specialised`]), the model's own numbers but for the phases of a
/// step's later stage times, turned from its first ([`OrbitKernel::phases`]): one `sin_cos`
/// beside the first instead of two more (AMD EPYC, CPU time: 65.8 -> 61.6 ns an RK4 step).
#[derive(Debug, Clone, Copy)]
struct OrbitRun<const N: usize> {
    kernel: OrbitKernel,
}

impl<const N: usize> OdeSystem<N> for OrbitRun<N> {
    #[inline(always)]
    fn increment(&self, t: f64, x: &[f64; N], s: f64) -> [f64; N] {
        self.increment_at(&self.at_time(t), x, s)
    }

    /// The orbit's phase (as [`TimeOnly::at`] makes it).
    #[inline(always)]
    fn at_time(&self, t: f64) -> StageTime {
        let mut at = StageTime::bare(t);
        (at.of_t[0], at.of_t[1]) = self.kernel.phase(t);
        at
    }

    #[inline(always)]
    fn stage_times(&self, t: f64, h: f64) -> [StageTime; 3] {
        let half = 0.5 * h;
        let times = [t, t + half, t + h];
        let phases = self.kernel.phases(t, half);
        std::array::from_fn(|k| {
            let mut at = StageTime::bare(times[k]);
            (at.of_t[0], at.of_t[1]) = phases[k];
            at
        })
    }

    #[inline(always)]
    fn increment_at(&self, at: &StageTime, x: &[f64; N], s: f64) -> [f64; N] {
        let q = [x[N - 4], x[N - 3], x[N - 2], x[N - 1]];
        let phase = (at.of_t[0], at.of_t[1]);
        let (dh, dq) = self.kernel.increment_at(phase, [x[0], x[1], x[2]], q, s);
        let mut dx = [0.0; N];
        dx[..3].copy_from_slice(&dh);
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }
}

/// A general model whose right-hand side is the damper kernel's ([`DamperKernel`]), as
/// [`OrbitRun`]: the model's own numbers, bit for bit.
#[derive(Debug, Clone, Copy)]
struct DamperRun<const N: usize> {
    kernel: DamperKernel,
}

impl<const N: usize> OdeSystem<N> for DamperRun<N> {
    #[inline(always)]
    fn increment(&self, _t: f64, x: &[f64; N], s: f64) -> [f64; N] {
        let q = [x[N - 4], x[N - 3], x[N - 2], x[N - 1]];
        let k = &self.kernel;
        let (dh, ds, dw, dq) = k.increment([x[0], x[1], x[2]], [x[3], x[4], x[5]], q, s);
        let mut dx = [0.0; N];
        dx[..3].copy_from_slice(&dh);
        dx[3..6].copy_from_slice(&ds);
        dx[N - 5] = dw;
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }
}

/// The general model (see the module doc); `N` is the state size, at least `7 +` the parts'
/// state (and one for the dissipated work). `HOT = false` is the model of a system whose parts
/// are all folded (constant wheels and torques, or none: a deployment): its right-hand side is
/// compiled without any part's code (see [`GeneralModel::is_lean`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralModel<const N: usize, const HOT: bool = true, M: Movers = NoMoving> {
    inertia: InertiaLaw,
    /// Every part, in the user's order (in the run's axes and units).
    parts: Vec<AnyPart>,
    /// The constant stored momenta, summed (constant wheels' `Σ h a`).
    stored: Option<Vector3<f64>>,
    /// The constant torques fixed in body axes, and in space, each summed.
    body_torque: Option<Vector3<f64>>,
    world_torque: Option<Vector3<f64>>,
    /// The parts whose stored momentum changes, whose torque is not constant, that have a
    /// state, that dissipate, that are sampled: what the right-hand side loops over.
    stores: Vec<Placed>,
    torques: Vec<Placed>,
    states: Vec<Placed>,
    dissipators: Vec<Placed>,
    sampled: Vec<Placed>,
    /// The right-hand side's view of the same (see [`Hot`]).
    hot: Hot,
    kernel: Kernel,
    /// What the right-hand side makes of `t` alone, once per stage time.
    time_only: TimeOnly,
    /// Whether there is any external torque.
    torqued: bool,
    /// The parts' state: how many numbers, and the dimension of each.
    width: usize,
    dims: Vec<Dim>,
    /// Where the dissipated work `W` is, if a part dissipates.
    balance: Option<usize>,
    kinds: Kinds,
    /// Whether the energy can only fall: a part dissipates, none (nor the body) does work.
    only_loses: bool,
    /// Where the right-hand side has a kink or a jump (tabulated laws; the sample times too,
    /// from `clocks`): every step ends there.
    kinks: Vec<f64>,
    /// Where it is not smooth: the kinks and a deployment's knots (adaptive steps end there).
    knots: Vec<f64>,
    /// The sampled parts' clocks, each with the index of its part in `sampled`: their sample
    /// times are asked for as the run goes, never listed.
    clocks: Clocks,
    /// The run's end (kept through a change of units).
    horizon: f64,
    /// The parts whose mass moves in the body and the hub they move in: the one extension of
    /// the model for such parts ([`Moving`]), or nothing ([`NoMoving`], every other model).
    moving: M,
}

/// The parts whose mass moves in the body (see [`super::multibody`]), the hub they move in
/// and the other parts with state as the joint solve's right-hand side takes them. Nothing in
/// it depends on the state's size `N`, and its joint solve is out of line: it is compiled once,
/// not once per state size and per stage of every method (generic over `N` and over four
/// buffer sizes, and inlined, it had made a release build of the module 4× as long).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Moving {
    parts: Vec<Placed>,
    /// The hub (the body's mass and tensor), once the body's mass is given.
    hub: Option<Hub>,
    /// A single such part on a body of constant inertia, in its closed form (see
    /// [`super::Part::alone`]), whatever else the system has (torques, wheels, parts whose
    /// mass does not move: they change `H'` and the body's own momentum, not the solve).
    alone: Option<AloneSolve>,
    /// The parts with state, and those that dissipate, whose mass does not move.
    fixed_states: Vec<Placed>,
    fixed_dissipators: Vec<Placed>,
    /// Whether RK4 takes a whole step of the lone part at once ([`super::lone_step`]): it is
    /// alone, first in the state, and beside it nothing but constant stored momenta and
    /// constant torques.
    stepped: bool,
}

/// What a general model holds of parts whose mass moves, chosen once when the run builds it:
/// [`Moving`], or [`NoMoving`] for every other model. `NoMoving` holds nothing and its
/// [`Movers::get`] is a constant `None`, so such a model's layout and right-hand side are
/// those of a model without the extension: a body pays nothing for parts it does not have.
pub trait Movers: Debug + Clone + PartialEq + Send + Sync + Sized {
    /// The moving parts of `moving` as this type holds them; `None` if it holds none and
    /// there are some (a bug in the caller: the run picks the type).
    fn from_moving(moving: Moving) -> Option<Self>;
    /// The moving parts, if the type holds them.
    fn get(&self) -> Option<&Moving>;
    fn get_mut(&mut self) -> Option<&mut Moving>;
    /// `model` as a model without moving parts, if it is one (what the splittings run).
    fn plain<const N: usize, const HOT: bool>(
        model: &GeneralModel<N, HOT, Self>,
    ) -> Option<&GeneralModel<N, HOT>>;
    /// One RK4 step of the lone part at once, if the model takes it so (see
    /// [`super::lone_step`]); `stored` and `torques` as [`GeneralModel`] holds them (the
    /// torques when it has any). A method of this trait, so that a model without moving
    /// parts compiles none of it.
    #[doc(hidden)]
    fn rk4_step<const N: usize>(
        &self,
        stored: Option<Vector3<f64>>,
        torques: super::lone_step::Torques,
        t: f64,
        h: f64,
        x: &mut [f64; N],
    ) -> bool;
}

/// No part whose mass moves (see [`Movers`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoMoving;

impl Movers for NoMoving {
    fn from_moving(moving: Moving) -> Option<Self> {
        moving.parts.is_empty().then_some(NoMoving)
    }
    #[inline(always)]
    fn get(&self) -> Option<&Moving> {
        None
    }
    #[inline(always)]
    fn get_mut(&mut self) -> Option<&mut Moving> {
        None
    }
    fn plain<const N: usize, const HOT: bool>(
        model: &GeneralModel<N, HOT, Self>,
    ) -> Option<&GeneralModel<N, HOT>> {
        Some(model)
    }
    #[inline(always)]
    fn rk4_step<const N: usize>(
        &self,
        _stored: Option<Vector3<f64>>,
        _torques: super::lone_step::Torques,
        _t: f64,
        _h: f64,
        _x: &mut [f64; N],
    ) -> bool {
        false
    }
}

impl Movers for Moving {
    fn from_moving(moving: Moving) -> Option<Self> {
        Some(moving)
    }
    #[inline(always)]
    fn get(&self) -> Option<&Moving> {
        Some(self)
    }
    #[inline(always)]
    fn get_mut(&mut self) -> Option<&mut Moving> {
        Some(self)
    }
    fn plain<const N: usize, const HOT: bool>(
        _model: &GeneralModel<N, HOT, Self>,
    ) -> Option<&GeneralModel<N, HOT>> {
        None
    }
    #[inline(always)]
    fn rk4_step<const N: usize>(
        &self,
        stored: Option<Vector3<f64>>,
        torques: super::lone_step::Torques,
        t: f64,
        h: f64,
        x: &mut [f64; N],
    ) -> bool {
        use super::lone_step::{rk4, LoneStage};
        let (true, Some(alone)) = (self.stepped, &self.alone) else {
            return false;
        };
        let beside = (stored, torques);
        match alone {
            AloneSolve::Spring(l) if N >= 10 => {
                rk4::<N, 10, _>(&LoneStage::new(l, beside), t, h, x)
            }
            AloneSolve::Hinge(l) if N >= 10 => {
                rk4::<N, 10, _>(&LoneStage::new(&**l, beside), t, h, x)
            }
            AloneSolve::Slosh(l) if N >= 14 => rk4::<N, 14, _>(&LoneStage::new(l, beside), t, h, x),
            _ => return false,
        }
        true
    }
}

impl Moving {
    /// Whether `parts` has one whose mass moves: the run then builds a model with [`Moving`].
    pub fn needed(parts: &[AnyPart]) -> bool {
        (parts.iter()).any(|p| p.info().traits.contains(Traits::MOVING_MASS))
    }
}

/// # Construction
impl<const N: usize, const HOT: bool, M: Movers> GeneralModel<N, HOT, M> {
    /// A body of inertia `inertia` with `parts` (in the run's axes and units), in the user's
    /// order.
    ///
    /// # Errors
    /// A state size `N` the parts do not fit (a bug in the caller).
    pub fn try_new(inertia: InertiaLaw, parts: Vec<AnyPart>) -> Result<Self> {
        let mut at = 3;
        let (mut stores, mut torques, mut states) = (Vec::new(), Vec::new(), Vec::new());
        let (mut dissipators, mut sampled, mut dims) = (Vec::new(), Vec::new(), Vec::new());
        let mut moving = Moving::default();
        let (mut stored, mut body_torque, mut world_torque) = (None, None, None);
        let mut torqued = false;
        let mut placed_all = Vec::new();
        for part in &parts {
            let info = part.info();
            let width = info.width();
            let placed = Placed {
                part: part.clone(),
                at,
                width,
            };
            if info.traits.contains(Traits::STORED_MOMENTUM) {
                match part.constant_momentum() {
                    Some(h) => stored = Some(stored.unwrap_or_else(Vector3::zeros) + h),
                    None => stores.push(placed.clone()),
                }
            }
            if info.external {
                torqued = true;
                match part.constant_torque() {
                    Some((v, Frame::Body)) => {
                        body_torque = Some(body_torque.unwrap_or_else(Vector3::zeros) + v)
                    }
                    Some((v, Frame::World)) => {
                        world_torque = Some(world_torque.unwrap_or_else(Vector3::zeros) + v)
                    }
                    None => torques.push(placed.clone()),
                }
            }
            if info.energy == EnergyRole::Dissipates {
                dissipators.push(placed.clone());
            }
            if part.sampling().is_some() {
                sampled.push(placed.clone());
            }
            for field in info.state {
                dims.extend(std::iter::repeat_n(field.dim, field.width));
            }
            if info.traits.contains(Traits::MOVING_MASS) {
                moving.parts.push(placed.clone());
            }
            if width > 0 {
                states.push(placed.clone());
            }
            placed_all.push(placed);
            at += width;
        }
        let width = at - 3;
        // the dissipated work just before `q`, at a place fixed by `N` (see [`Hot`])
        let balance = (!dissipators.is_empty()).then_some(N - 5);
        let used = at + usize::from(balance.is_some()) + 4;
        if used > N {
            return Err(Error::invalid(
                "parts",
                format!("must fit a state of {N} numbers (a bug: the run picks the size)"),
                used,
            ));
        }
        let hot = Hot::of(&placed_all);
        let lean = hot.columns.is_empty() && hot.rest.is_empty();
        if !(HOT || lean) {
            return Err(Error::invalid(
                "parts",
                "must all be folded for a lean model (a bug: the run picks the model)",
                parts.iter().map(AnyPart::name).collect::<Vec<_>>(),
            ));
        }
        let folded = body_torque.is_some() || world_torque.is_some();
        let kernel = match HOT {
            true => Kernel::of(&inertia, &parts, folded, stored),
            false => Kernel::None,
        };
        let still = |p: &&Placed| !p.part.info().traits.contains(Traits::MOVING_MASS);
        moving.fixed_states = states.iter().filter(still).cloned().collect();
        moving.fixed_dissipators = dissipators.iter().filter(still).cloned().collect();
        let Some(moving) = M::from_moving(moving) else {
            return Err(Error::invalid(
                "parts",
                "must not move mass in a model without moving parts (a bug: the run picks it)",
                parts.iter().map(AnyPart::name).collect::<Vec<_>>(),
            ));
        };
        let changing = matches!(inertia, InertiaLaw::Schedule(_));
        let kinds = kinds_of(changing, &parts);
        let works = kinds.models().any(|m| m.energy == EnergyRole::DoesWork);
        let time_only = TimeOnly::of(&parts);
        let mut model = Self {
            inertia,
            parts,
            stored,
            body_torque,
            world_torque,
            stores,
            torques,
            states,
            only_loses: !dissipators.is_empty() && !works,
            dissipators,
            sampled,
            hot,
            kernel,
            time_only,
            torqued,
            width,
            dims,
            balance,
            kinds,
            kinks: Vec::new(),
            knots: Vec::new(),
            clocks: Clocks::default(),
            horizon: 0.0,
            moving,
        };
        model.lay_out();
        Ok(model)
    }

    /// The same model carried by a hub of mass `mass` (the body's), for parts whose mass moves.
    ///
    /// # Errors
    /// Such parts and no mass; more rates than the joint solve holds.
    pub fn with_hub_mass(mut self, mass: Option<f64>) -> Result<Self> {
        // the one part with state, changing stored momentum (none: the mover's is 0) or not
        // constant torque is the mover, and nothing samples
        let beside = self.states.len() == 1
            && self.stores.len() == 1
            && self.torques.is_empty()
            && self.sampled.is_empty();
        let inertia = &self.inertia;
        let Some(moving) = self.moving.get_mut().filter(|m| !m.parts.is_empty()) else {
            return Ok(self);
        };
        let Some(mass) = mass else {
            return Err(Error::invalid(
                "body",
                "must have a mass (the system's `mass`) to carry parts whose mass moves in it",
                "no mass",
            ));
        };
        let movers = &moving.parts;
        let k: usize = movers.iter().map(|p| p.part.moving_rates()).sum();
        if k > MAX_RATES {
            return Err(Error::invalid(
                "parts",
                format!("must have at most {MAX_RATES} degrees of freedom"),
                k,
            ));
        }
        let carried: f64 = movers.iter().map(|p| p.part.moving_mass()).sum();
        let hub = Hub::try_new(inertia.tensor_at(0.0), mass, carried)?;
        let constant = matches!(inertia, InertiaLaw::Constant(_));
        // one mover on a hub of constant tensor: its closed form, whatever the other parts
        // (they change `H'` and the body's own momentum, not the solve)
        let alone = (constant && movers.len() == 1).then(|| movers[0].part.alone(&hub));
        moving.alone = alone.flatten();
        moving.stepped = moving.alone.is_some() && beside && !moving.has_fixed();
        moving.hub = Some(hub);
        Ok(self)
    }

    /// The same model for a run over `[0, t_end]` (its sample times are asked for as the run
    /// goes, see [`Clocks`]).
    pub fn until(mut self, t_end: f64) -> Self {
        self.horizon = t_end;
        self
    }

    /// The kinks (the parts' listed ones; the sample times come from the clocks) and the
    /// knots (with a deployment's).
    fn lay_out(&mut self) {
        let mut kinks: Vec<f64> = self.parts.iter().flat_map(AnyPart::kinks).collect();
        self.clocks = Clocks::of(self.sampled.iter().map(|p| p.part.sampling()));
        kinks.sort_by(f64::total_cmp);
        kinks.dedup();
        let mut knots = kinks.clone();
        if let InertiaLaw::Schedule(d) = &self.inertia {
            knots.extend_from_slice(d.times());
        }
        knots.sort_by(f64::total_cmp);
        knots.dedup();
        (self.kinks, self.knots) = (kinks, knots);
    }

    /// The state at `t0` from the body rates `omega0` and the attitude `q0`: each part's state
    /// from its start ([`super::Part::start`]), `H` the total momentum.
    pub fn state_from(&self, t0: f64, omega0: [f64; 3], q0: [f64; 4]) -> [f64; N] {
        let omega = Vector3::from(omega0);
        let mut x = [0.0; N];
        for p in &self.states {
            p.part.start(&omega, &mut x[p.at..p.at + p.width]);
        }
        let mut h = self.inertia.tensor_at(t0) * omega + self.stored.unwrap_or_default();
        for p in &self.stores {
            h += p.part.momentum(t0, p.of(&x));
        }
        let moving = self.moving.get();
        if let Some((moving, hub)) = moving.and_then(|m| Some((m, m.hub_at(&self.inertia, t0)?))) {
            // the parts' start rates into momenta, by the mass matrix at the start
            let mut carried = Vec::new();
            let mut v = [0.0; MAX_RATES];
            let mut row = 0;
            for m in &moving.parts {
                let c = m.part.carried(m.of(&x)).unwrap_or_default().0;
                let r = m.part.start_rates(m.of(&x));
                let n = c.rates.min(MAX_RATES - row);
                v[row..row + n].copy_from_slice(&r[..n]);
                row += c.rates;
                carried.push(c);
            }
            let (body, p) = MassMatrix::<MAX_RATES>::assemble(&hub, &carried).apply(&omega, &v);
            h += body - self.inertia.tensor_at(t0) * omega;
            let mut row = 0;
            for (m, c) in moving.parts.iter().zip(&carried) {
                m.part
                    .set_momenta(&mut x[m.at..m.at + m.width], &p[row..row + c.rates]);
                row += c.rates;
            }
        }
        x[..3].copy_from_slice(h.as_slice());
        x[N - 4..].copy_from_slice(&q0);
        x
    }

    /// The inertia law.
    pub fn inertia(&self) -> &InertiaLaw {
        &self.inertia
    }

    /// The parts, in the user's order.
    pub fn parts(&self) -> &[AnyPart] {
        &self.parts
    }

    /// Whether every part is folded once before the run (constant wheels and torques, or no
    /// part): the model then runs as `GeneralModel<N, false>`, whose right-hand side holds no
    /// part's code at all (the compiler lays out a smaller loop).
    pub fn is_lean(parts: &[AnyPart]) -> bool {
        parts.iter().all(|p| {
            let info = p.info();
            let stores =
                info.traits.contains(Traits::STORED_MOMENTUM) && p.constant_momentum().is_none();
            let torques = info.external && p.constant_torque().is_none();
            info.width() == 0 && !stores && !torques
        })
    }
}

/// # Evaluation
impl<const N: usize, const HOT: bool, M: Movers> GeneralModel<N, HOT, M> {
    /// What the parts see at `(t, x)` with body rates `omega` (each part making what it
    /// reads of `t` itself).
    #[inline(always)]
    fn ctx(&self, t: f64, x: &[f64; N], omega: Vector3<f64>) -> Ctx<'_> {
        Ctx {
            t,
            q: attitude(x),
            omega,
            inertia: &self.inertia,
            moving: None,
            timed: Timed::default(),
        }
    }

    /// [`GeneralModel::ctx`] at the stage time `at` (made by [`OdeSystem::at_time`]): the
    /// parts read what the model made of `at.t`.
    #[inline(always)]
    fn ctx_at(&self, at: &StageTime, x: &[f64; N], omega: Vector3<f64>) -> Ctx<'_> {
        Ctx {
            timed: match HOT {
                true => self.time_only.timed(at),
                false => Timed::default(),
            },
            ..self.ctx(at.t, x, omega)
        }
    }

    /// The body's own angular momentum `H − Σ h_k` at `t`.
    #[inline(always)]
    fn body_momentum(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        let mut h = Vector3::new(x[0], x[1], x[2]);
        if let Some(c) = self.stored {
            h -= c;
        }
        if HOT && self.hot.stores {
            h = self.hot.columns.less_momentum(t, x, h);
        }
        if HOT && !self.hot.rest.is_empty() {
            h -= self.rest_momenta(t, *x);
        }
        h
    }

    /// The momenta the parts with state after the first store, evaluated out of line on a
    /// copy of the state (see [`Hot`]).
    #[inline(never)]
    fn rest_momenta(&self, t: f64, x: [f64; N]) -> Vector3<f64> {
        (self.hot.rest.iter()).fold(Vector3::zeros(), |h, p| h + p.part.momentum(t, p.of(&x)))
    }

    /// The torques of the parts with state after the first (as above).
    #[inline(never)]
    fn rest_torques(&self, t: f64, x: [f64; N], omega: Vector3<f64>) -> Vector3<f64> {
        let c = self.ctx(t, &x, omega);
        (self.hot.rest.iter()).fold(Vector3::zeros(), |tau, p| tau + p.part.torque(&c, p.of(&x)))
    }

    /// The rates, times `s`, of the parts with state after the first, in a state's places,
    /// and the power they dissipate (as above).
    #[inline(never)]
    fn rest_rates(&self, t: f64, x: [f64; N], omega: Vector3<f64>, s: f64) -> ([f64; N], f64) {
        let c = self.ctx(t, &x, omega);
        let mut dx = [0.0; N];
        let mut power = 0.0;
        for p in &self.hot.rest {
            let d = &mut dx[p.at..p.at + p.width];
            p.part.rates(&c, p.of(&x), d);
            d.iter_mut().for_each(|v| *v *= s);
            power += p.part.dissipation(&c, p.of(&x));
        }
        (dx, power)
    }

    /// The external torque in body axes at `(at.t, x)`, the body turning at `omega`.
    #[inline(always)]
    fn torque_at(&self, at: &StageTime, x: &[f64; N], omega: Vector3<f64>) -> Vector3<f64> {
        let t = at.t;
        let mut tau = self.body_torque.unwrap_or_default();
        if let Some(v) = self.world_torque {
            tau += world_to_body(&attitude(x), &v);
        }
        if HOT && self.hot.torques {
            tau = self
                .hot
                .columns
                .plus_torque(&self.ctx_at(at, x, omega), x, tau);
        }
        if HOT && !self.hot.rest.is_empty() {
            tau += self.rest_torques(t, *x, omega);
        }
        tau
    }

    /// The external torque in body axes at `(t, x)` (the splittings' kicks).
    #[inline(always)]
    pub(crate) fn torque(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        self.torque_at(&self.at_time(t), x, self.omega_body(t, x))
    }

    /// Whether the system has parts with state, or parts storing momentum.
    pub fn has_parts_inside(&self) -> bool {
        self.kinds.traits().contains(Traits::STORED_MOMENTUM) || self.width > 0
    }
}

/// What the joint solve gives at one state: the motion, what each moving part carries, and
/// their momenta.
struct Joint {
    motion: multibody::Motion<MAX_RATES>,
    carried: [Carried; MAX_RATES],
    momenta: [f64; MAX_RATES],
}

/// # The joint solve (see [`super::multibody`]), whatever the state's size
impl Moving {
    /// The hub at `t` (a deployment's tensor then).
    #[inline(always)]
    fn hub_at(&self, inertia: &InertiaLaw, t: f64) -> Option<Hub> {
        let hub = self.hub?;
        Some(match inertia {
            InertiaLaw::Constant(_) => hub,
            InertiaLaw::Schedule(d) => hub.with_inertia(d.inertia_at(t)),
        })
    }

    /// The joint solve at `(t, x)`, `l` the body's own momentum `H − Σ h_k` there.
    #[inline(never)]
    fn joint(&self, inertia: &InertiaLaw, t: f64, x: &[f64], l: &Vector3<f64>) -> Joint {
        self.joint_inline(inertia, t, x, l)
    }

    /// [`Moving::joint`], inline.
    #[inline(always)]
    fn joint_inline(&self, inertia: &InertiaLaw, t: f64, x: &[f64], l: &Vector3<f64>) -> Joint {
        let mut carried = [Carried::default(); MAX_RATES];
        let mut p = [0.0; MAX_RATES];
        let mut row = 0;
        for (k, m) in self.parts.iter().enumerate().take(MAX_RATES) {
            let (c, mo) = m.part.carried(m.of(x)).unwrap_or_default();
            let n = c.rates.min(MAX_RATES - row);
            p[row..row + n].copy_from_slice(&mo[..n]);
            row += c.rates;
            carried[k] = c;
        }
        let n = self.parts.len().min(MAX_RATES);
        let motion = match self.hub_at(inertia, t) {
            Some(hub) => multibody::motion(&hub, &carried[..n], l, &p),
            None => multibody::Motion {
                omega: inertia.omega_from(t, l),
                rates: [0.0; MAX_RATES],
                drift: Vector3::zeros(),
            },
        };
        Joint {
            motion,
            carried,
            momenta: p,
        }
    }

    /// The joint solve at `(t, x)` (`q` the attitude there, `l` the body's own momentum) and
    /// with it `s ×` the rates of every part with state into `dx` (a state's places): `ω` and
    /// the power the parts dissipate. One call out of line, so that the solve's results (a
    /// few kB, sized for the most parts) stay where they were made, never copied.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &self,
        inertia: &InertiaLaw,
        t: f64,
        q: nalgebra::Quaternion<f64>,
        x: &[f64],
        l: &Vector3<f64>,
        s: f64,
        dx: &mut [f64],
    ) -> (Vector3<f64>, f64) {
        let j = self.joint_inline(inertia, t, x, l);
        let omega = j.motion.omega;
        let c = Ctx {
            t,
            q,
            omega,
            inertia,
            moving: None,
            timed: Timed::default(),
        };
        (omega, self.rates(&c, x, &j, s, dx))
    }

    /// What the joint solve gives mover `k`, whose rates start at `row`.
    #[inline(always)]
    fn moved(j: &Joint, k: usize, row: usize) -> Moved<'_> {
        let c = &j.carried[k];
        let (velocity, spin) = j.motion.element(c, row);
        let mut rates = [0.0; PART_RATES];
        for (i, r) in rates.iter_mut().enumerate().take(c.rates) {
            *r = j.motion.rates[row + i];
        }
        Moved {
            rates,
            velocity,
            spin,
            carried: c,
        }
    }

    /// `s ×` the rates of every part with state into `dx` (a state's places), given what
    /// the parts see `c` and the joint solve `j` at `x`; the power they dissipate.
    #[inline(always)]
    fn rates(&self, c: &Ctx<'_>, x: &[f64], j: &Joint, s: f64, dx: &mut [f64]) -> f64 {
        let mut power = self.fixed_rates(c, x, s, dx);
        let mut row = 0;
        for (k, p) in self.parts.iter().enumerate().take(MAX_RATES) {
            let moved = Ctx {
                moving: Some(Self::moved(j, k, row)),
                ..*c
            };
            let d = &mut dx[p.at..p.at + p.width];
            p.part.rates(&moved, p.of(x), d);
            d.iter_mut().for_each(|v| *v *= s);
            power += p.part.dissipation(&moved, p.of(x));
            row += j.carried[k].rates;
        }
        power
    }

    /// `s ×` the rates of the parts with state whose mass does not move into `dx`, given what
    /// they see `c` at `x`; the power they and the other fixed parts dissipate.
    #[inline(never)]
    fn fixed_rates(&self, c: &Ctx<'_>, x: &[f64], s: f64, dx: &mut [f64]) -> f64 {
        for p in &self.fixed_states {
            let d = &mut dx[p.at..p.at + p.width];
            p.part.rates(c, p.of(x), d);
            d.iter_mut().for_each(|v| *v *= s);
        }
        (self.fixed_dissipators.iter()).fold(0.0, |e, p| e + p.part.dissipation(c, p.of(x)))
    }

    /// Whether parts whose mass does not move have state or dissipate.
    #[inline(always)]
    fn has_fixed(&self) -> bool {
        !(self.fixed_states.is_empty() && self.fixed_dissipators.is_empty())
    }

    /// The kinetic energy `½ (ω · l + v · p)` at `(t, x)`, `l` the body's own momentum.
    fn kinetic(&self, inertia: &InertiaLaw, t: f64, x: &[f64], l: &Vector3<f64>) -> f64 {
        let j = self.joint(inertia, t, x, l);
        let k = j.carried.iter().map(|c| c.rates).sum();
        multibody::kinetic_energy(&j.motion.omega, &j.motion.rates, l, &j.momenta, k)
    }
}

/// # Parts whose mass moves (see [`Moving`])
impl<const N: usize, const HOT: bool, M: Movers> GeneralModel<N, HOT, M> {
    /// `s · x'` with the joint solve: out of line, so that a method's stages each call it
    /// rather than each hold a copy, and on a copy of the state, so that the caller's stays
    /// in registers (see [`Hot`]).
    #[inline(never)]
    fn increment_moving(&self, moving: &Moving, at: StageTime, x: [f64; N], s: f64) -> [f64; N] {
        let (x, t) = (&x, at.t);
        let mut dx = [0.0; N];
        let l = self.body_momentum(t, x);
        let (omega, power) = moving.solve(&self.inertia, t, attitude(x), x, &l, s, &mut dx);
        let h = Vector3::new(x[0], x[1], x[2]);
        let mut dh = h.cross(&omega);
        if self.torqued {
            dh += self.torque_at(&at, x, omega);
        }
        dx[..3].copy_from_slice((dh * s).as_slice());
        if let Some(k) = self.balance {
            dx[k] = power * s;
        }
        let dq = quaternion_increment([x[N - 4], x[N - 3], x[N - 2], x[N - 1]], omega, s);
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }

    /// `s · x'` of the one part whose mass moves, alone on its hub, by its closed form (out
    /// of line, on a copy of the state, as above): the solve takes the body's own momentum,
    /// the other parts' torques and rates are added as without moving mass.
    #[inline(never)]
    fn increment_alone(
        &self,
        moving: &Moving,
        alone: &AloneSolve,
        at: &StageTime,
        x: [f64; N],
        s: f64,
    ) -> [f64; N] {
        let (x, t) = (&x, at.t);
        let h = Vector3::new(x[0], x[1], x[2]);
        let p = &moving.parts[0];
        let mut dx = [0.0; N];
        let (omega, mut power) = alone.increment(
            &self.body_momentum(t, x),
            p.of(x),
            s,
            &mut dx[p.at..p.at + p.width],
        );
        if moving.has_fixed() {
            power += moving.fixed_rates(&self.ctx_at(at, x, omega), x, s, &mut dx);
        }
        let mut dh = h.cross(&omega);
        if self.torqued {
            dh += self.torque_at(at, x, omega);
        }
        dx[..3].copy_from_slice((dh * s).as_slice());
        if let Some(k) = self.balance {
            dx[k] = power * s;
        }
        let dq = quaternion_increment([x[N - 4], x[N - 3], x[N - 2], x[N - 1]], omega, s);
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }
}

/// # Body rates with parts whose mass moves
impl<const N: usize, const HOT: bool, M: Movers> GeneralModel<N, HOT, M> {
    /// `ω` by the lone part's closed form or the joint solve (out of line, on a copy of the
    /// state, as [`GeneralModel::increment_moving`]).
    #[inline(never)]
    fn omega_moving(&self, moving: &Moving, t: f64, x: [f64; N]) -> Vector3<f64> {
        match &moving.alone {
            Some(alone) => alone.omega(&self.body_momentum(t, &x), moving.parts[0].of(&x)),
            None => {
                (moving.joint(&self.inertia, t, &x, &self.body_momentum(t, &x)))
                    .motion
                    .omega
            }
        }
    }
}

impl<const N: usize, const HOT: bool, M: Movers> OdeSystem<N> for GeneralModel<N, HOT, M> {
    #[inline(always)]
    fn increment(&self, t: f64, x: &[f64; N], s: f64) -> [f64; N] {
        self.increment_at(&self.at_time(t), x, s)
    }

    /// A kernel's system when the model has one ([`Kernel`]), else the model itself: a step
    /// then runs the kernel's code alone, not a test of what the model is at every stage
    /// (AMD EPYC, CPU time an RK4 step: gravity gradient 68.4 -> 65.8 ns, damper 52.3 -> 47.3).
    #[inline(always)]
    fn specialised<V: Visit<N>>(&self, v: V) -> V::Out {
        if HOT && self.moving.get().is_none() {
            match self.kernel {
                Kernel::Orbit(kernel) => return v.visit(&OrbitRun::<N> { kernel }),
                Kernel::Damper(kernel) if N >= 11 => return v.visit(&DamperRun::<N> { kernel }),
                _ => {}
            }
        }
        v.visit(self)
    }

    /// The orbit's phase and the magnetic field in world axes at `t` (see [`TimeOnly`]).
    #[inline(always)]
    fn at_time(&self, t: f64) -> StageTime {
        match HOT {
            true => self.time_only.at(t),
            false => StageTime::bare(t),
        }
    }

    /// A lone moving part's whole step at once (see [`super::lone_step`]).
    #[inline(always)]
    fn rk4_step(&self, t: f64, h: f64, x: &mut [f64; N]) -> bool {
        let torques = (self.torqued).then_some((self.body_torque, self.world_torque));
        HOT && self.moving.rk4_step(self.stored, torques, t, h, x)
    }

    #[inline(always)]
    fn increment_at(&self, at: &StageTime, x: &[f64; N], s: f64) -> [f64; N] {
        let t = at.t;
        if let (true, Some(moving)) = (HOT, self.moving.get()) {
            return match &moving.alone {
                Some(alone) => self.increment_alone(moving, alone, at, *x, s),
                None => self.increment_moving(moving, *at, *x, s),
            };
        }
        let q = [x[N - 4], x[N - 3], x[N - 2], x[N - 1]];
        match self.kernel {
            Kernel::Orbit(k) if HOT => {
                let (dh, dq) = k.increment_at((at.of_t[0], at.of_t[1]), [x[0], x[1], x[2]], q, s);
                let mut dx = [0.0; N];
                dx[..3].copy_from_slice(&dh);
                dx[N - 4..].copy_from_slice(&dq);
                return dx;
            }
            Kernel::Damper(k) if HOT && N >= 11 => {
                let (dh, ds, dw, dq) = k.increment([x[0], x[1], x[2]], [x[3], x[4], x[5]], q, s);
                let mut dx = [0.0; N];
                dx[..3].copy_from_slice(&dh);
                dx[3..6].copy_from_slice(&ds);
                dx[N - 5] = dw;
                dx[N - 4..].copy_from_slice(&dq);
                return dx;
            }
            _ => {}
        }
        let h = Vector3::new(x[0], x[1], x[2]);
        let omega = self.omega_body(t, x);
        let mut dh = h.cross(&omega);
        if self.torqued {
            dh += self.torque_at(at, x, omega);
        }
        let dh = dh * s;
        let mut dx = [0.0; N];
        dx[..3].copy_from_slice(dh.as_slice());
        if HOT && self.hot.states {
            let mut power = self
                .hot
                .columns
                .rates(&self.ctx_at(at, x, omega), x, s, &mut dx);
            if !self.hot.rest.is_empty() {
                let (rates, more) = self.rest_rates(t, *x, omega, s);
                for k in 3..N - 4 {
                    dx[k] += rates[k];
                }
                power += more;
            }
            if self.balance.is_some() {
                dx[N - 5] = power * s;
            }
        }
        let dq = quaternion_increment([x[N - 4], x[N - 3], x[N - 2], x[N - 1]], omega, s);
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }

    fn is_sampled(&self) -> bool {
        !self.clocks.is_empty()
    }

    /// Each part sampled at `t` updates the state (see [`super::Part::sample`]). Out of line:
    /// every build of the drivers (AVX-512 or not) calls this one, so the laws' C library
    /// calls give the same bits in each.
    #[inline(never)]
    fn sample(&self, t: f64, x: &mut [f64; N]) {
        for k in self.clocks.at(t) {
            // each part sees the state as the parts before it left it
            let c = self.ctx(t, x, self.omega_body(t, x));
            let p = &self.sampled[k];
            p.part.sample(&c, p.at, x);
        }
    }
}

impl<const N: usize, const HOT: bool, M: Movers> Model<N> for GeneralModel<N, HOT, M> {
    /// `|H|` and `H` in space at the start.
    type Kept = MomentumProjection;

    fn conserved(&self) -> Conserved {
        self.kinds.conserved()
    }

    fn kinds(&self) -> Kinds {
        self.kinds
    }

    /// `ω = I(t)⁻¹ (H − Σ h_k)`: the one place a state's body rates are made.
    #[inline(always)]
    fn omega_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        match self.moving.get() {
            Some(moving) if HOT => self.omega_moving(moving, t, *x),
            _ => self.inertia.omega_from(t, &self.body_momentum(t, x)),
        }
    }

    #[inline(always)]
    fn momentum_body(&self, _t: f64, x: &[f64; N]) -> Vector3<f64> {
        Vector3::new(x[0], x[1], x[2])
    }

    /// `H' = H × ω + τ_b`.
    #[inline(always)]
    fn momentum_rate(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        let omega = self.omega_body(t, x);
        let h = self.momentum_body(t, x).cross(&omega);
        match self.torqued {
            false => h,
            true => h + self.torque_at(&self.at_time(t), x, omega),
        }
    }

    /// The integral a part brings (the Jacobi integral of an orbit, see
    /// [`super::GravityGradient`]).
    fn jacobi(&self, t: f64, x: &[f64; N]) -> Option<f64> {
        let (q, tensor) = (attitude(x), self.inertia.tensor_at(t));
        let (energy, h) = (self.energy(t, x), self.momentum_body(t, x));
        self.parts
            .iter()
            .find_map(|p| p.integral(t, &q, &tensor, energy, &h))
    }

    /// `½ lᵀ I⁻¹ l` of the body's own momentum `l`, plus the parts' own energies.
    fn energy(&self, t: f64, x: &[f64; N]) -> f64 {
        let l = self.body_momentum(t, x);
        let body = match self.moving.get() {
            None => 0.5 * l.dot(&self.inertia.omega_from(t, &l)),
            Some(m) => match &m.alone {
                Some(alone) => alone.kinetic(&l, m.parts[0].of(x)),
                None => m.kinetic(&self.inertia, t, x, &l),
            },
        };
        (self.states.iter()).fold(body, |e, p| e + p.part.energy(t, p.of(x)))
    }

    /// The energy plus the dissipated work, for a system whose parts dissipate.
    fn balance(&self, t: f64, x: &[f64; N]) -> Option<f64> {
        self.balance.map(|k| self.energy(t, x) + x[k])
    }

    /// `(|H| + Σ |h_k|) / λ_min` (`|ω| = |I⁻¹ (H − Σ h_k)|`); `√(2E / λ_min)` when a part
    /// dissipates (its energy `E ≥ ½ ωᵀ I ω` never rises, its parts' rates turn at the
    /// body's; their own decay is the model's [`Model::stiffness`]). With a part bringing an
    /// integral (the gravity gradient's Jacobi integral), the larger of that and its bound. A
    /// constant torque spins the body up without bound: the bound is the start's, and a long
    /// run under one wants an adaptive method or a `dt` of its own.
    fn rate_bound(&self, x0: &[f64; N]) -> f64 {
        let least = self.inertia.least();
        let stored = self.stored.map_or(0.0, |h| h.norm())
            + (self.stores.iter())
                .map(|p| p.part.largest_momentum())
                .sum::<f64>();
        let free = match self.dissipators.is_empty() {
            false => (2.0 * self.energy(0.0, x0) / least).sqrt(),
            true => (self.momentum_body(0.0, x0).norm() + stored) / least,
        };
        let bound = self.jacobi(0.0, x0).and_then(|j| {
            let largest = self.inertia.tensor_at(0.0).symmetric_eigenvalues().max();
            (self.parts.iter()).find_map(|p| p.rate_bound(least, largest, j, stored))
        });
        let free = free.max(bound.unwrap_or(0.0));
        let movers = self.moving.get().map_or(&[][..], |m| &m.parts[..]);
        movers
            .iter()
            .fold(free, |m, p| m.max(p.part.frequency(free)))
    }

    /// The size of `H` over the run (and of rate-like parts' state): the absolute tolerance's
    /// unit.
    fn state_size(&self, x0: &[f64; N]) -> f64 {
        let parts = x0[3..3 + self.width].iter().zip(&self.dims);
        (parts.filter(|(_, d)| d.rate == 1)).fold(
            x0[..3].iter().fold(0.0_f64, |m, v| m.max(v.abs())),
            |m, (v, _)| m.max(v.abs()),
        )
    }

    fn stiffness(&self) -> f64 {
        let least = self.inertia.least();
        self.parts
            .iter()
            .fold(0.0, |m, p| m.max(p.stiffness(least)))
    }

    /// A part dissipates and nothing (no part, no deployment) does work.
    fn energy_never_grows(&self) -> bool {
        self.only_loses
    }

    fn intermediate_axis(&self, t: f64) -> MidAxis {
        match &self.inertia {
            InertiaLaw::Constant(c) => c.mid,
            InertiaLaw::Schedule(d) => d.intermediate_axis(t),
        }
    }

    fn knots(&self) -> &[f64] {
        &self.knots
    }

    fn kinks(&self) -> &[f64] {
        &self.kinks
    }

    #[inline]
    fn next_kink(&self, t: f64) -> f64 {
        crate::ode::first_from(&self.kinks, t).min(self.clocks.next_from(t))
    }

    #[inline]
    fn next_knot(&self, t: f64) -> f64 {
        crate::ode::first_from(&self.knots, t).min(self.clocks.next_from(t))
    }

    fn parts_width(&self) -> usize {
        self.width
    }

    fn parts_dims(&self) -> &[Dim] {
        &self.dims
    }

    fn rate_power(&self, k: usize) -> i32 {
        match k {
            0..=2 => 1,
            k if k < 3 + self.width => self.dims[k - 3].rate,
            k if Some(k) == self.balance => Dim::TORQUE.rate,
            _ => 0,
        }
    }

    fn dimension(&self) -> usize {
        7 + self.width + usize::from(self.balance.is_some())
    }

    /// The state's rates and momenta (and the parts' state, by its dimension) over `2^e`.
    fn state_in_units(&self, x: &[f64; N], scale: RateScale) -> [f64; N] {
        let mut out = *x;
        let by = |v: f64, rate: i32| (0..rate).fold(v, |v, _| scale.rate_to_unit(v));
        for v in &mut out[..3] {
            *v = by(*v, 1);
        }
        for (v, d) in out[3..3 + self.width].iter_mut().zip(&self.dims) {
            *v = by(*v, d.rate);
        }
        if let Some(k) = self.balance {
            out[k] = by(out[k], Dim::TORQUE.rate);
        }
        out
    }

    fn kept(&self, t0: f64, x0: &[f64; N]) -> MomentumProjection {
        MomentumProjection::new(self.momentum_body(t0, x0), &attitude(x0))
    }

    /// `H` (and the parts' rates with it) scaled back to `|H₀|`, `q` normalised and turned so
    /// that `H` in space has its initial direction.
    #[inline]
    fn project(&self, kept: &MomentumProjection, t: f64, x: &mut [f64; N]) {
        let (factor, q) = kept.restore(&self.momentum_body(t, x), &attitude(x));
        for v in &mut x[..3] {
            *v *= factor;
        }
        for (v, d) in x[3..3 + self.width].iter_mut().zip(&self.dims) {
            if d.rate == 1 {
                *v *= factor;
            }
        }
        set_attitude(x, &q);
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        let inertia = match &self.inertia {
            InertiaLaw::Constant(c) => InertiaLaw::Constant(*c),
            InertiaLaw::Schedule(d) => InertiaLaw::Schedule(d.in_units(scale)?),
        };
        let parts = (self.parts.iter())
            .map(|p| p.in_units(scale))
            .collect::<Result<Vec<_>>>()?;
        // the kinks and sample times follow the laws' times, rebuilt in the run's units
        Ok(Self::try_new(inertia, parts)?
            .with_hub_mass(self.moving.get().and_then(|m| m.hub).map(|h| h.mass()))?
            .until(scale.time_to_unit(self.horizon)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{ConstantTorque, Damper, GravityGradient, Wheel};
    use approx::assert_relative_eq;

    fn tilted() -> Deployment {
        let a = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let b = Matrix3::new(5.0, 0.4, -0.2, 0.4, 3.5, 0.0, -0.2, 0.0, 2.5);
        Deployment::try_new(vec![1.0, 3.0], vec![a, b]).unwrap()
    }

    fn constant() -> InertiaLaw {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap())
    }

    fn damper() -> AnyPart {
        Damper::try_new(0.2, 0.05)
            .unwrap()
            .starting_at([0.2, 0.1, 0.9])
            .unwrap()
            .into()
    }

    /// The state advanced by `±h` along the right-hand side (a central difference's ends).
    fn along<const N: usize>(m: &GeneralModel<N>, t: f64, x: &[f64; N], h: f64) -> [f64; N] {
        let dx = m.rhs(t, x);
        std::array::from_fn(|k| x[k] + h * dx[k])
    }

    #[test]
    fn a_deployments_energy_changes_at_minus_half_omega_idot_omega() {
        let m = GeneralModel::<7>::try_new(InertiaLaw::Schedule(tilted()), vec![]).unwrap();
        let x = m.state_from(2.2, [0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
        let h = 1e-6;
        let numeric = (m.energy(2.2 + h, &along(&m, 2.2, &x, h))
            - m.energy(2.2 - h, &along(&m, 2.2, &x, -h)))
            / (2.0 * h);
        let omega = m.omega_body(2.2, &x);
        let idot = tilted().inertia_and_rate_at(2.2).1;
        assert_relative_eq!(
            numeric,
            -0.5 * omega.dot(&(idot * omega)),
            max_relative = 1e-7
        );
        assert!(!m.energy_never_grows());
    }

    #[test]
    fn a_dampers_energy_falls_at_c_times_the_slip_squared_and_the_balance_holds() {
        let m = GeneralModel::<11>::try_new(constant(), vec![damper()]).unwrap();
        assert_eq!(m.dimension(), 11);
        let x = m.state_from(0.0, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]);
        let h = 1e-6;
        let rate = |f: &dyn Fn(&[f64; 11]) -> f64| {
            (f(&along(&m, 0.0, &x, h)) - f(&along(&m, 0.0, &x, -h))) / (2.0 * h)
        };
        let slip = Vector3::new(0.2, 0.1, 0.9) - Vector3::new(0.3, -0.7, 1.1);
        assert_relative_eq!(
            rate(&|x| m.energy(0.0, x)),
            -0.05 * slip.norm_squared(),
            max_relative = 1e-7
        );
        // E + W stationary, the dissipated work rising by the loss
        assert!(rate(&|x| m.balance(0.0, x).unwrap()).abs() < 1e-9);
        assert_eq!(
            m.conserved().names(),
            ["momentum", "momentum_world", "q_norm", "energy_balance"]
        );
        assert!(m.energy_never_grows());
        let omega = m.omega_body(0.0, &x);
        assert!((omega - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-15);
    }

    #[test]
    fn a_state_too_small_for_the_parts_is_refused() {
        assert!(GeneralModel::<10>::try_new(constant(), vec![damper()]).is_err());
        // a larger one is padded: the padding stays zero, the rates the same
        let m = GeneralModel::<13>::try_new(constant(), vec![damper()]).unwrap();
        let n = GeneralModel::<11>::try_new(constant(), vec![damper()]).unwrap();
        let (x, y) = (
            m.state_from(0.0, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]),
            n.state_from(0.0, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]),
        );
        let (dx, dy) = (m.rhs(0.0, &x), n.rhs(0.0, &y));
        // [H, σ, padding, W, q] against [H, σ, W, q]
        assert_eq!(dx[..6], dy[..6]);
        assert_eq!(dx[6..8], [0.0, 0.0]);
        assert_eq!(dx[8..], dy[6..]);
        assert_eq!(m.dimension(), 11);
    }

    fn gravity(n: f64) -> AnyPart {
        GravityGradient::try_new(n).unwrap().into()
    }

    fn wheel() -> AnyPart {
        Wheel::try_new([0.3, -0.5, 0.7], 0.911).unwrap().into()
    }

    #[test]
    fn a_kernels_system_is_the_models_right_hand_side() {
        let diagonal = || {
            let i = Matrix3::from_diagonal(&Vector3::new(2.0, 3.0, 4.5));
            InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap())
        };
        let (n, h) = (0.37, 0.1);
        let model = GeneralModel::<7>::try_new(diagonal(), vec![gravity(n)]).unwrap();
        let Kernel::Orbit(kernel) = model.kernel else {
            panic!("a body in orbit alone takes the orbit's kernel")
        };
        let run = OrbitRun::<7> { kernel };
        let x = [0.3, -0.7, 1.1, 0.6 * 1.3, -0.2 * 1.3, 0.7 * 1.3, 0.3 * 1.3];
        for t in [0.0, 0.7, 13.1, -4.2, 250.0] {
            // the same numbers at the same stage time
            let at = model.at_time(t);
            assert_eq!(run.at_time(t), at);
            assert_eq!(
                run.increment_at(&at, &x, 0.3),
                model.increment_at(&at, &x, 0.3)
            );
            // a step's stage times, the later two turned from the first: the plain formula's
            // phase to the rounding of the angle n t, which it carries too
            let stages = run.stage_times(t, h);
            for (a, tk) in stages.iter().zip([t, t + 0.5 * h, t + h]) {
                assert_eq!(a.t, tk);
                let tol = 1e-15 + 4.0 * f64::EPSILON * (n * tk).abs();
                assert!((a.of_t[0] - (n * tk).sin()).abs() < tol, "{t}");
                assert!((a.of_t[1] - (n * tk).cos()).abs() < tol, "{t}");
            }
        }
        // the damper's, bit for bit (its stage times make nothing)
        let model = GeneralModel::<11>::try_new(diagonal(), vec![damper()]).unwrap();
        let Kernel::Damper(kernel) = model.kernel else {
            panic!("a damped body alone takes the damper's kernel")
        };
        let run = DamperRun::<11> { kernel };
        let x = [0.3, -0.7, 1.1, 0.2, 0.1, 0.9, 0.0, 0.6, -0.2, 0.7, 0.3];
        for s in [0.05, 0.1, 1.0 / 60.0] {
            assert_eq!(run.increment(1.0, &x, s), model.increment(1.0, &x, s));
        }
    }

    /// `dJ/dt` along the right-hand side by a central difference.
    fn jacobi_rate(m: &GeneralModel<7>, t: f64, x: &[f64; 7]) -> f64 {
        let h = 1e-6;
        let j = |s: f64| m.jacobi(t + s, &along(m, t, x, s)).unwrap();
        (j(h) - j(-h)) / (2.0 * h)
    }

    #[test]
    fn the_jacobi_integral_is_stationary_in_the_gravity_gradient_with_wheels() {
        let m = GeneralModel::<7>::try_new(constant(), vec![wheel(), gravity(0.8)]).unwrap();
        assert_eq!(m.conserved().names(), ["q_norm", "jacobi"]);
        let q = [0.6, -0.2, 0.7, 0.3];
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        let x = m.state_from(1.3, [0.3, -0.7, 1.1], q.map(|v| v / n));
        let j = m.jacobi(1.3, &x).unwrap();
        assert!(jacobi_rate(&m, 1.3, &x).abs() < 1e-8 * j.abs().max(1.0));
        // a constant torque breaks it, and the model no longer declares it
        let push = ConstantTorque::try_new([0.0, 0.2, 0.1], Frame::Body).unwrap();
        let pushed = GeneralModel::<7>::try_new(constant(), vec![gravity(0.8), push.into()]);
        let pushed = pushed.unwrap();
        assert!(jacobi_rate(&pushed, 1.3, &x).abs() > 1e-3);
        assert_eq!(pushed.conserved().names(), ["q_norm"]);
    }

    #[test]
    fn wheels_keep_the_momentum_in_space_and_the_bodys_energy() {
        let m = GeneralModel::<7>::try_new(constant(), vec![wheel()]).unwrap();
        let x = m.state_from(0.0, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]);
        let h = 1e-6;
        let e = |s: f64| m.energy(s, &along(&m, 0.0, &x, s));
        assert!(((e(h) - e(-h)) / (2.0 * h)).abs() < 1e-9);
        // H' = H × ω: |H| stationary
        let dh = m.momentum_rate(0.0, &x);
        assert!(dh.dot(&m.momentum_body(0.0, &x)).abs() < 1e-14);
        assert!((m.omega_body(0.0, &x) - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-15);
    }

    #[test]
    fn a_damper_with_anything_that_does_work_is_not_watched_for_growth() {
        for other in [
            gravity(0.3),
            ConstantTorque::try_new([0.0, 0.0, 0.1], Frame::World)
                .unwrap()
                .into(),
            crate::dynamics::WheelSchedule::try_new(
                [0.0, 0.0, 1.0],
                vec![0.0, 1.0],
                vec![1.0, 0.0],
            )
            .unwrap()
            .into(),
        ] {
            let m = GeneralModel::<11>::try_new(constant(), vec![damper(), other]).unwrap();
            assert!(!m.energy_never_grows(), "{:?}", m.kinds().names());
            assert!(!m.conserved().contains(Conserved::ENERGY_BALANCE));
        }
        let m = GeneralModel::<11>::try_new(constant(), vec![damper(), wheel()]).unwrap();
        assert!(m.energy_never_grows());
        let m = GeneralModel::<11>::try_new(InertiaLaw::Schedule(tilted()), vec![damper()]);
        assert!(!m.unwrap().energy_never_grows());
    }

    /// One part whose mass moves among parts whose mass does not (a damper with state before
    /// it, a changing wheel, torques in both frames): its closed form gives the right-hand
    /// side, `ω` and the energy the joint solve gives.
    #[test]
    fn a_lone_mover_among_other_parts_takes_its_closed_form_and_agrees_with_the_joint_solve() {
        use crate::dynamics::multibody::fixtures::{panel, spring, tank};
        use crate::dynamics::WheelSchedule;
        let movers: [AnyPart; 3] = [spring().into(), panel().into(), tank().into()];
        let others: Vec<AnyPart> = vec![
            ConstantTorque::try_new([0.02, -0.01, 0.03], Frame::Body)
                .unwrap()
                .into(),
            ConstantTorque::try_new([0.0, 0.05, 0.1], Frame::World)
                .unwrap()
                .into(),
            WheelSchedule::try_new([0.0, 0.6, 0.8], vec![0.0, 2.0], vec![0.4, 1.2])
                .unwrap()
                .into(),
        ];
        for (first, mover) in [(true, 0), (false, 0), (false, 1), (false, 2)] {
            let mut parts = match first {
                true => vec![damper()],
                false => vec![],
            };
            parts.push(movers[mover].clone());
            parts.extend(others.iter().cloned());
            let m = GeneralModel::<24, true, Moving>::try_new(constant(), parts)
                .unwrap()
                .with_hub_mass(Some(5.0))
                .unwrap();
            assert!(m.moving.get().unwrap().alone.is_some());
            let mut joint = m.clone();
            joint.moving.get_mut().unwrap().alone = None;
            let x = m.state_from(0.7, [0.3, -0.7, 1.1], [0.6, -0.2, 0.7, 0.3]);
            let (a, b) = (m.increment(0.7, &x, 0.3), joint.increment(0.7, &x, 0.3));
            for k in 0..24 {
                assert!(
                    (a[k] - b[k]).abs() < 1e-13,
                    "{mover} {k}: {} {}",
                    a[k],
                    b[k]
                );
            }
            assert!((m.omega_body(0.7, &x) - joint.omega_body(0.7, &x)).amax() < 1e-14);
            assert_relative_eq!(
                m.energy(0.7, &x),
                joint.energy(0.7, &x),
                max_relative = 1e-14
            );
        }
    }

    /// A dipole field of equatorial strength `moment / mu · n²` inclined by `i`, and the plain
    /// formula of it in world axes (see [`crate::dynamics::control::field`]): `B = B_eq (d̂ −
    /// 3 (d̂ · r̂) r̂)`, `d̂ = (0, sin i, cos i)`, `r̂ = (cos nt, sin nt, 0)`.
    fn field(n: f64, i: f64) -> (DipoleField, impl Fn(f64) -> Vector3<f64>) {
        let (moment, mu) = (7.7, 4.1);
        let f = DipoleField::try_new(n, i, moment, mu).unwrap();
        let plain = move |t: f64| {
            let d = Vector3::new(0.0, i.sin(), i.cos());
            let r = Vector3::new((n * t).cos(), (n * t).sin(), 0.0);
            (d - r * (3.0 * d.dot(&r))) * (moment / mu * n * n)
        };
        (f, plain)
    }

    /// A body dipole and the plain formula of the field it sits in (world axes, at `t`).
    type Dipole<'a> = ([f64; 3], &'a dyn Fn(f64) -> Vector3<f64>);

    fn residual(m: [f64; 3], f: DipoleField) -> AnyPart {
        crate::dynamics::control::ResidualDipole::try_new(m, f)
            .unwrap()
            .into()
    }

    /// `H' = H × ω + 3n² r̂_b × (I r̂_b) + Σ m_k × B_k`, body axes, from the plain formulas.
    fn plain_rate(t: f64, x: &[f64; 7], n: f64, dipoles: &[Dipole<'_>]) -> Vector3<f64> {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let q = attitude(x);
        let to_body = crate::kinematics::rotation_matrix(&q).transpose();
        let h = Vector3::new(x[0], x[1], x[2]);
        let omega = i.try_inverse().unwrap() * h;
        let r = to_body * Vector3::new((n * t).cos(), (n * t).sin(), 0.0);
        let mut rate = h.cross(&omega) + r.cross(&(i * r)) * (3.0 * n * n);
        for (m, b) in dipoles {
            rate += Vector3::from(*m).cross(&(to_body * b(t)));
        }
        rate
    }

    #[test]
    fn what_a_stage_time_holds_is_the_plain_formulas() {
        let (n, (f, plain)) = (0.37, field(0.37, 1.1));
        let m = [0.2, -0.5, 0.3];
        let model =
            GeneralModel::<7>::try_new(constant(), vec![gravity(n), residual(m, f.clone())]);
        let model = model.unwrap();
        // the one field made once per stage time, beside the orbit's phase
        assert_eq!(model.time_only.field, Some(f));
        let q = [0.6, -0.2, 0.7, 0.3];
        for t in [0.0, 0.7, 13.1, -4.2, 250.0] {
            let at = model.at_time(t);
            let v = at.of_t;
            assert!((v[0] - (n * t).sin()).abs() < 1e-14, "{t}");
            assert!((v[1] - (n * t).cos()).abs() < 1e-14, "{t}");
            let b = plain(t);
            assert!(
                (Vector3::new(v[2], v[3], v[4]) - b).amax() < 1e-14 * b.amax(),
                "{t}"
            );
            // the right-hand side through the stage time, at any size of q
            let x = [
                0.3,
                -0.7,
                1.1,
                q[0] * 1.3,
                q[1] * 1.3,
                q[2] * 1.3,
                q[3] * 1.3,
            ];
            let rate = plain_rate(t, &x, n, &[(m, &plain)]);
            let dx = model.increment_at(&at, &x, 0.5);
            assert!(
                (Vector3::new(dx[0], dx[1], dx[2]) * 2.0 - rate).amax() < 1e-14,
                "{t}"
            );
        }
    }

    #[test]
    fn parts_of_different_fields_each_make_their_own() {
        let (n, (f, plain), (g, other)) = (0.37, field(0.37, 1.1), field(0.37, 0.4));
        let (m, k) = ([0.2, -0.5, 0.3], [-0.1, 0.05, 0.4]);
        let parts = vec![residual(m, f), gravity(n), residual(k, g)];
        let model = GeneralModel::<7>::try_new(constant(), parts).unwrap();
        assert_eq!(model.time_only.field, None);
        let x = [0.3, -0.7, 1.1, 0.6, -0.2, 0.7, 0.3];
        for t in [0.0, 0.7, 13.1] {
            let rate = plain_rate(t, &x, n, &[(m, &plain), (k, &other)]);
            let dx = model.rhs(t, &x);
            assert!(
                (Vector3::new(dx[0], dx[1], dx[2]) - rate).amax() < 1e-14,
                "{t}"
            );
        }
    }

    #[test]
    fn an_rk4_step_through_the_stage_times_is_the_plain_rk4_step() {
        use crate::integrators::Rk4;
        use crate::ode::Stepper;
        let (n, (f, plain)) = (0.37, field(0.37, 1.1));
        let m = [0.2, -0.5, 0.3];
        let model = GeneralModel::<7>::try_new(constant(), vec![gravity(n), residual(m, f)]);
        let model = model.unwrap();
        // the plain right-hand side: H' above, q' = ½ q ⊗ (0, ω)
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let f = |t: f64, x: &[f64; 7]| -> [f64; 7] {
            let dh = plain_rate(t, x, n, &[(m, &plain)]);
            let omega = i.try_inverse().unwrap() * Vector3::new(x[0], x[1], x[2]);
            let dq = attitude(x) * nalgebra::Quaternion::from_imag(omega) * 0.5;
            [dh.x, dh.y, dh.z, dq.w, dq.i, dq.j, dq.k]
        };
        let (t, h) = (3.3, 0.05);
        let mut x = [0.3, -0.7, 1.1, 0.6, -0.2, 0.7, 0.3];
        let along = |x: &[f64; 7], k: &[f64; 7], c: f64| std::array::from_fn(|j| x[j] + c * k[j]);
        let k1 = f(t, &x);
        let k2 = f(t + h / 2.0, &along(&x, &k1, h / 2.0));
        let k3 = f(t + h / 2.0, &along(&x, &k2, h / 2.0));
        let k4 = f(t + h, &along(&x, &k3, h));
        let plain: [f64; 7] =
            std::array::from_fn(|j| x[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]));
        Rk4.step(&model, t, h, &mut x);
        for (a, b) in x.iter().zip(plain) {
            assert!((a - b).abs() < 1e-14, "{x:?} vs {plain:?}");
        }
    }
}
