//! The rigid body: its principal moments of inertia.

use nalgebra::Vector3;

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
        let i = self.inertia_body;
        let between = |m: f64, a: f64, b: f64| (a < m && m < b) || (b < m && m < a);
        (0..3).find(|&k| between(i[k], i[(k + 1) % 3], i[(k + 2) % 3]))
    }
}
