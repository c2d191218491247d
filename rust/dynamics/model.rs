//! What a run needs to know of a model: its state's layout, the rates, the total angular
//! momentum and energy it reports, what its exact motion keeps, where its intermediate axis
//! is (for the flips), where its right-hand side is not smooth, and how a projected method
//! puts a state back onto what it keeps.
//!
//! **State layout**, the same for every model: three components of rates or momenta (the
//! free body's `ω`, a general system's total angular momentum `H`), then each part's own
//! state (a damper's `σ`) and what the model adds (see [`super::GeneralModel`]), then the
//! body-to-world quaternion `(Q, U, V, W)`, scalar first, obeying the body-frame law
//! `q' = ½ q ⊗ (0, ω)`.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::Result;

pub use super::kinds::Conserved;
use super::part::Dim;
use crate::float::RateScale;
use crate::kinematics::rotation_matrix;
use crate::ode::OdeSystem;

/// Where a model's intermediate principal axis is at some time, for the flips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MidAxis {
    /// No intermediate axis: two moments equal (a symmetric top never flips).
    None,
    /// Body axis `k` (0 = x, 1 = y, 2 = z): the body axes are principal.
    Body(usize),
    /// Along this unit vector in body axes (a tensor that is not diagonal); its sign is
    /// arbitrary, the flip observer keeps it continuous.
    Along(Vector3<f64>),
}

/// The intermediate principal axis of the tensor `m`: a body axis for a `diagonal` one, else
/// the eigenvector of the middle eigenvalue (its sign arbitrary); none where two moments are
/// equal.
pub fn mid_axis_of(m: &Matrix3<f64>, diagonal: bool) -> MidAxis {
    if diagonal {
        return match crate::body::intermediate_index(&m.diagonal()) {
            Some(k) => MidAxis::Body(k),
            None => MidAxis::None,
        };
    }
    let eig = m.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    match crate::body::intermediate_index(&Vector3::new(
        eig.eigenvalues[order[0]],
        eig.eigenvalues[order[1]],
        eig.eigenvalues[order[2]],
    )) {
        Some(_) => MidAxis::Along(eig.eigenvectors.column(order[1]).into_owned()),
        None => MidAxis::None,
    }
}

/// A model of a rotating body: an ODE system of dimension `N` laid out as the module doc says.
pub trait Model<const N: usize>: OdeSystem<N> + Sync + Sized {
    /// What the model's projection keeps (see [`Model::kept`]).
    type Kept: Copy + Send + Sync + std::fmt::Debug;

    /// What the exact motion keeps: the drift measures the error in these; the others change
    /// by the model's own law (a deployment's work, a damper's loss, a torque's).
    fn conserved(&self) -> Conserved;

    /// The registry's models this one is made of ([`crate::dynamics::MODELS`]): a method runs
    /// it if it runs each of them.
    fn kinds(&self) -> super::kinds::Kinds;

    /// The body-frame angular velocity at `(t, x)`.
    fn omega_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64>;

    /// The total angular momentum at `(t, x)` in body axes (body and parts).
    fn momentum_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64>;

    /// The time derivative of [`Model::momentum_body`] in body axes: `L × ω` without external
    /// torque (the flips' interpolation slopes).
    fn momentum_rate(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        self.momentum_body(t, x).cross(&self.omega_body(t, x))
    }

    /// The total kinetic energy at `(t, x)`.
    fn energy(&self, t: f64, x: &[f64; N]) -> f64;

    /// The Jacobi integral at `(t, x)`, for a model that has one.
    fn jacobi(&self, _t: f64, _x: &[f64; N]) -> Option<f64> {
        None
    }

    /// A bound on the body rates over the run from `x0`, for the planned step and the adaptive
    /// error control.
    fn rate_bound(&self, x0: &[f64; N]) -> f64;

    /// The absolute-tolerance unit of the rates (or momenta) for the adaptive error control:
    /// the size of the first three components over the run.
    fn state_size(&self, x0: &[f64; N]) -> f64 {
        x0[..N - 4].iter().fold(0.0_f64, |m, v| m.max(v.abs()))
    }

    /// The fastest decay rate of the model's own dissipation (a damper's slip): an explicit
    /// method is stable while the step times it stays within its real-axis limit; 0 for none.
    fn stiffness(&self) -> f64 {
        0.0
    }

    /// Whether the exact motion can only lose energy (its parts declare that they dissipate
    /// and nothing does work: no torque, no deployment, no wheel spun up): a run whose energy
    /// grows beyond its error has then diverged (see
    /// [`crate::observe::DriftMonitor::watching_growth`]).
    fn energy_never_grows(&self) -> bool {
        false
    }

    /// The energy plus the work the parts dissipated since the start, for a model whose parts
    /// dissipate: kept by the exact motion when nothing does work.
    fn balance(&self, _t: f64, _x: &[f64; N]) -> Option<f64> {
        None
    }

    /// How many numbers of the parts' state follow the first three: what a run's frames keep
    /// of each state.
    fn parts_width(&self) -> usize {
        N - 7
    }

    /// The power of a rate in the dimension of the state's `k`-th number (`k < N − 4`): 1 for
    /// rates and momenta, 2 for an energy, 0 for an angle. The adaptive error control measures
    /// each number against a unit of that dimension, so that a run keeps its steps under
    /// `(ω, t) → (s ω, t / s)`.
    fn rate_power(&self, _k: usize) -> i32 {
        1
    }

