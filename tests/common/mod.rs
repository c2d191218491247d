//! What the integration tests share: the paper's moments and a run that keeps everything.
#![allow(dead_code)] // each test crate uses its own part of this

use std::sync::atomic::AtomicBool;

use dzhanibekov::run::{simulate, FrameGrid, Keep, Method, RunOutput};
use dzhanibekov::RigidBody;

/// The paper's principal moments `(Ix, Iy, Iz)`, as printed (erratum 2: x and y swapped).
pub const PAPER: [f64; 3] = [52.0833, 27.0833, 41.6666];

pub const KEEP_ALL: Keep = Keep {
    frames: true,
    flips: true,
    tilt: false,
};

pub fn no_cancel() -> AtomicBool {
    AtomicBool::new(false)
}

/// The frame grid of a run: the frames alone for methods that choose their own steps.
pub fn grid_for(method: Method, t_end: f64, frames: usize, dt: f64) -> FrameGrid {
    match method {
        Method::Exact => FrameGrid::try_frames(t_end, frames).unwrap(),
        m if m.is_adaptive() => FrameGrid::frames_only(t_end, frames).unwrap(),
        _ => FrameGrid::try_new(t_end, frames, dt, u64::MAX).unwrap(),
    }
}

/// A run keeping its frames and flips; the inputs are the test's own, so any error is a bug.
pub fn run(
    method: Method,
    inertia: [f64; 3],
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    dt: f64,
) -> RunOutput {
    let body = RigidBody::try_new(inertia).unwrap();
    let grid = grid_for(method, t_end, frames, dt);
    simulate(&body, omega0, q0, &grid, method, KEEP_ALL, &no_cancel()).unwrap()
}
