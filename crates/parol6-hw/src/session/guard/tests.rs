use proptest::prelude::*;

use super::*;
use crate::units::STANDBY_STEPS;

const PERIOD_S: f64 = 0.01;

#[test]
fn guard_refuses_out_of_limit_placeholders_and_speeds() {
    let mut f = CommandFrame::new(CommandCode::Idle);
    f.fields.positions_steps = STANDBY_STEPS;
    assert_eq!(guard_frame(&mut f, None, PERIOD_S), Ok(0));
    f.fields.positions_steps[2] = 0; // J3 min is 34700
    assert!(matches!(guard_frame(&mut f, None, PERIOD_S), Err(GuardViolation::Position { joint: 3, .. })));
    f.fields.positions_steps = STANDBY_STEPS;
    f.fields.speeds_steps_s[3] = 10_001;
    assert!(matches!(guard_frame(&mut f, None, PERIOD_S), Err(GuardViolation::Speed { joint: 4, .. })));
}

#[test]
fn guard_clamps_the_step_to_the_speed_limit_from_the_previous_target() {
    let mut f = CommandFrame::new(CommandCode::Move);
    f.fields.positions_steps = STANDBY_STEPS;
    f.fields.positions_steps[0] -= 5000;
    f.fields.positions_steps[3] -= 5000;
    assert_eq!(guard_frame(&mut f, Some((&STANDBY_STEPS, 1)), PERIOD_S), Ok(2));
    // J1 15 000 steps/s × 10 ms + 1 = 151 steps; J4 10 000 → 101.
    assert_eq!(f.fields.positions_steps[0], STANDBY_STEPS[0] - 151);
    assert_eq!(f.fields.positions_steps[3], STANDBY_STEPS[3] - 101);
    // Two periods since the last MOVE target: twice the reach.
    let mut f = CommandFrame::new(CommandCode::Move);
    f.fields.positions_steps = STANDBY_STEPS;
    f.fields.positions_steps[0] -= 5000;
    guard_frame(&mut f, Some((&STANDBY_STEPS, 2)), PERIOD_S).unwrap();
    assert_eq!(f.fields.positions_steps[0], STANDBY_STEPS[0] - 301);
    let mut f = CommandFrame::new(CommandCode::Move);
    assert_eq!(guard_frame(&mut f, None, PERIOD_S), Err(GuardViolation::NoReference));
}

/// Issue 29 item 11: a board reporting positions outside the step limits got MOVE targets
/// outside them ("hold where you are", J1 = 100 000). The guard, the last line, refuses every
/// target outside the limits, whatever the previous target was; one beyond a limit cannot be
/// followed by a MOVE at all.
#[test]
fn guard_refuses_every_target_outside_the_step_limits() {
    let mut f = CommandFrame::new(CommandCode::Move);
    let mut prev = STANDBY_STEPS;
    prev[0] = 13_990;
    f.fields.positions_steps = prev;
    f.fields.positions_steps[0] = 14_000;
    assert_eq!(guard_frame(&mut f, Some((&prev, 1)), PERIOD_S), Ok(0));
    f.fields.positions_steps[0] = 14_100;
    assert!(matches!(
        guard_frame(&mut f, Some((&prev, 1)), PERIOD_S),
        Err(GuardViolation::Target { joint: 1, steps: 14_100, .. })
    ));
    // Holding where a lying board says the arm is: refused.
    prev[0] = 100_000;
    prev[2] = -200_000;
    f.fields.positions_steps = prev;
    assert!(matches!(guard_frame(&mut f, Some((&prev, 1)), PERIOD_S), Err(GuardViolation::Target { joint: 1, .. })));
    // A little beyond (moved there by hand): holding there is refused too, and so is a jump
    // back inside faster than the speed limit.
    let mut prev = STANDBY_STEPS;
    prev[0] = 14_050;
    f.fields.positions_steps = prev;
    assert!(guard_frame(&mut f, Some((&prev, 1)), PERIOD_S).is_err());
    prev[0] = 14_500;
    f.fields.positions_steps = STANDBY_STEPS;
    f.fields.positions_steps[0] = 13_999;
    assert!(guard_frame(&mut f, Some((&prev, 1)), PERIOD_S).is_err(), "no target within reach");
    assert_eq!(allowed_target_range(0, 14_500, PERIOD_S, 1), (14_349, 14_000));
}

