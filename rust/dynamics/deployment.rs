//! A deployment: a body whose inertia tensor changes in a prescribed way while it turns freely
//! (booms, antennas or mirror frames unfolding in orbit).
//!
//! The schedule; the law it drives is [`super::general`]'s. **Law.** With no external torque the angular momentum is fixed in space; in body axes
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

use crate::buffer::try_collect;
use crate::error::{Error, Result};
use crate::float::RateScale;

use super::model::{mid_axis_of as axis_of, MidAxis};

/// What to say when a deployment's knots cannot be copied.
const KNOTS_HINT: &str = "give fewer knots";

/// A prescribed, smooth inertia tensor `I(t)` given at knots (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Deployment {
    times: Vec<f64>,
    tensors: Vec<Matrix3<f64>>,
    /// Every knot is diagonal: `I⁻¹ L` is three divisions.
    diagonal: bool,
    /// The intermediate axis before the first knot and after the last (the body is constant
    /// there: found once).
    ends: [MidAxis; 2],
    /// `I⁻¹` before the first knot and after the last (see [`Inverse`]), found once.
    inverses: [Inverse; 2],
}

/// A tensor's inverse as the rates take it: the reciprocal moments of a diagonal tensor, or
/// the six entries of a symmetric one.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Inverse {
    Diagonal(Vector3<f64>),
    Symmetric([f64; 6]),
}

impl Inverse {
    fn of(m: &Matrix3<f64>, diagonal: bool) -> Self {
        match diagonal {
            true => Inverse::Diagonal(m.diagonal().map(|v| 1.0 / v)),
            false => Inverse::Symmetric(symmetric_inverse(m)),
        }
    }

    #[inline(always)]
    fn times(&self, l: &Vector3<f64>) -> Vector3<f64> {
        match self {
            Inverse::Diagonal(r) => l.component_mul(r),
            Inverse::Symmetric([a, b, c, d, e, f]) => Vector3::new(
                a * l.x + b * l.y + c * l.z,
                b * l.x + d * l.y + e * l.z,
                c * l.x + e * l.y + f * l.z,
            ),
        }
    }
}

/// `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` and `s'(τ) = 30 τ² (1 − τ)²`.
#[inline(always)]
fn smootherstep(tau: f64) -> (f64, f64) {
    let t2 = tau * tau;
    let s = t2 * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
    let u = 1.0 - tau;
    (s, 30.0 * t2 * u * u)
}

/// The cofactors `(c00, c01, c02, c11, c12, c22)` of a symmetric `M` and the reciprocal of its
/// determinant: `M⁻¹ = C / det M`.
#[inline(always)]
fn cofactors(m: &Matrix3<f64>) -> ([f64; 6], f64) {
    let (a, bb, c) = (m[(0, 0)], m[(0, 1)], m[(0, 2)]);
    let (d, e, f) = (m[(1, 1)], m[(1, 2)], m[(2, 2)]);
    let c00 = d * f - e * e;
    let c01 = c * e - bb * f;
    let c02 = bb * e - c * d;
    let c11 = a * f - c * c;
    let c12 = bb * c - a * e;
    let c22 = a * d - bb * bb;
    let inv_det = 1.0 / (a * c00 + bb * c01 + c * c02);
    ([c00, c01, c02, c11, c12, c22], inv_det)
}

/// The six entries `(a, b, c, d, e, f)` of `M⁻¹ = [[a, b, c], [b, d, e], [c, e, f]]` for a
/// symmetric positive definite `M`.
fn symmetric_inverse(m: &Matrix3<f64>) -> [f64; 6] {
    let (c, inv_det) = cofactors(m);
    c.map(|v| v * inv_det)
}

