//! The runs: planning, one run, a batch, a sweep, and what a system says of its frames; their
//! results as frozen classes of NumPy arrays.

use std::sync::Arc;

use numpy::ndarray::{Ix1, Ix2, Ix3};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::body::{Inertia, RigidBody};
use crate::buffer::{ensure_room, try_collect, try_with_capacity};
use crate::dynamics::System;
use crate::ensemble::batch::Options as BatchOptions;
use crate::ensemble::lanes::Isa;
use crate::ensemble::plan::plan_systems;
use crate::ensemble::sweep::{sweep as core_sweep, RunStatus, RunSummary};
use crate::ensemble::systems::{free_starts, simulate_systems, Rows};
use crate::error::Error;
use crate::observe::Drift;
use crate::ode::Stats;
use crate::run::options::RunOptions;
use crate::run::progress::{metered, Meter};
use crate::run::step_size::StepPlan;
use crate::run::{watchdog, FrameGrid, Keep, Planned};

use super::arrays::owned;
use super::values::{PyRunOptions, PySystem};
use super::{detach, detach_reporting, detach_with};

/// The step a run will take and what it predicts (see `run::step_size::StepPlan`).
#[pyclass(name = "StepPlan", module = "dzhanibekov._core", frozen, get_all)]
#[derive(Clone)]
struct PyStepPlan {
    /// The step the run is given (None: an adaptive method's own, or no steps).
    dt: Option<f64>,
    /// The step a fixed-step method takes; an adaptive one's first step.
    step: f64,
    /// The rate bound `Ω`.
    rate_bound: f64,
    /// RK4's predicted relative drift of `|q|` over the run; 0 for methods it does not threaten.
    predicted_drift: f64,
    /// The model's fastest decay rate (a damper's slip); 0 for none.
    stiffness: f64,
    /// A fixed step's predicted error, truncation and round-off; 0 for other methods.
    predicted_error: f64,
    /// Whether no step meets `rtol` over the run (its round-off alone exceeds it).
    out_of_reach: bool,
    /// The cheapest fixed-step method that meets `rtol` where this one cannot (see
    /// `run::step_size::reaching`).
    reached_by: Option<&'static str>,
}

impl From<StepPlan> for PyStepPlan {
    fn from(p: StepPlan) -> Self {
        Self {
            dt: p.dt,
            step: p.step,
            rate_bound: p.rate_bound,
            predicted_drift: p.predicted_drift,
            stiffness: p.stiffness,
            predicted_error: p.predicted_error,
            out_of_reach: p.out_of_reach,
            reached_by: p.reached_by,
        }
    }
}

/// The step shared by the runs of a batch (or one run), its worst run for RK4's drift and its
/// stiffest model (see `ensemble::plan`).
#[pyclass(name = "BatchPlan", module = "dzhanibekov._core", frozen, get_all)]
struct PyBatchPlan {
    dt: Option<f64>,
    worst_row: Option<usize>,
    worst: Option<PyStepPlan>,
    stiffest_row: Option<usize>,
    stiffest: Option<PyStepPlan>,
}

/// A batch's rows as the core takes them: systems, rates, attitudes.
type CoreRows = (Vec<System>, Vec<[f64; 3]>, Vec<[f64; 4]>);

