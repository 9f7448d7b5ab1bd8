//! [`Program`] → G-code (see the [module docs](super) for what each step becomes).

use nalgebra::{Isometry3, Point3, Translation3, Vector3};

use super::arc::Plane;
use super::header::{abc_header, looks_like_header};
use super::path::{PathTolerance, simplify};
use super::{AbcConvention, GcodeGripper, format_number};
use crate::model::RobotModel;
use crate::motion::home_position;
use crate::motion::path::{TcpPath, circle_through};
use crate::program::{GripperAction, PoseMm, Program, Step};

/// How to write G-code.
#[derive(Debug, Clone, PartialEq)]
pub struct GcodeExportOptions {
    /// Joint values the program starts from, rad: an arc or spline at the start begins at
    /// their forward-kinematics pose (read the file back from the same start pose).
    pub start_q: Vec<f64>,
    /// What `M3`/`M4`/`M5` drive: `gripper` steps need [`GcodeGripper::Electric`],
    /// `set_output` steps [`GcodeGripper::Pneumatic`].
    pub gripper: GcodeGripper,
    /// How far the `G1` lines of sampled moves (splines, arcs outside the XY / ZX / YZ planes)
    /// may leave the path.
    pub tolerance: PathTolerance,
    /// How `A B C` are written (named in the file's header line).
    pub abc: AbcConvention,
}

impl GcodeExportOptions {
    /// Starting at `start_q`, gripper words as fit `program`'s tool, default tolerance.
    pub fn new(program: &Program, start_q: Vec<f64>) -> Self {
        Self {
            start_q,
            gripper: GcodeGripper::for_tool(program.tool),
            tolerance: PathTolerance::default(),
            abc: AbcConvention::default(),
        }
    }

    /// These options writing `A B C` in `abc`.
    pub fn with_abc(mut self, abc: AbcConvention) -> Self {
        self.abc = abc;
        self
    }
}

/// Why a program or path cannot be written as G-code.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GcodeExportError {
    /// A step with no G-code equivalent, or one that cannot be computed.
    #[error("step {} ({kind}): {message}", index + 1)]
    Step {
        /// 0-based step index.
        index: usize,
        /// Step type.
        kind: &'static str,
        /// Why.
        message: String,
    },
    /// Bad options or input.
    #[error("{0}")]
    Input(String),
}

/// `X… Y… Z… A… B… C…` of a pose (A/B/C in `abc`).
pub(crate) fn axis_words(p: &PoseMm, abc: AbcConvention) -> String {
    let abc = abc.from_rpy_deg(p.rpy_deg);
    let v = [p.position_mm[0], p.position_mm[1], p.position_mm[2], abc[0], abc[1], abc[2]];
    lettered("XYZABC", &v)
}

/// `letters[k]` followed by `values[k]`, space-separated.
fn lettered(letters: &str, values: &[f64]) -> String {
    letters.chars().zip(values).map(|(l, v)| format!("{l}{}", format_number(*v))).collect::<Vec<_>>().join(" ")
}

/// An arc ending closer than this to its start is a full circle, mm (the reader's is 1e-6).
const FULL_CIRCLE_MM: f64 = 1e-7;

/// The comment lines that open every file written: the header naming `abc` and what the axis
/// words mean.
pub(crate) fn preamble(abc: AbcConvention) -> String {
    let order = match abc {
        AbcConvention::Commander => {
            "R = Rx(C)·Ry(B)·Rz(A) (the PAROL commander's and the official API's until 2025-12)"
        }
        AbcConvention::Xyz => "R = Rx(A)·Ry(B)·Rz(C) (the official API's last G-code revision)",
    };
    format!("{}\n; X Y Z mm in the base frame; A B C deg, {order}\n", abc_header(abc))
}

