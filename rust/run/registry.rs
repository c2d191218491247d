//! The methods on offer, each declared once with its facts. The driver ([`run_method`]), the
//! step planner ([`crate::run::step_size`]), the batch and sweep kernels and the Python
//! bindings read these facts here; no other module names a method.
//!
//! Adding a method: its stepper (a [`crate::ode::Stepper`] or [`crate::ode::EmbeddedPair`])
//! in its own file, a variant of [`Method`], its entry in [`METHODS`] and its arm in
//! [`Runs::run_method`]. A method says which models it runs by what it can handle
//! ([`MethodInfo::handles`]: torque-free, a constant body, no part state, …), read against
//! each model's declared traits: a part added later is run by every method that can.

use std::str::FromStr;
use std::sync::atomic::AtomicBool;

use crate::dynamics::{
    Conserved, FreeRigidBody, GeneralModel, Kinds, Model, ModelInfo, Movers, State, Traits,
};
use crate::error::{Error, Result};
use crate::integrators::{Dop853, Dopri5, Rk4};
use crate::observe::Observer;
use crate::ode::controller::Adaptive;
pub use crate::ode::controller::{DEFAULT_ATOL, DEFAULT_RTOL};
use crate::ode::{EmbeddedPair, Stats, Stepper};
use crate::rigid::{
    CrouchGrossman3, Dmv, DmvModified, ExactKick, ExactKick4, ImplicitMidpoint, Rk4Projected,
    Rkmk4, Splitting2, Splitting4, Splitting6,
};
use crate::run::adaptive::{integrate_adaptive, Units};
use crate::run::fixed::{integrate, integrate_across};
use crate::run::grid::FrameGrid;

/// The method `simulate` runs unless told otherwise: the paper's.
pub const DEFAULT_METHOD: &str = "rk4";
/// Runs needing more steps are refused unless `max_steps` is raised (about 5 minutes of RK4).
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000_000;

/// The integration methods on offer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Classic fixed-step fourth-order Runge–Kutta, the paper's method.
    Rk4,
    /// The closed-form solution ([`crate::exact`]): frames evaluated directly, no steps.
    Exact,
    /// RK4, each step projected back onto the energy, `|L|`, `L_world` and `|q| = 1`.
    Rk4Projected,
    /// Strang's splitting into exact rotations about the body axes (order 2).
    Splitting,
    /// Suzuki's composition of the splitting (order 4).
    Splitting4,
    /// Kahan & Li's composition of the splitting (order 6).
    Splitting6,
    /// The implicit midpoint rule on `(L, q)`, solved by Newton's method (order 2).
    ImplicitMidpoint,
    /// The discrete Moser–Veselov algorithm (order 2).
    Dmv,
    /// The discrete Moser–Veselov algorithm with modified moments of inertia (order 4).
    DmvModified,
    /// Runge–Kutta–Munthe-Kaas of order 4 on the unit quaternions.
    Rkmk4,
    /// Crouch–Grossman of order 3 on the unit quaternions.
    CrouchGrossman3,
    /// Strang's splitting of a body under torques on the exact free flow (order 2).
    SplittingExact,
    /// Suzuki's composition of [`Method::SplittingExact`] (order 4).
    SplittingExact4,
    /// Dormand–Prince 5(4) with error control and dense output.
    Dopri5(Adaptive),
    /// DOP853: Dormand–Prince 8(5,3) with error control and dense output.
    Dop853(Adaptive),
}

/// How `dt = None` picks a method's step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepRule {
    /// No steps: the method evaluates the solution at the frames.
    NoSteps,
    /// A fixed step from the error model `ΩT · (C (hΩ)^order + R ε / (hΩ))` (see
    /// [`crate::run::step_size`]) with this `C` and `R`.
    Accuracy {
        /// `C` of the error model: the truncation error.
        constant: f64,
        /// `R` of the error model: the round-off a step adds, in units of `ε = 2⁻⁵²`.
        roundoff: f64,
    },
    /// Error control; the first step from the order of the error estimate.
    Adaptive {
        /// Order of the error estimate.
        error_order: u32,
    },
}

