//! Rotation of body points into the world frame without trigonometry.
//!
//! The paper's matrix `M(q)` (`M11 = 1 - 2V² - 2W²`, `M12 = 2UV - 2WQ`, …) is orthogonal only
//! for `|q| = 1`. Dividing the quadratic terms by `|q|²` gives a matrix that is orthogonal for
//! any non-zero `q` and equal to the paper's when `|q| = 1`, so a drifting `|q|` shows as
//! error in the attitude, never as a stretched body.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{Matrix3, Quaternion, Vector3};
use rayon::prelude::*;

use crate::error::{Error, Result};

/// The rotation matrix of a non-zero quaternion, body to world.
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// use nalgebra::{Quaternion, Vector3};
/// // a quarter turn about z, with a non-unit quaternion
/// let q = Quaternion::new(3.0, 0.0, 0.0, 3.0);
/// let m = dzhanibekov::kinematics::rotation_matrix(&q);
/// assert_relative_eq!(m * Vector3::x(), Vector3::y(), epsilon = 1e-15);
/// ```
#[inline]
pub fn rotation_matrix(q: &Quaternion<f64>) -> Matrix3<f64> {
    let (qs, u, v, w) = (q.w, q.i, q.j, q.k);
    let s = 2.0 / (qs * qs + u * u + v * v + w * w);
    let (uu, vv, ww) = (s * u * u, s * v * v, s * w * w);
    let (uv, uw, vw) = (s * u * v, s * u * w, s * v * w);
    let (qu, qv, qw) = (s * qs * u, s * qs * v, s * qs * w);
    Matrix3::new(
        1.0 - vv - ww,
        uv - qw,
        uw + qv,
        uv + qw,
        1.0 - uu - ww,
        vw - qu,
        uw - qv,
        vw + qu,
        1.0 - uu - vv,
    )
}

/// `M(q)ᵀ v`: a vector of world axes in body axes, for a non-zero quaternion (normalised here),
/// without building `M`: with `q = (w, u)`, `M(q)ᵀ v = v + (2 / |q|²) (u × (u × v) − w u × v)`
/// (the rotation by the conjugate, Rodrigues's formula in quaternion form).
///
/// # Example
/// ```
/// use approx::assert_relative_eq;
/// use nalgebra::{Quaternion, Vector3};
/// use dzhanibekov::kinematics::{rotation_matrix, world_to_body};
/// let q = Quaternion::new(0.9, 0.2, -0.3, 0.25) * 1.7;
/// let v = Vector3::new(0.3, -1.0, 2.0);
/// let plain = rotation_matrix(&q).transpose() * v;
/// assert_relative_eq!(world_to_body(&q, &v), plain, epsilon = 1e-15);
/// ```
#[inline(always)]
pub fn world_to_body(q: &Quaternion<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let u = q.imag();
    let uv = u.cross(v);
    let k = 2.0 / q.norm_squared();
    v + (u.cross(&uv) - uv * q.w) * k
}

/// The rotation matrix of a row `(Q, U, V, W)` of any finite, non-zero size: rows whose
/// squared norm would overflow or underflow are scaled by their largest component first.
#[inline]
fn matrix_of_row(c: &[f64]) -> Matrix3<f64> {
    let q = Quaternion::new(c[0], c[1], c[2], c[3]);
    let n2 = q.norm_squared();
    if (1e-300..=1e300).contains(&n2) {
        return rotation_matrix(&q);
    }
    let largest = c.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    rotation_matrix(&(q / largest))
}

/// The largest coordinate [`rotate_points`] takes: a rotated coordinate is a sum of three
/// terms bounded by `√3` times the largest, so no sum overflows.
pub const MAX_COORDINATE: f64 = f64::MAX / 4.0;

/// Work below this many point-frames runs on the calling thread; above, on all cores.
const PARALLEL_THRESHOLD: usize = 1 << 16;
/// Points per task: 2048 points (48 KiB in, 48 KiB out per frame) stay in L2.
const POINT_BLOCK: usize = 2048;
/// Frames per task, so that few points rotated by many frames still spread over the cores.
const FRAME_BLOCK: usize = 4096;

/// Checks a flat `(N, 4)` array of quaternions: finite and non-zero, row by row (of any
/// size: a row is scaled before its norm is taken).
///
/// # Errors
/// Names the first bad row.
pub fn check_quaternions(q: &[f64]) -> Result<()> {
    if !q.len().is_multiple_of(4) {
        return Err(Error::invalid("q", "must have shape (N, 4)", q.len()));
    }
    for (row, c) in q.chunks_exact(4).enumerate() {
        if !(c.iter().all(|x| x.is_finite()) && c.iter().any(|x| *x != 0.0)) {
            return Err(Error::InvalidArgument {
                name: "q",
                allowed: "rows must be finite, non-zero quaternions".into(),
                got: format!("row {row} = {c:?}"),
            });
        }
    }
    Ok(())
}

