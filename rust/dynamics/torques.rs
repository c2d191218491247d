//! External torques on a body: the gravity gradient of a circular orbit and a constant torque
//! (in body or world axes). A system's torques add to the general model's momentum law,
//! `H' = H × ω + τ_body` (see [`super::GeneralModel`]).
//!
//! **Gravity gradient.** The body's centre moves on a circular orbit in the world `x–y` plane
//! at rate `n`: the direction to it from the planet is `r̂(t) = (cos nt, sin nt, 0)` (world
//! axes, `t = 0` at `+x`; the orbit normal is world `+z`). With `r̂_b = M(q)ᵀ r̂` the same
//! direction in body axes (`q` world-from-body) and `I` the body's tensor, the torque is
//!
//! ```text
//! τ_b = 3 n² r̂_b × (I r̂_b)            (n² = μ / R³)
//! ```
//!
//! the first term of the expansion of the field over the body (Hughes, *Spacecraft Attitude
//! Dynamics*, 1986, §8.2; Kane, Likins & Levinson, *Spacecraft Dynamics*, 1983, §2.5). It
//! derives from the potential `V = (3/2) n² r̂_bᵀ I r̂_b` (the constant `−μm/R` dropped).
//!
//! **Jacobi integral.** The field turns with the orbit at the constant rate `n` about world
//! `z`, so the energy measured in the orbiting frame is kept (the Jacobi integral of the
//! restricted problem; Hughes §9.1, Beletsky, *Motion of an Artificial Satellite about its
//! Center of Mass*, 1966, ch. 2): with `T` the kinetic energy, `H` the total angular momentum
//! and `ẑ_b` the orbit normal in body axes,
//!
//! ```text
//! J = T − n ẑ_b · H + (3/2) n² r̂_bᵀ I r̂_b
//!   = ½ (ω − n ẑ_b)ᵀ I (ω − n ẑ_b) − ½ n² ẑ_bᵀ I ẑ_b + (3/2) n² r̂_bᵀ I r̂_b   (no wheels)
//! ```
//!
//! Proof that it is kept: `T' = ω·τ` (with constant wheels `ω·(H × ω) = 0`), `(ẑ_b·H)' = ẑ_b·τ`
//! (world `z` of `H` changes by the torque's), and `r̂_b' = r̂_b × ω + n ẑ_b × r̂_b` gives
//! `V' = −ω·τ + n ẑ_b·τ`; the three sum to zero. A constant body with constant wheels keeps
//! it; a deployment (its work), a damper (its loss) or another torque do not.
//!
//! **Constant torque.** A vector `τ` fixed in body axes, or fixed in space (`τ_b = M(q)ᵀ τ`).
//! It keeps nothing but `|q|`.

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};
use crate::kinematics::{rotation_matrix, world_to_body};

use super::callable::CallableTorque;
use super::gravity::gravity_gradient_torque;
use super::kinds::Kinds;
use super::tabulated::TabulatedTorque;

/// The axes a constant torque is fixed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    Body,
    World,
}

impl std::str::FromStr for Frame {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "body" => Ok(Frame::Body),
            "world" => Ok(Frame::World),
            _ => Err(Error::invalid("frame", "must be 'body' or 'world'", s)),
        }
    }
}

/// An external torque, as the user gives it (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub enum Torque {
    /// The gravity gradient of a circular orbit of rate `orbit_rate` in the world `x–y` plane.
    GravityGradient { orbit_rate: f64 },
    /// A constant torque fixed in `frame`.
    Constant { vector: [f64; 3], frame: Frame },
    /// A torque tabulated at knots (see [`super::tabulated`]).
    Tabulated(Arc<TabulatedTorque>),
    /// A torque computed by the user's function (see [`super::callable`]).
    Callable(CallableTorque),
}

/// # Construction
impl Torque {
    /// The gravity gradient of a circular orbit of rate `orbit_rate` (radians per unit time).
    ///
    /// # Errors
    /// `orbit_rate` not positive and finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::Torque;
    /// assert!(Torque::gravity_gradient(1e-3).is_ok());
    /// assert!(Torque::gravity_gradient(-1.0).is_err());
    /// ```
    pub fn gravity_gradient(orbit_rate: f64) -> Result<Self> {
        if !(orbit_rate.is_finite() && orbit_rate > 0.0) {
            return Err(Error::invalid(
                "orbit_rate",
                "must be positive and finite",
                orbit_rate,
            ));
        }
        Ok(Torque::GravityGradient { orbit_rate })
    }

