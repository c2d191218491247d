//! The atlas of rigid-body methods (issue 22) against the exact solution and the conservation
//! laws: every fixed-step method's order by halving the step on Hairer, Lubich & Wanner's
//! free body, the symplectic methods' bounded energy error, the Lie-group methods' unit
//! quaternion, the implicit methods' Newton iterations, and the clear errors of steps too
//! large and models they cannot run.

use std::sync::atomic::AtomicBool;

use dzhanibekov::dynamics::{Conserved, Damper, Kinds};
use dzhanibekov::exact::ExactMotion;
use dzhanibekov::ode::Stepper;
use dzhanibekov::rigid::{Dmv, DmvModified, ImplicitMidpoint};
use dzhanibekov::run::{simulate, FrameGrid, Keep, Method, RunOutput, METHODS};
use dzhanibekov::{Error, FreeRigidBody, RigidBody, State};

mod common;
use common::run;

/// Hairer, Lubich & Wanner's free rigid body (*Geometric Numerical Integration*, §VII.5,
/// Fig. 5.2 and ch. IX): moments `(2, 1, 2/3)`, angular momentum `(cos 1.1, 0, sin 1.1)`.
const HLW: [f64; 3] = [2.0, 1.0, 2.0 / 3.0];

fn hlw_omega0() -> [f64; 3] {
    let y = [1.1f64.cos(), 0.0, 1.1f64.sin()];
    [y[0] / HLW[0], y[1] / HLW[1], y[2] / HLW[2]]
}

/// A generic attitude (unit), so that every quaternion component moves.
const Q0: [f64; 4] = [0.8, 0.1, -0.3, 0.5];

fn q0() -> [f64; 4] {
    let n = Q0.iter().map(|c| c * c).sum::<f64>().sqrt();
    Q0.map(|c| c / n)
}

/// The methods of the atlas: every fixed-step method of the registry.
fn fixed_step_methods() -> Vec<Method> {
    METHODS
        .iter()
        .filter(|m| m.takes_steps() && !m.adaptive())
        // the free body's (splitting_exact runs bodies under torques)
        .filter(|m| m.method.for_kinds(Kinds::FREE).is_ok())
        .map(|m| m.method)
        .collect()
}

/// The symplectic ones.
const SYMPLECTIC: [Method; 6] = [
    Method::Splitting,
    Method::Splitting4,
    Method::Splitting6,
    Method::ImplicitMidpoint,
    Method::Dmv,
    Method::DmvModified,
];

/// The largest error in ω and in q (up to sign) at `t_end` against the closed form.
fn error_at_end(method: Method, t_end: f64, dt: f64) -> f64 {
    let out = run(method, HLW, hlw_omega0(), q0(), t_end, 2, dt);
    let body = RigidBody::try_new(HLW).unwrap();
    let want = ExactMotion::try_new(&body, hlw_omega0(), q0())
        .unwrap()
        .state_at(t_end);
    let omega = &out.omega[3..6];
    let q = &out.q[4..8];
    let sign = if (0..4).map(|k| q[k] * want[3 + k]).sum::<f64>() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let e_omega = (0..3)
        .map(|k| (omega[k] - want[k]).abs())
        .fold(0.0, f64::max);
    let e_q = (0..4)
        .map(|k| (q[k] - sign * want[3 + k]).abs())
        .fold(0.0, f64::max);
    e_omega.max(e_q)
}

#[test]
fn every_fixed_step_method_has_the_order_it_declares() {
    // Three steps, halving: errors from about 1e-3 down to well above round-off (the
    // sixth-order splitting from a larger step, so that its smallest error is still 4e-12).
    for method in fixed_step_methods() {
        let h0 = match method.order() {
            6 => 0.2,
            3 => 0.05,
            _ => 0.1,
        };
        let errors: Vec<f64> = [h0, h0 / 2.0, h0 / 4.0]
            .iter()
            .map(|&dt| error_at_end(method, 10.0, dt))
            .collect();
        for pair in errors.windows(2) {
            let slope = (pair[0] / pair[1]).log2();
            assert!(
                (slope - method.order() as f64).abs() < 0.15,
                "{}: slope {slope:.3}, errors {errors:?}",
                method.name()
            );
        }
    }
}

