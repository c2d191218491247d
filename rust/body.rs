//! The rigid body: its principal moments of inertia.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};

/// The largest ratio of largest to smallest principal moment that [`RigidBody::try_new`]
/// accepts.
pub const MAX_MOMENT_RATIO: f64 = 1e150;

/// The relative slack (of the moments' sum) within which a body satisfies the triangle
/// inequality: moments computed from a mass distribution meet it only to round-off.
pub const TRIANGLE_SLACK: f64 = 1e-12;

/// Principal moments of inertia `(Ix, Iy, Iz)` about the body axes x, y, z, in the user's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBody {
    inertia_body: Vector3<f64>,
}

/// # Construction
impl RigidBody {
    /// A body with the given principal moments.
    ///
    /// # Errors
    /// Each moment must be positive and finite, and every ratio of two moments finite and
    /// non-zero (Euler's equations divide one by another).
    ///
    /// # Example
    /// ```
    /// use approx::assert_relative_eq;
    /// let body = dzhanibekov::RigidBody::try_new([52.0833, 27.0833, 41.6666]).unwrap();
    /// assert_relative_eq!(body.inertia_body().y, 27.0833);
    /// assert!(dzhanibekov::RigidBody::try_new([1.0, 0.0, 1.0]).is_err());
    /// ```
    pub fn try_new(inertia: [f64; 3]) -> Result<Self> {
        if inertia.iter().any(|i| !(i.is_finite() && *i > 0.0)) {
            return Err(Error::invalid(
                "inertia",
                "must hold three positive, finite principal moments",
                inertia,
            ));
        }
        let max = inertia.iter().cloned().fold(f64::MIN, f64::max);
        let min = inertia.iter().cloned().fold(f64::MAX, f64::min);
        let ratio = max / min;
        if !ratio.is_finite() || ratio > MAX_MOMENT_RATIO {
            return Err(Error::invalid(
                "inertia",
                "must have a ratio of largest to smallest moment of at most 1e150",
                inertia,
            ));
        }
        Ok(Self {
            inertia_body: Vector3::from(inertia),
        })
    }

    /// A solid box of the given edge lengths along x, y, z: `Ix = m (b² + c²) / 12`, etc.
    ///
    /// # Errors
    /// Edges and mass must be positive and finite, and give moments that float64 holds (the
    /// squares are taken relative to the longest edge, so only moments that are themselves out
    /// of range are refused) within the ratio [`RigidBody::try_new`] allows.
    ///
    /// # Example
    /// ```
    /// use approx::assert_relative_eq;
    /// let body = dzhanibekov::RigidBody::from_box(20.0, 10.0, 15.0, 1.0).unwrap();
    /// assert_relative_eq!(body.inertia_body().x, 325.0 / 12.0);
    /// ```
    pub fn from_box(a: f64, b: f64, c: f64, mass: f64) -> Result<Self> {
        if [a, b, c].iter().any(|e| !(e.is_finite() && *e > 0.0)) {
            return Err(Error::invalid(
                "a, b, c",
                "must be positive and finite",
                [a, b, c],
            ));
        }
        if !(mass.is_finite() && mass > 0.0) {
            return Err(Error::invalid("mass", "must be positive and finite", mass));
        }
        let moments = |a: f64, b: f64, c: f64, k: f64| {
            [
                k * (b * b + c * c),
                k * (a * a + c * c),
                k * (a * a + b * b),
            ]
        };
        let mut inertia = moments(a, b, c, mass / 12.0);
        if !inertia.iter().all(|i| i.is_normal()) {
            // A square overflowed or underflowed: square the edges over the longest instead.
            let s = a.max(b).max(c);
            inertia = moments(a / s, b / s, c / s, mass / 12.0 * s * s);
        }
        Self::try_new(inertia).map_err(|_| {
            Error::invalid(
                "a, b, c",
                "and `mass` must give principal moments m (b² + c²) / 12, … that are positive \
                 and finite in float64, with a ratio of largest to smallest of at most 1e150",
                [a, b, c, mass],
            )
        })
    }
}

/// # Properties
impl RigidBody {
    /// The principal moments `(Ix, Iy, Iz)`.
    pub fn inertia_body(&self) -> Vector3<f64> {
        self.inertia_body
    }

    /// Whether each moment is at most the sum of the other two, as for every real mass
    /// distribution (to a relative tolerance of 1e-12).
    pub fn satisfies_triangle_inequality(&self) -> bool {
        let i = self.inertia_body;
        let slack = TRIANGLE_SLACK * i.sum();
        i.x <= i.y + i.z + slack && i.y <= i.x + i.z + slack && i.z <= i.x + i.y + slack
    }

    /// The axis (0 = x, 1 = y, 2 = z) of the strictly intermediate moment, about which spin is
    /// unstable; `None` when two moments are equal (a symmetric top has no such axis).
    pub fn intermediate_axis(&self) -> Option<usize> {
        intermediate_index(&self.inertia_body)
    }
}

/// The index of the strictly intermediate of three moments; `None` when two are equal.
pub fn intermediate_index(i: &Vector3<f64>) -> Option<usize> {
    let between = |m: f64, a: f64, b: f64| (a < m && m < b) || (b < m && m < a);
    (0..3).find(|&k| between(i[k], i[(k + 1) % 3], i[(k + 2) % 3]))
}