/// Writes `program` for `model` as G-code.
pub fn program_to_gcode(
    program: &Program,
    model: &RobotModel,
    options: &GcodeExportOptions,
) -> Result<String, GcodeExportError> {
    options.tolerance.check()?;
    if options.start_q.len() != model.dof() || !options.start_q.iter().all(|v| v.is_finite()) {
        return Err(GcodeExportError::Input(format!(
            "the start pose needs {} finite joint values, got {}",
            model.dof(),
            options.start_q.len()
        )));
    }
    let mut w = Writer {
        out: String::new(),
        pose: model.tcp_isometry(&options.start_q),
        feed_mm_min: None,
        plane: Plane::Xy,
        blend_mm: None,
        options,
    };
    w.out.push_str(&preamble(options.abc));
    for line in [&program.name, &program.description] {
        let line = line.replace(['\n', '\r'], " ");
        if looks_like_header(&line) {
            // not to be read back as a header
            w.line(&format!("; \"{line}\""));
        } else if !line.is_empty() {
            w.line(&format!("; {line}"));
        }
    }
    w.line("G21 G90 G17");
    for (index, s) in program.steps.iter().enumerate() {
        let kind = s.step.kind();
        w.step(&s.step, program, model).map_err(|message| GcodeExportError::Step { index, kind, message })?;
    }
    w.line("M30");
    Ok(w.out)
}

struct Writer<'a> {
    out: String,
    /// Where the TCP is.
    pose: Isometry3<f64>,
    feed_mm_min: Option<f64>,
    plane: Plane,
    blend_mm: Option<f64>,
    options: &'a GcodeExportOptions,
}

