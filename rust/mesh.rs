//! Meshes of body surfaces, for drawing: the inertia ellipsoid as a closed quad mesh.
//!
//! The ellipsoid `(x/a)² + (y/b)² + (z/c)² = 1` is parametrised as
//!
//! ```text
//! x = a sin θ cos φ,   y = b sin θ sin φ,   z = c cos θ,   φ ∈ [0, 2π),  θ ∈ [0, π]
//! ```
//!
//! The azimuth φ runs over a full turn and the polar angle θ over a half, so the surface is
//! covered once: the seam φ = 2π is the column φ = 0 (not a second copy of it), and each pole
//! is one vertex. The cells touching a pole are quads with two corners on that pole (triangles
//! in effect); every other cell is a proper quad.

use crate::error::{Error, Result};

/// The largest mesh built: far beyond what a drawing needs, and safely within `u32` indices.
const MAX_CELLS: usize = 1 << 24;

/// A quad mesh: vertices and cells as flat, row-major arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadMesh {
    /// `(V, 3)` vertex coordinates, body frame.
    pub vertices: Vec<f64>,
    /// `(C, 4)` vertex indices of each cell, counter-clockwise seen from outside (so the
    /// cross product of the first two edges points outward).
    pub quads: Vec<u32>,
}

impl QuadMesh {
    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len() / 3
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.quads.len() / 4
    }
}

/// The ellipsoid with semi-axes `semi_axes = (a, b, c)` along body x, y, z as a closed,
/// single-cover mesh of `n_around × n_along` quads: `n_around` cells around the z axis (φ
/// over a full turn) and `n_along` from pole to pole (θ over a half turn).
///
/// Vertex 0 is the pole `(0, 0, c)`, the last is `(0, 0, −c)`, and between them come the
/// `n_along − 1` rings of latitude from north to south, `n_around` vertices each, starting at
/// φ = 0: `n_around (n_along − 1) + 2` vertices in all. Cell `(i, j)` (ring band `i`, sector
/// `j`) is row `i · n_around + j` of `quads`.
///
/// # Errors
/// Semi-axes must be positive and finite, `n_around` at least 3, `n_along` at least 2, and
/// the mesh at most 2²⁴ cells.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// let mesh = dzhanibekov::mesh::ellipsoid([3.0, 2.0, 1.0], 8, 4).unwrap();
/// assert_eq!((mesh.n_vertices(), mesh.n_cells()), (8 * 3 + 2, 32));
/// for p in mesh.vertices.chunks_exact(3) {
///     let r = (p[0] / 3.0).powi(2) + (p[1] / 2.0).powi(2) + (p[2] / 1.0).powi(2);
///     assert_relative_eq!(r, 1.0, epsilon = 1e-15);
/// }
/// ```
pub fn ellipsoid(semi_axes: [f64; 3], n_around: usize, n_along: usize) -> Result<QuadMesh> {
    if semi_axes.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(Error::invalid(
            "semi_axes",
            "must be three positive, finite lengths",
            semi_axes,
        ));
    }
    if n_around < 3 {
        return Err(Error::invalid("n_around", "must be at least 3", n_around));
    }
    if n_along < 2 {
        return Err(Error::invalid("n_along", "must be at least 2", n_along));
    }
    let cells = n_around
        .checked_mul(n_along)
        .filter(|&c| c <= MAX_CELLS)
        .ok_or_else(|| Error::TooLarge {
            what: "the ellipsoid mesh".into(),
            needed: format!("n_around × n_along = {n_around} × {n_along} cells"),
            limit: format!("the limit of {MAX_CELLS} cells"),
            hint: "ask for fewer cells",
        })?;
    let [a, b, c] = semi_axes;
    let n_vertices = n_around * (n_along - 1) + 2;
    const HINT: &str = "ask for fewer cells";
    let mut vertices =
        crate::buffer::try_with_capacity(3 * n_vertices, "the mesh's vertices", HINT)?;
    vertices.extend_from_slice(&[0.0, 0.0, c]);
    for i in 1..n_along {
        let theta = std::f64::consts::PI * i as f64 / n_along as f64;
        let (sin_t, cos_t) = theta.sin_cos();
        for j in 0..n_around {
            let phi = std::f64::consts::TAU * j as f64 / n_around as f64;
            let (sin_p, cos_p) = phi.sin_cos();
            vertices.extend_from_slice(&[a * sin_t * cos_p, b * sin_t * sin_p, c * cos_t]);
        }
    }
    vertices.extend_from_slice(&[0.0, 0.0, -c]);

    let south = (n_vertices - 1) as u32;
    // Vertex (ring i, sector j); ring 0 is the north pole and ring n_along the south pole.
    let at = |i: usize, j: usize| -> u32 {
        match i {
            0 => 0,
            i if i == n_along => south,
            i => (1 + (i - 1) * n_around + j % n_around) as u32,
        }
    };
    let mut quads = crate::buffer::try_with_capacity(4 * cells, "the mesh's cells", HINT)?;
    for i in 0..n_along {
        for j in 0..n_around {
            // Down the meridian first, then east: e_θ × e_φ points outward.
            quads.extend_from_slice(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Ok(QuadMesh { vertices, quads })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn rejects_bad_sizes() {
        assert!(ellipsoid([1.0, 0.0, 1.0], 8, 4).is_err());
        assert!(ellipsoid([1.0, f64::NAN, 1.0], 8, 4).is_err());
        assert!(ellipsoid([1.0; 3], 2, 4).is_err());
        assert!(ellipsoid([1.0; 3], 3, 1).is_err());
        assert!(ellipsoid([1.0; 3], usize::MAX, 2).is_err());
        assert!(ellipsoid([1.0; 3], 3, 2).is_ok());
    }

    #[test]
    fn every_edge_joins_two_cells_in_opposite_directions() {
        for (n, m) in [(3, 2), (4, 3), (24, 12), (7, 5)] {
            let mesh = ellipsoid([3.0, 2.0, 1.0], n, m).unwrap();
            let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
            for q in mesh.quads.chunks_exact(4) {
                for k in 0..4 {
                    let (p, r) = (q[k], q[(k + 1) % 4]);
                    if p != r {
                        *directed.entry((p, r)).or_default() += 1;
                    }
                }
            }
            // each directed edge once, and its reverse once: a closed, oriented 2-manifold
            for (&(p, r), &count) in &directed {
                assert_eq!(count, 1, "edge {p}->{r} of {n}x{m}");
                assert_eq!(directed.get(&(r, p)), Some(&1), "edge {r}->{p} of {n}x{m}");
            }
            let (v, e, f) = (mesh.n_vertices(), directed.len() / 2, mesh.n_cells());
            assert_eq!(
                v as i64 - e as i64 + f as i64,
                2,
                "Euler characteristic of {n}x{m}"
            );
        }
    }
}
