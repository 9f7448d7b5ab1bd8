//! The header lines a G-code file may carry for PAROL6 Studio: whole-line comments of the form
//! `; parol6: abc=xyz` before the first G-code word. Other programs read them as comments.

use super::{AbcChoice, AbcConvention, GcodeError};

/// What opens a header comment (after `;`, case-insensitive).
const PREFIX: &str = "parol6:";

/// The header line export writes for `convention` (`; parol6: abc=commander`).
pub fn abc_header(convention: AbcConvention) -> String {
    format!("; {PREFIX} abc={}", convention.name())
}

/// True when `comment` (the text after `;`) would be read as a header: it opens with `parol6:`
/// and holds a `key=value`. Export writes such comment text otherwise.
pub(crate) fn looks_like_header(comment: &str) -> bool {
    let t = comment.trim_start();
    t.get(..PREFIX.len()).is_some_and(|p| p.eq_ignore_ascii_case(PREFIX)) && t.contains('=')
}

/// The `A B C` convention named on line `line` (1-based) of `raw`, if it is a header line.
/// A header with an unknown key or value is an error naming the line.
fn abc_of_line(line: usize, raw: &str) -> Result<Option<AbcConvention>, GcodeError> {
    let Some(comment) = raw.trim_start().strip_prefix(';') else { return Ok(None) };
    if !looks_like_header(comment) {
        return Ok(None);
    }
    let settings = comment.trim_start()[PREFIX.len()..].trim();
    let mut abc = None;
    for item in settings.split_whitespace() {
        let Some((key, value)) = item.split_once('=') else {
            return Err(GcodeError::at_line(
                line,
                format!("the parol6 header item \"{item}\" is not key=value (e.g. abc=xyz)"),
            ));
        };
        if !key.eq_ignore_ascii_case("abc") {
            return Err(GcodeError::at_line(line, format!("unknown parol6 header setting \"{key}\" (known: abc)")));
        }
        let convention: AbcConvention = value.parse().map_err(|e| GcodeError::at_line(line, format!("{e}")))?;
        if abc.is_some_and(|a| a != convention) {
            return Err(GcodeError::at_line(line, "the parol6 header names abc twice, differently"));
        }
        abc = Some(convention);
    }
    Ok(abc)
}

/// Follows the header lines of a file and decides the convention.
pub(crate) struct Header {
    choice: AbcChoice,
    /// The convention the file names, and the line that names it.
    named: Option<(AbcConvention, usize)>,
    /// A line with G-code words was read: headers are over.
    closed: bool,
}

impl Header {
    pub(crate) fn new(choice: AbcChoice) -> Self {
        Self { choice, named: None, closed: false }
    }

    /// Reads line `line` (`has_words`: it holds G-code words); `Some` when the convention is
    /// decided here (the first line with words), to use from then on.
    pub(crate) fn line(
        &mut self,
        line: usize,
        raw: &str,
        has_words: bool,
    ) -> Result<Option<AbcConvention>, GcodeError> {
        if let Some(abc) = abc_of_line(line, raw)? {
            if self.closed {
                return Err(GcodeError::at_line(
                    line,
                    "a \"; parol6:\" header line must come before the first G-code word",
                ));
            }
            if let Some((other, first)) = self.named
                && other != abc
            {
                return Err(GcodeError::at_line(
                    line,
                    format!("the header says abc={abc} here but abc={other} on line {first}"),
                ));
            }
            if self.choice.explicit && abc != self.choice.convention {
                return Err(GcodeError::at_line(
                    line,
                    format!(
                        "the file's header says abc={abc} but abc={} was asked for (--abc {}): \
                         remove the header line or ask for {abc}",
                        self.choice.convention, self.choice.convention
                    ),
                ));
            }
            self.named.get_or_insert((abc, line));
        }
        if has_words && !self.closed {
            self.closed = true;
            return Ok(Some(self.convention()));
        }
        Ok(None)
    }

    /// The convention in force: the header's, else the choice's.
    pub(crate) fn convention(&self) -> AbcConvention {
        self.named.map_or(self.choice.convention, |(c, _)| c)
    }
}
