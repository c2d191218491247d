//! Round-off over long runs (Brouwer's law): how the error of the invariants a method keeps in
//! exact arithmetic grows with the number of steps, over an ensemble of perturbed starts of
//! Hairer, Lubich & Wanner's free body, for the splittings with and without compensated
//! summation (and without the pull-back of the norms, to show their raw round-off), and for
//! the projected RK4, the DMV and the implicit midpoint rule.
//!
//! ```text
//! cargo bench --bench brouwer -- [--steps 1e7] [--starts 64] [--h 0.1] [--out FILE]
//!                                [--methods splitting,rk4_projected,...]
//! cargo bench --bench brouwer -- --cost
//! ```
//!
//! `--cost` times instead the splittings with compensated summation against without, 40
//! times alternately, in CPU time of the thread (`/proc/thread-self/schedstat`; wall time
//! elsewhere), and prints the median ratio and quartiles: the price of the compensation.
//!
//! Prints (or writes to FILE) one CSV row per method, variant and checkpoint `n` (1, 2, 5, 10,
//! … up to `--steps`): the root mean square over the starts of the relative errors of the
//! energy, `|L|`, `L_world` (relative to `|L|`) and `|q|`. `python benches/atlas.py brouwer`
//! runs this, fits the slopes of log error against log n and draws the figure. If round-off
//! errors were independent from step to step, the errors would grow like a random walk,
//! `√n` (slope 1/2: Brouwer's law); a bias that repeats step after step grows like `n`.

use std::io::Write;
use std::time::Instant;

use dzhanibekov::ode::Stepper;
use dzhanibekov::rigid::{
    Dmv, ImplicitMidpoint, Rk4Projected, Splitting, Splitting2, Splitting4, Splitting6,
};
use dzhanibekov::{FreeRigidBody, RigidBody, State};
use rayon::prelude::*;

const HLW: [f64; 3] = [2.0, 1.0, 2.0 / 3.0];