/// Rotates every point by every quaternion: `out[i, j] = M(q_i) · points[j]`.
///
/// `q` is a flat `(N, 4)` array (scalar first), `points` a flat `(P, 3)` array and `out` a flat
/// `(N, P, 3)` array. Large inputs run on all cores (rayon), in blocks of points that stay in
/// cache while every frame is written.
///
/// # Errors
/// Shapes that do not fit, a quaternion row that is zero or not finite, or a point that is
/// not finite or beyond [`MAX_COORDINATE`].
pub fn rotate_points(q: &[f64], points: &[f64], out: &mut [f64]) -> Result<()> {
    rotate_points_until(q, points, out, &AtomicBool::new(false))
}

/// [`rotate_points`], stopping soon after `cancel` is set (checked once per frame of each
/// block of points, so within microseconds); `out` is then partly written.
///
/// # Errors
/// As [`rotate_points`], and [`Error::Interrupted`] when cancelled.
pub fn rotate_points_until(
    q: &[f64],
    points: &[f64],
    out: &mut [f64],
    cancel: &AtomicBool,
) -> Result<()> {
    check_quaternions(q)?;
    if !points.len().is_multiple_of(3) {
        return Err(Error::invalid(
            "points",
            "must have shape (P, 3)",
            points.len(),
        ));
    }
    if let Some(row) = points
        .chunks_exact(3)
        .position(|p| !p.iter().all(|x| x.abs() <= MAX_COORDINATE))
    {
        return Err(Error::InvalidArgument {
            name: "points",
            allowed: "must be finite, of magnitude at most 4.49e307 (larger coordinates \
                      overflow when rotated)"
                .into(),
            got: format!("row {row} = {:?}", &points[3 * row..3 * row + 3]),
        });
    }
    let (n, p) = (q.len() / 4, points.len() / 3);
    if n.checked_mul(p).and_then(|np| np.checked_mul(3)) != Some(out.len()) {
        return Err(Error::invalid(
            "out",
            "must have shape (N, P, 3)",
            out.len(),
        ));
    }
    if n == 0 || p == 0 {
        return Ok(());
    }
    // Each frame's matrix is made where it is used, from its row of `q`: nothing is
    // allocated beside `out` (a table of N matrices, 72 bytes a frame, aborted the process
    // under an address-space limit that `out` itself fitted).
    let frame_len = p * 3;
    let stopped = || match cancel.load(Ordering::Relaxed) {
        true => Err(Error::Interrupted),
        false => Ok(()),
    };
    if n * p < PARALLEL_THRESHOLD {
        for (row, frame) in q.chunks_exact(4).zip(out.chunks_exact_mut(frame_len)) {
            rotate_block(&matrix_of_row(row), points, frame);
        }
        return stopped();
    }
    // Split the output into tiles of (a block of frames, a block of points): each task reads
    // its block of points once from memory and writes it for every frame of its block (a
    // frame's matrix is made once per block of points: 25 flops against the block's 15 a
    // point). Few points and many frames still make many tasks.
    let blocks = p.div_ceil(POINT_BLOCK);
    let chunks = n.div_ceil(FRAME_BLOCK);
    let out_ptr = SyncPtr(out.as_mut_ptr());
    crate::pool::install(|| {
        (0..blocks * chunks).into_par_iter().for_each(|tile| {
            let (b, c) = (tile / chunks, tile % chunks);
            let start = b * POINT_BLOCK;
            let end = (start + POINT_BLOCK).min(p);
            let src = &points[start * 3..end * 3];
            for i in c * FRAME_BLOCK..((c + 1) * FRAME_BLOCK).min(n) {
                if cancel.load(Ordering::Relaxed) {
                    return;
                }
                let offset = i * frame_len + start * 3;
                // SAFETY: tiles are disjoint ranges of `out`, each written by one task.
                let dst = unsafe {
                    std::slice::from_raw_parts_mut(out_ptr.get().add(offset), (end - start) * 3)
                };
                rotate_block(&matrix_of_row(&q[4 * i..4 * i + 4]), src, dst);
            }
        })
    })?;
    stopped()
}

