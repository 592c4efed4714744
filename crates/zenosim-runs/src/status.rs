//! How a run ended, in the words `summary.json` and a sweep's rows use.

use std::fmt;

use zenosim::Outcome;

/// How a run ended, or that it was never run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// It reached its stop time (through its Zeno points, if any).
    Finished,
    /// It stopped at a Zeno point (`zeno = off`).
    ZenoStalled,
    /// A numerical failure; what was computed up to then is kept.
    Failed,
    /// The caller stopped it ([`zenosim::Observer::interrupted`]).
    Interrupted,
    /// A sweep's point whose values the model refuses (a restitution outside `[0, 1]`, an
    /// initial state below a constraint): never run.
    Invalid,
}

impl Status {
    /// Every status, in the order of this enum.
    pub const ALL: [Status; 5] = [
        Status::Finished,
        Status::ZenoStalled,
        Status::Failed,
        Status::Interrupted,
        Status::Invalid,
    ];

    /// The status of a run that ended with `outcome`.
    pub fn of(outcome: &Outcome) -> Self {
        match outcome {
            Outcome::Finished => Self::Finished,
            Outcome::ZenoStalled { .. } => Self::ZenoStalled,
            Outcome::Failed(_) => Self::Failed,
            Outcome::Interrupted => Self::Interrupted,
        }
    }

    /// Its word: `finished`, `zeno_stalled`, `failed`, `interrupted` or `invalid`.
    pub fn word(self) -> &'static str {
        match self {
            Self::Finished => "finished",
            Self::ZenoStalled => "zeno_stalled",
            Self::Failed => "failed",
            Self::Interrupted => "interrupted",
            Self::Invalid => "invalid",
        }
    }

    /// The status whose [`Status::word`] is `word`.
    pub fn from_word(word: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.word() == word)
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_read_back() {
        for status in Status::ALL {
            assert_eq!(Status::from_word(status.word()), Some(status));
        }
        assert_eq!(Status::from_word("done"), None);
        assert_eq!(Status::of(&Outcome::Interrupted).word(), "interrupted");
    }
}