/// The systems of a batch's rows (one shared, or one each) and its starts, as the core's;
/// row `i` seeded `first_row + i` (its number in the whole batch: its parts' noise).
fn rows_of(
    systems: &[PyRef<'_, PySystem>],
    inertia: Option<&PyReadonlyArray2<'_, f64>>,
    omega0: &PyReadonlyArray2<'_, f64>,
    q0: &PyReadonlyArray2<'_, f64>,
    first_row: u64,
) -> PyResult<CoreRows> {
    let (omega, q) = (omega0.as_array(), q0.as_array());
    let m = omega.shape()[0];
    let given = inertia.map_or(systems.len(), |a| a.as_array().shape()[0]);
    let widths = inertia.is_none_or(|a| a.as_array().shape()[1] == 3);
    if omega.shape()[1] != 3 || q.shape() != [m, 4] || !(given == 1 || given == m) || !widths {
        return Err(Error::invalid(
            "omega0, q0",
            "must have shapes (M, 3) and (M, 4), with one system or M",
            (omega.shape().to_vec(), q.shape().to_vec(), given),
        )
        .into());
    }
    const HINT: &str = "run fewer starts at a time";
    // each row's copy of its system (and what the copy holds on the heap) and its start,
    // checked at once before any is made
    let copies: f64 = match inertia {
        Some(_) => 0.0,
        None if given == 1 => m as f64 * systems[0].inner.heap_bytes() as f64,
        None => systems.iter().map(|s| s.inner.heap_bytes() as f64).sum(),
    };
    let row = std::mem::size_of::<System>() + std::mem::size_of::<([f64; 3], [f64; 4])>();
    ensure_room(copies + (m * row) as f64, "the batch's systems", HINT)?;
    let mut s = try_with_capacity(m, "the batch's systems", HINT)?;
    let mut w = try_with_capacity(m, "the starts", HINT)?;
    let mut qs = try_with_capacity(m, "the starts", HINT)?;
    for i in 0..m {
        let k = i.min(given - 1);
        s.push(match inertia {
            Some(a) => {
                let a = a.as_array();
                let body = RigidBody::try_new([a[[k, 0]], a[[k, 1]], a[[k, 2]]])
                    .map_err(|e| e.in_row(k))?;
                System::rigid(Inertia::from_principal(body))
            }
            None => systems[k]
                .inner
                .clone()
                .with_seed(first_row.wrapping_add(i as u64)),
        });
        w.push([omega[[i, 0]], omega[[i, 1]], omega[[i, 2]]]);
        qs.push([q[[i, 0]], q[[i, 1]], q[[i, 2]], q[[i, 3]]]);
    }
    Ok((s, w, qs))
}

/// Plans the step of every row (one system or M, or rows of moments `inertia`; rates
/// (M, 3), attitudes (M, 4)).
#[pyfunction]
#[pyo3(signature = (systems, omega0, q0, options, inertia = None))]
fn plan(
    py: Python<'_>,
    systems: Vec<PyRef<'_, PySystem>>,
    omega0: PyReadonlyArray2<'_, f64>,
    q0: PyReadonlyArray2<'_, f64>,
    options: &PyRunOptions,
    inertia: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<PyBatchPlan> {
    let (systems, omega, q) = rows_of(&systems, inertia.as_ref(), &omega0, &q0, 0)?;
    ensure_room(
        systems.len() as f64 * (std::mem::size_of::<StepPlan>() + 32) as f64,
        "the step plans",
        "plan fewer starts at a time",
    )?;
    let options = options.inner;
    let p = py.detach(|| plan_systems(&systems, &omega, &q, &options))?;
    Ok(PyBatchPlan {
        dt: p.dt,
        worst_row: p.worst.map(|(row, _)| row),
        worst: p.worst.map(|(_, plan)| plan.into()),
        stiffest_row: p.stiffest.map(|(row, _)| row),
        stiffest: p.stiffest.map(|(_, plan)| plan.into()),
    })
}

/// The frame times of `grid`, as an array; none (an empty array) for a run that keeps no
/// frames, whose frames may be far more than memory holds (a sweep's `frames` only set where
/// its drift is measured).
fn frame_times(py: Python<'_>, grid: &FrameGrid, kept: bool) -> PyResult<Py<PyArray1<f64>>> {
    let n = if kept { grid.frames() } else { 0 };
    let t = try_collect(
        (0..n).map(|i| grid.time(i)),
        n,
        "the frame times",
        FRAMES_HINT,
    )?;
    Ok(owned(py, t, Ix1(n))?.unbind())
}

/// What to say when a result's arrays do not fit.
const FRAMES_HINT: &str = "ask for fewer runs or frames";

/// `values` as an array of `shape`.
fn shaped2(py: Python<'_>, v: Vec<f64>, shape: (usize, usize)) -> PyResult<Py<PyArray2<f64>>> {
    Ok(owned(py, v, Ix2(shape.0, shape.1))?.unbind())
}

fn shaped3(
    py: Python<'_>,
    v: Vec<f64>,
    shape: (usize, usize, usize),
) -> PyResult<Py<PyArray3<f64>>> {
    Ok(owned(py, v, Ix3(shape.0, shape.1, shape.2))?.unbind())
}

fn keep(options: &RunOptions, frames: bool) -> Keep {
    Keep {
        frames,
        flips: options.flips,
        tilt: false,
    }
}

/// What every run of a batch or sweep reports, one value per run in each column: the
/// drift `(energy, momentum, momentum_world, q_norm, jacobi, energy_balance)` (the last two
/// NaN where a model has none), the names of what the models keep, the cost and the step.
#[pyclass(name = "RunColumns", module = "dzhanibekov._core", frozen, get_all)]
struct PyRunColumns {
    drift: [Py<PyArray1<f64>>; 6],
    kept: Vec<&'static str>,
    nfev: Py<PyArray1<i64>>,
    n_steps: Py<PyArray1<i64>>,
    n_rejected: Py<PyArray1<i64>>,
    dt: Py<PyArray1<f64>>,
}

impl PyRunColumns {
    fn new(py: Python<'_>, drift: &[Drift], stats: &[Stats], dt: Vec<f64>) -> PyResult<Self> {
        let of = |f: fn(&Drift) -> f64| column_of(py, drift.iter().map(f), drift.len());
        let count =
            |f: fn(&Stats) -> u64| column_of(py, stats.iter().map(|s| f(s) as i64), stats.len());
        Ok(Self {
            drift: [
                of(|d| d.energy)?,
                of(|d| d.momentum)?,
                of(|d| d.momentum_world)?,
                of(|d| d.q_norm)?,
                of(|d| d.jacobi.unwrap_or(f64::NAN))?,
                of(|d| d.energy_balance.unwrap_or(f64::NAN))?,
            ],
            kept: drift.first().map_or(Vec::new(), |d| d.kept.names()),
            nfev: count(|s| s.nfev)?,
            n_steps: count(|s| s.n_steps)?,
            n_rejected: count(|s| s.n_rejected)?,
            dt: column(py, dt)?,
        })
    }
}

/// Per-row values as a NumPy array.
fn column<T: numpy::Element + Send + Sync + 'static>(
    py: Python<'_>,
    v: Vec<T>,
) -> PyResult<Py<PyArray1<T>>> {
    let n = v.len();
    Ok(owned(py, v, Ix1(n))?.unbind())
}

/// The `n` values of `values` as a NumPy array, every allocation fallible.
fn column_of<T: numpy::Element + Send + Sync + 'static>(
    py: Python<'_>,
    values: impl IntoIterator<Item = T>,
    n: usize,
) -> PyResult<Py<PyArray1<T>>> {
    column(py, try_collect(values, n, "the runs' columns", ROWS_HINT)?)
}

