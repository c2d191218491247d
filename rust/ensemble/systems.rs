//! A batch of systems: one run per row, each equal to its single run
//! ([`crate::run::simulate_system`]) bit for bit. Rows of free bodies go through the batch
//! kernel ([`super::batch`], RK4 in SIMD lanes) in their principal axes; a batch with any
//! other system runs its rows one by one on all cores. Frames go straight into the batch's
//! arrays, so a batch holds its frames once plus one row's per thread.

use std::sync::atomic::AtomicBool;

use rayon::prelude::*;

use crate::buffer::{try_collect, try_with_capacity, zeroed_for};
use crate::dynamics::System;
use crate::error::{Error, Result};
use crate::run::{simulate_system, Edge, FrameGrid, Keep, Method};

use super::batch::{simulate_batch, BatchOutput, Options, Start, Stop};

/// What to say when a batch's frames would not fit.
const FRAMES_HINT: &str = "ask for fewer runs or frames, or use `sweep` (or a Monte Carlo \
                           study) for per-run outcomes, which keep no frames";

/// The rows of a batch: `systems[i]` from `omega0[i]` and `q0[i]` (the user's axes).
#[derive(Debug, Clone, Copy)]
pub struct Rows<'a> {
    pub systems: &'a [System],
    pub omega0: &'a [[f64; 3]],
    pub q0: &'a [[f64; 4]],
}

impl Rows<'_> {
    pub fn len(&self) -> usize {
        self.systems.len()
    }

    pub fn is_empty(&self) -> bool {
        self.systems.is_empty()
    }

    /// The numbers of the parts' state per frame, the same for every row.
    ///
    /// # Errors
    /// Rows whose systems have parts of different sizes, or whose lengths differ.
    pub fn parts_width(&self) -> Result<usize> {
        let m = self.len();
        if self.omega0.len() != m || self.q0.len() != m {
            return Err(Error::invalid(
                "omega0, q0",
                "must give one row per system",
                (m, self.omega0.len(), self.q0.len()),
            ));
        }
        let width = self.systems.first().map_or(0, System::parts_width);
        match self.systems.iter().position(|s| s.parts_width() != width) {
            None => Ok(width),
            Some(row) => Err(Error::invalid(
                "system",
                "must have parts of the same kinds in every row of a batch",
                row,
            )
            .in_row(row)),
        }
    }
}

/// Simulates every row over `grid` (see the module docs), on `options`' threads.
///
/// # Errors
/// [`Error::TooLarge`] if the frames cannot be allocated; a row's error, naming the row;
/// [`Error::Interrupted`] soon after `cancel` is set.
pub fn simulate_systems(
    rows: Rows<'_>,
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    options: &Options,
    cancel: &AtomicBool,
) -> Result<BatchOutput> {
    let width = rows.parts_width()?;
    for (i, s) in rows.systems.iter().enumerate() {
        method.for_kinds(s.kinds()).map_err(|e| e.in_row(i))?;
    }
    if let ([system], [omega0], [q0]) = (rows.systems, rows.omega0, rows.q0) {
        return one_row(system, *omega0, *q0, grid, method, keep, cancel);
    }
    if rows.systems.iter().all(|s| s.as_free().is_some()) {
        return free_rows(rows, grid, method, keep, options, cancel);
    }
    let m = rows.len();
    let frames = grid.frames();
    crate::buffer::ensure_room(
        batch_bytes(m, frames, width, keep, options.threads_for(m)),
        "the batch",
        FRAMES_HINT,
    )?;
    let values = |w: usize| -> Result<Vec<f64>> {
        if !keep.frames || w == 0 {
            return Ok(Vec::new());
        }
        let len = m
            .checked_mul(frames)
            .and_then(|n| n.checked_mul(w))
            .ok_or_else(|| Error::TooLarge {
                what: "keeping the batch's frames".into(),
                needed: format!("{m} runs × {frames} frames × {} float64 values", 7 + w),
                limit: "the memory this process can address".into(),
                hint: FRAMES_HINT,
            })?;
        zeroed_for(len, "the batch's frames", FRAMES_HINT)
    };
    let (mut omega, mut q, mut parts) = (values(3)?, values(4)?, values(width)?);
    let stop = Stop::new(cancel);
    let outputs = options.install(m, || {
        let slots = slots(&mut omega, &mut q, &mut parts, m, frames, width)?;
        let mut results: Vec<Result<Row>> =
            try_with_capacity(m, "the batch's rows", "run fewer starts at a time")?;
        // room for every row is there already: `par_extend` allocates nothing
        results.par_extend(slots.into_par_iter().enumerate().map(|(i, slot)| {
            stop.check()?;
            let run = simulate_system(
                &rows.systems[i],
                rows.omega0[i],
                rows.q0[i],
                grid,
                method,
                keep,
                stop.cancel,
            );
            let run = stop.watch(run.map_err(|e| e.in_row(i)))?;
            if let Some((o, qq, p)) = slot {
                o.copy_from_slice(&run.omega);
                qq.copy_from_slice(&run.q);
                p.copy_from_slice(&run.parts);
            }
            Ok(Row {
                flip_times: run.flip_times,
                flat_time: run.flat_time,
                drift: run.drift,
                stats: run.stats,
                dt: run.dt,
                end: run.end,
            })
        }));
        stop.gather(results)
    })?;
    let mut out = BatchOutput {
        omega,
        q,
        parts,
        ..collect_rows(m)?
    };
    out.end = try_with_capacity(m, "the batch's ends", "run fewer starts at a time")?;
    out.flat_time = try_with_capacity(m, "the batch's ends", "run fewer starts at a time")?;
    for row in outputs {
        out.push_row(row.flip_times, row.drift, row.stats, row.dt)?;
        out.end.push(row.end);
        out.flat_time.extend(row.flat_time);
    }
    Ok(out)
}

