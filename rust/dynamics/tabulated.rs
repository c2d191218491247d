//! Tabulated laws: a vector given at knots, linear between them ([`Table`]); a torque
//! tabulated so ([`TabulatedTorque`]), and the wheels' scheduled momenta (see
//! [`super::WheelSchedule`]).
//!
//! **Interpolation.** Between knots `t_k < t_{k+1}` the value is
//! `v_k + (t − t_k) / (t_{k+1} − t_k) · (v_{k+1} − v_k)`; outside `[t_0, t_K]` it is zero or
//! the nearest end's value ([`Outside`]). The law is continuous with a kink at every knot
//! (held outside), or jumps at the two ends (zero outside, with non-zero end values).
//!
//! **Knots and sides.** Every stepper ends a step on every knot ([`super::Model::kinks`]):
//! a step that straddled one would lose its order there (one step of error `O(h²)` times the
//! kink, `O(h)` times a jump). At a knot the law takes the value from the left (the piece
//! `(t_{k−1}, t_k]`): a step that ends on the knot integrates the piece before it, and the
//! drivers start the next step one float64 after the knot (a shift of one unit in the last
//! place, round-off), so that it integrates the piece after it, jumps included.

use std::str::FromStr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use nalgebra::{Quaternion, Vector3};

use crate::buffer::try_collect;
use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};
use crate::kinematics::rotation_matrix;

use super::deployment::check_knot_times;
use super::kinds::{Conserved, Traits};
use super::part::{Ctx, EnergyRole, Fields, Frame, ModelInfo, Param, ParamKind, Part};
use super::torques::FRAMES;

/// What to ask for when a table's knots do not fit.
const KNOTS_HINT: &str = "give fewer knots";

/// What a table gives outside its knots.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outside {
    /// Zero before the first knot and after the last (a jump there if the ends are not zero).
    Zero,
    /// The first value before the first knot, the last after the last (continuous).
    Hold,
}

impl FromStr for Outside {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "zero" => Ok(Outside::Zero),
            "hold" => Ok(Outside::Hold),
            _ => Err(Error::invalid("outside", "must be 'zero' or 'hold'", s)),
        }
    }
}

/// A vector law given at knots, linear between them (see the module doc).
///
/// Its knots are shared by its clones (a batch copies its system for each row, a run its
/// model): a table of 10⁷ knots is 320 MB, held once; the laws made from it in a run's axes
/// and units hold new values (and times) of their own, allocated fallibly.
#[derive(Debug)]
pub struct Table {
    times: Arc<Vec<f64>>,
    values: Arc<Vec<Vector3<f64>>>,
    outside: Outside,
    /// The piece `k` (`t_{k−1} < t ≤ t_k`) the last evaluation found: a run's evaluations
    /// come in order, so the next one is mostly in it (a hint only: it changes no result).
    hint: AtomicUsize,
}

impl Clone for Table {
    fn clone(&self) -> Self {
        Self {
            times: Arc::clone(&self.times),
            values: Arc::clone(&self.values),
            outside: self.outside,
            hint: AtomicUsize::new(self.hint.load(Ordering::Relaxed)),
        }
    }
}

/// The same law (the hint aside).
impl PartialEq for Table {
    fn eq(&self, other: &Self) -> bool {
        self.times == other.times && self.values == other.values && self.outside == other.outside
    }
}

