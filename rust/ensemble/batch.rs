//! Many runs at once on all cores: a batch of starts (bodies, rates, attitudes) over one
//! frame grid.
//!
//! RK4 runs in groups of [`LANES`] runs in SIMD lanes ([`crate::ensemble::lanes`]), the groups spread
//! over the cores by rayon. Every other method runs as single runs, one per row, spread over
//! the cores the same way. Either way a row performs exactly the floating-point operations of
//! the single run of its inputs ([`crate::run::simulate`]), so it equals that run bit for
//! bit, and no result depends on the number of threads or on how rows fall into groups.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::body::RigidBody;
use crate::buffer::{try_collect_results, try_with_capacity, zeroed_for};
use crate::dynamics::{state_from, FreeRigidBody, State};
use crate::ensemble::lanes::{advance, Isa, Lanes, Span};
use crate::error::{Error, Result};
use crate::float::RateScale;
use crate::kinematics::normalized;
use crate::observe::tilt::TiltMonitor;
use crate::observe::{Drift, DriftMonitor, FlipDetector, Observer};
use crate::ode::Stats;
use crate::run::step_size::{plan, StepPlan};
use crate::run::{finite_drift, simulate, FrameGrid, Keep, Method, CHECK_EVERY, DIVERGED_HINT};

/// Runs integrated together in one group of SIMD lanes: two AVX-512 vectors, four AVX2 ones.
pub const LANES: usize = 16;

/// What to say when a batch's frames would not fit.
const FRAMES_HINT: &str = "ask for fewer runs or frames, or use `sweep` (or `summarize`) for \
                           per-run summaries, which keep no frames";

/// The start of one run of a batch: its body, body rates and attitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    pub body: RigidBody,
    pub omega0: [f64; 3],
    /// As given (a single run normalises it; so does the batch, in the same way).
    pub q0: [f64; 4],
}

impl Start {
    /// A run's start, checked as [`simulate`] checks it.
    ///
    /// # Errors
    /// Bad moments, non-finite rates, a zero or non-finite quaternion.
    pub fn try_new(inertia: [f64; 3], omega0: [f64; 3], q0: [f64; 4]) -> Result<Self> {
        let body = RigidBody::try_new(inertia)?;
        if !omega0.iter().all(|w| w.is_finite()) {
            return Err(Error::invalid(
                "omega0",
                "must be three finite body rates",
                omega0,
            ));
        }
        normalized(q0)?;
        Ok(Self { body, omega0, q0 })
    }

    /// The starts of rows of `inertia` (one row, or one per start), `omega0` and `q0` (one
    /// row, or one per start), flat and row-major; errors name the row.
    ///
    /// # Errors
    /// As [`Start::try_new`], and lengths that are not whole rows of the same count.
    pub fn rows(inertia: &[f64], omega0: &[f64], q0: &[f64]) -> Result<Vec<Start>> {
        let m = omega0.len() / 3;
        let shape_ok = |len: usize, width: usize| len == width || len == width * m;
        if !omega0.len().is_multiple_of(3) || !shape_ok(inertia.len(), 3) || !shape_ok(q0.len(), 4)
        {
            return Err(Error::InvalidArgument {
                name: "inertia, omega0, q0",
                allowed: "must have shapes (M, 3) or (3,), (M, 3), and (M, 4) or (4,)".into(),
                got: format!(
                    "{} / 3, {} / 3 and {} / 4 rows",
                    inertia.len(),
                    omega0.len(),
                    q0.len()
                ),
            });
        }
        let row = |v: &[f64], w: usize, i: usize| if v.len() == w { 0 } else { i * w };
        let starts = (0..m).map(|i| {
            let (a, b, c) = (row(inertia, 3, i), 3 * i, row(q0, 4, i));
            Start::try_new(
                [inertia[a], inertia[a + 1], inertia[a + 2]],
                [omega0[b], omega0[b + 1], omega0[b + 2]],
                [q0[c], q0[c + 1], q0[c + 2], q0[c + 3]],
            )
            .map_err(|e| e.in_row(i))
        });
        try_collect_results(starts, m, "the starts", "run fewer starts at a time")
    }