/// About how many bytes a batch of `m` rows of systems with parts of `width` numbers holds
/// beyond its inputs, on `threads` threads, at its largest: its frames (if kept, plus one
/// row's on each thread), each row's slot and outcome (twice: as run, then gathered), its
/// end's parts, the batch's columns, and their conversion to NumPy arrays (ends, columns,
/// frame times). The flip times are not counted: they are checked as they are gathered.
pub fn batch_bytes(m: usize, frames: usize, width: usize, keep: Keep, threads: usize) -> f64 {
    use std::mem::size_of;
    let f64s = |n: usize| n as f64 * 8.0;
    let frame_values = match keep.frames {
        true => f64s(frames) * (7 + width) as f64,
        false => 0.0,
    };
    // each heap block of an end's parts, with the allocator's header
    let end_parts = f64s(width).max(16.0) + 16.0;
    let per_row = frame_values
        + (size_of::<Option<(&mut [f64], &mut [f64], &mut [f64])>>() + size_of::<&mut [f64]>())
            as f64
        + 2.0 * size_of::<Result<Row>>() as f64
        + end_parts
        + (size_of::<crate::observe::End>()
            + size_of::<crate::observe::Drift>()
            + size_of::<crate::ode::Stats>()
            + 2 * size_of::<f64>()) as f64
        // NumPy: the ends (ω, q, parts), the flip offsets and the nine columns
        + f64s(7 + width + 1 + 9);
    let frame_times = match keep.frames {
        true => f64s(frames),
        false => 0.0,
    };
    m as f64 * per_row + threads as f64 * frame_values + frame_times
}

/// A batch of one row: its single run, whose frames become the batch's without a copy (a
/// batch of one costs what the run costs).
fn one_row(
    system: &System,
    omega0: [f64; 3],
    q0: [f64; 4],
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    cancel: &AtomicBool,
) -> Result<BatchOutput> {
    let run =
        simulate_system(system, omega0, q0, grid, method, keep, cancel).map_err(|e| e.in_row(0))?;
    Ok(BatchOutput {
        omega: run.omega,
        q: run.q,
        parts: run.parts,
        flip_offsets: vec![0, run.flip_times.len()],
        flip_times: run.flip_times,
        drift: vec![run.drift],
        stats: vec![run.stats],
        dt: vec![run.dt],
        end: vec![run.end],
        flat_time: run.flat_time.into_iter().collect(),
    })
}

/// What a row leaves besides its frames.
struct Row {
    flip_times: Vec<f64>,
    flat_time: Option<f64>,
    drift: crate::observe::Drift,
    stats: crate::ode::Stats,
    dt: f64,
    end: crate::observe::End,
}

