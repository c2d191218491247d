//! Physics of the core, checked against closed forms and conservation laws.

use std::sync::atomic::AtomicBool;

use approx::assert_relative_eq;
use dzhanibekov::kinematics::rotation_matrix;
use dzhanibekov::run::{simulate, FrameGrid, Method, RunOutput};
use dzhanibekov::{Error, RigidBody};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use proptest::prelude::*;

mod common;
use common::KEEP_ALL;

/// An RK4 run (the core engine's tests).
fn run(
    inertia: [f64; 3],
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    dt: f64,
) -> RunOutput {
    common::run(Method::Rk4, inertia, omega0, q0, t_end, frames, dt)
}

fn quaternion(q: &[f64]) -> Quaternion<f64> {
    Quaternion::new(q[0], q[1], q[2], q[3])
}

/// A symmetric top (I1 = I2 = I): ω⊥ turns in the body at Ω = (I3 − I) ω3 / I, and the
/// attitude is q(t) = exp(t L_world / 2I) ⊗ q0 ⊗ exp(−Ω t e3 / 2).
fn symmetric_top(
    i: f64,
    i3: f64,
    omega0: Vector3<f64>,
    q0: UnitQuaternion<f64>,
    t: f64,
) -> (Vector3<f64>, UnitQuaternion<f64>) {
    let big_omega = (i3 - i) * omega0.z / i;
    let body_turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), big_omega * t);
    let omega = body_turn * omega0;
    let l_world = q0 * Vector3::new(i * omega0.x, i * omega0.y, i3 * omega0.z);
    let space_turn = UnitQuaternion::from_scaled_axis(l_world * (t / i));
    (omega, space_turn * q0 * body_turn.inverse())
}

/// Max error in ω and q against the symmetric top's closed form, with sign-fixed quaternions.
fn symmetric_top_error(dt: f64) -> f64 {
    let (i, i3) = (2.0, 3.5);
    let omega0 = Vector3::new(0.6, -0.4, 1.3);
    let q0 = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1);
    let c = q0.into_inner();
    let out = run(
        [i, i, i3],
        omega0.into(),
        [c.w, c.i, c.j, c.k],
        10.0,
        11,
        dt,
    );
    (0..11)
        .map(|f| {
            let (omega, q) = symmetric_top(i, i3, omega0, q0, f as f64);
            let got_omega = Vector3::from_column_slice(&out.omega[3 * f..3 * f + 3]);
            let got_q = quaternion(&out.q[4 * f..4 * f + 4]);
            let dq = (got_q - q.into_inner())
                .norm()
                .min((got_q + q.into_inner()).norm());
            (got_omega - omega).amax().max(dq)
        })
        .fold(0.0, f64::max)
}

#[test]
fn symmetric_top_follows_its_closed_form() {
    assert!(symmetric_top_error(1e-3) < 1e-11);
}

#[test]
fn error_ratio_is_near_sixteen_when_the_step_halves() {
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&dt| symmetric_top_error(dt))
        .collect();
    for pair in errors.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (14.0..18.0).contains(&ratio),
            "ratio {ratio}, errors {errors:?}"
        );
    }
}

#[test]
fn world_momentum_energy_and_norm_are_kept() {
    let inertia = [52.0833, 27.0833, 41.6666];
    let out = run(
        inertia,
        [0.01, 0.01, 1.0],
        [1.0, 0.0, 0.0, 0.0],
        200.0,
        401,
        1e-3,
    );
    let i = Vector3::from(inertia);
    let at = |f: usize| {
        let omega = Vector3::from_column_slice(&out.omega[3 * f..3 * f + 3]);
        let q = quaternion(&out.q[4 * f..4 * f + 4]);
        (
            0.5 * omega.dot(&i.component_mul(&omega)),
            rotation_matrix(&q) * i.component_mul(&omega),
            q.norm(),
        )
    };
    let (e0, l0, _) = at(0);
    for f in 1..401 {
        let (e, l, n) = at(f);
        assert_relative_eq!(e, e0, max_relative = 1e-11);
        assert!((l - l0).norm() < 1e-11 * l0.norm());
        assert_relative_eq!(n, 1.0, epsilon = 1e-11);
    }
    assert!(
        out.drift.energy < 1e-11 && out.drift.momentum_world < 1e-11 && out.drift.q_norm < 1e-11
    );
}

#[test]
fn spin_about_the_intermediate_axis_flips_and_the_others_do_not() {
    let inertia = [3.0, 2.0, 1.0];
    let flips = |omega0| {
        run(inertia, omega0, [1.0, 0.0, 0.0, 0.0], 100.0, 2, 1e-2)
            .flip_times
            .len()
    };
    assert!(flips([0.01, 1.0, 0.01]) >= 3);
    assert_eq!(flips([1.0, 0.01, 0.01]), 0);
    assert_eq!(flips([0.01, 0.01, 1.0]), 0);
}

