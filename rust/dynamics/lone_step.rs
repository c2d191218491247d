//! A whole RK4 step of a body carrying one part whose mass moves, alone on its hub in closed
//! form ([`super::LoneSpring`], [`super::LoneHinge`], [`super::LoneSlosh`]), with at most
//! constant stored momenta and constant torques beside it: what the general model's
//! [`OdeSystem::rk4_step`] runs. Through the model's own right-hand side each of a step's four
//! stages is a call out of line that returns the state's increment through memory, read back
//! at once by the next stage (a store-forwarding stall each); here the four stages are one
//! function per part and state size, everything inlined, in the part's own state size
//! without the padding of the model's (a slosh's 14 numbers in a state of 24). The same
//! operations in the same order as [`GeneralModel`](super::GeneralModel)'s lone path through
//! [`Rk4`]: the same numbers, bit for bit.

use nalgebra::Vector3;

use crate::integrators::Rk4;
use crate::isa::Isa;
use crate::kinematics::world_to_body;
use crate::ode::{OdeSystem, Stepper};

use super::model::{attitude, quaternion_increment};
use super::multibody::Alone;

/// The lone part and what stands beside it: the constant stored momenta (summed), and when
/// the system has external torques, the constant ones in body and in world axes (summed).
#[derive(Debug, Clone, Copy)]
pub(crate) struct LoneStage<'a, L> {
    pub lone: &'a L,
    pub stored: Option<Vector3<f64>>,
    pub torques: Torques,
}

/// Constant torques in body and in world axes, each summed, when a system has torques.
pub type Torques = Option<(Option<Vector3<f64>>, Option<Vector3<f64>>)>;

impl<'a, L> LoneStage<'a, L> {
    /// `lone` with the stored momenta and torques `beside` it.
    #[inline(always)]
    pub fn new(lone: &'a L, (stored, torques): (Option<Vector3<f64>>, Torques)) -> Self {
        Self {
            lone,
            stored,
            torques,
        }
    }
}

/// The compact state `[H, the part's state, W, q]` of `M` numbers (the part's `M − 8`).
impl<const M: usize, L: Alone> OdeSystem<M> for LoneStage<'_, L> {
    #[inline(always)]
    fn increment(&self, _t: f64, x: &[f64; M], s: f64) -> [f64; M] {
        let w = M - 8;
        let h = Vector3::new(x[0], x[1], x[2]);
        let mut l = h;
        if let Some(c) = self.stored {
            l -= c;
        }
        let mut dx = [0.0; M];
        let (omega, power) = self.lone.increment(&l, &x[3..3 + w], s, &mut dx[3..3 + w]);
        let mut dh = h.cross(&omega);
        if let Some((body, world)) = self.torques {
            let mut tau = body.unwrap_or_default();
            if let Some(v) = world {
                tau += world_to_body(&attitude(x), &v);
            }
            dh += tau;
        }
        dx[..3].copy_from_slice((dh * s).as_slice());
        dx[M - 5] = power * s;
        let dq = quaternion_increment([x[M - 4], x[M - 3], x[M - 2], x[M - 1]], omega, s);
        dx[M - 4..].copy_from_slice(&dq);
        dx
    }
}

/// One RK4 step of `stage` from `(t, x)` by `h`, `x` the model's state of `N` numbers (the
/// part's state from index 3, the dissipated work at `N − 5`, `q` last; `M ≤ N`), in the
/// widest instruction set the CPU has (as the fixed-step driver is, see [`crate::isa`]).
#[inline(never)]
pub(crate) fn rk4<const N: usize, const M: usize, L: Alone>(
    stage: &LoneStage<'_, L>,
    t: f64,
    h: f64,
    x: &mut [f64; N],
) {
    #[cfg(target_arch = "x86_64")]
    {
        #[target_feature(enable = "avx512f")]
        fn avx512<const N: usize, const M: usize, L: Alone>(
            stage: &LoneStage<'_, L>,
            t: f64,
            h: f64,
            x: &mut [f64; N],
        ) {
            compact::<N, M, L>(stage, t, h, x)
        }
        if Isa::detect() == Isa::Avx512 {
            // SAFETY: the CPU has AVX-512F (checked just now).
            return unsafe { avx512::<N, M, L>(stage, t, h, x) };
        }
    }
    compact::<N, M, L>(stage, t, h, x)
}

