//! The flips: half-turns of the body's intermediate axis relative to the angular momentum,
//! for every model.
//!
//! A flip is counted when the intermediate principal axis of the body as it is now, having
//! been the axis nearest the total angular momentum `L` on one side (`|L_mid| > |L|/√2`,
//! which no other axis can then match), becomes the nearest on the other side. Its time is
//! the sign change of `L_mid` in between, located inside the step by cubic Hermite
//! interpolation (slopes from `dL/dt`, error O(h⁴)), or on the method's own continuous
//! extension when it has one (the adaptive methods), not on the frame grid. Dominance is seen
//! at the step ends and, on a continuous extension, also at the peak of `L_mid` inside a
//! step, whose long steps can hold a whole stretch of it. Small wobbles about a stable axis
//! also change that component's sign but never bring the intermediate axis near `L`, so they
//! are not flips. A symmetric top has no intermediate axis and no flips.
//!
//! So a deployment that makes the spin axis intermediate shows its tumbling as flips, one that
//! keeps it major shows none, and a damped body's flips stop once its spin goes flat.

use nalgebra::Vector3;

use crate::dynamics::{Conserved, MidAxis, Model};

use super::sides::{hermite_zero, side_of, Sides};
use super::{crosses, Observer};

/// Watches a run of `sys` for flips (see the module docs).
#[derive(Debug, Clone)]
pub struct FlipDetector<'a, S> {
    sys: &'a S,
    /// `|L₀|/√2` for a model that keeps `|L|`; NaN for one whose `|L|` changes (a torque),
    /// where it is taken at every step.
    threshold: f64,
    /// The last direction of an intermediate axis that is not a body axis, to keep its sign.
    along: Option<Vector3<f64>>,
    sides: Sides,
}

/// The intermediate axis as the detector reads it: a body axis, or a unit vector.
#[derive(Debug, Clone, Copy)]
enum Axis {
    Body(usize),
    Along(Vector3<f64>),
}

impl Axis {
    /// The component of `v` along the axis.
    #[inline(always)]
    fn of(&self, v: &Vector3<f64>) -> f64 {
        match self {
            Axis::Body(k) => match k {
                0 => v.x,
                1 => v.y,
                _ => v.z,
            },
            Axis::Along(e) => e.dot(v),
        }
    }
}

impl<'a, S> FlipDetector<'a, S> {
    /// A detector for a run of `sys` from `x0` at `t0`.
    pub fn new<const N: usize>(sys: &'a S, t0: f64, x0: &[f64; N]) -> Self
    where
        S: Model<N>,
    {
        let threshold = match sys.conserved().contains(Conserved::MOMENTUM) {
            true => sys.momentum_body(t0, x0).norm() * std::f64::consts::FRAC_1_SQRT_2,
            false => f64::NAN,
        };
        Self {
            sys,
            threshold,
            along: None,
            sides: Sides::default(),
        }
    }

    /// The flip times, or [`crate::Error::TooLarge`] if memory ran out for some of them.
    ///
    /// # Errors
    /// Flips whose times could not be stored.
    pub fn into_flip_times(mut self) -> crate::error::Result<Vec<f64>> {
        self.check_kept()?;
        Ok(std::mem::take(&mut self.sides.flip_times))
    }

    /// [`crate::Error::TooLarge`] if some flip times could not be stored.
    pub(crate) fn check_kept(&self) -> crate::error::Result<()> {
        self.sides.check_kept()
    }

    /// Moves the flip times found so far out of the detector (for runs that count them).
    pub(crate) fn take_flip_times(&mut self) -> Vec<f64> {
        std::mem::take(&mut self.sides.flip_times)
    }

    /// The side the intermediate axis was last seen nearest `L` on (−1, 0 before any, +1),
    /// and whether a crossing awaits that axis's arrival on a side.
    pub(crate) fn progress(&self) -> (f64, bool) {
        (f64::from(self.sides.side), self.sides.candidate.is_some())
    }

    /// The threshold of [`side_of`] for `L` at this step.
    #[inline(always)]
    fn threshold_for(&self, l: &Vector3<f64>) -> f64 {
        match self.threshold.is_nan() {
            true => l.norm() * std::f64::consts::FRAC_1_SQRT_2,
            false => self.threshold,
        }
    }
}

impl<S> FlipDetector<'_, S> {
    /// The intermediate axis at `t`, an axis that is not a body axis signed as it was last.
    #[inline(always)]
    fn axis<const N: usize>(&mut self, t: f64) -> Option<Axis>
    where
        S: Model<N>,
    {
        match self.sys.intermediate_axis(t) {
            MidAxis::None => None,
            MidAxis::Body(k) => Some(Axis::Body(k)),
            MidAxis::Along(e) => Some(Axis::Along(self.signed(e))),
        }
    }

    #[cold]
    #[inline(never)]
    fn signed(&mut self, e: Vector3<f64>) -> Vector3<f64> {
        let e = match self.along {
            Some(last) if last.dot(&e) < 0.0 => -e,
            _ => e,
        };
        self.along = Some(e);
        e
    }

