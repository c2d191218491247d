//! The exact motion of the free rigid body, evaluated directly at any time.
//!
//! **Body rates.** Relabel the body axes as a right-handed frame `(1, 2, 3)` (a signed
//! permutation of x, y, z with determinant +1) in which axis 2 is the intermediate one and the
//! angular momentum circulates about axis 3 — the major axis when `L² > 2E I_mid`, the minor
//! one when `L² < 2E I_mid`. Then (Landau & Lifshitz §37)
//!
//! ```text
//! ω1 = s1 A1 cn(u),  ω2 = s2 A2 sn(u),  ω3 = s3 A3 dn(u),   u = λ t + u0,
//! A1² = (2E J3 − L²) / (J1 (J3 − J1)),  A2² = (2E J3 − L²) / (J2 (J3 − J2)),
//! A3² = (L² − 2E J1) / (J3 (J3 − J1)),  λ² = (J3 − J2)(L² − 2E J1) / (J1 J2 J3),
//! m = (J2 − J1)(2E J3 − L²) / ((J3 − J2)(L² − 2E J1)),
//! m1 = 1 − m = (J3 − J1)(L² − 2E J2) / ((J3 − J2)(L² − 2E J1)).
//! ```
//!
//! Each amplitude is computed as a `hypot` of two rates and `m1` from `L² − 2E J2 =
//! J1 (J1 − J2) ω1² + J3 (J3 − J2) ω3²`, so that nothing cancels but what the initial
//! condition itself fixes. On the separatrix (`m1 = 0`) `sn, cn, dn` become `tanh, sech, sech`:
//! a single flip.
//!
//! **Attitude.** Let `n(t) = L_body(t) / |L|`, `a = s3 e3` (never opposite to `n`, since `ω3`
//! keeps its sign), and `B(t)` the smallest rotation taking `n` to `a`. Then
//! `q(t) = R(e_L, Φ(t)) ⊗ P ⊗ B(t)`, with `P` fixed by `q(0)`, `e_L = L_world / |L|`, and
//! the angle about the fixed angular momentum obeying
//!
//! ```text
//! Φ' = (2E + L s3 ω3) / (L + s3 L3) = L/J3 + (2E J3 − L²) / (J3 (L + κ dn u)),   κ = J3 A3,
//! ```
//!
//! whose integral is closed-form: with `N = −J3 (J2 − J1) / (J1 (J3 − J2)) < 0`,
//! `(J1 A1)² ∫ du / (L + κ dn u) = L Π(N; am u | m) − κ atan(√(1 − N) tan am u) / √(1 − N)`
//! (the elliptic integral of the third kind, by Carlson's `R_J`), and per half-period `2K`
//! it grows by a constant computed once. So each frame costs the same at any `t`.
//!
//! A symmetric top (two equal moments) has `ω⊥` turning at `Ω = (I3 − I) ω3 / I` in the body
//! and `q(t) = exp(t L_world / 2I) ⊗ q0 ⊗ exp(−Ω t e3 / 2)`; spin exactly about a principal
//! axis is steady rotation `q(t) = q0 ⊗ exp(ω t / 2)`.
//!
//! Flip times follow the definition of [`crate::observe::FlipDetector`]: a zero of `sn` (a
//! sign change of the intermediate rate) counts when the intermediate axis is dominant,
//! `|L2| > |L|/√2`, in the half-periods on both sides of it within the run.

pub(crate) mod compensated;
pub mod elliptic;

use nalgebra::{Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};

use crate::body::RigidBody;
use crate::dynamics::{state_from, State};
use crate::error::{Error, Result};
use crate::exact::compensated::{dd_mul, two_sum};
use crate::exact::elliptic::{sn2_integral, sn2_integral_complete, Jacobi};

/// Flip times a run may return at most (800 MB).
pub const MAX_FLIPS: u64 = 100_000_000;

/// `(J3 − J1) / J1` above which `G` is integrated numerically (see [`Asymmetric::g`]).
const ROD_RATIO: f64 = 4.0;

/// The most Gauss–Legendre panels [`integral_of_reciprocal`] takes.
const MAX_PANELS: f64 = 4096.0;

/// `∫₀^r du / (L + κ dn u)` for `0 ≤ r ≤ K`, by 16-point Gauss–Legendre on equal panels no
/// longer than `panel`.
fn integral_of_reciprocal(jacobi: &Jacobi, l: f64, kappa: f64, r: f64, panel: f64) -> f64 {
    let (nodes, weights) = gauss_legendre();
    // `r ≤ K` and `panel ≥ min(K, K')/2 ≥ π/4` give at most a few hundred panels; the cap
    // only guards against a degenerate parameter ever making this loop endless.
    let panels = (r / panel).ceil().clamp(1.0, MAX_PANELS);
    let h = r / panels;
    let mut sum = 0.0;
    for p in 0..panels as usize {
        let mid = h * (p as f64 + 0.5);
        let mut part = 0.0;
        for (x, w) in nodes.iter().zip(weights) {
            let dn = jacobi.sn_cn_dn_reduced((0.5 * h).mul_add(*x, mid)).2;
            part += w / kappa.mul_add(dn, l);
        }
        sum += 0.5 * h * part;
    }
    sum
}