/// [`rk4`] in the compact state: `x`'s padding (between the part's state and `W`) is left
/// as it is (its increments are zero).
#[inline(always)]
fn compact<const N: usize, const M: usize, L: Alone>(
    stage: &LoneStage<'_, L>,
    t: f64,
    h: f64,
    x: &mut [f64; N],
) {
    let mut y: [f64; M] = std::array::from_fn(|k| match k {
        k if k < M - 5 => x[k],
        k => x[N - M + k],
    });
    Rk4.step(stage, t, h, &mut y);
    x[..M - 5].copy_from_slice(&y[..M - 5]);
    x[N - 5..].copy_from_slice(&y[M - 5..]);
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix3;

    use super::*;
    use crate::dynamics::multibody::fixtures::{panel, spring, tank};
    use crate::dynamics::{
        AnyPart, ConstantInertia, ConstantTorque, Damper, Frame, GeneralModel, InertiaLaw, Moving,
        Wheel, WheelSchedule,
    };
    use crate::ode::add;

    fn movers() -> [AnyPart; 3] {
        [spring().into(), panel().into(), tank().into()]
    }

    fn model<const N: usize>(parts: Vec<AnyPart>) -> GeneralModel<N, true, Moving> {
        let i = Matrix3::new(2.0, -0.3, 0.1, -0.3, 3.0, 0.2, 0.1, 0.2, 4.0);
        let law = InertiaLaw::Constant(ConstantInertia::try_new(i).unwrap());
        (GeneralModel::try_new(law, parts).unwrap())
            .with_hub_mass(Some(5.0))
            .unwrap()
    }

    /// RK4's stages through the model's right-hand side, as [`Rk4`] takes them.
    fn stages<const N: usize>(
        m: &GeneralModel<N, true, Moving>,
        t: f64,
        h: f64,
        x: &[f64; N],
    ) -> [f64; N] {
        let half = 0.5 * h;
        let (start, middle, end) = (m.at_time(t), m.at_time(t + half), m.at_time(t + h));
        let k1 = m.increment_at(&start, x, half);
        let k2 = m.increment_at(&middle, &add(x, &k1), half);
        let k3 = m.increment_at(&middle, &add(x, &k2), h);
        let partial: [f64; N] =
            std::array::from_fn(|j| x[j] + (k1[j] + 2.0 * k2[j] + k3[j]) * (1.0 / 3.0));
        add(&partial, &m.increment_at(&end, &add(x, &k3), h / 6.0))
    }

    /// `n` steps of `h` from `x` by the model's whole-step hook, or `None` if it has none.
    fn hooked<const N: usize>(
        m: &GeneralModel<N, true, Moving>,
        h: f64,
        mut x: [f64; N],
        n: usize,
    ) -> Option<[f64; N]> {
        for k in 0..n {
            if !m.rk4_step(0.3 + k as f64 * h, h, &mut x) {
                return None;
            }
        }
        Some(x)
    }

    /// Each part alone, and beside a constant wheel and constant torques in both frames, in
    /// both state sizes: the whole step at once gives the stages' numbers bit for bit.
    #[test]
    fn a_whole_step_at_once_is_the_stages_bit_for_bit() {
        let beside: Vec<AnyPart> = vec![
            Wheel::try_new([0.1, 0.7, -0.3], 0.8).unwrap().into(),
            ConstantTorque::try_new([0.02, -0.01, 0.03], Frame::Body)
                .unwrap()
                .into(),
            ConstantTorque::try_new([0.0, 0.05, 0.1], Frame::World)
                .unwrap()
                .into(),
        ];
        for (k, mover) in movers().into_iter().enumerate() {
            for others in [&[][..], &beside[..]] {
                let mut parts = vec![mover.clone()];
                parts.extend(others.iter().cloned());
                let (h, n) = (0.01, 200);
                let check = |a: &[f64], b: &[f64]| {
                    for (j, (a, b)) in a.iter().zip(b).enumerate() {
                        assert_eq!(
                            a.to_bits(),
                            b.to_bits(),
                            "part {k}, {} others, {j}",
                            others.len()
                        );
                    }
                };
                let q = [0.6, -0.2, 0.7, 0.3];
                let m24 = model::<24>(parts.clone());
                let x = m24.state_from(0.3, [0.3, -0.7, 1.1], q);
                let mut y = x;
                for s in 0..n {
                    y = stages(&m24, 0.3 + s as f64 * h, h, &y);
                }
                check(&hooked(&m24, h, x, n).unwrap(), &y);
                if k < 2 {
                    let m10 = model::<10>(parts);
                    let x = m10.state_from(0.3, [0.3, -0.7, 1.1], q);
                    let mut y = x;
                    for s in 0..n {
                        y = stages(&m10, 0.3 + s as f64 * h, h, &y);
                    }
                    check(&hooked(&m10, h, x, n).unwrap(), &y);
                }
            }
        }
    }

    /// A part with state beside the mover, a stored momentum that changes, or a second mover:
    /// the model's own stages.
    #[test]
    fn other_parts_with_state_or_changing_take_the_stages() {
        let schedule: AnyPart =
            WheelSchedule::try_new([0.0, 0.6, 0.8], vec![0.0, 2.0], vec![0.4, 1.2])
                .unwrap()
                .into();
        let damper: AnyPart = Damper::try_new(0.2, 0.05).unwrap().into();
        let [spring, hinge, _] = movers();
        for parts in [
            vec![damper.clone(), spring.clone()],
            vec![spring.clone(), damper],
            vec![spring.clone(), schedule],
            vec![spring, hinge],
        ] {
            let m = model::<24>(parts);
            let x = m.state_from(0.3, [0.3, -0.7, 1.1], [1.0, 0.0, 0.0, 0.0]);
            assert!(hooked(&m, 0.01, x, 1).is_none());
        }
    }
}
