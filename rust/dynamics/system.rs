//! What is simulated, as the user describes it: a body (a constant tensor, or a deployment's
//! schedule) with its internal parts and external torques, in the user's own axes. A run turns it into a model
//! ([`super::FreeRigidBody`] or [`super::GeneralModel`]), in principal axes where the body is
//! constant ([`crate::run::simulate_system`]).

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::body::Inertia;
use crate::error::{Error, Result};
use crate::kinematics::rotation_matrix;

use super::kinds::Kinds;
use super::{Conserved, Damper, Deployment, Torque, TorqueFunction, Torques, Wheel, WheelSchedule};

/// A system's body.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemBody {
    /// A constant tensor.
    Rigid(Inertia),
    /// A prescribed `I(t)`.
    Deployment(Deployment),
}

/// An internal part, with what its state starts from.
#[derive(Debug, Clone, PartialEq)]
pub enum Part {
    /// A spherical viscous damper; its sphere's rates start at `sigma0` (body axes), or
    /// co-rotating with the body (`None`).
    Damper {
        damper: Damper,
        sigma0: Option<[f64; 3]>,
    },
    /// A momentum wheel of constant relative momentum (no state of its own).
    Wheel(Wheel),
    /// A momentum wheel whose relative momentum follows a schedule (no state of its own).
    ScheduledWheel(WheelSchedule),
}

impl Part {
    /// The part's name, as results show its state.
    pub fn name(&self) -> &'static str {
        match self {
            Part::Damper { .. } => "damper",
            Part::Wheel(_) => "wheel",
            Part::ScheduledWheel(_) => "wheel_schedule",
        }
    }

    /// How many numbers of state it has.
    pub fn width(&self) -> usize {
        match self {
            Part::Damper { .. } => 3,
            Part::Wheel(_) | Part::ScheduledWheel(_) => 0,
        }
    }
}

/// A body with its parts (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct System {
    body: SystemBody,
    parts: Vec<Part>,
    torques: Vec<Torque>,
}

impl System {
    /// `body` with `parts`.
    ///
    /// # Errors
    /// More than one damper; a damper's start that is not finite.
    pub fn try_new(body: SystemBody, parts: Vec<Part>) -> Result<Self> {
        let dampers = parts
            .iter()
            .filter(|p| matches!(p, Part::Damper { .. }))
            .count();
        if dampers > 1 {
            return Err(Error::invalid(
                "parts",
                "must hold at most one damper",
                dampers,
            ));
        }
        for part in &parts {
            if let Part::Damper {
                sigma0: Some(s), ..
            } = part
            {
                if !s.iter().all(|v| v.is_finite()) {
                    return Err(Error::invalid("sigma0", "must be three finite rates", s));
                }
            }
        }
        Ok(Self {
            body,
            parts,
            torques: Vec::new(),
        })
    }

    /// The same system under the external `torques`.
    ///
    /// # Errors
    /// More than one gravity gradient.
    pub fn with_torques(mut self, torques: Vec<Torque>) -> Result<Self> {
        Torques::of(&torques)?;
        self.torques = torques;
        Ok(self)
    }

    /// A constant body alone.
    pub fn rigid(inertia: Inertia) -> Self {
        Self {
            body: SystemBody::Rigid(inertia),
            parts: Vec::new(),
            torques: Vec::new(),
        }
    }

    pub fn body(&self) -> &SystemBody {
        &self.body
    }

    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    pub fn torques(&self) -> &[Torque] {
        &self.torques
    }

    /// The wheels' total momentum `Σ h a` in the user's body axes, if there are wheels.
    pub fn wheels_momentum(&self) -> Option<Vector3<f64>> {
        self.parts.iter().fold(None, |sum, p| match p {
            Part::Wheel(w) => Some(sum.unwrap_or_default() + w.momentum_body()),
            _ => sum,
        })
    }

    /// The wheels of scheduled momentum, in the user's body axes.
    pub fn wheel_schedules(&self) -> impl Iterator<Item = &WheelSchedule> {
        self.parts.iter().filter_map(|p| match p {
            Part::ScheduledWheel(w) => Some(w),
            _ => None,
        })
    }

    /// The damper and its start, if there is one.
    pub fn damper(&self) -> Option<(Damper, Option<[f64; 3]>)> {
        self.parts.iter().find_map(|p| match p {
            Part::Damper { damper, sigma0 } => Some((*damper, *sigma0)),
            _ => None,
        })
    }

    /// The constant body alone, if the system is nothing else: the free body.
    pub fn as_free(&self) -> Option<&Inertia> {
        match (&self.body, self.parts.is_empty() && self.torques.is_empty()) {
            (SystemBody::Rigid(inertia), true) => Some(inertia),
            _ => None,
        }
    }

