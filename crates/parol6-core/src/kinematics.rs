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

/// How close to pitch = ±90° (gimbal lock) [`rpy_from_matrix`] keeps roll within ±90°: 0.1°,
/// more than every joint of a PAROL6 a motor step off together moves the pitch (≤ 0.03°), so
/// the standby pose reads the same in the simulation and on the robot, which reports whole
/// motor steps.
pub const GIMBAL_LOCK_BAND_RAD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// Largest gap (rad) between the rotation and the rotation of the angles [`rpy_from_matrix`]
/// gives for it when it writes a pose at gimbal lock with roll = 0.
pub const GIMBAL_LOCK_EXACT_RAD: f64 = 1e-12;

/// The rule [`rpy_from_matrix`] follows at gimbal lock, in words, for tooltips and help.
pub const GIMBAL_LOCK_RULE: &str = "At gimbal lock (pitch ±90°) only yaw − roll (+90°) or yaw + roll (−90°) is defined: roll is 0 and yaw \
    carries the rotation about the vertical. Within 0.1° of it roll stays within ±90° (pitch may pass ±90° by \
    up to 0.1°), so a pose next to the lock reads as the lock does. The angles always give back the exact \
    rotation.";

/// Wraps an angle into (−π, π].
fn wrap_pi(a: f64) -> f64 {
    let w = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    if w <= -std::f64::consts::PI { w + std::f64::consts::TAU } else { w }
}

