//! The values Python builds and the core checks: bodies, deployments, any part (by its kind
//! and parameters: this file names none), systems, the options of a run, and the registries'
//! entries.

use nalgebra::Matrix3;
use numpy::ndarray::{Ix1, Ix3};
use numpy::{PyArray1, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::body::{Inertia, RigidBody};
use crate::buffer::{try_collect, try_with_capacity};
use crate::dynamics::{
    AnyPart, Conserved, Deployment, Fields, ModelInfo, Param, ParamKind, System, SystemBody, Value,
    MODELS,
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

/// A part of a system of any kind the registry knows, built from its kind and its parameters
/// by name (`fields`, kinds already coerced by the Python layer), validated by the core.
#[pyclass(name = "Part", module = "dzhanibekov._core", frozen)]
pub(crate) struct PyPart {
    pub(crate) inner: AnyPart,
}

/// The value of parameter `param` in `fields`, extracted by its declared kind; `None` if it is
/// left out (or None) and optional.
fn extract(param: &Param, fields: &Bound<'_, PyDict>) -> PyResult<Option<Value>> {
    let name = param.name;
    let Some(value) = fields.get_item(name)?.filter(|v| !v.is_none()) else {
        return match param.optional {
            true => Ok(None),
            false => Err(PyTypeError::new_err(format!("`{name}` must be given"))),
        };
    };
    let wrong = |what: &str| {
        let kind = value
            .get_type()
            .name()
            .map_or("?".into(), |n| n.to_string());
        PyTypeError::new_err(format!("`{name}` must be {what}, got {kind}"))
    };
    Ok(Some(match param.kind {
        ParamKind::Scalar => Value::Number(value.extract().map_err(|_| wrong("a number"))?),
        ParamKind::Vector => Value::Vector(value.extract().map_err(|_| wrong("three numbers"))?),
        ParamKind::Times | ParamKind::Values => {
            let a: PyReadonlyArray1<'_, f64> =
                value.extract().map_err(|_| wrong("a float64 array (K,)"))?;
            Value::Numbers(a.as_array().to_vec())
        }
        ParamKind::Vectors => {
            let a: PyReadonlyArray2<'_, f64> = value
                .extract()
                .map_err(|_| wrong("a float64 array (K, 3)"))?;
            let v = a.as_array();
            if v.shape()[1] != 3 {
                return Err(
                    Error::invalid(name, "must have shape (K, 3)", v.shape().to_vec()).into(),
                );
            }
            let mut rows = try_with_capacity(v.shape()[0], "the knots", "give fewer knots")?;
            rows.extend((0..v.shape()[0]).map(|k| [v[[k, 0]], v[[k, 1]], v[[k, 2]]]));
            Value::Vectors(rows)
        }
        ParamKind::Choice(allowed) => {
            let text: String = value.extract().map_err(|_| wrong("a string"))?;
            if !allowed.contains(&text.as_str()) {
                let names: Vec<String> = allowed.iter().map(|a| format!("'{a}'")).collect();
                return Err(
                    Error::invalid(name, format!("must be {}", names.join(" or ")), text).into(),
                );
            }
            Value::Text(text)
        }
        ParamKind::Function { returns, .. } => {
            if !value.is_callable() {
                return Err(super::callable::not_callable(name, &value));
            }
            Value::Function(super::callable::PyFunction::of(
                value.unbind(),
                name,
                returns,
            ))
        }
    }))
}

#[pymethods]
impl PyPart {
    /// The part of kind `kind` (a registry name) with the parameters `fields`.
    #[new]
    fn new(py: Python<'_>, kind: &str, fields: &Bound<'_, PyDict>) -> PyResult<Self> {
        let Some(info) = MODELS.iter().find(|m| m.name == kind && !m.law) else {
            return Err(AnyPart::build(kind, &Fields::new()).err().map_or_else(
                || PyValueError::new_err(format!("unknown part {kind:?}")),
                PyErr::from,
            ));
        };
        let mut values = Fields::new();
        for param in info.params {
            if let Some(v) = extract(param, fields)? {
                values.set(param.name, v);
            }
        }
        let inner = py.detach(|| AnyPart::build(kind, &values))?;
        Ok(Self { inner })
    }

    /// The registry name of its kind.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.name()
    }

    /// How many numbers of state it has.
    #[getter]
    fn width(&self) -> usize {
        self.inner.width()
    }
}

/// What is simulated: a body (a `RigidBody` or a `Deployment`) with its parts in the user's
/// order, validated.
#[pyclass(name = "System", module = "dzhanibekov._core", frozen)]
pub(crate) struct PySystem {
    pub(crate) inner: System,
}

#[pymethods]
impl PySystem {
    /// `body` with `parts` (internal parts and external torques, in order); `mass` the
    /// body's, which parts whose mass moves in it need.
    #[new]
    #[pyo3(signature = (body, parts = Vec::new(), mass = None))]
    fn new(
        body: &Bound<'_, PyAny>,
        parts: Vec<PyRef<'_, PyPart>>,
        mass: Option<f64>,
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
        let parts = parts.iter().map(|p| p.inner.clone()).collect();
        Ok(Self {
            inner: System::try_new(body, parts)?.with_mass(mass)?,
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

    /// Each part with state of its own: the name results show its state under and how many
    /// numbers of state it has (a wheel has none).
    #[getter]
    fn parts(&self) -> Vec<(String, usize)> {
        self.inner.state_names()
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
            models: info.models(),
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

/// What the core declares of a model (see `crate::dynamics::ModelInfo`), read-only: its
/// name, one line about it, whether it is an inertia law (the free body, a deployment) or a
/// part, its parameters `(name, kind, optional, about, choices)`, its state's fields
/// `(name, width, body_vector, about)`, what a system with it keeps, the invariant it brings,
/// its energy role, whether it is an external torque, whether a system holds at most one,
/// what it asks of a method and the methods that run it.
#[pyclass(name = "ModelInfo", module = "dzhanibekov._core", frozen, get_all)]
pub(crate) struct PyModelInfo {
    name: &'static str,
    about: &'static str,
    law: bool,
    params: Vec<ParamTuple>,
    state: Vec<(&'static str, usize, bool, &'static str)>,
    keeps: Vec<&'static str>,
    defines: Vec<&'static str>,
    energy: &'static str,
    external: bool,
    unique: bool,
    traits: Vec<&'static str>,
    methods: Vec<&'static str>,
}

/// A parameter: name, kind, optional, about, the words of a choice.
type ParamTuple = (
    &'static str,
    &'static str,
    bool,
    &'static str,
    Vec<&'static str>,
);

impl From<&'static ModelInfo> for PyModelInfo {
    fn from(m: &'static ModelInfo) -> Self {
        let params = m
            .params
            .iter()
            .map(|p| {
                let choices = match p.kind {
                    ParamKind::Choice(words) => words.to_vec(),
                    _ => Vec::new(),
                };
                (p.name, p.kind.name(), p.optional, p.about, choices)
            })
            .collect();
        Self {
            name: m.name,
            about: m.about,
            law: m.law,
            params,
            state: m
                .state
                .iter()
                .map(|f| (f.name, f.width, f.body_vector, f.about))
                .collect(),
            keeps: crate::dynamics::Kinds::named(m.name)
                .map_or(Vec::new(), |k| k.conserved().names()),
            defines: m.defines.names(),
            energy: m.energy.name(),
            external: m.external,
            unique: m.unique,
            traits: m.traits.names(),
            methods: (crate::run::METHODS.iter())
                .filter(|method| method.runs(m))
                .map(|method| method.name)
                .collect(),
        }
    }
}

#[pymethods]
impl PyModelInfo {
    /// Pickles by name: the entry is looked up again on load.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (&'static str,))> {
        let lookup = py.import("dzhanibekov._core")?.getattr("model_info")?;
        Ok((lookup, (self.name,)))
    }

    fn __repr__(&self) -> String {
        format!(
            "ModelInfo(name='{}', law={}, params={:?}, state={:?}, keeps={:?}, energy='{}')",
            self.name,
            if self.law { "True" } else { "False" },
            self.params.iter().map(|p| p.0).collect::<Vec<_>>(),
            self.state.iter().map(|f| f.0).collect::<Vec<_>>(),
            self.keeps,
            self.energy,
        )
    }
}

/// The declaration of the model called `name`.
#[pyfunction]
fn model_info(name: &str) -> PyResult<PyModelInfo> {
    match MODELS.iter().find(|m| m.name == name) {
        Some(m) => Ok(PyModelInfo::from(*m)),
        None => Err(AnyPart::build(name, &Fields::new())
            .err()
            .map_or_else(|| PyValueError::new_err(name.to_string()), PyErr::from)),
    }
}

pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRigidBody>()?;
    m.add_class::<PyDeployment>()?;
    m.add_class::<PyPart>()?;
    m.add_class::<PySystem>()?;
    m.add_class::<PyRunOptions>()?;
    m.add_class::<PyMethodInfo>()?;
    m.add_class::<PyModelInfo>()?;
    m.add_function(wrap_pyfunction!(method_info, m)?)?;
    m.add_function(wrap_pyfunction!(model_info, m)?)?;
    let models: Vec<PyModelInfo> = MODELS.iter().map(|m| PyModelInfo::from(*m)).collect();
    m.add("MODELS", PyTuple::new(m.py(), models)?)?;
    Ok(())
}
