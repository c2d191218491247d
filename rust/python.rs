//! The Python bindings, `dzhanibekov._core`: extract, validate, run without the GIL, wrap.
//! No physics here. Inputs arrive already coerced by the Python layer; everything is checked
//! again in the core, whose errors become `ValueError`.
#![deny(clippy::unwrap_used, clippy::expect_used)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::thread::ThreadId;

use numpy::ndarray::{Array2, Array3};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadwriteArray3, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::body::RigidBody;
use crate::buffer::{ensure_room, try_with_capacity};
use crate::dynamics::{state_from, Invariants};
use crate::dynamics::{DampedBody, DamperState, Deployment, DeploymentState, Model};
use crate::ensemble::batch::{
    simulate_batch as core_simulate_batch, Options as BatchOptions, Start,
};
use crate::ensemble::lanes::Isa;
use crate::ensemble::plan::plan_batch as core_plan_batch;
use crate::ensemble::sweep::{sweep as core_sweep, RunStatus, RunSummary};
use crate::error::Error;
use crate::exact;
use crate::exact::elliptic::Jacobi;
use crate::kinematics::rotate_points_until;
use crate::mesh::ellipsoid;
use crate::observe::Drift;
use crate::ode::Stats;
use crate::run::registry::{
    MethodInfo, DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_METHOD, DEFAULT_RTOL, METHODS,
};
use crate::run::step_size::{plan, StepPlan};
use crate::run::watchdog;
use crate::run::{
    method_and_grid, model_method_and_grid, rows_method_and_grid, simulate as core_simulate,
    simulate_model, simulate_models, FrameGrid, Keep, Method, ModelOutput,
};

/// The one mapping of the core's errors to Python's: the classes of `dzhanibekov.errors`
/// (all `ValueError`s), a batch or sweep row's error with its row in `.row`.
impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        Python::attach(|py| python_error(py, e))
    }
}

fn python_error(py: Python<'_>, e: Error) -> PyErr {
    let (row, error) = match e {
        Error::Row { row, error } => (Some(row), *error),
        error => (None, error),
    };
    let class = match error {
        Error::Diverged { .. } => "DivergedError",
        Error::TooLarge { .. } => "TooLargeError",
        _ => "DzhanibekovError",
    };
    let message = error.to_string();
    let raised = py
        .import("dzhanibekov.errors")
        .and_then(|errors| errors.getattr(class))
        .and_then(|class| class.call1((message.as_str(), row)));
    match raised {
        Ok(exception) => PyErr::from_value(exception),
        // only if the package is broken: the error still reaches the user
        Err(_) => PyValueError::new_err(message),
    }
}

/// Set by an `atexit` hook (registered when the module loads) once the interpreter begins to
/// shut down, with the id of the thread shutting it down.
static FINALIZING: AtomicBool = AtomicBool::new(false);
static FINALIZING_THREAD: OnceLock<ThreadId> = OnceLock::new();

/// The `atexit` hook: from now on no call of another thread touches the interpreter again.
#[pyfunction]
fn _finalizing() {
    let _ = FINALIZING_THREAD.set(std::thread::current().id());
    FINALIZING.store(true, Ordering::SeqCst);
}

/// Whether this thread must keep away from the interpreter: it is shutting down, and this is
/// not the thread doing it (a daemon thread still in a long call).
fn shut_out() -> bool {
    FINALIZING.load(Ordering::SeqCst)
        && FINALIZING_THREAD.get() != Some(&std::thread::current().id())
}

/// Blocks this thread for good: a daemon thread whose call ends while the interpreter shuts
/// down must not take the GIL again (CPython then ends or hangs it, and objects its call
/// would touch are being freed); the process exits around it.
fn park_forever() -> ! {
    loop {
        std::thread::park();
    }
}

/// Runs `work` without the GIL. Long work runs on a helper thread while this thread polls for
/// signals (see [`watchdog::watch`]), so Ctrl-C sets `cancel` and surfaces as
/// `KeyboardInterrupt` within a poll interval. Short work runs inline, sparing the thread start.
/// A signal that arrived during the call is raised before anything else touches Python
/// (converting the result could run Python code, e.g. NumPy's first import of its C API,
/// where it would surface as a panic).
///
/// Inputs borrowed by `work` must not be mutated by another Python thread during the call.
/// If the interpreter starts to shut down during the call, this thread never takes the GIL
/// again (see [`park_forever`]).
fn detach<T: Send>(
    py: Python<'_>,
    long: bool,
    work: impl FnOnce(&AtomicBool) -> Result<T, Error> + Send,
) -> PyResult<T> {
    if !long {
        let cancel = AtomicBool::new(false);
        let result = py.detach(|| {
            let result = work(&cancel);
            if shut_out() {
                park_forever();
            }
            result
        });
        py.check_signals()?;
        return result.map_err(PyErr::from);
    }
    let mut interrupt: Option<PyErr> = None;
    let outcome = py.detach(|| {
        let outcome = watchdog::watch(work, || {
            // a daemon thread's call while the interpreter shuts down: stop, never attach
            if shut_out() {
                return true;
            }
            match Python::attach(|py| py.check_signals()) {
                Err(e) => {
                    interrupt = Some(e);
                    true
                }
                Ok(()) => false,
            }
        });
        if shut_out() {
            park_forever();
        }
        outcome
    });
    py.check_signals()?;
    match (outcome, interrupt) {
        (_, Some(e)) => Err(e),
        (Ok(result), None) => result.map_err(PyErr::from),
        (Err(_), None) => Err(PyRuntimeError::new_err(
            "internal error in the dzhanibekov core (a bug; please report it)",
        )),
    }
}

/// Whether locating the flips of an exact run is long work: one flip per period, so a long
/// `t_end` can mean 10⁸ of them however few frames are kept.
fn long_flip_search(
    method: &Method,
    body: &RigidBody,
    omega0: [f64; 3],
    t_end: f64,
    flips: bool,
) -> bool {
    if !flips || method.info().takes_steps() {
        return false;
    }
    let period = exact::flip_period(body, omega0).unwrap_or(f64::INFINITY);
    t_end / period > watchdog::LONG_EXACT_FRAMES as f64
}

/// A body's principal moments, validated.
#[pyclass(name = "RigidBody", module = "dzhanibekov._core", frozen)]
struct PyRigidBody {
    inner: RigidBody,
}

