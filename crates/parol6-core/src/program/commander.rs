//! PAROL commander programs (the official PAROL6 commander GUI's `.txt` programs): import into
//! a [`Program`] and export from one.
//!
//! ```text
//! Begin()
//! MoveJoint(90, -80, 170, 0, 60, 180, t=2)
//! MoveCart(0, 312.463, 254.03, -90, 0, -50, t=1.5)
//! Output(1, HIGH)
//! Delay(0.5)
//! End()
//! ```
//!
//! One command per line, blank lines skipped; the first command is `Begin()` and the last
//! `End()` or `Loop()`. What each command becomes:
//!
//! | command | step |
//! |---|---|
//! | `Begin()` | (start of the program) |
//! | `End()` / `Loop()` | end; `Loop()` sets [`Program::looping`] (the runner starts over) |
//! | `MoveJoint(j1…j6 deg, opts)` | `move_joints` |
//! | `MovePose(x, y, z mm, rx, ry, rz deg, opts)` | `move_pose` (joint move to the pose; the pose in the commander's frame, see *Frame*) |
//! | `MoveCart(x, y, z, rx, ry, rz, opts)` | `move_l` (straight line; the pose in the commander's frame) |
//! | `MoveCartRelTRF(dx, dy, dz, rx, ry, rz, opts)` | `move_rel_tool` (offset and rotations in the commander's frame, converted to our TCP frame) |
//! | `Delay(s)` | `dwell` (the commander needs more than 0.01 s) |
//! | `Output(1\|2, HIGH\|LOW)` | `set_output` |
//! | `Gripper(position 0–255, speed 0–255, current 100–1000 mA)` | `gripper` to a position |
//! | `Dummy()` | `dwell` of 0 s (the commander's no-op) |
//!
//! `Gripper_cal()` (calibration has no program step here: calibrate from the gripper panel), the
//! commands the commander lists but never implemented (`Input()`, `Home()`, `SpeedJoint()`,
//! `SpeedCart()`, …) and anything else are errors naming the line and the command; nothing
//! is skipped. So is a typo in a move's options, such as `MoveCart(…,-50.t=3)`: the commander's
//! pattern takes the six numbers at the start of the line and drops the rest (the move runs in
//! its 3.6 s default), we refuse the line.
//!
//! **Frame.** The commander's poses are poses of its own TCP frame, frame 6 of its DH table,
//! not of our flange: `MoveCart` / `MovePose` `x, y, z, rx, ry, rz` are that frame's position and
//! orientation, and `MoveCartRelTRF` moves that frame along and about its own axes. The frame
//! is fixed to the flange by one constant transform, defined in [`crate::frames`] (Rx(π) at
//! (−45.25, 0, −25.8) mm in the flange frame). At standby the commander shows
//! `(0, 262.57, 288.75, -90, 0, -90)`, so after `MoveJoint(90,-90,180,0,0,180)` the line
//! `MoveCart(0,262.57,288.75,-90,0,-90)` does not move the arm, here as there.
//!
//! **Tool.** The commander has no tool: its frame stays on the flange whatever is mounted. Our
//! steps hold TCP poses (`flange · tool`), so import converts each commander pose to the TCP
//! pose of the *same flange pose* for the tool of [`CommanderOptions`] (the robot's tool when
//! read through [`super::files`]; the bare flange for [`parse_commander`]), and export the other
//! way. A commander program therefore moves the arm to the same joints whichever tool is set;
//! change the tool after importing and the steps keep their TCP poses, as in every format:
//! import again. `MoveCartRelTRF` becomes the `move_rel_tool` that ends at the same flange
//! pose: its angles are rotations about the commander frame's x, then y, then z axis
//! (`D' = D · Trans(d) · Rx·Ry·Rz`, as the commander applies them), which about our TCP axes are
//! `(rx, −ry, −rz)`, and its offset gains the lever between the commander frame's origin and
//! our TCP when it turns. Both programs move their own frame's origin on a straight line, so
//! where a move turns the tool the paths between the (equal) end poses differ slightly.
//!
//! Angles `rx, ry, rz` are the official convention `R = Rx(rz)·Ry(ry)·Rz(rx)`, converted by
//! [`crate::angles`].
//!
//! Options after the six numbers, as in the commander: `t=` seconds wins over everything (the
//! step's `duration_s`); otherwise `MoveJoint` / `MovePose` with both `v=` and `a=` (0–100 %)
//! run at `speed_fraction = v / 100` (our planner scales speed, acceleration and jerk by one
//! fraction, so `a=` only has to be in range), and with neither or only one of them at the
//! commander's default of 45 % (the imported program's `joint_fraction` is 0.45).
//! `MoveCart` / `MoveCartRelTRF` without `t=` take the commander's fixed 3.6 s (it ignores
//! `v=` / `a=` there; they are still range-checked). `trap` / `poly` choose the commander's
//! timing-law shape: accepted, and planned with our jerk-limited profile over the same time.
//! `speed` makes the commander track the same trajectory by velocity: accepted, followed by
//! position here.
//!
//! Export writes the steps that have an equivalent and refuses the first that has none, by
//! its number, line and type (Cartesian lines need a `duration_s`: the commander times them
//! only with `t=`). Every number is rounded to 3 decimals, as the commander's readout writes
//! them (`round(x, 3)`), and written in its shortest form: `-80`, not `-80.00001816331088`;
//! `0`, not `-0`. Import of an export gives the same numbers back.

