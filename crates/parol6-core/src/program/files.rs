//! Program files of every format, chosen by extension: reading (size-bounded, UTF-8 checked,
//! errors naming the file and the place in it) and writing.
//!
//! | extension | format |
//! | --- | --- |
//! | `.json` | the native format ([`super::json`]) |
//! | `.gcode`, `.nc`, `.ngc` | G-code in the official PAROL6 dialect ([`super::gcode`]) |
//! | `.csv` | a point table ([`super::table`]) |
//! | `.txt` | a PAROL commander program ([`super::commander`]) |
//!
//! Loading never touches a program in memory: it returns a new one or an error.

use std::path::Path;

use super::gcode::{AbcChoice, GcodeExportOptions, GcodeImportOptions, parse_gcode, program_to_gcode};
use super::{Program, commander, json, table};
use crate::RobotModel;

/// Files larger than this are refused before reading, bytes (every format).
pub const MAX_PROGRAM_FILE_BYTES: u64 = json::MAX_FILE_BYTES as u64;

/// A program file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramFormat {
    /// The native JSON format.
    Json,
    /// G-code (official PAROL6 dialect).
    Gcode,
    /// A CSV point table.
    Csv,
    /// A PAROL commander program.
    Commander,
}

impl ProgramFormat {
    /// Every format, with its extensions (the first is the one written by "save as").
    pub const ALL: [(ProgramFormat, &'static [&'static str]); 4] = [
        (ProgramFormat::Json, &["json"]),
        (ProgramFormat::Gcode, &["gcode", "nc", "ngc"]),
        (ProgramFormat::Csv, &["csv"]),
        (ProgramFormat::Commander, &["txt"]),
    ];

    /// The format of `path`, from its extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, ProgramIoError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
        Self::ALL.iter().find(|(_, exts)| exts.contains(&ext.as_str())).map(|(f, _)| *f).ok_or_else(|| {
            ProgramIoError::UnknownExtension { path: path.display().to_string(), extensions: Self::list() }
        })
    }

    /// The accepted extensions, for messages and file dialogs (`.json, …`).
    pub fn list() -> String {
        Self::ALL.iter().flat_map(|(_, e)| e.iter().map(|e| format!(".{e}"))).collect::<Vec<_>>().join(", ")
    }

    /// A short name for messages.
    pub fn name(self) -> &'static str {
        match self {
            ProgramFormat::Json => "program JSON",
            ProgramFormat::Gcode => "G-code",
            ProgramFormat::Csv => "point table",
            ProgramFormat::Commander => "commander program",
        }
    }
}

/// What reading or writing needs beyond the text: the robot (for poses of joint steps), the
/// pose the program starts from (where formats with modal or relative positions start) and how
/// G-code `A B C` read.
#[derive(Debug, Clone, Copy)]
pub struct FormatContext<'a> {
    /// The robot.
    pub model: &'a RobotModel,
    /// Joint values the program starts from, rad.
    pub start_q: &'a [f64],
    /// G-code `A B C` convention: read where a file's header names none (or, explicit, checked
    /// against the header), written on export.
    pub abc: AbcChoice,
}

impl<'a> FormatContext<'a> {
    /// `model` starting at `start_q`, G-code `A B C` in the default convention.
    pub fn new(model: &'a RobotModel, start_q: &'a [f64]) -> Self {
        Self { model, start_q, abc: AbcChoice::default() }
    }
}

/// Why a program file cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ProgramIoError {
    /// The extension names no format.
    #[error("{path}: unknown program file extension (use one of {extensions})")]
    UnknownExtension {
        /// The file.
        path: String,
        /// The accepted extensions.
        extensions: String,
    },
    /// The file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not a regular file, or could not be read or saved (saving replaces nothing
    /// then and leaves no temporary file).
    #[error(transparent)]
    File(#[from] crate::fsio::FsioError),
    /// Too big to be a program.
    #[error("{path}: {bytes} bytes is more than a program file may have ({max} bytes)")]
    TooBig {
        /// The file.
        path: String,
        /// Its size.
        bytes: u64,
        /// The limit.
        max: u64,
    },
    /// Not UTF-8 text.
    #[error("{path}: not UTF-8 text (byte {at})")]
    NotText {
        /// The file.
        path: String,
        /// Offset of the first bad byte.
        at: usize,
    },
    /// The content is malformed; the message names the place (line, column, field).
    #[error("{path}: {message}")]
    Content {
        /// The file (or `-`).
        path: String,
        /// What is wrong and where.
        message: String,
    },
}

/// Parses `text` as a program of `format`. `origin` names the text in messages.
pub fn parse_program(
    text: &str,
    format: ProgramFormat,
    ctx: &FormatContext<'_>,
    origin: &str,
) -> Result<Program, ProgramIoError> {
    let content = |message: String| ProgramIoError::Content { path: origin.to_string(), message };
    match format {
        ProgramFormat::Json => json::parse(text).map_err(|e| content(e.to_string())),
        ProgramFormat::Gcode => {
            parse_gcode(text, &GcodeImportOptions::for_model(ctx.model, ctx.start_q).with_abc(ctx.abc))
                .map_err(|e| content(e.to_string()))
        }
        ProgramFormat::Csv => table::parse_csv_table(text).map_err(|e| content(e.to_string())),
        ProgramFormat::Commander => {
            commander::parse_commander_with(text, &commander::CommanderOptions::for_model(ctx.model))
                .map_err(|e| content(e.to_string()))
        }
    }
}