/// What is known about a method before it runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodInfo {
    /// The method with its default settings.
    pub method: Method,
    /// The name users pass.
    pub name: &'static str,
    /// The order of the global error; `None` for the exact solution.
    pub order: Option<u32>,
    /// How `dt = None` picks the step; whether the method chooses its own steps.
    pub step_rule: StepRule,
    /// What it keeps to round-off of what a model keeps (see [`Method::keeps`]).
    pub keeps: Conserved,
    /// Right-hand-side evaluations per (accepted) step; 0 for a method that evaluates none.
    pub rhs_per_step: u64,
    /// Whether batches run it several rows at once in SIMD lanes ([`crate::ensemble::lanes`]).
    pub batch: bool,
    /// Whether RK4's silent dissipation of `|q|` is predicted for it before a run (the
    /// projection hides the drift, not the error behind it).
    pub rk4_dissipation: bool,
    /// What it can handle of what models ask ([`Traits`]): it runs every model
    /// ([`crate::dynamics::MODELS`]) whose traits are among these.
    pub handles: Traits,
    /// What a model must have for it to run it (an external torque: a splitting of the
    /// exact free flow and the torque's kicks has nothing to split without one).
    pub needs: Traits,
    /// Where a fixed-step method stays stable; `None` for the methods that choose their steps
    /// or take none, and for the splittings (compositions of exact rotations).
    pub stability: Option<Stability>,
    /// One line for users.
    pub about: &'static str,
}

/// How large `|hλ|` may be on the test equation `y' = λ y` before a method's steps grow
/// without bound (Hairer & Wanner, *Solving ODEs II*, §IV.2: `|R(hλ)| ≤ 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stability {
    /// Along the imaginary axis: an undamped wobble at rate `λ` (the free body's, at most its
    /// rate bound Ω).
    pub imaginary: f64,
    /// Along the negative real axis: a mode decaying at rate `λ` (a damper's slip).
    pub real: f64,
}

/// RK4's: `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24` has `|R(iy)| = 1` at `y = 2√2` and
/// `R(−x) = 1` at the real root of `x³ − 4x² + 12x − 24` (2.785…).
const RK4_STABILITY: Stability = Stability {
    imaginary: 2.0 * std::f64::consts::SQRT_2,
    real: 2.785_293_563_405_282,
};

impl MethodInfo {
    /// Whether it runs the model `model`.
    pub fn runs(&self, model: &ModelInfo) -> bool {
        self.handles.contains(model.traits) && model.traits.contains(self.needs)
    }

    /// Whether it runs every model of `kinds` (a system's).
    pub fn runs_all(&self, kinds: Kinds) -> bool {
        kinds.models().all(|m| self.runs(m))
    }

    /// The models it runs, in [`crate::dynamics::MODELS`]' order.
    pub fn models(&self) -> Vec<&'static str> {
        (crate::dynamics::MODELS.iter())
            .filter(|m| self.runs(m))
            .map(|m| m.name)
            .collect()
    }

    /// Whether the method chooses its own steps (then `dt` is only the first one tried).
    pub fn adaptive(&self) -> bool {
        matches!(self.step_rule, StepRule::Adaptive { .. })
    }

    /// Whether the method takes steps at all.
    pub fn takes_steps(&self) -> bool {
        !matches!(self.step_rule, StepRule::NoSteps)
    }
}

/// Everything a model keeps.
const ALL_INVARIANTS: Conserved = Conserved::FREE.union(Conserved::JACOBI);
/// The momenta and `|q|`: what a composition of exact rotations keeps.
const ROTATIONS: Conserved = Conserved::MOMENTA;
/// The constant free body alone (methods made for it).
const FREE_ONLY: Traits = Traits::NONE;
/// Every model but those under an external torque (a projection onto `|L|` and `L_world` is
/// valid for them alone).
const TORQUE_FREE: Traits = Traits::ALL.without(Traits::EXTERNAL_TORQUE);
/// Every model: the drivers end steps on kinks and sample times, and evaluate any part.
const EVERY_MODEL: Traits = Traits::ALL;
/// A constant body in principal axes under torques of time and attitude alone (kinks
/// included: steps end on them): the splittings on the exact free flow.
const TORQUES_ALONE: Traits = Traits::EXTERNAL_TORQUE.union(Traits::KINKS);

/// The rhs evaluations of a fixed-step method.
const fn fixed<M: Stepper<7, FreeRigidBody>>() -> u64 {
    M::RHS_PER_STEP
}

