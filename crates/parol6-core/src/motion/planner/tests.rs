use super::*;
use crate::model::RobotModel;
use crate::motion::{MotionCaps, home_position};
use crate::profile::ProfileKind;
use proptest::prelude::*;

fn planner() -> MotionPlanner {
    let model = RobotModel::parol6();
    let home = home_position(&model);
    MotionPlanner::new(model.limits.clone(), MotionCaps::of(&model), home.clone(), &home)
}

fn mv(goal: Vec<f64>) -> MotionCommand {
    MotionCommand::MoveJoints { goal_rad: goal, speed_fraction: 0.5, profile: ProfileKind::Trapezoidal }
}

/// Samples a scheduled script at `rate_hz` until `end_s`; returns (t, q) pairs.
fn run_script(script: &[(f64, MotionCommand)], rate_hz: f64, end_s: f64) -> Vec<(f64, Vec<f64>)> {
    let mut p = planner();
    for (t, c) in script {
        p.schedule(c.clone(), *t).expect("valid script");
    }
    let n = (end_s * rate_hz).round() as u64;
    (0..=n)
        .map(|k| {
            let t = k as f64 / rate_hz;
            (t, p.sample(t).q)
        })
        .collect()
}

#[test]
fn the_trajectory_does_not_depend_on_the_sampling_rate() {
    let home = crate::parol6::standby_rad().to_vec();
    let mut a = home.clone();
    a[0] += 0.4;
    let mut b = home.clone();
    b[1] -= 0.3;
    b[4] += 0.5;
    let script = vec![
        (0.05, MotionCommand::Follow { target_rad: a, speed_fraction: 1.0 }),
        (1.0, mv(b)),
        (1.5, MotionCommand::Stop),
        (1.8, MotionCommand::Home { speed_fraction: 0.8, profile: ProfileKind::JerkLimited }),
        (4.0, MotionCommand::JogJoint { joint: 2, fraction: -0.5 }),
        (4.1, MotionCommand::JogJoint { joint: 2, fraction: -0.5 }),
    ];
    let fast = run_script(&script, 1000.0, 5.0);
    let slow = run_script(&script, 100.0, 5.0);
    for (t, q) in &slow {
        let k = (t * 1000.0).round() as usize;
        let (tf, qf) = &fast[k];
        assert!((t - tf).abs() < 1e-12);
        for (x, y) in q.iter().zip(qf) {
            assert!((x - y).abs() <= 1e-9, "at t = {t}: {q:?} vs {qf:?}");
        }
    }
}

#[test]
fn out_of_limit_targets_are_refused_naming_the_joint() {
    let mut p = planner();
    let mut bad = crate::parol6::standby_rad().to_vec();
    bad[1] = 3.0;
    let e = p.apply(&mv(bad), 0.0).expect_err("refused");
    assert!(e.to_string().contains("joint 2"), "{e}");
    assert_eq!(p.mode(), PlannerMode::Hold);
}

#[test]
fn a_jog_stops_at_the_limit_and_after_the_deadman() {
    let mut p = planner();
    p.apply(&MotionCommand::JogJoint { joint: 0, fraction: 1.0 }, 0.0).expect("jog");
    let q = p.sample(0.1).q[0];
    assert!(q > crate::parol6::standby_rad()[0]);
    // not refreshed: stops at DEADMAN_S
    let held = p.sample(1.0).q[0];
    let at_deadman = p.setpoint_at(DEADMAN_S).q[0];
    assert!((held - at_deadman).abs() < 1e-12);
    assert_eq!(p.mode(), PlannerMode::Hold);
    // refreshed long enough it stops exactly at the limit
    let lim = p.limits().get(0).expect("J1").max;
    for k in 0..200 {
        p.apply(&MotionCommand::JogJoint { joint: 0, fraction: 1.0 }, 1.0 + k as f64 * 0.1).expect("jog");
    }
    assert!((p.sample(21.0).q[0] - lim).abs() < 1e-12);
    // at the limit, jogging further out is refused, back in is allowed
    p.sample(30.0);
    assert!(p.apply(&MotionCommand::JogJoint { joint: 0, fraction: 1.0 }, 30.0).is_err());
    p.apply(&MotionCommand::JogJoint { joint: 0, fraction: -1.0 }, 30.0).expect("back inside");
    assert!(p.sample(30.1).q[0] < lim);
}

