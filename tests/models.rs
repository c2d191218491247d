//! The models beyond the constant free body: deployments and damped bodies, run by the methods
//! that may run them, checked against what the code cannot fake (the constant body's own run,
//! conserved quantities, the energy balance, the major-axis rule).

use std::sync::atomic::AtomicBool;

use nalgebra::Matrix3;

use dzhanibekov::dynamics::{DampedBody, Deployment};
use dzhanibekov::ode::controller::Adaptive;
use dzhanibekov::run::{simulate, simulate_model, FrameGrid, Keep, Method, ModelOutput};
use dzhanibekov::RigidBody;

fn no_cancel() -> AtomicBool {
    AtomicBool::new(false)
}

fn diag(m: [f64; 3]) -> Matrix3<f64> {
    Matrix3::from_diagonal(&m.into())
}

fn tight() -> Adaptive {
    Adaptive::try_new(1e-13, 1e-15).unwrap()
}

/// `max_i |L_world(i) − L_world(0)| / |L_world(0)|`.
fn momentum_drift(out: &ModelOutput) -> f64 {
    let l0 = &out.momentum_world[..3];
    let n0 = l0.iter().map(|v| v * v).sum::<f64>().sqrt();
    out.momentum_world
        .chunks(3)
        .map(|l| (0..3).map(|k| (l[k] - l0[k]).powi(2)).sum::<f64>().sqrt() / n0)
        .fold(0.0, f64::max)
}