/// The relative energy error at each frame of a run.
fn energy_errors(out: &RunOutput) -> Vec<f64> {
    let energy = |w: &[f64]| (0..3).map(|k| HLW[k] * w[k] * w[k]).sum::<f64>();
    let e0 = energy(&out.omega[..3]);
    out.omega
        .chunks_exact(3)
        .map(|w| (energy(w) / e0 - 1.0).abs())
        .collect()
}

#[test]
fn the_symplectic_methods_energy_error_stays_bounded_over_1e5_steps() {
    // h = 0.1 (h|ω| ≈ 0.14) to T = 10⁴: about 250 periods of the motion, 1001 frames.
    for method in SYMPLECTIC {
        let out = run(method, HLW, hlw_omega0(), q0(), 1e4, 1001, 0.1);
        let errors = energy_errors(&out);
        let half = errors.len() / 2;
        let first = errors[1..=half].iter().cloned().fold(0.0, f64::max);
        let second = errors[half..].iter().cloned().fold(0.0, f64::max);
        let name = method.name();
        assert!(
            second <= 1.5 * first,
            "{name}: {first:.2e} then {second:.2e}"
        );
        if method.keeps(Conserved::FREE).contains(Conserved::ENERGY) {
            // kept exactly but for the arithmetic's round-off, which random-walks: about
            // √n ulps (measured 1.7–1.8e-14)
            assert!(second < 5e-14, "{name}: {first:.2e} then {second:.2e}");
        } else {
            // an O(h^p) oscillation about a modified energy, with no drift
            assert!(
                first > 1e-13,
                "{name}: the oscillation should show ({first:.2e})"
            );
        }
    }
}

#[test]
fn the_lie_group_methods_keep_the_unit_quaternion_and_what_they_declare() {
    // 10⁵ steps of h = 0.1: each step multiplies q by a unit quaternion (an exponential or a
    // Cayley transform) and turns L; their round-off stays within the 1e-14 pull-back.
    for method in [
        Method::Rkmk4,
        Method::CrouchGrossman3,
        Method::Dmv,
        Method::DmvModified,
        Method::ImplicitMidpoint,
        Method::Splitting6,
    ] {
        let out = run(method, HLW, hlw_omega0(), q0(), 1e4, 11, 0.1);
        let d = out.drift;
        let name = method.name();
        assert!(d.q_norm < 1e-14, "{name}: {d:?}");
        for kept in method.keeps(Conserved::FREE).names() {
            let drift = match kept {
                "energy" => d.energy,
                "momentum" => d.momentum,
                "momentum_world" => d.momentum_world,
                _ => d.q_norm,
            };
            // L_world is a sum of 10⁵ turns' round-off: about √n ulps
            assert!(drift < 1e-12, "{name} keeps {kept}: {d:?}");
        }
    }
}

/// Newton corrections per step over 20 time units of the HLW body at `h|ω₀| = hw`: the
/// smallest and largest count.
fn newton_counts<M: Stepper<7, FreeRigidBody>>(
    method: &M,
    step: impl Fn(&M, f64, &mut State) -> u32,
    hw: f64,
) -> (u32, u32) {
    let body = RigidBody::try_new(HLW).unwrap();
    let sys = FreeRigidBody::new(body);
    let w = hlw_omega0();
    let h = hw / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let mut x = method.to_internal(&sys, &[w[0], w[1], w[2], 1.0, 0.0, 0.0, 0.0]);
    let (mut lo, mut hi) = (u32::MAX, 0);
    for _ in 0..(20.0 / h) as usize {
        let n = step(method, h, &mut x);
        (lo, hi) = (lo.min(n), hi.max(n));
    }
    (lo, hi)
}

