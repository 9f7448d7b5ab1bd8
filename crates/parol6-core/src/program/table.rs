//! Point tables: CSV files of joint or TCP targets, one point per row, read into a program of
//! `move_joints` or `move_l` steps and written back from one.
//!
//! ```text
//! # joint table (j1_rad … j6_rad instead for radians); '#' starts a comment line
//! j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,speed_fraction
//! 90,-80,170,0,60,180,0.6
//! 90,-90,180,0,0,180,
//!
//! # Cartesian table: position mm, our URDF roll/pitch/yaw deg (R = Rz(yaw)·Ry(pitch)·Rx(roll)),
//! # or the official PAROL6 rx_deg, ry_deg, rz_deg (R = Rx(rz)·Ry(ry)·Rz(rx)) instead
//! x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,speed_mm_s,time_s
//! 30,263.6,292.1,-180,-50,-90,80,
//! 30,323.6,292.1,-180,-50,-90,,1.5
//! ```
//!
//! - The header names the columns, in any order; every column of one layout must be there and
//!   nothing else. Optional columns: `speed_fraction` (joint tables: fraction of the joint speed
//!   caps), `speed_mm_s` (Cartesian tables: TCP speed), `time_s` (both: the time to reach this
//!   point, the step's `duration_s`; it wins over a speed). An empty optional cell means the
//!   program's default.
//! - Every row becomes one step: `move_joints` (joint tables) or `move_l` (Cartesian tables: a
//!   straight line from wherever the TCP is, so the first row is reached by a line too). The
//!   step's line is the row's line in the file, for pre-flight messages.
//! - Spaces around cells are ignored, blank lines and lines starting with `#` are skipped.
//! - Errors name the row by its file line and the column:
//!   `row 5, column "y_mm": "abc" is not a number`.
//!
//! Writing ([`program_to_csv`]) takes a program of only `move_joints` or only `move_l` steps
//! (no blends) and writes degrees and roll/pitch/yaw (or rx/ry/rz with
//! [`program_to_csv_with`]); any other step is refused by name.

use super::{PoseMm, Program, SourcedStep, Step};
use crate::angles::{AngleConvention, abc_to_rpy_deg};

/// Tables larger than this are refused before parsing, bytes.
pub const MAX_TABLE_BYTES: usize = 16 * 1024 * 1024;
/// The most points a table may have.
pub const MAX_POINTS: usize = 100_000;

const JOINTS_DEG: [&str; 6] = ["j1_deg", "j2_deg", "j3_deg", "j4_deg", "j5_deg", "j6_deg"];
const JOINTS_RAD: [&str; 6] = ["j1_rad", "j2_rad", "j3_rad", "j4_rad", "j5_rad", "j6_rad"];
const POSITION: [&str; 3] = ["x_mm", "y_mm", "z_mm"];
const RPY: [&str; 3] = ["roll_deg", "pitch_deg", "yaw_deg"];
const ABC: [&str; 3] = ["rx_deg", "ry_deg", "rz_deg"];
const SPEED_FRACTION: &str = "speed_fraction";
const SPEED_MM_S: &str = "speed_mm_s";
const TIME_S: &str = "time_s";

