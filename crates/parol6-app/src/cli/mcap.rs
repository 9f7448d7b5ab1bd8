//! `parol6 mcap info FILE` and `parol6 mcap csv FILE -o OUT.csv`: our MCAP recordings from the
//! command line. A truncated file is read as far as its complete chunks (with a warning on
//! stderr); an empty, garbage or foreign file is refused with exit status 2; a file that
//! cannot be read or written is status 1. `mcap csv` reads and checks the whole recording
//! before the CSV replaces anything (written atomically), and refuses to write over its input.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use parol6_core::fsio;
use parol6_core::telemetry::reader::{Recording, scan_recording};
use parol6_core::telemetry::schema::JointStateMsg;
use serde_json::json;

use super::{CliError, CliResult, print_json, warn};

/// Arguments of `parol6 mcap`.
#[derive(Debug, clap::Args)]
pub struct McapArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: McapCommand,
}

/// `parol6 mcap` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum McapCommand {
    /// Topics with message counts, duration and start/end times of a recording (JSON).
    Info {
        /// The recording (.mcap).
        file: PathBuf,
    },
    /// One CSV row per joint-state sample: commanded and measured joints, units in the column names.
    Csv {
        /// The recording (.mcap).
        file: PathBuf,
        /// Output CSV file.
        #[arg(short = 'o', long = "output", value_name = "OUT.csv", value_parser = super::options::output_file)]
        output: PathBuf,
    },
}

impl McapCommand {
    /// The subcommand's name on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Info { .. } => "info",
            Self::Csv { .. } => "csv",
        }
    }
}

/// Runs `parol6 mcap`.
pub fn run(args: &McapArgs) -> CliResult {
    match &args.command {
        McapCommand::Info { file } => info(file),
        McapCommand::Csv { file, output } => csv(file, output),
    }
}

/// The largest recording the CLI reads whole, bytes (16 GiB: a one-hour recording is far
/// smaller). The bound matters for what is not a regular recording file.
pub const MAX_RECORDING_BYTES: u64 = 16 << 30;

/// Reads the recording `file` whole: a regular file only (a FIFO or a device is refused with
/// exit 2), at most [`MAX_RECORDING_BYTES`].
pub fn read_recording_file(file: &Path) -> Result<Vec<u8>, CliError> {
    Ok(fsio::read_regular_bounded(file, MAX_RECORDING_BYTES)?)
}

fn scan(file: &Path, visit: &mut dyn FnMut(&str, JointStateMsg)) -> Result<Recording, CliError> {
    scan_bytes(file, &read_recording_file(file)?, visit)
}

fn scan_bytes(file: &Path, bytes: &[u8], visit: &mut dyn FnMut(&str, JointStateMsg)) -> Result<Recording, CliError> {
    let rec = scan_recording(bytes, visit).map_err(|e| CliError::usage(format!("{}: {e}", file.display())))?;
    for w in &rec.warnings {
        warn(format!("{}: {w}", file.display()));
    }
    Ok(rec)
}

fn info(file: &Path) -> CliResult {
    let rec = scan(file, &mut |_, _| {})?;
    let topics: serde_json::Map<String, serde_json::Value> =
        rec.topics.iter().map(|(t, s)| (t.clone(), json!({"messages": s.messages, "schema": s.schema}))).collect();
    let (start, end) = rec.span_ns.map_or((None, None), |(a, b)| (Some(a as f64 * 1e-9), Some(b as f64 * 1e-9)));
    print_json(&json!({
        "file": file.display().to_string(),
        "robot": rec.robot(),
        "joints": rec.joint_names,
        "app_version": rec.metadata.get("app_version"),
        "tool": rec.metadata.get("tool"),
        "program": rec.metadata.get("program"),
        "tracking": rec.metadata.get("tracking"),
        "topics": topics,
        "samples": rec.topics.get("/joint_states").map_or(0, |t| t.messages),
        "duration_s": rec.duration_s(),
        "start_unix_s": start,
        "end_unix_s": end,
        "truncated": rec.truncated,
        "warnings": rec.warnings,
    }))
}

/// The CSV header for `n` joints: time, tick, then per quantity every joint (commanded, then
/// measured), the drive, program step and worst zone.
pub fn csv_header(n: usize) -> String {
    let mut cols = vec!["t_s".to_string(), "seq".to_string()];
    for unit in ["rad", "rad_s", "rad_s2"] {
        for side in ["cmd", "meas"] {
            cols.extend((1..=n).map(|j| format!("j{j}_{side}_{unit}")));
        }
    }
    cols.extend((1..=n).map(|j| format!("j{j}_effort_nm")));
    cols.extend((1..=n).map(|j| format!("j{j}_steps_s")));
    cols.push("program_step".into());
    cols.push("worst_zone_joint".into());
    cols.push("worst_zone".into());
    cols.join(",")
}

fn push_values(line: &mut String, values: &[f64], n: usize) {
    for j in 0..n {
        line.push(',');
        if let Some(v) = values.get(j).filter(|v| v.is_finite()) {
            line.push_str(&v.to_string());
        }
    }
}

