//! A body that carries moving mass: the hub and its parts about the system's mass centre,
//! which moves in the body as the parts move (Hughes, *Spacecraft Attitude Dynamics*, 1986,
//! ch. 5 and 8; Kane & Levinson, *Spacecraft Dynamics*, 1983).
//!
//! **Kinetic energy.** The hub has its tensor `I_h` about its own mass centre `O` (the origin
//! of the body axes) and mass `M_h`; each part carries a mass element `e` of mass `m_e`, its
//! centre at `r_e` from `O` (body axes), its tensor `I_e` about that centre (zero for a point).
//! Its velocity relative to the hub is `ṙ_e = Σ_j R_ej v_j` and its angular velocity relative
//! to the hub `ν_e = Σ_j G_ej v_j`, linear in the part's rates `v` (the columns `R_ej`, `G_ej`
//! are [`Carried::linear`] and [`Carried::angular`]). With no external force the total linear
//! momentum stays zero in the frame of the mass centre, so `O` moves at `v_O = −P/M`,
//! `P = Σ m_e (ω × r_e + ṙ_e)`, `M = M_h + Σ m_e`, and the kinetic energy is
//!
//! ```text
//! T = ½ ωᵀ I_h ω + Σ_e [½ m_e |ω × r_e + ṙ_e|² + ½ (ω + ν_e)ᵀ I_e (ω + ν_e)] − |P|² / (2M)
//!   = ½ [ω; v]ᵀ 𝕄 [ω; v]
//! ```
//!
//! with the mass matrix (`c = Σ m_e r_e`, `[a×]` the cross-product matrix, `a × R` column by
//! column)
//!
//! ```text
//! 𝕄_ωω = I_h + Σ_e [m_e (|r_e|² 𝟙 − r_e r_eᵀ) + I_e] − (|c|² 𝟙 − c cᵀ) / M
//! 𝕄_ωv = m_e (r_e − c/M) × R_e + I_e G_e                       (the part's columns)
//! 𝕄_vv = δ_ef (m_e R_eᵀ R_e + G_eᵀ I_e G_e) − m_e m_f R_eᵀ R_f / M
//! ```
//!
//! `𝕄_ωω` at rest is the composite body's tensor about the system's mass centre (the
//! parallel-axis theorem); the last terms of each block are the mass centre's motion.
//!
//! **Momenta.** The state holds the conjugate momenta `H = ∂T/∂ω` (the total angular momentum
//! about the mass centre, body axes) and `p = ∂T/∂v`, so that `[H; p] = 𝕄 [ω; v]`: the rates
//! come from one solve of the symmetric positive definite `𝕄` ([`MassMatrix::solve`], a
//! Cholesky factorisation of size `3 + Σ rates`), and the equations are Lagrange's
//! (Euler–Poincaré for the attitude and for a pendulum's direction): `H' = H × ω` (no external
//! torque), `p' = ∂T/∂θ − ∂V/∂θ − ∂R/∂v` for each part's coordinates `θ`, with its spring's
//! potential `V` and its Rayleigh dissipation `R`. `∂T/∂θ` at fixed rates needs only each
//! element's velocity in the frame of the mass centre, `u_e − P/M` ([`Motion`]): for a
//! coordinate moving `r_e` by `∂r_e/∂θ` and `ṙ_e` by `∂ṙ_e/∂θ`,
//! `∂T/∂θ = m_e (u_e − P/M) · (ω × ∂r_e/∂θ + ∂ṙ_e/∂θ) + (rotational terms)`.
//!
//! **Invariants.** `H' = H × ω` keeps `|H|` and `H` in space; `T + V` falls at exactly the
//! dissipated power `Σ v ∂R/∂v = Σ c v²`, so `T + V + W` with `W` the work the dampers took is
//! kept: the energy balance a run's drift reports. `T = ½ [ω; v] · [H; p]`.

use std::fmt::Debug;

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};

use super::{LoneHinge, LoneSlosh, LoneSpring};

/// A part whose mass moves, alone on its hub, in closed form ([`super::LoneSpring`],
/// [`super::LoneHinge`], [`super::LoneSlosh`]): the body rates and the part's own rates
/// straight from `H` and its state, without the general joint solve.
pub trait Alone: Debug + Send + Sync {
    /// `ω` from `h` and the part's state `x`, with `s ×` the part's state rates written into
    /// `dx` and the power it dissipates.
    fn increment(&self, h: &Vector3<f64>, x: &[f64], s: f64, dx: &mut [f64])
        -> (Vector3<f64>, f64);

    /// `ω` alone.
    fn omega(&self, h: &Vector3<f64>, x: &[f64]) -> Vector3<f64>;

    /// The whole system's kinetic energy `½ (ω · H + v · p)`.
    fn kinetic(&self, h: &Vector3<f64>, x: &[f64]) -> f64;
}

/// The closed form a model holds for its one part whose mass moves: an enum, not a trait
/// object, so that the right-hand side inlines it (an indirect call each stage kept it out of
/// line and wrote its rates through memory).
#[derive(Debug, Clone, PartialEq)]
pub enum AloneSolve {
    Spring(LoneSpring),
    Hinge(Box<LoneHinge>),
    Slosh(LoneSlosh),
}

/// `$e` with `$l` the closed form in each arm of `$a`.
macro_rules! each_alone {
    ($a:expr, $l:ident => $e:expr) => {
        match $a {
            AloneSolve::Spring($l) => $e,
            AloneSolve::Hinge($l) => $e,
            AloneSolve::Slosh($l) => $e,
        }
    };
}

impl Alone for AloneSolve {
    #[inline(always)]
    fn increment(
        &self,
        h: &Vector3<f64>,
        x: &[f64],
        s: f64,
        dx: &mut [f64],
    ) -> (Vector3<f64>, f64) {
        each_alone!(self, l => l.increment(h, x, s, dx))
    }

    #[inline(always)]
    fn omega(&self, h: &Vector3<f64>, x: &[f64]) -> Vector3<f64> {
        each_alone!(self, l => l.omega(h, x))
    }

    fn kinetic(&self, h: &Vector3<f64>, x: &[f64]) -> f64 {
        each_alone!(self, l => l.kinetic(h, x))
    }
}

/// The most rates one part may have.
pub const PART_RATES: usize = 3;

/// The hub: the body the parts move in, its tensor about its own mass centre (body axes) and
/// its mass, with the system's total mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hub {
    pub inertia: Matrix3<f64>,
    mass: f64,
    /// `1 / M`, `M` the hub's and every part's mass.
    inv_total: f64,
}

