//! A hinged appendage: a rigid panel or rod on a one-axis hinge of the body, with a torsional
//! spring and damper — a deployed antenna or solar panel (Hughes, *Spacecraft Attitude
//! Dynamics*, 1986, ch. 8; Basilisk's hinged rigid bodies).
//!
//! **Geometry** (body axes, from the hub's mass centre): the hinge at `h`, its unit axis `e`;
//! at hinge angle `β` the panel is turned from its rest position by `A(β)`, the rotation by
//! `β` about `e`, so its mass centre is at `r = h + ℓ s(β)`, `s(β) = A(β) s₀ = s₀ cos β +
//! (e × s₀) sin β` (`s₀ ⊥ e` the arm's direction at rest, `ℓ` the distance from the hinge),
//! and its tensor about its own centre is `I_b = j_s s sᵀ + j_e e eᵀ + j_g g gᵀ`, `g = e × s`
//! (`j_s`, `j_e`, `j_g` its moments about the arm, the hinge axis and their normal).
//!
//! **State** `[β, p]`, `p = ∂T/∂β̇`. Its velocity relative to the hub is `ṙ = β̇ ℓ g` and its
//! angular velocity `Ω = ω + β̇ e`; with `u = ω × r + β̇ ℓ g`, `∂u/∂β = ω × ℓ g − β̇ ℓ s` and
//! `∂I_b/∂β = [e×] I_b − I_b [e×]` (so `∂(½ Ωᵀ I_b Ω)/∂β = e · (I_b Ω × Ω)`), Lagrange gives
//!
//! ```text
//! β' = β̇                                                   (from the joint solve)
//! p' = m (u − P/M) · (ω × ℓ g − β̇ ℓ s) + e · (I_b Ω × Ω) − k β − c β̇
//! ```
//!
//! `V = ½ k β²` (the spring is unloaded at rest), the dissipated power `c β̇²`.
//!
//! **Alone on its hub** ([`LoneHinge`]) the joint solve has a closed form. With `μ = m M_h/M`,
//! `g₀ = e × s₀`, `q₁ = μℓ h × g₀`, `q₂ = μℓ h × s₀`, the coupling column is
//! `b = μℓ r × g + I_b e = cos β q₁ − sin β q₂ + d e` (`s × g = e`), the panel's own entry
//! `d = μℓ² + j_e` is constant, and eliminating `β̇ = (p − b·ω)/d`
//!
//! ```text
//! S(β) ω = H − p b / d,   S(β) = I_h + μ(|r|² 𝟙 − r rᵀ) + I_b − b bᵀ / d
//!                              = S₀ + cos β S_c + sin β S_s + cos 2β S_c2 + sin 2β S_s2
//! ```
//!
//! a trigonometric polynomial of degree two whose five symmetric coefficients are constant
//! (`r = h + ℓ s`, `s sᵀ`, `g gᵀ` and `b bᵀ` are of degree two in `cos β`, `sin β`); with
//! `P = 𝟙 − e eᵀ`, `D = s₀s₀ᵀ − g₀g₀ᵀ`, `X = s₀g₀ᵀ + g₀s₀ᵀ`, `J± = (j_s ± j_g)/2`:
//!
//! ```text
//! S₀   = I_h + μ(|h|² + ℓ²) 𝟙 − μ h hᵀ + (J₊ − μℓ²/2) P − μℓ² e eᵀ − (q₁q₁ᵀ + q₂q₂ᵀ)/2d
//! S_c  = 2μℓ (h·s₀) 𝟙 − μℓ (h s₀ᵀ + s₀ hᵀ) − (q₁ eᵀ + e q₁ᵀ)
//! S_s  = 2μℓ (h·g₀) 𝟙 − μℓ (h g₀ᵀ + g₀ hᵀ) + (q₂ eᵀ + e q₂ᵀ)
//! S_c2 = (J₋ − μℓ²/2) D − (q₁q₁ᵀ − q₂q₂ᵀ)/2d
//! S_s2 = (J₋ − μℓ²/2) X + (q₁q₂ᵀ + q₂q₁ᵀ)/2d
//! ```
//!
//! and the momentum's rate, with `e · (I_b Ω × Ω) = (j_s − j_g)(ω·s)(ω·g)`,
//!
//! ```text
//! p' = μℓ |ω|² (h·g) − (ω·g)(μℓ ω·h + (μℓ² − j_s + j_g) ω·s) − β̇ ω·(cos β q₂ + sin β q₁)
//!      − k β − c β̇
//! ```

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};