#[pymethods]
impl PyRigidBody {
    #[new]
    fn new(inertia: [f64; 3]) -> PyResult<Self> {
        Ok(Self {
            inner: RigidBody::try_new(inertia)?,
        })
    }

    #[staticmethod]
    #[pyo3(signature = (a, b, c, mass = 1.0))]
    fn from_box(a: f64, b: f64, c: f64, mass: f64) -> PyResult<Self> {
        Ok(Self {
            inner: RigidBody::from_box(a, b, c, mass)?,
        })
    }

    #[getter]
    fn inertia(&self) -> (f64, f64, f64) {
        let i = self.inner.inertia_body();
        (i.x, i.y, i.z)
    }

    #[getter]
    fn satisfies_triangle_inequality(&self) -> bool {
        self.inner.satisfies_triangle_inequality()
    }

    #[getter]
    fn intermediate_axis(&self) -> Option<usize> {
        self.inner.intermediate_axis()
    }

    fn __repr__(&self) -> String {
        let i = self.inner.inertia_body();
        format!("RigidBody(inertia=({}, {}, {}))", i.x, i.y, i.z)
    }

    /// Pickles by the moments, which rebuild the same body.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (Bound<'py, pyo3::types::PyType>, ((f64, f64, f64),)) {
        let i = slf.get().inner.inertia_body();
        (slf.get_type(), ((i.x, i.y, i.z),))
    }
}

/// What the core knows about a method (its entry in the registry), read-only.
#[pyclass(name = "MethodInfo", module = "dzhanibekov._core", frozen)]
struct PyMethodInfo {
    info: &'static MethodInfo,
}

#[pymethods]
impl PyMethodInfo {
    /// The name to pass as `method=`.
    #[getter]
    fn name(&self) -> &'static str {
        self.info.name
    }

    /// The order of the global error; None for the exact solution.
    #[getter]
    fn order(&self) -> Option<u32> {
        self.info.order
    }

    /// Whether the method chooses its own steps under `rtol` and `atol`.
    #[getter]
    fn adaptive(&self) -> bool {
        self.info.adaptive()
    }

    /// What the method keeps to round-off, by the names of `Drift`'s fields.
    #[getter]
    fn keeps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.info.keeps)
    }

    /// Right-hand-side evaluations per (accepted) step; 0 for a method that evaluates none.
    #[getter]
    fn rhs_per_step(&self) -> u64 {
        self.info.rhs_per_step
    }

    /// Whether a batch runs it several rows at once in SIMD lanes.
    #[getter]
    fn batch(&self) -> bool {
        self.info.batch
    }

    /// The models it can run.
    #[getter]
    fn models<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.info.models)
    }

    /// A fixed-step method's stability limit on `|h λ|` along the imaginary axis (an undamped
    /// wobble at rate `λ`); None for the others.
    #[getter]
    fn imaginary_limit(&self) -> Option<f64> {
        self.info.stability.map(|s| s.imaginary)
    }

    /// A fixed-step method's stability limit on `h λ` along the negative real axis (a mode
    /// decaying at rate `λ`, a damper's slip); None for the others.
    #[getter]
    fn real_limit(&self) -> Option<f64> {
        self.info.stability.map(|s| s.real)
    }

    /// One line about it.
    #[getter]
    fn about(&self) -> &'static str {
        self.info.about
    }

    /// Pickles by name: the entry is looked up again on load.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (&'static str,))> {
        let lookup = py.import("dzhanibekov._core")?.getattr("method_info")?;
        Ok((lookup, (self.info.name,)))
    }

    fn __repr__(&self) -> String {
        let info = self.info;
        let order = info.order.map_or("None".to_string(), |o| o.to_string());
        format!(
            "MethodInfo(name='{}', order={order}, adaptive={}, keeps={}, rhs_per_step={}, \
             batch={}, models={})",
            info.name,
            py_bool(info.adaptive()),
            py_tuple(info.keeps),
            info.rhs_per_step,
            py_bool(info.batch),
            py_tuple(info.models),
        )
    }
}

fn py_bool(b: bool) -> &'static str {
    if b {
        "True"
    } else {
        "False"
    }
}

/// Names as Python writes a tuple of strings.
fn py_tuple(names: &[&str]) -> String {
    match names {
        [one] => format!("('{one}',)"),
        _ => {
            let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
            format!("({})", quoted.join(", "))
        }
    }
}

/// The registry entry of the method called `name`.
#[pyfunction]
fn method_info(name: &str) -> PyResult<PyMethodInfo> {
    let method: Method = name.parse()?;
    Ok(PyMethodInfo {
        info: method.info(),
    })
}

#[pyfunction]
#[pyo3(signature = (body, omega0, q0, t_end, frames, dt, method, max_steps, keep_frames, keep_flips, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    body: &PyRigidBody,
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    keep_frames: bool,
    keep_flips: bool,
    rtol: f64,
    atol: f64,
) -> PyResult<PyRunResult> {
    let (method, grid) = method_and_grid(method, t_end, frames, dt, max_steps, rtol, atol)?;
    let keep = Keep {
        frames: keep_frames,
        flips: keep_flips,
        tilt: false,
    };
    let body = body.inner;
    let long = watchdog::is_long(&method, &grid, 1)
        || long_flip_search(&method, &body, omega0, t_end, keep_flips);
    let out = detach(py, long, |cancel| {
        core_simulate(&body, omega0, q0, &grid, method, keep, cancel)
    })?;
    let (omega, q) = match keep_frames {
        true => (
            Some(Array2::from_shape_vec((frames, 3), out.omega).map_err(internal)?),
            Some(Array2::from_shape_vec((frames, 4), out.q).map_err(internal)?),
        ),
        false => (None, None),
    };
    let d = out.drift;
    Ok(PyRunResult {
        t: frame_times(py, &grid),
        omega: omega.map(|a| a.into_pyarray(py).unbind()),
        q: q.map(|a| a.into_pyarray(py).unbind()),
        flip_times: PyArray1::from_vec(py, out.flip_times).unbind(),
        drift: (d.energy, d.momentum, d.momentum_world, d.q_norm),
        nfev: out.stats.nfev,
        n_steps: out.stats.n_steps,
        n_rejected: out.stats.n_rejected,
        dt: out.dt,
    })
}

