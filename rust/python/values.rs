//! The values Python builds and the core checks: bodies, deployments, dampers, systems, the
//! options of a run, and the registry's entries.

use nalgebra::Matrix3;
use numpy::ndarray::{Ix1, Ix3};
use numpy::{PyArray1, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::body::{Inertia, RigidBody};
use crate::buffer::{try_collect, try_with_capacity};
use crate::dynamics::{
    Conserved, Damper, Deployment, Frame, Outside, Part, System, SystemBody, TabulatedTorque,
    Torque, Wheel, WheelSchedule, MODELS,
};
use crate::error::Error;
use crate::run::options::RunOptions;
use crate::run::registry::MethodInfo;

use super::arrays::owned;

type Rows3 = [[f64; 3]; 3];

fn rows(m: &Matrix3<f64>) -> Rows3 {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// A body's tensor and its principal frame, validated.
#[pyclass(name = "RigidBody", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyRigidBody {
    pub(crate) inner: Inertia,
}

#[pymethods]
impl PyRigidBody {
    /// A body by its principal moments along the user's axes.
    #[new]
    fn new(inertia: [f64; 3]) -> PyResult<Self> {
        Ok(Self {
            inner: Inertia::from_principal(RigidBody::try_new(inertia)?),
        })
    }

    /// A body by its tensor in the user's axes (`L = T ω`).
    #[staticmethod]
    fn from_tensor(tensor: Rows3) -> PyResult<Self> {
        Ok(Self {
            inner: Inertia::try_new(Matrix3::from_fn(|i, j| tensor[i][j]))?,
        })
    }

    /// A solid box of edges `a`, `b`, `c` along x, y, z.
    #[staticmethod]
    #[pyo3(signature = (a, b, c, mass = 1.0))]
    fn from_box(a: f64, b: f64, c: f64, mass: f64) -> PyResult<Self> {
        Ok(Self {
            inner: Inertia::from_principal(RigidBody::from_box(a, b, c, mass)?),
        })
    }

    /// The principal moments, in the order of `principal_axes`' columns.
    #[getter]
    fn inertia(&self) -> (f64, f64, f64) {
        let i = self.inner.principal().inertia_body();
        (i.x, i.y, i.z)
    }

    #[getter]
    fn tensor(&self) -> Rows3 {
        rows(self.inner.tensor())
    }

    /// `R`, user axes from principal axes (its columns the principal axes).
    #[getter]
    fn principal_axes(&self) -> Rows3 {
        rows(&self.inner.axes())
    }

    #[getter]
    fn is_principal(&self) -> bool {
        self.inner.is_principal()
    }

    #[getter]
    fn satisfies_triangle_inequality(&self) -> bool {
        self.inner.principal().satisfies_triangle_inequality()
    }

    #[getter]
    fn intermediate_axis(&self) -> Option<usize> {
        self.inner.principal().intermediate_axis()
    }

    /// The smallest relative difference of two principal moments.
    #[getter]
    fn asymmetry(&self) -> f64 {
        self.inner.principal().asymmetry()
    }

    fn __repr__(&self) -> String {
        let (a, b, c) = self.inertia();
        format!("RigidBody(inertia=({a}, {b}, {c}))")
    }

    /// Pickles by the tensor, which rebuilds the same body.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (Rows3,))> {
        Ok((
            slf.get_type().getattr("from_tensor")?,
            (rows(slf.get().inner.tensor()),),
        ))
    }
}

/// A deployment's schedule `I(t)`, validated.
#[pyclass(name = "Deployment", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyDeployment {
    pub(crate) inner: Deployment,
}

#[pymethods]
impl PyDeployment {
    /// Knots at the increasing `times` (K,), with `tensors` (K, 3, 3).
    #[new]
    fn new(
        py: Python<'_>,
        times: PyReadonlyArray1<'_, f64>,
        tensors: PyReadonlyArray3<'_, f64>,
    ) -> PyResult<Self> {
        let times = times.as_array().to_vec();
        let t = tensors.as_array();
        if t.shape()[1..] != [3, 3] {
            return Err(
                Error::invalid("tensors", "must have shape (K, 3, 3)", t.shape().to_vec()).into(),
            );
        }
        let mut knots = try_with_capacity(t.shape()[0], "the knots", "give fewer knots")?;
        knots.extend((0..t.shape()[0]).map(|k| Matrix3::from_fn(|i, j| t[[k, i, j]])));
        let inner = py.detach(|| Deployment::try_new(times, knots))?;
        Ok(Self { inner })
    }

    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let times = self.inner.times();
        let n = times.len();
        let v = try_collect(times.iter().copied(), n, "the knots", "give fewer knots")?;
        owned(py, v, Ix1(n))
    }

    #[getter]
    fn tensors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let k = self.inner.tensors().len();
        let mut values = try_with_capacity(9 * k, "the knots", "give fewer knots")?;
        for m in self.inner.tensors() {
            values.extend_from_slice(m.transpose().as_slice());
        }
        owned(py, values, Ix3(k, 3, 3))
    }
}