    /// A constant torque `vector` fixed in `frame`.
    ///
    /// # Errors
    /// A `vector` that is not finite.
    pub fn constant(vector: [f64; 3], frame: Frame) -> Result<Self> {
        if !vector.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "vector",
                "must be three finite numbers",
                vector,
            ));
        }
        Ok(Torque::Constant { vector, frame })
    }

    /// The registry's model it is.
    pub fn kind(&self) -> Kinds {
        match self {
            Torque::GravityGradient { .. } => Kinds::GRAVITY_GRADIENT,
            Torque::Constant { .. } => Kinds::TORQUE,
            Torque::Tabulated(_) => Kinds::TABULATED_TORQUE,
            Torque::Callable(_) => Kinds::CALLABLE_TORQUE,
        }
    }
}

/// The torques of a model, summed where they can be: what its right-hand side evaluates.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Torques {
    /// The gravity gradient's orbit rate, if any.
    orbit_rate: Option<f64>,
    /// The constant torques fixed in body axes, summed; and whether there are any.
    body: Option<Vector3<f64>>,
    /// The constant torques fixed in space, summed; and whether there are any.
    world: Option<Vector3<f64>>,
    /// The tabulated torques.
    tables: Vec<TabulatedTorque>,
    /// The torques of the user's functions.
    callables: Vec<CallableTorque>,
}

/// # Construction
impl Torques {
    /// The sum of `torques`.
    ///
    /// # Errors
    /// More than one gravity gradient (one orbit per body).
    pub fn of(torques: &[Torque]) -> Result<Self> {
        let mut out = Self::default();
        for torque in torques {
            if let Torque::Tabulated(table) = torque {
                out.tables.push(TabulatedTorque::clone(table));
            }
            if let Torque::Callable(c) = torque {
                out.callables.push(c.clone());
            }
            match *torque {
                Torque::GravityGradient { orbit_rate } => {
                    if out.orbit_rate.is_some() {
                        return Err(Error::invalid(
                            "torques",
                            "must hold at most one gravity gradient (one orbit)",
                            torques.len(),
                        ));
                    }
                    out.orbit_rate = Some(orbit_rate);
                }
                Torque::Constant { vector, frame } => {
                    let slot = match frame {
                        Frame::Body => &mut out.body,
                        Frame::World => &mut out.world,
                    };
                    *slot = Some(slot.unwrap_or_default() + Vector3::from(vector));
                }
                Torque::Tabulated(_) | Torque::Callable(_) => {}
            }
        }
        Ok(out)
    }

    /// The registry's models they are.
    pub fn kinds(&self) -> Kinds {
        let mut kinds = Kinds::NONE;
        if self.orbit_rate.is_some() {
            kinds = kinds.union(Kinds::GRAVITY_GRADIENT);
        }
        if self.body.is_some() || self.world.is_some() {
            kinds = kinds.union(Kinds::TORQUE);
        }
        if !self.tables.is_empty() {
            kinds = kinds.union(Kinds::TABULATED_TORQUE);
        }
        if !self.callables.is_empty() {
            kinds = kinds.union(Kinds::CALLABLE_TORQUE);
        }
        kinds
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.kinds() == Kinds::NONE
    }

    /// The gravity gradient's orbit rate, if any.
    pub fn orbit_rate(&self) -> Option<f64> {
        self.orbit_rate
    }

    /// The same torques with the body-fixed ones mapped by `to_axes` (a change of body axes).
    pub fn in_axes(&self, to_axes: impl Fn([f64; 3]) -> [f64; 3]) -> Self {
        Self {
            body: self.body.map(|v| Vector3::from(to_axes(v.into()))),
            tables: self.tables.iter().map(|t| t.in_axes(&to_axes)).collect(),
            callables: self.callables.iter().map(|c| c.in_axes(&to_axes)).collect(),
            ..self.clone()
        }
    }