/// An empty output with room for `m` rows' columns.
fn collect_rows(m: usize) -> Result<BatchOutput> {
    const ROWS_HINT: &str = "run fewer starts at a time";
    let mut out = BatchOutput {
        flip_offsets: try_with_capacity(m + 1, "the batch's flip offsets", ROWS_HINT)?,
        drift: try_with_capacity(m, "the batch's drifts", ROWS_HINT)?,
        stats: try_with_capacity(m, "the batch's statistics", ROWS_HINT)?,
        dt: try_with_capacity(m, "the batch's steps", ROWS_HINT)?,
        ..BatchOutput::default()
    };
    out.flip_offsets.push(0);
    Ok(out)
}

/// Each row's place in the frames: its ω, q and parts' state; `None` for each row when no
/// frames are kept.
#[allow(clippy::type_complexity)]
fn slots<'a>(
    omega: &'a mut [f64],
    q: &'a mut [f64],
    parts: &'a mut [f64],
    m: usize,
    frames: usize,
    width: usize,
) -> Result<Vec<Option<(&'a mut [f64], &'a mut [f64], &'a mut [f64])>>> {
    const HINT: &str = "run fewer starts at a time";
    if omega.is_empty() {
        return try_collect((0..m).map(|_| None), m, "the batch's rows", HINT);
    }
    let parts_rows: Vec<&'a mut [f64]> = match width {
        0 => try_collect(
            (0..m).map(|_| <&mut [f64]>::default()),
            m,
            "the batch's rows",
            HINT,
        )?,
        w => try_collect(parts.chunks_mut(frames * w), m, "the batch's rows", HINT)?,
    };
    let rows = omega
        .chunks_mut(frames * 3)
        .zip(q.chunks_mut(frames * 4))
        .zip(parts_rows)
        .map(|((o, qq), p)| Some((o, qq, p)));
    try_collect(rows, m, "the batch's rows", HINT)
}

/// A batch of free bodies: their starts in principal axes through the batch kernel, each
/// row's frames back in its user's axes.
fn free_rows(
    rows: Rows<'_>,
    grid: &FrameGrid,
    method: Method,
    keep: Keep,
    options: &Options,
    cancel: &AtomicBool,
) -> Result<BatchOutput> {
    let (starts, edges) = free_starts(rows)?;
    let mut out = simulate_batch(&starts, grid, method, keep, options, cancel)?;
    if keep.frames {
        let frames = grid.frames();
        let chunks = out
            .omega
            .chunks_mut(frames * 3)
            .zip(out.q.chunks_mut(frames * 4));
        for (edge, (omega, q)) in edges.iter().zip(chunks) {
            edge.frames_out(omega, q, &mut [], (0, &[]));
        }
    }
    Ok(out)
}

/// The starts of free bodies in their principal axes, as their single runs make them, and
/// the edges back.
///
/// # Errors
/// A row that is not a free body or whose start is bad, naming the row.
pub fn free_starts(rows: Rows<'_>) -> Result<(Vec<Start>, Vec<Edge>)> {
    let mut starts = try_with_capacity(rows.len(), "the starts", "run fewer starts at a time")?;
    let mut edges = try_with_capacity(rows.len(), "the starts", "run fewer starts at a time")?;
    for i in 0..rows.len() {
        let (start, edge) =
            free_start(&rows.systems[i], rows.omega0[i], rows.q0[i]).map_err(|e| e.in_row(i))?;
        starts.push(start);
        edges.push(edge);
    }
    Ok((starts, edges))
}

/// A free body's start in its principal axes, as its single run makes it.
fn free_start(system: &System, omega0: [f64; 3], q0: [f64; 4]) -> Result<(Start, Edge)> {
    let Some(inertia) = system.as_free() else {
        return Err(Error::invalid(
            "system",
            "must be a constant body without parts (a sweep counts the free body's flips)",
            system.kinds().names(),
        ));
    };
    crate::run::check_rates(omega0)?;
    let q = crate::kinematics::normalized(q0)?;
    let edge = Edge::of(inertia);
    let start = Start {
        body: *inertia.principal(),
        omega0: edge.vector_in(omega0),
        q0: edge.attitude_in(q),
    };
    Ok((start, edge))
}