/// One CSV row of a measured / commanded pair; `t0_s` is the first sample's motion time.
pub fn csv_row(meas: &JointStateMsg, cmd: &JointStateMsg, t0_s: f64, n: usize) -> String {
    let mut line = format!("{},{}", meas.time_s - t0_s, meas.seq);
    push_values(&mut line, &cmd.position, n);
    push_values(&mut line, &meas.position, n);
    push_values(&mut line, &cmd.velocity, n);
    push_values(&mut line, &meas.velocity, n);
    push_values(&mut line, &cmd.acceleration, n);
    push_values(&mut line, &meas.acceleration, n);
    push_values(&mut line, &meas.effort, n);
    push_values(&mut line, meas.steps_per_s.as_deref().unwrap_or(&[]), n);
    line.push(',');
    if let Some(step) = meas.program_step {
        line.push_str(&step.to_string());
    }
    match &meas.worst_zone {
        Some(z) => line.push_str(&format!(",{},{}", z.joint + 1, z.zone)),
        None => line.push_str(",,safe"),
    }
    line
}

/// Refuses an output that is the input itself (the same file under any name).
fn refuse_same_file(input: &Path, output: &Path) -> CliResult {
    use std::os::unix::fs::MetadataExt;
    if let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output))
        && (a.dev(), a.ino()) == (b.dev(), b.ino())
    {
        return Err(CliError::usage(format!(
            "-o {}: that is the recording being read ({}); name another output file",
            output.display(),
            input.display()
        )));
    }
    Ok(())
}

/// `mcap csv`: the recording is read whole and checked before anything is written, and the CSV
/// is written atomically, so a refused recording or a failed write leaves `output` as it was.
fn csv(file: &Path, output: &Path) -> CliResult {
    refuse_same_file(file, output)?;
    let bytes = read_recording_file(file)?;
    let mut pending: VecDeque<JointStateMsg> = VecDeque::new();
    let mut rows = 0u64;
    let mut unpaired = 0u64;
    let mut scanned: Option<Result<Recording, CliError>> = None;
    let written = fsio::write_atomic(output, |out| {
        let mut t0_s: Option<f64> = None;
        let mut n: Option<usize> = None;
        let mut write_error: Option<std::io::Error> = None;
        let mut visit = |topic: &str, m: JointStateMsg| {
            if write_error.is_some() {
                return;
            }
            if topic == "/joint_states" {
                pending.push_back(m);
                // measured and commanded of a tick are written together; keep a few, never many
                while pending.len() > 16 {
                    pending.pop_front();
                    unpaired += 1;
                }
                return;
            }
            let Some(i) = pending.iter().position(|p| p.seq == m.seq) else {
                unpaired += 1;
                return;
            };
            unpaired += i as u64;
            let meas = pending.drain(..=i).next_back();
            let Some(meas) = meas else { return };
            let joints = *n.get_or_insert(meas.name.len());
            let result = (|| {
                if rows == 0 {
                    writeln!(out, "{}", csv_header(joints))?;
                }
                writeln!(out, "{}", csv_row(&meas, &m, *t0_s.get_or_insert(meas.time_s), joints))
            })();
            match result {
                Ok(()) => rows += 1,
                Err(e) => write_error = Some(e),
            }
        };
        let rec = scan_bytes(file, &bytes, &mut visit);
        if let Some(e) = write_error {
            return Err(e);
        }
        let refused = rec.is_err();
        scanned = Some(rec);
        if refused { Err(std::io::Error::other("the recording was refused")) } else { Ok(()) }
    });
    let rec = match (scanned, written) {
        (Some(Err(e)), _) => return Err(e),
        (_, Err(e)) => return Err(e.into()),
        (Some(Ok(rec)), Ok(())) => rec,
        (None, Ok(())) => return Err(CliError::runtime(format!("{}: the recording was not read", file.display()))),
    };
    if rows == 0 {
        warn(format!("{}: no joint-state samples; {} holds no rows", file.display(), output.display()));
    }
    print_json(&json!({
        "file": file.display().to_string(),
        "output": output.display().to_string(),
        "rows": rows,
        "unpaired_messages": unpaired + pending.len() as u64,
        "robot": rec.robot(),
        "truncated": rec.truncated,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_names_units_and_matches_the_rows() {
        let h = csv_header(6);
        assert!(h.starts_with("t_s,seq,j1_cmd_rad,j2_cmd_rad"), "{h}");
        assert!(h.contains(",j1_meas_rad,") && h.contains(",j6_meas_rad_s2,") && h.contains(",j3_effort_nm,"));
        let m = JointStateMsg {
            header: parol6_core::telemetry::schema::Header {
                stamp: parol6_core::telemetry::schema::Time::default(),
                frame_id: "base_link".into(),
            },
            name: (1..=6).map(|j| format!("J{j}")).collect(),
            position: vec![0.5; 6],
            velocity: vec![0.0; 6],
            effort: vec![],
            acceleration: vec![0.0; 6],
            seq: 7,
            time_s: 1.25,
            steps_per_s: Some(vec![100.0; 6]),
            program_step: Some(3),
            worst_zone: None,
        };
        let row = csv_row(&m, &m, 1.0, 6);
        assert_eq!(row.split(',').count(), h.split(',').count(), "{row}");
        assert!(row.starts_with("0.25,7,0.5,"), "{row}");
        assert!(row.ends_with(",3,,safe"), "{row}");
    }
}
