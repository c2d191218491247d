//! Runs at any rate: the free motion is the same under `(ω, t) → (s ω, t / s)`.
//!
//! Euler's equations are quadratic in the rates, so rates far from 1 make products that float64
//! cannot hold: `1e-300 · 1e-300` underflows to zero (the body stops turning), `1e200 · 1e200`
//! overflows. A run from rates `ω₀` is therefore integrated in the motion's own units, rates
//! over `2^e ≈ max|ω₀|` and times times `2^e`, and its results scaled back. Scaling by a power
//! of two is exact, so a run in its own units is bit for bit the run in the user's wherever
//! the latter has no overflow or underflow; runs with `|e|` up to [`UNSCALED`] are left as
//! they are.

use crate::body::RigidBody;

/// Runs whose largest initial rate is within `2^±UNSCALED` run unscaled: their products stay
/// far inside float64 for any body the core accepts.
pub const UNSCALED: i32 = 64;

/// `x · 2^e` for any `e`, in steps whose factors are themselves finite and normal.
#[inline]
pub fn ldexp(mut x: f64, mut e: i32) -> f64 {
    while e > 1000 {
        x *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= 2f64.powi(-1000);
        e += 1000;
    }
    x * 2f64.powi(e)
}

/// Where `t` lies in the interval `[t0, t1]` (`t0 < t1`, finite), `(t − t0) / (t1 − t0)`,
/// for intervals of any width: one wider than float64's largest number (knots at ±1.7e308)
/// is taken by its halves, where `t1 − t0` overflowed to infinity and made the place 0 at
/// every `t` (a tabulated torque silently 0 for the whole run).
///
/// # Example
/// ```
/// use dzhanibekov::float::fraction;
/// assert_eq!(fraction(0.0, -1.7e308, 1.7e308), 0.5);
/// assert_eq!(fraction(3.0, 2.0, 6.0), 0.25);
/// ```
#[inline]
pub fn fraction(t: f64, t0: f64, t1: f64) -> f64 {
    let gap = t1 - t0;
    match gap.is_finite() {
        true => (t - t0) / gap,
        false => (0.5 * t - 0.5 * t0) / (0.5 * t1 - 0.5 * t0),
    }
}

/// The binary exponent `e` with `2^e ≤ |x| < 2^(e + 1)`, for any finite non-zero `x`
/// (subnormals included).
pub fn exponent(x: f64) -> i32 {
    let x = x.abs();
    if x.is_normal() {
        ((x.to_bits() >> 52) & 0x7ff) as i32 - 1023
    } else {
        // a subnormal: 2^-1074 times its integer mantissa
        63 - x.to_bits().leading_zeros() as i32 - 1074
    }
}

/// The scale of a run: rates are divided by `2^e` and times multiplied by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RateScale {
    e: i32,
}

impl RateScale {
    /// The scale that brings the largest of `omega0` into `[1, 2)`; none (`e = 0`) for rates
    /// at rest, non-finite rates or rates within `2^±UNSCALED`.
    pub fn of(omega0: [f64; 3]) -> Self {
        let largest = omega0.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
        let e = match largest.is_finite() && largest > 0.0 {
            true => exponent(largest),
            false => 0,
        };
        Self {
            e: if e.abs() <= UNSCALED { 0 } else { e },
        }
    }

    /// Whether the run is left as it is.
    pub fn is_identity(&self) -> bool {
        self.e == 0
    }

    /// A rate in the run's own units.
    pub fn rate_to_unit(&self, w: f64) -> f64 {
        ldexp(w, -self.e)
    }

    /// A rate back in the user's units.
    pub fn rate_from_unit(&self, w: f64) -> f64 {
        ldexp(w, self.e)
    }

    /// A time in the run's own units.
    pub fn time_to_unit(&self, t: f64) -> f64 {
        ldexp(t, self.e)
    }

    /// A time back in the user's units.
    pub fn time_from_unit(&self, t: f64) -> f64 {
        ldexp(t, -self.e)
    }
}

/// `body` with its moments over a power of two near the largest, if that is beyond
/// `2^±UNSCALED`: the motion does not change (ω is the same for `I → cI`), the coefficients of
/// Euler's equations are the same bits (ratios of moments scale exactly), and the angular
/// momentum `Iω` of tiny moments and rates no longer underflows (nor that of huge ones
/// overflows).
pub fn unit_body(body: &RigidBody) -> Option<RigidBody> {
    let inertia = body.inertia_body();
    let e = exponent(inertia.max());
    if e.abs() <= UNSCALED {
        return None;
    }
    RigidBody::try_new([inertia.x, inertia.y, inertia.z].map(|i| ldexp(i, -e))).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponents_of_normals_and_subnormals() {
        assert_eq!(exponent(1.0), 0);
        assert_eq!(exponent(1.5), 0);
        assert_eq!(exponent(-2.0), 1);
        assert_eq!(exponent(f64::MIN_POSITIVE), -1022);
        assert_eq!(exponent(f64::from_bits(1)), -1074);
        assert_eq!(exponent(3.0 * f64::from_bits(1)), -1073);
        assert_eq!(exponent(f64::MAX), 1023);
    }

    #[test]
    fn the_largest_rate_lands_in_one_to_two() {
        for w in [f64::from_bits(1), 1e-300, 1e-30, 1e30, 1e300, f64::MAX] {
            let s = RateScale::of([0.0, -w, 0.5 * w]);
            let unit = s.rate_to_unit(w);
            if w.abs() > 1e-19 && w < 1e19 {
                assert!(s.is_identity());
            } else {
                assert!((1.0..2.0).contains(&unit), "{w}: {unit}");
                assert_eq!(s.rate_from_unit(unit), w);
            }
        }
    }

    #[test]
    fn ldexp_reaches_both_ends() {
        assert_eq!(ldexp(1.0, -1074), f64::from_bits(1));
        assert_eq!(ldexp(f64::from_bits(1), 1074), 1.0);
        assert_eq!(ldexp(1.0, 1023), 2f64.powi(1023));
        assert!(ldexp(1.0, 1024).is_infinite());
    }
}
