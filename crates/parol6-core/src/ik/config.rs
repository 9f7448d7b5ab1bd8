//! Arm configurations: which closed-form branch a pose is reached in, as a robot user names
//! it, and the rules moves follow.
//!
//! - A **joint move to a pose** (native `move_pose`, G-code `G0`, commander `MovePose`, the
//!   window's *Move to target*, ISO 9283 and calibration poses) takes the solution within the
//!   limits nearest the start joints, in any configuration ([`ConfigRule::ANY`]), unless the
//!   step names one ([`ConfigRule::exactly`]). This is what the official PAROL6 API does: it
//!   seeds its IK with the current joints.
//! - A **Cartesian move** (line, arc, spline, tool-frame move, Cartesian jog) keeps the
//!   configuration of its start ([`ConfigRule::of_start`]). Where the start lies on the border
//!   between two configurations (J5 = 0: the wrist is singular, standby is such a pose) the
//!   part on the border is free until the path leaves it, and is then kept.
//!
//! Distances are Euclidean in joint space (rad), J6's extra turn included: every joint value
//! is wrapped by whole turns into its limits nearest the seed.

use std::fmt;
use std::str::FromStr;

use nalgebra::Isometry3;

use super::{Branch, ElbowBranch, IkError, IkSolution, NumericIkOptions, ShoulderBranch, WristBranch};
use crate::model::RobotModel;

/// |J5| below this (rad) is the border between the wrist configurations: both count.
pub const WRIST_BORDER_RAD: f64 = 1e-6;

/// Which configurations a solution may be in: each part of the branch fixed, or free.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ConfigRule {
    /// Shoulder front / back, or free.
    pub shoulder: Option<ShoulderBranch>,
    /// Elbow up / down, or free.
    pub elbow: Option<ElbowBranch>,
    /// Wrist no-flip / flip, or free.
    pub wrist: Option<WristBranch>,
}

impl ConfigRule {
    /// Any configuration: the nearest solution wins.
    pub const ANY: Self = Self { shoulder: None, elbow: None, wrist: None };

    /// Exactly this configuration.
    pub fn exactly(branch: Branch) -> Self {
        Self { shoulder: Some(branch.shoulder), elbow: Some(branch.elbow), wrist: Some(branch.wrist) }
    }

    /// The configuration of the joints `q` (PAROL6 closed form), with the wrist left free where
    /// `q` lies on the wrist border; [`ConfigRule::ANY`] for other robots.
    pub fn of_start(model: &RobotModel, q: &[f64]) -> Self {
        match configuration_of(model, q) {
            Some(b) => {
                let mut rule = Self::exactly(b);
                if on_wrist_border(q) {
                    rule.wrist = None;
                }
                rule
            }
            None => Self::ANY,
        }
    }

    /// True when every part is fixed.
    pub fn is_fixed(&self) -> bool {
        self.shoulder.is_some() && self.elbow.is_some() && self.wrist.is_some()
    }

    /// True when `sol` is in a configuration this rule allows (a solution on the wrist border
    /// is in both wrist configurations).
    pub fn admits(&self, sol: &IkSolution) -> bool {
        sol.branch.is_none_or(|b| self.admits_branch(b, &sol.joints_rad))
    }

    /// True when joints `q` in branch `b` are in a configuration this rule allows
    /// ([`ConfigRule::admits`]).
    fn admits_branch(&self, b: Branch, q: &[f64]) -> bool {
        self.shoulder.is_none_or(|s| s == b.shoulder)
            && self.elbow.is_none_or(|e| e == b.elbow)
            && (self.wrist.is_none_or(|w| w == b.wrist) || on_wrist_border(q))
    }

    /// This rule with its free parts fixed by the solution `sol` where it is off their border
    /// (a Cartesian move that leaves the wrist border keeps the wrist it left it in).
    pub fn settled_by(self, sol: &IkSolution) -> Self {
        if self.is_fixed() || on_wrist_border(&sol.joints_rad) {
            return self;
        }
        match sol.branch {
            Some(b) => Self {
                shoulder: self.shoulder.or(Some(b.shoulder)),
                elbow: self.elbow.or(Some(b.elbow)),
                wrist: self.wrist.or(Some(b.wrist)),
            },
            None => self,
        }
    }

