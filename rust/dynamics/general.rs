//! The general model: a body whose inertia is constant or prescribed ([`Deployment`]), with
//! internal parts ([`Damper`], [`super::Wheel`]s) and external torques ([`Torques`]), in the total
//! angular momentum.
//!
//! **State** `[H (3), σ (3, with a damper), q (4)]`: `H` the total angular momentum in body
//! axes, `σ` a damper's sphere rates, `q` the attitude. With `I(t)` the body's tensor (a
//! damper's mass counted as a point at its centre) and `j` the sphere's moment,
//!
//! ```text
//! ω  = I(t)⁻¹ (H − j σ − Σ h a)          the body's own momentum, solved for its rates
//! H' = H × ω + τ_b(t, q)                 without torques H is fixed in space
//! σ' = σ × ω − (c / j) (σ − ω)           the damper (see [`Damper`])
//! q' = ½ q ⊗ (0, ω)
//! ```
//!
//! A deployment alone is `L' = L × ω, ω = I(t)⁻¹ L` (see [`Deployment`]); a damped body alone
//! is Hughes's spherical damper; wheels of constant momentum `h` along axes `a` make a
//! gyrostat (see [`super::Wheel`]); `τ_b` is the sum of the external torques in body axes (see
//! [`Torques`]: the gravity gradient of a circular orbit, constant torques). Without torques
//! every such model keeps `|H|` and `H` in space exactly; a deployment or a damper does not
//! keep the energy (internal work, loss). With the gravity gradient alone (and constant
//! wheels) the Jacobi integral is kept ([`Model::jacobi`]).

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::ode::OdeSystem;

use super::kinds::Kinds;
use super::model::{
    attitude, mid_axis_of, quaternion_increment, set_attitude, Conserved, MidAxis, Model,
    MomentumProjection,
};
use super::{Damper, Deployment, Table, Torques};

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

/// The general model (see the module doc); `N` is 7, or 10 with a damper.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralModel<const N: usize> {
    inertia: InertiaLaw,
    /// The damper, when `N` is 10 (a placeholder otherwise, never read).
    damper: Damper,
    /// The wheels' total momentum `Σ h a` in body axes, if there are wheels.
    wheels: Option<Vector3<f64>>,
    /// The scheduled wheels' `h(t) a` in body axes (see [`super::WheelSchedule`]).
    schedules: Vec<Table>,
    torques: Torques,
    kinds: Kinds,
    /// Where the right-hand side has a kink or a jump (tabulated laws): every step ends there.
    kinks: Vec<f64>,
    /// Where it is not smooth: the kinks and a deployment's knots (adaptive steps end there).
    knots: Vec<f64>,
}

/// # Construction
impl<const N: usize> GeneralModel<N> {
    /// A body of inertia `inertia` with `damper`, if any (then `N` must be 10, else 7).
    ///
    /// # Errors
    /// A state size that does not fit the parts (a bug in the caller).
    pub fn try_new(inertia: InertiaLaw, damper: Option<Damper>) -> Result<Self> {
        if N != 7 + 3 * usize::from(damper.is_some()) {
            return Err(Error::invalid(
                "parts",
                "must fit the model's state (at most one damper)",
                N,
            ));
        }
        let mut kinds = match inertia {
            InertiaLaw::Constant(_) => Kinds::NONE,
            InertiaLaw::Schedule(_) => Kinds::DEPLOYMENT,
        };
        if damper.is_some() {
            kinds = kinds.union(Kinds::DAMPER);
        }
        if kinds == Kinds::NONE {
            kinds = Kinds::FREE;
        }
        Ok(Self {
            inertia,
            damper: damper.unwrap_or(Damper::try_new(1.0, 0.0)?),
            wheels: None,
            schedules: Vec::new(),
            torques: Torques::default(),
            kinds,
            kinks: Vec::new(),
            knots: Vec::new(),
        }
        .with_kinds())
    }

