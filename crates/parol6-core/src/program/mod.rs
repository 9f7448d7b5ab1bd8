//! Robot programs: an ordered list of [`Step`]s (joint and Cartesian moves, dwell, gripper,
//! digital I/O, wait for an input, home) with their speed settings, tool and keep-out shapes.
//!
//! - [`json`]: the native, versioned file format (units in the field names);
//! - [`files`]: every program file format by extension (read, write);
//! - [`edit`]: editing with undo / redo (teach, duplicate, delete, reorder);
//! - [`builtin`]: the programs embedded in the binary (the demos);
//! - [`compile`]: steps → planned joint trajectories ([`compile::CompiledStep`]), from a start
//!   pose, at a chosen sample period (1 ms to run, 10 ms for pre-flight);
//! - [`check`]: pre-flight of a whole program before anything moves;
//! - [`torques`]: inverse dynamics over a compiled program (joint torques vs time, warnings
//!   over the motor limits);
//! - [`runner`]: runs a program on any [`RobotBackend`](crate::motion::RobotBackend) on its
//!   own thread, with pause, resume, single step, stop and a progress readout.
//!
//! A program means the same on the simulation and on the robot: every motion step becomes a
//! [`MotionCommand::Trajectory`](crate::motion::MotionCommand::Trajectory) scheduled on the
//! backend's motion clock, so both backends get identical commanded trajectories.

use serde::{Deserialize, Serialize};

use crate::ik::Branch;
use crate::kinematics::iso_from_xyz_rpy;
use crate::scene::KeepOut;

pub mod builtin;
pub mod check;
pub mod commander;
pub mod compile;
pub mod edit;
pub mod files;
pub mod gcode;
pub mod json;
pub mod runner;
pub mod table;
pub mod timefn;
pub mod torques;

/// A configuration in a file: its label (`front/up/no-flip`), parsed back with its error.
mod config_label {
    use serde::{Deserialize, Deserializer, Serializer, de::Error as _};

    use crate::ik::Branch;

