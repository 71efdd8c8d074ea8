//! Why a job script cannot be written.

/// Why a job script cannot be written; each names the option at fault.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum JobError {
    /// A tile count outside 1 to [`MAX_JOB_TILES`](super::MAX_JOB_TILES).
    #[error("--tiles: {value} is out of range: a job has 1 to {max} tiles")]
    Tiles {
        /// The count asked for.
        value: u32,
        /// The most a job has.
        max: u32,
    },
    /// A path or value the engine's script cannot carry as it is.
    #[error("{option}: `{value}` cannot go in the job: {why}")]
    Unfit {
        /// The option (or `the scene`) it came from.
        option: &'static str,
        /// The value, lossily as text.
        value: String,
        /// What is wrong with it.
        why: &'static str,
    },
}

/// A [`JobError::Unfit`] for `value` of `option`.
pub(crate) fn unfit(option: &'static str, value: &str, why: &'static str) -> JobError {
    JobError::Unfit {
        option,
        value: value.to_string(),
        why,
    }
}