#[test]
fn flips_alternate_the_signal_axis_between_hemispheres() {
    // Spin about the intermediate axis y: the body's y axis points along L at t = 0, against
    // it after the first flip, along it again after the second.
    let out = run(
        [3.0, 2.0, 1.0],
        [0.001, 1.0, 0.001],
        [1.0, 0.0, 0.0, 0.0],
        60.0,
        601,
        1e-3,
    );
    let flips = &out.flip_times;
    assert!(flips.len() >= 2);
    let y_world = |t: f64| {
        let f = (t * 10.0).round() as usize;
        (rotation_matrix(&quaternion(&out.q[4 * f..4 * f + 4])) * Vector3::y()).y
    };
    let mid = 0.5 * (flips[0] + flips[1]);
    assert!(y_world(0.5 * flips[0]) > 0.9);
    assert!(y_world(mid) < -0.9);
}

#[test]
fn cancel_stops_the_run() {
    let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
    let grid = FrameGrid::try_new(1e6, 2, 1e-3, u64::MAX).unwrap();
    let cancel = AtomicBool::new(true);
    let err = simulate(
        &body,
        [0.1, 0.2, 0.3],
        [1.0, 0.0, 0.0, 0.0],
        &grid,
        Method::Rk4,
        KEEP_ALL,
        &cancel,
    )
    .unwrap_err();
    assert_eq!(err, Error::Interrupted);
}

#[test]
fn bad_arguments_name_themselves() {
    let msg = |e: Error| e.to_string();
    assert!(msg(FrameGrid::try_new(-1.0, 2, 1e-3, 10).unwrap_err()).contains("`t_end`"));
    assert!(msg(FrameGrid::try_new(1.0, 1, 1e-3, 10).unwrap_err()).contains("`frames`"));
    assert!(msg(FrameGrid::try_new(1.0, 2, f64::NAN, 10).unwrap_err()).contains("`dt`"));
    assert!(msg(FrameGrid::try_new(1.0, 2, 1e-3, 10).unwrap_err()).contains("max_steps"));
    assert!(msg(RigidBody::try_new([1.0, f64::INFINITY, 1.0]).unwrap_err()).contains("`inertia`"));
    let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
    let grid = FrameGrid::try_new(1.0, 2, 1e-3, 10_000).unwrap();
    let cancel = AtomicBool::new(false);
    let bad_q = simulate(
        &body,
        [0.0; 3],
        [0.0; 4],
        &grid,
        Method::Rk4,
        KEEP_ALL,
        &cancel,
    );
    assert!(msg(bad_q.unwrap_err()).contains("`q0`"));
    let bad_omega = simulate(
        &body,
        [f64::NAN, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        &grid,
        Method::Rk4,
        KEEP_ALL,
        &cancel,
    );
    assert!(msg(bad_omega.unwrap_err()).contains("`omega0`"));
    assert!(msg("euler".parse::<Method>().unwrap_err()).contains("`method`"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Over random bodies (ratios up to 10⁴) and states, with a step small against the
    /// fastest rate, RK4 keeps the invariants to well below its truncation budget.
    #[test]
    fn invariants_hold_for_random_bodies(
        log_i in prop::array::uniform3(-2.0f64..2.0),
        omega0 in prop::array::uniform3(-1.0f64..1.0),
        q0 in prop::array::uniform4(-1.0f64..1.0),
    ) {
        prop_assume!(q0.iter().map(|c| c * c).sum::<f64>() > 1e-3);
        let inertia = log_i.map(|l| 10f64.powf(l));
        let body = RigidBody::try_new(inertia).unwrap();
        // the fastest rate of the body is bounded by |ω| times the largest moment ratio
        let ratio = inertia.iter().cloned().fold(0.0, f64::max) / inertia.iter().cloned().fold(f64::MAX, f64::min);
        let rate = Vector3::from(omega0).norm() * ratio.max(1.0);
        let dt = 0.01 / rate.max(1e-3);
        let grid = FrameGrid::try_new(2000.0 * dt, 11, dt, u64::MAX).unwrap();
        let out = simulate(&body, omega0, q0, &grid, Method::Rk4, KEEP_ALL, &AtomicBool::new(false)).unwrap();
        prop_assert!(out.drift.q_norm < 1e-9, "{:?}", out.drift);
        prop_assert!(out.drift.energy < 1e-8, "{:?}", out.drift);
        prop_assert!(out.drift.momentum_world < 1e-8, "{:?}", out.drift);
        prop_assert!(out.omega.iter().chain(&out.q).all(|v| v.is_finite()));
    }
}
