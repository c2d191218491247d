//! What is simulated, as the user describes it: a body (a constant tensor, or a deployment's
//! schedule) with its parts in the user's order — internal parts and external torques alike
//! ([`AnyPart`]) — in the user's own axes. A run turns it into a model
//! ([`super::FreeRigidBody`] or [`super::GeneralModel`]), in principal axes where the body is
//! constant ([`crate::run::simulate_system`]).

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::body::Inertia;
use crate::error::{Error, Result};
use crate::kinematics::rotation_matrix;

use super::general::MAX_PARTS_STATE;
use super::general::{ConstantInertia, InertiaLaw};
use super::kinds::{Conserved, Kinds};
use super::multibody::{self, Carried, Hub, MassMatrix, MAX_RATES, PART_RATES};
use super::part::{block, Ctx, Dim, EnergyRole, Function, MapFunction, Moved, Timed};
use super::registry::{kinds_of, AnyPart};
use super::Deployment;

/// A system's body.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemBody {
    /// A constant tensor.
    Rigid(Inertia),
    /// A prescribed `I(t)`.
    Deployment(Deployment),
}

/// A body with its parts (see the module doc), and the seed its parts draw noise from.
#[derive(Debug, Clone, PartialEq)]
pub struct System {
    body: SystemBody,
    parts: Vec<AnyPart>,
    seed: u64,
    /// The body's mass (parts whose mass moves need it).
    mass: Option<f64>,
}

impl System {
    /// `body` with `parts`, in the user's order.
    ///
    /// # Errors
    /// Two parts of a kind a system holds at most one of (one orbit), naming it; parts with
    /// more state together than a run holds ([`MAX_PARTS_STATE`]).
    pub fn try_new(body: SystemBody, parts: Vec<AnyPart>) -> Result<Self> {
        for (k, part) in parts.iter().enumerate() {
            let info = part.info();
            if info.unique && parts[..k].iter().any(|p| p.name() == info.name) {
                return Err(Error::invalid(
                    "parts",
                    format!("must hold at most one {} (one per system)", info.name),
                    parts.iter().map(AnyPart::name).collect::<Vec<_>>(),
                ));
            }
        }
        let system = Self {
            body,
            parts,
            seed: 0,
            mass: None,
        };
        match system.state_width() <= MAX_PARTS_STATE {
            true => Ok(system),
            false => Err(Self::too_much_state(system.state_width())),
        }
    }

    /// The numbers of state a run of the system adds to the body's: its parts' and, if a part
    /// dissipates, the work dissipated.
    pub fn state_width(&self) -> usize {
        let dissipates = (self.kinds().models()).any(|m| m.energy == EnergyRole::Dissipates);
        self.parts_width() + usize::from(dissipates)
    }

    /// The error for parts with `width` numbers of state together.
    pub(crate) fn too_much_state(width: usize) -> Error {
        Error::invalid(
            "parts",
            format!(
                "must have at most {MAX_PARTS_STATE} numbers of state together (with the \
                 dissipated work, if a part dissipates)"
            ),
            width,
        )
    }

    /// A constant body alone.
    pub fn rigid(inertia: Inertia) -> Self {
        Self {
            body: SystemBody::Rigid(inertia),
            parts: Vec::new(),
            seed: 0,
            mass: None,
        }
    }

    /// The same system for the run of seed `seed`, added to each part's own seed for its
    /// noise: a batch seeds row `i` with `i` (its number in the whole batch), so that its rows
    /// draw different noise, the same whatever the threads or blocks.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The same system with the body's mass `mass`.
    ///
    /// # Errors
    /// A mass that is not positive and finite.
    pub fn with_mass(mut self, mass: Option<f64>) -> Result<Self> {
        if let Some(m) = mass {
            if !(m.is_finite() && m > 0.0) {
                return Err(Error::invalid("mass", "must be positive and finite", m));
            }
        }
        self.mass = mass;
        Ok(self)
    }