impl Hub {
    /// A hub of tensor `inertia` and mass `mass` carrying parts of total mass `carried`.
    ///
    /// # Errors
    /// A mass that is not positive and finite, a carried mass that is negative or not finite.
    pub fn try_new(inertia: Matrix3<f64>, mass: f64, carried: f64) -> Result<Self> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(Error::invalid(
                "mass",
                "of a body that carries moving parts must be positive and finite",
                mass,
            ));
        }
        if !(carried.is_finite() && carried >= 0.0) {
            return Err(Error::invalid(
                "parts' mass",
                "must be non-negative and finite",
                carried,
            ));
        }
        Ok(Self {
            inertia,
            mass,
            inv_total: 1.0 / (mass + carried),
        })
    }

    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }

    /// The same hub with tensor `inertia` (a deployment's at some time).
    #[inline(always)]
    pub fn with_inertia(self, inertia: Matrix3<f64>) -> Self {
        Self { inertia, ..self }
    }

    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The total mass `M`.
    pub fn total_mass(&self) -> f64 {
        1.0 / self.inv_total
    }

    /// `μ = m M_h / M` of the one part of mass `m` it carries: alone on the hub, a part moves
    /// the system as a body of mass `μ` moving about the hub's mass centre would (the
    /// two-body problem's reduced mass).
    pub fn reduced_mass(&self, m: f64) -> f64 {
        debug_assert!(
            ((self.mass + m) * self.inv_total - 1.0).abs() < 1e-12,
            "one part"
        );
        m * self.mass * self.inv_total
    }
}

/// What a moving part carries at one configuration, as the kinetic energy sees it: a mass
/// element, its centre, its own tensor, and how its rates move it (see the module doc).
/// `Default` is nothing: no mass, no rates.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Carried {
    /// `m_e`.
    pub mass: f64,
    /// `r_e`, from the hub's mass centre, body axes.
    pub centre: Vector3<f64>,
    /// `I_e` about the element's own centre, body axes; `None` for a point mass.
    pub inertia: Option<Matrix3<f64>>,
    /// How many rates the part has (at most [`PART_RATES`]).
    pub rates: usize,
    /// `R_ej = ∂ṙ_e/∂v_j`.
    pub linear: [Vector3<f64>; PART_RATES],
    /// `G_ej = ∂ν_e/∂v_j` (read only with an `inertia`).
    pub angular: [Vector3<f64>; PART_RATES],
}

impl Carried {
    /// A point mass `mass` at `centre` moved by the rate columns `linear` (`rates` of them).
    pub fn point(mass: f64, centre: Vector3<f64>, linear: &[Vector3<f64>]) -> Self {
        let mut columns = [Vector3::zeros(); PART_RATES];
        columns[..linear.len()].copy_from_slice(linear);
        Self {
            mass,
            centre,
            inertia: None,
            rates: linear.len(),
            linear: columns,
            angular: [Vector3::zeros(); PART_RATES],
        }
    }

    /// The same element with its own tensor `inertia` (body axes, about its centre), turned
    /// relative to the hub by the rate columns `angular`.
    pub fn with_inertia(mut self, inertia: Matrix3<f64>, angular: &[Vector3<f64>]) -> Self {
        self.inertia = Some(inertia);
        self.angular[..angular.len()].copy_from_slice(angular);
        self
    }
}

/// The most rates all the parts of one body may have together: the capacity `K` of the
/// general model's joint solve. It is compiled for this one capacity (a part alone on its hub
/// takes its closed form instead, see [`Alone`]); the solve's loops run over the rates there
/// are, `K` only sizes its buffers.
pub const MAX_RATES: usize = 8;

/// The rates of the hub and its parts, with what the parts' equations read of them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion<const K: usize> {
    /// `ω`, body axes.
    pub omega: Vector3<f64>,
    /// `v`: each part's rates in order.
    pub rates: [f64; K],
    /// `P/M`: the hub's velocity is `−P/M`; an element's in the frame of the mass centre is
    /// `u_e − P/M`.
    pub drift: Vector3<f64>,
}

impl<const K: usize> Motion<K> {
    /// The velocity of `part`'s element (its rates at `offset` in [`Motion::rates`]) in the
    /// frame of the system's mass centre, `ω × r_e + ṙ_e − P/M`, and its angular velocity
    /// `ω + ν_e`.
    #[inline(always)]
    pub fn element(&self, part: &Carried, offset: usize) -> (Vector3<f64>, Vector3<f64>) {
        let mut v = self.omega.cross(&part.centre) - self.drift;
        let mut spin = self.omega;
        for j in 0..part.rates {
            v += part.linear[j] * self.rates[offset + j];
            spin += part.angular[j] * self.rates[offset + j];
        }
        (v, spin)
    }
}

/// The mass matrix `𝕄` of a hub and its parts (see the module doc) in blocks: the body's
/// `𝕄_ωω`, the coupling columns `𝕄_ωv` and the parts' `𝕄_vv` (its lower triangle read), for at
/// most `K` rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassMatrix<const K: usize> {
    body: Matrix3<f64>,
    coupling: [Vector3<f64>; K],
    parts: [[f64; K]; K],
    k: usize,
}

/// The number of rates `Σ rates` of `parts`, if at most [`MAX_RATES`].
///
/// # Errors
/// More rates than that.
pub fn check_capacity(parts: &[Carried]) -> Result<usize> {
    let k = parts.iter().map(|p| p.rates).sum::<usize>();
    match k <= MAX_RATES && parts.iter().all(|p| p.rates <= PART_RATES) {
        true => Ok(k),
        false => Err(Error::invalid(
            "parts",
            format!("must have at most {MAX_RATES} degrees of freedom in all"),
            k,
        )),
    }
}

/// `|a|² 𝟙 − a aᵀ` scaled by `s`: the tensor of a point mass `s` at `a`.
#[inline(always)]
fn point_tensor(a: &Vector3<f64>, s: f64) -> Matrix3<f64> {
    let sq = a.norm_squared();
    Matrix3::new(
        sq - a.x * a.x,
        -a.x * a.y,
        -a.x * a.z,
        -a.y * a.x,
        sq - a.y * a.y,
        -a.y * a.z,
        -a.z * a.x,
        -a.z * a.y,
        sq - a.z * a.z,
    ) * s
}

