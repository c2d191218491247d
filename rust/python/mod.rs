//! The Python bindings, `dzhanibekov._core`: extract, validate, run without the GIL, wrap.
//! No physics here. Inputs arrive coerced to the right kinds by the Python layer; values are
//! checked by the core, whose errors become `ValueError` subclasses. One file per what it
//! binds: the values ([`values`]), the runs and their results ([`runs`]), the numerics
//! ([`numerics`]); this one holds the error mapping, the GIL release and the module.
#![deny(clippy::unwrap_used, clippy::expect_used)]

mod arrays;
mod callable;
mod numerics;
mod runs;
mod values;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::thread::ThreadId;

use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::error::Error;
use crate::run::registry::{
    DEFAULT_ATOL, DEFAULT_MAX_STEPS, DEFAULT_METHOD, DEFAULT_RTOL, METHODS,
};
use crate::run::watchdog;

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
        Error::Diverged { .. } | Error::EnergyGrew { .. } => "DivergedError",
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
    detach_with(py, long, work, || {})
}

/// [`detach`], calling `on_stop` on this thread as soon as a signal stops the work (before
/// the work has seen its cancel flag): what the work calls back into Python can stop at once
/// (see [`callable`]).
fn detach_with<T: Send>(
    py: Python<'_>,
    long: bool,
    work: impl FnOnce(&AtomicBool) -> Result<T, Error> + Send,
    on_stop: impl Fn() + Send + Sync,
) -> PyResult<T> {
    detach_reporting(py, long, work, on_stop, |_| Ok(()))
}

/// [`detach_with`], calling `report` with the GIL at every poll of long work (after the look
/// for signals): a progress bar's update. An exception it raises stops the work like a signal.
fn detach_reporting<T: Send>(
    py: Python<'_>,
    long: bool,
    work: impl FnOnce(&AtomicBool) -> Result<T, Error> + Send,
    on_stop: impl Fn() + Send + Sync,
    mut report: impl FnMut(Python<'_>) -> PyResult<()> + Send,
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
            match Python::attach(|py| py.check_signals().and_then(|()| report(py))) {
                Err(e) => {
                    interrupt = Some(e);
                    on_stop();
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

/// A bug in the core, as Python sees it.
fn internal(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(format!("internal error in the dzhanibekov core: {e}"))
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
    values::register(m)?;
    runs::register(m)?;
    numerics::register(m)?;
    let methods: Vec<values::PyMethodInfo> = METHODS.iter().map(Into::into).collect();
    m.add("METHODS", PyTuple::new(py, methods)?)?;
    m.add("DEFAULT_METHOD", DEFAULT_METHOD)?;
    m.add("DEFAULT_RTOL", DEFAULT_RTOL)?;
    m.add("DEFAULT_ATOL", DEFAULT_ATOL)?;
    m.add("DEFAULT_MAX_STEPS", DEFAULT_MAX_STEPS)?;
    m.add("ENERGY_GROWTH_TOL", crate::run::ENERGY_GROWTH_TOL)?;
    m.add("FLAT_SHARE", crate::observe::FLAT_SHARE)?;
    m.add("MAX_MOMENT_RATIO", crate::body::MAX_MOMENT_RATIO)?;
    m.add("TRIANGLE_SLACK", crate::body::TRIANGLE_SLACK)?;
    m.add("SYMMETRY_TOLERANCE", crate::body::SYMMETRY_TOLERANCE)?;
    m.add("NEAR_SYMMETRY", crate::body::NEAR_SYMMETRY)?;
    m.add("EARTH_MU", crate::dynamics::control::EARTH_MU)?;
    m.add("EARTH_MOMENT", crate::dynamics::control::EARTH_MOMENT)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