/// What to say when a batch's per-run columns do not fit.
const ROWS_HINT: &str = "run fewer starts at a time";

/// A batch's output: the frame times; frames `(M, frames, ·)` and parts' state if kept; where
/// each row ended (`(M, 3)`, `(M, 4)`, `(M, k)`; NaN where not kept); every row's flip times
/// (row `i`'s are `flip_times[flip_offsets[i]:flip_offsets[i + 1]]`); the time each row's spin
/// went flat (NaN: not by the end; empty where not watched); per-row columns.
#[pyclass(name = "BatchResult", module = "dzhanibekov._core", frozen, get_all)]
struct PyBatchResult {
    t: Py<PyArray1<f64>>,
    omega: Option<Py<PyArray3<f64>>>,
    q: Option<Py<PyArray3<f64>>>,
    parts: Option<Py<PyArray3<f64>>>,
    end_omega: Py<PyArray2<f64>>,
    end_q: Py<PyArray2<f64>>,
    end_parts: Py<PyArray2<f64>>,
    flip_offsets: Py<PyArray1<i64>>,
    flip_times: Py<PyArray1<f64>>,
    flat_time: Py<PyArray1<f64>>,
    runs: Py<PyRunColumns>,
}

fn batch_options(threads: Option<usize>, isa: Option<&str>) -> PyResult<BatchOptions> {
    Ok(BatchOptions {
        threads,
        isa: isa.map(str::parse::<Isa>).transpose()?,
    })
}