/// The 16 nodes and weights of Gauss–Legendre quadrature on `[−1, 1]`, by Newton's method on
/// the Legendre polynomial (computed once).
fn gauss_legendre() -> &'static ([f64; 16], [f64; 16]) {
    static RULE: std::sync::OnceLock<([f64; 16], [f64; 16])> = std::sync::OnceLock::new();
    RULE.get_or_init(|| {
        const N: usize = 16;
        let (mut nodes, mut weights) = ([0.0; N], [0.0; N]);
        for i in 0..N {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (N as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                // P_N(x) and P_N'(x) by the three-term recurrence
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=N {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                derivative = N as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / derivative;
                x -= dx;
                if dx.abs() <= 1e-17 {
                    break;
                }
            }
            nodes[i] = x;
            weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
        }
        (nodes, weights)
    })
}

/// The exact free motion from one initial state.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// use dzhanibekov::exact::ExactMotion;
/// let body = dzhanibekov::RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
/// let motion = ExactMotion::try_new(&body, [0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]).unwrap();
/// let x = motion.state_at(1e6);
/// let q_norm = x[3..].iter().map(|c| c * c).sum::<f64>().sqrt();
/// assert_relative_eq!(q_norm, 1.0, epsilon = 1e-15);
/// assert!(motion.flip_period() > 0.0 && motion.flip_period().is_finite());
/// ```
#[derive(Debug, Clone)]
pub struct ExactMotion {
    kind: Kind,
    /// Whether the body has an intermediate axis (see [`RigidBody::intermediate_axis`]):
    /// moments equal within [`crate::body::SYMMETRY_TOLERANCE`] but not exactly move by the
    /// asymmetric closed form of their own moments, and never flip.
    flips: bool,
}

#[derive(Debug, Clone)]
enum Kind {
    Steady {
        omega: Vector3<f64>,
        q0: UnitQuaternion<f64>,
    },
    Symmetric {
        axis: usize,
        /// Ω, the turning rate of ω⊥ in the body.
        rate: f64,
        omega0: Vector3<f64>,
        /// `L_world / I`: the rotation vector of the space cone per unit time.
        spin_world: Vector3<f64>,
        q0: UnitQuaternion<f64>,
    },
    Asymmetric(Box<Asymmetric>),
}

/// The asymmetric top in its canonical frame, in scaled units: time `τ = scale · t`, rates
/// `ω / scale`, moments over a power of two, so that nothing overflows or underflows.
#[derive(Debug, Clone)]
struct Asymmetric {
    time_scale: f64,
    /// Canonical axis k is body axis `perm[k]` times `sign[k]`.
    perm: [usize; 3],
    sign: [f64; 3],
    /// Body-to-canonical coordinates, as a quaternion `r`: `q_body = q_canonical ⊗ r`.
    to_canonical: UnitQuaternion<f64>,
    inertia: Vector3<f64>,
    /// `(s1 A1, s2 A2, s3 A3)`.
    amplitude: Vector3<f64>,
    lambda: f64,
    u0: f64,
    jacobi: Jacobi,
    separatrix: bool,
    momentum: f64,
    axis_sign: f64,
    /// Which split of Φ' is used: see [`Asymmetric::g`].
    about_minor: bool,
    /// `G` by quadrature: a longest Gauss–Legendre panel, or 0 for the closed form.
    panel: f64,
    /// The constant part of Φ': `L / J3`, or `2E / L` about the minor axis.
    rate_mean: f64,
    /// The factor of `G(u)` in Φ: `(J3 − J1) / (J1 J3 λ)`, or `−(J3 − J1) / (J1 L λ)`.
    factor: f64,
    characteristic: f64,
    sqrt_1mn: f64,
    kappa: f64,
    /// `J1 A1`.
    rho: f64,
    /// `G(u + 2K) − G(u)`; `None` until a `u` beyond the first period asks for it (a motion
    /// built for one step, [`ExactMotion::try_new_for_step`], seldom does).
    g_period: Option<f64>,
    g0: f64,
    frame: UnitQuaternion<f64>,
    e_l: Unit<Vector3<f64>>,
    /// Half-width in `u` of the stretch around each zero of `sn` where the intermediate axis
    /// is not dominant; `None` if it never is.
    u_dominant: Option<f64>,
}

/// # Construction
impl ExactMotion {
    /// The motion of `body` from body rates `omega0` and attitude `q0` (scalar first,
    /// normalised here).
    ///
    /// # Errors
    /// Non-finite `omega0`; a zero or non-finite `q0`; rates so extreme that the solution's
    /// parameters are not finite.
    pub fn try_new(body: &RigidBody, omega0: [f64; 3], q0: [f64; 4]) -> Result<Self> {
        let motion = Self::build(body, omega0, q0, true)?;
        motion.starts_at(&Vector3::from(omega0), body)?;
        Ok(motion)
    }