    fn omega(&self) -> Vector3<f64> {
        Vector3::from(self.omega0)
    }
}

/// How a batch runs: on how many threads, with which instruction set.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Options {
    /// Threads to run on; `None` for the process's pool (all cores; see [`crate::pool`]).
    pub threads: Option<usize>,
    /// The SIMD instruction set of the RK4 lanes; `None` for the widest this CPU has.
    pub isa: Option<Isa>,
}

impl Options {
    /// Runs `work` on the threads asked for, at most one per run and at most
    /// [`MAX_THREADS`]. Pools are kept and reused: building one costs a thread start per
    /// thread.
    ///
    /// # Errors
    /// `threads` zero, or a pool that cannot be built; the errors of `work`.
    pub(crate) fn install<T: Send>(
        &self,
        runs: usize,
        work: impl FnOnce() -> Result<T> + Send,
    ) -> Result<T> {
        let Some(n) = self.threads else {
            return crate::pool::install(work)?;
        };
        if n == 0 {
            return Err(Error::invalid("threads", "must be at least 1", n));
        }
        pool(n.min(runs.max(1)).min(MAX_THREADS))?.install(work)
    }

    /// How many threads a call of `runs` runs uses at most (for its memory: one row's
    /// frames each).
    pub(crate) fn threads_for(&self, runs: usize) -> usize {
        match self.threads {
            Some(n) => n.min(runs.max(1)).min(MAX_THREADS),
            None => std::thread::available_parallelism()
                .map_or(1, |n| n.get())
                .min(runs.max(1)),
        }
    }

    /// The instruction set to run.
    ///
    /// # Errors
    /// One this CPU does not have.
    pub(crate) fn isa(&self) -> Result<Isa> {
        match self.isa {
            None => Ok(Isa::detect()),
            Some(isa) if isa.is_supported() => Ok(isa),
            Some(isa) => Err(Error::invalid(
                "isa",
                "must be an instruction set this CPU has",
                isa.name(),
            )),
        }
    }
}

/// The most threads a batch or sweep runs on; `threads` beyond it (or beyond the number of
/// runs) are capped.
pub const MAX_THREADS: usize = 256;

/// Pools kept for reuse, by size (the few last used), with the process they belong to: a
/// child made by `fork` has none of its parent's threads, so it builds its own.
static POOLS: Mutex<(u32, Vec<SizedPool>)> = Mutex::new((0, Vec::new()));

/// A pool and its number of threads.
type SizedPool = (usize, Arc<rayon::ThreadPool>);

/// Pools of as many sizes as are kept.
const POOLS_KEPT: usize = 4;

/// A pool of `n` threads, reused if one was built before in this process.
fn pool(n: usize) -> Result<Arc<rayon::ThreadPool>> {
    let mut guard = POOLS.lock().unwrap_or_else(PoisonError::into_inner);
    let (pid, pools) = &mut *guard;
    if *pid != std::process::id() {
        // the parent's pools have no threads here: forget them (dropping would wait on them)
        std::mem::forget(std::mem::take(pools));
        *pid = std::process::id();
    }
    if let Some((_, found)) = pools.iter().find(|(size, _)| *size == n) {
        return Ok(Arc::clone(found));
    }
    let built = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| Error::invalid("threads", "must give a thread pool", e.to_string()))?;
    let built = Arc::new(built);
    if pools.len() == POOLS_KEPT {
        pools.remove(0);
    }
    pools.push((n, Arc::clone(&built)));
    Ok(built)
}

/// The user's cancel flag, and the batch's own, set when a run fails so that the others stop.
pub(crate) struct Stop<'a> {
    pub(crate) cancel: &'a AtomicBool,
    abort: AtomicBool,
}

impl<'a> Stop<'a> {
    pub(crate) fn new(cancel: &'a AtomicBool) -> Self {
        Self {
            cancel,
            abort: AtomicBool::new(false),
        }
    }

    /// [`Error::Interrupted`] once the user or a failed run asked to stop.
    pub(crate) fn check(&self) -> Result<()> {
        if self.cancel.load(Ordering::Relaxed) || self.abort.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        Ok(())
    }

