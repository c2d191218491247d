//! A spherical viscous nutation damper, a part of a body: a sphere of moment of inertia `j`
//! (about any axis through its centre) in a spherical cavity filled with viscous fluid, the
//! fluid exerting a torque `c (σ − ω)` on the body and its opposite on the sphere (Hughes,
//! *Spacecraft Attitude Dynamics*, 1986, the spherical nutation damper; Kaplan, *Modern
//! Spacecraft Dynamics and Control*, 1976, energy-sink analysis).
//!
//! **Variables** (body axes): the sphere's absolute angular velocity `σ` is the part's state.
//! The body's tensor `I` counts the sphere's mass as a point at its centre, so that the total
//! angular momentum is `H = I ω + j σ`.
//!
//! **Equations.** No external torque: `H' = H × ω` in body axes. The sphere alone, its angular
//! momentum `j σ` written in body axes, feels only the fluid's torque:
//! `j (σ' + ω × σ) = −c (σ − ω)`, so
//!
//! ```text
//! σ' = σ × ω − (c / j) (σ − ω),    ω = I⁻¹ (H − j σ)
//! ```
//!
//! **Energy.** `T = ½ ωᵀ I ω + ½ j |σ|²`; with the equations above
//! `T' = c ω·(σ − ω) − c σ·(σ − ω) = −c |σ − ω|² ≤ 0`. At fixed `|H|` the least energy is a
//! spin about the major axis with the sphere co-rotating: the end of every motion with `c > 0`
//! (the major-axis rule of Explorer 1).

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::kinds::{Conserved, Traits};
use super::part::{Ctx, Dim, EnergyRole, Field, Fields, ModelInfo, Param, ParamKind, Part};

/// A spherical viscous damper (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    /// The sphere's moment `j`.
    sphere: f64,
    /// The damping coefficient `c`.
    damping: f64,
    /// `c / j`.
    rate: f64,
    /// The sphere's rates at the start (body axes); co-rotating with the body if `None`.
    sigma0: Option<[f64; 3]>,
}

impl Damper {
    /// A sphere of moment `sphere` with damping coefficient `damping`, co-rotating with the
    /// body at the start.
    ///
    /// # Errors
    /// `sphere` positive and finite, `damping` non-negative and finite, their ratio finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Damper;
    /// assert!(Damper::try_new(0.1, 0.05).is_ok());
    /// assert!(Damper::try_new(0.0, 0.05).is_err());
    /// ```
    pub fn try_new(sphere: f64, damping: f64) -> Result<Self> {
        if !(sphere.is_finite() && sphere > 0.0) {
            return Err(Error::invalid(
                "inertia",
                "(the damper sphere's moment) must be positive and finite",
                sphere,
            ));
        }
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(Error::invalid(
                "damping",
                "must be non-negative and finite",
                damping,
            ));
        }
        let rate = damping / sphere;
        if !rate.is_finite() {
            return Err(Error::invalid(
                "damping",
                "over the damper's inertia must be finite",
                (damping, sphere),
            ));
        }
        Ok(Self {
            sphere,
            damping,
            rate,
            sigma0: None,
        })
    }

    /// The same damper with its sphere's rates `sigma0` at the start (body axes).
    ///
    /// # Errors
    /// Rates that are not finite.
    pub fn starting_at(self, sigma0: [f64; 3]) -> Result<Self> {
        if !sigma0.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "sigma0",
                "must be three finite rates",
                sigma0,
            ));
        }
        Ok(Self {
            sigma0: Some(sigma0),
            ..self
        })
    }

    pub fn sphere(&self) -> f64 {
        self.sphere
    }

    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// The sphere's rates at the start, if given (else co-rotating).
    pub fn sigma0(&self) -> Option<[f64; 3]> {
        self.sigma0
    }

    /// `σ'` at rates `omega` of the body and `sigma` of the sphere.
    #[inline(always)]
    pub fn sigma_rate(&self, omega: &Vector3<f64>, sigma: &Vector3<f64>) -> Vector3<f64> {
        sigma.cross(omega) - (sigma - omega) * self.rate
    }

    /// The decay rate of the slip `σ − ω`, `c (1/j + 1/I_min)`, for a body whose least
    /// principal moment is `least`: the damper's stiffness.
    pub fn slip_rate(&self, least: f64) -> f64 {
        self.damping / self.sphere + self.damping / least
    }
}

