//! Jacobi elliptic functions that carry the complementary parameter, and the few elliptic
//! integrals the exact solution needs.
//!
//! Near the separatrix of the free top the parameter `m` is within 1e-11 (or much less) of 1.
//! A routine that takes `m` alone has already lost `m1 = 1 − m` to rounding, so its quarter
//! period `K` and everything past it are wrong. Here both `m` and `m1` are given, each computed
//! by the caller without cancellation, and every step uses the one that is accurate:
//!
//! - `K(m) = π / (2 AGM(1, √m1))` (Abramowitz & Stegun 17.6.1–17.6.4; DLMF 19.8.5);
//! - `sn, cn, dn` by the descending Gauss/Landen transformation on the AGM scale of `1` and
//!   `√m1` (A&S 16.4; DLMF 22.20.1) in Bulirsch's rational form, on an argument first reduced to
//!   `[0, K/2]` with the quarter-period and half-period shifts (A&S 16.8; DLMF 22.4.3), which
//!   give `dn(K) = √m1` exactly rather than as a difference;
//! - Carlson's symmetric integrals `R_F`, `R_J` (Carlson 1995, DLMF 19.16, 19.25), from the
//!   `ellip` crate, for the incomplete integrals of the first and third kinds.

use ellip::{elliprf, elliprj};

/// Levels of the AGM at most: from `b0 = √m1 ≥ 1e-162` it converges in fewer than 16.
const MAX_AGM: usize = 24;
/// `√ε`: the AGM stops one step after `|a − b| ≤ √ε a` (quadratic convergence).
const AGM_TOLERANCE: f64 = 1.5e-8;

/// `sn, cn, dn` of one parameter `m` (with its complement `m1 = 1 − m`), at any argument.
///
/// The AGM sequence depends on `m1` alone, so it is computed once here and each evaluation
/// costs one reduction, one `sin_cos` and a few rational steps.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// use dzhanibekov::exact::elliptic::Jacobi;
/// // 1 − m = 1e-15: K(m) = 18.7... and dn(K) = √m1
/// let jac = Jacobi::new(1.0 - 1e-15, 1e-15);
/// let k = jac.quarter_period();
/// let (sn, cn, dn) = jac.sn_cn_dn(k);
/// assert_relative_eq!(sn, 1.0, epsilon = 1e-15);
/// assert!(cn.abs() < 1e-15);
/// assert_relative_eq!(dn, 1e-15_f64.sqrt(), max_relative = 1e-14);
/// ```
#[derive(Debug, Clone)]
pub struct Jacobi {
    m: f64,
    m1: f64,
    sqrt_m1: f64,
    /// `K(m)`; infinite when `m1 = 0`.
    k: f64,
    /// The AGM of `1` and `√m1`: `a_n` and `b_n`, n = 0..levels.
    a: [f64; MAX_AGM],
    b: [f64; MAX_AGM],
    levels: usize,
    /// `AGM(1, √m1) = π / 2K`.
    mean: f64,
    /// `K'(m) = K(m1)`, the imaginary quarter period.
    k_prime: f64,
}

/// # Construction
impl Jacobi {
    /// The functions of parameter `m`, given together with `m1 = 1 − m`, each accurate to its
    /// own round-off. Both are clamped into `[0, 1]`.
    pub fn new(m: f64, m1: f64) -> Self {
        let m = m.clamp(0.0, 1.0);
        let m1 = m1.clamp(0.0, 1.0);
        let sqrt_m1 = m1.sqrt();
        let (mut a, mut b) = ([0.0; MAX_AGM], [0.0; MAX_AGM]);
        let (mut an, mut bn) = (1.0_f64, sqrt_m1);
        let mut levels = 0;
        let mut mean = 1.0;
        if m1 > 0.0 {
            // Stop one step after |a − b| ≤ √ε a: the AGM converges quadratically.
            while levels < MAX_AGM {
                a[levels] = an;
                b[levels] = bn;
                levels += 1;
                mean = 0.5 * (an + bn);
                if (an - bn).abs() <= AGM_TOLERANCE * an {
                    break;
                }
                bn = (an * bn).sqrt();
                an = mean;
            }
        }
        let k = if m1 > 0.0 {
            std::f64::consts::FRAC_PI_2 / mean
        } else {
            f64::INFINITY
        };
        Self {
            m,
            m1,
            sqrt_m1,
            k,
            a,
            b,
            levels,
            mean,
            k_prime: std::f64::consts::FRAC_PI_2 / agm(1.0, m.sqrt()),
        }
    }
}

/// # Evaluation
impl Jacobi {
    pub fn m(&self) -> f64 {
        self.m
    }

    pub fn m1(&self) -> f64 {
        self.m1
    }

    /// `K(m)`, the quarter period of `sn` and `cn` (half that of `dn`); infinite if `m = 1`.
    pub fn quarter_period(&self) -> f64 {
        self.k
    }

    /// `K'(m) = K(1 − m)`: `sn, cn, dn` are analytic within `K'` of the real axis.
    pub fn imaginary_quarter_period(&self) -> f64 {
        self.k_prime
    }

