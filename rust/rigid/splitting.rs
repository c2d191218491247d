//! The Lie–Poisson splitting of the free rigid body; see [`Splitting`].

use crate::body::RigidBody;
use crate::dynamics::{FreeRigidBody, State};

use crate::ode::{power_of_two_scale, Stepper};

use super::lie::Carry;

/// How far `|L|²/|L₀|²` and `|q|²` may wander from 1 before they are pulled back (about 45
/// ulps). Pulling back at every step would keep them within an ulp but rotates `L_world`: the
/// rounding of `c · (1 + η)` differs from component to component, and repeated at every step
/// with the same `η` it turns `L_world` steadily (about 2e-18 a step, measured); pulled back
/// only this rarely, the turn is thousands of times smaller.
const RENORMALIZE: f64 = 1e-14;

/// One exactly solvable piece: the flow of `L_axis² / (2 I_axis)` over `fraction` of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Flow {
    axis: usize,
    fraction: f64,
}

/// A composition of the exact rotations about the body axes, `FLOWS` of them per step,
/// working on `[L, q]` (observers see `[ω, q]`).
///
/// An explicit Lie–Poisson splitting of the free rigid body into exactly solvable rotations
/// (R. I. McLachlan, "Explicit Lie–Poisson integration and the Euler equations", Phys. Rev.
/// Lett. 71 (1993) 3043; J. Touma, J. Wisdom, "Lie–Poisson integrators for rigid body
/// dynamics in the solar system", Astron. J. 107 (1994) 1189; S. Reich, "Momentum
/// conserving symplectic integrators", Physica D 76 (1994) 375).
///
/// In the body angular momentum `L = I ω` the motion is `L' = L × ω` with the Hamiltonian
/// `H = Σ L_i² / (2 I_i)`. The flow of one term `L_i² / (2 I_i)` alone keeps `L_i` and turns
/// `L` about body axis `i` by the angle `−(L_i / I_i) t`, while the attitude turns about the
/// same axis: `q ← q ⊗ (cos φ, sin φ e_i)` with `φ = (L_i / I_i) t / 2`. Each piece is a
/// rotation, so `|L|` and `|q|` are kept exactly and `L_world = M(q) L` is kept exactly too
/// (the body turns one way as `L` turns the other); composing the pieces symmetrically
/// (Strang) gives a second-order method whose energy error stays bounded over any run length,
/// and composing that (Suzuki's fractal) gives fourth order.
///
/// In floating point each rotation changes `|L|` and `|q|` by up to an ulp, and over `n`
/// steps these round-offs random-walk to about `√n` ulps (or drift, when `sin² + cos²`
/// rounds the same way step after step). So whenever a squared norm has wandered more than
/// 1e-14 from its initial value it is pulled back by one Newton step of the inverse square
/// root, `x ← x (3 − |x|²/|x₀|²) / 2`: the norms then stay within about 1e-14 for any number
/// of steps (measured: |L| to 4e-15 over 10⁷ steps, `benches/python/bench_methods.py`).
///
/// **Compensated summation** (on by default, [`Splitting::compensated`]). Each step is
/// computed as an increment `δ` of the state — every rotation's change of `L` and `q` as a small
/// correction, summed — and added to the state by Kahan's compensated summation, the part
/// below the state's last bit carried to the next step (Hairer, Lubich & Wanner, §VIII.5;
/// for the rigid body, G. Vilmart, "Reducing round-off errors in rigid body dynamics",
/// J. Comput. Phys. 227 (2008) 7083). The rounding of the state, an ulp a rotation, then no
/// longer accumulates; what is left is that of the increments, smaller by their size `hΩ`.
/// Measured on the HLW body over 10⁷ steps of `h = 0.1`, the RMS over 64 perturbed starts
/// (`cargo bench --bench brouwer`, plotted by `python benches/atlas.py brouwer`): `L_world`
/// wanders 13 times less (3.9e-14 against 5.1e-13), still like a random walk (slopes 0.47
/// and 0.48 of log error against log n); `|L|` and `|q|` stay within the pull-back (2.3e-15)
/// either way. Without the pull-back the plain `|L|` grows like `n^0.65` and the compensated
/// one like `n^0.93`: what is left once the sum's rounding is carried is the rounding of
/// each rotation's coefficients, about `ε φ²` a rotation and of one sign, a bias that the
/// pull-back catches. It costs 0–3% of a step (the median of 40 alternate timings), so it
/// is the default.
///
/// Choices, measured on six bodies against DOP853 at `rtol = 1e-13`: the axis order of the
/// Strang step (smallest moment outside, largest at the centre) gave the smallest error of
/// the six orders on five of them; Suzuki's five-fold composition had 60–80 times less error
/// than Yoshida's triple jump at the same step, for 21 rotations a step against 13.
#[derive(Debug, Clone, PartialEq)]
pub struct Splitting<const FLOWS: usize> {
    flows: [Flow; FLOWS],
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    /// A power of two near `1 / max|L₀|`, so that `|L|²` is formed without overflow.
    l_scale: f64,
    /// `1/|L₀ l_scale|²` for the norm correction, 0 when `L₀ = 0` (nothing then moves).
    inv_l0_sq: f64,
    /// Compensated summation of each step's update (see [`Carry`]).
    compensate: bool,
    /// Whether `|L|` and `|q|` are pulled back when they wander (always, but in round-off
    /// studies).
    renormalize: bool,
    carry: Carry,
}

