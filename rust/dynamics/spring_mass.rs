//! A spring–mass damper: a point mass `m` sliding along a line of the body, `r = a + x d`
//! (`a` the spring's rest point from the hub's mass centre, `d` a unit direction, body axes),
//! on a spring of stiffness `k` with viscous damping `c` — the classic nutation damper
//! (Hughes, *Spacecraft Attitude Dynamics*, 1986, §8; Kaplan, *Modern Spacecraft Dynamics and
//! Control*, 1976, §5).
//!
//! **State** `[x, p]`: the displacement from the rest point and its conjugate momentum
//! `p = ∂T/∂ẋ = m (u − P/M) · d` (see [`super::multibody`]). With `u = ω × r + ẋ d`,
//! `∂u/∂x = ω × d`, Lagrange's equation is
//!
//! ```text
//! x' = ẋ                                        (from the joint solve)
//! p' = m (u − P/M) · (ω × d) − k x − c ẋ
//! ```
//!
//! `V = ½ k x²`, the dissipated power `c ẋ²`.
//!
//! **Alone on its hub** ([`LoneSpring`]) the joint solve has a closed form. With `μ = m M_h/M`
//! (the mass centre's motion folds into the reduced mass), `a⊥ = a − (a·d) d` and
//! `s = x + a·d` (so `r = a⊥ + s d`), `𝕄 = [[I_h + μ[r×]ᵀ[r×], μ r × d], [μ (r × d)ᵀ, μ]]`
//! and `r × d = a⊥ × d = w` is constant. Eliminating `ẋ = p/μ − w·ω`:
//!
//! ```text
//! S(s) ω = H − p w,   S(s) = I_h + μ[r×]ᵀ(𝟙 − d dᵀ)[r×]
//!                          = (I_h + μ|a⊥|² d dᵀ) − s μ (d a⊥ᵀ + a⊥ dᵀ) + s² μ (𝟙 − d dᵀ)
//! p' = μ (s |ω × d|² − (ω·a⊥)(ω·d)) − k x − c ẋ
//! ```
//!
//! (the mass is free along `d`, so only the part of its lever arm's motion normal to `d` is
//! stiff): three constant symmetric matrices combined by `s`, one 3 × 3 solve by Cramer's rule.

use nalgebra::Vector3;

use crate::error::Result;

use super::moving::{checked, point, unit, Coordinate};
use super::multibody::{Alone, AloneSolve, Carried, Hub, Sym3};

/// A spring–mass damper (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringMass {
    mass: f64,
    anchor: Vector3<f64>,
    direction: Vector3<f64>,
    /// The spring, the damper and the start.
    coordinate: Coordinate,
}

impl SpringMass {
    /// A mass `mass` at rest at `anchor`, sliding along `direction` (normalised here).
    ///
    /// # Errors
    /// A mass that is not positive, a stiffness or damping that is negative, any of them or
    /// of the vectors not finite, a zero direction.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::SpringMass;
    /// assert!(SpringMass::try_new(0.1, [1.0, 0.0, 0.0], [0.0, 0.0, 2.0], 5.0, 0.1).is_ok());
    /// assert!(SpringMass::try_new(0.1, [1.0, 0.0, 0.0], [0.0; 3], 5.0, 0.1).is_err());
    /// ```
    pub fn try_new(
        mass: f64,
        anchor: [f64; 3],
        direction: [f64; 3],
        stiffness: f64,
        damping: f64,
    ) -> Result<Self> {
        Ok(Self {
            mass: checked("mass", mass, true)?,
            anchor: point("anchor", anchor)?,
            direction: unit("direction", direction)?,
            coordinate: Coordinate::try_new(stiffness, damping)?,
        })
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    pub fn anchor(&self) -> Vector3<f64> {
        self.anchor
    }

    pub fn direction(&self) -> Vector3<f64> {
        self.direction
    }

    pub fn stiffness(&self) -> f64 {
        self.coordinate.stiffness
    }

    pub fn damping(&self) -> f64 {
        self.coordinate.damping
    }

    /// What it carries at displacement `x`.
    #[inline(always)]
    pub fn carried(&self, x: f64) -> Carried {
        Carried::point(
            self.mass,
            self.anchor + self.direction * x,
            &[self.direction],
        )
    }

    /// `p'` at displacement `x` and rate `rate`, the body rates `omega` and the mass's
    /// velocity `velocity` in the frame of the mass centre.
    #[inline(always)]
    pub fn momentum_rate(
        &self,
        x: f64,
        rate: f64,
        omega: &Vector3<f64>,
        velocity: &Vector3<f64>,
    ) -> f64 {
        self.mass * velocity.dot(&omega.cross(&self.direction)) - self.coordinate.force(x, rate)
    }

    /// `½ k x²`.
    pub fn potential(&self, x: f64) -> f64 {
        self.coordinate.potential(x)
    }

    /// The power the damping takes, `c ẋ²`.
    pub fn dissipation(&self, rate: f64) -> f64 {
        self.coordinate.dissipation(rate)
    }
}

/// A spring–mass damper alone on its hub: the joint solve and the momentum's rate in closed
/// form (see the module doc), what is constant computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoneSpring {
    part: SpringMass,
    /// `μ` and `1/μ`.
    reduced: f64,
    inv_reduced: f64,
    /// `a⊥` and `a · d`.
    normal: Vector3<f64>,
    along: f64,
    /// `w = a⊥ × d`.
    lever: Vector3<f64>,
    /// `S(s) = rest − s cross + s² free`.
    rest: Sym3,
    cross: Sym3,
    free: Sym3,
}