    pub fn serialize<S: Serializer>(config: &Option<Branch>, s: S) -> Result<S::Ok, S::Error> {
        match config {
            Some(b) => s.serialize_some(&b.label()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Branch>, D::Error> {
        Option::<String>::deserialize(d)?.map(|t| t.parse().map_err(D::Error::custom)).transpose()
    }
}

/// A TCP pose as written in a program: position in mm, orientation as our URDF roll / pitch /
/// yaw in degrees (R = Rz(yaw)·Ry(pitch)·Rx(roll)), in the robot's base frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseMm {
    /// Position, mm.
    pub position_mm: [f64; 3],
    /// Roll, pitch, yaw, deg.
    pub rpy_deg: [f64; 3],
}

impl PoseMm {
    /// The pose as an isometry in metres and radians.
    pub fn isometry(&self) -> nalgebra::Isometry3<f64> {
        let p = self.position_mm.map(|v| v / 1000.0);
        iso_from_xyz_rpy(p, self.rpy_deg.map(f64::to_radians))
    }

    /// From an isometry (metres, radians).
    pub fn from_isometry(iso: &nalgebra::Isometry3<f64>) -> Self {
        let pose = crate::kinematics::TcpPose::from_isometry(iso);
        Self { position_mm: pose.position_m.map(|v| v * 1000.0), rpy_deg: pose.rpy_rad.map(f64::to_degrees) }
    }
}

/// What the gripper step does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GripperAction {
    /// Open fully (position 0).
    Open,
    /// Close fully (position 255).
    Close,
    /// Go to `position`.
    Position,
}

/// One program step. Speeds left out use the program's [`SpeedSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Step {
    /// Profiled move to the home pose (PAROL6 standby).
    Home {
        /// Fraction of the joint speed caps (0 < f ≤ 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_fraction: Option<f64>,
    },
    /// Synchronised joint move to joint values.
    MoveJoints {
        /// Goal joint values, deg.
        joints_deg: Vec<f64>,
        /// Fraction of the joint speed caps (0 < f ≤ 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_fraction: Option<f64>,
        /// Time the move takes, s (the commander's `t=`, a point table's `time_s`): the move is
        /// stretched to take it and refused when the caps cannot make it that fast; the speed
        /// is then not used.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        duration_s: Option<f64>,
    },
    /// Joint move to a TCP pose: the IK solution within the limits nearest the start joints,
    /// in any configuration, or in `config` when it is given.
    MovePose {
        /// Goal pose.
        pose: PoseMm,
        /// The arm configuration to reach it in (`front/up/no-flip`: shoulder front|back, elbow
        /// up|down, wrist no-flip|flip); absent: the nearest solution, whichever it is in.
        #[serde(default, skip_serializing_if = "Option::is_none", with = "config_label")]
        config: Option<Branch>,
        /// Fraction of the joint speed caps (0 < f ≤ 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_fraction: Option<f64>,
        /// Time the move takes, s (the commander's `t=`, a point table's `time_s`): the move is
        /// stretched to take it and refused when the caps cannot make it that fast; the speed
        /// is then not used.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        duration_s: Option<f64>,
    },
    /// Straight TCP line to `pose`, orientation slerped. Consecutive `move_l` steps with a
    /// `blend_mm` are joined into one path whose corners are rounded with that radius.
    MoveL {
        /// Goal pose.
        pose: PoseMm,
        /// TCP speed, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
        /// Corner radius toward the next `move_l`, mm (0 or absent: stop at the corner).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        blend_mm: Option<f64>,
        /// Time the move takes, s (the commander's `t=`, a point table's `time_s`): the move is
        /// stretched to take it and refused when the caps cannot make it that fast; the speed
        /// is then not used.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        duration_s: Option<f64>,
    },
    /// Circular arc through `via_mm` to `pose` (orientation slerped).
    MoveC {
        /// A point on the arc, mm.
        via_mm: [f64; 3],
        /// Goal pose.
        pose: PoseMm,
        /// TCP speed, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
    },
    /// Arc about a centre in the plane normal to `normal` (right-hand rule), `angle_deg` of
    /// turn (360: a full circle); orientation kept.
    MoveCircle {
        /// Centre, mm.
        center_mm: [f64; 3],
        /// Plane normal (need not be unit length).
        normal: [f64; 3],
        /// Angle of turn, deg (negative: the other way).
        angle_deg: f64,
        /// TCP speed, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
    },
    /// Smooth spline (Catmull–Rom) through the waypoints, from the current pose.
    Spline {
        /// Waypoints after the start.
        waypoints: Vec<PoseMm>,
        /// TCP speed, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
    },
    /// Straight TCP line to a pose given relative to the TCP where the step starts (the
    /// commander's `MoveCartRelTRF`): the goal is `start · Trans(offset) · Rx·Ry·Rz`, i.e. the
    /// offset along the tool's own axes and then rotations about the tool's x, y and z axes.
    MoveRelTool {
        /// Offset along the tool's x, y, z axes, mm.
        offset_mm: [f64; 3],
        /// Rotation about the tool's x, then y, then z axis, deg.
        #[serde(default)]
        rotation_deg: [f64; 3],
        /// TCP speed, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
        /// Time the move takes, s (the commander's `t=`, a point table's `time_s`): the move is
        /// stretched to take it and refused when the caps cannot make it that fast; the speed
        /// is then not used.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        duration_s: Option<f64>,
    },
    /// The TCP follows x(t), y(t), z(t) (and optionally roll/pitch/yaw(t)) piece by piece in
    /// time; see [`timefn`]. Its first point must be where the TCP is when the step starts.
    TimeFunction {
        /// How often the expressions are evaluated, Hz (the path between is interpolated).
        sample_rate_hz: f64,
        /// The pieces, one after the other.
        pieces: Vec<timefn::TimePiece>,
    },
    /// Hold still.
    Dwell {
        /// Time, s.
        seconds: f64,
    },
    /// Electric gripper.
    Gripper {
        /// Open, close or go to a position.
        action: GripperAction,
        /// Position 0 (open) … 255 (closed), for `position`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        position: Option<u8>,
        /// Speed 0–255 (default 128).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed: Option<u8>,
        /// Current limit, mA (default 500).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        current_ma: Option<u16>,
    },
    /// Set a digital output.
    SetOutput {
        /// Output 1 or 2.
        output: u8,
        /// Level.
        on: bool,
    },
    /// Wait until a digital input has a level.
    WaitInput {
        /// Input 1 or 2.
        input: u8,
        /// Level to wait for.
        on: bool,
        /// Give up (the program fails) after this long, s (default 10).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        timeout_s: Option<f64>,
    },
    /// The run pauses here until the operator resumes (G-code `M0`); an optional pause
    /// (`M1`) only when the run has optional pauses on
    /// ([`RunOptions::optional_pauses`](runner::RunOptions::optional_pauses)).
    Pause {
        /// Only with optional pauses on.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        optional: bool,
    },
}

