//! Properties of every method over random bodies and states (proptest): each keeps what it
//! promises to keep, agrees with the exact solution, and is the same run bit for bit under
//! `(ω, t) → (2^k ω, t / 2^k)`; and the validating constructors and the run take any `f64`
//! (NaN, ±inf, subnormals, ±0) without panicking or returning non-finite output.

use std::sync::atomic::AtomicBool;

use dzhanibekov::dynamics::{state_from, Invariants};
use dzhanibekov::ensemble::batch::{simulate_batch, Options, Start};
use dzhanibekov::ensemble::sweep::sweep;
use dzhanibekov::run::adaptive::Adaptive;
use dzhanibekov::run::{simulate, FrameGrid, Method, RunOutput};
use dzhanibekov::RigidBody;
use nalgebra::Vector3;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

mod common;
use common::{grid_for as grid, no_cancel, KEEP_ALL};

/// Every method, the adaptive ones at a tight tolerance.
fn methods() -> [Method; 13] {
    let tight = Adaptive::try_new(1e-11, 1e-13).unwrap();
    [
        Method::Rk4,
        Method::Rk4Projected,
        Method::Splitting,
        Method::Splitting4,
        Method::Splitting6,
        Method::ImplicitMidpoint,
        Method::Dmv,
        Method::DmvModified,
        Method::Rkmk4,
        Method::CrouchGrossman3,
        Method::Dopri5(tight),
        Method::Dop853(tight),
        Method::Exact,
    ]
}

fn run(
    method: Method,
    body: &RigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
) -> RunOutput {
    simulate(body, omega0, q0, grid, method, KEEP_ALL, &no_cancel()).unwrap()
}

/// The largest relative departure over the frames of each invariant, recomputed from the
/// frames: `[energy, |L|, L_world, |q|]`.
fn drifts(body: &RigidBody, out: &RunOutput) -> [f64; 4] {
    let i = body.inertia_body();
    let at = |f: usize| {
        let w = &out.omega[3 * f..3 * f + 3];
        let q = &out.q[4 * f..4 * f + 4];
        Invariants::of(
            &i,
            &state_from([w[0], w[1], w[2]], [q[0], q[1], q[2], q[3]]),
        )
    };
    let first = at(0);
    let l0 = first.l_body.norm();
    let mut d = [0.0_f64; 4];
    for f in 0..out.omega.len() / 3 {
        let now = at(f);
        d[0] = d[0].max(((now.energy - first.energy) / first.energy).abs());
        d[1] = d[1].max((now.l_body.norm() / l0 - 1.0).abs());
        d[2] = d[2].max((now.l_world - first.l_world).norm() / l0);
        d[3] = d[3].max((now.q_norm - 1.0).abs());
    }
    d
}

/// What each method keeps, by its documentation, for a step of `hΩ ≤ 0.01` over `n` steps:
/// `[energy, |L|, L_world, |q|]`. Round-off grows with the rotations composed: one per step,
/// five per step of `splitting4` (Suzuki's composition of five Strang steps), nine of
/// `splitting6`.
fn promised(method: Method, n: u64) -> [f64; 4] {
    let stages = match method {
        Method::Splitting4 => 5.0,
        Method::Splitting6 => 9.0,
        _ => 1.0,
    };
    let n = stages * n as f64;
    let roundoff = 1e-14 * (1.0 + n).sqrt() + 1e-15 * n;
    match method {
        // RK4's O(h⁴) drift: (0.01)⁴ a radian, over at most 20 radians
        Method::Rk4 => [1e-8; 4],
        Method::Rk4Projected => [roundoff; 4],
        // energy bounded at O(h²) and O(h⁴); |L|, L_world and |q| to round-off
        Method::Splitting => [1e-3, roundoff, roundoff, roundoff],
        Method::Splitting4 => [1e-6, roundoff, roundoff, roundoff],
        Method::Splitting6 => [1e-9, roundoff, roundoff, roundoff],
        // energy and |L| kept (to Newton's round-off); L_world turns by (hΩ)³/16 a step
        Method::ImplicitMidpoint => [roundoff, roundoff, 1e-3, roundoff],
        Method::Dmv | Method::DmvModified => [roundoff; 4],
        // the energy drifts at O(h⁴) and O(h³) per radian; the rotations keep the rest
        Method::Rkmk4 => [1e-8, roundoff, roundoff, roundoff],
        Method::CrouchGrossman3 => [1e-4, roundoff, roundoff, roundoff],
        Method::Dopri5(_) | Method::Dop853(_) => [1e-8; 4],
        Method::Exact => [1e-11; 4],
        // runs bodies under torques, not the free body: not in `methods()`
        Method::SplittingExact | Method::SplittingExact4 => [0.0; 4],
    }
}