impl LoneSpring {
    /// `part` alone on `hub` (whose total mass counts the part's).
    pub fn new(hub: &Hub, part: SpringMass) -> Self {
        let mu = hub.reduced_mass(part.mass);
        let d = part.direction;
        let along = part.anchor.dot(&d);
        let normal = part.anchor - d * along;
        let dd = Sym3::square(&d);
        Self {
            part,
            reduced: mu,
            inv_reduced: 1.0 / mu,
            normal,
            along,
            lever: normal.cross(&d),
            rest: Sym3::of(hub.inertia()) + dd * (mu * normal.norm_squared()),
            cross: Sym3::outer(&d, &normal) * mu,
            free: (Sym3::scalar(1.0) - dd) * mu,
        }
    }

    pub fn part(&self) -> &SpringMass {
        &self.part
    }

    /// `(ω, ẋ)` from the angular momentum `h` (body axes), the displacement `x` and its
    /// momentum `p`.
    #[inline(always)]
    pub fn rates(&self, h: &Vector3<f64>, x: f64, p: f64) -> (Vector3<f64>, f64) {
        let s = x + self.along;
        let stiff = self
            .rest
            .add_scaled(-s, &self.cross)
            .add_scaled(s * s, &self.free);
        // `w · ω` formed while the division runs: what waits for it is one product
        let (adjugate, inv) = stiff.solve_parts(&(h - self.lever * p));
        let omega = adjugate * inv;
        (
            omega,
            p * self.inv_reduced - self.lever.dot(&adjugate) * inv,
        )
    }

    /// `p'` at displacement `x`, its rate `rate` and the body rates `omega`.
    #[inline(always)]
    pub fn momentum_rate(&self, x: f64, rate: f64, omega: &Vector3<f64>) -> f64 {
        let s = x + self.along;
        let wd = omega.dot(&self.part.direction);
        let wa = omega.dot(&self.normal);
        // summed as a tree, each product's earlier factor first: what waits for ω is short
        let swing = self.reduced * s * (omega.norm_squared() - wd * wd);
        let tilt = self.reduced * wa * wd;
        (swing - tilt) - self.part.coordinate.force(x, rate)
    }
}

use super::moving::{mover_hooks, moving_info, one_coordinate_hooks, OneCoordinate};
use super::part::{Ctx, Dim, Field, Fields, ModelInfo, Param, ParamKind, Part};
use crate::float::ldexp;

impl Alone for LoneSpring {
    #[inline(always)]
    fn increment(
        &self,
        h: &Vector3<f64>,
        x: &[f64],
        s: f64,
        dx: &mut [f64],
    ) -> (Vector3<f64>, f64) {
        let (omega, v) = self.rates(h, x[0], x[1]);
        let dp = self.momentum_rate(x[0], v, &omega);
        dx[0] = v * s;
        dx[1] = dp * s;
        (omega, self.part.dissipation(v))
    }

    fn omega(&self, h: &Vector3<f64>, x: &[f64]) -> Vector3<f64> {
        self.rates(h, x[0], x[1]).0
    }

    fn kinetic(&self, h: &Vector3<f64>, x: &[f64]) -> f64 {
        let (omega, v) = self.rates(h, x[0], x[1]);
        0.5 * (omega.dot(h) + v * x[1])
    }
}

