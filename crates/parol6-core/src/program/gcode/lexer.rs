//! One G-code line → its words: comments, the line number and tape marks removed, every
//! number checked (length, digits, finite).

use super::{GcodeError, MAX_LINE_CHARS, MAX_NUMBER_CHARS, MAX_WORDS_PER_LINE};

/// A letter and its number.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Word {
    /// Upper-case letter.
    pub letter: char,
    /// The number.
    pub value: f64,
    /// The word as written, letter upper case (`G1`, `X-1.5`), for messages.
    pub text: String,
}

/// The words of line `line` (1-based) of `raw`; empty for blank, comment-only and `%` lines.
pub(crate) fn words_of_line(line: usize, raw: &str) -> Result<Vec<Word>, GcodeError> {
    let raw = raw.strip_suffix('\r').unwrap_or(raw);
    if raw.chars().count() > MAX_LINE_CHARS {
        return Err(GcodeError::at_line(line, format!("the line is longer than {MAX_LINE_CHARS} characters")));
    }
    let code = strip_comments(line, raw)?;
    if code.trim() == "%" {
        return Ok(Vec::new());
    }
    let chars: Vec<char> = code.chars().collect();
    let mut words = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == ' ' || c == '\t' {
            i += 1;
            continue;
        }
        if !c.is_ascii_alphabetic() {
            return Err(GcodeError::at_line(line, format!("unexpected character '{}'", c.escape_debug())));
        }
        let letter = c.to_ascii_uppercase();
        let start = i + 1;
        let mut end = start;
        while end < chars.len() && (chars[end].is_ascii_digit() || matches!(chars[end], '.' | '+' | '-')) {
            end += 1;
        }
        let exponent = exponent_len(&chars[end..]);
        if end > start && exponent > 0 {
            // `X1e308`: name the number, not a word "E308"
            let number: String = chars[start..end + exponent].iter().collect();
            return Err(GcodeError::at_word(
                line,
                &format!("{letter}{number}"),
                format!("\"{number}\" is not a G-code number: exponents are not allowed, write it out"),
            ));
        }
        let number: String = chars[start..end].iter().collect();
        let text = format!("{letter}{number}");
        let value = parse_number(line, &text, &number)?;
        if letter == 'N' {
            if !words.is_empty() {
                return Err(GcodeError::at_word(line, &text, "a line number (N) must open the line"));
            }
            if number.contains(['.', '-', '+']) {
                return Err(GcodeError::at_word(line, &text, "a line number is a whole number"));
            }
        }
        words.push(Word { letter, value, text });
        if words.len() > MAX_WORDS_PER_LINE + 1 {
            return Err(GcodeError::at_line(line, format!("more than {MAX_WORDS_PER_LINE} words on one line")));
        }
        i = end;
    }
    // the line number is not a word of the block
    if words.first().is_some_and(|w| w.letter == 'N') {
        words.remove(0);
    }
    Ok(words)
}

/// Length of an exponent (`e5`, `E-12`) opening `rest`, 0 when there is none.
fn exponent_len(rest: &[char]) -> usize {
    if !rest.first().is_some_and(|c| matches!(c, 'e' | 'E')) {
        return 0;
    }
    let sign = usize::from(rest.get(1).is_some_and(|c| matches!(c, '+' | '-')));
    let digits = rest[1 + sign..].iter().take_while(|c| c.is_ascii_digit()).count();
    if digits == 0 { 0 } else { 1 + sign + digits }
}

/// The line without `;` and `( … )` comments.
fn strip_comments(line: usize, raw: &str) -> Result<String, GcodeError> {
    let mut out = String::with_capacity(raw.len());
    let mut in_paren = false;
    for c in raw.chars() {
        match (in_paren, c) {
            (false, ';') => break,
            (false, '(') => in_paren = true,
            (false, ')') => return Err(GcodeError::at_line(line, "a ')' without its '('")),
            (false, c) => out.push(c),
            (true, ')') => {
                in_paren = false;
                // a comment separates words like a space
                out.push(' ');
            }
            (true, '(') => return Err(GcodeError::at_line(line, "a '(' inside a comment: comments do not nest")),
            (true, _) => {}
        }
    }
    if in_paren {
        return Err(GcodeError::at_line(line, "a comment '(' is not closed on its line"));
    }
    Ok(out)
}