    /// The physical dimension of each number of the parts' state (see [`Dim`]).
    fn parts_dims(&self) -> &[Dim] {
        &[]
    }

    /// How many numbers of the state are the model's (the rest, before `q`, is padding of a
    /// state size shared by several models): what the adaptive error norm averages over.
    fn dimension(&self) -> usize {
        N
    }

    /// The state `x` in the units of `scale` (see [`crate::float`]): its rates and momenta over
    /// `2^e`, its parts' state by its dimension, its attitude as it is.
    fn state_in_units(&self, x: &[f64; N], scale: RateScale) -> [f64; N] {
        state_to_unit(x, scale)
    }

    /// The intermediate principal axis at `t`.
    fn intermediate_axis(&self, t: f64) -> MidAxis;

    /// The times (increasing) where the right-hand side is not smooth: an adaptive step ends
    /// exactly there, a fixed step is told in the docs.
    fn knots(&self) -> &[f64] {
        &[]
    }

    /// The knots (increasing, among [`Model::knots`]) where the right-hand side itself has a
    /// kink or a jump (a tabulated torque, a wheel's schedule): fixed-step methods end a step
    /// there too (a straddling step would be of order 1 or 2 there), and every driver starts
    /// the next step one float64 after it, so that a jump is taken from the side that step
    /// integrates (see [`crate::dynamics::Table`]).
    fn kinks(&self) -> &[f64] {
        &[]
    }

    /// The first kink at or after `t` (infinity if none): what the drivers ask as a run goes,
    /// so that times laid out by a clock (a controller's sample times) need no list.
    fn next_kink(&self, t: f64) -> f64 {
        crate::ode::first_from(self.kinks(), t)
    }

    /// The first knot at or after `t` (infinity if none), likewise.
    fn next_knot(&self, t: f64) -> f64 {
        crate::ode::first_from(self.knots(), t)
    }

    /// What a projected method restores after each step, taken at the start `(t0, x0)`.
    fn kept(&self, t0: f64, x0: &[f64; N]) -> Self::Kept;

    /// Puts `x` at `t` back onto what `kept` holds.
    fn project(&self, kept: &Self::Kept, t: f64, x: &mut [f64; N]);

    /// The same model with times in the units of `scale` (see [`crate::float`]): what carries
    /// a time (knot times, a damper's coefficient, an orbit's rate) changes with it.
    ///
    /// # Errors
    /// [`crate::Error::TooLarge`] when such a quantity leaves float64.
    fn in_units(&self, scale: RateScale) -> Result<Self>;
}

/// The attitude part of a model's state (its last four components).
#[inline(always)]
pub fn attitude<const N: usize>(x: &[f64; N]) -> Quaternion<f64> {
    Quaternion::new(x[N - 4], x[N - 3], x[N - 2], x[N - 1])
}

/// Writes the unit quaternion `q` into the last four components of `x`.
#[inline(always)]
pub fn set_attitude<const N: usize>(x: &mut [f64; N], q: &Quaternion<f64>) {
    x[N - 4] = q.w;
    x[N - 3] = q.i;
    x[N - 2] = q.j;
    x[N - 1] = q.k;
}

/// A state whose first `N − 4` numbers are rates in the units of `scale`: over `2^e`, its
/// attitude as it is.
pub fn state_to_unit<const N: usize>(x: &[f64; N], scale: RateScale) -> [f64; N] {
    std::array::from_fn(|k| match k < N - 4 {
        true => scale.rate_to_unit(x[k]),
        false => x[k],
    })
}

/// `s · ½ q ⊗ (0, ω)`: the body-frame quaternion law, scaled.
#[inline(always)]
pub fn quaternion_increment(q: [f64; 4], omega: Vector3<f64>, s: f64) -> [f64; 4] {
    let [q0, q1, q2, q3] = q;
    let (u, v, w) = (omega.x, omega.y, omega.z);
    let half = 0.5 * s;
    [
        -half * (q1 * u + q2 * v + q3 * w),
        half * (q0 * u + q2 * w - q3 * v),
        half * (q0 * v + q3 * u - q1 * w),
        half * (q0 * w + q1 * v - q2 * u),
    ]
}

/// The momentum invariants of a torque-free model, taken at the start: `|H|` and `H` in space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MomentumProjection {
    l0: f64,
    l_world0: Vector3<f64>,
}

impl MomentumProjection {
    /// The invariants of a state with total angular momentum `l` (body axes) and attitude `q`.
    pub fn new(l: Vector3<f64>, q: &Quaternion<f64>) -> Self {
        Self {
            l0: l.norm(),
            l_world0: rotation_matrix(q) * l,
        }
    }

    /// The factor that takes `l` back to `|L₀|` and `q` normalised and turned, in space, by the
    /// smallest rotation taking `M(q) L` onto its initial direction (`q ← δ ⊗ q`).
    #[inline]
    pub fn restore(&self, l: &Vector3<f64>, q: &Quaternion<f64>) -> (f64, Quaternion<f64>) {
        let n = l.norm();
        let mut q = *q;
        let mut factor = 1.0;
        if n > 0.0 && self.l0 > 0.0 {
            factor = self.l0 / n;
            let a = rotation_matrix(&q) * (l * factor);
            let b = &self.l_world0;
            // δ ∝ (|a||b| + a·b, a × b) turns a onto b (|a| = |b|)
            let delta = Quaternion::from_parts(self.l0 * self.l0 + a.dot(b), a.cross(b));
            q = delta * q;
        }
        (factor, q / q.norm())
    }
}
