//! Every error: its variant, where it points, and a message that says what to do.

use std::time::{Duration, Instant};

use zenosim_model::expr::{ExprError, Expression, Limits, DEFAULT_MAX_DEPTH, DEFAULT_MAX_LENGTH};

fn error(source: &str) -> ExprError {
    match Expression::parse(source, &["x", "y", "mass_1"]) {
        Ok(e) => panic!("{source:?} parsed: {e:?}"),
        Err(e) => e,
    }
}

/// Asserts where `error` points and that its message contains each of `phrases`.
fn check(error: &ExprError, line: usize, column: usize, phrases: &[&str]) {
    assert_eq!(error.position(), Some((line, column)), "{error:?}");
    let message = error.to_string();
    let at = format!("line {line}, column {column}");
    assert!(message.contains(&at), "{message:?} lacks {at:?}");
    for phrase in phrases {
        assert!(message.contains(phrase), "{message:?} lacks {phrase:?}");
    }
}

#[test]
fn empty() {
    for source in ["", "  \n\t "] {
        let e = error(source);
        assert_eq!(e, ExprError::Empty);
        assert!(e.to_string().contains("write a number"), "{e}");
    }
}

#[test]
fn unexpected_character() {
    let e = error("x +\n  y # 2");
    assert!(matches!(
        e,
        ExprError::UnexpectedCharacter { character: '#', .. }
    ));
    check(&e, 2, 5, &["'#'", "only numbers, names"]);
    let e = error("2 * θ");
    check(&e, 1, 5, &["'θ'"]);
    let e = error("x.y");
    check(&e, 1, 2, &["'.'"]);
}

#[test]
fn bad_number() {
    let e = error("2 * 1e+");
    assert!(matches!(&e, ExprError::BadNumber { text, .. } if text == "1e+"));
    check(&e, 1, 5, &["'1e+'", "digits after 'e'", "1e-3"]);
    let e = error("1e400");
    check(&e, 1, 1, &["'1e400'", "too large"]);
}

#[test]
fn unexpected_end() {
    let e = error("x +");
    assert!(matches!(&e, ExprError::UnexpectedEnd { after, .. } if after == "+"));
    check(
        &e,
        1,
        3,
        &["ends after '+'", "give the right operand of '+'"],
    );
    check(
        &error("x *\n  -"),
        2,
        3,
        &["after '-'", "operand of the sign '-'"],
    );
    check(
        &error("min(x,"),
        1,
        6,
        &["after ','", "the next argument of 'min'"],
    );
    check(
        &error("atan2("),
        1,
        6,
        &["after '('", "the arguments of 'atan2'"],
    );
    check(
        &error("x * ("),
        1,
        5,
        &["after '('", "an expression and a ')'"],
    );
    let e = error("2 * sin");
    assert!(matches!(&e, ExprError::UnexpectedEnd { after, .. } if after == "sin"));
    check(
        &e,
        1,
        5,
        &["after 'sin'", "'(' and the argument of the function 'sin'"],
    );
}

#[test]
fn unexpected_token() {
    let e = error("2 3");
    assert!(matches!(&e, ExprError::UnexpectedToken { found, .. } if found == "3"));
    check(
        &e,
        1,
        3,
        &["unexpected '3'", "an operator", "write '*' to multiply"],
    );
    check(
        &error("2x"),
        1,
        2,
        &["unexpected 'x'", "write '*' to multiply"],
    );
    check(&error("* x"), 1, 1, &["unexpected '*'", "a number, a name"]);
    check(
        &error("x ** 2"),
        1,
        4,
        &["unexpected '*'", "write '^' for a power"],
    );
    check(
        &error("x + / y"),
        1,
        5,
        &["unexpected '/'", "right operand of '+'"],
    );
    check(
        &error("(x, y)"),
        1,
        3,
        &["unexpected ','", "separates the arguments"],
    );
    check(
        &error("x, y"),
        1,
        2,
        &["unexpected ','", "end of the expression"],
    );
    check(
        &error("(x)(y)"),
        1,
        4,
        &["unexpected '('", "or the end of", "to multiply"],
    );
    check(&error("((x)(y))"), 1, 5, &["unexpected '('", "or a ')'"]);
    check(
        &error("sin(x y)"),
        1,
        7,
        &["unexpected 'y'", "a ',' or a ')'"],
    );
    check(
        &error("()"),
        1,
        2,
        &["unexpected ')'", "an expression and a ')'"],
    );
    check(&error(")"), 1, 1, &["unexpected ')'", "a number, a name"]);
    check(
        &error("\n\n  ,"),
        3,
        3,
        &["unexpected ','", "a number, a name"],
    );
    check(
        &error("sin + 1"),
        1,
        5,
        &["unexpected '+'", "'(' and the argument of"],
    );
    check(
        &error("x(2)"),
        1,
        2,
        &["unexpected '('", "'x', which is not a function"],
    );
    check(&error("pi (2)"), 1, 4, &["'pi', which is not a function"]);
}

#[test]
fn unbalanced_parenthesis() {
    let e = error("(x + (y)");
    assert!(matches!(
        e,
        ExprError::UnbalancedParenthesis {
            parenthesis: '(',
            ..
        }
    ));
    check(&e, 1, 1, &["'('", "never closed", "add a ')'"]);
    check(&error("sin(x + (y)"), 1, 4, &["never closed"]);
    let e = error("x + y)\n");
    assert!(matches!(
        e,
        ExprError::UnbalancedParenthesis {
            parenthesis: ')',
            ..
        }
    ));
    check(&e, 1, 6, &["')'", "closes nothing", "remove it"]);
    check(&error("(x))"), 1, 4, &["closes nothing"]);
}