/// The right-hand side, times `s`, of a body of constant principal moments with one damper
/// and nothing else: what a run of a damped body evaluates four times a step, written out for
/// its chain of dependent operations (the general model goes through each part's
/// contributions in turn). At round-off from the plain formulas (tested): the products by `s`
/// folded into what depends on `s` alone (`r s`, `c s / j`, `c s`, with `r` the reciprocal
/// moments), so that no product by `s` ends the chain; the quaternion's rate takes
/// `ω s / 2`, exactly half of `ω s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamperKernel {
    sphere: f64,
    rate: f64,
    damping: f64,
    reciprocals: Vector3<f64>,
}

impl DamperKernel {
    pub fn new(damper: &Damper, reciprocals: Vector3<f64>) -> Self {
        Self {
            sphere: damper.sphere,
            rate: damper.rate,
            damping: damper.damping,
            reciprocals,
        }
    }

    /// `(H' s, σ' s, W' s, q' s)` for the total momentum `h`, the sphere's rates `sigma` (body
    /// axes) and the attitude `q`.
    #[inline(always)]
    pub fn increment(
        &self,
        h: [f64; 3],
        sigma: [f64; 3],
        q: [f64; 4],
        s: f64,
    ) -> ([f64; 3], [f64; 3], f64, [f64; 4]) {
        let (h, sigma) = (Vector3::from(h), Vector3::from(sigma));
        let l = h - sigma * self.sphere;
        let omega = l.component_mul(&self.reciprocals);
        // ω s / 2 first, for the quaternion's rate; the cross products take it against 2σ and
        // 2H (exact): the same numbers as σ × ω s and H × ω s, a product shorter to q'
        let u = l.component_mul(&(self.reciprocals * (0.5 * s)));
        let slip = sigma - omega;
        let dsigma = (sigma + sigma).cross(&u) - slip * (self.rate * s);
        let [w, x, y, z] = q;
        let dq = [
            -(x * u.x + y * u.y + z * u.z),
            w * u.x + y * u.z - z * u.y,
            w * u.y + z * u.x - x * u.z,
            w * u.z + x * u.y - y * u.x,
        ];
        let dw = slip.norm_squared() * (self.damping * s);
        ((h + h).cross(&u).into(), dsigma.into(), dw, dq)
    }
}