/// A spherical viscous damper, validated.
#[pyclass(name = "Damper", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyDamper {
    inner: Damper,
}

#[pymethods]
impl PyDamper {
    #[new]
    fn new(inertia: f64, damping: f64) -> PyResult<Self> {
        Ok(Self {
            inner: Damper::try_new(inertia, damping)?,
        })
    }

    /// `c (1/j + 1/I_min)` for a body of least moment `least`: the damper's stiffness.
    fn slip_rate(&self, least: f64) -> f64 {
        self.inner.slip_rate(least)
    }
}

/// A momentum wheel of constant or scheduled relative momentum, validated.
#[pyclass(name = "Wheel", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyWheel {
    inner: Part,
}

#[pymethods]
impl PyWheel {
    #[new]
    fn new(axis: [f64; 3], momentum: f64) -> PyResult<Self> {
        Ok(Self {
            inner: Part::Wheel(Wheel::try_new(axis, momentum)?),
        })
    }

    /// A wheel about `axis` whose momentum is `values` (K,) at the increasing `times` (K,),
    /// linear between them and held outside.
    #[staticmethod]
    fn scheduled(
        py: Python<'_>,
        axis: [f64; 3],
        times: PyReadonlyArray1<'_, f64>,
        values: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let (times, values) = (times.as_array().to_vec(), values.as_array().to_vec());
        let wheel = py.detach(|| WheelSchedule::try_new(axis, times, values))?;
        Ok(Self {
            inner: Part::ScheduledWheel(wheel),
        })
    }

    /// The unit spin axis in body axes.
    #[getter]
    fn axis(&self) -> [f64; 3] {
        match &self.inner {
            Part::ScheduledWheel(w) => w.axis().into(),
            Part::Wheel(w) => w.axis().into(),
            Part::Damper { .. } => [f64::NAN; 3],
        }
    }
}

/// An external torque, validated: the gravity gradient of a circular orbit, or a constant
/// torque in body or world axes.
#[pyclass(name = "Torque", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyTorque {
    inner: Torque,
}

#[pymethods]
impl PyTorque {
    /// The gravity gradient of a circular orbit of rate `orbit_rate` in the world x–y plane.
    #[staticmethod]
    fn gravity_gradient(orbit_rate: f64) -> PyResult<Self> {
        Ok(Self {
            inner: Torque::gravity_gradient(orbit_rate)?,
        })
    }

    /// A constant torque `vector` fixed in `frame` ('body' or 'world').
    #[staticmethod]
    fn constant(vector: [f64; 3], frame: &str) -> PyResult<Self> {
        let frame: Frame = frame.parse()?;
        Ok(Self {
            inner: Torque::constant(vector, frame)?,
        })
    }

    /// A torque `vectors` (K, 3) at the increasing `times` (K,), linear between them, fixed
    /// in `frame` ('body' or 'world'), `outside` the knots 'zero' or 'hold'.
    #[staticmethod]
    fn tabulated(
        py: Python<'_>,
        times: PyReadonlyArray1<'_, f64>,
        vectors: PyReadonlyArray2<'_, f64>,
        frame: &str,
        outside: &str,
    ) -> PyResult<Self> {
        let frame: Frame = frame.parse()?;
        let outside: Outside = outside.parse()?;
        let times = times.as_array().to_vec();
        let v = vectors.as_array();
        if v.shape()[1] != 3 {
            return Err(
                Error::invalid("vectors", "must have shape (K, 3)", v.shape().to_vec()).into(),
            );
        }
        let mut rows = try_with_capacity(v.shape()[0], "the knots", "give fewer knots")?;
        rows.extend((0..v.shape()[0]).map(|k| [v[[k, 0]], v[[k, 1]], v[[k, 2]]]));
        let table = py.detach(|| TabulatedTorque::try_new(times, rows, frame, outside))?;
        Ok(Self {
            inner: Torque::Tabulated(std::sync::Arc::new(table)),
        })
    }

