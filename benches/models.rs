//! Criterion benches of the models beyond the constant free body, per RK4 step, beside the
//! free body's: `cargo bench --bench models` (`-- --quick` for a short pass). The orbit's
//! models (a wheel, the gravity gradient, constant torques in body and world axes; issue 21's
//! bar: at most 2× the free body per RK4 step) run the same body and start as the free body.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Matrix3;

use dzhanibekov::body::Inertia;
use dzhanibekov::dynamics::{
    AnyPart, ConstantTorque, Damper, Deployment, Fields, Frame, GravityGradient, Hinge, Part,
    Slosh, SpringMass, System, SystemBody, Value, Wheel,
};
use dzhanibekov::run::{simulate, simulate_system, FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;

fn models(c: &mut Criterion) {
    let cancel = AtomicBool::new(false);
    let steps = 1_000_000u64;
    let grid = FrameGrid::try_new(steps as f64 * 1e-3, 201, 1e-3, u64::MAX).unwrap();
    let mut group = c.benchmark_group("models_rk4");
    group.sample_size(10);
    group.throughput(Throughput::Elements(grid.n_steps()));
    let moments = [1.0, 2.0, 3.0];
    let body = RigidBody::try_new(moments).unwrap();
    let keep = Keep {
        frames: true,
        flips: false,
        tilt: false,
    };
    group.bench_with_input(BenchmarkId::new("free", steps), &grid, |b, grid| {
        b.iter(|| {
            let omega0 = black_box([0.01, 0.01, 1.0]);
            simulate(
                &body,
                omega0,
                [1.0, 0.0, 0.0, 0.0],
                grid,
                Method::Rk4,
                keep,
                &cancel,
            )
            .unwrap()
        })
    });
    let diagonal =
        Deployment::from_moments(vec![100.0, 110.0], &[moments, [1.0, 3.0, 2.0]]).unwrap();
    let tilted = Matrix3::new(1.0, 0.1, 0.0, 0.1, 3.0, -0.2, 0.0, -0.2, 2.0);
    let tensor = Deployment::try_new(
        vec![100.0, 110.0],
        vec![Matrix3::from_diagonal(&moments.into()), tilted],
    )
    .unwrap();
    let damper: AnyPart = Damper::try_new(0.05, 0.02).unwrap().into();
    let rigid = || SystemBody::Rigid(Inertia::from_principal(body));
    let wheel = || AnyPart::from(Wheel::try_new([0.0, 1.0, 0.0], 0.5).unwrap());
    let torqued = |mut parts: Vec<AnyPart>, torque: AnyPart| {
        parts.push(torque);
        System::try_new(rigid(), parts).unwrap()
    };
    let gravity: AnyPart = GravityGradient::try_new(0.1).unwrap().into();
    let moving = |part: AnyPart| {
        System::try_new(rigid(), vec![part])
            .unwrap()
            .with_mass(Some(5.0))
            .unwrap()
    };
    let systems = [
        ("wheel", System::try_new(rigid(), vec![wheel()]).unwrap()),
        ("gravity_gradient", torqued(vec![], gravity.clone())),
        ("wheel_gravity_gradient", torqued(vec![wheel()], gravity)),
        (
            "torque_body",
            torqued(
                vec![],
                ConstantTorque::try_new([0.0, 0.0, 1e-4], Frame::Body)
                    .unwrap()
                    .into(),
            ),
        ),
        (
            "torque_world",
            torqued(
                vec![],
                ConstantTorque::try_new([0.0, 0.0, 1e-4], Frame::World)
                    .unwrap()
                    .into(),
            ),
        ),
        (
            "deployment_diagonal",
            System::try_new(SystemBody::Deployment(diagonal), vec![]).unwrap(),
        ),
        (
            "deployment_tensor",
            System::try_new(SystemBody::Deployment(tensor), vec![]).unwrap(),
        ),
        (
            "damper",
            System::try_new(
                SystemBody::Rigid(Inertia::from_principal(body)),
                vec![damper],
            )
            .unwrap(),
        ),
        // the energy sinks (issue 31), each alone on a hub of mass 5 (the sinks bench's parts)
        ("spring_mass", moving(spring_mass())),
        ("hinge", moving(hinge())),
        ("slosh", moving(slosh())),
    ];
    for (name, system) in &systems {
        group.bench_with_input(BenchmarkId::new(*name, steps), &grid, |b, grid| {
            b.iter(|| {
                let w = black_box([0.01, 0.01, 1.0]);
                let q0 = [1.0, 0.0, 0.0, 0.0];
                simulate_system(system, w, q0, grid, Method::Rk4, keep, &cancel).unwrap()
            })
        });
    }
    group.finish();
}

/// A mass of 0.1 on a spring along z, at rest 0.5 out along x.
fn spring_mass() -> AnyPart {
    SpringMass::try_new(0.1, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], 2.0, 0.05)
        .unwrap()
        .into()
}

/// A rod of 0.1 hinged 0.5 out along x, flapping about y.
fn hinge() -> AnyPart {
    let rod = Hinge::try_new(
        0.1,
        [0.0, 0.003, 0.003],
        [0.5, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        0.3,
        0.5,
        0.01,
    );
    rod.unwrap().into()
}

/// A pendulum of 0.1 on a rod of 0.3 pivoted 0.5 out along x, hanging a little off x.
fn slosh() -> AnyPart {
    let fields = Fields::new()
        .with("mass", Value::Number(0.1))
        .with("pivot", Value::Vector([0.5, 0.0, 0.0]))
        .with("length", Value::Number(0.3))
        .with("damping", Value::Number(0.01))
        .with("direction0", Value::Vector([1.0, 0.1, 0.0]));
    Slosh::from_fields(&fields).unwrap().into()
}

criterion_group!(benches, models);
criterion_main!(benches);