    /// The motion of `body` from `omega0` and `q0` for one advance from it (a splitting's
    /// step, [`crate::rigid::ExactKick`]): [`ExactMotion::try_new`] without what such an
    /// advance never reads — the check that the closed form's state at `t = 0` is the start
    /// (a full evaluation; made once on a run's start by the caller) and where the
    /// intermediate axis is dominant (the flips'). The same motion at the same cost per
    /// [`ExactMotion::state_at`]; about a third cheaper to build.
    ///
    /// # Errors
    /// As [`ExactMotion::try_new`], less the check of the start.
    pub fn try_new_for_step(body: &RigidBody, omega0: [f64; 3], q0: [f64; 4]) -> Result<Self> {
        Self::build(body, omega0, q0, false)
    }

    fn build(body: &RigidBody, omega0: [f64; 3], q0: [f64; 4], flips: bool) -> Result<Self> {
        if !omega0.iter().all(|w| w.is_finite()) {
            return Err(Error::invalid(
                "omega0",
                "must be three finite body rates",
                omega0,
            ));
        }
        let q0 = crate::kinematics::normalized(q0)?;
        let q0 = UnitQuaternion::new_unchecked(Quaternion::new(q0[0], q0[1], q0[2], q0[3]));
        let omega = Vector3::from(omega0);
        let inertia = body.inertia_body();
        let kind = if omega.iter().filter(|w| **w != 0.0).count() <= 1 {
            Kind::Steady { omega, q0 }
        } else if exactly_symmetric(&inertia) {
            symmetric(inertia, omega, q0)
        } else {
            let motion = Asymmetric::new(inertia, omega, q0, flips);
            if motion.is_finite() {
                Kind::Asymmetric(Box::new(motion))
            } else if near_axis(&omega) {
                // so close to an axis that float64 holds no wobble: a steady spin, as
                // `flip_period_of_rates` (sweeps) says too
                Kind::Steady { omega, q0 }
            } else {
                return Err(Error::invalid(
                    "omega0",
                    "must give an exact solution with finite parameters",
                    omega0,
                ));
            }
        };
        let flips = flips && body.intermediate_axis().is_some();
        Ok(Self { kind, flips })
    }

    /// [`Error::InvalidArgument`] unless the solution's state at `t = 0` is the start: moments
    /// so far apart (one vanishing beside the others, e.g. `(1, 2, 1e-30)`) that the closed
    /// form cannot resolve them give another frame 0, and such a body is refused.
    fn starts_at(&self, omega0: &Vector3<f64>, body: &RigidBody) -> Result<()> {
        let x = self.state_at(0.0);
        let largest = omega0.amax();
        let off = (0..3).fold(0.0_f64, |m, k| m.max((x[k] - omega0[k]).abs()));
        match off <= START_TOLERANCE * largest {
            true => Ok(()),
            false => Err(Error::invalid(
                "inertia",
                "must have moments the closed form resolves for method='exact' (its state \
                 at t = 0 is not the start for these: a moment vanishes beside the others); \
                 use an integrator such as 'dop853'",
                body.inertia_body().as_slice(),
            )),
        }
    }
}

/// The largest distance of the closed form's rates at `t = 0` from the start, relative to the
/// largest rate, that [`ExactMotion::try_new`] accepts (round-off is ~1e-15).
const START_TOLERANCE: f64 = 1e-9;

/// Whether `omega` is so close to a principal axis (the other rates below 1e-150 of the
/// largest) that the squares of the deviation, which set the elliptic parameter's
/// complement, underflow.
fn near_axis(omega: &Vector3<f64>) -> bool {
    let largest = omega.amax();
    omega.iter().filter(|w| w.abs() > 1e-150 * largest).count() <= 1
}

/// Whether two moments are exactly equal: the symmetric top's closed form is then exact; moments
/// equal only within [`crate::body::SYMMETRY_TOLERANCE`] take the asymmetric one (exact for
/// them) and are told apart from it only in that they never flip.
fn exactly_symmetric(i: &Vector3<f64>) -> bool {
    i.x == i.y || i.y == i.z || i.x == i.z
}

fn symmetric(inertia: Vector3<f64>, omega: Vector3<f64>, q0: UnitQuaternion<f64>) -> Kind {
    // the symmetry axis: the one whose two others are nearest equal (equal within
    // `SYMMETRY_TOLERANCE`, perhaps not exactly: a mesh's moments differ by round-off)
    let gap = |k: usize| {
        let (a, b) = (inertia[(k + 1) % 3], inertia[(k + 2) % 3]);
        (a - b).abs() / a.max(b)
    };
    let axis = (0..3)
        .min_by(|&a, &b| gap(a).total_cmp(&gap(b)))
        .unwrap_or(2);
    let i = inertia[(axis + 1) % 3];
    let rate = (inertia[axis] - i) / i * omega[axis];
    // L_world / I = q0 (I ω0 / I) q0⁻¹, scaled before the product so it cannot overflow.
    let spin_world = q0
        * inertia
            .component_div(&Vector3::repeat(i))
            .component_mul(&omega);
    Kind::Symmetric {
        axis,
        rate,
        omega0: omega,
        spin_world,
        q0,
    }
}

