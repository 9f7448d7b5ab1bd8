//! Status replies and link supervision: plausibility of measured positions, E-stop, homing
//! progress, what the board shows about its enable latch, link loss / no answer / recovery.

use std::time::Instant;

use super::super::guard::{Plausibility, limit_breach};
use super::super::motion::Homing;
use super::super::snapshot::{HomingState, LinkState, impossible_answers};
use super::Worker;
use crate::frame::{CommandCode, StatusFrame};
use crate::units::{joints_steps_to_rad, steps_to_rad};

impl Worker {
    pub(super) fn port_failed(&mut self, msg: &str) {
        self.port = None;
        self.parser.clear();
        let was = self.snap.link;
        self.snap.link = if self.ever_answered { LinkState::Lost } else { LinkState::NoAnswer };
        self.stop_all("link lost during homing");
        self.plausibility.forget();
        if was == LinkState::Connected {
            self.snap.link_losses += 1;
        }
        if was != self.snap.link || was == LinkState::Connected {
            self.set_fault(msg.to_string());
        }
    }

    pub(super) fn on_status(&mut self, s: StatusFrame, now: Instant) {
        let at_s = now.duration_since(self.epoch).as_secs_f64();
        let homing = !matches!(self.streamer.homing, Homing::None);
        // Liveness: a well-formed frame arrived (plausible or not).
        self.snap.last_status_at = Some(now);
        self.first_unanswered_write = None;
        self.ever_answered = true;
        if homing {
            // Homing rewrites the step counters: nothing to compare against.
            self.plausibility.accept(&s.positions_steps, at_s);
        } else if let Plausibility::Implausible { joint, jump_steps, bound_steps, in_a_row } =
            self.plausibility.check(&s.positions_steps, at_s, self.cfg.period_s())
        {
            self.snap.implausible_frames += 1;
            tracing::debug!("implausible status: J{} jumped {jump_steps} steps (at most {bound_steps})", joint + 1);
            if in_a_row < self.cfg.implausible_frames_fault {
                return;
            }
            self.stop_all("implausible status during homing");
            self.set_fault(format!(
                "{in_a_row} status frames in a row with impossible positions (J{} jumped {jump_steps} steps, at \
                 most {bound_steps} possible): motion stopped; check the cable",
                joint + 1
            ));
            // Take the board's word from here on; motion needs a new command.
            self.plausibility.accept(&s.positions_steps, at_s);
        }
        self.use_status(s);
        // (Re)connected once a few plausible frames in a row arrived: motion may start from
        // the measured position then.
        if self.snap.link != LinkState::Connected && self.plausibility.confirmed() {
            if matches!(self.snap.link, LinkState::Lost | LinkState::NoAnswer) {
                // The link is back: the old "link lost" text must not stay (the count does).
                self.snap.fault = None;
            }
            self.snap.link = LinkState::Connected;
            self.connected_at = now;
        }
    }

