//! The gravity gradient of a circular orbit, a part of a system ([`GravityGradient`]), and
//! its torque evaluated at core speed.
//!
//! **Law.** The body's centre moves on a circular orbit in the world `x–y` plane at rate `n`:
//! the direction to it from the planet is `r̂(t) = (cos nt, sin nt, 0)` (world axes, `t = 0` at
//! `+x`; the orbit normal is world `+z`). With `r̂_b = M(q)ᵀ r̂` the same direction in body axes
//! (`q` world-from-body) and `I` the body's tensor, the torque is
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
//! **Speed.** A right-hand side of a body in orbit is the free body's plus this torque; issue
//! 21's bar is an RK4 step at most twice the free body's (not met: 3.4× on an AMD EPYC,
//! 2026-11-29, with [`OrbitKernel`]; the phase and `1/|q|⁴` alone cost about the free body's
//! step). What makes it cheap, each at round-off from the plain formula:
//! - **the orbit's phase** `(sin nt, cos nt)` by [`sin_cos`], inline (no call into libm, whose
//!   `sin` and `cos` each reduce the argument again and make the caller spill its registers):
//!   it depends on `t` alone, so it runs beside the state's chain of dependent operations,
//!   and an RK4 step makes it once, at its start `t`, and turns it by `n h/2` and `n h` for
//!   its later stage times `t + h/2`, `t + h` ([`OrbitKernel::phases`], one more `sin_cos`
//!   for the turn; other methods make it once per stage time, [`crate::ode::StageTime`]);
//! - **the radial direction in body axes** from the unnormalised matrix `M̃ = |q|² M(q)`
//!   (quadratic in `q`, no division): `r̃ = M̃ᵀ r̂ = |q|² r̂_b`, and the torque
//!   `3n² r̂_b × (I r̂_b) = (3n² / |q|⁴) r̃ × (I r̃)`, whose one division runs beside the
//!   products instead of before them.

// the constants as fdlibm prints them (the float64 nearest each is what counts)
#![allow(clippy::excessive_precision)]

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::rotation_matrix;

use super::kinds::{Conserved, Traits};
use super::part::{Ctx, EnergyRole, Fields, ModelInfo, Param, ParamKind, Part};

/// `2/π`.
const FRAC_2_PI: f64 = std::f64::consts::FRAC_2_PI;
/// `π/2` split as in fdlibm's `__ieee754_rem_pio2` (Sun Microsystems, 1993): its first 33 bits
/// (`k · PIO2_HI` is exact for `|k| < 2^20`) and the rest rounded to float64.
const PIO2_HI: f64 = 1.570_796_326_734_125_614_17e0;
const PIO2_LO: f64 = 6.077_100_506_506_192_249_32e-11;
/// `1.5 · 2^52`: adding it rounds a float64 below `2^51` in size to an integer, whose low
/// bits are then the low bits of the sum's representation.
const ROUND: f64 = 6_755_399_441_055_744.0;
/// The largest argument reduced here, `2^20 · π/2`; beyond it (and for NaN) the standard
/// library's `sin_cos`.
const REDUCED: f64 = 1_647_099.0;

/// fdlibm's `__kernel_sin` coefficients: `sin r ≈ r + r³ (S1 + r² S2 + … + r¹⁰ S6)` on
/// `|r| ≤ π/4`, error below 2^−58 (Sun Microsystems, 1993).
const S: [f64; 6] = [
    -1.666_666_666_666_663_243_48e-1,
    8.333_333_333_322_489_461_24e-3,
    -1.984_126_982_985_794_931_34e-4,
    2.755_731_370_707_006_767_89e-6,
    -2.505_076_025_340_686_341_95e-8,
    1.589_690_995_211_550_102_21e-10,
];
/// fdlibm's `__kernel_cos` coefficients: `cos r ≈ 1 − r²/2 + r⁴ (C1 + r² C2 + … + r¹⁰ C6)`
/// on `|r| ≤ π/4`, error below 2^−58.
const C: [f64; 6] = [
    4.166_666_666_666_660_190_37e-2,
    -1.388_888_888_887_410_957_49e-3,
    2.480_158_728_947_672_941_78e-5,
    -2.755_731_435_139_066_330_35e-7,
    2.087_572_321_298_174_827_90e-9,
    -1.135_964_755_778_819_482_65e-11,
];

