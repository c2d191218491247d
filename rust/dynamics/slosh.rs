//! Pendulum slosh: the equivalent mechanical model of a tank's first sloshing mode, a point
//! mass `m` on a massless rod of length `l` from a pivot `p` of the body, free to swing in
//! every direction, with a viscous torque `−c ν` at the pivot (`ν` the rod's angular velocity
//! relative to the body) — Abramson, *The Dynamic Behavior of Liquids in Moving Containers*,
//! NASA SP-106, 1966; Dodge, *The New Dynamic Behavior of Liquids in Moving Containers*, 2000.
//!
//! **No angles.** The rod's direction is a unit vector `n` (body axes) and the state holds it
//! with the rod's conjugate momentum `π` (3 + 3 numbers): two angles would be singular at
//! their poles. The mass is at `r = p + l n`, moving at `ṙ = l ν × n` relative to the body;
//! `ν ⊥ n` (a turn about the rod moves nothing). Varying the rod's direction by a small turn
//! `η` (`δn = η × n`, `δν = η̇ + η × ν`), Hamilton's principle with the dissipation gives the
//! Euler–Poincaré equations
//!
//! ```text
//! n' = ν × n
//! π' = ν × π + n × ∂T/∂n − c ν,      π = ∂T/∂ν = l m n × (u − P/M),
//! ∂T/∂n = l m (u − P/M) × (ω + ν)    (at fixed ω, ν; u = ω × r + ṙ)
//! ```
//!
//! Both keep `|n| = 1` and `π · n = 0` exactly (`(π · n)' = (ν × π)·n + π·(ν × n) = 0`). The
//! joint solve takes the rod's rates in a basis `t₁, t₂` of the plane normal to `n`
//! (`ν = a t₁ + b t₂`, `ṙ = l (b t₁ − a t₂)` for `t₂ = n × t₁`, momenta `π · t₁`, `π · t₂`),
//! picked afresh at each evaluation: the equations read only `n/|n|` and `π`'s part normal to it, so
//! integration error in `|n|` or `π · n` (of the order of the method's, and measured) never
//! feeds back into the motion. There is no spring: on a spinning body the centrifugal field is
//! the pendulum's restoring force. `V = 0`, the dissipated power `c |ν|²`.
//!
//! **Alone on its hub** ([`LoneSlosh`]) no basis is needed. With `μ = m M_h/M` and
//! `u = ω × r + ṙ` (the mass's velocity relative to the hub's mass centre), `π = lμ n × u`
//! gives `u`'s part normal to the rod, `u⊥ = π × n/(lμ)`, and `u · n = −ω · w` with
//! `w = n × r = n × p` (the rod is stiff along itself). Then `H = I_h ω + μ r × u` becomes
//!
//! ```text
//! (I_h + μ w wᵀ) ω = H − π⊥ − p × (π × n)/l
//! ```
//!
//! a rank-one update of the hub's tensor, solved by Sherman–Morrison with `I_h⁻¹` computed
//! once (its division `1/(1 + μ wᵀI_h⁻¹w)` waits only for `n`); then
//! `u = π × n/(lμ) − (ω·w) n`, `ν = n × (u − ω × r)/l = (π⊥/(lμ) − (n·r) ω + (n·ω) r)/l`, and
//! the equations above with `n × ∂T/∂n = lμ n × (u × (ω + ν)) = (n·ω) π × n +
//! lμ (ω·w)(ω + ν − (n·ω) n)`: `u` itself is never formed, and `ν` waits only for `ω`.

use nalgebra::Vector3;

use crate::error::Result;

use super::moving::{checked, point};
use super::multibody::{Alone, AloneSolve, Carried, Hub, Sym3};

/// A slosh pendulum (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slosh {
    mass: f64,
    pivot: Vector3<f64>,
    length: f64,
    damping: f64,
    /// The rod's direction and relative angular velocity at the start.
    direction0: Vector3<f64>,
    rate0: Vector3<f64>,
}

/// The rod at one direction: `n` normalised and a basis `t₁, t₂` of the plane normal to it,
/// orthogonal and of equal length (`t₁ = n × a`, `a` the body axis `n` is least along, so
/// `|t₁|² ≥ 2/3`; `t₂ = n × t₁`). The basis is not normalised: the joint solve takes the rates
/// in any basis, and the right-hand side never needs it to be.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rod {
    pub direction: Vector3<f64>,
    pub t1: Vector3<f64>,
    pub t2: Vector3<f64>,
}