/// The frame times of `grid`, as an array.
fn frame_times(py: Python<'_>, grid: &FrameGrid) -> Py<PyArray1<f64>> {
    let t: Vec<f64> = (0..grid.frames()).map(|i| grid.time(i)).collect();
    PyArray1::from_vec(py, t).unbind()
}

/// One run's output: the frame times, frames (if kept) and flip times as arrays, the invariants' drift
/// `(energy, momentum, momentum_world, q_norm)`, the run's cost and its step.
#[pyclass(name = "RunResult", module = "dzhanibekov._core", frozen, get_all)]
struct PyRunResult {
    /// The frame times (the frame grid's).
    t: Py<PyArray1<f64>>,
    omega: Option<Py<PyArray2<f64>>>,
    q: Option<Py<PyArray2<f64>>>,
    flip_times: Py<PyArray1<f64>>,
    drift: (f64, f64, f64, f64),
    nfev: u64,
    n_steps: u64,
    n_rejected: u64,
    dt: f64,
}

/// The step a run will take and RK4's predicted drift at it (see `step_size::plan`).
#[pyclass(name = "StepPlan", module = "dzhanibekov._core", frozen, get_all)]
#[derive(Clone)]
struct PyStepPlan {
    /// The step asked for or chosen (an adaptive method's first step).
    dt: f64,
    /// The step a fixed-step method takes (the frame interval split evenly).
    step: f64,
    /// The rate bound `Ω`.
    rate_bound: f64,
    /// RK4's predicted relative drift of `|q|` over the run; 0 for methods it does not threaten.
    predicted_drift: f64,
}

impl From<StepPlan> for PyStepPlan {
    fn from(p: StepPlan) -> Self {
        Self {
            dt: p.dt,
            step: p.step,
            rate_bound: p.rate_bound,
            predicted_drift: p.predicted_drift,
        }
    }
}

/// The step a run will take and RK4's predicted drift at it (see `step_size::plan`).
#[pyfunction]
#[pyo3(signature = (body, omega0, t_end, frames, dt, method, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL))]
#[allow(clippy::too_many_arguments)]
fn step_plan(
    body: &PyRigidBody,
    omega0: [f64; 3],
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    rtol: f64,
    atol: f64,
) -> PyResult<PyStepPlan> {
    let method = Method::named(method, rtol, atol, None)?;
    Ok(plan(&body.inner, omega0, t_end, frames, method, dt, rtol)?.into())
}

/// `rtol` if the core accepts it as a relative tolerance, else its `ValueError`.
#[pyfunction]
fn check_rtol(rtol: f64) -> PyResult<f64> {
    Ok(crate::ode::controller::check_rtol(rtol)?)
}

/// A model run's frames (time-major), what the model keeps or changes at each frame, its
/// cost and its step.
#[pyclass(name = "ModelResult", module = "dzhanibekov._core", frozen, get_all)]
struct PyModelResult {
    t: Py<PyArray1<f64>>,
    omega: Py<PyArray2<f64>>,
    q: Py<PyArray2<f64>>,
    /// Total angular momentum in space `(frames, 3)`.
    momentum_world: Py<PyArray2<f64>>,
    /// Total angular momentum in body axes `(frames, 3)`.
    momentum_body: Py<PyArray2<f64>>,
    /// Total kinetic energy `(frames,)`.
    energy: Py<PyArray1<f64>>,
    /// A damper's absolute rates in body axes `(frames, 3)`; None for a deployment.
    sigma: Option<Py<PyArray2<f64>>>,
    /// The flips located, if asked for and the model's tensors are diagonal; else None.
    flip_times: Option<Py<PyArray1<f64>>>,
    /// The drift `(energy, momentum, momentum_world, q_norm)` of what the model keeps (the
    /// energy entry its largest relative change), measured in the run's own units.
    drift: (f64, f64, f64, f64),
    nfev: u64,
    n_steps: u64,
    n_rejected: u64,
    dt: f64,
}

/// A model run's output as a [`PyModelResult`]; `sigma`: whether its extra output is a
/// damper's rates.
fn model_result(
    py: Python<'_>,
    out: ModelOutput,
    grid: &FrameGrid,
    sigma: bool,
) -> PyResult<PyModelResult> {
    let frames = grid.frames();
    let d = out.drift;
    let rows = |v: Vec<f64>, width: usize| {
        Array2::from_shape_vec((frames, width), v)
            .map(|a| a.into_pyarray(py).unbind())
            .map_err(internal)
    };
    Ok(PyModelResult {
        t: frame_times(py, grid),
        omega: rows(out.omega, 3)?,
        q: rows(out.q, 4)?,
        momentum_world: rows(out.momentum_world, 3)?,
        momentum_body: rows(out.momentum_body, 3)?,
        energy: PyArray1::from_vec(py, out.energy).unbind(),
        sigma: match sigma {
            true => Some(rows(out.extra, 3)?),
            false => None,
        },
        flip_times: out.flip_times.map(|t| PyArray1::from_vec(py, t).unbind()),
        drift: (d.energy, d.momentum, d.momentum_world, d.q_norm),
        nfev: out.stats.nfev,
        n_steps: out.stats.n_steps,
        n_rejected: out.stats.n_rejected,
        dt: out.dt,
    })
}

/// A deployment's run: knots `times` (K,) and `tensors` (K, 3, 3) given as (K, 9) rows.
#[pyfunction]
#[pyo3(signature = (times, tensors, omega0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, flips = false))]
#[allow(clippy::too_many_arguments)]
fn simulate_deployment<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    tensors: PyReadonlyArray2<'py, f64>,
    omega0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    flips: bool,
) -> PyResult<PyModelResult> {
    let times = times
        .as_slice()
        .map_err(|_| PyValueError::new_err("`times` must be C-contiguous"))?
        .to_vec();
    let rows = values("inertia", &tensors)?;
    if tensors.shape()[1] != 9 {
        return Err(PyValueError::new_err(
            "`inertia` must have rows of 9 (3 × 3 tensors)",
        ));
    }
    let tensors = rows
        .chunks_exact(9)
        .map(nalgebra::Matrix3::from_row_slice)
        .collect();
    let d = Deployment::try_new(times, tensors)?;
    let x0 = d.state_from(0.0, omega0, crate::kinematics::normalized(q0)?);
    let (method, grid) =
        model_method_and_grid(&d, &x0, method, t_end, frames, dt, max_steps, rtol, atol)?;
    let long = method.is_adaptive() || grid.n_steps() > watchdog::LONG_RUN_STEPS;
    let out = detach(py, long, |cancel| {
        simulate_model(&d, x0, &grid, method, flips, cancel)
    })?;
    model_result(py, out, &grid, false)
}