/// Why a table cannot be read or written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    /// A cell that is not what its column needs.
    #[error("row {line}, column \"{column}\": {message}")]
    Cell {
        /// 1-based file line of the row.
        line: usize,
        /// The column's name.
        column: String,
        /// What is wrong.
        message: String,
    },
    /// A row as a whole (number of cells, CSV quoting).
    #[error("row {line}: {message}")]
    Row {
        /// 1-based file line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The header line.
    #[error("header (line {line}): {message}")]
    Header {
        /// 1-based file line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A program step a table cannot hold (writing).
    #[error(transparent)]
    Step(#[from] super::StepRefusal),
    /// The file as a whole (empty, too large, no rows).
    #[error("{0}")]
    File(String),
}

/// Which table the header describes, with each needed column's index.
enum Layout {
    Joints { columns: [usize; 6], radians: bool },
    Cartesian { position: [usize; 3], angles: [usize; 3], official: bool },
}

/// Reads a point table into a program (`move_joints` or `move_l` steps, one per row).
pub fn parse_csv_table(text: &str) -> Result<Program, TableError> {
    if text.len() > MAX_TABLE_BYTES {
        return Err(TableError::File(format!(
            "the table is {} bytes; point tables are limited to {} MiB",
            text.len(),
            MAX_TABLE_BYTES / (1024 * 1024)
        )));
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut records = reader.records();
    let header = match records.next() {
        None => return Err(TableError::File("the table is empty: it needs a header line and rows".into())),
        Some(r) => r.map_err(|e| csv_error(text, e))?,
    };
    let header_line = line_at(text, header.position());
    let names: Vec<String> = header.iter().map(str::to_string).collect();
    let layout = layout(&names, header_line)?;
    let find = |name: &str| names.iter().position(|n| n == name);
    let (speed_col, time_col) = match layout {
        Layout::Joints { .. } => (find(SPEED_FRACTION), find(TIME_S)),
        Layout::Cartesian { .. } => (find(SPEED_MM_S), find(TIME_S)),
    };
    let mut steps = Vec::new();
    for record in records {
        let record = record.map_err(|e| csv_error(text, e))?;
        let line = line_at(text, record.position());
        if record.iter().all(str::is_empty) && record.len() == 1 {
            continue; // a line of spaces
        }
        if record.len() != names.len() {
            return Err(TableError::Row {
                line,
                message: format!("has {} cells; the header has {}", record.len(), names.len()),
            });
        }
        if steps.len() == MAX_POINTS {
            return Err(TableError::Row { line, message: format!("a table has at most {MAX_POINTS} points") });
        }
        let cell = |k: usize| -> Result<f64, TableError> {
            number(&record[k]).map_err(|message| TableError::Cell { line, column: names[k].clone(), message })
        };
        let optional = |k: Option<usize>| -> Result<Option<f64>, TableError> {
            match k {
                Some(k) if !record[k].is_empty() => cell(k).map(Some),
                _ => Ok(None),
            }
        };
        let duration_s = optional(time_col)?;
        let step = match &layout {
            Layout::Joints { columns, radians } => {
                let mut joints_deg = Vec::with_capacity(6);
                for &k in columns {
                    let v = cell(k)?;
                    joints_deg.push(if *radians { v.to_degrees() } else { v });
                }
                Step::MoveJoints { joints_deg, speed_fraction: optional(speed_col)?, duration_s }
            }
            Layout::Cartesian { position, angles, official } => {
                let position_mm = [cell(position[0])?, cell(position[1])?, cell(position[2])?];
                let given = [cell(angles[0])?, cell(angles[1])?, cell(angles[2])?];
                let rpy_deg = if *official { abc_to_rpy_deg(given) } else { given };
                Step::MoveL {
                    pose: PoseMm { position_mm, rpy_deg },
                    speed_mm_s: optional(speed_col)?,
                    blend_mm: None,
                    duration_s,
                }
            }
        };
        steps.push(SourcedStep { step, line });
    }
    if steps.is_empty() {
        return Err(TableError::File("the table has a header but no rows".into()));
    }
    Ok(Program { description: "point table".into(), steps, ..Program::default() })
}

/// The 1-based file line where a record starts. The csv crate's position of a record lies
/// before the blank and comment lines that precede it (and its line count leaves blank lines
/// out), so those are stepped over from there.
fn line_at(text: &str, position: Option<&csv::Position>) -> usize {
    let bytes = text.as_bytes();
    let mut at = position.map_or(0, |p| p.byte() as usize).min(bytes.len());
    loop {
        match bytes.get(at) {
            Some(b'\n' | b'\r') => at += 1,
            Some(b'#') if at == 0 || bytes[at - 1] == b'\n' => {
                at = bytes[at..].iter().position(|b| *b == b'\n').map_or(bytes.len(), |k| at + k + 1);
            }
            _ => break,
        }
    }
    bytes[..at].iter().filter(|b| **b == b'\n').count() + 1
}

fn csv_error(text: &str, e: csv::Error) -> TableError {
    let line = line_at(text, e.position());
    let message = match e.kind() {
        csv::ErrorKind::Utf8 { .. } => "is not UTF-8 text".to_string(),
        _ => e.to_string(),
    };
    TableError::Row { line, message }
}

fn number(text: &str) -> Result<f64, String> {
    if text.is_empty() {
        return Err("is empty; a number is needed".into());
    }
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("\"{text}\" is not a finite number")),
        Err(_) => Err(format!("\"{text}\" is not a number")),
    }
}

fn layout(names: &[String], line: usize) -> Result<Layout, TableError> {
    let err = |message: String| TableError::Header { line, message };
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            return Err(err(format!("column \"{n}\" appears twice")));
        }
    }
    let has = |n: &str| names.iter().any(|x| x == n);
    let index = |want: &[&str]| -> Result<Vec<usize>, TableError> {
        want.iter()
            .map(|w| names.iter().position(|n| n == w).ok_or_else(|| err(format!("column \"{w}\" is missing"))))
            .collect()
    };
    let (layout, allowed): (Layout, Vec<&str>) = if JOINTS_DEG.iter().chain(&JOINTS_RAD).any(|n| has(n)) {
        let radians = !JOINTS_DEG.iter().any(|n| has(n)) && JOINTS_RAD.iter().any(|n| has(n));
        let wanted = if radians { JOINTS_RAD } else { JOINTS_DEG };
        let cols = index(&wanted)?;
        let columns = [cols[0], cols[1], cols[2], cols[3], cols[4], cols[5]];
        (Layout::Joints { columns, radians }, [&wanted[..], &[SPEED_FRACTION, TIME_S]].concat())
    } else if has("x_mm") || has("y_mm") || has("z_mm") {
        let official = !RPY.iter().any(|n| has(n)) && ABC.iter().any(|n| has(n));
        let angle_names = if official { ABC } else { RPY };
        let p = index(&POSITION)?;
        let a = index(&angle_names)?;
        (
            Layout::Cartesian { position: [p[0], p[1], p[2]], angles: [a[0], a[1], a[2]], official },
            [&POSITION[..], &angle_names[..], &[SPEED_MM_S, TIME_S]].concat(),
        )
    } else {
        return Err(err(
            "a point table's header names j1_deg … j6_deg (or j1_rad … j6_rad) or x_mm, y_mm, z_mm with roll_deg, \
             pitch_deg, yaw_deg (or rx_deg, ry_deg, rz_deg)"
                .into(),
        ));
    };
    if let Some(other) = names.iter().find(|n| !allowed.contains(&n.as_str())) {
        let kind = if matches!(layout, Layout::Joints { .. }) { "a joint" } else { "a Cartesian" };
        return Err(err(format!(
            "column \"{other}\" does not belong in {kind} table (its columns: {})",
            allowed.join(", ")
        )));
    }
    Ok(layout)
}