mod frame;

use nalgebra::Isometry3;

use self::frame::{CommanderFrame, number_text};
use super::{GripperAction, Program, SourcedStep, SpeedSettings, Step};
use crate::RobotModel;

pub use self::frame::COMMANDER_DECIMALS;

/// Programs larger than this are refused, bytes.
pub const MAX_PROGRAM_BYTES: usize = 16 * 1024 * 1024;
/// The most commands one program may have.
pub const MAX_COMMANDS: usize = 100_000;
/// The commander's joint speed when a move gives no `v=` and `a=` (45 %).
pub const COMMANDER_JOINT_FRACTION: f64 = 0.45;
/// How long the commander's `MoveCart` / `MoveCartRelTRF` take without `t=`, s.
pub const COMMANDER_CART_DURATION_S: f64 = 3.6;
/// The commander's cycle: a `Delay` must be longer, s.
pub const COMMANDER_CYCLE_S: f64 = 0.01;

/// Why a commander program cannot be read or written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommanderError {
    /// A line that is not a valid command.
    #[error("line {line}, {command}: {message}")]
    Line {
        /// 1-based line.
        line: usize,
        /// The command's name as written (or the line's start).
        command: String,
        /// What is wrong.
        message: String,
    },
    /// A step with no commander equivalent (export).
    #[error(transparent)]
    Step(#[from] super::StepRefusal),
    /// The program as a whole.
    #[error("{0}")]
    File(String),
}

/// What converting between commander poses and ours needs beyond the text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommanderOptions {
    /// Our TCP in the flange (`L6`) frame: the robot's tip offset times its tool (metres).
    pub tool: Isometry3<f64>,
}

impl Default for CommanderOptions {
    /// The bare flange.
    fn default() -> Self {
        Self { tool: Isometry3::identity() }
    }
}

impl CommanderOptions {
    /// For the robot's TCP as it is set (tip offset and tool).
    pub fn for_model(model: &RobotModel) -> Self {
        Self { tool: model.tip_offset * model.tool }
    }
}

/// The commands the commander lists but does not run.
const NOT_IMPLEMENTED: [&str; 6] = ["Input", "Home", "SpeedJoint", "SpeedCart", "Get_data", "Timeouts"];

/// Reads a commander program, its poses for the bare flange (see [`parse_commander_with`]).
pub fn parse_commander(text: &str) -> Result<Program, CommanderError> {
    parse_commander_with(text, &CommanderOptions::default())
}

