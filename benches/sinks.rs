//! Criterion benches of one evaluation of an energy sink's right-hand side on its hub, beside
//! the free body's (`ω = I⁻¹H`, `H × ω`): `cargo bench --bench sinks` (`-- --quick` for a
//! short pass). Each evaluation is chained into the next by an Euler step of `h = 10⁻⁶` (the
//! state stays where it started), so the figure is the evaluation's latency, as in RK4, not
//! the throughput of independent ones. Each part runs two ways: through the general joint
//! solve of any parts (what a part carries, the mass matrix, its `LDLᵀ` and Schur complement,
//! the element's velocity) and through its closed form alone on its hub (`LoneSpring`,
//! `LoneHinge`, `LoneSlosh`). The general solve runs in a buffer sized for the part (`/general`:
//! 1 rate, 2 for the pendulum) and in the general model's one capacity, [`MAX_RATES`]
//! (`/general_max`), as a run of several parts takes it. Timed twice: in CPU time of the thread
//! (`/proc/thread-self/schedstat`, group `sinks_cpu`; wall time where it is absent) and in
//! wall time (`sinks_wall`). The groups `rk4_cpu` and `rk4_wall` take one RK4 step (`h =
//! 10⁻³`) of the whole state — `H`, the part's, the attitude quaternion — with each closed
//! form and with the free body's `ω = I⁻¹H`, by one plain RK4 written here for all four: the
//! issue's ratio per RK4 step before the parts reach the run's models.

use std::hint::black_box;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix3, Vector3};

use dzhanibekov::dynamics::multibody::{motion, Carried, Hub, MAX_RATES};
use dzhanibekov::dynamics::{Hinge, LoneHinge, LoneSlosh, LoneSpring, Rod, Slosh, SpringMass};

/// Nanoseconds of CPU time of this thread so far (wall time where Linux's schedstat is absent).
fn thread_ns() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| {
            let epoch = std::time::UNIX_EPOCH.elapsed().unwrap_or_default();
            epoch.as_nanos() as f64
        })
}

/// CPU time of the bench's thread.
struct CpuTime;

impl Measurement for CpuTime {
    type Intermediate = f64;
    type Value = f64;

    fn start(&self) -> f64 {
        thread_ns()
    }

    fn end(&self, start: f64) -> f64 {
        thread_ns() - start
    }

    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }

    fn zero(&self) -> f64 {
        0.0
    }

    fn to_f64(&self, value: &f64) -> f64 {
        *value
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        // nanoseconds, as the wall clock's
        let wall: &'static WallTime = &WallTime;
        wall.formatter()
    }
}

const H: f64 = 1e-6;

/// The hub: the models bench's body (moments 1, 2, 3) with a mass of 5.
fn hub(carried: f64) -> Hub {
    Hub::try_new(
        Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)),
        5.0,
        carried,
    )
    .unwrap()
}

fn spring() -> SpringMass {
    SpringMass::try_new(0.1, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], 2.0, 0.05).unwrap()
}

fn panel() -> Hinge {
    Hinge::try_new(
        0.1,
        [0.0, 0.003, 0.003],
        [0.5, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        0.3,
        0.5,
        0.01,
    )
    .unwrap()
}

fn tank() -> Slosh {
    Slosh::try_new(0.1, [0.5, 0.0, 0.0], 0.3, 0.01).unwrap()
}

/// The start: `H` of a spin about the major axis, slightly off, and each part a little moved.
const H0: [f64; 3] = [0.01, 0.02, 3.0];

/// An Euler step of `H` over the spring's general joint solve in a buffer of `K` rates.
#[inline(always)]
fn spring_general<const K: usize>(
    part: &SpringMass,
    hub: &Hub,
    (hm, x, p): (Vector3<f64>, f64, f64),
) -> (Vector3<f64>, f64, f64) {
    let carried = [part.carried(x)];
    let mut momenta = [0.0; K];
    momenta[0] = p;
    let moved = motion::<K>(hub, &carried, &hm, &momenta);
    let (velocity, _) = moved.element(&carried[0], 0);
    let v = moved.rates[0];
    let dp = part.momentum_rate(x, v, &moved.omega, &velocity);
    (hm + hm.cross(&moved.omega) * H, x + v * H, p + dp * H)
}

/// The same for the hinge.
#[inline(always)]
fn hinge_general<const K: usize>(
    part: &Hinge,
    hub: &Hub,
    (hm, beta, p): (Vector3<f64>, f64, f64),
) -> (Vector3<f64>, f64, f64) {
    let pose = part.pose(beta);
    let carried = [part.carried(&pose)];
    let mut momenta = [0.0; K];
    momenta[0] = p;
    let moved = motion::<K>(hub, &carried, &hm, &momenta);
    let (velocity, spin) = moved.element(&carried[0], 0);
    let v = moved.rates[0];
    let dp = part.momentum_rate(&pose, beta, v, &moved.omega, &velocity, &spin);
    (hm + hm.cross(&moved.omega) * H, beta + v * H, p + dp * H)
}

/// The same for the pendulum.
#[inline(always)]
fn slosh_general<const K: usize>(
    part: &Slosh,
    hub: &Hub,
    (hm, n, pi): (Vector3<f64>, Vector3<f64>, Vector3<f64>),
) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let rod = Rod::along(&n);
    let carried: [Carried; 1] = [part.carried(&rod)];
    let mut momenta = [0.0; K];
    momenta[..2].copy_from_slice(&part.momenta(&rod, &pi));
    let moved = motion::<K>(hub, &carried, &hm, &momenta);
    let (velocity, _) = moved.element(&carried[0], 0);
    let nu = rod.spin([moved.rates[0], moved.rates[1]]);
    let (dn, dpi) = part.rates(&n, &pi, &rod, &nu, &moved.omega, &velocity);
    (hm + hm.cross(&moved.omega) * H, n + dn * H, pi + dpi * H)
}

