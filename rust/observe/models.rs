//! Flips of the models beyond the free body (deployments, damped bodies), by the free body's
//! definition ([`crate::observe::FlipDetector`]) applied to the body as it is at each step: a
//! flip is the intermediate principal axis of the inertia *now* coming nearest the total
//! angular momentum `L` on one side (`|L_mid| > |L|/√2`) after it was nearest on the other,
//! timed at the sign change of `L_mid` in between (cubic Hermite interpolation, its slopes
//! from `dL/dt = L × ω`, which every torque-free model obeys in body axes).
//!
//! So a deployment that makes the spin axis intermediate shows its tumbling as flips, and one
//! that keeps it major shows none. Located where the principal axes are the body axes (every
//! tensor diagonal, [`Model::principal_moments`]) and the moments distinct; elsewhere none
//! are counted. An adaptive method's long steps are looked at at their ends only.

use nalgebra::Vector3;

use crate::dynamics::Model;
use crate::error::Result;

use super::sides::{hermite_zero, side_of, Sides};
use super::Observer;

/// Watches a model run for flips (see the module docs).
#[derive(Debug, Clone)]
pub struct ModelFlips<'a, S> {
    sys: &'a S,
    sides: Sides,
}

impl<'a, S> ModelFlips<'a, S> {
    pub fn new(sys: &'a S) -> Self {
        Self {
            sys,
            sides: Sides::default(),
        }
    }

    /// The flip times, or [`crate::Error::TooLarge`] if memory ran out for some of them.
    ///
    /// # Errors
    /// Flips whose times could not be stored.
    pub fn into_flip_times(self) -> Result<Vec<f64>> {
        self.sides.check_kept()?;
        Ok(self.sides.flip_times)
    }
}

/// The index of the strictly intermediate of three moments, if there is one.
fn intermediate(m: &Vector3<f64>) -> Option<usize> {
    (0..3).find(|&k| {
        let (a, b) = (m[(k + 1) % 3], m[(k + 2) % 3]);
        (a < m[k] && m[k] < b) || (b < m[k] && m[k] < a)
    })
}

/// `L` in body axes and the intermediate axis at `(t, x)`, where one is defined.
fn momentum_and_axis<const N: usize, S: Model<N>>(
    sys: &S,
    t: f64,
    x: &[f64; N],
) -> Option<(Vector3<f64>, usize)> {
    let k = intermediate(&sys.principal_moments(t)?)?;
    Some((sys.momentum_body(t, x), k))
}

impl<const N: usize, S: Model<N>> Observer<N> for ModelFlips<'_, S> {
    const WANTS_STEPS: bool = true;

    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        if let (0, Some((l, k))) = (index, momentum_and_axis(self.sys, t, x)) {
            self.sides.side = side_of(l[k], l.norm() * std::f64::consts::FRAC_1_SQRT_2);
        }
    }

    fn step(&mut self, t0: f64, x0: &[f64; N], t1: f64, x1: &[f64; N]) {
        let Some((l1, k)) = momentum_and_axis(self.sys, t1, x1) else {
            return;
        };
        let l0 = self.sys.momentum_body(t0, x0);
        if super::crosses(l0[k], l1[k]) {
            // the slope of L_k: (L × ω)_k, ω the body rates
            let slope =
                |t: f64, x: &[f64; N], l: &Vector3<f64>| l.cross(&self.sys.omega_body(t, x))[k];
            let h = t1 - t0;
            self.sides.candidate = Some(hermite_zero(
                t0,
                h,
                (l0[k], h * slope(t0, x0, &l0)),
                (l1[k], h * slope(t1, x1, &l1)),
            ));
        }
        let threshold = l1.norm() * std::f64::consts::FRAC_1_SQRT_2;
        self.sides.settle(side_of(l1[k], threshold));
    }
}