/// Reads a commander program; its poses become TCP poses of `options.tool`.
pub fn parse_commander_with(text: &str, options: &CommanderOptions) -> Result<Program, CommanderError> {
    let frame = CommanderFrame::new(&options.tool);
    if text.len() > MAX_PROGRAM_BYTES {
        return Err(CommanderError::File(format!(
            "the program is {} bytes; commander programs are limited to {} MiB",
            text.len(),
            MAX_PROGRAM_BYTES / (1024 * 1024)
        )));
    }
    let lines: Vec<(usize, &str)> =
        text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty()).collect();
    let (Some(&(first_line, _)), Some(&(last_line, _))) = (lines.first(), lines.last()) else {
        return Err(CommanderError::File("the program is empty: it needs Begin() … End()".into()));
    };
    if lines.len() > MAX_COMMANDS + 2 {
        return Err(CommanderError::File(format!("a program has at most {MAX_COMMANDS} commands")));
    }
    let mut steps = Vec::new();
    let (mut looping, mut begun, mut ended) = (false, false, false);
    for (k, &(line, text)) in lines.iter().enumerate() {
        let cmd = split_command(line, text)?;
        let err = |message: String| CommanderError::Line { line, command: cmd.name.to_string(), message };
        let (is_first, is_last) = (k == 0, k + 1 == lines.len());
        let step = match cmd.name {
            "Begin" => {
                cmd.no_arguments()?;
                if !is_first {
                    return Err(err("Begin() may only be the first command".into()));
                }
                begun = true;
                continue;
            }
            "End" | "Loop" => {
                cmd.no_arguments()?;
                if !is_last {
                    return Err(err(format!("{}() must be the last command", cmd.name)));
                }
                looping = cmd.name == "Loop";
                ended = true;
                continue;
            }
            _ if is_first => {
                return Err(CommanderError::Line {
                    line: first_line,
                    command: cmd.name.to_string(),
                    message: "the program must start with Begin()".into(),
                });
            }
            _ if is_last => {
                return Err(CommanderError::Line {
                    line: last_line,
                    command: cmd.name.to_string(),
                    message: "the program must end with End() or Loop()".into(),
                });
            }
            "MoveJoint" | "MovePose" | "MoveCart" | "MoveCartRelTRF" => move_step(&cmd, &frame)?,
            "Delay" => {
                let [s] = cmd.numbers::<1>()?;
                if s <= COMMANDER_CYCLE_S {
                    return Err(err(format!("the delay must be longer than {COMMANDER_CYCLE_S} s, got {s}")));
                }
                Step::Dwell { seconds: s }
            }
            "Output" => {
                let [n, level] = cmd.fixed::<2>()?;
                let output = match n {
                    "1" => 1,
                    "2" => 2,
                    _ => return Err(err(format!("the output is 1 or 2, got \"{n}\""))),
                };
                let on = match level {
                    "HIGH" => true,
                    "LOW" => false,
                    _ => return Err(err(format!("the level is HIGH or LOW, got \"{level}\""))),
                };
                Step::SetOutput { output, on }
            }
            "Gripper" => {
                let [p, s, c] = cmd.numbers::<3>()?;
                let int = |v: f64, what: &str, lo: f64, hi: f64| -> Result<f64, CommanderError> {
                    if v.fract() == 0.0 && (lo..=hi).contains(&v) {
                        Ok(v)
                    } else {
                        Err(err(format!("the {what} is a whole number {lo}–{hi}, got {v}")))
                    }
                };
                Step::Gripper {
                    action: GripperAction::Position,
                    position: Some(int(p, "position", 0.0, 255.0)? as u8),
                    speed: Some(int(s, "speed", 0.0, 255.0)? as u8),
                    current_ma: Some(int(c, "current (mA)", 100.0, 1000.0)? as u16),
                }
            }
            "Dummy" => {
                cmd.no_arguments()?;
                Step::Dwell { seconds: 0.0 }
            }
            "Gripper_cal" => {
                return Err(err(
                    "gripper calibration has no program step here; calibrate from the gripper panel".into()
                ));
            }
            name if NOT_IMPLEMENTED.contains(&name) => {
                return Err(err("the commander lists this command but does not implement it".into()));
            }
            _ => return Err(err("is not a PAROL commander command".into())),
        };
        steps.push(SourcedStep { step, line });
    }
    if !begun {
        return Err(CommanderError::Line {
            line: first_line,
            command: "End".into(),
            message: "the program must start with Begin()".into(),
        });
    }
    if !ended {
        return Err(CommanderError::Line {
            line: last_line,
            command: "Begin".into(),
            message: "the program must end with End() or Loop()".into(),
        });
    }
    Ok(Program {
        description: "imported from a PAROL commander program".into(),
        speed: SpeedSettings { joint_fraction: COMMANDER_JOINT_FRACTION, ..SpeedSettings::default() },
        steps,
        looping,
        ..Program::default()
    })
}

