//! [`SessionConfig`]: the settings of a controller session and their checks.

use std::time::Duration;

use parol6_core::limits::JointLimits;
use parol6_core::parol6::JOINT_COUNT;

use crate::HwError;

/// Farthest a tool's TCP may be from the flange, m.
const MAX_TOOL_REACH_M: f64 = 1.0;

/// Session settings.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionConfig {
    /// Command rate, Hz (50–500; default 100, which the firmware's MOVE law assumes).
    pub rate_hz: f64,
    /// Link loss is reported at most this long after the last valid status, checked once per
    /// period (default 80 ms: reported 70–80 ms after the last status at 100 Hz, leaving 20 ms of
    /// scheduling slack within the 100 ms promised) — provided a frame of ours has waited at
    /// least half of it for an answer, so a freeze of the session thread itself is not taken
    /// for a silent board.
    pub status_timeout: Duration,
    /// No valid status at all this long after opening the port → "no PAROL6 answered"
    /// (default 3 s).
    pub no_answer_timeout: Duration,
    /// Re-open the port this often while the link is down or nothing answers (default 2 s;
    /// quietly: one fault message, no message per attempt).
    pub reconnect_interval: Duration,
    /// Homing fails after this long (default 45 s).
    pub home_timeout: Duration,
    /// HOME frames sent before switching to IDLE (default 10, as the API does).
    pub home_frames: u32,
    /// Joint limits every command passes (the planner's limits).
    pub limits: JointLimits,
    /// Keep up to this many frame write times for [`crate::Session::take_write_times`]
    /// (0 = off; used by `parol6 bench serial`).
    pub write_log_capacity: usize,
    /// Busy-wait this long before each deadline instead of sleeping, to cut wake-up latency on
    /// a loaded machine (costs that fraction of one core; default zero: off).
    pub spin_before_deadline: Duration,
    /// This many implausible status frames in a row stop motion with a fault (default 5).
    pub implausible_frames_fault: u32,
    /// Commanded and measured positions disagreeing by more than this many steps on a joint …
    /// (default 2000 steps: the firmware MOVE law lags ≈ v/50 steps, at most 640 steps at the
    /// API speed limits) …
    pub disagreement_steps: i32,
    /// … for longer than this while streaming MOVE stops motion with a fault (default 0.5 s).
    pub disagreement_timeout: Duration,
    /// Ask the OS for a real-time (SCHED_FIFO) or raised (nice −10) priority for the session
    /// thread; refused requests (EPERM) are ignored (default on).
    pub raise_priority: bool,
    /// Which targets the MOVE frames carry (`parol6_core::motion::tracking`; default `lead`).
    pub tracking: parol6_core::motion::tracking::TrackingMode,
    /// The tool's TCP in the flange frame (`RobotModel::tool`; default none: the flange): the
    /// published TCP and the Cartesian jogs and steps are the tool tip's, as in the simulation
    /// (trial 22 D1: the robot's TCP read-out was the flange's with a tool fitted).
    pub tool_in_flange: parol6_core::na::Isometry3<f64>,
}

impl Default for SessionConfig {
    fn default() -> Self {
        Self {
            rate_hz: 100.0,
            status_timeout: Duration::from_millis(80),
            no_answer_timeout: Duration::from_secs(3),
            reconnect_interval: Duration::from_secs(2),
            home_timeout: Duration::from_secs(45),
            home_frames: 10,
            limits: JointLimits::parol6(),
            write_log_capacity: 0,
            spin_before_deadline: Duration::ZERO,
            implausible_frames_fault: 5,
            disagreement_steps: 2000,
            disagreement_timeout: Duration::from_millis(500),
            raise_priority: true,
            tracking: parol6_core::motion::tracking::TrackingMode::default(),
            tool_in_flange: parol6_core::na::Isometry3::identity(),
        }
    }
}

impl SessionConfig {
    /// Checks the settings.
    pub fn validate(&self) -> Result<(), HwError> {
        if !(self.rate_hz.is_finite() && (50.0..=500.0).contains(&self.rate_hz)) {
            return Err(HwError::BadConfig(format!("rate {} Hz is outside 50–500 Hz", self.rate_hz)));
        }
        if self.limits.len() != JOINT_COUNT {
            return Err(HwError::BadConfig(format!("limits have {} joints, expected 6", self.limits.len())));
        }
        if self.status_timeout.is_zero() || self.no_answer_timeout.is_zero() || self.home_frames == 0 {
            return Err(HwError::BadConfig("timeouts and home_frames must be > 0".into()));
        }
        let tool = self.tool_in_flange.to_homogeneous();
        if !tool.iter().all(|v| v.is_finite()) || self.tool_in_flange.translation.vector.norm() > MAX_TOOL_REACH_M {
            return Err(HwError::BadConfig(format!(
                "the tool's TCP must be finite and within {MAX_TOOL_REACH_M} m of the flange"
            )));
        }
        if self.implausible_frames_fault == 0 || self.disagreement_steps <= 0 {
            return Err(HwError::BadConfig("implausible_frames_fault and disagreement_steps must be > 0".into()));
        }
        Ok(())
    }

    /// The command period.
    pub fn period(&self) -> Duration {
        Duration::from_secs_f64(1.0 / self.rate_hz)
    }

    /// The command period, s.
    pub fn period_s(&self) -> f64 {
        1.0 / self.rate_hz
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_rate_is_checked() {
        let mut c = SessionConfig::default();
        assert!(c.validate().is_ok());
        c.rate_hz = 40.0;
        assert!(c.validate().is_err());
        c.rate_hz = 501.0;
        assert!(c.validate().is_err());
        c.rate_hz = f64::NAN;
        assert!(c.validate().is_err());
        c.rate_hz = 500.0;
        assert!(c.validate().is_ok());
        c.implausible_frames_fault = 0;
        assert!(c.validate().is_err());
    }
}
