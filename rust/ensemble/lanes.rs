//! Many runs at once: RK4 in SIMD lanes, structure of arrays.
//!
//! A group of `L` runs that share a frame grid is integrated together, its state held
//! component-major, `[[f64; L]; 7]`, so that one step of all `L` runs is a loop over lanes
//! that the compiler turns into vector instructions. Each lane takes [`Rk4`]'s step with the
//! right-hand side of a single run ([`increment_scaled`], which [`scaled_increment`] calls):
//! the same IEEE operations in the same order (Rust never contracts `a * b + c` into a fused
//! multiply-add, and lanes never interact), so a lane ends bit for bit where the single run
//! of its inputs ends, whatever the vector width, the group it falls in or the thread it runs
//! on. One thing is moved, not changed: the products `s · euler` of the step's three
//! fractions `s` are formed once per stretch of steps, not at every step (95 multiplications
//! in a step of 8 lanes instead of 104, in the AVX-512 build).
//!
//! The vector width is picked at run time ([`Isa::detect`]): the same generic kernel is
//! compiled for AVX-512, for AVX2 and for the x86-64 baseline (SSE2), and the widest that the
//! CPU offers runs, so that one wheel runs everywhere. Other architectures run the baseline
//! build (NEON on aarch64).
//!
//! Flip detection and the tilt watch ride along. After each step a vectorised test tells
//! whether any lane's [`FlipDetector`] would change state (a sign change of the intermediate
//! rate, or that axis arriving nearest `L`); only then, a few steps per flip, are the
//! detectors called, lane by lane, with the states before and after the step, exactly as a
//! single run calls its detector. The state is double-buffered so that both are at hand.

pub use crate::isa::Isa;

#[cfg(doc)]
use crate::dynamics::scaled_increment;
use crate::dynamics::{increment_scaled, FreeRigidBody, State};
#[cfg(doc)]
use crate::integrators::Rk4;
use crate::observe::tilt::TiltMonitor;
use crate::observe::{crosses, FlipDetector};
use crate::ode::add;

/// The states of `L` runs, component-major: component `c` of lane `l` at `[c][l]`.
pub type Soa<const L: usize> = [[f64; L]; 7];

/// Selects one of the three body rates of each lane, or none: bit masks, all ones for the
/// component picked (a selection by index or by comparison would become a gather, which is
/// slow). Picking none gives 1.0, a constant that never changes sign nor passes a threshold
/// of `+∞`.
#[derive(Clone, Copy)]
struct Selector<const L: usize> {
    masks: [[u64; L]; 4],
}

impl<const L: usize> Selector<L> {
    fn none() -> Self {
        Self {
            masks: [[0; L], [0; L], [0; L], [u64::MAX; L]],
        }
    }

    fn set(&mut self, l: usize, axis: Option<usize>) {
        for (k, mask) in self.masks.iter_mut().enumerate() {
            mask[l] = if axis.unwrap_or(3) == k { u64::MAX } else { 0 };
        }
    }

    /// The selected rate of lane `l` of `x`.
    #[inline(always)]
    fn pick(&self, x: &Soa<L>, l: usize) -> f64 {
        let m = &self.masks;
        f64::from_bits(
            (x[0][l].to_bits() & m[0][l])
                | (x[1][l].to_bits() & m[1][l])
                | (x[2][l].to_bits() & m[2][l])
                | (1f64.to_bits() & m[3][l]),
        )
    }
}

/// `L` runs in lanes: their coefficients, their double-buffered state, and what the flip and
/// tilt watches need each step, mirrored from the runs' own [`FlipDetector`] and
/// [`TiltMonitor`].
#[derive(Clone)]
pub struct Lanes<const L: usize> {
    euler: [[f64; L]; 3],
    x: [Soa<L>; 2],
    /// Which buffer holds the current state.
    current: usize,
    flips: FlipWatch<L>,
    tilt: TiltWatch<L>,
}

/// [`FlipDetector`]'s state, per lane: the intermediate axis (none for a symmetric top), its scaled moment `I`, the threshold `θ` past which it is nearest `L` (`+∞` for
/// none), and the band `[low, high]` of `I ω_mid` in which the detector stays as it is, set
/// by the side the axis was last seen on and whether a crossing awaits settling.
#[derive(Clone)]
struct FlipWatch<const L: usize> {
    axis: Selector<L>,
    inertia: [f64; L],
    threshold: [f64; L],
    low: [f64; L],
    high: [f64; L],
}

