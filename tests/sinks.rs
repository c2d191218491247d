//! The energy sinks through the run: a body with a spring–mass damper, a hinged panel or a
//! slosh pendulum (alone, which the run takes in closed form, and together, which it takes by
//! the general joint solve), built as a user builds it (parts from their fields, a body of any
//! tensor and a mass) and run by `simulate_system`, against a plain RK4 written here in the
//! user's axes on the general joint solve of `multibody` (the mass matrix assembled from what
//! each part carries) — what the run's change to principal axes, its units, its start (the
//! parts' momenta from their rates) and its closed forms must leave unchanged — and the
//! invariants: `H` in space and the energy balance `T + V + W` kept to round-off.

use std::sync::atomic::AtomicBool;

use nalgebra::{Matrix3, Vector3};

use dzhanibekov::body::Inertia;
use dzhanibekov::dynamics::multibody::{motion, Carried, Hub, MassMatrix, MAX_RATES};
use dzhanibekov::dynamics::{
    AnyPart, Fields, Hinge, Part, Rod, Slosh, SpringMass, System, SystemBody, Value,
};
use dzhanibekov::run::{simulate_system, FrameGrid, Keep, Method, RunOutput};

/// A hub of no particular axes: its principal axes are not the body's.
fn tensor() -> Matrix3<f64> {
    Matrix3::new(3.0, -0.2, 0.1, -0.2, 4.0, 0.3, 0.1, 0.3, 5.0)
}

const HUB_MASS: f64 = 4.0;
const OMEGA0: [f64; 3] = [0.3, -0.7, 1.1];
const H: f64 = 1e-3;
const T_END: f64 = 20.0;

fn run(parts: Vec<AnyPart>) -> RunOutput {
    let inertia = Inertia::try_new(tensor()).unwrap();
    let system = System::try_new(SystemBody::Rigid(inertia), parts)
        .unwrap()
        .with_mass(Some(HUB_MASS))
        .unwrap();
    let grid = FrameGrid::try_new(T_END, 11, H, u64::MAX).unwrap();
    let keep = Keep {
        frames: true,
        flips: false,
        tilt: false,
    };
    let cancel = AtomicBool::new(false);
    simulate_system(
        &system,
        OMEGA0,
        [1.0, 0.0, 0.0, 0.0],
        &grid,
        Method::Rk4,
        keep,
        &cancel,
    )
    .unwrap()
}

/// The run kept `H` in space and `T + V + W` to round-off, and it dissipated.
fn assert_kept(out: &RunOutput) {
    let d = &out.drift;
    assert!(d.momentum_world < 1e-12, "{d:?}");
    let balance = d
        .energy_balance
        .expect("a part that dissipates keeps the balance");
    assert!(balance < 1e-12, "{d:?}");
    assert!(
        d.energy > 1e-6,
        "the energy fell by the dissipated work: {d:?}"
    );
}

fn close(a: &[f64], b: &[f64], tol: f64) {
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(worst < tol, "{a:?} {b:?} {worst:e}");
}

/// A part as the reference integrates it.
#[derive(Clone, Copy)]
enum Moving {
    Spring(SpringMass),
    Hinge(Hinge),
    Slosh(Slosh),
}

impl Moving {
    fn width(&self) -> usize {
        match self {
            Moving::Slosh(_) => 6,
            _ => 2,
        }
    }

    fn mass(&self) -> f64 {
        match self {
            Moving::Spring(p) => p.mass(),
            Moving::Hinge(p) => p.mass(),
            Moving::Slosh(p) => p.mass(),
        }
    }

    /// What it carries at its state `s`, and its momenta in the joint solve's order.
    fn carried(&self, s: &[f64]) -> (Carried, Vec<f64>) {
        match self {
            Moving::Spring(p) => (p.carried(s[0]), vec![s[1]]),
            Moving::Hinge(p) => (p.carried(&p.pose(s[0])), vec![s[1]]),
            Moving::Slosh(p) => {
                let rod = Rod::along(&Vector3::new(s[0], s[1], s[2]));
                let pi = Vector3::new(s[3], s[4], s[5]);
                (p.carried(&rod), p.momenta(&rod, &pi).to_vec())
            }
        }
    }
}