/// A random body (moments 10⁻² to 10², ratios up to 10⁴) and state, with a step of
/// `hΩ_max = 0.01` at its fastest frequency and a span of `turns` radians of it.
fn setup(log_i: [f64; 3], omega0: [f64; 3], turns: f64) -> Option<(RigidBody, f64, f64)> {
    let inertia = log_i.map(|l| 10f64.powf(l));
    let body = RigidBody::try_new(inertia).ok()?;
    let ratio = inertia.iter().cloned().fold(0.0, f64::max)
        / inertia.iter().cloned().fold(f64::MAX, f64::min);
    let rate = Vector3::from(omega0).norm() * ratio;
    if rate < 1e-3 {
        return None;
    }
    let dt = 0.01 / rate;
    Some((body, turns / rate, dt))
}

/// Cases per property: 32 in CI; `DZ_PROPTEST_CASES=N` for a longer search.
fn cases() -> u32 {
    std::env::var("DZ_PROPTEST_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(32)
}

/// The config of every property: failures found are kept beside this file (the crate's
/// sources live in `rust/`, where proptest's default does not look).
fn config() -> ProptestConfig {
    ProptestConfig {
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "tests/properties.proptest-regressions",
        ))),
        ..ProptestConfig::with_cases(cases())
    }
}