/// Runs every row (as `plan` takes them) over one frame grid.
#[pyfunction]
#[pyo3(signature = (systems, omega0, q0, options, keep_frames, isa = None, inertia = None, first_row = 0))]
#[allow(clippy::too_many_arguments)]
fn simulate_batch(
    py: Python<'_>,
    systems: Vec<PyRef<'_, PySystem>>,
    omega0: PyReadonlyArray2<'_, f64>,
    q0: PyReadonlyArray2<'_, f64>,
    options: &PyRunOptions,
    keep_frames: bool,
    isa: Option<&str>,
    inertia: Option<PyReadonlyArray2<'_, f64>>,
    first_row: u64,
) -> PyResult<PyBatchResult> {
    let (mut systems, omega, q) = rows_of(&systems, inertia.as_ref(), &omega0, &q0, first_row)?;
    // this run's own view of each Python torque function (its failure, its Ctrl-C)
    let python = super::callable::PythonCalls::of(py, &mut systems);
    let options = options.inner;
    let (method, grid) = options.method_and_grid()?;
    let mut batch = batch_options(options.threads, isa)?;
    if python.any() {
        // each call of a Python torque takes the GIL: rows on several threads would only
        // queue for it (and answer Ctrl-C late); one thread runs them one after another
        batch.threads = Some(1);
    }
    let rows = Rows {
        systems: &systems,
        omega0: &omega,
        q0: &q,
    };
    let (m, f, k) = (rows.len(), grid.frames(), rows.parts_width()?);
    let keep = keep(&options, keep_frames);
    let long = watchdog::is_long(&method, &grid, m);
    let out = detach_with(
        py,
        long,
        |cancel| simulate_systems(rows, &grid, method, keep, &batch, cancel),
        || python.stop(),
    );
    // a Python torque function's failure stops the run: its own error reaches the caller
    let out = match python.failure() {
        Some(e) => return Err(e),
        None => out?,
    };
    let frames = |v: Vec<f64>, width: usize| match keep_frames && width > 0 {
        true => shaped3(py, v, (m, f, width)).map(Some),
        false => Ok(None),
    };
    let ends = |width: usize, of: &dyn Fn(&crate::observe::End) -> &[f64]| {
        let mut v = try_with_capacity(m * width, "the runs' ends", ROWS_HINT)?;
        match out.end.len() {
            0 => v.resize(m * width, f64::NAN),
            _ => out.end.iter().for_each(|e| v.extend_from_slice(of(e))),
        }
        shaped2(py, v, (m, width))
    };
    let (end_omega, end_q, end_parts) = (
        ends(3, &|e| &e.omega)?,
        ends(4, &|e| &e.q)?,
        ends(k, &|e| &e.parts)?,
    );
    let offsets = out.flip_offsets.iter().map(|&o| o as i64);
    let flip_offsets = column_of(py, offsets, out.flip_offsets.len())?;
    let runs = PyRunColumns::new(py, &out.drift, &out.stats, out.dt)?;
    Ok(PyBatchResult {
        t: frame_times(py, &grid, keep_frames)?,
        omega: frames(out.omega, 3)?,
        q: frames(out.q, 4)?,
        parts: frames(out.parts, k)?,
        end_omega,
        end_q,
        end_parts,
        flip_offsets,
        flip_times: column(py, out.flip_times)?,
        flat_time: column(py, out.flat_time)?,
        runs: Py::new(py, runs)?,
    })
}

/// One run's output: the frame times, rates `(F, 3)`, attitudes `(F, 4)` and parts' state
/// `(F, k)` (no frames where none were kept); its flip times (None unless asked for); the
/// time its spin went flat (None where not watched, NaN: not by the end); its drift
/// `(energy, momentum, momentum_world, q_norm, jacobi, energy_balance)` (the last two None
/// where its model has none) and what its model keeps; its step and cost.
#[pyclass(name = "Run", module = "dzhanibekov._core", frozen, get_all)]
struct PyRun {
    t: Py<PyArray1<f64>>,
    omega: Py<PyArray2<f64>>,
    q: Py<PyArray2<f64>>,
    parts: Py<PyArray2<f64>>,
    flip_times: Option<Py<PyArray1<f64>>>,
    flat_time: Option<f64>,
    drift: (f64, f64, f64, f64, Option<f64>, Option<f64>),
    kept: Vec<&'static str>,
    dt: f64,
    n_steps: u64,
    nfev: u64,
    n_rejected: u64,
}

