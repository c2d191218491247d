//! A Python function as a part's function ([`crate::dynamics::Function`]: a callable torque's
//! `f(t, q, omega)`): called with the GIL taken for each call (from whichever thread the run is
//! on), its result checked.
//!
//! **One run, one failure.** The function object a `System` holds ([`PyFunction`]) is shared by
//! every run of that system, from any Python thread. Each run (each call of the binding) gives
//! its copies of the systems functions of their own ([`PythonCalls::of`]): the first failure of
//! a run (the function's own exception, or a `ValueError` naming the part's function) is kept
//! for that run's caller and nothing is called after it in that run, and Ctrl-C stops that run
//! only. (A flag per function object stopped, and misreported, the runs of other threads.)

use std::any::Any;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyByteArray, PyBytes, PyFloat, PyList, PyString, PyTuple, PyType};

use crate::dynamics::{Arg, Function, System};

/// A Python function giving `returns` numbers, as a system holds it (see the module doc).
pub(crate) struct PyFunction {
    func: Py<PyAny>,
    /// What messages call it: the part's function, by its parameter's name.
    name: &'static str,
    returns: usize,
}

impl PyFunction {
    /// `func`, the parameter `name` of a part, giving `returns` numbers.
    pub(crate) fn of(func: Py<PyAny>, name: &'static str, returns: usize) -> Arc<dyn Function> {
        Arc::new(Self {
            func,
            name,
            returns,
        })
    }
}

