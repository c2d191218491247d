//! The numerics Python calls directly: rotating points, meshes, the exact flip period and the
//! elliptic functions behind it, the SIMD instruction sets.

use numpy::ndarray::{Ix1, Ix2};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadwriteArray3, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::ensemble::lanes::Isa;
use crate::exact;
use crate::exact::elliptic::Jacobi;
use crate::kinematics::rotate_points_until;
use crate::mesh::ellipsoid;
use crate::run::{watchdog, Edge};

use super::arrays::owned;
use super::values::PyRigidBody;
use super::{detach, internal};
use crate::buffer::{try_collect, try_with_capacity};

/// `M(q_i) · X_j` for every quaternion and point, into `out` if given.
#[pyfunction]
#[pyo3(signature = (q, points, out = None))]
fn rotate<'py>(
    py: Python<'py>,
    q: PyReadonlyArray2<'py, f64>,
    points: PyReadonlyArray2<'py, f64>,
    out: Option<PyReadwriteArray3<'py, f64>>,
) -> PyResult<Option<Bound<'py, PyArray3<f64>>>> {
    let (n, p) = (q.shape()[0], points.shape()[0]);
    let contiguous = |name: &str| PyValueError::new_err(format!("`{name}` must be C-contiguous"));
    let q = q.as_slice().map_err(|_| contiguous("q"))?;
    let points = points.as_slice().map_err(|_| contiguous("points"))?;
    let long = n.saturating_mul(p) > watchdog::LONG_ROTATION;
    match out {
        Some(mut out) => {
            if out.shape() != [n, p, 3] {
                return Err(PyValueError::new_err(format!(
                    "`out` must have shape ({n}, {p}, 3), got {:?}",
                    out.shape()
                )));
            }
            let dst = out.as_slice_mut().map_err(|_| contiguous("out"))?;
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
    Ok((
        owned(py, mesh.vertices, Ix2(v, 3))?,
        owned(py, mesh.quads, Ix2(c, 4))?,
    ))
}

/// The flip period `2K(m)/λ` of `body` spun at `omega0` (its user's axes; infinite when the
/// motion never flips).
#[pyfunction]
fn flip_period(body: &PyRigidBody, omega0: [f64; 3]) -> PyResult<f64> {
    let inertia = &body.inner;
    let omega = Edge::of(inertia).vector_in(omega0);
    Ok(exact::flip_period(inertia.principal(), omega)?)
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
    let n = u.len();
    let u = try_collect(u.as_array().iter().copied(), n, "the arguments", HINT)?;
    const HINT: &str = "evaluate fewer points at a time";
    let (sn, cn, dn) = py.detach(|| -> crate::error::Result<_> {
        let (mut sn, mut cn, mut dn) = (
            try_with_capacity(n, "sn", HINT)?,
            try_with_capacity(n, "cn", HINT)?,
            try_with_capacity(n, "dn", HINT)?,
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
        owned(py, sn, Ix1(n))?,
        owned(py, cn, Ix1(n))?,
        owned(py, dn, Ix1(n))?,
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

/// The SIMD instruction sets this CPU offers for the batch kernel, narrowest first.
#[pyfunction]
fn instruction_sets() -> Vec<&'static str> {
    Isa::available().into_iter().map(Isa::name).collect()
}

pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(rotate, m)?)?;
    m.add_function(wrap_pyfunction!(ellipsoid_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(flip_period, m)?)?;
    m.add_function(wrap_pyfunction!(ellipj, m)?)?;
    m.add_function(wrap_pyfunction!(ellipk, m)?)?;
    m.add_function(wrap_pyfunction!(instruction_sets, m)?)?;
    Ok(())
}