impl<const K: usize> MassMatrix<K> {
    /// `𝕄` of `hub` carrying `parts` (their rates in order).
    ///
    /// The caller has checked the capacity ([`check_capacity`]) once, when it built the parts.
    #[inline]
    pub fn assemble(hub: &Hub, parts: &[Carried]) -> Self {
        let first = parts
            .iter()
            .fold(Vector3::zeros(), |c, p| c + p.centre * p.mass);
        let drift = first * hub.inv_total;
        // the body block: I_h, each element's parallel-axis term and own tensor, less the
        // mass centre's
        let mut body = hub.inertia - point_tensor(&first, hub.inv_total);
        let mut coupling = [Vector3::zeros(); K];
        let mut block = [[0.0; K]; K];
        let mut row = 0;
        for (e, p) in parts.iter().enumerate() {
            body += point_tensor(&p.centre, p.mass);
            if let Some(i) = p.inertia {
                body += i;
            }
            let arm = p.centre - drift;
            let own = p.mass - p.mass * p.mass * hub.inv_total;
            for a in 0..p.rates {
                let r = row + a;
                let mut b = arm.cross(&p.linear[a]) * p.mass;
                if let Some(i) = p.inertia {
                    b += i * p.angular[a];
                }
                coupling[r] = b;
                // with the earlier parts' rates: the mass centre's motion alone
                let mut col = 0;
                for q in &parts[..e] {
                    let s = -p.mass * q.mass * hub.inv_total;
                    for k in 0..q.rates {
                        block[r][col + k] = s * p.linear[a].dot(&q.linear[k]);
                    }
                    col += q.rates;
                }
                // with its own rates
                for k in 0..=a {
                    let mut v = own * p.linear[a].dot(&p.linear[k]);
                    if let Some(i) = p.inertia {
                        v += p.angular[a].dot(&(i * p.angular[k]));
                    }
                    block[r][row + k] = v;
                }
            }
            row += p.rates;
        }
        Self {
            body,
            coupling,
            parts: block,
            k: row,
        }
    }

    /// The number of the parts' rates.
    pub fn rates(&self) -> usize {
        self.k
    }

    /// `𝕄 [ω; v]`: `(𝕄_ωω ω + 𝕄_ωv v, 𝕄_vω ω + 𝕄_vv v)`.
    pub fn apply(&self, omega: &Vector3<f64>, v: &[f64; K]) -> (Vector3<f64>, [f64; K]) {
        let mut h = self.body * omega;
        let mut p = [0.0; K];
        for r in 0..self.k {
            h += self.coupling[r] * v[r];
            p[r] = self.coupling[r].dot(omega)
                + (0..self.k)
                    .map(|c| self.parts[r.max(c)][r.min(c)] * v[c])
                    .sum::<f64>();
        }
        (h, p)
    }

    /// `[ω; v]` with `𝕄 [ω; v] = [h; p]`. The parts' block first, `𝕄_vv = L D Lᵀ` with each
    /// pivot's reciprocal taken once, then the body's Schur complement
    /// `S = 𝕄_ωω − 𝕄_ωv 𝕄_vv⁻¹ 𝕄_vω` (symmetric 3 × 3) by Cramer's rule, then the parts' rates:
    /// one division a pivot and one for the body, none of them square roots. `𝕄` is positive
    /// definite for positive masses and positive semi-definite tensors (a kinetic energy that
    /// vanishes only at rest), so every pivot and `det S` are positive.
    #[inline]
    pub fn solve(&self, h: &Vector3<f64>, p: &[f64; K]) -> (Vector3<f64>, [f64; K]) {
        let k = self.k;
        let mut l = self.parts;
        let mut inv = [0.0; K];
        for j in 0..k {
            // l[j][m] holds L_jm d_m for m < j until row j is done
            let mut d = l[j][j];
            for m in 0..j {
                d -= l[j][m] * l[j][m] * inv[m];
            }
            inv[j] = 1.0 / d;
            for i in j + 1..k {
                let mut s = l[i][j];
                for m in 0..j {
                    s -= l[i][m] * l[j][m] * inv[m];
                }
                l[i][j] = s;
            }
            for m in 0..j {
                l[j][m] *= inv[m];
            }
        }
        // Y = 𝕄_vv⁻¹ 𝕄_vω (a vector a row) and z = 𝕄_vv⁻¹ p, by L, D, Lᵀ
        let mut y = self.coupling;
        let mut z = *p;
        for i in 0..k {
            for m in 0..i {
                let lim = l[i][m];
                y[i] -= y[m] * lim;
                z[i] -= z[m] * lim;
            }
        }
        for i in 0..k {
            y[i] *= inv[i];
            z[i] *= inv[i];
        }
        for i in (0..k).rev() {
            for m in i + 1..k {
                let lmi = l[m][i];
                y[i] -= y[m] * lmi;
                z[i] -= z[m] * lmi;
            }
        }
        let mut s = self.body;
        let mut r = *h;
        for i in 0..k {
            s -= self.coupling[i] * y[i].transpose();
            r -= self.coupling[i] * z[i];
        }
        let omega = cramer(&s, &r);
        let mut v = z;
        for i in 0..k {
            v[i] -= y[i].dot(&omega);
        }
        (omega, v)
    }
}

/// `x` with `s x = r` for a symmetric positive definite `s`, by Cramer's rule.
#[inline(always)]
fn cramer(s: &Matrix3<f64>, r: &Vector3<f64>) -> Vector3<f64> {
    Sym3::of(s).solve(r)
}

/// A symmetric 3 × 3 matrix by its six entries: the closed-form solves of one part alone on
/// its hub ([`super::LoneSpring`], [`super::LoneHinge`]) sum constant ones weighted by the
/// part's coordinate and invert the sum, so that nothing is computed twice.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sym3 {
    pub xx: f64,
    pub yy: f64,
    pub zz: f64,
    pub xy: f64,
    pub yz: f64,
    pub xz: f64,
}

impl Sym3 {
    /// The symmetric part of `m`.
    pub fn of(m: &Matrix3<f64>) -> Self {
        Self {
            xx: m[(0, 0)],
            yy: m[(1, 1)],
            zz: m[(2, 2)],
            xy: 0.5 * (m[(0, 1)] + m[(1, 0)]),
            yz: 0.5 * (m[(1, 2)] + m[(2, 1)]),
            xz: 0.5 * (m[(0, 2)] + m[(2, 0)]),
        }
    }

    /// `s 𝟙`.
    pub fn scalar(s: f64) -> Self {
        Self {
            xx: s,
            yy: s,
            zz: s,
            ..Self::default()
        }
    }

    /// `a bᵀ + b aᵀ`.
    pub fn outer(a: &Vector3<f64>, b: &Vector3<f64>) -> Self {
        Self {
            xx: 2.0 * a.x * b.x,
            yy: 2.0 * a.y * b.y,
            zz: 2.0 * a.z * b.z,
            xy: a.x * b.y + b.x * a.y,
            yz: a.y * b.z + b.y * a.z,
            xz: a.x * b.z + b.x * a.z,
        }
    }

    /// `a aᵀ`.
    pub fn square(a: &Vector3<f64>) -> Self {
        Self::outer(a, a) * 0.5
    }

    pub fn matrix(&self) -> Matrix3<f64> {
        Matrix3::new(
            self.xx, self.xy, self.xz, self.xy, self.yy, self.yz, self.xz, self.yz, self.zz,
        )
    }