impl Writer<'_> {
    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn feed_word(&mut self, speed_mm_s: f64) -> String {
        let f = speed_mm_s * 60.0;
        if self.feed_mm_min == Some(f) {
            String::new()
        } else {
            self.feed_mm_min = Some(f);
            format!(" F{}", format_number(f))
        }
    }

    fn rapid(&mut self, goal: Isometry3<f64>, comment: &str) {
        let text = format!("G0 {}{comment}", axis_words(&PoseMm::from_isometry(&goal), self.options.abc));
        self.line(&text);
        self.pose = goal;
    }

    fn step(&mut self, step: &Step, program: &Program, model: &RobotModel) -> Result<(), String> {
        let speed_of = |s: &Option<f64>| s.unwrap_or(program.speed.tcp_speed_mm_s);
        match step {
            Step::Home { .. } => {
                self.line("G28");
                self.pose = model.tcp_isometry(&home_position(model));
            }
            Step::MoveJoints { joints_deg, .. } => {
                if joints_deg.len() != model.dof() || !joints_deg.iter().all(|v| v.is_finite()) {
                    return Err(format!("needs {} finite joint values", model.dof()));
                }
                let q: Vec<f64> = joints_deg.iter().map(|d| d.to_radians()).collect();
                let shown: Vec<String> = joints_deg.iter().map(|v| format_number(*v)).collect();
                self.rapid(model.tcp_isometry(&q), &format!(" ; joints [{}] deg", shown.join(", ")));
            }
            Step::MovePose { pose, .. } => self.rapid(checked(pose)?, ""),
            Step::MoveL { pose, speed_mm_s, blend_mm, duration_s } => {
                let blend = blend_mm.filter(|b| *b > 0.0);
                if blend != self.blend_mm {
                    match blend {
                        Some(b) => self.line(&format!("G64 P{}", format_number(b))),
                        None => self.line("G61"),
                    }
                    self.blend_mm = blend;
                }
                let goal = checked(pose)?;
                let speed = timed_speed(&self.pose, &goal, *duration_s).unwrap_or_else(|| speed_of(speed_mm_s));
                let f = self.feed_word(speed);
                self.line(&format!("G1 {}{f}", axis_words(pose, self.options.abc)));
                self.pose = goal;
            }
            Step::MoveRelTool { offset_mm, rotation_deg, speed_mm_s, duration_s } => {
                if !offset_mm.iter().chain(rotation_deg).all(|v| v.is_finite()) {
                    return Err("the offset and rotation must be finite numbers".into());
                }
                let goal = crate::program::compile::timed::tool_frame_goal(&self.pose, offset_mm, rotation_deg);
                let speed = timed_speed(&self.pose, &goal, *duration_s).unwrap_or_else(|| speed_of(speed_mm_s));
                let f = self.feed_word(speed);
                self.line(&format!(
                    "G1 {}{f} ; tool-frame move",
                    axis_words(&PoseMm::from_isometry(&goal), self.options.abc)
                ));
                self.pose = goal;
            }
            Step::TimeFunction { sample_rate_hz, pieces } => {
                let function =
                    crate::program::timefn::TimeFunction::new(pieces, *sample_rate_hz).map_err(|e| e.to_string())?;
                let points = function.sample(&self.pose).map_err(|e| e.to_string())?;
                self.line(&format!(
                    "; time function: {} points at {} Hz",
                    points.len(),
                    format_number(*sample_rate_hz)
                ));
                for w in points.windows(2) {
                    let ((t0, _), (t1, goal)) = (w[0], w[1]);
                    let speed = timed_speed(&self.pose, &goal, Some(t1 - t0)).unwrap_or_else(|| speed_of(&None));
                    let f = self.feed_word(speed);
                    self.line(&format!("G1 {}{f}", axis_words(&PoseMm::from_isometry(&goal), self.options.abc)));
                    self.pose = goal;
                }
            }
            Step::MoveC { via_mm, pose, speed_mm_s } => {
                let goal = checked(pose)?;
                let (a, c) = (Point3::from(self.pose.translation.vector), Point3::from(goal.translation.vector));
                let via = Point3::from(Vector3::from(*via_mm) / 1000.0);
                let (centre, normal) =
                    circle_through(&a, &via, &c).ok_or("the start, via and end points lie on one line")?;
                let speed = speed_of(speed_mm_s);
                match principal(&normal) {
                    Some((plane, ccw)) => self.arc(plane, ccw, &centre, &goal, speed),
                    None => {
                        let path = TcpPath::arc_through(&self.pose, &via, &goal).map_err(|e| e.to_string())?;
                        self.sampled(&path, speed, "an arc outside the XY, ZX and YZ planes");
                    }
                }
                self.pose = goal;
            }
            Step::MoveCircle { center_mm, normal, angle_deg, speed_mm_s } => {
                let centre = Point3::from(Vector3::from(*center_mm) / 1000.0);
                let n = Vector3::from(*normal);
                let path =
                    TcpPath::arc_about(&self.pose, &centre, &n, angle_deg.to_radians()).map_err(|e| e.to_string())?;
                let end = path.pose(path.parameter_length_m());
                let speed = speed_of(speed_mm_s);
                match principal(&n) {
                    Some((plane, positive)) => {
                        // the centre in the start's plane
                        let start = Point3::from(self.pose.translation.vector);
                        let axis = n.normalize();
                        let centre = centre + axis * (start - centre).dot(&axis);
                        let ccw = positive == (*angle_deg > 0.0);
                        let end = Isometry3::from_parts(Translation3::from(end.translation.vector), self.pose.rotation);
                        self.arc(plane, ccw, &centre, &end, speed);
                    }
                    None => self.sampled(&path, speed, "an arc outside the XY, ZX and YZ planes"),
                }
                self.pose = end;
            }
            Step::Spline { waypoints, speed_mm_s } => {
                let mut pts = vec![self.pose];
                for p in waypoints {
                    pts.push(checked(p)?);
                }
                let path = TcpPath::spline(&pts).map_err(|e| e.to_string())?;
                self.sampled(&path, speed_of(speed_mm_s), "a spline");
                self.pose = pts[pts.len() - 1];
            }
            Step::Dwell { seconds } => {
                if !seconds.is_finite() || *seconds < 0.0 {
                    return Err(format!("the dwell {seconds} s is not a time"));
                }
                self.line(&format!("G4 P{}", format_number(seconds * 1000.0)));
            }
            Step::Gripper { action, position, speed, current_ma } => {
                if self.options.gripper != GcodeGripper::Electric {
                    return Err("a gripper step drives the electric gripper, but this program's tool is not one, so \
                                M3/M5 would drive the pneumatic gripper's valve: set the program's tool to the SSG-48 \
                                or the MSG (\"tool\": \"Ssg48\" or \"Msg\" in its JSON file) to write them for the \
                                electric gripper, or use set_output steps for the valve"
                        .into());
                }
                if speed.is_some() || current_ma.is_some() {
                    return Err("a gripper speed or current has no G-code equivalent".into());
                }
                match action {
                    GripperAction::Open => self.line("M5"),
                    GripperAction::Close => self.line("M3"),
                    GripperAction::Position => {
                        return Err(format!(
                            "a gripper position ({}) has no G-code equivalent (only open M5 and close M3)",
                            position.map_or("none".into(), |p| p.to_string())
                        ));
                    }
                }
            }
            Step::SetOutput { output, on } => {
                if self.options.gripper != GcodeGripper::Pneumatic {
                    return Err("a digital output has no G-code word when M3/M5 drive the electric gripper".into());
                }
                if !(1..=2).contains(output) {
                    return Err(format!("output {output} has no G-code word (M3/M5 drive outputs 1 and 2)"));
                }
                // the pneumatic gripper opens (M5) with its output high
                self.line(&format!("{} P{output}", if *on { "M5" } else { "M3" }));
            }
            Step::WaitInput { .. } => {
                return Err("waiting for an input has no G-code equivalent in this dialect".into());
            }
            Step::Pause { optional } => self.line(if *optional { "M1" } else { "M0" }),
        }
        Ok(())
    }

    /// `G2`/`G3` from where the TCP is to `goal` about `centre` (in `plane` through the start).
    fn arc(&mut self, plane: Plane, ccw: bool, centre: &Point3<f64>, goal: &Isometry3<f64>, speed_mm_s: f64) {
        if plane != self.plane {
            self.line(plane.code());
            self.plane = plane;
        }
        let start = self.pose.translation.vector * 1000.0;
        let offset = centre.coords * 1000.0 - start;
        let (a, b, _) = plane.axes();
        let mut words = String::new();
        for k in [a.min(b), a.max(b)] {
            words.push_str(&format!(" {}{}", ['I', 'J', 'K'][k], format_number(offset[k])));
        }
        let f = self.feed_word(speed_mm_s);
        let goal_pose = PoseMm::from_isometry(goal);
        let axes = if (goal.translation.vector * 1000.0 - start).norm() < FULL_CIRCLE_MM {
            // a full circle keeps the orientation: its end written as X Y Z only, so that a
            // reader whose A B C are not yet set (0) reads the same circle
            lettered("XYZ", &goal_pose.position_mm)
        } else {
            axis_words(&goal_pose, self.options.abc)
        };
        let text = format!("{} {axes}{words}{f}", if ccw { "G3" } else { "G2" });
        self.line(&text);
    }

    /// `G1` lines along `path` within the tolerance.
    fn sampled(&mut self, path: &TcpPath, speed_mm_s: f64, what: &str) {
        let tol = self.options.tolerance;
        let step_m = (tol.position_mm.min(0.5) / 1000.0).max(1e-5);
        let n = ((path.parameter_length_m() / step_m).ceil() as usize).clamp(8, 200_000);
        let poses: Vec<Isometry3<f64>> =
            (0..=n).map(|k| path.pose(path.parameter_length_m() * k as f64 / n as f64)).collect();
        let kept = simplify(&poses, &tol);
        self.line(&format!(
            "; {what}: {} lines within {} mm and {} deg",
            kept.len() - 1,
            format_number(tol.position_mm),
            format_number(tol.orientation_deg)
        ));
        for k in kept.into_iter().skip(1) {
            let f = self.feed_word(speed_mm_s);
            let text = format!("G1 {}{f}", axis_words(&PoseMm::from_isometry(&poses[k]), self.options.abc));
            self.line(&text);
        }
    }
}

