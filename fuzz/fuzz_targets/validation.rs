//! The core's input validation under arbitrary `f64` bit patterns (NaN with any payload,
//! ±inf, ±0, subnormals, the extremes): `RigidBody::try_new`, the frame grids, `simulate` of
//! every method, batches, `rotate_points` and `flip_period` either return `Ok` with finite
//! output or `Err`; a panic (or an abort, a hang, an allocation beyond libFuzzer's limit) is
//! a finding.
//!
//!     cargo +nightly fuzz run validation -- -max_total_time=60
//!
//! Runs are kept short (at most a few thousand steps, 64 frames) so that each input takes
//! microseconds; what a run may cost is bounded by the validation itself (`max_steps`).

#![no_main]

use std::sync::atomic::AtomicBool;

use dzhanibekov::run::adaptive::Adaptive;
use dzhanibekov::ensemble::batch::{simulate_batch, Options, Start};
use dzhanibekov::exact::flip_period;
use dzhanibekov::kinematics::rotate_points;
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
use dzhanibekov::RigidBody;
use libfuzzer_sys::fuzz_target;

/// Reads `f64`s from the input, 8 bytes each, zeros past its end.
struct Floats<'a>(&'a [u8]);

impl Floats<'_> {
    fn next(&mut self) -> f64 {
        let mut b = [0u8; 8];
        let n = self.0.len().min(8);
        b[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        f64::from_le_bytes(b)
    }

    fn array<const N: usize>(&mut self) -> [f64; N] {
        std::array::from_fn(|_| self.next())
    }
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fuzz_target!(|data: &[u8]| {
    let Some((&control, rest)) = data.split_first() else {
        return;
    };
    let mut f = Floats(rest);
    let inertia: [f64; 3] = f.array();
    let omega0: [f64; 3] = f.array();
    let q0: [f64; 4] = f.array();
    let (t_end, dt) = (f.next(), f.next());
    let points: [f64; 6] = f.array();
    let frames = usize::from(control & 0x3f);
    let keep = Keep {
        frames: control & 0x40 != 0,
        flips: control & 0x80 != 0,
    };
    let cancel = AtomicBool::new(false);

    let mut out = [0.0; 2 * 2 * 3];
    if rotate_points(&q0, &points, &mut out[..6]).is_ok() {
        assert!(
            finite(&out[..6]),
            "rotate_points: {q0:?} {points:?} -> {out:?}"
        );
    }
    let body = match RigidBody::try_new(inertia) {
        Ok(body) => body,
        Err(_) => return,
    };
    assert!(finite(body.inertia_body().as_slice()));
    if let Ok(period) = flip_period(&body, omega0) {
        assert!(
            period > 0.0 && !period.is_nan(),
            "flip_period {inertia:?} {omega0:?}: {period}"
        );
    }
    let adaptive = Adaptive::try_new(1e-6, 1e-9).map(|a| a.with_max_steps(2_000));
    let Ok(adaptive) = adaptive else { return };
    for (k, method) in [
        Method::Rk4,
        Method::Rk4Projected,
        Method::Splitting,
        Method::Splitting4,
        Method::Dopri5(adaptive),
        Method::Dop853(adaptive),
        Method::Exact,
    ]
    .into_iter()
    .enumerate()
    {
        let grid = match method {
            Method::Exact => FrameGrid::try_frames(t_end, frames),
            Method::Dopri5(_) | Method::Dop853(_) => FrameGrid::frames_only(t_end, frames),
            _ => FrameGrid::try_new(t_end, frames, dt, 2_000),
        };
        let Ok(grid) = grid else { continue };
        assert!(grid.t_end().is_finite() && grid.t_end() > 0.0 && grid.frames() >= 2);
        if let Ok(run) = simulate(&body, omega0, q0, &grid, method, keep, &cancel) {
            assert!(
                finite(&run.omega) && finite(&run.q),
                "{method:?}: frames not finite"
            );
            assert!(finite(&run.flip_times), "{method:?}: flip times not finite");
            let d = run.drift;
            assert!(finite(&[
                d.energy,
                d.momentum,
                d.momentum_world,
                d.q_norm,
                run.dt
            ]));
        }
        // a batch of this start and a copy of it at half the rates: the lanes' path for RK4
        if k == 0 {
            let half = omega0.map(|w| 0.5 * w);
            let starts: Vec<Start> = [omega0, half]
                .iter()
                .filter_map(|w| Start::try_new(inertia, *w, q0).ok())
                .collect();
            let options = Options::default();
            if let Ok(b) = simulate_batch(&starts, &grid, method, keep, &options, &cancel) {
                assert!(finite(&b.omega) && finite(&b.q) && finite(&b.flip_times));
            }
        }
    }
});