/// `L² − 2E J2 = J3 (J3 − J2) ω3² − J1 (J2 − J1) ω1²` for moments `j = (J1, J2, J3)`, in
/// double-double arithmetic (error-free sums and FMA products) rounded once at the end.
///
/// Near the separatrix far from the intermediate axis the two terms are O(1) and cancel to
/// `1 − m`; each rounded in float64 would leave an error of 1e-16 in a difference of 1e-15,
/// and the flip period `2K/λ ≈ ln(16/(1 − m))/λ` would be off in its third digit.
fn separatrix_measure(j: [f64; 3], w1: f64, w3: f64) -> f64 {
    let [j1, j2, j3] = j;
    let major = dd_mul(dd_mul(dd_mul(two_sum(j3, -j2), j3), w3), w3);
    let minor = dd_mul(dd_mul(dd_mul(two_sum(j2, -j1), j1), w1), w1);
    let (hi, lo) = two_sum(major.0, -minor.0);
    hi + (lo + (major.1 - minor.1))
}

/// A power of two near `x > 0`.
fn power_of_two_near(x: f64) -> f64 {
    2.0_f64.powi(x.log2().floor() as i32)
}

/// The rates and moments in the solution's canonical frame: axes permuted (with a sign that
/// keeps the frame right-handed) so that ω₃ never changes sign (`L² ≥ 2E J₂`), rates over a
/// power of two near the largest and moments over one near the largest, with the amplitudes
/// `a₁, a₂, a₃` of ω, the rate `λ` and the separatrix measure `p_mid ∝ L² − 2E J₂`.
struct Canonical {
    perm: [usize; 3],
    sign: [f64; 3],
    time_scale: f64,
    w: Vector3<f64>,
    j: Vector3<f64>,
    a: Vector3<f64>,
    lambda: f64,
    p_mid: f64,
}

impl Canonical {
    fn new(inertia_body: Vector3<f64>, omega_body: Vector3<f64>) -> Self {
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| inertia_body[a].total_cmp(&inertia_body[b]));
        let [lo, mid, hi] = order;
        let time_scale = power_of_two_near(omega_body.amax());
        let inertia_scale = power_of_two_near(inertia_body.max());
        let w_body = omega_body / time_scale;
        let j_body = inertia_body / inertia_scale;
        // The separatrix measure L² − 2E I_mid, from the two rates that enter it.
        let p_mid_sign = separatrix_measure(
            [j_body[lo], j_body[mid], j_body[hi]],
            w_body[lo],
            w_body[hi],
        );
        let perm = if p_mid_sign >= 0.0 {
            [lo, mid, hi]
        } else {
            [hi, mid, lo]
        };
        let even = matches!(perm, [0, 1, 2] | [1, 2, 0] | [2, 0, 1]);
        let sign = [1.0, if even { 1.0 } else { -1.0 }, 1.0];
        let w = Vector3::from_fn(|k, _| sign[k] * w_body[perm[k]]);
        let j = Vector3::from_fn(|k, _| j_body[perm[k]]);
        let (j1, j2, j3) = (j.x, j.y, j.z);
        let (d21, d31, d32) = (j2 - j1, j3 - j1, j3 - j2);
        let a = Vector3::new(
            w.x.hypot((j2 * d32 / (j1 * d31)).sqrt() * w.y),
            ((j1 * d31 / (j2 * d32)).sqrt() * w.x).hypot(w.y),
            w.z.hypot((j2 * d21 / (j3 * d31)).sqrt() * w.y),
        );
        Self {
            perm,
            sign,
            time_scale,
            w,
            j,
            a,
            lambda: a.z * (d32 * d31 / (j1 * j2)).sqrt(),
            p_mid: separatrix_measure([j1, j2, j3], w.x, w.z),
        }
    }

    /// The elliptic parameter `m` and its complement `1 − m`, the latter from `p_mid` so that
    /// it keeps its digits near the separatrix; `(1, 0)` on it.
    ///
    /// An `m1` that underflows to zero is the separatrix as far as float64 can tell (and with
    /// no period, `K = ∞`, the periodic formulas would not end): `(1, 0)` then too.
    fn parameter(&self) -> (f64, f64) {
        if self.p_mid == 0.0 {
            return (1.0, 0.0);
        }
        let (j1, j2, j3) = (self.j.x, self.j.y, self.j.z);
        let ratio = self.a.x / self.a.z;
        let m1 = self.p_mid / ((j3 - j2) * j3 * self.a.z * self.a.z);
        if m1 == 0.0 {
            return (1.0, 0.0);
        }
        (ratio * ratio * (j1 * (j2 - j1) / (j3 * (j3 - j2))), m1)
    }
}

