//! The Earth's magnetic field along a circular orbit, as a tilted dipole (Wertz, *Spacecraft
//! Attitude Determination and Control*, 1978, App. H.2; Markley & Crassidis, *Fundamentals of
//! Spacecraft Attitude Determination and Control*, 2014, §3.3.3).
//!
//! **The dipole.** With `d̂` the unit vector toward the geomagnetic north pole (the dipole's
//! moment points the other way, `m = −|m| d̂`), the field at distance `R` in the direction `r̂`
//! is
//!
//! ```text
//! B = B_eq (d̂ − 3 (d̂ · r̂) r̂),        B_eq = B₀ R_E³ / R³ = (B₀ R_E³) n² / μ
//! ```
//!
//! `B_eq` the field on the magnetic equator at the orbit's radius, pointing north; over a pole
//! the field is `−2 B_eq d̂` (down into the Earth) and `|B| = B_eq √(1 + 3 sin² λ)` at magnetic
//! latitude `λ` (`sin λ = d̂ · r̂`). The orbit's radius comes from its rate by Kepler's third
//! law, `R³ = μ / n²`; only `B₀ R_E³ / μ` enters. The defaults of the Python layer are the
//! IGRF-13 dipole at 2020.0 (`B₀ = √(g₁₀² + g₁₁² + h₁₁²) = 29 805.9 nT` at `R_E = 6371.2 km`,
//! `B₀ R_E³ = 7.708e15 T·m³`, tilted 9.41° from the spin axis; Alken et al., *Earth, Planets and
//! Space* 73:49, 2021) and `μ = 3.986004418e14 m³/s²` (WGS 84).
//!
//! **The geometry**, in the orbit's world frame (see [`super`]): the orbit crosses the Earth's
//! equator northward at `t = 0` (world `+x`), so the Earth's spin axis is
//! `ê = (0, sin i, cos i)` for an orbit of inclination `i`. The dipole's axis is tilted by `θ`
//! from `ê` and turns with the Earth at `ω_E` about it:
//!
//! ```text
//! d̂(t) = cos θ ê + sin θ (cos φ ê₁ + sin φ ê₂),   φ = φ₀ + ω_E t,   ê₁ = x̂,  ê₂ = ê × ê₁
//! ```
//!
//! With `θ = 0` (the default) the dipole lies along the spin axis, the field is the same
//! whether the Earth turns or not, and `i` is the orbit's inclination to the magnetic equator
//! (Avanzini & Giulietti's `ξ_m`): the field repeats every orbit. With a tilt, the field
//! repeats only where the orbit's and the Earth's periods meet; the orbit itself is Keplerian
//! (no nodal regression).

use nalgebra::{Quaternion, Vector3};

use crate::dynamics::gravity::sin_cos;
use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::world_to_body;

/// A tilted dipole along a circular orbit (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DipoleField {
    /// The orbit's rate `n`.
    orbit_rate: f64,
    /// `B_eq`, the field on the magnetic equator at the orbit's radius.
    strength: f64,
    /// The Earth's spin axis `ê` and the equator's axes `ê₁`, `ê₂`, in world axes.
    spin_axis: Vector3<f64>,
    equator: (Vector3<f64>, Vector3<f64>),
    /// `(cos θ, sin θ)` of the dipole's tilt from the spin axis.
    tilt: (f64, f64),
    /// The Earth's rate `ω_E` and the dipole's longitude `φ₀` at `t = 0`.
    earth_rate: f64,
    longitude: f64,
}

