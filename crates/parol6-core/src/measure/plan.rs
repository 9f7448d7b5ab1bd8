//! The programs a measurement runs, and their pre-flight: the pose test moves to each test pose
//! of the cube in the ISO cycle order (P1 → P5 → P4 → P3 → P2) with joint moves; the path tests
//! trace a line (P2 → P4), a circle (centre P1, diameter 80 % of the edge) or a right-angled
//! triangle (legs 80 % of the edge along the plane's axes) in the cube's diagonal plane. The
//! triangle is given as the LabVIEW GUI gave it: a time function of three pieces, x/y/z(t)
//! linear in t on each leg at the test speed ([`Step::TimeFunction`]).
//!
//! A cube that cannot be reached from where the arm is is refused before anything moves, and
//! the refusal names the pose.

use serde::{Deserialize, Serialize};

use super::cube::{CYCLE_ORDER, CubeError, POSE_NAMES, TestCube};
use crate::model::RobotModel;
use crate::program::check::{CheckOptions, check_program};
use crate::program::compile::MAX_TCP_SPEED_MM_S;
use crate::program::timefn::TimePiece;
use crate::program::{PoseMm, Program, Step};

/// The path of a path test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PathKind {
    /// Straight line P2 → P4.
    Line,
    /// Full circle in the diagonal plane about P1.
    Circle,
    /// Right-angled triangle in the diagonal plane (the LabVIEW GUI's test path).
    Triangle,
}

impl PathKind {
    /// Every path.
    pub const ALL: [PathKind; 3] = [PathKind::Line, PathKind::Circle, PathKind::Triangle];

    /// Name as typed on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PathKind::Line => "line",
            PathKind::Circle => "circle",
            PathKind::Triangle => "triangle",
        }
    }
}

/// Why a test cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// The cube itself is invalid.
    #[error(transparent)]
    Cube(#[from] CubeError),
    /// A bad setting.
    #[error("{0}")]
    Setting(String),
    /// Pre-flight refused a pose or path (out of reach, a limit, a speed cap, a collision):
    /// what, and why.
    #[error("pre-flight refuses {what}: {why}")]
    Refused {
        /// "P3 at (x, y, z) mm" or "the circle path".
        what: String,
        /// The pre-flight's reason.
        why: String,
    },
}

/// The pose test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseTestPlan {
    /// The cube.
    pub cube: TestCube,
    /// Number of cycles (2…1000; ISO: 30).
    pub cycles: usize,
    /// Fraction of the joint speed caps (0.01…1).
    pub speed_fraction: f64,
    /// Time the arm rests at a pose before the attained pose is read, s of motion clock.
    pub settle_s: f64,
}

/// The pose test's default cycle count (ISO 9283).
pub const DEFAULT_CYCLES: usize = 30;
/// The most cycles a test may ask for.
pub const MAX_CYCLES: usize = 1000;

fn check_common(cube: &TestCube, cycles: usize, speed_fraction: f64) -> Result<(), PlanError> {
    cube.validate()?;
    if !(2..=MAX_CYCLES).contains(&cycles) {
        return Err(PlanError::Setting(format!("cycles must be 2…{MAX_CYCLES}, got {cycles}")));
    }
    if !(speed_fraction.is_finite() && (0.01..=1.0).contains(&speed_fraction)) {
        return Err(PlanError::Setting(format!("speed must be 0.01…1, got {speed_fraction}")));
    }
    Ok(())
}

fn describe(pose: &PoseMm, name: &str) -> String {
    let p = pose.position_mm;
    format!("{name} at ({:.1}, {:.1}, {:.1}) mm", p[0], p[1], p[2])
}

impl PoseTestPlan {
    /// The plan with ISO defaults: 30 cycles, half speed, 0.3 s settling.
    pub fn new(cube: TestCube) -> Self {
        Self { cube, cycles: DEFAULT_CYCLES, speed_fraction: 0.5, settle_s: 0.3 }
    }

    /// The move to test pose `pose` (0 = P1).
    pub fn move_to(&self, pose: usize) -> Program {
        let target = self.cube.poses()[pose];
        Program::from_steps(
            POSE_NAMES[pose],
            vec![Step::MovePose {
                pose: target,
                config: None,
                speed_fraction: Some(self.speed_fraction),
                duration_s: None,
            }],
        )
    }

