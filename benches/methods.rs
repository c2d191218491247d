//! Criterion benches of the methods beyond RK4, per step, beside RK4 measured in the same
//! run: `cargo bench --bench methods` (`-- --quick` for a short pass). The adaptive methods
//! are timed per accepted step at a fixed tolerance.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dzhanibekov::run::adaptive::Adaptive;
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;

const OMEGA0: [f64; 3] = [0.01, 0.1, 0.03];
const Q0: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

fn body() -> RigidBody {
    RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap()
}

fn fixed_step(c: &mut Criterion) {
    let body = body();
    let cancel = AtomicBool::new(false);
    let mut group = c.benchmark_group("fixed_step");
    group.sample_size(10);
    let steps = 1_000_000u64;
    let grid = FrameGrid::try_new(steps as f64 * 1e-2, 201, 1e-2, u64::MAX).unwrap();
    group.throughput(Throughput::Elements(grid.n_steps()));
    for (name, method) in [
        ("rk4", Method::Rk4),
        ("rk4_projected", Method::Rk4Projected),
        ("splitting", Method::Splitting),
        ("splitting4", Method::Splitting4),
        ("splitting6", Method::Splitting6),
        ("implicit_midpoint", Method::ImplicitMidpoint),
        ("dmv", Method::Dmv),
        ("dmv_modified", Method::DmvModified),
        ("rkmk4", Method::Rkmk4),
        ("crouch_grossman3", Method::CrouchGrossman3),
    ] {
        for flips in [false, true] {
            let keep = Keep {
                frames: true,
                flips,
                tilt: false,
            };
            let id = format!("{name}{}", if flips { "+flips" } else { "" });
            group.bench_function(BenchmarkId::new(id, steps), |b| {
                b.iter(|| {
                    simulate(&body, black_box(OMEGA0), Q0, &grid, method, keep, &cancel).unwrap()
                })
            });
        }
    }
    group.finish();
}

fn adaptive(c: &mut Criterion) {
    let body = body();
    let cancel = AtomicBool::new(false);
    let keep = Keep {
        frames: true,
        flips: true,
        tilt: false,
    };
    let mut group = c.benchmark_group("adaptive");
    group.sample_size(10);
    let grid = FrameGrid::frames_only(1e4, 201).unwrap();
    for rtol in [1e-6, 1e-12] {
        let a = Adaptive::try_new(rtol, rtol * 1e-3).unwrap();
        for (name, method) in [("dopri5", Method::Dopri5(a)), ("dop853", Method::Dop853(a))] {
            let run = || simulate(&body, black_box(OMEGA0), Q0, &grid, method, keep, &cancel);
            // per accepted step: the count is fixed by the tolerance
            group.throughput(Throughput::Elements(run().unwrap().stats.n_steps));
            group.bench_function(BenchmarkId::new(name, rtol), |b| b.iter(|| run().unwrap()));
        }
    }
    group.finish();
}

criterion_group!(benches, fixed_step, adaptive);
criterion_main!(benches);
