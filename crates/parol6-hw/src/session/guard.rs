//! The last line of defence, as pure functions (a fuzz target drives them):
//! - [`guard_frame`]: right before encoding, every position field must lie within the step
//!   limits (a frame with one outside is refused, never sent: the session holds with IDLE), and
//!   no MOVE target may move further from the previous frame's target than the joint's API
//!   speed limit allows in the elapsed periods (+1 step of rounding; clamped and counted);
//! - [`limit_breach`]: a measured position outside the step limits, a little (an arm pushed
//!   there: only a confirmed jog back inside may move it) or impossibly far;
//! - [`PlausibilityFilter`]: measured positions that jump further than the joint can move in
//!   the elapsed time are rejected and counted, never used;
//! - [`DisagreementMonitor`]: commanded and measured positions apart by more than a tolerance
//!   for too long stop motion.
//!
//! MOVE targets come only from the host's commanded trajectory: measured positions never pull
//! them (a single corrupted status frame cannot move a joint).

use parol6_core::parol6::{JOINT_COUNT, MAX_SPEED_STEPS_S};

use crate::frame::{CommandCode, CommandFrame};
use crate::units::{limits_steps, max_speed_steps_s};

/// Steps of rounding allowed on top of `speed limit × elapsed time` per frame.
pub const GUARD_ROUNDING_STEPS: i32 = 1;
/// A measured jump is plausible up to this factor × the API speed limit × elapsed time …
pub const PLAUSIBLE_SPEED_FACTOR: f64 = 1.5;
/// … plus this many steps (counter jitter, rounding).
pub const PLAUSIBLE_MARGIN_STEPS: i32 = 20;

/// Why the last-line guard refused a frame outright.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GuardViolation {
    /// A position field of a frame without a target is outside the joint's step limits.
    #[error("joint {joint} position field {steps} steps is outside {min}..{max}")]
    Position {
        /// 1-based joint.
        joint: usize,
        /// Field value, steps.
        steps: i32,
        /// Lower limit.
        min: i32,
        /// Upper limit.
        max: i32,
    },
    /// A speed field exceeds the joint's max speed.
    #[error("joint {joint} speed {steps_s} steps/s exceeds {max}")]
    Speed {
        /// 1-based joint.
        joint: usize,
        /// Speed, steps/s.
        steps_s: i32,
        /// Max speed.
        max: i32,
    },
    /// A MOVE target is outside the joint's step limits (whatever the previous target was).
    #[error("joint {joint} MOVE target {steps} steps is outside {min}..{max}")]
    Target {
        /// 1-based joint.
        joint: usize,
        /// Target, steps.
        steps: i32,
        /// Lower limit.
        min: i32,
        /// Upper limit.
        max: i32,
    },
    /// MOVE without a previous target to bound its step.
    #[error("MOVE without a previous target")]
    NoReference,
}

/// Largest target change of joint `joint` over `periods` frames of `period_s`, steps:
/// `floor(API max speed × periods × period_s) + 1`.
pub fn max_target_step(joint: usize, period_s: f64, periods: u32) -> i32 {
    let v = MAX_SPEED_STEPS_S[joint.min(JOINT_COUNT - 1)];
    let reach = v * period_s.max(0.0) * f64::from(periods.max(1));
    (reach.floor().min(f64::from(i32::MAX / 2)) as i32).saturating_add(GUARD_ROUNDING_STEPS)
}

/// The range a MOVE target of `joint` may take after `reference` (the previous frame's
/// target, `periods` frames ago): within the step limits and within [`max_target_step`] of the
/// reference. Empty (`lo > hi`) when the reference lies further outside the limits than one
/// step can bring back: no MOVE target is possible then.
pub fn allowed_target_range(joint: usize, reference: i32, period_s: f64, periods: u32) -> (i32, i32) {
    let (lo, hi) = limits_steps()[joint];
    let reach = max_target_step(joint, period_s, periods);
    (lo.max(reference.saturating_sub(reach)), hi.min(reference.saturating_add(reach)))
}

/// Last line of defence, right before encoding. Speed fields must not exceed the API max
/// speeds (the session sends zero). Every position field must lie within the step limits: a
/// frame with one outside is refused (for MOVE: [`GuardViolation::Target`], also when no
/// target within the limits is reachable from `reference`). A MOVE target within the limits is
/// clamped into [`allowed_target_range`] of `reference` (`(previous target, frames since)`).
/// Returns the number of joints it had to clamp (guard trips).
pub fn guard_frame(
    frame: &mut CommandFrame,
    reference: Option<(&[i32; JOINT_COUNT], u32)>,
    period_s: f64,
) -> Result<u32, GuardViolation> {
    let lim = limits_steps();
    let vmax = max_speed_steps_s();
    for (i, (&v, &max)) in frame.fields.speeds_steps_s.iter().zip(&vmax).enumerate() {
        if v.unsigned_abs() > max.unsigned_abs() {
            return Err(GuardViolation::Speed { joint: i + 1, steps_s: v, max });
        }
    }
    let mut trips = 0;
    if frame.command == CommandCode::Move {
        let (prev, periods) = reference.ok_or(GuardViolation::NoReference)?;
        for (i, (t, &r)) in frame.fields.positions_steps.iter_mut().zip(prev).enumerate() {
            let (min, max) = lim[i];
            let (lo, hi) = allowed_target_range(i, r, period_s, periods);
            if !(min..=max).contains(t) || lo > hi {
                return Err(GuardViolation::Target { joint: i + 1, steps: *t, min, max });
            }
            let c = (*t).clamp(lo, hi);
            if c != *t {
                *t = c;
                trips += 1;
            }
        }
        return Ok(trips);
    }
    for (i, (&p, &(min, max))) in frame.fields.positions_steps.iter().zip(&lim).enumerate() {
        if !(min..=max).contains(&p) {
            return Err(GuardViolation::Position { joint: i + 1, steps: p, min, max });
        }
    }
    Ok(trips)
}

