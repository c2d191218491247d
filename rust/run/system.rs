//! A system's run in the user's axes: the change to principal axes once at each edge of the
//! run (where the body is constant), the moments over a power of two near the largest, the
//! model the system makes, its run, and the frames back in the user's axes.

use std::sync::atomic::AtomicBool;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::body::Inertia;
use crate::dynamics::{
    state_from, AnyPart, ConstantInertia, FreeRigidBody, GeneralModel, InertiaLaw, Model, Movers,
    Moving, System, SystemBody, STATE_SIZES,
};
use crate::error::{Error, Result};
use crate::float::{exponent, ldexp, RateScale, UNSCALED};
use crate::kinematics::normalized;
use crate::ode::controller::check_rtol;

use super::options::RunOptions;
use super::registry::StepRule;
use super::step_size::{
    error_model, predicted_error, reaching, rk4_predicted_drift, step_for_accuracy, StepPlan,
};
use super::{check_rates, simulate, simulate_model, FrameGrid, Keep, Method, RunOutput};

/// The change between the user's axes and the principal axes of a constant body: `R`, user
/// axes from principal axes (`ω_p = Rᵀ ω`, `q_p = q ⊗ q_R`); none for a deployment, whose
/// runs stay in the user's axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    axes: Option<(Matrix3<f64>, Quaternion<f64>)>,
}

impl Edge {
    /// The edge of a body of tensor `inertia`.
    pub fn of(inertia: &Inertia) -> Self {
        let axes = (!inertia.is_principal()).then(|| {
            let r = inertia.axes();
            let q = UnitQuaternion::from_matrix(&r).into_inner();
            (r, q)
        });
        Self { axes }
    }

    /// No change of axes.
    pub const IDENTITY: Self = Self { axes: None };

    /// A vector of the user's axes in principal axes: `Rᵀ v`.
    pub fn vector_in(&self, v: [f64; 3]) -> [f64; 3] {
        match &self.axes {
            Some((r, _)) => (r.transpose() * Vector3::from(v)).into(),
            None => v,
        }
    }

    /// An attitude of the user's axes as one of the principal axes: `q ⊗ q_R`.
    pub fn attitude_in(&self, q: [f64; 4]) -> [f64; 4] {
        match &self.axes {
            Some((_, qr)) => {
                let p = Quaternion::new(q[0], q[1], q[2], q[3]) * qr;
                [p.w, p.i, p.j, p.k]
            }
            None => q,
        }
    }

    /// Frames of a run in principal axes back in the user's: `ω = R ω_p` and the body-axes
    /// vectors of the parts' state (`width` numbers a frame, the vectors starting at
    /// `vectors`) likewise, `q = q_p ⊗ q_R*`.
    pub fn frames_out(
        &self,
        omega: &mut [f64],
        q: &mut [f64],
        parts: &mut [f64],
        (width, vectors): (usize, &[usize]),
    ) {
        let Some((r, qr)) = &self.axes else { return };
        let turn = |v: &mut [f64]| {
            let out = r * Vector3::new(v[0], v[1], v[2]);
            v.copy_from_slice(out.as_slice());
        };
        omega.chunks_exact_mut(3).for_each(turn);
        if width > 0 && !vectors.is_empty() {
            for frame in parts.chunks_exact_mut(width) {
                vectors.iter().for_each(|&k| turn(&mut frame[k..k + 3]));
            }
        }
        let conj = qr.conjugate();
        for f in q.chunks_exact_mut(4) {
            let p = Quaternion::new(f[0], f[1], f[2], f[3]) * conj;
            f.copy_from_slice(&[p.w, p.i, p.j, p.k]);
        }
    }
}

