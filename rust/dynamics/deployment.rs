//! A deployment: a body whose inertia tensor changes in a prescribed way while it turns freely
//! (booms, antennas or mirror frames unfolding in orbit).
//!
//! **Law.** With no external torque the angular momentum is fixed in space; in body axes
//!
//! ```text
//! L' = L × ω,    ω = I(t)⁻¹ L,    q' = ½ q ⊗ (0, ω),
//! ```
//!
//! with `L` the body-frame angular momentum. The state is `[L_body (3), q (4)]`: `|L|` and
//! `M(q) L` are kept exactly by the law, and the rates follow from one 3 × 3 solve per
//! evaluation (a diagonal division when every knot is diagonal). The model assumes the moving
//! parts carry no angular momentum of their own relative to the body (symmetric deployments:
//! booms pushed out in opposite pairs, panels unfolded in mirror pairs), so that `L = I ω`.
//!
//! **Energy.** `E = ½ Lᵀ I⁻¹ L`, so `E' = ωᵀ L' + ½ Lᵀ (I⁻¹)' L = ωᵀ (L × ω) − ½ ωᵀ I' ω
//! = −½ ωᵀ I' ω`: the internal forces that move the mass outwards (I' positive definite) take
//! energy from the rotation, as a skater's arms spreading out do.
//!
//! **Interpolation.** Between knots `t_k < t_{k+1}` the tensor is
//! `I(t) = I_k + s(τ) (I_{k+1} − I_k)`, `τ = (t − t_k) / (t_{k+1} − t_k)`, with the quintic
//! "smootherstep" `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`: rate and acceleration are zero at every knot
//! (the law is C²), and each `I(t)` is a convex combination of two positive definite tensors,
//! so it stays positive definite. Before the first knot and after the last the tensor is
//! constant.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::ode::OdeSystem;

use super::model::{quaternion_increment, Model};

/// The state `[Lx, Ly, Lz, Q, U, V, W]`: body-frame angular momentum, then the attitude.
pub type DeploymentState = [f64; 7];

/// A prescribed, smooth inertia tensor `I(t)` given at knots (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Deployment {
    times: Vec<f64>,
    tensors: Vec<Matrix3<f64>>,
    /// Every knot is diagonal: `I⁻¹ L` is three divisions.
    diagonal: bool,
}

/// `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` and `s'(τ) = 30 τ² (1 − τ)²`.
#[inline(always)]
fn smootherstep(tau: f64) -> (f64, f64) {
    let t2 = tau * tau;
    let s = t2 * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
    let u = 1.0 - tau;
    (s, 30.0 * t2 * u * u)
}

/// `M⁻¹ b` for a symmetric positive definite `M`, by its cofactors.
#[inline(always)]
fn solve_symmetric(m: &Matrix3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    let (a, bb, c) = (m[(0, 0)], m[(0, 1)], m[(0, 2)]);
    let (d, e, f) = (m[(1, 1)], m[(1, 2)], m[(2, 2)]);
    let c00 = d * f - e * e;
    let c01 = c * e - bb * f;
    let c02 = bb * e - c * d;
    let c11 = a * f - c * c;
    let c12 = bb * c - a * e;
    let c22 = a * d - bb * bb;
    let inv_det = 1.0 / (a * c00 + bb * c01 + c * c02);
    Vector3::new(
        (c00 * b.x + c01 * b.y + c02 * b.z) * inv_det,
        (c01 * b.x + c11 * b.y + c12 * b.z) * inv_det,
        (c02 * b.x + c12 * b.y + c22 * b.z) * inv_det,
    )
}

