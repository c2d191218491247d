//! `System::heap_bytes` against what a copy of a system really allocates, counted by a global
//! allocator of this test binary: a batch checks that many copies fit before making them
//! (one per row), so a copy that holds more than the count says aborts the process under an
//! address-space limit (a batch of 10⁶ rows with a torque did, under 700 MiB: the torques'
//! list was not counted).

use std::alloc::{GlobalAlloc, Layout, System as Malloc};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use nalgebra::Matrix3;

use dzhanibekov::body::Inertia;
use dzhanibekov::dynamics::{
    AnyPart, Arg, CallableTorque, ConstantTorque, Damper, Deployment, Frame, Function,
    GravityGradient, Outside, System, SystemBody, TabulatedTorque, Wheel, WheelSchedule,
};
use dzhanibekov::RigidBody;

/// Counts, on this thread's request, what glibc's malloc takes for each allocation (the size
/// plus an 8-byte header, rounded up to 16, at least 32 bytes): in all (`TAKEN`), and the most
/// held at once (`PEAK`, of `HELD`, allocations less frees).
struct Counting;

static COUNTING: AtomicUsize = AtomicUsize::new(0);
static TAKEN: AtomicUsize = AtomicUsize::new(0);
static HELD: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// An allocation of this size is not counted: the run's own check of its room (a
/// reservation of `model_bytes`, released at once), not what the run holds.
static PROBE: AtomicUsize = AtomicUsize::new(usize::MAX);

fn chunk(layout: Layout) -> usize {
    ((layout.size() + 8).div_ceil(16) * 16).max(32)
}

fn counted(layout: Layout) -> bool {
    COUNTING.load(Ordering::SeqCst) == thread_id() && layout.size() != PROBE.load(Ordering::SeqCst)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if counted(layout) {
            TAKEN.fetch_add(chunk(layout), Ordering::SeqCst);
            let held = HELD.fetch_add(chunk(layout), Ordering::SeqCst) + chunk(layout);
            PEAK.fetch_max(held, Ordering::SeqCst);
        }
        unsafe { Malloc.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if counted(layout) {
            // frees of what was allocated before counting began are not counted down
            let _ = HELD.fetch_update(Ordering::SeqCst, Ordering::SeqCst, |h| {
                Some(h.saturating_sub(chunk(layout)))
            });
        }
        unsafe { Malloc.dealloc(ptr, layout) }
    }
}

