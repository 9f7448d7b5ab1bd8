//! Fuzz bodies of the program exchange formats: point tables (`csv_table`), time-function
//! expressions (`time_function`) and PAROL commander programs (`commander`). Whatever the
//! bytes, nothing panics; what reads writes back and reads again to the same steps; small
//! programs are compiled (steps → joint trajectories) by the `_compile` targets of the tables
//! and commander programs, and by `time_function` itself.

use std::sync::OnceLock;

use parol6_core::model::RobotModel;
use parol6_core::program::compile::{CompileOptions, StepAction, compile};
use parol6_core::program::timefn::{TimeFunction, TimePiece};
use parol6_core::program::{PoseMm, Program, Step, commander, table};

/// Joints (deg) compiling starts from: the Draw demo's first pose.
const START_DEG: [f64; 6] = [90.0, -80.0, 170.0, 0.0, 60.0, 180.0];

/// The PAROL6 model, loaded once (loading it is most of an input's time otherwise).
fn model() -> &'static RobotModel {
    static MODEL: OnceLock<RobotModel> = OnceLock::new();
    MODEL.get_or_init(RobotModel::parol6)
}

/// Compiles `program` at the pre-flight period: no panic, and every motion starts where the
/// one before ends and stays inside the joint limits. (The checks after compiling are fuzzed
/// by `program_file`.)
fn compiles(program: &Program) {
    let model = model();
    let start: Vec<f64> = START_DEG.iter().map(|d| d.to_radians()).collect();
    let Ok(compiled) = compile(model, program, &start, CompileOptions::PREFLIGHT) else { return };
    let mut q = start;
    for c in &compiled {
        if let StepAction::Motion(t) = &c.action {
            assert_eq!(t.samples().first(), Some(&q), "{}: starts where the last motion ended", c.kind);
            assert!(t.samples().iter().all(|s| s.iter().all(|v| v.is_finite())), "{}: finite joints", c.kind);
            q = t.goal().to_vec();
        }
    }
}

/// Point tables: a table that reads writes back (every step is a row) and reads again to the
/// same steps and the same text; tables of up to 3 rows are compiled.
pub fn csv_table(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(program) = table::parse_csv_table(&text) else { return };
    let written = match table::program_to_csv(&program) {
        Ok(t) => t,
        Err(e) => panic!("a table that reads must write back: {e}"),
    };
    let again = match table::parse_csv_table(&written) {
        Ok(p) => p,
        Err(e) => panic!("a written table must read back: {e}\n{written}"),
    };
    let steps = |p: &Program| p.steps.iter().map(|s| s.step.clone()).collect::<Vec<_>>();
    // rx/ry/rz tables are written as roll/pitch/yaw: compare from the second reading on
    assert_eq!(table::program_to_csv(&again).ok().as_deref(), Some(written.as_str()));
    if !text.contains("rx_deg") {
        assert_eq!(steps(&again), steps(&program));
    }
}

/// Point tables, planned: a table of up to 3 rows that reads is compiled. (Split from
/// [`csv_table`] so the reader runs at full fuzzing speed; planning a Cartesian row near a
/// singularity takes up to a second.)
pub fn csv_table_compile(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(program) = table::parse_csv_table(&text) else { return };
    if program.steps.len() <= 3 {
        compiles(&program);
    }
}

/// Time functions: the input's lines are the expressions x, y, z (and roll, pitch, yaw when
/// there are six); its first byte picks the duration. Parsing and sampling never panic; a
/// function that samples starts where asked, ends at its duration and moves forward in time.
pub fn time_function(data: &[u8]) {
    let _ = sampled_time_function(data);
}

/// Time functions, planned: a function that samples, moved to start at the TCP, is compiled
/// (split from [`time_function`] for the same reason as [`csv_table_compile`]).
pub fn time_function_compile(data: &[u8]) {
    let Some((piece, at_tcp)) = sampled_time_function(data) else { return };
    let mut moved = piece;
    [moved.x_mm, moved.y_mm, moved.z_mm] = at_tcp;
    moved.roll_deg = None;
    moved.pitch_deg = None;
    moved.yaw_deg = None;
    compiles(&Program::from_steps("fuzz", vec![Step::TimeFunction { sample_rate_hz: 20.0, pieces: vec![moved] }]));
}

