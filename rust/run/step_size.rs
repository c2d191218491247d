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
//!
//! **Round-off.** Each step also adds round-off, which over `n = T / h` steps grows about
//! linearly in `n` (a rounding that leans the same way, and a frequency moved by the invariants'
//! rounding, which moves the phase): `R · n · ε` with `ε = 2⁻⁵²` and `R` measured per method
//! (the registry's `roundoff`: 0.06–0.22 for RK4 on well-conditioned orbits, a tenth of that
//! for the methods that keep the invariants and so the frequency). So the error of a run is
//! `ΩT · (C (hΩ)^p + R ε / (hΩ))`, least at `(hΩ)* = (R ε / (p C))^{1/(p+1)}`. Where that least
//! error meets `rtol` the planner takes the truncation's step as before (`C` is twice the
//! largest measured, ten times the median: the margin holds the round-off); where it does not
//! (body (1, 1.7, 2.3) from ω₀ = (0.4, −0.9, 0.6) over T = 10⁴ at `rtol = 1e-10`: RK4 ended
//! 7.6 `rtol` off with the 1.2·10⁷ steps the truncation alone asked for) no step meets `rtol`:
//! the planner takes the step of least error (fewer steps, as good a run), and the plan says
//! so ([`StepPlan::predicted_error`] above `rtol`) and which method reaches `rtol`
//! ([`StepPlan::reached_by`]). Near the separatrix the round-off, amplified like any error
//! there, is ten to a hundred times more (RK4 on the paper's fig. 3a: `R` ≈ 8), and the
//! prediction is low.

use crate::body::RigidBody;
use crate::error::{Error, Result};
use crate::ode::controller::check_rtol;
use crate::run::registry::{Method, MethodInfo, StepRule, METHODS};

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

/// A method's error model: order `p`, truncation constant `C`, round-off `R` (see the module
/// docs and [`crate::run::registry::StepRule::Accuracy`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorModel {
    pub order: u32,
    pub constant: f64,
    pub roundoff: f64,
}

/// The error model a method's fixed step is planned by; `None` for the methods that choose
/// their own steps or take none.
pub fn error_model(info: &MethodInfo) -> Option<ErrorModel> {
    match (info.step_rule, info.order) {
        (StepRule::Accuracy { constant, roundoff }, Some(order)) => Some(ErrorModel {
            order,
            constant,
            roundoff,
        }),
        _ => None,
    }
}

/// The most steps a run can take and still be planned for the least error: beyond, the run
/// is refused by its length whatever the step (float64 counts steps exactly to 2⁵³).
const MOST_PLANNED_STEPS: f64 = 9_007_199_254_740_992.0;

impl ErrorModel {
    /// Whether no step meets `rtol` over `turns = ΩT` radians in a run that can be taken at
    /// all (see the module docs): its least error exceeds `rtol`, in a countable number of
    /// steps.
    pub fn out_of_reach(&self, turns: f64, rtol: f64) -> bool {
        let turns = turns.max(1.0);
        self.roundoff > 0.0
            && self.least_error(turns) > rtol
            && turns / self.best_step_rate() <= MOST_PLANNED_STEPS
    }

    /// The error per radian of the motion at `x = hΩ`: `C x^p + R ε / x`.
    pub fn per_turn(&self, x: f64) -> f64 {
        self.constant * x.powi(self.order as i32) + self.roundoff_per_turn(x)
    }

    /// Its round-off part, `R ε / x`.
    fn roundoff_per_turn(&self, x: f64) -> f64 {
        self.roundoff * f64::EPSILON / x
    }

    /// The `x = hΩ` of least error per radian, `(R ε / (p C))^{1/(p+1)}`, at most
    /// [`MAX_STEP_RATE`].
    pub fn best_step_rate(&self) -> f64 {
        let p = f64::from(self.order);
        (self.roundoff * f64::EPSILON / (p * self.constant))
            .powf(1.0 / (p + 1.0))
            .min(MAX_STEP_RATE)
    }

    /// The least error a run of `turns = ΩT` radians can have.
    pub fn least_error(&self, turns: f64) -> f64 {
        turns.max(1.0) * self.per_turn(self.best_step_rate())
    }

    /// The `x = hΩ` the planner takes for `rtol` over `turns = ΩT` radians (see the module
    /// docs): the truncation's `(rtol / (C ΩT))^{1/p}` (at most [`MAX_STEP_RATE`]) where
    /// some step meets `rtol`; else the step of least error.
    fn step_rate(&self, turns: f64, rtol: f64) -> f64 {
        if self.out_of_reach(turns, rtol) {
            return self.best_step_rate();
        }
        let target = rtol / turns;
        (target / self.constant)
            .powf(1.0 / f64::from(self.order))
            .min(MAX_STEP_RATE)
    }
}

