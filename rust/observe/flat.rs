//! The time a damped body goes flat: the first time its major principal axis carries
//! [`FLAT_SHARE`] of the total angular momentum `|L|`, located during the run like the flips.
//!
//! With `f = Σ_major L_k² − s² |L|²` (the major axis, or the plane of the two largest moments
//! of a symmetric top), the spin is flat from the first `f ≥ 0` on. Its time is the sign
//! change of `f` inside the step where it first happens, located by cubic Hermite
//! interpolation (slopes from `dL/dt`, error O(h⁴)), or on the method's continuous extension
//! when it has one (an adaptive method's long step is also looked at where `f` peaks inside
//! it). So the time does not depend on the frames: on the frame grid, the nutation that rides
//! on the slow rise of the share put it at the first frame past a crossing, by up to a
//! nutation period late (a (1, 2, 3) body with `Damper(0.05, 0.05)` from ω₀ = (1, 0.01, 0.01):
//! 1295 with 601 frames to t = 3000, 1258 with 3001).
//!
//! Only a damped body with a constant inertia is watched (see [`FlatAxes`]): it is where a
//! spin goes flat for good; other runs report no time.

use nalgebra::Vector3;

use crate::dynamics::{EnergyRole, FreeRigidBody, GeneralModel, InertiaLaw, Model, Movers};

use super::sides::hermite_zero;
use super::Observer;

/// The share of `|L|` on the major axis from which a spin is flat.
pub const FLAT_SHARE: f64 = 0.99;

/// Moments within this relative distance of the largest count as major (the plane of a
/// symmetric top's two largest).
const MAJOR_TOLERANCE: f64 = 1e-12;

/// The major principal axes of a model whose spin can go flat, as body axes: `Some` for a
/// damped body of constant, principal inertia; `None` for the others, which are not watched.
pub trait FlatAxes<const N: usize> {
    fn flat_axes(&self) -> Option<[bool; 3]>;
}

impl FlatAxes<7> for FreeRigidBody {
    fn flat_axes(&self) -> Option<[bool; 3]> {
        None
    }
}

impl<const N: usize, const HOT: bool, M: Movers> FlatAxes<N> for GeneralModel<N, HOT, M> {
    fn flat_axes(&self) -> Option<[bool; 3]> {
        // a part that dissipates (a damper) brings the spin to the major axis
        (self.parts().iter()).find(|p| p.info().energy == EnergyRole::Dissipates)?;
        let InertiaLaw::Constant(c) = self.inertia() else {
            return None;
        };
        let moments = c.moments()?;
        let largest = moments.max();
        Some(std::array::from_fn(|k| {
            moments[k] >= largest * (1.0 - MAJOR_TOLERANCE)
        }))
    }
}

/// Watches a run for the time its spin goes flat (see the module doc).
#[derive(Debug, Clone)]
pub struct FlatSpin<'a, S> {
    sys: &'a S,
    major: [bool; 3],
    share2: f64,
    /// The time found, once found.
    time: Option<f64>,
}

impl<'a, S> FlatSpin<'a, S> {
    /// A watch of `sys`'s run for the first time its `major` axes carry [`FLAT_SHARE`] of `|L|`.
    pub fn new(sys: &'a S, major: [bool; 3]) -> Self {
        Self {
            sys,
            major,
            share2: FLAT_SHARE * FLAT_SHARE,
            time: None,
        }
    }

    /// The time found; NaN if the spin never went flat.
    pub fn time(&self) -> f64 {
        self.time.unwrap_or(f64::NAN)
    }

    /// `Σ_major a_k b_k − s² a·b`: `f` for `a = b = L`, half its rate for `b = L'`.
    #[inline(always)]
    fn form(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        let major: f64 = (0..3).filter(|&k| self.major[k]).map(|k| a[k] * b[k]).sum();
        major - self.share2 * a.dot(b)
    }

    /// `f` at `(t, x)`.
    #[inline(always)]
    fn f<const N: usize>(&self, t: f64, x: &[f64; N]) -> f64
    where
        S: Model<N>,
    {
        let l = self.sys.momentum_body(t, x);
        self.form(&l, &l)
    }

    /// `f'` at `(t, x)`.
    fn slope<const N: usize>(&self, t: f64, x: &[f64; N]) -> f64
    where
        S: Model<N>,
    {
        let l = self.sys.momentum_body(t, x);
        2.0 * self.form(&l, &self.sys.momentum_rate(t, x))
    }

    /// The first `θ` in `[0, hi]` where `g(θ)` turns non-negative, `g(0) < 0 ≤ g(hi)`, by
    /// bisection.
    fn bisect(mut g: impl FnMut(f64) -> f64, hi: f64) -> f64 {
        let (mut lo, mut hi) = (0.0_f64, hi);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if g(mid) >= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

impl<const N: usize, S: Model<N>> Observer<N> for FlatSpin<'_, S> {
    const WANTS_STEPS: bool = true;

    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        if index == 0 && self.f(t, x) >= 0.0 {
            self.time = Some(t);
        }
    }

    #[inline(always)]
    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        if self.time.is_some() {
            return;
        }
        let f1 = self.f(t1, x1);
        if f1 >= 0.0 {
            self.cross(t0, x0, t1, x1, f1);
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
        if self.time.is_some() {
            return;
        }
        let h = t1 - t0;
        let end = if self.f(t1, x1) >= 0.0 {
            Some(1.0)
        } else if self.slope(t0, x0) > 0.0 && self.slope(t1, x1) <= 0.0 {
            // a long step can rise over the share and fall back inside: look where f peaks
            let peak = Self::bisect(|u| -self.slope(t0 + u * h, &at(u)), 1.0);
            (self.f(t0 + peak * h, &at(peak)) >= 0.0).then_some(peak)
        } else {
            None
        };
        if let Some(end) = end {
            let theta = Self::bisect(|u| self.f(t0 + u * h, &at(u)), end);
            self.time = Some(t0 + theta * h);
        }
    }
}

impl<S> FlatSpin<'_, S> {
    /// The crossing inside a step whose end is flat (`f1 ≥ 0`), on the cubic Hermite
    /// interpolant of `f`. Once a run, so kept out of the step loop.
    #[cold]
    #[inline(never)]
    fn cross<const N: usize>(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N], f1: f64)
    where
        S: Model<N>,
    {
        let h = t1 - t0;
        let f0 = self.f(t0, x0);
        let (m0, m1) = (h * self.slope(t0, x0), h * self.slope(t1, x1));
        // `hermite_zero` finds the sign change of a strict sign at its start
        self.time = Some(match f0 < 0.0 {
            true => hermite_zero(t0, h, (f0, m0), (f1, m1)),
            false => t0,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bisection_finds_the_first_non_negative_point() {
        // g(θ) = θ − 0.3: turns non-negative at 0.3
        let theta = FlatSpin::<'_, FreeRigidBody>::bisect(|u| u - 0.3, 1.0);
        assert!((theta - 0.3).abs() < 1e-15, "{theta}");
    }
}
