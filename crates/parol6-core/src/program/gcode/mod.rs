//! G-code import and export in the dialect of the official PAROL6 Python API
//! (`parol6/gcode/` of `PCrnjak/PAROL6-python-API`), with the gaps it leaves filled the way a
//! CNC user expects (marked *here* below). Every place where we read a file differently from
//! the official parser on purpose is a row of the dialect table in `docs/gcode-dialect.md`
//! (with the official source, the standard's view and a conformance file in
//! `tests/conformance/gcode/`).
//!
//! - [`parse_gcode`]: G-code text → [`Program`](crate::program::Program) (every step's `line` is its G-code line);
//! - [`program_to_gcode`]: any program → G-code;
//! - [`tcp_path_to_gcode`] / [`recording_to_gcode`]: a sampled TCP path (or the `/tcp_pose`
//!   topic of one of our MCAP recordings) → `G1` lines within a tolerance.
//!
//! # The dialect
//!
//! A line holds words: a letter and a number right after it (`G1`, `X-12.5`, `F3000`; upper or
//! lower case; no exponents: `X1e3` is an error naming the number). `;` starts a comment to the end of the line, `( … )` is a
//! comment inside a line (not nested, closed on the same line). `N123` may open a line (a line
//! number; ignored). A line that is only `%` (a tape mark) is ignored. Blank lines are ignored.
//! Anything else is an error naming the line and the word: nothing is skipped silently.
//!
//! Coordinates: `X Y Z` in mm (inch after `G20`), the TCP position in the robot base frame;
//! `A B C` in degrees, the TCP orientation in one of the two **official conventions**
//! ([`AbcConvention`], not our URDF roll/pitch/yaw): `commander` (the default),
//! `R = Rx(C)·Ry(B)·Rz(A)`, the PAROL commander's and the Python API's until 2025-12-29, where
//! our (roll 0, pitch 20, yaw 90)° is `A90 B0 C-20`; or `xyz`, `R = Rx(A)·Ry(B)·Rz(C)`, the API's
//! last G-code revision. The default is `commander` because the official G-code reader meant it
//! for four of its five months, the commander's readout (where users copy poses from) uses it,
//! and every file we wrote before the choice existed is in it. The choice comes from
//! [`GcodeImportOptions::abc`] ([`AbcChoice`]: the CLI's `--abc`, the GUI's setting) or from a
//! header line of the file before its first G-code word, `; parol6: abc=xyz` (case-insensitive;
//! `abc` is the only key), which export always writes. The header wins over a default; an
//! explicit choice that contradicts it is an error naming the header's line.
//!
//! Axes left out keep their value. Before any move sets them, `X Y Z` are the start pose's
//! position (the arm's pose when the program starts, as the official API's line-at-a-time path)
//! and **`A B C` are 0**, as in the official parser (an XYZ-only file no longer keeps the start
//! pose's orientation: it runs with the tool in the orientation `A0 B0 C0`). *Here* `A/B/C` are
//! never scaled by `G20` (the official interpreter scales them by 25.4 too).
//!
//! | word | meaning here |
//! |---|---|
//! | `G0` | joint move to the pose (`move_pose`) at the program's joint speed (*here*: the official `MOVEPOSE` at 100 % can drive the PAROL6's differential wrist past its motor step rate, which pre-flight refuses) |
//! | `G1` | straight TCP line (`move_l`) at the feed `F`, orientation slerped |
//! | `G2` / `G3` | arc clockwise / counter-clockwise seen from the positive normal of the plane (G17 +Z, G18 +Y, G19 +X), centre by `I J K` (offsets from the start, always relative) or radius `R` (negative: the arc over 180°); end point = start with `I/J/K` only: a full circle. A partial arc is a `move_c` through the arc's midpoint (orientation slerped to the end's `A B C`), a full circle a `move_circle` (orientation kept). Helical arcs (the third axis changing) are refused, as are start and end more than 0.01 mm apart in radius |
//! | `G4` | dwell: `P` in **milliseconds** or `S` in seconds (official meaning; LinuxCNC's `P` is seconds) |
//! | `G10 L2 P1…6` | *here*: sets the work offset of `G54`…`G59` to the axis words given (absolute; the official API sets offsets through its Python calls only) |
//! | `G17` / `G18` / `G19` | arc plane XY / ZX / YZ |
//! | `G20` / `G21` | inch / mm for `X Y Z I J K R F` and `G64 P` |
//! | `G28` | home (`home`, the PAROL6 standby); the position after it is the home pose of the options. Axis words on it (an intermediate point) are refused |
//! | `G54`…`G59` | active work offset: programmed `X…C` + offset = base-frame value (per axis, as the official API adds them); offsets come from the options or `G10 L2`, zero by default |
//! | `G61` / `G64 P` | *here*: exact stop / round the corners between `G1` lines with radius `P` (`blend_mm`) |
//! | `G90` / `G91` | absolute / incremental axis words (`I J K` are always incremental) |
//! | `F` | feed, mm/min (inch/min after `G20`), modal, on any line (*here*: the official parser drops an `F` on a motion line); at least 2 mm/s (the PAROL6's slowest TCP speed). A feed above its fastest (200 mm/s) is passed on as the step's speed, and pre-flight slows the move down with a warning. Before any `F`, lines use the program's TCP speed |
//! | `M0` / `M1` | pause until the operator resumes (`pause`); `M1` only when the run has optional stops on |
//! | `M3` / `M4` / `M5` | gripper close / close / open. Pneumatic ([`GcodeGripper::Pneumatic`], official): valve output `P` (1 or 2, default 1), open = output high; electric ([`GcodeGripper::Electric`]): the electric gripper fully closed / open |
//! | `M2` / `M30` | program end; any word after it is an error |
//!
//! Refused with an error: any other `G` or `M` code, `T` (the tool is set in PAROL6 Studio),
//! `S` except on `G4` (no spindle), `I J K R` off an arc, words that appear twice on a line, two
//! codes of one group on a line (`G0 G1`, `G20 G21`), more than one `M` code on a line, axis
//! words before any motion code, numbers that do not parse or are too long, positions beyond
//! ±10 000 mm and arcs whose circle reaches beyond them.
//!
//! Axis words on a line without a motion code move with the active one (*here*: the official
//! parser drops such lines); `R` > 0 is the arc of at most 180° (*here*: the official parser
//! inverts the sign).
//!
//! A line runs in this order: units, plane, distance mode, work offset, path mode, feed,
//! `G10`, gripper, then `G4` / `G28` / the motion, then `M0 M1 M2 M30`.
//!
//! Export writes the header line `; parol6: abc=…` of its [`GcodeExportOptions::abc`] first,
//! then base-frame coordinates (no work offset), all six axes on every move but a full circle's
//! end (its `X Y Z` only: a full circle keeps the orientation), `G21 G90 G17` first and `M30`
//! last. Joint steps (`move_joints`, `move_pose`) become `G0` to the
//! forward-kinematics pose of their goal (a `G0` read back is a `move_pose`, which takes the
//! inverse-kinematics solution nearest the start, not necessarily the same joint values);
//! splines and arcs outside the XY / ZX / YZ planes are sampled into `G1` lines within the
//! tolerance of the export options; a step with no G-code equivalent (`wait_input`, a gripper
//! position, an output in electric mode) is an error naming the step.

