//! Turns tokens into a postfix program: an operator-precedence (shunting-yard) parser.
//!
//! It never recurses: pending operators, parentheses and calls wait on an explicit stack whose
//! height is the nesting depth, checked against [`Limits::max_depth`] at every push. Each
//! operator is emitted, and folded if its operands are constant, as soon as both its operands
//! are complete.

use std::collections::HashSet;

use super::builder::Builder;
use super::error::{suggest_function, ExprError};
use super::lexer::{tokenize, Token, TokenKind};
use super::ops::Op;
use super::program::Expression;
use super::{Limits, Scope};

/// A binary operator of the language.
#[derive(Clone, Copy, Debug, PartialEq)]
enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

impl BinaryOp {
    /// Binding strength: `+ -` 1, `* /` 2, the signs 3, `^` 4.
    fn precedence(self) -> u8 {
        match self {
            BinaryOp::Add | BinaryOp::Sub => 1,
            BinaryOp::Mul | BinaryOp::Div => 2,
            BinaryOp::Pow => 4,
        }
    }
}

/// The precedence of a sign: looser than `^` (`-x^2 = -(x^2)`), tighter than `*`.
const SIGN_PRECEDENCE: u8 = 3;

/// Something begun and not yet complete, waiting on the stack; `token` indexes the token that
/// began it.
#[derive(Clone, Copy, Debug)]
enum Pending {
    /// A minus sign waiting for its operand.
    Negation { token: usize },
    /// A binary operator waiting for its right operand.
    Binary { op: BinaryOp, token: usize },
    /// An open parenthesis.
    Group { token: usize },
    /// A function call: `token` is the function's name, the `(` follows it.
    Call {
        op: Op,
        arity: usize,
        token: usize,
        commas: usize,
    },
}

pub(crate) fn parse<S: Scope + ?Sized>(
    source: &str,
    scope: &S,
    limits: &Limits,
) -> Result<Expression, ExprError> {
    if source.len() > limits.max_length {
        let length = source.chars().count();
        if length > limits.max_length {
            return Err(ExprError::TooLong {
                length,
                limit: limits.max_length,
            });
        }
    }
    let tokens = tokenize(source)?;
    if tokens.is_empty() {
        return Err(ExprError::Empty);
    }
    let mut parser = Parser {
        tokens: &tokens,
        scope,
        max_depth: limits.max_depth,
        pending: Vec::new(),
        builder: Builder::default(),
        names: Vec::new(),
        seen: HashSet::new(),
    };
    parser.run()?;
    Ok(parser.builder.finish(source, parser.names))
}

struct Parser<'t, 's, S: ?Sized> {
    tokens: &'t [Token<'s>],
    scope: &'t S,
    max_depth: usize,
    pending: Vec<Pending>,
    builder: Builder,
    /// The distinct names read, in order of appearance.
    names: Vec<String>,
    seen: HashSet<&'s str>,
}

impl<S: Scope + ?Sized> Parser<'_, '_, S> {
    fn run(&mut self) -> Result<(), ExprError> {
        let mut expect_operand = true;
        let mut i = 0;
        while i < self.tokens.len() {
            let token = self.tokens[i];
            if expect_operand {
                match token.kind {
                    TokenKind::Number(value) => {
                        self.builder.constant(value);
                        expect_operand = false;
                    }
                    TokenKind::Name(name) => {
                        // A call consumes its `(` too and still expects an operand.
                        if self.name(name, i)? {
                            i += 1;
                        } else {
                            expect_operand = false;
                        }
                    }
                    TokenKind::Minus => self.push(Pending::Negation { token: i })?,
                    TokenKind::Plus => {} // a plus sign changes nothing
                    TokenKind::LeftParen => self.push(Pending::Group { token: i })?,
                    TokenKind::RightParen => {
                        // `f()`: the call's `(` is the token just before.
                        if let Some(&Pending::Call { arity, token, .. }) = self
                            .pending
                            .last()
                            .filter(|_| self.tokens[i - 1].kind == TokenKind::LeftParen)
                        {
                            let name = self.tokens[token];
                            return Err(ExprError::WrongArity {
                                function: name.text.to_string(),
                                expected: arity,
                                got: 0,
                                line: name.line,
                                column: name.column,
                            });
                        }
                        return Err(self.unexpected(i, self.expected_operand(i)));
                    }
                    TokenKind::Star | TokenKind::Slash | TokenKind::Caret | TokenKind::Comma => {
                        let mut expected = self.expected_operand(i);
                        if token.kind == TokenKind::Star
                            && i > 0
                            && self.tokens[i - 1].kind == TokenKind::Star
                        {
                            expected.push_str("; write '^' for a power, not '**'");
                        }
                        return Err(self.unexpected(i, expected));
                    }
                }
            } else {
                let op = match token.kind {
                    TokenKind::Plus => Some(BinaryOp::Add),
                    TokenKind::Minus => Some(BinaryOp::Sub),
                    TokenKind::Star => Some(BinaryOp::Mul),
                    TokenKind::Slash => Some(BinaryOp::Div),
                    TokenKind::Caret => Some(BinaryOp::Pow),
                    _ => None,
                };
                match (op, token.kind) {
                    (Some(op), _) => {
                        self.reduce_for(op);
                        self.push(Pending::Binary { op, token: i })?;
                        expect_operand = true;
                    }
                    (None, TokenKind::RightParen) => self.close(i)?,
                    (None, TokenKind::Comma) => {
                        self.comma(i)?;
                        expect_operand = true;
                    }
                    _ => {
                        let expected =
                            format!("{}; write '*' to multiply", self.expected_operator());
                        return Err(self.unexpected(i, expected));
                    }
                }
            }
            i += 1;
        }
        let last = self.tokens.len() - 1;
        if expect_operand {
            let token = self.tokens[last];
            return Err(ExprError::UnexpectedEnd {
                after: token.text.to_string(),
                expected: self.expected_operand(last + 1),
                line: token.line,
                column: token.column,
            });
        }
        while let Some(pending) = self.pending.pop() {
            self.finish_pending(pending)?;
        }
        Ok(())
    }

