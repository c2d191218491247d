//! NumPy arrays over the core's buffers, without a copy, that fail with `MemoryError` rather
//! than crash when memory runs out.
//!
//! rust-numpy's `into_pyarray` and `PyArray::from_vec` do not check what NumPy's
//! `PyArray_NewFromDescr` returns: when the array object cannot be allocated (under an
//! address-space limit, after a large run) they pass a null pointer on to
//! `PyArray_SetBaseObject`, and the interpreter dies with SIGSEGV. Here each step that can
//! fail is checked and becomes a Python error; the buffer is freed with its owner.

use std::ffi::{c_int, c_void};
use std::ptr;

use numpy::ndarray::Dimension;
use numpy::npyffi::{self, npy_intp, NpyTypes, PyArrayObject, NPY_ARRAY_WRITEABLE, PY_ARRAY_API};
use numpy::{Element, PyArray, PyArrayDescrMethods};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;

/// Owns the buffer of one array made by [`owned`]: its base object, freed with it.
#[pyclass(module = "dzhanibekov._core", frozen)]
struct BufferOwner(#[allow(dead_code)] Box<dyn std::any::Any + Send + Sync>);

/// The array of shape `dims` over `v` (C order, writeable), `v` moved into it, not copied.
///
/// # Errors
/// `MemoryError` when NumPy or Python cannot allocate the array object (`v` is freed then);
/// an internal error when `dims` does not hold `v.len()` values.
pub(super) fn owned<'py, T, D>(
    py: Python<'py>,
    v: Vec<T>,
    dims: D,
) -> PyResult<Bound<'py, PyArray<T, D>>>
where
    T: Element + Send + Sync + 'static,
    D: Dimension,
{
    if dims.size_checked() != Some(v.len()) {
        return Err(super::internal(format!(
            "{} values for an array of shape {:?}",
            v.len(),
            dims.slice()
        )));
    }
    let mut shape: Vec<npy_intp> = dims.slice().iter().map(|&d| d as npy_intp).collect();
    // the heap buffer stays where it is when the Vec moves into its owner
    let data = v.as_ptr() as *mut c_void;
    let owner = Bound::new(py, BufferOwner(Box::new(v)))?;
    let descr = T::get_dtype(py).into_dtype_ptr();
    // SAFETY: the GIL is held; `descr` is a new reference, which NumPy steals (also on
    // failure); `shape` has `ndim` entries; `data` points to `dims.size()` values of `T`
    // owned by `owner`, which becomes the array's base (stolen by SetBaseObject, also on
    // failure) and so lives as long as the array; a null array or a failed SetBaseObject
    // is turned into the Python error NumPy set.
    unsafe {
        let array = PY_ARRAY_API.PyArray_NewFromDescr(
            py,
            npyffi::get_type_object(py, NpyTypes::PyArray_Type),
            descr,
            shape.len() as c_int,
            shape.as_mut_ptr(),
            ptr::null_mut(),
            data,
            NPY_ARRAY_WRITEABLE,
            ptr::null_mut(),
        );
        if array.is_null() {
            return Err(no_memory(py));
        }
        let array = Bound::from_owned_ptr(py, array);
        let base = owner.into_ptr();
        if PY_ARRAY_API.PyArray_SetBaseObject(py, array.as_ptr() as *mut PyArrayObject, base) < 0 {
            return Err(no_memory(py));
        }
        Ok(array.cast_into_unchecked())
    }
}

/// The error Python or NumPy set, or a `MemoryError` if none was.
fn no_memory(py: Python<'_>) -> PyErr {
    PyErr::take(py).unwrap_or_else(|| {
        PyMemoryError::new_err("could not allocate a NumPy array for the result")
    })
}
