//! The two ways PAROL6 users write a TCP orientation as three angles, and the conversions
//! between them.
//!
//! - [`AngleConvention::UrdfRpy`] (ours, every file format and CLI of this program): URDF roll /
//!   pitch / yaw, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
//! - [`AngleConvention::OfficialAbc`] (the official PAROL6 Python API, its G-code A/B/C words
//!   and the PAROL commander's `MovePose` / `MoveCart`): spatialmath
//!   `SE3.RPY([a, b, c], order='xyz')`, which is `R = Rx(c)·Ry(b)·Rz(a)`.
//!
//! Positions and the base frame are the same in both. Example: our (roll 0, pitch 20, yaw 90)°
//! is the official (A 90, B 0, C −20)°.

use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::kinematics::rpy_from_matrix;

/// Which three-angle convention a readout or an entry field uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleConvention {
    /// URDF roll / pitch / yaw: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    #[default]
    UrdfRpy,
    /// The official PAROL6 tools' RX / RY / RZ (G-code A / B / C): `R = Rx(c)·Ry(b)·Rz(a)`.
    OfficialAbc,
}

impl AngleConvention {
    /// Both conventions, for selectors.
    pub const ALL: [AngleConvention; 2] = [AngleConvention::UrdfRpy, AngleConvention::OfficialAbc];

    /// The three axis labels a user sees.
    pub fn labels(self) -> [&'static str; 3] {
        match self {
            AngleConvention::UrdfRpy => ["Roll", "Pitch", "Yaw"],
            AngleConvention::OfficialAbc => ["RX", "RY", "RZ"],
        }
    }

    /// A short name with the rotation order, for settings and tooltips.
    pub fn describe(self) -> &'static str {
        match self {
            AngleConvention::UrdfRpy => "URDF roll/pitch/yaw (R = Rz·Ry·Rx)",
            AngleConvention::OfficialAbc => "official PAROL6 RX/RY/RZ (R = Rx(RZ)·Ry(RY)·Rz(RX))",
        }
    }

    /// Angles in this convention (deg) → our roll / pitch / yaw (deg).
    pub fn to_rpy_deg(self, angles_deg: [f64; 3]) -> [f64; 3] {
        match self {
            AngleConvention::UrdfRpy => angles_deg,
            AngleConvention::OfficialAbc => abc_to_rpy_deg(angles_deg),
        }
    }

    /// Our roll / pitch / yaw (deg) → angles in this convention (deg).
    pub fn from_rpy_deg(self, rpy_deg: [f64; 3]) -> [f64; 3] {
        match self {
            AngleConvention::UrdfRpy => rpy_deg,
            AngleConvention::OfficialAbc => rpy_to_abc_deg(rpy_deg),
        }
    }
}

/// The rotation of the official `A/B/C` angles (deg): `R = Rx(c)·Ry(b)·Rz(a)`.
pub fn rotation_from_abc_deg(abc_deg: [f64; 3]) -> Rotation3<f64> {
    let [a, b, c] = abc_deg.map(f64::to_radians);
    Rotation3::from_axis_angle(&Vector3::x_axis(), c)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
        * Rotation3::from_axis_angle(&Vector3::z_axis(), a)
}

/// The official `A/B/C` angles (deg) of a rotation. Inverse of [`rotation_from_abc_deg`]: the
/// transpose `Rᵀ = Rz(−a)·Ry(−b)·Rx(−c)` is a URDF roll/pitch/yaw rotation, so the URDF
/// decomposition of `Rᵀ` (with its gimbal-lock rule) gives the angles negated.
pub fn abc_deg_from_rotation(rotation: &Rotation3<f64>) -> [f64; 3] {
    let [roll, pitch, yaw] = rpy_from_matrix(rotation.transpose().matrix());
    [-yaw, -pitch, -roll].map(|v: f64| {
        let d = v.to_degrees();
        // Keep +180° rather than −180° where both name the same angle, and no −0.
        if d <= -180.0 + 1e-9 {
            d + 360.0
        } else if d == 0.0 {
            0.0
        } else {
            d
        }
    })
}