/// Deployments run side by side on all cores: per row, knot `times` and tensors as rows of
/// 9 (row-major), one start `omega0`/`q0` per row; every run shares the frame grid and step.
#[pyfunction]
#[pyo3(signature = (times, tensors, omega0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, flips = false, threads = None))]
#[allow(clippy::too_many_arguments)]
fn simulate_deployments<'py>(
    py: Python<'py>,
    times: Vec<Vec<f64>>,
    tensors: Vec<Vec<f64>>,
    omega0: Vec<[f64; 3]>,
    q0: Vec<[f64; 4]>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    flips: bool,
    threads: Option<usize>,
) -> PyResult<Vec<PyModelResult>> {
    let (systems, x0s) = deployment_systems(times, tensors, &omega0, &q0)?;
    let run = ModelRows {
        t_end,
        frames,
        dt,
        method,
        max_steps,
        rtol,
        atol,
        flips,
        threads,
    };
    run.simulate(py, &systems, &x0s, false)
}

/// The systems and initial states of rows of deployments (knot `times`, tensors as rows of 9,
/// row-major) and their starts, each checked by the core (an error names its row).
fn deployment_systems(
    times: Vec<Vec<f64>>,
    tensors: Vec<Vec<f64>>,
    omega0: &[[f64; 3]],
    q0: &[[f64; 4]],
) -> PyResult<(Vec<Deployment>, Vec<DeploymentState>)> {
    let rows = times.len();
    if tensors.len() != rows || omega0.len() != rows || q0.len() != rows || rows == 0 {
        return Err(PyValueError::new_err(
            "`times`, `inertia`, `omega0` and `q0` must give the same number of runs (at least 1)",
        ));
    }
    let mut systems = Vec::with_capacity(rows);
    let mut x0s = Vec::with_capacity(rows);
    for (row, (t, m)) in times.into_iter().zip(tensors).enumerate() {
        if m.len() != 9 * t.len() {
            return Err(PyValueError::new_err(format!(
                "run {row}: `inertia` must hold one 3 × 3 tensor per knot time"
            )));
        }
        let knots = m
            .chunks_exact(9)
            .map(nalgebra::Matrix3::from_row_slice)
            .collect();
        let d = Deployment::try_new(t, knots).map_err(|e| e.in_row(row))?;
        let q = crate::kinematics::normalized(q0[row]).map_err(|e| e.in_row(row))?;
        x0s.push(d.state_from(0.0, omega0[row], q));
        systems.push(d);
    }
    Ok((systems, x0s))
}

/// The fixed step that `simulate_deployments` of the same arguments takes (shared by every
/// row); `None` for an adaptive method, whose runs choose their own.
#[pyfunction]
#[pyo3(signature = (times, tensors, omega0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL))]
#[allow(clippy::too_many_arguments)]
fn deployment_step(
    times: Vec<Vec<f64>>,
    tensors: Vec<Vec<f64>>,
    omega0: Vec<[f64; 3]>,
    q0: Vec<[f64; 4]>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
) -> PyResult<Option<f64>> {
    let (systems, x0s) = deployment_systems(times, tensors, &omega0, &q0)?;
    let run = ModelRows {
        t_end,
        frames,
        dt,
        method,
        max_steps,
        rtol,
        atol,
        flips: false,
        threads: None,
    };
    let (method, grid) = run.method_and_grid(&systems, &x0s)?;
    Ok((!method.is_adaptive()).then(|| grid.step_size()))
}

/// The arguments shared by every row of a batch of model runs.
struct ModelRows<'a> {
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &'a str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    flips: bool,
    threads: Option<usize>,
}

impl ModelRows<'_> {
    /// The method and the one frame grid of every row ([`rows_method_and_grid`]).
    fn method_and_grid<const N: usize, S: Model<N>>(
        &self,
        systems: &[S],
        x0s: &[[f64; N]],
    ) -> PyResult<(Method, FrameGrid)> {
        Ok(rows_method_and_grid(
            systems,
            x0s,
            self.method,
            self.t_end,
            self.frames,
            self.dt,
            self.max_steps,
            self.rtol,
            self.atol,
        )?)
    }

    /// Runs `systems[i]` from `x0s[i]` on `threads` (all cores by default) over the grid of
    /// [`Self::method_and_grid`]; `sigma`: whether the model's extra output is a damper's rates.
    fn simulate<const N: usize, S: Model<N>>(
        &self,
        py: Python<'_>,
        systems: &[S],
        x0s: &[[f64; N]],
        sigma: bool,
    ) -> PyResult<Vec<PyModelResult>> {
        let (method, grid) = self.method_and_grid(systems, x0s)?;
        let options = BatchOptions {
            threads: self.threads,
            isa: None,
        };
        let out = detach(py, true, |cancel| {
            options.install(systems.len(), || {
                simulate_models(systems, x0s, &grid, method, self.flips, cancel)
            })
        })?;
        out.into_iter()
            .map(|o| model_result(py, o, &grid, sigma))
            .collect()
    }
}

/// A damped body's run: body tensor (3, 3) as 9 values, the sphere's moment and damping.
#[pyfunction]
#[pyo3(signature = (inertia, sphere, damping, omega0, sigma0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, flips = false))]
#[allow(clippy::too_many_arguments)]
fn simulate_damper<'py>(
    py: Python<'py>,
    inertia: [f64; 9],
    sphere: f64,
    damping: f64,
    omega0: [f64; 3],
    sigma0: [f64; 3],
    q0: [f64; 4],
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    flips: bool,
) -> PyResult<PyModelResult> {
    let sys = DampedBody::try_new(nalgebra::Matrix3::from_row_slice(&inertia), sphere, damping)?;
    if !sigma0.iter().all(|s| s.is_finite()) {
        return Err(Error::invalid("sigma0", "must be three finite rates", sigma0).into());
    }
    let x0 = DampedBody::state_from(omega0, sigma0, crate::kinematics::normalized(q0)?);
    let (method, grid) =
        model_method_and_grid(&sys, &x0, method, t_end, frames, dt, max_steps, rtol, atol)?;
    let long = method.is_adaptive() || grid.n_steps() > watchdog::LONG_RUN_STEPS;
    let out = detach(py, long, |cancel| {
        simulate_model(&sys, x0, &grid, method, flips, cancel)
    })?;
    model_result(py, out, &grid, true)
}

