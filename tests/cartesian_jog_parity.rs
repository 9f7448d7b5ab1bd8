//! Issue 10 (Cartesian jog): a Cartesian jog and a Cartesian step, submitted through
//! `RobotBackend::submit` at exact motion-clock times, give the same commanded joint
//! trajectory on the simulation and on the serial session driving the firmware emulator, and
//! the jog is a straight TCP line on both.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::collections::BTreeMap;
use std::time::Duration;

use crossbeam_channel::Receiver;
use parol6_core::RobotModel;
use parol6_core::motion::{CartesianAxis, JogFrame, MotionCommand, MotionSample, RobotBackend};
use parol6_core::profile::ProfileKind;
use parol6_core::sim::{SimCommand, SimConfig, SimHandle};
use parol6_hw::session::{Session, SessionConfig};
use parol6_hw::units::{STANDBY_STEPS, joints_steps_to_rad};
use parol6_hw::{EmulatorConfig, EmulatorHandle};

const LONG: Duration = Duration::from_secs(10);
/// Length of the script, s.
const SCRIPT_S: f64 = 6.0;
/// When the jog starts and ends (released), s after t0.
const JOG_S: (f64, f64) = (2.5, 3.7);

/// The script: a move off the standby wrist singularity, a held world +X jog released after
/// 1.2 s, then a 2.5 mm tool −Z step.
fn script(q0: &[f64]) -> Vec<(f64, MotionCommand)> {
    let offset = |d: [f64; 6]| q0.iter().zip(d).map(|(q, d)| q + d).collect::<Vec<_>>();
    let mut s = vec![(
        0.0,
        MotionCommand::MoveJoints {
            goal_rad: offset([0.0, 0.2, -0.3, 0.0, 0.6, 0.0]),
            speed_fraction: 0.8,
            profile: ProfileKind::Trapezoidal,
        },
    )];
    let mut t = JOG_S.0;
    while t < JOG_S.1 - 1e-9 {
        s.push((t, MotionCommand::JogCartesian { frame: JogFrame::World, axis: CartesianAxis::X, fraction: 0.4 }));
        t += 0.1;
    }
    s.push((JOG_S.1, MotionCommand::JogRelease));
    s.push((
        4.0,
        MotionCommand::CartesianStep {
            frame: JogFrame::Tool,
            axis: CartesianAxis::Z,
            distance: -0.0025,
            speed_fraction: 0.5,
        },
    ));
    s
}

fn t0_ms(backend: &dyn RobotBackend) -> i64 {
    ((backend.state().time_s + 0.5) * 100.0).ceil() as i64 * 10
}

fn collect(rx: &Receiver<MotionSample>, t0_ms: i64) -> BTreeMap<i64, MotionSample> {
    rx.try_iter()
        .filter_map(|s| {
            let ms = (s.time_s * 1000.0).round() as i64 - t0_ms;
            (0..=(SCRIPT_S * 1000.0) as i64).contains(&ms).then_some((ms, s))
        })
        .collect()
}

#[test]
fn a_cartesian_jog_gives_the_same_commanded_trajectory_on_sim_and_robot() {
    let model = RobotModel::parol6();
    let q0 = joints_steps_to_rad(&STANDBY_STEPS).to_vec();

    let (sim_tx, sim_rx) = crossbeam_channel::bounded(100_000);
    let sim = SimHandle::spawn_with_tap(model.clone(), SimConfig::default(), Some(sim_tx)).expect("sim");
    sim.send(SimCommand::Teleport(q0.clone())).expect("teleport");
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let (hw_tx, hw_rx) = crossbeam_channel::bounded(100_000);
    let cfg = SessionConfig { status_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Session::open_with_tap(emu.path(), cfg, Some(hw_tx)).expect("session");
    session.wait_until(LONG, |s| s.status_frames >= 10).expect("status");
    std::thread::sleep(Duration::from_millis(50));

    let (sim_t0, hw_t0) = (t0_ms(&sim), t0_ms(&session));
    for (backend, t0) in [(&sim as &dyn RobotBackend, sim_t0), (&session as &dyn RobotBackend, hw_t0)] {
        for (dt, cmd) in script(&q0) {
            backend.submit(cmd, Some(t0 as f64 / 1000.0 + dt)).expect("scheduled");
        }
    }
    std::thread::sleep(Duration::from_secs_f64(SCRIPT_S + 1.0));
    assert!(session.state().last_refusal.is_none(), "{:?}", session.state().last_refusal);
    assert!(sim.state().last_refusal.is_none(), "{:?}", sim.state().last_refusal);
    assert_eq!(session.snapshot().link_losses, 0, "{:?}", session.snapshot().fault);

    let (a, b) = (collect(&sim_rx, sim_t0), collect(&hw_rx, hw_t0));
    let mut compared = 0;
    let mut jog_tcp = Vec::new();
    for ms in (0..=(SCRIPT_S * 1000.0) as i64).step_by(10) {
        let (Some(x), Some(y)) = (a.get(&ms), b.get(&ms)) else { continue };
        compared += 1;
        for j in 0..6 {
            let d = (x.commanded.q[j] - y.commanded.q[j]).abs();
            assert!(d <= 1e-9, "J{} commanded differs by {d:e} rad at t0 + {ms} ms", j + 1);
        }
        let t = ms as f64 / 1000.0;
        if t >= JOG_S.0 && t <= JOG_S.1 {
            jog_tcp.push(model.tcp_isometry(&y.commanded.q));
        }
    }
    assert!(compared > 450, "only {compared} common time stamps (sim {}, robot {})", a.len(), b.len());
    // the jog: a straight +X line of the commanded TCP, about 1.2 s × 64.6 mm/s long
    let (first, last) = (jog_tcp.first().expect("jog"), jog_tcp.last().expect("jog"));
    let d = last.translation.vector - first.translation.vector;
    assert!(d.x > 0.05, "jogged {:.1} mm along X", d.x * 1e3);
    for p in &jog_tcp {
        let e = p.translation.vector - first.translation.vector;
        assert!(e.y.hypot(e.z) < 0.05e-3, "{:.4} mm off the X line", e.y.hypot(e.z) * 1e3);
    }
    // the step: the end pose is exactly 2.5 mm along the tool −Z of the pose before it
    let before = model.tcp_isometry(&b[&3900].commanded.q);
    let end = model.tcp_isometry(&b.values().last().expect("end").commanded.q);
    let want = before.translation.vector - before.rotation * nalgebra_z() * 0.0025;
    assert!((end.translation.vector - want).norm() < 1e-6, "step ended {:?} off", end.translation.vector - want);
    eprintln!("Cartesian jog parity: {compared} common time stamps, jog {:.1} mm along +X", d.x * 1e3);
}

fn nalgebra_z() -> parol6_core::na::Vector3<f64> {
    parol6_core::na::Vector3::z()
}
