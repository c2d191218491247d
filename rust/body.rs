//! The rigid body: its principal moments of inertia.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};

/// The largest ratio of largest to smallest principal moment that [`RigidBody::try_new`]
/// accepts.
pub const MAX_MOMENT_RATIO: f64 = 1e150;

/// The relative slack (of the moments' sum) within which a body satisfies the triangle
/// inequality: moments computed from a mass distribution meet it only to round-off.
pub const TRIANGLE_SLACK: f64 = 1e-12;

/// The relative difference `|Ia − Ib| / max(Ia, Ib)` within which two principal moments count
/// as equal: the body is then a symmetric top, with no intermediate axis, no flips and an
/// infinite flip period.
///
/// Why 1e-9: moments computed from a mesh, a composite or a tensor with products of inertia
/// carry round-off of about ε (2.2e-16) times the largest moment per operation, some 1e-13 for
/// a mesh of a million faces, so an axisymmetric part's two equal moments come out 1e-16 to
/// 1e-13 apart, and without a tolerance every mesh of a cylinder would "flip" (its transverse
/// rates turn at the precession rate, and the flip detector would read each half-turn as a
/// flip). Three or more orders above that round-off, 1e-9 is still far below what any
/// measurement or manufacture resolves. Only the verdict changes: the integrators and the
/// exact method still run the moments as given (the closed form of a symmetric top only where
/// two are exactly equal), so the motion is the body's own; its "flips" within the tolerance
/// are the precession of a top symmetric to 1e-9, and are not counted.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// The looser relative difference below which the Python package warns that a body is nearly
/// symmetric (moments closer than this but not within [`SYMMETRY_TOLERANCE`]): its flips are
/// then the slow precession of a nearly symmetric top, and their count depends on digits no
/// measurement fixes.
pub const NEAR_SYMMETRY: f64 = 1e-6;

/// Whether two principal moments are equal within [`SYMMETRY_TOLERANCE`] (relative).
pub fn moments_equal(a: f64, b: f64) -> bool {
    (a - b).abs() <= SYMMETRY_TOLERANCE * a.abs().max(b.abs())
}

/// The smallest relative difference `|Ia − Ib| / max(Ia, Ib)` of two of the moments `i`: 0 for
/// a symmetric top; compared with [`SYMMETRY_TOLERANCE`] and [`NEAR_SYMMETRY`].
pub fn asymmetry(i: &Vector3<f64>) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (i[k], i[(k + 1) % 3]);
            (a - b).abs() / a.abs().max(b.abs())
        })
        .fold(f64::INFINITY, f64::min)
}

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
    /// unstable; `None` when two moments are equal within [`SYMMETRY_TOLERANCE`] (a symmetric
    /// top has no such axis).
    pub fn intermediate_axis(&self) -> Option<usize> {
        intermediate_index(&self.inertia_body)
    }

    /// The smallest relative difference of two moments (see [`asymmetry`]).
    pub fn asymmetry(&self) -> f64 {
        asymmetry(&self.inertia_body)
    }
}

