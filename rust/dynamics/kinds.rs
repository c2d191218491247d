//! The registry of models ([`MODELS`]): each model's name and what a system made of it keeps.
//! A set of models ([`Kinds`]) is what a system is made of, or what a method runs; a set of
//! invariants ([`Conserved`]) what a model keeps, or a method of it.

use crate::error::Result;

/// A set of the invariants a run's drift measures (see [`crate::observe::Drift`]): what a
/// model's exact motion keeps, or what a method keeps of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Conserved(u8);

impl Conserved {
    /// Nothing: a model with a general external torque.
    pub const NONE: Self = Self(0);
    /// The kinetic energy.
    pub const ENERGY: Self = Self(1);
    /// `|L|`, the norm of the total angular momentum.
    pub const MOMENTUM: Self = Self(2);
    /// `L_world`, the total angular momentum in space.
    pub const MOMENTUM_WORLD: Self = Self(4);
    /// `|q| = 1`.
    pub const Q_NORM: Self = Self(8);
    /// The Jacobi integral of a body in a circular orbit (kinetic energy relative to the
    /// orbiting frame plus the gravity-gradient potential).
    pub const JACOBI: Self = Self(16);
    /// What the constant free body keeps: energy, `|L|`, `L_world` and `|q|`.
    pub const FREE: Self = Self(1 | 2 | 4 | 8);
    /// What every torque-free model keeps: `|L|`, `L_world` and `|q|`.
    pub const MOMENTA: Self = Self(2 | 4 | 8);

    /// The names in [`crate::observe::Drift`]'s order, one per member.
    pub const NAMES: [(Self, &'static str); 5] = [
        (Self::ENERGY, "energy"),
        (Self::MOMENTUM, "momentum"),
        (Self::MOMENTUM_WORLD, "momentum_world"),
        (Self::Q_NORM, "q_norm"),
        (Self::JACOBI, "jacobi"),
    ];

    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    pub const fn intersection(self, other: Self) -> Self {
        Self(self.0 & other.0)
    }

    pub const fn without(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The names of the members, in [`Conserved::NAMES`]' order.
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .filter(|(c, _)| self.contains(*c))
            .map(|(_, name)| *name)
            .collect()
    }

    /// The set of the named invariants.
    ///
    /// # Errors
    /// An unknown name.
    pub fn from_names(names: &[&str]) -> Result<Self> {
        names.iter().try_fold(Self::NONE, |set, name| {
            match Self::NAMES.iter().find(|(_, n)| n == name) {
                Some((c, _)) => Ok(set.union(*c)),
                None => Err(crate::error::Error::invalid(
                    "keeps",
                    "must name energy, momentum, momentum_world, q_norm or jacobi",
                    name,
                )),
            }
        })
    }
}

/// A set of the registry's models ([`MODELS`]): what a system is made of, or what a method runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Kinds(u16);

impl Kinds {
    pub const NONE: Self = Self(0);
    /// The constant free body.
    pub const FREE: Self = Self(1);
    /// A prescribed, smooth `I(t)` ([`Deployment`]).
    pub const DEPLOYMENT: Self = Self(2);
    /// A spherical viscous damper ([`Damper`]).
    pub const DAMPER: Self = Self(4);
    /// Momentum wheels of constant relative momentum ([`super::Wheel`]).
    pub const WHEEL: Self = Self(8);
    /// The gravity gradient of a circular orbit ([`super::Torque::GravityGradient`]).
    pub const GRAVITY_GRADIENT: Self = Self(16);
    /// A constant external torque ([`super::Torque::Constant`]).
    pub const TORQUE: Self = Self(32);
    /// A torque tabulated at knots ([`super::TabulatedTorque`]).
    pub const TABULATED_TORQUE: Self = Self(64);
    /// Momentum wheels whose momentum follows a schedule ([`super::WheelSchedule`]).
    pub const WHEEL_SCHEDULE: Self = Self(128);
    /// A torque computed by the user's code ([`super::CallableTorque`]).
    pub const CALLABLE_TORQUE: Self = Self(256);

    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The names of the models in the set, in [`MODELS`]' order.
    pub fn names(self) -> Vec<&'static str> {
        MODELS
            .iter()
            .filter(|m| self.contains(m.kind))
            .map(|m| m.name)
            .collect()
    }

