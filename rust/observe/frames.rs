//! The frames a run keeps: the body rates, the attitude and the parts' state at each.

use crate::buffer::zeroed;
use crate::dynamics::Model;
use crate::error::Result;

use super::Observer;

/// Stores, at every frame of a run of `sys`, time-major: the body rates `omega` `(frames, 3)`,
/// the attitude `q` `(frames, 4)` and the parts' state `parts` `(frames, k)` (a damper's σ;
/// `k` the model's [`Model::parts_width`], empty for a body without parts).
#[derive(Debug, Clone)]
pub struct Recorder<'a, const N: usize, S> {
    sys: &'a S,
    pub omega: Vec<f64>,
    pub q: Vec<f64>,
    pub parts: Vec<f64>,
}

impl<'a, const N: usize, S: Model<N>> Recorder<'a, N, S> {
    /// A recorder with room for `frames` frames.
    ///
    /// # Errors
    /// [`crate::Error::TooLarge`] if the buffers cannot be allocated.
    pub fn with_frames(sys: &'a S, frames: usize) -> Result<Self> {
        let len = |k: usize| frames.saturating_mul(k);
        Ok(Self {
            sys,
            omega: zeroed(len(3), "the frames")?,
            q: zeroed(len(4), "the frames")?,
            parts: zeroed(len(sys.parts_width()), "the frames")?,
        })
    }

    /// The frames' `(omega, q, parts)`.
    pub fn into_frames(self) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        (self.omega, self.q, self.parts)
    }
}

impl<const N: usize, S: Model<N>> Observer<N> for Recorder<'_, N, S> {
    fn keeps_frames(&self) -> bool {
        true
    }

    #[inline]
    fn frame(&mut self, index: usize, t: f64, x: &[f64; N]) {
        let omega = self.sys.omega_body(t, x);
        self.omega[3 * index..3 * index + 3].copy_from_slice(omega.as_slice());
        self.q[4 * index..4 * index + 4].copy_from_slice(&x[N - 4..]);
        let k = self.sys.parts_width();
        if k > 0 {
            self.parts[k * index..k * (index + 1)].copy_from_slice(&x[3..3 + k]);
        }
    }
}

/// The state at the last frame seen: what a run ends in, kept whether or not its frames are.
#[derive(Debug, Clone)]
pub struct LastFrame<'a, const N: usize, S> {
    sys: &'a S,
    t: f64,
    x: [f64; N],
}

impl<'a, const N: usize, S: Model<N>> LastFrame<'a, N, S> {
    pub fn new(sys: &'a S) -> Self {
        Self {
            sys,
            t: 0.0,
            x: [f64::NAN; N],
        }
    }

    /// The body rates, attitude and parts' state of the last frame.
    pub fn end(&self) -> End {
        End {
            omega: self.sys.omega_body(self.t, &self.x).into(),
            q: [self.x[N - 4], self.x[N - 3], self.x[N - 2], self.x[N - 1]],
            parts: self.x[3..3 + self.sys.parts_width()].to_vec(),
        }
    }
}

impl<const N: usize, S: Model<N>> Observer<N> for LastFrame<'_, N, S> {
    #[inline]
    fn frame(&mut self, _index: usize, t: f64, x: &[f64; N]) {
        self.t = t;
        self.x = *x;
    }
}

/// Where a run ended: the body rates, the attitude and the parts' state at `t_end`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct End {
    pub omega: [f64; 3],
    pub q: [f64; 4],
    pub parts: Vec<f64>,
}