    /// The branch when every part is fixed.
    pub fn branch(&self) -> Option<Branch> {
        Some(Branch { shoulder: self.shoulder?, elbow: self.elbow?, wrist: self.wrist? })
    }
}

impl fmt::Display for ConfigRule {
    /// `front/up/no-flip`, with `any` for a free part (`any` alone when all are free).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if *self == Self::ANY {
            return f.write_str("any");
        }
        let s = self.shoulder.map_or("any", |s| if s == ShoulderBranch::Front { "front" } else { "back" });
        let e = self.elbow.map_or("any", |e| if e == ElbowBranch::Up { "up" } else { "down" });
        let w = self.wrist.map_or("any", |w| if w == WristBranch::NoFlip { "no-flip" } else { "flip" });
        write!(f, "{s}/{e}/{w}")
    }
}

/// Why a configuration label does not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "\"{0}\" is not a configuration: write shoulder/elbow/wrist, e.g. front/up/no-flip \
     (shoulder front|back, elbow up|down, wrist no-flip|flip)"
)]
pub struct ConfigParseError(pub String);

impl FromStr for Branch {
    type Err = ConfigParseError;

    /// Parses a label as [`Branch::label`] writes it (`front/up/no-flip`; case and blanks
    /// around the parts ignored).
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let err = || ConfigParseError(text.to_string());
        let parts: Vec<String> = text.split('/').map(|p| p.trim().to_ascii_lowercase()).collect();
        let [s, e, w] = parts.as_slice() else {
            return Err(err());
        };
        let shoulder = match s.as_str() {
            "front" => ShoulderBranch::Front,
            "back" => ShoulderBranch::Back,
            _ => return Err(err()),
        };
        let elbow = match e.as_str() {
            "up" => ElbowBranch::Up,
            "down" => ElbowBranch::Down,
            _ => return Err(err()),
        };
        let wrist = match w.as_str() {
            "no-flip" | "noflip" => WristBranch::NoFlip,
            "flip" => WristBranch::Flip,
            _ => return Err(err()),
        };
        Ok(Branch { shoulder, elbow, wrist })
    }
}

/// True when J5 of `q` lies on the border between the wrist configurations.
pub fn on_wrist_border(q: &[f64]) -> bool {
    q.get(4).is_some_and(|q5| q5.abs() < WRIST_BORDER_RAD)
}

/// A solution this close to the joints (rad, Euclidean) reproduces them.
const SAME_JOINTS_RAD: f64 = 1e-6;

/// The configuration the joints `q` are in (PAROL6 closed form; `None` for other robots or
/// joints the closed form does not reproduce).
///
/// Every Cartesian move asks this of its start, so it first solves one configuration, the
/// one found last on this thread, then the others one by one, and
/// solves all eight together only where that cannot decide: the answer is the same.
pub fn configuration_of(model: &RobotModel, q: &[f64]) -> Option<Branch> {
    if !model.is_parol6 {
        return None;
    }
    let pose = model.tcp_isometry(q);
    if let Some(found) = configuration_by_one(model, &pose, q) {
        return found;
    }
    let sols = super::solve_parol6(model, &pose, q).ok()?;
    sols.into_iter().find(|s| s.distance_to_seed < SAME_JOINTS_RAD).and_then(|s| s.branch)
}

thread_local! {
    /// The configuration [`configuration_by_one`] found last: consecutive moves of a program
    /// are mostly in one configuration. Only the order of the tries; never the answer.
    static LAST_CONFIGURATION: std::cell::Cell<Option<Branch>> = const { std::cell::Cell::new(None) };
}