    /// `result`, and on a failure tells the other runs to stop.
    pub(crate) fn watch<T>(&self, result: Result<T>) -> Result<T> {
        if result.is_err() {
            self.abort.store(true, Ordering::Relaxed);
        }
        result
    }

    /// The results of every part of a batch, in order; or the first real error (a row's),
    /// rather than the interruptions it caused.
    pub(crate) fn gather<T>(&self, parts: Vec<Result<T>>) -> Result<Vec<T>> {
        if parts.iter().any(Result::is_err) {
            let mut errors = parts.into_iter().filter_map(Result::err);
            let first = errors.next().unwrap_or(Error::Interrupted);
            return Err(match first {
                Error::Interrupted => errors
                    .find(|e| !matches!(e, Error::Interrupted))
                    .unwrap_or(Error::Interrupted),
                e => e,
            });
        }
        let n = parts.len();
        crate::buffer::try_collect(
            parts.into_iter().filter_map(Result::ok),
            n,
            "the batch's rows",
            "run fewer starts at a time",
        )
    }
}

/// What a group of lanes watches and keeps.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Watch {
    /// Locate the flips.
    pub flips: bool,
    /// Track the tilt of the spin axis.
    pub tilt: bool,
    /// Keep only the count, first and last of the flip times (see [`FlipTally`]).
    pub count_only: bool,
}

/// The flips of a run, counted: how many, the first and the last.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipTally {
    pub count: u64,
    /// The first flip time; NaN if none.
    pub first: f64,
    /// The last flip time; NaN if none.
    pub last: f64,
}

impl Default for FlipTally {
    fn default() -> Self {
        Self {
            count: 0,
            first: f64::NAN,
            last: f64::NAN,
        }
    }
}

impl FlipTally {
    /// Counts the flips at `times` (in order, after those counted so far).
    pub fn absorb(&mut self, times: &[f64]) {
        if let (Some(&first), Some(&last)) = (times.first(), times.last()) {
            if self.count == 0 {
                self.first = first;
            }
            self.last = last;
            self.count += times.len() as u64;
        }
    }

    /// The measured flip period: the mean time between consecutive flips,
    /// `(last − first) / (count − 1)`; NaN with fewer than two flips.
    pub fn mean_period(&self) -> f64 {
        if self.count < 2 {
            return f64::NAN;
        }
        (self.last - self.first) / (self.count - 1) as f64
    }
}

/// Where a group's frames go: ω and q of its rows, each row's `(frames, 3)` and `(frames, 4)`
/// in turn; `None` when no frames are kept.
pub(crate) type Frames<'a> = Option<(&'a mut [f64], &'a mut [f64])>;

/// What one run of a group of lanes leaves.
#[derive(Debug, Clone)]
pub(crate) struct LaneRun {
    /// Every flip time, unless only counted.
    pub flip_times: Vec<f64>,
    pub flips: FlipTally,
    pub drift: Drift,
    /// The largest tilt of the spin axis (radians), if watched.
    pub tilt: f64,
}

