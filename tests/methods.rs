//! The methods beyond RK4, checked against the symmetric top's closed form and the
//! conservation laws: orders, error estimates and dense output of the adaptive pairs, the
//! splitting's invariants, flips for every method, and the (ω, t) → (sω, t/s) symmetry.

use std::sync::atomic::AtomicBool;

use dzhanibekov::dynamics::{state_from, FreeRigidBody, State};
use dzhanibekov::integrators::{Dop853, Dopri5};
use dzhanibekov::ode::{DenseOutput, EmbeddedPair, EmbeddedStep, OdeSystem};
use dzhanibekov::run::adaptive::Adaptive;
use dzhanibekov::run::{simulate, FrameGrid, Method, RunOutput};
use dzhanibekov::{Error, RigidBody};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

mod common;
use common::{run, KEEP_ALL};

/// Every method, adaptive ones at tight tolerances.
fn all_methods() -> Vec<(&'static str, Method)> {
    let tight = Adaptive::try_new(1e-11, 1e-13).unwrap();
    vec![
        ("rk4", Method::Rk4),
        ("rk4_projected", Method::Rk4Projected),
        ("splitting", Method::Splitting),
        ("splitting4", Method::Splitting4),
        ("dopri5", Method::Dopri5(tight)),
        ("dop853", Method::Dop853(tight)),
    ]
}

/// The symmetric top (I1 = I2 = I): ω⊥ turns in the body at Ω = (I3 − I) ω3 / I and the
/// attitude is q(t) = exp(t L_world / 2I) ⊗ q0 ⊗ exp(−Ω t e3 / 2).
struct SymmetricTop {
    i: f64,
    i3: f64,
    omega0: Vector3<f64>,
    q0: UnitQuaternion<f64>,
}

impl SymmetricTop {
    fn new() -> Self {
        Self {
            i: 2.0,
            i3: 3.5,
            omega0: Vector3::new(0.6, -0.4, 1.3),
            q0: UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
        }
    }

    fn inertia(&self) -> [f64; 3] {
        [self.i, self.i, self.i3]
    }

    fn q0(&self) -> [f64; 4] {
        let c = self.q0.into_inner();
        [c.w, c.i, c.j, c.k]
    }

    fn state0(&self) -> State {
        state_from(self.omega0.into(), self.q0())
    }

    fn at(&self, t: f64) -> State {
        let big_omega = (self.i3 - self.i) * self.omega0.z / self.i;
        let body_turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), big_omega * t);
        let omega = body_turn * self.omega0;
        let l_world = self.q0
            * Vector3::new(
                self.i * self.omega0.x,
                self.i * self.omega0.y,
                self.i3 * self.omega0.z,
            );
        let space_turn = UnitQuaternion::from_scaled_axis(l_world * (t / self.i));
        let q = (space_turn * self.q0 * body_turn.inverse()).into_inner();
        state_from(omega.into(), [q.w, q.i, q.j, q.k])
    }

    /// Max error in ω and in q (sign-fixed) of `x` against the closed form at `t`.
    fn error(&self, t: f64, x: &State) -> f64 {
        let want = self.at(t);
        let dw = (0..3).map(|k| (x[k] - want[k]).abs()).fold(0.0, f64::max);
        let q = |s: &State| Quaternion::new(s[3], s[4], s[5], s[6]);
        let dq = (q(x) - q(&want)).norm().min((q(x) + q(&want)).norm());
        dw.max(dq)
    }

    /// Max error over the frames of a run of `method` to t = 10 with 11 frames.
    fn run_error(&self, method: Method, dt: f64) -> f64 {
        let out = run(
            method,
            self.inertia(),
            self.omega0.into(),
            self.q0(),
            10.0,
            11,
            dt,
        );
        (0..11)
            .map(|f| {
                let w = &out.omega[3 * f..3 * f + 3];
                let q = &out.q[4 * f..4 * f + 4];
                self.error(
                    f as f64,
                    &state_from([w[0], w[1], w[2]], [q[0], q[1], q[2], q[3]]),
                )
            })
            .fold(0.0, f64::max)
    }
}

/// Ratios of successive errors as the step halves.
fn ratios(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|p| p[0] / p[1]).collect()
}