/// The model a system makes for a run, with its start, in principal axes where the body is
/// constant (see [`Edge`]) and with its moments over a power of two near the largest: the
/// free body, or the general model in the least state size that holds it. The general
/// models are boxed: a few kilobytes each, which every move of the enum (out of `build`, into
/// a [`Planned`]) copied, for the free body too (a quarter of a batch's planning time).
enum Built {
    /// The free body, its start in principal axes (its run scales itself).
    Free(crate::body::RigidBody, [f64; 3], [f64; 4]),
    /// Every part folded: no part's code in the right-hand side.
    Lean(Box<GeneralModel<7, false>>, [f64; 7]),
    G7(Box<GeneralModel<7>>, [f64; 7]),
    G8(Box<GeneralModel<8>>, [f64; 8]),
    G10(Box<GeneralModel<10>>, [f64; 10]),
    G11(Box<GeneralModel<11>>, [f64; 11]),
    G12(Box<GeneralModel<12>>, [f64; 12]),
    G14(Box<GeneralModel<14>>, [f64; 14]),
    G16(Box<GeneralModel<16>>, [f64; 16]),
    G24(Box<GeneralModel<24>>, [f64; 24]),
    /// Parts whose mass moves in the body (see [`Moving`]): a model of its own, in two sizes
    /// only, so that no other model carries its code and the build makes few copies of it.
    M10(Box<GeneralModel<10, true, Moving>>, [f64; 10]),
    M24(Box<GeneralModel<24, true, Moving>>, [f64; 24]),
}

/// The state sizes of a model with parts whose mass moves (see [`Built::M10`]).
const MOVING_SIZES: [usize; 2] = [10, 24];