    /// The poses the pre-flight visits: P2 (where every cycle's P1 is approached from), then
    /// one cycle P1, P5, P4, P3, P2.
    pub const VISITS: [usize; 6] = [1, CYCLE_ORDER[0], CYCLE_ORDER[1], CYCLE_ORDER[2], CYCLE_ORDER[3], CYCLE_ORDER[4]];

    /// The approach (to P2) and one cycle as one program, for pre-flight.
    pub fn cycle_program(&self) -> Program {
        let poses = self.cube.poses();
        let steps = Self::VISITS
            .iter()
            .map(|&i| Step::MovePose {
                pose: poses[i],
                config: None,
                speed_fraction: Some(self.speed_fraction),
                duration_s: None,
            })
            .collect();
        Program::from_steps("ISO 9283 pose cycle", steps)
    }

    /// Checks the settings and pre-flights one cycle from joints `start_q`; the error names
    /// the first pose that cannot be reached.
    pub fn preflight(&self, model: &RobotModel, start_q: &[f64]) -> Result<(), PlanError> {
        check_common(&self.cube, self.cycles, self.speed_fraction)?;
        if !(self.settle_s.is_finite() && (0.0..=10.0).contains(&self.settle_s)) {
            return Err(PlanError::Setting(format!("settle time must be 0…10 s, got {}", self.settle_s)));
        }
        let report = check_program(model, &self.cycle_program(), start_q, CheckOptions::default());
        match report.issues.iter().find(|i| i.severity == crate::program::check::Severity::Error) {
            None => Ok(()),
            Some(issue) => {
                let pose = Self::VISITS[issue.move_index.min(5)];
                Err(PlanError::Refused {
                    what: describe(&self.cube.poses()[pose], POSE_NAMES[pose]),
                    why: issue.message.clone(),
                })
            }
        }
    }
}

/// A path test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathTestPlan {
    /// The cube.
    pub cube: TestCube,
    /// Which path.
    pub kind: PathKind,
    /// Number of cycles (2…1000; ISO: 10).
    pub cycles: usize,
    /// Fraction of the rated TCP speed (200 mm/s) along the path, and of the joint caps for
    /// the approach (0.01…1).
    pub speed_fraction: f64,
    /// Number of points along the path for AT_p / RT_p.
    pub points: usize,
}

/// The path tests' default cycle count (ISO 9283).
pub const DEFAULT_PATH_CYCLES: usize = 10;

impl PathTestPlan {
    /// The plan with ISO defaults: 10 cycles, half speed, 50 points.
    pub fn new(cube: TestCube, kind: PathKind) -> Self {
        Self { cube, kind, cycles: DEFAULT_PATH_CYCLES, speed_fraction: 0.5, points: 50 }
    }

    /// TCP speed along the path, mm/s.
    pub fn tcp_speed_mm_s(&self) -> f64 {
        (self.speed_fraction * MAX_TCP_SPEED_MM_S).max(crate::program::compile::MIN_TCP_SPEED_MM_S)
    }

    fn pose_at(&self, position_mm: [f64; 3]) -> PoseMm {
        PoseMm { position_mm, rpy_deg: self.cube.orientation_rpy_deg }
    }

    /// The corners of the path in order (the line's ends; the circle's start; the
    /// triangle's vertices, the right angle first), mm.
    pub fn corners_mm(&self) -> Vec<[f64; 3]> {
        let e = self.cube.edge_mm;
        match self.kind {
            PathKind::Line => {
                let p = self.cube.pose_positions_mm();
                vec![p[1], p[3]]
            }
            PathKind::Circle => vec![self.cube.plane_point_mm(0.4 * e, 0.0)],
            PathKind::Triangle => {
                let s = 0.4 * e;
                vec![self.cube.plane_point_mm(-s, -s), self.cube.plane_point_mm(s, -s), self.cube.plane_point_mm(-s, s)]
            }
        }
    }

    /// The commanded path's vertices in order, mm: the line's two ends, the triangle's three
    /// vertices and back to the first (its corners are the inner ones); none for the circle.
    pub fn legs_mm(&self) -> Vec<[f64; 3]> {
        let mut c = self.corners_mm();
        match self.kind {
            PathKind::Line => c,
            PathKind::Circle => Vec::new(),
            PathKind::Triangle => {
                c.push(c[0]);
                c
            }
        }
    }

    /// Where every cycle starts.
    pub fn start(&self) -> PoseMm {
        self.pose_at(self.corners_mm()[0])
    }

