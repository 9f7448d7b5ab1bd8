//! Issue 31: the simulation predicts the robot. The simulation's joints are stepped by the
//! firmware's law (`parol6_core::motion::stepper`) from the targets of a tracking mode
//! (`parol6_core::motion::tracking`); the emulated board (`parol6_hw::ControllerModel`, the
//! `--fake-robot` firmware) is fed the MOVE frames the serial session builds from the same
//! planner and tracking mode, exactly every 10 ms. Both must measure the same joints.
//!
//! Also: link loss injected at every 10 ms of full-speed moves in each mode (the board then
//! holds its last frame) leaves the arm on the planned path and inside the limits; and the
//! tracking error per mode on the emulated board.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::time::Instant;

use parol6_core::RobotModel;
use parol6_core::motion::stepper::StepperCommand;
use parol6_core::motion::tracking::{Tracker, TrackingMode};
use parol6_core::motion::{MotionCaps, MotionCommand, MotionPlanner, Setpoint};
use parol6_core::parol6::{JOINT_COUNT, LIMITS_STEPS, rad_per_step};
use parol6_core::profile::ProfileKind;
use parol6_core::program::compile::{CompileOptions, StepAction, compile};
use parol6_core::program::gcode::{GcodeImportOptions, parse_gcode};
use parol6_core::program::{PoseMm, Program, builtin};
use parol6_core::sim::{ServoModel, SimCommand, SimConfig, Simulation};
use parol6_hw::units::{STANDBY_STEPS, joints_steps_to_rad};
use parol6_hw::{CommandCode, CommandFields, CommandFrame, ControllerModel, EmulatorConfig, ReceivedCommand};

const FRAME_S: f64 = 0.01;
const START_S: f64 = 0.05;

fn standby() -> Vec<f64> {
    joints_steps_to_rad(&STANDBY_STEPS).to_vec()
}

/// The program's motions as commands scheduled on the motion clock (dwells as gaps; I/O and
/// waits take no time here), and when the last ends.
fn schedule(model: &RobotModel, program: &Program) -> (Vec<(f64, MotionCommand)>, f64) {
    let steps = compile(model, program, &standby(), CompileOptions::RUN).expect("compiles");
    let mut t = START_S;
    let mut out = Vec::new();
    for s in steps {
        match s.action {
            StepAction::Motion(traj) => {
                let d = traj.duration_s();
                out.push((t, MotionCommand::Trajectory(traj)));
                t += d;
            }
            StepAction::Dwell(d) => t += d,
            _ => {}
        }
    }
    (out, t)
}

/// The emulated board fed exactly every 10 ms with the session's MOVE frames.
struct Board {
    fw: ControllerModel,
    planner: MotionPlanner,
    tracker: Tracker,
    tick: u64,
    sp: Setpoint,
}

impl Board {
    fn new(model: &RobotModel, mode: TrackingMode, cmds: &[(f64, MotionCommand)]) -> Self {
        let q0 = standby();
        let mut planner = MotionPlanner::new(model.limits.clone(), MotionCaps::of(model), q0.clone(), &q0);
        for (at, c) in cmds {
            planner.note_scheduled();
            planner.schedule_arriving(c.clone(), *at, 0.0).expect("scheduled");
        }
        let fw = ControllerModel::new(EmulatorConfig { log_commands: false, ..EmulatorConfig::homed_at_standby() });
        Self { fw, planner, tracker: Tracker::new(mode, FRAME_S), tick: 0, sp: Setpoint::at_rest(&q0) }
    }

    fn frame(cmd: StepperCommand) -> ReceivedCommand {
        let StepperCommand::Move { target_steps, speed_steps_s } = cmd else { panic!("not a MOVE") };
        let fields =
            CommandFields { positions_steps: target_steps, speeds_steps_s: speed_steps_s, ..Default::default() };
        let bytes = CommandFrame { command: CommandCode::Move, fields }.encode().expect("encodes");
        ReceivedCommand::decode(&bytes).expect("decodes")
    }

