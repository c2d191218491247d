//! Choosing and checking the step before a run: the fastest rate of the motion, RK4's silent
//! dissipation on this problem, and the step that meets a requested accuracy.
//!
//! **The rate bound.** The kinetic energy `2E = Σ I_i ω_i²` gives `|ω|² ≤ 2E / I_min`, so
//! `Ω = √(2E / I_min)` bounds the body rates for the whole run, known before it starts (also
//! `|ω| ≤ |L| / I_min`, a weaker bound). `Ω` also bounds the frequency of the wobble about a
//! stable axis (`ω_3 √((I_3 − I_1)(I_3 − I_2) / (I_1 I_2))` about axis 3, and likewise about
//! axis 1) for every body that satisfies the triangle inequality.
//!
//! **RK4's dissipation.** The quaternion law `q' = ½ q ⊗ (0, ω)` is linear in `q` with
//! eigenvalues `±i|ω|/2`. One RK4 step multiplies such a mode by `R(iy)`, `y = h|ω|/2`, with
//! `|R(iy)|² = 1 − y⁶/72 + y⁸/576`: below `y = 2√2` (`h|ω| < 4√2 ≈ 5.66`) every step shrinks
//! `|q|` a little, above it `|q|` grows without bound. Over `n` steps at the bound `Ω` the
//! predicted relative drift of `|q|` is `|1 − |R(iy)|ⁿ|`: at `hΩ = 0.5` that is 3.3 % per 10⁴
//! radians (`Ω t = 10⁴`), at `hΩ = 1` 65 %. Because `|ω| ≤ Ω` and `1 − |R|²` grows with `y`
//! up to `y = √6`, it is an upper bound for the slow decay at `y ≤ √6` (exact for a spin
//! about the axis of least inertia, where `|ω| = Ω` throughout).
//!
//! **The step for an accuracy.** A method of order `p` run for `T` with step `h` makes a
//! global error (on well-conditioned orbits, where it grows linearly: a phase error) of about
//! `C_p · ΩT · (hΩ)^p`, relative to `Ω` for the rates and absolute for `q`. Solving for `h`
//! with each method's constant (its `StepRule` in [`crate::run::registry`]) gives the step
//! `dt = None` takes. Near the separatrix the
//! error grows faster than linearly and this rule does not hold (no fixed rule can).

use crate::body::RigidBody;
use crate::error::{Error, Result};
use crate::ode::controller::check_rtol;
use crate::run::registry::Method;

pub use crate::dynamics::{frequency_factor, rate_bound};

/// `|R(iy)|²` for RK4's stability function `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`.
pub fn rk4_gain_squared(y: f64) -> f64 {
    let y2 = y * y;
    let y6 = y2 * y2 * y2;
    1.0 - y6 / 72.0 + y6 * y2 / 576.0
}

/// The predicted relative drift `|1 − |R(iy)|ⁿ|` of `|q|` after `n_steps` RK4 steps of size
/// `h` at rate `rate` (`y = h · rate / 2`); infinite when it overflows.
pub fn rk4_predicted_drift(h: f64, rate: f64, n_steps: f64) -> f64 {
    let y = 0.5 * h * rate;
    if y.is_nan() || y >= 8f64.sqrt() {
        return f64::INFINITY; // at or past the stability limit: |q| grows without bound
    }
    let g = rk4_gain_squared(y);
    if g <= 0.0 {
        return 1.0; // a step that maps the mode to zero: all of |q| is lost
    }
    // |R|ⁿ = exp(n ln|R|); ln_1p keeps the tiny per-step losses of small steps
    let log_gain = 0.5 * (g - 1.0).ln_1p();
    (n_steps * log_gain).exp_m1().abs()
}

/// The largest `hΩ` the accuracy rule picks: beyond it the error model (leading term only)
/// no longer describes the method.
pub const MAX_STEP_RATE: f64 = 0.5;