pub use crate::angles::AbcConvention;
use crate::model::RobotModel;
use crate::parol6::Tool;

use super::PoseMm;

mod arc;
mod block;
mod export;
mod header;
mod import;
mod lexer;
mod path;

pub use export::{GcodeExportError, GcodeExportOptions, program_to_gcode};
pub use header::abc_header;
pub use import::parse_gcode;
pub use path::{PathTolerance, recording_to_gcode, tcp_path_to_gcode};

/// G-code files larger than this are refused before parsing, bytes.
pub const MAX_GCODE_BYTES: usize = 16 * 1024 * 1024;
/// Longest line, characters.
pub const MAX_LINE_CHARS: usize = 4096;
/// Most words on one line.
pub const MAX_WORDS_PER_LINE: usize = 64;
/// Longest number, characters (sign and point included).
pub const MAX_NUMBER_CHARS: usize = 24;
/// Most steps one G-code file may give.
pub const MAX_STEPS: usize = 200_000;
/// Largest angle an `A`/`B`/`C` word may reach, deg.
pub const MAX_ANGLE_DEG: f64 = 100_000.0;
/// Start and end of an arc may differ this much in radius, mm (the official API's tolerance).
pub const ARC_RADIUS_TOLERANCE_MM: f64 = 0.01;

/// What `M3` / `M4` / `M5` drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GcodeGripper {
    /// The official meaning: a pneumatic valve on digital output `P` (1 or 2, default 1);
    /// `M5` (open) sets it high, `M3`/`M4` (close) low (`set_output` steps).
    #[default]
    Pneumatic,
    /// The electric gripper (SSG-48, MSG): `M3`/`M4` close fully, `M5` opens fully (`gripper`).
    Electric,
}