    /// `self + s b`, entry by entry (no `mul_add`: without FMA in the target it is a call).
    #[inline(always)]
    pub fn add_scaled(&self, s: f64, b: &Sym3) -> Self {
        Self {
            xx: self.xx + s * b.xx,
            yy: self.yy + s * b.yy,
            zz: self.zz + s * b.zz,
            xy: self.xy + s * b.xy,
            yz: self.yz + s * b.yz,
            xz: self.xz + s * b.xz,
        }
    }

    /// `self v`.
    #[inline(always)]
    pub fn apply(&self, v: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.xx * v.x + self.xy * v.y + self.xz * v.z,
            self.xy * v.x + self.yy * v.y + self.yz * v.z,
            self.xz * v.x + self.yz * v.y + self.zz * v.z,
        )
    }

    /// `x` with `self x = r`, `self` positive definite, by Cramer's rule (its adjugate over its
    /// determinant: one division, no square root).
    #[inline(always)]
    pub fn solve(&self, r: &Vector3<f64>) -> Vector3<f64> {
        let (adjugate, inv) = self.solve_parts(r);
        adjugate * inv
    }

    /// [`Sym3::solve`] before its one division: `adj(self) r` and `1 / det(self)`, whose
    /// product it is. A dot product of the solution, `w · x = (w · adj r) / det`, is then
    /// formed while the division runs, not after it.
    #[inline(always)]
    pub fn solve_parts(&self, r: &Vector3<f64>) -> (Vector3<f64>, f64) {
        let (a, b, c) = (self.xx, self.yy, self.zz);
        let (d, e, f) = (self.xy, self.yz, self.xz);
        let c00 = b * c - e * e;
        let c01 = f * e - d * c;
        let c02 = d * e - b * f;
        let c11 = a * c - f * f;
        let c12 = d * f - a * e;
        let c22 = a * b - d * d;
        let inv = 1.0 / (a * c00 + d * c01 + f * c02);
        let adjugate = Vector3::new(
            c00 * r.x + c01 * r.y + c02 * r.z,
            c01 * r.x + c11 * r.y + c12 * r.z,
            c02 * r.x + c12 * r.y + c22 * r.z,
        );
        (adjugate, inv)
    }

    /// `self⁻¹` (positive definite).
    pub fn inverse(&self) -> Self {
        let cols = [Vector3::x(), Vector3::y(), Vector3::z()].map(|e| self.solve(&e));
        Self {
            xx: cols[0].x,
            yy: cols[1].y,
            zz: cols[2].z,
            xy: 0.5 * (cols[1].x + cols[0].y),
            yz: 0.5 * (cols[2].y + cols[1].z),
            xz: 0.5 * (cols[2].x + cols[0].z),
        }
    }
}

impl std::ops::Add for Sym3 {
    type Output = Sym3;
    fn add(self, b: Sym3) -> Sym3 {
        self.add_scaled(1.0, &b)
    }
}

impl std::ops::Sub for Sym3 {
    type Output = Sym3;
    fn sub(self, b: Sym3) -> Sym3 {
        self.add_scaled(-1.0, &b)
    }
}

impl std::ops::Mul<f64> for Sym3 {
    type Output = Sym3;
    fn mul(self, s: f64) -> Sym3 {
        Sym3::default().add_scaled(s, &self)
    }
}

/// The rates `ω` and `v` from the momenta `h` and `p` (each part's in order), and the mass
/// centre's drift `P/M` the parts' equations read.
#[inline]
pub fn motion<const K: usize>(
    hub: &Hub,
    parts: &[Carried],
    h: &Vector3<f64>,
    p: &[f64; K],
) -> Motion<K> {
    let (omega, rates) = MassMatrix::<K>::assemble(hub, parts).solve(h, p);
    let mut first = Vector3::zeros();
    let mut offset = 0;
    for part in parts {
        let mut u = omega.cross(&part.centre);
        for j in 0..part.rates {
            u += part.linear[j] * rates[offset + j];
        }
        first += u * part.mass;
        offset += part.rates;
    }
    Motion {
        omega,
        rates,
        drift: first * hub.inv_total,
    }
}