/// The configuration of `q` (whose TCP is at `pose`) found by solving one configuration at a
/// time, or `None` when this cannot decide and all eight must be solved together
/// ([`super::solve_parol6`] then sorts them by distance to `q`).
///
/// It decides only where exactly one solution reproduces `q`. Solutions of two shoulder or two
/// wrist configurations differ by π in J1 or J4 (the closed form gives the shoulder and the
/// wrist only one solution where they are singular), so they cannot both lie within
/// [`SAME_JOINTS_RAD`]; the two elbows meet at full stretch and full fold, so the other
/// elbow of a match is solved too, and if it matches as well, all eight are solved.
fn configuration_by_one(model: &RobotModel, pose: &Isometry3<f64>, q: &[f64]) -> Option<Option<Branch>> {
    // the nearest solution of the branch, when it reproduces `q` (what the sorted list's first
    // entry was), without building the list
    let matching = |branch: Branch| -> Option<Branch> {
        let nearest = super::closed_form::nearest_parol6_in(model, pose, q, Some(branch), |_, _| true).ok()??;
        (nearest.distance_to_seed < SAME_JOINTS_RAD).then_some(nearest.branch).flatten()
    };
    let wrist_of_q = if q.get(4).is_some_and(|q5| *q5 < 0.0) { WristBranch::Flip } else { WristBranch::NoFlip };
    let mut tries: Vec<Branch> = Vec::with_capacity(9);
    if let Some(last) = LAST_CONFIGURATION.with(std::cell::Cell::get) {
        tries.push(last);
    }
    for wrist in [wrist_of_q, if wrist_of_q == WristBranch::Flip { WristBranch::NoFlip } else { WristBranch::Flip }] {
        for shoulder in [ShoulderBranch::Front, ShoulderBranch::Back] {
            for elbow in [ElbowBranch::Up, ElbowBranch::Down] {
                let b = Branch { shoulder, elbow, wrist };
                if !tries.contains(&b) {
                    tries.push(b);
                }
            }
        }
    }
    for b in tries {
        let Some(found) = matching(b) else { continue };
        let other_elbow = if found.elbow == ElbowBranch::Up { ElbowBranch::Down } else { ElbowBranch::Up };
        if matching(Branch { elbow: other_elbow, ..found }).is_some() {
            return None;
        }
        LAST_CONFIGURATION.with(|c| c.set(Some(found)));
        return Some(Some(found));
    }
    None
}

/// The IK solution within the limits nearest `seed` among those `rule` admits.
///
/// PAROL6: the closed form (every branch, or only the fixed one). Other robots: the numeric
/// solver from the seed (a rule that fixes a part is refused there: only the PAROL6's closed
/// form has named configurations).
///
/// # Errors
/// The IK's own errors; [`IkError::OtherConfiguration`] when the pose is reachable within the
/// limits, but only in configurations the rule does not allow.
pub fn solve_nearest(
    model: &RobotModel,
    target: &Isometry3<f64>,
    seed: &[f64],
    rule: ConfigRule,
) -> Result<IkSolution, IkError> {
    if !model.is_parol6 {
        if rule != ConfigRule::ANY {
            return Err(IkError::InvalidInput(format!(
                "configuration {rule} applies to the PAROL6 closed form only; this robot has no named configurations"
            )));
        }
        return super::solve_numeric(model, target, seed, &NumericIkOptions::default());
    }
    let only = rule.branch();
    let first_error =
        match super::closed_form::nearest_parol6_in(model, target, seed, only, |b, q| rule.admits_branch(b, q)) {
            Ok(found) => match found {
                Some(best) => return Ok(best),
                None => IkError::NoSolutionWithinLimits {
                    branches: 0,
                    detail: format!("no solution in configuration {rule} lies within the limits"),
                },
            },
            Err(e @ (IkError::InvalidInput(_) | IkError::NotParol6)) => return Err(e),
            Err(e) if rule == ConfigRule::ANY => return Err(e),
            Err(e) => e,
        };
    // say which configurations would reach it
    let all = super::solve_parol6(model, target, seed).unwrap_or_default();
    let mut reachable: Vec<String> = all.iter().filter_map(|s| s.branch.map(|b| b.label())).collect();
    reachable.dedup();
    if reachable.is_empty() {
        return Err(first_error);
    }
    Err(IkError::OtherConfiguration { wanted: rule.to_string(), reachable })
}

#[cfg(test)]
mod tests;