    /// The body's mass, if known.
    pub fn mass(&self) -> Option<f64> {
        self.mass
    }

    pub fn body(&self) -> &SystemBody {
        &self.body
    }

    /// The parts, in the user's order.
    pub fn parts(&self) -> &[AnyPart] {
        &self.parts
    }

    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The constant body alone, if the system is nothing else: the free body.
    pub fn as_free(&self) -> Option<&Inertia> {
        match (&self.body, self.parts.is_empty()) {
            (SystemBody::Rigid(inertia), true) => Some(inertia),
            _ => None,
        }
    }

    /// The registry's models it is made of.
    pub fn kinds(&self) -> Kinds {
        kinds_of(matches!(self.body, SystemBody::Deployment(_)), &self.parts)
    }

    /// What its exact motion keeps: what each of its models keeps.
    pub fn conserved(&self) -> Conserved {
        self.kinds().conserved()
    }

    /// Replaces each user function its parts call by `f` of it (a run's own view of the
    /// function: see the Python binding's `callable`).
    pub fn map_functions(&mut self, f: &mut MapFunction<'_>) {
        for part in &mut self.parts {
            *part = part.map_functions(f);
        }
    }

    /// About how many bytes a copy of the system holds on the heap (its parts, a
    /// deployment's knots), with the allocator's headers: what a batch of one system per row
    /// adds for each row.
    pub fn heap_bytes(&self) -> usize {
        let knots = match &self.body {
            SystemBody::Rigid(_) => 0,
            SystemBody::Deployment(d) => {
                block::<f64>(d.times().len()) + block::<Matrix3<f64>>(d.tensors().len())
            }
        };
        // the parts' list; a table (a wheel's schedule, a torque's) or a function is shared
        // by the clones, not copied
        let parts: usize = self.parts.iter().map(AnyPart::heap_bytes).sum();
        knots + block::<AnyPart>(self.parts.len()) + parts
    }

    /// About the most bytes a run of it holds while it builds its model (each part's copies of
    /// its tables in the run's axes and units, the kinks and knots its steps end on, a
    /// deployment's tensors scaled), with the allocator's headers: what a run checks it can
    /// have before it starts (a wheel's schedule of 10⁷ knots aborted the process in these
    /// copies). Measured by tests/heap_bytes.rs: 240 bytes a deployment's knot in a run in its
    /// own units (rates of 1e30), about half that in the user's; a part's, its own.
    pub fn model_bytes(&self) -> usize {
        const DEPLOYMENT_KNOT: usize = 248;
        let knots = match &self.body {
            SystemBody::Rigid(_) => 0,
            SystemBody::Deployment(d) => d.times().len(),
        };
        (self.parts.iter())
            .fold(0_usize, |n, p| n.saturating_add(p.model_bytes()))
            .saturating_add(knots.saturating_mul(DEPLOYMENT_KNOT))
            .saturating_add(Self::model_itself())
    }

    /// The run's model itself, boxed (in the user's units and again in the run's): two of the
    /// largest a run builds. A model grows with what its parts carry (a tabulated field made
    /// the lean one 256 bytes larger), so this is counted, not folded into a knot's bytes.
    fn model_itself() -> usize {
        2 * block::<super::general::GeneralModel<24, true, super::general::Moving>>(1)
    }

    /// The numbers of state of every part, in order.
    pub fn parts_width(&self) -> usize {
        self.parts.iter().map(AnyPart::width).sum()
    }

    /// Each part with state of its own, by the name results show its state under (its kind;
    /// `kind_k` for the `k`-th of several of a kind), and how many numbers it has.
    pub fn state_names(&self) -> Vec<(String, usize)> {
        let with_state: Vec<&AnyPart> = self.parts.iter().filter(|p| p.width() > 0).collect();
        let mut seen: Vec<&str> = Vec::new();
        with_state
            .iter()
            .map(|p| {
                let name = p.name();
                let of_kind = with_state.iter().filter(|o| o.name() == name).count();
                let k = seen.iter().filter(|n| **n == name).count();
                seen.push(name);
                match of_kind {
                    1 => (name.to_string(), p.width()),
                    _ => (format!("{name}_{k}"), p.width()),
                }
            })
            .collect()
    }