/// One command line split into its name and arguments.
struct Command<'a> {
    line: usize,
    name: &'a str,
    args: Vec<&'a str>,
}

fn split_command(line: usize, text: &str) -> Result<Command<'_>, CommanderError> {
    let head: String = text.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
    let err = |message: String| CommanderError::Line {
        line,
        command: if head.is_empty() {
            format!("\"{}\"", text.chars().take(20).collect::<String>())
        } else {
            head.clone()
        },
        message,
    };
    let rest = &text[head.len()..];
    // trial 23 m4: a `#` line was refused as "a command is written Name(arguments)"
    if head.is_empty() && (text.starts_with('#') || text.starts_with("//")) {
        return Err(err("a comment: the commander's program format has no comments; delete the line".into()));
    }
    let Some(inner) = rest.trim_start().strip_prefix('(') else {
        return Err(err("a command is written Name(arguments)".into()));
    };
    let Some(inner) = inner.strip_suffix(')') else {
        return Err(err("the line must end with ')'".into()));
    };
    if inner.contains(['(', ')']) {
        return Err(err("parentheses inside the arguments".into()));
    }
    if head.is_empty() {
        return Err(err("the command has no name".into()));
    }
    let name = &text[..head.len()];
    let args = if inner.trim().is_empty() { Vec::new() } else { inner.split(',').map(str::trim).collect() };
    Ok(Command { line, name, args })
}

impl Command<'_> {
    fn err(&self, message: String) -> CommanderError {
        CommanderError::Line { line: self.line, command: self.name.to_string(), message }
    }

    fn no_arguments(&self) -> Result<(), CommanderError> {
        if self.args.is_empty() { Ok(()) } else { Err(self.err(format!("{}() takes no arguments", self.name))) }
    }

    fn fixed<const N: usize>(&self) -> Result<[&str; N], CommanderError> {
        <[&str; N]>::try_from(self.args.as_slice())
            .map_err(|_| self.err(format!("takes {N} arguments, got {}", self.args.len())))
    }

    fn numbers<const N: usize>(&self) -> Result<[f64; N], CommanderError> {
        let args = self.fixed::<N>()?;
        let mut out = [0.0; N];
        for (o, a) in out.iter_mut().zip(args) {
            *o = self.number(a)?;
        }
        Ok(out)
    }

    /// A number as the commander writes them: `-12.5`, `3` (no exponent, no `+`).
    fn number(&self, text: &str) -> Result<f64, CommanderError> {
        let digits = text.strip_prefix('-').unwrap_or(text);
        let (int, frac) = digits.split_once('.').unwrap_or((digits, "0"));
        let ok = !int.is_empty()
            && !frac.is_empty()
            && int.bytes().all(|b| b.is_ascii_digit())
            && frac.bytes().all(|b| b.is_ascii_digit());
        match text.parse::<f64>() {
            Ok(v) if ok && v.is_finite() => Ok(v),
            _ => Err(self.err(format!("\"{text}\" is not a number (written like -12.5)"))),
        }
    }
}