fn checked(p: &PoseMm) -> Result<Isometry3<f64>, String> {
    if p.position_mm.iter().chain(&p.rpy_deg).all(|v| v.is_finite()) {
        Ok(p.isometry())
    } else {
        Err("the pose is not finite numbers".into())
    }
}

/// The G-code plane whose normal is parallel to `normal`, and whether `normal` points along
/// the plane's positive normal.
fn principal(normal: &Vector3<f64>) -> Option<(Plane, bool)> {
    let n = normal.try_normalize(1e-12)?;
    Plane::ALL.into_iter().find_map(|p| {
        let d = n.dot(&Vector3::from(p.normal()));
        (d.abs() > 1.0 - 1e-9).then_some((p, d > 0.0))
    })
}

/// The TCP speed (mm/s) that covers `from` → `to` in `duration_s`, within the dialect's feed
/// range (2–200 mm/s); `None` without a duration or for a move that does not travel.
fn timed_speed(from: &Isometry3<f64>, to: &Isometry3<f64>, duration_s: Option<f64>) -> Option<f64> {
    let d = duration_s.filter(|d| d.is_finite() && *d > 0.0)?;
    let mm = (to.translation.vector - from.translation.vector).norm() * 1000.0;
    (mm > 1e-9).then(|| (mm / d).clamp(2.0, 200.0))
}
