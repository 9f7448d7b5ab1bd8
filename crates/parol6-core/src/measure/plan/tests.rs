use super::*;
use crate::measure::cube::CYCLE_ORDER;
use crate::motion::home_position;
use crate::program::compile::{CompileOptions, compile};

/// A cube the PAROL6 reaches from standby, tool horizontal.
pub(crate) fn reachable_cube() -> TestCube {
    TestCube { center_mm: [0.0, 250.0, 220.0], edge_mm: 60.0, orientation_rpy_deg: [90.0, 0.0, 0.0] }
}

#[test]
fn a_reachable_cube_passes_pre_flight_for_every_test() {
    let model = RobotModel::parol6();
    let start = home_position(&model);
    let plan = PoseTestPlan::new(reachable_cube());
    plan.preflight(&model, &start).unwrap();
    for kind in PathKind::ALL {
        PathTestPlan::new(reachable_cube(), kind).preflight(&model, &start).unwrap_or_else(|e| panic!("{kind:?}: {e}"));
    }
}

#[test]
fn an_unreachable_pose_is_named() {
    let model = RobotModel::parol6();
    // the far upper corner out of reach: P4 (and P5) are beyond the arm
    let far = TestCube { center_mm: [0.0, 330.0, 250.0], edge_mm: 300.0, ..reachable_cube() };
    let e = PoseTestPlan::new(far).preflight(&model, &home_position(&model)).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, PlanError::Refused { .. }), "{text}");
    assert!(text.starts_with("pre-flight refuses P") && text.contains(" at (") && text.contains("mm: "), "{text}");
    let e = PathTestPlan::new(far, PathKind::Circle).preflight(&model, &home_position(&model)).unwrap_err();
    assert!(e.to_string().starts_with("pre-flight refuses the circle path"), "{e}");
}

#[test]
fn bad_settings_are_refused() {
    let model = RobotModel::parol6();
    let start = home_position(&model);
    let plan = PoseTestPlan { cycles: 1, ..PoseTestPlan::new(reachable_cube()) };
    assert_eq!(plan.preflight(&model, &start).unwrap_err().to_string(), "cycles must be 2…1000, got 1");
    let plan = PoseTestPlan { speed_fraction: 2.0, ..PoseTestPlan::new(reachable_cube()) };
    assert!(plan.preflight(&model, &start).unwrap_err().to_string().contains("speed must be 0.01…1"));
    let bad = TestCube { edge_mm: -1.0, ..reachable_cube() };
    assert!(matches!(PoseTestPlan::new(bad).preflight(&model, &start), Err(PlanError::Cube(_))));
    let path = PathTestPlan { points: 1, ..PathTestPlan::new(reachable_cube(), PathKind::Line) };
    assert!(path.preflight(&model, &start).unwrap_err().to_string().contains("points"));
}

#[test]
fn the_pose_cycle_visits_p2_then_the_iso_order() {
    let plan = PoseTestPlan::new(reachable_cube());
    let poses = plan.cube.poses();
    let visited: Vec<PoseMm> = plan
        .cycle_program()
        .steps
        .iter()
        .map(|s| match &s.step {
            Step::MovePose { pose, .. } => *pose,
            other => panic!("{other:?}"),
        })
        .collect();
    let want: Vec<PoseMm> = std::iter::once(1).chain(CYCLE_ORDER).map(|i| poses[i]).collect();
    assert_eq!(visited, want);
    assert_eq!(CYCLE_ORDER, [0, 4, 3, 2, 1]);
}

#[test]
fn paths_lie_in_the_diagonal_plane_and_close_where_they_start() {
    let model = RobotModel::parol6();
    let cube = reachable_cube();
    let [_, _, n] = TestCube::plane_axes();
    for kind in PathKind::ALL {
        let plan = PathTestPlan::new(cube, kind);
        let approach = compile(&model, &plan.approach(), &home_position(&model), CompileOptions::PREFLIGHT).unwrap();
        let start_q = approach.last().unwrap().end_q.clone();
        let compiled = compile(&model, &plan.cycle(), &start_q, CompileOptions::PREFLIGHT).unwrap();
        for c in &compiled {
            let crate::program::compile::StepAction::Motion(t) = &c.action else { panic!() };
            for s in t.samples() {
                let p = model.tcp_isometry(s).translation.vector * 1000.0;
                let off = (p - nalgebra::Vector3::from(cube.center_mm)).dot(&n);
                assert!(off.abs() < 0.05, "{kind:?}: {off} mm off the plane");
            }
        }
        let end = model.tcp_isometry(&compiled.last().unwrap().end_q).translation.vector * 1000.0;
        let start = nalgebra::Vector3::from(plan.start().position_mm);
        let want_end = match kind {
            PathKind::Line => nalgebra::Vector3::from(cube.pose_positions_mm()[3]),
            _ => start,
        };
        assert!((end - want_end).norm() < 0.01, "{kind:?}: ends at {end:?}");
    }
    // the line is P2 → P4; the triangle's legs are 0.8 × the edge with the right angle first
    let tri = PathTestPlan::new(cube, PathKind::Triangle).corners_mm();
    let v = |i: usize| nalgebra::Vector3::from(tri[i]);
    assert!(((v(1) - v(0)).norm() - 48.0).abs() < 1e-9 && ((v(2) - v(0)).norm() - 48.0).abs() < 1e-9);
    assert!((v(1) - v(0)).dot(&(v(2) - v(0))).abs() < 1e-9);
    // the triangle is traced as a time function of three pieces, like the LabVIEW GUI's
    let cycle = PathTestPlan::new(cube, PathKind::Triangle).cycle();
    assert!(
        matches!(&cycle.steps[0].step, crate::program::Step::TimeFunction { pieces, .. } if pieces.len() == 3),
        "{:?}",
        cycle.steps[0].step.kind()
    );
    assert_eq!(PathTestPlan::new(cube, PathKind::Line).tcp_speed_mm_s(), 100.0);
}
