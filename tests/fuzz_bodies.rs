//! Bodies of the cargo-fuzz targets in `fuzz/`, kept here so that stable Rust replays the
//! committed corpora and regression files through exactly the same checks
//! (`tests/fuzz_corpora.rs`). Each body takes arbitrary bytes, must never panic on its own
//! account, and asserts the invariants its target stands for; an assertion failure is a bug.

use std::time::{Duration, Instant};

use parol6_core::collision::CollisionGuard;
use parol6_core::ik::{self, pose_error};
use parol6_core::model::{LoadOptions, ModelError, RobotModel, Shape};
use parol6_core::parol6::JOINT_COUNT;
use parol6_core::sim::{SimConfig, Simulation};
use parol6_core::urdf_input::check_urdf_input;
use parol6_hw::frame::{
    COMMAND_FRAME_SIZE, CommandCode, CommandFrame, I24_MAX, I24_MIN, ReceivedCommand, STATUS_FRAME_SIZE, StatusFrame,
};
use parol6_hw::parser::{CommandParser, StatusParser};
use parol6_hw::units::{FW_MAX_SPEED_STEPS_S, STANDBY_STEPS};
use parol6_hw::{ControllerModel, EmulatorConfig};

mod formats;
mod fsio;
mod handshake;
mod mcap_cut;
mod ros2;

pub use formats::{commander, commander_compile, csv_table, csv_table_compile, time_function, time_function_compile};
pub use fsio::atomic_writer;
pub use handshake::foxglove_handshake;
pub use mcap_cut::mcap_cut;
pub use ros2::ros2_cdr;

/// A fuzz target body: arbitrary bytes in, a panic on a broken invariant.
pub type FuzzBody = fn(&[u8]);

/// A fuzz target: its `fuzz/fuzz_targets/<name>.rs`, the folder name of its seeds and corpora
/// (targets that plan what a parser reads share the parser's inputs) and its body.
#[derive(Debug, Clone, Copy)]
pub struct FuzzTarget {
    /// Name of the cargo-fuzz target.
    pub name: &'static str,
    /// Folder of its inputs under `fuzz/seeds`, `fuzz/corpus-min` and `fuzz/regressions`.
    pub corpus: &'static str,
    /// What runs on every input.
    pub body: FuzzBody,
}

const fn target(name: &'static str, body: FuzzBody) -> FuzzTarget {
    FuzzTarget { name, corpus: name, body }
}

/// The fuzz targets whose bodies live here.
pub const TARGETS: [FuzzTarget; 16] = [
    target("status_parser", status_parser),
    target("command_emulator", command_emulator),
    target("urdf_loader", urdf_loader),
    target("program_file", program_file),
    FuzzTarget { name: "program_file_check", corpus: "program_file", body: program_file_check },
    target("gcode", gcode),
    target("csv_table", csv_table),
    FuzzTarget { name: "csv_table_compile", corpus: "csv_table", body: csv_table_compile },
    target("time_function", time_function),
    FuzzTarget { name: "time_function_compile", corpus: "time_function", body: time_function_compile },
    target("commander", commander),
    FuzzTarget { name: "commander_compile", corpus: "commander", body: commander_compile },
    target("atomic_writer", atomic_writer),
    target("mcap_cut", mcap_cut),
    target("ros2_cdr", ros2_cdr),
    target("foxglove_handshake", foxglove_handshake),
];

/// Host side: the streaming status parser and the frame decoders. Every frame the parser
/// returns re-encodes to itself, nothing stays buffered that could still be a frame, and the
/// result does not depend on how the stream is split.
pub fn status_parser(data: &[u8]) {
    let mut p = StatusParser::new();
    for frame in p.feed(data) {
        let bytes = frame.encode();
        assert_eq!(StatusFrame::decode(&bytes).ok(), Some(frame));
    }
    assert!(p.buffered() < STATUS_FRAME_SIZE);
    let split = data.first().map_or(0, |&b| usize::from(b)).min(data.len());
    let mut q = StatusParser::new();
    let mut n = q.feed(&data[..split]).len();
    n += q.feed(&data[split..]).len();
    assert_eq!(n, StatusParser::new().feed(data).len());

    let mut c = CommandParser::new();
    let _ = c.feed(data);
    let _ = StatusFrame::decode(data);
    let _ = ReceivedCommand::decode(data);
    let _ = ReceivedCommand::decode_payload(data);
    if data.len() >= STATUS_FRAME_SIZE {
        let _ = StatusFrame::decode(&data[..STATUS_FRAME_SIZE]);
    }
}