/// The registry, in the order users see it.
pub const METHODS: [MethodInfo; 15] = [
    MethodInfo {
        method: Method::Rk4,
        name: "rk4",
        order: Some(4),
        // Measured over 300 radians (`ΩT = 300`) at `hΩ = 0.1–0.4` on 42 orbits (seven bodies,
        // symmetric tops and the paper's among them, spun about each axis with two wobble
        // sizes) against scipy's DOP853 at `rtol = 1e-13`, the largest `C` was 1.2e-3 (median
        // 1.6e-4); this is twice that. (The quaternion's own phase error alone gives 1/3840.)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 400.0,
            // Round-off (measured by `benches/python/step_roundoff.py` on three well-conditioned
            // orbits, `ΩT` up to 15000, `hΩ` = 5e-4–2e-3): at most 0.22 ε a step, median
            // 0.11; this is the largest, rounded up (`C` has the margin). Near the separatrix
            // it is ten to a hundred times more (see `crate::run::step_size`).
            roundoff: 0.25,
        },
        keeps: Conserved::NONE,
        rhs_per_step: fixed::<Rk4>(),
        batch: true,
        rk4_dissipation: true,
        handles: EVERY_MODEL,
        needs: Traits::NONE,
        stability: Some(RK4_STABILITY),
        about: "classic fixed-step fourth-order Runge–Kutta, the paper's method",
    },
    MethodInfo {
        method: Method::Rk4Projected,
        name: "rk4_projected",
        order: Some(4),
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 400.0, // as RK4's
            // round-off measured at most 0.011 ε a step (the projection keeps the frequency)
            roundoff: 0.012,
        },
        keeps: ALL_INVARIANTS,
        rhs_per_step: fixed::<Rk4Projected<crate::dynamics::FreeProjection>>(),
        batch: false,
        rk4_dissipation: true,
        handles: TORQUE_FREE,
        needs: Traits::NONE,
        stability: Some(RK4_STABILITY),
        about: "RK4, each step projected back onto what the model keeps: for the free body the \
                energy, |L|, L_world and |q| = 1 (E and |L| to round-off for dt·Ω ≲ 0.25, beyond \
                to the square of RK4's change per step); for the other torque-free models |L|, L_world \
                and |q| (under an external torque L is not kept: refused)",
    },
    MethodInfo {
        method: Method::Splitting,
        name: "splitting",
        order: Some(2),
        // measured at most 0.086 (median 2.1e-3; the largest on a symmetric top spun in its
        // equatorial plane), this is twice that
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 6.0,
            // round-off measured at most 1e-4 ε a step over ΩT = 10; splitting4's (0.008) for
            // longer runs
            roundoff: 0.008,
        },
        keeps: ROTATIONS,
        rhs_per_step: fixed::<Splitting2>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "the classical Lie–Poisson splitting of McLachlan (1993) and Reich (1994): exact \
                rotations about the body axes composed by Strang (order 2; energy error bounded)",
    },
    MethodInfo {
        method: Method::Splitting4,
        name: "splitting4",
        order: Some(4),
        // measured at most 2.3e-4 (median 2.9e-5)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 2000.0,
            // round-off measured at most 0.008 ε a step
            roundoff: 0.008,
        },
        keeps: ROTATIONS,
        rhs_per_step: fixed::<Splitting4>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "Suzuki's fourth-order composition of the classical splitting",
    },
    MethodInfo {
        method: Method::Splitting6,
        name: "splitting6",
        order: Some(6),
        // Measured as RK4's constant was, on the 24 orbits of `python benches/atlas.py
        // constants` away from the separatrix (where the existing entries' constants hold
        // too): at most 2.1e-5 (median 3.8e-7); this is twice that, rounded up.
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 20000.0,
            // round-off measured at most 0.003 ε a step
            roundoff: 0.003,
        },
        keeps: ROTATIONS,
        rhs_per_step: fixed::<Splitting6>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "Kahan & Li's sixth-order composition of the classical splitting (37 rotations a \
                step)",
    },
    MethodInfo {
        method: Method::ImplicitMidpoint,
        name: "implicit_midpoint",
        order: Some(2),
        // measured at most 1.3e-2 (median 8.4e-3; `python benches/atlas.py constants`)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 35.0,
            // round-off measured at most 0.008 ε a step (over ΩT = 10, `hΩ` = 1e-6–2e-6)
            roundoff: 0.01,
        },
        keeps: Conserved::ENERGY
            .union(Conserved::MOMENTUM)
            .union(Conserved::Q_NORM),
        rhs_per_step: fixed::<ImplicitMidpoint>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "the implicit midpoint rule on (L, q), symplectic and Poisson: keeps the energy \
                and |L| (order 2; Newton's method to round-off, 2 iterations a step at dt·|ω| = \
                0.1, 3 at 1)",
    },
    MethodInfo {
        method: Method::Dmv,
        name: "dmv",
        order: Some(2),
        // measured at most 8.4e-2 (median 2.9e-2)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 5.0,
            // round-off measured at most 0.008 ε a step (over ΩT = 10, `hΩ` = 1e-6–2e-6)
            roundoff: 0.01,
        },
        keeps: ALL_INVARIANTS,
        rhs_per_step: fixed::<Dmv>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "the discrete Moser–Veselov algorithm in quaternion form (Moser & Veselov 1991; \
                Hairer & Vilmart 2006), symplectic and integrable (order 2; Newton's method, 3 \
                iterations a step at dt·|ω| = 0.1, 6 at 1; no solution much beyond 1)",
    },
    MethodInfo {
        method: Method::DmvModified,
        name: "dmv_modified",
        order: Some(4),
        // measured at most 4.5e-3 (median 2.1e-3)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 100.0,
            // round-off measured at most 0.27 ε a step
            roundoff: 0.3,
        },
        keeps: ALL_INVARIANTS,
        rhs_per_step: fixed::<DmvModified>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "the discrete Moser–Veselov algorithm with modified moments of inertia \
                (McLachlan & Zanna 2005; Hairer & Vilmart 2006): order 4 at the DMV's cost (3 \
                Newton iterations a step at dt·|ω| = 0.1, 4 at 1)",
    },
    MethodInfo {
        method: Method::Rkmk4,
        name: "rkmk4",
        order: Some(4),
        // measured at most 8.6e-3 (median 1.0e-4; the largest on a symmetric top spun about
        // its axis with a wide wobble)
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 50.0,
            // round-off measured at most 0.14 ε a step
            roundoff: 0.15,
        },
        keeps: Conserved::MOMENTA,
        rhs_per_step: fixed::<Rkmk4>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "Runge–Kutta–Munthe-Kaas of order 4 on the unit quaternions (Munthe-Kaas 1999), \
                explicit: RK4 on the rotation group",
    },
    MethodInfo {
        method: Method::CrouchGrossman3,
        name: "crouch_grossman3",
        order: Some(3),
        // measured at most 0.45 (median 1.1e-2; the largest on HLW's body spun about its
        // smallest moment)
        step_rule: StepRule::Accuracy {
            constant: 1.0,
            // round-off measured at most 0.087 ε a step (over ΩT = 100); as rkmk4's
            roundoff: 0.15,
        },
        keeps: Conserved::MOMENTA,
        rhs_per_step: fixed::<CrouchGrossman3>(),
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "Crouch–Grossman of order 3 on the unit quaternions (Crouch & Grossman 1993), \
                explicit and commutator-free",
    },
    MethodInfo {
        method: Method::SplittingExact,
        name: "splitting_exact",
        order: Some(2),
        // not measured yet over many bodies: the splitting's constant
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 6.0,
            // round-off not measured: it carries the invariants and the phase (see
            // `crate::rigid::ExactKick`), as the splittings keep theirs
            roundoff: 0.01,
        },
        keeps: Conserved::Q_NORM,
        rhs_per_step: <ExactKick as Stepper<7, GeneralModel<7>>>::RHS_PER_STEP,
        batch: false,
        rk4_dissipation: false,
        handles: TORQUES_ALONE,
        needs: Traits::EXTERNAL_TORQUE,
        stability: None,
        about: "Strang's splitting of a constant body under torques: the exact free motion \
                (elliptic functions) between half kicks of the torque (order 2; |q| to \
                round-off)",
    },
    MethodInfo {
        method: Method::SplittingExact4,
        name: "splitting_exact4",
        order: Some(4),
        // not measured yet over many bodies: the free body's fourth-order splitting's constant
        step_rule: StepRule::Accuracy {
            constant: 1.0 / 2000.0,
            // round-off not measured: it carries the invariants and the phase (see
            // `crate::rigid::ExactKick`), as the splittings keep theirs
            roundoff: 0.01,
        },
        keeps: Conserved::Q_NORM,
        rhs_per_step: <ExactKick4 as Stepper<7, GeneralModel<7>>>::RHS_PER_STEP,
        batch: false,
        rk4_dissipation: false,
        handles: TORQUES_ALONE,
        needs: Traits::EXTERNAL_TORQUE,
        stability: None,
        about: "Suzuki's fourth-order composition of splitting_exact for a constant body under \
                torques: five exact free motions (elliptic functions, one of them backwards) \
                and six torque kicks a step (order 4; |q| to round-off)",
    },
    MethodInfo {
        method: Method::Dopri5(Adaptive::DEFAULT),
        name: "dopri5",
        order: Some(<Dopri5 as EmbeddedPair<7, FreeRigidBody>>::ORDER),
        step_rule: StepRule::Adaptive {
            error_order: <Dopri5 as EmbeddedPair<7, FreeRigidBody>>::ERROR_ORDER,
        },
        keeps: Conserved::NONE,
        rhs_per_step: <Dopri5 as EmbeddedPair<7, FreeRigidBody>>::RHS_PER_STEP,
        batch: false,
        rk4_dissipation: false,
        handles: EVERY_MODEL,
        needs: Traits::NONE,
        stability: None,
        about: "Dormand–Prince 5(4) with error control and dense output",
    },
    MethodInfo {
        method: Method::Dop853(Adaptive::DEFAULT),
        name: "dop853",
        order: Some(<Dop853 as EmbeddedPair<7, FreeRigidBody>>::ORDER),
        step_rule: StepRule::Adaptive {
            error_order: <Dop853 as EmbeddedPair<7, FreeRigidBody>>::ERROR_ORDER,
        },
        keeps: Conserved::NONE,
        rhs_per_step: <Dop853 as EmbeddedPair<7, FreeRigidBody>>::RHS_PER_STEP,
        batch: false,
        rk4_dissipation: false,
        handles: EVERY_MODEL,
        needs: Traits::NONE,
        stability: None,
        about: "Dormand–Prince 8(5,3) (Hairer's DOP853) with error control and dense output",
    },
    MethodInfo {
        method: Method::Exact,
        name: "exact",
        order: None,
        step_rule: StepRule::NoSteps,
        keeps: ALL_INVARIANTS,
        rhs_per_step: 0,
        batch: false,
        rk4_dissipation: false,
        handles: FREE_ONLY,
        needs: Traits::NONE,
        stability: None,
        about: "the closed-form solution (Jacobi elliptic functions), evaluated at the frames",
    },
];

