//! Splits an expression's source into tokens, each with its line and column.

use super::error::ExprError;

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum TokenKind<'s> {
    /// A numeric literal, already converted (always finite and non-negative).
    Number(f64),
    /// An identifier: a name, a constant or a function.
    Name(&'s str),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LeftParen,
    RightParen,
    Comma,
}

/// One token of the source, with where it starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Token<'s> {
    pub kind: TokenKind<'s>,
    /// The token's text exactly as written (for messages).
    pub text: &'s str,
    /// 1-based line of the token's first character.
    pub line: usize,
    /// 1-based column, in characters, of the token's first character within its line.
    pub column: usize,
}

/// Splits `source` into tokens; whitespace (spaces, tabs, carriage returns, newlines) separates
/// tokens and is otherwise ignored.
pub(crate) fn tokenize(source: &str) -> Result<Vec<Token<'_>>, ExprError> {
    let mut lexer = Lexer {
        source,
        bytes: source.as_bytes(),
        offset: 0,
        line: 1,
        column: 1,
    };
    let mut tokens = Vec::new();
    while let Some(token) = lexer.next_token()? {
        tokens.push(token);
    }
    Ok(tokens)
}

struct Lexer<'s> {
    source: &'s str,
    bytes: &'s [u8],
    /// Byte offset of the next character.
    offset: usize,
    /// Line and column of the next character.
    line: usize,
    column: usize,
}

impl<'s> Lexer<'s> {
    fn peek_byte(&self, ahead: usize) -> Option<u8> {
        self.bytes.get(self.offset + ahead).copied()
    }

    /// Advances over `count` ASCII bytes that are not newlines.
    fn advance_ascii(&mut self, count: usize) {
        self.offset += count;
        self.column += count;
    }

    fn skip_digits(&mut self) -> usize {
        let start = self.offset;
        while self.peek_byte(0).is_some_and(|b| b.is_ascii_digit()) {
            self.advance_ascii(1);
        }
        self.offset - start
    }

