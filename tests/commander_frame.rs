//! Commander poses are read in the commander's frame: a pose the PAROL commander GUI shows for
//! some joints, written as `MoveCart`, is the TCP pose of those joints here, and as `MovePose`
//! its nearest IK solution is those joints; `MoveCartRelTRF` ends where the commander's does.
//!
//! The commander's pose is computed here with this file's own FK of the commander's DH table
//! (standard DH, no joint offsets, θᵢ = the software joint angle), its parameters restated
//! from `GUI/files/PAROL6_ROBOT.py` of PCrnjak/PAROL-commander-software (the same in every
//! version of its history):
//!
//! | i | d (mm) | a (mm) | α |
//! |---|---|---|---|
//! | 1 | 110.5 | 23.42 | −π/2 |
//! | 2 | 0 | 180 | π |
//! | 3 | 0 | −43.5 | π/2 |
//! | 4 | −176.35 | 0 | −π/2 |
//! | 5 | 0 | 0 | π/2 |
//! | 6 | −62.8 | −45.25 | π |
//!
//! Its readout is `x, y, z` in mm and `rx, ry, rz` with `R = Rx(rz)·Ry(ry)·Rz(rx)`, each
//! rounded to 3 decimals; the angles are taken out of the matrix here by hand.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::f64::consts::{FRAC_PI_2, PI};

use parol6_core::na::{Isometry3, Matrix4, Rotation3, Translation3, UnitQuaternion, Vector3};
use parol6_core::program::check::{CheckOptions, check_program};
use parol6_core::program::commander::{CommanderOptions, parse_commander_with};
use parol6_core::program::{Program, Step};
use parol6_core::{RobotModel, Tool, ik};
use proptest::prelude::*;

/// (d mm, a mm, α rad) per joint.
const DH: [(f64, f64, f64); 6] = [
    (110.5, 23.42, -FRAC_PI_2),
    (0.0, 180.0, PI),
    (0.0, -43.5, FRAC_PI_2),
    (-176.35, 0.0, -FRAC_PI_2),
    (0.0, 0.0, FRAC_PI_2),
    (-62.8, -45.25, PI),
];

/// The commander's frame 6 for joints in degrees (metres).
fn dh_fk(q_deg: &[f64]) -> Matrix4<f64> {
    let mut t = Matrix4::identity();
    for (q, (d, a, alpha)) in q_deg.iter().zip(DH) {
        let (st, ct) = q.to_radians().sin_cos();
        let (sa, ca) = alpha.sin_cos();
        #[rustfmt::skip]
        let link = Matrix4::new(
            ct, -st * ca, st * sa, a / 1000.0 * ct,
            st, ct * ca, -ct * sa, a / 1000.0 * st,
            0.0, sa, ca, d / 1000.0,
            0.0, 0.0, 0.0, 1.0,
        );
        t *= link;
    }
    t
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0 + 0.0
}

/// What the commander shows for `q_deg`: x, y, z (mm), rx, ry, rz (deg), 3 decimals.
fn shown(q_deg: &[f64]) -> [f64; 6] {
    unrounded(q_deg).map(round3)
}