    /// What a system made of these models keeps: what each of them keeps, the Jacobi integral
    /// only where there is an orbit to measure it in.
    pub fn conserved(self) -> Conserved {
        let kept = MODELS
            .iter()
            .filter(|m| self.contains(m.kind))
            .fold(Conserved::FREE.union(Conserved::JACOBI), |c, m| {
                c.intersection(m.keeps)
            });
        match self.contains(Self::GRAVITY_GRADIENT) {
            true => kept,
            false => kept.without(Conserved::JACOBI),
        }
    }

    /// The first model of `self` that `runner` does not hold.
    pub fn first_missing(self, runner: Self) -> Option<&'static str> {
        MODELS
            .iter()
            .find(|m| self.contains(m.kind) && !runner.contains(m.kind))
            .map(|m| m.name)
    }
}

/// What is known about a model before it runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelInfo {
    pub kind: Kinds,
    /// The name users and the registry use.
    pub name: &'static str,
    /// What a system made of it (and the free body) keeps; a system keeps what each of its
    /// models keeps.
    pub keeps: Conserved,
    /// One line for users.
    pub about: &'static str,
}

/// The models, in the order users see them.
pub const MODELS: [ModelInfo; 9] = [
    ModelInfo {
        kind: Kinds::FREE,
        name: "free",
        keeps: Conserved::FREE,
        about: "the constant free rigid body (eq. 1)",
    },
    ModelInfo {
        kind: Kinds::DEPLOYMENT,
        name: "deployment",
        keeps: Conserved::MOMENTA,
        about: "a prescribed, smooth inertia tensor I(t) (dL/dt = L × ω, ω = I(t)⁻¹ L)",
    },
    ModelInfo {
        kind: Kinds::DAMPER,
        name: "damper",
        keeps: Conserved::MOMENTA,
        about: "a spherical viscous nutation damper (energy never rising)",
    },
    ModelInfo {
        kind: Kinds::WHEEL,
        name: "wheel",
        // with a gravity gradient too, the Jacobi integral stays kept (see `torques`)
        keeps: Conserved::MOMENTA.union(Conserved::JACOBI),
        about: "momentum wheels of constant relative momentum (a gyrostat: \
                I ω' = (I ω + Σ h a) × ω)",
    },
    ModelInfo {
        kind: Kinds::GRAVITY_GRADIENT,
        name: "gravity_gradient",
        keeps: Conserved::JACOBI.union(Conserved::Q_NORM),
        about: "the gravity gradient of a circular orbit in the world x–y plane \
                (τ = 3 n² r̂_b × I r̂_b; the Jacobi integral kept)",
    },
    ModelInfo {
        kind: Kinds::TORQUE,
        name: "torque",
        keeps: Conserved::Q_NORM,
        about: "a constant external torque in body or world axes (nothing kept but |q|)",
    },
    ModelInfo {
        kind: Kinds::TABULATED_TORQUE,
        name: "tabulated_torque",
        keeps: Conserved::Q_NORM,
        about: "a torque tabulated at knots in body or world axes, linear between them, zero \
                or held outside (nothing kept but |q|; every step ends on a knot)",
    },
    ModelInfo {
        kind: Kinds::WHEEL_SCHEDULE,
        name: "wheel_schedule",
        // the wheels' work changes the energy (and, in an orbit, the Jacobi integral)
        keeps: Conserved::MOMENTA,
        about: "momentum wheels whose momentum follows a schedule, linear between knots \
                (I ω' = (I ω + Σ h a) × ω − Σ ḣ a; |L| and L in space kept, the energy \
                changed by the wheels' work; every step ends on a knot)",
    },
    ModelInfo {
        kind: Kinds::CALLABLE_TORQUE,
        name: "callable_torque",
        keeps: Conserved::Q_NORM,
        about: "a torque computed by the user's function f(t, q, ω) in body axes, called at \
                each evaluation (Python speed; nothing kept but |q|)",
    },
];
