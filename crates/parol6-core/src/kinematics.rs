//! Forward kinematics, the geometric Jacobian and manipulability (nalgebra, f64).
//!
//! Conventions: poses are in the root-link ("world") frame, metres; RPY follows URDF,
//! `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.

use nalgebra::{Isometry3, Matrix3, Matrix4, Matrix6xX, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::model::{ChainJoint, JointKind, RobotModel};

/// Below this smallest singular value of the Jacobian (metres per radian for the position rows,
/// dimensionless for the orientation rows) a configuration is flagged singular. 1e-3 means one
/// direction of TCP motion moves less than 1 mm per radian of joint motion.
pub const SINGULARITY_SIGMA_MIN: f64 = 1e-3;

/// A TCP (or any frame) pose in every representation the app shows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TcpPose {
    /// Position, metres.
    pub position_m: [f64; 3],
    /// Rotation matrix, row-major.
    pub rotation: [[f64; 3]; 3],
    /// Roll, pitch, yaw in radians, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub rpy_rad: [f64; 3],
    /// Unit quaternion `[w, x, y, z]`.
    pub quaternion_wxyz: [f64; 4],
}

impl TcpPose {
    /// From an isometry.
    pub fn from_isometry(iso: &Isometry3<f64>) -> Self {
        let r = iso.rotation.to_rotation_matrix();
        let m = r.matrix();
        let q = iso.rotation;
        Self {
            position_m: [iso.translation.x, iso.translation.y, iso.translation.z],
            rotation: [
                [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
                [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
                [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
            ],
            rpy_rad: rpy_from_matrix(m),
            quaternion_wxyz: [q.w, q.i, q.j, q.k],
        }
    }

    /// From a position and URDF roll-pitch-yaw.
    pub fn from_xyz_rpy(position_m: [f64; 3], rpy_rad: [f64; 3]) -> Self {
        Self::from_isometry(&iso_from_xyz_rpy(position_m, rpy_rad))
    }

    /// As an isometry.
    pub fn isometry(&self) -> Isometry3<f64> {
        let [w, x, y, z] = self.quaternion_wxyz;
        Isometry3::from_parts(
            Translation3::new(self.position_m[0], self.position_m[1], self.position_m[2]),
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)),
        )
    }

    /// The 4×4 homogeneous matrix, row-major.
    pub fn matrix4(&self) -> [[f64; 4]; 4] {
        let r = &self.rotation;
        let p = &self.position_m;
        [
            [r[0][0], r[0][1], r[0][2], p[0]],
            [r[1][0], r[1][1], r[1][2], p[1]],
            [r[2][0], r[2][1], r[2][2], p[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }
}

/// Isometry from a position and URDF RPY.
pub fn iso_from_xyz_rpy(p: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// URDF roll-pitch-yaw of a rotation matrix (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`).
///
/// Gimbal lock (pitch = ±90°, where only `yaw ∓ roll` is defined): yaw is set to 0 and the
/// whole rotation about the vertical is given to roll, so the angles still reproduce `R`.
pub fn rpy_from_matrix(m: &Matrix3<f64>) -> [f64; 3] {
    let r20 = m[(2, 0)].clamp(-1.0, 1.0);
    if r20.abs() < 1.0 - 1e-12 {
        let pitch = (-r20).asin();
        let roll = m[(2, 1)].atan2(m[(2, 2)]);
        let yaw = m[(1, 0)].atan2(m[(0, 0)]);
        [roll, pitch, yaw]
    } else if r20 < 0.0 {
        // pitch = +90°: R = [[0, sin(r−y), cos(r−y)], [0, cos(r−y), −sin(r−y)], [−1, 0, 0]]
        [m[(0, 1)].atan2(m[(1, 1)]), std::f64::consts::FRAC_PI_2, 0.0]
    } else {
        // pitch = −90°: R = [[0, −sin(r+y), −cos(r+y)], [0, cos(r+y), −sin(r+y)], [1, 0, 0]]
        [(-m[(0, 1)]).atan2(m[(1, 1)]), -std::f64::consts::FRAC_PI_2, 0.0]
    }
}

/// 4×4 homogeneous matrix of an isometry, row-major.
pub fn matrix4_rows(iso: &Isometry3<f64>) -> [[f64; 4]; 4] {
    let m: Matrix4<f64> = iso.to_homogeneous();
    [0, 1, 2, 3].map(|r| [m[(r, 0)], m[(r, 1)], m[(r, 2)], m[(r, 3)]])
}

#[inline]
fn joint_motion(j: &ChainJoint, q: f64) -> Isometry3<f64> {
    match j.kind {
        JointKind::Prismatic => {
            Isometry3::from_parts(Translation3::from(j.axis.into_inner() * q), UnitQuaternion::identity())
        }
        _ => {
            if j.axis_is_z {
                let (s, c) = (0.5 * q).sin_cos();
                Isometry3::from_parts(
                    Translation3::identity(),
                    UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(c, 0.0, 0.0, s)),
                )
            } else {
                Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_axis_angle(&j.axis, q))
            }
        }
    }
}

impl RobotModel {
    /// Chain frames for joint values `q`: element 0 is the root frame (identity), element k the
    /// frame of movable joint k after its motion. `q` must have [`RobotModel::dof`] values;
    /// missing values count as 0.
    pub fn chain_frames(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let mut out = Vec::with_capacity(self.joints.len() + 1);
        let mut t = Isometry3::identity();
        out.push(t);
        for (i, j) in self.joints.iter().enumerate() {
            t = t * j.origin * joint_motion(j, q.get(i).copied().unwrap_or(0.0));
            out.push(t);
        }
        out
    }

    /// World pose of every link (same order as [`RobotModel::links`]).
    pub fn link_poses(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let frames = self.chain_frames(q);
        self.link_poses_from_frames(&frames)
    }

    /// Link poses from already computed chain frames.
    pub fn link_poses_from_frames(&self, frames: &[Isometry3<f64>]) -> Vec<Isometry3<f64>> {
        self.links.iter().map(|l| frames.get(l.frame).copied().unwrap_or_else(Isometry3::identity) * l.offset).collect()
    }

    /// Pose of the tip link (bare flange).
    pub fn flange_pose(&self, q: &[f64]) -> Isometry3<f64> {
        let mut t = Isometry3::identity();
        for (i, j) in self.joints.iter().enumerate() {
            t = t * j.origin * joint_motion(j, q.get(i).copied().unwrap_or(0.0));
        }
        t * self.tip_offset
    }

    /// Pose of the TCP (flange × tool) as an isometry.
    pub fn tcp_isometry(&self, q: &[f64]) -> Isometry3<f64> {
        self.flange_pose(q) * self.tool
    }

    /// Pose of the TCP in every representation.
    pub fn fk(&self, q: &[f64]) -> TcpPose {
        TcpPose::from_isometry(&self.tcp_isometry(q))
    }

    /// Geometric Jacobian (6 × N) of the TCP in the world frame: rows 0–2 linear velocity
    /// (m/s per joint unit), rows 3–5 angular velocity (rad/s per joint unit).
    pub fn jacobian(&self, q: &[f64]) -> Matrix6xX<f64> {
        let frames = self.chain_frames(q);
        let tcp = frames[frames.len() - 1] * self.tip_offset * self.tool;
        self.jacobian_from_frames(&frames, &tcp.translation.vector)
    }

    /// Jacobian from chain frames and the TCP position.
    pub fn jacobian_from_frames(&self, frames: &[Isometry3<f64>], tcp: &Vector3<f64>) -> Matrix6xX<f64> {
        let n = self.joints.len();
        let mut jac = Matrix6xX::zeros(n);
        for (i, j) in self.joints.iter().enumerate() {
            let f = &frames[i + 1];
            let axis = f.rotation * j.axis.into_inner();
            let origin = f.translation.vector;
            let (lin, ang) = match j.kind {
                JointKind::Prismatic => (axis, Vector3::zeros()),
                _ => (axis.cross(&(tcp - origin)), axis),
            };
            jac.fixed_view_mut::<3, 1>(0, i).copy_from(&lin);
            jac.fixed_view_mut::<3, 1>(3, i).copy_from(&ang);
        }
        jac
    }

    /// Yoshikawa manipulability `sqrt(det(J·Jᵀ))` and the singularity assessment.
    pub fn manipulability(&self, q: &[f64]) -> Manipulability {
        Manipulability::of(&self.jacobian(q))
    }
}

/// Manipulability measures of a Jacobian.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Manipulability {
    /// Yoshikawa's measure `sqrt(det(J·Jᵀ))` (product of the singular values).
    pub yoshikawa: f64,
    /// Smallest singular value of J.
    pub sigma_min: f64,
    /// Largest singular value of J.
    pub sigma_max: f64,
    /// True when `sigma_min < SINGULARITY_SIGMA_MIN`.
    pub singular: bool,
}

impl Manipulability {
    /// Measures of `jac` (6 × N).
    pub fn of(jac: &Matrix6xX<f64>) -> Self {
        let svd = jac.clone().svd(false, false);
        let sv = svd.singular_values;
        let k = sv.len().min(6);
        let yoshikawa = sv.iter().take(k).product::<f64>().abs();
        let sigma_min = sv.iter().take(k).copied().fold(f64::INFINITY, f64::min);
        let sigma_max = sv.iter().copied().fold(0.0, f64::max);
        Self { yoshikawa, sigma_min, sigma_max, singular: sigma_min < SINGULARITY_SIGMA_MIN }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn standby_flange_matches_robot_md() {
        let m = RobotModel::parol6();
        let p = m.fk(&crate::parol6::standby_rad());
        assert!((p.position_m[0] - 0.0).abs() < 1e-9);
        assert!((p.position_m[1] - 0.236770721).abs() < 1e-9);
        assert!((p.position_m[2] - 0.334).abs() < 1e-9);
    }

    #[test]
    fn rpy_gimbal_lock_reproduces_rotation() {
        for pitch in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2] {
            let r = UnitQuaternion::from_euler_angles(0.3, pitch, -0.4).to_rotation_matrix();
            let rpy = rpy_from_matrix(r.matrix());
            assert_eq!(rpy[2], 0.0);
            let back = UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]).to_rotation_matrix();
            assert!((back.matrix() - r.matrix()).norm() < 1e-9, "pitch {pitch}: {rpy:?}");
        }
    }