/// The jog-at-limit rule is one function (`jog_refusal`), which the planner applies and the
/// serial session asks before queueing (it had its own copy, without the limit's angle).
#[test]
fn the_jog_at_a_limit_rule_refuses_outward_only() {
    let limits = RobotModel::parol6().limits.clone();
    let j2 = limits.get(1).expect("J2").clone();
    let mut q = crate::parol6::standby_rad().to_vec();
    assert_eq!(jog_refusal(&limits, &q, 1, 1.0), None, "inside: both ways");
    assert_eq!(jog_refusal(&limits, &q, 1, -1.0), None);
    for (at, outward) in [(j2.max, 1.0), (j2.max + 0.01, 1.0), (j2.min, -1.0), (j2.min - 0.01, -1.0)] {
        q[1] = at;
        let why = jog_refusal(&limits, &q, 1, outward).expect("outward from a limit is refused");
        assert!(why.contains("joint 2") && why.contains("jog the other way") && why.contains('°'), "{why}");
        assert_eq!(jog_refusal(&limits, &q, 1, -outward), None, "back inside is allowed");
        assert_eq!(jog_refusal(&limits, &q, 1, 0.0), None, "no motion is no jog");
    }
    assert_eq!(jog_refusal(&limits, &q, 9, 1.0), None, "no such joint: the command's own check refuses it");
}

#[test]
fn motion_from_beyond_a_limit_back_inside_is_allowed() {
    let mut p = planner();
    let mut outside = crate::parol6::standby_rad().to_vec();
    outside[1] = p.limits().get(1).expect("J2").min - 0.01;
    p.reset(&outside);
    p.apply(&mv(crate::parol6::standby_rad().to_vec()), 0.0).expect("move back inside");
    p.reset(&outside);
    p.apply(&MotionCommand::JogJoint { joint: 1, fraction: 0.3 }, 0.0).expect("jog back inside");
    assert!(p.apply(&MotionCommand::JogJoint { joint: 1, fraction: -0.3 }, 0.0).is_err());
}

#[test]
fn an_immediate_stop_drops_scheduled_commands_a_scheduled_one_does_not() {
    let mut p = planner();
    let mut a = crate::parol6::standby_rad().to_vec();
    a[0] += 0.2;
    p.schedule(MotionCommand::Stop, 1.0).expect("stop");
    p.schedule(mv(a.clone()), 2.0).expect("move");
    p.sample(1.5);
    assert_eq!(p.pending(), 1);
    p.apply(&MotionCommand::Stop, 1.6).expect("stop");
    assert_eq!(p.pending(), 0);
}

#[test]
fn a_refused_scheduled_command_is_reported() {
    let mut p = planner();
    let lim = p.limits().get(0).expect("J1").max;
    let mut at = crate::parol6::standby_rad().to_vec();
    at[0] = lim;
    p.reset(&at);
    p.schedule(MotionCommand::JogJoint { joint: 0, fraction: 1.0 }, 0.5).expect("scheduled");
    p.sample(1.0);
    let (id, msg) = p.last_refusal().expect("refusal").clone();
    assert_eq!(id, 1);
    assert!(msg.contains("upper limit"), "{msg}");
}

/// A planner holding a pose clear of the wrist singularity at t1 = 10 s, and a planned line of
/// `dx_m` along +X from there (the model, the planner, the line's start TCP, the trajectory).
fn line_from_rest(
    dx_m: f64,
) -> (RobotModel, MotionPlanner, nalgebra::Isometry3<f64>, Arc<crate::motion::trajectory::SampledTrajectory>) {
    use crate::motion::cartesian::{CartesianCaps, plan};
    use crate::motion::path::TcpPath;
    let model = RobotModel::parol6();
    let mut p = planner();
    let mut q0 = crate::parol6::standby_rad().to_vec();
    q0[4] = 0.6;
    p.apply(&mv(q0.clone()), 0.0).expect("move");
    p.sample(10.0);
    let a = model.tcp_isometry(&q0);
    let mut b = a;
    b.translation.vector.x += dx_m;
    let traj = plan(&model, &q0, &TcpPath::line(&a, &b), &CartesianCaps::default(), p.caps(), 1.0, 0.001)
        .expect("plans")
        .trajectory;
    (model, p, a, traj)
}

#[test]
fn a_planned_cartesian_trajectory_is_followed_and_must_start_where_the_arm_is() {
    let (model, mut p, a, traj) = line_from_rest(0.04);
    let t1 = 10.0;
    let end = traj.goal().to_vec();
    let d = traj.duration_s();
    p.apply(&MotionCommand::Trajectory(traj.clone()), t1).expect("starts where the arm is");
    assert_eq!(p.mode(), PlannerMode::Trajectory);
    let mid = p.sample(t1 + d / 2.0).q;
    assert!((model.tcp_isometry(&mid).translation.y - a.translation.y).abs() < 1e-6);
    assert_eq!(p.sample(t1 + d + 0.01).q, end);
    assert_eq!(p.mode(), PlannerMode::Hold);
    // now the arm is at the end: the same trajectory no longer starts here
    let e = p.apply(&MotionCommand::Trajectory(traj), t1 + d + 0.02).expect_err("gap");
    assert!(e.to_string().contains("away from the commanded position"), "{e}");
}