/// `(sin x, cos x)`, within about one unit in the last place of the standard library's (an
/// absolute error below `3e-16` for `|x| ≤ 2^20 π/2`; the standard library's beyond).
///
/// The argument is reduced by the nearest multiple `k` of `π/2` (Cody & Waite's two-part
/// constant, exact products for `|k| < 2^20`); `sin` and `cos` of the remainder `|r| ≤ π/4` are
/// fdlibm's polynomials, and the quadrant `k mod 4` swaps and negates them.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// let (s, c) = dzhanibekov::dynamics::gravity::sin_cos(2.0);
/// assert_relative_eq!(s, 2.0_f64.sin(), epsilon = 3e-16);
/// assert_relative_eq!(c, 2.0_f64.cos(), epsilon = 3e-16);
/// ```
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > REDUCED {
        return x.sin_cos();
    }
    let shifted = x * FRAC_2_PI + ROUND;
    let quadrant = shifted.to_bits() & 3;
    let k = shifted - ROUND;
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let z = r * r;
    let z2 = z * z;
    // Estrin's scheme: the two halves of each polynomial in parallel
    let sin_tail = (S[0] + z * S[1]) + z2 * ((S[2] + z * S[3]) + z2 * (S[4] + z * S[5]));
    let cos_tail = (C[0] + z * C[1]) + z2 * ((C[2] + z * C[3]) + z2 * (C[4] + z * C[5]));
    let sin_r = r + r * z * sin_tail;
    let cos_r = (1.0 - 0.5 * z) + z2 * cos_tail;
    let (s, c) = match quadrant & 1 {
        0 => (sin_r, cos_r),
        _ => (cos_r, -sin_r),
    };
    match quadrant & 2 {
        0 => (s, c),
        _ => (-s, -c),
    }
}

/// The gravity gradient's torque `3n² r̂_b × (I r̂_b)` in body axes at `t` on a body at attitude
/// `q` (world-from-body, any non-zero size: normalised here), for an orbit of rate `n` in the
/// world `x–y` plane (`r̂ = (cos nt, sin nt, 0)`), `inertia` applying the body's tensor to a
/// vector. See the module doc for how.
#[inline(always)]
pub fn gravity_gradient_torque(
    n: f64,
    t: f64,
    q: &Quaternion<f64>,
    inertia: impl FnOnce(&Vector3<f64>) -> Vector3<f64>,
) -> Vector3<f64> {
    gravity_gradient_torque_at(n, sin_cos(n * t), q, inertia)
}

/// [`gravity_gradient_torque`] at the orbit phase `(sin nt, cos nt)` made once for the stage
/// time (see [`crate::ode::StageTime`]).
#[inline(always)]
pub fn gravity_gradient_torque_at(
    n: f64,
    (s, c): (f64, f64),
    q: &Quaternion<f64>,
    inertia: impl FnOnce(&Vector3<f64>) -> Vector3<f64>,
) -> Vector3<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
    let norm2 = (ww + xx) + (yy + zz);
    // the first two rows of M̃ = |q|² M(q) (see `crate::kinematics::rotation_matrix`), taken
    // as columns of M̃ᵀ: r̃ = c M̃[0,:] + s M̃[1,:]
    let (xy, wz) = (x * y, w * z);
    let r = Vector3::new(
        c * ((ww + xx) - (yy + zz)) + s * (2.0 * (xy + wz)),
        c * (2.0 * (xy - wz)) + s * ((ww - xx) + (yy - zz)),
        c * (2.0 * (x * z + w * y)) + s * (2.0 * (y * z - w * x)),
    );
    let scale = 3.0 * n * n / (norm2 * norm2);
    r.cross(&inertia(&r)) * scale
}

/// The right-hand side, times `s`, of a body of constant principal moments in the gravity
/// gradient alone (constant wheels aside): what a run of such a system evaluates four times a
/// step, written out for its chain of dependent operations (the general model's for a right-hand
/// side of any parts goes through each kind's contribution in turn). At round-off from the
/// plain formulas (tested), with what depends on `t` and `s` alone formed beside the chain:
/// - `ω s / 2` from `H − h` by a multiplication by `r s / 2` (`r` the reciprocal moments): the
///   quaternion's rate takes it without a product after its sums, and `(H × ω) s` is
///   `2H × (ω s / 2)`, `2H` exact;
/// - the torque of a diagonal tensor, `r̂_b × (I r̂_b) = (r_y r_z (I_z − I_y), …)`, as
///   `(r̃_y r̃_z) (3 n² s ΔI_x) / |q|⁴` from the unnormalised `r̃` (see
///   [`gravity_gradient_torque`]): the division waits on `q` alone and meets the products last.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitKernel {
    orbit_rate: f64,
    /// `3 n² (I_z − I_y, I_x − I_z, I_y − I_x)`.
    gradient: Vector3<f64>,
    reciprocals: Vector3<f64>,
    /// The constant stored momenta (constant wheels), summed.
    stored: Vector3<f64>,
}