#[inline(always)]
fn sigma(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl Part for Damper {
    const INFO: ModelInfo = ModelInfo {
        name: "damper",
        about: "a spherical viscous nutation damper (energy never rising; the energy balance \
                kept)",
        law: false,
        params: &[
            Param::new(
                "inertia",
                ParamKind::Scalar,
                "the sphere's moment of inertia j about its centre (positive)",
            ),
            Param::new(
                "damping",
                ParamKind::Scalar,
                "the viscous coefficient c: torque per unit relative rate (non-negative)",
            ),
            Param::new(
                "sigma0",
                ParamKind::Vector,
                "the sphere's rates at the start, body axes (co-rotating with the body if left \
                 out)",
            )
            .optional(),
        ],
        state: &[Field {
            name: "sigma",
            width: 3,
            body_vector: true,
            dim: Dim::RATE,
            about: "the sphere's absolute angular velocity, body axes",
        }],
        keeps: Conserved::MOMENTA.union(Conserved::ENERGY_BALANCE),
        defines: Conserved::NONE,
        energy: EnergyRole::Dissipates,
        external: false,
        unique: false,
        traits: Traits::PART_STATE.union(Traits::STORED_MOMENTUM),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        let damper = Self::try_new(fields.number("inertia")?, fields.number("damping")?)?;
        match fields.optional_vector("sigma0")? {
            Some(s) => damper.starting_at(s),
            None => Ok(damper),
        }
    }

    /// `j σ`.
    #[inline(always)]
    fn momentum(&self, _t: f64, x: &[f64]) -> Vector3<f64> {
        sigma(x) * self.sphere
    }

    #[inline(always)]
    fn rates(&self, c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        let d = self.sigma_rate(&c.omega, &sigma(x));
        dx[..3].copy_from_slice(d.as_slice());
    }

    /// `σ₀`, or co-rotating: `ω₀`.
    fn start(&self, omega0: &Vector3<f64>, x: &mut [f64]) {
        let s = self.sigma0.unwrap_or((*omega0).into());
        x[..3].copy_from_slice(&s);
    }

    /// `½ j |σ|²`.
    fn energy(&self, _t: f64, x: &[f64]) -> f64 {
        0.5 * self.sphere * sigma(x).norm_squared()
    }

    /// `c |σ − ω|²`.
    #[inline(always)]
    fn dissipation(&self, c: &Ctx<'_>, x: &[f64]) -> f64 {
        (sigma(x) - c.omega).norm_squared() * self.damping
    }

    fn stiffness(&self, least: f64) -> f64 {
        self.slip_rate(least)
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            sigma0: self.sigma0.map(to_axes),
            ..*self
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            sigma0: self.sigma0,
            ..Self::try_new(ldexp(self.sphere, -m), ldexp(self.damping, -m))?
        })
    }

    /// The torque `c (σ − ω)` is over `2^(2e)` in the run's units and the rates over `2^e`,
    /// so `c` is over `2^e`.
    fn in_units(&self, scale: RateScale) -> Result<Self> {
        Ok(Self {
            sigma0: self.sigma0.map(|s| s.map(|v| scale.rate_to_unit(v))),
            ..Self::try_new(self.sphere, scale.rate_to_unit(self.damping))?
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Quaternion;

    #[test]
    fn the_kernel_is_the_plain_right_hand_side() {
        let i = Vector3::new(1.0, 2.5, 3.0);
        let d = Damper::try_new(0.07, 0.03).unwrap();
        let kernel = DamperKernel::new(&d, i.map(|v| 1.0 / v));
        for k in 0..40 {
            let a = f64::from(k);
            let h = Vector3::new(0.3 + 0.05 * a, -1.2, 2.0 - 0.02 * a);
            let sigma = Vector3::new(0.5, 0.1 * a - 2.0, 0.9);
            let q = Quaternion::new(0.8, -0.1, 0.3 + 0.01 * a, 0.2);
            let s = 1e-3 * (1.0 + a);
            // ω = I⁻¹ (H − j σ): H' = H × ω, σ' = σ × ω − (c/j)(σ − ω), W' = c |σ − ω|²
            let omega = (h - sigma * 0.07).component_div(&i);
            let dh = h.cross(&omega) * s;
            let ds = (sigma.cross(&omega) - (sigma - omega) * (0.03 / 0.07)) * s;
            let dw = 0.03 * (sigma - omega).norm_squared() * s;
            let dq = q * Quaternion::from_imag(omega) * (0.5 * s);
            let (fh, fs, fw, fq) =
                kernel.increment(h.into(), sigma.into(), [q.w, q.i, q.j, q.k], s);
            let close = |a: &[f64], b: &[f64]| {
                let size = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-14 * size)
            };
            assert!(close(&fh, dh.as_slice()), "{fh:?} vs {dh}");
            assert!(close(&fs, ds.as_slice()), "{fs:?} vs {ds}");
            assert!((fw - dw).abs() <= 1e-14 * dw, "{fw} vs {dw}");
            // nalgebra's quaternion coordinates are (i, j, k, w)
            let plain = [dq.w, dq.i, dq.j, dq.k];
            assert!(close(&fq, &plain), "{fq:?} vs {plain:?}");
        }
    }
}