/// Controller side: `data` is the host → controller byte stream. The firmware receiver
/// ([`CommandParser`]) must give the same commands however the stream is cut, count every
/// accepted frame, and read back any known command it accepted when the host encodes it
/// again. Each accepted command then drives the emulated board ([`ControllerModel`]) for a
/// stretch of time taken from the stream, and the board must keep its promises: it echoes
/// the command, mirrors the outputs, clamps JOG / MOVE speeds to the firmware maximum, moves
/// no faster than that, stands still when disabled or not told to move, and sends status
/// frames that decode to themselves.
pub fn command_emulator(data: &[u8]) {
    let commands = CommandParser::new().feed(data);
    let mut bytewise = CommandParser::new();
    let one_by_one: Vec<ReceivedCommand> = data.iter().filter_map(|&b| bytewise.push_byte(b)).collect();
    assert_eq!(one_by_one, commands);
    assert_eq!(bytewise.stats().accepted, commands.len() as u64);
    let split = data.len() / 2;
    let mut halves = CommandParser::new();
    let mut rejoined = halves.feed(&data[..split]);
    rejoined.extend(halves.feed(&data[split..]));
    assert_eq!(rejoined, commands);

    let config = EmulatorConfig {
        start_homed: data.first().is_some_and(|b| b & 1 == 1),
        home_duration_s: 0.05,
        log_commands: false,
        ..EmulatorConfig::default()
    };
    let mut board = ControllerModel::new(config);
    let mut now = Instant::now();
    for (k, cmd) in commands.iter().enumerate() {
        check_host_roundtrip(cmd);
        // Time and pins between frames come from the command itself (deterministic).
        let knob = cmd.fields.timeout;
        board.estop_pressed = knob & 0x80 != 0;
        board.in1 = knob & 0x40 != 0;
        board.in2 = k % 2 == 1;
        now += Duration::from_micros(u64::from(knob) * 997);
        let status = board.accept(*cmd, now);
        assert_eq!(status.echoed_command, cmd.code);
        assert_eq!((status.out1(), status.out2()), (cmd.out1(), cmd.out2()));
        assert_eq!(status.estop_pressed(), board.estop_pressed);
        assert_eq!((status.in1(), status.in2()), (board.in1, board.in2));
        assert_eq!(status, board.status());
        let moving_command = matches!(cmd.command(), Some(CommandCode::Jog) | Some(CommandCode::Move));
        if moving_command && !board.is_homing() {
            let fw_max = FW_MAX_SPEED_STEPS_S;
            if board.is_disabled() {
                assert_eq!(board.speed_steps_s(), [0; JOINT_COUNT]);
            } else {
                assert!(board.speed_steps_s().iter().all(|v| (-fw_max..=fw_max).contains(v)), "{status:?}");
            }
        }
        check_status_roundtrip(&status);

        let dt_s = f64::from(knob & 0x3F) * 0.004;
        let (before, homing_before, homed_before) = (board.position_steps(), board.is_homing(), board.homed());
        board.advance(dt_s);
        let after = board.position_steps();
        if homing_before {
            // Joints hold still during the (compressed) stages; a finished run sets standby.
            assert!(after == before || after == STANDBY_STEPS, "{before:?} -> {after:?}");
            continue;
        }
        assert!(!board.is_homing(), "homing started without a HOME command");
        assert_eq!(board.homed(), homed_before);
        if !moving_command || board.is_disabled() {
            assert_eq!(after, before, "the arm moved without JOG / MOVE");
        } else {
            let max_step = f64::from(FW_MAX_SPEED_STEPS_S) * dt_s + 1.0;
            for (a, b) in after.iter().zip(before) {
                assert!(f64::from((a - b).abs()) <= max_step, "{before:?} -> {after:?} in {dt_s} s");
            }
        }
        check_status_roundtrip(&board.status());
    }
}