    /// Splits `u = 2K j + r` with `r ∈ [−K, K]`; returns `(j, r)`. With `m = 1` (no period),
    /// `(0, u)`.
    #[inline]
    pub fn reduce(&self, u: f64) -> (f64, f64) {
        if !self.k.is_finite() {
            return (0.0, u);
        }
        let two_k = 2.0 * self.k;
        let j = (u / two_k).round();
        (j, (-two_k).mul_add(j, u))
    }

    /// `(sn u, cn u, dn u)`.
    #[inline]
    pub fn sn_cn_dn(&self, u: f64) -> (f64, f64, f64) {
        let (j, r) = self.reduce(u);
        let (sn, cn, dn) = self.sn_cn_dn_reduced(r);
        // sn(r + 2Kj) = (−1)^j sn r, likewise cn; dn has period 2K.
        if j % 2.0 != 0.0 {
            (-sn, -cn, dn)
        } else {
            (sn, cn, dn)
        }
    }

    /// `(sn r, cn r, dn r)` for `r ∈ [−K, K]` (any `r` when `m = 1`).
    #[inline]
    pub fn sn_cn_dn_reduced(&self, r: f64) -> (f64, f64, f64) {
        if self.m1 == 0.0 {
            let sech = 1.0 / r.cosh();
            return (r.tanh(), sech, sech);
        }
        let s = r.abs();
        let (sn, cn, dn) = if s > 0.5 * self.k {
            // sn(K − x) = cd x, cn(K − x) = √m1 sd x, dn(K − x) = √m1 nd x (A&S 16.8.1)
            let (sx, cx, dx) = self.gauss(self.k - s);
            (cx / dx, self.sqrt_m1 * sx / dx, self.sqrt_m1 / dx)
        } else {
            self.gauss(s)
        };
        (sn.copysign(r), cn, dn)
    }

    /// The descending Gauss (AGM) transformation for `0 ≤ s ≤ K/2`, in Bulirsch's rational
    /// form (Bulirsch 1965, *Numer. Math.* 7, 78; A&S 16.4): from `cot(s · AGM)` back down
    /// the AGM with one division per level. Unlike the `asin` form of A&S 16.4.3, which loses
    /// half the digits of `cn` and `dn` when `m` is near 1, every step is well conditioned.
    #[inline]
    fn gauss(&self, s: f64) -> (f64, f64, f64) {
        let (sin, cos) = (s * self.mean).sin_cos();
        if sin == 0.0 {
            return (0.0, 1.0, 1.0);
        }
        let mut ratio = cos / sin;
        let mut c = self.mean * ratio;
        let mut dn = 1.0;
        for n in (0..self.levels).rev() {
            let a = self.a[n];
            ratio *= c;
            c *= dn;
            dn = (self.b[n] + ratio) / (a + ratio);
            ratio = c / a;
        }
        let sn = 1.0 / c.hypot(1.0);
        (sn, c * sn, dn)
    }

    /// `F(arcsin x | m)` for `0 ≤ x ≤ 1`: the `u ∈ [0, K]` with `sn u = x`.
    pub fn inverse_sn(&self, x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        let c2 = (1.0 - x) * (1.0 + x);
        // 1 − m x² = (1 − x²) + m1 x², without cancellation
        x * carlson_rf(c2, self.m1.mul_add(x * x, c2), 1.0)
    }

    /// The `u` with `(sn u, cn u, dn u) = (sn, cn, dn)`, in `(−2K, 2K]`, from values that
    /// satisfy the identities up to round-off. Uses `dn` directly (it carries `m1`).
    pub fn argument_of(&self, sn: f64, cn: f64, dn: f64) -> f64 {
        let sn = sn.clamp(-1.0, 1.0);
        let f = sn * carlson_rf(cn * cn, dn * dn, 1.0);
        if cn >= 0.0 {
            f
        } else {
            // F(π − φ) = 2K − F(φ)
            (2.0 * self.k).copysign(if sn == 0.0 { 1.0 } else { sn }) - f
        }
    }
}

/// The arithmetic-geometric mean of `a ≥ b ≥ 0`; 0 if `b = 0`.
fn agm(mut a: f64, mut b: f64) -> f64 {
    if b == 0.0 {
        return 0.0;
    }
    for _ in 0..MAX_AGM {
        let mean = 0.5 * (a + b);
        if (a - b).abs() <= AGM_TOLERANCE * a {
            return mean;
        }
        b = (a * b).sqrt();
        a = mean;
    }
    a
}

/// Carlson's `R_F(x, y, z)` (DLMF 19.16.1); NaN outside its domain.
#[inline]
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    elliprf(x, y, z).unwrap_or(f64::NAN)
}

/// Carlson's `R_J(x, y, z, p)` (DLMF 19.16.2) for `p > 0`; NaN outside its domain.
#[inline]
pub fn carlson_rj(x: f64, y: f64, z: f64, p: f64) -> f64 {
    elliprj(x, y, z, p).unwrap_or(f64::NAN)
}