/// Rows of damped bodies and their starts: per row a body tensor as 9 values (row-major),
/// the sphere's moment and damping, and `omega0`, `sigma0`, `q0`.
type DamperRows<'a, 'py> = (
    &'a PyReadonlyArray2<'py, f64>,
    &'a PyReadonlyArray1<'py, f64>,
    &'a PyReadonlyArray1<'py, f64>,
    &'a PyReadonlyArray2<'py, f64>,
    &'a PyReadonlyArray2<'py, f64>,
    &'a PyReadonlyArray2<'py, f64>,
);

/// The systems and initial states of [`DamperRows`], each checked by the core (an error
/// names its row).
fn damper_systems(rows: DamperRows<'_, '_>) -> PyResult<(Vec<DampedBody>, Vec<DamperState>)> {
    let (inertia, sphere, damping, omega0, sigma0, q0) = rows;
    let m = omega0.shape()[0];
    let shapes = [
        (inertia.shape(), 9),
        (omega0.shape(), 3),
        (sigma0.shape(), 3),
        (q0.shape(), 4),
    ];
    if shapes.iter().any(|(s, width)| *s != [m, *width]) || sphere.len() != m || damping.len() != m
    {
        return Err(PyValueError::new_err(
            "`inertia` (M, 9), `sphere` (M,), `damping` (M,), `omega0` (M, 3), `sigma0` \
             (M, 3) and `q0` (M, 4) must give the same number of runs M",
        ));
    }
    let column = |name: &str, a: &PyReadonlyArray1<'_, f64>| -> PyResult<Vec<f64>> {
        Ok(a.as_slice()
            .map_err(|_| PyValueError::new_err(format!("`{name}` must be C-contiguous")))?
            .to_vec())
    };
    let (sphere, damping) = (column("sphere", sphere)?, column("damping", damping)?);
    let inertia = values("inertia", inertia)?;
    let (omega0, sigma0, q0) = (
        values("omega0", omega0)?,
        values("sigma0", sigma0)?,
        values("q0", q0)?,
    );
    let mut systems = Vec::with_capacity(m);
    let mut x0s = Vec::with_capacity(m);
    for row in 0..m {
        let tensor = nalgebra::Matrix3::from_row_slice(&inertia[9 * row..9 * row + 9]);
        let sys =
            DampedBody::try_new(tensor, sphere[row], damping[row]).map_err(|e| e.in_row(row))?;
        let sigma = [sigma0[3 * row], sigma0[3 * row + 1], sigma0[3 * row + 2]];
        if !sigma.iter().all(|s| s.is_finite()) {
            let e = Error::invalid("sigma0", "must be three finite rates", sigma);
            return Err(e.in_row(row).into());
        }
        let omega = [omega0[3 * row], omega0[3 * row + 1], omega0[3 * row + 2]];
        let q = [
            q0[4 * row],
            q0[4 * row + 1],
            q0[4 * row + 2],
            q0[4 * row + 3],
        ];
        let q = crate::kinematics::normalized(q).map_err(|e| e.in_row(row))?;
        x0s.push(DampedBody::state_from(omega, sigma, q));
        systems.push(sys);
    }
    Ok((systems, x0s))
}

/// Damped bodies run side by side on all cores ([`DamperRows`]); every run shares the frame
/// grid and step (see [`ModelRows::method_and_grid`]).
#[pyfunction]
#[pyo3(signature = (inertia, sphere, damping, omega0, sigma0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, flips = false, threads = None))]
#[allow(clippy::too_many_arguments)]
fn simulate_dampers<'py>(
    py: Python<'py>,
    inertia: PyReadonlyArray2<'py, f64>,
    sphere: PyReadonlyArray1<'py, f64>,
    damping: PyReadonlyArray1<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    sigma0: PyReadonlyArray2<'py, f64>,
    q0: PyReadonlyArray2<'py, f64>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    flips: bool,
    threads: Option<usize>,
) -> PyResult<Vec<PyModelResult>> {
    let (systems, x0s) = damper_systems((&inertia, &sphere, &damping, &omega0, &sigma0, &q0))?;
    let run = ModelRows {
        t_end,
        frames,
        dt,
        method,
        max_steps,
        rtol,
        atol,
        flips,
        threads,
    };
    run.simulate(py, &systems, &x0s, true)
}

/// The fixed step that `simulate_dampers` of the same arguments takes (shared by every
/// row); `None` for an adaptive method, whose runs choose their own.
#[pyfunction]
#[pyo3(signature = (inertia, sphere, damping, omega0, sigma0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL))]
#[allow(clippy::too_many_arguments)]
fn damper_step<'py>(
    inertia: PyReadonlyArray2<'py, f64>,
    sphere: PyReadonlyArray1<'py, f64>,
    damping: PyReadonlyArray1<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    sigma0: PyReadonlyArray2<'py, f64>,
    q0: PyReadonlyArray2<'py, f64>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
) -> PyResult<Option<f64>> {
    let (systems, x0s) = damper_systems((&inertia, &sphere, &damping, &omega0, &sigma0, &q0))?;
    let run = ModelRows {
        t_end,
        frames,
        dt,
        method,
        max_steps,
        rtol,
        atol,
        flips: false,
        threads: None,
    };
    let (method, grid) = run.method_and_grid(&systems, &x0s)?;
    Ok((!method.is_adaptive()).then(|| grid.step_size()))
}

fn internal(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(format!("internal error in the dzhanibekov core: {e}"))
}

