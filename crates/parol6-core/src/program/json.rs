//! The native program file: JSON, versioned, units in the field names.
//!
//! ```json
//! {
//!   "format": "parol6-program",
//!   "version": 1,
//!   "name": "pick and place",
//!   "description": "one line on what it does",
//!   "tool": "Ssg48",
//!   "speed": { "joint_fraction": 0.5, "tcp_speed_mm_s": 100, "tcp_accel_mm_s2": 500, "tcp_jerk_mm_s3": 5000 },
//!   "keep_out": [ { "name": "fixture", "kind": "box", "center_mm": [250, 0, 50], "size_mm": [100, 100, 100] } ],
//!   "looping": false,
//!   "tracking": "lead",
//!   "steps": [
//!     { "type": "home" },
//!     { "type": "move_l", "pose": { "position_mm": [0, 250, 300], "rpy_deg": [180, 0, 90] }, "speed_mm_s": 50 },
//!     { "type": "dwell", "seconds": 0.5 }
//!   ]
//! }
//! ```
//!
//! Every step type is [`Step`] in `snake_case` with a `type` tag. A file of another
//! format or a newer version, and any malformed field, is refused with an error naming the
//! field (`steps[3].pose.position_mm`), the line and the column; loading never touches the
//! program already in memory (it returns a new one or an error).

use serde::{Deserialize, Serialize};

use super::{Program, SourcedStep, SpeedSettings, Step};
use crate::parol6::Tool;
use crate::scene::KeepOut;

/// The `format` field of a program file.
pub const FORMAT: &str = "parol6-program";
/// The newest version this build reads and the one it writes.
pub const VERSION: u32 = 1;
/// Files larger than this are refused before parsing, bytes.
pub const MAX_FILE_BYTES: usize = 16 * 1024 * 1024;

/// Why a program file cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProgramFileError {
    /// Not JSON, or a field with the wrong type or value.
    #[error("line {line}, column {column}: {field}: {message}")]
    Field {
        /// The field's path, e.g. `steps[2].pose.rpy_deg`.
        field: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// Not a program file, or a version this build does not read.
    #[error("{0}")]
    Format(String),
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ProgramFile {
    format: String,
    version: u32,
    #[serde(default)]
    name: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    description: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tool: Option<Tool>,
    #[serde(default)]
    speed: SpeedSettings,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    keep_out: Vec<KeepOut>,
    #[serde(default, skip_serializing_if = "is_false")]
    looping: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tracking: Option<crate::motion::tracking::TrackingMode>,
    steps: Vec<Step>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

#[derive(Deserialize)]
struct Header {
    format: Option<serde_json::Value>,
    version: Option<serde_json::Value>,
}

/// Parses a program file.
pub fn parse(text: &str) -> Result<Program, ProgramFileError> {
    if text.len() > MAX_FILE_BYTES {
        return Err(ProgramFileError::Format(format!(
            "the file is {} bytes; program files are limited to {} MiB",
            text.len(),
            MAX_FILE_BYTES / (1024 * 1024)
        )));
    }
    if text.trim().is_empty() {
        return Err(ProgramFileError::Format("the file is empty".into()));
    }
    // the header first, so a file of another format or version gets that message rather
    // than one about a field this version does not know
    let header: Header = serde_json::from_str(text).map_err(|e| field_error("(file)", &e))?;
    match header.format.as_ref().and_then(|v| v.as_str()) {
        Some(FORMAT) => {}
        Some(other) => {
            return Err(ProgramFileError::Format(format!(
                "format: \"{other}\" is not a PAROL6 program (\"{FORMAT}\")"
            )));
        }
        None => {
            return Err(ProgramFileError::Format(format!(
                "format: missing; a program file has \"format\": \"{FORMAT}\""
            )));
        }
    }
    match header.version.as_ref().and_then(serde_json::Value::as_u64) {
        Some(v) if v >= 1 && v <= u64::from(VERSION) => {}
        Some(v) => {
            return Err(ProgramFileError::Format(format!(
                "version: {v} is not readable by this build (it reads versions 1 to {VERSION}); update PAROL6 Studio"
            )));
        }
        None => return Err(ProgramFileError::Format("version: missing or not a whole number".into())),
    }
    let mut de = serde_json::Deserializer::from_str(text);
    let lines = step_lines(text);
    let file: ProgramFile = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let mut err = field_error(&path, e.inner());
        // serde reads a tagged step whole and reports the end of it: point at its start
        if let ProgramFileError::Field { line, column, .. } = &mut err
            && let Some(start) = step_index(&path).and_then(|i| lines.get(i))
            && *start != *line
        {
            *line = *start;
            *column = 1;
        }
        err
    })?;
    let steps = file
        .steps
        .into_iter()
        .enumerate()
        .map(|(i, step)| SourcedStep { step, line: lines.get(i).copied().unwrap_or(0) })
        .collect();
    Ok(Program {
        name: file.name,
        description: file.description,
        tool: file.tool,
        speed: file.speed,
        keep_out: file.keep_out,
        steps,
        looping: file.looping,
        tracking: file.tracking,
    })
}