impl Part for SpringMass {
    const INFO: ModelInfo = moving_info(
        "spring_mass",
        "a point mass on a spring and viscous damper along a line of the body (the \
                classic nutation damper)",
        &[
            Param::new("mass", ParamKind::Scalar, "the moving mass m (positive)"),
            Param::new(
                "anchor",
                ParamKind::Vector,
                "where it rests, from the body's mass centre, body axes",
            ),
            Param::new(
                "direction",
                ParamKind::Vector,
                "the line it slides along, body axes",
            ),
            Param::new(
                "stiffness",
                ParamKind::Scalar,
                "the spring's k (non-negative)",
            ),
            Param::new(
                "damping",
                ParamKind::Scalar,
                "the damper's c (non-negative)",
            ),
            Param::new("x0", ParamKind::Scalar, "the displacement at the start (0)").optional(),
            Param::new("rate0", ParamKind::Scalar, "its rate at the start (0)").optional(),
        ],
        &[
            Field {
                name: "displacement",
                width: 1,
                body_vector: false,
                dim: Dim::NONE,
                about: "x",
            },
            Field {
                name: "momentum",
                width: 1,
                body_vector: false,
                dim: Dim::MOMENTUM,
                about: "p = ∂T/∂ẋ",
            },
        ],
    );

    fn from_fields(fields: &Fields) -> Result<Self> {
        let s = Self::try_new(
            fields.number("mass")?,
            fields.vector("anchor")?,
            fields.vector("direction")?,
            fields.number("stiffness")?,
            fields.number("damping")?,
        )?;
        Ok(Self {
            coordinate: s.coordinate.starting(fields, "x0")?,
            ..s
        })
    }

    mover_hooks!();
    one_coordinate_hooks!();

    #[inline(always)]
    fn rates(&self, c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        if let Some(m) = &c.moving {
            dx[0] = m.rates[0];
            dx[1] = self.momentum_rate(x[0], m.rates[0], &c.omega, &m.velocity);
        }
    }

    fn stiffness(&self, _least: f64) -> f64 {
        self.coordinate.damping / self.mass
    }

    fn frequency(&self, rate: f64) -> f64 {
        (self.coordinate.stiffness / self.mass).sqrt() + 2.0 * rate
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            anchor: Vector3::from(to_axes(self.anchor.into())),
            direction: Vector3::from(to_axes(self.direction.into())),
            ..*self
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            mass: ldexp(self.mass, -m),
            coordinate: self.coordinate.scaled(m),
            ..*self
        })
    }
}

impl OneCoordinate for SpringMass {
    fn coordinate(&self) -> &Coordinate {
        &self.coordinate
    }

    fn moved_mass(&self) -> f64 {
        self.mass
    }

    #[inline(always)]
    fn carried_at(&self, x: f64) -> Carried {
        SpringMass::carried(self, x)
    }

    fn lone_on(&self, hub: &Hub) -> AloneSolve {
        AloneSolve::Spring(LoneSpring::new(hub, *self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::multibody::{motion, MassMatrix};
    use nalgebra::Matrix3;

    #[test]
    fn alone_on_its_hub_the_closed_form_is_the_joint_solve() {
        let part = SpringMass::try_new(0.3, [0.4, -0.3, 0.6], [0.2, 0.9, -0.4], 2.0, 0.15).unwrap();
        let i = Matrix3::new(3.0, -0.2, 0.1, -0.2, 4.0, 0.3, 0.1, 0.3, 5.0);
        let hub = Hub::try_new(i, 4.0, part.mass()).unwrap();
        let lone = LoneSpring::new(&hub, part);
        for (x, omega, v) in [
            (0.0, [0.3, -0.7, 1.1], 0.2),
            (0.35, [-1.2, 0.1, 0.4], -0.8),
            (-2.0, [0.0, 0.0, 2.0], 0.0),
        ] {
            let omega = Vector3::from(omega);
            let carried = [part.carried(x)];
            let (h, p) = MassMatrix::<1>::assemble(&hub, &carried).apply(&omega, &[v]);
            let (w, rate) = lone.rates(&h, x, p[0]);
            assert!((w - omega).amax() < 1e-14, "{w} {omega}");
            assert!((rate - v).abs() < 1e-14, "{rate} {v}");
            let moved = motion(&hub, &carried, &h, &p);
            let (velocity, _) = moved.element(&carried[0], 0);
            let general = part.momentum_rate(x, v, &omega, &velocity);
            let closed = lone.momentum_rate(x, v, &omega);
            assert!((closed - general).abs() < 1e-14, "{closed} {general}");
        }
    }
}
