//! Options shared by several subcommands: the robot selection and the controller connection
//! (both global: accepted before or after the subcommand), and the range-checking value
//! parsers every numeric option uses, so that out-of-range input is refused by clap (exit 2)
//! with the range in the message.

use std::path::PathBuf;

use parol6_core::{RobotModel, Tool};

use super::{CliError, warn};

/// Robot selection: the GUI, `fk`, `ik`, `dynamics`, `screenshot` and `bench render`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RobotArgs {
    /// URDF file of another robot (default: the embedded PAROL6). GUI, fk, ik, dynamics,
    /// screenshot, bench render.
    #[arg(long, value_name = "PATH", global = true)]
    pub urdf: Option<PathBuf>,
    /// Tip link of the chain (default: the single leaf link).
    #[arg(long, value_name = "LINK", global = true)]
    pub tip: Option<String>,
    /// Tool on the flange: none, pneumatic-vertical, pneumatic-horizontal, ssg48, msg, vacuum.
    /// Names are normalised: case and surrounding spaces are ignored, and the aliases `flange`
    /// (none), `pneumatic` (pneumatic-vertical) and `ssg-48` (ssg48) are accepted; any other name
    /// is refused.
    #[arg(long, value_name = "NAME", global = true)]
    pub tool: Option<String>,
}

impl RobotArgs {
    /// True when any robot option was given.
    pub fn any_given(&self) -> bool {
        self.urdf.is_some() || self.tip.is_some() || self.tool.is_some()
    }

    /// The first robot option given, as typed on the command line.
    pub fn first_given(&self) -> Option<&'static str> {
        [(self.urdf.is_some(), "--urdf"), (self.tip.is_some(), "--tip"), (self.tool.is_some(), "--tool")]
            .into_iter()
            .find_map(|(given, name)| given.then_some(name))
    }

    /// Loads the selected robot with its tool.
    pub fn load(&self) -> Result<RobotModel, CliError> {
        let mut model = match &self.urdf {
            None => {
                if let Some(t) = &self.tip
                    && t != "L6"
                {
                    return Err(CliError::usage(format!(
                        "tip link \"{t}\" does not exist in the embedded PAROL6 (its tip is L6)"
                    )));
                }
                RobotModel::parol6()
            }
            // a file that cannot be read is an I/O failure (exit 1); bad content is bad input (2)
            Some(p) => RobotModel::from_urdf_file(p, self.tip.as_deref()).map_err(|e| match e {
                parol6_core::model::ModelError::Io { .. } => CliError::runtime(e),
                e => CliError::usage(e),
            })?,
        };
        for w in &model.warnings {
            warn(w);
        }
        if let Some(name) = &self.tool {
            let tool = Tool::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = Tool::ALL.iter().map(|t| t.name()).collect();
                CliError::usage(format!("unknown tool \"{name}\" (known: {})", names.join(", ")))
            })?;
            model.set_tool(tool);
        }
        Ok(model)
    }
}

/// Controller connection: the GUI and the `hw` subcommands that talk to a controller.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ConnectArgs {
    /// Serial port of the PAROL6 controller (hw: default, the first USB device 0483:5740).
    /// GUI and hw status|enable|disable|home|jog|move.
    #[arg(long, value_name = "PORT", global = true, conflicts_with = "fake_robot")]
    pub port: Option<String>,
    /// Use the built-in controller emulator (powered up homed at standby) instead of a port.
    #[arg(long, global = true)]
    pub fake_robot: bool,
}

impl ConnectArgs {
    /// The first connection option given, as typed on the command line.
    pub fn first_given(&self) -> Option<&'static str> {
        if self.port.is_some() {
            Some("--port")
        } else if self.fake_robot {
            Some("--fake-robot")
        } else {
            None
        }
    }
}

/// Why `text` is not the name of a file to write, if it is not: `-` (stdout carries the JSON
/// report, so output never goes there) and the empty name. Used by every output-file
/// argument: `screenshot OUT.png`, `record -o`, and each `--record`.
pub fn output_file_refusal(text: &std::ffi::OsStr) -> Option<String> {
    if text == "-" {
        Some("\"-\" is refused: stdout carries the JSON report; give a file name".to_string())
    } else if text.is_empty() {
        Some("\"\" is not a file name".to_string())
    } else {
        None
    }
}

/// A clap value parser for an output file ([`output_file_refusal`]): `--record -` is a usage
/// error (exit 2), never a file named `-`.
pub fn output_file(text: &str) -> Result<PathBuf, String> {
    match output_file_refusal(std::ffi::OsStr::new(text)) {
        Some(why) => Err(why),
        None => Ok(PathBuf::from(text)),
    }
}

/// A clap value parser: a finite number within `min…max` (both included).
pub fn f64_within(min: f64, max: f64) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let v = parse_finite(text)?;
        if (min..=max).contains(&v) { Ok(v) } else { Err(format!("must be within {min}…{max}")) }
    }
}

/// A clap value parser: a finite number greater than `min` and at most `max`.
pub fn f64_above(min: f64, max: f64) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let v = parse_finite(text)?;
        if v > min && v <= max { Ok(v) } else { Err(format!("must be > {min} and ≤ {max}")) }
    }
}

fn parse_finite(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err("not a finite number".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_ranges_refuse_out_of_range_and_non_numbers() {
        let speed = f64_within(0.05, 1.0);
        assert_eq!(speed("0.5"), Ok(0.5));
        assert_eq!(speed("1"), Ok(1.0));
        for bad in ["5", "1e-300", "NaN", "inf", "", "abc", "-0.1", "1e400"] {
            let e = speed(bad).expect_err(bad);
            assert!(e.contains("0.05…1") || e.contains("finite"), "{bad}: {e}");
        }
        let seconds = f64_above(0.0, 60.0);
        assert!(seconds("0").is_err() && seconds("60.1").is_err() && seconds("-1").is_err());
        assert_eq!(seconds("60"), Ok(60.0));
    }
}