    #[test]
    fn wrist_singularity_is_flagged() {
        let m = RobotModel::parol6();
        let mut q = crate::parol6::standby_rad();
        q[4] = 0.0; // J5 = 0: J4 and J6 axes align
        assert!(m.manipulability(&q).singular);
        q[4] = 0.6;
        let ok = m.manipulability(&q);
        assert!(!ok.singular, "{ok:?}");
        assert!(ok.yoshikawa > 0.0);
    }

    proptest! {
        #[test]
        fn rpy_round_trip(r in -3.1f64..3.1, p in -1.55f64..1.55, y in -3.1f64..3.1) {
            let rot = UnitQuaternion::from_euler_angles(r, p, y).to_rotation_matrix();
            let rpy = rpy_from_matrix(rot.matrix());
            let back = UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]).to_rotation_matrix();
            prop_assert!((back.matrix() - rot.matrix()).norm() < 1e-9);
        }

        #[test]
        fn jacobian_matches_finite_differences(q in proptest::collection::vec(-2.0f64..2.0, 6)) {
            let m = RobotModel::parol6();
            let jac = m.jacobian(&q);
            let h = 1e-6;
            for i in 0..6 {
                let mut qp = q.clone();
                let mut qm = q.clone();
                qp[i] += h;
                qm[i] -= h;
                let (tp, tm) = (m.tcp_isometry(&qp), m.tcp_isometry(&qm));
                let dp = (tp.translation.vector - tm.translation.vector) / (2.0 * h);
                let dr = (tp.rotation * tm.rotation.inverse()).scaled_axis() / (2.0 * h);
                for k in 0..3 {
                    prop_assert!((jac[(k, i)] - dp[k]).abs() < 1e-6);
                    prop_assert!((jac[(k + 3, i)] - dr[k]).abs() < 1e-6);
                }
            }
        }
    }
}