    /// Where each body-axes vector of the parts' state starts, in it: what turns with the
    /// body's axes at the edge of a run.
    pub fn body_vectors(&self) -> Vec<usize> {
        let mut at = 0;
        let mut out = Vec::new();
        for field in self.parts.iter().flat_map(AnyPart::state) {
            if field.body_vector {
                out.push(at);
            }
            at += field.width;
        }
        out
    }

    /// The physical dimension of each number of the parts' state.
    pub fn parts_dims(&self) -> Vec<Dim> {
        (self.parts.iter().flat_map(AnyPart::state))
            .flat_map(|f| std::iter::repeat_n(f.dim, f.width))
            .collect()
    }

    /// The user's functions the parts call.
    pub fn functions(&self) -> impl Iterator<Item = &Arc<dyn Function>> {
        self.parts.iter().flat_map(AnyPart::functions)
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
    /// the run's model defines them: the body's kinetic energy and its parts' own (a wheel's
    /// spin relative to the body left out: with constant momentum, a constant; a spring's
    /// potential), the body's angular momentum and what its parts store (a schedule's at
    /// `t`). With parts whose mass moves, the kinetic energy and momentum are the whole
    /// system's about its mass centre, by the mass matrix ([`Self::moving_observed`]).
    pub fn observe(
        &self,
        t: f64,
        omega: [f64; 3],
        parts: &[f64],
        q: [f64; 4],
    ) -> (f64, Vector3<f64>, Vector3<f64>) {
        let omega = Vector3::from(omega);
        let (mut energy, mut l) = self.moving_observed(t, &omega, parts).unwrap_or_else(|| {
            let body_l = self.tensor_at(t) * omega;
            (0.5 * omega.dot(&body_l), body_l)
        });
        let mut at = 0;
        for part in &self.parts {
            let x = &parts[at..at + part.width()];
            energy += part.energy(t, x);
            l += part.momentum(t, x);
            at += part.width();
        }
        let world = rotation_matrix(&Quaternion::new(q[0], q[1], q[2], q[3])) * l;
        (energy, l, world)
    }

    /// For parts whose mass moves (and a body with a mass), the kinetic energy of the hub and
    /// those parts, `½ (H·ω + p·v)`, and their angular momentum `H` about the system's mass
    /// centre, from the hub's rates `omega` and the parts' state (coordinates and conjugate
    /// momenta `p`): `𝕄 [ω; v] = [H; p]` is solved for `H` and the rates `v` by the mass
    /// matrix's own solve — `ω` is linear in `H` at fixed `p`, `ω = S⁻¹ H + ω_p`, so three
    /// solves give `S⁻¹`'s columns and one more `ω_p`. None without such parts.
    fn moving_observed(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        parts: &[f64],
    ) -> Option<(f64, Vector3<f64>)> {
        let (hub, carried, p, row) = self.moving_carried(t, parts)?;
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &carried);
        let h = Self::moving_momentum(&m, omega, &p)?;
        let (_, v) = m.solve(&h, &p);
        let kinetic = 0.5 * (h.dot(omega) + (0..row).map(|r| p[r] * v[r]).sum::<f64>());
        Some((kinetic, h))
    }

    /// `H` of hub rates `omega` and parts' momenta `p`: `ω` is linear in `H` at fixed `p`,
    /// `ω = S⁻¹ H + ω_p`, so three solves give `S⁻¹`'s columns and one more `ω_p`.
    fn moving_momentum(
        m: &MassMatrix<MAX_RATES>,
        omega: &Vector3<f64>,
        p: &[f64; MAX_RATES],
    ) -> Option<Vector3<f64>> {
        let (omega_p, _) = m.solve(&Vector3::zeros(), p);
        let columns = Matrix3::from_columns(
            &[0, 1, 2].map(|i| m.solve(&Vector3::ith(i, 1.0), &[0.0; MAX_RATES]).0),
        );
        Some(columns.try_inverse()? * (omega - omega_p))
    }