/// # Construction
impl Deployment {
    /// A deployment through the tensors `tensors[k]` (body axes, products of inertia with a
    /// minus sign off the diagonal) at the increasing times `times[k]`.
    ///
    /// # Errors
    /// At least one knot; as many tensors as times; finite, strictly increasing times;
    /// symmetric, positive definite, finite tensors.
    ///
    /// # Example
    /// ```
    /// use approx::assert_relative_eq;
    /// use nalgebra::Matrix3;
    /// use dzhanibekov::dynamics::Deployment;
    /// let stowed = Matrix3::from_diagonal(&[1.0, 2.0, 3.0].into());
    /// let deployed = Matrix3::from_diagonal(&[1.0, 3.0, 2.0].into());
    /// let d = Deployment::try_new(vec![0.0, 10.0], vec![stowed, deployed]).unwrap();
    /// assert_relative_eq!(d.inertia_at(5.0)[(1, 1)], 2.5);
    /// assert_relative_eq!(d.inertia_at(20.0)[(2, 2)], 2.0);
    /// ```
    pub fn try_new(times: Vec<f64>, tensors: Vec<Matrix3<f64>>) -> Result<Self> {
        if times.is_empty() || times.len() != tensors.len() {
            return Err(Error::invalid(
                "times",
                "must be non-empty and give one time per inertia tensor",
                (times.len(), tensors.len()),
            ));
        }
        if !times.iter().all(|t| t.is_finite()) || times.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::invalid(
                "times",
                "must be finite and strictly increasing",
                times,
            ));
        }
        for m in &tensors {
            let symmetric = (m - m.transpose()).amax() <= 1e-12 * m.amax();
            let spd = m.iter().all(|v| v.is_finite())
                && symmetric
                && m.cholesky().is_some()
                && m.determinant() > 0.0;
            if !spd {
                return Err(Error::invalid(
                    "inertia",
                    "must hold symmetric, positive definite, finite tensors (3 × 3)",
                    m.as_slice(),
                ));
            }
        }
        let tensors: Vec<Matrix3<f64>> =
            tensors.iter().map(|m| (m + m.transpose()) * 0.5).collect();
        let diagonal = tensors
            .iter()
            .all(|m| (0..3).all(|i| (0..3).all(|j| i == j || m[(i, j)] == 0.0)));
        Ok(Self {
            times,
            tensors,
            diagonal,
        })
    }

    /// Knots from principal moments: diagonal tensors.
    ///
    /// # Errors
    /// As [`Deployment::try_new`].
    pub fn from_moments(times: Vec<f64>, moments: &[[f64; 3]]) -> Result<Self> {
        let tensors = moments
            .iter()
            .map(|m| Matrix3::from_diagonal(&Vector3::from(*m)))
            .collect();
        Self::try_new(times, tensors)
    }
}

/// # Properties
impl Deployment {
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    pub fn tensors(&self) -> &[Matrix3<f64>] {
        &self.tensors
    }

    /// `(I(t), I'(t))`.
    #[inline(always)]
    pub fn inertia_and_rate_at(&self, t: f64) -> (Matrix3<f64>, Matrix3<f64>) {
        let k = self.times.partition_point(|&tk| tk <= t);
        if k == 0 {
            return (self.tensors[0], Matrix3::zeros());
        }
        if k == self.times.len() {
            return (self.tensors[k - 1], Matrix3::zeros());
        }
        let (ta, tb) = (self.times[k - 1], self.times[k]);
        let span = tb - ta;
        let (s, ds) = smootherstep((t - ta) / span);
        let delta = self.tensors[k] - self.tensors[k - 1];
        (self.tensors[k - 1] + delta * s, delta * (ds / span))
    }

    /// The tensor `I(t)`.
    pub fn inertia_at(&self, t: f64) -> Matrix3<f64> {
        self.inertia_and_rate_at(t).0
    }

    /// `ω = I(t)⁻¹ L`.
    #[inline(always)]
    pub fn omega_from_momentum(&self, t: f64, l: &Vector3<f64>) -> Vector3<f64> {
        let k = self.times.partition_point(|&tk| tk <= t);
        let m = if k == 0 {
            self.tensors[0]
        } else if k == self.times.len() {
            self.tensors[k - 1]
        } else {
            let (ta, tb) = (self.times[k - 1], self.times[k]);
            let (s, _) = smootherstep((t - ta) / (tb - ta));
            self.tensors[k - 1] + (self.tensors[k] - self.tensors[k - 1]) * s
        };
        if self.diagonal {
            Vector3::new(l.x / m[(0, 0)], l.y / m[(1, 1)], l.z / m[(2, 2)])
        } else {
            solve_symmetric(&m, l)
        }
    }

    /// The state at `t0` from the body rates `omega_body` and the attitude `q`.
    pub fn state_from(&self, t0: f64, omega_body: [f64; 3], q: [f64; 4]) -> DeploymentState {
        let l = self.inertia_at(t0) * Vector3::from(omega_body);
        [l.x, l.y, l.z, q[0], q[1], q[2], q[3]]
    }
}

impl OdeSystem<7> for Deployment {
    #[inline(always)]
    fn increment(&self, t: f64, x: &DeploymentState, s: f64) -> DeploymentState {
        let l = Vector3::new(x[0], x[1], x[2]);
        let omega = self.omega_from_momentum(t, &l);
        let dl = l.cross(&omega) * s;
        let dq = quaternion_increment([x[3], x[4], x[5], x[6]], omega, s);
        [dl.x, dl.y, dl.z, dq[0], dq[1], dq[2], dq[3]]
    }
}

impl Model<7> for Deployment {
    const NAME: &'static str = "deployment";

