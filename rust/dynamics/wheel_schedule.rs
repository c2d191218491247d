//! A momentum wheel whose relative momentum follows a schedule (a spin-up or spin-down): a
//! [`super::Wheel`] whose `h(t)` is given at knots, linear between them and held outside
//! (see [`super::Table`]).
//!
//! **Law** (the general model's, one law for every part): with `H` the total angular momentum
//! in body axes,
//!
//! ```text
//! ω  = I⁻¹ (H − Σ h(t) a)
//! H' = H × ω (+ τ_b)         i.e.  I ω' = (I ω + Σ h a) × ω − Σ ḣ a (+ τ_b)
//! ```
//!
//! The motor's torque on the rotor is internal: without an external torque `H` stays fixed
//! in space (`|L|` and `L` in space kept), while the body's kinetic energy `½ ωᵀ I ω` changes
//! by the wheels' work on it, `T' = −Σ ḣ (a · ω)`. The schedule's knots are kinks of the law:
//! every step ends on them ([`super::Model::kinks`]).

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::float::{ldexp, RateScale};

use super::kinds::{Conserved, Traits};
use super::part::{EnergyRole, Fields, ModelInfo, Param, ParamKind, Part};
use super::tabulated::{Outside, Table};
use super::wheel::unit_axis;

/// A wheel of scheduled momentum (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSchedule {
    /// The unit spin axis in body axes.
    axis: Vector3<f64>,
    /// `h(t) a`, body axes, held outside the knots.
    table: Table,
}

impl WheelSchedule {
    /// A wheel spinning about `axis` (body axes, any non-zero length: normalised here) with
    /// relative momentum `values[k]` at `times[k]`.
    ///
    /// # Errors
    /// A bad `axis` (as [`super::Wheel::try_new`]); the table's errors ([`Table::try_new`]),
    /// the values named `values`.
    ///
    /// # Example
    /// ```
    /// use dzhanibekov::dynamics::WheelSchedule;
    /// let w = WheelSchedule::try_new([0.0, 0.0, 2.0], vec![0.0, 10.0], vec![0.0, 1.0]).unwrap();
    /// assert_eq!(w.momentum_at(5.0).z, 0.5);
    /// assert_eq!(w.momentum_at(20.0).z, 1.0);
    /// ```
    pub fn try_new(axis: [f64; 3], times: Vec<f64>, values: Vec<f64>) -> Result<Self> {
        let axis = unit_axis(axis)?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "values",
                "(the wheel's momenta) must be finite",
                format!("values[{k}] = {}", values[k]),
            ));
        }
        let vectors = crate::buffer::try_collect(
            values.iter().map(|&h| (axis * h).into()),
            values.len(),
            "the schedule's momenta",
            "give fewer knots",
        )?;
        Ok(Self {
            axis,
            table: Table::try_new(times, vectors, Outside::Hold, "values")?,
        })
    }

    /// The unit spin axis in body axes.
    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    /// The schedule of `h(t) a` (body axes).
    pub fn table(&self) -> &Table {
        &self.table
    }

    /// `h(t) a` in body axes.
    #[inline]
    pub fn momentum_at(&self, t: f64) -> Vector3<f64> {
        self.table.at(t)
    }
}

impl Part for WheelSchedule {
    const INFO: ModelInfo = ModelInfo {
        name: "wheel_schedule",
        about: "a momentum wheel whose momentum follows a schedule, linear between knots and \
                held outside (I ω' = (I ω + Σ h a) × ω − Σ ḣ a; |L| and L in space kept, the \
                energy changed by the wheel's work; every step ends on a knot)",
        law: false,
        params: &[
            Param::new(
                "axis",
                ParamKind::Vector,
                "the spin axis, body axes (normalised)",
            ),
            Param::new("times", ParamKind::Times, "the schedule's knot times"),
            Param::new(
                "values",
                ParamKind::Values,
                "the rotor's relative momentum at each knot",
            ),
        ],
        state: &[],
        // the wheel's work changes the energy (and, in an orbit, the Jacobi integral)
        keeps: Conserved::MOMENTA,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: false,
        unique: false,
        traits: Traits::STORED_MOMENTUM.union(Traits::KINKS),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Self::try_new(
            fields.vector("axis")?,
            fields.numbers("times")?,
            fields.numbers("values")?,
        )
    }

