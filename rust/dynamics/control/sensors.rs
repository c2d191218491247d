//! What the sensors measure at a sample: the truth, with noise drawn from the run's seed
//! ([`Noise`]); noise-free by default (every standard deviation zero gives the truth exactly).
//!
//! **Gyro** (Farrenkopf, "Analytic steady-state accuracy solutions for two common spacecraft
//! attitude estimators", *J. Guidance and Control* 1(4), 1978; in the discrete form of
//! Crassidis & Markley, "Unscented filtering for spacecraft attitude estimation", *J. Guidance,
//! Control, and Dynamics* 26(4), 2003, without the bias's own random walk): the rate plus a
//! constant bias `β`, plus the angle random walk `σ_v` (rad/√time) averaged over the sample's
//! period `T`,
//!
//! ```text
//! ω̃_k = ω_k + β + (σ_v / √T) N_k
//! ```
//!
//! (`N_k` a standard normal vector.) **Magnetometer**: the
//! field in body axes plus a constant bias and white noise `σ` per axis. **Star tracker**: the
//! attitude turned by a small rotation `θ = σ N` in body axes, `q̃ = q ⊗ exp(θ / 2)`.
//!
//! Each sensor draws from its own stream; sample `k` uses counter `k`, so its noise does not
//! depend on when or how often it is asked.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::error::{Error, Result};

use super::noise::Noise;

/// A standard deviation: finite and not negative.
fn deviation(name: &'static str, v: f64) -> Result<f64> {
    match v.is_finite() && v >= 0.0 {
        true => Ok(v),
        false => Err(Error::invalid(name, "must be finite and not negative", v)),
    }
}

/// A bias: three finite numbers.
fn bias(name: &'static str, v: [f64; 3]) -> Result<Vector3<f64>> {
    match v.iter().all(|c| c.is_finite()) {
        true => Ok(Vector3::from(v)),
        false => Err(Error::invalid(name, "must be three finite numbers", v)),
    }
}

/// A rate gyro (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gyro {
    /// The bias `β` (body axes).
    bias: Vector3<f64>,
    /// `σ_v`, the angle random walk.
    angle_random_walk: f64,
}

impl Gyro {
    /// A gyro of bias `bias` and angle random walk `angle_random_walk`.
    ///
    /// # Errors
    /// A bias that is not finite, or a random walk that is negative or not finite.
    pub fn try_new(bias_: [f64; 3], angle_random_walk: f64) -> Result<Self> {
        Ok(Self {
            bias: bias("bias", bias_)?,
            angle_random_walk: deviation("angle_random_walk", angle_random_walk)?,
        })
    }

    /// The rate measured at sample `sample` of period `period` for the true rate `omega`.
    #[inline]
    pub fn measure(
        &self,
        noise: &Noise,
        sample: u64,
        period: f64,
        omega: &Vector3<f64>,
    ) -> Vector3<f64> {
        let measured = omega + self.bias;
        match self.angle_random_walk > 0.0 {
            true => measured + noise.vector(sample, 0) * (self.angle_random_walk / period.sqrt()),
            false => measured,
        }
    }
}

/// A three-axis magnetometer (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Magnetometer {
    bias: Vector3<f64>,
    noise: f64,
}

impl Magnetometer {
    /// A magnetometer of constant bias `bias` and white noise `noise` per axis (field units).
    ///
    /// # Errors
    /// A bias that is not finite, or a noise that is negative or not finite.
    pub fn try_new(bias_: [f64; 3], noise: f64) -> Result<Self> {
        Ok(Self {
            bias: bias("bias", bias_)?,
            noise: deviation("noise", noise)?,
        })
    }

    /// The field measured at sample `sample` for the true field `field` (body axes).
    #[inline]
    pub fn measure(&self, noise: &Noise, sample: u64, field: &Vector3<f64>) -> Vector3<f64> {
        let measured = field + self.bias;
        match self.noise > 0.0 {
            true => measured + noise.vector(sample, 0) * self.noise,
            false => measured,
        }
    }

    /// The same magnetometer with its field units over `2^(2e)` (see
    /// [`super::DipoleField::in_units`]).
    pub fn scaled(&self, to_unit: impl Fn(f64) -> f64) -> Self {
        Self {
            bias: self.bias.map(&to_unit),
            noise: to_unit(self.noise),
        }
    }
}

/// A star tracker (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StarTracker {
    noise: f64,
}

impl StarTracker {
    /// A star tracker of noise `noise` (radians per axis, body axes).
    ///
    /// # Errors
    /// A noise that is negative or not finite.
    pub fn try_new(noise: f64) -> Result<Self> {
        Ok(Self {
            noise: deviation("noise", noise)?,
        })
    }