/// A run that did not go through [`PythonCalls::of`] calls the function without keeping why
/// it failed (the part's output is then NaN and the run stops as diverged); the binding's runs
/// all go through it.
impl Function for PyFunction {
    fn call(&self, args: &[Arg<'_>], out: &mut [f64]) -> bool {
        if super::shut_out() {
            return false;
        }
        Python::attach(|py| call(&self.func, self.name, self.returns, py, args, out).is_ok())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// One run's view of a Python function: the failure and the stop of that run alone.
struct RunFunction {
    func: Py<PyAny>,
    name: &'static str,
    returns: usize,
    /// Set once the function failed or the run was stopped: nothing is called again.
    failed: AtomicBool,
    /// Why, for the run's caller.
    error: Mutex<Option<PyErr>>,
}

impl Function for RunFunction {
    fn call(&self, args: &[Arg<'_>], out: &mut [f64]) -> bool {
        // after a failure, or from a daemon thread while the interpreter shuts down: stop
        if self.failed.load(Ordering::Relaxed) || super::shut_out() {
            return false;
        }
        Python::attach(
            |py| match call(&self.func, self.name, self.returns, py, args, out) {
                Ok(()) => true,
                Err(e) => {
                    self.failed.store(true, Ordering::SeqCst);
                    if let Ok(mut slot) = self.error.lock() {
                        slot.get_or_insert(e);
                    }
                    false
                }
            },
        )
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
    /// Gives the Python functions among `systems`' parts (a run's own copies of the systems)
    /// a view of their own for this run: one per function object, shared by the rows that
    /// hold it.
    pub(crate) fn of(py: Python<'_>, systems: &mut [System]) -> Self {
        let mut views: HashMap<usize, Arc<RunFunction>> = HashMap::new();
        for system in systems.iter_mut() {
            system.map_functions(&mut |f: &Arc<dyn Function>| {
                let Some(user) = f.as_any().downcast_ref::<PyFunction>() else {
                    return Arc::clone(f);
                };
                let key = Arc::as_ptr(f) as *const () as usize;
                let view = views.entry(key).or_insert_with(|| {
                    Arc::new(RunFunction {
                        func: user.func.clone_ref(py),
                        name: user.name,
                        returns: user.returns,
                        failed: AtomicBool::new(false),
                        error: Mutex::new(None),
                    })
                });
                Arc::clone(view) as Arc<dyn Function>
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
    /// next look at the state (the part's output NaN) or its cancel flag.
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

/// The function as messages name it: a callable torque's is `torque` (the last word of its
/// part's kind is what it gives), else its parameter's name.
fn label(name: &'static str) -> &'static str {
    match name {
        "func" => "torque",
        name => name,
    }
}

/// `func(args…)` into `out`: `returns` finite real numbers, or an error naming the function.
/// Six numbers are two vectors (a controller's law: a torque and a dipole), which the function
/// may give as a pair, or as the torque alone (the dipole then zero). Nothing is formatted
/// unless the call fails: the time in a message costs a float's formatting, which a
/// controller called once a sample paid at every call.
fn call(
    func: &Py<PyAny>,
    name: &'static str,
    returns: usize,
    py: Python<'_>,
    args: &[Arg<'_>],
    out: &mut [f64],
) -> PyResult<()> {
    let at = || match args.first() {
        Some(Arg::Number(t)) => format!(" at t = {t}"),
        _ => String::new(),
    };
    let given = PyTuple::new(
        py,
        args.iter().map(|a| match a {
            Arg::Number(v) => PyFloat::new(py, *v).into_any(),
            Arg::Vector(v) => PyArray1::from_slice(py, v).into_any(),
        }),
    )?;
    let result = func.bind(py).call1(given)?;
    let label = label(name);
    let read = match returns {
        PAIR => torque_and_dipole(py, &result, out),
        _ => reals(py, &result, out),
    };
    read.map_err(|got| {
        let what = match (name, returns) {
            ("func", _) => "three real numbers (body axes, shape (3,))".to_string(),
            (_, PAIR) => "a torque (three real numbers) or a pair (torque, dipole) of three \
                          each"
                .to_string(),
            (_, 1) => "one real number (shape (1,))".to_string(),
            (_, 2) => "two real numbers (shape (2,))".to_string(),
            (_, 3) => "three real numbers (shape (3,))".to_string(),
            (_, n) => format!("{n} real numbers (shape ({n},))"),
        };
        PyValueError::new_err(format!(
            "the `{label}` function must return {what}, got {got}{}",
            at()
        ))
    })?;
    if !out.iter().all(|v| v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "the `{label}` function must return finite numbers, got {out:?}{}",
            at()
        )));
    }
    Ok(())
}

/// The numbers of a function giving two vectors (see [`call`]).
const PAIR: usize = 6;

/// A torque and a dipole from `result` into `out` (see [`call`]): a pair of three numbers
/// each, the torque alone (the dipole zero), or six numbers.
fn torque_and_dipole(
    py: Python<'_>,
    result: &Bound<'_, PyAny>,
    out: &mut [f64],
) -> Result<(), String> {
    let (torque, dipole) = out.split_at_mut(3);
    if let Ok(pair) = result.cast::<PyTuple>() {
        if pair.len() == 2 {
            let item = |k| pair.get_item(k).map_err(|_| "a pair".to_string());
            reals(py, &item(0)?, torque).map_err(|got| format!("a torque {got}"))?;
            return reals(py, &item(1)?, dipole).map_err(|got| format!("a dipole {got}"));
        }
    }
    match reals(py, result, torque) {
        Ok(()) => {
            dipole.fill(0.0);
            Ok(())
        }
        Err(got) => reals(py, result, out).map_err(|_| got),
    }
}

/// The `out.len()` real numbers `result` holds, into `out` — a sequence of them, or an array
/// of that shape of a real dtype, whatever its strides — or, in a few words, what it is
/// instead. Refused however they look like numbers: bytes and strings (a sequence of codes), a
/// masked array (its mask would be ignored), complex numbers (their imaginary part would be
/// dropped), bools.
fn reals(py: Python<'_>, result: &Bound<'_, PyAny>, out: &mut [f64]) -> Result<(), String> {
    static MASKED: PyOnceLock<Py<PyType>> = PyOnceLock::new();
    let n = out.len();
    let name = || {
        result
            .get_type()
            .name()
            .map_or("?".into(), |n| n.to_string())
    };
    let masked = || {
        MASKED
            .import(py, "numpy.ma", "MaskedArray")
            .is_ok_and(|m| result.is_instance(m).unwrap_or(false))
    };
    // the common case: a float64 array of n, any strides
    if let Ok(a) = result.cast::<PyArray1<f64>>() {
        if a.len() == n && !masked() {
            let r = a.readonly();
            let v = r.as_array();
            out.iter_mut().zip(v.iter()).for_each(|(o, v)| *o = *v);
            return Ok(());
        }
    }
    // a tuple or a list of n floats (`return (0.0, 0.0, tau)`): read as they are (NumPy's
    // asarray took about a µs a call); ints, bools and the rest go the long way below
    if let Some(items) = floats(result, n) {
        out.copy_from_slice(&items[..n]);
        return Ok(());
    }
    if result.is_instance_of::<PyBytes>() || result.is_instance_of::<PyByteArray>() {
        return Err(format!("{} (a sequence of byte codes)", name()));
    }
    if result.is_instance_of::<PyString>() {
        return Err("str".into());
    }
    if masked() {
        return Err("a masked array (its mask would be ignored)".into());
    }
    // anything else NumPy takes as an array: a list, a tuple, an array of another dtype
    let array = numpy::get_array_module(py)
        .and_then(|np| np.call_method1("asarray", (result,)))
        .and_then(|a| a.cast_into::<PyUntypedArray>().map_err(PyErr::from))
        .map_err(|_| name())?;
    let dtype = array.dtype();
    match dtype.kind() {
        b'f' | b'i' | b'u' => {}
        b'c' => return Err(format!("complex numbers ({}, dtype {dtype})", name())),
        b'b' => return Err(format!("bools ({})", name())),
        _ => return Err(name()),
    }
    if array.shape() != [n] {
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
    out.iter_mut().zip(v.iter()).for_each(|(o, v)| *o = *v);
    Ok(())
}

/// The `n` (at most 6) numbers of a tuple or a list of `n` Python floats (or float
/// subclasses, NumPy's float64 among them), or `None`.
fn floats(result: &Bound<'_, PyAny>, n: usize) -> Option<[f64; 6]> {
    let read = |items: &mut dyn ExactSizeIterator<Item = Bound<'_, PyAny>>| {
        if items.len() != n || n > 6 {
            return None;
        }
        let mut out = [0.0; 6];
        for (o, item) in out.iter_mut().zip(items) {
            *o = item.cast::<PyFloat>().ok()?.value();
        }
        Some(out)
    };
    if let Ok(t) = result.cast::<PyTuple>() {
        return read(&mut t.iter());
    }
    if let Ok(l) = result.cast::<PyList>() {
        return read(&mut l.iter());
    }
    None
}

/// A `TypeError` for a parameter `name` whose `func` cannot be called.
pub(crate) fn not_callable(name: &str, func: &Bound<'_, PyAny>) -> PyErr {
    let kind = func.get_type().name().map_or("?".into(), |n| n.to_string());
    PyTypeError::new_err(format!("`{name}` must be callable, got {kind}"))
}