impl Step {
    /// Short name for lists and messages (the `type` of the file format).
    pub fn kind(&self) -> &'static str {
        match self {
            Step::Home { .. } => "home",
            Step::MoveJoints { .. } => "move_joints",
            Step::MovePose { .. } => "move_pose",
            Step::MoveL { .. } => "move_l",
            Step::MoveC { .. } => "move_c",
            Step::MoveCircle { .. } => "move_circle",
            Step::Spline { .. } => "spline",
            Step::MoveRelTool { .. } => "move_rel_tool",
            Step::TimeFunction { .. } => "time_function",
            Step::Dwell { .. } => "dwell",
            Step::Gripper { .. } => "gripper",
            Step::SetOutput { .. } => "set_output",
            Step::WaitInput { .. } => "wait_input",
            Step::Pause { .. } => "pause",
        }
    }

    /// A one-line description with units, for the program panel and reports.
    pub fn summary(&self) -> String {
        let text = self.what();
        match self {
            Step::MoveJoints { duration_s: Some(d), .. }
            | Step::MovePose { duration_s: Some(d), .. }
            | Step::MoveL { duration_s: Some(d), .. }
            | Step::MoveRelTool { duration_s: Some(d), .. } => format!("{text} in {d:.2} s"),
            _ => text,
        }
    }

    /// [`Step::summary`] without the duration.
    fn what(&self) -> String {
        let pose = |p: &PoseMm| {
            format!(
                "({:.1}, {:.1}, {:.1}) mm ({:.1}, {:.1}, {:.1})°",
                p.position_mm[0], p.position_mm[1], p.position_mm[2], p.rpy_deg[0], p.rpy_deg[1], p.rpy_deg[2]
            )
        };
        match self {
            Step::Home { .. } => "home to standby".into(),
            Step::MoveJoints { joints_deg, .. } => {
                let j: Vec<String> = joints_deg.iter().map(|v| format!("{v:.1}")).collect();
                format!("joints [{}]°", j.join(", "))
            }
            Step::MovePose { pose: p, config: Some(c), .. } => format!("joint move to {} in {}", pose(p), c.label()),
            Step::MovePose { pose: p, .. } => format!("joint move to {}", pose(p)),
            Step::MoveL { pose: p, blend_mm, .. } => match blend_mm {
                Some(b) if *b > 0.0 => format!("line to {} blend {b:.1} mm", pose(p)),
                _ => format!("line to {}", pose(p)),
            },
            Step::MoveC { pose: p, .. } => format!("arc to {}", pose(p)),
            Step::MoveCircle { angle_deg, .. } => format!("arc of {angle_deg:.1}° about a centre"),
            Step::Spline { waypoints, .. } => format!("spline through {} waypoints", waypoints.len()),
            Step::MoveRelTool { offset_mm: d, rotation_deg: r, .. } => format!(
                "line by ({:.1}, {:.1}, {:.1}) mm ({:.1}, {:.1}, {:.1})° in the tool frame",
                d[0], d[1], d[2], r[0], r[1], r[2]
            ),
            Step::TimeFunction { pieces, .. } => {
                let total_s: f64 = pieces.iter().map(|p| p.duration_s).sum();
                let n = pieces.len();
                format!("time function, {n} piece{}, {total_s:.2} s", if n == 1 { "" } else { "s" })
            }
            Step::Dwell { seconds } => format!("dwell {seconds:.2} s"),
            Step::Gripper { action, position, .. } => match action {
                GripperAction::Open => "gripper open".into(),
                GripperAction::Close => "gripper close".into(),
                GripperAction::Position => format!("gripper to {}", position.unwrap_or(0)),
            },
            Step::SetOutput { output, on } => format!("output {output} {}", if *on { "on" } else { "off" }),
            Step::WaitInput { input, on, .. } => format!("wait for input {input} {}", if *on { "high" } else { "low" }),
            Step::Pause { optional: false } => "pause until resumed".into(),
            Step::Pause { optional: true } => "optional pause".into(),
        }
    }
}