/// URDF roll-pitch-yaw of a rotation matrix (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`), angles in
/// (−π, π]. The angles always reproduce `R` (to [`GIMBAL_LOCK_EXACT_RAD`]); which of the
/// spellings of `R` is given:
///
/// - away from gimbal lock, pitch in [−90°, 90°];
/// - within [`GIMBAL_LOCK_BAND_RAD`] of pitch = ±90°, roll in [−90°, 90°] (the other exact
///   spelling `(roll ± 180°, ±180° − pitch, yaw ± 180°)` when needed, so pitch may pass ±90° by
///   up to the band): a pose beside the lock reads continuously through it, whichever side of
///   it a motor step or a sag puts the arm;
/// - at the lock itself (where only `yaw ∓ roll` is defined), roll = 0 and yaw carries the
///   whole rotation about the vertical, whenever those angles give back `R` to
///   [`GIMBAL_LOCK_EXACT_RAD`] (else the angles above, which do).
///
/// Every RPY the app shows, the simulation's and the robot's alike, comes from here
/// ([`GIMBAL_LOCK_RULE`] says it in words).
pub fn rpy_from_matrix(m: &Matrix3<f64>) -> [f64; 3] {
    use std::f64::consts::{FRAC_PI_2, PI};
    let q = UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(*m));
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    // With half angles (r, p, y)/2 and p in [−90°, 90°]: w + y = (cos + sin)(p/2)·cos((yaw − roll)/2),
    // z − x = (cos + sin)(p/2)·sin((yaw − roll)/2), w − y = (cos − sin)(p/2)·cos((yaw + roll)/2),
    // z + x = (cos − sin)(p/2)·sin((yaw + roll)/2). Beside −90° yaw + roll is then read from
    // entries of size ~1, and yaw − roll, read from tiny ones, counts in R only as much as they
    // do: the angles give back R to rounding on both sides of the lock, where the matrix
    // entries' roll and yaw (atan2 of entries ~cos p each) would lose ~1e-16 / cos p.
    let (plus, minus) = ((w + y).hypot(z - x), (w - y).hypot(z + x));
    let pitch = 2.0 * (plus - minus).atan2(plus + minus);
    let diff = 2.0 * (z - x).atan2(w + y);
    let sum = 2.0 * (z + x).atan2(w - y);
    let (roll, yaw) = (wrap_pi(0.5 * (sum - diff)), wrap_pi(0.5 * (sum + diff)));
    if FRAC_PI_2 - pitch.abs() > GIMBAL_LOCK_BAND_RAD {
        return [roll, pitch, yaw];
    }
    let side = pitch.signum();
    let [roll, pitch, yaw] = if roll.abs() > FRAC_PI_2 {
        [wrap_pi(roll + PI), side * PI - pitch, wrap_pi(yaw + PI)]
    } else {
        [roll, pitch, yaw]
    };
    // at +90° R depends on yaw − roll only, at −90° on yaw + roll: roll 0 gives it all to yaw
    let locked = [0.0, side * FRAC_PI_2, wrap_pi(if side > 0.0 { diff } else { sum })];
    let back = UnitQuaternion::from_euler_angles(locked[0], locked[1], locked[2]).to_rotation_matrix();
    // ‖A − B‖ = 2√2·sin(θ/2) ≈ √2·θ for the small angle θ between them
    if (back.matrix() - m).norm() <= std::f64::consts::SQRT_2 * GIMBAL_LOCK_EXACT_RAD {
        locked
    } else {
        [roll, pitch, yaw]
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
            assert_eq!(rpy[0], 0.0, "at the lock roll is 0: {rpy:?}");
            assert_eq!(rpy[1], pitch);
            let back = UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]).to_rotation_matrix();
            assert!((back.matrix() - r.matrix()).norm() < 1e-12, "pitch {pitch}: {rpy:?}");
        }
    }

    /// Beside the lock, roll stays within ±90° and pitch may pass ±90°: a pose read on either
    /// side of the lock (a motor step, a sag) reads continuously, and always exactly.
    #[test]
    fn rpy_beside_the_lock_keeps_roll_within_90_degrees_and_is_exact() {
        use std::f64::consts::FRAC_PI_2;
        let band = GIMBAL_LOCK_BAND_RAD;
        for side in [1.0, -1.0] {
            for roll in [0.0, 0.3, -1.2, 2.5, -3.0] {
                let mut previous: Option<[f64; 3]> = None;
                for k in -20..=20 {
                    let p = side * FRAC_PI_2 + f64::from(k) / 20.0 * 0.99 * band;
                    let r = rotation_of([roll, p, -0.4]);
                    let rpy = rpy_from_matrix(&r);
                    assert!(rotation_gap_rad(&r, &rotation_of(rpy)) < 1e-12, "{roll} {p}: {rpy:?}");
                    assert!(rpy[0].abs() <= FRAC_PI_2 + 1e-12, "roll beyond 90° beside the lock: {rpy:?}");
                    assert!((rpy[1].abs() - FRAC_PI_2).abs() <= band, "{rpy:?}");
                    if let Some(prev) = previous.filter(|_| k != 0 && k != 1) {
                        // no jump of roll or yaw between neighbours (the lock itself spells roll 0)
                        let gap = |a: f64, b: f64| wrap_pi(a - b).abs();
                        assert!(gap(prev[0], rpy[0]) < 1e-6 && gap(prev[2], rpy[2]) < 1e-6, "{prev:?} → {rpy:?}");
                    }
                    previous = Some(rpy);
                }
            }
            // beyond the band: pitch within ±90° as everywhere else
            let p = side * (FRAC_PI_2 - 1.01 * band);
            let rpy = rpy_from_matrix(&rotation_of([2.5, p, -0.4]));
            assert!((rpy[0] - 2.5).abs() < 1e-9 && (rpy[1] - p).abs() < 1e-9 && (rpy[2] + 0.4).abs() < 1e-9, "{rpy:?}");
        }
    }

    /// The angle between two rotations, rad (accurate for small angles, where acos of the
    /// trace is not: ‖A − B‖ = 2√2·sin(θ/2)).
    fn rotation_gap_rad(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
        2.0 * ((a - b).norm() / (2.0 * std::f64::consts::SQRT_2)).min(1.0).asin()
    }

    fn rotation_of(rpy: [f64; 3]) -> Matrix3<f64> {
        *UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]).to_rotation_matrix().matrix()
    }

    /// Issue 32 minor: "The same standby pose reads RPY (90, −90, 0) in simulation and (−180,
    /// −90, −90) on the robot. Pick one representation at gimbal lock, and say so." The robot
    /// reports whole motor steps (J3's 180° is 57 904.76 steps: 57 905, 13 µrad off), so its
    /// standby lies just beside the lock. It, and the joints that tilt the flange about J2's axis
    /// or turn it about the vertical (J1, J2, J3, J5) up to a step off either way (a sag, a step
    /// of error), read as the simulation's exact standby does; every reading, J4 and J6 a step
    /// off too, gives back the arm's rotation. (J4 and J6, coaxial at J5 = 0, tilt the flange
    /// across: a step of them is another rotation beside the lock, whose exact roll and yaw
    /// differ; no exact spelling can read it as the lock.)
    #[test]
    fn the_standby_pose_reads_one_rpy_in_simulation_and_on_the_robot() {
        let m = RobotModel::parol6();
        let exact = crate::parol6::standby_rad();
        let sim = m.fk(&exact).rpy_rad.map(f64::to_degrees);
        let step = crate::parol6::rad_per_step;
        let robot_q: Vec<f64> = (0..6).map(|j| (exact[j] / step(j)).round_ties_even() * step(j)).collect();
        let robot = m.fk(&robot_q).rpy_rad.map(f64::to_degrees);
        let gap = |a: f64, b: f64| (a - b + 540.0).rem_euclid(360.0) - 180.0;
        for i in 0..3 {
            assert!(gap(robot[i], sim[i]).abs() < 0.01, "robot {robot:?} vs simulation {sim:?}");
        }
        let mut worst_gap_rad: f64 = 0.0;
        for signs in 0..3usize.pow(6) {
            let q: Vec<f64> = (0..6)
                .map(|j| {
                    let k = (signs / 3usize.pow(j as u32)) % 3;
                    robot_q[j] + (k as f64 - 1.0) * step(j)
                })
                .collect();
            let pose = m.fk(&q);
            let shown = pose.rpy_rad.map(f64::to_degrees);
            if q[3] == robot_q[3] && q[5] == robot_q[5] {
                for i in 0..3 {
                    assert!(gap(shown[i], sim[i]).abs() < 0.05, "{shown:?} vs simulation {sim:?} (q {q:?})");
                }
            }
            let r = Matrix3::from_fn(|i, k| pose.rotation[i][k]);
            worst_gap_rad = worst_gap_rad.max(rotation_gap_rad(&r, &rotation_of(pose.rpy_rad)));
        }
        assert!(worst_gap_rad < 1e-12, "the shown angles miss the rotation by {worst_gap_rad:e} rad");
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