impl Asymmetric {
    /// The motion; with `flips`, where the intermediate axis is dominant too.
    fn new(
        inertia_body: Vector3<f64>,
        omega_body: Vector3<f64>,
        q0: UnitQuaternion<f64>,
        flips: bool,
    ) -> Self {
        let c = Canonical::new(inertia_body, omega_body);
        let mut rotation = Matrix3::zeros();
        for k in 0..3 {
            rotation[(k, c.perm[k])] = c.sign[k];
        }
        let to_canonical =
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rotation));

        let (w, j, time_scale, lambda) = (c.w, c.j, c.time_scale, c.lambda);
        let (j1, j2, j3) = (j.x, j.y, j.z);
        let (d21, d31, d32) = (j2 - j1, j3 - j1, j3 - j2);
        let (a1, a2, a3) = (c.a.x, c.a.y, c.a.z);
        let (m, m1) = c.parameter();
        let separatrix = m1 == 0.0;
        let jacobi = Jacobi::new(m, m1);

        let s3 = w.z.signum();
        let (s1, s2) = if separatrix {
            (w.x.signum(), w.x.signum() * s3)
        } else {
            (s3 * d32.signum(), 1.0)
        };
        let amplitude = Vector3::new(s1 * a1, s2 * a2, s3 * a3);
        let u0 = if separatrix {
            ((w.y / (s2 * a2)) / (w.x.abs() / a1)).asinh()
        } else {
            jacobi.argument_of(w.y / a2, w.x / (s1 * a1), w.z.abs() / a3)
        };

        let l_body = j.component_mul(&w);
        let momentum = l_body.norm();
        let two_energy = w.dot(&l_body);
        let kappa = j3 * a3;
        let characteristic = -j3 * d21 / (j1 * d32);
        let sqrt_1mn = (1.0 - characteristic).sqrt();
        let about_minor = d31 < 0.0;
        // Tumbling about the major axis with J1 ≪ J3 (a rod), L Π − κ C cancels to a
        // fraction J1 / J3 of its terms: integrate 1/(L + κ dn) numerically instead.
        let quadrature = !about_minor && !separatrix && d31 > ROD_RATIO * j1;
        let panel = if quadrature {
            0.5 * jacobi
                .quarter_period()
                .min(jacobi.imaginary_quarter_period())
        } else {
            0.0
        };
        let (rate_mean, factor) = if about_minor {
            (two_energy / momentum, -d31 / (j1 * momentum * lambda))
        } else if quadrature {
            let rho = j1 * a1;
            (momentum / j3, rho * rho * d31 / (j1 * j3 * lambda))
        } else {
            (momentum / j3, d31 / (j1 * j3 * lambda))
        };

        let q_canonical0 = q0 * to_canonical.inverse();
        let n0 = l_body / momentum;
        let e_l = Unit::new_normalize(q_canonical0 * n0);
        let mut motion = Self {
            time_scale,
            perm: c.perm,
            sign: c.sign,
            to_canonical,
            inertia: j,
            amplitude,
            lambda,
            u0,
            jacobi,
            separatrix,
            momentum,
            axis_sign: s3,
            about_minor,
            panel,
            rate_mean,
            factor,
            characteristic,
            sqrt_1mn,
            kappa,
            rho: j1 * a1,
            g_period: None,
            g0: 0.0,
            frame: UnitQuaternion::identity(),
            e_l,
            u_dominant: None,
        };
        if flips {
            motion.g_period = Some(motion.period_of_g());
        }
        motion.g0 = motion.g(u0);
        motion.frame = q_canonical0 * motion.swing(&n0).inverse();
        let threshold = momentum * std::f64::consts::FRAC_1_SQRT_2 / (j2 * a2);
        if flips && threshold < 1.0 {
            motion.u_dominant = Some(motion.jacobi.inverse_sn(threshold));
        }
        motion
    }

    fn is_finite(&self) -> bool {
        [
            self.lambda,
            self.u0,
            self.g0,
            self.g_period.unwrap_or(0.0),
            self.factor,
            self.rate_mean,
            self.momentum,
        ]
        .iter()
        .chain(self.amplitude.iter())
        .all(|v| v.is_finite())
            && self.frame.coords.iter().all(|v| v.is_finite())
            && self.e_l.iter().all(|v| v.is_finite())
    }

    /// The non-constant part of Φ, up to [`Asymmetric::factor`]. Φ' is a Möbius function of
    /// `dn`, split so that neither part is large when the other is small:
    ///
    /// - about the major axis, `Φ' = L/J3 + (2E J3 − L²) / (J3 (L + κ dn))` and
    ///   `G = ρ² ∫ du / (L + κ dn) = L Π(N; am u) − κ C(u)`;
    /// - about the minor axis (where `L/J3` can be huge for a thin rod),
    ///   `Φ' = 2E/L + (L² − 2E J3) A3 dn / (L (L + κ dn))` and
    ///   `G = ρ² ∫ A3 dn du / (L + κ dn) = A3 (L C(u) − κ (u + (N − m) S(u)))`,
    ///
    /// with `ρ² = L² − κ² = (J1 A1)²`, `C(u) = ∫ dn du / (1 − N sn²) = atan(√(1 − N) tan am u) /
    /// √(1 − N)`, `S(u) = ∫ sn² du / (1 − N sn²)` and `Π = u + N S`. On the separatrix
    /// (`dn = sech`, about the major axis by convention) `G` is elementary. For a body
    /// tumbling about its major axis with `J3 − J1 > 4 J1`, where `L Π − κ C` is a small
    /// difference of large terms, `G = ∫ du / (L + κ dn)` (with `ρ²` moved into the factor)
    /// by Gauss–Legendre quadrature on panels no longer than `min(K, K')/2`: the integrand is
    /// analytic within `K'` of the real axis, so 16 nodes a panel reach round-off.
    fn g(&self, u: f64) -> f64 {
        let (l, kappa) = (self.momentum, self.kappa);
        if self.separatrix {
            // ∫ du / (L + κ sech u) = u/L − (2κ / (L ρ)) atan(ρ tanh(u/2) / (L + κ))
            let rho = self.rho;
            return rho * rho * u / l
                - 2.0 * kappa * rho / l * (rho / (l + kappa) * (0.5 * u).tanh()).atan();
        }
        let n = self.characteristic;
        let (j, r) = self.jacobi.reduce(u);
        if self.panel > 0.0 {
            let part = integral_of_reciprocal(&self.jacobi, l, kappa, r.abs(), self.panel);
            return self.periods(j, part.copysign(r));
        }
        let (sn, cn, dn) = self.jacobi.sn_cn_dn_reduced(r);
        let sn2 = sn2_integral(n, sn, cn, dn);
        let circular = (self.sqrt_1mn * sn).atan2(cn) / self.sqrt_1mn;
        let part = if self.about_minor {
            let a3 = self.amplitude.z.abs();
            a3 * (l * circular - kappa * (n - self.jacobi.m()).mul_add(sn2, r))
        } else {
            l * n.mul_add(sn2, r) - kappa * circular
        };
        self.periods(j, part)
    }

    /// `G` from its part within the period, `j` periods on: `j (G(u + 2K) − G(u)) + part`.
    #[inline]
    fn periods(&self, j: f64, part: f64) -> f64 {
        match (j, self.g_period) {
            (0.0, _) => part,
            (_, Some(period)) => j.mul_add(period, part),
            (_, None) => j.mul_add(self.period_of_g(), part),
        }
    }

    /// `G(u + 2K) − G(u)` (see [`Asymmetric::g`]): by quadrature for a rod, else from the
    /// complete integrals (`Π(N | m) = K + N S`, `S` by Carlson's `R_J`).
    fn period_of_g(&self) -> f64 {
        if self.separatrix {
            return 0.0;
        }
        let (l, kappa) = (self.momentum, self.kappa);
        let k = self.jacobi.quarter_period();
        if self.panel > 0.0 {
            return 2.0 * integral_of_reciprocal(&self.jacobi, l, kappa, k, self.panel);
        }
        let n = self.characteristic;
        let sn2 = 2.0 * sn2_integral_complete(n, self.jacobi.m1());
        let circular = std::f64::consts::PI / self.sqrt_1mn;
        if self.about_minor {
            let a3 = self.amplitude.z.abs();
            a3 * (l * circular - kappa * (n - self.jacobi.m()).mul_add(sn2, 2.0 * k))
        } else {
            l * n.mul_add(sn2, 2.0 * k) - kappa * circular
        }
    }

    /// The smallest rotation taking the unit vector `n` to `a = s3 e3`: `∝ (1 + n·a, n × a)`.
    fn swing(&self, n: &Vector3<f64>) -> UnitQuaternion<f64> {
        let s = self.axis_sign;
        UnitQuaternion::new_normalize(Quaternion::new(1.0 + s * n.z, s * n.y, -s * n.x, 0.0))
    }

    fn state_at(&self, t: f64) -> State {
        let tau = self.time_scale * t;
        let u = self.lambda.mul_add(tau, self.u0);
        let (sn, cn, dn) = self.jacobi.sn_cn_dn(u);
        let w = self.amplitude.component_mul(&Vector3::new(cn, sn, dn));
        let n = self.inertia.component_mul(&w) / self.momentum;
        let phi = self.rate_mean * tau + self.factor * (self.g(u) - self.g0);
        let about_l = UnitQuaternion::from_axis_angle(&self.e_l, phi);
        let q = about_l * self.frame * self.swing(&n) * self.to_canonical;
        let mut omega = [0.0; 3];
        for k in 0..3 {
            omega[self.perm[k]] = self.sign[k] * w[k] * self.time_scale;
        }
        let q = q.into_inner();
        state_from(omega, [q.w, q.i, q.j, q.k])
    }

    /// The first and last `j` with a counted flip at `u = 2K j` in `[u0, u_end]`.
    fn flip_range(&self, t_end: f64) -> Option<(f64, f64)> {
        let width = self.u_dominant?;
        let u_end = self.lambda.mul_add(self.time_scale * t_end, self.u0);
        if self.separatrix {
            return (self.u0 < -width && width < u_end).then_some((0.0, 0.0));
        }
        let two_k = 2.0 * self.jacobi.quarter_period();
        let first = ((self.u0 + width) / two_k).floor() + 1.0;
        let last = ((u_end - width) / two_k).ceil() - 1.0;
        (first <= last).then_some((first, last))
    }
}