#[pyfunction]
#[pyo3(signature = (q, points, out = None))]
fn rotate<'py>(
    py: Python<'py>,
    q: PyReadonlyArray2<'py, f64>,
    points: PyReadonlyArray2<'py, f64>,
    out: Option<PyReadwriteArray3<'py, f64>>,
) -> PyResult<Option<Bound<'py, PyArray3<f64>>>> {
    let (n, p) = (q.shape()[0], points.shape()[0]);
    let q = q
        .as_slice()
        .map_err(|_| PyValueError::new_err("`q` must be C-contiguous"))?;
    let points = points
        .as_slice()
        .map_err(|_| PyValueError::new_err("`points` must be C-contiguous"))?;
    let long = n.saturating_mul(p) > watchdog::LONG_ROTATION;
    match out {
        Some(mut out) => {
            if out.shape() != [n, p, 3] {
                return Err(PyValueError::new_err(format!(
                    "`out` must have shape ({n}, {p}, 3), got {:?}",
                    out.shape()
                )));
            }
            let dst = out
                .as_slice_mut()
                .map_err(|_| PyValueError::new_err("`out` must be C-contiguous"))?;
            detach(py, long, |cancel| {
                rotate_points_until(q, points, dst, cancel)
            })?;
            Ok(None)
        }
        None => {
            // NumPy allocates the output (its allocator asks for huge pages, so fresh memory
            // faults in far fewer, larger pieces); the core fills it without the GIL. Through
            // `numpy.empty`, whose failure is a MemoryError, not a null pointer.
            let array = py
                .import("numpy")?
                .call_method1("empty", ((n, p, 3),))?
                .cast_into::<PyArray3<f64>>()?;
            // SAFETY: the array is new, C-contiguous and not yet shared with Python code.
            let dst = unsafe { array.as_slice_mut() }.map_err(internal)?;
            detach(py, long, |cancel| {
                rotate_points_until(q, points, dst, cancel)
            })?;
            Ok(Some(array))
        }
    }
}

/// Energy, body and world angular momentum and `|q|` at each row of `omega` and `q`.
#[pyfunction]
fn invariants<'py>(
    py: Python<'py>,
    body: &PyRigidBody,
    omega: PyReadonlyArray2<'py, f64>,
    q: PyReadonlyArray2<'py, f64>,
) -> PyResult<PyInvariants> {
    let n = omega.shape()[0];
    let omega = omega
        .as_slice()
        .map_err(|_| PyValueError::new_err("`omega` must be C-contiguous"))?;
    let q = q
        .as_slice()
        .map_err(|_| PyValueError::new_err("`q` must be C-contiguous"))?;
    if omega.len() != 3 * n || q.len() != 4 * n {
        return Err(PyValueError::new_err(
            "`omega` must have shape (N, 3) and `q` shape (N, 4) with the same N",
        ));
    }
    let inertia = body.inner.inertia_body();
    let (energy, l_body, l_world, q_norm) = detach(py, n > watchdog::LONG_INVARIANTS, |_| {
        const HINT: &str = "compute them over fewer frames at a time";
        let (mut energy, mut l_body, mut l_world, mut q_norm) = (
            try_with_capacity(n, "the energies", HINT)?,
            try_with_capacity(3 * n, "the angular momenta", HINT)?,
            try_with_capacity(3 * n, "the angular momenta in space", HINT)?,
            try_with_capacity(n, "the quaternion norms", HINT)?,
        );
        for (w, c) in omega.chunks_exact(3).zip(q.chunks_exact(4)) {
            let x = state_from([w[0], w[1], w[2]], [c[0], c[1], c[2], c[3]]);
            let inv = Invariants::of(&inertia, &x);
            energy.push(inv.energy);
            l_body.extend_from_slice(inv.l_body.as_slice());
            l_world.extend_from_slice(inv.l_world.as_slice());
            q_norm.push(inv.q_norm);
        }
        Ok((energy, l_body, l_world, q_norm))
    })?;
    let shaped = |v: Vec<f64>| Array2::from_shape_vec((n, 3), v).map_err(internal);
    Ok(PyInvariants {
        energy: PyArray1::from_vec(py, energy).unbind(),
        momentum_body: shaped(l_body)?.into_pyarray(py).unbind(),
        momentum_world: shaped(l_world)?.into_pyarray(py).unbind(),
        q_norm: PyArray1::from_vec(py, q_norm).unbind(),
    })
}

/// The invariants at each of N states: energy `(N,)`, angular momentum in body axes and in
/// space `(N, 3)`, `|q|` `(N,)`.
#[pyclass(name = "Invariants", module = "dzhanibekov._core", frozen, get_all)]
struct PyInvariants {
    energy: Py<PyArray1<f64>>,
    momentum_body: Py<PyArray2<f64>>,
    momentum_world: Py<PyArray2<f64>>,
    q_norm: Py<PyArray1<f64>>,
}

/// A mesh as NumPy arrays: vertices `(V, 3)` and cells `(C, 4)`.
type PyMesh<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>);

/// The ellipsoid with the given semi-axes as a closed quad mesh.
#[pyfunction]
fn ellipsoid_mesh<'py>(
    py: Python<'py>,
    semi_axes: [f64; 3],
    n_around: usize,
    n_along: usize,
) -> PyResult<PyMesh<'py>> {
    let long = n_around.saturating_mul(n_along) > watchdog::LONG_MESH;
    let mesh = detach(py, long, |_| ellipsoid(semi_axes, n_around, n_along))?;
    let (v, c) = (mesh.n_vertices(), mesh.n_cells());
    let vertices = Array2::from_shape_vec((v, 3), mesh.vertices).map_err(internal)?;
    let quads = Array2::from_shape_vec((c, 4), mesh.quads).map_err(internal)?;
    Ok((vertices.into_pyarray(py), quads.into_pyarray(py)))
}

/// The flip period `2K(m)/λ` (infinite when the motion never flips).
#[pyfunction]
fn flip_period(body: &PyRigidBody, omega0: [f64; 3]) -> PyResult<f64> {
    Ok(exact::flip_period(&body.inner, omega0)?)
}

type Triple<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// `(sn, cn, dn)` of parameter `m` (given with its complement `m1 = 1 − m`) at each `u`.
#[pyfunction]
fn ellipj<'py>(
    py: Python<'py>,
    u: PyReadonlyArray1<'py, f64>,
    m: f64,
    m1: f64,
) -> PyResult<Triple<'py>> {
    check_parameter(m, m1)?;
    let jacobi = Jacobi::new(m, m1);
    let u = u.as_array().to_vec();
    let (sn, cn, dn) = detach(py, false, |_| {
        let (mut sn, mut cn, mut dn) = (
            Vec::with_capacity(u.len()),
            Vec::with_capacity(u.len()),
            Vec::with_capacity(u.len()),
        );
        for &x in &u {
            let (s, c, d) = jacobi.sn_cn_dn(x);
            sn.push(s);
            cn.push(c);
            dn.push(d);
        }
        Ok((sn, cn, dn))
    })?;
    Ok((
        PyArray1::from_vec(py, sn),
        PyArray1::from_vec(py, cn),
        PyArray1::from_vec(py, dn),
    ))
}