/// Program-wide speed settings (what a step without its own speed uses).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SpeedSettings {
    /// Fraction of the joint speed / acceleration caps for joint moves (0 < f ≤ 1).
    pub joint_fraction: f64,
    /// TCP speed of Cartesian moves, mm/s.
    pub tcp_speed_mm_s: f64,
    /// TCP acceleration, mm/s².
    pub tcp_accel_mm_s2: f64,
    /// TCP jerk, mm/s³.
    pub tcp_jerk_mm_s3: f64,
}

impl Default for SpeedSettings {
    /// Half the joint caps; 100 mm/s, 500 mm/s², 5 000 mm/s³.
    fn default() -> Self {
        Self { joint_fraction: 0.5, tcp_speed_mm_s: 100.0, tcp_accel_mm_s2: 500.0, tcp_jerk_mm_s3: 5000.0 }
    }
}

/// A step with the 1-based line of the source file it came from (0: not from a file).
#[derive(Debug, Clone, PartialEq)]
pub struct SourcedStep {
    /// The step.
    pub step: Step,
    /// 1-based source line, 0 when unknown.
    pub line: usize,
}

/// A step a writer cannot express in its format (commander text, a point table): which step,
/// where it came from, and why. One type for every exporter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("step {index} (line {line}, {kind}): {message}")]
pub struct StepRefusal {
    /// 1-based step.
    pub index: usize,
    /// Its source line (0: unknown).
    pub line: usize,
    /// Its type.
    pub kind: &'static str,
    /// Why.
    pub message: String,
}

impl StepRefusal {
    /// The refusal of step `i` (0-based) of a program.
    pub fn new(i: usize, step: &SourcedStep, message: impl Into<String>) -> Self {
        Self { index: i + 1, line: step.line, kind: step.step.kind(), message: message.into() }
    }
}

/// A robot program.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Program {
    /// Name shown in lists.
    pub name: String,
    /// One line on what it does.
    pub description: String,
    /// The tool the program is written for; `None`: the model's tool as it is.
    pub tool: Option<crate::parol6::Tool>,
    /// Speed settings.
    pub speed: SpeedSettings,
    /// Keep-out shapes the pre-flight checks against (the floor is always one).
    pub keep_out: Vec<KeepOut>,
    /// The steps in order.
    pub steps: Vec<SourcedStep>,
    /// Run the steps over and over until stopped (the commander's `Loop()`).
    pub looping: bool,
    /// The tracking mode the program is meant to run in (`None`: the caller's choice;
    /// `parol6 program run --tracking` overrides it).
    pub tracking: Option<crate::motion::tracking::TrackingMode>,
}

impl Program {
    /// A program from steps (no source lines).
    pub fn from_steps(name: impl Into<String>, steps: Vec<Step>) -> Self {
        Self {
            name: name.into(),
            steps: steps.into_iter().map(|step| SourcedStep { step, line: 0 }).collect(),
            ..Self::default()
        }
    }
}

#[cfg(test)]
mod summary_tests {
    use super::*;

    /// Issue 32 minor: the step list said "1 pieces".
    #[test]
    fn a_time_function_of_one_piece_says_piece() {
        let one =
            Step::TimeFunction { sample_rate_hz: 100.0, pieces: vec![timefn::TimePiece::position(1.0, "0", "0", "0")] };
        assert!(one.summary().starts_with("time function, 1 piece, "), "{}", one.summary());
        let two = Step::TimeFunction {
            sample_rate_hz: 100.0,
            pieces: vec![timefn::TimePiece::position(1.0, "0", "0", "0"); 2],
        };
        assert!(two.summary().starts_with("time function, 2 pieces, "), "{}", two.summary());
    }
}