/// Regression: on a busy machine the first step of a program reached the simulation 37–87 ms
/// after its scheduled time, so it started late, and the next step, scheduled for when the
/// first should have ended, was refused with only "starts 0.03° away". The refusal now says
/// that the running trajectory ends later and why.
#[test]
fn a_continuation_refused_because_the_running_trajectory_started_late_says_so() {
    let (_, mut p, _, traj) = line_from_rest(0.04);
    let d = traj.duration_s();
    let back: Vec<Vec<f64>> = traj.samples().iter().rev().cloned().collect();
    let back = Arc::new(crate::motion::trajectory::SampledTrajectory::new(traj.dt_s(), back));
    // planned to start at 10.00 s, applied at 10.037 s
    p.apply(&MotionCommand::Trajectory(traj), 10.037).expect("starts where the arm is");
    let e = p.apply(&MotionCommand::Trajectory(back.clone()), 10.0 + d).expect_err("too early");
    let msg = e.to_string();
    assert!(msg.contains("away from the commanded position"), "{msg}");
    assert!(msg.contains("ends 37 ms later") && msg.contains("started late"), "{msg}");
    // on time it continues
    p.apply(&MotionCommand::Trajectory(back), 10.037 + d).expect("continues at the end");
}

/// A pause slows a trajectory to a stop on its path within the acceleration caps; a resume
/// finishes it at its goal; the pair costs exactly the ramp time.
#[test]
fn a_paused_trajectory_stops_on_its_path_and_resumes_to_its_goal() {
    let (model, mut p, a, traj) = line_from_rest(0.08);
    let t1 = 10.0;
    let d = traj.duration_s();
    p.apply(&MotionCommand::Trajectory(traj.clone()), t1).expect("starts");
    let t_pause = t1 + d * 0.4;
    p.sample(t_pause);
    p.apply(&MotionCommand::Pause, t_pause).expect("pause");
    assert_eq!(p.mode(), PlannerMode::Paused);
    let caps = p.caps().clone();
    let mut t = t_pause;
    let mut prev = p.sample(t);
    let mut stopped_at = None;
    while t < t_pause + 3.0 {
        t += 0.001;
        let sp = p.sample(t);
        // on the line
        let tcp = model.tcp_isometry(&sp.q);
        assert!(
            (tcp.translation.y - a.translation.y).abs() < 0.05e-3
                && (tcp.translation.z - a.translation.z).abs() < 0.05e-3
        );
        for j in 0..6 {
            assert!(sp.qd[j].abs() <= caps.speed_rad_s[j] * 1.0001);
            assert!(((sp.qd[j] - prev.qd[j]) / 0.001).abs() <= caps.accel_rad_s2[j] * 1.01, "joint {j} at {t}");
        }
        if stopped_at.is_none() && !p.is_moving(t) {
            stopped_at = Some(t);
        }
        prev = sp;
    }
    let stopped_at = stopped_at.expect("the pause stops the arm");
    assert!(p.sample(t).q != traj.goal().to_vec(), "paused before the end");
    assert_eq!(p.sample(t).q, p.sample(t + 5.0).q, "holds while paused");
    let t_resume = t_pause + 5.0;
    p.apply(&MotionCommand::Resume, t_resume).expect("resume");
    assert_eq!(p.mode(), PlannerMode::Trajectory);
    // the stop took one ramp and covered half a ramp of path time; the resume ramp covers the
    // other half, so the rest of the path ends as if it had never paused from the resume on
    assert!(stopped_at - t_pause >= super::super::warp::MIN_RAMP_S - 0.002);
    let end = t_resume + (d - (t_pause - t1));
    assert!(p.is_moving(end - 0.01));
    assert_eq!(p.sample(end + 0.002).q, traj.goal().to_vec());
    assert_eq!(p.mode(), PlannerMode::Hold);
}

