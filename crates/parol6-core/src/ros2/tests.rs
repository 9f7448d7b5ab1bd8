use proptest::prelude::*;

use super::cdr::{self, CdrError, MAX_MESSAGE_BYTES};
use super::graph::{Attachment, EntityKind, NodeIdentity, Qos, gid, topic_key};
use super::msgs::{
    Duration, Header, JointState, JointTrajectory, JointTrajectoryPoint, StringMsg, TfMessage, Time, TransformStamped,
};
use super::trajectory::{TrajectoryError, plan_trajectory};
use super::{JOINT_STATE, JOINT_TRAJECTORY};
use crate::model::RobotModel;
use crate::telemetry::frames::TfFrames;

fn names() -> Vec<String> {
    ["J1", "J2", "J3", "J4", "J5", "J6"].iter().map(|s| s.to_string()).collect()
}

fn standby() -> Vec<f64> {
    crate::parol6::standby_rad().to_vec()
}

fn point(q: &[f64], t_s: f64) -> JointTrajectoryPoint {
    JointTrajectoryPoint { positions: q.to_vec(), time_from_start: Duration::from_secs_f64(t_s), ..Default::default() }
}

fn trajectory(points: Vec<JointTrajectoryPoint>) -> JointTrajectory {
    JointTrajectory { header: Header::default(), joint_names: names(), points }
}

/// A small move from standby: J1 +0.2 rad in 1 s, then back in 1 s.
fn small_move() -> JointTrajectory {
    let q0 = standby();
    let mut q1 = q0.clone();
    q1[0] += 0.2;
    trajectory(vec![point(&q0, 0.0), point(&q1, 1.0), point(&q0, 2.0)])
}

#[test]
fn a_string_encodes_as_ros_sends_it() {
    let bytes = cdr::encode(&StringMsg { data: "hi".into() }).unwrap();
    assert_eq!(bytes, [0, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0]);
}

#[test]
fn a_joint_state_aligns_its_doubles_to_eight_bytes_of_the_body() {
    let js = JointState::new(Time { sec: 1, nanosec: 2 }, &["a".to_string()], &[1.5], &[0.0], &[]);
    let b = cdr::encode(&js).unwrap();
    // header: sec, nanosec, frame_id "" (count 1, NUL), padding to 4 (body bytes 0–15)
    assert_eq!(&b[4..20], &[1, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]);
    // name: count 1, "a\0" (count 2), padding (body 16–27)
    assert_eq!(&b[20..30], &[1, 0, 0, 0, 2, 0, 0, 0, b'a', 0]);
    // position: count 1 at body byte 28, padding, 1.5 at body byte 32
    assert_eq!(&b[4 + 28..4 + 32], &[1, 0, 0, 0]);
    assert_eq!(&b[4 + 32..4 + 40], &1.5f64.to_le_bytes());
    assert_eq!(cdr::decode::<JointState>(&b).unwrap(), js);
}

#[test]
fn a_big_endian_payload_decodes_too() {
    let mut b = vec![0, 0, 0, 0];
    b.extend_from_slice(&3u32.to_be_bytes());
    b.extend_from_slice(b"ok\0");
    assert_eq!(cdr::decode::<StringMsg>(&b).unwrap().data, "ok");
}

