//! The models beyond the constant free body: deployments and damped bodies, run by the methods
//! that may run them, checked against what the code cannot fake (the constant body's own run,
//! conserved quantities, the energy balance, the major-axis rule).

use std::sync::atomic::AtomicBool;

use nalgebra::{Matrix3, Vector3};

use dzhanibekov::body::Inertia;
use dzhanibekov::dynamics::{Damper, Deployment, Kinds, System, SystemBody};
use dzhanibekov::ode::controller::Adaptive;
use dzhanibekov::run::{simulate, simulate_system, FrameGrid, Keep, Method, RunOutput};
use dzhanibekov::RigidBody;

fn no_cancel() -> AtomicBool {
    AtomicBool::new(false)
}

/// A run's output and what its system says of each frame: the energy and `L` in space.
struct Run {
    out: RunOutput,
    energy: Vec<f64>,
    momentum_world: Vec<Vector3<f64>>,
}

fn run(system: &System, omega0: [f64; 3], grid: &FrameGrid, method: Method, flips: bool) -> Run {
    run_from(system, omega0, [1.0, 0.0, 0.0, 0.0], grid, method, flips)
}

fn run_from(
    system: &System,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    flips: bool,
) -> Run {
    let keep = Keep {
        frames: true,
        flips,
        tilt: false,
    };
    let out = simulate_system(system, omega0, q0, grid, method, keep, &no_cancel()).unwrap();
    let width = system.parts_width();
    let (mut energy, mut momentum_world) = (Vec::new(), Vec::new());
    for i in 0..grid.frames() {
        let w = [out.omega[3 * i], out.omega[3 * i + 1], out.omega[3 * i + 2]];
        let q = [
            out.q[4 * i],
            out.q[4 * i + 1],
            out.q[4 * i + 2],
            out.q[4 * i + 3],
        ];
        let parts = &out.parts[width * i..width * (i + 1)];
        let (e, _, l) = system.observe(grid.time(i), w, parts, q);
        energy.push(e);
        momentum_world.push(l);
    }
    Run {
        out,
        energy,
        momentum_world,
    }
}

fn deployment(d: Deployment) -> System {
    System::try_new(SystemBody::Deployment(d), vec![]).unwrap()
}

fn damped(tensor: Matrix3<f64>, sphere: f64, damping: f64, sigma0: Option<[f64; 3]>) -> System {
    let mut damper = Damper::try_new(sphere, damping).unwrap();
    if let Some(s) = sigma0 {
        damper = damper.starting_at(s).unwrap();
    }
    let body = SystemBody::Rigid(Inertia::try_new(tensor).unwrap());
    System::try_new(body, vec![damper.into()]).unwrap()
}

fn diag(m: [f64; 3]) -> Matrix3<f64> {
    Matrix3::from_diagonal(&m.into())
}

fn tight() -> Adaptive {
    Adaptive::try_new(1e-13, 1e-15).unwrap()
}

/// `max_i |L_world(i) − L_world(0)| / |L_world(0)|`.
fn momentum_drift(run: &Run) -> f64 {
    let l0 = run.momentum_world[0];
    run.momentum_world
        .iter()
        .map(|l| (l - l0).norm() / l0.norm())
        .fold(0.0, f64::max)
}

#[test]
fn a_deployment_with_equal_knots_is_the_constant_body() {
    let moments = [52.0833, 27.0833, 41.6666];
    let d = Deployment::try_new(vec![1.0, 2.0, 5.0], vec![diag(moments); 3]).unwrap();
    let grid = FrameGrid::try_new(50.0, 101, 1e-3, u64::MAX).unwrap();
    let (omega0, q0) = ([0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]);
    let out = run(&deployment(d), omega0, &grid, Method::Rk4, false).out;
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
    let d = deployment(Deployment::try_new(vec![2.0, 6.0], vec![a, b]).unwrap());
    let (w0, q0) = ([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.2]);
    let grid = FrameGrid::try_new(20.0, 201, 1e-4, u64::MAX).unwrap();
    let rk4 = run_from(&d, w0, q0, &grid, Method::Rk4, false);
    assert!(momentum_drift(&rk4) < 1e-12, "{:e}", momentum_drift(&rk4));
    let dop = run_from(&d, w0, q0, &grid, Method::Dop853(tight()), false);
    assert!(momentum_drift(&dop) < 1e-12, "{:e}", momentum_drift(&dop));
    let proj = FrameGrid::try_new(20.0, 201, 1e-2, u64::MAX).unwrap();
    let p = run_from(&d, w0, q0, &proj, Method::Rk4Projected, false);
    assert!(momentum_drift(&p) < 1e-13, "{:e}", momentum_drift(&p));
    // energy changed (it is not an invariant here), and the methods agree on it
    let (e0, e1) = (rk4.energy[0], *rk4.energy.last().unwrap());
    assert!((e1 - e0).abs() > 1e-2 * e0);
    assert!((e1 - dop.energy.last().unwrap()).abs() < 1e-10 * e0);
}