/// The options of a move: `v=`, `a=`, `t=`, `trap` / `poly`, `speed`.
#[derive(Default)]
struct MoveOptions {
    v: Option<f64>,
    a: Option<f64>,
    t: Option<f64>,
}

fn move_step(cmd: &Command<'_>, frame: &CommanderFrame) -> Result<Step, CommanderError> {
    if cmd.args.len() < 6 {
        return Err(cmd.err(format!("needs 6 numbers, got {}", cmd.args.len())));
    }
    let mut v = [0.0; 6];
    for (o, a) in v.iter_mut().zip(&cmd.args[..6]) {
        *o = cmd.number(a)?;
    }
    let mut opts = MoveOptions::default();
    let mut seen: Vec<&str> = Vec::new();
    for arg in &cmd.args[6..] {
        let (key, value) = match arg.split_once('=') {
            Some((k, val)) => (k.trim(), Some(val.trim())),
            None => (*arg, None),
        };
        let group = if key == "poly" { "trap" } else { key };
        if seen.contains(&group) {
            return Err(cmd.err(format!("option \"{arg}\" repeats or conflicts with an earlier one")));
        }
        seen.push(group);
        match (key, value) {
            ("v" | "a", Some(val)) => {
                let x = cmd.number(val)?;
                if !(0.0..=100.0).contains(&x) {
                    return Err(cmd.err(format!("{key}= is a percentage 0–100, got {x}")));
                }
                if key == "v" { opts.v = Some(x) } else { opts.a = Some(x) }
            }
            ("t", Some(val)) => {
                let x = cmd.number(val)?;
                if x <= 0.0 {
                    return Err(cmd.err(format!("t= is a time above 0 s, got {x}")));
                }
                opts.t = Some(x);
            }
            ("trap" | "poly" | "speed", None) => {}
            _ => {
                return Err(cmd.err(format!(
                    "\"{arg}\" is not a move option (v=%, a=%, t=s, trap or poly, speed) or comes before a number"
                )));
            }
        }
    }
    let joint_fraction = match (opts.t, opts.v, opts.a) {
        (None, Some(v), Some(_)) => Some((v / 100.0).max(super::compile::MIN_JOINT_FRACTION)),
        _ => None,
    };
    let pose = || frame.pose_in(v);
    let cart_duration_s = Some(opts.t.unwrap_or(COMMANDER_CART_DURATION_S));
    Ok(match cmd.name {
        "MoveJoint" => Step::MoveJoints { joints_deg: v.to_vec(), speed_fraction: joint_fraction, duration_s: opts.t },
        "MovePose" => Step::MovePose { pose: pose(), config: None, speed_fraction: joint_fraction, duration_s: opts.t },
        "MoveCart" => Step::MoveL { pose: pose(), speed_mm_s: None, blend_mm: None, duration_s: cart_duration_s },
        _ => {
            let (offset_mm, rotation_deg) = frame.rel_in(v);
            Step::MoveRelTool { offset_mm, rotation_deg, speed_mm_s: None, duration_s: cart_duration_s }
        }
    })
}

/// Writes a program as commander text, its poses for the bare flange (see
/// [`program_to_commander_with`]).
pub fn program_to_commander(program: &Program) -> Result<String, CommanderError> {
    program_to_commander_with(program, &CommanderOptions::default())
}

