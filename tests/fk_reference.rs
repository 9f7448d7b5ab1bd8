//! FK of the embedded PAROL6 against the reference pack: the poses of `vectors/fk_poses.json`
//! and the official python-API URDF loaded through the same loader.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_core::na::Isometry3;
use parol6_core::{RobotModel, ik};
use rand::{Rng, SeedableRng};

fn rows(v: &serde_json::Value) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (r, row) in m.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = v[r][c].as_f64().expect("number");
        }
    }
    m
}

#[test]
fn fk_matches_reference_vectors() {
    let Some(dir) = parol6_tests::shared_dir() else { return };
    let doc = parol6_tests::read_json(&dir.join("vectors/fk_poses.json"));
    let model = RobotModel::parol6();
    let vectors = doc["vectors"].as_array().expect("vectors");
    assert!(vectors.len() >= 4);
    for v in vectors {
        let q: Vec<f64> =
            v["joint_deg"].as_array().expect("joints").iter().map(|x| x.as_f64().expect("deg").to_radians()).collect();
        let want = rows(&v["python_api_urdf_L6_pose"]);
        let got = model.fk(&q).matrix4();
        for r in 0..3 {
            for c in 0..4 {
                assert!(
                    (got[r][c] - want[r][c]).abs() <= 1e-6,
                    "{}: [{r}][{c}] {} vs {}",
                    v["name"],
                    got[r][c],
                    want[r][c]
                );
            }
        }
    }
}

#[test]
fn fk_equals_official_python_api_urdf() {
    let Some(dir) = parol6_tests::shared_dir() else { return };
    let official =
        RobotModel::from_urdf_file(&dir.join("urdf/python-api/PAROL6.urdf"), None).expect("official URDF loads");
    assert!(official.warnings.is_empty(), "meshes resolve: {:?}", official.warnings);
    assert!(official.is_parol6, "official chain recognised as PAROL6");
    let ours = RobotModel::parol6();
    assert_eq!(official.dof(), 6);
    let mut rng = rand::rngs::StdRng::seed_from_u64(2026);
    for _ in 0..10_000 {
        let q: Vec<f64> = ours.limits.iter().map(|l| rng.random_range(l.min..=l.max)).collect();
        let a: Isometry3<f64> = ours.flange_pose(&q);
        let b = official.flange_pose(&q);
        let (dp, dr) = ik::pose_error(&a, &b);
        assert!(dp <= 1e-9 && dr <= 1e-9, "q={q:?}: {dp} m, {dr} rad");
    }
}

#[test]
fn official_original_urdf_loads_with_meshes() {
    let Some(dir) = parol6_tests::shared_dir() else { return };
    let m = RobotModel::from_urdf_file(&dir.join("urdf/PAROL6.urdf"), None).expect("original URDF loads");
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert_eq!(m.dof(), 6);
    assert!(!m.is_parol6, "different joint convention: numeric IK applies");
    let meshes = m
        .links
        .iter()
        .flat_map(|l| &l.visuals)
        .filter(|g| matches!(g.shape, parol6_core::model::Shape::Mesh { .. }))
        .count();
    assert_eq!(meshes, 7);
}