    /// The same model with wheels of total momentum `wheels` (`Σ h a`, body axes), if any.
    pub fn with_wheels(mut self, wheels: Option<Vector3<f64>>) -> Self {
        self.wheels = wheels;
        self.with_kinds()
    }

    /// The same model with wheels of scheduled momentum, each `h(t) a` in body axes.
    pub fn with_schedules(mut self, schedules: Vec<Table>) -> Self {
        self.schedules = schedules;
        self.with_kinds()
    }

    /// The same model with the external torques `torques`.
    pub fn with_torques(mut self, torques: Torques) -> Self {
        self.torques = torques;
        self.with_kinds()
    }

    fn with_kinds(mut self) -> Self {
        let mut kinds = match self.inertia {
            InertiaLaw::Constant(_) => Kinds::NONE,
            InertiaLaw::Schedule(_) => Kinds::DEPLOYMENT,
        };
        if self.has_damper() {
            kinds = kinds.union(Kinds::DAMPER);
        }
        if self.wheels.is_some() {
            kinds = kinds.union(Kinds::WHEEL);
        }
        if !self.schedules.is_empty() {
            kinds = kinds.union(Kinds::WHEEL_SCHEDULE);
        }
        kinds = kinds.union(self.torques.kinds());
        self.kinds = match kinds == Kinds::NONE {
            true => Kinds::FREE,
            false => kinds,
        };
        self.with_knots()
    }

    /// The kinks and knots of the model's laws (see the fields).
    fn with_knots(mut self) -> Self {
        let mut kinks = self.torques.kinks();
        for s in &self.schedules {
            kinks.extend_from_slice(s.times());
        }
        kinks.sort_by(f64::total_cmp);
        kinks.dedup();
        self.kinks = kinks;
        let mut knots = self.kinks.clone();
        if let InertiaLaw::Schedule(d) = &self.inertia {
            knots.extend_from_slice(d.times());
        }
        knots.sort_by(f64::total_cmp);
        knots.dedup();
        self.knots = knots;
        self
    }

    /// The state at `t0` from the body rates `omega0`, the damper's rates `sigma0` and the
    /// attitude `q0`.
    pub fn state_from(
        &self,
        t0: f64,
        omega0: [f64; 3],
        sigma0: [f64; 3],
        q0: [f64; 4],
    ) -> [f64; N] {
        let omega = Vector3::from(omega0);
        let sigma = Vector3::from(sigma0);
        let mut h = self.inertia.tensor_at(t0) * omega + self.wheels.unwrap_or_default();
        for s in &self.schedules {
            h += s.at(t0);
        }
        if self.has_damper() {
            h += sigma * self.damper.sphere();
        }
        let mut x = [0.0; N];
        x[..3].copy_from_slice(h.as_slice());
        if self.has_damper() {
            x[3..6].copy_from_slice(&sigma0);
        }
        x[N - 4..].copy_from_slice(&q0);
        x
    }

    /// The inertia law.
    pub fn inertia(&self) -> &InertiaLaw {
        &self.inertia
    }

    /// The damper, if any.
    pub fn damper(&self) -> Option<&Damper> {
        self.has_damper().then_some(&self.damper)
    }

    /// Whether it has wheels (constant or scheduled).
    pub fn has_wheels(&self) -> bool {
        self.wheels.is_some() || !self.schedules.is_empty()
    }

    #[inline(always)]
    const fn has_damper(&self) -> bool {
        N == 10
    }
}

/// # The parts of a state
impl<const N: usize> GeneralModel<N> {
    #[inline(always)]
    fn sigma(x: &[f64; N]) -> Vector3<f64> {
        Vector3::new(x[3], x[4], x[5])
    }

    /// The body's own angular momentum `H − j σ − Σ h a` at `t`.
    #[inline(always)]
    fn body_momentum(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        let mut h = Vector3::new(x[0], x[1], x[2]);
        if let Some(w) = self.wheels {
            h -= w;
        }
        for s in &self.schedules {
            h -= s.at(t);
        }
        match self.has_damper() {
            true => h - Self::sigma(x) * self.damper.sphere(),
            false => h,
        }
    }