impl Method {
    /// This method's entry in [`METHODS`].
    pub fn info(&self) -> &'static MethodInfo {
        let kind = std::mem::discriminant(self);
        match METHODS
            .iter()
            .find(|m| std::mem::discriminant(&m.method) == kind)
        {
            Some(info) => info,
            None => unreachable!("every method has an entry in METHODS"),
        }
    }

    /// The method's name.
    pub fn name(&self) -> &'static str {
        self.info().name
    }

    /// Whether the method chooses its own steps (then `dt` is only the first one tried).
    pub fn is_adaptive(&self) -> bool {
        self.info().adaptive()
    }

    /// An adaptive method's settings.
    pub fn adaptive_settings(&self) -> Option<Adaptive> {
        match self {
            Method::Dopri5(a) | Method::Dop853(a) => Some(*a),
            _ => None,
        }
    }

    /// The method named `name`; an adaptive one with tolerances `rtol`, `atol` and first step
    /// `first_step` (others ignore them).
    ///
    /// # Errors
    /// An unknown name; bad tolerances or first step for an adaptive method.
    pub fn named(name: &str, rtol: f64, atol: f64, first_step: Option<f64>) -> Result<Self> {
        let method: Method = name.parse()?;
        if !method.is_adaptive() {
            return Ok(method);
        }
        let settings = Adaptive::try_new(rtol, atol)?;
        Ok(method.with_adaptive(match first_step {
            Some(h) => settings.with_first_step(h)?,
            None => settings,
        }))
    }

    /// The same method capped at `max_steps` step attempts, if adaptive (a fixed-step method's
    /// cap is its grid's, see [`FrameGrid::try_new`]).
    pub fn with_max_steps(self, max_steps: u64) -> Self {
        match self.adaptive_settings() {
            Some(a) => self.with_adaptive(a.with_max_steps(max_steps)),
            None => self,
        }
    }

    /// The same method with adaptive `settings` (unchanged for a fixed-step method).
    pub fn with_adaptive(self, settings: Adaptive) -> Self {
        match self {
            Method::Dopri5(_) => Method::Dopri5(settings),
            Method::Dop853(_) => Method::Dop853(settings),
            fixed => fixed,
        }
    }

    /// The order of the method's global error (`u32::MAX` for the exact solution, which has
    /// no truncation error).
    pub fn order(&self) -> u32 {
        self.info().order.unwrap_or(u32::MAX)
    }
}

