//! What can be wrong with an expression, said so that the writer knows what to change.

use super::FUNCTION_NAMES;

/// Why an expression could not be parsed.
///
/// Every variant that points at a place carries its `line` (1-based) and `column` (1-based, in
/// characters) within the expression's own source; a caller that embeds expressions in a larger
/// file (a multi-line TOML string, say) adds its own context around the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ExprError {
    /// The source holds nothing but whitespace.
    #[error("the expression is empty: write a number, a name or a formula")]
    Empty,

    /// The source is longer than [`super::Limits::max_length`].
    #[error(
        "the expression is {length} characters long, more than the limit of {limit}: \
         split it into several parameters"
    )]
    TooLong {
        /// The source's length, in characters.
        length: usize,
        /// The limit it exceeds.
        limit: usize,
    },

    /// A character that no token starts with (`#`, `%`, `=`, a non-ASCII letter …).
    #[error(
        "unexpected character '{character}' at line {line}, column {column}: expressions hold \
         only numbers, names, the operators + - * / ^, parentheses and commas"
    )]
    UnexpectedCharacter {
        /// The character.
        character: char,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// A numeric literal that is malformed (`1e`) or out of range (`1e999`).
    #[error("bad number '{text}' at line {line}, column {column}: {reason}")]
    BadNumber {
        /// The literal as written.
        text: String,
        /// What is wrong with it and how to write it.
        reason: String,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// The source stops where something more is needed (`x +`, `sin`, `min(a,`).
    #[error(
        "the expression ends after '{after}' at line {line}, column {column}: give {expected}"
    )]
    UnexpectedEnd {
        /// The last token of the source.
        after: String,
        /// What must follow it.
        expected: String,
        /// The last token's line.
        line: usize,
        /// The last token's column.
        column: usize,
    },

    /// A token where it cannot stand (`2 3`, `* x`, `x (`, `f(,)`).
    #[error("unexpected '{found}' at line {line}, column {column}: expected {expected}")]
    UnexpectedToken {
        /// The token as written.
        found: String,
        /// What could stand there instead.
        expected: String,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// A `(` that is never closed, or a `)` that closes nothing.
    #[error("{}", unbalanced_message(*.parenthesis, *.line, *.column))]
    UnbalancedParenthesis {
        /// The offending parenthesis: `'('` (never closed) or `')'` (closes nothing).
        parenthesis: char,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// A name that the scope does not define.
    #[error(
        "unknown name '{name}' at line {line}, column {column}: define it before using it, \
         or check its spelling"
    )]
    UnknownName {
        /// The name as written.
        name: String,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// A call of a function the language does not have.
    #[error("{}", unknown_function_message(.name, .suggestion.as_deref(), *.line, *.column))]
    UnknownFunction {
        /// The name as written.
        name: String,
        /// The function that was probably meant (`sin` for `sine`), if one is close.
        suggestion: Option<String>,
        /// Its line.
        line: usize,
        /// Its column.
        column: usize,
    },

    /// A function called with the wrong number of arguments.
    #[error(
        "'{function}' takes {expected} argument{} but is given {got}, at line {line}, \
         column {column}: write it as {}",
        if *.expected == 1 { "" } else { "s" },
        usage(.function)
    )]
    WrongArity {
        /// The function.
        function: String,
        /// How many arguments it takes.
        expected: usize,
        /// How many it was given.
        got: usize,
        /// The function name's line.
        line: usize,
        /// The function name's column.
        column: usize,
    },

    /// Parentheses, calls, signs and powers nested deeper than [`super::Limits::max_depth`].
    #[error(
        "the expression nests more than {limit} levels deep at line {line}, column {column}: \
         simplify it or split it into several parameters"
    )]
    TooDeep {
        /// The limit.
        limit: usize,
        /// Line of the token that went past the limit.
        line: usize,
        /// Its column.
        column: usize,
    },
}

impl ExprError {
    /// The `(line, column)` the error points at, if it points at one.
    pub fn position(&self) -> Option<(usize, usize)> {
        match *self {
            Self::Empty | Self::TooLong { .. } => None,
            Self::UnexpectedCharacter { line, column, .. }
            | Self::BadNumber { line, column, .. }
            | Self::UnexpectedEnd { line, column, .. }
            | Self::UnexpectedToken { line, column, .. }
            | Self::UnbalancedParenthesis { line, column, .. }
            | Self::UnknownName { line, column, .. }
            | Self::UnknownFunction { line, column, .. }
            | Self::WrongArity { line, column, .. }
            | Self::TooDeep { line, column, .. } => Some((line, column)),
        }
    }
}