/// # Evaluation
impl ExactMotion {
    /// The state `[u, v, w, Q, U, V, W]` at time `t`, at a cost independent of `t`.
    pub fn state_at(&self, t: f64) -> State {
        match &self.kind {
            Kind::Steady { omega, q0 } => {
                let q = (q0 * UnitQuaternion::from_scaled_axis(omega * t)).into_inner();
                state_from((*omega).into(), [q.w, q.i, q.j, q.k])
            }
            Kind::Symmetric {
                axis,
                rate,
                omega0,
                spin_world,
                q0,
            } => {
                let e = Unit::new_unchecked(Vector3::ith(*axis, 1.0));
                let body_turn = UnitQuaternion::from_axis_angle(&e, rate * t);
                let omega = body_turn * omega0;
                let space_turn = UnitQuaternion::from_scaled_axis(spin_world * t);
                let q = (space_turn * q0 * body_turn.inverse()).into_inner();
                state_from(omega.into(), [q.w, q.i, q.j, q.k])
            }
            Kind::Asymmetric(motion) => motion.state_at(t),
        }
    }

    /// The time between flips, `2K(m)/λ`; infinite when the motion never flips: on the
    /// separatrix (one flip at most), for spin exactly about a principal axis, for a symmetric
    /// top (no intermediate axis), and for wobbles about a stable axis that never bring the
    /// intermediate axis nearest to `L` (its rate still changes sign every `2K/λ`).
    pub fn flip_period(&self) -> f64 {
        match &self.kind {
            Kind::Asymmetric(motion)
                if self.flips && motion.u_dominant.is_some() && !motion.separatrix =>
            {
                2.0 * motion.jacobi.quarter_period() / motion.lambda / motion.time_scale
            }
            _ => f64::INFINITY,
        }
    }