/// Second order: Strang's symmetric composition `A(h/2) B(h/2) C(h) B(h/2) A(h/2)`.
pub type Splitting2 = Splitting<5>;
/// Fourth order: Suzuki's five-fold composition of [`Splitting2`], 21 rotations per step.
pub type Splitting4 = Splitting<21>;
/// Sixth order: Kahan & Li's nine-fold composition of [`Splitting2`], 37 rotations per step.
pub type Splitting6 = Splitting<37>;

/// Suzuki's fourth-order fractal weights `(p, p, 1 − 4p, p, p)`, `p = 1/(4 − 4^{1/3})`
/// (M. Suzuki, "Fractal decomposition of exponential operators", Phys. Lett. A 146 (1990)
/// 319; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §II.4, eq. 4.5).
pub(crate) fn suzuki_weights() -> [f64; 5] {
    let p = 1.0 / (4.0 - 4f64.cbrt());
    [p, p, 1.0 - 4.0 * p, p, p]
}

/// Kahan & Li's sixth-order symmetric composition of a symmetric second-order method, nine
/// stages `(γ₁, …, γ₅, …, γ₁)` (W. Kahan, R.-C. Li, "Composition constants for raising the
/// orders of unconventional schemes for ordinary differential equations", Math. Comp. 66
/// (1997) 1089; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §V.3.2, eq. 3.12).
/// Hairer, Lubich & Wanner find it markedly more accurate than Yoshida's seven-stage order-6
/// composition (H. Yoshida, Phys. Lett. A 150 (1990) 262); measured here on the HLW body to
/// `T = 10`, its error at the same step is 17 times smaller, for 37 rotations a step against
/// 29 (about 4 times smaller at the same cost).
#[allow(clippy::excessive_precision)] // the published digits, rounded by the compiler
const KAHAN_LI_6: [f64; 9] = {
    let g = [
        0.392_161_444_007_314_139_279_250_56,
        0.332_599_136_789_359_438_599_748_64,
        -0.706_246_172_557_639_359_809_964_82,
        0.082_213_596_293_550_800_231_490_45,
        0.798_543_990_934_829_963_398_950_35,
    ];
    [g[0], g[1], g[2], g[3], g[4], g[3], g[2], g[1], g[0]]
};

/// The order of the axes in the Strang step, outer to centre: smallest moment outside,
/// largest at the centre (see [`Splitting`]). The centre piece is taken whole, the others in
/// halves.
fn axes_of(body: &RigidBody) -> [usize; 3] {
    let i = body.inertia_body();
    let mut axes = [0, 1, 2];
    axes.sort_by(|&a, &b| i[a].total_cmp(&i[b]));
    axes
}

/// The flows of the composition of Strang steps with `weights`, adjacent flows about the
/// same axis merged (`4 m + 1` flows for `m` weights).
fn composed(axes: [usize; 3], weights: &[f64]) -> Vec<Flow> {
    let [a, b, c] = axes;
    let mut flows: Vec<Flow> = Vec::with_capacity(4 * weights.len() + 1);
    for &w in weights {
        for (axis, fraction) in [
            (a, 0.5 * w),
            (b, 0.5 * w),
            (c, w),
            (b, 0.5 * w),
            (a, 0.5 * w),
        ] {
            match flows.last_mut() {
                Some(last) if last.axis == axis => last.fraction += fraction,
                _ => flows.push(Flow { axis, fraction }),
            }
        }
    }
    flows
}