/// Integrates `starts` (at most [`LANES`]; rows `first_row..` of the batch) by RK4 in SIMD
/// lanes over `grid`, as [`crate::run::integrate`] integrates each: the same steps, the same
/// observers shown the same frames and, when they would change, the same steps. Writes the
/// frames into `frames` (ω then q, each row's `(frames, 3)` and `(frames, 4)` in turn) if
/// given.
///
/// # Errors
/// [`Error::Interrupted`] soon after `stop` is set; a row's [`Error::Diverged`].
pub(crate) fn run_group(
    isa: Isa,
    starts: &[Start],
    first_row: usize,
    grid: &FrameGrid,
    watch: Watch,
    mut frames: Frames,
    stop: &Stop,
) -> Result<Vec<LaneRun>> {
    let real = starts.len();
    assert!(
        (1..=LANES).contains(&real),
        "a group holds 1 to {LANES} runs"
    );
    stop.check()?;
    // Spare lanes repeat the last run; their results are dropped.
    let start = |l: usize| &starts[l.min(real - 1)];
    let systems: [FreeRigidBody; LANES] =
        std::array::from_fn(|l| FreeRigidBody::new(start(l).body));
    let mut x0 = [[0.0; 7]; LANES];
    for (l, x) in x0.iter_mut().enumerate() {
        *x = state_from(start(l).omega0, normalized(start(l).q0)?);
    }
    let euler = systems.map(|s| s.euler_coefficients().into());
    let mut lanes = Lanes::<LANES>::new(&euler, &x0);
    let mut drift: Vec<DriftMonitor<'_, FreeRigidBody>> =
        systems[..real].iter().map(DriftMonitor::new).collect();
    let mut detectors: Vec<FlipDetector<'_, FreeRigidBody>> = match watch.flips {
        true => (0..LANES)
            .map(|l| FlipDetector::new(&systems[l], 0.0, &x0[l]))
            .collect(),
        false => Vec::new(),
    };
    let mut tilts: Vec<TiltMonitor> = match watch.tilt {
        true => (0..LANES)
            .map(|l| TiltMonitor::new(&start(l).body, &start(l).omega()))
            .collect(),
        false => Vec::new(),
    };
    let mut tallies = vec![FlipTally::default(); real];
    let n_frames = grid.frames();
    let record = |i: usize, l: usize, x: &State, frames: &mut Frames| {
        if let Some((omega, q)) = frames {
            let (a, b) = (3 * (l * n_frames + i), 4 * (l * n_frames + i));
            omega[a..a + 3].copy_from_slice(&x[..3]);
            q[b..b + 4].copy_from_slice(&x[3..]);
        }
    };
    for l in 0..LANES {
        let x = &x0[l];
        if l < real {
            drift[l].frame(0, 0.0, x);
            record(0, l, x, &mut frames);
        }
        if let Some(d) = detectors.get_mut(l) {
            d.frame(0, 0.0, x);
            lanes.watch_flips(l, d);
        }
        if let Some(t) = tilts.get_mut(l) {
            t.frame(0, 0.0, x);
            lanes.watch_tilt(l, t);
        }
    }
    let n = grid.substeps();
    for i in 1..n_frames {
        let (ta, tb) = (grid.time(i - 1), grid.time(i));
        let h = (tb - ta) / n as f64;
        let mut done = 0;
        while done < n {
            let to = done + (n - done).min(CHECK_EVERY);
            let span = Span {
                ta,
                tb,
                h,
                n,
                from: done,
                to,
            };
            advance(
                isa,
                &mut lanes,
                &mut detectors,
                span,
                watch.flips,
                watch.tilt,
            );
            done = to;
            stop.check()?;
            for l in 0..real {
                if !lanes.is_finite(l) {
                    let t = ta + done as f64 * h;
                    return Err(Error::Diverged {
                        t,
                        hint: DIVERGED_HINT,
                    }
                    .in_row(first_row + l));
                }
            }
            if watch.count_only {
                for (tally, d) in tallies.iter_mut().zip(&mut detectors) {
                    tally.absorb(&d.take_flip_times());
                }
            }
        }
        for (l, monitor) in drift.iter_mut().enumerate() {
            let x = lanes.state(l);
            monitor.frame(i, tb, &x);
            record(i, l, &x, &mut frames);
        }
    }
    // as a single run: invariants that overflow mean the run diverged
    for (l, monitor) in drift.iter().enumerate() {
        finite_drift(monitor.drift, grid.t_end()).map_err(|e| e.in_row(first_row + l))?;
        if let Some(d) = detectors.get(l) {
            d.check_kept().map_err(|e| e.in_row(first_row + l))?;
        }
    }
    Ok((0..real)
        .map(|l| {
            let flip_times = detectors
                .get_mut(l)
                .map(|d| d.take_flip_times())
                .unwrap_or_default();
            let mut flips = tallies[l];
            flips.absorb(&flip_times);
            let tilt = match tilts.get_mut(l) {
                Some(t) => {
                    t.set_lowest(lanes.tilt_lowest(l));
                    t.tilt()
                }
                None => f64::NAN,
            };
            LaneRun {
                flip_times,
                flips,
                drift: drift[l].drift,
                tilt,
            }
        })
        .collect())
}