impl FromStr for Method {
    type Err = Error;

    /// The method of the given name, adaptive ones with default tolerances.
    fn from_str(s: &str) -> Result<Self> {
        match METHODS.iter().find(|m| m.name == s) {
            Some(info) => Ok(info.method),
            None => {
                let names: Vec<String> = METHODS.iter().map(|m| format!("'{}'", m.name)).collect();
                Err(Error::invalid(
                    "method",
                    format!("must be one of {}", names.join(", ")),
                    s,
                ))
            }
        }
    }
}

impl FrameGrid {
    /// The grid of a run of `method`: frames and substeps no longer than `dt` for a fixed step,
    /// the frames alone for a method that chooses its own steps or takes none (`dt` and
    /// does not apply to the exact solution; `max_steps` caps an adaptive method's attempts,
    /// see [`Method::with_max_steps`], and both methods' frames, which are their work).
    ///
    /// # Errors
    /// As [`FrameGrid::try_new`].
    pub fn for_method(
        method: &Method,
        t_end: f64,
        frames: usize,
        dt: f64,
        max_steps: u64,
    ) -> Result<Self> {
        // the exact solution's and an adaptive method's frames are their work: they count
        // toward `max_steps`
        match method.info().step_rule {
            StepRule::NoSteps => Self::try_frames_within(t_end, frames, max_steps, false),
            StepRule::Adaptive { .. } => Self::try_frames_within(t_end, frames, max_steps, true),
            StepRule::Accuracy { .. } => Self::try_new(t_end, frames, dt, max_steps),
        }
    }
}