#[test]
fn pause_outside_a_trajectory_holds_and_resume_without_a_pause_does_nothing() {
    let mut p = planner();
    let mut goal = home_position(&RobotModel::parol6());
    goal[0] += 0.5;
    p.apply(&mv(goal.clone()), 0.0).expect("move");
    p.sample(0.3);
    p.apply(&MotionCommand::Pause, 0.3).expect("pause");
    assert_eq!(p.mode(), PlannerMode::Hold);
    let held = p.sample(0.4).q;
    p.apply(&MotionCommand::Resume, 0.5).expect("resume");
    assert_eq!(p.sample(1.0).q, held);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Whatever the commands, the commanded trajectory stays within the limits and never
    /// moves a joint faster than its speed cap.
    #[test]
    fn commanded_motion_respects_limits_and_speed(
        cmds in proptest::collection::vec((0u8..5, 0usize..6, -1.5f64..1.5, 0.05f64..1.0, 0.0f64..0.6), 1..12)
    ) {
        let mut p = planner();
        let caps = p.caps().clone();
        let limits = p.limits().clone();
        let mut t = 0.0;
        let mut prev = p.sample(0.0).q;
        let dt = 0.001;
        for (kind, joint, delta, frac, wait) in cmds {
            let here = p.setpoint_at(t).q;
            let mut goal = here.clone();
            goal[joint] = limits.get(joint).map_or(goal[joint], |l| l.clamp(goal[joint] + delta));
            let cmd = match kind {
                0 => MotionCommand::Follow { target_rad: goal, speed_fraction: frac },
                1 => mv(goal),
                2 => MotionCommand::JogJoint { joint, fraction: delta.clamp(-1.0, 1.0) },
                3 => MotionCommand::Stop,
                _ => MotionCommand::Home { speed_fraction: frac, profile: ProfileKind::JerkLimited },
            };
            let _ = p.apply(&cmd, t);
            let steps = (wait / dt) as usize;
            for _ in 0..steps {
                t += dt;
                let q = p.sample(t).q;
                for i in 0..q.len() {
                    let l = limits.get(i).expect("joint");
                    prop_assert!(l.contains(q[i]), "joint {} at {} outside", i + 1, q[i]);
                    prop_assert!((q[i] - prev[i]).abs() <= caps.speed_rad_s[i] * dt * (1.0 + 1e-9) + 1e-12);
                }
                prev = q;
            }
        }
    }
}

/// Issue 28: a scheduled trajectory that arrives after its time starts when it arrives, and
/// the schedule slips as a whole: the continuation scheduled for when the late one should have
/// ended starts when it does end (exactly where it ends), and a command after a gap keeps its
/// distance. STOP drops the schedule and its delay.
#[test]
fn a_late_step_slips_the_whole_schedule_and_the_continuation_starts_at_its_end() {
    let (_, mut p, _, traj) = line_from_rest(0.04);
    let d = traj.duration_s();
    let back: Vec<Vec<f64>> = traj.samples().iter().rev().cloned().collect();
    let back = Arc::new(crate::motion::trajectory::SampledTrajectory::new(traj.dt_s(), back));
    let start = traj.samples()[0].clone();
    // planned 10.00 s, arrives at 10.037 s; the return is planned for 10 + d, then a hold 0.5 s
    // after it ends
    p.sample(10.037);
    p.note_scheduled();
    p.schedule_arriving(MotionCommand::Trajectory(traj.clone()), 10.0, 10.037).expect("valid");
    p.note_scheduled();
    p.schedule_arriving(MotionCommand::Trajectory(back.clone()), 10.0 + d, 10.037).expect("valid");
    p.note_scheduled();
    p.schedule_arriving(mv(start.clone()), 10.0 + 2.0 * d + 0.5, 10.037).expect("valid");
    let state = p.schedule_state();
    assert_eq!(state.received, 3);
    assert!((state.delay_s - 0.037).abs() < 1e-12, "{state:?}");
    let mut t = 10.037;
    let mut prev = p.sample(t).q;
    let mut max_step: f64 = 0.0;
    while t < 10.037 + 2.0 * d + 0.6 {
        t += 0.001;
        let q = p.sample(t).q;
        max_step = q.iter().zip(&prev).map(|(a, b)| (a - b).abs()).fold(max_step, f64::max);
        prev = q;
    }
    assert!(p.last_refusal().is_none(), "{:?}", p.last_refusal());
    assert_eq!(p.applied(), 1 + 3, "the move of `line_from_rest`, then all three");
    assert!(max_step < 0.01, "no jump: {max_step} rad in 1 ms");
    assert_eq!(p.sample(t).q, start, "back at the start");
    assert!((p.schedule_state().delay_s - 0.037).abs() < 1e-9, "{:?}", p.schedule_state());
    // a continuation that falls due while the running one still runs waits for its end
    p.apply(&MotionCommand::Trajectory(traj.clone()), t).expect("starts here");
    p.schedule(MotionCommand::Trajectory(back), t + d / 2.0 - 0.037).expect("valid");
    let mid = p.sample(t + d / 2.0).q;
    assert_ne!(mid, traj.goal(), "still on the first line");
    assert_eq!(p.mode(), PlannerMode::Trajectory);
    assert!(p.pending() == 1 && p.last_refusal().is_none());
    assert_eq!(p.sample(t + 2.0 * d + 0.01).q, start, "then back, without a refusal");
    assert!(p.last_refusal().is_none(), "{:?}", p.last_refusal());
    assert!((p.schedule_state().delay_s - (0.037 + d / 2.0)).abs() < 1e-6, "{:?}", p.schedule_state());
    // STOP drops the delay
    p.apply(&MotionCommand::Stop, t + 3.0 * d).expect("stop");
    assert_eq!(p.schedule_state().delay_s, 0.0);
}
