//! Pointing by quaternion feedback: three reaction wheels commanded at each sample to give the
//! body `τ = −K_p e − K_d (ω̃ − ω_t)` toward a target fixed in space or in the orbiting frame,
//! from a star tracker's attitude and a gyro's rates (see [`super::laws`],
//! [`super::reaction`], [`super::sensors`]). The gains are diagonal in the body's axes. The
//! wheels' torque is internal: `H` stays fixed in space without external torques. With
//! `feedforward = "gyroscopic"` the law adds `ω̃ × H` (Wie, Weiss & Arapostathis's regulator:
//! `H = I ω + Σ h a`, the total momentum in body axes, as the controller's model of its body
//! and its wheels' tachometers give it), which cancels the gyroscopic coupling of a body whose
//! wheels hold much momentum.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::error::{Error, Result};

use super::super::kinds::{Conserved, Traits};
use super::super::part::{
    Ctx, Dim, EnergyRole, Fields, ModelInfo, Param, ParamKind, Part, Sampling,
};
use super::common::{
    gyro_from, number_or, saturated, star_tracker_from, view_hooks, Clock, View, Viewed,
    GYRO_ANGLE_RANDOM_WALK, GYRO_BIAS, PERIOD, PHASE, SEED, STAR_TRACKER_NOISE,
};
use super::laws::{quaternion_feedback, Target};
use super::reaction::{self, ReactionWheels};
use super::sensors::{Gyro, StarTracker};

/// The saturation bits follow the wheels' two fields.
const SATURATED_AT: usize = reaction::WIDTH;

/// Quaternion feedback on three reaction wheels (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct QuaternionFeedback {
    kp: Matrix3<f64>,
    kd: Matrix3<f64>,
    target: Target,
    gyroscopic: bool,
    clock: Clock,
    wheels: ReactionWheels,
    star_tracker: StarTracker,
    gyro: Gyro,
    view: View,
}

/// Three non-negative, finite gains.
fn gains(name: &'static str, v: [f64; 3]) -> Result<Matrix3<f64>> {
    match v.iter().all(|c| c.is_finite() && *c >= 0.0) {
        true => Ok(Matrix3::from_diagonal(&Vector3::from(v))),
        false => Err(Error::invalid(
            name,
            "must be three finite, non-negative gains",
            v,
        )),
    }
}

impl Part for QuaternionFeedback {
    const INFO: ModelInfo = ModelInfo {
        name: "quaternion_feedback",
        about: "three reaction wheels commanded τ = −Kp e − Kd (ω − ω_t) toward a target fixed \
                in space or in LVLH (e = 2 sgn(δq₀) δq_v, the shorter way) at each sample, \
                limited in torque and momentum, held",
        law: false,
        params: &[
            Param::new(
                "kp",
                ParamKind::Vector,
                "the proportional gains, body axes (torque per radian)",
            ),
            Param::new(
                "kd",
                ParamKind::Vector,
                "the rate gains, body axes (torque per rate)",
            ),
            PERIOD,
            Param::new(
                "target",
                ParamKind::Values,
                "the target's attitude (Q, U, V, W): world-from-target, or LVLH-from-target \
                 (default identity)",
            )
            .optional(),
            Param::new(
                "frame",
                ParamKind::Choice(&["inertial", "lvlh"]),
                "what the target is fixed in (default inertial)",
            )
            .optional(),
            Param::new(
                "orbit_rate",
                ParamKind::Scalar,
                "the orbit's rate, for a target fixed in LVLH",
            )
            .optional(),
            Param::new(
                "feedforward",
                ParamKind::Choice(&["none", "gyroscopic"]),
                "'gyroscopic' adds ω × H, cancelling the gyroscopic coupling (default 'none')",
            )
            .optional(),
            PHASE,
            reaction::AXES,
            reaction::MOMENTUM,
            reaction::TORQUE_LIMIT,
            reaction::MOMENTUM_LIMIT,
            STAR_TRACKER_NOISE,
            GYRO_BIAS,
            GYRO_ANGLE_RANDOM_WALK,
            SEED,
        ],
        state: &[
            reaction::STATE[0],
            reaction::STATE[1],
            saturated(
                "bit k set where wheel k's torque limit, bit 3 + k where its momentum limit cut \
                 its command at the last sample",
            ),
        ],
        keeps: Conserved::MOMENTA,
        defines: Conserved::NONE,
        energy: EnergyRole::DoesWork,
        external: false,
        unique: false,
        traits: Traits::STORED_MOMENTUM
            .union(Traits::PART_STATE)
            .union(Traits::SAMPLED),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        let q = match fields.get("target") {
            None => vec![1.0, 0.0, 0.0, 0.0],
            Some(_) => fields.numbers("target")?,
        };
        let target = match q[..] {
            [w, x, y, z] if q.iter().all(|c| c.is_finite()) && q.iter().any(|c| *c != 0.0) => {
                Quaternion::new(w, x, y, z).normalize()
            }
            _ => {
                return Err(Error::invalid(
                    "target",
                    "must be a finite, non-zero quaternion (Q, U, V, W)",
                    q,
                ))
            }
        };
        let lvlh = match fields.get("frame") {
            None => false,
            Some(_) => match fields.choice::<Frame>("frame")? {
                Frame::Inertial => false,
                Frame::Lvlh => true,
            },
        };
        let target = match lvlh {
            false => Target::Inertial(target),
            true => {
                let n = number_or(fields, "orbit_rate", f64::NAN)?;
                if !(n.is_finite() && n > 0.0) {
                    return Err(Error::invalid(
                        "orbit_rate",
                        "must be positive and finite for a target fixed in LVLH",
                        n,
                    ));
                }
                Target::Lvlh {
                    orbit_rate: n,
                    offset: target,
                }
            }
        };
        let gyroscopic = match fields.get("feedforward") {
            None => false,
            Some(_) => fields.choice::<Feedforward>("feedforward")? == Feedforward::Gyroscopic,
        };
        Ok(Self {
            gyroscopic,
            kp: gains("kp", fields.vector("kp")?)?,
            kd: gains("kd", fields.vector("kd")?)?,
            target,
            clock: Clock::from_fields(fields)?,
            wheels: ReactionWheels::from_fields(fields)?,
            star_tracker: star_tracker_from(fields)?,
            gyro: gyro_from(fields)?,
            view: View::from_fields(fields)?,
        })
    }

