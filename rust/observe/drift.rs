//! How far a run wandered from what its model's exact motion keeps.

use nalgebra::Vector3;

use crate::dynamics::model::attitude;
use crate::dynamics::{Conserved, Model};
use crate::kinematics::rotation_matrix;

use super::Observer;

/// The largest departure of each invariant from its initial value, over the frames.
///
/// Energy and `|L|` are relative; the world-frame momentum is `|L(t) - L(0)| / |L(0)|`; the
/// quaternion's is `||q| - 1|` (the run starts from a unit quaternion); the Jacobi integral's
/// is relative (`None` for a model without one), and so is the energy balance's (the energy
/// plus the work the parts dissipated, for a model whose parts dissipate; `None` otherwise).
/// `kept` says which of them the model's exact motion keeps: those measure the integration error, the others the model's own change (a
/// deployment's work on the energy, a torque's on the momentum). Computed in the run's own
/// units (see [`crate::float`]), where no square overflows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    pub energy: f64,
    pub momentum: f64,
    pub momentum_world: f64,
    pub q_norm: f64,
    pub jacobi: Option<f64>,
    pub energy_balance: Option<f64>,
    /// What the model keeps (see [`Conserved`]).
    pub kept: Conserved,
}

impl Default for Drift {
    fn default() -> Self {
        Self {
            energy: 0.0,
            momentum: 0.0,
            momentum_world: 0.0,
            q_norm: 0.0,
            jacobi: None,
            energy_balance: None,
            kept: Conserved::FREE,
        }
    }
}

impl Drift {
    /// Whether every entry is finite: past a stability limit a run can end finite but so
    /// large that its energy is not.
    pub fn is_finite(&self) -> bool {
        [self.energy, self.momentum, self.momentum_world, self.q_norm]
            .iter()
            .chain(&self.jacobi)
            .chain(&self.energy_balance)
            .all(|v| v.is_finite())
    }
}

/// What is compared at every frame.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Invariants {
    energy: f64,
    l_body: Vector3<f64>,
    l_world: Vector3<f64>,
    q_norm: f64,
    jacobi: Option<f64>,
    balance: Option<f64>,
}

fn relative(a: f64, a0: f64) -> f64 {
    if a0 == 0.0 {
        (a - a0).abs()
    } else {
        ((a - a0) / a0).abs()
    }
}

/// Watches the invariants of a run of `sys` at every frame and keeps their [`Drift`].
#[derive(Debug, Clone)]
pub struct DriftMonitor<'a, S> {
    sys: &'a S,
    initial: Option<Invariants>,
    pub drift: Drift,
    /// The relative energy gain beyond which a model that only loses energy has diverged;
    /// `None` watches none (see [`DriftMonitor::watching_growth`]).
    growth_tol: Option<f64>,
    /// The first frame time at which the energy grew beyond `growth_tol`, and `E / E₀` there.
    pub grew: Option<(f64, f64)>,
}

impl<'a, S> DriftMonitor<'a, S> {
    pub fn new<const N: usize>(sys: &'a S) -> Self
    where
        S: Model<N>,
    {
        Self {
            sys,
            initial: None,
            drift: Drift {
                kept: sys.conserved(),
                ..Drift::default()
            },
            growth_tol: None,
            grew: None,
        }
    }

    /// The same monitor, also noting ([`DriftMonitor::grew`]) the first frame at which the
    /// energy exceeds `E₀ (1 + tol)`, if the model's energy can only fall
    /// ([`Model::energy_never_grows`]): growth it cannot have, a run past the method's
    /// stability limit.
    pub fn watching_growth<const N: usize>(self, tol: f64) -> Self
    where
        S: Model<N>,
    {
        Self {
            growth_tol: self.sys.energy_never_grows().then_some(tol),
            ..self
        }
    }
}

impl<const N: usize, S: Model<N>> Observer<N> for DriftMonitor<'_, S> {
    fn frame(&mut self, _index: usize, t: f64, x: &[f64; N]) {
        let q = attitude(x);
        let l_body = self.sys.momentum_body(t, x);
        let now = Invariants {
            energy: self.sys.energy(t, x),
            l_body,
            l_world: rotation_matrix(&q) * l_body,
            q_norm: q.norm(),
            jacobi: self.sys.jacobi(t, x),
            balance: self.sys.balance(t, x),
        };
        let first = *self.initial.get_or_insert(now);
        let l0 = first.l_body.norm();
        if let (Some(tol), None) = (self.growth_tol, self.grew) {
            // the energy itself, not the balance: at a coarse step inside the stability limit
            // the dissipated work's quadrature errs by percents (3.6 % at h·Ω = 1, hλ = 2.7)
            // while the energy stays within 5e-5 of never rising; a NaN counts as grown
            if now.energy.is_nan() || now.energy > first.energy * (1.0 + tol) {
                self.grew = Some((t, now.energy / first.energy));
            }
        }
        let d = &mut self.drift;
        d.energy = d.energy.max(relative(now.energy, first.energy));
        d.momentum = d.momentum.max(relative(now.l_body.norm(), l0));
        let dl = (now.l_world - first.l_world).norm();
        d.momentum_world = d.momentum_world.max(if l0 > 0.0 { dl / l0 } else { dl });
        d.q_norm = d.q_norm.max((now.q_norm - 1.0).abs());
        if let (Some(j), Some(j0)) = (now.jacobi, first.jacobi) {
            d.jacobi = Some(d.jacobi.unwrap_or(0.0).max(relative(j, j0)));
        }
        if let (Some(b), Some(b0)) = (now.balance, first.balance) {
            d.energy_balance = Some(d.energy_balance.unwrap_or(0.0).max(relative(b, b0)));
        }
    }
}