use super::moving::{checked, point, unit, Coordinate};
use super::multibody::{Alone, AloneSolve, Carried, Hub, Sym3};

/// A hinged appendage (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hinge {
    mass: f64,
    /// `j_s`, `j_e`, `j_g`.
    moments: Vector3<f64>,
    hinge: Vector3<f64>,
    axis: Vector3<f64>,
    /// `s₀`.
    arm: Vector3<f64>,
    /// `e × s₀`.
    normal: Vector3<f64>,
    length: f64,
    /// The torsional spring, the damper and the start.
    coordinate: Coordinate,
}

/// The panel at one hinge angle: its arm `s`, `g = e × s`, and tensor `I_b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub arm: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub inertia: Matrix3<f64>,
}

impl Hinge {
    /// A panel of mass `mass` and moments `moments` (about the arm, the hinge axis and their
    /// normal, through its own centre) hinged at `hinge` about `axis`, its centre at `length`
    /// from the hinge along `arm` at rest (`arm` is taken perpendicular to `axis`: its
    /// component along the axis is removed).
    ///
    /// # Errors
    /// A mass that is not positive; a moment, length, stiffness or damping that is negative
    /// (every one finite); moments that break the triangle inequality (no rigid body has
    /// them); a zero axis, or an arm along the axis.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Hinge;
    /// // a thin rod of length 2 hinged at (1, 0, 0), flapping about y
    /// let rod = Hinge::try_new(0.3, [0.0, 0.1, 0.1], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///                          [1.0, 0.0, 0.0], 1.0, 0.5, 0.01);
    /// assert!(rod.is_ok());
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn try_new(
        mass: f64,
        moments: [f64; 3],
        hinge: [f64; 3],
        axis: [f64; 3],
        arm: [f64; 3],
        length: f64,
        stiffness: f64,
        damping: f64,
    ) -> Result<Self> {
        let mass = checked("mass", mass, true)?;
        for j in moments {
            checked("moments", j, false)?;
        }
        let [js, je, jg] = moments;
        let slack = 1e-12 * (js + je + jg);
        if js > je + jg + slack || je > js + jg + slack || jg > js + je + slack {
            return Err(Error::invalid(
                "moments",
                "must meet the triangle inequality (each at most the sum of the other two)",
                moments,
            ));
        }
        let axis = unit("axis", axis)?;
        let raw = point("arm", arm)?;
        let along = raw - axis * axis.dot(&raw);
        let arm = match along.norm() > 1e-12 * raw.norm() {
            true => along.normalize(),
            false => {
                return Err(Error::invalid(
                    "arm",
                    "must not lie along the hinge axis",
                    raw.as_slice(),
                ))
            }
        };
        Ok(Self {
            mass,
            moments: Vector3::from(moments),
            hinge: point("hinge", hinge)?,
            axis,
            arm,
            normal: axis.cross(&arm),
            length: checked("length", length, false)?,
            coordinate: Coordinate::try_new(stiffness, damping)?,
        })
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    pub fn moments(&self) -> Vector3<f64> {
        self.moments
    }

    pub fn hinge(&self) -> Vector3<f64> {
        self.hinge
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    pub fn arm(&self) -> Vector3<f64> {
        self.arm
    }

    pub fn length(&self) -> f64 {
        self.length
    }

    pub fn stiffness(&self) -> f64 {
        self.coordinate.stiffness
    }

    pub fn damping(&self) -> f64 {
        self.coordinate.damping
    }

    /// The panel at hinge angle `beta`.
    #[inline(always)]
    pub fn pose(&self, beta: f64) -> Pose {
        let (sin, cos) = super::gravity::sin_cos(beta);
        let arm = self.arm * cos + self.normal * sin;
        let normal = self.axis.cross(&arm);
        let [js, je, jg] = [self.moments.x, self.moments.y, self.moments.z];
        let inertia = arm * arm.transpose() * js
            + self.axis * self.axis.transpose() * je
            + normal * normal.transpose() * jg;
        Pose {
            arm,
            normal,
            inertia,
        }
    }

    /// What it carries in `pose`.
    #[inline(always)]
    pub fn carried(&self, pose: &Pose) -> Carried {
        Carried::point(
            self.mass,
            self.hinge + pose.arm * self.length,
            &[pose.normal * self.length],
        )
        .with_inertia(pose.inertia, &[self.axis])
    }

    /// `p'` in `pose` at angle `beta` and rate `rate`, the body rates `omega`, the panel's
    /// centre's velocity `velocity` in the frame of the mass centre and its angular velocity
    /// `spin`.
    #[inline(always)]
    pub fn momentum_rate(
        &self,
        pose: &Pose,
        beta: f64,
        rate: f64,
        omega: &Vector3<f64>,
        velocity: &Vector3<f64>,
        spin: &Vector3<f64>,
    ) -> f64 {
        let moved = omega.cross(&pose.normal) - pose.arm * rate;
        self.mass * self.length * velocity.dot(&moved)
            + self.axis.dot(&(pose.inertia * spin).cross(spin))
            - self.coordinate.force(beta, rate)
    }

    /// `½ k β²`.
    pub fn potential(&self, beta: f64) -> f64 {
        self.coordinate.potential(beta)
    }

    /// The power the damping takes, `c β̇²`.
    pub fn dissipation(&self, rate: f64) -> f64 {
        self.coordinate.dissipation(rate)
    }
}

/// A hinged appendage alone on its hub: the joint solve and the momentum's rate in closed
/// form (see the module doc), the five coefficients of `S(β)` computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoneHinge {
    part: Hinge,
    /// `μℓ`, `μℓ² − j_s + j_g`.
    moment: f64,
    swing: f64,
    /// `d` and `1/d`.
    block: f64,
    inv_block: f64,
    /// `q₁`, `q₂`.
    q1: Vector3<f64>,
    q2: Vector3<f64>,
    /// `h · g₀`, `h · s₀`.
    hg: f64,
    hs: f64,
    /// `S₀`, `S_c`, `S_s`, `S_c2`, `S_s2`.
    terms: [Sym3; 5],
}

impl LoneHinge {
    /// `part` alone on `hub` (whose total mass counts the part's).
    pub fn new(hub: &Hub, part: Hinge) -> Self {
        let mu = hub.reduced_mass(part.mass);
        let (l, h, e) = (part.length, part.hinge, part.axis);
        let (s0, g0) = (part.arm, part.normal);
        let [js, je, jg] = [part.moments.x, part.moments.y, part.moments.z];
        let ml = mu * l;
        let block = ml * l + je;
        let (q1, q2) = (h.cross(&g0) * ml, h.cross(&s0) * ml);
        let plane = Sym3::scalar(1.0) - Sym3::square(&e);
        let twice = 0.5 / block;
        let half = 0.5 * (js - jg) - 0.5 * ml * l;
        let rest = Sym3::of(hub.inertia()) + Sym3::scalar(mu * (h.norm_squared() + l * l))
            - Sym3::square(&h) * mu
            + plane * (0.5 * (js + jg) - 0.5 * ml * l)
            - Sym3::square(&e) * (ml * l)
            - (Sym3::square(&q1) + Sym3::square(&q2)) * twice;
        let cos =
            Sym3::scalar(2.0 * ml * h.dot(&s0)) - Sym3::outer(&h, &s0) * ml - Sym3::outer(&q1, &e);
        let sin =
            Sym3::scalar(2.0 * ml * h.dot(&g0)) - Sym3::outer(&h, &g0) * ml + Sym3::outer(&q2, &e);
        let cos2 = (Sym3::square(&s0) - Sym3::square(&g0)) * half
            - (Sym3::square(&q1) - Sym3::square(&q2)) * twice;
        let sin2 = Sym3::outer(&s0, &g0) * half + Sym3::outer(&q1, &q2) * twice;
        Self {
            part,
            moment: ml,
            swing: ml * l - js + jg,
            block,
            inv_block: 1.0 / block,
            q1,
            q2,
            hg: h.dot(&g0),
            hs: h.dot(&s0),
            terms: [rest, cos, sin, cos2, sin2],
        }
    }

