//! Error control of the adaptive pairs: the settings of a run (tolerances, first step, cap on
//! attempts) and the step-size controller's constants.

use crate::error::{Error, Result};

/// The default relative tolerance: of the adaptive methods, and the accuracy `dt = None` aims at.
pub const DEFAULT_RTOL: f64 = 1e-9;
/// The default absolute tolerance of the adaptive methods (on `q`, and on `ω` in units of
/// `Ω`): [`default_atol`] of [`DEFAULT_RTOL`].
pub const DEFAULT_ATOL: f64 = DEFAULT_RTOL / RTOL_PER_ATOL;

/// How much smaller than `rtol` the absolute tolerance is when none is given.
///
/// A fixed `atol` put a floor under every tighter `rtol`: the transverse rates and three of
/// the quaternion's components of a spin near a principal axis are small, their error is held
/// to `atol` rather than to `rtol` times their size, and a tumble after it amplifies that
/// error. A deployment (1, 2, 3) → (1, 3, 2) over t ∈ [100, 110] from ω₀ = (0.002, 0.001, 1)
/// with DOP853 at `atol = 1e-12`: ω wrong by 1.8e-8, 1.4e-8 and 8.5e-9 (relative, to
/// t = 160) at `rtol` 1e-11, 1e-12 and 1e-13, against scipy's DOP853 split at the knots; with
/// `atol = rtol / 1000` by 3.0e-10, 2.1e-10 and 6.9e-11 (the reference's own round-off, which
/// the tumble amplifies too), and at t = 110, before the tumble, by 8.3e-13, 6.8e-14 and
/// 7.1e-15 (1.7e-10, 1.3e-10 and 8.1e-11 before). At the default `rtol` this is the 1e-12 it
/// always was.
pub const RTOL_PER_ATOL: f64 = 1e3;

/// The absolute tolerance an adaptive run takes when given `rtol` and no `atol`.
pub fn default_atol(rtol: f64) -> f64 {
    rtol / RTOL_PER_ATOL
}

/// The settings of an adaptive run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adaptive {
    /// Relative tolerance of the local error.
    pub rtol: f64,
    /// Absolute tolerance: on `q`, and on `ω` in units of the rate bound `Ω`.
    pub atol: f64,
    /// The first step tried; `None` picks `(rtol + atol)^(1/(q+1)) / Ω`.
    pub first_step: Option<f64>,
    /// Refuse runs needing more step attempts than this.
    pub max_steps: u64,
}

/// The smallest relative tolerance allowed: 100 ulps, below which the error estimate is
/// round-off.
pub const MIN_RTOL: f64 = 100.0 * f64::EPSILON;

impl Default for Adaptive {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Adaptive {
    /// The default tolerances, no first step, no cap.
    pub const DEFAULT: Self = Self {
        rtol: DEFAULT_RTOL,
        atol: DEFAULT_ATOL,
        first_step: None,
        max_steps: u64::MAX,
    };

    /// Settings with the given tolerances.
    ///
    /// # Errors
    /// `rtol` must lie in `[100 ε, 1)` and `atol` be positive and finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::run::adaptive::Adaptive;
    /// assert!(Adaptive::try_new(1e-10, 1e-12).is_ok());
    /// assert!(Adaptive::try_new(1e-17, 1e-12).is_err());
    /// ```
    pub fn try_new(rtol: f64, atol: f64) -> Result<Self> {
        check_rtol(rtol)?;
        if !(atol.is_finite() && atol > 0.0) {
            return Err(Error::invalid("atol", "must be positive and finite", atol));
        }
        Ok(Self {
            rtol,
            atol,
            ..Self::default()
        })
    }

    /// The same settings with a first step.
    ///
    /// # Errors
    /// `h` must be positive and finite.
    pub fn with_first_step(self, h: f64) -> Result<Self> {
        if !(h.is_finite() && h > 0.0) {
            return Err(Error::invalid("dt", "must be positive and finite", h));
        }
        Ok(Self {
            first_step: Some(h),
            ..self
        })
    }

    /// The same settings with a cap on step attempts.
    pub fn with_max_steps(self, max_steps: u64) -> Self {
        Self { max_steps, ..self }
    }

    /// The first step tried for a pair whose estimate has order `error_order`, at rate bound
    /// `rate`, over `t_end`: scale-free, so that it follows `(ω, t) → (s ω, t / s)`.
    pub fn first_step_for(&self, error_order: u32, rate: f64, t_end: f64) -> f64 {
        let h = match self.first_step {
            Some(h) => h,
            None if rate > 0.0 && rate.is_finite() => {
                (self.rtol + self.atol).powf(1.0 / (error_order + 1) as f64) / rate
            }
            None => t_end,
        };
        h.min(t_end)
    }
}

/// A step-size controller's constants (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4):
/// the next step is `h · clamp(safety · err^(−α) · err_prev^β, min_factor, max_factor)`,
/// Gustafsson's PI control in Hairer's form, `α = 1/(q+1) − 0.75 β` for an estimate of
/// order `q`. Each pair declares its own ([`crate::ode::EmbeddedPair::CONTROLLER`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Controller {
    pub alpha: f64,
    pub beta: f64,
    pub safety: f64,
    pub min_factor: f64,
    pub max_factor: f64,
}

impl Controller {
    /// Hairer's PI controller for an error estimate of order `error_order`, with his
    /// safety factor 0.9.
    pub const fn pi(error_order: u32, beta: f64, min_factor: f64, max_factor: f64) -> Self {
        Self {
            alpha: 1.0 / (error_order + 1) as f64 - 0.75 * beta,
            beta,
            safety: 0.9,
            min_factor,
            max_factor,
        }
    }
}

/// Checks a relative tolerance: positive and finite (said first: a sign slip is the usual
/// mistake), then at least 100 ulps and below 1.
///
/// # Errors
/// Names `rtol`.
pub fn check_rtol(rtol: f64) -> Result<f64> {
    if !(rtol.is_finite() && rtol > 0.0) {
        Err(Error::invalid("rtol", "must be positive and finite", rtol))
    } else if (MIN_RTOL..1.0).contains(&rtol) {
        Ok(rtol)
    } else {
        Err(Error::invalid(
            "rtol",
            "must be at least 100 ulps (2.2e-14) and below 1",
            rtol,
        ))
    }
}