/// A model the registry's methods run: its arms of the dispatch. Every model runs the methods
/// that run any model ([`run_any`]); the free body adds those made for it.
pub trait Runs<const N: usize>: Model<N> {
    /// Runs `method` over `grid` from `x0`, showing frames (and steps, if asked) to `obs`.
    ///
    /// # Errors
    /// The drivers' errors.
    fn run_method<O: Observer<N>>(
        &self,
        method: Method,
        x0: [f64; N],
        grid: &FrameGrid,
        obs: &mut O,
        cancel: &AtomicBool,
    ) -> Result<Stats>;

    /// Evaluates the closed-form solution at the frames, showing them to `obs`; the flip times
    /// if `flips`.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a model without one (refused before, by [`Method::for_kinds`]).
    fn run_exact<O: Observer<N>>(
        &self,
        _x0: [f64; N],
        _grid: &FrameGrid,
        _obs: &mut O,
        _flips: bool,
        _cancel: &AtomicBool,
    ) -> Result<Vec<f64>> {
        Method::Exact.for_kinds(self.kinds()).map(|_| Vec::new())
    }
}

/// Runs a method that runs every model, by the drivers; `None` for the methods made for one.
fn run_any<const N: usize, S: Model<N>, O: Observer<N>>(
    method: Method,
    sys: &S,
    x0: [f64; N],
    grid: &FrameGrid,
    obs: &mut O,
    cancel: &AtomicBool,
) -> Option<Result<Stats>> {
    // absolute tolerance: `atol` on q, `atol` times the size of the rates (or momenta) elsewhere
    let units = || {
        let size = sys.state_size(&x0);
        Units::new(sys.rate_bound(&x0), size, N - 4)
            .with_powers(size, |k| sys.rate_power(k))
            .with_dims(sys.dimension())
    };
    // the kinks and knots asked for as the run goes (a clock's sample times are never listed)
    let (kinks, knots) = (|t| sys.next_kink(t), |t| sys.next_knot(t));
    let run = match method {
        Method::Rk4 => integrate_across(&Rk4, sys, x0, grid, &kinks, obs, cancel),
        Method::Rk4Projected => {
            let stepper = Rk4Projected::new(sys, &x0);
            integrate_across(&stepper, sys, x0, grid, &kinks, obs, cancel)
        }
        Method::Dopri5(a) => integrate_adaptive(
            &Dopri5,
            sys,
            x0,
            grid,
            &a,
            &units(),
            (&knots, &kinks),
            obs,
            cancel,
        ),
        Method::Dop853(a) => integrate_adaptive(
            &Dop853,
            sys,
            x0,
            grid,
            &a,
            &units(),
            (&knots, &kinks),
            obs,
            cancel,
        ),
        Method::Exact
        | Method::Splitting
        | Method::Splitting4
        | Method::Splitting6
        | Method::ImplicitMidpoint
        | Method::Dmv
        | Method::DmvModified
        | Method::Rkmk4
        | Method::CrouchGrossman3
        | Method::SplittingExact
        | Method::SplittingExact4 => return None,
    };
    Some(run.map(|(_, stats)| stats))
}

