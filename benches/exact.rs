//! Criterion benches of the exact solution: 201 frames at T = 10⁶ (target: under 50 ms),
//! with and without the flip times, on the paper's well- and ill-conditioned cases, beside
//! the cost of one RK4 run of the same frames over T = 100 as a baseline.
//! `cargo bench --bench exact`; `-- --quick` for a short pass.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;

fn exact(c: &mut Criterion) {
    let body = RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
    let cancel = AtomicBool::new(false);
    let mut group = c.benchmark_group("exact");
    group.sample_size(10);
    let grid = FrameGrid::try_frames(1e6, 201).unwrap();
    group.throughput(Throughput::Elements(201));
    for (case, omega0) in [("fig3a", [0.01, 0.01, 1.0]), ("example", [5e-6, 5e-6, 1.0])] {
        for (name, flips) in [("frames", false), ("frames+flips", true)] {
            let keep = Keep {
                frames: true,
                flips,
                tilt: false,
            };
            let id = BenchmarkId::new(format!("{case}/{name}"), "T=1e6");
            group.bench_with_input(id, &grid, |b, grid| {
                b.iter(|| {
                    simulate(
                        &body,
                        black_box(omega0),
                        [1.0, 0.0, 0.0, 0.0],
                        grid,
                        Method::Exact,
                        keep,
                        &cancel,
                    )
                    .unwrap()
                })
            });
        }
    }
    let grid = FrameGrid::try_new(100.0, 201, 1e-3, u64::MAX).unwrap();
    let keep = Keep {
        frames: true,
        flips: true,
        tilt: false,
    };
    group.bench_with_input(
        BenchmarkId::new("rk4-baseline/fig3a", "T=100"),
        &grid,
        |b, grid| {
            b.iter(|| {
                simulate(
                    &body,
                    black_box([0.01, 0.01, 1.0]),
                    [1.0, 0.0, 0.0, 0.0],
                    grid,
                    Method::Rk4,
                    keep,
                    &cancel,
                )
                .unwrap()
            })
        },
    );
    group.finish();
}

criterion_group!(benches, exact);
criterion_main!(benches);