impl GcodeGripper {
    /// The meaning that fits a tool: electric for the SSG-48 and the MSG, else pneumatic.
    pub fn for_tool(tool: Option<Tool>) -> Self {
        match tool {
            Some(Tool::Ssg48 | Tool::Msg) => GcodeGripper::Electric,
            _ => GcodeGripper::Pneumatic,
        }
    }
}

/// Which [`AbcConvention`] reads a G-code file's `A B C`, and how firmly it was chosen.
///
/// A file may name its convention in a header line (`; parol6: abc=xyz`, see the
/// [module docs](self)). The header wins over a default ([`AbcChoice::default_to`]: the GUI's
/// setting, the CLI without `--abc`); a choice the user made for this file
/// ([`AbcChoice::explicit`]: `--abc`) that contradicts the header is an error naming the
/// header's line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AbcChoice {
    /// The convention for a file without a header (and for export).
    pub convention: AbcConvention,
    /// True when the user asked for `convention` for this file: a header naming the other one
    /// is then an error.
    pub explicit: bool,
}

impl AbcChoice {
    /// `convention` for files that do not name theirs.
    pub fn default_to(convention: AbcConvention) -> Self {
        Self { convention, explicit: false }
    }

    /// `convention`, asked for explicitly: a file whose header names the other is refused.
    pub fn explicit(convention: AbcConvention) -> Self {
        Self { convention, explicit: true }
    }
}

/// How to read a G-code file.
#[derive(Debug, Clone, PartialEq)]
pub struct GcodeImportOptions {
    /// Program name.
    pub name: String,
    /// The TCP pose the program starts from: `X Y Z` left out take its position until a move
    /// sets them, and the first arc starts there. Its orientation is not used: `A B C` not yet
    /// given are 0, as in the official parser.
    pub start_pose: PoseMm,
    /// The TCP pose after `G28` (the home / standby pose).
    pub home_pose: PoseMm,
    /// Work offsets of `G54` … `G59`: `[X, Y, Z (mm), A, B, C (deg)]`, added per axis.
    pub work_offsets: [[f64; 6]; 6],
    /// What `M3`/`M4`/`M5` drive.
    pub gripper: GcodeGripper,
    /// How `A B C` make a rotation.
    pub abc: AbcChoice,
}

impl GcodeImportOptions {
    /// Options starting at `start_pose` with home at `home_pose`, no work offsets, pneumatic
    /// gripper words, the default `A B C` convention.
    pub fn new(start_pose: PoseMm, home_pose: PoseMm) -> Self {
        Self {
            name: String::new(),
            start_pose,
            home_pose,
            work_offsets: [[0.0; 6]; 6],
            gripper: GcodeGripper::default(),
            abc: AbcChoice::default(),
        }
    }

    /// These options with `A B C` read as `abc` says.
    pub fn with_abc(mut self, abc: AbcChoice) -> Self {
        self.abc = abc;
        self
    }

    /// Options for `model` starting at joints `start_q` (rad): the start pose is their forward
    /// kinematics, home the model's home (standby) pose.
    pub fn for_model(model: &RobotModel, start_q: &[f64]) -> Self {
        let home = crate::motion::home_position(model);
        Self::new(
            PoseMm::from_isometry(&model.tcp_isometry(start_q)),
            PoseMm::from_isometry(&model.tcp_isometry(&home)),
        )
    }
}

/// Why a G-code file cannot be read: the 1-based line, the word as written (when one word is
/// at fault) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.render())]
pub struct GcodeError {
    /// 1-based line (0: the whole file).
    pub line: usize,
    /// The word at fault, upper case as written (`G5`, `X1.5`).
    pub word: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl GcodeError {
    fn render(&self) -> String {
        match (self.line, &self.word) {
            (0, _) => self.message.clone(),
            (line, Some(w)) => format!("line {line}: word \"{w}\": {}", self.message),
            (line, None) => format!("line {line}: {}", self.message),
        }
    }

    pub(crate) fn at_word(line: usize, word: &str, message: impl Into<String>) -> Self {
        Self { line, word: Some(word.to_string()), message: message.into() }
    }

    pub(crate) fn at_line(line: usize, message: impl Into<String>) -> Self {
        Self { line, word: None, message: message.into() }
    }
}

/// A number as G-code writes it: at most 7 decimals, no trailing zeros, no `-0`.
pub(crate) fn format_number(v: f64) -> String {
    let s = format!("{v:.7}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if s == "-0" { "0".to_string() } else { s }
}

#[cfg(test)]
mod abc_tests;
#[cfg(test)]
mod tests;