/// One run of `system` from `omega0` (3,) and `q0` (4,): its step planned and the run made
/// on one model, built once; `warn(plan)` called with its plan (a `StepPlan`) before it
/// starts, and `progress(share)` now and then with the share of its span done (see
/// `run::progress`). The same bits as row 0 of `simulate_batch` with the planned step.
#[pyfunction]
#[pyo3(signature = (system, omega0, q0, options, keep_frames = true, warn = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    system: &PySystem,
    omega0: PyReadonlyArray1<'_, f64>,
    q0: PyReadonlyArray1<'_, f64>,
    options: &PyRunOptions,
    keep_frames: bool,
    warn: Option<Py<PyAny>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PyRun> {
    let (omega0, q0) = match (omega0.as_slice()?, q0.as_slice()?) {
        (&[a, b, c], &[w, x, y, z]) => ([a, b, c], [w, x, y, z]),
        (w, q) => {
            let shapes = (w.len(), q.len());
            return Err(
                Error::invalid("omega0, q0", "must have shapes (3,) and (4,)", shapes).into(),
            );
        }
    };
    // the run's own system, seeded as a batch's row 0, with its own view of each Python
    // torque function (its failure, its Ctrl-C)
    let mut systems = [system.inner.clone().with_seed(0)];
    let python = super::callable::PythonCalls::of(py, &mut systems);
    let options = options.inner;
    let planned = py.detach(|| Planned::new(&systems[0], omega0, q0, &options))?;
    if let Some(warn) = &warn {
        warn.call1(py, (PyStepPlan::from(planned.plan),))?;
    }
    let (method, grid) = options.with_dt(planned.plan.dt)?.method_and_grid()?;
    let keep = keep(&options, keep_frames);
    let meter = Arc::new(Meter::new());
    let mut shown = -1.0;
    let out = detach_reporting(
        py,
        watchdog::is_long(&method, &grid, 1),
        |cancel| {
            let run = || planned.run(&grid, method, keep, cancel);
            match &progress {
                Some(_) => metered(meter.clone(), run),
                None => run(),
            }
        },
        || python.stop(),
        |py| match &progress {
            Some(report) if meter.share() != shown => {
                shown = meter.share();
                report.call1(py, (shown,)).map(|_| ())
            }
            _ => Ok(()),
        },
    );
    // a Python torque function's failure stops the run: its own error reaches the caller
    let out = match python.failure() {
        Some(e) => return Err(e),
        None => out?,
    };
    let (n, k) = (out.omega.len() / 3, systems[0].parts_width());
    let part_frames = out.parts.len().checked_div(k).unwrap_or(n);
    let d = out.drift;
    let known = |x: Option<f64>| x.filter(|x| !x.is_nan());
    Ok(PyRun {
        t: frame_times(py, &grid, keep_frames)?,
        omega: shaped2(py, out.omega, (n, 3))?,
        q: shaped2(py, out.q, (n, 4))?,
        parts: shaped2(py, out.parts, (part_frames, k))?,
        flip_times: match options.flips {
            true => Some(column(py, out.flip_times)?),
            false => None,
        },
        flat_time: out.flat_time,
        drift: (
            d.energy,
            d.momentum,
            d.momentum_world,
            d.q_norm,
            known(d.jacobi),
            known(d.energy_balance),
        ),
        kept: d.kept.names(),
        dt: out.dt,
        n_steps: out.stats.n_steps,
        nfev: out.stats.nfev,
        n_rejected: out.stats.n_rejected,
    })
}