/// A batch's output: only what [`Keep`] asked for is filled.
#[derive(Debug, Clone, Default)]
pub struct BatchOutput {
    /// `(M, frames, 3)` body rates, row-major; empty unless frames were kept.
    pub omega: Vec<f64>,
    /// `(M, frames, 4)` quaternions, scalar first; empty unless frames were kept.
    pub q: Vec<f64>,
    /// `(M, frames, k)` the parts' state; empty unless frames were kept and there are parts.
    pub parts: Vec<f64>,
    /// Row `i`'s flip times are `flip_times[flip_offsets[i]..flip_offsets[i + 1]]`.
    pub flip_offsets: Vec<usize>,
    pub flip_times: Vec<f64>,
    pub drift: Vec<Drift>,
    pub stats: Vec<Stats>,
    /// The step taken by each row; for an adaptive method, its mean accepted step.
    pub dt: Vec<f64>,
    /// Where each row ended (kept by batches of systems with parts or a schedule; empty for
    /// free bodies, whose last frame says it when frames are kept).
    pub end: Vec<crate::observe::End>,
    /// The time each row's spin went flat (NaN: not by the end); empty for batches whose rows
    /// are not watched (see [`crate::run::RunOutput::flat_time`]).
    pub flat_time: Vec<f64>,
}

impl BatchOutput {
    /// Appends a row's columns (its frames are in place already).
    ///
    /// # Errors
    /// [`Error::TooLarge`] if the flip times cannot be stored.
    pub(crate) fn push_row(
        &mut self,
        flip_times: Vec<f64>,
        drift: Drift,
        stats: Stats,
        dt: f64,
    ) -> Result<()> {
        self.flip_times
            .try_reserve(flip_times.len())
            .map_err(|_| Error::TooLarge {
                what: "keeping the batch's flip times".into(),
                needed: format!("{} values", self.flip_times.len() + flip_times.len()),
                limit: "the memory this process can allocate".into(),
                hint: "take a shorter t_end, or do not ask for the flips (`flips=False`)",
            })?;
        self.flip_times.extend_from_slice(&flip_times);
        self.flip_offsets.push(self.flip_times.len());
        self.drift.push(drift);
        self.stats.push(stats);
        self.dt.push(dt);
        Ok(())
    }
}

/// One row's part of a [`BatchOutput`], before it is put in place.
struct RowOutput {
    flip_times: Vec<f64>,
    drift: Drift,
    stats: Stats,
    dt: f64,
}