/// The step at which a method with error model `model` is predicted to meet `rtol` over
/// `t_end` at rate bound `rate` (see the module docs), or the step of least error where none
/// does; at most `t_end`.
///
/// # Errors
/// As [`check_rtol`].
pub fn step_for_accuracy(model: ErrorModel, rate: f64, t_end: f64, rtol: f64) -> Result<f64> {
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
    let h_rate = model.step_rate(turns, rtol);
    let h = (h_rate / rate).min(t_end);
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

/// The error `model` predicts for a run of `t_end` at rate bound `rate` with steps `h`:
/// `ΩT · (C (hΩ)^p + R ε / (hΩ))` (0 for a motion that does not move).
pub fn predicted_error(model: ErrorModel, rate: f64, t_end: f64, h: f64) -> f64 {
    let x = h * rate;
    match x > 0.0 && x.is_finite() {
        true => (rate * t_end).max(1.0) * model.per_turn(x),
        false => 0.0,
    }
}

/// The fixed-step method of the registry that runs every model of `kinds` and whose least
/// error over `t_end` at rate `rate` meets `rtol`, in the fewest steps (the registry holds
/// no cost a step that compares them all: the splittings evaluate no right-hand side; at a
/// tolerance this tight the higher orders win by their steps); `None` if there is none.
pub fn reaching(
    kinds: crate::dynamics::Kinds,
    rate: f64,
    t_end: f64,
    rtol: f64,
) -> Option<&'static str> {
    let turns = (rate * t_end).max(1.0);
    METHODS
        .iter()
        .filter(|m| m.runs_all(kinds))
        .filter_map(|m| {
            let model = error_model(m)?;
            (model.least_error(turns) <= rtol)
                .then(|| (m.name, turns / model.step_rate(turns, rtol)))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(name, _)| name)
}

/// The step of a run and what it predicts, worked out before the run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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
    /// The error (ω in units of Ω, q absolute) a fixed-step method's error model predicts at
    /// the step, truncation and round-off (see the module docs); 0 for other methods.
    pub predicted_error: f64,
    /// Whether no step of the method meets `rtol` over the run (its round-off alone exceeds
    /// it): the planner took the step of least error. Only for a step picked for `rtol`.
    pub out_of_reach: bool,
    /// Where `rtol` is out of reach, the cheapest fixed-step method that meets it (see
    /// [`reaching`]), if one does.
    pub reached_by: Option<&'static str>,
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
    let mut plan = crate::run::system::plan_step(rate, 0.0, t_end, frames, method, dt, rtol)?;
    if plan.out_of_reach {
        plan.reached_by = reaching(crate::dynamics::Kinds::FREE, rate, t_end, rtol);
    }
    Ok(plan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_least_error_is_the_minimum_of_the_error_model() {
        let rk4 = error_model(Method::Rk4.info()).unwrap();
        // brute force over hΩ from 1e-6 to 0.5
        let brute = (0..4000)
            .map(|i| 1e-6 * (0.5e6_f64).powf(f64::from(i) / 3999.0))
            .map(|x| rk4.per_turn(x))
            .fold(f64::INFINITY, f64::min);
        assert_relative_eq!(rk4.least_error(1.0), brute, max_relative = 1e-5);
    }

    #[test]
    fn the_step_is_the_truncations_unless_no_step_meets_rtol() {
        let rk4 = error_model(Method::Rk4.info()).unwrap();
        // within reach: (rtol / (C ΩT))^(1/4) / Ω, as before round-off was counted
        let (rate, t_end, rtol) = (1.54, 1e3, 1e-9);
        let h = step_for_accuracy(rk4, rate, t_end, rtol).unwrap();
        let truncation = (rtol / (rk4.constant * rate * t_end)).powf(0.25) / rate;
        assert_eq!(h, truncation);
        // the issue's run (ΩT = 1.54·10⁴, rtol 1e-10): out of reach for RK4, whose step is
        // then the one of least error (fewer steps than the truncation's), but not for the
        // splittings
        let (t_end, rtol) = (1e4, 1e-10);
        assert!(rk4.least_error(rate * t_end) > rtol);
        let h = step_for_accuracy(rk4, rate, t_end, rtol).unwrap();
        assert_relative_eq!(h * rate, rk4.best_step_rate(), max_relative = 1e-12);
        assert!(h > (rtol / (rk4.constant * rate * t_end)).powf(0.25) / rate);
        let free = crate::dynamics::Kinds::FREE;
        assert_eq!(reaching(free, rate, t_end, rtol), Some("splitting6"));
        // a damped body has RK4 and its projection only
        let damped = crate::dynamics::Damper::KIND;
        assert_eq!(reaching(damped, rate, t_end, rtol), Some("rk4_projected"));
        assert_eq!(reaching(damped, rate, 1e6, rtol), None);
    }

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