impl Rod {
    /// The rod along `n` (any non-zero length).
    #[inline(always)]
    pub fn along(n: &Vector3<f64>) -> Self {
        let direction = n * (1.0 / n.norm());
        let a = direction.map(f64::abs);
        let t1 = match (a.x <= a.y, a.x <= a.z, a.y <= a.z) {
            (true, true, _) => Vector3::new(0.0, direction.z, -direction.y),
            (false, _, true) => Vector3::new(-direction.z, 0.0, direction.x),
            _ => Vector3::new(direction.y, -direction.x, 0.0),
        };
        Self {
            direction,
            t1,
            t2: direction.cross(&t1),
        }
    }

    /// `ν = a t₁ + b t₂` of the rates `[a, b]`.
    #[inline(always)]
    pub fn spin(&self, rates: [f64; 2]) -> Vector3<f64> {
        self.t1 * rates[0] + self.t2 * rates[1]
    }

    /// The rates `[a, b]` of an angular velocity `nu` (its part along the rod left out).
    pub fn rates_of(&self, nu: &Vector3<f64>) -> [f64; 2] {
        let s = self.t1.norm_squared();
        [nu.dot(&self.t1) / s, nu.dot(&self.t2) / s]
    }

    /// The momentum `π` normal to the rod whose components are `momenta` (`π · t₁`, `π · t₂`).
    pub fn momentum_of(&self, momenta: [f64; 2]) -> Vector3<f64> {
        (self.t1 * momenta[0] + self.t2 * momenta[1]) / self.t1.norm_squared()
    }

    /// `π`'s part normal to the rod.
    #[inline(always)]
    pub fn normal_part(&self, pi: &Vector3<f64>) -> Vector3<f64> {
        pi - self.direction * self.direction.dot(pi)
    }
}

impl Slosh {
    /// A mass `mass` on a rod of length `length` from `pivot`, with pivot damping `damping`.
    ///
    /// # Errors
    /// A mass or length that is not positive, a damping that is negative, any not finite; a
    /// pivot that is not finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Slosh;
    /// assert!(Slosh::try_new(0.1, [0.0, 0.0, 3.0], 0.5, 0.01).is_ok());
    /// assert!(Slosh::try_new(0.1, [0.0, 0.0, 3.0], 0.0, 0.01).is_err());
    /// ```
    pub fn try_new(mass: f64, pivot: [f64; 3], length: f64, damping: f64) -> Result<Self> {
        Ok(Self {
            mass: checked("mass", mass, true)?,
            pivot: point("pivot", pivot)?,
            length: checked("length", length, true)?,
            damping: checked("damping", damping, false)?,
            direction0: Vector3::x(),
            rate0: Vector3::zeros(),
        })
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    pub fn pivot(&self) -> Vector3<f64> {
        self.pivot
    }

    pub fn length(&self) -> f64 {
        self.length
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// What it carries with the rod `rod`, its rates `[a, b]` about `t₁`, `t₂`.
    #[inline(always)]
    pub fn carried(&self, rod: &Rod) -> Carried {
        let l = self.length;
        Carried::point(
            self.mass,
            self.pivot + rod.direction * l,
            &[-rod.t2 * l, rod.t1 * l],
        )
    }

    /// The momenta `[π · t₁, π · t₂]` the joint solve takes.
    #[inline(always)]
    pub fn momenta(&self, rod: &Rod, pi: &Vector3<f64>) -> [f64; 2] {
        [pi.dot(&rod.t1), pi.dot(&rod.t2)]
    }

    /// `(n', π')` of the stored direction `n` and momentum `pi`, with the rod `rod` (of `n`),
    /// its angular velocity `nu` relative to the body, the body rates `omega` and the mass's
    /// velocity `velocity` in the frame of the mass centre.
    #[inline(always)]
    pub fn rates(
        &self,
        n: &Vector3<f64>,
        pi: &Vector3<f64>,
        rod: &Rod,
        nu: &Vector3<f64>,
        omega: &Vector3<f64>,
        velocity: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let dn = nu.cross(n);
        let pull = velocity.cross(&(omega + nu)) * (self.length * self.mass);
        let dpi = nu.cross(&rod.normal_part(pi)) + rod.direction.cross(&pull) - nu * self.damping;
        (dn, dpi)
    }

    /// The power the damping takes, `c |ν|²`.
    pub fn dissipation(&self, nu: &Vector3<f64>) -> f64 {
        self.damping * nu.norm_squared()
    }
}

/// A slosh pendulum alone on its hub: the joint solve and the rates in closed form (see the
/// module doc), the hub's inverse tensor computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoneSlosh {
    part: Slosh,
    /// `I_h⁻¹`.
    inverse: Sym3,
    /// `μ`, `lμ`, `1/l`.
    reduced: f64,
    moment: f64,
    inv_length: f64,
    /// `1/(l²μ)`, `p/l`.
    inv_spread: f64,
    lever: Vector3<f64>,
}

/// `1/|n|` of a direction kept near unit length: `(1 + δ)^(-1/2)`, `δ = |n|² − 1`, by its
/// series to `δ²` where `|δ| < 5·10⁻⁶` (error `5|δ|³/16 < 4·10⁻¹⁷`, below round-off; no square
/// root or division on the evaluation's path), else exactly.
#[inline(always)]
fn inverse_norm(n: &Vector3<f64>) -> f64 {
    let delta = n.norm_squared() - 1.0;
    match delta.abs() < 5e-6 {
        true => 1.0 + delta * (0.375 * delta - 0.5),
        false => 1.0 / (1.0 + delta).sqrt(),
    }
}

/// The body's and the rod's rates of a [`LoneSlosh`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SloshRates {
    /// `ω`, body axes.
    pub omega: Vector3<f64>,
    /// `ν`, the rod's angular velocity relative to the body.
    pub nu: Vector3<f64>,
    /// `n'`, `π'`.
    pub direction: Vector3<f64>,
    pub momentum: Vector3<f64>,
}