/// `K(m)` from the AGM of `1` and `√m1` (infinite for `m1 = 0`).
#[pyfunction]
fn ellipk(m: f64, m1: f64) -> PyResult<f64> {
    check_parameter(m, m1)?;
    Ok(Jacobi::new(m, m1).quarter_period())
}

fn check_parameter(m: f64, m1: f64) -> PyResult<()> {
    if !((0.0..=1.0).contains(&m) && (0.0..=1.0).contains(&m1)) {
        return Err(PyValueError::new_err(format!(
            "`m` and `m1` must lie in [0, 1], got m = {m}, m1 = {m1}"
        )));
    }
    Ok(())
}

/// A C-contiguous array's values, or a `ValueError` naming it.
fn values<'a>(name: &str, array: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [f64]> {
    array
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("`{name}` must be C-contiguous")))
}

/// The starts of a batch from rows of moments, rates and attitudes (one row of moments or
/// attitudes is shared by all).
fn starts(
    inertia: &PyReadonlyArray2<'_, f64>,
    omega0: &PyReadonlyArray2<'_, f64>,
    q0: &PyReadonlyArray2<'_, f64>,
) -> PyResult<Vec<Start>> {
    let (inertia, omega0, q0) = (
        values("inertia", inertia)?,
        values("omega0", omega0)?,
        values("q0", q0)?,
    );
    Ok(Start::rows(inertia, omega0, q0)?)
}

fn batch_options(threads: Option<usize>, isa: Option<&str>) -> PyResult<BatchOptions> {
    Ok(BatchOptions {
        threads,
        isa: isa.map(str::parse::<Isa>).transpose()?,
    })
}

/// Per-row values as a NumPy array.
fn column<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyArray1<T>> {
    PyArray1::from_vec(py, v)
}

/// What every run of a batch or sweep reports, one value per run in each column: the
/// invariants' drift `(energy, momentum, momentum_world, q_norm)`, the cost and the step.
#[pyclass(name = "RunColumns", module = "dzhanibekov._core", frozen, get_all)]
struct PyRunColumns {
    drift: [Py<PyArray1<f64>>; 4],
    nfev: Py<PyArray1<i64>>,
    n_steps: Py<PyArray1<i64>>,
    n_rejected: Py<PyArray1<i64>>,
    dt: Py<PyArray1<f64>>,
}

impl PyRunColumns {
    fn new(py: Python<'_>, drift: &[Drift], stats: &[Stats], dt: Vec<f64>) -> Self {
        let of = |f: fn(&Drift) -> f64| column(py, drift.iter().map(f).collect()).unbind();
        let count =
            |f: fn(&Stats) -> u64| column(py, stats.iter().map(|s| f(s) as i64).collect()).unbind();
        Self {
            drift: [
                of(|d| d.energy),
                of(|d| d.momentum),
                of(|d| d.momentum_world),
                of(|d| d.q_norm),
            ],
            nfev: count(|s| s.nfev),
            n_steps: count(|s| s.n_steps),
            n_rejected: count(|s| s.n_rejected),
            dt: column(py, dt).unbind(),
        }
    }
}

/// A batch's output: the frame times, frames `(M, frames, 3|4)` if kept, every row's flip
/// times (row `i`'s are `flip_times[flip_offsets[i]:flip_offsets[i + 1]]`), and per-row
/// columns of drift, cost and step.
#[pyclass(name = "BatchResult", module = "dzhanibekov._core", frozen, get_all)]
struct PyBatchResult {
    t: Py<PyArray1<f64>>,
    omega: Option<Py<PyArray3<f64>>>,
    q: Option<Py<PyArray3<f64>>>,
    flip_offsets: Py<PyArray1<i64>>,
    flip_times: Py<PyArray1<f64>>,
    runs: Py<PyRunColumns>,
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

/// Many runs over one frame grid: rows of `inertia` (or one), `omega0`, `q0` (or one).
#[pyfunction]
#[pyo3(signature = (inertia, omega0, q0, t_end, frames, dt, method, max_steps, keep_frames, keep_flips, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, threads = None, isa = None))]
#[allow(clippy::too_many_arguments)]
fn simulate_batch<'py>(
    py: Python<'py>,
    inertia: PyReadonlyArray2<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    q0: PyReadonlyArray2<'py, f64>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    keep_frames: bool,
    keep_flips: bool,
    rtol: f64,
    atol: f64,
    threads: Option<usize>,
    isa: Option<&str>,
) -> PyResult<PyBatchResult> {
    let (method, grid) = method_and_grid(method, t_end, frames, dt, max_steps, rtol, atol)?;
    let options = batch_options(threads, isa)?;
    let starts = starts(&inertia, &omega0, &q0)?;
    let keep = Keep {
        frames: keep_frames,
        flips: keep_flips,
        tilt: false,
    };
    let long = watchdog::is_long(&method, &grid, starts.len());
    let out = detach(py, long, |cancel| {
        core_simulate_batch(&starts, &grid, method, keep, &options, cancel)
    })?;
    let m = starts.len();
    let (omega, q) = match keep_frames {
        true => (
            Some(Array3::from_shape_vec((m, frames, 3), out.omega).map_err(internal)?),
            Some(Array3::from_shape_vec((m, frames, 4), out.q).map_err(internal)?),
        ),
        false => (None, None),
    };
    let offsets = out.flip_offsets.iter().map(|&o| o as i64).collect();
    let runs = PyRunColumns::new(py, &out.drift, &out.stats, out.dt);
    Ok(PyBatchResult {
        t: frame_times(py, &grid),
        omega: omega.map(|a| a.into_pyarray(py).unbind()),
        q: q.map(|a| a.into_pyarray(py).unbind()),
        flip_offsets: column(py, offsets).unbind(),
        flip_times: column(py, out.flip_times).unbind(),
        runs: Py::new(py, runs)?,
    })
}

