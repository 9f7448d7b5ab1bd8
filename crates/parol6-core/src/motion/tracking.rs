//! Tracking modes: which MOVE target (and feed-forward) each 10 ms frame carries, the one place
//! both backends take it from (the serial session for the board, the simulation for its
//! simulated drives, [`super::stepper`]).
//!
//! The firmware's MOVE law with zero feed-forward is a first-order lag (τ = 20 ms) toward a
//! target held for each period T = 10 ms. For a target moving at a steady speed V, the step
//! counter at each frame instant trails the target sent by V·L with
//!
//! ```text
//! L = T / (1 − (1 − h/τ)^(T/h))      h = 0.5 ms, the firmware's sub-step
//!   ≈ 25.2 ms                          (T / (1 − e^(−T/τ)) = 25.4 ms in continuous time)
//! ```
//!
//! - [`TrackingMode::Official`]: the planned position *now*, zero feed-forward, as the official
//!   API streams: the arm trails the plan by ≈ V·25 ms (2.97° on Draw at full speed).
//! - [`TrackingMode::Lead`]: the planned position L ahead ([`lead_s`]), zero feed-forward: the
//!   arm is where the plan says when the plan says it.
//! - [`TrackingMode::Feedforward`]: the planned position L − T ahead with the feed-forward
//!   speed that, should the link drop, makes the drives settle on the planned position L ahead
//!   (`speed = (plan(t + L) − plan(t + L − T)) / T` in whole steps): the same tracking as
//!   `lead` for steady speeds. The commander GUI's feed-forward (target now, speed = planned
//!   speed) settles 10 ms of travel *past* its target when the link drops, which can be off the
//!   path and past a limit; that form is not offered.
//!
//! Per frame a target moves at most the joint's ROBOT.md §5 speed × the period from the
//! previous one (the serial session's last-line guard bound): where the plan itself jumps in
//! speed (a jog or a dragged slider starts without an acceleration phase) the lead builds up
//! over a few frames instead of jumping.
//!
//! Safety: on link loss the board holds its last MOVE target (and feed-forward). Every target
//! here is a planned position (a sample of the planner, which keeps every setpoint inside the
//! limits) and, with feed-forward, so is the point the drives then settle on (within a step).

use serde::{Deserialize, Serialize};

use super::stepper::{FW_MOVE_PERIOD_S, MOVE_TIME_CONSTANT_S, SUBSTEP_S, StepperCommand, move_fields};
use super::{MotionPlanner, Setpoint};

/// How the streamed targets relate to the plan (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackingMode {
    /// The planned position now, zero feed-forward (the official API's way).
    Official,
    /// The planned position a fixed lead ahead ([`lead_s`]), zero feed-forward.
    #[default]
    Lead,
    /// The planned position `lead − period` ahead, with the feed-forward speed toward the
    /// planned position `lead` ahead.
    Feedforward,
}

impl TrackingMode {
    /// Every mode, in the order tables list them.
    pub const ALL: [TrackingMode; 3] = [TrackingMode::Official, TrackingMode::Lead, TrackingMode::Feedforward];

    /// The name used on the command line, in settings and in files.
    pub fn name(self) -> &'static str {
        match self {
            TrackingMode::Official => "official",
            TrackingMode::Lead => "lead",
            TrackingMode::Feedforward => "feedforward",
        }
    }

    /// The mode of a name ([`TrackingMode::name`]).
    pub fn from_name(name: &str) -> Option<TrackingMode> {
        TrackingMode::ALL.into_iter().find(|m| m.name() == name)
    }
}

impl std::fmt::Display for TrackingMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for TrackingMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TrackingMode::from_name(s).ok_or_else(|| format!("unknown tracking mode {s:?} (official, lead, feedforward)"))
    }
}

/// The lead of [`TrackingMode::Lead`] for a frame period (s): how far the firmware's step
/// counters trail a steadily moving target at the frame instants, `T / (1 − (1 − h/τ)^(T/h))`.
pub fn lead_s(period_s: f64) -> f64 {
    let decay = (1.0 - SUBSTEP_S / MOVE_TIME_CONSTANT_S).powf(period_s / SUBSTEP_S);
    period_s / (1.0 - decay)
}