/// A sweep's per-run columns (see `crate::ensemble::sweep::RunSummary`).
#[pyclass(name = "SweepResult", module = "dzhanibekov._core", frozen, get_all)]
struct PySweepResult {
    /// Flips counted; −1 for a run that did not finish (never mistaken for a stable one).
    flips: Py<PyArray1<i64>>,
    /// Indices into `RUN_STATUSES`.
    status: Py<PyArray1<u8>>,
    first_flip: Py<PyArray1<f64>>,
    period: Py<PyArray1<f64>>,
    exact_period: Py<PyArray1<f64>>,
    tilt: Py<PyArray1<f64>>,
    runs: Py<PyRunColumns>,
}

/// Free bodies' runs summarised, no frames kept (see `crate::ensemble::sweep`): rows as
/// `simulate_batch` takes them, in the user's axes (run in principal axes).
#[pyfunction]
#[pyo3(signature = (systems, omega0, q0, options, isa = None, inertia = None))]
fn sweep(
    py: Python<'_>,
    systems: Vec<PyRef<'_, PySystem>>,
    omega0: PyReadonlyArray2<'_, f64>,
    q0: PyReadonlyArray2<'_, f64>,
    options: &PyRunOptions,
    isa: Option<&str>,
    inertia: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<PySweepResult> {
    let (systems, omega, q) = rows_of(&systems, inertia.as_ref(), &omega0, &q0, 0)?;
    let options = options.inner;
    let (method, grid) = options.method_and_grid()?;
    let batch = batch_options(options.threads, isa)?;
    let rows = Rows {
        systems: &systems,
        omega0: &omega,
        q0: &q,
    };
    let (starts, _) = free_starts(rows)?;
    let long = watchdog::is_long(&method, &grid, starts.len());
    let runs = detach(py, long, |cancel| {
        core_sweep(&starts, &grid, method, &batch, cancel)
    })?;
    let n = runs.len();
    let of = |f: fn(&RunSummary) -> f64| column_of(py, runs.iter().map(f), n);
    let drift: Vec<Drift> = try_collect(runs.iter().map(|r| r.drift), n, "the drifts", ROWS_HINT)?;
    let stats: Vec<Stats> = try_collect(runs.iter().map(|r| r.stats), n, "the costs", ROWS_HINT)?;
    let dt = try_collect(runs.iter().map(|r| r.dt), n, "the steps", ROWS_HINT)?;
    let columns = PyRunColumns::new(py, &drift, &stats, dt)?;
    Ok(PySweepResult {
        flips: column_of(py, runs.iter().map(RunSummary::flip_count), n)?,
        status: column_of(py, runs.iter().map(|r| r.status as u8), n)?,
        first_flip: of(|r| r.flips.first)?,
        period: of(|r| r.flips.mean_period())?,
        exact_period: of(|r| r.exact_period)?,
        tilt: of(|r| r.tilt)?,
        runs: Py::new(py, columns)?,
    })
}

/// What a system says of frames: energy (F,), total angular momentum in body axes (F, 3) and
/// in space (F, 3), from the times (F,), rates (F, 3), attitudes (F, 4) and parts' state (F, k).
type Observed<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
);

/// The frames' arrays `observe` and `part_rates` read, checked: times (F,), rates (F, 3),
/// attitudes (F, 4) and the parts' state (F, `k`), each C-contiguous.
type Frames<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a [f64]);

fn frames_of<'a>(
    function: &'static str,
    k: usize,
    t: &'a PyReadonlyArray1<'_, f64>,
    omega: &'a PyReadonlyArray2<'_, f64>,
    q: &'a PyReadonlyArray2<'_, f64>,
    parts: &'a PyReadonlyArray2<'_, f64>,
) -> PyResult<Frames<'a>> {
    let n = t.len();
    if omega.shape() != [n, 3] || q.shape() != [n, 4] || parts.shape() != [n, k] {
        return Err(Error::invalid(
            "omega, q, parts",
            "must have shapes (F, 3), (F, 4) and (F, parts) for F times",
            (
                omega.shape().to_vec(),
                q.shape().to_vec(),
                parts.shape().to_vec(),
            ),
        )
        .into());
    }
    let contiguous = |name: &str| Error::invalid(function, "takes C-contiguous arrays", name);
    Ok((
        t.as_slice().map_err(|_| contiguous("t"))?,
        omega.as_slice().map_err(|_| contiguous("omega"))?,
        q.as_slice().map_err(|_| contiguous("q"))?,
        parts.as_slice().map_err(|_| contiguous("parts"))?,
    ))
}