/// Simulates every start over `grid`, each as [`simulate`] would alone, on all cores.
///
/// RK4 runs in SIMD lanes (`run_group`); other methods as single runs, one per row.
/// Either way row `i` equals `simulate` of `starts[i]` bit for bit, whatever `options`.
///
/// # Errors
/// [`Error::TooLarge`] if the frames cannot be allocated; a row's error, naming the row
/// ([`Error::Row`]); [`Error::Interrupted`] soon after `cancel` is set.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use dzhanibekov::ensemble::batch::{simulate_batch, Options, Start};
/// use dzhanibekov::run::{simulate, FrameGrid, Keep, Method};
/// let grid = FrameGrid::try_new(10.0, 11, 1e-2, u64::MAX).unwrap();
/// let keep = Keep { frames: true, flips: true, tilt: false };
/// let starts = [
///     Start::try_new([52.0833, 27.0833, 41.6666], [0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]).unwrap(),
///     Start::try_new([1.0, 2.0, 3.0], [0.3, -0.2, 0.1], [0.5, 0.5, 0.5, 0.5]).unwrap(),
/// ];
/// let cancel = AtomicBool::new(false);
/// let batch = simulate_batch(&starts, &grid, Method::Rk4, keep, &Options::default(), &cancel).unwrap();
/// let one = simulate(&starts[1].body, starts[1].omega0, starts[1].q0, &grid, Method::Rk4, keep, &cancel).unwrap();
/// assert_eq!(batch.q[11 * 4..], one.q[..]);
/// ```
pub fn simulate_batch(
    starts: &[Start],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    options: &Options,
    cancel: &AtomicBool,
) -> Result<BatchOutput> {
    let m = starts.len();
    let isa = options.isa()?;
    // each row's output, held twice (per group, then in order), and the columns made from it
    let per_row = 2 * std::mem::size_of::<RowOutput>() + 16 * std::mem::size_of::<f64>();
    crate::buffer::ensure_room(
        m as f64 * per_row as f64,
        "the batch's rows",
        "run fewer starts at a time",
    )?;
    let (mut omega, mut q) = match keep.frames {
        true => {
            let values = |width: usize| m.checked_mul(grid.frames())?.checked_mul(width);
            let too_large = || Error::TooLarge {
                what: "keeping the batch's frames".into(),
                needed: format!("{m} runs × {} frames × 7 float64 values", grid.frames()),
                limit: "the memory this process can address".into(),
                hint: FRAMES_HINT,
            };
            (
                zeroed_for(
                    values(3).ok_or_else(too_large)?,
                    "the batch's frames",
                    FRAMES_HINT,
                )?,
                zeroed_for(
                    values(4).ok_or_else(too_large)?,
                    "the batch's frames",
                    FRAMES_HINT,
                )?,
            )
        }
        false => (Vec::new(), Vec::new()),
    };
    let stop = Stop::new(cancel);
    let rows: Vec<RowOutput> = options.install(m, || {
        let parts = if method.info().batch {
            lane_rows(isa, method, starts, grid, keep, &mut omega, &mut q, &stop)
        } else {
            single_rows(starts, grid, method, keep, &mut omega, &mut q, &stop)
        };
        let parts = stop.gather(parts)?;
        crate::buffer::try_collect(
            parts.into_iter().flatten(),
            m,
            "the runs' results",
            "run fewer starts at a time",
        )
    })?;
    let total_flips = rows.iter().map(|r| r.flip_times.len()).sum();
    const FLIPS_HINT: &str = "take a shorter t_end, or do not ask for the flips (`flips=False`)";
    const ROWS_HINT: &str = "run fewer starts at a time";
    let mut out = BatchOutput {
        omega,
        q,
        parts: Vec::new(),
        flip_offsets: try_with_capacity(m + 1, "the batch's flip offsets", FLIPS_HINT)?,
        flip_times: try_with_capacity(total_flips, "the batch's flip times", FLIPS_HINT)?,
        drift: try_with_capacity(m, "the batch's drifts", ROWS_HINT)?,
        stats: try_with_capacity(m, "the batch's statistics", ROWS_HINT)?,
        dt: try_with_capacity(m, "the batch's steps", ROWS_HINT)?,
        end: Vec::new(),
        flat_time: Vec::new(),
    };
    out.flip_offsets.push(0);
    for row in rows {
        out.flip_times.extend_from_slice(&row.flip_times);
        out.flip_offsets.push(out.flip_times.len());
        out.drift.push(row.drift);
        out.stats.push(row.stats);
        out.dt.push(row.dt);
    }
    Ok(out)
}

/// The frames of each group of `group` rows, or nothing for each if none are kept.
fn frame_chunks<'a>(
    omega: &'a mut [f64],
    q: &'a mut [f64],
    rows: usize,
    group: usize,
    frames: usize,
) -> Vec<Frames<'a>> {
    let groups = rows.div_ceil(group);
    if omega.is_empty() {
        return (0..groups).map(|_| None).collect();
    }
    omega
        .chunks_mut(group * frames * 3)
        .zip(q.chunks_mut(group * frames * 4))
        .map(Some)
        .collect()
}