    pub fn part(&self) -> &Hinge {
        &self.part
    }

    /// `(ω, β̇, cos β, sin β)` from the angular momentum `h` (body axes), the angle `beta` and
    /// its momentum `p`.
    #[inline(always)]
    pub fn rates(&self, h: &Vector3<f64>, beta: f64, p: f64) -> (Vector3<f64>, f64, f64, f64) {
        let (sin, cos) = super::gravity::sin_cos(beta);
        let [rest, c1, s1, c2, s2] = &self.terms;
        let stiff = rest
            .add_scaled(cos, c1)
            .add_scaled(sin, s1)
            .add_scaled(cos * cos - sin * sin, c2)
            .add_scaled(2.0 * sin * cos, s2);
        let b = self.q1 * cos - self.q2 * sin + self.part.axis * self.block;
        // `b · ω` formed while the division runs (see [`Sym3::solve_parts`])
        let (adjugate, inv) = stiff.solve_parts(&(h - b * (p * self.inv_block)));
        let omega = adjugate * inv;
        (
            omega,
            (p - b.dot(&adjugate) * inv) * self.inv_block,
            cos,
            sin,
        )
    }

    /// `p'` at angle `beta` (its `cos`, `sin` from [`LoneHinge::rates`]), its rate `rate` and
    /// the body rates `omega`.
    #[inline(always)]
    pub fn momentum_rate(
        &self,
        beta: f64,
        cos: f64,
        sin: f64,
        rate: f64,
        omega: &Vector3<f64>,
    ) -> f64 {
        let p = &self.part;
        let s = p.arm * cos + p.normal * sin;
        let g = p.normal * cos - p.arm * sin;
        let wg = omega.dot(&g);
        let hg = self.hg * cos - self.hs * sin;
        // summed as a tree, each product's earlier factor first: what waits for ω is short
        let centrifugal = self.moment * hg * omega.norm_squared();
        let swing = wg * (self.moment * omega.dot(&p.hinge) + self.swing * omega.dot(&s));
        let coriolis = rate * omega.dot(&(self.q2 * cos + self.q1 * sin));
        (centrifugal - swing) - (coriolis + p.coordinate.force(beta, rate))
    }
}

use super::moving::{mover_hooks, moving_info, one_coordinate_hooks, OneCoordinate};
use super::part::{Ctx, Dim, Field, Fields, ModelInfo, Param, ParamKind, Part};
use crate::float::ldexp;

impl Alone for LoneHinge {
    #[inline(always)]
    fn increment(
        &self,
        h: &Vector3<f64>,
        x: &[f64],
        s: f64,
        dx: &mut [f64],
    ) -> (Vector3<f64>, f64) {
        let (omega, v, cos, sin) = self.rates(h, x[0], x[1]);
        let dp = self.momentum_rate(x[0], cos, sin, v, &omega);
        dx[0] = v * s;
        dx[1] = dp * s;
        (omega, self.part.dissipation(v))
    }

