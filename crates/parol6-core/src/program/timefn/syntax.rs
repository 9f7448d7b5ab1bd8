//! The syntax check of a time-function expression before `exmex` parses it: one left-to-right
//! pass over the tokens that knows whether a value or an operator comes next, so every
//! mistake gets the column where it is (exmex's own errors carry no position). Whatever passes
//! here is plain ASCII of numbers, known names, `+ - * / ^`, parentheses and commas, nested at
//! most [`MAX_NESTING`](super::MAX_NESTING) deep and at most
//! [`MAX_EXPRESSION_CHARS`](super::MAX_EXPRESSION_CHARS) long.

use super::{MAX_EXPRESSION_CHARS, MAX_NESTING};

/// An open parenthesis: its column, and for a function call its name, arity and commas seen.
struct Open {
    column: usize,
    function: Option<(&'static str, usize)>,
    commas: usize,
}

/// Checks `text`. `names`: variables and constants; `unary` / `binary`: functions of one and
/// two arguments. Error: (1-based column, message).
pub(super) fn check(
    text: &str,
    names: &[&str],
    unary: &[&'static str],
    binary: &[&'static str],
) -> Result<(), (usize, String)> {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() > MAX_EXPRESSION_CHARS {
        return Err((
            MAX_EXPRESSION_CHARS + 1,
            format!("the expression is {} characters long; at most {MAX_EXPRESSION_CHARS}", chars.len()),
        ));
    }
    let mut open: Vec<Open> = Vec::new();
    // true: a number, a name, a function or '(' comes next; false: an operator, ',' or ')'
    let mut want_value = true;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c == ' ' || c == '\t' {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            let number: String = chars[start..i].iter().collect();
            if !want_value {
                return Err((column, format!("an operator (+ - * / ^) is missing before \"{number}\"")));
            }
            if number.matches('.').count() > 1 || number == "." {
                return Err((column, format!("\"{number}\" is not a number")));
            }
            want_value = false;
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let name: String = chars[start..i].iter().collect();
            if !want_value {
                return Err((column, format!("an operator (+ - * / ^) is missing before \"{name}\"")));
            }
            let function = unary
                .iter()
                .find(|f| **f == name)
                .map(|f| (*f, 1))
                .or_else(|| binary.iter().find(|f| **f == name).map(|f| (*f, 2)));
            if let Some(function) = function {
                let mut j = i;
                while j < chars.len() && (chars[j] == ' ' || chars[j] == '\t') {
                    j += 1;
                }
                if chars.get(j) != Some(&'(') {
                    return Err((column, format!("the function {name} needs its argument in parentheses: {name}(…)")));
                }
                if open.len() >= MAX_NESTING {
                    return Err((j + 1, format!("parentheses nest deeper than {MAX_NESTING} levels")));
                }
                open.push(Open { column: j + 1, function: Some(function), commas: 0 });
                i = j + 1;
                continue;
            }
            if !names.contains(&name.as_str()) {
                return Err((
                    column,
                    format!(
                        "unknown name \"{name}\" (the variable is t; constants pi, tau, e; functions such as sin, \
                         cos, sqrt, atan2)"
                    ),
                ));
            }
            want_value = false;
            continue;
        }
        match c {
            '(' => {
                if !want_value {
                    return Err((column, "an operator (+ - * / ^) is missing before '('".into()));
                }
                if open.len() >= MAX_NESTING {
                    return Err((column, format!("parentheses nest deeper than {MAX_NESTING} levels")));
                }
                open.push(Open { column, function: None, commas: 0 });
            }
            ')' => {
                if want_value {
                    return Err((column, "a number, t, a function or '(' is expected before ')'".into()));
                }
                let Some(o) = open.pop() else {
                    return Err((column, "')' without a matching '('".into()));
                };
                if let Some((name, arity)) = o.function
                    && o.commas + 1 != arity
                {
                    return Err((
                        column,
                        format!("{name} takes {arity} argument{}", if arity == 1 { "" } else { "s" }),
                    ));
                }
            }
            ',' => {
                if want_value {
                    return Err((column, "a number, t, a function or '(' is expected before ','".into()));
                }
                match open.last_mut() {
                    Some(Open { function: Some((_, 2)), commas, .. }) if *commas == 0 => {
                        *commas += 1;
                        want_value = true;
                    }
                    _ => return Err((column, "',' outside the arguments of atan2, min or max".into())),
                }
            }
            '+' | '-' => {
                // unary where a value is expected, binary otherwise
                want_value = true;
            }
            '*' | '/' | '^' => {
                if want_value {
                    return Err((column, format!("a number, t, a function or '(' is expected before '{c}'")));
                }
                want_value = true;
            }
            other => return Err((column, format!("unexpected character '{other}'"))),
        }
        i += 1;
    }
    if let Some(o) = open.last() {
        return Err((o.column, "'(' is never closed".into()));
    }
    if want_value {
        if chars.iter().all(|c| *c == ' ' || *c == '\t') {
            return Err((1, "the expression is empty".into()));
        }
        return Err((chars.len() + 1, "the expression ends where a number, t, a function or '(' is expected".into()));
    }
    Ok(())
}
