//! A Python function as a part's function ([`crate::dynamics::Function`]: a callable torque's
//! `f(t, q, omega)`): called with the GIL taken for each call (from whichever thread the run is
//! on), its result checked; the first failure kept (the function's own exception, or a
//! `ValueError`/`TypeError` naming the part's function) for the run's caller, and nothing
//! called after it.

use std::any::Any;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::dynamics::{Arg, Function, System};

/// A Python function giving `returns` numbers (see the module doc).
pub(crate) struct PyFunction {
    func: Py<PyAny>,
    /// What messages call it: the part's function, by its parameter's name.
    name: &'static str,
    returns: usize,
    /// Set once the function failed: the run stops, nothing is called again.
    failed: AtomicBool,
    /// Why, for the run's caller.
    error: Mutex<Option<PyErr>>,
}

impl PyFunction {
    /// `func`, the parameter `name` of a part, giving `returns` numbers.
    pub(crate) fn of(func: Py<PyAny>, name: &'static str, returns: usize) -> Arc<dyn Function> {
        Arc::new(Self {
            func,
            name,
            returns,
            failed: AtomicBool::new(false),
            error: Mutex::new(None),
        })
    }

    fn call(&self, py: Python<'_>, args: &[Arg<'_>], out: &mut [f64]) -> PyResult<()> {
        let args: Vec<Bound<'_, PyAny>> = args
            .iter()
            .map(|a| match a {
                Arg::Number(v) => pyo3::types::PyFloat::new(py, *v).into_any(),
                Arg::Vector(v) => PyArray1::from_slice(py, v).into_any(),
            })
            .collect();
        let at = match args.first().and_then(|a| a.extract::<f64>().ok()) {
            Some(t) => format!(" at t = {t}"),
            None => String::new(),
        };
        let args = pyo3::types::PyTuple::new(py, args)?;
        let result = self.func.bind(py).call1(args)?;
        let n = self.returns;
        let count = match n {
            1 => "one number".to_string(),
            2 => "two numbers".to_string(),
            3 => "three numbers".to_string(),
            n => format!("{n} numbers"),
        };
        let label = self.label();
        let wrong = || {
            let shape = result
                .getattr("shape")
                .map(|s| format!("shape {s}"))
                .unwrap_or_else(|_| {
                    let kind = result
                        .get_type()
                        .name()
                        .map_or("?".into(), |n| n.to_string());
                    // a sequence says how many numbers it held
                    match result.len() {
                        Ok(n) => format!("a {kind} of {n}"),
                        Err(_) => kind,
                    }
                });
            PyValueError::new_err(format!(
                "the `{label}` function must return {count} (shape ({n},)), got {shape}{at}"
            ))
        };
        let values: Vec<f64> = match result.cast::<PyArray1<f64>>() {
            Ok(a) if a.len() == n => a.readonly().as_slice()?.to_vec(),
            _ => result.extract().map_err(|_| wrong())?,
        };
        if values.len() != n {
            return Err(wrong());
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "the `{label}` function must return finite numbers, got {values:?}{at}"
            )));
        }
        out.copy_from_slice(&values);
        Ok(())
    }

    /// The function as messages name it: a callable torque's is `torque` (the last word of
    /// its part's kind is what it gives), else its parameter's name.
    fn label(&self) -> &'static str {
        match self.name {
            "func" => "torque",
            name => name,
        }
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

impl Function for PyFunction {
    fn call(&self, args: &[Arg<'_>], out: &mut [f64]) -> bool {
        // after a failure, or from a daemon thread while the interpreter shuts down: stop
        if self.failed.load(Ordering::Relaxed) || super::shut_out() {
            return false;
        }
        Python::attach(|py| match PyFunction::call(self, py, args, out) {
            Ok(()) => true,
            Err(e) => {
                self.keep(e);
                false
            }
        })
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The Python functions among `systems`' parts.
fn functions(systems: &[System]) -> impl Iterator<Item = &PyFunction> {
    systems
        .iter()
        .flat_map(System::functions)
        .filter_map(|f| f.as_any().downcast_ref::<PyFunction>())
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
    functions(systems).for_each(PyFunction::reset);
}

/// Why a Python function of `systems` stopped their run, if one did.
pub(crate) fn failure(systems: &[System]) -> Option<PyErr> {
    functions(systems).find_map(PyFunction::take)
}

/// A `TypeError` for a parameter `name` whose `func` cannot be called.
pub(crate) fn not_callable(name: &str, func: &Bound<'_, PyAny>) -> PyErr {
    let kind = func.get_type().name().map_or("?".into(), |n| n.to_string());
    PyTypeError::new_err(format!("`{name}` must be callable, got {kind}"))
}