#[test]
fn unknown_name() {
    let e = error("0.5 *\n   mass * x");
    assert_eq!(
        e,
        ExprError::UnknownName {
            name: "mass".into(),
            line: 2,
            column: 4
        }
    );
    check(&e, 2, 4, &["unknown name 'mass'", "define it", "spelling"]);
}

#[test]
fn unknown_function() {
    let e = error("2 * sine(x)");
    assert_eq!(
        e,
        ExprError::UnknownFunction {
            name: "sine".into(),
            suggestion: Some("sin".into()),
            line: 1,
            column: 5
        }
    );
    check(
        &e,
        1,
        5,
        &["'sine'", "did you mean 'sin'?", "sin, cos, tan", "min, max"],
    );
    let e = error("frob(x)");
    assert!(matches!(
        e,
        ExprError::UnknownFunction {
            suggestion: None,
            ..
        }
    ));
    assert!(!e.to_string().contains("did you mean"), "{e}");
    check(&e, 1, 1, &["the functions are sin"]);
    assert!(matches!(
        error("log10(x)"),
        ExprError::UnknownFunction {
            suggestion: None,
            ..
        }
    ));
}

#[test]
fn wrong_arity() {
    let e = error("1 + atan2(y)");
    assert_eq!(
        e,
        ExprError::WrongArity {
            function: "atan2".into(),
            expected: 2,
            got: 1,
            line: 1,
            column: 5
        }
    );
    check(
        &e,
        1,
        5,
        &["'atan2' takes 2 arguments", "given 1", "atan2(y, x)"],
    );
    check(
        &error("sin(x, y)"),
        1,
        1,
        &["'sin' takes 1 argument ", "given 2", "sin(x)"],
    );
    check(&error("max()"), 1, 1, &["given 0", "max(a, b)"]);
    check(&error("pow(x, y, 2)"), 1, 1, &["given 3", "pow(x, y)"]);
}

#[test]
fn too_deep_with_the_column_that_went_past() {
    let limits = Limits {
        max_depth: 4,
        ..Limits::default()
    };
    // A sign, a group, a '+' waiting for its right operand, and a group: 4 levels.
    assert!(Expression::parse_with("-(x + (y))", &["x", "y"], &limits).is_ok());
    let e = Expression::parse_with("-(x + (-y))", &["x", "y"], &limits).unwrap_err();
    assert_eq!(
        e,
        ExprError::TooDeep {
            limit: 4,
            line: 1,
            column: 8
        }
    );
    check(&e, 1, 8, &["more than 4 levels", "split it"]);
    // Exactly the default depth parses; one more does not.
    let at_limit = format!(
        "{}x{}",
        "(".repeat(DEFAULT_MAX_DEPTH),
        ")".repeat(DEFAULT_MAX_DEPTH)
    );
    assert!(Expression::parse(&at_limit, &["x"]).is_ok());
    let past = format!("({at_limit})");
    assert!(matches!(
        Expression::parse(&past, &["x"]),
        Err(ExprError::TooDeep { limit: 256, .. })
    ));
    // Chains of signs and powers count too.
    let signs = format!("{}x", "-".repeat(1000));
    assert!(matches!(error(&signs), ExprError::TooDeep { .. }));
    let powers = format!("x{}", "^x".repeat(1000));
    assert!(matches!(error(&powers), ExprError::TooDeep { .. }));
    // A long flat sum is not deep.
    let sum = format!("x{}", "+x".repeat(10_000));
    assert_eq!(
        Expression::parse(&sum, &["x"]).unwrap().eval(&[1.0]),
        10_001.0
    );
}

#[test]
fn a_hundred_thousand_parentheses_fail_fast() {
    let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    let limits = Limits {
        max_length: 1_000_000,
        ..Limits::default()
    };
    let start = Instant::now();
    let e = Expression::parse_with(&deep, &["x"], &limits).unwrap_err();
    assert_eq!(
        e,
        ExprError::TooDeep {
            limit: 256,
            line: 1,
            column: 257
        }
    );
    // Within the default length limit, too.
    let e = Expression::parse(&deep[..DEFAULT_MAX_LENGTH], &["x"]).unwrap_err();
    assert!(matches!(e, ExprError::TooDeep { column: 257, .. }), "{e:?}");
    // Even a huge depth limit never recurses: the parser keeps its own stack.
    let unlimited = Limits {
        max_depth: usize::MAX,
        max_length: usize::MAX,
        max_operations: usize::MAX,
    };
    let e = Expression::parse_with(&deep, &["x"], &unlimited).unwrap();
    assert_eq!(e.eval(&[3.0]), 3.0);
    assert!(
        start.elapsed() < Duration::from_secs(1),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn too_long() {
    let huge = "x+".repeat(500_000) + "x";
    let start = Instant::now();
    let e = error(&huge);
    assert_eq!(
        e,
        ExprError::TooLong {
            length: 1_000_001,
            limit: DEFAULT_MAX_LENGTH
        }
    );
    assert!(e.to_string().contains("1000001 characters"), "{e}");
    assert!(e.to_string().contains("limit of 100000"), "{e}");
    assert_eq!(e.position(), None);
    assert!(start.elapsed() < Duration::from_millis(200));
    // Length is counted in characters, not bytes.
    let limits = Limits {
        max_length: 3,
        ..Limits::default()
    };
    let e = Expression::parse_with("ééé", &(), &limits).unwrap_err();
    assert!(matches!(
        e,
        ExprError::UnexpectedCharacter {
            character: 'é', ..
        }
    ));
    let e = Expression::parse_with("éééé", &(), &limits).unwrap_err();
    assert!(matches!(
        e,
        ExprError::TooLong {
            length: 4,
            limit: 3
        }
    ));
}