#[test]
fn a_deployment_with_equal_knots_is_the_constant_body() {
    let moments = [52.0833, 27.0833, 41.6666];
    let d = Deployment::try_new(vec![1.0, 2.0, 5.0], vec![diag(moments); 3]).unwrap();
    let grid = FrameGrid::try_new(50.0, 101, 1e-3, u64::MAX).unwrap();
    let (omega0, q0) = ([0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]);
    let x0 = d.state_from(0.0, omega0, q0);
    let out = simulate_model(&d, x0, &grid, Method::Rk4, false, &no_cancel()).unwrap();
    let body = RigidBody::try_new(moments).unwrap();
    let keep = Keep {
        frames: true,
        flips: false,
        tilt: false,
    };
    let free = simulate(&body, omega0, q0, &grid, Method::Rk4, keep, &no_cancel()).unwrap();
    // Two roundings apart per step (L = Iω against ω), over 50 000 steps of a run that
    // crosses the separatrix: round-off, grown by the motion's sensitivity.
    let dw = out
        .omega
        .iter()
        .zip(&free.omega)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let dq = out
        .q
        .iter()
        .zip(&free.q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(dw < 1e-9 && dq < 1e-9, "dω = {dw:e}, dq = {dq:e}");
    assert_eq!(out.stats.n_steps, free.stats.n_steps);
}

#[test]
fn deployments_keep_the_momentum_in_space() {
    let a = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
    let b = Matrix3::new(5.0, 0.4, -0.2, 0.4, 3.5, 0.0, -0.2, 0.0, 2.5);
    let d = Deployment::try_new(vec![2.0, 6.0], vec![a, b]).unwrap();
    let x0 = d.state_from(0.0, [0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
    let grid = FrameGrid::try_new(20.0, 201, 1e-4, u64::MAX).unwrap();
    let rk4 = simulate_model(&d, x0, &grid, Method::Rk4, false, &no_cancel()).unwrap();
    assert!(momentum_drift(&rk4) < 1e-12, "{:e}", momentum_drift(&rk4));
    let dop = simulate_model(&d, x0, &grid, Method::Dop853(tight()), false, &no_cancel()).unwrap();
    assert!(momentum_drift(&dop) < 1e-12, "{:e}", momentum_drift(&dop));
    let proj = FrameGrid::try_new(20.0, 201, 1e-2, u64::MAX).unwrap();
    let p = simulate_model(&d, x0, &proj, Method::Rk4Projected, false, &no_cancel()).unwrap();
    assert!(momentum_drift(&p) < 1e-13, "{:e}", momentum_drift(&p));
    // energy changed (it is not an invariant here), and the methods agree on it
    let (e0, e1) = (rk4.energy[0], *rk4.energy.last().unwrap());
    assert!((e1 - e0).abs() > 1e-2 * e0);
    assert!((e1 - dop.energy.last().unwrap()).abs() < 1e-10 * e0);
}

/// Share of |L| on body axis `k` at each frame, from the rates and the known moments.
fn spin_share(out: &ModelOutput, d: &Deployment, grid: &FrameGrid, k: usize) -> Vec<f64> {
    (0..grid.frames())
        .map(|i| {
            let w = nalgebra::Vector3::from_column_slice(&out.omega[3 * i..3 * i + 3]);
            let l = d.inertia_at(grid.time(i)) * w;
            l[k] / l.norm()
        })
        .collect()
}

#[test]
fn a_major_axis_spin_tumbles_once_deployed_to_intermediate() {
    // stowed (1, 2, 3): z is the major axis; deployed (1, 3, 2): z is intermediate
    let d =
        Deployment::from_moments(vec![100.0, 110.0], &[[1.0, 2.0, 3.0], [1.0, 3.0, 2.0]]).unwrap();
    let x0 = d.state_from(0.0, [0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]);
    let grid = FrameGrid::try_new(300.0, 3001, 1e-3, u64::MAX).unwrap();
    let out = simulate_model(&d, x0, &grid, Method::Rk4, false, &no_cancel()).unwrap();
    let share = spin_share(&out, &d, &grid, 2);
    let before = share[..1000].iter().cloned().fold(f64::INFINITY, f64::min);
    let after = share[1100..].iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(before > 0.999, "stowed: z keeps {before} of |L|");
    assert!(after < -0.9, "deployed: z turns over, down to {after}");
}

fn explorer() -> DampedBody {
    // a long cylinder spun about its axis (z, minor) with a damper
    DampedBody::try_new(diag([10.0, 9.0, 1.0]), 0.2, 0.05).unwrap()
}

#[test]
fn a_damped_minor_axis_spin_goes_flat_about_the_major_axis() {
    let d = explorer();
    let x0 = DampedBody::state_from([0.01, 0.0, 2.0], [0.01, 0.0, 2.0], [1.0, 0.0, 0.0, 0.0]);
    let grid = FrameGrid::try_new(1500.0, 1501, 5e-3, u64::MAX).unwrap();
    for method in [Method::Rk4, Method::Rk4Projected] {
        let out = simulate_model(&d, x0, &grid, method, false, &no_cancel()).unwrap();
        assert!(momentum_drift(&out) < 1e-9, "{:e}", momentum_drift(&out));
        // energy never rises (beyond round-off)
        let rises = out
            .energy
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::MIN, f64::max);
        assert!(rises < 1e-12 * out.energy[0], "energy rose by {rises:e}");
        // final: spin about x (the major axis), the sphere co-rotating
        let n = out.omega.len();
        let w = &out.omega[n - 3..];
        let l = [10.0 * w[0], 9.0 * w[1], 1.0 * w[2]];
        let norm = l.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(l[0].abs() / norm > 0.999, "{l:?}");
        let s = &out.extra[n - 3..];
        assert!((0..3).all(|k| (s[k] - w[k]).abs() < 1e-3 * norm / 10.0));
    }
}

#[test]
fn a_damped_major_axis_spin_stays() {
    let d = explorer();
    let x0 = DampedBody::state_from([0.2, 0.001, 0.001], [0.2, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    let grid = FrameGrid::try_new(2000.0, 201, 1e-2, u64::MAX).unwrap();
    let out = simulate_model(&d, x0, &grid, Method::Dopri5(tight()), false, &no_cancel()).unwrap();
    for w in out.omega.chunks(3) {
        assert!(w[0] / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt() > 0.9999);
    }
    // and the nutation died out
    let n = out.omega.len();
    assert!(out.omega[n - 2].abs() < 1e-5 && out.omega[n - 1].abs() < 1e-5);
}

#[test]
fn constant_body_methods_refuse_the_models_by_name() {
    for method in [Method::Exact, Method::Splitting, Method::Splitting4] {
        for model in ["deployment", "damper"] {
            let e = method.for_model(model).unwrap_err().to_string();
            assert!(
                e.contains(&format!("'{}'", method.name())) && e.contains(model),
                "{e}"
            );
            assert!(e.contains("'rk4'") && e.contains("'dop853'"), "{e}");
        }
    }
    for method in ["rk4", "rk4_projected", "dopri5", "dop853"] {
        let m: Method = method.parse().unwrap();
        assert!(m.for_model("damper").is_ok());
    }
}

/// Rates of 2^±997 (1e±300) with times scaled the other way are the same motion: Euler's
/// equations keep `(ω, t) → (sω, t/s)`, a deployment's knot times and a damper's coefficient
/// (a moment per unit time) scaling with `t`. Unscaled, such rates underflow or overflow in
/// the products; the run scales them by a power of two, so the frames are those of the run
/// at rates near 1, scaled, bit for bit.
#[test]
fn models_at_rates_near_the_ends_of_float64_are_the_scaled_motion() {
    let (omega0, q0) = ([0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]);
    let keep_scaled = |out: &ModelOutput, unit: &ModelOutput, s: f64| {
        let check = |a: &[f64], b: &[f64], p: f64| {
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(b) {
                assert_eq!(*x, y * p, "{x} vs {y} × {p}");
            }
        };
        check(&out.omega, &unit.omega, s);
        check(&out.momentum_world, &unit.momentum_world, s);
        check(&out.extra, &unit.extra, s);
        check(&out.energy, &unit.energy, s * s);
        assert_eq!(out.flip_times.is_some(), unit.flip_times.is_some());
        if let (Some(flips), Some(unit_flips)) = (&out.flip_times, &unit.flip_times) {
            check(flips, unit_flips, 1.0 / s);
        }
        assert_eq!(out.q, unit.q);
        assert_eq!(out.dt, unit.dt / s);
        assert_eq!(out.stats, unit.stats);
    };
    for e in [-997, 997] {
        let s = 2f64.powi(e);
        for method in [Method::Rk4, Method::Dop853(tight())] {
            let times = |t: &[f64]| t.iter().map(|t| t / s).collect::<Vec<_>>();
            let knots = vec![diag([1.0, 2.0, 3.0]), diag([1.0, 3.0, 2.0])];
            let d = Deployment::try_new(vec![10.0, 20.0], knots.clone()).unwrap();
            let d_s = Deployment::try_new(times(&[10.0, 20.0]), knots).unwrap();
            let grid = FrameGrid::try_new(40.0, 9, 1e-2, u64::MAX).unwrap();
            let grid_s = FrameGrid::try_new(40.0 / s, 9, 1e-2 / s, u64::MAX).unwrap();
            let unit = simulate_model(
                &d,
                d.state_from(0.0, omega0, q0),
                &grid,
                method,
                true,
                &no_cancel(),
            );
            let w_s = omega0.map(|w| w * s);
            let x_s = d_s.state_from(0.0, w_s, q0);
            let out = simulate_model(&d_s, x_s, &grid_s, method, true, &no_cancel());
            keep_scaled(&out.unwrap(), &unit.unwrap(), s);

            let body = diag([1.0, 2.0, 3.0]);
            let damped = DampedBody::try_new(body, 0.1, 0.05).unwrap();
            let damped_s = DampedBody::try_new(body, 0.1, 0.05 * s).unwrap();
            let x0 = DampedBody::state_from([0.9, 0.1, 0.1], [0.0; 3], q0);
            let x0_s = DampedBody::state_from([0.9 * s, 0.1 * s, 0.1 * s], [0.0; 3], q0);
            let unit = simulate_model(&damped, x0, &grid, method, false, &no_cancel()).unwrap();
            let out =
                simulate_model(&damped_s, x0_s, &grid_s, method, false, &no_cancel()).unwrap();
            keep_scaled(&out, &unit, s);
        }
    }
}