/// `$e` with `$model` and `$x0` the general model of `$built` and its start, whatever its
/// size; `$free` for the free body.
macro_rules! each_size {
    ($built:expr, $model:ident, $x0:ident => $e:expr, $free:pat => $f:expr) => {
        match $built {
            $free => $f,
            Built::Lean(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G7(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G8(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G10(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G11(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G12(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G14(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G16(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::G24(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::M10(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
            Built::M24(boxed, $x0) => {
                let $model = &**boxed;
                $e
            }
        }
    };
}

/// The general model of `law` with `parts` up to `t_end`, in a state of `N` numbers, and its
/// start from `omega` and `q` (the run's axes).
fn general<const N: usize, const HOT: bool, M: Movers>(
    law: InertiaLaw,
    parts: Vec<AnyPart>,
    omega: [f64; 3],
    q: [f64; 4],
    t_end: f64,
    mass: Option<f64>,
) -> Result<(Box<GeneralModel<N, HOT, M>>, [f64; N])> {
    let model = GeneralModel::<N, HOT, M>::try_new(law, parts)?
        .with_hub_mass(mass)?
        .until(t_end);
    let x0 = model.state_from(0.0, omega, q);
    finite_start(&x0)?;
    Ok((Box::new(model), x0))
}

/// The sample times the parts of `system` have in `[0, t_end]` (the user's units).
pub fn sample_times(system: &System, t_end: f64) -> f64 {
    (system.parts().iter().filter_map(AnyPart::sampling))
        .filter(|s| s.period > 0.0 && s.period.is_finite() && t_end >= s.phase)
        .map(|s| ((t_end - s.phase) / s.period).floor() + 1.0)
        .sum()
}

/// Refuses a run whose parts' sample times over `[0, t_end]` are more than `max_steps` (each
/// ends a step of its own, and is evaluated), before it starts, naming `t_end`. Nothing is
/// listed: the drivers ask the parts' clocks for each next sample time as the run goes
/// ([`crate::dynamics::Clocks`]), so a 1 kHz law over 10⁶ s costs its steps, not memory.
fn check_sample_times(system: &System, t_end: f64, max_steps: u64) -> Result<()> {
    let n = sample_times(system, t_end);
    if n.is_nan() || n > max_steps as f64 {
        let periods: Vec<(&str, f64)> = (system.parts().iter())
            .filter_map(|p| p.sampling().map(|s| (p.name(), s.period)))
            .collect();
        return Err(Error::invalid(
            "t_end",
            format!(
                "must give the parts' laws no more sample times together (t_end / period \
                 each) than {} (each ends a step of its own): run a shorter t_end, raise \
                 max_steps, or sample less often; the parts' periods: {periods:?}",
                super::max_steps_limit(max_steps)
            ),
            n,
        ));
    }
    Ok(())
}

/// The largest moment's binary exponent, if beyond `2^±UNSCALED`: moments over `2^m` then.
fn moment_exponent(system: &System) -> i32 {
    let largest = match system.body() {
        SystemBody::Rigid(inertia) => inertia.principal().inertia_body().max(),
        SystemBody::Deployment(d) => d.tensors().iter().map(|t| t.amax()).fold(0.0, f64::max),
    };
    let m = exponent(largest);
    if m.abs() <= UNSCALED {
        0
    } else {
        m
    }
}

/// The model of `system` over `[0, t_end]` and its start from the body rates `omega0` and
/// attitude `q0` (the user's axes; `q0` normalised here), the edge back to the user's axes
/// and the moments' exponent.
fn build(
    system: &System,
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
) -> Result<(Built, Edge, i32)> {
    check_rates(omega0)?;
    let q0 = normalized(q0)?;
    // the copies of its knots the model makes: room for them, or an error (not an abort)
    let bytes = system.model_bytes();
    if bytes >= 1 << 20 {
        crate::buffer::ensure_room(
            bytes as f64,
            "a run's copies of its knots",
            "give fewer knots",
        )?;
    }
    // the moments over a power of two near the largest, before any is inverted
    let m = moment_exponent(system);
    let scaled = |x: f64| ldexp(x, -m);
    let (law, edge) = match system.body() {
        SystemBody::Rigid(inertia) => {
            let edge = Edge::of(inertia);
            if system.as_free().is_some() {
                let built = Built::Free(
                    *inertia.principal(),
                    edge.vector_in(omega0),
                    edge.attitude_in(q0),
                );
                return Ok((built, edge, 0));
            }
            let moments = inertia.principal().inertia_body().map(scaled);
            let tensor = Matrix3::from_diagonal(&moments);
            (
                InertiaLaw::Constant(ConstantInertia::try_new(tensor)?),
                edge,
            )
        }
        SystemBody::Deployment(d) => (
            InertiaLaw::Schedule(d.with_moments_scaled(m)?),
            Edge::IDENTITY,
        ),
    };
    let (omega, q) = (edge.vector_in(omega0), edge.attitude_in(q0));
    // the parts in the run's axes, over the moments' power of two, with the run's seed
    let to_axes = |v: [f64; 3]| edge.vector_in(v);
    let parts = (system.parts().iter().enumerate())
        .map(|(k, p)| {
            p.in_axes(&to_axes)
                .with_moments_scaled(m)
                .map(|p| p.seeded(system.seed(), k))
        })
        .collect::<Result<Vec<_>>>()?;
    // the body's mass over the moments' power of two (its parts' masses go with them)
    let mass = system.mass().map(scaled);
    let needed = 7 + system.state_width();
    let Some(&size) = STATE_SIZES.iter().find(|&&n| n >= needed) else {
        return Err(System::too_much_state(needed - 7));
    };
    if Moving::needed(&parts) {
        let size = MOVING_SIZES.iter().find(|&&n| n >= needed);
        let built = match size {
            Some(10) => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::M10(m, x)),
            _ => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::M24(m, x)),
        }?;
        return Ok((built, edge, m));
    }
    let built = match size {
        7 if GeneralModel::<7>::is_lean(&parts) => {
            general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::Lean(m, x))
        }
        7 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G7(m, x)),
        8 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G8(m, x)),
        10 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G10(m, x)),
        11 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G11(m, x)),
        12 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G12(m, x)),
        14 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G14(m, x)),
        16 => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G16(m, x)),
        _ => general(law, parts, omega, q, t_end, mass).map(|(m, x)| Built::G24(m, x)),
    }?;
    Ok((built, edge, m))
}

/// A start whose momenta float64 holds.
fn finite_start<const N: usize>(x: &[f64; N]) -> Result<()> {
    match x.iter().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(Error::invalid(
            "omega0",
            "must give an angular momentum that float64 holds (the moments times the rates)",
            &x[..N - 4],
        )),
    }
}