/// A method made for one model, asked of another: refused before (by [`Method::for_kinds`]).
fn refused(method: Method, kinds: Kinds) -> Result<Stats> {
    method.for_kinds(kinds).map(|_| Stats::default())
}

impl Runs<7> for FreeRigidBody {
    fn run_method<O: Observer<7>>(
        &self,
        method: Method,
        x0: State,
        grid: &FrameGrid,
        obs: &mut O,
        cancel: &AtomicBool,
    ) -> Result<Stats> {
        if let Some(run) = run_any(method, self, x0, grid, obs, cancel) {
            return run;
        }
        let body = self.body();
        let (_, stats) = match method {
            Method::Splitting => {
                integrate(&Splitting2::new(body, &x0), self, x0, grid, obs, cancel)?
            }
            Method::Splitting4 => {
                integrate(&Splitting4::new(body, &x0), self, x0, grid, obs, cancel)?
            }
            Method::Splitting6 => {
                integrate(&Splitting6::new(body, &x0), self, x0, grid, obs, cancel)?
            }
            Method::ImplicitMidpoint => {
                let stepper = ImplicitMidpoint::new(body, &x0);
                integrate(&stepper, self, x0, grid, obs, cancel)?
            }
            Method::Dmv => integrate(&Dmv::new(body, &x0), self, x0, grid, obs, cancel)?,
            Method::DmvModified => {
                integrate(&DmvModified::new(body, &x0), self, x0, grid, obs, cancel)?
            }
            Method::Rkmk4 => integrate(&Rkmk4::new(body, &x0), self, x0, grid, obs, cancel)?,
            Method::CrouchGrossman3 => integrate(
                &CrouchGrossman3::new(body, &x0),
                self,
                x0,
                grid,
                obs,
                cancel,
            )?,
            // the closed form takes no steps: `run_exact`
            other => return refused(other, self.kinds()),
        };
        Ok(stats)
    }

    fn run_exact<O: Observer<7>>(
        &self,
        x0: State,
        grid: &FrameGrid,
        obs: &mut O,
        flips: bool,
        cancel: &AtomicBool,
    ) -> Result<Vec<f64>> {
        crate::run::evaluate::evaluate_exact(self.body(), x0, grid, obs, flips, cancel)
    }
}

impl<const N: usize, const HOT: bool, M: Movers> Runs<N> for GeneralModel<N, HOT, M> {
    fn run_method<O: Observer<N>>(
        &self,
        method: Method,
        x0: [f64; N],
        grid: &FrameGrid,
        obs: &mut O,
        cancel: &AtomicBool,
    ) -> Result<Stats> {
        if let Some(run) = run_any(method, self, x0, grid, obs, cancel) {
            return run;
        }
        // the splittings run a body without moving parts only
        let Some(plain) = M::plain(self) else {
            return refused(method, self.kinds());
        };
        match method {
            Method::SplittingExact => {
                let stepper = ExactKick::of(plain, &x0)?;
                let kinks = |t| self.next_kink(t);
                let (_, stats) = integrate_across(&stepper, plain, x0, grid, &kinks, obs, cancel)?;
                Ok(stats)
            }
            Method::SplittingExact4 => {
                let stepper = ExactKick4::of(plain, &x0)?;
                let kinks = |t| self.next_kink(t);
                let (_, stats) = integrate_across(&stepper, plain, x0, grid, &kinks, obs, cancel)?;
                Ok(stats)
            }
            other => refused(other, self.kinds()),
        }
    }
}