/// # Construction
impl Table {
    /// The law through `values[k]` at `times[k]`, `values` named `name` in errors.
    ///
    /// # Errors
    /// Fewer than two knots; not as many values as times; times not finite and strictly
    /// increasing; values not finite.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::{Outside, Table};
    /// let t = Table::try_new(vec![0.0, 2.0], vec![[0.0, 0.0, 0.0], [2.0, 0.0, 4.0]],
    ///                        Outside::Hold, "vectors").unwrap();
    /// assert_eq!(t.at(1.0).z, 2.0);
    /// assert_eq!(t.at(5.0).x, 2.0);
    /// assert!(Table::try_new(vec![1.0, 0.0], vec![[0.0; 3]; 2], Outside::Zero, "vectors").is_err());
    /// ```
    pub fn try_new(
        times: Vec<f64>,
        values: Vec<[f64; 3]>,
        outside: Outside,
        name: &'static str,
    ) -> Result<Self> {
        if times.len() < 2 {
            return Err(Error::invalid(
                "times",
                "must hold at least two knots",
                times.len(),
            ));
        }
        if times.len() != values.len() {
            return Err(Error::invalid(
                name,
                "must give one value per time (as many rows as `times`)",
                (times.len(), values.len()),
            ));
        }
        check_knot_times(&times)?;
        if let Some(k) = values.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(Error::invalid(
                name,
                "must be finite",
                format!("{name}[{k}] = {:?}", values[k]),
            ));
        }
        Ok(Self {
            times: Arc::new(times),
            // in place: `[f64; 3]` and `Vector3<f64>` have one layout
            values: Arc::new(values.into_iter().map(Vector3::from).collect()),
            outside,
            hint: AtomicUsize::new(1),
        })
    }

    /// The knots' times.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The values at the knots.
    pub fn values(&self) -> &[Vector3<f64>] {
        &self.values
    }

    pub fn outside(&self) -> Outside {
        self.outside
    }

    /// The same law with every value mapped by `f` (a change of axes, of units); the times
    /// shared.
    ///
    /// # Errors
    /// A value that leaves float64 (or a non-zero one that underflows to zero), named
    /// `name`; values that cannot be allocated.
    pub fn map_values(
        &self,
        f: impl Fn(Vector3<f64>) -> Vector3<f64>,
        name: &'static str,
    ) -> Result<Self> {
        let k = self.values.len();
        let mut values = crate::buffer::try_with_capacity(k, "a table's values", KNOTS_HINT)?;
        for v in self.values.iter() {
            let out = f(*v);
            if !(out.iter().all(|c| c.is_finite()) && ((v.amax() == 0.0) == (out.amax() == 0.0))) {
                return Err(Error::invalid(
                    name,
                    "must stay within float64 in the run's units (moments and rates scaled)",
                    v.as_slice(),
                ));
            }
            values.push(out);
        }
        Ok(Self {
            values: Arc::new(values),
            ..self.clone()
        })
    }

    /// The same law with every value turned by `to_axes` (a change of axes: a rotation keeps
    /// finite values finite, so there is nothing to refuse).
    pub fn turned(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        // a rotation keeps finite values finite: no error to report
        Self {
            values: Arc::new(
                (self.values.iter())
                    .map(|v| Vector3::from(to_axes((*v).into())))
                    .collect(),
            ),
            ..self.clone()
        }
    }

    /// The same law with times in the units of `scale` (times times `2^e`), its values mapped
    /// by `f`.
    ///
    /// # Errors
    /// A time or value that leaves float64.
    pub fn in_units(
        &self,
        scale: RateScale,
        f: impl Fn(Vector3<f64>) -> Vector3<f64>,
        name: &'static str,
    ) -> Result<Self> {
        let unit = self.times.iter().map(|&t| scale.time_to_unit(t));
        let times = try_collect(unit, self.times.len(), "a table's times", KNOTS_HINT)?;
        let ok = times.iter().all(|t| t.is_finite()) && times.windows(2).all(|w| w[0] < w[1]);
        if !ok {
            return Err(Error::invalid(
                "times",
                "must stay within float64 in the run's units (times scaled with the rates)",
                self.times.len(),
            ));
        }
        Ok(Self {
            times: Arc::new(times),
            ..self.map_values(f, name)?
        })
    }
}

/// # Evaluation
impl Table {
    /// The value at `t` (from the left at a knot, see the module doc). Inline but for the
    /// search, which a run's evaluations seldom need: a call in the right-hand side would
    /// make it save and restore the state's registers around it at every evaluation.
    #[inline(always)]
    pub fn at(&self, t: f64) -> Vector3<f64> {
        let (ts, vs) = (&self.times, &self.values);
        let last = ts.len() - 1;
        if t <= ts[0] || t > ts[last] {
            return match (self.outside, t <= ts[0]) {
                (Outside::Zero, _) => Vector3::zeros(),
                (Outside::Hold, true) => vs[0],
                (Outside::Hold, false) => vs[last],
            };
        }
        // ts[k − 1] < t ≤ ts[k]: the hint's piece, else a search
        let h = self.hint.load(Ordering::Relaxed);
        let k = match h >= 1 && h <= last && ts[h - 1] < t && t <= ts[h] {
            true => h,
            false => self.search(t),
        };
        let s = crate::float::fraction(t, ts[k - 1], ts[k]);
        vs[k - 1] + (vs[k] - vs[k - 1]) * s
    }

    /// The piece `k` with `ts[k − 1] < t ≤ ts[k]` of a `t` inside the knots, kept as the hint.
    #[cold]
    #[inline(never)]
    fn search(&self, t: f64) -> usize {
        let (ts, last) = (&self.times, self.times.len() - 1);
        let k = ts.partition_point(|&s| s < t).clamp(1, last);
        self.hint.store(k, Ordering::Relaxed);
        k
    }
}

/// A torque tabulated at knots, linear between them, fixed in body axes or in space.
#[derive(Debug, Clone, PartialEq)]
pub struct TabulatedTorque {
    table: Table,
    frame: Frame,
}

/// What a table gives outside its knots, as parameters name it.
const OUTSIDE: &[&str] = &["zero", "hold"];

impl TabulatedTorque {
    /// The torque `vectors[k]` at `times[k]` (see [`Table::try_new`]), fixed in `frame`,
    /// `outside` the knots zero or held.
    ///
    /// # Errors
    /// Those of [`Table::try_new`].
    pub fn try_new(
        times: Vec<f64>,
        vectors: Vec<[f64; 3]>,
        frame: Frame,
        outside: Outside,
    ) -> Result<Self> {
        Ok(Self {
            table: Table::try_new(times, vectors, outside, "vectors")?,
            frame,
        })
    }