/// The commander's pose for `q_deg` at full precision.
fn unrounded(q_deg: &[f64]) -> [f64; 6] {
    let t = dh_fk(q_deg);
    // R = Rx(c)·Ry(b)·Rz(a): R[0][2] = sin b, R[0][0..2] = cos b (cos a, −sin a), R[1..3][2] = cos b (−sin c, cos c)
    let b = t[(0, 2)].clamp(-1.0, 1.0).asin();
    let a = (-t[(0, 1)]).atan2(t[(0, 0)]);
    let c = (-t[(1, 2)]).atan2(t[(2, 2)]);
    [t[(0, 3)] * 1000.0, t[(1, 3)] * 1000.0, t[(2, 3)] * 1000.0, a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

fn text(v: &[f64]) -> String {
    v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(",")
}

fn rad(q_deg: &[f64]) -> Vec<f64> {
    q_deg.iter().map(|d| d.to_radians()).collect()
}

fn model_with(tool: Tool) -> RobotModel {
    let mut m = RobotModel::parol6();
    m.set_tool(tool);
    m
}

/// Position (mm) and orientation (deg) differences.
fn diff(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let (dp, dr) = ik::pose_error(a, b);
    (dp * 1000.0, dr.to_degrees())
}

/// `MoveJoint(q)` then `MoveCart(pose)` / `MovePose(pose)` read for `model`'s tool.
fn read_program(model: &RobotModel, q_deg: &[f64], command: &str, pose: &[f64; 6]) -> Program {
    let src = format!("Begin()\nMoveJoint({})\n{command}({},t=2)\nEnd()\n", text(q_deg), text(pose));
    parse_commander_with(&src, &CommanderOptions::for_model(model)).expect("reads")
}

fn target(program: &Program) -> Isometry3<f64> {
    match &program.steps[1].step {
        Step::MoveL { pose, .. } | Step::MovePose { pose, .. } => pose.isometry(),
        other => panic!("{other:?}"),
    }
}

/// The shown pose as `MoveCart` is the TCP pose of `q` (every tool, ≤ 0.01 mm, ≤ 0.01°); as
/// `MovePose` the IK solution nearest `q` has that pose, and is `q` (≤ 0.01° per joint) wherever
/// the arm is not near a singular pose. Near one, the readout's rounding (≤ 0.0005 mm / °) and
/// the 0.7 µm by which the two tables' shoulder offsets differ move the joints by more, and
/// only the pose is compared. Both as shown (3 decimals) and at full precision.
fn assert_reaches(q_deg: &[f64], within_limits: bool) -> Result<(), TestCaseError> {
    for tool in Tool::ALL {
        let model = model_with(tool);
        let q = rad(q_deg);
        let want = model.tcp_isometry(&q);
        let (dp, dr) = diff(&target(&read_program(&model, q_deg, "MoveCart", &shown(q_deg))), &want);
        prop_assert!(dp <= 0.01 && dr <= 0.01, "{q_deg:?} {tool:?}: MoveCart {dp} mm {dr}°");
        // the smallest singular value of the Jacobian (m or rad per rad): away from singular
        // poses a pose error of 0.001 mm / 0.001° moves the joints by well under 0.01°
        let sigma_min = model.jacobian(&q).svd(false, false).singular_values.min();
        for pose in [shown(q_deg), unrounded(q_deg)] {
            let target_pose = target(&read_program(&model, q_deg, "MovePose", &pose));
            let (dp, dr) = diff(&target_pose, &want);
            prop_assert!(dp <= 0.01 && dr <= 0.01, "{q_deg:?} {tool:?}: MovePose {dp} mm {dr}°");
            if !within_limits {
                continue;
            }
            let solutions = match ik::solve_parol6(&model, &target_pose, &q) {
                Ok(s) => s,
                // near a singular pose the readout's rounding (≤ 0.0005°) can swing the wrist's
                // J4/J6 split past a limit: the pose as shown has no solution within the limits
                Err(ik::IkError::NoSolutionWithinLimits { .. }) if sigma_min < 0.02 && pose == shown(q_deg) => {
                    continue;
                }
                Err(e) => return Err(TestCaseError::fail(format!("{q_deg:?} {tool:?}: {pose:?} unreachable: {e}"))),
            };
            let best = &solutions[0].joints_rad;
            let (dp, dr) = diff(&model.tcp_isometry(best), &want);
            prop_assert!(dp <= 0.01 && dr <= 0.01, "{q_deg:?} {tool:?}: IK {dp} mm {dr}°");
            if sigma_min >= 0.02 {
                let worst = best.iter().zip(&q).map(|(a, b)| (a - b).abs().to_degrees()).fold(0.0, f64::max);
                prop_assert!(worst <= 0.01, "{q_deg:?} {tool:?}: IK nearest {best:?} is {worst}° away");
            }
        }
    }
    Ok(())
}

#[test]
fn dh_table_and_transform_match_the_reference_vectors() {
    let Some(dir) = parol6_tests::shared_dir() else { return };
    let doc = parol6_tests::read_json(&dir.join("vectors/fk_poses.json"));
    let model = RobotModel::parol6();
    let vectors = doc["vectors"].as_array().expect("vectors");
    assert!(vectors.len() >= 4);
    let k = parol6_core::frames::commander_frame_in_flange().to_homogeneous();
    for v in vectors {
        let q_deg: Vec<f64> = v["joint_deg"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let dh = dh_fk(&q_deg);
        let flange = model.flange_pose(&rad(&q_deg)).to_homogeneous();
        for r in 0..3 {
            for c in 0..4 {
                let want = v["commander_dh_frame6_pose"][r][c].as_f64().unwrap();
                assert!((dh[(r, c)] - want).abs() <= 1e-6, "{}: DH [{r}][{c}] {} vs {want}", v["name"], dh[(r, c)]);
            }
        }
        let between = flange.try_inverse().unwrap() * dh;
        assert!((between - k).abs().max() <= 1e-6, "{}: inv(L6)·DH6 {between} vs {k}", v["name"]);
        let within = model.limits.check(&rad(&q_deg)).is_ok();
        assert_reaches(&q_deg, within).unwrap();
    }
}

#[test]
fn the_issue_example_is_a_no_op() {
    // the commander shows (0, 262.57, 288.75, -90, 0, -90) at standby
    assert_eq!(shown(&[90.0, -90.0, 180.0, 0.0, 0.0, 180.0]), [0.0, 262.57, 288.75, -90.0, 0.0, -90.0]);
    let src = "Begin()\nMoveJoint(90,-90,180,0,0,180)\nMoveCart(0,262.57,288.75,-90,0,-90)\nEnd()\n";
    for tool in Tool::ALL {
        let model = model_with(tool);
        let program = parse_commander_with(src, &CommanderOptions::for_model(&model)).unwrap();
        let standby = rad(&[90.0, -90.0, 180.0, 0.0, 0.0, 180.0]);
        let (dp, dr) = diff(&target(&program), &model.tcp_isometry(&standby));
        assert!(dp <= 0.01 && dr <= 0.01, "{tool:?}: {dp} mm {dr}°");
    }
}

#[test]
fn a_shown_pose_as_move_cart_passes_check_as_a_no_op() {
    // away from the standby wrist singularity, where a line of no length is still a line
    let q_deg = [90.0, -80.0, 170.0, 0.0, 60.0, 180.0];
    for tool in Tool::ALL {
        let model = model_with(tool);
        let program = read_program(&model, &q_deg, "MoveCart", &shown(&q_deg));
        let report = check_program(&model, &program, &rad(&q_deg), CheckOptions::default());
        assert_eq!(report.first_error(), None, "{tool:?}");
    }
}

/// Our TCP after `move_rel_tool`: `start · Trans(offset) · Rx·Ry·Rz`.
fn tool_move(start: &Isometry3<f64>, offset_mm: [f64; 3], rotation_deg: [f64; 3]) -> Isometry3<f64> {
    let [a, b, c] = rotation_deg.map(f64::to_radians);
    let r = Rotation3::from_axis_angle(&Vector3::x_axis(), a)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
        * Rotation3::from_axis_angle(&Vector3::z_axis(), c);
    start
        * Isometry3::from_parts(
            Translation3::from(Vector3::from(offset_mm) / 1000.0),
            UnitQuaternion::from_rotation_matrix(&r),
        )
}

fn joints() -> impl Strategy<Value = Vec<f64>> {
    let model = RobotModel::parol6();
    let ranges: Vec<_> = model.limits.iter().map(|l| (l.min.to_degrees() + 0.5)..(l.max.to_degrees() - 0.5)).collect();
    ranges
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// What the commander shows for random joints reaches those joints.
    #[test]
    fn shown_poses_reach_their_joints(q_deg in joints()) {
        assert_reaches(&q_deg, true)?;
    }

    /// `MoveCartRelTRF` ends at the flange pose the commander's move ends at, every tool: the
    /// commander's frame goes to `DH6 · Trans(d) · Rx(a)·Ry(b)·Rz(c)`.
    #[test]
    fn relative_tool_moves_end_where_the_commanders_do(
        q_deg in joints(),
        d in proptest::array::uniform3(-80_000i32..80_000),
        r in proptest::array::uniform3(-90_000i32..90_000),
    ) {
        let v: Vec<f64> = d.iter().chain(&r).map(|x| f64::from(*x) / 1000.0).collect();
        let src = format!("Begin()\nMoveCartRelTRF({},t=2)\nEnd()\n", text(&v));
        let dh = dh_fk(&q_deg);
        let q = rad(&q_deg);
        // the commander's target, and the flange pose under it (the constant between the two
        // chains taken from this joint vector itself)
        let dh_iso = Isometry3::from_parts(
            Translation3::new(dh[(0, 3)], dh[(1, 3)], dh[(2, 3)]),
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(dh.fixed_view::<3, 3>(0, 0).into_owned())),
        );
        let model = RobotModel::parol6();
        let between = model.flange_pose(&q).inverse() * dh_iso;
        let goal_dh = tool_move(&dh_iso, [v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let goal_flange = goal_dh * between.inverse();
        for tool in Tool::ALL {
            let model = model_with(tool);
            let program = parse_commander_with(&src, &CommanderOptions::for_model(&model)).unwrap();
            let Step::MoveRelTool { offset_mm, rotation_deg, .. } = &program.steps[0].step else {
                panic!("{:?}", program.steps[0]);
            };
            let ours = tool_move(&model.tcp_isometry(&q), *offset_mm, *rotation_deg);
            let want = goal_flange * model.tool;
            let (dp, dr) = diff(&ours, &want);
            prop_assert!(dp <= 0.005 && dr <= 1e-4, "{tool:?}: {dp} mm {dr}°");
        }
    }
}

/// A pose the proptest found (CI, 2026-11-26): J5 at −89.17°, where the wrist is near singular
/// (σ_min < 0.02); the shown pose, rounded to 0.001°, then has no IK solution within the limits
/// for any tool, while the pose at full precision is reached.
#[test]
fn a_shown_pose_near_a_singular_wrist_may_leave_the_limits() {
    let q_deg = [
        -120.02831783325023,
        -141.4084384336969,
        256.3913400708493,
        19.101198051224056,
        -89.16535244917392,
        185.26011523549568,
    ];
    let model = model_with(Tool::Ssg48);
    let q = rad(&q_deg);
    assert!(model.jacobian(&q).svd(false, false).singular_values.min() < 0.02);
    let exact = target(&read_program(&model, &q_deg, "MovePose", &unrounded(&q_deg)));
    assert!(ik::solve_parol6(&model, &exact, &q).is_ok());
    assert_reaches(&q_deg, true).unwrap();
}

/// Regression (CI): joints at full stretch with the wrist singular. The commander's pose of
/// them at full precision lay 0.2 µm beyond our reach, and IK refused it.
#[test]
fn a_commander_pose_at_full_stretch_reaches_its_joints() {
    assert_reaches(&[0.0, -112.03894939811698, 256.21922221893874, 0.0, 0.0, 0.497193125], true).unwrap();
}