impl<const FLOWS: usize> Splitting<FLOWS> {
    fn with_flows(body: &RigidBody, flows: Vec<Flow>, x0: &State) -> Self {
        let inertia: [f64; 3] = body.inertia_body().into();
        let l0 = [0, 1, 2].map(|k| inertia[k] * x0[k]);
        let l_scale = power_of_two_scale(l0.iter().fold(0.0, |m, l| m.max(l.abs())));
        let l0_sq: f64 = l0.iter().map(|l| (l * l_scale).powi(2)).sum();
        let flows: [Flow; FLOWS] = flows
            .try_into()
            .unwrap_or_else(|f: Vec<Flow>| panic!("{} flows, not {FLOWS}", f.len()));
        Self {
            flows,
            inertia,
            inv_inertia: inertia.map(|i| 1.0 / i),
            l_scale,
            inv_l0_sq: if l0_sq > 0.0 && l0_sq.is_finite() {
                1.0 / l0_sq
            } else {
                0.0
            },
            compensate: true,
            renormalize: true,
            carry: Carry::default(),
        }
    }

    /// The same splitting with compensated summation of each step's update on (the
    /// default) or off, the plain sum of the rotations (for round-off studies).
    pub fn compensated(mut self, on: bool) -> Self {
        self.compensate = on;
        self
    }

    /// The same splitting with the pull-back of `|L|` and `|q|` on (the default) or off (for
    /// round-off studies: the norms then show their raw round-off).
    pub fn renormalized(mut self, on: bool) -> Self {
        self.renormalize = on;
        self
    }

    /// The axis order (outer to centre) and the fraction of the step of each rotation.
    pub fn flows(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.flows.iter().map(|f| (f.axis, f.fraction))
    }
}

impl Splitting2 {
    /// Strang's splitting for `body`, starting from state `x0` (`[ω, q]`): the initial `|L|`
    /// is the one kept.
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        Self::with_axes(body, axes_of(body), x0)
    }

    /// Strang's splitting with the axes in the given order, outer to centre.
    pub fn with_axes(body: &RigidBody, axes: [usize; 3], x0: &State) -> Self {
        Self::with_flows(body, composed(axes, &[1.0]), x0)
    }
}

impl Splitting4 {
    /// Suzuki's fourth-order composition of [`Splitting2`] for `body` from `x0`.
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        Self::with_flows(body, composed(axes_of(body), &suzuki_weights()), x0)
    }
}

impl Splitting6 {
    /// Kahan & Li's sixth-order composition of [`Splitting2`] for `body` from `x0`.
    pub fn new(body: &RigidBody, x0: &State) -> Self {
        Self::with_flows(body, composed(axes_of(body), &KAHAN_LI_6), x0)
    }
}

/// The exact flow of `L_I² / (2 I_I)` for time `tau`, `(I, J, K)` cyclic.
#[inline(always)]
fn rotate<const I: usize, const J: usize, const K: usize>(
    l: &mut [f64; 3],
    q: &mut [f64; 4],
    tau_over_inertia: f64,
) {
    let phi = 0.5 * tau_over_inertia * l[I];
    let (s, c) = phi.sin_cos();
    // L turns by −2φ about axis I, exactly the inverse of the turn `(c, s)` gives the
    // attitude, so that L_world = M(q) L stays put: `sin 2φ = 2sc / n`, `1 − cos 2φ = 2s² / n`
    // with `n = c² + s²`, which is 1 only to round-off — leaving `n` out biases the two turns
    // apart by about `(n − 1) · 2φ` per rotation, a drift of L_world that grows linearly.
    // The update is a small correction, so its round-off is relative to the change.
    let k = 2.0 / (c * c + s * s);
    let (s2, one_minus_c2) = (k * s * c, k * s * s);
    let (lj, lk) = (l[J], l[K]);
    l[J] = lj + (s2 * lk - one_minus_c2 * lj);
    l[K] = lk - (s2 * lj + one_minus_c2 * lk);
    // q ← q ⊗ (cos φ, sin φ e_I); q is scalar first, so body axis I is q[1 + I].
    let (q0, qi, qj, qk) = (q[0], q[1 + I], q[1 + J], q[1 + K]);
    q[0] = c * q0 - s * qi;
    q[1 + I] = c * qi + s * q0;
    q[1 + J] = c * qj + s * qk;
    q[1 + K] = c * qk - s * qj;
}

