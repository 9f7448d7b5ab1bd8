use super::*;
use proptest::prelude::*;

fn pose(p: [f64; 3], rpy: [f64; 3]) -> PoseMm {
    PoseMm { position_mm: p, rpy_deg: rpy }
}

fn sample(cycle: u32, pose_index: usize, commanded: PoseMm, attained: PoseMm) -> PoseSample {
    PoseSample { cycle, pose: pose_index, commanded, attained }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn pose_accuracy_and_repeatability_match_a_hand_computed_example() {
    // P1 commanded at the origin, roll 179°; attained x = 1, 3, 2 mm, roll −179°, 179°, 177°
    let cmd = pose([0.0; 3], [179.0, 0.0, 0.0]);
    let samples = [
        sample(1, 0, cmd, pose([1.0, 0.0, 0.0], [-179.0, 0.0, 0.0])),
        sample(2, 0, cmd, pose([3.0, 0.0, 0.0], [179.0, 0.0, 0.0])),
        sample(3, 0, cmd, pose([2.0, 0.0, 0.0], [177.0, 0.0, 0.0])),
    ];
    let f = compute(&samples).unwrap();
    let p1 = &f.poses[0];
    assert_eq!(p1.name, "P1");
    // mean (2, 0, 0): AP_x = AP_p = 2
    assert!(close(p1.ap_x_mm, 2.0) && close(p1.ap_p_mm, 2.0) && close(p1.ap_y_mm, 0.0));
    // l = 1, 1, 0; l̄ = 2/3; S_l = √((1/9 + 1/9 + 4/9) / 2) = √(1/3); RP_l = 2/3 + 3·√(1/3)
    assert!(close(p1.rp_l_mm, 2.0 / 3.0 + 3.0 * (1.0f64 / 3.0).sqrt()), "{}", p1.rp_l_mm);
    // roll differences +2, 0, −2 (wrapped): AP_a = 0, S = 2, RP_a = 6
    assert!(close(p1.ap_a_deg, 0.0) && close(p1.rp_a_deg, 6.0), "{p1:?}");
    assert!(close(p1.rp_b_deg, 0.0) && close(p1.rp_c_deg, 0.0));
    assert_eq!(p1.cycles, 3);
    assert_eq!(p1.mean_mm, [2.0, 0.0, 0.0]);
    // no P2 / P4: no distance figures
    assert_eq!((f.ad_p_mm, f.rd_mm), (None, None));
}

#[test]
fn distance_accuracy_and_repeatability_between_p2_and_p4() {
    // commanded 100 mm apart; attained 101 and 103 mm: AD = 2, S_D = √2, RD = 3√2
    let (p2, p4) = (pose([0.0; 3], [0.0; 3]), pose([100.0, 0.0, 0.0], [0.0; 3]));
    let samples = [
        sample(1, 1, p2, p2),
        sample(1, 3, p4, pose([101.0, 0.0, 0.0], [0.0; 3])),
        sample(2, 1, p2, pose([-1.0, 0.0, 0.0], [0.0; 3])),
        sample(2, 3, p4, pose([102.0, 0.0, 0.0], [0.0; 3])),
    ];
    let f = compute(&samples).unwrap();
    assert_eq!(f.poses.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), ["P2", "P4"]);
    assert!(close(f.ad_p_mm.unwrap(), 2.0));
    assert!(close(f.rd_mm.unwrap(), 3.0 * 2f64.sqrt()));
}

#[test]
fn too_few_cycles_or_bad_values_are_errors() {
    let p = pose([0.0; 3], [0.0; 3]);
    assert_eq!(compute(&[]), Err(FigureError::Empty));
    assert_eq!(compute(&[sample(1, 2, p, p)]), Err(FigureError::TooFewCycles { pose: "P3", cycles: 1 }));
    let nan = pose([f64::NAN, 0.0, 0.0], [0.0; 3]);
    let e = compute(&[sample(4, 0, p, nan), sample(5, 0, p, p)]).unwrap_err();
    assert_eq!(e.to_string(), "cycle 4, P1: a value is not a finite number");
}

#[test]
fn the_json_has_the_documented_keys() {
    let p = pose([0.0; 3], [0.0; 3]);
    let f = compute(&[sample(1, 0, p, p), sample(2, 0, p, p)]).unwrap();
    let v = serde_json::to_value(&f).unwrap();
    let keys: Vec<&String> = v["poses"][0].as_object().unwrap().keys().collect();
    let want = [
        "name", "AP_p_mm", "AP_x_mm", "AP_y_mm", "AP_z_mm", "AP_a_deg", "AP_b_deg", "AP_c_deg", "RP_l_mm", "RP_a_deg",
        "RP_b_deg", "RP_c_deg",
    ];
    let mut sorted_want: Vec<&str> = want.to_vec();
    sorted_want.sort_unstable();
    let mut sorted_keys: Vec<&str> = keys.iter().map(|k| k.as_str()).collect();
    sorted_keys.sort_unstable();
    assert_eq!(sorted_keys, sorted_want);
    assert!(v.get("AD_p_mm").is_some() && v.get("RD_mm").is_some());
}

#[test]
fn angle_differences_wrap_to_plus_minus_180() {
    assert!(close(angle_difference_deg(-179.0, 179.0), 2.0));
    assert!(close(angle_difference_deg(179.0, -179.0), -2.0));
    assert!(close(angle_difference_deg(10.0, 10.0), 0.0));
    assert!(close(angle_difference_deg(180.0, 0.0), 180.0));
}

proptest! {
    /// Shifting every attained pose by a constant moves AP by that constant and leaves RP alone.
    #[test]
    fn a_constant_offset_changes_accuracy_not_repeatability(
        xs in proptest::collection::vec(-5.0f64..5.0, 2..20),
        dx in -10.0f64..10.0,
    ) {
        let cmd = pose([100.0, 0.0, 200.0], [180.0, 0.0, 0.0]);
        let make = |off: f64| -> Vec<PoseSample> {
            xs.iter().enumerate().map(|(i, x)| {
                sample(i as u32 + 1, 0, cmd, pose([100.0 + x + off, 0.5 * x, 200.0], [180.0 + 0.1 * x, 0.0, 0.0]))
            }).collect()
        };
        let a = compute(&make(0.0)).unwrap();
        let b = compute(&make(dx)).unwrap();
        prop_assert!((b.poses[0].ap_x_mm - a.poses[0].ap_x_mm - dx).abs() < 1e-9);
        prop_assert!((b.poses[0].rp_l_mm - a.poses[0].rp_l_mm).abs() < 1e-9);
        prop_assert!((b.poses[0].rp_a_deg - a.poses[0].rp_a_deg).abs() < 1e-9);
        prop_assert!(a.poses[0].rp_l_mm >= 0.0);
    }
}
