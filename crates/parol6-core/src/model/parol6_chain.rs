//! Recognises the PAROL6 kinematic chain (ROBOT.md §6.1) in a loaded model, so the closed-form
//! IK (`ik::solve_parol6`) can be used for it.

use std::f64::consts::PI;

use nalgebra::Isometry3;

use super::{ChainJoint, JointKind, iso_from_pose};

/// Origins (xyz m, rpy rad) of PAROL6 joints J2…J6 in the previous joint's frame.
const PAROL6_ORIGINS: [([f64; 3], [f64; 3]); 5] = [
    ([0.0234207210610375, 0.0, 0.0], [-PI / 2.0, 0.0, 0.0]),
    ([0.18, 0.0, 0.0], [PI, 0.0, 0.0]),
    ([-0.0435, 0.17635, 0.0], [PI / 2.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [-PI / 2.0, 0.0, 0.0]),
    ([0.0, 0.037, 0.0], [PI / 2.0, 0.0, 0.0]),
];

/// How close (m and rad) a joint origin must be to the PAROL6 one.
const ORIGIN_TOLERANCE: f64 = 1e-6;

/// True when `joints` (+ `tip_offset`) form the PAROL6 chain of ROBOT.md §6.1 (any base
/// placement: J1's origin may be anything).
pub fn is_parol6_chain(joints: &[ChainJoint], tip_offset: &Isometry3<f64>) -> bool {
    if joints.len() != 6 || joints.iter().any(|j| j.kind == JointKind::Prismatic || !j.axis_is_z) {
        return false;
    }
    let tip_ok = tip_offset.translation.vector.norm() < 1e-9 && tip_offset.rotation.angle() < 1e-9;
    tip_ok
        && joints[1..].iter().zip(PAROL6_ORIGINS.iter()).all(|(j, (xyz, rpy))| {
            let want = iso_from_pose(&urdf_rs::Pose { xyz: urdf_rs::Vec3(*xyz), rpy: urdf_rs::Vec3(*rpy) });
            let position_error_m = (j.origin.translation.vector - want.translation.vector).norm();
            let rotation_error_rad = j.origin.rotation.angle_to(&want.rotation);
            position_error_m < ORIGIN_TOLERANCE && rotation_error_rad < ORIGIN_TOLERANCE
        })
}