/// Simulates `system` from body rates `omega0` and attitude `q0`, both of the user's own axes
/// (`q0` normalised here), over `grid` with `method`, keeping what `keep` asks: the run of a
/// batch's row. The frames come back in the user's axes; the parts' state (a damper's σ) too.
///
/// # Errors
/// A method that cannot run the system ([`Error::Unsupported`]), bad starts, and the errors
/// of [`simulate`] and [`simulate_model`].
pub fn simulate_system(
    system: &System,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    method.for_kinds(system.kinds())?;
    check_sample_times(system, grid.t_end(), grid.max_steps())?;
    let (built, edge, m) = build(system, omega0, q0, grid.t_end())?;
    run_built(system, &built, edge, m, grid, method, keep, cancel)
}

/// The run of a system's built model (see [`build`]): its frames and ends back in the
/// user's moments and axes.
#[allow(clippy::too_many_arguments)]
fn run_built(
    system: &System,
    built: &Built,
    edge: Edge,
    m: i32,
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
) -> Result<RunOutput> {
    let mut out = each_size!(built,
        model, x0 => simulate_model(model, *x0, grid, method, keep, cancel)?,
        Built::Free(body, omega, q) => simulate(body, *omega, *q, grid, method, keep, cancel)?
    );
    // the parts' state in the user's moments and axes
    let dims = system.parts_dims();
    if m != 0 && dims.iter().any(|d| d.moment != 0) {
        let unscale = |v: &mut [f64]| {
            for (x, d) in v.iter_mut().zip(dims.iter().cycle()) {
                *x = ldexp(*x, m * d.moment);
            }
        };
        unscale(&mut out.parts);
        unscale(&mut out.end.parts);
    }
    let layout = (system.parts_width(), system.body_vectors());
    let layout = (layout.0, layout.1.as_slice());
    edge.frames_out(&mut out.omega, &mut out.q, &mut out.parts, layout);
    let end = &mut out.end;
    edge.frames_out(&mut end.omega, &mut end.q, &mut end.parts, layout);
    // turned back into the user's axes, rates at the edge of float64 can leave it
    super::finite_frames(out, grid)
}

/// One run of a system, planned and then run on the model built once for both (a batch
/// plans all its rows before it runs any, so builds each row's model twice).
pub struct Planned<'a> {
    system: &'a System,
    built: Built,
    edge: Edge,
    m: i32,
    /// The step the run takes and what it predicts, as [`plan_system`] gives it.
    pub plan: StepPlan,
}

impl<'a> Planned<'a> {
    /// The plan of the run of `system` from `omega0` and `q0` (the user's axes) with
    /// `options`, as [`plan_system`] makes it.
    ///
    /// # Errors
    /// As [`plan_system`].
    pub fn new(
        system: &'a System,
        omega0: [f64; 3],
        q0: [f64; 4],
        options: &RunOptions,
    ) -> Result<Self> {
        let o = options;
        o.method.for_kinds(system.kinds())?;
        let (built, edge, m) =
            build(system, omega0, q0, o.t_end).map_err(|e| blame_sizes(system, omega0, e))?;
        let plan = plan_built(system, omega0, &built, o)?;
        Ok(Self {
            system,
            built,
            edge,
            m,
            plan,
        })
    }

    /// The run as planned, over `grid` with `method` (the planned step's: see
    /// [`RunOptions::with_dt`]), keeping what `keep` asks; the same bits as
    /// [`simulate_system`] with the planned step.
    ///
    /// # Errors
    /// As [`simulate_system`].
    pub fn run(
        &self,
        grid: &FrameGrid,
        method: Method,
        keep: Keep,
        cancel: &AtomicBool,
    ) -> Result<RunOutput> {
        check_sample_times(self.system, grid.t_end(), grid.max_steps())?;
        let (system, built) = (self.system, &self.built);
        run_built(system, built, self.edge, self.m, grid, method, keep, cancel)
    }
}

