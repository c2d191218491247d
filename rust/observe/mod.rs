//! What a run keeps: observers see the frames (and, if they ask, every step) and keep only
//! what a caller needs — stored frames, invariant drift, flip times.

pub mod models;
mod sides;
pub mod tilt;

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::buffer::zeroed;
use crate::dynamics::{Invariants, State};
use sides::{hermite_zero, side_of, Sides};

/// Sees a run of an `N`-dimensional system as it goes (the free body's 7 by default).
/// Observers compose as tuples: `(A, B)` is an observer.
pub trait Observer<const N: usize = 7> {
    /// Whether [`Observer::step`] must be called; `false` keeps the step loop bare.
    const WANTS_STEPS: bool = false;

    /// Called at frame `index` (time `t`), including the first (t = 0) and the last.
    fn frame(&mut self, _index: usize, _t: f64, _x: &[f64; N]) {}

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

/// Stores ω and q at every frame, time-major: `omega` is `(frames, 3)`, `q` is `(frames, 4)`.
#[derive(Debug, Clone, Default)]
pub struct FrameRecorder {
    pub omega: Vec<f64>,
    pub q: Vec<f64>,
}

impl FrameRecorder {
    /// A recorder with room for `frames` frames.
    ///
    /// # Errors
    /// [`crate::Error::TooLarge`] if the buffers cannot be allocated.
    pub fn with_frames(frames: usize) -> crate::Result<Self> {
        let len = |k: usize| frames.saturating_mul(k);
        Ok(Self {
            omega: zeroed(len(3), "the frames")?,
            q: zeroed(len(4), "the frames")?,
        })
    }
}

impl Observer for FrameRecorder {
    #[inline]
    fn frame(&mut self, index: usize, _t: f64, x: &State) {
        self.omega[3 * index..3 * index + 3].copy_from_slice(&x[..3]);
        self.q[4 * index..4 * index + 4].copy_from_slice(&x[3..]);
    }
}

/// The largest departure of each invariant from its initial value, over the frames.
///
/// Energy and `|L|` are relative; the world-frame momentum is `|L(t) - L(0)| / |L(0)|`; the
/// quaternion's is `||q| - 1|` (the run starts from a unit quaternion). Computed on a scaled
/// copy (moments over the largest, ω over its largest initial component) so that no
/// intermediate overflows; relative measures do not change under the scaling.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Drift {
    pub energy: f64,
    pub momentum: f64,
    pub momentum_world: f64,
    pub q_norm: f64,
}

/// Watches the invariants at every frame and keeps their [`Drift`].
#[derive(Debug, Clone)]
pub struct DriftMonitor {
    inertia_scaled: Vector3<f64>,
    omega_scale: f64,
    initial: Option<Invariants>,
    pub drift: Drift,
}

impl DriftMonitor {
    pub fn new(body: &RigidBody, omega0: &Vector3<f64>) -> Self {
        let inertia = body.inertia_body();
        let largest = omega0.amax();
        Self {
            inertia_scaled: inertia / inertia.max(),
            omega_scale: if largest > 0.0 { 1.0 / largest } else { 1.0 },
            initial: None,
            drift: Drift {
                energy: 0.0,
                momentum: 0.0,
                momentum_world: 0.0,
                q_norm: 0.0,
            },
        }
    }
}

fn relative(a: f64, a0: f64) -> f64 {
    if a0 == 0.0 {
        (a - a0).abs()
    } else {
        ((a - a0) / a0).abs()
    }
}