/// [`TiltMonitor`]'s state, per lane: the spin axis, its direction, the smallest `s ω_k`.
#[derive(Clone)]
struct TiltWatch<const L: usize> {
    axis: Selector<L>,
    sign: [f64; L],
    lowest: [f64; L],
}

impl<const L: usize> Lanes<L> {
    /// Lanes holding `states` (one per lane) of bodies with Euler coefficients `euler`.
    pub fn new(euler: &[[f64; 3]; L], states: &[State; L]) -> Self {
        let mut x = [[[0.0; L]; 7]; 2];
        for l in 0..L {
            for c in 0..7 {
                x[0][c][l] = states[l][c];
            }
        }
        Self {
            euler: std::array::from_fn(|c| std::array::from_fn(|l| euler[l][c])),
            x,
            current: 0,
            flips: FlipWatch {
                axis: Selector::none(),
                inertia: [0.0; L],
                threshold: [f64::INFINITY; L],
                low: [f64::NEG_INFINITY; L],
                high: [f64::INFINITY; L],
            },
            tilt: TiltWatch {
                axis: Selector::none(),
                sign: [1.0; L],
                lowest: [f64::INFINITY; L],
            },
        }
    }

    /// The current state of lane `l`.
    #[inline(always)]
    pub fn state(&self, l: usize) -> State {
        let x = &self.x[self.current];
        std::array::from_fn(|c| x[c][l])
    }

    /// Mirrors the detector of lane `l` (after it saw the first frame).
    pub fn watch_flips(&mut self, l: usize, detector: &FlipDetector<'_, FreeRigidBody>) {
        let w = &mut self.flips;
        if let Some((axis, inertia, threshold)) = detector.watch() {
            w.axis.set(l, Some(axis));
            w.inertia[l] = inertia;
            w.threshold[l] = threshold;
        }
        w.mirror(l, detector);
    }

    /// Mirrors the tilt monitor of lane `l` (after it saw the first frame).
    pub fn watch_tilt(&mut self, l: usize, monitor: &TiltMonitor) {
        let (axis, sign) = monitor.spin_axis();
        self.tilt.axis.set(l, Some(axis));
        self.tilt.sign[l] = sign;
        self.tilt.lowest[l] = monitor.lowest();
    }

    /// The smallest `s ω_k` lane `l` has seen, for its [`TiltMonitor`].
    pub fn tilt_lowest(&self, l: usize) -> f64 {
        self.tilt.lowest[l]
    }

    /// Whether lane `l`'s state is finite.
    pub fn is_finite(&self, l: usize) -> bool {
        self.state(l).iter().all(|v| v.is_finite())
    }
}

impl<const L: usize> FlipWatch<L> {
    /// Sets lane `l`'s band: the detector changes only when the axis comes nearest `L`
    /// (`|I ω_mid| > θ`) on a side other than the last, or on any side while a crossing is
    /// pending.
    fn mirror(&mut self, l: usize, detector: &FlipDetector<'_, FreeRigidBody>) {
        let threshold = self.threshold[l];
        let (low, high) = match detector.progress() {
            (side, false) if side > 0.0 => (-threshold, f64::INFINITY),
            (side, false) if side < 0.0 => (f64::NEG_INFINITY, threshold),
            _ => (-threshold, threshold),
        };
        self.low[l] = low;
        self.high[l] = high;
    }
}

/// Substeps `from..to` of the `n` equal substeps of length `h` between frames at `ta` and
/// `tb` (the last lands exactly on `tb`), as in [`crate::run::integrate`].
#[derive(Debug, Clone, Copy)]
pub struct Span {
    pub ta: f64,
    pub tb: f64,
    pub h: f64,
    pub n: u64,
    pub from: u64,
    pub to: u64,
}

/// What [`Rk4`]'s step of `h` asks of a lane's right-hand side, formed once for a stretch of
/// steps: for each of its fractions `s` (`h/2`, `h`, `h/6`) the products `s · euler` of every
/// lane and `s / 2`, each as [`scaled_increment`] forms them.
struct Fractions<const L: usize> {
    scaled: [[[f64; L]; 3]; 3],
    half: [f64; 3],
}