fn unbalanced_message(parenthesis: char, line: usize, column: usize) -> String {
    if parenthesis == '(' {
        format!("the '(' at line {line}, column {column} is never closed: add a ')'")
    } else {
        format!(
            "the ')' at line {line}, column {column} closes nothing: remove it or add a '(' \
             before it"
        )
    }
}

fn unknown_function_message(
    name: &str,
    suggestion: Option<&str>,
    line: usize,
    column: usize,
) -> String {
    let hint = match suggestion {
        Some(s) => format!(" did you mean '{s}'?"),
        None => String::new(),
    };
    format!(
        "unknown function '{name}' at line {line}, column {column}:{hint} the functions are {}",
        FUNCTION_NAMES.join(", ")
    )
}

/// How a function is called, for messages.
fn usage(function: &str) -> String {
    match function {
        "atan2" => "atan2(y, x)".into(),
        "pow" => "pow(x, y)".into(),
        "min" | "max" => format!("{function}(a, b)"),
        _ => format!("{function}(x)"),
    }
}

/// The function that an unknown `name` was probably meant to be: a common alias (`arctan`), or
/// the function within a small edit distance (`sine` → `sin`, `sqr` → `sqrt`).
pub(crate) fn suggest_function(name: &str) -> Option<String> {
    const ALIASES: [(&str, &str); 10] = [
        ("arcsin", "asin"),
        ("arccos", "acos"),
        ("arctan", "atan"),
        ("arctan2", "atan2"),
        ("sine", "sin"),
        ("cosine", "cos"),
        ("tangent", "tan"),
        ("power", "pow"),
        ("fabs", "abs"),
        ("minimum", "min"),
    ];
    let lower = name.to_ascii_lowercase();
    if let Some((_, to)) = ALIASES.iter().find(|(from, _)| *from == lower) {
        return Some((*to).to_string());
    }
    if FUNCTION_NAMES.contains(&lower.as_str()) {
        return Some(lower); // `Sin`, `EXP`
    }
    // One edit for short names, two from six characters on; `log10` gets no suggestion, since
    // `log` is the natural logarithm and would silently change the value.
    let allowed = if lower.chars().count() >= 6 { 2 } else { 1 };
    FUNCTION_NAMES
        .iter()
        .map(|f| (edit_distance(&lower, f), f.len().abs_diff(lower.len()), *f))
        .filter(|(d, _, _)| *d <= allowed)
        .min_by_key(|(d, length_difference, _)| (*d, *length_difference))
        .map(|(_, _, f)| f.to_string())
}

/// Levenshtein distance between two short strings, counting an adjacent swap as one edit.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // rows[i][j]: distance between a[..i] and b[..j].
    let mut rows = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in rows.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in rows[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let substitution = rows[i - 1][j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut best = substitution.min(rows[i - 1][j] + 1).min(rows[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(rows[i - 2][j - 2] + 1);
            }
            rows[i][j] = best;
        }
    }
    rows[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("sine", "sin"), 1);
        assert_eq!(edit_distance("snI", "sni"), 1);
        assert_eq!(edit_distance("sni", "sin"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn suggestions() {
        for (typo, meant) in [
            ("sine", Some("sin")),
            ("sni", Some("sin")),
            ("sqr", Some("sqrt")),
            ("arctan", Some("atan")),
            ("Exp", Some("exp")),
            ("atan3", Some("atan2")),
            ("log10", None),
            ("frobnicate", None),
        ] {
            assert_eq!(suggest_function(typo).as_deref(), meant, "{typo}");
        }
    }

    #[test]
    fn messages_name_the_token_and_the_remedy() {
        let error = ExprError::UnknownFunction {
            name: "sine".into(),
            suggestion: Some("sin".into()),
            line: 2,
            column: 7,
        };
        let text = error.to_string();
        assert!(
            text.contains("'sine'") && text.contains("did you mean 'sin'?"),
            "{text}"
        );
        assert!(
            text.contains("line 2, column 7") && text.contains("atan2, sinh"),
            "{text}"
        );
        let error = ExprError::WrongArity {
            function: "atan2".into(),
            expected: 2,
            got: 1,
            line: 1,
            column: 1,
        };
        assert!(
            error.to_string().contains("write it as atan2(y, x)"),
            "{error}"
        );
        assert_eq!(error.position(), Some((1, 1)));
        assert_eq!(ExprError::Empty.position(), None);
    }
}