#[test]
fn fixed_step_methods_converge_at_their_order() {
    let top = SymmetricTop::new();
    for (method, steps, lo, hi) in [
        (Method::Rk4Projected, [0.04, 0.02, 0.01], 14.0, 18.0),
        (Method::Splitting, [0.04, 0.02, 0.01], 3.7, 4.3),
        (Method::Splitting4, [0.04, 0.02, 0.01], 14.0, 18.0),
    ] {
        let errors: Vec<f64> = steps.iter().map(|&dt| top.run_error(method, dt)).collect();
        let r = ratios(&errors);
        assert!(
            r.iter().all(|x| (lo..hi).contains(x)),
            "{method:?}: ratios {r:?}, errors {errors:?}"
        );
    }
}

/// Integrates the symmetric top to t = 2 with `pair` at the fixed step `h` (no control).
fn fixed_step_error<P: EmbeddedPair<7, FreeRigidBody>>(pair: &P, h: f64) -> f64 {
    let top = SymmetricTop::new();
    let sys = FreeRigidBody::new(RigidBody::try_new(top.inertia()).unwrap());
    let n = (2.0 / h).round() as usize;
    let mut x = top.state0();
    for k in 0..n {
        let t = k as f64 * h;
        let f0 = sys.rhs(t, &x);
        x = *pair.attempt(&sys, t, h, &x, &f0).x1();
    }
    top.error(n as f64 * h, &x)
}

#[test]
fn adaptive_pairs_propagate_at_their_order() {
    let e5: Vec<f64> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&h| fixed_step_error(&Dopri5, h))
        .collect();
    let r = ratios(&e5);
    assert!(r.iter().all(|x| (28.0..36.0).contains(x)), "{r:?} {e5:?}");
    let e8: Vec<f64> = [0.4, 0.2, 0.1]
        .iter()
        .map(|&h| fixed_step_error(&Dop853, h))
        .collect();
    let r = ratios(&e8);
    assert!(r.iter().all(|x| (200.0..320.0).contains(x)), "{r:?} {e8:?}");
}

/// One step of `pair` of size `h` from the top's initial state: the error estimate (scaled by
/// 1) and the dense output's error at `theta` against the closed form.
fn one_step<P: EmbeddedPair<7, FreeRigidBody>>(pair: &P, h: f64, theta: f64) -> (f64, f64) {
    let top = SymmetricTop::new();
    let sys = FreeRigidBody::new(RigidBody::try_new(top.inertia()).unwrap());
    let x0 = top.state0();
    let step = pair.attempt(&sys, 0.0, h, &x0, &sys.rhs(0.0, &x0));
    let estimate = step.error_norm(h, &[1.0; 7]);
    let dense = pair.dense(&sys, 0.0, h, &x0, &step);
    (estimate, top.error(theta * h, &dense.at(theta)))
}

#[test]
fn error_estimates_and_dense_output_have_their_orders() {
    // DOPRI5: a fourth-order estimate (local error h⁵) and a fourth-order interpolant (h⁵)
    let (a, b) = (one_step(&Dopri5, 0.4, 0.37), one_step(&Dopri5, 0.2, 0.37));
    assert!((24.0..40.0).contains(&(a.0 / b.0)), "estimate {a:?} {b:?}");
    assert!((24.0..40.0).contains(&(a.1 / b.1)), "dense {a:?} {b:?}");
    // DOP853: Hairer's combined estimate behaves as h⁸; the interpolant is seventh order (h⁸)
    let (a, b) = (one_step(&Dop853, 0.8, 0.37), one_step(&Dop853, 0.4, 0.37));
    assert!(
        (180.0..360.0).contains(&(a.0 / b.0)),
        "estimate {a:?} {b:?}"
    );
    assert!((180.0..360.0).contains(&(a.1 / b.1)), "dense {a:?} {b:?}");
    // the interpolants meet the step's ends
    let top = SymmetricTop::new();
    let sys = FreeRigidBody::new(RigidBody::try_new(top.inertia()).unwrap());
    let x0 = top.state0();
    let f0 = sys.rhs(0.0, &x0);
    let step = Dop853.attempt(&sys, 0.0, 0.3, &x0, &f0);
    let dense = Dop853.dense(&sys, 0.0, 0.3, &x0, &step);
    let (start, end) = (dense.at(0.0), dense.at(1.0));
    for k in 0..7 {
        assert!((start[k] - x0[k]).abs() < 1e-15);
        assert!((end[k] - step.x1()[k]).abs() < 1e-15);
    }
}

