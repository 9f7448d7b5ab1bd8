//! The frames other PAROL6 software reports poses in, where they are not ours, and the one
//! place the constant transform to each is defined.
//!
//! Our poses are poses of the TCP, `flange · tool`, where the flange is URDF link `L6` (the
//! official Python API's poses are also poses of `L6`: no transform).
//!
//! **The PAROL commander GUI** (PCrnjak/PAROL-commander-software, `GUI/files/PAROL6_ROBOT.py`,
//! unchanged in every version of its history) computes its readout and reads `MoveCart`,
//! `MovePose` and `MoveCartRelTRF` poses with a standard-DH table (no joint offsets, joint
//! angles = the software angles), and the pose it uses is that of the table's **frame 6**,
//! which is not `L6`. The two chains describe the same arm, so `inv(L6) · DH6` is one constant:
//!
//! - rotation Rx(π) (DH6's y and z axes are `L6`'s −y and −z),
//! - translation (−45.25, 0, −25.8) mm in the `L6` frame: −45.25 mm is the table's last link
//!   length (its `a7` = 45.25 mm), −25.8 mm is its last offset (`a6` = 62.8 mm from the wrist
//!   centre) less the URDF's 37 mm from the wrist centre to `L6`.
//!
//! The reference pack gives it per joint vector (`vectors/fk_poses.json`,
//! `check_L6_inverse_times_dh6`, with an independent FK of both models); the tests recompute it
//! with their own DH FK. At standby (90, −90, 180, 0, 0, 180)° the commander shows
//! (0, 262.57, 288.75) mm where our flange is at (0, 236.77, 334) mm.
//!
//! The commander has no tool: its frame 6 is fixed to the flange whatever tool is mounted.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// Origin of the commander's frame (its DH frame 6) in our flange frame (`L6`), mm.
pub const COMMANDER_FRAME_ORIGIN_MM: [f64; 3] = [-45.25, 0.0, -25.8];

/// `inv(L6) · DH6`: the commander's frame in our flange frame, Rx(π) at
/// [`COMMANDER_FRAME_ORIGIN_MM`] (metres, as every isometry here).
pub fn commander_frame_in_flange() -> Isometry3<f64> {
    let [x, y, z] = COMMANDER_FRAME_ORIGIN_MM.map(|v| v / 1000.0);
    // Rx(π) written exactly: w = cos(π/2) = 0, axis x.
    let rx_pi = UnitQuaternion::new_unchecked(Quaternion::new(0.0, 1.0, 0.0, 0.0));
    Isometry3::from_parts(Translation3::new(x, y, z), rx_pi)
}

/// The commander's pose (its frame 6) of a flange pose: `flange · inv(L6)·DH6`.
pub fn commander_from_flange(flange: &Isometry3<f64>) -> Isometry3<f64> {
    flange * commander_frame_in_flange()
}

/// The flange pose of a commander pose: `commander · inv(inv(L6)·DH6)`.
pub fn flange_from_commander(commander: &Isometry3<f64>) -> Isometry3<f64> {
    commander * commander_frame_in_flange().inverse()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RobotModel;

    #[test]
    fn standby_reads_as_the_commander_shows_it() {
        let model = RobotModel::parol6();
        let q: Vec<f64> = [90.0f64, -90.0, 180.0, 0.0, 0.0, 180.0].iter().map(|d| d.to_radians()).collect();
        let flange = model.flange_pose(&q);
        let p = flange.translation.vector * 1000.0;
        assert!((p - nalgebra::Vector3::new(0.0, 236.77, 334.0)).norm() < 0.01, "{p}");
        let c = commander_from_flange(&flange);
        let t = c.translation.vector * 1000.0;
        assert!((t - nalgebra::Vector3::new(0.0, 262.57, 288.75)).norm() < 0.01, "{t}");
        // the commander's readout (-90, 0, -90) in its RX/RY/RZ: R = Rx(-90)·Ry(0)·Rz(-90)
        let want = crate::angles::rotation_from_abc_deg([-90.0, 0.0, -90.0]);
        assert!(
            (c.rotation.to_rotation_matrix().matrix() - want.matrix()).norm() < 1e-12,
            "{} vs {want}",
            c.to_homogeneous()
        );
        let back = flange_from_commander(&c);
        assert!((back.to_homogeneous() - flange.to_homogeneous()).norm() < 1e-12);
    }

    #[test]
    fn the_transform_is_rx_pi_at_the_stated_origin() {
        let c = commander_frame_in_flange().to_homogeneous();
        let want = nalgebra::Matrix4::new(
            1.0, 0.0, 0.0, -0.04525, //
            0.0, -1.0, 0.0, 0.0, //
            0.0, 0.0, -1.0, -0.0258, //
            0.0, 0.0, 0.0, 1.0,
        );
        assert_eq!(c, want);
    }
}