/// A known command the firmware accepted, encoded again by the host and parsed again,
/// is the same command.
fn check_host_roundtrip(cmd: &ReceivedCommand) {
    let Some(code) = cmd.command() else { return };
    let frame = CommandFrame { command: code, fields: cmd.fields };
    let bytes: [u8; COMMAND_FRAME_SIZE] = match frame.encode() {
        Ok(b) => b,
        Err(e) => panic!("an accepted command does not encode again: {e} ({cmd:?})"),
    };
    let again = CommandParser::new().feed(&bytes);
    assert_eq!(again.len(), 1);
    assert_eq!((again[0].code, again[0].fields), (cmd.code, cmd.fields));
}

/// A status frame whose counters fit the wire's 24 bits decodes to itself.
fn check_status_roundtrip(status: &StatusFrame) {
    let fits = |v: &i32| (I24_MIN..=I24_MAX).contains(v);
    if status.positions_steps.iter().all(fits) && status.speeds_steps_s.iter().all(fits) {
        assert_eq!(StatusFrame::decode(&status.encode()).ok().as_ref(), Some(status));
    }
}

/// Largest chain the body runs numeric IK and the simulation on (bigger ones only load,
/// run FK, Jacobian and the collision guard, to keep the fuzzer fast).
const MAX_DOF_FOR_IK_AND_SIM: usize = 8;

/// URDF text → [`RobotModel`]: text over the size or nesting bounds is refused with
/// [`ModelError::InputRefused`] before the parser runs; a model that loads has consistent
/// limits and finite kinematics inside them; any IK solution lies within the limits and
/// reaches its target; the collision guard, SRDF pairs and the simulation accept it or report
/// an error. Mesh shapes are dropped before the guard and the simulation so that the body
/// never reads files the input names.
pub fn urdf_loader(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let bounded = check_urdf_input(&text);
    let loaded = RobotModel::from_urdf_str(&text, &LoadOptions::default());
    if let Err(refusal) = bounded {
        assert_eq!(loaded.err(), Some(ModelError::InputRefused(refusal)));
        return;
    }
    let Ok(mut model) = loaded else { return };
    let n = model.dof();
    assert!(n >= 1 && model.limits.len() == n && model.joint_names().len() == n);
    assert!(model.limits.iter().all(|l| l.min <= l.max), "{:?}", model.limits);

    let q = joint_values_within_limits(&model, data);
    assert!(model.limits.check(&q).is_ok(), "{q:?} vs {:?}", model.limits);
    let frames = model.chain_frames(&q);
    assert_eq!(frames.len(), n + 1);
    assert_eq!(model.link_poses(&q).len(), model.links.len());
    let tcp = model.tcp_isometry(&q);
    let _ = model.fk(&q);
    let jac = model.jacobian(&q);
    assert_eq!((jac.nrows(), jac.ncols()), (6, n));
    let _ = model.manipulability(&q);

    for l in &mut model.links {
        l.collisions.retain(|g| !matches!(g.shape, Shape::Mesh { .. }));
        l.visuals.retain(|g| !matches!(g.shape, Shape::Mesh { .. }));
    }
    model.apply_srdf(&text);
    let guard = CollisionGuard::new(&model);
    let _ = guard.check(&model, &q);
    if n > MAX_DOF_FOR_IK_AND_SIM {
        return;
    }
    if let Ok(solutions) = ik::solve(&model, &tcp, &q) {
        let scale = 1.0 + tcp.translation.vector.norm();
        for s in &solutions {
            assert!(model.limits.check(&s.joints_rad).is_ok(), "IK left the limits: {s:?}");
            let (dp, dr) = pose_error(&model.tcp_isometry(&s.joints_rad), &tcp);
            assert!(dp <= 1e-6 * scale && dr <= 1e-6, "IK solution misses by {dp} m / {dr} rad: {s:?}");
        }
    }
    if let Ok(mut sim) = Simulation::new(model, SimConfig::default()) {
        for _ in 0..3 {
            sim.step();
        }
    }
}