/// `∫₀^r sn²u du / (1 − n sn²u)` for `r ∈ [−K, K]`, from `sn, cn, dn` of `r`:
/// `sn³ R_J(cn², dn², 1, 1 − n sn²) / 3` (DLMF 19.25.14 less its `R_F` term), so that no
/// division by `n` is needed.
#[inline]
pub fn sn2_integral(n: f64, sn: f64, cn: f64, dn: f64) -> f64 {
    if sn == 0.0 {
        return 0.0;
    }
    let s2 = sn * sn;
    sn * s2 * carlson_rj(cn * cn, dn * dn, 1.0, (-n).mul_add(s2, 1.0)) / 3.0
}

/// `∫₀^K sn²u du / (1 − n sn²u) = R_J(0, m1, 1, 1 − n) / 3`.
pub fn sn2_integral_complete(n: f64, m1: f64) -> f64 {
    carlson_rj(0.0, m1, 1.0, 1.0 - n) / 3.0
}

/// `Π(n; am r | m) = ∫₀^r du / (1 − n sn²u)` for `r ∈ [−K, K]`, from `sn, cn, dn` of `r`
/// (DLMF 19.25.14 with `F(am r) = r`).
#[inline]
pub fn pi_incomplete(n: f64, r: f64, sn: f64, cn: f64, dn: f64) -> f64 {
    n.mul_add(sn2_integral(n, sn, cn, dn), r)
}

/// `Π(n | m) = ∫₀^K du / (1 − n sn²u)` (DLMF 19.25.2), from `K` and `m1`.
pub fn pi_complete(n: f64, k: f64, m1: f64) -> f64 {
    n.mul_add(sn2_integral_complete(n, m1), k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn circular_and_hyperbolic_limits() {
        let jac = Jacobi::new(0.0, 1.0);
        let (sn, cn, dn) = jac.sn_cn_dn(2.3);
        assert_relative_eq!(sn, 2.3_f64.sin(), epsilon = 1e-15);
        assert_relative_eq!(cn, 2.3_f64.cos(), epsilon = 1e-15);
        assert_eq!(dn, 1.0);
        assert_relative_eq!(jac.quarter_period(), std::f64::consts::FRAC_PI_2);
        let jac = Jacobi::new(1.0, 0.0);
        let (sn, cn, dn) = jac.sn_cn_dn(0.7);
        assert_relative_eq!(sn, 0.7_f64.tanh(), epsilon = 1e-15);
        assert_relative_eq!(cn, 1.0 / 0.7_f64.cosh(), epsilon = 1e-15);
        assert_eq!(cn, dn);
    }

    #[test]
    fn identities_hold_across_periods() {
        for (m, m1) in [(0.3, 0.7), (0.999, 1e-3), (1.0 - 1e-12, 1e-12)] {
            let jac = Jacobi::new(m, m1);
            for u in [-31.0, -3.3, 0.1, 1.7, 9.0, 55.5] {
                let (sn, cn, dn) = jac.sn_cn_dn(u);
                assert_relative_eq!(sn * sn + cn * cn, 1.0, epsilon = 4e-15);
                assert_relative_eq!(dn * dn + m * sn * sn, 1.0, epsilon = 4e-15);
            }
        }
    }

    #[test]
    fn argument_is_recovered() {
        let jac = Jacobi::new(0.8, 0.2);
        let k = jac.quarter_period();
        for u in [-1.9 * k, -0.4 * k, 0.0, 0.3, 1.2 * k, 1.99 * k] {
            let (sn, cn, dn) = jac.sn_cn_dn(u);
            assert_relative_eq!(jac.argument_of(sn, cn, dn), u, epsilon = 1e-14);
        }
        assert_relative_eq!(jac.inverse_sn(jac.sn_cn_dn(0.9).0), 0.9, epsilon = 1e-14);
    }

    #[test]
    fn pi_matches_quadrature() {
        // ∫₀^r du / (1 − n sn²u) by the composite Simpson rule
        let (n, m) = (-2.5, 0.6);
        let jac = Jacobi::new(m, 1.0 - m);
        let r = 0.9 * jac.quarter_period();
        let steps = 2000;
        let h = r / steps as f64;
        let f = |u: f64| 1.0 / (1.0 - n * jac.sn_cn_dn(u).0.powi(2));
        let simpson = (0..=steps)
            .map(|i| {
                let w = if i == 0 || i == steps {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(i as f64 * h)
            })
            .sum::<f64>()
            * h
            / 3.0;
        let (sn, cn, dn) = jac.sn_cn_dn(r);
        assert_relative_eq!(pi_incomplete(n, r, sn, cn, dn), simpson, epsilon = 1e-12);
        let k = jac.quarter_period();
        let (sn, cn, dn) = jac.sn_cn_dn(k);
        assert_relative_eq!(
            pi_incomplete(n, k, sn, cn, dn),
            pi_complete(n, k, 1.0 - m),
            epsilon = 1e-13
        );
    }
}
