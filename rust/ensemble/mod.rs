//! Many runs at once: batches and sweeps, RK4 in SIMD lanes.

pub mod batch;
pub mod lanes;
pub mod plan;
pub mod sweep;
pub mod systems;