/// Our roll / pitch / yaw (deg) → the official A / B / C (deg).
pub fn rpy_to_abc_deg(rpy_deg: [f64; 3]) -> [f64; 3] {
    let [r, p, y] = rpy_deg.map(f64::to_radians);
    let rotation = UnitQuaternion::from_euler_angles(r, p, y).to_rotation_matrix();
    abc_deg_from_rotation(&rotation)
}

/// The official A / B / C (deg) → our roll / pitch / yaw (deg).
pub fn abc_to_rpy_deg(abc_deg: [f64; 3]) -> [f64; 3] {
    let rotation = rotation_from_abc_deg(abc_deg);
    rpy_from_matrix(rotation.matrix()).map(f64::to_degrees)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    fn rotation_rpy_deg(rpy_deg: [f64; 3]) -> Rotation3<f64> {
        let [r, p, y] = rpy_deg.map(f64::to_radians);
        UnitQuaternion::from_euler_angles(r, p, y).to_rotation_matrix()
    }

    #[test]
    fn official_example_roll0_pitch20_yaw90_is_a90_b0_cm20() {
        let abc = rpy_to_abc_deg([0.0, 20.0, 90.0]);
        assert!(close(abc, [90.0, 0.0, -20.0], 1e-9), "{abc:?}");
        let rpy = abc_to_rpy_deg([90.0, 0.0, -20.0]);
        assert!(close(rpy, [0.0, 20.0, 90.0], 1e-9), "{rpy:?}");
    }

    #[test]
    fn single_axis_angles_agree_between_conventions() {
        // One rotation about one axis reads the same in both.
        assert!(close(rpy_to_abc_deg([0.0, 0.0, 30.0]), [30.0, 0.0, 0.0], 1e-9));
        assert!(close(rpy_to_abc_deg([0.0, 25.0, 0.0]), [0.0, 25.0, 0.0], 1e-9));
        assert!(close(rpy_to_abc_deg([-40.0, 0.0, 0.0]), [0.0, 0.0, -40.0], 1e-9));
    }

    #[test]
    fn abc_rotation_is_rx_c_ry_b_rz_a() {
        // A hand-built product, not the function's own formula.
        let (a, b, c) = (10f64.to_radians(), 20f64.to_radians(), 30f64.to_radians());
        let rx = Rotation3::from_euler_angles(c, 0.0, 0.0);
        let ry = Rotation3::from_euler_angles(0.0, b, 0.0);
        let rz = Rotation3::from_euler_angles(0.0, 0.0, a);
        let expected = rx * ry * rz;
        let got = rotation_from_abc_deg([10.0, 20.0, 30.0]);
        assert!((expected.matrix() - got.matrix()).norm() < 1e-12);
    }

    #[test]
    fn tool_pointing_down_reads_180_in_both() {
        let abc = rpy_to_abc_deg([180.0, 0.0, 0.0]);
        let back = rotation_from_abc_deg(abc);
        assert!((back.matrix() - rotation_rpy_deg([180.0, 0.0, 0.0]).matrix()).norm() < 1e-9);
        assert!(close(abc, [0.0, 0.0, 180.0], 1e-9), "{abc:?}");
    }

    proptest! {
        #[test]
        fn round_trip_keeps_the_rotation(r in -180.0f64..180.0, p in -89.0f64..89.0, y in -180.0f64..180.0) {
            let abc = rpy_to_abc_deg([r, p, y]);
            let rotation = rotation_from_abc_deg(abc);
            prop_assert!((rotation.matrix() - rotation_rpy_deg([r, p, y]).matrix()).norm() < 1e-9);
            let rpy = abc_to_rpy_deg(abc);
            prop_assert!((rotation_rpy_deg(rpy).matrix() - rotation.matrix()).norm() < 1e-9);
            for convention in AngleConvention::ALL {
                let shown = convention.from_rpy_deg([r, p, y]);
                let taken = convention.to_rpy_deg(shown);
                prop_assert!((rotation_rpy_deg(taken).matrix() - rotation.matrix()).norm() < 1e-9);
            }
        }
    }
}