    /// The flip times in `[0, t_end]`, by the definition of [`crate::observe::FlipDetector`].
    ///
    /// # Errors
    /// [`Error::TooLarge`] for more than [`MAX_FLIPS`] flips.
    pub fn flip_times(&self, t_end: f64) -> Result<Vec<f64>> {
        let Kind::Asymmetric(motion) = &self.kind else {
            return Ok(Vec::new());
        };
        if !self.flips {
            return Ok(Vec::new());
        }
        let Some((first, last)) = motion.flip_range(t_end) else {
            return Ok(Vec::new());
        };
        let count = last - first + 1.0;
        if count > MAX_FLIPS as f64 {
            return Err(Error::TooLarge {
                what: "keeping the flip times".into(),
                needed: format!("{count:.3e} values"),
                limit: format!("the limit of {MAX_FLIPS} flips a run"),
                hint: "take a shorter t_end, or do not ask for the flips",
            });
        }
        let two_k = 2.0 * motion.jacobi.quarter_period();
        let to_time = motion.lambda * motion.time_scale;
        // counted from the period above, allocated fallibly: never an abort
        let times = (0..count as u64).map(|i| {
            let j = first + i as f64;
            if motion.separatrix {
                -motion.u0 / to_time
            } else {
                two_k.mul_add(j, -motion.u0) / to_time
            }
        });
        crate::buffer::try_collect(
            times,
            count as usize,
            "the flip times",
            "take a shorter t_end, or do not ask for the flips (`flips=False`)",
        )
    }

    /// The elliptic parameter and its complement `(m, 1 − m)` of an asymmetric top's motion;
    /// `None` for steady rotation and symmetric tops.
    pub fn parameter(&self) -> Option<(f64, f64)> {
        match &self.kind {
            Kind::Asymmetric(motion) => Some((motion.jacobi.m(), motion.jacobi.m1())),
            _ => None,
        }
    }

    /// `λ`, the rate of the elliptic argument `u = λ t + u0`; `None` for steady rotation and
    /// symmetric tops.
    pub fn lambda(&self) -> Option<f64> {
        match &self.kind {
            Kind::Asymmetric(motion) => Some(motion.lambda * motion.time_scale),
            _ => None,
        }
    }
}

