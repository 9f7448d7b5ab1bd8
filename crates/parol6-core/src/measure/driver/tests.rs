use super::*;
use crate::measure::plan::PathKind;
use crate::measure::pose_figures;
use crate::measure::{PathTestPlan, TestCube};
use crate::motion::MotionCommand;
use crate::sim::{SimConfig, SimHandle, SimMode};

fn cube() -> TestCube {
    TestCube { center_mm: [0.0, 250.0, 220.0], edge_mm: 60.0, orientation_rpy_deg: [90.0, 0.0, 0.0] }
}

fn sim(tap: Option<crossbeam_channel::Sender<MotionSample>>) -> (RobotModel, Arc<SimHandle>) {
    let model = RobotModel::parol6();
    let config = SimConfig { mode: SimMode::Dynamic, time_scale: 10.0, ..SimConfig::default() };
    let sim = Arc::new(SimHandle::spawn_with_tap(model.clone(), config, tap).expect("sim"));
    (model, sim)
}

#[test]
fn the_pose_test_reads_settled_poses_on_the_simulation() {
    let (model, sim) = sim(None);
    let plan = PoseTestPlan { cycles: 2, speed_fraction: 0.8, settle_s: 0.1, ..PoseTestPlan::new(cube()) };
    let run = start_pose_test(sim.clone(), model, plan).unwrap();
    let samples = run.join().unwrap();
    // every pose of every cycle, in the ISO order
    let order: Vec<(u32, usize)> = samples.iter().map(|s| (s.cycle, s.pose)).collect();
    assert_eq!(order, [(1, 0), (1, 4), (1, 3), (1, 2), (1, 1), (2, 0), (2, 4), (2, 3), (2, 2), (2, 1)]);
    for s in &samples {
        let d = nalgebra::Vector3::from(s.attained.position_mm) - nalgebra::Vector3::from(s.commanded.position_mm);
        assert!(d.norm() < 1.0, "{s:?}: the simulated arm settles within 1 mm");
    }
    let f = pose_figures::compute(&samples).unwrap();
    assert_eq!(f.poses.len(), 5);
    assert!(f.ad_p_mm.unwrap().abs() < 1.0 && f.rd_mm.unwrap() < 1.0, "{f:?}");
    assert!(!sim.state().moving);
}

#[test]
fn an_unreachable_cube_is_refused_before_anything_moves() {
    let (model, sim) = sim(None);
    let before = sim.state().commands_applied;
    let far = TestCube { center_mm: [0.0, 330.0, 250.0], edge_mm: 300.0, ..cube() };
    let run = start_pose_test(sim.clone(), model, PoseTestPlan::new(far)).unwrap();
    let progress = {
        let t0 = Instant::now();
        while !run.progress().is_finished() {
            assert!(t0.elapsed() < Duration::from_secs(20));
            std::thread::sleep(Duration::from_millis(5));
        }
        run.progress()
    };
    let e = run.join().unwrap_err();
    assert!(matches!(e, MeasureError::Plan(PlanError::Refused { .. })), "{e}");
    assert!(matches!(progress.phase, Phase::Failed(ref why) if why.starts_with("pre-flight refuses P")));
    assert_eq!(sim.state().commands_applied, before);
}

#[test]
fn abort_stops_the_arm_and_ends_the_run() {
    let (model, sim) = sim(None);
    let plan = PoseTestPlan { cycles: 30, ..PoseTestPlan::new(cube()) };
    let run = start_pose_test(sim.clone(), model, plan).unwrap();
    let t0 = Instant::now();
    while run.progress().attained.is_empty() {
        assert!(t0.elapsed() < Duration::from_secs(30), "{:?}", run.progress());
        std::thread::sleep(Duration::from_millis(2));
    }
    let p = run.progress();
    assert_eq!((p.phase.clone(), p.cycle, p.cycles), (Phase::Running, 1, 30));
    assert!(p.fraction > 0.0 && p.fraction < 0.1, "{p:?}");
    run.abort();
    assert_eq!(run.join().unwrap_err(), MeasureError::Aborted);
    let t0 = Instant::now();
    while sim.state().moving {
        assert!(t0.elapsed() < Duration::from_secs(5), "the arm stops");
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn a_path_test_records_every_cycle_from_the_tap_or_by_polling() {
    for tapped in [true, false] {
        let (tx, rx) = crossbeam_channel::bounded(1 << 16);
        let (model, sim) = if tapped { sim(Some(tx)) } else { sim(None) };
        let plan =
            PathTestPlan { cycles: 2, points: 20, speed_fraction: 0.8, ..PathTestPlan::new(cube(), PathKind::Line) };
        let run = start_path_test(sim.clone(), model.clone(), plan, tapped.then_some(rx)).unwrap();
        let rec = run.join().unwrap();
        assert_eq!(rec.cycles.len(), 2);
        for c in &rec.cycles {
            assert!(c.len() > 20, "tapped {tapped}: {} samples", c.len());
            assert!(c.first().unwrap().t_s >= 0.0 && c.windows(2).all(|w| w[1].t_s > w[0].t_s));
        }
        let f = rec.figures(&model).unwrap();
        assert!(f.at_p_mm < 2.0 && f.rt_p_mm < 2.0 && f.max_deviation_mm < 3.0, "tapped {tapped}: {f:?}");
        let (commanded, _) = rec.tcp_paths_mm(&model);
        let p = cube().pose_positions_mm();
        let first = nalgebra::Vector3::from(commanded[0]);
        assert!((first - nalgebra::Vector3::from(p[1])).norm() < 0.5, "starts at P2: {first:?}");
    }
}

#[test]
fn an_abort_whose_stop_is_refused_records_it_in_the_progress() {
    let (model, sim) = sim(None);
    let plan = PoseTestPlan { cycles: 30, ..PoseTestPlan::new(cube()) };
    let backend = Arc::new(crate::program::runner::tests::RefusesStop(sim.clone()));
    let run = start_pose_test(backend, model, plan).unwrap();
    let t0 = Instant::now();
    while run.progress().attained.is_empty() {
        assert!(t0.elapsed() < Duration::from_secs(30), "{:?}", run.progress());
        std::thread::sleep(Duration::from_millis(2));
    }
    assert_eq!(run.progress().stop_failed, None);
    run.abort();
    while !run.is_finished() {
        std::thread::sleep(Duration::from_millis(2));
    }
    let p = run.progress();
    assert_eq!(p.phase, Phase::Aborted);
    assert_eq!(p.stop_failed.as_deref(), Some("STOP (the measurement was aborted) failed: the link is down"), "{p:?}");
    assert_eq!(run.join().unwrap_err(), MeasureError::Aborted);
    // the simulation itself still takes a STOP
    RobotBackend::send(sim.as_ref(), MotionCommand::Stop).unwrap();
}
