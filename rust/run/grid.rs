//! The frame grid of a run: frames exactly at `t_end · i / (frames − 1)`, equal substeps between
//! them no longer than `dt`. Only frames reach the observers' storage, so the memory of a run
//! is set by `frames`, never by the step count.

use crate::error::{Error, Result};

/// The frame times of a run and the substeps between them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameGrid {
    t_end: f64,
    frames: usize,
    substeps: u64,
    /// The most steps the run may take (sample times count: each ends a step of its own).
    max_steps: u64,
}

impl FrameGrid {
    /// `frames` frames over `[0, t_end]` with substeps no longer than `dt`.
    ///
    /// # Errors
    /// `t_end` and `dt` must be positive and finite, `frames` at least 2, and the run's total
    /// step count at most `max_steps`.
    ///
    /// # Example
    /// ```
    /// let grid = dzhanibekov::run::FrameGrid::try_new(100.0, 201, 1e-3, u64::MAX).unwrap();
    /// assert_eq!(grid.n_steps(), 100_000);
    /// assert_eq!(grid.time(200), 100.0);
    /// ```
    pub fn try_new(t_end: f64, frames: usize, dt: f64, max_steps: u64) -> Result<Self> {
        if !(t_end.is_finite() && t_end > 0.0) {
            return Err(Error::invalid(
                "t_end",
                "must be positive and finite",
                t_end,
            ));
        }
        if frames < 2 {
            return Err(Error::invalid("frames", "must be at least 2", frames));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid("dt", "must be positive and finite", dt));
        }
        let intervals = (frames - 1) as f64;
        let substeps = (t_end / intervals / dt).ceil().max(1.0);
        let total = substeps * intervals;
        if total.is_nan() || total > max_steps as f64 {
            let (needed, hint) = match total.is_finite() {
                true => (
                    format!("{total:.3e} steps (t_end / dt)"),
                    "raise max_steps, or take a larger dt",
                ),
                // t_end / dt beyond float64: say so, not "inf steps" (no max_steps helps)
                false => (
                    format!(
                        "more steps than float64 counts (t_end / dt = {t_end:e} / {dt:e} \
                         overflows)"
                    ),
                    "take a shorter t_end or a larger dt",
                ),
            };
            return Err(Error::TooLarge {
                what: "the run".into(),
                needed,
                limit: max_steps_limit(max_steps),
                hint,
            });
        }
        Ok(Self {
            t_end,
            frames,
            substeps: substeps as u64,
            max_steps,
        })
    }

    /// [`FrameGrid::try_frames`] or [`FrameGrid::frames_only`] with the frames counted toward
    /// `max_steps`: each frame is work (an evaluation of the closed form, or of an adaptive
    /// method's interpolant), so a frame grid of 2^62 is refused up front like 2^62 steps.
    ///
    /// # Errors
    /// As those, and more than `max_steps` frames.
    pub fn try_frames_within(
        t_end: f64,
        frames: usize,
        max_steps: u64,
        adaptive: bool,
    ) -> Result<Self> {
        let mut grid = match adaptive {
            true => Self::frames_only(t_end, frames)?,
            false => Self::try_frames(t_end, frames)?,
        };
        grid.max_steps = max_steps;
        if frames as u64 > max_steps {
            return Err(Error::TooLarge {
                what: "the run".into(),
                needed: format!("{frames} frames (each is evaluated)"),
                limit: max_steps_limit(max_steps),
                hint: "ask for fewer frames, or raise max_steps",
            });
        }
        Ok(grid)
    }

    /// Frames only, for a method that takes no steps (`method = "exact"`).
    ///
    /// # Errors
    /// `t_end` must be positive and finite, and `frames` at least 2.
    pub fn try_frames(t_end: f64, frames: usize) -> Result<Self> {
        let mut grid = Self::try_new(t_end, frames, t_end, u64::MAX)?;
        grid.substeps = 0;
        Ok(grid)
    }

    /// The frames alone, for a method that chooses its own steps: one "substep" per frame.
    ///
    /// # Errors
    /// As [`FrameGrid::try_new`] for `t_end` and `frames`.
    pub fn frames_only(t_end: f64, frames: usize) -> Result<Self> {
        Self::try_new(t_end, frames, t_end.max(f64::MIN_POSITIVE), u64::MAX)
    }

    pub fn frames(&self) -> usize {
        self.frames
    }

    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// The most steps the run may take.
    pub fn max_steps(&self) -> u64 {
        self.max_steps
    }

    /// Substeps between consecutive frames.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// Steps in the whole run.
    pub fn n_steps(&self) -> u64 {
        self.substeps * (self.frames as u64 - 1)
    }

    /// The time of frame `i`; exactly `t_end` for the last.
    pub fn time(&self, i: usize) -> f64 {
        self.t_end * (i as f64 / (self.frames - 1) as f64)
    }

    /// The last frame at or before `t` (`0 ≤ t`), at most the last frame.
    pub fn frame_at_or_before(&self, t: f64) -> usize {
        let last = self.frames - 1;
        let guess = (t / self.t_end * last as f64).floor();
        let mut i = if guess >= 0.0 {
            (guess as usize).min(last)
        } else {
            0
        };
        while i < last && self.time(i + 1) <= t {
            i += 1;
        }
        while i > 0 && self.time(i) > t {
            i -= 1;
        }
        i
    }

    /// The step actually taken, at most the `dt` asked for; 0 for a grid without steps.
    pub fn step_size(&self) -> f64 {
        if self.substeps == 0 {
            return 0.0;
        }
        self.t_end / (self.frames - 1) as f64 / self.substeps as f64
    }

    /// The same frames and substeps over a span of `t_end` (a span in other units).
    pub(crate) fn with_t_end(&self, t_end: f64) -> Self {
        Self { t_end, ..*self }
    }
}

/// `max_steps` for a message: its value, unless it is the unlimited `u64::MAX`.
pub(crate) fn max_steps_limit(max_steps: u64) -> String {
    match max_steps {
        u64::MAX => "the most steps a run can count (2^64 - 1)".into(),
        n => format!("the limit max_steps = {n}"),
    }
}

#[cfg(test)]
mod limits {
    use super::*;

    #[test]
    fn a_step_count_beyond_float64_is_not_shown_as_inf() {
        let err = FrameGrid::try_new(1e300, 201, 1e-10, u64::MAX).unwrap_err();
        let text = err.to_string();
        assert!(!text.contains("inf steps"), "{text}");
        assert!(
            text.contains("t_end / dt = 1e300 / 1e-10 overflows"),
            "{text}"
        );
    }

    #[test]
    fn an_unlimited_max_steps_is_not_shown_as_a_number() {
        assert_eq!(max_steps_limit(10), "the limit max_steps = 10");
        assert!(!max_steps_limit(u64::MAX).contains("18446744073709551615"));
        let grid = FrameGrid::try_frames_within(1.0, 1 << 40, u64::MAX - 1, false);
        assert!(grid.is_ok());
        let err = FrameGrid::try_frames_within(1.0, 1 << 40, 1 << 20, true).unwrap_err();
        assert!(err.to_string().contains("1099511627776 frames"), "{err}");
    }
}