impl LoneSlosh {
    /// `part` alone on `hub` (whose total mass counts the part's).
    pub fn new(hub: &Hub, part: Slosh) -> Self {
        let mu = hub.reduced_mass(part.mass);
        let moment = part.length * mu;
        Self {
            part,
            inverse: Sym3::of(hub.inertia()).inverse(),
            reduced: mu,
            moment,
            inv_length: 1.0 / part.length,
            inv_spread: 1.0 / (moment * part.length),
            lever: part.pivot / part.length,
        }
    }

    pub fn part(&self) -> &Slosh {
        &self.part
    }

    /// The rates from the angular momentum `h` (body axes), the stored direction `n` (any
    /// length; its direction is read) and momentum `pi` (its part normal to the rod is read).
    #[inline(always)]
    pub fn rates(&self, h: &Vector3<f64>, n: &Vector3<f64>, pi: &Vector3<f64>) -> SloshRates {
        let unit = n * inverse_norm(n);
        let normal = pi - unit * unit.dot(pi);
        let lead = normal.cross(&unit);
        let pivot = &self.part.pivot;
        let w = unit.cross(pivot);
        let z = self.inverse.apply(&w);
        // what waits only for n, off the path through π and H: the division among it
        let scale = self.reduced / (1.0 + self.reduced * w.dot(&z));
        let reach = (unit.dot(pivot) + self.part.length) * self.inv_length;
        let arm = pivot * self.inv_length + unit;
        let y = self.inverse.apply(&(h - normal - self.lever.cross(&lead)));
        let omega = y - z * (w.dot(&y) * scale);
        // ν = n × (u − ω × r)/l, n × u = π⊥/(lμ), n × (ω × r) = (n·r) ω − (n·ω) r
        let along = unit.dot(&omega);
        let nu = normal * self.inv_spread - omega * reach + arm * along;
        // n × ∂T/∂n = lμ n × (u × Ω) = lμ ((n·Ω) u − (n·u) Ω), n·Ω = n·ω, n·u = −ω·w
        let torque = lead * along + (omega + nu - unit * along) * (self.moment * omega.dot(&w));
        SloshRates {
            omega,
            nu,
            direction: nu.cross(n),
            momentum: nu.cross(&normal) + torque - nu * self.part.damping,
        }
    }
}

use super::moving::{mover_hooks, moving_info, unit, Mover};
use super::multibody::PART_RATES;
use super::part::{Ctx, Dim, Field, Fields, ModelInfo, Param, ParamKind, Part};
use crate::error::Error;
use crate::float::{ldexp, RateScale};