    fn next_token(&mut self) -> Result<Option<Token<'s>>, ExprError> {
        // Whitespace.
        while let Some(b) = self.peek_byte(0) {
            match b {
                b'\n' => {
                    self.offset += 1;
                    self.line += 1;
                    self.column = 1;
                }
                b' ' | b'\t' | b'\r' => self.advance_ascii(1),
                _ => break,
            }
        }
        let Some(first) = self.peek_byte(0) else {
            return Ok(None);
        };
        let (start, line, column) = (self.offset, self.line, self.column);
        let kind = match first {
            b'+' | b'-' | b'*' | b'/' | b'^' | b'(' | b')' | b',' => {
                self.advance_ascii(1);
                match first {
                    b'+' => TokenKind::Plus,
                    b'-' => TokenKind::Minus,
                    b'*' => TokenKind::Star,
                    b'/' => TokenKind::Slash,
                    b'^' => TokenKind::Caret,
                    b'(' => TokenKind::LeftParen,
                    b')' => TokenKind::RightParen,
                    _ => TokenKind::Comma,
                }
            }
            b'0'..=b'9' => self.number(line, column)?,
            b'.' if self.peek_byte(1).is_some_and(|b| b.is_ascii_digit()) => {
                self.number(line, column)?
            }
            b if b.is_ascii_alphabetic() || b == b'_' => {
                while self
                    .peek_byte(0)
                    .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_')
                {
                    self.advance_ascii(1);
                }
                TokenKind::Name(&self.source[start..self.offset])
            }
            _ => {
                let character = self.source[start..].chars().next().unwrap_or('\u{fffd}');
                return Err(ExprError::UnexpectedCharacter {
                    character,
                    line,
                    column,
                });
            }
        };
        Ok(Some(Token {
            kind,
            text: &self.source[start..self.offset],
            line,
            column,
        }))
    }

    /// A number: `digits [. digits?] | . digits`, then an optional exponent `e[+-]digits`.
    fn number(&mut self, line: usize, column: usize) -> Result<TokenKind<'s>, ExprError> {
        let start = self.offset;
        self.skip_digits();
        if self.peek_byte(0) == Some(b'.') {
            self.advance_ascii(1);
            self.skip_digits();
        }
        if matches!(self.peek_byte(0), Some(b'e' | b'E')) {
            let sign = usize::from(matches!(self.peek_byte(1), Some(b'+' | b'-')));
            if self.peek_byte(1 + sign).is_some_and(|b| b.is_ascii_digit()) {
                self.advance_ascii(1 + sign);
                self.skip_digits();
            } else {
                // Take in the whole malformed literal (e.g. `1e`, `2e+x`) for the message.
                self.advance_ascii(1 + sign);
                while self
                    .peek_byte(0)
                    .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_')
                {
                    self.advance_ascii(1);
                }
                return Err(ExprError::BadNumber {
                    text: self.source[start..self.offset].to_string(),
                    reason: "an exponent needs digits after 'e', as in 1e-3 or 2.5E+4".into(),
                    line,
                    column,
                });
            }
        }
        let text = &self.source[start..self.offset];
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(TokenKind::Number(value)),
            _ => Err(ExprError::BadNumber {
                text: text.to_string(),
                reason: "it is too large for a 64-bit float (the largest is about 1.8e308)".into(),
                line,
                column,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(source: &str) -> Vec<TokenKind<'_>> {
        tokenize(source)
            .unwrap()
            .into_iter()
            .map(|t| t.kind)
            .collect()
    }

    #[test]
    fn numbers_in_every_spelling() {
        for (text, value) in [
            ("2", 2.0),
            ("1.5e-3", 1.5e-3),
            (".5", 0.5),
            ("3.", 3.0),
            ("1E+3", 1000.0),
            ("007", 7.0),
            ("6.02e23", 6.02e23),
        ] {
            assert_eq!(kinds(text), vec![TokenKind::Number(value)], "{text}");
        }
    }

    #[test]
    fn names_operators_and_positions() {
        let tokens = tokenize("a_1+ _b\n\t*(x2, 3)").unwrap();
        let summary: Vec<_> = tokens.iter().map(|t| (t.text, t.line, t.column)).collect();
        assert_eq!(
            summary,
            vec![
                ("a_1", 1, 1),
                ("+", 1, 4),
                ("_b", 1, 6),
                ("*", 2, 2),
                ("(", 2, 3),
                ("x2", 2, 4),
                (",", 2, 6),
                ("3", 2, 8),
                (")", 2, 9),
            ]
        );
        assert_eq!(tokens[0].kind, TokenKind::Name("a_1"));
    }

    #[test]
    fn a_number_then_a_name_are_two_tokens() {
        assert_eq!(
            kinds("2x"),
            vec![TokenKind::Number(2.0), TokenKind::Name("x")]
        );
        assert_eq!(
            kinds("1.2.3"),
            vec![TokenKind::Number(1.2), TokenKind::Number(0.3)]
        );
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let error = tokenize("é + ∑").unwrap_err();
        assert_eq!(
            error,
            ExprError::UnexpectedCharacter {
                character: 'é',
                line: 1,
                column: 1
            }
        );
        let error = tokenize("x + ∑").unwrap_err();
        assert_eq!(
            error,
            ExprError::UnexpectedCharacter {
                character: '∑',
                line: 1,
                column: 5
            }
        );
    }

    #[test]
    fn malformed_and_overflowing_numbers() {
        for (source, text) in [
            ("1e", "1e"),
            ("2*1e+", "1e+"),
            ("3E-x", "3E-x"),
            ("1e999", "1e999"),
        ] {
            match tokenize(source).unwrap_err() {
                ExprError::BadNumber { text: got, .. } => assert_eq!(got, text, "{source}"),
                other => panic!("{source}: {other:?}"),
            }
        }
    }
}