/// Share of |L| on body axis `k` at each frame, from the rates and the known moments.
fn spin_share(out: &RunOutput, d: &Deployment, grid: &FrameGrid, k: usize) -> Vec<f64> {
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
    let grid = FrameGrid::try_new(300.0, 3001, 1e-3, u64::MAX).unwrap();
    let out = run(
        &deployment(d.clone()),
        [0.01, 0.01, 1.0],
        &grid,
        Method::Rk4,
        false,
    )
    .out;
    let share = spin_share(&out, &d, &grid, 2);
    let before = share[..1000].iter().cloned().fold(f64::INFINITY, f64::min);
    let after = share[1100..].iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(before > 0.999, "stowed: z keeps {before} of |L|");
    assert!(after < -0.9, "deployed: z turns over, down to {after}");
}

fn explorer(sigma0: [f64; 3]) -> System {
    // a long cylinder spun about its axis (z, minor) with a damper
    damped(diag([10.0, 9.0, 1.0]), 0.2, 0.05, Some(sigma0))
}

#[test]
fn a_damped_minor_axis_spin_goes_flat_about_the_major_axis() {
    let d = explorer([0.01, 0.0, 2.0]);
    let grid = FrameGrid::try_new(1500.0, 1501, 5e-3, u64::MAX).unwrap();
    for method in [Method::Rk4, Method::Rk4Projected] {
        let r = run(&d, [0.01, 0.0, 2.0], &grid, method, false);
        assert!(momentum_drift(&r) < 1e-9, "{:e}", momentum_drift(&r));
        // energy never rises (beyond round-off)
        let rises = r
            .energy
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::MIN, f64::max);
        assert!(rises < 1e-12 * r.energy[0], "energy rose by {rises:e}");
        // final: spin about x (the major axis), the sphere co-rotating
        let out = r.out;
        let n = out.omega.len();
        let w = &out.omega[n - 3..];
        let l = [10.0 * w[0], 9.0 * w[1], 1.0 * w[2]];
        let norm = l.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(l[0].abs() / norm > 0.999, "{l:?}");
        let s = &out.parts[n - 3..];
        assert!((0..3).all(|k| (s[k] - w[k]).abs() < 1e-3 * norm / 10.0));
    }
}

#[test]
fn a_damped_major_axis_spin_stays() {
    let d = explorer([0.2, 0.0, 0.0]);
    let grid = FrameGrid::try_new(2000.0, 201, 1e-2, u64::MAX).unwrap();
    let out = run(
        &d,
        [0.2, 0.001, 0.001],
        &grid,
        Method::Dopri5(tight()),
        false,
    )
    .out;
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
        for (model, kind) in [("deployment", Kinds::DEPLOYMENT), ("damper", Damper::KIND)] {
            let e = method.for_kinds(kind).unwrap_err().to_string();
            assert!(
                e.contains(&format!("'{}'", method.name())) && e.contains(model),
                "{e}"
            );
            assert!(e.contains("'rk4'") && e.contains("'dop853'"), "{e}");
        }
    }
    for method in ["rk4", "rk4_projected", "dopri5", "dop853"] {
        let m: Method = method.parse().unwrap();
        assert!(m.for_kinds(Damper::KIND).is_ok());
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
    let keep_scaled = |out: &RunOutput, unit: &RunOutput, s: f64| {
        let check = |a: &[f64], b: &[f64], p: f64| {
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(b) {
                assert_eq!(*x, y * p, "{x} vs {y} × {p}");
            }
        };
        check(&out.omega, &unit.omega, s);
        check(&out.parts, &unit.parts, s);
        check(&out.flip_times, &unit.flip_times, 1.0 / s);
        assert_eq!(out.q, unit.q);
        assert_eq!(out.dt, unit.dt / s);
        assert_eq!(out.stats, unit.stats);
        assert_eq!(out.drift, unit.drift);
    };
    for e in [-997, 997] {
        let s = 2f64.powi(e);
        for method in [Method::Rk4, Method::Dop853(tight())] {
            let times = |t: &[f64]| t.iter().map(|t| t / s).collect::<Vec<_>>();
            let knots = vec![diag([1.0, 2.0, 3.0]), diag([1.0, 3.0, 2.0])];
            let d = deployment(Deployment::try_new(vec![10.0, 20.0], knots.clone()).unwrap());
            let d_s = deployment(Deployment::try_new(times(&[10.0, 20.0]), knots).unwrap());
            let grid = FrameGrid::try_new(40.0, 9, 1e-2, u64::MAX).unwrap();
            let grid_s = FrameGrid::try_new(40.0 / s, 9, 1e-2 / s, u64::MAX).unwrap();
            let unit = run_from(&d, omega0, q0, &grid, method, true).out;
            let w_s = omega0.map(|w| w * s);
            let out = run_from(&d_s, w_s, q0, &grid_s, method, true).out;
            keep_scaled(&out, &unit, s);

            let body = diag([1.0, 2.0, 3.0]);
            let damped_1 = damped(body, 0.1, 0.05, Some([0.0; 3]));
            let damped_s = damped(body, 0.1, 0.05 * s, Some([0.0; 3]));
            let unit = run(&damped_1, [0.9, 0.1, 0.1], &grid, method, false).out;
            let out = run(
                &damped_s,
                [0.9 * s, 0.1 * s, 0.1 * s],
                &grid_s,
                method,
                false,
            )
            .out;
            keep_scaled(&out, &unit, s);
        }
    }
}