    /// The attitude measured at sample `sample` for the true attitude `q` (world-from-body,
    /// unit).
    #[inline]
    pub fn measure(&self, noise: &Noise, sample: u64, q: &Quaternion<f64>) -> Quaternion<f64> {
        match self.noise > 0.0 {
            true => {
                let turn = noise.vector(sample, 0) * self.noise;
                q * UnitQuaternion::from_scaled_axis(turn).into_inner()
            }
            false => *q,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The mean and variance of `values`.
    fn moments(values: &[f64]) -> (f64, f64) {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        (
            mean,
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n,
        )
    }

    /// Whether a sample variance of `n` normal values is within five standard errors of `var`.
    fn variance_is(sample: f64, var: f64, n: usize) -> bool {
        (sample - var).abs() < 5.0 * var * (2.0 / n as f64).sqrt()
    }

    #[test]
    fn noise_free_sensors_measure_the_truth() {
        let noise = Noise::new(1, 2);
        let omega = Vector3::new(0.1, -0.2, 0.3);
        let gyro = Gyro::try_new([0.0; 3], 0.0).unwrap();
        assert_eq!(gyro.measure(&noise, 5, 0.1, &omega), omega);
        let b = Vector3::new(1e-5, 2e-5, -3e-5);
        assert_eq!(
            Magnetometer::try_new([0.0; 3], 0.0)
                .unwrap()
                .measure(&noise, 5, &b),
            b
        );
        let q = Quaternion::new(0.5, 0.5, -0.5, 0.5);
        assert_eq!(StarTracker::try_new(0.0).unwrap().measure(&noise, 5, &q), q);
    }

    #[test]
    fn the_angle_random_walk_averaged_over_a_sample_has_variance_sigma_squared_over_t() {
        let (sv, period) = (1e-3, 0.25);
        let bias = Vector3::new(1e-4, -2e-4, 0.0);
        let gyro = Gyro::try_new(bias.into(), sv).unwrap();
        let noise = Noise::new(42, 3);
        let errors: Vec<f64> = (0..20_000)
            .flat_map(|k| {
                let m = gyro.measure(&noise, k, period, &Vector3::zeros());
                (m - bias).iter().copied().collect::<Vec<_>>()
            })
            .collect();
        let (mean, var) = moments(&errors);
        assert!(mean.abs() < 5.0 * (sv * sv / period / errors.len() as f64).sqrt());
        assert!(variance_is(var, sv * sv / period, errors.len()), "{var}");
    }

    #[test]
    fn a_magnetometer_adds_its_bias_and_noise() {
        let (bias, sigma) = ([1e-7, 0.0, -2e-7], 5e-8);
        let mag = Magnetometer::try_new(bias, sigma).unwrap();
        let field = Vector3::new(2e-5, -1e-5, 3e-5);
        let noise = Noise::new(11, 0);
        let errors: Vec<f64> = (0..20_000)
            .flat_map(|k| {
                (mag.measure(&noise, k, &field) - field - Vector3::from(bias))
                    .iter()
                    .copied()
                    .collect::<Vec<_>>()
            })
            .collect();
        let (mean, var) = moments(&errors);
        assert!(mean.abs() < 5.0 * sigma / (errors.len() as f64).sqrt());
        assert!(variance_is(var, sigma * sigma, errors.len()), "{var}");
    }

    #[test]
    fn a_star_trackers_error_angle_follows_the_chi_law_of_three_degrees() {
        // |θ| = σ χ₃: mean σ √(8/π), mean square 3σ²
        let sigma = 1e-4;
        let tracker = StarTracker::try_new(sigma).unwrap();
        let q = Quaternion::new(0.3, -0.5, 0.7, 0.2).normalize();
        let noise = Noise::new(5, 9);
        let n = 20_000;
        let angles: Vec<f64> = (0..n)
            .map(|k| {
                let m = tracker.measure(&noise, k, &q);
                assert_relative_eq!(m.norm(), 1.0, epsilon = 1e-15);
                let d = q.conjugate() * m;
                2.0 * d.imag().norm().atan2(d.w.abs())
            })
            .collect();
        let (mean, _) = moments(&angles);
        let chi_mean = (8.0 / std::f64::consts::PI).sqrt();
        let chi_sd = (3.0 - 8.0 / std::f64::consts::PI).sqrt();
        assert!(
            (mean / sigma - chi_mean).abs() < 5.0 * chi_sd / (n as f64).sqrt(),
            "{mean}"
        );
        let square = angles.iter().map(|a| a * a).sum::<f64>() / n as f64;
        assert_relative_eq!(square / (sigma * sigma), 3.0, max_relative = 0.05);
    }

    #[test]
    fn bad_deviations_are_refused_by_name() {
        let name = |e: Error| match e {
            Error::InvalidArgument { name, .. } => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(Gyro::try_new([0.0; 3], -1.0).unwrap_err()),
            "angle_random_walk"
        );
        assert_eq!(
            name(Gyro::try_new([0.0; 3], f64::NAN).unwrap_err()),
            "angle_random_walk"
        );
        assert_eq!(
            name(Gyro::try_new([f64::INFINITY, 0.0, 0.0], 0.0).unwrap_err()),
            "bias"
        );
        assert_eq!(
            name(Magnetometer::try_new([0.0; 3], -1e-9).unwrap_err()),
            "noise"
        );
        assert_eq!(name(StarTracker::try_new(f64::NAN).unwrap_err()), "noise");
    }
}