#[inline]
fn rotate_block(m: &Matrix3<f64>, src: &[f64], dst: &mut [f64]) {
    for (x, y) in src.chunks_exact(3).zip(dst.chunks_exact_mut(3)) {
        y[0] = m.m11 * x[0] + m.m12 * x[1] + m.m13 * x[2];
        y[1] = m.m21 * x[0] + m.m22 * x[1] + m.m23 * x[2];
        y[2] = m.m31 * x[0] + m.m32 * x[1] + m.m33 * x[2];
    }
}

/// A raw pointer that tasks may share because each writes a disjoint range.
#[derive(Clone, Copy)]
struct SyncPtr(*mut f64);
unsafe impl Send for SyncPtr {}
unsafe impl Sync for SyncPtr {}
impl SyncPtr {
    fn get(self) -> *mut f64 {
        self.0
    }
}

/// `q / |q|`.
///
/// # Errors
/// A zero or non-finite quaternion.
pub fn normalized(q: [f64; 4]) -> Result<[f64; 4]> {
    let largest = q.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(largest.is_finite() && largest > 0.0) {
        return Err(Error::invalid(
            "q0",
            "must be a finite, non-zero quaternion (Q, U, V, W)",
            q,
        ));
    }
    // Scale first so that the norm neither overflows nor underflows.
    let s = q.map(|c| c / largest);
    let n = s.iter().map(|c| c * c).sum::<f64>().sqrt();
    Ok(s.map(|c| c / n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn matches_nalgebra_for_unit_and_scaled_quaternions() {
        let uq = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.7)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -1.3);
        let expected = uq.to_rotation_matrix().into_inner();
        for scale in [1.0, 1e-3, 47.0] {
            let q = uq.into_inner() * scale;
            assert_relative_eq!(rotation_matrix(&q), expected, epsilon = 1e-14);
        }
    }

    #[test]
    fn parallel_and_serial_paths_agree_exactly() {
        let q: Vec<f64> = (0..40)
            .flat_map(|i| [1.0, 0.01 * i as f64, -0.2, 0.3])
            .collect();
        let points: Vec<f64> = (0..3 * 5000).map(|k| (k as f64).sin()).collect();
        let mut par = vec![0.0; 40 * 5000 * 3];
        rotate_points(&q, &points, &mut par).unwrap();
        for (i, c) in q.chunks_exact(4).enumerate() {
            let mut serial = vec![0.0; 5000 * 3];
            let m = rotation_matrix(&Quaternion::new(c[0], c[1], c[2], c[3]));
            rotate_block(&m, &points, &mut serial);
            assert_eq!(&par[i * 15000..(i + 1) * 15000], &serial[..]);
        }
    }

    #[test]
    fn quaternions_of_any_finite_size_rotate_alike() {
        let points = [1.0, -2.0, 3.0, 1e300, 0.0, -4e307];
        let mut unit = vec![0.0; 6];
        rotate_points(&[0.5, 0.5, -0.5, 0.5], &points, &mut unit).unwrap();
        for scale in [1e-320, 1e-200, 1e200, 1e307] {
            let mut out = vec![0.0; 6];
            let q = [0.5 * scale, 0.5 * scale, -0.5 * scale, 0.5 * scale];
            rotate_points(&q, &points, &mut out).unwrap();
            for (a, b) in out.iter().zip(&unit) {
                assert!(
                    (a - b).abs() <= 1e-15 * b.abs().max(1.0),
                    "{scale}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn rejects_points_that_would_overflow() {
        let mut out = vec![0.0; 3];
        let q = [0.5, 0.5, -0.5, 0.5];
        assert!(rotate_points(&q, &[f64::MAX, 0.0, 0.0], &mut out).is_err());
        assert!(rotate_points(&q, &[f64::NAN, 0.0, 0.0], &mut out).is_err());
        rotate_points(&q, &[MAX_COORDINATE; 3], &mut out).unwrap();
        assert!(out.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn a_cancelled_rotation_stops() {
        let q = vec![1.0; 4 * 64];
        let points = vec![1.0; 3 * 4096];
        let mut out = vec![f64::NAN; 64 * 4096 * 3];
        let cancel = AtomicBool::new(true);
        let err = rotate_points_until(&q, &points, &mut out, &cancel).unwrap_err();
        assert_eq!(err, Error::Interrupted);
        assert!(
            out.iter().all(|x| x.is_nan()),
            "nothing written after the cancel"
        );
    }

    #[test]
    fn rejects_zero_and_non_finite_quaternions() {
        let mut out = vec![0.0; 3];
        assert!(rotate_points(&[0.0; 4], &[1.0, 2.0, 3.0], &mut out).is_err());
        assert!(rotate_points(&[f64::NAN, 0.0, 0.0, 1.0], &[1.0, 2.0, 3.0], &mut out).is_err());
    }
}
