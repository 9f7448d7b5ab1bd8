//! The confirmed jog back inside: a joint measured a little beyond one of its limits (an arm
//! pushed there by a crash or by hand) cannot be moved with MOVE (its first target, the
//! measured position, lies outside the limits), so on the operator's confirmation
//! ([`crate::Session::jog_back_inside`]) it is stepped back with JOG (speed) frames: one joint,
//! inward only, at a quarter of the jog speed, with the jog's dead-man, until the joint is
//! within its limits. JOG ignores the position fields; they carry the clamped placeholders.

use std::time::{Duration, Instant};

use parol6_core::motion::DEADMAN_S;

use super::super::guard::limit_breach;
use super::Worker;
use crate::frame::{CommandCode, CommandFrame};
use crate::units::jog_speed_steps_s;

/// Share of the jog speed a recovery jog runs at.
pub const RECOVERY_SPEED_SHARE: f64 = 0.25;

/// A recovery jog in progress.
#[derive(Debug, Clone, Copy)]
pub(in super::super) struct Recovery {
    /// 0-based joint.
    joint: usize,
    /// Signed speed, steps/s (toward the inside).
    speed_steps_s: i32,
    /// The dead-man: no refresh by then stops it.
    until: Instant,
}

impl Worker {
    /// Starts or refreshes a recovery jog of `joint` at `fraction` of the jog speed (its sign is
    /// the direction): refused unless the joint is a little beyond one of its limits and the
    /// direction is inward.
    pub(super) fn start_recovery(&mut self, joint: usize, fraction: f64, now: Instant) -> Result<(), String> {
        let refused = |why: String| Err(format!("jog back inside refused: {why}"));
        let mut blocked = self.snap.clone();
        blocked.limit_breach = None;
        if let Err(e) = blocked.motion_allowed() {
            return refused(e.to_string());
        }
        if self.streamer.is_streaming() {
            return refused("motion is being streamed: stop it first".into());
        }
        let breach = limit_breach(&self.snap.joint_steps).filter(|b| b.joint == joint + 1);
        let Some(b) = breach else {
            return refused(format!("J{} is within its limits: jog it as usual", joint + 1));
        };
        if b.impossible {
            return refused(super::super::snapshot::impossible_answers(&b));
        }
        let inward = if b.above() { -1.0 } else { 1.0 };
        if fraction.signum() != inward || fraction == 0.0 {
            return refused(format!(
                "{b}: only a jog back inside (speed {}) is allowed",
                if b.above() { "< 0" } else { "> 0" }
            ));
        }
        let speed = jog_speed_steps_s(joint, fraction * RECOVERY_SPEED_SHARE).map_err(|e| e.to_string())?;
        self.recovery = Some(Recovery {
            joint,
            speed_steps_s: speed.trunc() as i32,
            until: now + Duration::from_secs_f64(DEADMAN_S),
        });
        Ok(())
    }

    /// This period's JOG frame of the recovery jog, or `None` (and the jog ended) once the
    /// joint is back within its limits, the dead-man ran out or motion is not allowed.
    pub(super) fn recovery_frame(&mut self, now: Instant) -> Option<CommandFrame> {
        let r = self.recovery?;
        let still_beyond =
            limit_breach(&self.snap.joint_steps).is_some_and(|b| b.joint == r.joint + 1 && !b.impossible);
        let mut others = self.snap.clone();
        others.limit_breach = None;
        if now > r.until || !still_beyond || others.motion_allowed().is_err() {
            self.recovery = None;
            return None;
        }
        let mut f = self.frame(CommandCode::Jog);
        f.fields.speeds_steps_s[r.joint] = r.speed_steps_s;
        Some(f)
    }
}