/// [`rotate`] in increment form: the running `l`, `q` move as there, and the change of each
/// component is added to `d` as well, computed as a small correction so that its round-off is
/// relative to the change.
#[inline(always)]
fn rotate_by_increments<const I: usize, const J: usize, const K: usize>(
    l: &mut [f64; 3],
    q: &mut [f64; 4],
    d: &mut [f64; 7],
    tau_over_inertia: f64,
) {
    let phi = 0.5 * tau_over_inertia * l[I];
    let (s, c) = phi.sin_cos();
    let k = 2.0 / (c * c + s * s);
    let (s2, one_minus_c2) = (k * s * c, k * s * s);
    let (lj, lk) = (l[J], l[K]);
    let (dlj, dlk) = (s2 * lk - one_minus_c2 * lj, -(s2 * lj + one_minus_c2 * lk));
    l[J] = lj + dlj;
    l[K] = lk + dlk;
    d[J] += dlj;
    d[K] += dlk;
    // exact for c ≥ 1/2 (Sterbenz): the attitude turns by the same (c, s) as without
    // increments, and the rounding of c shows in |q| alone, which the pull-back holds
    let cm1 = c - 1.0;
    let (q0, qi, qj, qk) = (q[0], q[1 + I], q[1 + J], q[1 + K]);
    let dq = [
        cm1 * q0 - s * qi,
        cm1 * qi + s * q0,
        cm1 * qj + s * qk,
        cm1 * qk - s * qj,
    ];
    q[0] = q0 + dq[0];
    q[1 + I] = qi + dq[1];
    q[1 + J] = qj + dq[2];
    q[1 + K] = qk + dq[3];
    d[3] += dq[0];
    d[4 + I] += dq[1];
    d[4 + J] += dq[2];
    d[4 + K] += dq[3];
}

impl<const FLOWS: usize> Stepper<7, FreeRigidBody> for Splitting<FLOWS> {
    const ORDER: u32 = match FLOWS {
        5 => 2,
        21 => 4,
        _ => 6,
    };
    /// The splitting evaluates no right-hand side: its cost is `FLOWS` sines and cosines.
    const RHS_PER_STEP: u64 = 0;

    #[inline]
    fn step(&self, _sys: &FreeRigidBody, _t: f64, h: f64, x: &mut State) {
        let mut l = [x[0], x[1], x[2]];
        let mut q = [x[3], x[4], x[5], x[6]];
        if self.compensate {
            let mut d = [0.0; 7];
            for f in &self.flows {
                let tau = f.fraction * h * self.inv_inertia[f.axis];
                match f.axis {
                    0 => rotate_by_increments::<0, 1, 2>(&mut l, &mut q, &mut d, tau),
                    1 => rotate_by_increments::<1, 2, 0>(&mut l, &mut q, &mut d, tau),
                    _ => rotate_by_increments::<2, 0, 1>(&mut l, &mut q, &mut d, tau),
                }
            }
            let y = self.carry.add(x, &d);
            l = [y[0], y[1], y[2]];
            q = [y[3], y[4], y[5], y[6]];
        } else {
            for f in &self.flows {
                let tau = f.fraction * h * self.inv_inertia[f.axis];
                match f.axis {
                    0 => rotate::<0, 1, 2>(&mut l, &mut q, tau),
                    1 => rotate::<1, 2, 0>(&mut l, &mut q, tau),
                    _ => rotate::<2, 0, 1>(&mut l, &mut q, tau),
                }
            }
        }
        if !self.renormalize {
            *x = [l[0], l[1], l[2], q[0], q[1], q[2], q[3]];
            return;
        }
        let [l0, l1, l2] = l.map(|c| c * self.l_scale);
        let l_sq = (l0 * l0 + l1 * l1 + l2 * l2) * self.inv_l0_sq;
        let q_sq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        if (l_sq - 1.0).abs() > RENORMALIZE && self.inv_l0_sq > 0.0 {
            l = l.map(|c| c * (1.5 - 0.5 * l_sq));
            self.carry.clear();
        }
        if (q_sq - 1.0).abs() > RENORMALIZE {
            q = q.map(|c| c * (1.5 - 0.5 * q_sq));
            self.carry.clear();
        }
        *x = [l[0], l[1], l[2], q[0], q[1], q[2], q[3]];
    }

    /// `L = I ω`.
    #[inline(always)]
    fn to_internal(&self, _sys: &FreeRigidBody, x: &State) -> State {
        let i = &self.inertia;
        [
            i[0] * x[0],
            i[1] * x[1],
            i[2] * x[2],
            x[3],
            x[4],
            x[5],
            x[6],
        ]
    }

