//! Criterion benches of batches: the SIMD lane kernel on each instruction set (one thread),
//! and whole batches and sweeps on 1 and 2 threads; throughput in run-steps.
//! `cargo bench --bench batch`; `-- --quick` for a short pass.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dzhanibekov::dynamics::{state_from, FreeRigidBody, State};
use dzhanibekov::ensemble::batch::{simulate_batch, Options, Start, LANES};
use dzhanibekov::ensemble::lanes::{advance, Isa, Lanes, Span};
use dzhanibekov::ensemble::sweep::sweep;
use dzhanibekov::observe::{FlipDetector, Observer};
use dzhanibekov::run::{FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;

const PAPER: [f64; 3] = [52.0833, 27.0833, 41.6666];
const RUNS: usize = 4096;
const STEPS: u64 = 1000;

/// Rates near each axis and between, seeded: a mix that flips and wobbles.
fn rates(i: usize) -> [f64; 3] {
    let f = i as f64;
    [
        0.3 * (1.7 * f).sin(),
        0.3 * (0.9 * f).cos(),
        1.0 - 0.5 * (0.3 * f).sin(),
    ]
}

fn kernel(c: &mut Criterion) {
    let body = RigidBody::try_new(PAPER).unwrap();
    let sys = FreeRigidBody::new(body);
    let euler = [sys.euler_coefficients().into(); LANES];
    let mut group = c.benchmark_group("lanes");
    group.sample_size(10);
    group.throughput(Throughput::Elements(RUNS as u64 * STEPS));
    let span = Span {
        ta: 0.0,
        tb: STEPS as f64 * 1e-3,
        h: 1e-3,
        n: STEPS,
        from: 0,
        to: STEPS,
    };
    for isa in Isa::available() {
        for flips in [false, true] {
            let name = if flips { "flips" } else { "bare" };
            group.bench_function(BenchmarkId::new(name, isa.name()), |b| {
                b.iter(|| {
                    let mut sink = 0.0;
                    for g in 0..RUNS / LANES {
                        let states: [State; LANES] = std::array::from_fn(|l| {
                            state_from(rates(g * LANES + l), [1.0, 0.0, 0.0, 0.0])
                        });
                        let mut lanes = Lanes::<LANES>::new(&euler, &states);
                        let mut detectors: Vec<FlipDetector<'_, FreeRigidBody>> = Vec::new();
                        if flips {
                            for (l, x) in states.iter().enumerate() {
                                let mut d = FlipDetector::new(&sys, 0.0, x);
                                d.frame(0, 0.0, x);
                                lanes.watch_flips(l, &d);
                                detectors.push(d);
                            }
                        }
                        advance(
                            isa,
                            &mut lanes,
                            &mut detectors,
                            black_box(span),
                            flips,
                            false,
                        );
                        sink += lanes.state(0)[3];
                    }
                    sink
                })
            });
        }
    }
    group.finish();
}

fn batches(c: &mut Criterion) {
    let starts: Vec<Start> = (0..RUNS)
        .map(|i| Start::try_new(PAPER, rates(i), [1.0, 0.0, 0.0, 0.0]).unwrap())
        .collect();
    let grid = FrameGrid::try_new(STEPS as f64 * 1e-3, 2, 1e-3, u64::MAX).unwrap();
    let cancel = AtomicBool::new(false);
    let mut group = c.benchmark_group("batch");
    group.sample_size(10);
    group.throughput(Throughput::Elements(RUNS as u64 * STEPS));
    for threads in [1, 2] {
        let options = Options {
            threads: Some(threads),
            isa: None,
        };
        for flips in [false, true] {
            let keep = Keep {
                frames: true,
                flips,
                tilt: false,
            };
            let name = if flips { "simulate+flips" } else { "simulate" };
            group.bench_function(BenchmarkId::new(name, threads), |b| {
                b.iter(|| {
                    simulate_batch(&starts, &grid, Method::Rk4, keep, &options, &cancel).unwrap()
                })
            });
        }
        group.bench_function(BenchmarkId::new("sweep", threads), |b| {
            b.iter(|| sweep(&starts, &grid, Method::Rk4, &options, &cancel).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, kernel, batches);
criterion_main!(benches);