/// The step a run of `system` from `omega0` (with `q0`) will take and what it predicts:
/// `dt` if given, else the step predicted to meet `rtol` (fixed-step methods, by the method's
/// rule in the registry and the model's rate bound) or the automatic first step (adaptive
/// ones), with RK4's predicted drift of `|q|` and the model's stiffness (a damper's slip rate).
///
/// # Errors
/// A method that cannot run the system; bad starts, `t_end`, `frames`, `dt` or `rtol`.
#[allow(clippy::too_many_arguments)]
pub fn plan_system(
    system: &System,
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
) -> Result<StepPlan> {
    method.for_kinds(system.kinds())?;
    let (built, _, _) =
        build(system, omega0, q0, t_end).map_err(|e| blame_sizes(system, omega0, e))?;
    let options = RunOptions {
        t_end,
        frames,
        method,
        dt,
        rtol,
        ..RunOptions::default()
    };
    plan_built(system, omega0, &built, &options)
}

/// The plan of a run of `system`'s built model (see [`plan_system`]).
fn plan_built(
    system: &System,
    omega0: [f64; 3],
    built: &Built,
    options: &RunOptions,
) -> Result<StepPlan> {
    let o = options;
    let (rate, stiffness) = each_size!(built,
        model, x0 => (rate_in_units(model, x0), model.stiffness()),
        Built::Free(body, omega, q) => {
            let model = FreeRigidBody::new(*body);
            (rate_in_units(&model, &state_from(*omega, *q)), 0.0)
        }
    );
    let rate = rate.map_err(|e| blame_sizes(system, omega0, e))?;
    let mut plan = plan_step(rate, stiffness, o.t_end, o.frames, o.method, o.dt, o.rtol)?;
    if plan.out_of_reach {
        plan.reached_by = reaching(system.kinds(), rate, o.t_end, o.rtol);
    }
    Ok(plan)
}

/// `error`, if it blames `omega0` for a size float64 cannot hold, blaming instead what of
/// `system` and the start is largest as a rate — the start's rates (times √(I_max / I_min)), or
/// the largest rate a part brings ([`crate::dynamics::Part::largest_rate`]: a wheel's momentum
/// over the least moment, an orbit's rate) — with the value the user gave (a wheel's momentum
/// of 1e308 and an orbit rate of 1e200 were reported as `omega0`, with the momenta the run
/// computes from them).
fn blame_sizes(system: &System, omega0: [f64; 3], error: Error) -> Error {
    if !matches!(&error, Error::InvalidArgument { name: "omega0", .. }) {
        return error;
    }
    let moments = system.tensor_at(0.0).symmetric_eigenvalues();
    let (least, largest) = (moments.min(), moments.max());
    let spin = omega0.iter().fold(0.0_f64, |m, w| m.max(w.abs())) * (largest / least).sqrt();
    let part = (system.parts().iter())
        .filter_map(|p| p.largest_rate(least))
        .fold(None, |m: Option<(&str, f64, f64)>, r| match m {
            Some(m) if m.2 >= r.2 => Some(m),
            _ => Some(r),
        });
    match part {
        Some((name, value, rate)) if rate > 0.0 && rate >= spin => Error::invalid(
            name,
            match name {
                "orbit_rate" => {
                    "must give, with the body's moments, a rate bound that float64 holds (the \
                     gravity gradient's potential is 3 n² I)"
                }
                "momentum" => {
                    "must give, over the body's least moment of inertia, a rate that float64 \
                     holds (a wheel's momentum, a schedule's largest)"
                }
                _ => "must give a rate that float64 holds",
            },
            value,
        ),
        _ => Error::invalid(
            "omega0",
            "must give a rate bound √(2E / I_min) (and an angular momentum) that float64 holds",
            omega0,
        ),
    }
}