/// Writes a program of only `move_joints` or only `move_l` steps as a point table (degrees,
/// our roll / pitch / yaw).
pub fn program_to_csv(program: &Program) -> Result<String, TableError> {
    program_to_csv_with(program, AngleConvention::UrdfRpy)
}

/// [`program_to_csv`] with the Cartesian angles in `angles` (`rx_deg, ry_deg, rz_deg` columns
/// for the official convention).
pub fn program_to_csv_with(program: &Program, angles: AngleConvention) -> Result<String, TableError> {
    let Some(first) = program.steps.first() else {
        return Err(TableError::File("the program has no steps to write as a table".into()));
    };
    let joints = matches!(first.step, Step::MoveJoints { .. });
    let refuse = |i: usize, s: &SourcedStep, message: String| TableError::Step(super::StepRefusal::new(i, s, message));
    let mut rows: Vec<(Vec<f64>, Option<f64>, Option<f64>)> = Vec::with_capacity(program.steps.len());
    for (i, s) in program.steps.iter().enumerate() {
        match (&s.step, joints) {
            (Step::MoveJoints { joints_deg, speed_fraction, duration_s }, true) => {
                if joints_deg.len() != 6 {
                    return Err(refuse(i, s, format!("has {} joint values; a table has 6", joints_deg.len())));
                }
                rows.push((joints_deg.clone(), *speed_fraction, *duration_s));
            }
            (Step::MoveL { pose, speed_mm_s, blend_mm, duration_s }, false) => {
                if blend_mm.is_some_and(|b| b != 0.0) {
                    return Err(refuse(i, s, "a point table has no blend column; remove blend_mm".into()));
                }
                let a = angles.from_rpy_deg(pose.rpy_deg);
                let p = pose.position_mm;
                rows.push((vec![p[0], p[1], p[2], a[0], a[1], a[2]], *speed_mm_s, *duration_s));
            }
            _ => {
                let want = if joints { "move_joints" } else { "move_l" };
                return Err(refuse(
                    i,
                    s,
                    format!(
                        "a point table holds one kind of step, here {want} (as the first step); this one has no row form"
                    ),
                ));
            }
        }
    }
    let mut header: Vec<&str> = if joints {
        JOINTS_DEG.to_vec()
    } else {
        let a = if angles == AngleConvention::OfficialAbc { ABC } else { RPY };
        [&POSITION[..], &a[..]].concat()
    };
    let with_speed = rows.iter().any(|r| r.1.is_some());
    let with_time = rows.iter().any(|r| r.2.is_some());
    if with_speed {
        header.push(if joints { SPEED_FRACTION } else { SPEED_MM_S });
    }
    if with_time {
        header.push(TIME_S);
    }
    let mut out = header.join(",");
    out.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for (values, speed, time) in rows {
        let mut cells: Vec<String> = values.iter().map(f64::to_string).collect();
        if with_speed {
            cells.push(opt(speed));
        }
        if with_time {
            cells.push(opt(time));
        }
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