/// The kinetic energy `½ (ω · H + v · p)` of rates `omega`, `v` and momenta `h`, `p` (`k`
/// parts' rates).
pub fn kinetic_energy<const K: usize>(
    omega: &Vector3<f64>,
    v: &[f64; K],
    h: &Vector3<f64>,
    p: &[f64; K],
    k: usize,
) -> f64 {
    0.5 * (omega.dot(h) + (0..k).map(|j| v[j] * p[j]).sum::<f64>())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The kinetic energy summed body by body in the frame of the mass centre, from the hub's
    /// velocity `−P/M` (no mass matrix): what `𝕄` must reproduce.
    pub(crate) fn direct_energy(
        hub: &Hub,
        parts: &[Carried],
        omega: Vector3<f64>,
        v: &[f64],
    ) -> f64 {
        let mut u = Vec::new();
        let mut spins = Vec::new();
        let mut at = 0;
        for p in parts {
            let mut ui = omega.cross(&p.centre);
            let mut si = omega;
            for j in 0..p.rates {
                ui += p.linear[j] * v[at + j];
                si += p.angular[j] * v[at + j];
            }
            u.push(ui);
            spins.push(si);
            at += p.rates;
        }
        let momentum: Vector3<f64> = parts.iter().zip(&u).map(|(p, ui)| ui * p.mass).sum();
        let v_hub = -momentum * hub.inv_total;
        let mut t = 0.5 * omega.dot(&(hub.inertia * omega)) + 0.5 * hub.mass * v_hub.norm_squared();
        for ((p, ui), si) in parts.iter().zip(&u).zip(&spins) {
            t += 0.5 * p.mass * (v_hub + ui).norm_squared();
            if let Some(i) = p.inertia {
                t += 0.5 * si.dot(&(i * si));
            }
        }
        t
    }

    pub(crate) fn hub() -> Hub {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        Hub::try_new(i, 5.0, 0.3 + 0.2 + 0.4).unwrap()
    }

    /// A point on one rate, a panel on one, a point on two.
    pub(crate) fn parts() -> Vec<Carried> {
        let panel = Matrix3::new(0.02, 0.003, 0.0, 0.003, 0.05, -0.001, 0.0, -0.001, 0.04);
        vec![
            Carried::point(
                0.3,
                Vector3::new(0.5, -0.2, 0.7),
                &[Vector3::new(0.0, 0.6, 0.8)],
            ),
            Carried::point(
                0.2,
                Vector3::new(-0.9, 0.4, 0.1),
                &[Vector3::new(0.1, 0.3, -0.2)],
            )
            .with_inertia(panel, &[Vector3::new(0.0, 0.0, 1.0)]),
            Carried::point(
                0.4,
                Vector3::new(0.2, 0.8, -0.5),
                &[Vector3::new(0.4, 0.0, 0.3), Vector3::new(-0.1, 0.5, 0.0)],
            ),
        ]
    }

    const OMEGA: [f64; 3] = [0.3, -0.7, 1.1];
    const RATES: [f64; 4] = [0.25, -0.4, 0.15, 0.6];

    fn rates(scale: f64) -> (Vector3<f64>, [f64; MAX_RATES]) {
        let mut v = [0.0; MAX_RATES];
        for (k, r) in RATES.iter().enumerate() {
            v[k] = r * scale;
        }
        (Vector3::from(OMEGA) * scale, v)
    }

    #[test]
    fn the_mass_matrix_is_the_hessian_of_the_direct_energy() {
        let (hub, parts) = (hub(), parts());
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &parts);
        assert_eq!(m.rates(), 4);
        // ½ xᵀ 𝕄 x against the body-by-body sum at several rates: 𝕄 is the Hessian
        for scale in [1.0, -0.3, 2.5] {
            let (omega, v) = rates(scale);
            let direct = direct_energy(&hub, &parts, omega, &v[..4]);
            let (h, p) = m.apply(&omega, &v);
            assert_relative_eq!(
                kinetic_energy(&omega, &v, &h, &p, 4),
                direct,
                max_relative = 1e-14
            );
        }
    }

    #[test]
    fn the_solve_inverts_the_mass_matrix() {
        let (hub, parts) = (hub(), parts());
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &parts);
        let (omega, v) = rates(1.0);
        let (h, p) = m.apply(&omega, &v);
        let (back, rates) = m.solve(&h, &p);
        assert!((back - omega).amax() < 1e-14, "{back}");
        for k in 0..4 {
            assert!((rates[k] - v[k]).abs() < 1e-14, "{rates:?}");
        }
        let moved = motion(&hub, &parts, &h, &p);
        assert_eq!(moved.omega, back);
        // one part alone, and a hub with none: the Schur complement is then 𝕄_ωω
        let one = MassMatrix::<MAX_RATES>::assemble(&hub, &parts[1..2]);
        let (h1, p1) = one.apply(&omega, &v);
        let (w1, v1) = one.solve(&h1, &p1);
        assert!((w1 - omega).amax() < 1e-14 && (v1[0] - v[0]).abs() < 1e-14);
        // the capacity is only room: one part in a buffer of 1 solves as in one of 8
        let tight = MassMatrix::<1>::assemble(&hub, &parts[1..2]);
        let (ht, pt) = tight.apply(&omega, &[v[0]]);
        assert_eq!((ht, pt[0]), (h1, p1[0]));
        let (wt, vt) = tight.solve(&ht, &pt);
        assert!((wt - w1).amax() < 1e-15 && (vt[0] - v1[0]).abs() < 1e-15);
        let none = MassMatrix::<MAX_RATES>::assemble(&hub, &[]);
        let (w0, _) = none.solve(&(hub.inertia * omega), &[0.0; MAX_RATES]);
        assert!((w0 - omega).amax() < 1e-14);
    }

    #[test]
    fn at_rest_the_body_block_is_the_composite_tensor_about_the_mass_centre() {
        let (hub, parts) = (hub(), parts());
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &parts);
        // Huygens–Steiner about the system's mass centre, each body at its own offset
        let total = hub.mass() + parts.iter().map(|p| p.mass).sum::<f64>();
        let centre = parts
            .iter()
            .map(|p| p.centre * p.mass)
            .sum::<Vector3<f64>>()
            / total;
        let mut composite = hub.inertia + point_tensor(&(-centre), hub.mass());
        for p in &parts {
            composite += point_tensor(&(p.centre - centre), p.mass) + p.inertia.unwrap_or_default();
        }
        assert!(
            (m.body - composite).amax() < 1e-15,
            "{}",
            m.body - composite
        );
    }

    #[test]
    fn the_momenta_are_the_angular_momentum_about_the_mass_centre() {
        // H = Σ (r_k − r_cm) × m_k v_k + Σ I_k Ω_k in the frame of the mass centre
        let (hub, parts) = (hub(), parts());
        let m = MassMatrix::<MAX_RATES>::assemble(&hub, &parts);
        let (omega, v) = rates(1.0);
        let (h, p) = m.apply(&omega, &v);
        let moved = motion(&hub, &parts, &h, &p);
        let total = hub.total_mass();
        let centre = parts
            .iter()
            .map(|p| p.centre * p.mass)
            .sum::<Vector3<f64>>()
            / total;
        let mut l = hub.inertia * omega + (-centre).cross(&(-moved.drift)) * hub.mass();
        let mut at = 0;
        let mut linear = -moved.drift * hub.mass();
        for p in &parts {
            let (v, spin) = moved.element(p, at);
            l += (p.centre - centre).cross(&v) * p.mass;
            if let Some(i) = p.inertia {
                l += i * spin;
            }
            linear += v * p.mass;
            at += p.rates;
        }
        assert!((h - l).amax() < 1e-14, "{h} {l}");
        // and the linear momentum in that frame is zero
        assert!(linear.amax() < 1e-15, "{linear}");
    }

    #[test]
    fn too_many_rates_are_refused() {
        let parts = parts();
        assert_eq!(check_capacity(&parts), Ok(4));
        let many: Vec<Carried> = parts.iter().cycle().take(7).copied().collect();
        assert!(check_capacity(&many).is_err());
        assert!(Hub::try_new(Matrix3::identity(), 0.0, 1.0).is_err());
        assert!(Hub::try_new(Matrix3::identity(), 1.0, f64::NAN).is_err());
    }
}

/// The three parts on one hub, integrated as a whole: what the seam's model will do, written
/// here plainly (`Vec` state, no capacity tricks) to check the equations — the energy falls
/// at exactly the dissipated power, the conjugate momenta are those of the directly summed
/// energy, and `∂T/∂θ` of each part is the derivative of that energy.
#[cfg(test)]
mod assembled {
    use super::fixtures::{panel, spring, tank};
    use super::tests::direct_energy;
    use super::*;
    use crate::dynamics::{Hinge, Rod, Slosh, SpringMass};
    use crate::kinematics::rotation_matrix;
    use nalgebra::Quaternion;

    #[derive(Clone, Copy)]
    enum Moving {
        Spring(SpringMass),
        Hinge(Hinge),
        Slosh(Slosh),
    }

    impl Moving {
        fn width(&self) -> usize {
            match self {
                Moving::Spring(_) | Moving::Hinge(_) => 2,
                Moving::Slosh(_) => 6,
            }
        }