#[inline(always)]
fn vector(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl Alone for LoneSlosh {
    #[inline(always)]
    fn increment(
        &self,
        h: &Vector3<f64>,
        x: &[f64],
        s: f64,
        dx: &mut [f64],
    ) -> (Vector3<f64>, f64) {
        let r = self.rates(
            h,
            &Vector3::new(x[0], x[1], x[2]),
            &Vector3::new(x[3], x[4], x[5]),
        );
        for k in 0..3 {
            dx[k] = r.direction[k] * s;
            dx[3 + k] = r.momentum[k] * s;
        }
        (r.omega, self.part.dissipation(&r.nu))
    }

    fn omega(&self, h: &Vector3<f64>, x: &[f64]) -> Vector3<f64> {
        let (n, pi) = (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]),
        );
        self.rates(h, &n, &pi).omega
    }

    fn kinetic(&self, h: &Vector3<f64>, x: &[f64]) -> f64 {
        let (n, pi) = (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]),
        );
        let r = self.rates(h, &n, &pi);
        0.5 * (r.omega.dot(h) + r.nu.dot(&pi))
    }
}

impl Mover for Slosh {
    const RATES: usize = 2;

    fn mover_mass(&self) -> f64 {
        self.mass
    }

    fn lone(&self, hub: &Hub) -> AloneSolve {
        AloneSolve::Slosh(LoneSlosh::new(hub, *self))
    }

    #[inline(always)]
    fn carry(&self, x: &[f64]) -> (Carried, [f64; PART_RATES]) {
        let rod = Rod::along(&vector(x));
        let [a, b] = Slosh::momenta(self, &rod, &vector(&x[3..]));
        (Slosh::carried(self, &rod), [a, b, 0.0])
    }

    fn begin(&self, x: &mut [f64]) {
        x[..3].copy_from_slice(self.direction0.as_slice());
        x[3..6].copy_from_slice(self.rate0.as_slice());
    }

    fn begin_rates(&self, x: &[f64]) -> [f64; PART_RATES] {
        let [a, b] = Rod::along(&vector(x)).rates_of(&vector(&x[3..]));
        [a, b, 0.0]
    }

    fn put_momenta(&self, x: &mut [f64], p: &[f64]) {
        let pi = Rod::along(&vector(x)).momentum_of([p[0], p[1]]);
        x[3..6].copy_from_slice(pi.as_slice());
    }
}

impl Part for Slosh {
    const INFO: ModelInfo = moving_info(
        "slosh",
        "a tank's first sloshing mode as a spherical pendulum damped at its pivot, free of angle singularities",
        &[
            Param::new("mass", ParamKind::Scalar, "the sloshing mass (positive)"),
            Param::new("pivot", ParamKind::Vector, "the pivot, from the body's mass centre, body axes"),
            Param::new("length", ParamKind::Scalar, "the rod's length (positive)"),
            Param::new("damping", ParamKind::Scalar, "the pivot's viscous c: torque per relative rate"),
            Param::new("direction0", ParamKind::Vector, "the rod's direction at the start, body axes"),
            Param::new("rate0", ParamKind::Vector, "the rod's angular velocity relative to the body at the start (0)").optional(),
        ],
        &[
            Field { name: "direction", width: 3, body_vector: true, dim: Dim::NONE, about: "n" },
            Field { name: "momentum", width: 3, body_vector: true, dim: Dim::MOMENTUM, about: "π" },
        ],
    );