/// The rows in groups of [`LANES`] run in SIMD lanes ([`crate::ensemble::lanes`]): the
/// methods whose registry entry says `batch`.
#[allow(clippy::too_many_arguments)]
fn lane_rows(
    isa: Isa,
    method: Method,
    starts: &[Start],
    grid: &FrameGrid,
    keep: Keep,
    omega: &mut [f64],
    q: &mut [f64],
    stop: &Stop,
) -> Vec<Result<Vec<RowOutput>>> {
    let watch = Watch {
        flips: keep.flips,
        tilt: false,
        count_only: false,
    };
    let n_steps = grid.n_steps();
    let chunks = frame_chunks(omega, q, starts.len(), LANES, grid.frames());
    starts
        .par_chunks(LANES)
        .zip(chunks)
        .enumerate()
        .map(|(g, (group, frames))| {
            if group.iter().any(needs_scaling) {
                return single_group(group, g * LANES, grid, method, keep, frames, stop);
            }
            let runs = stop.watch(run_group(isa, group, g * LANES, grid, watch, frames, stop))?;
            Ok(runs
                .into_iter()
                .map(|run| RowOutput {
                    flip_times: run.flip_times,
                    drift: run.drift,
                    stats: Stats {
                        nfev: method.info().rhs_per_step * n_steps,
                        n_steps,
                        n_rejected: 0,
                    },
                    dt: grid.step_size(),
                })
                .collect())
        })
        .collect()
}

/// The step each start's run will take and what it predicts (see
/// [`crate::run::step_size::plan`]); an error names its row.
///
/// # Errors
/// As [`crate::run::step_size::plan`], in a row.
pub fn plan_rows(
    starts: &[Start],
    t_end: f64,
    frames: usize,
    method: Method,
    dt: Option<f64>,
    rtol: f64,
) -> Result<Vec<StepPlan>> {
    starts
        .iter()
        .enumerate()
        .map(|(i, s)| {
            plan(&s.body, s.omega0, t_end, frames, method, dt, rtol).map_err(|e| e.in_row(i))
        })
        .collect()
}

/// Whether a start's rates or moments are so far from 1 that its run is integrated in its
/// own units (see [`crate::float`]): such rows run alone, as [`simulate`] runs them, since the lanes of a
/// group share one step.
pub(crate) fn needs_scaling(start: &Start) -> bool {
    !RateScale::of(start.omega0).is_identity() || crate::float::unit_body(&start.body).is_some()
}

/// The rows of a group, rows `first_row..` of the batch, run one by one by [`simulate`].
fn single_group(
    group: &[Start],
    first_row: usize,
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    mut frames: Frames,
    stop: &Stop,
) -> Result<Vec<RowOutput>> {
    let n_frames = grid.frames();
    let mut rows = Vec::with_capacity(group.len());
    for (l, s) in group.iter().enumerate() {
        stop.check()?;
        let run = simulate(&s.body, s.omega0, s.q0, grid, method, keep, stop.cancel);
        let run = stop.watch(run.map_err(|e| e.in_row(first_row + l)))?;
        if let Some((omega, q)) = &mut frames {
            omega[3 * l * n_frames..3 * (l + 1) * n_frames].copy_from_slice(&run.omega);
            q[4 * l * n_frames..4 * (l + 1) * n_frames].copy_from_slice(&run.q);
        }
        rows.push(RowOutput {
            flip_times: run.flip_times,
            drift: run.drift,
            stats: run.stats,
            dt: run.dt,
        });
    }
    Ok(rows)
}

fn single_rows(
    starts: &[Start],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    omega: &mut [f64],
    q: &mut [f64],
    stop: &Stop,
) -> Vec<Result<Vec<RowOutput>>> {
    let chunks = frame_chunks(omega, q, starts.len(), 1, grid.frames());
    starts
        .par_iter()
        .zip(chunks)
        .enumerate()
        .map(|(i, (s, frames))| {
            stop.check()?;
            let run = simulate(&s.body, s.omega0, s.q0, grid, method, keep, stop.cancel);
            let run = stop.watch(run.map_err(|e| e.in_row(i)))?;
            if let Some((omega, q)) = frames {
                omega.copy_from_slice(&run.omega);
                q.copy_from_slice(&run.q);
            }
            Ok(vec![RowOutput {
                flip_times: run.flip_times,
                drift: run.drift,
                stats: run.stats,
                dt: run.dt,
            }])
        })
        .collect()
}