    /// Brings the arm to the start, approaching it as every cycle will.
    pub fn approach(&self) -> Program {
        let joint = |pose: PoseMm| Step::MovePose {
            pose,
            config: None,
            speed_fraction: Some(self.speed_fraction),
            duration_s: None,
        };
        let mut steps = Vec::new();
        if let Some(end) = self.return_from_end() {
            // the line comes back to P2 from P4 every cycle: come from there the first time too
            steps.push(joint(self.pose_at(self.corners_mm()[1])));
            steps.push(end);
        } else {
            steps.push(joint(self.start()));
        }
        Program::from_steps(format!("{} approach", self.kind.name()), steps)
    }

    /// The measured part of one cycle, from the start.
    pub fn cycle(&self) -> Program {
        let v = Some(self.tcp_speed_mm_s());
        let line = |p: [f64; 3]| Step::MoveL { pose: self.pose_at(p), speed_mm_s: v, blend_mm: None, duration_s: None };
        let c = self.corners_mm();
        let steps = match self.kind {
            PathKind::Line => vec![line(c[1])],
            PathKind::Circle => {
                let [_, _, n] = TestCube::plane_axes();
                vec![Step::MoveCircle {
                    center_mm: self.cube.center_mm,
                    normal: n.into(),
                    angle_deg: 360.0,
                    speed_mm_s: v,
                }]
            }
            PathKind::Triangle => vec![triangle_function(&[c[0], c[1], c[2]], self.tcp_speed_mm_s())],
        };
        Program::from_steps(format!("{} path", self.kind.name()), steps)
    }

    /// The unmeasured move back to the start after a cycle, for paths that do not end there.
    pub fn return_from_end(&self) -> Option<Step> {
        (self.kind == PathKind::Line).then(|| Step::MoveL {
            pose: self.start(),
            speed_mm_s: Some(self.tcp_speed_mm_s()),
            blend_mm: None,
            duration_s: None,
        })
    }

    /// The whole test as one program (approach, then every cycle), for pre-flight.
    pub fn whole_cycle(&self) -> Program {
        let mut p = self.approach();
        p.steps.extend(self.cycle().steps);
        if let Some(back) = self.return_from_end() {
            p.steps.push(crate::program::SourcedStep { step: back, line: 0 });
        }
        p
    }

    /// Checks the settings and pre-flights the approach and one cycle from `start_q`.
    pub fn preflight(&self, model: &RobotModel, start_q: &[f64]) -> Result<(), PlanError> {
        check_common(&self.cube, self.cycles, self.speed_fraction)?;
        if !(2..=1000).contains(&self.points) {
            return Err(PlanError::Setting(format!("points along the path must be 2…1000, got {}", self.points)));
        }
        let program = self.whole_cycle();
        let report = check_program(model, &program, start_q, CheckOptions::default());
        match report.issues.iter().find(|i| i.severity == crate::program::check::Severity::Error) {
            None => Ok(()),
            Some(issue) => {
                let what = match &program.steps.get(issue.move_index).map(|s| &s.step) {
                    Some(Step::MovePose { pose, .. } | Step::MoveL { pose, .. }) => {
                        describe(pose, &format!("the {} path's corner", self.kind.name()))
                    }
                    _ => format!("the {} path", self.kind.name()),
                };
                Err(PlanError::Refused { what, why: issue.message.clone() })
            }
        }
    }
}

#[cfg(test)]
mod tests;

/// Sample rate of the triangle's time function, Hz.
pub const TRIANGLE_SAMPLE_RATE_HZ: f64 = 100.0;

/// The right-angled triangle through `corners_mm` (and back to the first) as a time function:
/// one piece per leg, each coordinate linear in the piece's time `t` at `speed_mm_s`.
pub fn triangle_function(corners_mm: &[[f64; 3]; 3], speed_mm_s: f64) -> Step {
    let leg = |a: [f64; 3], b: [f64; 3]| {
        let d: f64 = (0..3).map(|k| (b[k] - a[k]).powi(2)).sum::<f64>().sqrt();
        let t_s = (d / speed_mm_s.max(1e-3)).max(0.01);
        let axis = |k: usize| format!("({:.6}) + ({:.6}) * t / {:.6}", a[k], b[k] - a[k], t_s);
        TimePiece::position(t_s, &axis(0), &axis(1), &axis(2))
    };
    let [p0, p1, p2] = *corners_mm;
    Step::TimeFunction { sample_rate_hz: TRIANGLE_SAMPLE_RATE_HZ, pieces: vec![leg(p0, p1), leg(p1, p2), leg(p2, p0)] }
}