/// The most bytes held at once while `f` runs on this thread, and what `f` returned.
fn peak_of<T>(f: impl FnOnce() -> T) -> (usize, T) {
    HELD.store(0, Ordering::SeqCst);
    PEAK.store(0, Ordering::SeqCst);
    COUNTING.store(thread_id(), Ordering::SeqCst);
    let out = f();
    COUNTING.store(0, Ordering::SeqCst);
    (PEAK.load(Ordering::SeqCst), out)
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A number for this thread (tests run on several): the address of a thread-local.
fn thread_id() -> usize {
    thread_local!(static MARK: u8 = const { 0 });
    MARK.with(|m| m as *const u8 as usize)
}

/// The bytes a clone of `system` takes from the allocator.
fn clone_cost(system: &System) -> usize {
    TAKEN.store(0, Ordering::SeqCst);
    COUNTING.store(thread_id(), Ordering::SeqCst);
    let copy = system.clone();
    COUNTING.store(0, Ordering::SeqCst);
    drop(copy);
    TAKEN.load(Ordering::SeqCst)
}

struct Zero;

impl Function for Zero {
    fn call(&self, _args: &[Arg<'_>], out: &mut [f64]) -> bool {
        out.fill(0.0);
        true
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// A system of every kind of body, part and torque, alone and together.
fn systems() -> Vec<(&'static str, System)> {
    let rigid = || {
        SystemBody::Rigid(Inertia::from_principal(
            RigidBody::try_new([1.0, 2.0, 3.0]).unwrap(),
        ))
    };
    let knots: Vec<f64> = (0..100).map(f64::from).collect();
    let tensors = vec![Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 2.0, 3.0)); 100];
    let deployment = SystemBody::Deployment(Deployment::try_new(knots.clone(), tensors).unwrap());
    let damper = AnyPart::from(Damper::try_new(0.1, 0.05).unwrap());
    let wheel = AnyPart::from(Wheel::try_new([0.0, 1.0, 0.0], 0.5).unwrap());
    let schedule = AnyPart::from(
        WheelSchedule::try_new([1.0, 0.0, 0.0], knots.clone(), vec![0.25; 100]).unwrap(),
    );
    let table = TabulatedTorque::try_new(
        knots,
        vec![[0.0, 0.0, 1.0]; 100],
        Frame::World,
        Outside::Zero,
    )
    .unwrap();
    let gravity = || AnyPart::from(GravityGradient::try_new(0.1).unwrap());
    let torques = || {
        vec![
            gravity(),
            ConstantTorque::try_new([0.0, 0.0, 1.0], Frame::Body)
                .unwrap()
                .into(),
            table.clone().into(),
            CallableTorque::new(Arc::new(Zero)).into(),
        ]
    };
    let with = |body: SystemBody, mut parts: Vec<AnyPart>, torques: Vec<AnyPart>| {
        parts.extend(torques);
        System::try_new(body, parts).unwrap()
    };
    vec![
        (
            "free",
            System::rigid(Inertia::from_principal(
                RigidBody::try_new([1.0, 2.0, 3.0]).unwrap(),
            )),
        ),
        ("deployment", with(deployment.clone(), vec![], vec![])),
        ("damper", with(rigid(), vec![damper.clone()], vec![])),
        (
            "wheels",
            with(rigid(), vec![wheel.clone(), schedule.clone()], vec![]),
        ),
        ("gravity", with(rigid(), vec![], vec![gravity()])),
        ("torques", with(rigid(), vec![], torques())),
        (
            "everything",
            with(deployment, vec![damper, wheel, schedule], torques()),
        ),
    ]
}

#[test]
fn heap_bytes_counts_all_that_a_copy_of_any_system_allocates() {
    for (name, system) in systems() {
        let taken = clone_cost(&system);
        let counted = system.heap_bytes();
        assert!(
            counted >= taken,
            "{name}: a copy takes {taken} bytes from the allocator, heap_bytes says {counted}"
        );
        // and not wildly more: the count is what a batch reserves per row
        assert!(
            counted <= 2 * taken.max(64),
            "{name}: {counted} for {taken}"
        );
    }
}

/// A system of a constant body with `k` knots in a wheel's schedule and in two tabulated
/// torques (one in body axes, one in space), whose run's model copies them into its axes and
/// units.
fn knotted(k: usize) -> System {
    let times: Vec<f64> = (0..k).map(|i| i as f64 * 1e-3).collect();
    let body = SystemBody::Rigid(Inertia::from_principal(
        RigidBody::try_new([1.0, 2.0, 3.0]).unwrap(),
    ));
    let schedule = WheelSchedule::try_new([1.0, 1.0, 0.0], times.clone(), vec![0.25; k]).unwrap();
    // the tables' knots apart: the kinks the steps end on are all three tables'
    let table = |frame, offset: f64| {
        let times = times.iter().map(|t| t + offset).collect();
        let t = TabulatedTorque::try_new(times, vec![[0.0, 1e-3, 0.0]; k], frame, Outside::Zero);
        AnyPart::from(t.unwrap())
    };
    let parts = vec![
        schedule.into(),
        table(Frame::Body, 1e-4),
        table(Frame::World, 2e-4),
    ];
    System::try_new(body, parts).unwrap()
}

/// A deployment of `k` knots.
fn deployed(k: usize) -> System {
    let times: Vec<f64> = (0..k).map(|i| i as f64 * 1e-3).collect();
    let tensors = (0..k)
        .map(|i| Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 2.0, 3.0 + 1e-6 * i as f64)))
        .collect();
    let body = SystemBody::Deployment(Deployment::try_new(times, tensors).unwrap());
    System::try_new(body, vec![]).unwrap()
}

#[test]
fn model_bytes_counts_what_building_a_runs_model_holds() {
    use dzhanibekov::run::{simulate_system, FrameGrid, Keep, Method};
    let keep = Keep {
        frames: false,
        flips: false,
        tilt: false,
    };
    let cancel = std::sync::atomic::AtomicBool::new(false);
    for (k, system) in [1000, 100_000]
        .into_iter()
        .flat_map(|k| [(k, knotted(k)), (k, deployed(k))])
    {
        // a run of one step: what it holds is the model it builds
        let grid = FrameGrid::try_new(1e-9, 2, 1e-9, u64::MAX).unwrap();
        // rates of 1e30: the run goes in its own units, where the tables are copied again
        let mut peaks = Vec::new();
        PROBE.store(system.model_bytes(), Ordering::SeqCst);
        for omega in [[0.01, 0.01, 1.0], [0.0, 0.0, 1e30]] {
            let (peak, out) = peak_of(|| {
                simulate_system(
                    &system,
                    omega,
                    [1.0, 0.0, 0.0, 0.0],
                    &grid,
                    Method::Rk4,
                    keep,
                    &cancel,
                )
            });
            out.unwrap();
            peaks.push(peak);
        }
        PROBE.store(usize::MAX, Ordering::SeqCst);
        let (counted, most) = (system.model_bytes(), peaks.iter().copied().max().unwrap());
        assert!(
            counted >= most,
            "{k} knots: a run held {peaks:?} bytes, model_bytes says {counted}"
        );
        // and not wildly more: a run checks it has that much room
        assert!(counted <= 2 * most, "{k} knots: {counted} for {peaks:?}");
    }
}
