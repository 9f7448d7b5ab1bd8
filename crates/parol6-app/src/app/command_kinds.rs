//! Which commands are which, and which wins in a frame: what sets the arm moving, what the
//! latched E-stop refuses, what an operator gives by hand, and what STOP, HOME or a clicked move
//! override when they come in the same frame as another motion. Pure functions of the commands;
//! `execute` acts on them.

use parol6_core::motion::{IoCommand, MotionCommand};

use crate::panels::{AppCommand, LinkCommand};

/// True for a command that sets the arm moving (not STOP, a pause or a jog release).
pub(super) fn sets_arm_moving(cmd: &AppCommand) -> bool {
    use parol6_core::program::runner::RunnerControl;
    match cmd {
        AppCommand::Motion(m) | AppCommand::TypedMotion(m) => {
            !matches!(m, MotionCommand::Stop | MotionCommand::JogRelease)
        }
        AppCommand::Jog(held) => held.is_some(),
        AppCommand::CartesianJog(held) => held.is_some(),
        AppCommand::RunProgram { .. } | AppCommand::StartMeasurement(_) | AppCommand::RunTorques(_) => true,
        AppCommand::Program(c) => matches!(c, RunnerControl::Resume | RunnerControl::Step),
        _ => false,
    }
}

/// True for a command the latched E-stop (or an open recording) refuses: whatever sets the arm or
/// the gripper moving (the controller's homing routine included), and ENABLE other than by
/// releasing the E-stop (the I/O panel's or the Robot connection's: either re-enabled the drives
/// under the latch, and homing then moved the arm, trial13 D1).
pub(super) fn refused_by_estop(cmd: &AppCommand) -> bool {
    sets_arm_moving(cmd)
        || matches!(cmd, AppCommand::Io(IoCommand::Gripper { .. } | IoCommand::GripperCalibrate | IoCommand::Enable))
        || matches!(cmd, AppCommand::Link(LinkCommand::Enable | LinkCommand::Home))
}

/// True for a command an operator gives by hand that sets the arm moving: a joint or Cartesian jog,
/// a move (typed joint, slider, Go, HOME, Move to target) or the controller's homing routine; not
/// STOP, a jog release, a program control or a run that checks itself for a running one.
pub(super) fn manual_motion(cmd: &AppCommand) -> bool {
    match cmd {
        AppCommand::Motion(m) | AppCommand::TypedMotion(m) => {
            !matches!(m, MotionCommand::Stop | MotionCommand::JogRelease)
        }
        AppCommand::Jog(held) => held.is_some(),
        AppCommand::CartesianJog(held) => held.is_some(),
        AppCommand::Link(l) => matches!(l, LinkCommand::Home),
        _ => false,
    }
}

/// True for STOP (Esc, the button) and E-STOP.
pub(super) fn is_stop(c: &AppCommand) -> bool {
    matches!(c, AppCommand::Motion(MotionCommand::Stop) | AppCommand::EStop(true))
}

/// What overrides `commands[i]`, if anything, in the frame that gave `commands` (in the words of
/// the notice): STOP or E-STOP drops every other command that sets the arm moving, HOME every other
/// motion but STOP, and any other clicked move a typed one ([`AppCommand::TypedMotion`]). Such a
/// motion beside them is one the operator did not mean: a joint's typed value committed because
/// the click on STOP or HOME took its field's keyboard (trial 24 D1: J1 swung to the typed 20°
/// after STOP; HOME went to the typed 60°), or a held jog key or a jog queued behind STOP
/// (trial15 D1).
pub(super) fn overridden(commands: &[AppCommand], i: usize) -> Option<&'static str> {
    let home = |c: &AppCommand| matches!(c, AppCommand::Motion(MotionCommand::Home { .. }));
    let c = &commands[i];
    if !sets_arm_moving(c) || is_stop(c) {
        return None;
    }
    // a click on a button that moves the arm (Go, Move to target, Run…) over a typed value
    // (trial 25 m2: Go dropped the typed value without a word)
    let clicked_move = |o: &AppCommand| {
        sets_arm_moving(o)
            && !matches!(o, AppCommand::TypedMotion(_) | AppCommand::Jog(_) | AppCommand::CartesianJog(_))
    };
    if commands.iter().any(is_stop) {
        Some("STOP pressed")
    } else if !home(c) && commands.iter().any(home) {
        Some("HOME pressed")
    } else if matches!(c, AppCommand::TypedMotion(_)) && commands.iter().any(clicked_move) {
        Some("another move clicked")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parol6_core::profile::ProfileKind;

    fn move_to(j1_rad: f64) -> MotionCommand {
        MotionCommand::MoveJoints { goal_rad: vec![j1_rad; 6], speed_fraction: 0.5, profile: ProfileKind::default() }
    }

    #[test]
    fn stop_home_and_a_clicked_move_win_over_a_typed_move_in_their_frame() {
        let typed = AppCommand::TypedMotion(move_to(0.3));
        let go = AppCommand::Motion(move_to(0.1));
        let stop = AppCommand::Motion(MotionCommand::Stop);
        let home = AppCommand::Motion(MotionCommand::Home { speed_fraction: 0.5, profile: ProfileKind::default() });
        // either order of the panels
        assert_eq!(overridden(&[typed.clone(), go.clone()], 0), Some("another move clicked"));
        assert_eq!(overridden(&[go.clone(), typed.clone()], 1), Some("another move clicked"));
        assert_eq!(overridden(&[go.clone(), typed.clone()], 0), None, "the clicked move runs");
        assert_eq!(overridden(&[typed.clone(), stop.clone()], 0), Some("STOP pressed"));
        assert_eq!(overridden(&[typed.clone(), home.clone()], 0), Some("HOME pressed"));
        assert_eq!(overridden(&[home.clone(), go.clone()], 1), Some("HOME pressed"));
        // alone, or beside a jog, it runs
        assert_eq!(overridden(std::slice::from_ref(&typed), 0), None);
        assert_eq!(overridden(&[typed, AppCommand::Jog(Some((0, 1)))], 0), None);
        // two clicked moves: both sent, the later wins in the backend
        assert_eq!(overridden(&[go.clone(), go], 0), None);
    }
}
