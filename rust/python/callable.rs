//! A Python function as a torque ([`crate::dynamics::TorqueFunction`]): called with the GIL
//! taken for each evaluation (from whichever thread the run is on), its result checked; the
//! first failure kept (the function's own exception, or a `ValueError`/`TypeError` naming
//! `torque`) for the run's caller, and nothing called after it.

use std::any::Any;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::dynamics::{CallableTorque, System, Torque, TorqueFunction};

/// A Python function `func(t, q, omega) -> (3,)` (see the module doc).
pub(crate) struct PyTorqueFunction {
    func: Py<PyAny>,
    /// Set once the function failed: the run stops, nothing is called again.
    failed: AtomicBool,
    /// Why, for the run's caller.
    error: Mutex<Option<PyErr>>,
}

impl PyTorqueFunction {
    /// The torque of `func`.
    pub(crate) fn torque(func: Py<PyAny>) -> Torque {
        let f = Self {
            func,
            failed: AtomicBool::new(false),
            error: Mutex::new(None),
        };
        Torque::Callable(CallableTorque::new(Arc::new(f)))
    }

    fn call(&self, py: Python<'_>, t: f64, q: [f64; 4], omega: [f64; 3]) -> PyResult<[f64; 3]> {
        let q = PyArray1::from_slice(py, &q);
        let omega = PyArray1::from_slice(py, &omega);
        let out = self.func.bind(py).call1((t, q, omega))?;
        let tau: [f64; 3] = match out.cast::<PyArray1<f64>>() {
            Ok(a) if a.len() == 3 => {
                let r = a.readonly();
                let s = r.as_slice()?;
                [s[0], s[1], s[2]]
            }
            _ => out.extract().map_err(|_| {
                let shape = out
                    .getattr("shape")
                    .map(|s| format!("shape {s}"))
                    .unwrap_or_else(|_| {
                        let kind = out.get_type().name().map_or("?".into(), |n| n.to_string());
                        // a sequence says how many numbers it held
                        match out.len() {
                            Ok(n) => format!("a {kind} of {n}"),
                            Err(_) => kind,
                        }
                    });
                PyValueError::new_err(format!(
                    "the `torque` function must return three numbers (body axes, shape (3,)), \
                     got {shape} at t = {t}"
                ))
            })?,
        };
        if !tau.iter().all(|v| v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "the `torque` function must return finite numbers, got {tau:?} at t = {t}"
            )));
        }
        Ok(tau)
    }

    fn keep(&self, e: PyErr) {
        self.failed.store(true, Ordering::SeqCst);
        if let Ok(mut slot) = self.error.lock() {
            slot.get_or_insert(e);
        }
    }

    /// Ready for a new run: no failure kept.
    fn reset(&self) {
        if let Ok(mut slot) = self.error.lock() {
            *slot = None;
        }
        self.failed.store(false, Ordering::SeqCst);
    }

    fn take(&self) -> Option<PyErr> {
        self.error.lock().ok().and_then(|mut slot| slot.take())
    }
}

impl TorqueFunction for PyTorqueFunction {
    fn torque(&self, t: f64, q: [f64; 4], omega: [f64; 3]) -> Option<[f64; 3]> {
        // after a failure, or from a daemon thread while the interpreter shuts down: stop
        if self.failed.load(Ordering::Relaxed) || super::shut_out() {
            return None;
        }
        Python::attach(|py| match self.call(py, t, q, omega) {
            Ok(tau) => Some(tau),
            Err(e) => {
                self.keep(e);
                None
            }
        })
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The Python functions among `systems`' torques.
fn functions(systems: &[System]) -> impl Iterator<Item = &PyTorqueFunction> {
    systems
        .iter()
        .flat_map(|s| s.torques())
        .filter_map(|t| match t {
            Torque::Callable(c) => c.function().as_any().downcast_ref::<PyTorqueFunction>(),
            _ => None,
        })
}

/// Whether a run of `systems` calls Python functions.
pub(crate) fn calls_python(systems: &[System]) -> bool {
    functions(systems).next().is_some()
}

/// Stops the Python functions of `systems` (Ctrl-C): no more calls, no error kept; the run
/// stops at its next look at the state (the torque NaN) or its cancel flag.
pub(crate) fn stop(systems: &[System]) {
    functions(systems).for_each(|f| f.failed.store(true, Ordering::SeqCst));
}

/// Readies the Python functions of `systems` for a run.
pub(crate) fn reset(systems: &[System]) {
    functions(systems).for_each(PyTorqueFunction::reset);
}

/// Why a Python function of `systems` stopped their run, if one did.
pub(crate) fn failure(systems: &[System]) -> Option<PyErr> {
    functions(systems).find_map(PyTorqueFunction::take)
}

/// A `TypeError` for a `func` that cannot be called.
pub(crate) fn not_callable(func: &Bound<'_, PyAny>) -> PyErr {
    let kind = func.get_type().name().map_or("?".into(), |n| n.to_string());
    PyTypeError::new_err(format!("`func` must be callable, got {kind}"))
}
