//! The Lie–Poisson splitting of the free rigid body; see [`Splitting`].

use crate::body::RigidBody;
use crate::dynamics::{FreeRigidBody, State};

use crate::ode::{power_of_two_scale, Stepper};

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
/// Choices, measured on six bodies against DOP853 at `rtol = 1e-13`: the axis order of the
/// Strang step (smallest moment outside, largest at the centre) gave the smallest error of
/// the six orders on five of them; Suzuki's five-fold composition had 60–80 times less error
/// than Yoshida's triple jump at the same step, for 21 rotations a step against 13.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Splitting<const FLOWS: usize> {
    flows: [Flow; FLOWS],
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    /// A power of two near `1 / max|L₀|`, so that `|L|²` is formed without overflow.
    l_scale: f64,
    /// `1/|L₀ l_scale|²` for the norm correction, 0 when `L₀ = 0` (nothing then moves).
    inv_l0_sq: f64,
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
fn suzuki_weights() -> [f64; 5] {
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
        }
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
        for f in &self.flows {
            let tau = f.fraction * h * self.inv_inertia[f.axis];
            match f.axis {
                0 => rotate::<0, 1, 2>(&mut l, &mut q, tau),
                1 => rotate::<1, 2, 0>(&mut l, &mut q, tau),
                _ => rotate::<2, 0, 1>(&mut l, &mut q, tau),
            }
        }
        let [l0, l1, l2] = l.map(|c| c * self.l_scale);
        let l_sq = (l0 * l0 + l1 * l1 + l2 * l2) * self.inv_l0_sq;
        let q_sq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        if (l_sq - 1.0).abs() > RENORMALIZE && self.inv_l0_sq > 0.0 {
            l = l.map(|c| c * (1.5 - 0.5 * l_sq));
        }
        if (q_sq - 1.0).abs() > RENORMALIZE {
            q = q.map(|c| c * (1.5 - 0.5 * q_sq));
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
