//! The exact solution against RK4 at a small step (an independent method), conservation
//! laws at t = 10⁶, the flow property, the flips RK4's detector finds, and the special cases.

use std::sync::atomic::AtomicBool;

use approx::assert_relative_eq;
use dzhanibekov::dynamics::Invariants;
use dzhanibekov::exact::{flip_period, ExactMotion};
use dzhanibekov::run::{simulate, FrameGrid, Method, RunOutput};
use dzhanibekov::{Error, RigidBody};
use nalgebra::{UnitQuaternion, Vector3};
use proptest::prelude::*;

mod common;
use common::{KEEP_ALL, PAPER};

/// A run from the attitude these tests share, with RK4 at `dt = 1e-3`.
fn run(
    method: Method,
    inertia: [f64; 3],
    omega0: [f64; 3],
    t_end: f64,
    frames: usize,
) -> RunOutput {
    common::run(
        method,
        inertia,
        omega0,
        [0.8, 0.1, -0.3, 0.5],
        t_end,
        frames,
        1e-3,
    )
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Both regimes in all six axis orderings, near and far from the separatrix.
#[test]
fn exact_matches_rk4_in_both_regimes_and_every_ordering() {
    let cases = [
        (PAPER, [0.01, 0.01, 1.0]),
        (PAPER, [0.01, 0.1, 0.03]),
        (PAPER, [0.01, 0.01, 0.03]),
        ([1.0, 2.0, 3.0], [0.3, -0.5, 0.7]),
        ([3.0, 1.0, 2.0], [-0.3, 0.5, -0.9]),
        ([1.0, 3.0, 2.0], [-0.7, 0.2, 0.4]),
        ([2.0, 3.0, 1.0], [0.7, -0.2, 0.4]),
        ([3.0, 2.0, 1.0], [0.1, -0.9, 0.4]),
        ([2.0, 1.0, 3.0], [1.1, 0.2, -0.3]),
    ];
    for (inertia, omega0) in cases {
        let exact = run(Method::Exact, inertia, omega0, 30.0, 31);
        let rk4 = run(Method::Rk4, inertia, omega0, 30.0, 31);
        // RK4 at dt = 1e-3 is good to about 1e-12 over this span
        assert!(
            max_diff(&exact.omega, &rk4.omega) < 2e-12,
            "{inertia:?} {omega0:?}"
        );
        assert!(max_diff(&exact.q, &rk4.q) < 2e-12, "{inertia:?} {omega0:?}");
        assert_eq!(exact.flip_times.len(), rk4.flip_times.len());
        for (a, b) in exact.flip_times.iter().zip(&rk4.flip_times) {
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
        assert_eq!(exact.stats.n_steps, 0);
        assert_eq!(exact.stats.nfev, 0);
    }
}

#[test]
fn invariants_hold_to_round_off_at_t_1e6() {
    for (inertia, omega0) in [
        (PAPER, [5e-6, 5e-6, 1.0]),
        ([1.0, 2.0, 3.0], [0.3, -0.5, 0.7]),
    ] {
        let body = RigidBody::try_new(inertia).unwrap();
        let motion = ExactMotion::try_new(&body, omega0, [0.8, 0.1, -0.3, 0.5]).unwrap();
        let i = body.inertia_body();
        let first = Invariants::of(&i, &motion.state_at(0.0));
        for t in [1e3, 123_456.7, 1e6] {
            let now = Invariants::of(&i, &motion.state_at(t));
            assert_relative_eq!(now.energy, first.energy, max_relative = 8e-16);
            assert_relative_eq!(now.l_body.norm(), first.l_body.norm(), max_relative = 8e-16);
            let l = first.l_body.norm();
            assert!((now.l_world - first.l_world).norm() < 8e-16 * l);
            assert_relative_eq!(now.q_norm, 1.0, epsilon = 4e-16);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// x(t1 + t2; x0) = x(t2; x(t1; x0)): a late state, refitted from scratch, continues the
    /// same motion. Any error in the phase, the period or the angle about L breaks this.
    #[test]
    fn restarting_from_a_later_state_continues_the_motion(
        a in 0.2..2.0f64, b in 0.2..2.0f64, c in 0.2..2.0f64,
        w in prop::array::uniform3(-2.0..2.0f64),
        t1 in 0.0..500.0f64, t2 in 0.0..50.0f64,
    ) {
        let body = RigidBody::try_new([b + c, a + c, a + b]).unwrap();
        prop_assume!(w.iter().map(|x| x.abs()).fold(0.0, f64::max) > 0.1);
        let q0 = [0.3, -0.4, 0.5, 0.7];
        let motion = ExactMotion::try_new(&body, w, q0).unwrap();
        let mid = motion.state_at(t1);
        let rest = ExactMotion::try_new(&body, [mid[0], mid[1], mid[2]], [mid[3], mid[4], mid[5], mid[6]])
            .unwrap()
            .state_at(t2);
        let far = motion.state_at(t1 + t2);
        let scale = w.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for k in 0..3 {
            prop_assert!((rest[k] - far[k]).abs() < 1e-11 * scale, "{rest:?} {far:?}");
        }
        for k in 3..7 {
            prop_assert!((rest[k] - far[k]).abs() < 1e-11, "{rest:?} {far:?}");
        }
    }
}

#[test]
fn flip_period_is_the_spacing_of_rk4_flips() {
    for (inertia, omega0) in [
        (PAPER, [0.01, 0.01, 1.0]),
        ([1.0, 2.0, 3.0], [0.05, 1.0, 0.3]),
    ] {
        let body = RigidBody::try_new(inertia).unwrap();
        let period = flip_period(&body, omega0).unwrap();
        let rk4 = run(Method::Rk4, inertia, omega0, 4.5 * period, 11);
        assert!(rk4.flip_times.len() >= 3);
        for pair in rk4.flip_times.windows(2) {
            assert_relative_eq!(pair[1] - pair[0], period, max_relative = 1e-8);
        }
    }
}

#[test]
fn flip_period_is_infinite_when_nothing_flips() {
    let body = RigidBody::try_new(PAPER).unwrap();
    assert!(flip_period(&body, [0.0, 0.0, 1.0]).unwrap().is_infinite()); // on an axis
    assert!(flip_period(&body, [0.01, 0.1, 0.03]).unwrap().is_infinite()); // stable wobble
    let top = RigidBody::try_new([2.0, 2.0, 3.0]).unwrap();
    assert!(flip_period(&top, [0.3, 1.0, 0.2]).unwrap().is_infinite()); // symmetric top
                                                                        // the separatrix: L² − 2E Iy = 2.25·0.25·1 − 1·1·0.5625 = 0 exactly
    let body = RigidBody::try_new([1.0, 2.0, 2.25]).unwrap();
    assert!(flip_period(&body, [0.75, -2.0, 1.0]).unwrap().is_infinite());
    let out = run(Method::Exact, [1.0, 2.0, 2.25], [0.75, -2.0, 1.0], 1e4, 3);
    assert_eq!(out.flip_times.len(), 1);
}

#[test]
fn symmetric_top_turns_its_rates_in_the_body_at_omega() {
    let (i, i3) = (2.0, 3.5);
    let omega0 = Vector3::new(0.6, -0.4, 1.3);
    let big_omega = (i3 - i) * omega0.z / i;
    let out = run(Method::Exact, [i, i, i3], omega0.into(), 100.0, 11);
    for f in 0..11 {
        let t = 10.0 * f as f64;
        let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), big_omega * t);
        let expected = turn * omega0;
        for k in 0..3 {
            assert!((out.omega[3 * f + k] - expected[k]).abs() < 1e-13);
        }
    }
    let rk4 = run(Method::Rk4, [i, i, i3], omega0.into(), 10.0, 11);
    let exact = run(Method::Exact, [i, i, i3], omega0.into(), 10.0, 11);
    assert!(max_diff(&exact.q, &rk4.q) < 1e-11);
    assert!(exact.flip_times.is_empty());
}

#[test]
fn bad_input_and_cancel_are_errors() {
    let body = RigidBody::try_new(PAPER).unwrap();
    assert!(ExactMotion::try_new(&body, [f64::NAN, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]).is_err());
    assert!(ExactMotion::try_new(&body, [0.1, 0.0, 1.0], [0.0; 4]).is_err());
    let grid = FrameGrid::try_frames(10.0, 11).unwrap();
    let cancel = AtomicBool::new(true);
    let out = simulate(
        &body,
        [0.01, 0.01, 1.0],
        [1.0, 0.0, 0.0, 0.0],
        &grid,
        Method::Exact,
        KEEP_ALL,
        &cancel,
    );
    assert_eq!(out.unwrap_err(), Error::Interrupted);
    let grid = FrameGrid::try_frames(1e13, 2).unwrap();
    let out = simulate(
        &body,
        [0.01, 0.01, 1.0],
        [1.0, 0.0, 0.0, 0.0],
        &grid,
        Method::Exact,
        KEEP_ALL,
        &AtomicBool::new(false),
    );
    assert!(matches!(out, Err(Error::TooLarge { .. })));
}