impl<const L: usize> Fractions<L> {
    #[inline(always)]
    fn new(euler: &[[f64; L]; 3], h: f64) -> Self {
        let s = [0.5 * h, h, h / 6.0];
        Self {
            scaled: s.map(|s| euler.map(|e| e.map(|e| s * e))),
            half: s.map(|s| 0.5 * s),
        }
    }

    /// `s · f(x)` of lane `l` for fraction `k` ([`scaled_increment`]).
    #[inline(always)]
    fn increment(&self, k: usize, l: usize, x: &State) -> State {
        let e = &self.scaled[k];
        increment_scaled([e[0][l], e[1][l], e[2][l]], self.half[k], x)
    }
}

/// One RK4 step of every lane, from `src` into `dst`: [`Rk4`]'s step, operation for
/// operation (`each_lane_steps_as_a_single_run_bit_for_bit` holds them together).
#[inline(always)]
fn step_lanes<const L: usize>(f: &Fractions<L>, src: &Soa<L>, dst: &mut Soa<L>) {
    for l in 0..L {
        let x: State = std::array::from_fn(|c| src[c][l]);
        let k1 = f.increment(0, l, &x);
        let k2 = f.increment(0, l, &add(&x, &k1));
        let k3 = f.increment(1, l, &add(&x, &k2));
        let y4 = add(&x, &k3);
        let partial: State =
            std::array::from_fn(|j| x[j] + (k1[j] + 2.0 * k2[j] + k3[j]) * (1.0 / 3.0));
        let k4 = f.increment(2, l, &y4);
        let x = add(&partial, &k4);
        for c in 0..7 {
            dst[c][l] = x[c];
        }
    }
}

/// Whether the step `src → dst` changes any lane's flip detector: a sign change of the
/// intermediate rate, or the axis nearest `L` on a side other than the last, or on the same
/// side with a crossing pending. Otherwise [`FlipDetector`]'s `step` would change nothing.
#[inline(always)]
fn flip_event<const L: usize>(w: &FlipWatch<L>, src: &Soa<L>, dst: &Soa<L>) -> bool {
    let mut any = false;
    for l in 0..L {
        let (r0, r1) = (w.axis.pick(src, l), w.axis.pick(dst, l));
        let l_mid = w.inertia[l] * r1;
        any |= crosses(r0, r1) | (l_mid < w.low[l]) | (l_mid > w.high[l]);
    }
    any
}

/// Lowers each lane's smallest `s ω_k` to that of `x`.
#[inline(always)]
fn see_tilt<const L: usize>(w: &mut TiltWatch<L>, x: &Soa<L>) {
    for l in 0..L {
        w.lowest[l] = w.lowest[l].min(w.sign[l] * w.axis.pick(x, l));
    }
}

