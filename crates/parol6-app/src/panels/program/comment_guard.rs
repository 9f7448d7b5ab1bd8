//! Save writes a program file from the program's steps, so the comments of a file written by
//! hand (G-code `( … )` and `; …`, a point table's `#` lines) that the steps do not carry
//! would be lost. Save onto the program's own file counts them first and asks while there are
//! any (trial17 D1: they went without a word); "Save and quit" refuses, naming them.

use std::collections::HashSet;
use std::path::Path;

use parol6_core::program::files::{FormatContext, MAX_PROGRAM_FILE_BYTES, ProgramFormat, format_program};
use parol6_core::program::gcode::AbcChoice;

use super::ProgramPanel;

impl ProgramPanel {
    /// How many comment lines of the file at `path` a save of the program there would drop:
    /// those whose comments the written text does not hold again. 0 when the file cannot be
    /// read or the program cannot be written in its format (the save then says why).
    pub(super) fn comments_a_save_drops(
        &self,
        path: &Path,
        model: &parol6_core::RobotModel,
        start_q: &[f64],
        settings: &crate::panels::Settings,
    ) -> usize {
        let Ok(format) = ProgramFormat::from_path(path) else { return 0 };
        if matches!(format, ProgramFormat::Json | ProgramFormat::Commander) {
            return 0; // neither holds comments
        }
        let Ok(old) = parol6_core::fsio::read_regular_bounded_string(path, MAX_PROGRAM_FILE_BYTES) else {
            return 0;
        };
        let fctx =
            FormatContext { abc: AbcChoice::default_to(settings.gcode_abc), ..FormatContext::new(model, start_q) };
        let shown = path.display().to_string();
        let Ok(new) = format_program(self.editor.program(), format, &fctx, &shown) else { return 0 };
        dropped_comment_lines(&old, &new, format)
    }
}

/// The lines of `old` with a comment that `new` does not hold (compared trimmed).
pub(super) fn dropped_comment_lines(old: &str, new: &str, format: ProgramFormat) -> usize {
    let kept: HashSet<&str> = new.lines().flat_map(|l| line_comments(l, format)).collect();
    old.lines().filter(|l| line_comments(l, format).iter().any(|c| !kept.contains(c))).count()
}

/// The comments of one line, trimmed, empty ones left out.
fn line_comments(line: &str, format: ProgramFormat) -> Vec<&str> {
    let mut found = Vec::new();
    match format {
        ProgramFormat::Csv => {
            if let Some(rest) = line.trim_start().strip_prefix('#') {
                found.push(rest.trim());
            }
        }
        ProgramFormat::Gcode => {
            let mut rest = line;
            while let Some(at) = rest.find(['(', ';']) {
                if rest[at..].starts_with(';') {
                    found.push(rest[at + 1..].trim());
                    break;
                }
                let inner = &rest[at + 1..];
                let end = inner.find(')').unwrap_or(inner.len());
                found.push(inner[..end].trim());
                rest = inner.get(end + 1..).unwrap_or("");
            }
        }
        ProgramFormat::Json | ProgramFormat::Commander => {}
    }
    found.retain(|c| !c.is_empty());
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gcode_comments_the_new_text_does_not_hold_are_counted_by_line() {
        let old = "(my square)\nG0 X1 ; above the start\nG1 X2 (fast) ; both\nG1 X3\n; parol6: abc=commander\n";
        let new = "; parol6: abc=commander\nG0 X1\nG1 X2\nG1 X3\n";
        assert_eq!(dropped_comment_lines(old, new, ProgramFormat::Gcode), 3);
        assert_eq!(dropped_comment_lines(new, new, ProgramFormat::Gcode), 0, "our own comments come back");
    }

    #[test]
    fn point_table_comments_are_hash_lines() {
        let old = "# taught on Monday\nj1_deg,j2_deg\n1,2\n";
        assert_eq!(dropped_comment_lines(old, "j1_deg,j2_deg\n1,2\n", ProgramFormat::Csv), 1);
        assert_eq!(dropped_comment_lines("a;b\n(c)\n", "", ProgramFormat::Commander), 0);
    }
}