#[test]
fn a_cut_trajectory_names_the_field_and_byte() {
    let b = cdr::encode(&small_move()).unwrap();
    let cut = &b[..b.len() - 6];
    match cdr::decode::<JointTrajectory>(cut) {
        Err(CdrError::Field { field, offset, reason }) => {
            assert_eq!(field, "points[2].time_from_start.sec");
            assert!(offset <= cut.len(), "{offset}");
            assert!(reason.contains("end of input"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_huge_sequence_count_is_refused_without_allocating_it() {
    // header, stamp, frame_id "", joint_names count 0xffff_ffff
    let mut b = vec![0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0];
    b.extend_from_slice(&u32::MAX.to_le_bytes());
    let e = cdr::decode::<JointTrajectory>(&b).unwrap_err();
    assert!(e.to_string().starts_with("field joint_names"), "{e}");
    // a count cap: 65 names of one byte each
    let mut t = small_move();
    t.joint_names = (0..65).map(|i| format!("j{i}")).collect();
    let e = cdr::decode::<JointTrajectory>(&cdr::encode(&t).unwrap()).unwrap_err();
    assert!(e.to_string().contains("more than 64 elements"), "{e}");
}

#[test]
fn headers_sizes_and_trailing_bytes_are_checked() {
    assert_eq!(cdr::decode::<StringMsg>(&[0, 1]), Err(CdrError::NoHeader { len: 2 }));
    assert_eq!(cdr::decode::<StringMsg>(&[0, 7, 0, 0, 1, 0, 0, 0, 0]), Err(CdrError::Encapsulation { id: 7 }));
    let big = vec![0; MAX_MESSAGE_BYTES + 1];
    assert!(matches!(cdr::decode::<StringMsg>(&big), Err(CdrError::TooLarge { .. })));
    let mut b = cdr::encode(&StringMsg { data: "x".into() }).unwrap();
    b.extend_from_slice(&[0; 3]);
    assert!(cdr::decode::<StringMsg>(&b).is_ok(), "padding is accepted");
    b.extend_from_slice(&[0; 16]);
    assert!(matches!(cdr::decode::<StringMsg>(&b), Err(CdrError::Trailing { offset: 10, count: 19 })));
}

#[test]
fn tf_message_carries_the_urdf_joints_transforms() {
    let model = RobotModel::parol6();
    let frames = TfFrames::new(&model, Some(crate::model::PAROL6_URDF));
    let stamp = Time { sec: 5, nanosec: 7 };
    let tfs = frames.transforms(&model, &standby(), crate::telemetry::schema::Time::default());
    let msg = TfMessage::from_frames(&tfs, stamp);
    assert_eq!(msg.transforms.len(), 6);
    let first: &TransformStamped = &msg.transforms[0];
    assert_eq!((first.header.frame_id.as_str(), first.child_frame_id.as_str()), ("base_link", "L1"));
    assert_eq!(first.header.stamp, stamp);
    assert_eq!(cdr::decode::<TfMessage>(&cdr::encode(&msg).unwrap()).unwrap(), msg);
}

#[test]
fn key_expressions_tokens_and_qos_follow_rmw_zenoh() {
    assert_eq!(
        topic_key(0, "/joint_states", &JOINT_STATE),
        "0/joint_states/sensor_msgs::msg::dds_::JointState_/RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e"
    );
    assert_eq!(Qos::reliable(10).token(), "::,10:,:,:,,");
    assert_eq!(Qos::LATCHED.token(), ":1:,1:,:,:,,");
    assert_eq!(Qos { reliable: false, transient_local: false, depth: 42 }.token(), "2::,:,:,:,,");
    let node = NodeIdentity { domain_id: 3, zid: "abc".into(), node_id: 0, name: "parol6".into() };
    assert_eq!(node.node_token(), "@ros2_lv/3/abc/0/0/NN/%/%/parol6");
    let sub = node.topic_token(
        4,
        EntityKind::Subscription,
        "/parol6/joint_trajectory",
        &JOINT_TRAJECTORY,
        &Qos::reliable(10),
    );
    assert_eq!(
        sub,
        format!(
            "@ros2_lv/3/abc/0/4/MS/%/%/parol6/%parol6%joint_trajectory/trajectory_msgs::msg::dds_::JointTrajectory_/{}/::,10:,:,:,,",
            JOINT_TRAJECTORY.hash
        )
    );
    assert_ne!(gid(&sub), gid(&node.node_token()));
}

#[test]
fn the_gid_is_xxh3_128_low_half_first() {
    // XXH3-128 of the empty input is 99aa06d3014798d8_6001c324468d497f
    let g = gid("");
    assert_eq!(&g[..8], &0x6001c324468d497fu64.to_le_bytes());
    assert_eq!(&g[8..], &0x99aa06d3014798d8u64.to_le_bytes());
}

#[test]
fn an_attachment_is_33_bytes_and_reads_back() {
    let a = Attachment { sequence_number: 1, source_timestamp_ns: 1_700_000_000_000_000_000, source_gid: [7; 16] };
    let b = a.to_bytes();
    assert_eq!(b.len(), 33);
    assert_eq!(&b[..8], &[1, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(b[16], 16);
    assert_eq!(Attachment::from_bytes(&b), Some(a));
    assert_eq!(Attachment::from_bytes(&b[..32]), None);
}

#[test]
fn a_valid_trajectory_becomes_timed_joint_moves_and_passes_preflight() {
    let model = RobotModel::parol6();
    let plan = plan_trajectory(&model, &small_move(), &standby()).unwrap();
    assert_eq!(plan.points, 3);
    assert_eq!(plan.duration_s, 2.0);
    assert_eq!(plan.program.steps.len(), 2, "the point at time 0 is the start");
    assert!(plan.report.ok);
    assert!((plan.report.duration_s - 2.0).abs() < 0.05, "{}", plan.report.duration_s);
}

#[test]
fn joint_names_in_another_order_are_reordered() {
    let model = RobotModel::parol6();
    let mut t = small_move();
    t.joint_names.reverse();
    for p in &mut t.points {
        p.positions.reverse();
    }
    let plan = plan_trajectory(&model, &t, &standby()).unwrap();
    let crate::program::Step::MoveJoints { joints_deg, .. } = &plan.program.steps[0].step else { panic!() };
    assert!((joints_deg[0] - (standby()[0] + 0.2).to_degrees()).abs() < 1e-9);
}

#[test]
fn hostile_trajectories_are_refused_with_the_reason() {
    let model = RobotModel::parol6();
    let q = standby();
    let refuse = |t: JointTrajectory| plan_trajectory(&model, &t, &q).unwrap_err().to_string();
    let mut t = small_move();
    t.points[1].positions[2] = f64::NAN;
    assert_eq!(refuse(t), "points[1].positions: value 2 is NaN, not a finite number");
    let mut t = small_move();
    t.points[1].velocities = vec![0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0];
    assert!(refuse(t).starts_with("points[1].velocities: value 1 is inf"));
    let mut t = small_move();
    t.joint_names[5] = "wrist".into();
    assert!(refuse(t).starts_with("joint_names [\"J1\", \"J2\", \"J3\", \"J4\", \"J5\", \"wrist\"] must be exactly"));
    let mut t = small_move();
    t.joint_names[5] = "J1".into();
    assert!(refuse(t).starts_with("joint_names"), "a joint named twice");
    let mut t = small_move();
    t.points[1].positions[1] = 3.0;
    assert!(refuse(t).contains("is above its upper limit"));
    let mut t = small_move();
    t.points[2].time_from_start = t.points[1].time_from_start;
    assert!(refuse(t).starts_with("points[2].time_from_start: 1 s is not after the previous point's 1 s"));
    let mut t = small_move();
    t.points[1].time_from_start = Duration { sec: 0, nanosec: 1_000_000_000 };
    assert!(refuse(t).contains("is not below 10⁹"));
    let mut t = small_move();
    t.points[1].time_from_start = Duration::from_secs_f64(0.01);
    assert!(refuse(t).contains("its speed cap"), "0.2 rad in 10 ms");
    let mut t = small_move();
    t.points[0].positions[0] += 0.1;
    assert!(refuse(t).contains("the point at time 0 must be where the arm is"));
    assert_eq!(refuse(trajectory(vec![])), "the trajectory has no points");
    let mut t = small_move();
    t.points[1].positions.pop();
    assert_eq!(refuse(t), "points[1].positions: 5 values; 6 expected (one per joint)");
}

#[test]
fn a_trajectory_into_the_floor_is_refused_by_the_preflight() {
    let model = RobotModel::parol6();
    let q0 = standby();
    // J2 and J3 folded down: the flange goes below the floor (within the joint limits)
    let mut low = q0.clone();
    low[1] = model.limits.get(1).unwrap().max - 0.05;
    low[2] = model.limits.get(2).unwrap().min + 0.05;
    let t = trajectory(vec![point(&q0, 0.0), point(&low, 6.0)]);
    match plan_trajectory(&model, &t, &q0) {
        Err(TrajectoryError::Preflight(why)) => assert!(!why.is_empty()),
        other => panic!("expected a pre-flight refusal, got {other:?}"),
    }
}

fn finite() -> impl Strategy<Value = f64> {
    -1e6f64..1e6
}

fn arb_trajectory() -> impl Strategy<Value = JointTrajectory> {
    let pt = (
        prop::collection::vec(finite(), 0..7),
        prop::collection::vec(finite(), 0..7),
        any::<i32>(),
        0u32..1_000_000_000,
    )
        .prop_map(|(positions, velocities, sec, nanosec)| JointTrajectoryPoint {
            positions,
            velocities,
            accelerations: vec![],
            effort: vec![],
            time_from_start: Duration { sec, nanosec },
        });
    (any::<i32>(), "[a-z_/]{0,12}", prop::collection::vec("[A-Za-z0-9_]{0,8}", 0..7), prop::collection::vec(pt, 0..6))
        .prop_map(|(sec, frame_id, joint_names, points)| JointTrajectory {
            header: Header { stamp: Time { sec, nanosec: 0 }, frame_id },
            joint_names,
            points,
        })
}

proptest! {
    #[test]
    fn trajectories_round_trip(t in arb_trajectory()) {
        prop_assert_eq!(cdr::decode::<JointTrajectory>(&cdr::encode(&t).unwrap()).unwrap(), t);
    }

    #[test]
    fn joint_states_round_trip(q in prop::collection::vec(finite(), 6), sec in any::<i32>(), nanosec in 0u32..1_000_000_000) {
        let js = JointState::new(Time { sec, nanosec }, &names(), &q, &q, &[]);
        prop_assert_eq!(cdr::decode::<JointState>(&cdr::encode(&js).unwrap()).unwrap(), js);
    }

    #[test]
    fn hostile_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let mut b = vec![0, 1, 0, 0];
        b.extend_from_slice(&bytes);
        for payload in [&bytes[..], &b[..]] {
            if let Ok(t) = cdr::decode::<JointTrajectory>(payload) {
                let _ = plan_trajectory(&RobotModel::parol6(), &t, &standby());
            }
            let _ = cdr::decode::<JointState>(payload);
            let _ = cdr::decode::<TfMessage>(payload);
            let _ = cdr::decode::<StringMsg>(payload);
        }
    }

    #[test]
    fn mutated_trajectories_decode_or_name_the_field(t in arb_trajectory(), at in any::<prop::sample::Index>(), byte in any::<u8>()) {
        let mut b = cdr::encode(&t).unwrap();
        let i = at.index(b.len());
        b[i] = byte;
        match cdr::decode::<JointTrajectory>(&b) {
            Ok(_) => {}
            Err(CdrError::Field { offset, .. }) => prop_assert!(offset <= b.len()),
            Err(CdrError::Encapsulation { .. } | CdrError::Trailing { .. }) => {}
            Err(e) => prop_assert!(false, "{e}"),
        }
    }
}
