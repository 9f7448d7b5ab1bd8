//! The measurement CSV: one attained pose per row, written by `parol6 iso9283 --raw` and read
//! back (or from a laser tracker / camera export) by `parol6 iso9283 --measurements`.
//!
//! Columns (any order, names as here, extra columns ignored):
//! `cycle,pose,cmd_x_mm,cmd_y_mm,cmd_z_mm,cmd_a_deg,cmd_b_deg,cmd_c_deg,x_mm,y_mm,z_mm,a_deg,b_deg,c_deg`.
//! `cycle` is a positive integer, `pose` is P1…P5 (or 1…5), the angles are our URDF roll /
//! pitch / yaw in degrees (R = Rz(c)·Ry(b)·Rx(a)). Every error names the row (the file's line,
//! the header is line 1) and the column.

use std::fmt::Write as _;

use super::cube::{POSE_NAMES, pose_index};
use super::pose_figures::PoseSample;
use crate::program::PoseMm;

/// The columns, in the order they are written.
pub const COLUMNS: [&str; 14] = [
    "cycle",
    "pose",
    "cmd_x_mm",
    "cmd_y_mm",
    "cmd_z_mm",
    "cmd_a_deg",
    "cmd_b_deg",
    "cmd_c_deg",
    "x_mm",
    "y_mm",
    "z_mm",
    "a_deg",
    "b_deg",
    "c_deg",
];

/// The largest measurement file read, bytes.
pub const MAX_FILE_BYTES: usize = 16 * 1024 * 1024;

/// What is wrong with a measurement file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CsvError {
    /// No header, or a header and no rows.
    #[error("the file is empty{}", if *.header { " (a header and no rows)" } else { "" })]
    Empty {
        /// True when it has a header.
        header: bool,
    },
    /// The header lacks a column.
    #[error("row 1 (header): column `{0}` is missing")]
    MissingColumn(&'static str),
    /// A field is not what its column needs.
    #[error("row {row}, column `{column}`: {message}")]
    Field {
        /// The file's line (the header is 1).
        row: u64,
        /// Column name.
        column: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The row itself is malformed (wrong number of fields, not UTF-8).
    #[error("row {row}: {message}")]
    Row {
        /// The file's line.
        row: u64,
        /// What is wrong.
        message: String,
    },
    /// The file is too large.
    #[error("{0} bytes; measurement files are limited to {MAX_FILE_BYTES} bytes")]
    TooLarge(usize),
}

/// Parses a measurement file.
pub fn parse(text: &str) -> Result<Vec<PoseSample>, CsvError> {
    if text.len() > MAX_FILE_BYTES {
        return Err(CsvError::TooLarge(text.len()));
    }
    if text.trim().is_empty() {
        return Err(CsvError::Empty { header: false });
    }
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(false).from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| row_error(1, &e))?.clone();
    let mut index = [0usize; 14];
    for (slot, name) in index.iter_mut().zip(COLUMNS) {
        *slot = header.iter().position(|h| h == name).ok_or(CsvError::MissingColumn(name))?;
    }
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| row_error(e.position().map_or(0, |p| p.line()), &e))?;
        let row = record.position().map_or(0, |p| p.line());
        let field = |k: usize| record.get(index[k]).unwrap_or("");
        let number = |k: usize| -> Result<f64, CsvError> {
            let text = field(k);
            let err = |message: String| CsvError::Field { row, column: COLUMNS[k], message };
            if text.is_empty() {
                return Err(err("empty".into()));
            }
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(err(format!("\"{text}\" is not a finite number"))),
            }
        };
        let cycle = match field(0).parse::<u32>() {
            Ok(c) if c > 0 => c,
            _ => {
                return Err(CsvError::Field {
                    row,
                    column: "cycle",
                    message: format!("\"{}\" is not a positive whole number", field(0)),
                });
            }
        };
        let pose = pose_index(field(1)).ok_or_else(|| CsvError::Field {
            row,
            column: "pose",
            message: format!("\"{}\" is not a test pose (P1…P5)", field(1)),
        })?;
        let mut v = [0.0; 12];
        for (k, slot) in v.iter_mut().enumerate() {
            *slot = number(k + 2)?;
        }
        out.push(PoseSample {
            cycle,
            pose,
            commanded: PoseMm { position_mm: [v[0], v[1], v[2]], rpy_deg: [v[3], v[4], v[5]] },
            attained: PoseMm { position_mm: [v[6], v[7], v[8]], rpy_deg: [v[9], v[10], v[11]] },
        });
    }
    if out.is_empty() {
        return Err(CsvError::Empty { header: true });
    }
    Ok(out)
}

fn row_error(row: u64, e: &csv::Error) -> CsvError {
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths { expected_len, len, .. } => {
            format!("{len} fields where the header has {expected_len}")
        }
        csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".to_string(),
        _ => e.to_string(),
    };
    CsvError::Row { row, message }
}

/// Writes samples as a measurement file (header and one row each, 6 decimals).
pub fn write(samples: &[PoseSample]) -> String {
    let mut out = COLUMNS.join(",");
    out.push('\n');
    for s in samples {
        let _ = write!(out, "{},{}", s.cycle, POSE_NAMES.get(s.pose).unwrap_or(&"P?"));
        let c = &s.commanded;
        let a = &s.attained;
        for v in c.position_mm.iter().chain(&c.rpy_deg).chain(&a.position_mm).chain(&a.rpy_deg) {
            // rounded first, so a tiny negative value is written 0.000000, not -0.000000
            let _ = write!(out, ",{:.6}", (v * 1e6).round() / 1e6 + 0.0);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests;