#[test]
fn limit_breaches_tell_a_pushed_arm_from_an_impossible_answer() {
    assert_eq!(limit_breach(&STANDBY_STEPS), None);
    let mut m = STANDBY_STEPS;
    m[0] = 14_050;
    let b = limit_breach(&m).unwrap();
    assert_eq!((b.joint, b.beyond_steps(), b.impossible, b.above()), (1, 50, false, true));
    assert!(b.to_string().contains("50 steps (0.4°) beyond its upper limit 14000"), "{b}");
    m[2] = -200_000;
    let b = limit_breach(&m).unwrap();
    assert_eq!((b.joint, b.impossible), (3, true), "the impossible one first");
    assert!(b.to_string().contains("J3 reads -200000 steps"), "{b}");
}

#[test]
fn placeholder_positions_stay_in_limits() {
    let p = placeholder_positions(Some(&[0; JOINT_COUNT]));
    let lim = limits_steps();
    for i in 0..JOINT_COUNT {
        assert!((lim[i].0..=lim[i].1).contains(&p[i]));
    }
}

/// Regression: "a single bit error in one status frame makes a joint that is not being moved
/// twitch at 3× its speed limit" — the flipped measurement is rejected.
/// Regression (long adversarial run): a burst of stale status frames, held by a stalled link
/// and delivered at once, showed the arm at rest where it had been; motion started from there
/// and commanded a joint nobody moved back by 3 steps.
#[test]
fn a_late_burst_of_identical_frames_is_not_an_arm_at_rest() {
    let mut f = PlausibilityFilter::default();
    let old = STANDBY_STEPS;
    for _ in 0..4 {
        assert_eq!(f.check(&old, 1.0, PERIOD_S), Plausibility::Accepted);
    }
    assert!(f.confirmed());
    assert!(!f.steady(), "four frames read at the same instant are one observation");
    assert_eq!(f.check(&old, 1.0 + PERIOD_S, PERIOD_S), Plausibility::Accepted);
    assert!(!f.steady());
    assert_eq!(f.check(&old, 1.0 + 2.0 * PERIOD_S, PERIOD_S), Plausibility::Accepted);
    assert!(f.steady(), "three reads a period apart show the arm at rest");
    let mut moved = old;
    moved[0] += 3;
    assert_eq!(f.check(&moved, 1.0 + 3.0 * PERIOD_S, PERIOD_S), Plausibility::Accepted);
    assert!(!f.steady());
}

#[test]
fn a_single_bit_error_in_one_status_frame_is_implausible() {
    let mut f = PlausibilityFilter::default();
    let mut m = STANDBY_STEPS;
    assert_eq!(f.check(&m, 0.0, PERIOD_S), Plausibility::Accepted);
    m[3] += 80; // J4 jogging
    assert_eq!(f.check(&m, 0.01, PERIOD_S), Plausibility::Accepted);
    let mut bad = m;
    bad[0] ^= 1 << 11;
    assert!(matches!(f.check(&bad, 0.02, PERIOD_S), Plausibility::Implausible { joint: 0, in_a_row: 1, .. }));
    assert_eq!(f.reference(), Some(&m), "never used");
    m[3] += 80;
    assert_eq!(f.check(&m, 0.03, PERIOD_S), Plausibility::Accepted);
}