/// The number of word `text`: optional sign, digits with at most one point, at least one digit.
fn parse_number(line: usize, text: &str, number: &str) -> Result<f64, GcodeError> {
    if number.is_empty() {
        return Err(GcodeError::at_word(line, text, "a letter needs a number right after it"));
    }
    if number.chars().count() > MAX_NUMBER_CHARS {
        return Err(GcodeError::at_word(
            line,
            text,
            format!("the number is longer than {MAX_NUMBER_CHARS} characters"),
        ));
    }
    let body = number.strip_prefix(['+', '-']).unwrap_or(number);
    let digits = body.chars().filter(char::is_ascii_digit).count();
    let points = body.chars().filter(|&c| c == '.').count();
    if digits == 0 || points > 1 || body.contains(['+', '-']) {
        return Err(GcodeError::at_word(line, text, format!("\"{number}\" is not a number")));
    }
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(GcodeError::at_word(line, text, format!("\"{number}\" is not a number"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &str) -> Vec<String> {
        words_of_line(1, line).expect("valid").into_iter().map(|w| w.text).collect()
    }

    fn err(line: &str) -> String {
        words_of_line(3, line).expect_err("invalid").to_string()
    }

    #[test]
    fn words_comments_and_line_numbers() {
        assert_eq!(texts("N10 G1 x10.5 Y-2 (move) Z.5 ; rest"), ["G1", "X10.5", "Y-2", "Z.5"]);
        assert_eq!(texts("g01x1y+2"), ["G01", "X1", "Y+2"]);
        assert!(texts("  ; only a comment").is_empty());
        assert!(texts("%").is_empty());
        assert!(texts("(whole line)\r").is_empty());
        let w = words_of_line(1, "G1 X-0.25").expect("valid");
        assert_eq!((w[1].letter, w[1].value), ('X', -0.25));
    }

    #[test]
    fn bad_lines_name_the_word() {
        assert_eq!(err("G1 X"), "line 3: word \"X\": a letter needs a number right after it");
        assert_eq!(err("G1 X1.2.3"), "line 3: word \"X1.2.3\": \"1.2.3\" is not a number");
        assert_eq!(err("G1 X1-2"), "line 3: word \"X1-2\": \"1-2\" is not a number");
        assert_eq!(err("G1 X-"), "line 3: word \"X-\": \"-\" is not a number");
        assert_eq!(
            err("G1 X1e308"),
            "line 3: word \"X1e308\": \"1e308\" is not a G-code number: exponents are not allowed, write it out"
        );
        assert!(err("G1 Y-2.5E-3 Z1").starts_with("line 3: word \"Y-2.5E-3\": \"-2.5E-3\""));
        // an E word of its own (a 3D printer's extruder) is still an unknown word, not a number
        assert_eq!(texts("G1 X1 E5"), ["G1", "X1", "E5"]);
        assert_eq!(err("G1 * 2"), "line 3: unexpected character '*'");
        assert_eq!(err("G1 (open"), "line 3: a comment '(' is not closed on its line");
        assert_eq!(err("G1 (a (b) c)"), "line 3: a '(' inside a comment: comments do not nest");
        assert_eq!(err("G1 X1 N5"), "line 3: word \"N5\": a line number (N) must open the line");
        assert!(err(&format!("G1 X{}", "1".repeat(30))).contains("longer than 24 characters"));
        assert!(err(&"G1 ".repeat(100)).contains("more than 64 words"));
        assert!(err(&"X".repeat(5000)).contains("longer than 4096 characters"));
    }
}