    /// One frame: 10 ms of firmware (after the first), then the frame of this tick. Returns the
    /// time, the planned setpoint and the measured joints (rad) at that time.
    fn tick(&mut self) -> (f64, Vec<f64>, Vec<f64>) {
        let t = self.tick as f64 * FRAME_S;
        if self.tick > 0 {
            self.fw.advance(FRAME_S);
        }
        self.sp = self.planner.sample(t);
        let cmd = self.tracker.command(&self.planner, t, &self.sp).expect("finite");
        let status = self.fw.accept(Self::frame(cmd), Instant::now());
        self.tick += 1;
        (t, self.sp.q.clone(), joints_steps_to_rad(&status.positions_steps).to_vec())
    }
}

/// Max and RMS over time of the worst joint's |planned − measured|, degrees.
#[derive(Debug, Default, Clone, Copy)]
struct Errors {
    max_deg: f64,
    sum_sq: f64,
    n: usize,
}

impl Errors {
    fn add(&mut self, planned: &[f64], measured: &[f64]) {
        let e = planned.iter().zip(measured).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max).to_degrees();
        self.max_deg = self.max_deg.max(e);
        self.sum_sq += e * e;
        self.n += 1;
    }
    fn rms_deg(&self) -> f64 {
        (self.sum_sq / self.n.max(1) as f64).sqrt()
    }
}

/// Runs `program` on the simulation and the board in `mode`; returns the largest difference of
/// their measured joints (deg) at the 10 ms samples and the board's tracking errors.
fn compare(model: &RobotModel, program: &Program, mode: TrackingMode) -> (f64, Errors, Errors) {
    compare_with(model, program, mode, ServoModel::Firmware)
}

fn compare_with(model: &RobotModel, program: &Program, mode: TrackingMode, servo: ServoModel) -> (f64, Errors, Errors) {
    let (cmds, end_s) = schedule(model, program);
    let mut board = Board::new(model, mode, &cmds);
    let mut sim =
        Simulation::new(model.clone(), SimConfig { tracking: mode, servo, ..SimConfig::default() }).expect("sim");
    sim.apply(SimCommand::Teleport(standby())).expect("teleport");
    for (at, c) in &cmds {
        sim.apply(SimCommand::MotionAt { cmd: c.clone(), at_s: *at }).expect("scheduled");
    }
    let (mut worst_deg, mut on_board, mut on_sim) = (0.0f64, Errors::default(), Errors::default());
    let ticks = ((end_s + 0.5) / FRAME_S).ceil() as u64;
    for _ in 0..ticks {
        let (t, planned, measured) = board.tick();
        while sim.sim_time_s() < t - 1e-9 {
            sim.step();
        }
        assert!((sim.sim_time_s() - t).abs() < 1e-9);
        let d = sim.q().iter().zip(&measured).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max).to_degrees();
        worst_deg = worst_deg.max(d);
        on_board.add(&planned, &measured);
        on_sim.add(&sim.planner().setpoint_at(t).q, sim.q());
    }
    (worst_deg, on_board, on_sim)
}

/// 5 000 G1 lines blended with `G64 P1` at 200 mm/s: a circle of 2.5 mm chords, 100 turns.
fn blended_gcode(lines: usize) -> String {
    let mut s = String::from("G21 G90 G17\nG0 X20 Y220 Z240 A90 B0 C90\nG64 P1\nF12000\n");
    for i in 1..=lines {
        let a = i as f64 * std::f64::consts::TAU / 50.0;
        s.push_str(&format!("G1 X{:.3} Y{:.3}\n", 20.0 * a.cos(), 220.0 + 20.0 * a.sin()));
    }
    s.push_str("G61\nM30\n");
    s
}