impl OrbitKernel {
    /// The kernel of `gravity` on a body of principal moments `moments` (reciprocals
    /// `reciprocals`) holding the constant momenta `stored`.
    pub fn new(
        gravity: &GravityGradient,
        moments: Vector3<f64>,
        reciprocals: Vector3<f64>,
        stored: Vector3<f64>,
    ) -> Self {
        let n = gravity.orbit_rate;
        let (i, k) = (moments, 3.0 * n * n);
        Self {
            orbit_rate: n,
            gradient: Vector3::new(k * (i.z - i.y), k * (i.x - i.z), k * (i.y - i.x)),
            reciprocals,
            stored,
        }
    }

    /// `(H' s, q' s)` at `t` for the total momentum `h` (body axes) and the attitude `q`
    /// (world-from-body, any non-zero size).
    #[inline(always)]
    pub fn increment(&self, t: f64, h: [f64; 3], q: [f64; 4], s: f64) -> ([f64; 3], [f64; 4]) {
        self.increment_at(self.phase(t), h, q, s)
    }

    /// The orbit's phase `(sin nt, cos nt)` at `t`: what [`OrbitKernel::increment_at`] takes,
    /// made once per stage time.
    #[inline(always)]
    pub fn phase(&self, t: f64) -> (f64, f64) {
        sin_cos(self.orbit_rate * t)
    }

    /// The orbit's phases at `t`, `t + d` and `t + 2d`: the later two turned from the first
    /// by `n d` and `2 n d` (one [`sin_cos`] beside the first), at round-off from
    /// [`OrbitKernel::phase`] of each time.
    #[inline(always)]
    pub fn phases(&self, t: f64, d: f64) -> [(f64, f64); 3] {
        let (s0, c0) = self.phase(t);
        let (sd, cd) = sin_cos(self.orbit_rate * d);
        let (s2d, c2d) = (2.0 * (sd * cd), 1.0 - 2.0 * (sd * sd));
        [
            (s0, c0),
            (s0 * cd + c0 * sd, c0 * cd - s0 * sd),
            (s0 * c2d + c0 * s2d, c0 * c2d - s0 * s2d),
        ]
    }

    /// [`OrbitKernel::increment`] at the phase `(sin nt, cos nt)` of [`OrbitKernel::phase`].
    #[inline(always)]
    pub fn increment_at(
        &self,
        (sn, cn): (f64, f64),
        h: [f64; 3],
        q: [f64; 4],
        s: f64,
    ) -> ([f64; 3], [f64; 4]) {
        let h = Vector3::from(h);
        let u = (h - self.stored).component_mul(&(self.reciprocals * (0.5 * s)));
        let turn = (h + h).cross(&u);
        let [w, x, y, z] = q;
        let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
        let norm2 = (ww + xx) + (yy + zz);
        let (xy, wz) = (x * y, w * z);
        let r = Vector3::new(
            cn * ((ww + xx) - (yy + zz)) + sn * (2.0 * (xy + wz)),
            cn * (2.0 * (xy - wz)) + sn * ((ww - xx) + (yy - zz)),
            cn * (2.0 * (x * z + w * y)) + sn * (2.0 * (y * z - w * x)),
        );
        let inv = 1.0 / (norm2 * norm2);
        let g = self.gradient * s;
        let torque = Vector3::new(
            (r.y * r.z * g.x) * inv,
            (r.z * r.x * g.y) * inv,
            (r.x * r.y * g.z) * inv,
        );
        let dq = [
            -(x * u.x + y * u.y + z * u.z),
            w * u.x + y * u.z - z * u.y,
            w * u.y + z * u.x - x * u.z,
            w * u.z + x * u.y - y * u.x,
        ];
        ((turn + torque).into(), dq)
    }
}

/// The gravity gradient of a circular orbit of rate `orbit_rate` in the world `x–y` plane
/// (see the module doc): an external torque.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GravityGradient {
    orbit_rate: f64,
}

