//! What the Lie-group and implicit methods share: unit quaternions as the rotation group
//! (products, the exponential, turning a vector back), a 3 × 3 linear solve for their Newton
//! iterations, and the pull-back of `|L|` and `|q|` that keeps their round-off bounded.
//!
//! Conventions as everywhere in the crate: quaternions scalar first, `q` world-from-body, the
//! body-frame law `q' = ½ q ⊗ (0, ω)`. A rotation vector `φ` (angle `|φ|` about `φ/|φ|`)
//! stands for an element of the Lie algebra so(3) ≅ su(2); its bracket is `φ × ψ`.

use crate::ode::power_of_two_scale;

/// How far `|L|²/|L₀|²` and `|q|²` may wander from 1 before they are pulled back (as the
/// splitting does, see [`crate::rigid::Splitting`]: rarely, so that the pull-back's own
/// rounding does not turn `L_world`).
const RENORMALIZE: f64 = 1e-14;

/// `q ⊗ p`, scalar first.
#[inline(always)]
pub(crate) fn mul(q: &[f64; 4], p: &[f64; 4]) -> [f64; 4] {
    let [a0, a1, a2, a3] = *q;
    let [b0, b1, b2, b3] = *p;
    [
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 + a2 * b0 + a3 * b1 - a1 * b3,
        a0 * b3 + a3 * b0 + a1 * b2 - a2 * b1,
    ]
}

