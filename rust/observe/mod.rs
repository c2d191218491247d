//! What a run keeps: observers see the frames (and, if they ask, every step) and keep only
//! what a caller needs — stored frames, invariant drift, flip times.

mod drift;
pub mod flat;
mod flips;
mod frames;
mod sides;
pub mod tilt;

pub use drift::{Drift, DriftMonitor};
pub use flat::{FlatAxes, FlatSpin, FLAT_SHARE};
pub use flips::FlipDetector;
pub use frames::{End, LastFrame, Recorder};

use crate::dynamics::State;

/// Sees a run of an `N`-dimensional system as it goes (the free body's 7 by default).
/// Observers compose as tuples: `(A, B)` is an observer.
pub trait Observer<const N: usize = 7> {
    /// Whether [`Observer::step`] must be called; `false` keeps the step loop bare.
    const WANTS_STEPS: bool = false;

    /// Called at frame `index` (time `t`), including the first (t = 0) and the last.
    fn frame(&mut self, _index: usize, _t: f64, _x: &[f64; N]) {}

    /// Whether it keeps every frame (a [`Recorder`]). A driver that reads frames off a step's
    /// interpolant shows every frame to such an observer; to others, of a step that spans
    /// more than [`crate::run::adaptive::FRAMES_READ_IN_A_STEP`] frames, the last only, so
    /// that a run that keeps no frames reads a bounded number a step (`frames = 2**31` ran for
    /// hours). The first and the last frame are always shown.
    fn keeps_frames(&self) -> bool {
        false
    }

    /// Called after every step from `(t0, x0)` to `(t1, x1)`.
    fn step(&mut self, _t0: f64, _x0: &[f64; N], _t1: f64, _x1: &[f64; N]) {}

    /// Called instead of [`Observer::step`] by methods with a continuous extension (the
    /// adaptive ones, whose steps can be long): `at(θ)` is the state at `t0 + θ (t1 − t0)`,
    /// to the method's accuracy. By default it is ignored.
    fn step_dense(
        &mut self,
        t0: f64,
        x0: &[f64; N],
        t1: f64,
        x1: &[f64; N],
        _at: &mut dyn FnMut(f64) -> [f64; N],
    ) {
        self.step(t0, x0, t1, x1);
    }
}

impl<const N: usize> Observer<N> for () {}

impl<const N: usize, A: Observer<N>, B: Observer<N>> Observer<N> for (A, B) {
    const WANTS_STEPS: bool = A::WANTS_STEPS || B::WANTS_STEPS;

    fn keeps_frames(&self) -> bool {
        self.0.keeps_frames() || self.1.keeps_frames()
    }

    #[inline(always)]
    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        self.0.frame(index, t, x);
        self.1.frame(index, t, x);
    }

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        if A::WANTS_STEPS {
            self.0.step(t0, x0, t1, x1);
        }
        if B::WANTS_STEPS {
            self.1.step(t0, x0, t1, x1);
        }
    }

    fn step_dense(
        &mut self,
        t0: f64,
        x0: &[f64; N],
        t1: f64,
        x1: &[f64; N],
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) {
        if A::WANTS_STEPS {
            self.0.step_dense(t0, x0, t1, x1, at);
        }
        if B::WANTS_STEPS {
            self.1.step_dense(t0, x0, t1, x1, at);
        }
    }
}

impl<const N: usize, O: Observer<N>> Observer<N> for &mut O {
    const WANTS_STEPS: bool = O::WANTS_STEPS;

    fn keeps_frames(&self) -> bool {
        (**self).keeps_frames()
    }

    #[inline(always)]
    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        (**self).frame(index, t, x);
    }

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        (**self).step(t0, x0, t1, x1);
    }

    fn step_dense(
        &mut self,
        t0: f64,
        x0: &[f64; N],
        t1: f64,
        x1: &[f64; N],
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) {
        (**self).step_dense(t0, x0, t1, x1, at);
    }
}

impl<const N: usize, O: Observer<N>> Observer<N> for Option<O> {
    const WANTS_STEPS: bool = O::WANTS_STEPS;

    fn keeps_frames(&self) -> bool {
        self.as_ref().is_some_and(O::keeps_frames)
    }

    #[inline(always)]
    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        if let Some(o) = self {
            o.frame(index, t, x);
        }
    }

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        if let Some(o) = self {
            o.step(t0, x0, t1, x1);
        }
    }

    fn step_dense(
        &mut self,
        t0: f64,
        x0: &[f64; N],
        t1: f64,
        x1: &[f64; N],
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) {
        if let Some(o) = self {
            o.step_dense(t0, x0, t1, x1, at);
        }
    }
}

/// Whether the rate changes sign from `r0` to `r1` (reaching zero counts).
#[inline(always)]
pub(crate) fn crosses(r0: f64, r1: f64) -> bool {
    (r0 > 0.0 && r1 <= 0.0) || (r0 < 0.0 && r1 >= 0.0)
}

/// `x[k]` for `k < 3`, by selection rather than indexing, so that the state can stay in
/// registers across the step loop.
#[inline(always)]
pub(crate) fn component(x: &State, k: usize) -> f64 {
    match k {
        0 => x[0],
        1 => x[1],
        _ => x[2],
    }
}