    fn omega_body(&self, t: f64, x: &DeploymentState) -> Vector3<f64> {
        self.omega_from_momentum(t, &Vector3::new(x[0], x[1], x[2]))
    }

    fn momentum_body(&self, _t: f64, x: &DeploymentState) -> Vector3<f64> {
        Vector3::new(x[0], x[1], x[2])
    }

    fn energy(&self, t: f64, x: &DeploymentState) -> f64 {
        let l = Vector3::new(x[0], x[1], x[2]);
        0.5 * l.dot(&self.omega_from_momentum(t, &l))
    }

    fn scale_rates(&self, x: &mut DeploymentState, factor: f64) {
        for v in &mut x[..3] {
            *v *= factor;
        }
    }

    fn principal_moments(&self, t: f64) -> Option<Vector3<f64>> {
        self.diagonal.then(|| self.inertia_at(t).diagonal())
    }

    fn in_units(&self, scale: RateScale) -> Result<Self> {
        let times: Vec<f64> = self.times.iter().map(|t| scale.time_to_unit(*t)).collect();
        if !times.iter().all(|t| t.is_finite()) {
            return Err(Error::TooLarge {
                what: "the deployment",
                needed: format!(
                    "its knot times ({:.3e}) times the rates' scale ({:.3e})",
                    self.times.last().copied().unwrap_or(0.0),
                    scale.time_to_unit(1.0)
                ),
                limit: "what float64 holds".into(),
                hint: "take knot times within t_end, or smaller rates",
            });
        }
        Self::try_new(times, self.tensors.clone())
    }

    /// `|L| / λ_min`, with `λ_min` the smallest eigenvalue over the knots: `|ω| ≤ |L| / λ_min(I(t))`
    /// and the smallest eigenvalue of a convex combination is at least the smallest of the two.
    fn rate_bound(&self, x0: &DeploymentState) -> f64 {
        let l = Vector3::new(x0[0], x0[1], x0[2]).norm();
        let lambda_min = self
            .tensors
            .iter()
            .map(|m| m.symmetric_eigenvalues().min())
            .fold(f64::INFINITY, f64::min);
        l / lambda_min
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

    #[test]
    fn interpolation_is_continuous_with_zero_rate_at_the_knots() {
        let d = tilted();
        for t in [1.0, 3.0] {
            let (before, rate_before) = d.inertia_and_rate_at(t - 1e-9);
            let (after, rate_after) = d.inertia_and_rate_at(t + 1e-9);
            assert!((before - after).amax() < 1e-8);
            assert!(rate_before.amax() < 1e-6 && rate_after.amax() < 1e-6);
        }
        // the rate is the derivative of the tensor (central difference)
        let h = 1e-6;
        let numeric = (d.inertia_at(1.7 + h) - d.inertia_at(1.7 - h)) / (2.0 * h);
        assert!((numeric - d.inertia_and_rate_at(1.7).1).amax() < 1e-8);
    }

    #[test]
    fn energy_rate_is_minus_half_omega_idot_omega() {
        let d = tilted();
        let x = d.state_from(2.2, [0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
        let dx = d.rhs(2.2, &x);
        let h = 1e-6;
        let mut xp = x;
        let mut xm = x;
        for k in 0..7 {
            xp[k] += h * dx[k];
            xm[k] -= h * dx[k];
        }
        let numeric = (d.energy(2.2 + h, &xp) - d.energy(2.2 - h, &xm)) / (2.0 * h);
        let omega = d.omega_body(2.2, &x);
        let idot = d.inertia_and_rate_at(2.2).1;
        assert_relative_eq!(
            numeric,
            -0.5 * omega.dot(&(idot * omega)),
            max_relative = 1e-7
        );
    }

    #[test]
    fn the_solve_inverts_the_tensor() {
        let d = tilted();
        let l = Vector3::new(0.3, -1.0, 2.0);
        let omega = d.omega_from_momentum(2.0, &l);
        assert!((d.inertia_at(2.0) * omega - l).amax() < 1e-14);
    }

    #[test]
    fn bad_knots_are_refused() {
        let i = Matrix3::identity();
        assert!(Deployment::try_new(vec![0.0, 0.0], vec![i, i]).is_err());
        assert!(Deployment::try_new(vec![0.0], vec![i, i]).is_err());
        assert!(Deployment::try_new(vec![0.0], vec![-i]).is_err());
        let skew = Matrix3::new(1.0, 0.5, 0.0, -0.5, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(Deployment::try_new(vec![0.0], vec![skew]).is_err());
        assert!(Deployment::try_new(vec![f64::NAN], vec![i]).is_err());
    }
}
