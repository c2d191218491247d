//! RK4 projected onto what a model keeps; see [`Rk4Projected`].

use crate::dynamics::Model;
use crate::integrators::Rk4;
use crate::ode::Stepper;

/// RK4, each step followed by the model's projection onto what its exact motion keeps
/// ([`Model::project`]): for the free body the energy, `|L|`, `L_world` and `|q| = 1`
/// ([`crate::dynamics::FreeProjection`], which says what that keeps at large steps); for a
/// model without torque `|H|`, `H` in space and `|q|` (never the energy, which a
/// deployment's work or a damper's loss changes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4Projected<K> {
    kept: K,
}

impl<K> Rk4Projected<K> {
    /// Projected RK4 keeping what `sys` keeps from `x0` at `t = 0`.
    pub fn new<const N: usize, S: Model<N, Kept = K>>(sys: &S, x0: &[f64; N]) -> Self {
        Self {
            kept: sys.kept(0.0, x0),
        }
    }
}

impl<const N: usize, S: Model<N>> Stepper<N, S> for Rk4Projected<S::Kept> {
    const ORDER: u32 = 4;
    const RHS_PER_STEP: u64 = 4;

    #[inline]
    fn step(&self, sys: &S, t: f64, h: f64, x: &mut [f64; N]) {
        Stepper::<N, S>::step(&Rk4, sys, t, h, x);
        sys.project(&self.kept, t + h, x);
    }
}

#[cfg(test)]
mod tests {
    use crate::body::RigidBody;
    use crate::dynamics::{q_body_to_world, FreeProjection, State};
    use crate::kinematics::rotation_matrix;
    use approx::assert_relative_eq;
    use nalgebra::Vector3;

    #[test]
    fn projection_lands_on_both_invariants() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let x0 = [0.3, -0.4, 0.5, 1.0, 0.0, 0.0, 0.0];
        let p = FreeProjection::new(&body, &x0);
        // an RK4-sized departure: one Gauss–Newton step leaves its square
        let mut x = [
            0.3 * (1.0 + 1e-6),
            -0.4 * (1.0 - 1e-6),
            0.5 + 1e-6,
            1.01,
            0.02,
            0.0,
            0.0,
        ];
        p.project(&mut x);
        let i = body.inertia_body();
        let energy = |x: &State| (0..3).map(|k| i[k] * x[k] * x[k]).sum::<f64>();
        let momentum = |x: &State| (0..3).map(|k| (i[k] * x[k]).powi(2)).sum::<f64>();
        let world = |x: &State| {
            rotation_matrix(&q_body_to_world(x)) * Vector3::new(i.x * x[0], i.y * x[1], i.z * x[2])
        };
        assert_relative_eq!(energy(&x), energy(&x0), max_relative = 1e-11);
        assert_relative_eq!(momentum(&x), momentum(&x0), max_relative = 1e-11);
        let q_norm = (3..7).map(|k| x[k] * x[k]).sum::<f64>().sqrt();
        assert_relative_eq!(q_norm, 1.0, epsilon = 1e-15);
        assert!((world(&x) - world(&x0)).norm() < 1e-11 * world(&x0).norm());
    }

    #[test]
    fn huge_and_tiny_rates_are_projected_without_overflow() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        for s in [1e150, 1e-150] {
            let x0 = [0.3 * s, -0.4 * s, 0.5 * s, 1.0, 0.0, 0.0, 0.0];
            let p = FreeProjection::new(&body, &x0);
            let mut x = [
                0.3 * s * (1.0 + 1e-9),
                -0.4 * s,
                0.5 * s,
                1.0,
                0.0,
                0.0,
                0.0,
            ];
            p.project(&mut x);
            assert!(x.iter().all(|v| v.is_finite()));
            assert_relative_eq!(x[1], x0[1], max_relative = 1e-8);
        }
    }

    #[test]
    fn spin_about_an_axis_is_rescaled() {
        let body = RigidBody::try_new([1.0, 2.0, 3.0]).unwrap();
        let x0 = [0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0];
        let p = FreeProjection::new(&body, &x0);
        let mut x = [0.0, 0.0, 2.002, 1.0, 0.0, 0.0, 0.0];
        p.project(&mut x);
        assert_relative_eq!(x[2], 2.0, epsilon = 1e-15);
    }
}
