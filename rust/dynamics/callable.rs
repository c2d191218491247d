//! A torque computed by the user's own code, `τ_b = f(t, q, ω)`: the core sees a
//! [`Function`] (a trait object), the Python binding implements it by calling a Python
//! function with the GIL taken for each call. The core stays free of Python.
//!
//! **Units and axes.** A run goes in its own axes and units (principal axes, moments over a
//! power of two, times and rates scaled at extreme rates; see [`crate::run::simulate_system`]);
//! the function sees the user's: time, the attitude (world-from-body of the user's body axes,
//! normalised), the body rates in the user's body axes, and gives the torque in them.
//!
//! **Failure.** A function that fails (the binding: raises, or returns what is not three finite
//! numbers) returns false and keeps why; the torque is then NaN, the state stops being finite
//! and the run stops at its next check with an error, which the binding replaces by the
//! function's own. Nothing is called again once it failed.
//!
//! It keeps nothing but `|q|`.

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::error::Result;
use crate::float::{ldexp, RateScale};

use super::kinds::{Conserved, Traits};
use super::part::{
    Arg, Ctx, EnergyRole, Fields, Function, MapFunction, ModelInfo, Param, ParamKind, Part,
};

/// A user's torque function, seen from a run's axes and units (see the module doc).
#[derive(Clone)]
pub struct CallableTorque {
    function: Arc<dyn Function>,
    /// `R` (user axes from the run's) and `q_R`, if the run's axes are not the user's.
    axes: Option<(Matrix3<f64>, Quaternion<f64>)>,
    /// The run's moments are the user's over `2^moments`.
    moments: i32,
    /// The run's times and rates (identity: the user's).
    scale: RateScale,
}

impl std::fmt::Debug for CallableTorque {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CallableTorque")
            .field("axes", &self.axes)
            .field("moments", &self.moments)
            .field("scale", &self.scale)
            .finish_non_exhaustive()
    }
}

/// The same function (the same object), seen the same way.
impl PartialEq for CallableTorque {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.function, &other.function)
            && self.axes == other.axes
            && self.moments == other.moments
            && self.scale == other.scale
    }
}

impl CallableTorque {
    /// The torque `function` gives, seen in the user's axes and units.
    pub fn new(function: Arc<dyn Function>) -> Self {
        Self {
            function,
            axes: None,
            moments: 0,
            scale: RateScale::of([1.0; 3]),
        }
    }

    /// The user's function.
    pub fn function(&self) -> &Arc<dyn Function> {
        &self.function
    }

    /// [`CallableTorque::torque_body`], out of line (see [`Part::torque`]'s).
    #[inline(never)]
    fn torque_of(&self, t: f64, q: Quaternion<f64>, omega: Vector3<f64>) -> Vector3<f64> {
        self.torque_body(t, &q, &omega)
    }

    /// The torque in the run's body axes and units at the run's `t`, attitude `q` and rates
    /// `omega`; NaN if the function failed.
    #[inline]
    pub fn torque_body(&self, t: f64, q: &Quaternion<f64>, omega: &Vector3<f64>) -> Vector3<f64> {
        let s = self.scale;
        let t = s.time_from_unit(t);
        let w = omega.map(|c| s.rate_from_unit(c));
        let (q, w) = match &self.axes {
            Some((r, qr)) => (q * qr.conjugate(), r * w),
            None => (*q, w),
        };
        let n = q.norm();
        let q = [q.w / n, q.i / n, q.j / n, q.k / n];
        let mut tau = [0.0; 3];
        let args = [Arg::Number(t), Arg::Vector(&q), Arg::Vector(w.as_slice())];
        if !self.function.call(&args, &mut tau) {
            return Vector3::repeat(f64::NAN);
        }
        let mut tau = Vector3::from(tau);
        if let Some((r, _)) = &self.axes {
            tau = r.tr_mul(&tau);
        }
        // a torque is a moment times a rate squared
        tau.map(|c| s.rate_to_unit(s.rate_to_unit(ldexp(c, -self.moments))))
    }
}

