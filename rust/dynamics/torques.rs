//! A constant external torque, fixed in body axes or in space: a part of a system
//! ([`ConstantTorque`]). External torques add to the general model's momentum law,
//! `H' = H × ω + τ_body` (see [`super::GeneralModel`]); the others are the gravity gradient
//! ([`super::GravityGradient`]), a tabulated torque ([`super::TabulatedTorque`]) and the
//! user's function ([`super::CallableTorque`]).
//!
//! **Law.** A vector `τ` fixed in body axes, or fixed in space (`τ_b = M(q)ᵀ τ`). It keeps
//! nothing but `|q|`. Constant torques are summed once before a run (one vector in each axes).

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};
use crate::kinematics::world_to_body;

use super::kinds::{Conserved, Traits};
use super::part::{Ctx, EnergyRole, Fields, Frame, ModelInfo, Param, ParamKind, Part};

/// The frames a vector can be fixed in, as parameters name them.
pub(crate) const FRAMES: &[&str] = &["body", "world"];

/// A constant external torque (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantTorque {
    vector: Vector3<f64>,
    frame: Frame,
}

impl ConstantTorque {
    /// A constant torque `vector` fixed in `frame`.
    ///
    /// # Errors
    /// A `vector` that is not finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::{ConstantTorque, Frame};
    /// assert!(ConstantTorque::try_new([0.0, 0.0, 1.0], Frame::World).is_ok());
    /// assert!(ConstantTorque::try_new([1.0, f64::INFINITY, 0.0], Frame::Body).is_err());
    /// ```
    pub fn try_new(vector: [f64; 3], frame: Frame) -> Result<Self> {
        if !vector.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "vector",
                "must be three finite numbers",
                vector,
            ));
        }
        Ok(Self {
            vector: Vector3::from(vector),
            frame,
        })
    }

    pub fn vector(&self) -> Vector3<f64> {
        self.vector
    }

    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// The same torque with its vector mapped by `f` (units), refused if float64 no longer
    /// holds it (or a non-zero torque underflows to zero).
    fn mapped(&self, f: impl Fn(f64) -> f64) -> Result<Self> {
        let out = self.vector.map(f);
        match out.iter().all(|c| c.is_finite())
            && ((self.vector.amax() == 0.0) == (out.amax() == 0.0))
        {
            true => Ok(Self {
                vector: out,
                ..*self
            }),
            false => Err(Error::invalid(
                "vector",
                "(a torque) must stay within float64 in the run's units (moments and rates \
                 scaled)",
                self.vector.as_slice(),
            )),
        }
    }
}

impl Part for ConstantTorque {
    const INFO: ModelInfo = ModelInfo {
        name: "constant_torque",
        about: "a constant external torque in body or world axes (nothing kept but |q|)",
        law: false,
        params: &[
            Param::new("vector", ParamKind::Vector, "the torque"),
            Param::new(
                "frame",
                ParamKind::Choice(FRAMES),
                "the axes it is fixed in: the body's own or space's",
            ),
        ],
        state: &[],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE,
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(fields.vector("vector")?, fields.choice("frame")?)
    }

    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        match self.frame {
            Frame::Body => self.vector,
            Frame::World => world_to_body(&c.q, &self.vector),
        }
    }

    fn constant_torque(&self) -> Option<(Vector3<f64>, Frame)> {
        Some((self.vector, self.frame))
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        match self.frame {
            Frame::Body => Self {
                vector: Vector3::from(to_axes(self.vector.into())),
                ..*self
            },
            Frame::World => *self,
        }
    }

    /// A torque is a moment times a rate squared.
    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        self.mapped(|v| ldexp(v, -m))
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        self.mapped(|v| scale.rate_to_unit(scale.rate_to_unit(v)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::general::{ConstantInertia, InertiaLaw};
    use crate::dynamics::GravityGradient;
    use crate::kinematics::rotation_matrix;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Quaternion};

    fn ctx(law: &InertiaLaw, t: f64, q: Quaternion<f64>) -> Ctx<'_> {
        Ctx {
            t,
            q,
            omega: Vector3::zeros(),
            inertia: law,
            moving: None,
            timed: Default::default(),
        }
    }

    fn law(i: Matrix3<f64>) -> InertiaLaw {
        InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap())
    }

    #[test]
    fn a_body_aligned_with_the_radius_feels_no_gravity_gradient() {
        let g = GravityGradient::try_new(0.5).unwrap();
        let l = law(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)));
        let tau = g.torque(&ctx(&l, 0.0, Quaternion::identity()), &[]);
        assert_eq!(tau, Vector3::zeros());
    }

    #[test]
    fn the_gravity_gradient_is_minus_the_gradient_of_its_potential() {
        // a small turn δ about body axis k changes V by −τ_k δ
        let n = 0.7;
        let g = GravityGradient::try_new(n).unwrap();
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let l = law(i);
        let q = Quaternion::new(0.9, 0.2, -0.3, 0.25).normalize();
        let v = |q: &Quaternion<f64>| {
            let r = rotation_matrix(q).transpose()
                * Vector3::new((n * 0.4).cos(), (n * 0.4).sin(), 0.0);
            1.5 * n * n * r.dot(&(i * r))
        };
        let tau = g.torque(&ctx(&l, 0.4, q), &[]);
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
    fn bad_torques_are_refused() {
        assert!(GravityGradient::try_new(f64::NAN).is_err());
        assert!(ConstantTorque::try_new([1.0, f64::INFINITY, 0.0], Frame::Body).is_err());
        assert!("space".parse::<Frame>().is_err());
    }

    #[test]
    fn a_world_torque_is_seen_turned_in_body_axes() {
        let t = ConstantTorque::try_new([0.0, 0.0, 1.0], Frame::World).unwrap();
        let l = law(Matrix3::identity());
        // body turned +90° about world x: body y points along world z
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let tau = t.torque(&ctx(&l, 0.0, Quaternion::new(h, h, 0.0, 0.0)), &[]);
        assert!((tau - Vector3::new(0.0, 1.0, 0.0)).amax() < 1e-15);
    }
}