/// Reads the program file `path` (format from its extension).
pub fn read_program(path: &Path, ctx: &FormatContext<'_>) -> Result<Program, ProgramIoError> {
    let format = ProgramFormat::from_path(path)?;
    let shown = path.display().to_string();
    let io = |source| ProgramIoError::Io { path: shown.clone(), source };
    // A regular file only, read through the bound: a FIFO or a device (which says it holds 0
    // bytes) is refused by its type, not read.
    let raw = match crate::fsio::read_regular_bounded(path, MAX_PROGRAM_FILE_BYTES) {
        Ok(raw) => raw,
        Err(crate::fsio::FsioError::TooLarge { .. }) => {
            let bytes = std::fs::metadata(path).map_err(io)?.len();
            return Err(ProgramIoError::TooBig { path: shown, bytes, max: MAX_PROGRAM_FILE_BYTES });
        }
        Err(e) => return Err(e.into()),
    };
    let text = String::from_utf8(raw)
        .map_err(|e| ProgramIoError::NotText { path: shown.clone(), at: e.utf8_error().valid_up_to() })?;
    let mut program = parse_program(&text, format, ctx, &shown)?;
    if program.name.trim().is_empty() {
        program.name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    }
    Ok(program)
}

/// The text of `program` in `format`.
pub fn format_program(
    program: &Program,
    format: ProgramFormat,
    ctx: &FormatContext<'_>,
    origin: &str,
) -> Result<String, ProgramIoError> {
    let content = |message: String| ProgramIoError::Content { path: origin.to_string(), message };
    match format {
        ProgramFormat::Json => Ok(json::to_string(program)),
        ProgramFormat::Gcode => {
            let options = GcodeExportOptions::new(program, ctx.start_q.to_vec()).with_abc(ctx.abc.convention);
            program_to_gcode(program, ctx.model, &options).map_err(|e| content(e.to_string()))
        }
        ProgramFormat::Csv => table::program_to_csv(program).map_err(|e| content(e.to_string())),
        ProgramFormat::Commander => {
            commander::program_to_commander_with(program, &commander::CommanderOptions::for_model(ctx.model))
                .map_err(|e| content(e.to_string()))
        }
    }
}

/// What writing `program` in `format` made of its gripper and output steps, in words, for the
/// message after a save or a conversion: the commander's `Gripper(position, speed, current)`
/// drives the electric gripper (SSG-48 / MSG) whatever the program's tool, and G-code's
/// `M3` / `M5` drive the electric gripper or the pneumatic gripper's valve as the program's
/// tool says ([`super::gcode::GcodeGripper::for_tool`]). Empty when there is nothing to say.
pub fn export_notes(program: &Program, format: ProgramFormat) -> Vec<String> {
    use super::Step;
    let count = |f: fn(&Step) -> bool| program.steps.iter().filter(|s| f(&s.step)).count();
    let grippers = count(|s| matches!(s, Step::Gripper { .. }));
    let outputs = count(|s| matches!(s, Step::SetOutput { .. }));
    let steps = |n: usize, what: &str| if n == 1 { format!("1 {what} step") } else { format!("{n} {what} steps") };
    let mut notes = Vec::new();
    match format {
        ProgramFormat::Commander if grippers > 0 => notes.push(format!(
            "{} written as the commander's Gripper(position, speed, current): commands for the electric gripper \
             (SSG-48 / MSG)",
            steps(grippers, "gripper")
        )),
        ProgramFormat::Gcode => match super::gcode::GcodeGripper::for_tool(program.tool) {
            super::gcode::GcodeGripper::Electric if grippers > 0 => notes.push(format!(
                "{} written as M3 / M5 for the electric gripper (the program's tool)",
                steps(grippers, "gripper")
            )),
            super::gcode::GcodeGripper::Pneumatic if outputs > 0 => notes.push(format!(
                "{} written as M3 / M5 P<output> for the pneumatic gripper's valve",
                steps(outputs, "output")
            )),
            _ => {}
        },
        _ => {}
    }
    notes
}