impl Part for CallableTorque {
    const INFO: ModelInfo = ModelInfo {
        name: "callable_torque",
        about: "a torque computed by the user's function f(t, q, ω) in body axes, called at \
                each evaluation (Python speed; nothing kept but |q|)",
        law: false,
        params: &[Param::new(
            "func",
            ParamKind::Function {
                args: "t, q, omega",
                returns: 3,
            },
            "the torque in body axes at time t, attitude q (world-from-body, scalar first) and \
             body rates omega",
        )],
        state: &[],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE.union(Traits::RATE_TORQUE),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Ok(Self::new(fields.function("func")?))
    }

    /// The call is out of line and takes its arguments by value: a context passed on by
    /// reference would keep every evaluation's context in memory.
    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        self.torque_of(c.t, c.q, c.omega)
    }

    /// Seen in the run's body axes, `to_axes` taking a vector of the user's axes into them
    /// (`Rᵀ v`).
    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        // the columns of Rᵀ are the images of the user's basis vectors (exact for a basis)
        let rt = Matrix3::from_columns(&[
            Vector3::from(to_axes([1.0, 0.0, 0.0])),
            Vector3::from(to_axes([0.0, 1.0, 0.0])),
            Vector3::from(to_axes([0.0, 0.0, 1.0])),
        ]);
        let axes = match rt == Matrix3::identity() {
            true => None,
            false => {
                let r = rt.transpose();
                Some((r, UnitQuaternion::from_matrix(&r).into_inner()))
            }
        };
        Self {
            axes,
            ..self.clone()
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            moments: self.moments + m,
            ..self.clone()
        })
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        Ok(Self {
            scale,
            ..self.clone()
        })
    }

    fn functions(&self) -> Vec<&Arc<dyn Function>> {
        vec![&self.function]
    }

    fn map_functions(&self, f: &mut MapFunction<'_>) -> Self {
        Self {
            function: f(&self.function),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::any::Any;

    /// `τ = (t, ω_x, q_0)`, failing before `t = 0`.
    struct Probe;

    impl Function for Probe {
        fn call(&self, args: &[Arg<'_>], out: &mut [f64]) -> bool {
            let [Arg::Number(t), Arg::Vector(q), Arg::Vector(w)] = args else {
                return false;
            };
            out.copy_from_slice(&[*t, w[0], q[0]]);
            *t >= 0.0
        }
        fn as_any(&self) -> &dyn Any {
            self
        }
    }

    #[test]
    fn the_function_sees_the_users_axes_and_units_and_a_failure_is_nan() {
        let c = CallableTorque::new(Arc::new(Probe));
        let q = Quaternion::new(2.0, 0.0, 0.0, 0.0);
        let tau = c.torque_body(1.5, &q, &Vector3::new(0.25, 0.0, 0.0));
        assert_eq!(tau, Vector3::new(1.5, 0.25, 1.0));
        // moments over 2: the torque over 2; a turn of the axes by 90° about z
        let turned = c
            .with_moments_scaled(1)
            .unwrap()
            .in_axes(&|v| [v[1], -v[0], v[2]]);
        let tau = turned.torque_body(1.0, &Quaternion::identity(), &Vector3::new(0.0, 0.5, 0.0));
        // R = Rz(90°): the user's ω = R (0, 0.5, 0) = (−0.5, 0, 0), the user's q = q_R*; the
        // function's (1, −0.5, cos 45°) back in the run's axes (Rᵀ) and over 2
        assert_eq!((tau.x, tau.y), (-0.25, -0.5));
        assert!((tau.z.abs() - 0.5 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        assert!(c.torque_body(-1.0, &q, &Vector3::zeros()).x.is_nan());
        assert_eq!(c, c.clone());
        assert_ne!(c, CallableTorque::new(Arc::new(Probe)));
    }
}
