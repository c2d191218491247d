//! A Python function as a torque ([`crate::dynamics::TorqueFunction`]): called with the GIL
//! taken for each evaluation (from whichever thread the run is on), its result checked.
//!
//! **One run, one failure.** The function object a `System` holds ([`PyTorqueFunction`]) is
//! shared by every run of that system, from any Python thread. Each run (each call of the
//! binding) gives its copies of the systems functions of their own ([`PythonCalls::of`]): the
//! first failure of a run (the function's own exception, or a `ValueError` naming `torque`)
//! is kept for that run's caller and nothing is called after it in that run, and Ctrl-C stops
//! that run only. (A flag per function object stopped, and misreported, the runs of other
//! threads.)

use std::any::Any;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyByteArray, PyBytes, PyString, PyType};

use crate::dynamics::{CallableTorque, System, Torque, TorqueFunction};

/// A Python function `func(t, q, omega) -> (3,)`, as a system holds it (see the module doc).
pub(crate) struct PyTorqueFunction {
    func: Py<PyAny>,
}

impl PyTorqueFunction {
    /// The torque of `func`.
    pub(crate) fn torque(func: Py<PyAny>) -> Torque {
        Torque::Callable(CallableTorque::new(Arc::new(Self { func })))
    }
}

/// A run that did not go through [`PythonCalls::of`] calls the function without keeping why
/// it failed (the torque is then NaN and the run stops as diverged); the binding's runs all
/// go through it.
impl TorqueFunction for PyTorqueFunction {
    fn torque(&self, t: f64, q: [f64; 4], omega: [f64; 3]) -> Option<[f64; 3]> {
        if super::shut_out() {
            return None;
        }
        Python::attach(|py| call(&self.func, py, t, q, omega).ok())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// One run's view of a Python function: the failure and the stop of that run alone.
struct RunFunction {
    func: Py<PyAny>,
    /// Set once the function failed or the run was stopped: nothing is called again.
    failed: AtomicBool,
    /// Why, for the run's caller.
    error: Mutex<Option<PyErr>>,
}

impl TorqueFunction for RunFunction {
    fn torque(&self, t: f64, q: [f64; 4], omega: [f64; 3]) -> Option<[f64; 3]> {
        // after a failure, or from a daemon thread while the interpreter shuts down: stop
        if self.failed.load(Ordering::Relaxed) || super::shut_out() {
            return None;
        }
        Python::attach(|py| match call(&self.func, py, t, q, omega) {
            Ok(tau) => Some(tau),
            Err(e) => {
                self.failed.store(true, Ordering::SeqCst);
                if let Ok(mut slot) = self.error.lock() {
                    slot.get_or_insert(e);
                }
                None
            }
        })
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The Python functions of one run, each its own (see the module doc).
pub(crate) struct PythonCalls {
    functions: Vec<Arc<RunFunction>>,
}

impl PythonCalls {
    /// Gives the Python functions among `systems`' torques (a run's own copies of the
    /// systems) a view of their own for this run: one per function object, shared by the
    /// rows that hold it.
    pub(crate) fn of(py: Python<'_>, systems: &mut [System]) -> Self {
        let mut views: HashMap<usize, Arc<RunFunction>> = HashMap::new();
        for system in systems.iter_mut() {
            system.map_functions(|f| {
                let Some(user) = f.as_any().downcast_ref::<PyTorqueFunction>() else {
                    return Arc::clone(f);
                };
                let key = Arc::as_ptr(f) as *const () as usize;
                let view = views.entry(key).or_insert_with(|| {
                    Arc::new(RunFunction {
                        func: user.func.clone_ref(py),
                        failed: AtomicBool::new(false),
                        error: Mutex::new(None),
                    })
                });
                Arc::clone(view) as Arc<dyn TorqueFunction>
            });
        }
        Self {
            functions: views.into_values().collect(),
        }
    }

    /// Whether the run calls Python functions.
    pub(crate) fn any(&self) -> bool {
        !self.functions.is_empty()
    }

    /// Stops this run's calls (Ctrl-C): no more calls, no error kept; the run stops at its
    /// next look at the state (the torque NaN) or its cancel flag.
    pub(crate) fn stop(&self) {
        for f in &self.functions {
            f.failed.store(true, Ordering::SeqCst);
        }
    }

    /// Why a Python function stopped this run, if one did.
    pub(crate) fn failure(&self) -> Option<PyErr> {
        self.functions
            .iter()
            .find_map(|f| f.error.lock().ok().and_then(|mut slot| slot.take()))
    }
}

/// `func(t, q, omega)` as a torque: three finite real numbers, or an error naming `torque`.
fn call(
    func: &Py<PyAny>,
    py: Python<'_>,
    t: f64,
    q: [f64; 4],
    omega: [f64; 3],
) -> PyResult<[f64; 3]> {
    let q = PyArray1::from_slice(py, &q);
    let omega = PyArray1::from_slice(py, &omega);
    let out = func.bind(py).call1((t, q, omega))?;
    let tau = three_reals(py, &out).map_err(|got| {
        PyValueError::new_err(format!(
            "the `torque` function must return three real numbers (body axes, shape (3,)), \
             got {got} at t = {t}"
        ))
    })?;
    if !tau.iter().all(|v| v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "the `torque` function must return finite numbers, got {tau:?} at t = {t}"
        )));
    }
    Ok(tau)
}

/// The three real numbers `out` holds — a sequence of them, or an array of shape (3,) of a
/// real dtype, whatever its strides — or, in a few words, what it is instead. Refused however
/// they look like numbers: bytes and strings (a sequence of codes), a masked array (its mask
/// would be ignored), complex numbers (their imaginary part would be dropped), bools.
fn three_reals(py: Python<'_>, out: &Bound<'_, PyAny>) -> Result<[f64; 3], String> {
    static MASKED: PyOnceLock<Py<PyType>> = PyOnceLock::new();
    let name = || out.get_type().name().map_or("?".into(), |n| n.to_string());
    let masked = || {
        MASKED
            .import(py, "numpy.ma", "MaskedArray")
            .is_ok_and(|m| out.is_instance(m).unwrap_or(false))
    };
    // the common case: a float64 array of three, any strides
    if let Ok(a) = out.cast::<PyArray1<f64>>() {
        if a.len() == 3 && !masked() {
            let r = a.readonly();
            let v = r.as_array();
            return Ok([v[0], v[1], v[2]]);
        }
    }
    if out.is_instance_of::<PyBytes>() || out.is_instance_of::<PyByteArray>() {
        return Err(format!("{} (a sequence of byte codes)", name()));
    }
    if out.is_instance_of::<PyString>() {
        return Err("str".into());
    }
    if masked() {
        return Err("a masked array (its mask would be ignored)".into());
    }
    // anything else NumPy takes as an array: a list, a tuple, an array of another dtype
    let array = numpy::get_array_module(py)
        .and_then(|np| np.call_method1("asarray", (out,)))
        .and_then(|a| a.cast_into::<PyUntypedArray>().map_err(PyErr::from))
        .map_err(|_| name())?;
    let dtype = array.dtype();
    match dtype.kind() {
        b'f' | b'i' | b'u' => {}
        b'c' => return Err(format!("complex numbers ({}, dtype {dtype})", name())),
        b'b' => return Err(format!("bools ({})", name())),
        _ => return Err(name()),
    }
    if array.shape() != [3] {
        let dims: Vec<String> = array.shape().iter().map(usize::to_string).collect();
        let shape = match dims.len() {
            1 => format!("({},)", dims[0]),
            _ => format!("({})", dims.join(", ")),
        };
        return Err(format!("{} of shape {shape}", name()));
    }
    let floats = array
        .call_method1("astype", ("float64",))
        .and_then(|a| a.cast_into::<PyArray1<f64>>().map_err(PyErr::from))
        .map_err(|_| name())?;
    let r = floats.readonly();
    let v = r.as_array();
    Ok([v[0], v[1], v[2]])
}

/// A `TypeError` for a `func` that cannot be called.
pub(crate) fn not_callable(func: &Bound<'_, PyAny>) -> PyErr {
    let kind = func.get_type().name().map_or("?".into(), |n| n.to_string());
    PyTypeError::new_err(format!("`func` must be callable, got {kind}"))
}