#[test]
fn implausible_frames_count_in_a_row_and_time_widens_the_bound() {
    let mut f = PlausibilityFilter::default();
    f.accept(&STANDBY_STEPS, 0.0);
    let mut far = STANDBY_STEPS;
    far[1] += 20_000;
    for n in 1..=5 {
        assert!(
            matches!(f.check(&far, 0.01 * f64::from(n), PERIOD_S), Plausibility::Implausible { in_a_row, .. } if in_a_row == n)
        );
    }
    // A second later the joint could have got there.
    assert_eq!(f.check(&far, 1.0, PERIOD_S), Plausibility::Accepted);
}

#[test]
fn disagreement_needs_both_size_and_time() {
    let mut d = DisagreementMonitor::default();
    let c = STANDBY_STEPS;
    let mut m = STANDBY_STEPS;
    m[2] += 2500;
    assert_eq!(d.check(&c, &m, 0.0, 2000, 0.5), None);
    assert_eq!(d.check(&c, &m, 0.4, 2000, 0.5), None);
    assert_eq!(d.check(&c, &m, 0.6, 2000, 0.5), Some((2, 2500)));
    m[2] = c[2] + 100;
    assert_eq!(d.check(&c, &m, 0.7, 2000, 0.5), None);
}

proptest! {
    /// Whatever targets the planner (or a bug) produces: a frame with a target outside the step
    /// limits is refused; every MOVE target the guard passes lies within the step limits and
    /// within the speed limit × elapsed periods (+1) of the previous target.
    #[test]
    fn guarded_targets_never_exceed_limits_or_speed(
        start in proptest::array::uniform6(-100_000i32..100_000),
        targets in proptest::collection::vec(proptest::array::uniform6(-9_000_000i32..9_000_000), 1..40),
        gaps in proptest::collection::vec(1u32..4, 40),
    ) {
        let lim = limits_steps();
        let mut prev: [i32; JOINT_COUNT] = std::array::from_fn(|i| start[i].clamp(lim[i].0, lim[i].1));
        for (k, t) in targets.iter().enumerate() {
            let periods = gaps[k];
            let mut f = CommandFrame::new(CommandCode::Move);
            f.fields.positions_steps = *t;
            let outside = (0..JOINT_COUNT).any(|i| !(lim[i].0..=lim[i].1).contains(&t[i]));
            let guarded = guard_frame(&mut f, Some((&prev, periods)), PERIOD_S);
            prop_assert_eq!(guarded.is_err(), outside);
            if outside {
                continue;
            }
            for i in 0..JOINT_COUNT {
                let p = f.fields.positions_steps[i];
                prop_assert!((lim[i].0..=lim[i].1).contains(&p), "J{} {p}", i + 1);
                prop_assert!((p - prev[i]).abs() <= max_target_step(i, PERIOD_S, periods));
            }
            prev = f.fields.positions_steps;
        }
    }

    /// Garbage measurements, bit flips and random timing: an accepted measurement never jumps
    /// further than the joint can move in the elapsed time.
    #[test]
    fn accepted_measurements_are_plausible(
        stream in proptest::collection::vec(
            (proptest::array::uniform6(-8_388_608i32..8_388_607), 0u8..3, 0usize..6, 0u32..24, 0.0f64..0.05),
            1..200,
        ),
    ) {
        let mut f = PlausibilityFilter::default();
        let mut truth = STANDBY_STEPS;
        let mut t = 0.0;
        let mut last: Option<([i32; JOINT_COUNT], f64)> = None;
        for (garbage, kind, joint, bit, dt) in stream {
            t += dt;
            truth[3] += 50;
            let m = match kind {
                0 => truth,
                1 => { let mut m = truth; m[joint] ^= 1 << bit; m }
                _ => garbage,
            };
            if f.check(&m, t, PERIOD_S) == Plausibility::Accepted {
                if let Some((prev, _)) = last {
                    for i in 0..JOINT_COUNT {
                        // The filter's own bound, at most 1 s + slack of elapsed time here.
                        prop_assert!((m[i] - prev[i]).abs() <= max_plausible_jump(i, 60.0));
                    }
                }
                last = Some((m, t));
            }
        }
    }
}
