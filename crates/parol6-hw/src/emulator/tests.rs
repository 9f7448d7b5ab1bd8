//! Unit tests of the firmware model.
use super::*;
use crate::frame::{CommandFields, CommandFrame};

fn cmd(code: CommandCode, fields: CommandFields) -> ReceivedCommand {
    let bytes = CommandFrame { command: code, fields }.encode().unwrap();
    ReceivedCommand::decode(&bytes).unwrap()
}

fn at_standby() -> ControllerModel {
    ControllerModel::new(EmulatorConfig::homed_at_standby())
}

#[test]
fn move_law_converges_and_reports_speed() {
    let mut m = at_standby();
    let mut f = CommandFields { positions_steps: STANDBY_STEPS, ..Default::default() };
    f.positions_steps[0] += 1000;
    let now = Instant::now();
    let s = m.accept(cmd(CommandCode::Move, f), now);
    // v = trunc((0 + trunc(1000 / 0.01)) / 2) = 50 000 (clamped to 50 000).
    assert_eq!(s.speeds_steps_s[0], 50_000);
    m.advance(0.2);
    let p = m.position_steps()[0];
    assert!((p - (STANDBY_STEPS[0] + 1000)).abs() <= 1, "{p}");
    assert_eq!(s.echoed_command, 156);
}

#[test]
fn move_with_feedforward_settles_past_target() {
    let mut m = at_standby();
    let mut f = CommandFields { positions_steps: STANDBY_STEPS, ..Default::default() };
    f.speeds_steps_s[1] = 1000;
    m.accept(cmd(CommandCode::Move, f), Instant::now());
    m.advance(0.5);
    // Settles about v_ff/100 = 10 steps past the target.
    let over = m.position_steps()[1] - STANDBY_STEPS[1];
    assert!((9..=11).contains(&over), "{over}");
}

#[test]
fn jog_runs_forever_without_new_frames() {
    let mut m = at_standby();
    let mut f = CommandFields::default();
    f.speeds_steps_s[2] = -2000;
    f.speeds_steps_s[3] = 90_000;
    let s = m.accept(cmd(CommandCode::Jog, f), Instant::now());
    assert_eq!(s.speeds_steps_s[3], 50_000);
    m.advance(1.0);
    assert_eq!(m.position_steps()[2], STANDBY_STEPS[2] - 2000);
    m.advance(1.0);
    assert_eq!(m.position_steps()[2], STANDBY_STEPS[2] - 4000);
}

#[test]
fn disable_latches_until_enable() {
    let mut m = at_standby();
    m.accept(cmd(CommandCode::Disable, CommandFields::default()), Instant::now());
    let mut f = CommandFields::default();
    f.speeds_steps_s[0] = 1000;
    m.accept(cmd(CommandCode::Jog, f), Instant::now());
    m.advance(0.5);
    assert_eq!(m.position_steps(), STANDBY_STEPS);
    m.accept(cmd(CommandCode::Enable, CommandFields::default()), Instant::now());
    m.accept(cmd(CommandCode::Jog, f), Instant::now());
    m.advance(0.5);
    assert_eq!(m.position_steps()[0], STANDBY_STEPS[0] + 500);
}

#[test]
fn idle_does_not_step_but_shows_speeds() {
    let mut m = at_standby();
    let mut f = CommandFields::default();
    f.speeds_steps_s[0] = 1234;
    let s = m.accept(cmd(CommandCode::Idle, f), Instant::now());
    assert_eq!(s.speeds_steps_s[0], 1234);
    m.advance(0.5);
    assert_eq!(m.position_steps(), STANDBY_STEPS);
}

#[test]
fn homing_sets_bits_in_stages_then_standby() {
    let mut m = ControllerModel::new(EmulatorConfig::default());
    assert_eq!(m.status().homed_bits, 0x03);
    m.accept(cmd(CommandCode::Home, CommandFields::default()), Instant::now());
    m.accept(cmd(CommandCode::Idle, CommandFields::default()), Instant::now());
    assert!(m.is_homing());
    m.advance(0.5);
    assert_eq!(m.homed(), [true, true, true, false, false, false]);
    m.advance(0.2);
    assert_eq!(m.homed(), [true, true, true, true, false, false]);
    m.advance(0.4);
    assert!(!m.is_homing());
    assert_eq!(m.status().homed_bits, 0xFF);
    assert_eq!(m.position_steps(), STANDBY_STEPS);
}

#[test]
fn homing_restarts_when_home_is_still_the_last_command_and_move_aborts_it() {
    let mut m = ControllerModel::new(EmulatorConfig::default());
    m.accept(cmd(CommandCode::Home, CommandFields::default()), Instant::now());
    m.advance(1.2);
    assert!(m.is_homing(), "restarted");
    m.accept(cmd(CommandCode::Move, CommandFields::default()), Instant::now());
    assert!(!m.is_homing());
}

#[test]
fn estop_and_outputs_are_reported() {
    let mut m = at_standby();
    m.estop_pressed = true;
    m.in1 = true;
    let f = CommandFields { io_bits: IO_OUT1, ..Default::default() };
    let s = m.accept(cmd(CommandCode::Idle, f), Instant::now());
    assert!(s.estop_pressed() && s.in1() && s.out1() && !s.out2());
}
