//! Batches and sweeps against single runs: bit for bit, on every instruction set this CPU
//! has, on one thread and on two; and against the physics (the exact flip period, stable
//! axes that never flip).

use std::sync::atomic::AtomicBool;

use dzhanibekov::ensemble::batch::{simulate_batch, BatchOutput, Options, Start, LANES};
use dzhanibekov::ensemble::lanes::Isa;
use dzhanibekov::ensemble::sweep::sweep;
use dzhanibekov::exact::flip_period;
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
use dzhanibekov::Error;
use proptest::prelude::*;

mod common;
use common::{no_cancel, KEEP_ALL, PAPER};

/// A deterministic spread of starts: mixed bodies (the paper's, boxes, a symmetric top),
/// rates near each axis and in between, attitudes of every kind.
fn mixed_starts(m: usize) -> Vec<Start> {
    let bodies = [
        PAPER,
        [1.0, 2.0, 3.0],
        [3.0, 1.0, 2.5],
        [1.0, 1.0, 2.0],
        [2.0, 2.9, 1.1],
    ];
    (0..m)
        .map(|i| {
            let f = i as f64;
            let omega = [
                0.3 * (1.3 * f).sin(),
                0.02 + 0.5 * (0.7 * f).cos(),
                1.0 - 0.01 * f,
            ];
            let q = [1.0 + (0.3 * f).cos(), 0.2 * f.sin(), -0.1, 0.05 * f];
            Start::try_new(bodies[i % bodies.len()], omega, q).unwrap()
        })
        .collect()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Asserts that row `i` of `batch` is `simulate` of `starts[i]`, bit for bit.
fn assert_rows_are_single_runs(
    batch: &BatchOutput,
    starts: &[Start],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
) {
    let (f, cancel) = (grid.frames(), no_cancel());
    for (i, s) in starts.iter().enumerate() {
        let one = simulate(&s.body, s.omega0, s.q0, grid, method, keep, &cancel).unwrap();
        if keep.frames {
            assert_eq!(
                bits(&batch.omega[i * f * 3..(i + 1) * f * 3]),
                bits(&one.omega),
                "row {i} ω"
            );
            assert_eq!(
                bits(&batch.q[i * f * 4..(i + 1) * f * 4]),
                bits(&one.q),
                "row {i} q"
            );
        }
        let flips = &batch.flip_times[batch.flip_offsets[i]..batch.flip_offsets[i + 1]];
        assert_eq!(bits(flips), bits(&one.flip_times), "row {i} flips");
        assert_eq!(batch.drift[i], one.drift, "row {i} drift");
        assert_eq!(batch.stats[i], one.stats, "row {i} stats");
        assert_eq!(batch.dt[i].to_bits(), one.dt.to_bits(), "row {i} dt");
    }
}

#[test]
fn rk4_rows_equal_single_runs_on_every_instruction_set_and_thread_count() {
    // 37 rows: two full groups of 16 and a part group of 5; runs long enough to flip
    let starts = mixed_starts(2 * LANES + 5);
    let grid = FrameGrid::try_new(60.0, 31, 5e-3, u64::MAX).unwrap();
    let flipped = |b: &BatchOutput| b.flip_offsets[starts.len()];
    for isa in Isa::available() {
        for threads in [1, 2] {
            let options = Options {
                threads: Some(threads),
                isa: Some(isa),
            };
            let batch = simulate_batch(
                &starts,
                &grid,
                Method::Rk4,
                KEEP_ALL,
                &options,
                &no_cancel(),
            )
            .unwrap();
            assert_rows_are_single_runs(&batch, &starts, &grid, Method::Rk4, KEEP_ALL);
            assert!(
                flipped(&batch) > 10,
                "the test should see flips, saw {}",
                flipped(&batch)
            );
        }
    }
}

#[test]
fn rows_whose_intermediate_rate_starts_at_zero_flip_as_single_runs() {
    // The lanes show a step to the detectors only when a vectorised test of the intermediate
    // rate says it may change them: rates that start at zero (of either sign), that stay at
    // zero (spins about a principal axis), and that start at zero mid-tumble beside the
    // separatrix (a² = 3c² for moments 1, 2, 3) must see the steps their single runs see.
    let rows: [([f64; 3], [f64; 3]); 8] = [
        ([1.0, 2.0, 3.0], [1.0, 0.0, 0.58]),
        ([1.0, 2.0, 3.0], [1.0, -0.0, 0.576]),
        ([1.0, 2.0, 3.0], [-1.0, 0.0, 0.577]),
        ([1.0, 2.0, 3.0], [0.0, 0.0, 1.0]),
        ([1.0, 2.0, 3.0], [0.0, 0.5, 0.0]),
        (PAPER, [0.2, 0.01, 0.0]),
        (PAPER, [-0.2, 0.01, -0.0]),
        (PAPER, [0.01, 0.0, 1.0]),
    ];
    let mut starts: Vec<Start> = rows
        .iter()
        .map(|&(body, omega)| Start::try_new(body, omega, [1.0, 0.0, 0.0, 0.0]).unwrap())
        .collect();
    starts.extend(mixed_starts(LANES));
    let grid = FrameGrid::try_new(40.0, 21, 5e-3, u64::MAX).unwrap();
    for isa in Isa::available() {
        let options = Options {
            threads: Some(1),
            isa: Some(isa),
        };
        let batch = simulate_batch(
            &starts,
            &grid,
            Method::Rk4,
            KEEP_ALL,
            &options,
            &no_cancel(),
        )
        .unwrap();
        assert_rows_are_single_runs(&batch, &starts, &grid, Method::Rk4, KEEP_ALL);
        let near_zero_flips = batch.flip_offsets[3];
        assert!(
            near_zero_flips > 3,
            "the tumbling rows should flip, saw {near_zero_flips}"
        );
    }
}

#[test]
fn rows_keep_what_was_asked() {
    let starts = mixed_starts(20);
    let grid = FrameGrid::try_new(30.0, 7, 1e-2, u64::MAX).unwrap();
    for keep in [
        Keep {
            frames: false,
            flips: true,
            tilt: false,
        },
        Keep {
            frames: true,
            flips: false,
            tilt: false,
        },
        Keep {
            frames: false,
            flips: false,
            tilt: false,
        },
    ] {
        let batch = simulate_batch(
            &starts,
            &grid,
            Method::Rk4,
            keep,
            &Options::default(),
            &no_cancel(),
        )
        .unwrap();
        assert_eq!(batch.omega.is_empty(), !keep.frames);
        assert_rows_are_single_runs(&batch, &starts, &grid, Method::Rk4, keep);
    }
}

#[test]
fn other_methods_run_as_single_runs_row_by_row() {
    let starts = mixed_starts(9);
    let grid = FrameGrid::try_new(20.0, 11, 1e-2, u64::MAX).unwrap();
    for method in [Method::Splitting, Method::Rk4Projected, Method::Splitting4] {
        let options = Options {
            threads: Some(2),
            isa: None,
        };
        let batch =
            simulate_batch(&starts, &grid, method, KEEP_ALL, &options, &no_cancel()).unwrap();
        assert_rows_are_single_runs(&batch, &starts, &grid, method, KEEP_ALL);
    }
    let frames = FrameGrid::frames_only(20.0, 11).unwrap();
    let dopri = "dopri5".parse::<Method>().unwrap();
    let batch = simulate_batch(
        &starts,
        &frames,
        dopri,
        KEEP_ALL,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap();
    assert_rows_are_single_runs(&batch, &starts, &frames, dopri, KEEP_ALL);
    let exact = FrameGrid::try_frames(20.0, 11).unwrap();
    let batch = simulate_batch(
        &starts,
        &exact,
        Method::Exact,
        KEEP_ALL,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap();
    assert_rows_are_single_runs(&batch, &starts, &exact, Method::Exact, KEEP_ALL);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn random_rows_equal_single_runs(
        rows in prop::collection::vec(
            (prop::array::uniform3(0.1f64..10.0), prop::array::uniform3(-3.0f64..3.0),
             prop::array::uniform4(-1.0f64..1.0)),
            1..40),
        dt in 1e-3f64..2e-2,
    ) {
        let starts: Vec<Start> = rows
            .iter()
            .filter_map(|&(i, w, q)| Start::try_new(i, w, q).ok())
            .collect();
        prop_assume!(!starts.is_empty());
        let grid = FrameGrid::try_new(5.0, 6, dt, u64::MAX).unwrap();
        let batch = simulate_batch(&starts, &grid, Method::Rk4, KEEP_ALL, &Options::default(), &no_cancel()).unwrap();
        assert_rows_are_single_runs(&batch, &starts, &grid, Method::Rk4, KEEP_ALL);
    }
}

#[test]
fn sweep_rows_are_summaries_of_single_runs() {
    let starts = mixed_starts(2 * LANES + 3);
    let grid = FrameGrid::try_new(60.0, 9, 5e-3, u64::MAX).unwrap();
    let keep = Keep {
        frames: false,
        flips: true,
        tilt: false,
    };
    for method in [Method::Rk4, Method::Splitting] {
        for threads in [1, 2] {
            let options = Options {
                threads: Some(threads),
                isa: None,
            };
            let runs = sweep(&starts, &grid, method, &options, &no_cancel()).unwrap();
            for (i, (s, run)) in starts.iter().zip(&runs).enumerate() {
                let one =
                    simulate(&s.body, s.omega0, s.q0, &grid, method, keep, &no_cancel()).unwrap();
                assert_eq!(run.flips.count, one.flip_times.len() as u64, "row {i}");
                if let (Some(first), Some(last)) = (one.flip_times.first(), one.flip_times.last()) {
                    assert_eq!(run.flips.first.to_bits(), first.to_bits());
                    assert_eq!(run.flips.last.to_bits(), last.to_bits());
                }
                assert_eq!(run.drift, one.drift, "row {i}");
                assert_eq!(run.stats, one.stats, "row {i}");
                let exact = flip_period(&s.body, s.omega0).unwrap();
                assert_eq!(run.exact_period.to_bits(), exact.to_bits());
            }
        }
    }
}

#[test]
fn sweep_periods_match_the_exact_flip_period_on_a_grid() {
    // The paper's body spun mostly about its intermediate axis z, u0 and v0 on a grid: every
    // start flips, with periods from about 25 to 70.
    let mut starts = Vec::new();
    for u in [0.01, 0.03, 0.1] {
        for v in [0.01, 0.05, 0.2] {
            starts.push(Start::try_new(PAPER, [u, v, 1.0], [1.0, 0.0, 0.0, 0.0]).unwrap());
        }
    }
    let grid = FrameGrid::try_new(400.0, 2, 4e-3, u64::MAX).unwrap();
    let runs = sweep(
        &starts,
        &grid,
        Method::Rk4,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap();
    for (s, run) in starts.iter().zip(&runs) {
        let exact = flip_period(&s.body, s.omega0).unwrap();
        assert!(exact.is_finite() && run.flips.count >= 4, "{s:?}: {run:?}");
        let measured = run.flips.mean_period();
        assert!(
            (measured - exact).abs() < 1e-6 * exact,
            "{s:?}: {measured} vs {exact}"
        );
        // the intermediate axis turned over: its tilt from L passed 90° and went close to 180°
        assert!(
            run.tilt > 0.9 * std::f64::consts::PI,
            "{s:?}: tilt {}",
            run.tilt
        );
    }
}

#[test]
fn stable_axes_report_no_flips_and_small_tilts() {
    // Spin near the largest (x) and the smallest (y) axis of the paper's body.
    let starts = [
        Start::try_new(PAPER, [1.0, 0.05, 0.05], [1.0, 0.0, 0.0, 0.0]).unwrap(),
        Start::try_new(PAPER, [0.05, 1.0, 0.05], [1.0, 0.0, 0.0, 0.0]).unwrap(),
        Start::try_new(PAPER, [-1.0, 0.01, -0.02], [0.0, 1.0, 0.0, 0.0]).unwrap(),
        // a symmetric top has no intermediate axis
        Start::try_new([1.0, 1.0, 2.0], [0.3, 0.1, 1.0], [1.0, 0.0, 0.0, 0.0]).unwrap(),
    ];
    let grid = FrameGrid::try_new(300.0, 2, 4e-3, u64::MAX).unwrap();
    let runs = sweep(
        &starts,
        &grid,
        Method::Rk4,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap();
    for (s, run) in starts.iter().zip(&runs) {
        assert_eq!(run.flips.count, 0, "{s:?}");
        assert!(run.flips.first.is_nan() && run.flips.mean_period().is_nan());
        assert_eq!(run.exact_period, f64::INFINITY);
        assert!(run.tilt < 0.2, "{s:?}: tilt {}", run.tilt);
    }
}

#[test]
fn bad_rows_are_named() {
    let err = Start::rows(
        &[1.0, 2.0, 3.0],
        &[0.0, 0.0, 1.0, 0.0, f64::NAN, 1.0],
        &[1.0, 0.0, 0.0, 0.0],
    )
    .unwrap_err();
    assert!(err.to_string().starts_with("row 1: `omega0`"), "{err}");
    let err = Start::rows(
        &[1.0, 2.0, 3.0, 1.0, -2.0, 3.0],
        &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
        &[1.0, 0.0, 0.0, 0.0],
    )
    .unwrap_err();
    assert!(err.to_string().starts_with("row 1: `inertia`"), "{err}");
    let err = Start::rows(&[1.0, 2.0, 3.0], &[0.0, 0.0, 1.0], &[0.0; 8]).unwrap_err();
    assert!(err.to_string().contains("shapes"), "{err}");
    let grid = FrameGrid::try_new(1.0, 2, 0.1, u64::MAX).unwrap();
    let starts = mixed_starts(2);
    let zero = Options {
        threads: Some(0),
        isa: None,
    };
    let err =
        simulate_batch(&starts, &grid, Method::Rk4, KEEP_ALL, &zero, &no_cancel()).unwrap_err();
    assert!(
        err.to_string().starts_with("`threads` must be at least 1"),
        "{err}"
    );
}

#[test]
fn a_diverging_row_is_named_and_stops_the_batch() {
    let mut starts = mixed_starts(40);
    // a step far beyond RK4's stability limit for this one row
    starts[23] = Start::try_new([1.0, 2.0, 3.0], [1e4, 2e4, 1e4], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let grid = FrameGrid::try_new(10.0, 2, 0.5, u64::MAX).unwrap();
    for method in [Method::Rk4, Method::Rk4Projected] {
        let err = simulate_batch(
            &starts,
            &grid,
            method,
            KEEP_ALL,
            &Options::default(),
            &no_cancel(),
        );
        match err {
            Err(Error::Row { row: 23, error }) if matches!(*error, Error::Diverged { .. }) => {}
            other => panic!("{method:?}: {:?}", other.err()),
        }
    }
}

#[test]
fn a_batch_that_cannot_be_allocated_says_so() {
    let starts = mixed_starts(1000);
    // 1000 runs × 2^42 frames: too many values to address
    let grid = FrameGrid::try_new(1.0, 1 << 42, 1.0, u64::MAX).unwrap();
    let err = simulate_batch(
        &starts,
        &grid,
        Method::Rk4,
        KEEP_ALL,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap_err();
    assert!(matches!(err, Error::TooLarge { .. }), "{err}");
    assert!(err.to_string().contains("sweep"), "{err}");
    // 4 runs × 2^40 frames: addressable, but no machine has the memory
    let grid = FrameGrid::try_new(1.0, 1 << 40, 1.0, u64::MAX).unwrap();
    let err = simulate_batch(
        &starts[..4],
        &grid,
        Method::Rk4,
        KEEP_ALL,
        &Options::default(),
        &no_cancel(),
    )
    .unwrap_err();
    assert!(matches!(err, Error::TooLarge { .. }), "{err}");
}

#[test]
fn cancel_stops_every_group() {
    let starts = mixed_starts(64);
    let grid = FrameGrid::try_new(1e4, 2, 1e-3, u64::MAX).unwrap();
    let cancel = AtomicBool::new(true);
    let keep = Keep {
        frames: false,
        flips: true,
        tilt: false,
    };
    let err = simulate_batch(
        &starts,
        &grid,
        Method::Rk4,
        keep,
        &Options::default(),
        &cancel,
    )
    .unwrap_err();
    assert_eq!(err, Error::Interrupted);
    let err = sweep(&starts, &grid, Method::Rk4, &Options::default(), &cancel).unwrap_err();
    assert_eq!(err, Error::Interrupted);
}