impl GravityGradient {
    /// The gravity gradient of a circular orbit of rate `orbit_rate` (radians per unit time).
    ///
    /// # Errors
    /// `orbit_rate` not positive and finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::GravityGradient;
    /// assert!(GravityGradient::try_new(1e-3).is_ok());
    /// assert!(GravityGradient::try_new(-1.0).is_err());
    /// ```
    pub fn try_new(orbit_rate: f64) -> Result<Self> {
        if !(orbit_rate.is_finite() && orbit_rate > 0.0) {
            return Err(Error::invalid(
                "orbit_rate",
                "must be positive and finite",
                orbit_rate,
            ));
        }
        Ok(Self { orbit_rate })
    }

    pub fn orbit_rate(&self) -> f64 {
        self.orbit_rate
    }
}

impl Part for GravityGradient {
    const INFO: ModelInfo = ModelInfo {
        name: "gravity_gradient",
        about: "the gravity gradient of a circular orbit in the world x–y plane (τ = 3 n² r̂_b × \
                I r̂_b; the Jacobi integral kept)",
        law: false,
        params: &[Param::new(
            "orbit_rate",
            ParamKind::Scalar,
            "the orbit's rate n = √(μ / R³), radians per unit time (positive)",
        )],
        state: &[],
        keeps: Conserved::JACOBI.union(Conserved::Q_NORM),
        defines: Conserved::JACOBI,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: true,
        traits: Traits::EXTERNAL_TORQUE,
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(fields.number("orbit_rate")?)
    }

    fn largest_rate(&self, _least: f64) -> Option<(&'static str, f64, f64)> {
        Some(("orbit_rate", self.orbit_rate, self.orbit_rate))
    }