fn bench<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let mut g = c.benchmark_group(group);
    g.sample_size(20);

    let inv = Vector3::new(1.0, 0.5, 1.0 / 3.0);
    let mut h = Vector3::from(H0);
    g.bench_function("free", |b| {
        b.iter(|| {
            let x = black_box(h);
            let omega = x.component_mul(&inv);
            h = x + x.cross(&omega) * H;
        })
    });

    let part = spring();
    let hub1 = hub(part.mass());
    let mut state = (Vector3::from(H0), 0.01, 0.0);
    g.bench_function("spring_mass/general", |b| {
        b.iter(|| state = spring_general::<1>(&part, &hub1, black_box(state)))
    });
    let mut state = (Vector3::from(H0), 0.01, 0.0);
    g.bench_function("spring_mass/general_max", |b| {
        b.iter(|| state = spring_general::<MAX_RATES>(&part, &hub1, black_box(state)))
    });
    let lone = LoneSpring::new(&hub1, part);
    let mut state = (Vector3::from(H0), 0.01, 0.0);
    g.bench_function("spring_mass/alone", |b| {
        b.iter(|| {
            let (hm, x, p) = black_box(state);
            let (omega, v) = lone.rates(&hm, x, p);
            let dp = lone.momentum_rate(x, v, &omega);
            state = (hm + hm.cross(&omega) * H, x + v * H, p + dp * H);
        })
    });

    let part = panel();
    let hub1 = hub(part.mass());
    let mut state = (Vector3::from(H0), 0.05, 0.0);
    g.bench_function("hinge/general", |b| {
        b.iter(|| state = hinge_general::<1>(&part, &hub1, black_box(state)))
    });
    let mut state = (Vector3::from(H0), 0.05, 0.0);
    g.bench_function("hinge/general_max", |b| {
        b.iter(|| state = hinge_general::<MAX_RATES>(&part, &hub1, black_box(state)))
    });
    let lone = LoneHinge::new(&hub1, part);
    let mut state = (Vector3::from(H0), 0.05, 0.0);
    g.bench_function("hinge/alone", |b| {
        b.iter(|| {
            let (hm, beta, p) = black_box(state);
            let (omega, v, cos, sin) = lone.rates(&hm, beta, p);
            let dp = lone.momentum_rate(beta, cos, sin, v, &omega);
            state = (hm + hm.cross(&omega) * H, beta + v * H, p + dp * H);
        })
    });

    let part = tank();
    let hub1 = hub(part.mass());
    let start = (
        Vector3::from(H0),
        Vector3::new(1.0, 0.1, 0.0).normalize(),
        Vector3::zeros(),
    );
    let mut state = start;
    g.bench_function("slosh/general", |b| {
        b.iter(|| state = slosh_general::<2>(&part, &hub1, black_box(state)))
    });
    let mut state = start;
    g.bench_function("slosh/general_max", |b| {
        b.iter(|| state = slosh_general::<MAX_RATES>(&part, &hub1, black_box(state)))
    });
    let lone = LoneSlosh::new(&hub1, part);
    let mut state = start;
    g.bench_function("slosh/alone", |b| {
        b.iter(|| {
            let (hm, n, pi) = black_box(state);
            let r = lone.rates(&hm, &n, &pi);
            state = (
                hm + hm.cross(&r.omega) * H,
                n + r.direction * H,
                pi + r.momentum * H,
            );
        })
    });
    g.finish();
}