/// # Construction
impl DipoleField {
    /// An untilted dipole of strength `moment` (`B₀ R_E³`, field times length cubed) around a
    /// planet of gravitational parameter `mu`, along an orbit of rate `orbit_rate` inclined by
    /// `inclination` (radians, `0..=π`) to the magnetic equator.
    ///
    /// # Errors
    /// `orbit_rate`, `moment` or `mu` not positive and finite; `inclination` outside
    /// `0..=π`; a field at the orbit that float64 does not hold.
    ///
    /// # Example
    /// ```
    /// use approx::assert_relative_eq;
    /// use dzhanibekov::dynamics::control::DipoleField;
    /// // a polar orbit at 500 km in the IGRF-13 dipole
    /// let n = (3.986004418e14_f64 / 6878.137e3_f64.powi(3)).sqrt();
    /// let f = DipoleField::try_new(n, std::f64::consts::FRAC_PI_2, 7.708e15, 3.986004418e14)?;
    /// assert_relative_eq!(f.strength(), 23.69e-6, max_relative = 1e-3);  // tesla
    /// # Ok::<(), dzhanibekov::Error>(())
    /// ```
    pub fn try_new(orbit_rate: f64, inclination: f64, moment: f64, mu: f64) -> Result<Self> {
        let positive = |name, v: f64| match v.is_finite() && v > 0.0 {
            true => Ok(v),
            false => Err(Error::invalid(name, "must be positive and finite", v)),
        };
        let n = positive("orbit_rate", orbit_rate)?;
        positive("moment", moment)?;
        positive("mu", mu)?;
        if !(0.0..=std::f64::consts::PI).contains(&inclination) {
            return Err(Error::invalid(
                "inclination",
                "must be an angle in 0..=π (radians)",
                inclination,
            ));
        }
        let strength = moment / mu * n * n;
        if !(strength.is_finite() && strength > 0.0) {
            return Err(Error::invalid(
                "moment",
                "must give a field at the orbit that float64 holds (moment · n² / mu)",
                moment,
            ));
        }
        let (s, c) = inclination.sin_cos();
        let spin_axis = Vector3::new(0.0, s, c);
        let east = Vector3::x();
        Ok(Self {
            orbit_rate: n,
            strength,
            spin_axis,
            equator: (east, spin_axis.cross(&east)),
            tilt: (1.0, 0.0),
            earth_rate: 0.0,
            longitude: 0.0,
        })
    }

    /// The same field with the dipole tilted by `tilt` (radians, `0..=π`) from the spin axis,
    /// at longitude `longitude` from the orbit's ascending node at `t = 0`, the Earth turning
    /// at `earth_rate` (radians per unit time; 0 for an Earth at rest).
    ///
    /// # Errors
    /// `tilt` outside `0..=π`; `earth_rate` or `longitude` not finite.
    pub fn tilted(mut self, tilt: f64, earth_rate: f64, longitude: f64) -> Result<Self> {
        if !(0.0..=std::f64::consts::PI).contains(&tilt) {
            return Err(Error::invalid(
                "tilt",
                "must be an angle in 0..=π (radians)",
                tilt,
            ));
        }
        if !earth_rate.is_finite() {
            return Err(Error::invalid("earth_rate", "must be finite", earth_rate));
        }
        if !longitude.is_finite() {
            return Err(Error::invalid("longitude", "must be finite", longitude));
        }
        let (s, c) = tilt.sin_cos();
        self.tilt = (c, s);
        self.earth_rate = earth_rate;
        self.longitude = longitude;
        Ok(self)
    }

    /// The same field with times in the units of `scale` (the orbit's and the Earth's rates
    /// over `2^e`) and the field over `2^(2e)`: the field enters the equations as a torque per
    /// unit dipole, a moment times a rate squared (see [`crate::float`]).
    ///
    /// # Errors
    /// A field that float64 no longer holds.
    pub fn in_units(&self, scale: RateScale) -> Result<Self> {
        let strength = scale.rate_to_unit(scale.rate_to_unit(self.strength));
        if !(strength.is_finite() && strength > 0.0) {
            return Err(Error::invalid(
                "moment",
                "must give a field that float64 holds in the run's units",
                self.strength,
            ));
        }
        Ok(Self {
            orbit_rate: scale.rate_to_unit(self.orbit_rate),
            earth_rate: scale.rate_to_unit(self.earth_rate),
            strength,
            ..*self
        })
    }
}