    /// The external torque in body axes at `(t, x)`.
    #[inline(always)]
    pub(crate) fn torque(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        let tau = self
            .torques
            .torque_body(t, &attitude(x), |v| self.inertia.apply(t, v));
        match self.torques.has_callables() {
            false => tau,
            true => tau + (self.torques).callables_body(t, &attitude(x), &self.omega_body(t, x)),
        }
    }
}

impl<const N: usize> OdeSystem<N> for GeneralModel<N> {
    #[inline(always)]
    fn increment(&self, t: f64, x: &[f64; N], s: f64) -> [f64; N] {
        let h = Vector3::new(x[0], x[1], x[2]);
        let omega = self.inertia.omega_from(t, &self.body_momentum(t, x));
        let mut dh = h.cross(&omega);
        if !self.torques.is_empty() {
            dh += self.torque(t, x);
        }
        let dh = dh * s;
        let mut dx = [0.0; N];
        dx[..3].copy_from_slice(dh.as_slice());
        if self.has_damper() {
            let dsigma = self.damper.sigma_rate(&omega, &Self::sigma(x)) * s;
            dx[3..6].copy_from_slice(dsigma.as_slice());
        }
        let dq = quaternion_increment([x[N - 4], x[N - 3], x[N - 2], x[N - 1]], omega, s);
        dx[N - 4..].copy_from_slice(&dq);
        dx
    }
}

impl<const N: usize> Model<N> for GeneralModel<N> {
    /// `|H|` and `H` in space at the start.
    type Kept = MomentumProjection;

    fn conserved(&self) -> Conserved {
        self.kinds.conserved()
    }

    fn kinds(&self) -> Kinds {
        self.kinds
    }

    #[inline(always)]
    fn omega_body(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        self.inertia.omega_from(t, &self.body_momentum(t, x))
    }

    #[inline(always)]
    fn momentum_body(&self, _t: f64, x: &[f64; N]) -> Vector3<f64> {
        Vector3::new(x[0], x[1], x[2])
    }

    /// `H' = H × ω + τ_b`.
    #[inline(always)]
    fn momentum_rate(&self, t: f64, x: &[f64; N]) -> Vector3<f64> {
        let h = self.momentum_body(t, x).cross(&self.omega_body(t, x));
        match self.torques.is_empty() {
            true => h,
            false => h + self.torque(t, x),
        }
    }

    /// With a gravity gradient: `J = T − n ẑ_b · H + (3/2) n² r̂_bᵀ I r̂_b` (see [`Torques`]).
    fn jacobi(&self, t: f64, x: &[f64; N]) -> Option<f64> {
        self.torques.jacobi(
            t,
            &attitude(x),
            &self.inertia.tensor_at(t),
            self.energy(t, x),
            &self.momentum_body(t, x),
        )
    }

    fn energy(&self, t: f64, x: &[f64; N]) -> f64 {
        let l = self.body_momentum(t, x);
        let body = 0.5 * l.dot(&self.inertia.omega_from(t, &l));
        match self.has_damper() {
            true => body + 0.5 * self.damper.sphere() * Self::sigma(x).norm_squared(),
            false => body,
        }
    }

    /// `(|H| + |Σ h a|) / λ_min` without a damper (`|ω| = |I⁻¹ (H − Σ h a)|`);
    /// `√(2T / λ_min)` with one (the total energy `T ≥ ½ ωᵀ I ω` never rises). The sphere's
    /// rates turn at the body's; its slip decays at the damper's own rate, the model's
    /// [`Model::stiffness`]. With a gravity gradient, the larger of that and the bound the
    /// Jacobi integral gives ([`Torques::rate_bound`]). A constant torque spins the body up
    /// without bound: the bound is the start's, and a long run under one wants an adaptive
    /// method or a `dt` of its own.
    fn rate_bound(&self, x0: &[f64; N]) -> f64 {
        let least = self.inertia.least();
        // a schedule's |h a| is largest at one of its knots (linear between them)
        let scheduled: f64 = (self.schedules.iter())
            .map(|s| s.values().iter().fold(0.0, |m: f64, v| m.max(v.norm())))
            .sum();
        let wheels = self.wheels.map_or(0.0, |w| w.norm()) + scheduled;
        let free = match self.has_damper() {
            true => (2.0 * self.energy(0.0, x0) / least).sqrt(),
            false => (self.momentum_body(0.0, x0).norm() + wheels) / least,
        };
        let orbit = self.jacobi(0.0, x0).and_then(|j| {
            let largest = self.inertia.tensor_at(0.0).symmetric_eigenvalues().max();
            self.torques.rate_bound(least, largest, j, wheels)
        });
        free.max(orbit.unwrap_or(0.0))
    }

