//! Double-double arithmetic: a value carried as the unevaluated sum of two float64s, `hi +
//! lo` with `|lo| ≤ ulp(hi)/2`, from error-free sums (Knuth's TwoSum) and FMA products
//! (T. J. Dekker, "A floating-point technique for extending the available precision", Numer.
//! Math. 18 (1971) 224). For differences that cancel (the separatrix measure) and for sums
//! that must not gather round-off over millions of terms (a splitting's invariants).

/// A double-double `(hi, lo)`.
pub(crate) type Dd = (f64, f64);

/// `a + b` as an unevaluated sum `(s, e)` with `s = fl(a + b)` exactly (Knuth's TwoSum).
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The double-double `x` times `y`, renormalised (the product `x.0 · y` error-free by FMA).
#[inline]
pub(crate) fn dd_mul(x: Dd, y: f64) -> Dd {
    let p = x.0 * y;
    let e = x.0.mul_add(y, -p) + x.1 * y;
    let s = p + e;
    (s, e - (s - p))
}

/// `x + y` of two double-doubles, renormalised.
#[inline]
pub(crate) fn dd_add(x: Dd, y: Dd) -> Dd {
    let (s, e) = two_sum(x.0, y.0);
    let e = e + (x.1 + y.1);
    let hi = s + e;
    (hi, e - (hi - s))
}

/// `x − y` of two double-doubles, rounded to float64 once.
#[inline]
pub(crate) fn dd_diff(x: Dd, y: Dd) -> f64 {
    let (s, e) = two_sum(x.0, -y.0);
    s + (e + (x.1 - y.1))
}

/// `a · b` as an unevaluated sum, error-free (by FMA).
#[inline(always)]
pub(crate) fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `Σ w_k v_k²` in double-double: each product error-free, the sum compensated.
#[inline]
pub(crate) fn weighted_squares(w: [f64; 3], v: [f64; 3]) -> Dd {
    (0..3).fold((0.0, 0.0), |sum, k| {
        dd_add(sum, dd_mul(two_prod(w[k], v[k]), v[k]))
    })
}

/// `Σ v_k²` in double-double: each square error-free, the sum compensated.
#[inline]
pub(crate) fn squares(v: [f64; 3]) -> Dd {
    (0..3).fold((0.0, 0.0), |sum, k| dd_add(sum, two_prod(v[k], v[k])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_of_squares_keep_what_float64_loses() {
        // 1 + (1e-9)² holds 1e-18 that a float64 sum rounds away
        let s = weighted_squares([1.0, 1.0, 0.0], [1.0, 1e-9, 0.0]);
        assert_eq!(s.0, 1.0);
        assert!((s.1 - 1e-18).abs() < 1e-33, "{s:?}");
        assert_eq!(dd_diff(s, (1.0, 0.0)), s.1);
        // (1 + 2⁻⁵²)² = 1 + 2⁻⁵¹ + 2⁻¹⁰⁴: all of it, hi + lo
        let x = 1.0 + f64::EPSILON;
        let sq = weighted_squares([1.0, 0.0, 0.0], [x, 0.0, 0.0]);
        assert_eq!(sq.0, 1.0 + 2.0 * f64::EPSILON);
        assert_eq!(sq.1, f64::EPSILON * f64::EPSILON);
    }
}