/// The kernel: the substeps of `span` for every lane, with the flip detectors (one per lane)
/// if `FLIPS` and the tilt watch if `TILT`.
#[inline(always)]
fn advance_generic<const L: usize, const FLIPS: bool, const TILT: bool>(
    k: &mut Lanes<L>,
    detectors: &mut [FlipDetector<'_, FreeRigidBody>],
    span: Span,
) {
    let Lanes {
        euler,
        x: [a, b],
        current,
        flips,
        tilt,
    } = k;
    let fractions = Fractions::new(euler, span.h);
    for s in span.from..span.to {
        let (src, dst) = if *current == 0 {
            (&mut *a, &mut *b)
        } else {
            (&mut *b, &mut *a)
        };
        step_lanes(&fractions, src, dst);
        if FLIPS && flip_event(flips, src, dst) {
            // timed as `run::advance` times the step it shows to observers
            let t0 = span.ta + s as f64 * span.h;
            let t1 = if s + 1 == span.n {
                span.tb
            } else {
                t0 + span.h
            };
            flip_step(flips, detectors, src, dst, t0, t1);
        }
        if TILT {
            see_tilt(tilt, dst);
        }
        *current ^= 1;
    }
}

/// Shows the step `src → dst` to every lane's detector, and mirrors them again. A lane
/// whose detector would not change (see [`flip_event`]) is left as it was.
#[cold]
#[inline(never)]
fn flip_step<const L: usize>(
    w: &mut FlipWatch<L>,
    detectors: &mut [FlipDetector<'_, FreeRigidBody>],
    src: &Soa<L>,
    dst: &Soa<L>,
    t0: f64,
    t1: f64,
) {
    for (l, detector) in detectors.iter_mut().enumerate().take(L) {
        let before: State = std::array::from_fn(|c| src[c][l]);
        let after: State = std::array::from_fn(|c| dst[c][l]);
        crate::observe::Observer::step(detector, t0, &before, t1, &after);
        w.mirror(l, detector);
    }
}

/// The kernel compiled for each instruction set. The `unsafe` blocks call a function built
/// for CPU features that [`Isa::is_supported`] has just confirmed.
macro_rules! dispatch {
    ($isa:expr, $f:ident :: <$($g:tt),*> ($($arg:expr),*)) => {{
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = "avx512f")]
            unsafe fn avx512<const L: usize, const FLIPS: bool, const TILT: bool>(
                k: &mut Lanes<L>,
                detectors: &mut [FlipDetector<'_, FreeRigidBody>],
                span: Span,
            ) {
                $f::<L, FLIPS, TILT>(k, detectors, span)
            }
            #[target_feature(enable = "avx2")]
            unsafe fn avx2<const L: usize, const FLIPS: bool, const TILT: bool>(
                k: &mut Lanes<L>,
                detectors: &mut [FlipDetector<'_, FreeRigidBody>],
                span: Span,
            ) {
                $f::<L, FLIPS, TILT>(k, detectors, span)
            }
            match $isa {
                // SAFETY: the CPU has AVX-512F (checked just now).
                Isa::Avx512 if Isa::Avx512.is_supported() => unsafe { avx512::<$($g),*>($($arg),*) },
                // SAFETY: the CPU has AVX2 (checked just now).
                Isa::Avx2 if Isa::Avx2.is_supported() => unsafe { avx2::<$($g),*>($($arg),*) },
                _ => $f::<$($g),*>($($arg),*),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = $isa;
            $f::<$($g),*>($($arg),*)
        }
    }};
}

/// Advances every lane over `span` with the kernel built for `isa` (the baseline one if this
/// CPU lacks it), showing steps to `detectors` (one per lane) when `flips`, and watching the
/// tilt when `tilt`.
pub fn advance<const L: usize>(
    isa: Isa,
    k: &mut Lanes<L>,
    detectors: &mut [FlipDetector<'_, FreeRigidBody>],
    span: Span,
    flips: bool,
    tilt: bool,
) {
    debug_assert!(!flips || detectors.len() >= L);
    match (flips, tilt) {
        (false, false) => dispatch!(isa, advance_generic::<L, false, false>(k, detectors, span)),
        (true, false) => dispatch!(isa, advance_generic::<L, true, false>(k, detectors, span)),
        (false, true) => dispatch!(isa, advance_generic::<L, false, true>(k, detectors, span)),
        (true, true) => dispatch!(isa, advance_generic::<L, true, true>(k, detectors, span)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RigidBody;
    use crate::dynamics::{state_from, FreeRigidBody};
    use crate::integrators::Rk4;
    use crate::ode::Stepper;

    #[test]
    fn each_lane_steps_as_a_single_run_bit_for_bit() {
        let bodies = [
            [52.0833, 27.0833, 41.6666],
            [1.0, 2.0, 3.0],
            [3.0, 1.0, 2.5],
            [1.0, 1.0, 2.0],
        ];
        let systems = bodies.map(|i| FreeRigidBody::new(RigidBody::try_new(i).unwrap()));
        let states = [
            state_from([0.01, 0.01, 1.0], [1.0, 0.0, 0.0, 0.0]),
            state_from([0.3, -0.7, 1.1], [0.5, -0.1, 0.7, 0.5]),
            state_from([-2.0, 0.1, 0.4], [0.0, 1.0, 0.0, 0.0]),
            state_from([0.2, 0.0, 5.0], [0.5, 0.5, 0.5, 0.5]),
        ];
        let euler = systems.map(|s| s.euler_coefficients().into());
        for isa in Isa::available() {
            let mut lanes = Lanes::<4>::new(&euler, &states);
            let span = Span {
                ta: 0.0,
                tb: 1.0,
                h: 1e-2,
                n: 100,
                from: 0,
                to: 100,
            };
            advance(isa, &mut lanes, &mut [], span, false, false);
            for l in 0..4 {
                let mut x = states[l];
                for _ in 0..100 {
                    Rk4.step(&systems[l], 0.0, 1e-2, &mut x);
                }
                assert_eq!(
                    lanes.state(l).map(f64::to_bits),
                    x.map(f64::to_bits),
                    "{isa:?}"
                );
            }
        }
    }
}