#[test]
fn adaptive_runs_meet_their_tolerance_on_the_closed_form() {
    let top = SymmetricTop::new();
    for rtol in [1e-5, 1e-8, 1e-11] {
        let a = Adaptive::try_new(rtol, rtol * 1e-2).unwrap();
        for method in [Method::Dopri5(a), Method::Dop853(a)] {
            let err = top.run_error(method, 0.0);
            // local error control: the global error over 10 time units (a few turns) stays
            // within a small multiple of the tolerance
            assert!(err < 10.0 * rtol, "{method:?}: error {err:e}");
        }
    }
}

#[test]
fn adaptive_counters_add_up_and_the_frames_are_exact() {
    let top = SymmetricTop::new();
    let a = Adaptive::try_new(1e-8, 1e-10).unwrap();
    let out = run(
        Method::Dop853(a),
        top.inertia(),
        top.omega0.into(),
        top.q0(),
        10.0,
        11,
        0.0,
    );
    let s = out.stats;
    // one evaluation to start, twelve per attempt, three more for each interpolated step
    let dense = s.nfev - 1 - 12 * (s.n_steps + s.n_rejected);
    assert!(
        s.n_steps > 5 && dense.is_multiple_of(3) && dense <= 3 * s.n_steps,
        "{s:?}"
    );
    // the last frame is the last step's end, the others interpolated: all on the solution
    assert!(top.error(10.0, &out_state(&out, 10)) < 1e-7);
    assert!(out.dt > 0.0 && (out.dt * s.n_steps as f64 - 10.0).abs() < 1e-12);
}

fn out_state(out: &RunOutput, f: usize) -> State {
    let w = &out.omega[3 * f..3 * f + 3];
    let q = &out.q[4 * f..4 * f + 4];
    state_from([w[0], w[1], w[2]], [q[0], q[1], q[2], q[3]])
}

/// Relative |L|, energy and L_world at every frame of `out`, against frame 0.
fn invariant_drifts(inertia: [f64; 3], out: &RunOutput) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let i = Vector3::from(inertia);
    let frames = out.q.len() / 4;
    let at = |f: usize| {
        let x = out_state(out, f);
        let w = Vector3::new(x[0], x[1], x[2]);
        let l = i.component_mul(&w);
        let q = Quaternion::new(x[3], x[4], x[5], x[6]);
        let world = dzhanibekov::kinematics::rotation_matrix(&q) * l;
        (l.norm(), 0.5 * w.dot(&l), world)
    };
    let (l0, e0, w0) = at(0);
    let mut d = (vec![], vec![], vec![]);
    for f in 0..frames {
        let (l, e, w) = at(f);
        d.0.push((l - l0).abs() / l0);
        d.1.push((e - e0).abs() / e0);
        d.2.push((w - w0).norm() / l0);
    }
    d
}

#[test]
fn splitting_keeps_the_momentum_and_bounds_the_energy_error() {
    let inertia = [52.0833, 27.0833, 41.6666];
    for method in [Method::Splitting, Method::Splitting4] {
        // 2·10⁶ steps at a coarse step: 40 frames over T = 10⁴, compare T with 10 T
        let out = run(
            method,
            inertia,
            [0.01, 0.1, 0.03],
            [1.0, 0.0, 0.0, 0.0],
            2e4,
            41,
            1e-2,
        );
        let (l, e, w) = invariant_drifts(inertia, &out);
        let max = |v: &[f64]| v.iter().cloned().fold(0.0, f64::max);
        assert!(max(&l) < 1e-14, "{method:?} |L| {:e}", max(&l));
        assert!(max(&w) < 1e-12, "{method:?} L_world {:e}", max(&w));
        assert!(out.drift.q_norm < 1e-14);
        // energy: the error over the first tenth bounds the error over the whole run, up to
        // round-off (splitting4's O(h⁴) oscillation at this step is below 1e-15, where the
        // round-off, which random-walks, takes over: 5e-16 then 1.6e-15 measured)
        let (first, all) = (max(&e[..5]), max(&e));
        assert!(
            all < 1.5 * first + 1e-14 && all > 0.0,
            "{method:?}: {first:e} then {all:e}"
        );
    }
}