/// Writes a program file (pretty-printed, one step per line).
pub fn to_string(program: &Program) -> String {
    let file = ProgramFile {
        format: FORMAT.into(),
        version: VERSION,
        name: program.name.clone(),
        description: program.description.clone(),
        tool: program.tool,
        speed: program.speed,
        keep_out: program.keep_out.clone(),
        looping: program.looping,
        tracking: program.tracking,
        steps: Vec::new(),
    };
    // the envelope pretty-printed, each step compact on its own line (a diff shows the steps)
    let mut head = serde_json::to_value(&file).unwrap_or_default();
    if let Some(map) = head.as_object_mut() {
        map.remove("steps");
    }
    let head = serde_json::to_string_pretty(&head).unwrap_or_else(|_| "{}".into());
    let head = head.trim_end().trim_end_matches('}').trim_end();
    let steps: Vec<String> = program
        .steps
        .iter()
        .map(|s| format!("    {}", serde_json::to_string(&s.step).unwrap_or_else(|_| "{}".into())))
        .collect();
    let sep = if head.ends_with('{') { "" } else { "," };
    format!("{head}{sep}\n  \"steps\": [\n{}\n  ]\n}}\n", steps.join(",\n"))
}

fn field_error(field: &str, e: &serde_json::Error) -> ProgramFileError {
    let message = e.to_string();
    // serde_json appends " at line L column C"; the position is reported separately
    let message = match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message,
    };
    let field = if field.is_empty() || field == "." { "(file)".to_string() } else { field.to_string() };
    ProgramFileError::Field { field, line: e.line(), column: e.column(), message }
}

/// `N` of a path `steps[N]…`.
fn step_index(path: &str) -> Option<usize> {
    let rest = path.strip_prefix("steps[")?;
    rest[..rest.find(']')?].parse().ok()
}