        fn carried(&self, s: &[f64]) -> Carried {
            match self {
                Moving::Spring(p) => p.carried(s[0]),
                Moving::Hinge(p) => p.carried(&p.pose(s[0])),
                Moving::Slosh(p) => p.carried(&Rod::along(&Vector3::new(s[0], s[1], s[2]))),
            }
        }

        fn momenta(&self, s: &[f64]) -> Vec<f64> {
            match self {
                Moving::Spring(_) | Moving::Hinge(_) => vec![s[1]],
                Moving::Slosh(p) => {
                    let rod = Rod::along(&Vector3::new(s[0], s[1], s[2]));
                    p.momenta(&rod, &Vector3::new(s[3], s[4], s[5])).to_vec()
                }
            }
        }
    }

    struct Assembly {
        hub: Hub,
        parts: Vec<Moving>,
    }

    impl Assembly {
        fn new(parts: Vec<Moving>) -> Self {
            let carried: f64 = parts
                .iter()
                .map(|p| match p {
                    Moving::Spring(s) => s.mass(),
                    Moving::Hinge(h) => h.mass(),
                    Moving::Slosh(s) => s.mass(),
                })
                .sum();
            let i = Matrix3::new(3.0, -0.2, 0.1, -0.2, 4.0, 0.3, 0.1, 0.3, 5.0);
            Self {
                hub: Hub::try_new(i, 4.0, carried).unwrap(),
                parts,
            }
        }

        /// Each part's state slice and what it carries.
        fn carried(&self, x: &[f64]) -> Vec<Carried> {
            let mut at = 3;
            self.parts
                .iter()
                .map(|p| {
                    let c = p.carried(&x[at..at + p.width()]);
                    at += p.width();
                    c
                })
                .collect()
        }

        fn motion(
            &self,
            x: &[f64],
        ) -> (
            Motion<MAX_RATES>,
            Vec<Carried>,
            Vector3<f64>,
            [f64; MAX_RATES],
        ) {
            let carried = self.carried(x);
            let h = Vector3::new(x[0], x[1], x[2]);
            let mut momenta = [0.0; MAX_RATES];
            let (mut at, mut row) = (3, 0);
            for p in &self.parts {
                for m in p.momenta(&x[at..at + p.width()]) {
                    momenta[row] = m;
                    row += 1;
                }
                at += p.width();
            }
            check_capacity(&carried).unwrap();
            (
                motion(&self.hub, &carried, &h, &momenta),
                carried,
                h,
                momenta,
            )
        }

        /// `x' = f(x)`, `x = [H, parts, q]`.
        fn rhs(&self, x: &[f64]) -> Vec<f64> {
            let (motion, carried, h, _) = self.motion(x);
            let omega = motion.omega;
            let mut dx = vec![0.0; x.len()];
            dx[..3].copy_from_slice(h.cross(&omega).as_slice());
            let (mut at, mut row) = (3, 0);
            for (p, c) in self.parts.iter().zip(&carried) {
                let s = &x[at..at + p.width()];
                let (velocity, spin) = motion.element(c, row);
                match p {
                    Moving::Spring(m) => {
                        let v = motion.rates[row];
                        dx[at] = v;
                        dx[at + 1] = m.momentum_rate(s[0], v, &omega, &velocity);
                    }
                    Moving::Hinge(m) => {
                        let v = motion.rates[row];
                        dx[at] = v;
                        dx[at + 1] =
                            m.momentum_rate(&m.pose(s[0]), s[0], v, &omega, &velocity, &spin);
                    }
                    Moving::Slosh(m) => {
                        let n = Vector3::new(s[0], s[1], s[2]);
                        let rod = Rod::along(&n);
                        let nu = rod.spin([motion.rates[row], motion.rates[row + 1]]);
                        let pi = Vector3::new(s[3], s[4], s[5]);
                        let (dn, dpi) = m.rates(&n, &pi, &rod, &nu, &omega, &velocity);
                        dx[at..at + 3].copy_from_slice(dn.as_slice());
                        dx[at + 3..at + 6].copy_from_slice(dpi.as_slice());
                    }
                }
                at += p.width();
                row += c.rates;
            }
            let n = x.len();
            let q = Quaternion::new(x[n - 4], x[n - 3], x[n - 2], x[n - 1]);
            let dq = q * Quaternion::from_parts(0.0, omega) * 0.5;
            dx[n - 4..].copy_from_slice(&[dq.w, dq.i, dq.j, dq.k]);
            dx
        }

        /// `T + V` and the dissipated power at `x`.
        fn energy(&self, x: &[f64]) -> (f64, f64) {
            let (motion, carried, h, momenta) = self.motion(x);
            let k = carried.iter().map(|c| c.rates).sum::<usize>();
            let mut e = kinetic_energy(&motion.omega, &motion.rates, &h, &momenta, k);
            let mut loss = 0.0;
            let (mut at, mut row) = (3, 0);
            for (p, c) in self.parts.iter().zip(&carried) {
                let s = &x[at..at + p.width()];
                match p {
                    Moving::Spring(m) => {
                        e += m.potential(s[0]);
                        loss += m.dissipation(motion.rates[row]);
                    }
                    Moving::Hinge(m) => {
                        e += m.potential(s[0]);
                        loss += m.dissipation(motion.rates[row]);
                    }
                    Moving::Slosh(m) => {
                        let rod = Rod::along(&Vector3::new(s[0], s[1], s[2]));
                        loss +=
                            m.dissipation(&rod.spin([motion.rates[row], motion.rates[row + 1]]));
                    }
                }
                at += p.width();
                row += c.rates;
            }
            (e, loss)
        }

        /// The state from body rates `omega`, each part's configuration and rates, `q`.
        fn state(&self, omega: [f64; 3], parts: &[(&[f64], &[f64])], q: [f64; 4]) -> Vec<f64> {
            let mut x = vec![0.0; 3];
            let mut rates = Vec::new();
            for (p, (config, rate)) in self.parts.iter().zip(parts) {
                match p {
                    Moving::Spring(_) | Moving::Hinge(_) => {
                        x.extend_from_slice(&[config[0], 0.0]);
                        rates.push(rate[0]);
                    }
                    Moving::Slosh(_) => {
                        let rod = Rod::along(&Vector3::new(config[0], config[1], config[2]));
                        let nu = Vector3::new(rate[0], rate[1], rate[2]);
                        x.extend_from_slice(config);
                        x.extend_from_slice(&[0.0; 3]);
                        rates.extend_from_slice(&rod.rates_of(&nu));
                    }
                }
            }
            x.extend_from_slice(&q);
            let carried = self.carried(&x);
            let mut v = [0.0; MAX_RATES];
            v[..rates.len()].copy_from_slice(&rates);
            let (h, p) = MassMatrix::<MAX_RATES>::assemble(&self.hub, &carried)
                .apply(&Vector3::from(omega), &v);
            x[..3].copy_from_slice(h.as_slice());
            let (mut at, mut row) = (3, 0);
            for (part, c) in self.parts.iter().zip(&carried) {
                match part {
                    Moving::Spring(_) | Moving::Hinge(_) => x[at + 1] = p[row],
                    Moving::Slosh(_) => {
                        let rod = Rod::along(&Vector3::new(x[at], x[at + 1], x[at + 2]));
                        let pi = rod.momentum_of([p[row], p[row + 1]]);
                        x[at + 3..at + 6].copy_from_slice(pi.as_slice());
                    }
                }
                at += part.width();
                row += c.rates;
            }
            x
        }
    }