impl Method {
    /// `self`, if its registry entry says it runs every model of `kinds`.
    ///
    /// # Errors
    /// [`Error::Unsupported`], naming the method, the first model it does not run and the
    /// methods that run that one.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Kinds;
    /// use dzhanibekov::run::Method;
    /// let e = Method::Exact.for_kinds(Kinds::DEPLOYMENT).unwrap_err();
    /// assert!(e.to_string().starts_with("method 'exact' cannot run model 'deployment'"));
    /// assert!(Method::Rk4.for_kinds(Kinds::named("damper").unwrap()).is_ok());
    /// ```
    pub fn for_kinds(self, kinds: Kinds) -> Result<Self> {
        let info = self.info();
        let Some(model) = kinds.models().find(|m| !info.runs(m)) else {
            return Ok(self);
        };
        Err(Error::Unsupported {
            method: self.name(),
            model: model.name,
            supported: METHODS
                .iter()
                .filter(|m| m.runs(model))
                .map(|m| format!("'{}'", m.name))
                .collect::<Vec<_>>()
                .join(", "),
        })
    }

    /// What this method keeps to round-off of what a model of `conserved` keeps.
    pub fn keeps(&self, conserved: Conserved) -> Conserved {
        self.info().keeps.intersection(conserved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RK4's stability function, written out (Hairer & Wanner II, §IV.2).
    fn rk4_r(re: f64, im: f64) -> (f64, f64) {
        let z = nalgebra::Complex::new(re, im);
        let r = 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
        (r.re, r.im)
    }

    #[test]
    fn rk4s_stability_limits_are_where_its_amplification_reaches_one() {
        let norm = |(re, im): (f64, f64)| (re * re + im * im).sqrt();
        let s = RK4_STABILITY;
        assert!((norm(rk4_r(0.0, s.imaginary)) - 1.0).abs() < 1e-14);
        assert!(norm(rk4_r(0.0, 0.99 * s.imaginary)) < 1.0);
        assert!(norm(rk4_r(0.0, 1.01 * s.imaginary)) > 1.0);
        assert!((rk4_r(-s.real, 0.0).0 - 1.0).abs() < 1e-14);
        assert!(norm(rk4_r(-0.99 * s.real, 0.0)) < 1.0);
        assert!(norm(rk4_r(-1.01 * s.real, 0.0)) > 1.0);
    }

    #[test]
    fn a_projection_onto_the_momentum_is_refused_under_a_torque() {
        let e = Method::Rk4Projected
            .for_kinds(Kinds::named("gravity_gradient").unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("'gravity_gradient'") && e.contains("'dop853'"),
            "{e}"
        );
        let named = |name| Kinds::named(name).unwrap();
        assert!(Method::Rk4Projected.for_kinds(named("wheel")).is_ok());
        assert!(Method::Splitting
            .for_kinds(named("constant_torque"))
            .is_err());
        assert!(Method::Rk4.for_kinds(named("constant_torque")).is_ok());
        // a splitting of the free flow and kicks needs a torque, and one of time and attitude
        assert!(Method::SplittingExact.for_kinds(Kinds::FREE).is_err());
        assert!(Method::SplittingExact
            .for_kinds(named("tabulated_torque"))
            .is_ok());
        assert!(Method::SplittingExact
            .for_kinds(named("callable_torque"))
            .is_err());
    }

    #[test]
    fn every_method_parses_back_from_its_name_to_its_own_entry() {
        for info in &METHODS {
            let m: Method = info.name.parse().unwrap();
            assert_eq!(m.info().name, info.name);
        }
        let err = "rk5".parse::<Method>().unwrap_err().to_string();
        assert!(err.contains("'dop853'") && err.contains("rk5"), "{err}");
    }
}