    fn stiffness(&self) -> f64 {
        match self.has_damper() {
            true => self.damper.slip_rate(self.inertia.least()),
            false => 0.0,
        }
    }

    /// A damper only takes energy (`T' = −c |σ − ω|²`); a deployment's internal forces can
    /// give it.
    fn energy_never_grows(&self) -> bool {
        self.has_damper() && matches!(self.inertia, InertiaLaw::Constant(_))
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

    fn kept(&self, t0: f64, x0: &[f64; N]) -> MomentumProjection {
        MomentumProjection::new(self.momentum_body(t0, x0), &attitude(x0))
    }

    /// `H` (and the damper's rates with it) scaled back to `|H₀|`, `q` normalised and turned
    /// so that `H` in space has its initial direction.
    #[inline]
    fn project(&self, kept: &MomentumProjection, t: f64, x: &mut [f64; N]) {
        let (factor, q) = kept.restore(&self.momentum_body(t, x), &attitude(x));
        for v in &mut x[..N - 4] {
            *v *= factor;
        }
        set_attitude(x, &q);
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        let inertia = match &self.inertia {
            InertiaLaw::Constant(c) => InertiaLaw::Constant(*c),
            InertiaLaw::Schedule(d) => InertiaLaw::Schedule(d.in_units(scale)?),
        };
        let damper = match self.has_damper() {
            true => Some(self.damper.in_units(scale)?),
            false => None,
        };
        let wheels = self.wheels.map(|w| w.map(|v| scale.rate_to_unit(v)));
        let to_unit = |v: Vector3<f64>| v.map(|c| scale.rate_to_unit(c));
        let schedules = (self.schedules.iter())
            .map(|s| s.in_units(scale, to_unit, "momentum"))
            .collect::<Result<Vec<_>>>()?;
        // the knots follow the laws' times, rebuilt in the run's units
        Ok(Self::try_new(inertia, damper)?
            .with_wheels(wheels)
            .with_schedules(schedules)
            .with_torques(self.torques.in_units(scale)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn tilted() -> Deployment {
        let a = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let b = Matrix3::new(5.0, 0.4, -0.2, 0.4, 3.5, 0.0, -0.2, 0.0, 2.5);
        Deployment::try_new(vec![1.0, 3.0], vec![a, b]).unwrap()
    }

    fn damped() -> GeneralModel<10> {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        GeneralModel::try_new(
            InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap()),
            Some(Damper::try_new(0.2, 0.05).unwrap()),
        )
        .unwrap()
    }

    /// The state advanced by `±h` along the right-hand side (a central difference's ends).
    fn along<const N: usize>(m: &GeneralModel<N>, t: f64, x: &[f64; N], h: f64) -> [f64; N] {
        let dx = m.rhs(t, x);
        std::array::from_fn(|k| x[k] + h * dx[k])
    }

    #[test]
    fn a_deployments_energy_changes_at_minus_half_omega_idot_omega() {
        let m = GeneralModel::<7>::try_new(InertiaLaw::Schedule(tilted()), None).unwrap();
        let x = m.state_from(2.2, [0.3, -0.7, 1.1], [0.0; 3], [0.5, -0.1, 0.7, 0.2]);
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
    }

    #[test]
    fn a_dampers_energy_falls_at_c_times_the_slip_squared() {
        let m = damped();
        let x = m.state_from(0.0, [0.3, -0.7, 1.1], [0.2, 0.1, 0.9], [1.0, 0.0, 0.0, 0.0]);
        let h = 1e-6;
        let numeric = (m.energy(0.0, &along(&m, 0.0, &x, h))
            - m.energy(0.0, &along(&m, 0.0, &x, -h)))
            / (2.0 * h);
        let slip = Vector3::new(0.2, 0.1, 0.9) - Vector3::new(0.3, -0.7, 1.1);
        assert_relative_eq!(numeric, -0.05 * slip.norm_squared(), max_relative = 1e-7);
    }

    #[test]
    fn the_rates_are_those_the_state_was_built_from() {
        let m = damped();
        let x = m.state_from(0.0, [0.3, -0.7, 1.1], [0.2, 0.1, 0.9], [1.0, 0.0, 0.0, 0.0]);
        let omega = m.omega_body(0.0, &x);
        assert!((omega - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-15);
    }

    fn orbiting(wheels: Option<Vector3<f64>>, torques: &[super::super::Torque]) -> GeneralModel<7> {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        GeneralModel::try_new(
            InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap()),
            None,
        )
        .unwrap()
        .with_wheels(wheels)
        .with_torques(Torques::of(torques).unwrap())
    }

    /// `dJ/dt` along the right-hand side by a central difference.
    fn jacobi_rate(m: &GeneralModel<7>, t: f64, x: &[f64; 7]) -> f64 {
        let h = 1e-6;
        let j = |s: f64| m.jacobi(t + s, &along(m, t, x, s)).unwrap();
        (j(h) - j(-h)) / (2.0 * h)
    }

    #[test]
    fn the_jacobi_integral_is_stationary_in_the_gravity_gradient_with_wheels() {
        let gg = super::super::Torque::gravity_gradient(0.8).unwrap();
        let m = orbiting(
            Some(Vector3::new(0.3, -0.5, 0.7)),
            std::slice::from_ref(&gg),
        );
        assert_eq!(m.conserved().names(), ["q_norm", "jacobi"]);
        let q = [0.6, -0.2, 0.7, 0.3];
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        let x = m.state_from(1.3, [0.3, -0.7, 1.1], [0.0; 3], q.map(|v| v / n));
        let j = m.jacobi(1.3, &x).unwrap();
        assert!(jacobi_rate(&m, 1.3, &x).abs() < 1e-8 * j.abs().max(1.0));
        // a constant torque breaks it, and the model no longer declares it
        let push = super::super::Torque::constant([0.0, 0.2, 0.1], super::super::Frame::Body);
        let pushed = orbiting(None, &[gg, push.unwrap()]);
        assert!(jacobi_rate(&pushed, 1.3, &x).abs() > 1e-3);
        assert_eq!(pushed.conserved().names(), ["q_norm"]);
    }

    #[test]
    fn wheels_keep_the_momentum_in_space_and_the_bodys_energy() {
        let m = orbiting(Some(Vector3::new(0.3, -0.5, 0.7)), &[]);
        let x = m.state_from(0.0, [0.3, -0.7, 1.1], [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
        let h = 1e-6;
        let e = |s: f64| m.energy(s, &along(&m, 0.0, &x, s));
        assert!(((e(h) - e(-h)) / (2.0 * h)).abs() < 1e-9);
        // H' = H × ω: |H| stationary
        let dh = m.momentum_rate(0.0, &x);
        assert!(dh.dot(&m.momentum_body(0.0, &x)).abs() < 1e-14);
        assert!((m.omega_body(0.0, &x) - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-15);
    }

    #[test]
    fn a_state_size_that_does_not_fit_the_parts_is_refused() {
        let i = ConstantInertia::try_new(Matrix3::identity()).unwrap();
        assert!(GeneralModel::<10>::try_new(InertiaLaw::Constant(i), None).is_err());
    }
}
