//! What pre-flight validation hands back: the issues found (each naming the move, the source
//! line, the joint / link / shape and where along the move), the predicted duration, and the
//! TCP path coloured by status for the 3D view.

use serde::{Deserialize, Serialize};

/// How bad an issue is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Runs, but worth a look (close to a singularity).
    Warning,
    /// Must not run (a limit, a speed or a collision).
    Error,
}

/// Status of a point of the checked TCP path (green / amber / red in the 3D view).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CheckStatus {
    /// No issue.
    Ok,
    /// A warning is active here.
    Warning,
    /// An error is active here.
    Error,
}

impl From<Severity> for CheckStatus {
    fn from(s: Severity) -> Self {
        match s {
            Severity::Warning => CheckStatus::Warning,
            Severity::Error => CheckStatus::Error,
        }
    }
}

/// What an issue is about. Joints and motors are 1-based (J1 = 1), links by URDF name.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum IssueKind {
    /// A joint beyond its position limit.
    JointLimit {
        /// 1-based joint.
        joint: usize,
    },
    /// A joint faster than its speed cap.
    JointSpeed {
        /// 1-based joint.
        joint: usize,
    },
    /// A motor faster than its step rate (PAROL6: motor 6 turns with J4 and J6).
    MotorSpeed {
        /// 1-based motor.
        motor: usize,
    },
    /// Close to a singular pose (manipulability below the thresholds of `singularity`).
    Singularity,
    /// Two links of the robot touch.
    SelfCollision {
        /// First link.
        a: String,
        /// Second link.
        b: String,
    },
    /// A link enters a keep-out shape.
    KeepOut {
        /// The link.
        link: String,
        /// The keep-out shape's name.
        shape: String,
    },
    /// A link goes below the floor (z = 0).
    Ground {
        /// The link.
        link: String,
    },
    /// A TCP pose of the move has no IK solution (reported by the program compiler).
    Unreachable,
    /// The move's samples cannot be checked: wrong number of joints, a value that is not
    /// finite, no samples, or a bad sample period.
    InvalidTrajectory,
    /// The move does not start where the previous one ends.
    Discontinuity {
        /// 1-based joint with the largest jump.
        joint: usize,
    },
}

/// One problem found before running.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PreflightIssue {
    /// 0-based move index in the program.
    pub move_index: usize,
    /// 1-based line of the program source.
    pub line: usize,
    /// Warning or error.
    pub severity: Severity,
    /// What it is about.
    pub kind: IssueKind,
    /// Time along the move where it first occurs, s.
    pub t_s: f64,
    /// TCP position there, mm (world frame). Zeros when the joint values are unusable.
    pub tcp_mm: [f64; 3],
    /// The whole story: move, joint or links, where.
    pub message: String,
}

impl PreflightIssue {
    /// An unreachable TCP pose found while compiling a move (the IK error in `reason`), for
    /// the program compiler to merge into the report.
    pub fn unreachable(move_index: usize, line: usize, label: &str, t_s: f64, tcp_mm: [f64; 3], reason: &str) -> Self {
        Self {
            move_index,
            line,
            severity: Severity::Error,
            kind: IssueKind::Unreachable,
            t_s,
            tcp_mm,
            message: format!(
                "line {line}, move {move_index} ({label}): TCP ({:.1}, {:.1}, {:.1}) mm at t = {t_s:.3} s is unreachable: {reason}",
                tcp_mm[0], tcp_mm[1], tcp_mm[2]
            ),
        }
    }
}

/// One point of the checked TCP path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CheckedPoint {
    /// 0-based move index.
    pub move_index: usize,
    /// Time along that move, s.
    pub t_s: f64,
    /// TCP position, m (world frame).
    pub tcp_m: [f64; 3],
    /// Worst issue active between the previous point and this one.
    pub status: CheckStatus,
}

/// The result of checking a program.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PreflightReport {
    /// Problems, in move order, then time.
    pub issues: Vec<PreflightIssue>,
    /// Predicted duration: the sum of the moves' durations, s.
    pub duration_s: f64,
    /// Number of moves checked.
    pub moves: usize,
    /// The TCP path, decimated (see the module docs), coloured by status.
    pub path: Vec<CheckedPoint>,
}

impl PreflightReport {
    /// True when no issue is an error (warnings allowed): the program may run.
    pub fn ok(&self) -> bool {
        !self.issues.iter().any(|i| i.severity == Severity::Error)
    }

    /// Number of errors.
    pub fn errors(&self) -> usize {
        self.issues.iter().filter(|i| i.severity == Severity::Error).count()
    }

    /// Number of warnings.
    pub fn warnings(&self) -> usize {
        self.issues.iter().filter(|i| i.severity == Severity::Warning).count()
    }

    /// Adds issues found elsewhere (e.g. [`PreflightIssue::unreachable`] from compiling),
    /// keeping move / time order.
    pub fn merge_issues(&mut self, issues: impl IntoIterator<Item = PreflightIssue>) {
        self.issues.extend(issues);
        self.issues.sort_by(|a, b| a.move_index.cmp(&b.move_index).then(a.t_s.total_cmp(&b.t_s)));
    }
}
