//! Sets the registry reads: what a model keeps ([`Conserved`]), which models a system is made of
//! ([`Kinds`]), and what a model asks of a method ([`Traits`]). The models themselves, and the
//! one place a system's sets are computed, are in [`super::registry`].

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
    /// The energy balance of a system whose parts dissipate: the energy plus the work its
    /// parts dissipated since the start (see [`super::GeneralModel`]).
    pub const ENERGY_BALANCE: Self = Self(32);
    /// What the constant free body keeps: energy, `|L|`, `L_world` and `|q|`.
    pub const FREE: Self = Self(1 | 2 | 4 | 8);
    /// What every torque-free model keeps: `|L|`, `L_world` and `|q|`.
    pub const MOMENTA: Self = Self(2 | 4 | 8);
    /// Every invariant a model may keep.
    pub const ALL: Self = Self(63);

    /// The names in [`crate::observe::Drift`]'s order, one per member.
    pub const NAMES: [(Self, &'static str); 6] = [
        (Self::ENERGY, "energy"),
        (Self::MOMENTUM, "momentum"),
        (Self::MOMENTUM_WORLD, "momentum_world"),
        (Self::Q_NORM, "q_norm"),
        (Self::JACOBI, "jacobi"),
        (Self::ENERGY_BALANCE, "energy_balance"),
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
}

/// A set of the registry's models ([`super::MODELS`]): what a system is made of. Bit `k` is
/// the `k`-th model of [`super::MODELS`]: the inertia laws first, then the parts in the
/// registry's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Kinds(pub(crate) u64);

impl Kinds {
    pub const NONE: Self = Self(0);
    /// The constant free body.
    pub const FREE: Self = Self(1);
    /// A prescribed, smooth `I(t)` ([`super::Deployment`]).
    pub const DEPLOYMENT: Self = Self(2);

    /// The model at index `k` of [`super::MODELS`].
    pub const fn at(k: usize) -> Self {
        Self(1 << k)
    }

    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The models of the set, in [`super::MODELS`]' order.
    pub fn models(self) -> impl Iterator<Item = &'static super::ModelInfo> {
        super::MODELS
            .iter()
            .enumerate()
            .filter(move |(k, _)| self.contains(Self::at(*k)))
            .map(|(_, m)| *m)
    }

    /// The names of the models in the set, in [`super::MODELS`]' order.
    pub fn names(self) -> Vec<&'static str> {
        self.models().map(|m| m.name).collect()
    }

    /// The model called `name`.
    pub fn named(name: &str) -> Option<Self> {
        super::MODELS
            .iter()
            .position(|m| m.name == name)
            .map(Self::at)
    }

    /// What a system made of these models keeps: what each of them keeps, an invariant a
    /// model defines (the Jacobi integral of an orbit) only where such a model is there, the
    /// energy balance only where a part dissipates (then the energy alone is not kept).
    pub fn conserved(self) -> Conserved {
        let mut kept = Conserved::ALL;
        let mut defined = Conserved::FREE;
        let mut dissipates = false;
        for m in self.models() {
            kept = kept.intersection(m.keeps);
            defined = defined.union(m.defines);
            dissipates |= m.energy == super::EnergyRole::Dissipates;
        }
        if dissipates {
            defined = defined.union(Conserved::ENERGY_BALANCE);
        }
        kept.intersection(defined)
    }

    /// What the models ask of a method: the union of their traits.
    pub fn traits(self) -> Traits {
        self.models().fold(Traits::NONE, |t, m| t.union(m.traits))
    }
}

/// What a model asks of a method that runs it, read from the models' declarations: a method
/// says which of these it handles ([`crate::run::MethodInfo::handles`]), and runs every model
/// whose traits it handles, the models of parts added later included.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Traits(u16);

impl Traits {
    /// Nothing: the constant free body.
    pub const NONE: Self = Self(0);
    /// The body's inertia changes over the run (a deployment).
    pub const CHANGING_BODY: Self = Self(1);
    /// Parts with state of their own (a damper's sphere).
    pub const PART_STATE: Self = Self(2);
    /// Parts storing angular momentum (a wheel's `h a`): the body's rates are not `I⁻¹ H`.
    pub const STORED_MOMENTUM: Self = Self(4);
    /// An external torque: `L` is not kept in space.
    pub const EXTERNAL_TORQUE: Self = Self(8);
    /// A torque depending on the body rates (not a function of time and attitude alone).
    pub const RATE_TORQUE: Self = Self(16);
    /// A law with kinks or jumps at given times: every step ends on them.
    pub const KINKS: Self = Self(32);
    /// A part evaluated at sample times of its own (a controller): every step ends on them,
    /// and the run calls the part there.
    pub const SAMPLED: Self = Self(64);
    /// A part whose mass moves in the body (a spring–mass damper, a hinged appendage, slosh):
    /// the body rates and the parts' come from one solve of the system's mass matrix.
    pub const MOVING_MASS: Self = Self(128);
    /// Every trait: what a method that runs any model handles.
    pub const ALL: Self = Self(255);

    /// The names of the traits, for users.
    pub const NAMES: [(Self, &'static str); 8] = [
        (Self::CHANGING_BODY, "changing body"),
        (Self::PART_STATE, "part state"),
        (Self::STORED_MOMENTUM, "stored momentum"),
        (Self::EXTERNAL_TORQUE, "external torque"),
        (Self::RATE_TORQUE, "rate-dependent torque"),
        (Self::KINKS, "kinks"),
        (Self::SAMPLED, "sample times"),
        (Self::MOVING_MASS, "moving mass"),
    ];

    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    pub const fn without(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The names of the members, in [`Traits::NAMES`]' order.
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .filter(|(c, _)| self.contains(*c))
            .map(|(_, name)| *name)
            .collect()
    }
}
