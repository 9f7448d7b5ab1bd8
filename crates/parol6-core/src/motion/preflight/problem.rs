//! Problems as found at one instant (cheap, `Copy`, link and shape by index) and the rule that
//! collapses consecutive occurrences of the same problem in a move into one issue.

use super::report::{CheckStatus, IssueKind, Severity};

/// A problem at one instant. Joints / motors 0-based, links by index into the model's links,
/// keep-out shapes by index into the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Problem {
    JointLimit(usize),
    JointSpeed(usize),
    MotorSpeed(usize),
    Singularity,
    SelfCollision(usize, usize),
    KeepOut(usize, usize),
    Ground(usize),
    InvalidTrajectory,
    Discontinuity(usize),
}

impl Problem {
    /// The serialisable kind, with names.
    pub(super) fn kind(self, link_names: &[String], keep_out_names: &[String]) -> IssueKind {
        let link = |l: usize| link_names.get(l).cloned().unwrap_or_else(|| format!("link {l}"));
        match self {
            Problem::JointLimit(j) => IssueKind::JointLimit { joint: j + 1 },
            Problem::JointSpeed(j) => IssueKind::JointSpeed { joint: j + 1 },
            Problem::MotorSpeed(m) => IssueKind::MotorSpeed { motor: m + 1 },
            Problem::Singularity => IssueKind::Singularity,
            Problem::SelfCollision(a, b) => IssueKind::SelfCollision { a: link(a), b: link(b) },
            Problem::KeepOut(l, k) => IssueKind::KeepOut {
                link: link(l),
                shape: keep_out_names.get(k).cloned().unwrap_or_else(|| format!("keep-out {k}")),
            },
            Problem::Ground(l) => IssueKind::Ground { link: link(l) },
            Problem::InvalidTrajectory => IssueKind::InvalidTrajectory,
            Problem::Discontinuity(j) => IssueKind::Discontinuity { joint: j + 1 },
        }
    }
}

/// The problems of one check category (per-sample limits, singularity, collision) at its
/// previous and current evaluation. A problem becomes an issue only when it was not active
/// at the previous evaluation of its category in the same move.
#[derive(Debug, Default)]
pub(super) struct Tracker {
    prev: Vec<(Problem, Severity)>,
    cur: Vec<(Problem, Severity)>,
}

impl Tracker {
    /// Forgets everything (a new move).
    pub(super) fn reset(&mut self) {
        self.prev.clear();
        self.cur.clear();
    }

    /// Starts an evaluation.
    pub(super) fn begin(&mut self) {
        self.cur.clear();
    }

    /// Notes a problem of this evaluation; true when it is new (becomes an issue).
    pub(super) fn note(&mut self, p: Problem, s: Severity) -> bool {
        if self.cur.contains(&(p, s)) {
            return false;
        }
        self.cur.push((p, s));
        !self.prev.contains(&(p, s))
    }

    /// Ends an evaluation.
    pub(super) fn end(&mut self) {
        std::mem::swap(&mut self.prev, &mut self.cur);
    }

    /// Worst severity of the last finished evaluation.
    pub(super) fn status(&self) -> CheckStatus {
        self.prev.iter().map(|&(_, s)| CheckStatus::from(s)).max().unwrap_or(CheckStatus::Ok)
    }

    /// True when any problem of the last finished evaluation is a contact.
    pub(super) fn any(&self) -> bool {
        !self.prev.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consecutive_occurrences_collapse() {
        let mut t = Tracker::default();
        t.begin();
        assert!(t.note(Problem::JointSpeed(1), Severity::Error));
        assert!(!t.note(Problem::JointSpeed(1), Severity::Error), "twice in one evaluation");
        t.end();
        assert_eq!(t.status(), CheckStatus::Error);
        t.begin();
        assert!(!t.note(Problem::JointSpeed(1), Severity::Error), "still active");
        t.end();
        t.begin();
        t.end();
        assert_eq!(t.status(), CheckStatus::Ok);
        t.begin();
        assert!(t.note(Problem::JointSpeed(1), Severity::Error), "a new occurrence");
        t.end();
    }
}