impl Observer for DriftMonitor {
    fn frame(&mut self, _index: usize, _t: f64, x: &State) {
        let mut scaled = *x;
        for w in &mut scaled[..3] {
            *w *= self.omega_scale;
        }
        let now = Invariants::of(&self.inertia_scaled, &scaled);
        let first = *self.initial.get_or_insert(now);
        let l0 = first.l_body.norm();
        let d = &mut self.drift;
        d.energy = d.energy.max(relative(now.energy, first.energy));
        d.momentum = d.momentum.max(relative(now.l_body.norm(), l0));
        let dl = (now.l_world - first.l_world).norm();
        d.momentum_world = d.momentum_world.max(if l0 > 0.0 { dl / l0 } else { dl });
        d.q_norm = d.q_norm.max((now.q_norm - 1.0).abs());
    }
}

/// Finds the flips: half-turns of the intermediate axis relative to the angular momentum.
///
/// A flip is counted when the body's intermediate axis, having been the axis nearest to `L`
/// on one side (`|L_mid| > |L|/√2`, which no other axis can then match), becomes the nearest
/// on the other side. Its time is the sign change of the intermediate-axis rate in between,
/// located inside the step by cubic Hermite interpolation (error O(h⁴)), or on the method's
/// own continuous extension when it has one (the adaptive methods), not on the frame grid.
/// Dominance is seen at the step ends and, on a continuous extension, also at the peak of
/// `ω_mid` inside a step, whose long steps can hold a whole stretch of it. Small wobbles about
/// a stable axis also change that rate's sign but never bring the intermediate axis near
/// `L`, so they are not flips. A symmetric top has no intermediate axis and no flips.
#[derive(Debug, Clone)]
pub struct FlipDetector {
    axis: Option<usize>,
    inertia_mid: f64,
    euler_mid: f64,
    threshold: f64,
    sides: Sides,
}

impl FlipDetector {
    /// A detector for `body` starting from body rates `omega0`; `euler` are the coefficients of
    /// Euler's equations (see [`crate::FreeRigidBody::euler_coefficients`]).
    pub fn new(body: &RigidBody, euler: &Vector3<f64>, omega0: &Vector3<f64>) -> Self {
        let axis = body.intermediate_axis();
        let inertia = body.inertia_body();
        let k = axis.unwrap_or(0);
        let scale = inertia.max();
        let l0 = (inertia / scale).component_mul(omega0).norm();
        Self {
            axis,
            inertia_mid: inertia[k] / scale,
            euler_mid: euler[k],
            threshold: l0 * std::f64::consts::FRAC_1_SQRT_2,
            sides: Sides::default(),
        }
    }

    #[inline(always)]
    fn side_of(&self, rate: f64) -> i8 {
        side_of(self.inertia_mid * rate, self.threshold)
    }

    /// The zero of the cubic Hermite interpolant of ω_mid on `[t0, t1]`, its slopes from
    /// Euler's equation. Rare (twice per flip period), so kept out of the step loop.
    #[cold]
    #[inline(never)]
    fn crossing(&self, k: usize, t0: f64, x0: &State, t1: f64, x1: &State) -> f64 {
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let h = t1 - t0;
        hermite_zero(
            t0,
            h,
            (x0[k], h * self.euler_mid * x0[a] * x0[b]),
            (x1[k], h * self.euler_mid * x1[a] * x1[b]),
        )
    }

    /// The zero of ω_mid on `[t0, t1]` on a continuous extension `at`, by bisection.
    #[cold]
    #[inline(never)]
    fn crossing_on(
        &self,
        k: usize,
        t0: f64,
        t1: f64,
        positive_at_t0: bool,
        at: &mut dyn FnMut(f64) -> State,
    ) -> f64 {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if (at(mid)[k] > 0.0) == positive_at_t0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        t0 + 0.5 * (lo + hi) * (t1 - t0)
    }

    /// The time and value of the extremum of ω_mid on `[t0, t1]` on a continuous extension
    /// `at`: the sign change of its slope `∝ ω_a ω_b`, by bisection.
    #[cold]
    #[inline(never)]
    fn peak_on(
        &self,
        k: usize,
        t0: f64,
        t1: f64,
        positive_at_t0: bool,
        at: &mut dyn FnMut(f64) -> State,
    ) -> (f64, f64) {
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            let x = at(mid);
            if (x[a] * x[b] > 0.0) == positive_at_t0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let theta = 0.5 * (lo + hi);
        (t0 + theta * (t1 - t0), at(theta)[k])
    }