    /// Handles a name in operand position; returns whether it opened a call.
    fn name(&mut self, name: &'_ str, i: usize) -> Result<bool, ExprError> {
        let token = self.tokens[i];
        let next = self.tokens.get(i + 1);
        let opens = next.is_some_and(|t| t.kind == TokenKind::LeftParen);
        if let Some((op, arity)) = Op::function(name) {
            if opens {
                self.push(Pending::Call {
                    op,
                    arity,
                    token: i,
                    commas: 0,
                })?;
                return Ok(true);
            }
            let expected = format!("'(' and the argument{}", if arity == 1 { "" } else { "s" });
            return Err(match next {
                None => ExprError::UnexpectedEnd {
                    after: name.to_string(),
                    expected: format!("{expected} of the function '{name}'"),
                    line: token.line,
                    column: token.column,
                },
                Some(_) => self.unexpected(i + 1, format!("{expected} of the function '{name}'")),
            });
        }
        // A name bound to a constant compiles to its value, so that folding applies to it.
        let (constant, slot) = if name == "pi" {
            (Some(std::f64::consts::PI), None)
        } else {
            match self.scope.constant(name) {
                Some(value) => (Some(value), None),
                None => (None, self.scope.resolve(name)),
            }
        };
        if opens {
            if constant.is_some() || slot.is_some() {
                let expected = format!("an operator after '{name}', which is not a function");
                return Err(self.unexpected(i + 1, format!("{expected}; write '*' to multiply")));
            }
            return Err(ExprError::UnknownFunction {
                name: name.to_string(),
                suggestion: suggest_function(name),
                line: token.line,
                column: token.column,
            });
        }
        if let Some(value) = constant {
            self.builder.constant(value);
        } else if let Some(slot) = slot {
            self.builder.variable(slot);
        } else {
            return Err(ExprError::UnknownName {
                name: name.to_string(),
                line: token.line,
                column: token.column,
            });
        }
        // Names bound to constants are listed too: the caller may need to know they were read.
        if name != "pi" && self.seen.insert(token.text) {
            self.names.push(name.to_string());
        }
        Ok(false)
    }

    fn push(&mut self, pending: Pending) -> Result<(), ExprError> {
        if self.pending.len() >= self.max_depth {
            let token = match pending {
                Pending::Negation { token }
                | Pending::Binary { token, .. }
                | Pending::Group { token }
                | Pending::Call { token, .. } => self.tokens[token],
            };
            return Err(ExprError::TooDeep {
                limit: self.max_depth,
                line: token.line,
                column: token.column,
            });
        }
        self.pending.push(pending);
        Ok(())
    }

    /// Before pushing `op`: emits the pending operators that bind at least as tightly (strictly
    /// more tightly for the right-associative `^`).
    fn reduce_for(&mut self, op: BinaryOp) {
        let precedence = op.precedence();
        let right_associative = op == BinaryOp::Pow;
        while let Some(&top) = self.pending.last() {
            let top_precedence = match top {
                Pending::Negation { .. } => SIGN_PRECEDENCE,
                Pending::Binary { op, .. } => op.precedence(),
                Pending::Group { .. } | Pending::Call { .. } => break,
            };
            if top_precedence > precedence || (top_precedence == precedence && !right_associative) {
                self.pending.pop();
                self.emit_operator(top);
            } else {
                break;
            }
        }
    }