/// A measured joint up to this far beyond one of its limits, degrees of joint angle, is
/// physically possible (an arm pushed there by a crash or by hand); further out, the board's
/// answer is impossible.
pub const PLAUSIBLE_BEYOND_LIMIT_DEG: f64 = 10.0;

/// A measured position outside a joint's step limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct LimitBreach {
    /// 1-based joint.
    pub joint: usize,
    /// Measured position, steps.
    pub steps: i32,
    /// Lower limit, steps.
    pub min: i32,
    /// Upper limit, steps.
    pub max: i32,
    /// Further beyond than [`PLAUSIBLE_BEYOND_LIMIT_DEG`]: no PAROL6 can be there.
    pub impossible: bool,
}

impl LimitBreach {
    /// How far beyond the nearer limit, steps (> 0).
    pub fn beyond_steps(&self) -> i64 {
        (i64::from(self.min) - i64::from(self.steps)).max(i64::from(self.steps) - i64::from(self.max))
    }

    /// True when the joint is beyond its upper limit (else its lower one).
    pub fn above(&self) -> bool {
        self.steps > self.max
    }
}

impl std::fmt::Display for LimitBreach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let beyond = self.beyond_steps();
        let deg = crate::units::steps_to_deg(self.joint.saturating_sub(1), beyond.clamp(0, i64::from(i32::MAX)) as i32);
        let (side, limit) = if self.above() { ("upper", self.max) } else { ("lower", self.min) };
        write!(
            f,
            "J{} reads {} steps, {beyond} steps ({deg:.1}°) beyond its {side} limit {limit}",
            self.joint, self.steps
        )
    }
}

/// The measured joint furthest beyond its step limits (an impossible one first), or `None`
/// when every joint is within them.
pub fn limit_breach(measured: &[i32; JOINT_COUNT]) -> Option<LimitBreach> {
    let lim = limits_steps();
    (0..JOINT_COUNT)
        .filter(|&i| !(lim[i].0..=lim[i].1).contains(&measured[i]))
        .map(|i| {
            let (min, max) = lim[i];
            let plausible = crate::units::deg_to_steps(i, PLAUSIBLE_BEYOND_LIMIT_DEG).unwrap_or(0).abs();
            let mut b = LimitBreach { joint: i + 1, steps: measured[i], min, max, impossible: false };
            b.impossible = b.beyond_steps() > i64::from(plausible);
            b
        })
        .max_by_key(|b| (b.impossible, b.beyond_steps()))
}

/// Position fields for frames that carry no target: the measured position clamped into the
/// step limits (the firmware ignores them; they are kept in range anyway).
pub fn placeholder_positions(measured: Option<&[i32; JOINT_COUNT]>) -> [i32; JOINT_COUNT] {
    let lim = limits_steps();
    let base = measured.copied().unwrap_or(crate::units::STANDBY_STEPS);
    std::array::from_fn(|i| base[i].clamp(lim[i].0, lim[i].1))
}

/// Largest plausible change of a measured position of `joint` in `elapsed_s`, steps.
pub fn max_plausible_jump(joint: usize, elapsed_s: f64) -> i32 {
    let v = MAX_SPEED_STEPS_S[joint.min(JOINT_COUNT - 1)] * PLAUSIBLE_SPEED_FACTOR;
    let e = if elapsed_s.is_finite() { elapsed_s.clamp(0.0, 60.0) } else { 60.0 };
    ((v * e).ceil() as i32).saturating_add(PLAUSIBLE_MARGIN_STEPS)
}

/// What [`PlausibilityFilter::check`] decided about a measurement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plausibility {
    /// Use it.
    Accepted,
    /// A jump larger than physically possible: do not use it.
    Implausible {
        /// 0-based joint with the jump.
        joint: usize,
        /// The jump, steps.
        jump_steps: i32,
        /// The largest plausible jump, steps.
        bound_steps: i32,
        /// Implausible frames in a row, this one included.
        in_a_row: u32,
    },
}