proptest! {
    #![proptest_config(config())]

    /// Each method keeps its invariants as its documentation says.
    #[test]
    fn every_method_keeps_what_it_promises(
        log_i in prop::array::uniform3(-2.0f64..2.0),
        omega0 in prop::array::uniform3(-1.0f64..1.0),
        q0 in prop::array::uniform4(-1.0f64..1.0),
        turns in 1.0f64..20.0,
    ) {
        prop_assume!(q0.iter().map(|c| c * c).sum::<f64>() > 1e-3);
        let Some((body, t_end, dt)) = setup(log_i, omega0, turns) else {
            return Ok(());
        };
        for method in methods() {
            let out = run(method, &body, omega0, q0, &grid(method, t_end, 11, dt));
            prop_assert!(out.omega.iter().chain(&out.q).all(|v| v.is_finite()));
            let got = drifts(&body, &out);
            let allowed = promised(method, out.stats.n_steps);
            for k in 0..4 {
                prop_assert!(got[k] <= allowed[k], "{:?}: drift {:?} beyond {:?}", method, got, allowed);
            }
            // the run's own drift measure is the same
            let own = [out.drift.energy, out.drift.momentum, out.drift.momentum_world, out.drift.q_norm];
            for k in 0..4 {
                prop_assert!((own[k] - got[k]).abs() <= 1e-14 + 1e-6 * got[k], "{:?}: {:?} vs {:?}", method, own, got);
            }
        }
    }

    /// Every integrator follows the closed-form solution (away from the separatrix, where
    /// every float64 method loses digits at each flip, its error stays within a few steps'
    /// worth).
    #[test]
    fn every_method_follows_the_exact_solution(
        log_i in prop::array::uniform3(-1.0f64..1.0),
        omega0 in prop::array::uniform3(-1.0f64..1.0),
        q0 in prop::array::uniform4(-1.0f64..1.0),
    ) {
        prop_assume!(q0.iter().map(|c| c * c).sum::<f64>() > 1e-3);
        let Some((body, t_end, dt)) = setup(log_i, omega0, 2.0) else {
            return Ok(());
        };
        let exact = run(Method::Exact, &body, omega0, q0, &grid(Method::Exact, t_end, 5, dt));
        let scale = Vector3::from(omega0).amax();
        for method in methods() {
            let out = run(method, &body, omega0, q0, &grid(method, t_end, 5, dt));
            let dw = out.omega.iter().zip(&exact.omega).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            let tol = match method {
                Method::Splitting | Method::ImplicitMidpoint | Method::Dmv => 1e-4,
                Method::CrouchGrossman3 => 1e-5,
                _ => 1e-7,
            };
            prop_assert!(dw <= tol * scale, "{:?}: |Δω| = {:e} against the exact solution", method, dw);
        }
    }

    /// `(ω, t) → (2^k ω, t / 2^k)` is the same motion, and the same bits: rates of 1e-300 or
    /// 1e270 run in the motion's own units.
    #[test]
    fn a_run_at_any_rate_is_the_run_at_unit_rate(
        omega0 in prop::array::uniform3(-1.0f64..1.0),
        k in prop_oneof![-1020i32..-70, 70i32..900],
        method_index in 0usize..13,
    ) {
        let body = RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
        prop_assume!(Vector3::from(omega0).amax() > 1e-3);
        let method = methods()[method_index];
        let s = 2f64.powi(k / 2) * 2f64.powi(k - k / 2);
        // the scaled rates must be the same numbers (not rounded to subnormals)
        prop_assume!(omega0.iter().all(|w| (w * s) / s == *w));
        let q0 = [0.9, 0.1, -0.3, 0.2];
        let unit = run(method, &body, omega0, q0, &grid(method, 10.0, 6, 0.01));
        let scaled_grid = grid(method, 10.0 / s, 6, 0.01 / s);
        let scaled = run(method, &body, omega0.map(|w| w * s), q0, &scaled_grid);
        prop_assert_eq!(&scaled.q, &unit.q);
        // rates and times come back rounded once, as `unit · s` is (subnormals included)
        prop_assert_eq!(scaled.omega.clone(), unit.omega.iter().map(|w| w * s).collect::<Vec<_>>());
        prop_assert_eq!(scaled.flip_times.clone(), unit.flip_times.iter().map(|t| t / s).collect::<Vec<_>>());
        prop_assert_eq!(scaled.drift, unit.drift);
    }

    /// The constructors take any f64 and either build something valid or refuse it.
    #[test]
    fn constructors_validate_any_float(
        inertia in prop::array::uniform3(prop::num::f64::ANY),
        t_end in prop::num::f64::ANY,
        dt in prop::num::f64::ANY,
        frames in 0usize..1000,
        max_steps in any::<u64>(),
    ) {
        if let Ok(body) = RigidBody::try_new(inertia) {
            let i = body.inertia_body();
            prop_assert!(i.iter().all(|x| x.is_finite() && *x > 0.0));
            prop_assert!(i.max() / i.min() <= 1e150);
        }
        if let Ok(grid) = FrameGrid::try_new(t_end, frames, dt, max_steps) {
            prop_assert!(grid.t_end().is_finite() && grid.t_end() > 0.0 && grid.frames() >= 2);
            prop_assert!(grid.n_steps() <= max_steps && grid.substeps() >= 1);
            prop_assert!(grid.step_size() <= dt && grid.step_size() >= 0.0);
            prop_assert_eq!(grid.time(grid.frames() - 1), t_end);
        }
    }

    /// A run from any rates and attitude, on a short grid, gives finite frames or an error.
    #[test]
    fn runs_from_any_state_are_finite_or_refused(
        omega0 in prop::array::uniform3(prop::num::f64::ANY),
        q0 in prop::array::uniform4(prop::num::f64::ANY),
        method_index in 0usize..13,
    ) {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let method = methods()[method_index].with_adaptive(
            Adaptive::try_new(1e-9, 1e-12).unwrap().with_max_steps(10_000));
        let grid = grid(method, 1.0, 3, 0.05);
        let out = simulate(&body, omega0, q0, &grid, method, KEEP_ALL, &AtomicBool::new(false));
        if let Ok(out) = out {
            prop_assert!(out.omega.iter().chain(&out.q).chain(&out.flip_times).all(|v| v.is_finite()));
            let d = out.drift;
            prop_assert!([d.energy, d.momentum, d.momentum_world, d.q_norm].iter().all(|v| v.is_finite()));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases() / 4 + 1, ..config() })]

    /// Every row of a batch is the single run of its start, bit for bit, and every row of a
    /// sweep summarises it: rates of any size (rows far from 1 run in their own units, as a
    /// single run does), mixed bodies, every lane width this CPU has.
    #[test]
    fn batch_and_sweep_rows_are_single_runs(
        rows in prop::collection::vec(
            (prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-1.0f64..1.0),
             prop::array::uniform4(-1.0f64..1.0)),
            1..12),
        k in prop_oneof![Just(0i32), -300i32..300],
        method_index in 0usize..13,
    ) {
        // rates of order 2^k, the span and step in the same units (a few radians)
        let s = 2f64.powi(k);
        let starts: Vec<Start> = rows
            .iter()
            .filter_map(|&(log_i, w, q)| {
                Start::try_new(log_i.map(|l| 10f64.powf(l)), w.map(|w| w * s), q).ok()
            })
            .collect();
        prop_assume!(!starts.is_empty());
        let method = methods()[method_index];
        let grid = grid(method, 3.0 / s, 4, 0.05 / s);
        let cancel = AtomicBool::new(false);
        let singles: Vec<Option<RunOutput>> = starts
            .iter()
            .map(|s| simulate(&s.body, s.omega0, s.q0, &grid, method, KEEP_ALL, &cancel).ok())
            .collect();
        let batch = simulate_batch(&starts, &grid, method, KEEP_ALL, &Options::default(), &cancel);
        match &batch {
            Ok(b) => {
                for (i, one) in singles.iter().enumerate() {
                    let one = one.as_ref().expect("a batch that ran ran every row");
                    let f = grid.frames();
                    prop_assert_eq!(bits(&b.omega[i * f * 3..(i + 1) * f * 3]), bits(&one.omega));
                    prop_assert_eq!(bits(&b.q[i * f * 4..(i + 1) * f * 4]), bits(&one.q));
                    let flips = &b.flip_times[b.flip_offsets[i]..b.flip_offsets[i + 1]];
                    prop_assert_eq!(bits(flips), bits(&one.flip_times));
                    prop_assert_eq!(b.drift[i], one.drift);
                    prop_assert_eq!(b.dt[i].to_bits(), one.dt.to_bits());
                }
            }
            Err(_) => prop_assert!(singles.iter().any(Option::is_none), "the batch failed, no run alone did"),
        }
        let summaries = sweep(&starts, &grid, method, &Options::default(), &cancel);
        prop_assert_eq!(summaries.is_ok(), batch.is_ok());
        if let Ok(summaries) = summaries {
            for (run, one) in summaries.iter().zip(&singles) {
                let one = one.as_ref().expect("checked above");
                prop_assert_eq!(run.flips.count, one.flip_times.len() as u64);
                if let (Some(first), Some(last)) = (one.flip_times.first(), one.flip_times.last()) {
                    prop_assert_eq!(run.flips.first.to_bits(), first.to_bits());
                    prop_assert_eq!(run.flips.last.to_bits(), last.to_bits());
                }
                prop_assert_eq!(run.drift, one.drift);
                prop_assert_eq!(run.dt.to_bits(), one.dt.to_bits());
                prop_assert!((0.0..=std::f64::consts::PI).contains(&run.tilt) || method == Method::Exact);
            }
        }
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}