/// The time function of `data`, checked as [`time_function`] says, and its x, y, z
/// expressions moved to start at the TCP of the start pose.
fn sampled_time_function(data: &[u8]) -> Option<(TimePiece, [String; 3])> {
    let (&first, rest) = data.split_first()?;
    let text = String::from_utf8_lossy(rest);
    let lines: Vec<&str> = text.split('\n').collect();
    let at = |i: usize| lines.get(i).copied().unwrap_or("0").to_string();
    let duration_s = 0.05 + f64::from(first % 16) * 0.1;
    let mut piece = TimePiece::position(duration_s, &at(0), &at(1), &at(2));
    if lines.len() >= 6 {
        piece.roll_deg = Some(at(3));
        piece.pitch_deg = Some(at(4));
        piece.yaw_deg = Some(at(5));
    }
    let function = TimeFunction::new(std::slice::from_ref(&piece), 20.0).ok()?;
    let start_q: Vec<f64> = START_DEG.iter().map(|d| d.to_radians()).collect();
    let here = model().tcp_isometry(&start_q);
    let points = function.sample(&here).ok()?;
    assert!(points.windows(2).all(|w| w[1].0 > w[0].0), "time moves forward");
    assert_eq!(points.first().map(|p| p.0), Some(0.0));
    assert!(points.last().is_some_and(|p| (p.0 - duration_s).abs() < 1e-9));
    let tcp = PoseMm::from_isometry(&here).position_mm;
    let p0 = points[0].1.translation.vector * 1000.0;
    let shifted: [String; 3] = std::array::from_fn(|k| format!("({}) + ({})", at(k), tcp[k] - p0[k]));
    Some((piece, shifted))
}

/// Commander programs: a program that reads and writes back reads again to the same steps
/// within the 3 decimals export writes (poses: ≤ 0.005 mm with the lever between the
/// commander's frame and the flange, ≤ 1e-4 rad; joints, offsets and times ≤ 0.0005), and
/// writing that again gives the same text where the numbers are of a size whose 3 decimals an
/// `f64` holds; programs of up to 3 steps are compiled.
pub fn commander(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(program) = commander::parse_commander(&text) else { return };
    let Ok(written) = commander::program_to_commander(&program) else { return };
    let again = match commander::parse_commander(&written) {
        Ok(p) => p,
        Err(e) => panic!("a written program must read back: {e}\n{written}"),
    };
    assert_eq!(again.looping, program.looping);
    assert_eq!(again.steps.len(), program.steps.len());
    // rounding to 3 decimals, and the float error of numbers far from 0
    let near = |x: f64, y: f64, tol: f64| (x - y).abs() <= tol + 1e-9 * x.abs().max(y.abs());
    let all_near =
        |x: &[f64], y: &[f64], tol: f64| x.len() == y.len() && x.iter().zip(y).all(|(a, b)| near(*a, *b, tol));
    let mut small = true;
    for (a, b) in program.steps.iter().zip(&again.steps) {
        match (&a.step, &b.step) {
            (Step::MovePose { pose: x, .. }, Step::MovePose { pose: y, .. })
            | (Step::MoveL { pose: x, .. }, Step::MoveL { pose: y, .. }) => {
                assert!(all_near(&x.position_mm, &y.position_mm, 0.005), "{x:?} vs {y:?}");
                let turn = x.isometry().rotation.angle_to(&y.isometry().rotation);
                assert!(turn < 1e-4, "orientation changed by {turn} rad: {x:?} vs {y:?}");
                small &= x.position_mm.iter().all(|v| v.abs() < 1e6);
            }
            (
                Step::MoveJoints { joints_deg: x, duration_s: dx, .. },
                Step::MoveJoints { joints_deg: y, duration_s: dy, .. },
            ) => {
                assert!(all_near(x, y, 0.0005), "{x:?} vs {y:?}");
                assert!(dx.is_some() == dy.is_some() && near(dx.unwrap_or(0.0), dy.unwrap_or(0.0), 0.0005));
                small &= x.iter().all(|v| v.abs() < 1e6);
            }
            (
                Step::MoveRelTool { offset_mm: x, rotation_deg: rx, .. },
                Step::MoveRelTool { offset_mm: y, rotation_deg: ry, .. },
            ) => {
                assert!(all_near(x, y, 0.005) && all_near(rx, ry, 0.0005), "{x:?} {rx:?} vs {y:?} {ry:?}");
                small &= x.iter().chain(rx).all(|v| v.abs() < 1e6);
            }
            (x, y) => assert_eq!(x.kind(), y.kind()),
        }
    }
    if small {
        let twice = match commander::program_to_commander(&again) {
            Ok(t) => t,
            Err(e) => panic!("a program read back must write again: {e}\n{written}"),
        };
        assert_eq!(twice, written, "writing again changed the text");
    }
}

/// Commander programs, planned: a program of up to 3 steps that reads is compiled (split from
/// [`commander`](fn@commander) for the same reason as [`csv_table_compile`]).
pub fn commander_compile(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(program) = commander::parse_commander(&text) else { return };
    if program.steps.len() <= 3 {
        compiles(&program);
    }
}