    fn omega(&self, h: &Vector3<f64>, x: &[f64]) -> Vector3<f64> {
        self.rates(h, x[0], x[1]).0
    }

    fn kinetic(&self, h: &Vector3<f64>, x: &[f64]) -> f64 {
        let (omega, v, _, _) = self.rates(h, x[0], x[1]);
        0.5 * (omega.dot(h) + v * x[1])
    }
}

impl Part for Hinge {
    const INFO: ModelInfo = moving_info(
        "hinge",
        "a rigid panel or rod on a one-axis hinge of the body with a torsional spring and damper",
        &[
            Param::new("mass", ParamKind::Scalar, "the panel's mass (positive)"),
            Param::new(
                "moments",
                ParamKind::Vector,
                "its moments about its own centre: about the arm, the hinge axis, their normal",
            ),
            Param::new(
                "hinge",
                ParamKind::Vector,
                "the hinge point, from the body's mass centre, body axes",
            ),
            Param::new("axis", ParamKind::Vector, "the hinge axis, body axes"),
            Param::new(
                "arm",
                ParamKind::Vector,
                "from the hinge towards the panel's centre at rest, body axes",
            ),
            Param::new(
                "length",
                ParamKind::Scalar,
                "the distance of its centre from the hinge",
            ),
            Param::new(
                "stiffness",
                ParamKind::Scalar,
                "the torsional spring's k (non-negative)",
            ),
            Param::new(
                "damping",
                ParamKind::Scalar,
                "the damper's c (non-negative)",
            ),
            Param::new(
                "angle0",
                ParamKind::Scalar,
                "the hinge angle at the start (0)",
            )
            .optional(),
            Param::new("rate0", ParamKind::Scalar, "its rate at the start (0)").optional(),
        ],
        &[
            Field {
                name: "angle",
                width: 1,
                body_vector: false,
                dim: Dim::NONE,
                about: "β, from rest",
            },
            Field {
                name: "momentum",
                width: 1,
                body_vector: false,
                dim: Dim::MOMENTUM,
                about: "p = ∂T/∂β̇",
            },
        ],
    );