/// The parts' state of `configs` (a spring's `x`, a hinge's `β`, a rod's unit `n`) and
/// `rates` (`ẋ`, `β̇`, `ν`) with `H`, by the mass matrix: `[H, each part's state]`.
fn start(hub: &Hub, parts: &[Moving], configs: &[&[f64]], rates: &[&[f64]]) -> Vec<f64> {
    let mut x = vec![0.0; 3];
    let mut v = [0.0; MAX_RATES];
    let mut row = 0;
    for ((p, c), r) in parts.iter().zip(configs).zip(rates) {
        match p {
            Moving::Slosh(_) => {
                let rod = Rod::along(&Vector3::new(c[0], c[1], c[2]));
                let nu = Vector3::new(r[0], r[1], r[2]);
                [v[row], v[row + 1]] = rod.rates_of(&nu);
                x.extend_from_slice(&[c[0], c[1], c[2], 0.0, 0.0, 0.0]);
                row += 2;
            }
            _ => {
                v[row] = r[0];
                x.extend_from_slice(&[c[0], 0.0]);
                row += 1;
            }
        }
    }
    let carried: Vec<Carried> = at(parts, &x).into_iter().map(|(c, _)| c).collect();
    let (h, p) = MassMatrix::<MAX_RATES>::assemble(hub, &carried).apply(&Vector3::from(OMEGA0), &v);
    x[..3].copy_from_slice(h.as_slice());
    let (mut k, mut row) = (3, 0);
    for (part, c) in parts.iter().zip(&carried) {
        match part {
            Moving::Slosh(_) => {
                let rod = Rod::along(&Vector3::new(x[k], x[k + 1], x[k + 2]));
                let pi = rod.momentum_of([p[row], p[row + 1]]);
                x[k + 3..k + 6].copy_from_slice(pi.as_slice());
            }
            _ => x[k + 1] = p[row],
        }
        k += part.width();
        row += c.rates;
    }
    x
}

/// What each part carries at `x`, with its momenta.
fn at(parts: &[Moving], x: &[f64]) -> Vec<(Carried, Vec<f64>)> {
    let mut k = 3;
    parts
        .iter()
        .map(|p| {
            let c = p.carried(&x[k..k + p.width()]);
            k += p.width();
            c
        })
        .collect()
}

/// `(ω, x')` of the state `x` by the general joint solve.
fn rhs(hub: &Hub, parts: &[Moving], x: &[f64]) -> (Vector3<f64>, Vec<f64>) {
    let carried = at(parts, x);
    let mut p = [0.0; MAX_RATES];
    let mut row = 0;
    for (c, m) in &carried {
        p[row..row + m.len()].copy_from_slice(m);
        row += c.rates;
    }
    let list: Vec<Carried> = carried.iter().map(|(c, _)| *c).collect();
    let h = Vector3::new(x[0], x[1], x[2]);
    let moved = motion::<MAX_RATES>(hub, &list, &h, &p);
    let omega = moved.omega;
    let mut dx = h.cross(&omega).as_slice().to_vec();
    let (mut k, mut row) = (3, 0);
    for (part, c) in parts.iter().zip(&list) {
        let s = &x[k..k + part.width()];
        let (velocity, spin) = moved.element(c, row);
        let v = moved.rates[row];
        match part {
            Moving::Spring(m) => {
                dx.extend_from_slice(&[v, m.momentum_rate(s[0], v, &omega, &velocity)]);
            }
            Moving::Hinge(m) => {
                let dp = m.momentum_rate(&m.pose(s[0]), s[0], v, &omega, &velocity, &spin);
                dx.extend_from_slice(&[v, dp]);
            }
            Moving::Slosh(m) => {
                let n = Vector3::new(s[0], s[1], s[2]);
                let rod = Rod::along(&n);
                let nu = rod.spin([v, moved.rates[row + 1]]);
                let pi = Vector3::new(s[3], s[4], s[5]);
                let (dn, dpi) = m.rates(&n, &pi, &rod, &nu, &omega, &velocity);
                dx.extend_from_slice(dn.as_slice());
                dx.extend_from_slice(dpi.as_slice());
            }
        }
        k += part.width();
        row += c.rates;
    }
    (omega, dx)
}