    fn all() -> (Assembly, Vec<f64>) {
        let a = Assembly::new(vec![
            Moving::Spring(spring()),
            Moving::Hinge(panel()),
            Moving::Slosh(tank()),
            Moving::Hinge(
                Hinge::try_new(
                    0.1,
                    [0.0, 0.02, 0.02],
                    [-0.7, -0.4, 0.1],
                    [0.0, 0.3, 1.0],
                    [-1.0, 0.0, 0.0],
                    0.5,
                    0.0,
                    0.0,
                )
                .unwrap(),
            ),
        ]);
        let n0 = [0.3, -0.8, 0.52];
        let x = a.state(
            [0.3, -0.7, 1.1],
            &[
                (&[0.05], &[0.2]),
                (&[-0.3], &[0.4]),
                (&n0, &[0.1, 0.2, 0.3]),
                (&[0.7], &[-0.5]),
            ],
            [0.6, -0.2, 0.7, 0.3],
        );
        (a, x)
    }

    /// `dE/dt` along the right-hand side, by a central difference.
    fn energy_rate(a: &Assembly, x: &[f64]) -> f64 {
        let dx = a.rhs(x);
        let at = |s: f64| {
            a.energy(
                &x.iter()
                    .zip(&dx)
                    .map(|(v, d)| v + s * d)
                    .collect::<Vec<_>>(),
            )
            .0
        };
        five_point(at, 1e-3)
    }

    /// `f'(0)` by the five-point stencil (error of order `h⁴`).
    fn five_point(f: impl Fn(f64) -> f64, h: f64) -> f64 {
        (f(-2.0 * h) - 8.0 * f(-h) + 8.0 * f(h) - f(2.0 * h)) / (12.0 * h)
    }

    #[test]
    fn the_energy_falls_at_exactly_the_dissipated_power() {
        let (a, x) = all();
        let (_, loss) = a.energy(&x);
        assert!(loss > 0.01, "{loss}");
        let rate = energy_rate(&a, &x);
        assert!((rate + loss).abs() < 1e-8 * loss, "{rate} {loss}");
        // without damping it is kept
        let undamped = Assembly::new(vec![
            Moving::Spring(
                SpringMass::try_new(0.3, [0.4, -0.3, 0.6], [0.2, 0.9, -0.4], 2.0, 0.0).unwrap(),
            ),
            Moving::Slosh(Slosh::try_new(0.35, [-0.5, 0.3, 0.7], 0.45, 0.0).unwrap()),
        ]);
        let x = undamped.state(
            [0.3, -0.7, 1.1],
            &[(&[0.05], &[0.2]), (&[0.3, -0.8, 0.52], &[0.1, 0.2, 0.3])],
            [1.0, 0.0, 0.0, 0.0],
        );
        let rate = energy_rate(&undamped, &x);
        assert!(rate.abs() < 1e-9 * undamped.energy(&x).0, "{rate}");
    }

    #[test]
    fn the_angular_momentum_in_space_is_stationary() {
        let (a, x) = all();
        let dx = a.rhs(&x);
        let h = 1e-3;
        let world = |s: f64| {
            let y: Vec<f64> = x.iter().zip(&dx).map(|(v, d)| v + s * d).collect();
            let n = y.len();
            let q = Quaternion::new(y[n - 4], y[n - 3], y[n - 2], y[n - 1]);
            rotation_matrix(&(q / q.norm())) * Vector3::new(y[0], y[1], y[2])
        };
        let rate =
            (world(-2.0 * h) - world(-h) * 8.0 + world(h) * 8.0 - world(2.0 * h)) / (12.0 * h);
        assert!(rate.amax() < 1e-10, "{rate:?}");
    }