    /// The zero of `L_mid` on `[t0, t1]` on a continuous extension `at`, by bisection.
    #[cold]
    #[inline(never)]
    fn crossing_on<const N: usize>(
        &self,
        axis: Axis,
        (t0, t1): (f64, f64),
        positive_at_t0: bool,
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) -> f64
    where
        S: Model<N>,
    {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            let t = t0 + mid * (t1 - t0);
            if (axis.of(&self.sys.momentum_body(t, &at(mid))) > 0.0) == positive_at_t0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        t0 + 0.5 * (lo + hi) * (t1 - t0)
    }

    /// The time and momentum of the extremum of `L_mid` on `[t0, t1]` on a continuous
    /// extension `at`: the sign change of its rate, by bisection.
    #[cold]
    #[inline(never)]
    fn peak_on<const N: usize>(
        &self,
        axis: Axis,
        (t0, t1): (f64, f64),
        rising_at_t0: bool,
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) -> (f64, Vector3<f64>)
    where
        S: Model<N>,
    {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            let t = t0 + mid * (t1 - t0);
            if (axis.of(&self.sys.momentum_rate(t, &at(mid))) > 0.0) == rising_at_t0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let theta = 0.5 * (lo + hi);
        let t = t0 + theta * (t1 - t0);
        (t, self.sys.momentum_body(t, &at(theta)))
    }

    /// The zero of the cubic Hermite interpolant of `L_mid` over a step, its slopes from the
    /// momentum's rate. Rare (twice per flip period), so kept out of the step loop. The
    /// states come by value: a reference would make the step loop keep them in memory for
    /// this call's sake, and reload them there (a stall: a wide load of narrow stores).
    #[cold]
    #[inline(never)]
    fn crossing<const N: usize>(
        &self,
        axis: Axis,
        (t0, x0, l0): (f64, [f64; N], f64),
        (t1, x1, l1): (f64, [f64; N], f64),
    ) -> f64
    where
        S: Model<N>,
    {
        let h = t1 - t0;
        let slope = |t: f64, x: &[f64; N]| h * axis.of(&self.sys.momentum_rate(t, x));
        hermite_zero(t0, h, (l0, slope(t0, &x0)), (l1, slope(t1, &x1)))
    }

    /// Counts a flip if the intermediate axis has come near `L` on the side opposite to the
    /// last one, at the crossing seen since.
    #[inline(always)]
    fn settle(&mut self, axis: Axis, l: &Vector3<f64>) {
        let side = side_of(axis.of(l), self.threshold_for(l));
        self.sides.settle(side);
    }
}

/// # The lanes' view
///
/// What the SIMD lanes of a batch ([`crate::ensemble::lanes`]) mirror to tell, for many runs
/// at once, whether [`Observer::step`] would change anything; only then is it called.
impl FlipDetector<'_, crate::dynamics::FreeRigidBody> {
    /// The intermediate axis, its moment and the threshold of `side_of`; `None` for a
    /// symmetric top, which never flips.
    pub(crate) fn watch(&self) -> Option<(usize, f64, f64)> {
        match Model::<7>::intermediate_axis(self.sys, 0.0) {
            MidAxis::Body(k) => Some((k, self.sys.body().inertia_body()[k], self.threshold)),
            _ => None,
        }
    }
}

impl<const N: usize, S: Model<N>> Observer<N> for FlipDetector<'_, S> {
    const WANTS_STEPS: bool = true;

    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        if index == 0 {
            if let Some(axis) = self.axis(t) {
                let l = self.sys.momentum_body(t, x);
                self.sides.side = side_of(axis.of(&l), self.threshold_for(&l));
            }
        }
    }

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        let Some(axis) = self.axis(t1) else { return };
        let l1 = self.sys.momentum_body(t1, x1);
        let (r0, r1) = (axis.of(&self.sys.momentum_body(t0, x0)), axis.of(&l1));
        if crosses(r0, r1) {
            self.sides.candidate = Some(self.crossing(axis, (t0, *x0, r0), (t1, *x1, r1)));
        }
        self.settle(axis, &l1);
    }

    fn step_dense(
        &mut self,
        t0: f64,
        x0: &[f64; N],
        t1: f64,
        x1: &[f64; N],
        at: &mut dyn FnMut(f64) -> [f64; N],
    ) {
        let Some(axis) = self.axis(t1) else { return };
        let l1 = self.sys.momentum_body(t1, x1);
        let (r0, r1) = (axis.of(&self.sys.momentum_body(t0, x0)), axis.of(&l1));
        let crossing = crosses(r0, r1).then(|| self.crossing_on(axis, (t0, t1), r0 > 0.0, at));
        // A long step can hold a whole stretch of dominance that neither end shows: where
        // L_mid peaks inside it (its rate changes sign), the peak is looked at too.
        let (s0, s1) = (
            axis.of(&self.sys.momentum_rate(t0, x0)),
            axis.of(&self.sys.momentum_rate(t1, x1)),
        );
        let peak = crosses(s0, s1).then(|| self.peak_on(axis, (t0, t1), s0 > 0.0, at));
        match (crossing, peak) {
            (Some(tc), Some((tp, l))) if tp < tc => {
                self.settle(axis, &l);
                self.sides.candidate = Some(tc);
            }
            (crossing, peak) => {
                if let Some(tc) = crossing {
                    self.sides.candidate = Some(tc);
                }
                if let Some((_, l)) = peak {
                    self.settle(axis, &l);
                }
            }
        }
        self.settle(axis, &l1);
    }
}