/// The run of `parts` from `configs` and `rates` against the reference's RK4 over `T_END`.
fn check(parts: &[Moving], configs: &[&[f64]], rates: &[&[f64]], out: &RunOutput) {
    assert_kept(out);
    let carried: f64 = parts.iter().map(Moving::mass).sum();
    let hub = Hub::try_new(tensor(), HUB_MASS, carried).unwrap();
    let mut x = start(&hub, parts, configs, rates);
    let steps = (T_END / H).round() as usize;
    let f = |y: &[f64]| rhs(&hub, parts, y).1;
    let add = |y: &[f64], k: &[f64], s: f64| -> Vec<f64> {
        y.iter().zip(k).map(|(a, b)| a + s * b).collect()
    };
    for _ in 0..steps {
        let k1 = f(&x);
        let k2 = f(&add(&x, &k1, 0.5 * H));
        let k3 = f(&add(&x, &k2, 0.5 * H));
        let k4 = f(&add(&x, &k3, H));
        for j in 0..x.len() {
            x[j] += H / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
        }
    }
    let (omega, _) = rhs(&hub, parts, &x);
    close(&out.end.omega, omega.as_slice(), 1e-10);
    close(&out.end.parts[..x.len() - 3], &x[3..], 1e-10);
}

fn spring() -> SpringMass {
    let fields = Fields::new()
        .with("mass", Value::Number(0.3))
        .with("anchor", Value::Vector([0.4, -0.3, 0.6]))
        .with("direction", Value::Vector([0.2, 0.9, -0.4]))
        .with("stiffness", Value::Number(2.0))
        .with("damping", Value::Number(0.15))
        .with("x0", Value::Number(0.05))
        .with("rate0", Value::Number(0.2));
    SpringMass::from_fields(&fields).unwrap()
}

fn panel() -> Hinge {
    let fields = Fields::new()
        .with("mass", Value::Number(0.25))
        .with("moments", Value::Vector([0.01, 0.03, 0.035]))
        .with("hinge", Value::Vector([0.8, 0.5, -0.2]))
        .with("axis", Value::Vector([0.1, 1.0, 0.3]))
        .with("arm", Value::Vector([1.0, -0.1, 0.2]))
        .with("length", Value::Number(0.6))
        .with("stiffness", Value::Number(0.7))
        .with("damping", Value::Number(0.05))
        .with("angle0", Value::Number(0.3))
        .with("rate0", Value::Number(-0.4));
    Hinge::from_fields(&fields).unwrap()
}

const N0: [f64; 3] = [0.3, -0.8, 0.52];

fn tank() -> Slosh {
    let n0 = Vector3::from(N0).normalize();
    let fields = Fields::new()
        .with("mass", Value::Number(0.35))
        .with("pivot", Value::Vector([-0.5, 0.3, 0.7]))
        .with("length", Value::Number(0.45))
        .with("damping", Value::Number(0.04))
        .with("direction0", Value::Vector(n0.into()))
        .with("rate0", Value::Vector([0.1, 0.2, 0.3]));
    Slosh::from_fields(&fields).unwrap()
}

#[test]
fn a_spring_mass_damper_alone_runs_as_the_joint_solve() {
    let out = run(vec![spring().into()]);
    check(&[Moving::Spring(spring())], &[&[0.05]], &[&[0.2]], &out);
}

#[test]
fn a_hinged_panel_alone_runs_as_the_joint_solve() {
    let out = run(vec![panel().into()]);
    check(&[Moving::Hinge(panel())], &[&[0.3]], &[&[-0.4]], &out);
}

#[test]
fn a_slosh_pendulum_alone_runs_as_the_joint_solve() {
    let n0 = Vector3::from(N0).normalize();
    let out = run(vec![tank().into()]);
    check(
        &[Moving::Slosh(tank())],
        &[n0.as_slice()],
        &[&[0.1, 0.2, 0.3]],
        &out,
    );
}

#[test]
fn all_three_on_one_hub_run_as_the_joint_solve() {
    let n0 = Vector3::from(N0).normalize();
    let out = run(vec![spring().into(), panel().into(), tank().into()]);
    let parts = [
        Moving::Spring(spring()),
        Moving::Hinge(panel()),
        Moving::Slosh(tank()),
    ];
    let configs: [&[f64]; 3] = [&[0.05], &[0.3], n0.as_slice()];
    check(&parts, &configs, &[&[0.2], &[-0.4], &[0.1, 0.2, 0.3]], &out);
}
