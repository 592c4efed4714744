//! What is wrong with a model file, where, and what to do about it.

use std::fmt;

/// Where in the input a [`ModelError`] points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// A place in the file: a syntax error, or a value whose meaning is wrong. `key` is the
    /// value's key path (`constraint[1].restitution`), when the place belongs to one.
    At {
        /// 1-based line.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// The key path of the value, if any.
        key: Option<Box<str>>,
    },
    /// A key that is missing (its full path, e.g. `constraint[2].h`).
    Missing(String),
    /// A command-line override, as written (`--set m=2`).
    Override(String),
    /// The file as a whole (too large to read, say).
    File,
}

/// Why a model file was refused.
///
/// Its `Display` names the file, then the line and column (and the key, when the error is about
/// a value's meaning) or the missing key, then what is wrong, the offending line with a caret
/// under the place, and what to do:
///
/// ```text
/// ball.toml:9:5: constraint[1].restitution: the restitution is 1.5, outside [0, 1]
///    |
///  9 | restitution = 1.5
///    |               ^
///    = help: a coefficient of restitution lies between 0 (perfectly plastic) and 1 (elastic)
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError {
    /// The file, as the user named it.
    pub file: Box<str>,
    /// Where.
    pub location: Location,
    /// What is wrong.
    pub message: String,
    /// What to do about it.
    pub help: Option<String>,
    /// The source line pointed at, when there is one.
    pub(crate) snippet: Option<Box<str>>,
}

impl ModelError {
    /// An error about the file as a whole.
    pub(crate) fn file(file: &str, message: impl Into<String>, help: impl Into<String>) -> Self {
        Self {
            file: file.into(),
            location: Location::File,
            message: message.into(),
            help: Some(help.into()),
            snippet: None,
        }
    }

    /// The key path the error is about, if any.
    pub fn key(&self) -> Option<&str> {
        match &self.location {
            Location::At { key, .. } => key.as_deref(),
            Location::Missing(key) => Some(key),
            _ => None,
        }
    }

    /// The 1-based `(line, column)` the error points at, if any.
    pub fn position(&self) -> Option<(usize, usize)> {
        match self.location {
            Location::At { line, column, .. } => Some((line, column)),
            _ => None,
        }
    }
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Location::At { line, column, key } => {
                write!(f, "{}:{line}:{column}: ", self.file)?;
                if let Some(key) = key {
                    write!(f, "{key}: ")?;
                }
            }
            Location::Missing(key) => write!(f, "{}: missing key `{key}`: ", self.file)?,
            Location::Override(arg) => write!(f, "{}: --set {arg}: ", self.file)?,
            Location::File => write!(f, "{}: ", self.file)?,
        }
        f.write_str(&self.message)?;
        if let Some(snippet) = &self.snippet {
            write!(f, "\n{snippet}")?;
        }
        if let Some(help) = &self.help {
            write!(f, "\n   = help: {help}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ModelError {}

/// The byte offsets where each line of `source` starts, to turn offsets into lines and columns.
#[derive(Clone, Debug)]
pub(crate) struct Lines<'s> {
    source: &'s str,
    starts: Vec<usize>,
}

impl<'s> Lines<'s> {
    pub(crate) fn new(source: &'s str) -> Self {
        let starts = std::iter::once(0)
            .chain(source.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self { source, starts }
    }

    /// The 1-based line and column (in characters) of byte `offset`.
    pub(crate) fn position(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.source.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let column = self
            .source
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count());
        (line + 1, column + 1)
    }

    /// The source line `line` (1-based) with a caret under `column`.
    pub(crate) fn snippet(&self, line: usize, column: usize) -> Option<String> {
        let start = *self.starts.get(line - 1)?;
        let end = self.starts.get(line).map_or(self.source.len(), |&e| e - 1);
        let text = self.source.get(start..end)?.trim_end_matches('\r');
        // Very long lines (a generated expression) are cut around the column.
        let (shown, caret) = if text.chars().count() > 120 {
            let from = column.saturating_sub(60);
            let cut: String = text.chars().skip(from).take(120).collect();
            (format!("…{cut}…"), column - from + 1)
        } else {
            (text.to_string(), column)
        };
        let number = line.to_string();
        let pad = " ".repeat(number.len());
        let under: String = shown
            .chars()
            .take(caret.saturating_sub(1))
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        Some(format!("{pad} |\n{number} | {shown}\n{pad} | {under}^"))
    }

    /// An error at byte `offset` of the source.
    pub(crate) fn error_at(
        &self,
        file: &str,
        offset: usize,
        key: Option<&str>,
        message: impl Into<String>,
        help: Option<String>,
    ) -> ModelError {
        let (line, column) = self.position(offset);
        ModelError {
            file: file.into(),
            location: Location::At {
                line,
                column,
                key: key.map(Box::from),
            },
            message: message.into(),
            help,
            snippet: self.snippet(line, column).map(String::into_boxed_str),
        }
    }
}

/// The candidate closest to `word` by edit distance, if it is close enough to be a likely typo.
pub(crate) fn suggest<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(1);
    // A shortening or a lengthening (`eps` for `epsilon`) counts as close.
    let affix =
        |c: &str| word.len().min(c.len()) >= 3 && (c.starts_with(word) || word.starts_with(c));
    candidates
        .into_iter()
        .map(|c| (if affix(c) { 1 } else { edit_distance(word, c) }, c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// `"did you mean `x`? "` for the candidate closest to `word`, or nothing.
pub(crate) fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> String {
    match suggest(word, candidates) {
        Some(s) => format!("did you mean `{s}`? "),
        None => String::new(),
    }
}

/// Levenshtein distance, in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (diagonal + usize::from(ca != cb))
                .min(above + 1)
                .min(row[j] + 1);
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_characters() {
        let lines = Lines::new("a = 1\nπ = \"x\"\n");
        assert_eq!(lines.position(0), (1, 1));
        assert_eq!(lines.position(4), (1, 5));
        assert_eq!(lines.position(6), (2, 1));
        // 'π' is two bytes but one column.
        assert_eq!(lines.position(6 + 2 + 3), (2, 5));
        assert_eq!(
            lines.snippet(2, 5).unwrap(),
            "  |\n2 | π = \"x\"\n  |     ^"
        );
    }

    #[test]
    fn errors_are_small_enough_to_return() {
        // Clippy's `result_large_err` warns above 128 bytes, in every caller.
        assert!(
            std::mem::size_of::<ModelError>() <= 128,
            "{}",
            std::mem::size_of::<ModelError>()
        );
    }

    #[test]
    fn suggestions() {
        assert_eq!(
            suggest("constraints", ["constraint", "name"]),
            Some("constraint")
        );
        assert_eq!(
            suggest("lagrangain", ["lagrangian", "name"]),
            Some("lagrangian")
        );
        assert_eq!(suggest("zzz", ["lagrangian", "name"]), None);
        assert_eq!(suggest("eps", ["epsilon"]), Some("epsilon"));
        assert_eq!(suggest("mass", ["m", "g"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