    /// The times where a tabulated torque has a knot, increasing, each once: where the
    /// right-hand side has a kink or a jump (see [`super::tabulated`]).
    pub fn kinks(&self) -> Vec<f64> {
        let mut times: Vec<f64> = self
            .tables
            .iter()
            .flat_map(|t| t.table().times().iter().copied())
            .collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }

    /// The same torques for moments over `2^m` (see [`crate::float`]): a torque is a moment
    /// times a rate squared.
    ///
    /// # Errors
    /// A torque that float64 no longer holds.
    pub fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        let tables = self.tables.iter().map(|t| t.with_moments_scaled(m));
        Ok(Self {
            tables: tables.collect::<Result<_>>()?,
            callables: self
                .callables
                .iter()
                .map(|c| c.with_moments_scaled(m))
                .collect(),
            ..self.map_vectors(|v| ldexp(v, -m))?
        })
    }

    /// The same torques with times in the units of `scale`: the orbit rate over `2^e`, a
    /// torque (moment times rate squared) over `2^(2e)`.
    ///
    /// # Errors
    /// A torque that float64 no longer holds.
    pub fn in_units(&self, scale: RateScale) -> Result<Self> {
        let out = self.map_vectors(|v| scale.rate_to_unit(scale.rate_to_unit(v)))?;
        let tables = self.tables.iter().map(|t| t.in_units(scale));
        Ok(Self {
            orbit_rate: self.orbit_rate.map(|n| scale.rate_to_unit(n)),
            tables: tables.collect::<Result<_>>()?,
            callables: self.callables.iter().map(|c| c.in_units(scale)).collect(),
            ..out
        })
    }

    fn map_vectors(&self, f: impl Fn(f64) -> f64) -> Result<Self> {
        let map = |v: Option<Vector3<f64>>| -> Result<Option<Vector3<f64>>> {
            let Some(v) = v else { return Ok(None) };
            let out = v.map(&f);
            match out.iter().all(|c| c.is_finite()) && ((v.amax() == 0.0) == (out.amax() == 0.0)) {
                true => Ok(Some(out)),
                false => Err(Error::invalid(
                    "torques",
                    "must stay within float64 in the run's units (moments and rates scaled)",
                    v.as_slice(),
                )),
            }
        };
        Ok(Self {
            orbit_rate: self.orbit_rate,
            body: map(self.body)?,
            world: map(self.world)?,
            tables: self.tables.clone(),
            callables: self.callables.clone(),
        })
    }
}

/// # Evaluation
impl Torques {
    /// The direction from the planet to the body at `t` in world axes, `(cos nt, sin nt, 0)`.
    #[inline(always)]
    fn radial(n: f64, t: f64) -> Vector3<f64> {
        let (s, c) = (n * t).sin_cos();
        Vector3::new(c, s, 0.0)
    }

    /// The torque in body axes at `t` on a body at attitude `q` (world-from-body, normalised
    /// here), `inertia` applying its tensor (body axes) to a vector.
    #[inline(always)]
    pub fn torque_body(
        &self,
        t: f64,
        q: &Quaternion<f64>,
        inertia: impl FnOnce(&Vector3<f64>) -> Vector3<f64>,
    ) -> Vector3<f64> {
        let mut tau = self.body.unwrap_or_default();
        if let Some(n) = self.orbit_rate {
            tau += gravity_gradient_torque(n, t, q, inertia);
        }
        if let Some(v) = self.world {
            tau += world_to_body(q, &v);
        }
        for table in &self.tables {
            tau += table.torque_body(t, q);
        }
        tau
    }

    /// Whether the user's functions give a torque: it wants the body rates
    /// ([`Torques::callables_body`]).
    #[inline(always)]
    pub fn has_callables(&self) -> bool {
        !self.callables.is_empty()
    }

    /// The torque of the user's functions in body axes at `t` on a body at attitude `q`
    /// turning at `omega`.
    #[inline]
    pub fn callables_body(
        &self,
        t: f64,
        q: &Quaternion<f64>,
        omega: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.callables
            .iter()
            .fold(Vector3::zeros(), |tau, c| tau + c.torque_body(t, q, omega))
    }