/// Many runs summarised, no frames kept (see `crate::ensemble::sweep`).
#[pyfunction]
#[pyo3(signature = (inertia, omega0, q0, t_end, frames, dt, method, max_steps, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL, threads = None, isa = None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    inertia: PyReadonlyArray2<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    q0: PyReadonlyArray2<'py, f64>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    max_steps: u64,
    rtol: f64,
    atol: f64,
    threads: Option<usize>,
    isa: Option<&str>,
) -> PyResult<PySweepResult> {
    let (method, grid) = method_and_grid(method, t_end, frames, dt, max_steps, rtol, atol)?;
    let options = batch_options(threads, isa)?;
    let starts = starts(&inertia, &omega0, &q0)?;
    let long = watchdog::is_long(&method, &grid, starts.len());
    let runs = detach(py, long, |cancel| {
        core_sweep(&starts, &grid, method, &options, cancel)
    })?;
    let of = |f: fn(&RunSummary) -> f64| column(py, runs.iter().map(f).collect()).unbind();
    let drift: Vec<Drift> = runs.iter().map(|r| r.drift).collect();
    let stats: Vec<Stats> = runs.iter().map(|r| r.stats).collect();
    let columns = PyRunColumns::new(py, &drift, &stats, runs.iter().map(|r| r.dt).collect());
    Ok(PySweepResult {
        flips: column(py, runs.iter().map(RunSummary::flip_count).collect()).unbind(),
        status: column(py, runs.iter().map(|r| r.status as u8).collect()).unbind(),
        first_flip: of(|r| r.flips.first),
        period: of(|r| r.flips.mean_period()),
        exact_period: of(|r| r.exact_period),
        tilt: of(|r| r.tilt),
        runs: Py::new(py, columns)?,
    })
}

/// The step shared by a batch's runs and its worst run (see `ensemble::plan`).
#[pyclass(name = "BatchPlan", module = "dzhanibekov._core", frozen, get_all)]
struct PyBatchPlan {
    /// The step every run is given; None for an adaptive method without `dt`.
    dt: Option<f64>,
    /// The run RK4 threatens most (the first of equals), None without runs or shared step.
    worst_row: Option<usize>,
    /// That run's plan.
    worst: Option<PyStepPlan>,
}

/// The step of a batch's runs from rows of `inertia` (or one) and `omega0`, each row checked
/// as its single run would be (see `ensemble::plan::plan_batch`).
#[pyfunction]
#[pyo3(signature = (inertia, omega0, t_end, frames, dt, method, rtol = DEFAULT_RTOL, atol = DEFAULT_ATOL))]
#[allow(clippy::too_many_arguments)]
fn plan_batch<'py>(
    py: Python<'py>,
    inertia: PyReadonlyArray2<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    t_end: f64,
    frames: usize,
    dt: Option<f64>,
    method: &str,
    rtol: f64,
    atol: f64,
) -> PyResult<PyBatchPlan> {
    let method = Method::named(method, rtol, atol, None)?;
    let identity = [1.0, 0.0, 0.0, 0.0];
    let starts = Start::rows(
        values("inertia", &inertia)?,
        values("omega0", &omega0)?,
        &identity,
    )?;
    ensure_room(
        starts.len() as f64 * (std::mem::size_of::<StepPlan>() + 32) as f64,
        "the step plans",
        "plan fewer starts at a time",
    )?;
    let p = py.detach(|| core_plan_batch(&starts, t_end, frames, method, dt, rtol))?;
    Ok(PyBatchPlan {
        dt: p.dt,
        worst_row: p.worst.map(|(row, _)| row),
        worst: p.worst.map(|(_, plan)| plan.into()),
    })
}

/// The SIMD instruction sets this CPU offers for the batch kernel, narrowest first.
#[pyfunction]
fn instruction_sets() -> Vec<&'static str> {
    Isa::available().into_iter().map(Isa::name).collect()
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // NumPy's C API is loaded now, at import, not at a call's first array: loading it runs
    // Python code, where a pending Ctrl-C would surface as a panic.
    PyArray1::<f64>::zeros(py, 0, false);
    m.add_function(wrap_pyfunction!(_finalizing, m)?)?;
    py.import("atexit")?
        .call_method1("register", (m.getattr("_finalizing")?,))?;
    m.add_class::<PyRigidBody>()?;
    m.add_class::<PyMethodInfo>()?;
    m.add_class::<PyRunResult>()?;
    m.add_class::<PyStepPlan>()?;
    m.add_class::<PyBatchPlan>()?;
    m.add_class::<PyInvariants>()?;
    m.add_class::<PyRunColumns>()?;
    m.add_class::<PyBatchResult>()?;
    m.add_class::<PySweepResult>()?;
    m.add_class::<PyModelResult>()?;
    m.add_function(wrap_pyfunction!(method_info, m)?)?;
    let methods: Vec<PyMethodInfo> = METHODS.iter().map(|info| PyMethodInfo { info }).collect();
    m.add("METHODS", PyTuple::new(m.py(), methods)?)?;
    m.add("DEFAULT_METHOD", DEFAULT_METHOD)?;
    m.add("DEFAULT_RTOL", DEFAULT_RTOL)?;
    m.add("DEFAULT_ATOL", DEFAULT_ATOL)?;
    m.add("DEFAULT_MAX_STEPS", DEFAULT_MAX_STEPS)?;
    m.add("MAX_MOMENT_RATIO", crate::body::MAX_MOMENT_RATIO)?;
    m.add("TRIANGLE_SLACK", crate::body::TRIANGLE_SLACK)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_deployment, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_damper, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_deployments, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_dampers, m)?)?;
    m.add_function(wrap_pyfunction!(damper_step, m)?)?;
    m.add_function(wrap_pyfunction!(deployment_step, m)?)?;
    m.add_function(wrap_pyfunction!(rotate, m)?)?;
    m.add_function(wrap_pyfunction!(invariants, m)?)?;
    m.add_function(wrap_pyfunction!(ellipsoid_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(flip_period, m)?)?;
    m.add_function(wrap_pyfunction!(ellipj, m)?)?;
    m.add_function(wrap_pyfunction!(ellipk, m)?)?;
    m.add_function(wrap_pyfunction!(step_plan, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(plan_batch, m)?)?;
    m.add_function(wrap_pyfunction!(check_rtol, m)?)?;
    m.add_function(wrap_pyfunction!(instruction_sets, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // a sweep's `status` codes index this tuple
    m.add(
        "RUN_STATUSES",
        PyTuple::new(m.py(), RunStatus::ALL.map(RunStatus::name))?,
    )?;
    Ok(())
}