/// # Evaluation
impl DipoleField {
    /// `B_eq`, the field on the magnetic equator at the orbit's radius.
    pub fn strength(&self) -> f64 {
        self.strength
    }

    /// The orbit's rate.
    pub fn orbit_rate(&self) -> f64 {
        self.orbit_rate
    }

    /// The unit vector toward the geomagnetic north pole at `t`, in world axes.
    #[inline(always)]
    pub fn north(&self, t: f64) -> Vector3<f64> {
        let (cos_tilt, sin_tilt) = self.tilt;
        if sin_tilt == 0.0 {
            return self.spin_axis * cos_tilt;
        }
        let (s, c) = sin_cos(self.longitude + self.earth_rate * t);
        let (e1, e2) = &self.equator;
        self.spin_axis * cos_tilt + (e1 * c + e2 * s) * sin_tilt
    }

    /// The field at `t` in world axes.
    #[inline(always)]
    pub fn world(&self, t: f64) -> Vector3<f64> {
        let (s, c) = sin_cos(self.orbit_rate * t);
        let r = Vector3::new(c, s, 0.0);
        let d = self.north(t);
        (d - r * (3.0 * d.dot(&r))) * self.strength
    }

    /// The field at `t` in the axes of a body at attitude `q` (world-from-body, any non-zero
    /// size).
    #[inline(always)]
    pub fn body(&self, t: f64, q: &Quaternion<f64>) -> Vector3<f64> {
        world_to_body(q, &self.world(t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::{FRAC_PI_2, PI};

    const MU: f64 = 3.986004418e14;
    const MOMENT: f64 = 7.708e15;

    fn orbit_rate(radius: f64) -> f64 {
        (MU / radius.powi(3)).sqrt()
    }

    #[test]
    fn an_equatorial_orbit_sees_a_constant_field_along_the_normal() {
        let f = DipoleField::try_new(1e-3, 0.0, MOMENT, MU).unwrap();
        for t in [0.0, 700.0, 3000.0] {
            let b = f.world(t);
            assert_relative_eq!(b, Vector3::z() * f.strength(), epsilon = 1e-20);
        }
    }

    #[test]
    fn the_field_strength_is_the_dipoles_at_the_keplerian_radius() {
        // B_eq = B₀ (R_E / R)³ with R from n² R³ = μ
        let radius = 6878.137e3;
        let f = DipoleField::try_new(orbit_rate(radius), 1.0, MOMENT, MU).unwrap();
        assert_relative_eq!(f.strength(), MOMENT / radius.powi(3), max_relative = 1e-14);
    }

    #[test]
    fn over_the_pole_the_field_points_down_at_twice_the_equators() {
        let n = 1e-3;
        let f = DipoleField::try_new(n, FRAC_PI_2, MOMENT, MU).unwrap();
        // a polar orbit reaches the north pole a quarter orbit after the ascending node
        let b = f.world(FRAC_PI_2 / n);
        assert_relative_eq!(
            b,
            Vector3::y() * (-2.0 * f.strength()),
            epsilon = 1e-9 * f.strength()
        );
        // and at the ascending node the field points north, along the track
        assert_relative_eq!(f.world(0.0), Vector3::y() * f.strength(), epsilon = 1e-20);
    }

    #[test]
    fn the_size_of_the_field_follows_the_magnetic_latitude() {
        // |B| = B_eq √(1 + 3 sin² λ), sin λ = d̂ · r̂: here sin λ = sin ξ sin nt
        let (n, xi) = (1.1e-3, 0.9);
        let f = DipoleField::try_new(n, xi, MOMENT, MU).unwrap();
        for k in 0..40 {
            let t = 173.0 * f64::from(k);
            let sin_lat = xi.sin() * (n * t).sin();
            let expected = f.strength() * (1.0 + 3.0 * sin_lat * sin_lat).sqrt();
            assert_relative_eq!(f.world(t).norm(), expected, max_relative = 1e-14);
        }
    }

    #[test]
    fn the_field_is_minus_the_gradient_of_the_dipoles_potential() {
        // Φ(r) = −B_eq R³ (d̂ · r) / |r|³ (the scalar potential of the dipole, B = −∇Φ),
        // differentiated numerically at the orbit, for a tilted dipole on a turning Earth
        let radius = 7000e3;
        let n = orbit_rate(radius);
        let f = DipoleField::try_new(n, 1.2, MOMENT, MU)
            .unwrap()
            .tilted(0.3, 7.292e-5, 2.0)
            .unwrap();
        for t in [0.0, 1234.5, 5000.0] {
            let d = f.north(t);
            let potential =
                |r: Vector3<f64>| -f.strength() * radius.powi(3) * d.dot(&r) / r.norm().powi(3);
            let r = Vector3::new((n * t).cos(), (n * t).sin(), 0.0) * radius;
            // a step whose truncation (h/R)² and round-off ε R/h both stay near 1e-11
            let h = 30.0;
            let gradient = Vector3::from_fn(|k, _| {
                let mut step = Vector3::zeros();
                step[k] = h;
                (potential(r + step) - potential(r - step)) / (2.0 * h)
            });
            assert_relative_eq!(f.world(t), -gradient, epsilon = 1e-9 * f.strength());
        }
    }

    #[test]
    fn a_tilted_dipole_turns_with_the_earth_about_its_spin_axis() {
        let (tilt, rate) = (0.164, 7.292e-5);
        let f = DipoleField::try_new(1e-3, 0.7, MOMENT, MU)
            .unwrap()
            .tilted(tilt, rate, 0.4)
            .unwrap();
        let axis = Vector3::new(0.0, 0.7_f64.sin(), 0.7_f64.cos());
        for t in [0.0, 3e3, 4e4] {
            assert_relative_eq!(f.north(t).norm(), 1.0, epsilon = 1e-15);
            assert_relative_eq!(f.north(t).dot(&axis), tilt.cos(), epsilon = 1e-15);
            assert_relative_eq!(f.north(t), f.north(t + 2.0 * PI / rate), epsilon = 1e-9);
        }
        // and an Earth at rest holds it still
        let still = DipoleField::try_new(1e-3, 0.7, MOMENT, MU)
            .unwrap()
            .tilted(tilt, 0.0, 0.4)
            .unwrap();
        assert_eq!(still.north(0.0), still.north(5e4));
    }

    #[test]
    fn the_body_sees_the_field_turned_into_its_axes() {
        let f = DipoleField::try_new(1e-3, FRAC_PI_2, MOMENT, MU).unwrap();
        // body turned +90° about world x: its y along world z, its z along world −y
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = Quaternion::new(h, h, 0.0, 0.0);
        let b = f.body(0.0, &q);
        assert_relative_eq!(b, Vector3::new(0.0, 0.0, -f.strength()), epsilon = 1e-20);
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let name = |r: Result<DipoleField>| match r {
            Err(Error::InvalidArgument { name, .. }) => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(DipoleField::try_new(0.0, 0.1, MOMENT, MU)),
            "orbit_rate"
        );
        assert_eq!(
            name(DipoleField::try_new(1e-3, 4.0, MOMENT, MU)),
            "inclination"
        );
        assert_eq!(name(DipoleField::try_new(1e-3, 0.1, -1.0, MU)), "moment");
        assert_eq!(
            name(DipoleField::try_new(1e-3, 0.1, MOMENT, f64::NAN)),
            "mu"
        );
        assert_eq!(
            name(DipoleField::try_new(1e150, 0.1, 1e300, 1e-300)),
            "moment"
        );
        let f = DipoleField::try_new(1e-3, 0.1, MOMENT, MU).unwrap();
        assert_eq!(name(f.tilted(-0.1, 0.0, 0.0)), "tilt");
        assert_eq!(name(f.tilted(0.1, f64::INFINITY, 0.0)), "earth_rate");
        assert_eq!(name(f.tilted(0.1, 0.0, f64::NAN)), "longitude");
    }
}