/// Joint values inside the model's limits, picked by a hash of `data` (unbounded joints
/// within ±π rad or ±1 m).
fn joint_values_within_limits(model: &RobotModel, data: &[u8]) -> Vec<f64> {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data.iter().take(4096) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    model
        .limits
        .iter()
        .map(|l| {
            h = h.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let u = (h >> 11) as f64 / (1u64 << 53) as f64;
            let lo = if l.min.is_finite() { l.min } else { -std::f64::consts::PI };
            let hi = if l.max.is_finite() { l.max } else { std::f64::consts::PI };
            (lo * (1.0 - u) + hi * u).clamp(l.min, l.max)
        })
        .collect()
}

/// Program files: whatever the bytes, parsing never panics; a file that parses writes back to
/// text that parses to the same steps.
pub fn program_file(data: &[u8]) {
    let _ = program_file_roundtrip(data);
}

/// Program files, checked: a program of up to 6 steps that reads goes through the whole
/// pre-flight from the standby pose, and a report without errors says `ok` (split from
/// [`program_file`] so the reader runs at full fuzzing speed).
pub fn program_file_check(data: &[u8]) {
    use parol6_core::program::check::{CheckOptions, Severity, check_program};
    let Some(program) = program_file_roundtrip(data) else { return };
    if program.steps.len() <= 6 {
        let model = parol6_model();
        let start = parol6_core::motion::home_position(model);
        let report = check_program(model, &program, &start, CheckOptions::default());
        assert_eq!(report.ok, !report.issues.iter().any(|i| i.severity == Severity::Error));
    }
}

/// The program `data` holds, written back and read again to the same steps.
fn program_file_roundtrip(data: &[u8]) -> Option<parol6_core::program::Program> {
    use parol6_core::program::json;
    let text = String::from_utf8_lossy(data);
    let program = json::parse(&text).ok()?;
    let again = match json::parse(&json::to_string(&program)) {
        Ok(p) => p,
        Err(e) => panic!("a parsed program must write back readable: {e}"),
    };
    let steps = |p: &parol6_core::program::Program| p.steps.iter().map(|s| s.step.clone()).collect::<Vec<_>>();
    assert_eq!(steps(&again), steps(&program));
    Some(program)
}

/// The PAROL6 model, loaded once (loading is most of an input's time otherwise).
fn parol6_model() -> &'static RobotModel {
    static MODEL: std::sync::OnceLock<RobotModel> = std::sync::OnceLock::new();
    MODEL.get_or_init(RobotModel::parol6)
}

/// G-code import: any text either reads or gets an error naming a line of it (or the whole
/// file); a program it reads has every step on a line of the text, and when it exports, the
/// G-code written reads back with as many steps or more (arcs outside the three planes become
/// lines).
pub fn gcode(data: &[u8]) {
    use parol6_core::program::gcode::{GcodeExportOptions, GcodeImportOptions, parse_gcode, program_to_gcode};
    static MODEL: std::sync::OnceLock<RobotModel> = std::sync::OnceLock::new();
    let model = MODEL.get_or_init(RobotModel::parol6);
    let start_q = parol6_core::motion::home_position(model);
    let options = GcodeImportOptions::for_model(model, &start_q);
    let text = String::from_utf8_lossy(data);
    let lines = text.split('\n').count();
    let program = match parse_gcode(&text, &options) {
        Ok(p) => p,
        Err(e) => {
            assert!(e.line <= lines, "error on line {} of {lines}: {e}", e.line);
            assert!(!e.message.is_empty());
            return;
        }
    };
    assert!(program.steps.iter().all(|s| (1..=lines).contains(&s.line)));
    let Ok(written) = program_to_gcode(&program, model, &GcodeExportOptions::new(&program, start_q.clone())) else {
        return;
    };
    match parse_gcode(&written, &options) {
        Ok(again) => assert!(again.steps.len() >= program.steps.len(), "{written}"),
        Err(e) => panic!("the G-code written for a program read from G-code must read back: {e}\n{written}"),
    }
}
