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
    CallableTorque, Damper, Deployment, Frame, Outside, Part, System, SystemBody, TabulatedTorque,
    Torque, TorqueFunction, Wheel, WheelSchedule,
};
use dzhanibekov::RigidBody;

/// Counts, on this thread's request, the allocations made and what glibc's malloc takes for
/// each: the size plus an 8-byte header, rounded up to 16, at least 32 bytes.
struct Counting;

static COUNTING: AtomicUsize = AtomicUsize::new(0);
static TAKEN: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::SeqCst) == thread_id() {
            let chunk = ((layout.size() + 8).div_ceil(16) * 16).max(32);
            TAKEN.fetch_add(chunk, Ordering::SeqCst);
        }
        unsafe { Malloc.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { Malloc.dealloc(ptr, layout) }
    }
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

impl TorqueFunction for Zero {
    fn torque(&self, _t: f64, _q: [f64; 4], _omega: [f64; 3]) -> Option<[f64; 3]> {
        Some([0.0; 3])
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
    let damper = Part::Damper {
        damper: Damper::try_new(0.1, 0.05).unwrap(),
        sigma0: None,
    };
    let wheel = Part::Wheel(Wheel::try_new([0.0, 1.0, 0.0], 0.5).unwrap());
    let schedule = Part::ScheduledWheel(
        WheelSchedule::try_new([1.0, 0.0, 0.0], knots.clone(), vec![0.25; 100]).unwrap(),
    );
    let table = TabulatedTorque::try_new(
        knots,
        vec![[0.0, 0.0, 1.0]; 100],
        Frame::World,
        Outside::Zero,
    )
    .unwrap();
    let torques = || {
        vec![
            Torque::gravity_gradient(0.1).unwrap(),
            Torque::constant([0.0, 0.0, 1.0], Frame::Body).unwrap(),
            Torque::Tabulated(Arc::new(table.clone())),
            Torque::Callable(CallableTorque::new(Arc::new(Zero))),
        ]
    };
    let with = |body: SystemBody, parts: Vec<Part>, torques: Vec<Torque>| {
        System::try_new(body, parts)
            .unwrap()
            .with_torques(torques)
            .unwrap()
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
        (
            "gravity",
            with(
                rigid(),
                vec![],
                vec![Torque::gravity_gradient(0.1).unwrap()],
            ),
        ),
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