    #[test]
    fn the_rates_are_those_the_state_was_built_from() {
        let (a, x) = all();
        let (motion, _, _, _) = a.motion(&x);
        let omega = motion.omega;
        assert!(
            (omega - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-14,
            "{omega}"
        );
        assert!((motion.rates[0] - 0.2).abs() < 1e-14);
        assert!((motion.rates[1] - 0.4).abs() < 1e-14);
        // the pendulum's ν is the given one's part normal to the rod
        let n = Vector3::new(0.3, -0.8, 0.52).normalize();
        let given = Vector3::new(0.1, 0.2, 0.3);
        let rod = Rod::along(&n);
        let nu = rod.spin([motion.rates[2], motion.rates[3]]);
        assert!((nu - (given - n * n.dot(&given))).amax() < 1e-14, "{nu}");
        assert!((motion.rates[4] + 0.5).abs() < 1e-14);
    }

    /// `∂T/∂θ` at fixed rates: the part's momentum rate plus its spring and damping terms,
    /// against a central difference of the directly summed energy.
    #[test]
    fn each_parts_force_is_the_derivative_of_the_directly_summed_energy() {
        let hub = Assembly::new(vec![]).hub;
        let omega = Vector3::new(0.3, -0.7, 1.1);
        let h = 1e-6;
        // the spring: T(x) with ω and ẋ held
        let s = spring();
        let hub1 = Hub::try_new(*hub.inertia(), hub.mass(), s.mass()).unwrap();
        let (x, v) = (0.07, 0.3);
        let t = |x: f64| direct_energy(&hub1, &[s.carried(x)], omega, &[v]);
        let numeric = (t(x + h) - t(x - h)) / (2.0 * h);
        let parts = [s.carried(x)];
        let mut r = [0.0; MAX_RATES];
        r[0] = v;
        let (hm, pm) = MassMatrix::<MAX_RATES>::assemble(&hub1, &parts).apply(&omega, &r);
        let moved = motion(&hub1, &parts, &hm, &pm);
        let (velocity, _) = moved.element(&parts[0], 0);
        let analytic =
            s.momentum_rate(x, v, &omega, &velocity) + s.stiffness() * x + s.damping() * v;
        assert!((analytic - numeric).abs() < 1e-9, "{analytic} {numeric}");
        // the panel: T(β) with ω and β̇ held
        let p = panel();
        let hub1 = Hub::try_new(*hub.inertia(), hub.mass(), p.mass()).unwrap();
        let (beta, v) = (0.4, -0.6);
        let t = |b: f64| direct_energy(&hub1, &[p.carried(&p.pose(b))], omega, &[v]);
        let numeric = (t(beta + h) - t(beta - h)) / (2.0 * h);
        let parts = [p.carried(&p.pose(beta))];
        r[0] = v;
        let (hm, pm) = MassMatrix::<MAX_RATES>::assemble(&hub1, &parts).apply(&omega, &r);
        let moved = motion(&hub1, &parts, &hm, &pm);
        let (velocity, spin) = moved.element(&parts[0], 0);
        let analytic = p.momentum_rate(&p.pose(beta), beta, v, &omega, &velocity, &spin)
            + p.stiffness() * beta
            + p.damping() * v;
        assert!((analytic - numeric).abs() < 1e-9, "{analytic} {numeric}");
    }

    #[test]
    fn the_pendulums_torque_is_the_derivative_of_the_energy_under_a_turn_of_the_rod() {
        // η · (n × ∂T/∂n) = d/dε T(ω, n turned by ε about η, ν held)
        let hub = Assembly::new(vec![]).hub;
        let s = tank();
        let hub1 = Hub::try_new(*hub.inertia(), hub.mass(), s.mass()).unwrap();
        let omega = Vector3::new(0.3, -0.7, 1.1);
        let n = Vector3::new(0.3, -0.8, 0.52).normalize();
        let nu_full = Vector3::new(0.1, 0.2, 0.3);
        let nu = nu_full - n * n.dot(&nu_full);
        let energy = |n: Vector3<f64>| {
            // ṙ = l ν × n written directly, as a point moved by one rate of column l ν × n
            let c = Carried::point(
                s.mass(),
                s.pivot() + n * s.length(),
                &[nu.cross(&n) * s.length()],
            );
            direct_energy(&hub1, &[c], omega, &[1.0])
        };
        let rod = Rod::along(&n);
        let parts = [s.carried(&rod)];
        let mut r = [0.0; MAX_RATES];
        [r[0], r[1]] = rod.rates_of(&nu);
        let (hm, momenta) = MassMatrix::<MAX_RATES>::assemble(&hub1, &parts).apply(&omega, &r);
        let moved = motion(&hub1, &parts, &hm, &momenta);
        let (velocity, _) = moved.element(&parts[0], 0);
        // the torque with π held normal and ν × π removed: n × ∂T/∂n
        let pi = rod.momentum_of([momenta[0], momenta[1]]);
        let (_, dpi) = s.rates(&n, &pi, &rod, &nu, &omega, &velocity);
        let torque = dpi - nu.cross(&pi) + nu * s.damping();
        for eta in [Vector3::x(), Vector3::y(), Vector3::z(), n] {
            let h = 1e-6;
            let turned = |e: f64| nalgebra::Rotation3::new(eta * e) * n;
            let numeric = (energy(turned(h)) - energy(turned(-h))) / (2.0 * h);
            assert!(
                (eta.dot(&torque) - numeric).abs() < 1e-9,
                "{eta} {torque} {numeric}"
            );
        }
        // and π is ∂T/∂ν: l m n × (u − P/M)
        let expected = n.cross(&velocity) * (s.length() * s.mass());
        assert!((pi - expected).amax() < 1e-14, "{pi} {expected}");
    }

    /// RK4 of the assembly over `steps` steps of `h`, returning the largest drift of
    /// `T + V + W` (W the dissipated work, by the same steps), of `|n|` and of `π · n/|n|`.
    fn rk4_balance(a: &Assembly, x0: &[f64], h: f64, steps: usize) -> (f64, f64, f64) {
        let mut x = x0.to_vec();
        x.push(0.0); // W
        let f = |y: &[f64]| {
            let mut d = a.rhs(&y[..y.len() - 1]);
            d.push(a.energy(&y[..y.len() - 1]).1);
            d
        };
        let e0 = a.energy(x0).0;
        let (mut worst, mut norm, mut normal) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..steps {
            let k1 = f(&x);
            let y: Vec<f64> = x.iter().zip(&k1).map(|(v, k)| v + 0.5 * h * k).collect();
            let k2 = f(&y);
            let y: Vec<f64> = x.iter().zip(&k2).map(|(v, k)| v + 0.5 * h * k).collect();
            let k3 = f(&y);
            let y: Vec<f64> = x.iter().zip(&k3).map(|(v, k)| v + h * k).collect();
            let k4 = f(&y);
            for j in 0..x.len() {
                x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
            let w = x[x.len() - 1];
            worst = worst.max((a.energy(&x[..x.len() - 1]).0 + w - e0).abs());
            let n = Vector3::new(x[7], x[8], x[9]);
            norm = norm.max((n.norm() - Vector3::new(x0[7], x0[8], x0[9]).norm()).abs());
            normal = normal.max(Vector3::new(x[10], x[11], x[12]).dot(&n).abs() / n.norm());
        }
        (worst, norm, normal)
    }

    #[test]
    fn rk4_keeps_the_energy_balance_to_fourth_order() {
        let (a, x) = all();
        // the state's layout: H (3), spring (2), panel (2), pendulum (6) from 7, hinge (2)
        let (coarse, _, _) = rk4_balance(&a, &x, 0.02, 200);
        let (fine, norm, normal) = rk4_balance(&a, &x, 0.01, 400);
        let ratio = coarse / fine;
        assert!(
            (12.0..20.0).contains(&ratio),
            "{coarse} {fine} {ratio} {norm}"
        );
        // the rod's constraints, kept by the equations, drift by the method's error only
        assert!(norm < 1e-8 && normal < 1e-8, "{norm} {normal}");
    }
}

/// One of each part whose mass moves, off every axis: the parts the tests of the multibody
/// solve, the general model and the lone mover's step share.
#[cfg(test)]
pub(crate) mod fixtures {
    use crate::dynamics::{Hinge, Slosh, SpringMass};

    pub(crate) fn spring() -> SpringMass {
        SpringMass::try_new(0.3, [0.4, -0.3, 0.6], [0.2, 0.9, -0.4], 2.0, 0.15).unwrap()
    }

    pub(crate) fn panel() -> Hinge {
        Hinge::try_new(
            0.25,
            [0.01, 0.03, 0.035],
            [0.8, 0.5, -0.2],
            [0.1, 1.0, 0.3],
            [1.0, -0.1, 0.2],
            0.6,
            0.7,
            0.05,
        )
        .unwrap()
    }

    pub(crate) fn tank() -> Slosh {
        Slosh::try_new(0.35, [-0.5, 0.3, 0.7], 0.45, 0.04).unwrap()
    }
}