    /// The user's functions.
    pub fn callables(&self) -> &[CallableTorque] {
        &self.callables
    }

    /// The Jacobi integral (see the module doc) at `t` of a body of tensor `tensor` at attitude
    /// `q`, with kinetic energy `energy` and total angular momentum `momentum` (body axes);
    /// `None` without a gravity gradient.
    pub fn jacobi(
        &self,
        t: f64,
        q: &Quaternion<f64>,
        tensor: &Matrix3<f64>,
        energy: f64,
        momentum: &Vector3<f64>,
    ) -> Option<f64> {
        let n = self.orbit_rate?;
        let to_body = rotation_matrix(q).transpose();
        let r = to_body * Self::radial(n, t);
        let normal = to_body * Vector3::z();
        Some(energy - n * normal.dot(momentum) + 1.5 * n * n * r.dot(&(tensor * r)))
    }

    /// A bound on the body rates of a motion of Jacobi integral `jacobi` in the gravity
    /// gradient, for a body of least and largest moments `least`, `largest` with wheels of
    /// total momentum `wheels` (a norm): from `J ≥ ½ λ_min |ω − n ẑ_b|² − ½ n² λ_max − n |h|`,
    /// `|ω| ≤ √(2 (J + ½ n² λ_max + n |h|) / λ_min) + n`. `None` without a gravity gradient.
    pub fn rate_bound(&self, least: f64, largest: f64, jacobi: f64, wheels: f64) -> Option<f64> {
        let n = self.orbit_rate?;
        let room = jacobi + 0.5 * n * n * largest + n * wheels;
        Some((2.0 * room.max(0.0) / least).sqrt() + n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn a_body_aligned_with_the_radius_feels_no_gravity_gradient() {
        let t = Torques::of(&[Torque::gravity_gradient(0.5).unwrap()]).unwrap();
        let i = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
        let tau = t.torque_body(0.0, &Quaternion::identity(), |v| i * v);
        assert_eq!(tau, Vector3::zeros());
    }

    #[test]
    fn the_gravity_gradient_is_minus_the_gradient_of_its_potential() {
        // a small turn δ about body axis k changes V by −τ_k δ
        let n = 0.7;
        let t = Torques::of(&[Torque::gravity_gradient(n).unwrap()]).unwrap();
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let q = Quaternion::new(0.9, 0.2, -0.3, 0.25).normalize();
        let v = |q: &Quaternion<f64>| {
            let r = rotation_matrix(q).transpose()
                * Vector3::new((n * 0.4).cos(), (n * 0.4).sin(), 0.0);
            1.5 * n * n * r.dot(&(i * r))
        };
        let tau = t.torque_body(0.4, &q, |v| i * v);
        let h = 1e-6;
        for k in 0..3 {
            let mut a = Vector3::<f64>::zeros();
            a[k] = 0.5 * h;
            let turn =
                |s: f64| q * Quaternion::from_parts((1.0_f64 - a.norm_squared()).sqrt(), a * s);
            let dv = (v(&turn(1.0)) - v(&turn(-1.0))) / (2.0 * h);
            assert_relative_eq!(dv, -tau[k], epsilon = 1e-8);
        }
    }

    #[test]
    fn two_gravity_gradients_are_refused() {
        let g = Torque::gravity_gradient(1.0).unwrap();
        assert!(Torques::of(&[g.clone(), g]).is_err());
        assert!(Torque::gravity_gradient(f64::NAN).is_err());
        assert!(Torque::constant([1.0, f64::INFINITY, 0.0], Frame::Body).is_err());
        assert!("space".parse::<Frame>().is_err());
    }

    #[test]
    fn a_world_torque_is_seen_turned_in_body_axes() {
        let t = Torques::of(&[Torque::constant([0.0, 0.0, 1.0], Frame::World).unwrap()]).unwrap();
        // body turned +90° about world x: body y points along world z
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let tau = t.torque_body(0.0, &Quaternion::new(h, h, 0.0, 0.0), |v| *v);
        assert!((tau - Vector3::new(0.0, 1.0, 0.0)).amax() < 1e-15);
    }
}