/// `M⁻¹ b` for a symmetric positive definite `M`, by its cofactors: the division runs beside
/// the products by `b`, not before them.
#[inline(always)]
fn solve_symmetric(m: &Matrix3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    let ([c00, c01, c02, c11, c12, c22], inv_det) = cofactors(m);
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
        check_knot_times(&times)?;
        for (k, m) in tensors.iter().enumerate() {
            let symmetric = (m - m.transpose()).amax() <= 1e-12 * m.amax();
            // Cholesky of the tensor over a power of two near its largest entry: moments of
            // any size, no product of them formed
            let unit = m * crate::ode::power_of_two_scale(m.amax());
            let spd = m.iter().all(|v| v.is_finite()) && symmetric && unit.cholesky().is_some();
            if !spd {
                return Err(Error::invalid(
                    "inertia",
                    "must hold symmetric, positive definite, finite tensors (3 × 3)",
                    format!("inertia[{k}] = {:?}", m.transpose().as_slice()),
                ));
            }
        }
        // halves first: a moment near the largest float64 would overflow in `m + mᵀ`
        let symmetric = tensors.iter().map(|m| m * 0.5 + m.transpose() * 0.5);
        let tensors = try_collect(symmetric, tensors.len(), "the knots", KNOTS_HINT)?;
        let diagonal = tensors
            .iter()
            .all(|m| (0..3).all(|i| (0..3).all(|j| i == j || m[(i, j)] == 0.0)));
        let (Some(first), Some(last)) = (tensors.first(), tensors.last()) else {
            unreachable!("at least one knot, checked above")
        };
        let ends = [axis_of(first, diagonal), axis_of(last, diagonal)];
        let inverses = [Inverse::of(first, diagonal), Inverse::of(last, diagonal)];
        Ok(Self {
            times,
            tensors,
            diagonal,
            ends,
            inverses,
        })
    }

    /// Knots from principal moments: diagonal tensors.
    ///
    /// # Errors
    /// As [`Deployment::try_new`].
    pub fn from_moments(times: Vec<f64>, moments: &[[f64; 3]]) -> Result<Self> {
        let diagonal = moments
            .iter()
            .map(|m| Matrix3::from_diagonal(&Vector3::from(*m)));
        let tensors = try_collect(diagonal, moments.len(), "the knots", KNOTS_HINT)?;
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
        // (a span beyond float64, knots at ±1.7e308: its rate is 0 to float64's precision)
        let span = tb - ta;
        let (s, ds) = smootherstep(crate::float::fraction(t, ta, tb));
        let delta = self.tensors[k] - self.tensors[k - 1];
        (self.tensors[k - 1] + delta * s, delta * (ds / span))
    }

    /// The tensor `I(t)`.
    pub fn inertia_at(&self, t: f64) -> Matrix3<f64> {
        self.inertia_and_rate_at(t).0
    }

    /// `ω = I(t)⁻¹ L`: before the first knot and after the last by the inverse found once;
    /// between knots, a diagonal tensor's reciprocals (they depend on `t` alone, so the
    /// state's chain of dependent operations takes a multiplication, not a division) or a full
    /// tensor's cofactors.
    #[inline(always)]
    pub fn omega_from_momentum(&self, t: f64, l: &Vector3<f64>) -> Vector3<f64> {
        let (first, last) = (self.times[0], self.times[self.times.len() - 1]);
        // (a NaN time takes the first tensor, as a search would give it)
        if t < first || t.is_nan() {
            return self.inverses[0].times(l);
        }
        if t >= last {
            return self.inverses[1].times(l);
        }
        // first <= t < last: the piece with times[k − 1] <= t < times[k]
        let k = self.times.partition_point(|&tk| tk <= t);
        let (ta, tb) = (self.times[k - 1], self.times[k]);
        let (s, _) = smootherstep(crate::float::fraction(t, ta, tb));
        let m = self.tensors[k - 1] + (self.tensors[k] - self.tensors[k - 1]) * s;
        if self.diagonal {
            l.component_mul(&Vector3::new(
                1.0 / m[(0, 0)],
                1.0 / m[(1, 1)],
                1.0 / m[(2, 2)],
            ))
        } else {
            solve_symmetric(&m, l)
        }
    }
}

/// # For the runs
impl Deployment {
    /// The intermediate principal axis of `I(t)`: a body axis when every knot is diagonal,
    /// else the eigenvector of the middle eigenvalue (its sign arbitrary); none where two
    /// moments are equal.
    pub fn intermediate_axis(&self, t: f64) -> MidAxis {
        match self.times.as_slice() {
            [first, ..] if t <= *first => self.ends[0],
            [.., last] if t >= *last => self.ends[1],
            _ => axis_of(&self.inertia_at(t), self.diagonal),
        }
    }

    /// The smallest eigenvalue over the knots: `|ω| ≤ |L| / λ_min(I(t))`, and the smallest
    /// eigenvalue of a convex combination is at least the smallest of the two.
    pub fn least_moment(&self) -> f64 {
        self.tensors
            .iter()
            .map(|m| m.symmetric_eigenvalues().min())
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether every knot is diagonal.
    pub fn is_diagonal(&self) -> bool {
        self.diagonal
    }

    /// The same deployment with its tensors over `2^m` (see [`crate::float`]).
    pub fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        let k = self.tensors.len();
        let scaled = self
            .tensors
            .iter()
            .map(|t| t.map(|v| crate::float::ldexp(v, -m)));
        let tensors = try_collect(scaled, k, "the knots", KNOTS_HINT)?;
        let times = try_collect(self.times.iter().copied(), k, "the knots", KNOTS_HINT)?;
        Self::try_new(times, tensors)
    }

    /// The same deployment with its knot times in the units of `scale`.
    ///
    /// # Errors
    /// [`Error::TooLarge`] when a knot time leaves float64.
    pub(crate) fn in_units(&self, scale: RateScale) -> Result<Self> {
        let k = self.times.len();
        let unit = self.times.iter().map(|t| scale.time_to_unit(*t));
        let times: Vec<f64> = try_collect(unit, k, "the knots", KNOTS_HINT)?;
        if !times.iter().all(|t| t.is_finite()) {
            return Err(Error::TooLarge {
                what: "the deployment".into(),
                needed: format!(
                    "its knot times ({:.3e}) times the rates' scale ({:.3e})",
                    self.times.last().copied().unwrap_or(0.0),
                    scale.time_to_unit(1.0)
                ),
                limit: "what float64 holds".into(),
                hint: "take knot times within t_end, or smaller rates",
            });
        }
        let tensors = try_collect(self.tensors.iter().copied(), k, "the knots", KNOTS_HINT)?;
        Self::try_new(times, tensors)
    }
}

/// Checks a schedule's knot `times` (named `times` in errors): finite and strictly increasing.
/// A deployment's knots and a table's share it.
pub(crate) fn check_knot_times(times: &[f64]) -> Result<()> {
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(Error::invalid(
            "times",
            "must be finite and strictly increasing",
            format!("times[{k}] = {}", times[k]),
        ));
    }
    if let Some(k) = times.windows(2).position(|w| w[0] >= w[1]) {
        return Err(Error::invalid(
            "times",
            "must be finite and strictly increasing",
            format!(
                "times[{k}] = {} then times[{}] = {}",
                times[k],
                k + 1,
                times[k + 1]
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
