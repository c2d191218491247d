//! The bookkeeping of flips shared by the free body's detector and the models': which side
//! of `L` the intermediate axis was last seen nearest, the crossing seen since, the times.

use crate::error::{Error, Result};

/// The side the intermediate axis was last seen nearest `L` on, the sign change of its
/// component seen since, and the flips counted.
#[derive(Debug, Clone, Default)]
pub(crate) struct Sides {
    /// −1 or +1: the side last seen; 0 before any.
    pub(crate) side: i8,
    /// The time of the sign change seen since that side.
    pub(crate) candidate: Option<f64>,
    pub(crate) flip_times: Vec<f64>,
    /// Flips found but not kept: the memory for their times could not be had.
    lost: u64,
}

impl Sides {
    /// Counts a flip if the axis has come near `L` on `side` (−1, 0 for neither, +1),
    /// opposite to the last one, with a crossing seen since.
    #[inline(always)]
    pub(crate) fn settle(&mut self, side: i8) {
        // the common cases first, without a store: between sides, or staying on the last
        if side == 0 || (side == self.side && self.candidate.is_none()) {
            return;
        }
        self.arrive(side);
    }

    /// The axis has come near `L` on `side`: a flip if that is the other side and a crossing
    /// was seen since. Rare (twice per flip period), so kept out of the step loop.
    #[cold]
    #[inline(never)]
    fn arrive(&mut self, side: i8) {
        if side == -self.side {
            if let Some(tc) = self.candidate {
                // grown fallibly: a run of 10¹⁰ steps can find more flips than memory holds,
                // and that is an error at the end of the run, not an abort
                match self.flip_times.try_reserve(1) {
                    Ok(()) => self.flip_times.push(tc),
                    Err(_) => self.lost += 1,
                }
            }
        }
        self.side = side;
        self.candidate = None;
    }

    /// [`Error::TooLarge`] if some flip times could not be stored.
    pub(crate) fn check_kept(&self) -> Result<()> {
        match self.lost {
            0 => Ok(()),
            lost => Err(Error::TooLarge {
                what: "keeping the flip times".into(),
                needed: format!("{} values", self.flip_times.len() as u64 + lost),
                limit: "the memory this process can allocate".into(),
                hint: "take a shorter t_end, or do not ask for the flips (`flips=False`)",
            }),
        }
    }
}

/// −1, 0 or +1: whether a component `l_k` of `L` is beyond `threshold` on either side.
#[inline(always)]
pub(crate) fn side_of(l_k: f64, threshold: f64) -> i8 {
    if l_k > threshold {
        1
    } else if l_k < -threshold {
        -1
    } else {
        0
    }
}

/// The zero in `[t0, t0 + h]` of the cubic Hermite interpolant with values `p0`, `p1` and
/// slopes times `h` `m0`, `m1` (a sign change of `p`), by bisection.
#[cold]
#[inline(never)]
pub(crate) fn hermite_zero(t0: f64, h: f64, (p0, m0): (f64, f64), (p1, m1): (f64, f64)) -> f64 {
    let hermite = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * p0
            + (s3 - 2.0 * s2 + s) * m0
            + (-2.0 * s3 + 3.0 * s2) * p1
            + (s3 - s2) * m1
    };
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let positive_at_lo = p0 > 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (hermite(mid) > 0.0) == positive_at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    t0 + 0.5 * (lo + hi) * h
}