    /// The torque `func(t, q, omega)` returns, in body axes, called at each evaluation with
    /// the GIL taken.
    #[staticmethod]
    fn callable(func: Bound<'_, PyAny>) -> PyResult<Self> {
        if !func.is_callable() {
            return Err(super::callable::not_callable(&func));
        }
        Ok(Self {
            inner: super::callable::PyTorqueFunction::torque(func.unbind()),
        })
    }

    /// The registry's model it is.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner
            .kind()
            .names()
            .first()
            .copied()
            .unwrap_or("torque")
    }
}

/// What is simulated: a body (a `RigidBody` or a `Deployment`) with its parts, validated.
#[pyclass(name = "System", module = "dzhanibekov._core", frozen)]
pub(crate) struct PySystem {
    pub(crate) inner: System,
}

#[pymethods]
impl PySystem {
    /// `body` with `dampers`, each with its sphere's start (`None`: co-rotating), `wheels`
    /// and external `torques`.
    #[new]
    #[pyo3(signature = (body, dampers, wheels = Vec::new(), torques = Vec::new()))]
    fn new(
        body: &Bound<'_, PyAny>,
        dampers: Vec<(PyRef<'_, PyDamper>, Option<[f64; 3]>)>,
        wheels: Vec<PyRef<'_, PyWheel>>,
        torques: Vec<PyRef<'_, PyTorque>>,
    ) -> PyResult<Self> {
        let body = match (body.cast::<PyRigidBody>(), body.cast::<PyDeployment>()) {
            (Ok(b), _) => SystemBody::Rigid(b.get().inner),
            (_, Ok(d)) => SystemBody::Deployment(d.get().inner.clone()),
            _ => {
                return Err(Error::invalid(
                    "body",
                    "must be a body or a deployment",
                    body.get_type().name()?.to_string(),
                )
                .into())
            }
        };
        let parts = dampers
            .iter()
            .map(|(d, sigma0)| Part::Damper {
                damper: d.inner,
                sigma0: *sigma0,
            })
            .chain(wheels.iter().map(|w| w.inner.clone()))
            .collect();
        let torques = torques.iter().map(|t| t.inner.clone()).collect();
        Ok(Self {
            inner: System::try_new(body, parts)?.with_torques(torques)?,
        })
    }

    /// The registry's models it is made of.
    #[getter]
    fn kinds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.inner.kinds().names())
    }

    /// What its exact motion keeps, by the names of the drift's fields.
    #[getter]
    fn conserved<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.inner.conserved().names())
    }

    /// Each part with state of its own: its name and how many numbers of state it has (a
    /// wheel has none).
    #[getter]
    fn parts(&self) -> Vec<(&'static str, usize)> {
        self.inner
            .parts()
            .iter()
            .filter(|p| p.width() > 0)
            .map(|p| (p.name(), p.width()))
            .collect()
    }

    /// The body's tensor at `t`, in the user's axes.
    fn tensor_at(&self, t: f64) -> Rows3 {
        rows(&self.inner.tensor_at(t))
    }
}

/// The options of a run, checked once by the core; read-only.
#[pyclass(name = "RunOptions", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyRunOptions {
    pub(crate) inner: RunOptions,
    #[pyo3(get)]
    t_end: f64,
    #[pyo3(get)]
    frames: usize,
    #[pyo3(get)]
    dt: Option<f64>,
    #[pyo3(get)]
    method: &'static str,
    #[pyo3(get)]
    rtol: f64,
    #[pyo3(get)]
    atol: f64,
    #[pyo3(get)]
    max_steps: u64,
    #[pyo3(get)]
    flips: bool,
    #[pyo3(get)]
    threads: Option<usize>,
}

impl From<RunOptions> for PyRunOptions {
    fn from(o: RunOptions) -> Self {
        let (t_end, frames, dt, method) = (o.t_end, o.frames, o.dt, o.method.name());
        let (rtol, atol, max_steps, flips, threads) =
            (o.rtol, o.atol, o.max_steps, o.flips, o.threads);
        Self {
            inner: o,
            t_end,
            frames,
            dt,
            method,
            rtol,
            atol,
            max_steps,
            flips,
            threads,
        }
    }
}