/// Picks each frame's target from the planner in a [`TrackingMode`] (scratch setpoints kept,
/// no allocation once sized).
#[derive(Debug, Clone)]
pub struct Tracker {
    mode: TrackingMode,
    period_s: f64,
    target: Setpoint,
    stop: Setpoint,
    /// The previous frame's target, rad (the bound of the next one's step).
    prev: Vec<f64>,
}

/// Share of the ROBOT.md §5 speed a target may move per frame: all of it (a plan cruising at
/// the speed limit is not bounded; the guard adds a rounding margin of its own).
const FRAME_STEP_SHARE: f64 = 1.0;

impl Tracker {
    /// A tracker for frames every `period_s` (the firmware's law assumes 10 ms).
    pub fn new(mode: TrackingMode, period_s: f64) -> Self {
        Self { mode, period_s, target: Setpoint::at_rest(&[]), stop: Setpoint::at_rest(&[]), prev: Vec::new() }
    }

    /// Streaming (re)starts with the drives at `q_rad`: the next target's step is bounded from there.
    pub fn reset(&mut self, q_rad: &[f64]) {
        self.prev.clear();
        self.prev.extend_from_slice(q_rad);
    }

    /// The mode.
    pub fn mode(&self) -> TrackingMode {
        self.mode
    }

    /// Changes the mode (takes effect with the next frame).
    pub fn set_mode(&mut self, mode: TrackingMode) {
        self.mode = mode;
    }

    /// The frame's joint target (rad) and, with feed-forward, the planned point (rad) the
    /// drives settle on if the link drops. `commanded` is the planner sampled at `t_s`.
    pub fn targets<'a>(
        &'a mut self,
        planner: &MotionPlanner,
        t_s: f64,
        commanded: &'a Setpoint,
    ) -> (&'a [f64], Option<&'a [f64]>) {
        let lead = lead_s(self.period_s.max(FW_MOVE_PERIOD_S * 0.5));
        let ahead = match self.mode {
            TrackingMode::Official => {
                self.target.clone_from(commanded);
                false
            }
            TrackingMode::Lead => {
                planner.preview_into(t_s + lead, &mut self.target);
                true
            }
            TrackingMode::Feedforward => {
                planner.preview_into(t_s + lead - self.period_s, &mut self.target);
                planner.preview_into(t_s + lead, &mut self.stop);
                true
            }
        };
        if ahead && self.prev.len() == self.target.q.len() {
            let vmax = crate::parol6::max_speed_rad_s();
            for (j, (q, p)) in self.target.q.iter_mut().zip(&self.prev).enumerate() {
                let d = vmax.get(j).map_or(f64::INFINITY, |v| v * self.period_s * FRAME_STEP_SHARE);
                let bounded = q.clamp(p - d, p + d);
                if bounded != *q {
                    // the lead is building up: the stop point moves back by as much
                    let excess = *q - bounded;
                    *q = bounded;
                    if let Some(s) = self.stop.q.get_mut(j) {
                        *s -= excess;
                    }
                }
            }
        }
        self.prev.clone_from(&self.target.q);
        match self.mode {
            TrackingMode::Feedforward => (&self.target.q, Some(&self.stop.q)),
            _ => (&self.target.q, None),
        }
    }

    /// The MOVE frame (PAROL6 steps) of this frame; `None` when a value is not finite.
    pub fn command(&mut self, planner: &MotionPlanner, t_s: f64, commanded: &Setpoint) -> Option<StepperCommand> {
        let (target, stop) = self.targets(planner, t_s, commanded);
        move_fields(target, stop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lead_is_about_25_ms_at_100_hz() {
        let l = lead_s(0.01);
        assert!((l - 0.02517).abs() < 1e-4, "{l}");
        for m in TrackingMode::ALL {
            assert_eq!(TrackingMode::from_name(m.name()), Some(m));
        }
        assert!("fast".parse::<TrackingMode>().is_err());
    }
}
