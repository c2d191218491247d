//! Three reaction wheels driven by a controller, as the parts that hold them use them (not a
//! part itself): each wheel's relative momentum `h_i` is state, its rate the held command
//! `u_i` (`ḣ_i = u_i`, limited at each sample; see [`super::actuators`]); the wheels store
//! `Σ h_i a_i` in the body (the gyrostat of [`crate::dynamics::Wheel`]), so the body feels
//! `−Σ u_i a_i` and the total angular momentum is unchanged by them.
//!
//! State, two fields of three numbers from the part's offset: `wheel_momentum` and
//! `wheel_torque` (the held command). What the limits cut is reported as bits of the part's
//! `saturated` number: bit `k` the torque limit of wheel `k`, bit `3 + k` its momentum limit.

use nalgebra::Vector3;

use crate::error::{Error, Result};

use super::super::part::{Dim, Field, Fields, Param, ParamKind};
use super::actuators::{limit_wheel, wheel_torques, WheelAllocation};
use super::common::{number_or, set_slot, slot, vector_or, View};

/// The wheels' parameters.
pub const AXES: Param = Param::new(
    "axes",
    ParamKind::Vectors,
    "the three wheels' spin axes, body axes (default the body's x, y, z)",
)
.optional();
pub const MOMENTUM: Param = Param::new(
    "momentum",
    ParamKind::Vector,
    "the wheels' relative momenta at the start, one a wheel (default 0)",
)
.optional();
pub const TORQUE_LIMIT: Param = Param::new(
    "torque_limit",
    ParamKind::Scalar,
    "each motor's largest torque (default: no limit)",
)
.optional();
pub const MOMENTUM_LIMIT: Param = Param::new(
    "momentum_limit",
    ParamKind::Scalar,
    "each wheel's largest relative momentum (default: no limit)",
)
.optional();

/// The wheels' state fields.
pub const STATE: [Field; 2] = [
    Field {
        name: "wheel_momentum",
        width: 3,
        body_vector: false,
        dim: Dim::MOMENTUM,
        about: "each wheel's relative momentum h",
    },
    Field {
        name: "wheel_torque",
        width: 3,
        body_vector: false,
        dim: Dim::TORQUE,
        about: "each wheel's held command ḣ = u (after its limits)",
    },
];

/// How many numbers of state the wheels have.
pub const WIDTH: usize = 6;

const MOMENTUM_AT: usize = 0;
const TORQUE_AT: usize = 3;

/// Three reaction wheels (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ReactionWheels {
    /// The unit axes in the user's body axes, and in the run's.
    axes: [Vector3<f64>; 3],
    run_axes: [Vector3<f64>; 3],
    allocation: WheelAllocation,
    momentum: Vector3<f64>,
    torque_limit: f64,
    momentum_limit: f64,
}

impl ReactionWheels {
    /// The wheels of the parameters [`AXES`], [`MOMENTUM`], [`TORQUE_LIMIT`],
    /// [`MOMENTUM_LIMIT`].
    ///
    /// # Errors
    /// Not three axes, an axis that is zero or not finite, axes that do not span the body's
    /// (a torque they cannot give), a limit that is not positive.
    pub fn from_fields(fields: &Fields) -> Result<Self> {
        let raw = match fields.get("axes") {
            None => vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            Some(_) => fields.vectors("axes")?,
        };
        if raw.len() != 3 {
            return Err(Error::invalid(
                "axes",
                "must be three axes (3 × 3)",
                raw.len(),
            ));
        }
        let mut axes = [Vector3::zeros(); 3];
        for (a, r) in axes.iter_mut().zip(&raw) {
            let v = Vector3::from(*r);
            let n = v.norm();
            if !(v.iter().all(|c| c.is_finite()) && n > 0.0 && n.is_finite()) {
                return Err(Error::invalid(
                    "axes",
                    "must be three finite axes, none zero",
                    raw.clone(),
                ));
            }
            *a = v / n;
        }
        let spans = axes[0].cross(&axes[1]).dot(&axes[2]).abs() > 1e-9;
        if !spans {
            return Err(Error::invalid(
                "axes",
                "must span the body's axes (three independent directions)",
                raw,
            ));
        }
        let momentum = Vector3::from(vector_or(fields, "momentum", [0.0; 3])?);
        if !momentum.iter().all(|c| c.is_finite()) {
            return Err(Error::invalid(
                "momentum",
                "must be three finite numbers",
                momentum.as_slice(),
            ));
        }
        let positive = |name, v: f64| match v > 0.0 {
            true => Ok(v),
            false => Err(Error::invalid(
                name,
                "must be positive (infinite for no limit)",
                v,
            )),
        };
        Ok(Self {
            allocation: WheelAllocation::try_new(&axes)?,
            run_axes: axes,
            axes,
            momentum,
            torque_limit: positive(
                "torque_limit",
                number_or(fields, "torque_limit", f64::INFINITY)?,
            )?,
            momentum_limit: positive(
                "momentum_limit",
                number_or(fields, "momentum_limit", f64::INFINITY)?,
            )?,
        })
    }