fn gcode_program(model: &RobotModel, lines: usize) -> Program {
    let pose = PoseMm::from_isometry(&model.tcp_isometry(&standby()));
    parse_gcode(&blended_gcode(lines), &GcodeImportOptions::new(pose, pose)).expect("G-code parses")
}

fn programs(model: &RobotModel) -> Vec<Program> {
    let mut all = builtin::programs(model);
    all.push(gcode_program(model, 400));
    all
}

#[test]
fn the_simulation_measures_what_the_emulated_board_measures_in_every_mode() {
    let model = RobotModel::parol6();
    for program in programs(&model) {
        for mode in TrackingMode::ALL {
            let (diff_deg, board, sim) = compare(&model, &program, mode);
            eprintln!(
                "{:<28} {:<12} |sim − board| ≤ {diff_deg:.5}°; tracking board max {:.3}° rms {:.3}°, sim max {:.3}° rms {:.3}°",
                program.name,
                mode.name(),
                board.max_deg,
                board.rms_deg(),
                sim.max_deg,
                sim.rms_deg()
            );
            assert!(diff_deg <= 0.05, "{} in {mode}: the simulation is {diff_deg:.4}° from the board", program.name);
        }
    }
}

/// The simulation before issue 31 (ideal motors tracking the plan itself) fails the check above:
/// it is degrees away from the board in the official API's mode.
#[test]
fn the_old_ideal_motors_do_not_predict_the_board() {
    let model = RobotModel::parol6();
    let draw = builtin::programs(&model).into_iter().find(|p| p.name.to_lowercase().contains("draw")).expect("draw");
    let (diff_deg, _, sim) = compare_with(&model, &draw, TrackingMode::Official, ServoModel::Ideal);
    eprintln!("ideal motors, Draw, official: |sim − board| up to {diff_deg:.3}°, sim tracking max {:.3}°", sim.max_deg);
    assert!(diff_deg > 1.0, "{diff_deg}");
}

/// The acceptance figures: full speed, Draw, Pick & place and the 5 000-line blended G-code.
#[test]
fn lead_tracks_the_plan_within_0_3_degrees_on_the_emulated_board() {
    let model = RobotModel::parol6();
    let builtins = builtin::programs(&model);
    let named = |n: &str| builtins.iter().find(|p| p.name.to_lowercase().contains(n)).cloned().expect(n);
    let set = [named("draw"), named("pick"), gcode_program(&model, 5000)];
    for program in &set {
        let (cmds, end_s) = schedule(&model, program);
        for mode in TrackingMode::ALL {
            let mut board = Board::new(&model, mode, &cmds);
            let mut e = Errors::default();
            for _ in 0..((end_s + 0.5) / FRAME_S).ceil() as u64 {
                let (_, planned, measured) = board.tick();
                e.add(&planned, &measured);
            }
            eprintln!(
                "{:<28} {:<12} {:>7.2} s: max {:.3}°, rms {:.4}°",
                program.name,
                mode.name(),
                end_s,
                e.max_deg,
                e.rms_deg()
            );
            if mode != TrackingMode::Official {
                assert!(e.max_deg <= 0.3, "{} in {mode}: max tracking error {:.3}°", program.name, e.max_deg);
            }
        }
    }
}

/// Largest joint distance (steps) from `rest` to the nearest point of the segment `a`–`b`
/// (rad; the Euclidean projection in steps, measured in the max norm).
fn off_segment(a: &[f64], b: &[f64], rest: &[i32; JOINT_COUNT]) -> f64 {
    let steps = |q: &[f64], j: usize| q[j] / rad_per_step(j);
    let (mut num, mut den) = (0.0, 0.0);
    for (j, r) in rest.iter().enumerate() {
        let d = steps(b, j) - steps(a, j);
        num += (f64::from(*r) - steps(a, j)) * d;
        den += d * d;
    }
    let l = if den > 0.0 { (num / den).clamp(0.0, 1.0) } else { 0.0 };
    (0..JOINT_COUNT)
        .map(|j| (steps(a, j) + l * (steps(b, j) - steps(a, j)) - f64::from(rest[j])).abs())
        .fold(0.0, f64::max)
}