    pub(super) fn use_status(&mut self, s: StatusFrame) {
        let was_pressed = self.snap.estop_pressed;
        self.snap.status = Some(s);
        self.snap.joint_steps = s.positions_steps;
        self.snap.joint_rad = joints_steps_to_rad(&s.positions_steps);
        self.snap.joint_speed_steps_s = s.speeds_steps_s;
        self.snap.joint_speed_rad_s = std::array::from_fn(|i| steps_to_rad(i, s.speeds_steps_s[i]));
        self.snap.homed = s.homed_joints();
        // Before homing the counters mean nothing (the board boots at 0 steps).
        self.snap.limit_breach = if s.all_homed() { limit_breach(&s.positions_steps) } else { None };
        if let Some(b) = self.snap.limit_breach.filter(|b| b.impossible) {
            // No arm can be there: hold with IDLE, start nothing, say so.
            self.stop_all("impossible positions during homing");
            self.deferred = None;
            self.set_fault(impossible_answers(&b));
        }
        self.snap.estop_pressed = s.estop_pressed();
        self.snap.io = [s.in1(), s.in2(), s.out1(), s.out2()];
        self.snap.gripper_position = s.gripper_position;
        self.snap.gripper_current_ma = s.gripper_current_ma;
        self.snap.gripper_status = s.gripper_status;
        // What the board has shown about its enable latch.
        match CommandCode::from_byte(s.echoed_command) {
            Some(CommandCode::Enable) if !s.estop_pressed() => self.snap.enabled = Some(true),
            Some(CommandCode::Disable) => self.snap.enabled = Some(false),
            Some(CommandCode::Move | CommandCode::Jog) if s.speeds_steps_s.iter().any(|v| *v != 0) => {
                self.snap.enabled = Some(true);
            }
            _ => {}
        }
        if s.estop_pressed() && !was_pressed {
            self.stop_all("E-stop pressed during homing");
            self.snap.needs_enable = true;
            self.snap.enabled = Some(false);
            self.set_fault(super::ESTOP_FAULT);
        }
        // Homing progress.
        let all = s.all_homed();
        match &mut self.streamer.homing {
            Homing::Sending { seen_unhomed, .. } | Homing::Waiting { seen_unhomed, .. } => {
                if !all {
                    *seen_unhomed = true;
                }
            }
            Homing::None => {}
        }
        if let Homing::Waiting { seen_unhomed: true, .. } = self.streamer.homing
            && all
        {
            self.streamer.homing = Homing::None;
            self.snap.homing = HomingState::Done;
            // Homing runs only on an enabled board.
            self.snap.enabled = Some(true);
        }
    }

    pub(super) fn check_link(&mut self, now: Instant) {
        if self.port.is_none() {
            if now.duration_since(self.last_open_attempt) >= self.cfg.reconnect_interval {
                self.last_open_attempt = now;
                match crate::ports::open_port(&self.port_name) {
                    Ok(p) => {
                        self.port = Some(p);
                        self.parser.clear();
                        self.snap.reconnects += 1;
                        self.connected_at = now;
                        tracing::debug!("parol6 session: re-opened {}", self.port_name);
                    }
                    Err(e) => tracing::debug!("parol6 session: re-open of {} failed: {e}", self.port_name),
                }
            }
            return;
        }
        if !self.ever_answered {
            let waited = now.duration_since(self.opened_at);
            if waited >= self.cfg.no_answer_timeout && self.snap.link != LinkState::NoAnswer {
                self.snap.link = LinkState::NoAnswer;
                self.stop_all("no controller answered");
                self.set_fault(format!(
                    "no PAROL6 answered on {} within {:.0} s: check the port and the power",
                    self.port_name,
                    self.cfg.no_answer_timeout.as_secs_f64()
                ));
            }
            if self.snap.link == LinkState::NoAnswer
                && now.duration_since(self.last_open_attempt) >= self.cfg.reconnect_interval
            {
                // Quietly close and re-open (a board plugged in later is found).
                self.port = None;
                self.last_open_attempt = now.checked_sub(self.cfg.reconnect_interval).unwrap_or(now);
            }
            return;
        }
        let last_valid = self.snap.last_status_at.unwrap_or(self.connected_at).max(self.connected_at);
        let silent = now.duration_since(last_valid);
        // The board must have had a fair chance to answer: a frame of ours has waited at least
        // half the timeout (after a stall of this thread, the board has not been asked yet).
        let asked = self.first_unanswered_write.is_some_and(|t| now.duration_since(t) >= self.cfg.status_timeout / 2);
        // Checked once per period: reported at most `status_timeout` after the last status.
        let late = silent + self.cfg.period() > self.cfg.status_timeout;
        if late && asked && self.snap.link == LinkState::Connected {
            self.snap.link = LinkState::Lost;
            self.snap.link_losses += 1;
            self.stop_all("link lost during homing");
            self.plausibility.forget();
            self.set_fault(format!(
                "link lost: no valid status for {:.0} ms; motion stopped",
                silent.as_secs_f64() * 1e3
            ));
        }
        if self.snap.link != LinkState::Connected
            && silent >= self.cfg.reconnect_interval
            && now.duration_since(self.last_open_attempt) >= self.cfg.reconnect_interval
        {
            // Still silent: close and re-open the port (every reconnect interval).
            self.port = None;
            self.last_open_attempt = now.checked_sub(self.cfg.reconnect_interval).unwrap_or(now);
        }
    }
}
