//! The bounds that refuse unbounded adaptive runs up front never refuse a run that fits: no
//! accepted step of dopri5 or dop853 turns the attitude by more than a fraction of
//! `MAX_TURN_PER_STEP`, at the loosest tolerances the bound is taken for (`rtol` up to
//! `MEASURED_RTOL`, `atol` below `MEASURED_ATOL`), over bodies and starts of every kind; so
//! `least_adaptive_steps` is below every run's own count. (Looser still, at `rtol` 0.5 or
//! 0.9, steps of 30 and 50 radians were accepted: no bound is taken there.)

use std::sync::atomic::AtomicBool;

use dzhanibekov::dynamics::{state_from, FreeRigidBody, Model};
use dzhanibekov::integrators::{Dop853, Dopri5};
use dzhanibekov::observe::Observer;
use dzhanibekov::ode::controller::Adaptive;
use dzhanibekov::ode::EmbeddedPair;
use dzhanibekov::run::adaptive::{integrate_adaptive, Units};
use dzhanibekov::run::{
    least_adaptive_steps, FrameGrid, MAX_TURN_PER_STEP, MEASURED_ATOL, MEASURED_RTOL,
};
use dzhanibekov::RigidBody;

/// The largest turn of the attitude in one accepted step: `h |ω|` at its larger end.
#[derive(Default)]
struct LargestTurn {
    sys: Option<FreeRigidBody>,
    largest: f64,
}

impl Observer<7> for LargestTurn {
    const WANTS_STEPS: bool = true;
    fn step(&mut self, t0: f64, x0: &[f64; 7], t1: f64, x1: &[f64; 7]) {
        let sys = self.sys.as_ref().unwrap();
        let rate = sys
            .omega_body(t0, x0)
            .norm()
            .max(sys.omega_body(t1, x1).norm());
        self.largest = self.largest.max((t1 - t0) * rate);
    }
}

fn largest_turn<P: EmbeddedPair<7, FreeRigidBody>>(
    pair: &P,
    body: RigidBody,
    omega0: [f64; 3],
    settings: &Adaptive,
    t_end: f64,
) -> (f64, u64, f64) {
    let sys = FreeRigidBody::new(body);
    let x0 = state_from(omega0, [1.0, 0.0, 0.0, 0.0]);
    let grid = FrameGrid::frames_only(t_end, 2).unwrap();
    let rate = sys.rate_bound(&x0);
    let units = Units::new(rate, rate, 3);
    let mut obs = LargestTurn {
        sys: Some(sys),
        largest: 0.0,
    };
    let cancel = AtomicBool::new(false);
    let run = integrate_adaptive(
        pair,
        &sys,
        x0,
        &grid,
        settings,
        &units,
        (&|_| f64::INFINITY, &|_| f64::INFINITY),
        &mut obs,
        &cancel,
    );
    // (loose tolerances can fail to finish, "below round-off": the steps they took count)
    let n_steps = run.map_or(u64::MAX, |(_, stats)| stats.n_steps);
    let (least, _) = least_adaptive_steps(&sys, &x0, t_end, settings).unwrap();
    (obs.largest, n_steps, least)
}

#[test]
fn no_accepted_step_turns_the_attitude_near_the_bound() {
    let bodies = [
        [1.0, 2.0, 3.0],
        [1.0, 1.7, 2.3],
        [1.0, 50.0, 50.5],
        [1.0, 1.0, 1.0001],
    ];
    let starts = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [0.01, 1.0, 0.01],
        [0.3, -0.9, 0.6],
        [2.0, -1.0, 0.5],
        [5.0, 0.1, -0.1],
    ];
    let mut most: f64 = 0.0;
    for rtol in [MEASURED_RTOL, 1e-2, 1e-3, 1e-6, 1e-9] {
        for atol in [0.99 * MEASURED_ATOL, 1e-2, 1e-6, 1e-12] {
            let settings = Adaptive::try_new(rtol, atol).unwrap();
            for body in bodies {
                let body = RigidBody::try_new(body).unwrap();
                for omega0 in starts {
                    for (turn, n_steps, least) in [
                        largest_turn(&Dop853, body, omega0, &settings, 200.0),
                        largest_turn(&Dopri5, body, omega0, &settings, 200.0),
                    ] {
                        assert!(least <= n_steps as f64, "{least} > {n_steps}");
                        if n_steps < u64::MAX {
                            // a run that finished (one that blew up at a loose tolerance
                            // ends in an error whatever its steps)
                            most = most.max(turn);
                        }
                    }
                }
            }
        }
    }
    // a wide margin: the bound counts steps four times larger than any seen
    assert!(
        most < MAX_TURN_PER_STEP / 4.0,
        "a step turned {most} radians"
    );
    println!("the largest turn in one step: {most:.2} radians");
}