    /// The rates of the state of each part whose mass moves at one frame (as a run's
    /// right-hand side has them: a spring's `x'`, `p'`, a hinge's `β'`, `p'`, a pendulum's
    /// `n'`, `π'`), written into their places of `out` (as long as the parts' state; the
    /// other places are left as they are), from the hub's rates `omega`, the attitude `q` and
    /// the law `law` ([`Self::inertia_law`]): the same solve as [`Self::observe`], and each
    /// part's element moving as [`multibody::motion`] has it. False without such parts.
    pub fn moving_rates(
        &self,
        law: &InertiaLaw,
        t: f64,
        omega: [f64; 3],
        parts: &[f64],
        q: [f64; 4],
        out: &mut [f64],
    ) -> bool {
        let omega = Vector3::from(omega);
        let Some((hub, carried, p, _)) = self.moving_carried(t, parts) else {
            return false;
        };
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &carried);
        let Some(h) = Self::moving_momentum(&m, &omega, &p) else {
            return false;
        };
        let motion = multibody::motion::<MAX_RATES>(&hub, &carried, &h, &p);
        let (mut at, mut row, mut k) = (0, 0, 0);
        for part in &self.parts {
            let width = part.width();
            if part.carried(&parts[at..at + width]).is_some() {
                let c = &carried[k];
                let (velocity, spin) = motion.element(c, row);
                let mut rates = [0.0; PART_RATES];
                rates[..c.rates].copy_from_slice(&motion.rates[row..row + c.rates]);
                let ctx = Ctx {
                    t,
                    q: Quaternion::new(q[0], q[1], q[2], q[3]),
                    omega,
                    inertia: law,
                    moving: Some(Moved {
                        rates,
                        velocity,
                        spin,
                        carried: c,
                    }),
                    timed: Timed::default(),
                };
                part.rates(&ctx, &parts[at..at + width], &mut out[at..at + width]);
                row += c.rates;
                k += 1;
            }
            at += width;
        }
        true
    }

    /// The body's inertia law as a run's model reads it (what [`Self::moving_rates`] takes).
    ///
    /// # Errors
    /// A constant tensor [`ConstantInertia::try_new`] refuses.
    pub fn inertia_law(&self) -> Result<InertiaLaw> {
        Ok(match &self.body {
            SystemBody::Rigid(inertia) => {
                InertiaLaw::Constant(ConstantInertia::try_new(*inertia.tensor())?)
            }
            SystemBody::Deployment(d) => InertiaLaw::Schedule(d.clone()),
        })
    }

    /// The hub (the body's tensor at `t`, its mass) and what the parts whose mass moves carry
    /// at state `parts`, with their momenta and how many rates they have; None without such
    /// parts, a mass, or room in the joint solve.
    #[allow(clippy::type_complexity)]
    fn moving_carried(
        &self,
        t: f64,
        parts: &[f64],
    ) -> Option<(Hub, Vec<Carried>, [f64; MAX_RATES], usize)> {
        let mut carried = Vec::new();
        let mut p = [0.0; MAX_RATES];
        let (mut row, mut at) = (0, 0);
        for part in &self.parts {
            let x = &parts[at..at + part.width()];
            at += part.width();
            if let Some((c, momenta)) = part.carried(x) {
                if row + c.rates > MAX_RATES {
                    return None;
                }
                p[row..row + c.rates].copy_from_slice(&momenta[..c.rates]);
                row += c.rates;
                carried.push(c);
            }
        }
        if carried.is_empty() {
            return None;
        }
        let moved: f64 = carried.iter().map(|c| c.mass).sum();
        let hub = Hub::try_new(self.tensor_at(t), self.mass?, moved).ok()?;
        Some((hub, carried, p, row))
    }
}