/// The 1-based line on which each element of the top-level `steps` array starts.
fn step_lines(text: &str) -> Vec<usize> {
    let mut lines = Vec::new();
    let (mut depth, mut line) = (0usize, 1usize);
    let (mut in_string, mut escaped) = (false, false);
    let mut string_start = 0usize;
    let mut last_key: Option<(usize, usize)> = None;
    let mut in_steps = false;
    let mut expect_element = false;
    for (i, c) in text.char_indices() {
        if c == '\n' {
            line += 1;
        }
        if in_string {
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
                if depth == 1 {
                    last_key = Some((string_start, i));
                }
            }
            continue;
        }
        if in_steps && expect_element && depth == 2 && !c.is_whitespace() && c != ',' && c != ']' {
            lines.push(line);
            expect_element = false;
        }
        match c {
            '"' => {
                in_string = true;
                string_start = i + 1;
            }
            '{' | '[' => {
                if c == '[' && depth == 1 && last_key.is_some_and(|(a, b)| &text[a..b] == "steps") {
                    in_steps = true;
                    expect_element = true;
                }
                depth += 1;
            }
            '}' | ']' => {
                depth = depth.saturating_sub(1);
                if depth == 1 && in_steps && c == ']' {
                    in_steps = false;
                }
            }
            ',' if in_steps && depth == 2 => expect_element = true,
            _ => {}
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::{GripperAction, PoseMm};

    const EXAMPLE: &str = r#"{
  "format": "parol6-program",
  "version": 1,
  "name": "demo",
  "tool": "Ssg48",
  "speed": { "joint_fraction": 0.4, "tcp_speed_mm_s": 80, "tcp_accel_mm_s2": 400, "tcp_jerk_mm_s3": 4000 },
  "keep_out": [ { "name": "fixture", "kind": "box", "center_mm": [250, 0, 50], "size_mm": [100, 100, 100] } ],
  "steps": [
    { "type": "home" },
    { "type": "move_l", "pose": { "position_mm": [0, 250, 300], "rpy_deg": [180, 0, 90] }, "speed_mm_s": 50 },

    {
      "type": "gripper", "action": "close"
    },
    { "type": "dwell", "seconds": 0.5 }
  ]
}"#;

    #[test]
    fn a_program_file_reads_with_the_line_of_every_step() {
        let p = parse(EXAMPLE).expect("valid");
        assert_eq!(p.name, "demo");
        assert_eq!(p.tool, Some(Tool::Ssg48));
        assert_eq!(p.speed.tcp_speed_mm_s, 80.0);
        assert_eq!(p.keep_out.len(), 1);
        let lines: Vec<usize> = p.steps.iter().map(|s| s.line).collect();
        assert_eq!(lines, vec![9, 10, 12, 15]);
        assert_eq!(
            p.steps[1].step,
            Step::MoveL {
                pose: PoseMm { position_mm: [0.0, 250.0, 300.0], rpy_deg: [180.0, 0.0, 90.0] },
                speed_mm_s: Some(50.0),
                blend_mm: None,
                duration_s: None
            }
        );
        assert!(matches!(p.steps[2].step, Step::Gripper { action: GripperAction::Close, .. }));
    }

    #[test]
    fn saving_and_loading_gives_the_same_program() {
        let p = parse(EXAMPLE).expect("valid");
        let text = to_string(&p);
        let back = parse(&text).expect("reads its own output");
        assert_eq!(
            back.steps.iter().map(|s| &s.step).collect::<Vec<_>>(),
            p.steps.iter().map(|s| &s.step).collect::<Vec<_>>()
        );
        assert_eq!((back.name, back.tool, back.speed, back.keep_out), (p.name, p.tool, p.speed, p.keep_out));
        // one step per line, from line 12 on in the written file
        assert!(back.steps.windows(2).all(|w| w[1].line == w[0].line + 1), "{text}");
    }

    #[test]
    fn a_program_keeps_its_tracking_mode() {
        use crate::motion::tracking::TrackingMode;
        let with = EXAMPLE.replacen("\"steps\"", "\"tracking\": \"official\",\n  \"steps\"", 1);
        let p = parse(&with).expect("valid");
        assert_eq!(p.tracking, Some(TrackingMode::Official));
        assert_eq!(parse(&to_string(&p)).expect("reads its own output").tracking, Some(TrackingMode::Official));
        assert_eq!(parse(EXAMPLE).expect("valid").tracking, None);
        let e = parse(&with.replace("\"official\"", "\"fast\"")).expect_err("unknown mode");
        assert!(e.to_string().contains("tracking") && e.to_string().contains("fast"), "{e}");
    }

    #[test]
    fn a_bad_field_names_the_field_line_and_column() {
        let bad = EXAMPLE.replace("\"seconds\": 0.5", "\"seconds\": \"half\"");
        let e = parse(&bad).expect_err("text in a number");
        match &e {
            ProgramFileError::Field { field, line, message, .. } => {
                // serde reads a tagged step as a whole: the path ends at the step
                assert_eq!(field, "steps[3]");
                assert!(message.contains("\"half\"") && message.contains("f64"), "{message}");
                assert_eq!(*line, 15);
            }
            other => panic!("{other:?}"),
        }
        let bad = EXAMPLE.replace("\"move_l\"", "\"move_sideways\"");
        let e = parse(&bad).expect_err("unknown step");
        assert!(e.to_string().contains("steps[1]") && e.to_string().contains("move_sideways"), "{e}");
        let bad = EXAMPLE.replace("\"speed_mm_s\": 50", "\"speed_mm_s\": 50, \"sped\": 3");
        assert!(parse(&bad).expect_err("unknown field").to_string().contains("sped"));
    }

    #[test]
    fn other_formats_versions_and_garbage_are_refused_clearly() {
        let e = parse(&EXAMPLE.replace("\"version\": 1", "\"version\": 7")).expect_err("newer");
        assert!(e.to_string().contains("version: 7"), "{e}");
        let e = parse(&EXAMPLE.replace("parol6-program", "gcode")).expect_err("format");
        assert!(e.to_string().contains("not a PAROL6 program"), "{e}");
        assert!(parse("").expect_err("empty").to_string().contains("empty"));
        assert!(parse("[1, 2").is_err());
        assert!(parse("{\"version\": 1}").expect_err("no format").to_string().contains("format"));
        let e = parse("{\"format\": \"parol6-program\", \"version\": 1, \"steps\": [ {\"type\": \"dwell\"} ]}")
            .expect_err("missing seconds");
        assert!(e.to_string().contains("seconds"), "{e}");
    }

    /// Regression (found by the `program_file` fuzzer): a number with many digits came back
    /// one unit in the last place different after save and load (serde_json's fast float
    /// parsing); parsing is now exact (`float_roundtrip`).
    #[test]
    fn saving_changed_a_number_by_one_ulp() {
        let text = r#"{"format": "parol6-program", "version": 1, "steps": [
            {"type": "move_c", "via_mm": [-10888888888888888888888888888888888888888888888888888888888888888888888888, 285, 292],
             "pose": {"position_mm": [0, 263.6, 292.1], "rpy_deg": [-180, -50, -90]}}]}"#;
        let p = parse(text).expect("valid");
        let back = parse(&to_string(&p)).expect("reads its own output");
        assert_eq!(back.steps[0].step, p.steps[0].step);
    }

    proptest::proptest! {
        #[test]
        fn parsing_never_panics(text in "\\PC{0,300}") {
            let _ = parse(&text);
            let _ = step_lines(&text);
        }

        #[test]
        fn mutated_files_never_panic(cut in 0usize..700, byte in 0u8..128) {
            let mut t = EXAMPLE.as_bytes().to_vec();
            let i = cut % t.len();
            t[i] = byte;
            if let Ok(s) = std::str::from_utf8(&t) {
                let _ = parse(s);
            }
        }
    }
}