/// Link loss at every 10 ms of full-speed moves (joint moves onto the limits, Draw): the board
/// holds its last frame; where its drives come to rest must be a planned position (within two
/// steps per joint) inside the limits.
#[test]
fn link_loss_at_every_frame_leaves_the_arm_on_the_planned_path_in_every_mode() {
    let model = RobotModel::parol6();
    let to_limits: Vec<f64> = (0..JOINT_COUNT)
        .map(|j| {
            let l = model.limits.get(j).expect("joint");
            if j % 2 == 0 { l.max } else { l.min }
        })
        .collect();
    let onto_limits = vec![(
        START_S,
        MotionCommand::MoveJoints { goal_rad: to_limits, speed_fraction: 1.0, profile: ProfileKind::Trapezoidal },
    )];
    let builtins = builtin::programs(&model);
    let draw = builtins.iter().find(|p| p.name.to_lowercase().contains("draw")).expect("draw");
    let cases = [("joint move onto the limits", onto_limits), ("draw", schedule(&model, draw).0)];
    for (name, cmds) in &cases {
        // the plan, sampled every 1 ms
        let mut p = Board::new(&model, TrackingMode::Official, cmds).planner;
        let end_s = p.path_end_s().max(cmds.last().map_or(0.0, |c| c.0)) + 30.0;
        let plan: Vec<Vec<f64>> =
            (0..).map(|i| i as f64 * 1e-3).take_while(|t| *t < end_s).map(|t| p.sample(t).q).collect();
        let plan_end = plan.iter().rposition(|q| q != plan.last().expect("samples")).unwrap_or(0) as f64 * 1e-3;
        for mode in TrackingMode::ALL {
            let mut board = Board::new(&model, mode, cmds);
            let mut worst_steps = 0.0f64;
            let ticks = ((plan_end + 0.2) / FRAME_S).ceil() as u64;
            for k in 0..ticks {
                board.tick();
                let mut lost = board.fw.clone();
                lost.advance(1.0);
                lost.advance(1.0);
                let rest = lost.position_steps();
                for (j, s) in rest.iter().enumerate() {
                    let (lo, hi) = LIMITS_STEPS[j];
                    assert!((lo..=hi).contains(s), "{name}, {mode}, lost at frame {k}: J{} at {s} steps", j + 1);
                }
                // nearest planned position (the 1 ms plan as line segments, in steps) within
                // -0.2 s … +0.25 s of the frame
                let t = k as f64 * FRAME_S;
                let i0 = ((t - 0.2).max(0.0) * 1e3) as usize;
                let i1 = (((t + 0.25) * 1e3) as usize).min(plan.len() - 1);
                let nearest =
                    (i0..i1).map(|i| off_segment(&plan[i], &plan[i + 1], &rest)).fold(f64::INFINITY, f64::min);
                worst_steps = worst_steps.max(nearest);
                assert!(nearest <= 2.0, "{name}, {mode}, lost at frame {k}: {nearest:.1} steps off the plan");
            }
            eprintln!("link loss, {name}, {mode}: {ticks} frames, worst {worst_steps:.2} steps from the plan");
        }
    }
}

/// The simulated arm comes to rest after a move (its physics then sleeps): the drives stop on
/// whole steps and the links settle on them.
#[test]
fn the_simulated_arm_rests_after_a_move() {
    let model = RobotModel::parol6();
    let mut sim = Simulation::new(model, SimConfig::default()).expect("sim");
    let mut goal = standby();
    goal[0] += 0.3;
    sim.apply(SimCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal,
        speed_fraction: 0.8,
        profile: ProfileKind::Trapezoidal,
    }))
    .expect("move");
    for _ in 0..3000 {
        sim.step();
    }
    assert!(sim.resting(), "not resting 3 s after a 0.5 s move");
}