/// Writes `program` to `path` in the format of its extension, atomically
/// ([`crate::fsio::write_atomic`]): a failed save leaves the old file as it was and no
/// temporary file, and a target that is not a regular file (a FIFO, a device) is refused.
pub fn write_program(program: &Program, path: &Path, ctx: &FormatContext<'_>) -> Result<(), ProgramIoError> {
    let format = ProgramFormat::from_path(path)?;
    let shown = path.display().to_string();
    let text = format_program(program, format, ctx, &shown)?;
    Ok(crate::fsio::write_atomic_bytes(path, text.as_bytes())?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::Step;

    fn model() -> RobotModel {
        RobotModel::parol6()
    }

    #[test]
    fn gcode_files_read_and_write_by_extension() {
        let m = model();
        let q = crate::parol6::standby_rad().to_vec();
        let ctx = FormatContext::new(&m, &q);
        let text = "G21 G90\nG1 X0 Y250 Z300 A90 B0 C180 F3000\nG4 P500\n";
        let p = parse_program(text, ProgramFormat::Gcode, &ctx, "t.gcode").unwrap();
        assert_eq!(p.steps.len(), 2);
        assert_eq!(p.steps[1].step, Step::Dwell { seconds: 0.5 });
        let out = format_program(&p, ProgramFormat::Gcode, &ctx, "t.gcode").unwrap();
        let back = parse_program(&out, ProgramFormat::Gcode, &ctx, "t.gcode").unwrap();
        assert_eq!(back.steps.len(), 2);
        let e = parse_program("G1 X1 Q5\n", ProgramFormat::Gcode, &ctx, "bad.gcode").unwrap_err().to_string();
        assert!(e.starts_with("bad.gcode: line 1"), "{e}");
        assert_eq!(ProgramFormat::from_path(Path::new("a.NC")).unwrap(), ProgramFormat::Gcode);
    }

    /// Issue 32 minor: "Save as `.txt` silently writes electric-gripper commands."
    #[test]
    fn an_export_says_what_it_made_of_the_gripper_steps() {
        let m = model();
        let q = crate::parol6::standby_rad().to_vec();
        let ctx = FormatContext::new(&m, &q);
        let pick = crate::program::builtin::programs(&m).into_iter().find(|p| p.name == "Pick & place").unwrap();
        let txt = format_program(&pick, ProgramFormat::Commander, &ctx, "pick.txt").unwrap();
        assert!(txt.contains("Gripper("), "{txt}");
        let notes = export_notes(&pick, ProgramFormat::Commander);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("electric gripper") && notes[0].contains("Gripper("), "{notes:?}");
        assert!(export_notes(&pick, ProgramFormat::Json).is_empty());
        let mut electric = pick.clone();
        electric.tool = Some(crate::parol6::Tool::Ssg48);
        format_program(&electric, ProgramFormat::Gcode, &ctx, "pick.gcode").unwrap();
        assert!(export_notes(&electric, ProgramFormat::Gcode)[0].contains("electric gripper (the program's tool)"));
    }

    #[test]
    fn tables_and_commander_programs_convert_through_files() {
        let m = model();
        let q = crate::parol6::standby_rad().to_vec();
        let ctx = FormatContext::new(&m, &q);
        let csv = "j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg\n90,-80,170,0,60,180\n80,-80,170,0,60,180\n";
        let p = parse_program(csv, ProgramFormat::Csv, &ctx, "t.csv").unwrap();
        assert_eq!(p.steps.len(), 2);
        let txt = format_program(&p, ProgramFormat::Commander, &ctx, "t.txt").unwrap();
        let back = parse_program(&txt, ProgramFormat::Commander, &ctx, "t.txt").unwrap();
        let joints = |p: &Program| -> Vec<Vec<f64>> {
            p.steps
                .iter()
                .filter_map(|s| match &s.step {
                    Step::MoveJoints { joints_deg, .. } => Some(joints_deg.clone()),
                    _ => None,
                })
                .collect()
        };
        assert_eq!(joints(&back), joints(&p), "table → commander → program keeps the joints");
        let e = parse_program("x_mm,y_mm\n1,abc\n", ProgramFormat::Csv, &ctx, "bad.csv").unwrap_err().to_string();
        assert!(e.starts_with("bad.csv: "), "{e}");
        assert_eq!(ProgramFormat::from_path(Path::new("p.TXT")).unwrap(), ProgramFormat::Commander);
    }

    #[test]
    fn unknown_extension_names_the_accepted_ones() {
        let e = ProgramFormat::from_path(Path::new("a.docx")).unwrap_err().to_string();
        assert!(e.contains("a.docx") && e.contains(".json"), "{e}");
        assert_eq!(ProgramFormat::from_path(Path::new("A.JSON")).unwrap(), ProgramFormat::Json);
    }

    #[test]
    fn save_then_read_gives_the_same_program_and_errors_name_the_file() {
        let m = model();
        let q = crate::parol6::standby_rad().to_vec();
        let ctx = FormatContext::new(&m, &q);
        let dir = std::env::temp_dir().join(format!("parol6-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.json");
        let program = Program::from_steps("p", vec![Step::Dwell { seconds: 1.5 }]);
        write_program(&program, &path, &ctx).unwrap();
        let back = read_program(&path, &ctx).unwrap();
        assert_eq!(back.steps[0].step, program.steps[0].step);
        std::fs::write(&path, "{ \"format\": 3 }").unwrap();
        let e = read_program(&path, &ctx).unwrap_err().to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        std::fs::write(&path, [0xff, 0xfe, 0x00]).unwrap();
        let e = read_program(&path, &ctx).unwrap_err().to_string();
        assert!(e.contains("not UTF-8"), "{e}");
        let e = read_program(&dir.join("missing.json"), &ctx).unwrap_err().to_string();
        assert!(e.contains("missing.json"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