    /// `Σ h_i a_i` in the run's body axes, from the part's state `x` (the wheels' fields at
    /// `at`).
    #[inline]
    pub fn stored(&self, x: &[f64], at: usize) -> Vector3<f64> {
        let h = &x[at + MOMENTUM_AT..at + MOMENTUM_AT + 3];
        self.run_axes[0] * h[0] + self.run_axes[1] * h[1] + self.run_axes[2] * h[2]
    }

    /// `ḣ_i = u_i`, into `dx`.
    #[inline]
    pub fn rates(&self, x: &[f64], at: usize, dx: &mut [f64]) {
        let (from, to) = (at + TORQUE_AT, at + MOMENTUM_AT);
        dx[to..to + 3].copy_from_slice(&x[from..from + 3]);
    }

    /// The wheels' momenta at the start, into the state.
    pub fn start(&self, view: &View, x: &mut [f64], at: usize) {
        set_slot(
            x,
            at + MOMENTUM_AT,
            &view.as_run(&self.momentum, Dim::MOMENTUM, false),
        );
    }

    /// A bound on `|Σ h_i a_i|` over a run: the limits', or the start's without limits.
    pub fn largest(&self) -> f64 {
        match self.momentum_limit.is_finite() {
            true => 3.0_f64.sqrt() * self.momentum_limit,
            false => self.momentum.norm(),
        }
    }

    /// The wheels' momenta in the user's units.
    pub fn momenta(&self, view: &View, x: &[f64], at: usize) -> Vector3<f64> {
        view.as_user(&slot(x, at + MOMENTUM_AT), Dim::MOMENTUM, false)
    }

    /// Commands the wheels to give the body `torque` (the user's axes and units) over a hold
    /// of `hold`, each limited; written into the state. Gives the bits of what the limits cut.
    pub fn command(
        &self,
        view: &View,
        torque: &Vector3<f64>,
        hold: f64,
        x: &mut [f64],
        at: usize,
    ) -> u32 {
        let h = self.momenta(view, x, at);
        let mut u = [0.0; 3];
        wheel_torques(&self.allocation, torque, &mut u);
        let mut given = Vector3::zeros();
        let mut bits = 0;
        for k in 0..3 {
            let c = limit_wheel(u[k], h[k], hold, self.torque_limit, self.momentum_limit);
            given[k] = c.torque;
            bits |= u32::from(c.torque_saturated) << k | u32::from(c.momentum_saturated) << (3 + k);
        }
        set_slot(x, at + TORQUE_AT, &view.as_run(&given, Dim::TORQUE, false));
        bits
    }

    /// The same wheels with the run's axes mapped by `to_axes`.
    pub fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            run_axes: self.run_axes.map(|a| Vector3::from(to_axes(a.into()))),
            ..self.clone()
        }
    }

    /// About how many bytes the wheels hold on the heap.
    pub fn heap_bytes(&self) -> usize {
        crate::dynamics::part::block::<Vector3<f64>>(self.allocation.len())
    }
}