    /// `ω = L / I`.
    #[inline(always)]
    fn to_state(&self, _sys: &FreeRigidBody, x: &State) -> State {
        let i = &self.inertia;
        [
            x[0] / i[0],
            x[1] / i[1],
            x[2] / i[2],
            x[3],
            x[4],
            x[5],
            x[6],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn composition_weights_are_fourth_order() {
        let w = suzuki_weights();
        assert_relative_eq!(w.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
        assert!(w.iter().map(|x| x.powi(3)).sum::<f64>().abs() < 1e-15);
    }

    /// A symmetric composition of a symmetric second-order method has order 6 when `Σγ = 1`,
    /// `Σγ³ = 0`, `Σγ⁵ = 0` and one more condition of order 5 holds (HLW, §V.3.2); the sums are
    /// checked here, the order itself is measured in `tests/atlas.rs`.
    #[test]
    fn kahan_li_weights_are_sixth_order_sums() {
        let g = KAHAN_LI_6;
        assert_relative_eq!(g.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
        assert!(g.iter().map(|x| x.powi(3)).sum::<f64>().abs() < 1e-15);
        assert!(g.iter().map(|x| x.powi(5)).sum::<f64>().abs() < 1e-15);
    }

    #[test]
    fn the_compensated_and_the_plain_sum_are_the_same_step_to_round_off() {
        let body = RigidBody::try_new([2.0, 1.0, 2.0 / 3.0]).unwrap();
        let sys = FreeRigidBody::new(body);
        let x0 = [0.22, 0.1, 1.3, 0.9, 0.1, -0.3, 0.2];
        let x0 = {
            let n = x0[3..].iter().map(|c| c * c).sum::<f64>().sqrt();
            [
                x0[0],
                x0[1],
                x0[2],
                x0[3] / n,
                x0[4] / n,
                x0[5] / n,
                x0[6] / n,
            ]
        };
        let plain = Splitting4::new(&body, &x0).compensated(false);
        let compensated = Splitting4::new(&body, &x0);
        let (mut a, mut b) = (
            plain.to_internal(&sys, &x0),
            compensated.to_internal(&sys, &x0),
        );
        for _ in 0..1000 {
            plain.step(&sys, 0.0, 0.05, &mut a);
            compensated.step(&sys, 0.0, 0.05, &mut b);
        }
        for k in 0..7 {
            assert!((a[k] - b[k]).abs() < 1e-13, "{a:?} {b:?}");
        }
    }

    #[test]
    fn flows_cover_each_axis_for_a_whole_step() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let x0 = [0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0];
        let s2 = Splitting2::new(&body, &x0);
        let s4 = Splitting4::new(&body, &x0);
        for axis in 0..3 {
            let total = |f: &mut dyn Iterator<Item = (usize, f64)>| {
                f.filter(|&(a, _)| a == axis).map(|(_, t)| t).sum::<f64>()
            };
            assert_relative_eq!(total(&mut s2.flows()), 1.0, epsilon = 1e-15);
            assert_relative_eq!(total(&mut s4.flows()), 1.0, epsilon = 1e-14);
        }
        // symmetric: the flows read the same backwards
        let f: Vec<_> = s4.flows().collect();
        for (a, b) in f.iter().zip(f.iter().rev()) {
            assert_eq!(a.0, b.0);
            assert_relative_eq!(a.1, b.1, epsilon = 1e-15);
        }
    }

    #[test]
    fn one_rotation_matches_the_exact_flow_of_its_term() {
        // H = L_z²/(2 I_z) alone: ω = (0, 0, L_z/I_z) is constant, L turns about z at that
        // rate (L' = L × ω), and q' = ½ q ⊗ (0, ω).
        let (iz, tau) = (2.0, 0.7);
        let mut l = [0.3, -0.5, 0.8];
        let mut q = [0.9, 0.1, -0.3, 0.2];
        let (l0, q0) = (l, q);
        rotate::<2, 0, 1>(&mut l, &mut q, tau / iz);
        let rate = l0[2] / iz;
        let a = rate * tau;
        assert_relative_eq!(l[0], a.cos() * l0[0] + a.sin() * l0[1], epsilon = 1e-15);
        assert_relative_eq!(l[1], -a.sin() * l0[0] + a.cos() * l0[1], epsilon = 1e-15);
        assert_eq!(l[2], l0[2]);
        let half = nalgebra::Quaternion::new((a / 2.0).cos(), 0.0, 0.0, (a / 2.0).sin());
        let want = nalgebra::Quaternion::new(q0[0], q0[1], q0[2], q0[3]) * half;
        assert_relative_eq!(q[0], want.w, epsilon = 1e-15);
        assert_relative_eq!(q[1], want.i, epsilon = 1e-15);
        assert_relative_eq!(q[2], want.j, epsilon = 1e-15);
        assert_relative_eq!(q[3], want.k, epsilon = 1e-15);
    }
}
