//! Criterion benches of the core: the RK4 run (per step) and `rotate_points` (per point-frame).
//! `cargo bench --bench core`; `-- --quick` for a short pass.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dzhanibekov::kinematics::rotate_points;
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;

fn rk4(c: &mut Criterion) {
    let body = RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
    let cancel = AtomicBool::new(false);
    let mut group = c.benchmark_group("rk4");
    group.sample_size(10);
    for steps in [10_000u64, 1_000_000] {
        let grid = FrameGrid::try_new(steps as f64 * 1e-3, 201, 1e-3, u64::MAX).unwrap();
        group.throughput(Throughput::Elements(grid.n_steps()));
        for (name, keep) in [
            (
                "frames",
                Keep {
                    frames: true,
                    flips: false,
                    tilt: false,
                },
            ),
            (
                "frames+flips",
                Keep {
                    frames: true,
                    flips: true,
                    tilt: false,
                },
            ),
        ] {
            group.bench_with_input(BenchmarkId::new(name, steps), &grid, |b, grid| {
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
            });
        }
    }
    group.finish();
}

fn rotate(c: &mut Criterion) {
    let mut group = c.benchmark_group("rotate");
    group.sample_size(10);
    for (frames, points) in [(200usize, 10_000usize), (200, 1_000_000)] {
        let q: Vec<f64> = (0..frames)
            .flat_map(|i| {
                let a = 0.01 * i as f64;
                [a.cos(), 0.3 * a.sin(), 0.5 * a.sin(), 0.1]
            })
            .collect();
        let p: Vec<f64> = (0..3 * points).map(|k| (k as f64 * 0.37).sin()).collect();
        group.throughput(Throughput::Elements((frames * points) as u64));
        group.bench_function(BenchmarkId::new("point_frames", frames * points), |b| {
            b.iter(|| {
                let mut out = vec![0.0; frames * points * 3];
                rotate_points(black_box(&q), black_box(&p), &mut out).unwrap();
                out
            })
        });
    }
    group.finish();
}

criterion_group!(benches, rk4, rotate);
criterion_main!(benches);