    pub fn table(&self) -> &Table {
        &self.table
    }

    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// The torque in body axes at `t` on a body at attitude `q` (world-from-body): inline,
    /// the table's search aside (see [`Table::at`]).
    #[inline(always)]
    pub fn torque_at(&self, t: f64, q: Quaternion<f64>) -> Vector3<f64> {
        let v = self.table.at(t);
        match self.frame {
            Frame::Body => v,
            Frame::World => rotation_matrix(&q).tr_mul(&v),
        }
    }
}

impl Part for TabulatedTorque {
    const INFO: ModelInfo = ModelInfo {
        name: "tabulated_torque",
        about: "a torque tabulated at knots in body or world axes, linear between them, zero \
                or held outside (nothing kept but |q|; every step ends on a knot)",
        law: false,
        params: &[
            Param::new("times", ParamKind::Times, "knot times"),
            Param::new("vectors", ParamKind::Vectors, "the torque at each knot"),
            Param::new(
                "frame",
                ParamKind::Choice(FRAMES),
                "the axes the vectors are given in: the body's own or space's",
            ),
            Param::new(
                "outside",
                ParamKind::Choice(OUTSIDE),
                "the torque before the first knot and after the last: zero or held",
            ),
        ],
        state: &[],
        keeps: Conserved::Q_NORM,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: true,
        unique: false,
        traits: Traits::EXTERNAL_TORQUE.union(Traits::KINKS),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(
            fields.numbers("times")?,
            fields.vectors("vectors")?,
            fields.choice("frame")?,
            fields.choice("outside")?,
        )
    }

    /// The torque in body axes at `t` on a body at attitude `q` (world-from-body).
    #[inline(always)]
    fn torque(&self, c: &Ctx<'_>, _x: &[f64]) -> Vector3<f64> {
        self.torque_at(c.t, c.q)
    }

    fn kinks(&self) -> Vec<f64> {
        self.table.times().to_vec()
    }

    /// Its vectors mapped by `to_axes` if fixed in body axes.
    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        match self.frame {
            Frame::World => self.clone(),
            Frame::Body => Self {
                table: self.table.turned(to_axes),
                frame: self.frame,
            },
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            table: self
                .table
                .map_values(|v| v.map(|c| ldexp(c, -m)), "vectors")?,
            frame: self.frame,
        })
    }

    /// The knots' times times `2^e`, the torque (a moment times a rate squared) over `2^(2e)`.
    fn in_units(&self, scale: RateScale) -> Result<Self> {
        let f = |v: Vector3<f64>| v.map(|c| scale.rate_to_unit(scale.rate_to_unit(c)));
        Ok(Self {
            table: self.table.in_units(scale, f, "vectors")?,
            frame: self.frame,
        })
    }

    /// The table's values and times in the run's axes and units, and the kinks they add:
    /// 122 bytes a knot measured in a run in its own units (tests/heap_bytes.rs: the general
    /// model keeps the kinks and the knots its steps end on), with the allocator's headers.
    fn model_bytes(&self) -> usize {
        const TABLE_KNOT: usize = 128;
        self.table.times().len().saturating_mul(TABLE_KNOT)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(outside: Outside) -> Table {
        Table::try_new(
            vec![1.0, 2.0, 4.0],
            vec![[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [-1.0, 0.0, 2.0]],
            outside,
            "vectors",
        )
        .unwrap()
    }

    #[test]
    fn a_table_is_linear_between_its_knots_and_zero_or_held_outside() {
        let z = ramp(Outside::Zero);
        assert_eq!(z.at(1.5).x, 2.0);
        assert_eq!(z.at(3.0), Vector3::new(1.0, 0.0, 1.0));
        assert_eq!(z.at(2.0).x, 3.0);
        // from the left at a knot: at the first knot the value before it
        assert_eq!(z.at(1.0), Vector3::zeros());
        assert_eq!(z.at(4.0), Vector3::new(-1.0, 0.0, 2.0));
        assert_eq!(z.at(4.5), Vector3::zeros());
        let h = ramp(Outside::Hold);
        assert_eq!(h.at(0.0).x, 1.0);
        assert_eq!(h.at(1.0).x, 1.0);
        assert_eq!(h.at(9.0), Vector3::new(-1.0, 0.0, 2.0));
    }

    #[test]
    fn bad_tables_are_refused_naming_the_argument() {
        let bad = |t: Vec<f64>, v: Vec<[f64; 3]>| {
            Table::try_new(t, v, Outside::Zero, "vectors")
                .unwrap_err()
                .to_string()
        };
        assert!(bad(vec![0.0], vec![[0.0; 3]]).contains("times"));
        assert!(bad(vec![0.0, 1.0], vec![[0.0; 3]]).contains("vectors"));
        assert!(bad(vec![0.0, 0.0], vec![[0.0; 3]; 2]).contains("times"));
        assert!(bad(vec![0.0, f64::NAN], vec![[0.0; 3]; 2]).contains("times"));
        assert!(bad(vec![0.0, 1.0], vec![[0.0; 3], [f64::NAN, 0.0, 0.0]]).contains("vectors"));
        assert!("both".parse::<Outside>().is_err());
    }
}