/// One RK4 step of `h` of `x' = f(x)`.
#[inline(always)]
fn rk4<const N: usize>(f: impl Fn(&[f64; N]) -> [f64; N], x: &[f64; N], h: f64) -> [f64; N] {
    let at = |k: &[f64; N], s: f64| std::array::from_fn(|j| x[j] + s * k[j]);
    let k1 = f(x);
    let k2 = f(&at(&k1, 0.5 * h));
    let k3 = f(&at(&k2, 0.5 * h));
    let k4 = f(&at(&k3, h));
    std::array::from_fn(|j| x[j] + h / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]))
}

/// `q' = ½ q ⊗ (0, ω)` (scalar first).
#[inline(always)]
fn attitude(q: &[f64], w: &Vector3<f64>) -> [f64; 4] {
    [
        -0.5 * (q[1] * w.x + q[2] * w.y + q[3] * w.z),
        0.5 * (q[0] * w.x + q[2] * w.z - q[3] * w.y),
        0.5 * (q[0] * w.y + q[3] * w.x - q[1] * w.z),
        0.5 * (q[0] * w.z + q[1] * w.y - q[2] * w.x),
    ]
}

fn v3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

fn steps<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let mut g = c.benchmark_group(group);
    g.sample_size(20);
    let h = 1e-3;
    let q0 = [1.0, 0.0, 0.0, 0.0];

    let inv = Vector3::new(1.0, 0.5, 1.0 / 3.0);
    let free = |x: &[f64; 7]| {
        let m = v3(x);
        let omega = m.component_mul(&inv);
        let dm = m.cross(&omega);
        let dq = attitude(&x[3..], &omega);
        [dm.x, dm.y, dm.z, dq[0], dq[1], dq[2], dq[3]]
    };
    let mut x = [H0[0], H0[1], H0[2], q0[0], q0[1], q0[2], q0[3]];
    g.bench_function("free", |b| b.iter(|| x = rk4(free, &black_box(x), h)));

    let part = spring();
    let lone = LoneSpring::new(&hub(part.mass()), part);
    let spring = |x: &[f64; 9]| {
        let m = v3(x);
        let (omega, v) = lone.rates(&m, x[3], x[4]);
        let dp = lone.momentum_rate(x[3], v, &omega);
        let dm = m.cross(&omega);
        let dq = attitude(&x[5..], &omega);
        [dm.x, dm.y, dm.z, v, dp, dq[0], dq[1], dq[2], dq[3]]
    };
    let mut x = [H0[0], H0[1], H0[2], 0.01, 0.0, q0[0], q0[1], q0[2], q0[3]];
    g.bench_function("spring_mass", |b| {
        b.iter(|| x = rk4(spring, &black_box(x), h))
    });

    let part = panel();
    let lone = LoneHinge::new(&hub(part.mass()), part);
    let hinge = |x: &[f64; 9]| {
        let m = v3(x);
        let (omega, v, cos, sin) = lone.rates(&m, x[3], x[4]);
        let dp = lone.momentum_rate(x[3], cos, sin, v, &omega);
        let dm = m.cross(&omega);
        let dq = attitude(&x[5..], &omega);
        [dm.x, dm.y, dm.z, v, dp, dq[0], dq[1], dq[2], dq[3]]
    };
    let mut x = [H0[0], H0[1], H0[2], 0.05, 0.0, q0[0], q0[1], q0[2], q0[3]];
    g.bench_function("hinge", |b| b.iter(|| x = rk4(hinge, &black_box(x), h)));

    let part = tank();
    let lone = LoneSlosh::new(&hub(part.mass()), part);
    let slosh = |x: &[f64; 13]| {
        let m = v3(x);
        let r = lone.rates(&m, &v3(&x[3..]), &v3(&x[6..]));
        let dm = m.cross(&r.omega);
        let dq = attitude(&x[9..], &r.omega);
        let (dn, dp) = (r.direction, r.momentum);
        [
            dm.x, dm.y, dm.z, dn.x, dn.y, dn.z, dp.x, dp.y, dp.z, dq[0], dq[1], dq[2], dq[3],
        ]
    };
    let mut x = [
        H0[0], H0[1], H0[2], 1.0, 0.1, 0.0, 0.0, 0.0, 0.0, q0[0], q0[1], q0[2], q0[3],
    ];
    let norm = v3(&x[3..]).norm();
    x[3..6].iter_mut().for_each(|c| *c /= norm);
    g.bench_function("slosh", |b| b.iter(|| x = rk4(slosh, &black_box(x), h)));
    g.finish();
}

fn cpu(c: &mut Criterion<CpuTime>) {
    bench(c, "sinks_cpu");
    steps(c, "rk4_cpu");
}

fn wall(c: &mut Criterion) {
    bench(c, "sinks_wall");
    steps(c, "rk4_wall");
}

criterion_group! {
    name = cpu_group;
    config = Criterion::default().with_measurement(CpuTime);
    targets = cpu
}
criterion_group!(wall_group, wall);
criterion_main!(cpu_group, wall_group);