    #[inline]
    fn momentum(&self, _t: f64, x: &[f64]) -> Vector3<f64> {
        self.wheels.stored(x, 0)
    }

    #[inline]
    fn rates(&self, _c: &Ctx<'_>, x: &[f64], dx: &mut [f64]) {
        self.wheels.rates(x, 0, dx);
    }

    fn start(&self, _omega0: &Vector3<f64>, x: &mut [f64]) {
        self.wheels.start(&self.view, x, 0);
    }

    fn largest_momentum(&self) -> f64 {
        self.wheels.largest()
    }

    fn sampling(&self) -> Option<Sampling> {
        Some(self.clock.in_run(&self.view))
    }

    fn sample(&self, c: &Ctx<'_>, at: usize, x: &mut [f64]) {
        let v = &self.view;
        let total = v.as_user(&Vector3::new(x[0], x[1], x[2]), Dim::MOMENTUM, true);
        let own = &mut x[at..at + Self::INFO.width()];
        let t = v.time(c.t);
        let k = self.clock.index(t);
        let period = self.clock.period;
        let q = self.star_tracker.measure(&v.noise(2), k, &v.attitude(&c.q));
        let omega = self.gyro.measure(
            &v.noise(1),
            k,
            period,
            &v.as_user(&c.omega, Dim::RATE, true),
        );
        let (target, target_rate) = self.target.at(t);
        let mut torque = quaternion_feedback(&q, &omega, &target, &target_rate, &self.kp, &self.kd);
        if self.gyroscopic {
            torque += omega.cross(&total);
        }
        let bits = self.wheels.command(v, &torque, period, own, 0);
        own[SATURATED_AT] = f64::from(bits);
    }

    view_hooks!();

    fn heap_bytes(&self) -> usize {
        self.wheels.heap_bytes()
    }
}

impl Viewed for QuaternionFeedback {
    fn view_mut(&mut self) -> &mut View {
        &mut self.view
    }

    fn axes_too(&mut self, to_axes: &dyn Fn([f64; 3]) -> [f64; 3]) {
        self.wheels = self.wheels.in_axes(to_axes);
    }
}

/// What a pointing target is fixed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frame {
    Inertial,
    Lvlh,
}

impl std::str::FromStr for Frame {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "inertial" => Ok(Frame::Inertial),
            "lvlh" => Ok(Frame::Lvlh),
            _ => Err(Error::invalid("frame", "must be 'inertial' or 'lvlh'", s)),
        }
    }
}

/// What a pointing law adds to its feedback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Feedforward {
    None,
    Gyroscopic,
}

impl std::str::FromStr for Feedforward {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "none" => Ok(Feedforward::None),
            "gyroscopic" => Ok(Feedforward::Gyroscopic),
            _ => Err(Error::invalid(
                "feedforward",
                "must be 'none' or 'gyroscopic'",
                s,
            )),
        }
    }
}
