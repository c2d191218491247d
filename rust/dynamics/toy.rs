//! A part that exists only to test the seam's hook for sampled parts ([`super::Part::sample`]):
//! a counter of its own sample times, held between them.

use crate::error::Result;

use super::kinds::{Conserved, Traits};
use super::part::{Dim, EnergyRole, Field, Fields, ModelInfo, Param, ParamKind, Part, Sampling};

/// Counts the samples it is called at (its state's rate is 0: a zero-order hold).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Counter {
    pub sampling: Sampling,
}

impl Part for Counter {
    const INFO: ModelInfo = ModelInfo {
        name: "counter",
        about: "counts its sample times (a test of the seam)",
        law: false,
        params: &[
            Param::new("period", ParamKind::Scalar, "time between samples"),
            Param::new("phase", ParamKind::Scalar, "the first sample time"),
        ],
        state: &[Field {
            name: "count",
            width: 1,
            body_vector: false,
            dim: Dim::NONE,
            about: "samples so far",
        }],
        keeps: Conserved::ALL,
        defines: Conserved::NONE,
        energy: EnergyRole::Neither,
        external: false,
        unique: false,
        traits: Traits::PART_STATE.union(Traits::SAMPLED),
    };

    fn from_fields(fields: &Fields) -> Result<Self> {
        Ok(Self {
            sampling: Sampling {
                period: fields.number("period")?,
                phase: fields.number("phase")?,
            },
        })
    }

    fn sampling(&self) -> Option<Sampling> {
        Some(self.sampling)
    }

    fn sample(&self, _c: &super::part::Ctx<'_>, at: usize, x: &mut [f64]) {
        x[at] += 1.0;
    }

    fn in_units(&self, scale: crate::float::RateScale) -> Result<Self> {
        Ok(Self {
            sampling: Sampling {
                period: scale.time_to_unit(self.sampling.period),
                phase: scale.time_to_unit(self.sampling.phase),
            },
        })
    }
}