/// Rejects measured positions that jump further than the joint can move since the last
/// accepted measurement. The elapsed time is at least one period per status frame since then
/// plus one period of slack (replies can arrive in bursts on a loaded host).
#[derive(Debug, Clone, Default)]
pub struct PlausibilityFilter {
    last: Option<([i32; JOINT_COUNT], f64)>,
    frames_since: u32,
    in_a_row: u32,
    accepted_in_a_row: u32,
    /// Accepted measurements in a row equal to the one before (the arm at rest), counted once
    /// per [`STEADY_SPACING_S`].
    steady_in_a_row: u32,
    /// When the last of those was counted.
    steady_counted_at_s: f64,
}

/// Identical measurements count toward [`PlausibilityFilter::steady`] only this far apart: a
/// burst of frames delivered late (held by a stalled link) arrives at once and shows where the
/// arm *was*, so it must not pass for an arm at rest.
pub const STEADY_SPACING_S: f64 = 0.001;

/// Accepted measurements in a row needed before motion may start from a measured position.
pub const CONFIRMING_FRAMES: u32 = 3;

impl PlausibilityFilter {
    /// Checks `measured` arriving at `at_s` (any monotonic clock, s). Accepted measurements
    /// become the new reference.
    pub fn check(&mut self, measured: &[i32; JOINT_COUNT], at_s: f64, period_s: f64) -> Plausibility {
        let Some((last, last_at)) = self.last else {
            self.accept(measured, at_s);
            return Plausibility::Accepted;
        };
        self.frames_since = self.frames_since.saturating_add(1);
        let by_frames = f64::from(self.frames_since) * period_s;
        let elapsed = (at_s - last_at).max(by_frames) + period_s;
        for i in 0..JOINT_COUNT {
            let jump = measured[i].saturating_sub(last[i]).saturating_abs();
            let bound = max_plausible_jump(i, elapsed);
            if jump > bound {
                self.in_a_row = self.in_a_row.saturating_add(1);
                self.accepted_in_a_row = 0;
                return Plausibility::Implausible {
                    joint: i,
                    jump_steps: jump,
                    bound_steps: bound,
                    in_a_row: self.in_a_row,
                };
            }
        }
        self.accept(measured, at_s);
        Plausibility::Accepted
    }

    /// Takes `measured` as the reference without checking it (homing rewrites the counters).
    pub fn accept(&mut self, measured: &[i32; JOINT_COUNT], at_s: f64) {
        let same = self.last.as_ref().is_some_and(|(m, _)| m == measured);
        if !same {
            self.steady_in_a_row = 0;
            self.steady_counted_at_s = at_s;
        } else if at_s - self.steady_counted_at_s >= STEADY_SPACING_S {
            self.steady_in_a_row = self.steady_in_a_row.saturating_add(1);
            self.steady_counted_at_s = at_s;
        }
        self.last = Some((*measured, at_s));
        self.frames_since = 0;
        self.in_a_row = 0;
        self.accepted_in_a_row = self.accepted_in_a_row.saturating_add(1);
    }

    /// True once [`CONFIRMING_FRAMES`] measurements in a row were accepted: motion may start
    /// from the measured position (a lone garbage frame accepted after a fault never is).
    pub fn confirmed(&self) -> bool {
        self.accepted_in_a_row >= CONFIRMING_FRAMES
    }

    /// True when the last [`CONFIRMING_FRAMES`] accepted measurements are identical and arrived
    /// at [`STEADY_SPACING_S`] or more from each other: the arm is at rest, so a motion may start
    /// from this position (a status frame can be one period old while the arm still coasts
    /// after IDLE, and a late burst of frames is older still).
    pub fn steady(&self) -> bool {
        self.steady_in_a_row + 1 >= CONFIRMING_FRAMES
    }

    /// Forgets the reference (the next measurement is taken as it is).
    pub fn forget(&mut self) {
        *self = Self::default();
    }

    /// The last accepted measurement.
    pub fn reference(&self) -> Option<&[i32; JOINT_COUNT]> {
        self.last.as_ref().map(|(m, _)| m)
    }
}

/// Watches commanded against measured positions while MOVE is streamed.
#[derive(Debug, Clone, Default)]
pub struct DisagreementMonitor {
    since_s: Option<f64>,
}

impl DisagreementMonitor {
    /// Feeds one tick at `now_s`; returns `(0-based joint, difference in steps)` once some
    /// joint has been more than `tolerance_steps` apart for longer than `timeout_s`.
    pub fn check(
        &mut self,
        commanded: &[i32; JOINT_COUNT],
        measured: &[i32; JOINT_COUNT],
        now_s: f64,
        tolerance_steps: i32,
        timeout_s: f64,
    ) -> Option<(usize, i32)> {
        let worst = (0..JOINT_COUNT)
            .map(|i| (i, commanded[i].saturating_sub(measured[i]).saturating_abs()))
            .max_by_key(|(_, d)| *d)?;
        if worst.1 <= tolerance_steps {
            self.since_s = None;
            return None;
        }
        let since = *self.since_s.get_or_insert(now_s);
        (now_s - since > timeout_s).then_some(worst)
    }

    /// Forgets any disagreement (motion stopped).
    pub fn reset(&mut self) {
        self.since_s = None;
    }
}

#[cfg(test)]
mod tests;