/// The energy and angular momenta of `system` at each frame (see [`Observed`]), without
/// the GIL for many frames.
#[pyfunction]
fn observe<'py>(
    py: Python<'py>,
    system: &PySystem,
    t: PyReadonlyArray1<'py, f64>,
    omega: PyReadonlyArray2<'py, f64>,
    q: PyReadonlyArray2<'py, f64>,
    parts: PyReadonlyArray2<'py, f64>,
) -> PyResult<Observed<'py>> {
    let (n, k) = (t.len(), system.inner.parts_width());
    let (t, omega, q, parts) = frames_of("observe", k, &t, &omega, &q, &parts)?;
    let system = &system.inner;
    let (energy, body, world) = detach(py, n > watchdog::LONG_INVARIANTS, |_| {
        const HINT: &str = "compute them over fewer frames at a time";
        let mut energy = try_with_capacity(n, "the energies", HINT)?;
        let mut body = try_with_capacity(3 * n, "the angular momenta", HINT)?;
        let mut world = try_with_capacity(3 * n, "the angular momenta", HINT)?;
        for i in 0..n {
            let w = [omega[3 * i], omega[3 * i + 1], omega[3 * i + 2]];
            let a = [q[4 * i], q[4 * i + 1], q[4 * i + 2], q[4 * i + 3]];
            let (e, l, lw) = system.observe(t[i], w, &parts[k * i..k * (i + 1)], a);
            energy.push(e);
            body.extend_from_slice(l.as_slice());
            world.extend_from_slice(lw.as_slice());
        }
        Ok((energy, body, world))
    })?;
    Ok((
        owned(py, energy, Ix1(n))?,
        shaped2(py, body, (n, 3))?.into_bound(py),
        shaped2(py, world, (n, 3))?.into_bound(py),
    ))
}

/// The rates of the parts' state at each frame `(F, k)`, laid out as the state: a part whose
/// mass moves has its rates as the run's right-hand side gives them (from the same solve as
/// [`observe`]), every other part NaN; from the same arrays as [`observe`].
#[pyfunction]
fn part_rates<'py>(
    py: Python<'py>,
    system: &PySystem,
    t: PyReadonlyArray1<'py, f64>,
    omega: PyReadonlyArray2<'py, f64>,
    q: PyReadonlyArray2<'py, f64>,
    parts: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (n, k) = (t.len(), system.inner.parts_width());
    let (t, omega, q, parts) = frames_of("part_rates", k, &t, &omega, &q, &parts)?;
    let system = &system.inner;
    let law = system.inertia_law()?;
    let rates = detach(py, n > watchdog::LONG_INVARIANTS, |_| {
        let mut rates = try_with_capacity(n * k, "the parts' rates", "ask for fewer frames")?;
        rates.resize(n * k, f64::NAN);
        for i in 0..n {
            let w = [omega[3 * i], omega[3 * i + 1], omega[3 * i + 2]];
            let a = [q[4 * i], q[4 * i + 1], q[4 * i + 2], q[4 * i + 3]];
            let x = &parts[k * i..k * (i + 1)];
            system.moving_rates(&law, t[i], w, x, a, &mut rates[k * i..k * (i + 1)]);
        }
        Ok(rates)
    })?;
    Ok(shaped2(py, rates, (n, k))?.into_bound(py))
}

pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyStepPlan>()?;
    m.add_class::<PyBatchPlan>()?;
    m.add_class::<PyRunColumns>()?;
    m.add_class::<PyBatchResult>()?;
    m.add_class::<PyRun>()?;
    m.add_class::<PySweepResult>()?;
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(observe, m)?)?;
    m.add_function(wrap_pyfunction!(part_rates, m)?)?;
    // a sweep's `status` codes index this tuple
    m.add(
        "RUN_STATUSES",
        pyo3::types::PyTuple::new(m.py(), RunStatus::ALL.map(RunStatus::name))?,
    )?;
    Ok(())
}
