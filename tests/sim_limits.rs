//! Property test: over random command streams (targets anywhere, moves, teleports, stops,
//! mode switches, torques, malformed input) no simulated joint leaves its range by more than
//! 1 mrad, in both limit policies.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_core::RobotModel;
use parol6_core::limits::LimitPolicy;
use parol6_core::motion::MotionCommand;
use parol6_core::profile::ProfileKind;
use parol6_core::sim::{SimCommand, SimConfig, SimMode, Simulation};
use proptest::prelude::*;

const TOLERANCE_RAD: f64 = 1e-3;

fn joint_vec() -> impl Strategy<Value = Vec<f64>> {
    // well beyond every PAROL6 range on both sides (J3 reaches 5.02 rad, J6 2π)
    proptest::collection::vec(-7.0f64..7.0, 6)
}

fn command() -> impl Strategy<Value = SimCommand> {
    prop_oneof![
        3 => joint_vec().prop_map(|q| SimCommand::Motion(MotionCommand::follow(q))),
        3 => (joint_vec(), 0.05f64..1.0, any::<bool>()).prop_map(|(goal, f, jerk)| SimCommand::Motion(MotionCommand::MoveJoints {
            goal_rad: goal,
            speed_fraction: f,
            profile: if jerk { ProfileKind::JerkLimited } else { ProfileKind::Trapezoidal },
        })),
        1 => joint_vec().prop_map(SimCommand::Teleport),
        1 => Just(SimCommand::Motion(MotionCommand::Stop)),
        1 => Just(SimCommand::Motion(MotionCommand::home())),
        1 => prop_oneof![Just(SimMode::Kinematic), Just(SimMode::Dynamic)].prop_map(SimCommand::SetMode),
        1 => proptest::collection::vec(-3.0f64..3.0, 6).prop_map(SimCommand::ApplyJointTorques),
        1 => proptest::collection::vec(-7.0f64..7.0, 0..9).prop_map(|q| SimCommand::Motion(MotionCommand::follow(q))),
        1 => Just(SimCommand::Motion(MotionCommand::follow(vec![f64::NAN; 6]))),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn no_joint_exceeds_its_limit(
        cmds in proptest::collection::vec((command(), 1usize..400), 1..12),
        clamp in any::<bool>(),
        dynamic in any::<bool>(),
    ) {
        let model = RobotModel::parol6();
        let config = SimConfig {
            policy: if clamp { LimitPolicy::Clamp } else { LimitPolicy::Reject },
            mode: if dynamic { SimMode::Dynamic } else { SimMode::Kinematic },
            ..SimConfig::default()
        };
        let mut sim = Simulation::new(model.clone(), config).expect("embedded model builds");
        for (cmd, steps) in cmds {
            let _ = sim.apply(cmd);
            for _ in 0..steps {
                sim.step();
                for (i, (l, &v)) in model.limits.iter().zip(sim.q()).enumerate() {
                    prop_assert!(v.is_finite(), "J{} is {v}", i + 1);
                    prop_assert!(v >= l.min - TOLERANCE_RAD && v <= l.max + TOLERANCE_RAD,
                        "J{} at {v} outside [{}, {}] (t = {:.3} s)", i + 1, l.min, l.max, sim.sim_time_s());
                }
            }
        }
    }
}