/// A body's inertia tensor in the user's own axes, and its principal frame: the moments
/// and the proper rotation `R` (user axes from principal axes, its columns the principal axes
/// in user coordinates) with `T = R diag(I) Rᵀ`. Runs happen in the principal frame; the
/// change of axes is made once at each edge of a run ([`crate::run`]).
///
/// Which principal axis is called x, y or z: each is matched to the user axis it lies
/// nearest (the permutation with the largest `Σ |R_kk|`), so that a tensor that is diagonal,
/// or nearly so (a mesh's, to round-off), keeps its moments in the user's x, y, z order; where
/// two matchings tie (an axis at 45° between two user axes), the moments are ascending. Each
/// axis then points to the side of its user axis, and `det R = +1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    tensor: Matrix3<f64>,
    principal: RigidBody,
    /// `R`; `None` when the user's axes are principal (a diagonal tensor).
    axes: Option<Matrix3<f64>>,
}

/// How far two matchings' scores may differ and still count as a tie.
const TIE: f64 = 1e-9;

impl Inertia {
    /// The tensor `tensor` (products of inertia with a minus sign off the diagonal, so that
    /// `L = T ω`), symmetric to 1e-10 of its largest entry (the mean of it and its transpose is
    /// used) and positive definite, with principal moments [`RigidBody::try_new`] accepts.
    ///
    /// # Errors
    /// A tensor that is not finite, symmetric or positive definite, or whose moments are out
    /// of range.
    ///
    /// # Example
    /// ```
    /// use approx::assert_relative_eq;
    /// use nalgebra::Matrix3;
    /// let t = Matrix3::new(2.0, -0.5, 0.0, -0.5, 2.0, 0.0, 0.0, 0.0, 3.0);
    /// let body = dzhanibekov::body::Inertia::try_new(t).unwrap();
    /// assert_relative_eq!(body.principal().inertia_body().x, 1.5, epsilon = 1e-14);
    /// assert_relative_eq!(body.axes().determinant(), 1.0, epsilon = 1e-14);
    /// ```
    pub fn try_new(tensor: Matrix3<f64>) -> Result<Self> {
        let largest = tensor.amax();
        if !tensor.iter().all(|v| v.is_finite()) || largest <= 0.0 {
            return Err(Error::invalid(
                "tensor",
                "must be finite and positive definite",
                tensor.as_slice(),
            ));
        }
        if (tensor - tensor.transpose()).amax() > 1e-10 * largest {
            return Err(Error::invalid(
                "tensor",
                "must be symmetric (to 1e-10 of its largest entry)",
                tensor.as_slice(),
            ));
        }
        // the eigen-decomposition of the tensor over its largest entry: no square overflows
        let unit = (tensor + tensor.transpose()) * (0.5 / largest);
        let diagonal = (0..3).all(|i| (0..3).all(|j| i == j || unit[(i, j)] == 0.0));
        let (moments, axes) = match diagonal {
            // the diagonal itself, not scaled there and back (which rounds)
            true => (tensor.diagonal() / largest, None),
            false => {
                let (m, r) = principal_frame(&unit);
                (m, Some(r))
            }
        };
        if moments.min().is_nan() || moments.min() <= 0.0 {
            return Err(Error::invalid(
                "tensor",
                "must be positive definite",
                tensor.as_slice(),
            ));
        }
        let moments = match axes {
            None => tensor.diagonal(),
            Some(_) => moments * largest,
        };
        let principal = RigidBody::try_new(moments.into()).map_err(|_| {
            Error::invalid(
                "tensor",
                "must have principal moments that float64 holds, with a ratio of largest to \
                 smallest of at most 1e150",
                tensor.as_slice(),
            )
        })?;
        Ok(Self {
            tensor: (tensor + tensor.transpose()) * 0.5,
            principal,
            axes,
        })
    }

    /// A body given by its principal moments along the user's axes.
    pub fn from_principal(body: RigidBody) -> Self {
        Self {
            tensor: Matrix3::from_diagonal(&body.inertia_body()),
            principal: body,
            axes: None,
        }
    }

    /// The tensor in the user's axes.
    pub fn tensor(&self) -> &Matrix3<f64> {
        &self.tensor
    }

    /// The principal moments (in the order of [`Inertia::axes`]' columns).
    pub fn principal(&self) -> &RigidBody {
        &self.principal
    }

    /// `R`, user axes from principal axes.
    pub fn axes(&self) -> Matrix3<f64> {
        self.axes.unwrap_or_else(Matrix3::identity)
    }

    /// Whether the user's axes are the principal axes.
    pub fn is_principal(&self) -> bool {
        self.axes.is_none()
    }
}

/// The eigen-decomposition of a symmetric positive definite `m`, ordered and signed as
/// [`Inertia`] says.
fn principal_frame(m: &Matrix3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let eig = m.symmetric_eigen();
    // ascending first, so that a tie keeps the ascending order
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    const PERMUTATIONS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let score = |p: &[usize; 3]| -> f64 {
        (0..3)
            .map(|k| eig.eigenvectors[(k, order[p[k]])].abs())
            .sum()
    };
    let mut best = PERMUTATIONS[0];
    for p in &PERMUTATIONS[1..] {
        if score(p) > score(&best) + TIE {
            best = *p;
        }
    }
    let mut moments = Vector3::zeros();
    let mut axes = Matrix3::zeros();
    for k in 0..3 {
        let j = order[best[k]];
        moments[k] = eig.eigenvalues[j];
        let mut column = eig.eigenvectors.column(j).into_owned();
        if column[k] < 0.0 {
            column = -column;
        }
        axes.set_column(k, &column);
    }
    if axes.determinant() < 0.0 {
        // the axis least aligned with its user axis takes the sign
        let k = (0..3)
            .min_by(|&a, &b| axes[(a, a)].abs().total_cmp(&axes[(b, b)].abs()))
            .unwrap_or(2);
        let flipped = -axes.column(k);
        axes.set_column(k, &flipped);
    }
    (moments, axes)
}