    #[inline(always)]
    fn momentum(&self, t: f64, _x: &[f64]) -> Vector3<f64> {
        self.table.at(t)
    }

    /// A schedule's `|h a|` is largest at one of its knots (linear between them).
    fn largest_momentum(&self) -> f64 {
        self.table
            .values()
            .iter()
            .fold(0.0, |m: f64, v| m.max(v.norm()))
    }

    fn largest_rate(&self, least: f64) -> Option<(&'static str, f64, f64)> {
        let h = self.largest_momentum();
        Some(("momentum", h, h / least))
    }

    fn kinks(&self) -> Vec<f64> {
        self.table.times().to_vec()
    }

    fn in_axes(&self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) -> Self {
        let turn = |v: Vector3<f64>| Vector3::from(to_axes(v.into()));
        Self {
            axis: turn(self.axis),
            table: self.table.turned(to_axes),
        }
    }

    fn with_moments_scaled(&self, m: i32) -> Result<Self> {
        Ok(Self {
            axis: self.axis,
            table: self
                .table
                .map_values(|v| v.map(|c| ldexp(c, -m)), "values")?,
        })
    }

    /// Times times `2^e`, momenta (a moment times a rate) over it.
    fn in_units(&self, scale: RateScale) -> Result<Self> {
        let to_unit = |v: Vector3<f64>| v.map(|c| scale.rate_to_unit(c));
        Ok(Self {
            axis: self.axis,
            table: self.table.in_units(scale, to_unit, "values")?,
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
    use crate::dynamics::{ConstantInertia, GeneralModel, InertiaLaw, Model};
    use crate::ode::OdeSystem;
    use nalgebra::Matrix3;

    #[test]
    fn the_bodys_energy_changes_by_the_wheels_work_and_the_momentum_only_turns() {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let w = WheelSchedule::try_new([0.0, 1.0, 1.0], vec![0.0, 2.0], vec![0.5, 1.5]).unwrap();
        let m = GeneralModel::<7>::try_new(
            InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap()),
            vec![w.clone().into()],
        )
        .unwrap();
        assert_eq!(m.kinks(), &[0.0, 2.0]);
        let x = m.state_from(0.7, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]);
        assert!((m.omega_body(0.7, &x) - Vector3::new(0.3, -0.7, 1.1)).amax() < 1e-15);
        // T' = −ḣ (a · ω), ḣ = 0.5, by a central difference along the right-hand side
        let h = 1e-6;
        let dx = m.rhs(0.7, &x);
        let e = |s: f64| m.energy(0.7 + s, &std::array::from_fn(|k| x[k] + s * dx[k]));
        let omega = m.omega_body(0.7, &x);
        let expected = -0.5 * w.axis().dot(&omega);
        assert!(((e(h) - e(-h)) / (2.0 * h) - expected).abs() < 1e-8);
        // H' = H × ω: |H| stationary
        assert!(
            m.momentum_rate(0.7, &x)
                .dot(&m.momentum_body(0.7, &x))
                .abs()
                < 1e-14
        );
    }

    #[test]
    fn a_schedule_is_held_outside_and_refuses_bad_input_by_name() {
        let w = WheelSchedule::try_new([1.0, 0.0, 0.0], vec![1.0, 3.0], vec![2.0, -2.0]).unwrap();
        assert_eq!(w.momentum_at(0.0).x, 2.0);
        assert_eq!(w.momentum_at(2.0).x, 0.0);
        assert_eq!(w.momentum_at(9.0).x, -2.0);
        let err = |a: [f64; 3], t: Vec<f64>, v: Vec<f64>| {
            WheelSchedule::try_new(a, t, v).unwrap_err().to_string()
        };
        assert!(err([0.0; 3], vec![0.0, 1.0], vec![0.0; 2]).contains("axis"));
        assert!(err([1.0, 0.0, 0.0], vec![1.0, 0.0], vec![0.0; 2]).contains("times"));
        assert!(err([1.0, 0.0, 0.0], vec![0.0, 1.0], vec![0.0, f64::NAN]).contains("values"));
        assert!(err([1.0, 0.0, 0.0], vec![0.0, 1.0], vec![0.0; 3]).contains("values"));
    }
}