/// `a × b`.
#[inline(always)]
pub(crate) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a · b`.
#[inline(always)]
pub(crate) fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Taylor coefficients of `cos(θ/2)` and `sin(θ/2)/θ` in powers of `θ²`, through `θ¹⁴`: for
/// `θ² ≤ 1` the first term left out is below 7.3e-19 (cos) and 2.1e-20 (sin), so the
/// polynomials are exact to round-off there and need no square root.
const COS_HALF: [f64; 8] = half_angle_taylor(0);
const SIN_HALF_OVER: [f64; 8] = half_angle_taylor(1);

/// `(−1)ᵏ / (2^(2k+j) (2k+j)!)` for `k = 0..8`: the coefficients of `x = θ²` in `cos(θ/2)`
/// (`j = 0`) and in `sin(θ/2)/θ` (`j = 1`).
const fn half_angle_taylor(j: u32) -> [f64; 8] {
    let mut c = [0.0; 8];
    let mut k = 0;
    while k < 8 {
        let n = 2 * k + j as usize;
        let mut denominator = 1.0;
        let mut i = 1;
        while i <= n {
            denominator *= 2.0 * i as f64; // 2ⁿ n!
            i += 1;
        }
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        c[k] = sign / denominator;
        k += 1;
    }
    c
}

/// The polynomial `Σ cₖ xᵏ` by Estrin's scheme: three levels of multiply-adds instead of
/// Horner's seven, which shortens the chain of dependent operations a Lie-group stage waits
/// on (the stages of a step follow one another).
#[inline(always)]
fn estrin(c: &[f64; 8], x: f64) -> f64 {
    let x2 = x * x;
    let x4 = x2 * x2;
    let p01 = c[0] + c[1] * x;
    let p23 = c[2] + c[3] * x;
    let p45 = c[4] + c[5] * x;
    let p67 = c[6] + c[7] * x;
    (p01 + p23 * x2) + (p45 + p67 * x2) * x4
}

/// The unit quaternion `exp(φ)` of the rotation by the rotation vector `φ`:
/// `(cos(θ/2), sin(θ/2)/θ · φ)` with `θ = |φ|`. Small angles (`θ ≤ 1`, every stage of a step
/// with `hΩ ≲ 1`) take two polynomials in `θ²`; larger ones `sin_cos`.
#[inline(always)]
pub(crate) fn exp(phi: &[f64; 3]) -> [f64; 4] {
    let theta_sq = dot(phi, phi);
    let (c, s) = if theta_sq <= 1.0 {
        (
            estrin(&COS_HALF, theta_sq),
            estrin(&SIN_HALF_OVER, theta_sq),
        )
    } else {
        let theta = theta_sq.sqrt();
        let (s, c) = (0.5 * theta).sin_cos();
        (c, s / theta)
    };
    [c, s * phi[0], s * phi[1], s * phi[2]]
}

/// `R(p)ᵀ v` for a unit quaternion `p`: `v` turned by the inverse of `p`. A body vector of a
/// body whose attitude turns `q ← q ⊗ p` while the vector stays fixed in space.
#[inline(always)]
pub(crate) fn rotate_back(p: &[f64; 4], v: &[f64; 3]) -> [f64; 3] {
    let u = [p[1], p[2], p[3]];
    let t = cross(&u, v).map(|c| 2.0 * c);
    let ut = cross(&u, &t);
    [
        v[0] - p[0] * t[0] + ut[0],
        v[1] - p[0] * t[1] + ut[1],
        v[2] - p[0] * t[2] + ut[2],
    ]
}

/// `x` solving `A x = b`, by the cofactors of `A`'s rows (`None` if `A` is singular to
/// working precision). Newton's 3 × 3 systems here are `I` plus a perturbation of size
/// `hΩ`, far from singular at any step a method can take.
#[inline(always)]
pub(crate) fn solve3(a: &[[f64; 3]; 3], b: &[f64; 3]) -> Option<[f64; 3]> {
    let c0 = cross(&a[1], &a[2]);
    let c1 = cross(&a[2], &a[0]);
    let c2 = cross(&a[0], &a[1]);
    let det = dot(&a[0], &c0);
    // a NaN determinant fails the comparison too
    if det.abs() > f64::MIN_POSITIVE {
        let inv = 1.0 / det;
        Some([
            inv * (c0[0] * b[0] + c1[0] * b[1] + c2[0] * b[2]),
            inv * (c0[1] * b[0] + c1[1] * b[1] + c2[1] * b[2]),
            inv * (c0[2] * b[0] + c1[2] * b[1] + c2[2] * b[2]),
        ])
    } else {
        None
    }
}

/// The largest `|x_k|`.
#[inline(always)]
pub(crate) fn amax(x: &[f64; 3]) -> f64 {
    x[0].abs().max(x[1].abs()).max(x[2].abs())
}

/// Newton's iteration stops once its correction is below this fraction of the unknown: the
/// error left is then about the square of it, round-off.
const NEWTON_TOL: f64 = 1.0 / (1u64 << 27) as f64;
/// More corrections than this and the step is refused (the state becomes NaN, which the driver
/// reports as a step far too large): Newton takes 2–5 at any step the methods can take.
pub(crate) const NEWTON_MAX: u32 = 50;

/// The root of three equations by Newton's method from `y`, the implicit methods' one solve:
/// `system(y)` gives the residual `r(y)` and its Jacobian. The root and the corrections it
/// took, or `None` for a singular Jacobian or no convergence in [`NEWTON_MAX`] corrections.
#[inline(always)]
pub(crate) fn newton3(
    mut y: [f64; 3],
    system: impl Fn(&[f64; 3]) -> ([f64; 3], [[f64; 3]; 3]),
) -> Option<([f64; 3], u32)> {
    for n in 1..=NEWTON_MAX {
        let (r, jac) = system(&y);
        let delta = solve3(&jac, &r)?;
        y = [y[0] - delta[0], y[1] - delta[1], y[2] - delta[2]];
        // NaN fails the comparison and goes on to the cap
        if amax(&delta) <= NEWTON_TOL * amax(&y) {
            return Some((y, n));
        }
    }
    None
}

/// The norms a rotation keeps in exact arithmetic, `|L|` and `|q|`, pulled back by one Newton
/// step of the inverse square root, `x ← x (3 − |x|²/|x₀|²) / 2`, whenever their squares have
/// wandered more than 1e-14 from the start (the splitting's rule, which it explains).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Norms {
    /// A power of two near `1 / max|L₀|`, so that `|L|²` is formed without overflow.
    l_scale: f64,
    /// `1/|L₀ l_scale|²`, 0 when `L₀ = 0` (nothing then moves).
    inv_l0_sq: f64,
}

impl Norms {
    /// The norms of the start `l0` (and `|q| = 1`).
    pub(crate) fn new(l0: &[f64; 3]) -> Self {
        let l_scale = power_of_two_scale(amax(l0));
        let l0_sq: f64 = l0.iter().map(|l| (l * l_scale).powi(2)).sum();
        Self {
            l_scale,
            inv_l0_sq: if l0_sq > 0.0 && l0_sq.is_finite() {
                1.0 / l0_sq
            } else {
                0.0
            },
        }
    }

    /// The step's end: the body turned by `p` (body-frame, unit) from `x` — `q ← q ⊗ p`, the
    /// momentum seen from the turned axes `L ← R(p)ᵀ l0` — pulled back and stored in `x`.
    #[inline(always)]
    pub(crate) fn turn(&self, x: &mut [f64; 7], p: &[f64; 4], l0: &[f64; 3]) {
        let mut q = mul(&[x[3], x[4], x[5], x[6]], p);
        let mut l = rotate_back(p, l0);
        self.pull_back(&mut l, &mut q);
        *x = [l[0], l[1], l[2], q[0], q[1], q[2], q[3]];
    }

    /// Pulls `l` and `q` back toward `|L₀|` and 1 if they have wandered.
    #[inline(always)]
    pub(crate) fn pull_back(&self, l: &mut [f64; 3], q: &mut [f64; 4]) {
        let [l0, l1, l2] = l.map(|c| c * self.l_scale);
        let l_sq = (l0 * l0 + l1 * l1 + l2 * l2) * self.inv_l0_sq;
        let q_sq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        if (l_sq - 1.0).abs() > RENORMALIZE && self.inv_l0_sq > 0.0 {
            *l = l.map(|c| c * (1.5 - 0.5 * l_sq));
        }
        if (q_sq - 1.0).abs() > RENORMALIZE {
            *q = q.map(|c| c * (1.5 - 0.5 * q_sq));
        }
    }
}

/// The state with its first three entries scaled by `s`: `L = I ω` (s the moments) or
/// `ω = L / I` (s their inverses), the attitude as it is. The steppers on `[L, q]` convert with it.
#[inline(always)]
pub fn scale_momentum(s: &[f64; 3], x: &[f64; 7]) -> [f64; 7] {
    [
        s[0] * x[0],
        s[1] * x[1],
        s[2] * x[2],
        x[3],
        x[4],
        x[5],
        x[6],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Quaternion, UnitQuaternion, Vector3};

    #[test]
    fn the_exponential_is_the_rotation_by_the_vector() {
        for phi in [
            [0.0, 0.0, 0.0],
            [1e-9, -2e-9, 0.5e-9],
            [0.3, -0.2, 0.1],
            [0.6, 0.5, -0.6], // θ² = 0.97: the polynomials
            [0.6, 0.6, -0.6], // θ² = 1.08: sin_cos
            [2.0, -1.0, 3.0],
        ] {
            let want = UnitQuaternion::from_scaled_axis(Vector3::from(phi)).into_inner();
            let got = exp(&phi);
            assert_relative_eq!(got[0], want.w, epsilon = 2e-16);
            assert_relative_eq!(got[1], want.i, epsilon = 2e-16);
            assert_relative_eq!(got[2], want.j, epsilon = 2e-16);
            assert_relative_eq!(got[3], want.k, epsilon = 2e-16);
        }
    }

    #[test]
    fn products_and_turns_are_nalgebras() {
        let q = [0.9, 0.1, -0.3, 0.2];
        let p = [0.5, -0.5, 0.5, 0.5];
        let want =
            Quaternion::new(q[0], q[1], q[2], q[3]) * Quaternion::new(p[0], p[1], p[2], p[3]);
        let got = mul(&q, &p);
        assert_relative_eq!(
            Quaternion::new(got[0], got[1], got[2], got[3]),
            want,
            epsilon = 1e-15
        );
        let unit = UnitQuaternion::from_quaternion(Quaternion::new(p[0], p[1], p[2], p[3]));
        let v = [0.3, -1.2, 0.7];
        let back = unit.inverse() * Vector3::from(v);
        assert_relative_eq!(Vector3::from(rotate_back(&p, &v)), back, epsilon = 1e-15);
    }

    #[test]
    fn a_compensated_sum_keeps_what_a_plain_sum_loses() {
        // 1e-17 is below half an ulp of 1: added a million times, a plain sum never moves
        let carry = Carry::default();
        let (mut x, delta) = ([1.0; 7], [1e-17; 7]);
        for _ in 0..1_000_000 {
            x = carry.add(&x, &delta);
        }
        assert_relative_eq!(x[0], 1.0 + 1e-11, epsilon = 4.0 * f64::EPSILON);
        // cleared, a carry adds nothing
        carry.clear();
        let other = [2.0; 7];
        assert_eq!(carry.add(&other, &[0.0; 7]), other);
    }

    #[test]
    fn the_solve_inverts_the_matrix() {
        let a = [[1.0, 0.1, -0.2], [0.05, 1.0, 0.3], [-0.1, 0.2, 1.0]];
        let b = [0.3, -0.4, 0.5];
        let x = solve3(&a, &b).unwrap();
        for (row, bi) in a.iter().zip(b) {
            assert_relative_eq!(dot(row, &x), bi, epsilon = 1e-15);
        }
        assert!(solve3(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]], &b).is_none());
    }
}

/// Compensated summation of a step's update across steps (Kahan; Hairer, Lubich & Wanner,
/// §VIII.5): the state is `x + e`, `x` what the driver holds and `e` the part of it below `x`'s
/// last bit, kept here between steps. A step's increment `δ` is added as `y = δ + e`,
/// `x' = x + y`, `e' = (x − x') + y` (exact when `|y| ≤ |x|`), so the rounding of the sum
/// no longer accumulates; what is left is the rounding of the increments themselves, which is
/// smaller by their size, about `hΩ`.
///
/// The carry is below an ulp of the state it was made with: applied to any other state (a
/// run's first step, a state pulled back; [`Carry::clear`] where the method knows) it adds at
/// most that ulp once, so it is not checked against the state, which would cost a tenth of a
/// cheap step.
#[derive(Debug, Clone, Default)]
pub(crate) struct Carry(std::cell::Cell<[f64; 7]>);

impl PartialEq for Carry {
    fn eq(&self, other: &Self) -> bool {
        self.0.get() == other.0.get()
    }
}

impl Carry {
    /// `x + δ`, compensated; keeps the new carry.
    #[inline(always)]
    pub(crate) fn add(&self, x: &[f64; 7], delta: &[f64; 7]) -> [f64; 7] {
        let e = self.0.get();
        let mut out = [0.0; 7];
        let mut next = [0.0; 7];
        for k in 0..7 {
            let y = delta[k] + e[k];
            let t = x[k] + y;
            next[k] = (x[k] - t) + y;
            out[k] = t;
        }
        self.0.set(next);
        out
    }

    /// Forgets the carry (the state was changed by other means).
    #[inline(always)]
    pub(crate) fn clear(&self) {
        self.0.set([0.0; 7]);
    }
}