#[test]
fn the_implicit_methods_converge_in_a_few_newton_iterations() {
    // what the docs (and the registry's `about`) state, at h|ω| = 0.1 and 1
    let body = RigidBody::try_new(HLW).unwrap();
    let w = hlw_omega0();
    let x0 = [w[0], w[1], w[2], 1.0, 0.0, 0.0, 0.0];
    let midpoint = ImplicitMidpoint::new(&body, &x0);
    let dmv = Dmv::new(&body, &x0);
    let dmv_modified = DmvModified::new(&body, &x0);
    let m = |s: &ImplicitMidpoint, h, x: &mut State| s.step_counted(h, x);
    assert_eq!(newton_counts(&midpoint, m, 0.1), (2, 2));
    assert_eq!(newton_counts(&midpoint, m, 1.0), (3, 3));
    let d = |s: &Dmv, h, x: &mut State| s.step_counted(h, x);
    assert_eq!(newton_counts(&dmv, d, 0.1), (3, 3));
    assert_eq!(newton_counts(&dmv, d, 1.0), (6, 6));
    let d = |s: &DmvModified, h, x: &mut State| s.step_counted(h, x);
    assert_eq!(newton_counts(&dmv_modified, d, 0.1), (3, 3));
    assert_eq!(newton_counts(&dmv_modified, d, 1.0), (4, 4));
}

#[test]
fn the_energy_kept_by_newton_is_kept_to_round_off_at_large_steps_too() {
    // at h|ω| ≈ 1 the midpoint rule and the modified DMV still solve to round-off: over 1430
    // steps the energy wanders by a few ulps, as at small steps (measured 6e-15)
    for method in [Method::ImplicitMidpoint, Method::DmvModified] {
        let out = run(method, HLW, hlw_omega0(), q0(), 1e3, 101, 0.7);
        assert!(
            out.drift.energy < 2e-14,
            "{}: {:?}",
            method.name(),
            out.drift
        );
    }
}

#[test]
fn a_step_the_dmv_has_no_solution_for_is_a_clear_error() {
    // For a spin about an axis the DMV's rotation angle φ solves sin φ = h|ω|: beyond h|ω| = 1
    // (roughly, on other orbits) its equations have no real solution. Newton then fails and
    // the run stops with the driver's "diverged" error, never a silent NaN.
    let body = RigidBody::try_new(HLW).unwrap();
    let grid = FrameGrid::try_new(100.0, 11, 2.0 / 1.36, u64::MAX).unwrap();
    let keep = Keep {
        frames: true,
        flips: true,
        tilt: false,
    };
    let cancel = AtomicBool::new(false);
    let err = simulate(&body, hlw_omega0(), q0(), &grid, Method::Dmv, keep, &cancel).unwrap_err();
    assert!(matches!(err, Error::Diverged { .. }), "{err}");
    assert!(err.to_string().contains("take a smaller dt"), "{err}");
}

#[test]
fn the_new_methods_refuse_the_models_they_cannot_run_by_name() {
    for method in [
        Method::Splitting6,
        Method::ImplicitMidpoint,
        Method::Dmv,
        Method::DmvModified,
        Method::Rkmk4,
        Method::CrouchGrossman3,
    ] {
        for (model, kind) in [("deployment", Kinds::DEPLOYMENT), ("damper", Damper::KIND)] {
            let err = method.for_kinds(kind).unwrap_err().to_string();
            let want = format!("method '{}' cannot run model '{model}'", method.name());
            assert!(err.starts_with(&want), "{err}");
            // and names the methods that do, as for the other free-body methods
            assert!(err.contains("'rk4'") && err.contains("'dop853'"), "{err}");
            let (_, supported) = err.split_once("use one of").unwrap();
            assert!(
                !supported.contains(&format!("'{}'", method.name())),
                "{err}"
            );
        }
        assert!(method.for_kinds(Kinds::FREE).is_ok());
    }
}