#[pymethods]
impl PyRunOptions {
    #[new]
    #[pyo3(signature = (t_end, frames, dt = None, method = None, rtol = None, atol = None, max_steps = None, flips = true, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        t_end: f64,
        frames: i64,
        dt: Option<f64>,
        method: Option<&str>,
        rtol: Option<f64>,
        atol: Option<f64>,
        max_steps: Option<i64>,
        flips: bool,
        threads: Option<i64>,
    ) -> PyResult<Self> {
        let options = RunOptions::try_new(
            t_end, frames, dt, method, rtol, atol, max_steps, flips, threads,
        )?;
        Ok(options.into())
    }

    /// The same options with the step `dt` (a plan's).
    fn with_dt(&self, dt: Option<f64>) -> PyResult<Self> {
        Ok(self.inner.with_dt(dt)?.into())
    }
}

/// What the core knows about a method (its entry in the registry), read-only: its name (to
/// pass as `method=`), the order of its global error (None: exact), whether it is adaptive,
/// what it keeps to round-off of what the free body keeps, its right-hand-side evaluations per
/// step (0: none), whether a batch runs it in SIMD lanes, the models it runs, a fixed-step
/// method's stability limits on `|h λ|` along the imaginary axis (an undamped wobble) and on
/// `h λ` along the negative real axis (a damper's slip), and one line about it.
#[pyclass(name = "MethodInfo", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyMethodInfo {
    #[pyo3(get)]
    name: &'static str,
    #[pyo3(get)]
    order: Option<u32>,
    #[pyo3(get)]
    adaptive: bool,
    keeps: Vec<&'static str>,
    #[pyo3(get)]
    rhs_per_step: u64,
    #[pyo3(get)]
    batch: bool,
    models: Vec<&'static str>,
    #[pyo3(get)]
    imaginary_limit: Option<f64>,
    #[pyo3(get)]
    real_limit: Option<f64>,
    #[pyo3(get)]
    about: &'static str,
}

impl From<&'static MethodInfo> for PyMethodInfo {
    fn from(info: &'static MethodInfo) -> Self {
        Self {
            name: info.name,
            order: info.order,
            adaptive: info.adaptive(),
            keeps: info.keeps.intersection(Conserved::FREE).names(),
            rhs_per_step: info.rhs_per_step,
            batch: info.batch,
            models: info.models.names(),
            imaginary_limit: info.stability.map(|s| s.imaginary),
            real_limit: info.stability.map(|s| s.real),
            about: info.about,
        }
    }
}

#[pymethods]
impl PyMethodInfo {
    #[getter]
    fn keeps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, &self.keeps)
    }

    #[getter]
    fn models<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, &self.models)
    }

    /// Pickles by name: the entry is looked up again on load.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (&'static str,))> {
        let lookup = py.import("dzhanibekov._core")?.getattr("method_info")?;
        Ok((lookup, (self.name,)))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let tuple = |names: &[&str]| PyTuple::new(py, names)?.repr().map(|r| r.to_string());
        let (name, order) = (
            self.name,
            self.order.map_or("None".into(), |o| o.to_string()),
        );
        let bool = |b: bool| if b { "True" } else { "False" };
        Ok(format!(
            "MethodInfo(name='{name}', order={order}, adaptive={}, keeps={}, rhs_per_step={}, \
             batch={}, models={})",
            bool(self.adaptive),
            tuple(&self.keeps)?,
            self.rhs_per_step,
            bool(self.batch),
            tuple(&self.models)?,
        ))
    }
}

/// The registry entry of the method called `name`.
#[pyfunction]
fn method_info(name: &str) -> PyResult<PyMethodInfo> {
    let method: crate::run::Method = name.parse()?;
    Ok(method.info().into())
}

/// The models the registry knows: `(name, keeps, about)` each.
#[pyfunction]
fn models() -> Vec<(&'static str, Vec<&'static str>, &'static str)> {
    MODELS
        .iter()
        .map(|m| (m.name, m.keeps.names(), m.about))
        .collect()
}

pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRigidBody>()?;
    m.add_class::<PyDeployment>()?;
    m.add_class::<PyDamper>()?;
    m.add_class::<PyWheel>()?;
    m.add_class::<PyTorque>()?;
    m.add_class::<PySystem>()?;
    m.add_class::<PyRunOptions>()?;
    m.add_class::<PyMethodInfo>()?;
    m.add_function(wrap_pyfunction!(method_info, m)?)?;
    m.add_function(wrap_pyfunction!(models, m)?)?;
    Ok(())
}