    /// Counts a flip if the intermediate axis has come near `L` on the side opposite to the
    /// last one, at the crossing seen since.
    #[inline(always)]
    fn settle(&mut self, rate: f64) {
        self.sides.settle(self.side_of(rate));
    }
}

/// # The lanes' view
///
/// What the SIMD lanes of a batch ([`crate::ensemble::lanes`]) mirror to tell, for many runs at once,
/// whether [`Observer::step`] would change anything; only then is it called.
impl FlipDetector {
    /// The intermediate axis, its moment (scaled as in `side_of`) and the threshold of
    /// `side_of`; `None` for a symmetric top, which never flips.
    pub(crate) fn watch(&self) -> Option<(usize, f64, f64)> {
        self.axis.map(|k| (k, self.inertia_mid, self.threshold))
    }

    /// The side the intermediate axis was last seen nearest `L` on (−1, 0 before any, +1),
    /// and whether a crossing awaits that axis's arrival on a side.
    pub(crate) fn progress(&self) -> (f64, bool) {
        (f64::from(self.sides.side), self.sides.candidate.is_some())
    }

    /// Moves the flip times found so far out of the detector (for runs that count them).
    pub(crate) fn take_flip_times(&mut self) -> Vec<f64> {
        std::mem::take(&mut self.sides.flip_times)
    }

    /// The flip times, or [`Error::TooLarge`] if memory ran out for some of them.
    ///
    /// # Errors
    /// Flips whose times could not be stored.
    pub fn into_flip_times(mut self) -> crate::error::Result<Vec<f64>> {
        self.check_kept()?;
        Ok(std::mem::take(&mut self.sides.flip_times))
    }

    /// [`Error::TooLarge`] if some flip times could not be stored.
    pub(crate) fn check_kept(&self) -> crate::error::Result<()> {
        self.sides.check_kept()
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

impl Observer for FlipDetector {
    const WANTS_STEPS: bool = true;

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &State, t1: f64, x1: &State) {
        let Some(k) = self.axis else { return };
        let (r0, r1) = (component(x0, k), component(x1, k));
        if crosses(r0, r1) {
            self.sides.candidate = Some(self.crossing(k, t0, x0, t1, x1));
        }
        self.settle(r1);
    }

    fn step_dense(
        &mut self,
        t0: f64,
        x0: &State,
        t1: f64,
        x1: &State,
        at: &mut dyn FnMut(f64) -> State,
    ) {
        let Some(k) = self.axis else { return };
        let (r0, r1) = (component(x0, k), component(x1, k));
        let crossing = crosses(r0, r1).then(|| self.crossing_on(k, t0, t1, r0 > 0.0, at));
        // A long step can hold a whole stretch of dominance that neither end shows: where
        // ω_mid peaks inside it (its slope ∝ ω_a ω_b changes sign), the peak is looked at too.
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let peak = crosses(x0[a] * x0[b], x1[a] * x1[b])
            .then(|| self.peak_on(k, t0, t1, x0[a] * x0[b] > 0.0, at));
        match (crossing, peak) {
            (Some(tc), Some((tp, rate))) if tp < tc => {
                self.settle(rate);
                self.sides.candidate = Some(tc);
            }
            (crossing, peak) => {
                if let Some(tc) = crossing {
                    self.sides.candidate = Some(tc);
                }
                if let Some((_, rate)) = peak {
                    self.settle(rate);
                }
            }
        }
        self.settle(r1);
    }

    fn frame(&mut self, index: usize, _t: f64, x: &State) {
        if index == 0 {
            if let Some(k) = self.axis {
                self.sides.side = self.side_of(x[k]);
            }
        }
    }
}