/// A rotation of the body's own axes: `R` (user from principal) and the tensor `R D Rᵀ`.
fn turned(moments: [f64; 3]) -> (Matrix3<f64>, Matrix3<f64>) {
    let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
    (r, r * diag(moments) * r.transpose())
}

/// The same damped body given in principal axes and as a turned tensor is the same motion:
/// the run changes to principal axes at its edges, so the frames agree once turned (to
/// round-off), and the flips, located for any tensor, come at the same times.
#[test]
fn a_damped_body_given_by_a_turned_tensor_is_the_same_motion() {
    let moments = [3.0, 2.0, 1.0]; // spun about y, the intermediate axis: it flips
    let (r, tensor) = turned(moments);
    let w = [0.01, 1.0, 0.01];
    let principal = damped(diag(moments), 0.01, 1e-4, None);
    let user = damped(tensor, 0.01, 1e-4, None);
    let grid = FrameGrid::try_new(60.0, 61, 1e-3, u64::MAX).unwrap();
    let a = run(&principal, w, &grid, Method::Rk4, true).out;
    let w_user: [f64; 3] = (r * Vector3::from(w)).into();
    let b = run(&user, w_user, &grid, Method::Rk4, true).out;
    assert!(!a.flip_times.is_empty());
    assert_eq!(a.flip_times.len(), b.flip_times.len());
    for (x, y) in a.flip_times.iter().zip(&b.flip_times) {
        assert!((x - y).abs() < 1e-8, "{x} vs {y}");
    }
    for i in 0..grid.frames() {
        let wa = Vector3::from_column_slice(&a.omega[3 * i..3 * i + 3]);
        let wb = Vector3::from_column_slice(&b.omega[3 * i..3 * i + 3]);
        assert!((r * wa - wb).amax() < 1e-8, "frame {i}");
    }
}

/// A deployment through tensors that are not diagonal tumbles once its spin axis has become
/// the intermediate one, and the flips are located (on the intermediate eigenvector of I(t));
/// after the last knot they come every flip period of the deployed body (closed form).
#[test]
fn flips_are_located_for_a_deployment_of_turned_tensors() {
    let (r, stowed) = turned([1.0, 2.0, 3.0]);
    let (_, deployed) = turned([1.0, 3.0, 2.0]);
    let d = deployment(Deployment::try_new(vec![10.0, 20.0], vec![stowed, deployed]).unwrap());
    let spin: [f64; 3] = (r * Vector3::new(0.01, 0.01, 1.0)).into();
    let grid = FrameGrid::try_new(300.0, 301, 1e-3, u64::MAX).unwrap();
    let out = run(&d, spin, &grid, Method::Rk4, true).out;
    let flips = &out.flip_times;
    assert!(flips.len() >= 5, "{flips:?}");
    assert!(
        flips[0] > 20.0,
        "no flip while z is the major axis: {flips:?}"
    );
    // the deployed body's motion from the state at the end, in its principal axes
    let w_end = r.transpose() * Vector3::from(out.end.omega);
    let body = RigidBody::try_new([1.0, 3.0, 2.0]).unwrap();
    let period = dzhanibekov::exact::flip_period(&body, w_end.into()).unwrap();
    for pair in flips[1..].windows(2) {
        assert!(
            ((pair[1] - pair[0]) - period).abs() < 1e-4 * period,
            "{pair:?} vs {period}"
        );
    }
}