/// The model's rate bound from `x0`, taken in the motion's own units (where its squares stay
/// in float64) and given back in the user's.
///
/// # Errors
/// A model whose times leave float64 in those units.
fn rate_in_units<const N: usize, S: Model<N>>(sys: &S, x0: &[f64; N]) -> Result<f64> {
    let scale = RateScale::of(sys.omega_body(0.0, x0).into());
    let rate = match scale.is_identity() {
        true => sys.rate_bound(x0),
        false => {
            let x = sys.state_in_units(x0, scale);
            scale.rate_from_unit(sys.in_units(scale)?.rate_bound(&x))
        }
    };
    match rate.is_finite() {
        true => Ok(rate),
        false => Err(Error::invalid(
            "omega0",
            "must give a rate bound √(2E / I_min) that float64 holds",
            x0[..3].to_vec(),
        )),
    }
}

/// The plan of a run whose rates are bounded by `rate` (see [`plan_system`]).
///
/// # Errors
/// Bad `t_end`, `frames`, `dt` or `rtol`.
pub(crate) fn plan_step(
    rate: f64,
    stiffness: f64,
    t_end: f64,
    frames: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
) -> Result<StepPlan> {
    let info = method.info();
    let model = match info.step_rule {
        StepRule::NoSteps => {
            FrameGrid::try_frames(t_end, frames)?;
            return Ok(StepPlan {
                dt: None,
                step: 0.0,
                rate_bound: rate,
                predicted_drift: 0.0,
                stiffness,
                ..StepPlan::default()
            });
        }
        StepRule::Adaptive { error_order } => {
            FrameGrid::frames_only(t_end, frames)?;
            check_rtol(rtol)?;
            let a = method.adaptive_settings().unwrap_or_default();
            let a = match dt {
                Some(h) => a.with_first_step(h)?,
                None => a,
            };
            let h = a.first_step_for(error_order, rate, t_end);
            return Ok(StepPlan {
                dt,
                step: h,
                rate_bound: rate,
                predicted_drift: 0.0,
                stiffness,
                ..StepPlan::default()
            });
        }
        StepRule::Accuracy { .. } => error_model(info),
    };
    let model = model.ok_or_else(|| Error::invalid("method", "has no order", info.name))?;
    let planned = dt.is_none() && rate > 0.0;
    let dt = match dt {
        Some(dt) => dt,
        None => step_for_accuracy(model, rate, t_end, rtol)?,
    };
    let grid = FrameGrid::try_new(t_end, frames, dt, u64::MAX)?;
    let predicted_drift = match info.rk4_dissipation {
        true => rk4_predicted_drift(grid.step_size(), rate, grid.n_steps() as f64),
        false => 0.0,
    };
    Ok(StepPlan {
        dt: Some(dt),
        step: grid.step_size(),
        rate_bound: rate,
        predicted_drift,
        stiffness,
        predicted_error: predicted_error(model, rate, t_end, grid.step_size()),
        out_of_reach: planned && model.out_of_reach(rate * t_end, rtol),
        reached_by: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::toy::Counter;
    use crate::dynamics::{Fields, Part, Value};
    use crate::observe::Observer;

    /// The end of every step.
    #[derive(Default)]
    struct Ends(Vec<f64>);

    impl Observer<8> for Ends {
        const WANTS_STEPS: bool = true;
        fn step(&mut self, _: f64, _: &[f64; 8], t1: f64, _: &[f64; 8]) {
            self.0.push(t1);
        }
    }

    /// The seam's hook for sampled parts, driven by each kind of driver: a counter sampled at
    /// `0.1 + 0.25 k` counts the sample times in `[0, t_end)` (its state held between them),
    /// and every step ends on them, however the steps fall.
    #[test]
    fn every_driver_ends_its_steps_on_sample_times_and_samples_there() {
        let fields = Fields::new()
            .with("period", Value::Number(0.25))
            .with("phase", Value::Number(0.1));
        let counter = AnyPart::from(Counter::from_fields(&fields).unwrap());
        let law = InertiaLaw::Constant(
            ConstantInertia::try_new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).unwrap(),
        );
        let model = GeneralModel::<8>::try_new(law, vec![counter])
            .unwrap()
            .until(2.0);
        let x0 = model.state_from(0.0, [0.3, 0.2, 1.0], [1.0, 0.0, 0.0, 0.0]);
        let samples: Vec<f64> = (0..8).map(|k| 0.1 + 0.25 * f64::from(k)).collect();
        let cancel = AtomicBool::new(false);
        for method in ["rk4", "dop853"] {
            let method = Method::named(method, 1e-9, 1e-12, None).unwrap();
            let grid = FrameGrid::for_method(&method, 2.0, 5, 0.07, u64::MAX).unwrap();
            let mut ends = Ends::default();
            use crate::run::registry::Runs;
            model
                .run_method(method, x0, &grid, &mut ends, &cancel)
                .unwrap();
            for t in &samples {
                assert!(ends.0.contains(t), "{}: no step ends on {t}", method.name());
            }
            let keep = Keep {
                frames: true,
                flips: false,
                tilt: false,
            };
            let out = simulate_model(&model, x0, &grid, method, keep, &cancel).unwrap();
            assert_eq!(out.end.parts, vec![8.0], "{}", method.name());
            // the frames hold the count before each frame's time (a frame on a sample time
            // shows the state before it)
            assert_eq!(
                out.parts,
                vec![0.0, 2.0, 4.0, 6.0, 8.0],
                "{}",
                method.name()
            );
        }
    }

    /// A 1 kHz law over 10⁶ s: its 10⁹ sample times are never listed (the model is built at
    /// once, its clock finds the last of them without walking there); a run whose sample
    /// times are more than its `max_steps` is refused before it starts, naming `t_end`. At the
    /// limit's edge a run goes ahead, sampled at every one.
    #[test]
    fn sample_times_are_never_listed_and_count_toward_max_steps() {
        let fields = Fields::new()
            .with("period", Value::Number(1e-3))
            .with("phase", Value::Number(0.0));
        let counter = AnyPart::from(Counter::from_fields(&fields).unwrap());
        let body = crate::body::RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let system = System::try_new(
            SystemBody::Rigid(Inertia::from_principal(body)),
            vec![counter],
        )
        .unwrap();
        assert_eq!(sample_times(&system, 1e6), 1e9 + 1.0);
        assert_eq!(sample_times(&system, 100.0), 1e5 + 1.0);
        let start = std::time::Instant::now();
        let (built, _, _) = build(&system, [0.1; 3], [1.0, 0.0, 0.0, 0.0], 1e6).unwrap();
        let Built::G8(model, _) = built else {
            panic!("a counter's model is of 8 numbers")
        };
        assert!(model.kinks().is_empty(), "no sample time listed");
        assert_eq!(model.next_kink(1e6 - 0.0005), 1e9 * 1e-3);
        assert!(start.elapsed().as_secs_f64() < 1.0);
        let method = Method::named("rk4", 1e-9, 1e-12, None).unwrap();
        let keep = Keep {
            frames: false,
            flips: false,
            tilt: false,
        };
        let cancel = AtomicBool::new(false);
        let run = |t_end: f64, max_steps: u64| {
            let grid = FrameGrid::try_new(t_end, 2, 1.0, max_steps).unwrap();
            simulate_system(
                &system,
                [0.1; 3],
                [1.0, 0.0, 0.0, 0.0],
                &grid,
                method,
                keep,
                &cancel,
            )
        };
        match run(1e6, 1_000_000_000).unwrap_err() {
            Error::InvalidArgument { name, allowed, .. } => {
                assert_eq!(name, "t_end");
                assert!(allowed.contains("sample times"), "{allowed}");
                assert!(allowed.contains("max_steps = 1000000000"), "{allowed}");
            }
            e => panic!("not an invalid t_end: {e:?}"),
        }
        // at the limit's edge a run goes ahead: 1001 sample times in [0, 1]
        let out = run(1.0, 1001).unwrap();
        assert_eq!(out.end.parts, vec![1000.0]);
        assert!(run(1.0, 1000).is_err());
    }
}