/// The flip period `2K(m)/λ` of `body` spinning from `omega0`; see
/// [`ExactMotion::flip_period`] for when it is infinite.
///
/// # Errors
/// Non-finite `omega0`; a period that underflows float64 (below 5e-324: rates near the
/// largest float64 on a body of moments far apart).
///
/// # Example
/// ```
/// let body = dzhanibekov::RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
/// let period = dzhanibekov::exact::flip_period(&body, [0.01, 1.0, 0.01]).unwrap();
/// assert!(period > 0.0 && period.is_finite());
/// assert!(dzhanibekov::exact::flip_period(&body, [0.0, 1.0, 0.0]).unwrap().is_infinite());
/// ```
pub fn flip_period(body: &RigidBody, omega0: [f64; 3]) -> Result<f64> {
    let period = ExactMotion::try_new(body, omega0, [1.0, 0.0, 0.0, 0.0])?.flip_period();
    representable_period(period, omega0)
}

/// `period`, unless it underflowed to zero (a flip period is never zero).
///
/// # Errors
/// A zero period, naming the rates.
pub(crate) fn representable_period(period: f64, omega0: [f64; 3]) -> Result<f64> {
    match period > 0.0 {
        true => Ok(period),
        false => Err(Error::invalid(
            "omega0",
            "must give a flip period that float64 holds (at least 5e-324); these rates \
             on this body flip faster",
            omega0,
        )),
    }
}

/// [`flip_period`] from the body rates alone, without the attitude part of the solution
/// (elliptic integrals of the third kind, the frames), at a fraction of the cost: for sweeps,
/// which ask it of every run. The same operations as [`Asymmetric::new`] on the rates, so
/// the same value; `None` where the solution's parameters are not finite (there
/// [`flip_period`] decides, or fails).
pub(crate) fn flip_period_of_rates(body: &RigidBody, omega0: [f64; 3]) -> Option<f64> {
    let omega_body = Vector3::from(omega0);
    if !omega0.iter().all(|w| w.is_finite()) {
        return None;
    }
    if omega_body.iter().filter(|w| **w != 0.0).count() <= 1 || body.intermediate_axis().is_none() {
        return Some(f64::INFINITY);
    }
    let c = Canonical::new(body.inertia_body(), omega_body);
    let j2 = c.j.y;
    let momentum = c.j.component_mul(&c.w).norm();
    if ![c.a.x, c.a.y, c.a.z, c.lambda, momentum]
        .iter()
        .all(|v| v.is_finite())
    {
        return None;
    }
    let threshold = momentum * std::f64::consts::FRAC_1_SQRT_2 / (j2 * c.a.y);
    if c.p_mid == 0.0 || threshold >= 1.0 {
        return Some(f64::INFINITY); // on the separatrix, or never dominant
    }
    let (m, m1) = c.parameter();
    let k = Jacobi::new(m, m1).quarter_period();
    Some(2.0 * k / c.lambda / c.time_scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_period_from_the_rates_is_that_of_the_whole_solution() {
        let bodies = [
            [52.0833, 27.0833, 41.6666],
            [1.0, 2.0, 3.0],
            [3.0, 1.0, 2.5],
            [1.0, 1.0, 2.0],
            [1.0, 40.0, 41.0],
        ];
        let mut finite = 0;
        for (b, inertia) in bodies.iter().enumerate() {
            let body = RigidBody::try_new(*inertia).unwrap();
            for i in 0..400 {
                let f = i as f64;
                let scale = [1e-3, 1.0, 1e5][i % 3];
                let mut omega = [
                    scale * (1.7 * f).sin(),
                    scale * (0.9 * f).cos(),
                    (0.3 * f).sin(),
                ];
                if i % 11 == 0 {
                    omega[i % 3] = 0.0;
                }
                if i % 37 == 0 {
                    omega = [0.0, 0.0, 2.0];
                }
                let full = flip_period(&body, omega).unwrap();
                let fast = flip_period_of_rates(&body, omega).unwrap();
                assert_eq!(fast.to_bits(), full.to_bits(), "body {b}, {omega:?}");
                finite += usize::from(full.is_finite());
            }
        }
        // on the separatrix of the paper's body (z intermediate, v = 0): never a flip period
        let paper = RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
        let on = [
            ((27.0833f64 * 14.5833) / (52.0833 * 10.4167)).sqrt(),
            1.0,
            0.0,
        ];
        assert_eq!(
            flip_period_of_rates(&paper, [on[0], 0.0, 1.0])
                .unwrap()
                .to_bits(),
            flip_period(&paper, [on[0], 0.0, 1.0]).unwrap().to_bits()
        );
        assert!(finite > 300, "{finite}");
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_31_exactly() {
        let (nodes, weights) = gauss_legendre();
        assert_relative_eq!(weights.iter().sum::<f64>(), 2.0, epsilon = 1e-15);
        for degree in [2, 10, 30] {
            let sum: f64 = nodes
                .iter()
                .zip(weights)
                .map(|(x, w)| w * x.powi(degree))
                .sum();
            assert_relative_eq!(sum, 2.0 / (degree as f64 + 1.0), epsilon = 1e-15);
        }
    }
}