    /// At the orbit's phase the model made for the stage's time ([`Ctx::timed`]), or made here.
    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        let n = self.orbit_rate;
        let phase = c.timed.orbit.unwrap_or_else(|| sin_cos(n * c.t));
        gravity_gradient_torque_at(n, phase, &c.q, |v| c.inertia_times(v))
    }

    /// The Jacobi integral `J = T − n ẑ_b · H + (3/2) n² r̂_bᵀ I r̂_b` (see the module doc).
    fn integral(
        &self,
        t: f64,
        q: &Quaternion<f64>,
        tensor: &Matrix3<f64>,
        energy: f64,
        momentum: &Vector3<f64>,
    ) -> Option<f64> {
        let n = self.orbit_rate;
        let to_body = rotation_matrix(q).transpose();
        let (s, c) = (n * t).sin_cos();
        let r = to_body * Vector3::new(c, s, 0.0);
        let normal = to_body * Vector3::z();
        Some(energy - n * normal.dot(momentum) + 1.5 * n * n * r.dot(&(tensor * r)))
    }

    /// From `J ≥ ½ λ_min |ω − n ẑ_b|² − ½ n² λ_max − n |h|`,
    /// `|ω| ≤ √(2 (J + ½ n² λ_max + n |h|) / λ_min) + n`, for stored momenta of at most
    /// `stored` (a norm).
    fn rate_bound(&self, least: f64, largest: f64, integral: f64, stored: f64) -> Option<f64> {
        let n = self.orbit_rate;
        let room = integral + 0.5 * n * n * largest + n * stored;
        Some((2.0 * room.max(0.0) / least).sqrt() + n)
    }

    /// The orbit's rate over `2^e`.
    fn in_units(&self, scale: RateScale) -> Result<Self> {
        Self::try_new(scale.rate_to_unit(self.orbit_rate))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::rotation_matrix;
    use nalgebra::Matrix3;

    /// A reproducible spread of arguments (a linear congruential generator).
    fn arguments(count: usize, scale: f64) -> impl Iterator<Item = f64> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        (0..count).map(move |_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * scale
        })
    }

    #[test]
    fn sin_cos_agrees_with_the_standard_librarys_to_round_off() {
        let mut worst = 0.0_f64;
        for scale in [1e-3, 1.0, 10.0, 1e3, 1e5, REDUCED] {
            for x in arguments(20_000, scale) {
                let (s, c) = sin_cos(x);
                worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
            }
        }
        assert!(worst < 3e-16, "{worst:e}");
        // the quadrants' ends, zero and beyond the reduced range
        for k in -8..=8 {
            let x = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let (s, c) = sin_cos(x);
            assert!(
                (s - x.sin()).abs() < 3e-16 && (c - x.cos()).abs() < 3e-16,
                "{x}"
            );
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(1e7), 1e7_f64.sin_cos());
        assert!(sin_cos(f64::NAN).0.is_nan());
    }

    #[test]
    fn the_kernel_is_the_plain_right_hand_side_at_any_size_of_q() {
        let (n, i) = (0.3, Vector3::new(2.0, 3.0, 4.5));
        let stored = Vector3::new(0.1, -0.4, 0.25);
        let g = GravityGradient::try_new(n).unwrap();
        let kernel = OrbitKernel::new(&g, i, i.map(|v| 1.0 / v), stored);
        for (k, t) in arguments(50, 40.0).enumerate() {
            let size = 0.5 + k as f64 * 0.03;
            let q = Quaternion::new(0.9, 0.2 - t * 0.01, -0.3, 0.25) * size;
            let h = Vector3::new(0.7 + t * 0.01, -1.1, 2.3);
            let s = 0.01 + k as f64 * 1e-3;
            // H' = H × ω + 3n² r̂_b × (I r̂_b), q' = ½ q ⊗ (0, ω), ω = I⁻¹ (H − h)
            let omega = (h - stored).component_div(&i);
            let tensor = Matrix3::from_diagonal(&i);
            let rb =
                rotation_matrix(&q).transpose() * Vector3::new((n * t).cos(), (n * t).sin(), 0.0);
            let dh = (h.cross(&omega) + rb.cross(&(tensor * rb)) * (3.0 * n * n)) * s;
            let dq = q * Quaternion::from_imag(omega) * (0.5 * s);
            let (fh, fq) = kernel.increment(t, h.into(), [q.w, q.i, q.j, q.k], s);
            let size_h = dh.amax().max(1e-300);
            assert!(
                (Vector3::from(fh) - dh).amax() < 1e-14 * size_h,
                "{t}: {fh:?} vs {dh}"
            );
            let plain = [dq.w, dq.i, dq.j, dq.k];
            let size_q = plain.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (a, b) in fq.iter().zip(plain) {
                assert!((a - b).abs() < 1e-14 * size_q, "{t}: {fq:?} vs {plain:?}");
            }
        }
    }

    #[test]
    fn the_turned_phases_are_the_exact_ones_to_the_rounding_of_the_angle() {
        let n = 0.3;
        let g = GravityGradient::try_new(n).unwrap();
        let i = Vector3::new(2.0, 3.0, 4.5);
        let kernel = OrbitKernel::new(&g, i, i.map(|v| 1.0 / v), Vector3::zeros());
        for (k, t) in arguments(400, 2000.0).enumerate() {
            let d = 1e-4 * (1.0 + k as f64);
            let phases = kernel.phases(t, d);
            assert_eq!(phases[0], sin_cos(n * t));
            for (j, (s, c)) in phases.into_iter().enumerate() {
                // the exact angle n (t + j d) as hi + lo (products split by a fused
                // multiply-add, the sum by Knuth's two-sum), its phase to first order in lo
                let jd = j as f64 * d;
                let (p, q) = (n * t, n * jd);
                let hi = p + q;
                let z = hi - p;
                let lo = (p - (hi - z)) + (q - z) + n.mul_add(t, -p) + n.mul_add(jd, -q);
                let (es, ec) = (hi.sin() + hi.cos() * lo, hi.cos() - hi.sin() * lo);
                // within the rounding of n t (which `sin_cos(n * t)` carries as well)
                let tol = 1e-15 + f64::EPSILON * (n * t).abs();
                assert!((s - es).abs() < tol && (c - ec).abs() < tol, "{t} {d}: {j}");
            }
        }
    }

    #[test]
    fn the_torque_is_the_plain_formulas_at_any_size_of_q() {
        let n = 0.3;
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        for (k, t) in arguments(50, 40.0).enumerate() {
            let size = 0.5 + k as f64 * 0.03;
            let q = Quaternion::new(0.9, 0.2 - t * 0.01, -0.3, 0.25) * size;
            let r =
                rotation_matrix(&q).transpose() * Vector3::new((n * t).cos(), (n * t).sin(), 0.0);
            let plain = r.cross(&(i * r)) * (3.0 * n * n);
            let fast = gravity_gradient_torque(n, t, &q, |v| i * v);
            assert!((fast - plain).amax() < 1e-15, "{t}: {fast} vs {plain}");
        }
    }
}
