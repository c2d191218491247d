//! The options of a run, in one place: one default, one validation. The bindings build them
//! from what Python gives (kinds already coerced), and every entry point reads them.

use crate::error::{Error, Result};
use crate::ode::controller::check_rtol;

use crate::ode::controller::default_atol;

use super::registry::{Method, DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_METHOD, DEFAULT_RTOL};

/// What a run is asked to do, checked (see [`RunOptions::try_new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// The end time, positive and finite.
    pub t_end: f64,
    /// Frames stored, at least 2, at `t_end · i / (frames − 1)`.
    pub frames: usize,
    /// The largest step of a fixed-step method, the first step of an adaptive one; `None`
    /// picks it (for the accuracy `rtol`, or by the adaptive method itself).
    pub dt: Option<f64>,
    /// The method, an adaptive one with its tolerances.
    pub method: Method,
    /// The accuracy a fixed step is picked for, an adaptive method's relative tolerance.
    pub rtol: f64,
    /// An adaptive method's absolute tolerance.
    pub atol: f64,
    /// Refuse runs needing more steps (or adaptive attempts, or evaluated frames).
    pub max_steps: u64,
    /// Locate the flips.
    pub flips: bool,
    /// A batch's threads; `None` for all cores.
    pub threads: Option<usize>,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            t_end: 100.0,
            frames: 201,
            dt: None,
            method: Method::Rk4,
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
            max_steps: DEFAULT_MAX_STEPS,
            flips: true,
            threads: None,
        }
    }
}

impl RunOptions {
    /// Options checked against each other: `t_end` positive and finite; `frames` at least 2;
    /// `dt` positive and finite; `method` a name of the registry; `rtol` (default
    /// [`DEFAULT_RTOL`]) at least 100 ulps and below 1; `atol` (default [`default_atol`] of
    /// `rtol`: [`DEFAULT_ATOL`] at the default `rtol`) positive and finite and given only to an adaptive method; `rtol` not given with a `dt`
    /// to a fixed-step method (it sets the step only with `dt = None`); `max_steps` and
    /// `threads` at least 1. `None` for `method` and `max_steps` takes the defaults. The counts
    /// come signed, as callers give them, and are refused below their minimum here.
    ///
    /// # Errors
    /// What the list above refuses, naming the argument.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::run::options::RunOptions;
    /// let o = RunOptions::try_new(10.0, 11, None, Some("dop853"), Some(1e-10), None, None, true, None).unwrap();
    /// assert!(RunOptions::try_new(10.0, 1, None, None, None, None, None, true, None).is_err());
    /// assert!(o.method.is_adaptive());
    /// let e = RunOptions::try_new(10.0, 11, Some(0.1), Some("rk4"), None, Some(1e-9), None, true, None);
    /// assert!(e.unwrap_err().to_string().contains("`atol`"));
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn try_new(
        t_end: f64,
        frames: i64,
        dt: Option<f64>,
        method: Option<&str>,
        rtol: Option<f64>,
        atol: Option<f64>,
        max_steps: Option<i64>,
        flips: bool,
        threads: Option<i64>,
    ) -> Result<Self> {
        if !(t_end.is_finite() && t_end > 0.0) {
            return Err(Error::invalid(
                "t_end",
                "must be positive and finite",
                t_end,
            ));
        }
        let frames = usize::try_from(frames)
            .ok()
            .filter(|f| *f >= 2)
            .ok_or_else(|| Error::invalid("frames", "must be at least 2", frames))?;
        if let Some(h) = dt {
            if !(h.is_finite() && h > 0.0) {
                return Err(Error::invalid(
                    "dt",
                    "must be positive and finite, or None",
                    h,
                ));
            }
        }
        let name = method.unwrap_or(DEFAULT_METHOD);
        let adaptive = name.parse::<Method>()?.is_adaptive();
        if !adaptive {
            if let Some(a) = atol {
                return Err(Error::invalid(
                    "atol",
                    "applies to the adaptive methods ('dopri5', 'dop853') only",
                    a,
                ));
            }
            if let (Some(_), Some(h)) = (rtol, dt) {
                return Err(Error::invalid(
                    "rtol",
                    "sets the step of a fixed-step method only with dt=None",
                    format!("rtol with dt={h}"),
                ));
            }
        }
        let rtol = check_rtol(rtol.unwrap_or(DEFAULT_RTOL))?;
        let atol = atol.unwrap_or_else(|| default_atol(rtol));
        let method = Method::named(name, rtol, atol, dt)?;
        let max_steps = match max_steps {
            None => DEFAULT_MAX_STEPS,
            Some(n) => u64::try_from(n)
                .ok()
                .filter(|n| *n >= 1)
                .ok_or_else(|| Error::invalid("max_steps", "must be at least 1", n))?,
        };
        let threads = match threads {
            None => None,
            Some(n) => Some(
                usize::try_from(n)
                    .ok()
                    .filter(|n| *n >= 1)
                    .ok_or_else(|| Error::invalid("threads", "must be at least 1", n))?,
            ),
        };
        Ok(Self {
            t_end,
            frames,
            dt,
            method,
            rtol,
            atol,
            max_steps,
            flips,
            threads,
        })
    }

    /// The same options with the step `dt` (a plan's).
    pub fn with_dt(self, dt: Option<f64>) -> Result<Self> {
        Ok(Self {
            dt,
            method: Method::named(self.method.name(), self.rtol, self.atol, dt)?,
            ..self
        })
    }

    /// The method and frame grid of a run with these options (the step planned: `dt` given,
    /// or `None` for an adaptive method or the closed form).
    ///
    /// # Errors
    /// As [`super::method_and_grid`].
    pub fn method_and_grid(&self) -> Result<(Method, super::FrameGrid)> {
        super::method_and_grid(
            self.method.name(),
            self.t_end,
            self.frames,
            self.dt,
            self.max_steps,
            self.rtol,
            self.atol,
        )
    }
}