/// The index of the strictly intermediate of three moments; `None` when two are equal within
/// [`SYMMETRY_TOLERANCE`] (relative): a symmetric top.
///
/// # Example
/// ```
/// use dzhanibekov::body::intermediate_index;
/// use nalgebra::Vector3;
/// assert_eq!(intermediate_index(&Vector3::new(1.0, 3.0, 2.0)), Some(2));
/// // a cylinder's two equal moments as a mesh gives them, 1e-15 apart: a symmetric top
/// assert_eq!(intermediate_index(&Vector3::new(35.0, 35.0 * (1.0 + 1e-15), 4.5)), None);
/// ```
pub fn intermediate_index(i: &Vector3<f64>) -> Option<usize> {
    if (0..3).any(|k| moments_equal(i[k], i[(k + 1) % 3])) {
        return None;
    }
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
        let diagonal = (0..3).all(|i| (0..3).all(|j| i == j || tensor[(i, j)] == 0.0));
        if diagonal {
            // the diagonal itself, not scaled there and back (which rounds): any scale float64
            // holds, 1e308 included
            let principal = RigidBody::try_new(tensor.diagonal().into()).map_err(|_| {
                Error::invalid(
                    "tensor",
                    "must be positive definite, with moments whose ratio of largest to smallest \
                     is at most 1e150",
                    tensor.as_slice(),
                )
            })?;
            return Ok(Self {
                tensor,
                principal,
                axes: None,
            });
        }
        // scaled by a power of two (exact) so that neither the mean with the transpose nor the
        // eigensolver overflows or underflows, whatever the tensor's scale
        let exponent = largest.log2().floor() as i32;
        let unit = ldexp(&tensor, -exponent);
        let unit = (unit + unit.transpose()) * 0.5;
        let (moments, axes) = principal_frame(&unit);
        let factored = unit.cholesky().is_some();
        // with products of inertia an eigenvalue is found to about ε × the largest: a smaller
        // one is round-off, whatever its sign (Cholesky may factor such a tensor or not)
        let resolution = 4.0 * f64::EPSILON * moments.max();
        if !(factored && moments.min() > resolution) {
            let least = moments.min();
            let allowed = if least.is_nan() || least < -resolution {
                "must be positive definite".into()
            } else {
                format!(
                    "must be positive definite, but it is singular to round-off: its smallest \
                     eigenvalue ({:.3e}) is within what float64 resolves beside the largest, \
                     about {:.3e} (ε × the largest) for a tensor with products of inertia; give \
                     principal moments (a Body, or a diagonal tensor) to go below",
                    scale(least, exponent),
                    scale(resolution, exponent)
                )
            };
            return Err(Error::invalid("tensor", allowed, tensor.as_slice()));
        }
        let moments = moments.map(|m| scale(m, exponent));
        let principal = RigidBody::try_new(moments.into()).map_err(|_| {
            Error::invalid(
                "tensor",
                "must have principal moments that float64 holds, with a ratio of largest to \
                 smallest of at most 1e150",
                tensor.as_slice(),
            )
        })?;
        Ok(Self {
            tensor: ldexp(&unit, exponent),
            principal,
            axes: Some(axes),
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

/// `x · 2^exponent`, exact unless the result overflows or underflows (two factors, so that any
/// exponent a float64's scale gives, −1074 to 1023, is reached).
fn scale(x: f64, exponent: i32) -> f64 {
    let half = exponent / 2;
    x * 2f64.powi(half) * 2f64.powi(exponent - half)
}

/// [`scale`] of every entry.
fn ldexp(m: &Matrix3<f64>, exponent: i32) -> Matrix3<f64> {
    m.map(|x| scale(x, exponent))
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

#[cfg(test)]
mod edges {
    use super::*;

    fn rotation() -> Matrix3<f64> {
        nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner()
    }

    #[test]
    fn a_diagonal_tensor_is_taken_as_it_is_at_any_scale() {
        for d in [
            [1e308, 1e308, 1e308],
            [3e-300, 2e-300, 1e-300],
            [1.0, 1e-15, 1.0],
        ] {
            let t = Matrix3::from_diagonal(&Vector3::from(d));
            let body = Inertia::try_new(t).unwrap();
            assert_eq!(body.tensor(), &t);
            assert_eq!(body.principal().inertia_body(), Vector3::from(d));
            assert!(body.is_principal());
        }
    }

    #[test]
    fn a_tensor_with_products_of_inertia_near_float64s_limits() {
        let r = rotation();
        for s in [1e300, 1e-300] {
            let t = r * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)) * r.transpose() * s;
            let body = Inertia::try_new(t).unwrap();
            let mut m: Vec<f64> = body.principal().inertia_body().iter().copied().collect();
            m.sort_by(f64::total_cmp);
            for (got, want) in m.iter().zip([1.0, 2.0, 3.0]) {
                assert!((got / s - want).abs() < 1e-13, "{got} at scale {s}");
            }
            assert!(body.tensor().iter().all(|v| v.is_finite()));
        }
    }

    #[test]
    fn moments_equal_to_round_off_make_a_symmetric_top_everywhere() {
        // a cylinder's moments (Iz = m r²/2, Ix = Iy = m (3 r² + h²)/12 for r = 3, h = 20),
        // turned into a tensor with products of inertia: its two equal moments come back from
        // the eigensolver a few ulps apart
        let d = Vector3::new(427.0 / 12.0, 427.0 / 12.0, 4.5);
        let r = rotation();
        let t = r * Matrix3::from_diagonal(&d) * r.transpose();
        let body = Inertia::try_new(t).unwrap();
        let m = body.principal().inertia_body();
        assert!(
            m.x != m.y || m.y != m.z || m.x != m.z,
            "{m}: no round-off to test"
        );
        assert_eq!(body.principal().intermediate_axis(), None);
        assert!(body.principal().asymmetry() <= SYMMETRY_TOLERANCE);
        assert_eq!(
            crate::dynamics::model::mid_axis_of(&t, false),
            crate::dynamics::model::MidAxis::None
        );
        let w = [0.3, 0.01, 1.0];
        let period = crate::exact::flip_period(body.principal(), w).unwrap();
        assert!(period.is_infinite(), "{period}");
        // just beyond the tolerance the body is asymmetric again
        let apart = Vector3::new(1.0, 1.0 + 2.0 * SYMMETRY_TOLERANCE, 0.2);
        assert_eq!(intermediate_index(&apart), Some(0));
        let within = Vector3::new(1.0, 1.0 + 0.5 * SYMMETRY_TOLERANCE, 0.2);
        assert_eq!(intermediate_index(&within), None);
    }

    #[test]
    fn a_singular_tensor_is_refused_naming_the_resolution() {
        let r = rotation();
        let t = r * Matrix3::from_diagonal(&Vector3::new(0.0, 1.0, 2.0)) * r.transpose();
        let text = Inertia::try_new(t).unwrap_err().to_string();
        assert!(text.contains("singular to round-off"), "{text}");
        assert!(text.contains("ε × the largest"), "{text}");
        let t = r * Matrix3::from_diagonal(&Vector3::new(-0.5, 1.0, 2.0)) * r.transpose();
        let text = Inertia::try_new(t).unwrap_err().to_string();
        assert!(text.contains("must be positive definite") && !text.contains("round-off"));
    }
}
