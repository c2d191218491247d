//! The splittings on the exact free flow (`splitting_exact`, `splitting_exact4`) on a body in
//! the gravity gradient: their orders measured against DOP853 at `rtol = 1e-13` (a method of
//! another kind, at a tolerance far below the errors measured), `|q|` kept to round-off, and
//! with no torque the exact solution; under a tabulated torque (steps end on its knots) of
//! order 2 still.

use std::sync::atomic::AtomicBool;

use dzhanibekov::body::Inertia;
use dzhanibekov::dynamics::{
    AnyPart, ConstantTorque, Frame, GravityGradient, Outside, System, SystemBody, TabulatedTorque,
};
use dzhanibekov::run::{simulate, simulate_system, FrameGrid, Keep, Method, RunOutput};
use dzhanibekov::RigidBody;

const MOMENTS: [f64; 3] = [2.0, 3.0, 4.0];
const W0: [f64; 3] = [0.3, -0.7, 1.1];
const Q0: [f64; 4] = [0.6, -0.2, 0.7, 0.3];
const KEEP: Keep = Keep {
    frames: true,
    flips: false,
    tilt: false,
};

fn orbiting(torque: impl Into<AnyPart>) -> System {
    let body = Inertia::from_principal(RigidBody::try_new(MOMENTS).unwrap());
    System::try_new(SystemBody::Rigid(body), vec![torque.into()]).unwrap()
}

fn run(system: &System, method: Method, t_end: f64, dt: f64) -> RunOutput {
    let grid = FrameGrid::for_method(&method, t_end, 11, dt, u64::MAX).unwrap();
    simulate_system(system, W0, Q0, &grid, method, KEEP, &AtomicBool::new(false)).unwrap()
}

/// The largest difference of the rates and the quaternions over the frames.
fn distance(a: &RunOutput, b: &RunOutput) -> f64 {
    let omega = a.omega.iter().zip(&b.omega).map(|(x, y)| (x - y).abs());
    let q = a.q.iter().zip(&b.q).map(|(x, y)| (x - y).abs());
    omega.chain(q).fold(0.0, f64::max)
}

/// `log2` of the error ratios as the step halves, on the gravity gradient of rate 0.8 over
/// `t = 5` (about 0.6 orbits; the body turns at about 1.3 rad a unit time).
fn slopes(name: &str, steps: [f64; 3]) -> [f64; 2] {
    slopes_of(
        &orbiting(GravityGradient::try_new(0.8).unwrap()),
        name,
        steps,
    )
}

fn slopes_of(system: &System, name: &str, steps: [f64; 3]) -> [f64; 2] {
    let reference = run(
        system,
        Method::named("dop853", 1e-13, 1e-15, None).unwrap(),
        5.0,
        0.0,
    );
    let method: Method = name.parse().unwrap();
    let e = steps.map(|dt| distance(&run(system, method, 5.0, dt), &reference));
    assert!(
        e[2] > 1e-10,
        "{name}: {e:?} too close to the reference's own error"
    );
    [(e[0] / e[1]).log2(), (e[1] / e[2]).log2()]
}

#[test]
fn the_fourth_order_composition_is_of_order_four_in_the_gravity_gradient() {
    // from 0.1 on (hΩ ≈ 0.13); at 0.4 and 0.2 it is not yet asymptotic (slopes 2.4, 3.0)
    let s = slopes("splitting_exact4", [0.1, 0.05, 0.025]);
    assert!(s.iter().all(|p| (3.7..4.3).contains(p)), "{s:?}");
    assert_eq!(Method::SplittingExact4.order(), 4);
}

#[test]
fn strangs_splitting_is_of_order_two_in_the_gravity_gradient() {
    let s = slopes("splitting_exact", [0.1, 0.05, 0.025]);
    assert!(s.iter().all(|p| (1.9..2.1).contains(p)), "{s:?}");
}

#[test]
fn strangs_splitting_is_of_order_two_under_a_tabulated_torque() {
    // a body-axes torque with kinks at t = 1.03 and 2.71 and jumps at 0.5 and 4.2 (zero
    // outside): steps that straddled them would make the run of order 1
    let table = TabulatedTorque::try_new(
        vec![0.5, 1.03, 2.71, 4.2],
        vec![
            [0.2, -0.1, 0.3],
            [-0.4, 0.5, 0.1],
            [0.3, 0.2, -0.6],
            [0.1, -0.3, 0.2],
        ],
        Frame::Body,
        Outside::Zero,
    )
    .unwrap();
    let s = slopes_of(&orbiting(table), "splitting_exact", [0.1, 0.05, 0.025]);
    assert!(s.iter().all(|p| (1.8..2.2).contains(p)), "{s:?}");
}

#[test]
fn the_splittings_keep_the_quaternions_norm_to_round_off() {
    let system = orbiting(GravityGradient::try_new(0.8).unwrap());
    for method in [Method::SplittingExact, Method::SplittingExact4] {
        let out = run(&system, method, 200.0, 0.1);
        let worst = out.q.chunks_exact(4).fold(0.0_f64, |m, q| {
            m.max((q.iter().map(|c| c * c).sum::<f64>().sqrt() - 1.0).abs())
        });
        assert!(worst < 1e-14, "{}: {worst:e}", method.name());
    }
}

#[test]
fn with_no_torque_the_splittings_are_the_exact_solution() {
    let zero = orbiting(ConstantTorque::try_new([0.0; 3], Frame::Body).unwrap());
    let body = RigidBody::try_new(MOMENTS).unwrap();
    let grid = FrameGrid::for_method(&Method::Exact, 20.0, 11, 0.0, u64::MAX).unwrap();
    let exact = simulate(
        &body,
        W0,
        Q0,
        &grid,
        Method::Exact,
        KEEP,
        &AtomicBool::new(false),
    );
    let exact = exact.unwrap();
    for method in [Method::SplittingExact, Method::SplittingExact4] {
        let split = run(&zero, method, 20.0, 0.5);
        let d = distance(&split, &exact);
        assert!(d < 1e-11, "{}: {d:e}", method.name());
    }
}