/// SplitMix64: a start's perturbation from its index, the same on every machine.
fn uniform(seed: u64, k: u64) -> f64 {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(k.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// Start `i`: HLW's angular momentum `(cos 1.1, 0, sin 1.1)` moved by up to 0.05 in each
/// component, and a random attitude.
fn start(i: u64) -> State {
    let l = [
        1.1f64.cos() + 0.05 * uniform(i, 0),
        0.05 * uniform(i, 1),
        1.1f64.sin() + 0.05 * uniform(i, 2),
    ];
    let q = [0, 1, 2, 3].map(|k| uniform(i, 3 + k));
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    [
        l[0] / HLW[0],
        l[1] / HLW[1],
        l[2] / HLW[2],
        q[0] / n,
        q[1] / n,
        q[2] / n,
        q[3] / n,
    ]
}

/// `[energy, |L|, L_world, |q|]` of a state (`[ω, q]`).
fn invariants(x: &State) -> ([f64; 3], [f64; 3]) {
    let l = [HLW[0] * x[0], HLW[1] * x[1], HLW[2] * x[2]];
    let energy = HLW[0] * x[0] * x[0] + HLW[1] * x[1] * x[1] + HLW[2] * x[2] * x[2];
    let l_norm = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let q = nalgebra::Quaternion::new(x[3], x[4], x[5], x[6]);
    let world = dzhanibekov::kinematics::rotation_matrix(&q) * nalgebra::Vector3::from(l);
    let q_norm = q.norm();
    ([energy, l_norm, q_norm], [world.x, world.y, world.z])
}

/// Relative errors `[energy, |L|, L_world, |q|]` of `x` against the start `x0`.
fn errors(x: &State, x0: &State) -> [f64; 4] {
    let ((a, aw), (b, bw)) = (invariants(x), invariants(x0));
    let dw = ((aw[0] - bw[0]).powi(2) + (aw[1] - bw[1]).powi(2) + (aw[2] - bw[2]).powi(2)).sqrt();
    [
        (a[0] / b[0] - 1.0).abs(),
        (a[1] / b[1] - 1.0).abs(),
        dw / b[1],
        (a[2] - 1.0).abs(),
    ]
}

/// The RMS over `starts` runs of the errors at each checkpoint.
fn study<M, F>(make: F, h: f64, checkpoints: &[u64], starts: u64) -> Vec<[f64; 4]>
where
    M: Stepper<7, FreeRigidBody>,
    F: Fn(&RigidBody, &State) -> M + Sync,
{
    let body = RigidBody::try_new(HLW).expect("HLW's moments are positive");
    let sys = FreeRigidBody::new(body);
    let per_start: Vec<Vec<[f64; 4]>> = (0..starts)
        .into_par_iter()
        .map(|i| {
            let x0 = start(i);
            let method = make(&body, &x0);
            let mut x = method.to_internal(&sys, &x0);
            let mut n = 0u64;
            checkpoints
                .iter()
                .map(|&c| {
                    while n < c {
                        method.step(&sys, 0.0, h, &mut x);
                        n += 1;
                    }
                    errors(&method.to_state(&sys, &x), &x0)
                })
                .collect()
        })
        .collect();
    (0..checkpoints.len())
        .map(|k| {
            std::array::from_fn(|j| {
                let sum: f64 = per_start.iter().map(|e| e[k][j] * e[k][j]).sum();
                (sum / starts as f64).sqrt()
            })
        })
        .collect()
}

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

/// CPU ns per step of `method` over `n` steps of `h` from `x0`.
fn per_step<const F: usize>(method: &Splitting<F>, x0: &State, n: u64) -> f64 {
    let sys = FreeRigidBody::new(RigidBody::try_new(HLW).expect("positive moments"));
    let mut x = method.to_internal(&sys, x0);
    let start = thread_ns();
    for _ in 0..n {
        method.step(&sys, 0.0, std::hint::black_box(0.1), &mut x);
    }
    std::hint::black_box(x);
    (thread_ns() - start) / n as f64
}

/// The median, first and third quartile of the compensated splittings' cost over the plain.
fn cost() {
    let body = RigidBody::try_new(HLW).expect("positive moments");
    let x0 = start(0);
    let mut ratios = [vec![], vec![], vec![]];
    for _ in 0..40 {
        let (a, b) = (Splitting2::new(&body, &x0), Splitting2::new(&body, &x0));
        ratios[0].push(per_step(&a, &x0, 100_000) / per_step(&b.compensated(false), &x0, 100_000));
        let (a, b) = (Splitting4::new(&body, &x0), Splitting4::new(&body, &x0));
        ratios[1].push(per_step(&a, &x0, 30_000) / per_step(&b.compensated(false), &x0, 30_000));
        let (a, b) = (Splitting6::new(&body, &x0), Splitting6::new(&body, &x0));
        ratios[2].push(per_step(&a, &x0, 20_000) / per_step(&b.compensated(false), &x0, 20_000));
    }
    for (name, r) in ["splitting", "splitting4", "splitting6"]
        .iter()
        .zip(&mut ratios)
    {
        r.sort_by(f64::total_cmp);
        println!(
            "{name}: compensated / plain per step, median {:.3} (quartiles {:.3}–{:.3})",
            r[20], r[10], r[30]
        );
    }
}

struct Args {
    steps: u64,
    starts: u64,
    h: f64,
    out: Option<String>,
    methods: Vec<String>,
}

fn args() -> Args {
    let mut a = Args {
        steps: 10_000_000,
        starts: 64,
        h: 0.1,
        out: None,
        methods: ["splitting", "rk4_projected", "dmv", "implicit_midpoint"]
            .map(String::from)
            .to_vec(),
    };
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut it = argv.iter();
    // (`cargo bench` adds `--bench`; anything unknown is ignored)
    while let Some(flag) = it.next() {
        let mut value = || it.next().cloned().unwrap_or_default();
        match flag.as_str() {
            "--steps" => a.steps = value().parse::<f64>().map_or(a.steps, |v| v as u64),
            "--starts" => a.starts = value().parse().unwrap_or(a.starts),
            "--h" => a.h = value().parse().unwrap_or(a.h),
            "--out" => a.out = Some(value()),
            "--methods" => a.methods = value().split(',').map(String::from).collect(),
            _ => {}
        }
    }
    a
}

fn main() {
    if std::env::args().any(|a| a == "--cost") {
        cost();
        return;
    }
    let a = args();
    let mut checkpoints = vec![];
    let mut decade = 1u64;
    'outer: loop {
        for m in [1, 2, 5] {
            let c = m * decade;
            if c > a.steps {
                break 'outer;
            }
            checkpoints.push(c);
        }
        decade *= 10;
    }
    let mut rows = vec!["method,variant,n,energy,momentum,momentum_world,q_norm".to_string()];
    let mut record = |method: &str, variant: &str, result: Vec<[f64; 4]>, seconds: f64| {
        eprintln!("{method} ({variant}): {seconds:.1} s");
        for (c, e) in checkpoints.iter().zip(result) {
            rows.push(format!(
                "{method},{variant},{c},{:.4e},{:.4e},{:.4e},{:.4e}",
                e[0], e[1], e[2], e[3]
            ));
        }
    };
    let (h, n, s) = (a.h, &checkpoints[..], a.starts);
    for method in &a.methods {
        let t = Instant::now();
        match method.as_str() {
            "splitting" | "splitting4" => {
                for (variant, compensated, renormalized) in [
                    ("plain", false, true),
                    ("compensated", true, true),
                    ("plain (no pull-back)", false, false),
                    ("compensated (no pull-back)", true, false),
                ] {
                    let t = Instant::now();
                    let result = if method == "splitting" {
                        study(
                            |b, x| {
                                Splitting2::new(b, x)
                                    .compensated(compensated)
                                    .renormalized(renormalized)
                            },
                            h,
                            n,
                            s,
                        )
                    } else {
                        study(
                            |b, x| {
                                Splitting4::new(b, x)
                                    .compensated(compensated)
                                    .renormalized(renormalized)
                            },
                            h,
                            n,
                            s,
                        )
                    };
                    record(method, variant, result, t.elapsed().as_secs_f64());
                }
                continue;
            }
            "rk4_projected" => record(
                method,
                "plain",
                study(
                    |b, x| Rk4Projected::new(&FreeRigidBody::new(*b), x),
                    h,
                    n,
                    s,
                ),
                t.elapsed().as_secs_f64(),
            ),
            "dmv" => record(
                method,
                "plain",
                study(Dmv::new, h, n, s),
                t.elapsed().as_secs_f64(),
            ),
            "implicit_midpoint" => record(
                method,
                "plain",
                study(ImplicitMidpoint::new, h, n, s),
                t.elapsed().as_secs_f64(),
            ),
            other => eprintln!("unknown method {other}, skipped"),
        }
    }
    let text = rows.join("\n") + "\n";
    match a.out {
        Some(path) => std::fs::write(&path, text).expect("the output file is writable"),
        None => std::io::stdout()
            .write_all(text.as_bytes())
            .expect("stdout is writable"),
    }
}