/// Writes a program as commander text, its poses read as TCP poses of `options.tool`;
/// refuses the first step with no commander equivalent.
pub fn program_to_commander_with(program: &Program, options: &CommanderOptions) -> Result<String, CommanderError> {
    let frame = CommanderFrame::new(&options.tool);
    let mut out = String::from("Begin()\n");
    for (i, s) in program.steps.iter().enumerate() {
        let refuse = |message: &str| CommanderError::Step(super::StepRefusal::new(i, s, message));
        let num = |x: f64| number_text(x).ok_or_else(|| refuse(&format!("{x} is not a number the commander can read")));
        let six = |v: &[f64]| -> Result<String, CommanderError> {
            Ok(v.iter().map(|x| num(*x)).collect::<Result<Vec<_>, _>>()?.join(","))
        };
        // a time as written must still be above 0 s
        let time = |d: f64| -> Result<String, CommanderError> {
            let t = num(d)?;
            if t == "0" { Err(refuse(&format!("duration_s {d} s is 0 at 3 decimals"))) } else { Ok(format!(",t={t}")) }
        };
        // joint moves: t= wins; otherwise the speed as v= and a= unless it is the commander's default
        let joint_opts = |fraction: Option<f64>, duration_s: Option<f64>| match duration_s {
            Some(d) => time(d),
            None => {
                let f = fraction.unwrap_or(program.speed.joint_fraction);
                if f == COMMANDER_JOINT_FRACTION {
                    Ok(String::new())
                } else {
                    let pct = num(f * 100.0)?;
                    Ok(format!(",v={pct},a={pct}"))
                }
            }
        };
        let cart_time = |duration_s: Option<f64>| match duration_s {
            Some(d) => time(d),
            None => Err(refuse(
                "the commander times Cartesian moves only by t= (3.6 s without it); give the step a duration_s",
            )),
        };
        let text = match &s.step {
            Step::MoveJoints { joints_deg, speed_fraction, duration_s } => {
                if joints_deg.len() != 6 {
                    return Err(refuse("MoveJoint takes 6 joint values"));
                }
                format!("MoveJoint({}{})", six(joints_deg)?, joint_opts(*speed_fraction, *duration_s)?)
            }
            Step::MovePose { pose, speed_fraction, duration_s, .. } => {
                format!("MovePose({}{})", six(&frame.pose_out(pose))?, joint_opts(*speed_fraction, *duration_s)?)
            }
            Step::MoveL { pose, blend_mm, duration_s, .. } => {
                if blend_mm.is_some_and(|b| b != 0.0) {
                    return Err(refuse("the commander does not blend lines; remove blend_mm"));
                }
                format!("MoveCart({}{})", six(&frame.pose_out(pose))?, cart_time(*duration_s)?)
            }
            Step::MoveRelTool { offset_mm, rotation_deg, duration_s, .. } => {
                format!("MoveCartRelTRF({}{})", six(&frame.rel_out(offset_mm, rotation_deg))?, cart_time(*duration_s)?)
            }
            Step::Dwell { seconds } if *seconds == 0.0 => "Dummy()".into(),
            Step::Dwell { seconds } => match num(*seconds)? {
                t if t.parse::<f64>().is_ok_and(|v| v > COMMANDER_CYCLE_S) => format!("Delay({t})"),
                _ => return Err(refuse("the commander's Delay() is longer than 0.01 s")),
            },
            Step::SetOutput { output, on } if matches!(output, 1 | 2) => {
                format!("Output({output},{})", if *on { "HIGH" } else { "LOW" })
            }
            Step::Gripper { action, position, speed, current_ma } => {
                let p = match action {
                    GripperAction::Open => 0,
                    GripperAction::Close => 255,
                    GripperAction::Position => position.ok_or_else(|| refuse("a position step needs its position"))?,
                };
                let current = current_ma.unwrap_or(500);
                if !(100..=1000).contains(&current) {
                    return Err(refuse("the commander's gripper current lies in 100–1000 mA"));
                }
                format!("Gripper({p},{},{current})", speed.unwrap_or(128))
            }
            _ => return Err(refuse("has no PAROL commander equivalent")),
        };
        out.push_str(&text);
        out.push('\n');
    }
    out.push_str(if program.looping { "Loop()\n" } else { "End()\n" });
    Ok(out)
}

#[cfg(test)]
mod tests;
