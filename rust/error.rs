//! The one error type of the core; the bindings map it to `ValueError`.

use std::borrow::Cow;

/// Everything the core refuses, each naming the argument at fault and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An argument outside its allowed range.
    #[error("`{name}` {allowed}, got {got}")]
    InvalidArgument {
        name: &'static str,
        allowed: Cow<'static, str>,
        got: String,
    },
    /// A request whose output or step count is too large to honour. `what` is a singular
    /// phrase ("the run", "keeping the frames") and `limit` a noun phrase ("the limit
    /// max_steps = 100", "the memory this process can allocate"), so that the message reads
    /// as a sentence.
    #[error("{what} needs {needed}, more than {limit}; {hint}")]
    TooLarge {
        what: Cow<'static, str>,
        needed: String,
        limit: String,
        hint: &'static str,
    },
    /// The state stopped being finite: the step is far beyond the method's stability limit.
    /// (`t` is shown as Debug shows an `f64`: `1e-280`, not 280 zeros.)
    #[error("the run diverged (non-finite state) at t = {t:?}: {hint}")]
    Diverged { t: f64, hint: &'static str },
    /// A model whose parts only dissipate gained energy beyond the run's error, at the first
    /// frame `t` that showed it, by the factor `ratio`: the step is beyond the method's
    /// stability limit for the parts' dissipation.
    #[error(
        "the run diverged at t = {t:?}: the energy grew to {ratio:.4} times its start, and a \
         body whose parts only dissipate only loses energy: take a smaller dt (below the \
         stability limit of its parts' dissipation)"
    )]
    EnergyGrew { t: f64, ratio: f64 },
    /// A method asked to run a model it cannot run.
    #[error("method '{method}' cannot run model '{model}'; use one of {supported}")]
    Unsupported {
        method: &'static str,
        model: &'static str,
        supported: String,
    },
    /// The caller asked the run to stop (Ctrl-C in Python).
    #[error("interrupted")]
    Interrupted,
    /// What went wrong with one run of a batch, and which.
    #[error("row {row}: {error}")]
    Row { row: usize, error: Box<Error> },
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// This error, as that of run `row` of a batch.
    pub(crate) fn in_row(self, row: usize) -> Self {
        match self {
            Error::Interrupted | Error::Row { .. } => self,
            error => Error::Row {
                row,
                error: Box::new(error),
            },
        }
    }

    pub(crate) fn invalid(
        name: &'static str,
        allowed: impl Into<Cow<'static, str>>,
        got: impl std::fmt::Debug,
    ) -> Self {
        Error::InvalidArgument {
            name,
            allowed: allowed.into(),
            got: format!("{got:?}"),
        }
    }
}

#[cfg(test)]
mod display {
    use super::*;

    #[test]
    fn a_divergence_time_is_short_at_any_scale() {
        for (t, shown) in [(1e-280, "1e-280"), (15.5, "15.5"), (1e300, "1e300")] {
            let text = Error::Diverged { t, hint: "h" }.to_string();
            assert!(text.contains(&format!("t = {shown}:")), "{text}");
            assert!(text.len() < 80, "{text}");
        }
    }

    #[test]
    fn a_request_too_large_reads_as_a_sentence() {
        // an allocation names what it holds ("the step plans needs" read wrongly)
        let text = crate::buffer::ensure_room(1e30, "the step plans", "plan fewer")
            .unwrap_err()
            .to_string();
        assert!(
            text.starts_with(
                "holding the step plans needs about 1.000e30 bytes, more than the memory"
            ),
            "{text}"
        );
        // a step limit is named once ("more than the limit the most steps a run can count")
        let text = crate::run::FrameGrid::try_new(1e300, 3, 1e-300, u64::MAX)
            .unwrap_err()
            .to_string();
        assert!(
            text.contains(", more than the most steps a run can count (2^64 - 1);"),
            "{text}"
        );
        let text = crate::run::FrameGrid::try_new(1.0, 3, 1e-12, 100)
            .unwrap_err()
            .to_string();
        assert!(
            text.contains(", more than the limit max_steps = 100;"),
            "{text}"
        );
    }
}