    fn emit_operator(&mut self, pending: Pending) {
        match pending {
            Pending::Negation { .. } => self.builder.apply(Op::Neg),
            Pending::Binary { op, .. } => self.builder.apply(match op {
                BinaryOp::Add => Op::Add,
                BinaryOp::Sub => Op::Sub,
                BinaryOp::Mul => Op::Mul,
                BinaryOp::Div => Op::Div,
                BinaryOp::Pow => Op::Pow,
            }),
            Pending::Group { .. } | Pending::Call { .. } => unreachable!("not an operator"),
        }
    }

    /// At the end of the source: emits an operator, or reports a parenthesis left open.
    fn finish_pending(&mut self, pending: Pending) -> Result<(), ExprError> {
        let open = match pending {
            Pending::Group { token } => token,
            Pending::Call { token, .. } => token + 1,
            operator => {
                self.emit_operator(operator);
                return Ok(());
            }
        };
        let token = self.tokens[open];
        Err(ExprError::UnbalancedParenthesis {
            parenthesis: '(',
            line: token.line,
            column: token.column,
        })
    }

    /// A `)` after a complete operand: closes the innermost group or call.
    fn close(&mut self, i: usize) -> Result<(), ExprError> {
        loop {
            match self.pending.pop() {
                None => {
                    let token = self.tokens[i];
                    return Err(ExprError::UnbalancedParenthesis {
                        parenthesis: ')',
                        line: token.line,
                        column: token.column,
                    });
                }
                Some(Pending::Group { .. }) => return Ok(()),
                Some(Pending::Call {
                    op,
                    arity,
                    token,
                    commas,
                }) => {
                    if commas + 1 != arity {
                        let name = self.tokens[token];
                        return Err(ExprError::WrongArity {
                            function: name.text.to_string(),
                            expected: arity,
                            got: commas + 1,
                            line: name.line,
                            column: name.column,
                        });
                    }
                    self.builder.apply(op);
                    return Ok(());
                }
                Some(operator) => self.emit_operator(operator),
            }
        }
    }

    /// A `,` after a complete operand: ends an argument of the innermost call.
    fn comma(&mut self, i: usize) -> Result<(), ExprError> {
        loop {
            match self.pending.last_mut() {
                Some(Pending::Call { commas, .. }) => {
                    *commas += 1;
                    return Ok(());
                }
                Some(Pending::Group { .. }) | None => {
                    let expected = format!(
                        "{}; a ',' only separates the arguments of a function call",
                        self.expected_operator()
                    );
                    return Err(self.unexpected(i, expected));
                }
                Some(&mut operator) => {
                    self.pending.pop();
                    self.emit_operator(operator);
                }
            }
        }
    }

    fn unexpected(&self, i: usize, expected: String) -> ExprError {
        let token = self.tokens[i];
        ExprError::UnexpectedToken {
            found: token.text.to_string(),
            expected,
            line: token.line,
            column: token.column,
        }
    }

    /// What may stand at token `i` (or the end, `i == len`) when an operand is due.
    fn expected_operand(&self, i: usize) -> String {
        let previous = i.checked_sub(1).map(|p| self.tokens[p]);
        let call_name = || match self.pending.last() {
            Some(Pending::Call { token, .. }) => Some(self.tokens[*token].text),
            _ => None,
        };
        match previous.map(|t| (t.kind, t.text)) {
            None => "a number, a name, a function call or '('".into(),
            Some((TokenKind::LeftParen, _)) => match call_name() {
                Some(name) => format!("the arguments of '{name}' and a ')'"),
                None => "an expression and a ')'".into(),
            },
            Some((TokenKind::Comma, _)) => match call_name() {
                Some(name) => format!("the next argument of '{name}'"),
                None => "the next argument".into(),
            },
            Some((_, text)) => match self.pending.last() {
                Some(Pending::Binary { token, .. }) if *token == i - 1 => {
                    format!("the right operand of '{text}'")
                }
                _ => format!("the operand of the sign '{text}'"),
            },
        }
    }

    /// What may follow a complete operand, given the innermost open group or call.
    fn expected_operator(&self) -> &'static str {
        let innermost = self
            .pending
            .iter()
            .rev()
            .find(|p| matches!(p, Pending::Group { .. } | Pending::Call { .. }));
        match innermost {
            Some(Pending::Call { .. }) => "an operator such as '+' or '*', a ',' or a ')'",
            Some(_) => "an operator such as '+' or '*', or a ')'",
            None => "an operator such as '+' or '*', or the end of the expression",
        }
    }
}