#[test]
fn every_method_flips_about_the_intermediate_axis_only() {
    let inertia = [3.0, 2.0, 1.0];
    for (name, method) in all_methods() {
        let flips =
            |omega0| run(method, inertia, omega0, [1.0, 0.0, 0.0, 0.0], 60.0, 2, 1e-2).flip_times;
        let unstable = flips([0.01, 1.0, 0.01]);
        assert!(unstable.len() >= 3, "{name}: {unstable:?}");
        assert!(flips([1.0, 0.01, 0.01]).is_empty(), "{name}");
        assert!(flips([0.01, 0.01, 1.0]).is_empty(), "{name}");
        // the same flips, to the accuracy of the method at this step
        let reference = run(
            Method::Dop853(Adaptive::try_new(1e-12, 1e-14).unwrap()),
            inertia,
            [0.01, 1.0, 0.01],
            [1.0, 0.0, 0.0, 0.0],
            60.0,
            2,
            0.0,
        )
        .flip_times;
        assert_eq!(unstable.len(), reference.len(), "{name}");
        for (a, b) in unstable.iter().zip(&reference) {
            assert!((a - b).abs() < 1e-3, "{name}: {a} vs {b}");
        }
    }
}

#[test]
fn runs_are_unchanged_bit_for_bit_when_rates_double_and_time_halves() {
    // (ω, t) → (sω, t/s) maps solutions to solutions; with s a power of two every
    // floating-point operation of every method scales exactly.
    let inertia = [52.0833, 27.0833, 41.6666];
    let (omega0, q0) = ([0.01, 0.1, 0.03], [0.9, 0.1, -0.2, 0.3]);
    for (name, method) in all_methods() {
        let a = run(method, inertia, omega0, q0, 100.0, 21, 1e-2);
        let s = 1024.0;
        let b = run(
            method,
            inertia,
            omega0.map(|w| w * s),
            q0,
            100.0 / s,
            21,
            1e-2 / s,
        );
        let scaled: Vec<f64> = a.omega.iter().map(|w| w * s).collect();
        assert_eq!(scaled, b.omega, "{name}");
        assert_eq!(a.q, b.q, "{name}");
        let flips: Vec<f64> = a.flip_times.iter().map(|t| t / s).collect();
        assert_eq!(flips, b.flip_times, "{name}");
        assert_eq!(a.stats, b.stats, "{name}");
    }
}

#[test]
fn adaptive_runs_stop_on_cancel_and_refuse_runaway_step_counts() {
    let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
    let grid = FrameGrid::frames_only(1e7, 2).unwrap();
    let a = Adaptive::try_new(1e-12, 1e-14).unwrap();
    let go = |method, cancel: bool| {
        simulate(
            &body,
            [0.1, 0.2, 0.3],
            [1.0, 0.0, 0.0, 0.0],
            &grid,
            method,
            KEEP_ALL,
            &AtomicBool::new(cancel),
        )
    };
    assert_eq!(go(Method::Dop853(a), true).unwrap_err(), Error::Interrupted);
    let capped = Method::Dopri5(a.with_max_steps(1000));
    let err = go(capped, false).unwrap_err().to_string();
    assert!(err.contains("max_steps = 1000"), "{err}");
}

#[test]
fn bad_tolerances_name_themselves() {
    for (rtol, atol, name) in [
        (0.0, 1e-12, "`rtol`"),
        (1e-17, 1e-12, "`rtol`"),
        (1.0, 1e-12, "`rtol`"),
        (f64::NAN, 1e-12, "`rtol`"),
        (1e-9, 0.0, "`atol`"),
        (1e-9, f64::INFINITY, "`atol`"),
    ] {
        let err = Adaptive::try_new(rtol, atol).unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
    }
    for name in [
        "rk4_projected",
        "splitting",
        "splitting4",
        "dopri5",
        "dop853",
    ] {
        assert!(name.parse::<Method>().is_ok());
    }
}