    fn from_fields(fields: &Fields) -> Result<Self> {
        let mut s = Self::try_new(
            fields.number("mass")?,
            fields.vector("pivot")?,
            fields.number("length")?,
            fields.number("damping")?,
        )?;
        s.direction0 = unit("direction0", fields.vector("direction0")?)?;
        let r = fields.optional_vector("rate0")?.unwrap_or([0.0; 3]);
        if !r.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid("rate0", "must be three finite rates", r));
        }
        s.rate0 = Vector3::from(r);
        Ok(s)
    }

    mover_hooks!();

    #[inline(always)]
    fn rates(&self, c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        if let Some(m) = &c.moving {
            let n = vector(x);
            // the rod the solve built: l n̂ = r − p, its rates' columns −l t₂, l t₁
            let inv = 1.0 / self.length;
            let carried = m.carried;
            let rod = Rod {
                direction: (carried.centre - self.pivot) * inv,
                t1: carried.linear[1] * inv,
                t2: -carried.linear[0] * inv,
            };
            let nu = rod.spin([m.rates[0], m.rates[1]]);
            let (dn, dpi) =
                Slosh::rates(self, &n, &vector(&x[3..]), &rod, &nu, &c.omega, &m.velocity);
            dx[..3].copy_from_slice(dn.as_slice());
            dx[3..6].copy_from_slice(dpi.as_slice());
        }
    }

    fn energy(&self, _t: f64, _x: &[f64]) -> f64 {
        0.0
    }

    #[inline(always)]
    fn dissipation(&self, c: &Ctx<'_>, _x: &[f64]) -> f64 {
        c.moving.map_or(0.0, |m| {
            let r = m.carried.linear[0] * m.rates[0] + m.carried.linear[1] * m.rates[1];
            self.damping * r.norm_squared() / (self.length * self.length)
        })
    }

    fn stiffness(&self, _least: f64) -> f64 {
        self.damping / (self.mass * self.length * self.length)
    }

    fn frequency(&self, rate: f64) -> f64 {
        rate * ((1.0 + self.pivot.norm() / self.length).sqrt() + 1.0)
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        let v = |a: Vector3<f64>| Vector3::from(to_axes(a.into()));
        Self {
            pivot: v(self.pivot),
            direction0: v(self.direction0),
            rate0: v(self.rate0),
            ..*self
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            mass: ldexp(self.mass, -m),
            damping: ldexp(self.damping, -m),
            ..*self
        })
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        Ok(Self {
            damping: scale.rate_to_unit(self.damping),
            rate0: self.rate0.map(|v| scale.rate_to_unit(v)),
            ..*self
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::multibody::{motion, MassMatrix};
    use nalgebra::Matrix3;

    #[test]
    fn alone_on_its_hub_the_closed_form_is_the_joint_solve() {
        let part = Slosh::try_new(0.35, [-0.5, 0.3, 0.7], 0.45, 0.04).unwrap();
        let i = Matrix3::new(3.0, -0.2, 0.1, -0.2, 4.0, 0.3, 0.1, 0.3, 5.0);
        let hub = Hub::try_new(i, 4.0, part.mass()).unwrap();
        let lone = LoneSlosh::new(&hub, part);
        let cases = [
            ([0.3, -0.8, 0.52], [0.3, -0.7, 1.1], [0.1, 0.2, 0.3]),
            ([0.0, 0.0, -2.0], [-1.2, 0.1, 0.4], [0.5, -0.4, 0.0]),
            ([1.0, 1e-3, 0.0], [0.0, 0.0, 2.0], [0.0, 0.0, 0.0]),
        ];
        // a stored direction off unit length (far: 1.1; near, as integration leaves it, where
        // 1/|n| is a series: 1 + 1e-6 and 1 − 2e-6) and a momentum off the normal plane: all
        // read as the equations read them
        for ((n, omega, nu), length) in cases
            .iter()
            .flat_map(|c| [1.1, 1.0 + 1e-6, 1.0 - 2e-6].map(|l| (*c, l)))
        {
            let n = Vector3::from(n).normalize() * length;
            let omega = Vector3::from(omega);
            let rod = Rod::along(&n);
            let nu = Vector3::from(nu);
            let nu = nu - rod.direction * rod.direction.dot(&nu);
            let carried = [part.carried(&rod)];
            let v = rod.rates_of(&nu);
            let (h, p) = MassMatrix::<2>::assemble(&hub, &carried).apply(&omega, &v);
            let pi = rod.momentum_of(p) + rod.direction * 0.3;
            let closed = lone.rates(&h, &n, &pi);
            let close = |a: Vector3<f64>, b: Vector3<f64>| (a - b).amax() < 1e-14;
            assert!(close(closed.omega, omega), "{} {omega}", closed.omega);
            assert!(close(closed.nu, nu), "{} {nu}", closed.nu);
            let moved = motion(&hub, &carried, &h, &p);
            let (velocity, _) = moved.element(&carried[0], 0);
            let (dn, dpi) = part.rates(&n, &pi, &rod, &nu, &omega, &velocity);
            assert!(close(closed.direction, dn), "{} {dn}", closed.direction);
            assert!(close(closed.momentum, dpi), "{} {dpi}", closed.momentum);
        }
    }
}