    /// The registry's models it is made of.
    pub fn kinds(&self) -> Kinds {
        let mut kinds = match self.body {
            SystemBody::Rigid(_) => Kinds::NONE,
            SystemBody::Deployment(_) => Kinds::DEPLOYMENT,
        };
        for part in &self.parts {
            kinds = kinds.union(match part {
                Part::Damper { .. } => Kinds::DAMPER,
                Part::Wheel(_) => Kinds::WHEEL,
                Part::ScheduledWheel(_) => Kinds::WHEEL_SCHEDULE,
            });
        }
        for torque in &self.torques {
            kinds = kinds.union(torque.kind());
        }
        match kinds == Kinds::NONE {
            true => Kinds::FREE,
            false => kinds,
        }
    }

    /// What its exact motion keeps: what each of its models keeps.
    pub fn conserved(&self) -> Conserved {
        self.kinds().conserved()
    }

    /// Replaces each user function among its torques by `f` of it (a run's own view of the
    /// function: see the Python binding's `callable`).
    pub fn map_functions(
        &mut self,
        mut f: impl FnMut(&Arc<dyn TorqueFunction>) -> Arc<dyn TorqueFunction>,
    ) {
        for torque in &mut self.torques {
            if let Torque::Callable(c) = torque {
                *c = c.with_function(f(c.function()));
            }
        }
    }

    /// About how many bytes a copy of the system holds on the heap (its parts, a
    /// deployment's knots), with the allocator's headers: what a batch of one system per row
    /// adds for each row.
    pub fn heap_bytes(&self) -> usize {
        let block = |bytes: usize| if bytes == 0 { 0 } else { bytes.max(16) + 16 };
        let knots = match &self.body {
            SystemBody::Rigid(_) => 0,
            SystemBody::Deployment(d) => {
                block(std::mem::size_of_val(d.times())) + block(std::mem::size_of_val(d.tensors()))
            }
        };
        // the torques' list; a table (a wheel's schedule, a torque's) or a function is shared
        // by the clones, not copied
        let torques = block(std::mem::size_of_val(self.torques.as_slice()));
        knots + block(std::mem::size_of_val(self.parts.as_slice())) + torques
    }

    /// About the most bytes a run of it holds while it builds its model (each table's values
    /// and times copied into the run's axes and units, the kinks and knots its steps end on,
    /// a deployment's tensors scaled), with the allocator's headers: what a run checks it can
    /// have before it starts (a wheel's schedule of 10⁷ knots aborted the process in these
    /// copies). Measured by tests/heap_bytes.rs: 104 bytes a table's knot and 240 a
    /// deployment's in a run in its own units (rates of 1e30), about half that in the user's.
    pub fn model_bytes(&self) -> usize {
        const TABLE_KNOT: usize = 112;
        const DEPLOYMENT_KNOT: usize = 248;
        let schedules = self.wheel_schedules().map(|w| w.table().times().len());
        let tables = self.torques.iter().map(|t| match t {
            Torque::Tabulated(t) => t.table().times().len(),
            _ => 0,
        });
        let knots = match &self.body {
            SystemBody::Rigid(_) => 0,
            SystemBody::Deployment(d) => d.times().len(),
        };
        let table_knots: usize = schedules.chain(tables).sum();
        table_knots
            .saturating_mul(TABLE_KNOT)
            .saturating_add(knots.saturating_mul(DEPLOYMENT_KNOT))
    }

    /// The numbers of state of every part, in order.
    pub fn parts_width(&self) -> usize {
        self.parts.iter().map(Part::width).sum()
    }

    /// The body's tensor at `t`, in the user's axes.
    pub fn tensor_at(&self, t: f64) -> Matrix3<f64> {
        match &self.body {
            SystemBody::Rigid(inertia) => *inertia.tensor(),
            SystemBody::Deployment(d) => d.inertia_at(t),
        }
    }

    /// The energy, the total angular momentum in body axes and in space at one frame from
    /// the body rates `omega`, the parts' state `parts` and the attitude `q` (user axes), as
    /// the run's model defines them: the energy is the body's and its dampers' kinetic energy
    /// (a wheel's spin relative to the body left out: with constant momentum, a constant), the
    /// momentum counts the wheels' `Σ h a` (a schedule's at `t`).
    pub fn observe(
        &self,
        t: f64,
        omega: [f64; 3],
        parts: &[f64],
        q: [f64; 4],
    ) -> (f64, Vector3<f64>, Vector3<f64>) {
        let omega = Vector3::from(omega);
        let body_l = self.tensor_at(t) * omega;
        let (mut energy, mut l) = (0.5 * omega.dot(&body_l), body_l);
        let mut at = 0;
        for part in &self.parts {
            match part {
                Part::Damper { damper, .. } => {
                    let sigma = Vector3::new(parts[at], parts[at + 1], parts[at + 2]);
                    energy += 0.5 * damper.sphere() * sigma.norm_squared();
                    l += sigma * damper.sphere();
                }
                Part::Wheel(w) => l += w.momentum_body(),
                Part::ScheduledWheel(w) => l += w.momentum_at(t),
            }
            at += part.width();
        }
        let world = rotation_matrix(&Quaternion::new(q[0], q[1], q[2], q[3])) * l;
        (energy, l, world)
    }
}