/// The step at which a method of `order` with error constant `constant` is predicted to meet
/// `rtol` over `t_end` at rate bound `rate` (see the module docs); at most `t_end`.
///
/// # Errors
/// As [`check_rtol`].
pub fn step_for_accuracy(
    order: u32,
    constant: f64,
    rate: f64,
    t_end: f64,
    rtol: f64,
) -> Result<f64> {
    check_rtol(rtol)?;
    if !(rate > 0.0 && rate.is_finite()) {
        return Ok(t_end); // nothing moves
    }
    let turns = (rate * t_end).max(1.0);
    if !turns.is_finite() {
        return Err(Error::TooLarge {
            what: "the run".into(),
            needed: format!("t_end · Ω = {t_end:.3e} · {rate:.3e} radians"),
            limit: "what float64 holds".into(),
            hint: "take a shorter t_end",
        });
    }
    let h_rate = (rtol / (constant * turns)).powf(1.0 / order as f64);
    let h = (h_rate.min(MAX_STEP_RATE) / rate).min(t_end);
    if h.is_nan() || h <= 0.0 {
        // a step below float64's smallest: more steps than a run can count
        let steps = turns / h_rate;
        let needed = match steps.is_finite() {
            true => format!("{steps:.3e} steps (t_end · Ω / {h_rate:.3e}, at Ω = {rate:.3e})"),
            false => format!(
                "more steps than float64 counts (steps of {h_rate:.3e} / Ω, at Ω = {rate:.3e})"
            ),
        };
        return Err(Error::TooLarge {
            what: "the run".into(),
            needed,
            limit: super::grid::max_steps_limit(u64::MAX),
            hint: "take a larger rtol or a shorter t_end",
        });
    }
    Ok(h)
}

/// The step of a run and what it predicts, worked out before the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPlan {
    /// The step the run is given: the planned (or asked) step of a fixed-step method; the
    /// asked first step of an adaptive one (`None`: each run picks its own); `None` for the
    /// closed form, which takes no steps.
    pub dt: Option<f64>,
    /// The step a fixed-step method will take (`t_end / (frames − 1)` split evenly, at most
    /// `dt`); an adaptive method's first step; 0 for the closed form.
    pub step: f64,
    /// The rate bound `Ω` (see the module docs), times [`frequency_factor`] for moments that
    /// break the triangle inequality.
    pub rate_bound: f64,
    /// RK4's predicted relative drift of `|q|` over the run, for `rk4` and `rk4_projected`
    /// (whose projection hides the drift, not the error behind it); 0 for other methods.
    pub predicted_drift: f64,
    /// The fastest decay rate of the model (a damper's slip, [`crate::dynamics::Damper::slip_rate`]):
    /// an explicit method is stable while `step · stiffness` is within its real-axis limit;
    /// 0 for a model without one.
    pub stiffness: f64,
}

/// Plans the step of a run of the free body `body` (principal moments) from `omega0` (see
/// [`crate::run::plan_system`], which plans any system's).
///
/// # Errors
/// Bad `t_end`, `frames`, `dt` or `rtol`.
pub fn plan(
    body: &RigidBody,
    omega0: [f64; 3],
    t_end: f64,
    frames: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
) -> Result<StepPlan> {
    // Ω, or the faster precession of moments that break the triangle inequality
    let rate = rate_bound(body, omega0) * frequency_factor(body);
    if !rate.is_finite() {
        return Err(Error::invalid(
            "omega0",
            "must give a rate bound √(2E / I_min) that float64 holds",
            omega0,
        ));
    }
    crate::run::system::plan_step(rate, 0.0, t_end, frames, method, dt, rtol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn gain_is_one_at_the_stability_limit() {
        // |R(iy)| = 1 at y = 2√2, below 1 inside, above 1 beyond
        assert_relative_eq!(rk4_gain_squared(8f64.sqrt()), 1.0, epsilon = 1e-14);
        assert!(rk4_gain_squared(2.8) < 1.0 && rk4_gain_squared(2.9) > 1.0);
    }

    #[test]
    fn gain_matches_the_stability_function() {
        for y in [0.01_f64, 0.3, 1.0, 2.5] {
            let (re, im) = (1.0 - y * y / 2.0 + y.powi(4) / 24.0, y - y.powi(3) / 6.0);
            assert_relative_eq!(rk4_gain_squared(y), re * re + im * im, epsilon = 1e-14);
        }
    }

    #[test]
    fn the_issues_figures_follow_from_the_gain() {
        // 10⁴ radians at hΩ = 0.5 is 2·10⁴ steps of y = 0.25: 3.3 % of |q| lost
        let drift = rk4_predicted_drift(0.5, 1.0, 2e4);
        assert!((0.032..0.034).contains(&drift), "{drift}");
        // at hΩ = 1 more than half
        let drift = rk4_predicted_drift(1.0, 1.0, 1e4);
        assert!((0.6..0.7).contains(&drift), "{drift}");
    }

    #[test]
    fn rate_bound_bounds_the_rates_and_survives_huge_rates() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let w = [0.3, -1.2, 0.7];
        let norm = (w.iter().map(|x| x * x).sum::<f64>()).sqrt();
        assert!(rate_bound(&body, w) >= norm);
        assert_relative_eq!(
            rate_bound(&body, w.map(|x| x * 1e200)),
            rate_bound(&body, w) * 1e200,
            max_relative = 1e-15
        );
    }
}