    fn from_fields(fields: &Fields) -> Result<Self> {
        let h = Self::try_new(
            fields.number("mass")?,
            fields.vector("moments")?,
            fields.vector("hinge")?,
            fields.vector("axis")?,
            fields.vector("arm")?,
            fields.number("length")?,
            fields.number("stiffness")?,
            fields.number("damping")?,
        )?;
        Ok(Self {
            coordinate: h.coordinate.starting(fields, "angle0")?,
            ..h
        })
    }

    mover_hooks!();
    one_coordinate_hooks!();

    #[inline(always)]
    fn rates(&self, c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        if let Some(m) = &c.moving {
            // the pose the solve built: ℓ s = r − h, ℓ g its rate's column, I_b its tensor
            let carried = m.carried;
            let rate = m.rates[0];
            let moved = c.omega.cross(&carried.linear[0]) - (carried.centre - self.hinge) * rate;
            let spin = m.spin;
            let tensor = carried.inertia.unwrap_or_default();
            dx[0] = rate;
            dx[1] = self.mass * m.velocity.dot(&moved)
                + self.axis.dot(&(tensor * spin).cross(&spin))
                - self.coordinate.force(x[0], rate);
        }
    }

    fn stiffness(&self, _least: f64) -> f64 {
        self.coordinate.damping
            / (self.mass * self.length * self.length + self.moments.y).max(f64::MIN_POSITIVE)
    }

    fn frequency(&self, rate: f64) -> f64 {
        let j = (self.mass * self.length * self.length + self.moments.y).max(f64::MIN_POSITIVE);
        let reach = self.hinge.norm() + self.length;
        (self.coordinate.stiffness / j).sqrt()
            + rate * (1.0 + reach / self.length.max(1e-300)).sqrt().min(1e3)
            + rate
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        let v = |a: Vector3<f64>| Vector3::from(to_axes(a.into()));
        Self {
            hinge: v(self.hinge),
            axis: v(self.axis),
            arm: v(self.arm),
            normal: v(self.normal),
            ..*self
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            mass: ldexp(self.mass, -m),
            moments: self.moments.map(|j| ldexp(j, -m)),
            coordinate: self.coordinate.scaled(m),
            ..*self
        })
    }
}

impl OneCoordinate for Hinge {
    fn coordinate(&self) -> &Coordinate {
        &self.coordinate
    }

    fn moved_mass(&self) -> f64 {
        self.mass
    }

    #[inline(always)]
    fn carried_at(&self, beta: f64) -> Carried {
        Hinge::carried(self, &self.pose(beta))
    }

    fn lone_on(&self, hub: &Hub) -> AloneSolve {
        AloneSolve::Hinge(Box::new(LoneHinge::new(hub, *self)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::multibody::{motion, MassMatrix};

    #[test]
    fn alone_on_its_hub_the_closed_form_is_the_joint_solve() {
        let part = Hinge::try_new(
            0.25,
            [0.01, 0.03, 0.035],
            [0.8, 0.5, -0.2],
            [0.1, 1.0, 0.3],
            [1.0, -0.1, 0.2],
            0.6,
            0.7,
            0.05,
        )
        .unwrap();
        let i = Matrix3::new(3.0, -0.2, 0.1, -0.2, 4.0, 0.3, 0.1, 0.3, 5.0);
        let hub = Hub::try_new(i, 4.0, part.mass()).unwrap();
        let lone = LoneHinge::new(&hub, part);
        for (beta, omega, v) in [
            (0.0, [0.3, -0.7, 1.1], 0.2),
            (0.9, [-1.2, 0.1, 0.4], -0.8),
            (-2.5, [0.0, 0.0, 2.0], 0.0),
            (4.0, [0.5, 0.5, -0.5], 1.5),
        ] {
            let omega = Vector3::from(omega);
            let pose = part.pose(beta);
            let carried = [part.carried(&pose)];
            let (h, p) = MassMatrix::<1>::assemble(&hub, &carried).apply(&omega, &[v]);
            let (w, rate, cos, sin) = lone.rates(&h, beta, p[0]);
            assert!((w - omega).amax() < 1e-14, "{w} {omega}");
            assert!((rate - v).abs() < 1e-14, "{rate} {v}");
            let moved = motion(&hub, &carried, &h, &p);
            let (velocity, spin) = moved.element(&carried[0], 0);
            let general = part.momentum_rate(&pose, beta, v, &omega, &velocity, &spin);
            let closed = lone.momentum_rate(beta, cos, sin, v, &omega);
            assert!((closed - general).abs() < 1e-14, "{closed} {general}");
        }
    }
}
