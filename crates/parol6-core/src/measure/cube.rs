//! The ISO 9283 test cube: centre, edge and the tool orientation every test pose keeps; its
//! diagonal plane and the five test poses P1–P5 on it.
//!
//! The cube's edges are parallel to the robot's base axes. Its diagonal plane is the one
//! through the cube's lower edge along x at −y (corners C1, C2) and its upper edge along x at
//! +y (corners C3, C4): it contains the x axis and the direction (0, 1, 1)/√2, its normal is
//! (0, −1, 1)/√2. P1 is the centre; P2–P5 lie on the plane's diagonals at 10 % of the
//! diagonal's length from the corners C1–C4 (so P2 and P4 are opposite, 0.8 × the diagonal
//! apart).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::program::PoseMm;

/// Names of the test poses, in index order.
pub const POSE_NAMES: [&str; 5] = ["P1", "P2", "P3", "P4", "P5"];

/// The order one cycle visits the poses (indices into [`POSE_NAMES`]): P1 → P5 → P4 → P3 →
/// P2, the ISO 9283 cycle, so every pose is approached from the same pose every cycle.
pub const CYCLE_ORDER: [usize; 5] = [0, 4, 3, 2, 1];

/// The fraction of the plane's diagonal between a corner and its test pose.
pub const CORNER_INSET: f64 = 0.1;

/// The largest cube edge accepted, mm (the PAROL6 reaches about 440 mm).
pub const MAX_EDGE_MM: f64 = 1000.0;

/// Why a cube is not a valid test cube.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CubeError {
    /// A value is not finite.
    #[error("the cube's {0} is not a finite number")]
    NotFinite(&'static str),
    /// The edge is out of range.
    #[error("the cube's edge must be > 0 and ≤ {MAX_EDGE_MM} mm, got {0} mm")]
    Edge(f64),
}

/// The test cube.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TestCube {
    /// Centre in the base frame, mm.
    pub center_mm: [f64; 3],
    /// Edge length, mm.
    pub edge_mm: f64,
    /// Tool orientation at every pose: our URDF roll, pitch, yaw, deg
    /// (R = Rz(yaw)·Ry(pitch)·Rx(roll)).
    pub orientation_rpy_deg: [f64; 3],
}

impl TestCube {
    /// The default cube of the window's measurement panel and of `parol6 iso9283` / `path-test`:
    /// centre (0, 250, 220) mm, edge 60 mm, tool roll/pitch/yaw (90, 0, 0)°.
    pub const DEFAULT: TestCube =
        TestCube { center_mm: [0.0, 250.0, 220.0], edge_mm: 60.0, orientation_rpy_deg: [90.0, 0.0, 0.0] };

    /// Checks that every value is finite and the edge is in range.
    pub fn validate(&self) -> Result<(), CubeError> {
        if !self.center_mm.iter().all(|v| v.is_finite()) {
            return Err(CubeError::NotFinite("centre"));
        }
        if !self.orientation_rpy_deg.iter().all(|v| v.is_finite()) {
            return Err(CubeError::NotFinite("orientation"));
        }
        if !self.edge_mm.is_finite() {
            return Err(CubeError::NotFinite("edge"));
        }
        if self.edge_mm <= 0.0 || self.edge_mm > MAX_EDGE_MM {
            return Err(CubeError::Edge(self.edge_mm));
        }
        Ok(())
    }

    fn center(&self) -> Vector3<f64> {
        Vector3::from(self.center_mm)
    }

    /// The in-plane unit axes of the diagonal plane (u along x, v along (0, 1, 1)/√2) and its
    /// unit normal u × v = (0, −1, 1)/√2.
    pub fn plane_axes() -> [Vector3<f64>; 3] {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        [Vector3::x(), Vector3::new(0.0, s, s), Vector3::new(0.0, -s, s)]
    }

    /// The eight corners, mm: bit 0 of the index is +x, bit 1 +y, bit 2 +z.
    pub fn corners_mm(&self) -> [[f64; 3]; 8] {
        let h = 0.5 * self.edge_mm;
        std::array::from_fn(|i| {
            let sign = |bit: usize| if i & (1 << bit) != 0 { h } else { -h };
            [self.center_mm[0] + sign(0), self.center_mm[1] + sign(1), self.center_mm[2] + sign(2)]
        })
    }

    /// The corners C1–C4 of the diagonal plane, mm, in order around it: C1 (−x, −y, −z), C2
    /// (+x, −y, −z), C3 (+x, +y, +z), C4 (−x, +y, +z).
    pub fn plane_corners_mm(&self) -> [[f64; 3]; 4] {
        let h = 0.5 * self.edge_mm;
        let c = self.center();
        [[-h, -h, -h], [h, -h, -h], [h, h, h], [-h, h, h]].map(|d| (c + Vector3::from(d)).into())
    }

    /// Length of the plane's diagonal (C1–C3), mm: √3 × the edge.
    pub fn plane_diagonal_mm(&self) -> f64 {
        3f64.sqrt() * self.edge_mm
    }

    /// Positions of P1–P5, mm. A corner's pose is 10 % of the diagonal from it toward the
    /// opposite corner, i.e. the centre + 0.8 × (corner − centre).
    pub fn pose_positions_mm(&self) -> [[f64; 3]; 5] {
        let c = self.center();
        let corners = self.plane_corners_mm();
        let k = 1.0 - 2.0 * CORNER_INSET;
        std::array::from_fn(|i| if i == 0 { c.into() } else { (c + k * (Vector3::from(corners[i - 1]) - c)).into() })
    }

    /// The test poses P1–P5 (position and the cube's tool orientation).
    pub fn poses(&self) -> [PoseMm; 5] {
        self.pose_positions_mm().map(|p| PoseMm { position_mm: p, rpy_deg: self.orientation_rpy_deg })
    }

    /// The commanded distance P2–P4, mm (0.8 × the plane's diagonal).
    pub fn distance_p2_p4_mm(&self) -> f64 {
        let p = self.pose_positions_mm();
        (Vector3::from(p[1]) - Vector3::from(p[3])).norm()
    }

    /// A point of the diagonal plane at (`u_mm`, `v_mm`) from the centre along its axes.
    pub fn plane_point_mm(&self, u_mm: f64, v_mm: f64) -> [f64; 3] {
        let [u, v, _] = Self::plane_axes();
        (self.center() + u * u_mm + v * v_mm).into()
    }
}

/// The index of a pose name ("P1"…"P5", or "1"…"5"), if it is one.
pub fn pose_index(name: &str) -> Option<usize> {
    let digits = name.trim().strip_prefix(['P', 'p']).unwrap_or(name.trim());
    match digits.parse::<usize>() {
        Ok(n @ 1..=5) => Some(n - 1),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> TestCube {
        TestCube { center_mm: [200.0, 0.0, 300.0], edge_mm: 100.0, orientation_rpy_deg: [180.0, 0.0, 0.0] }
    }

    #[test]
    fn the_poses_are_the_centre_and_ten_percent_in_from_the_plane_corners() {
        // by hand: half edge 50; P2 = centre + 0.8·(−50, −50, −50) = centre − (40, 40, 40)
        let p = cube().pose_positions_mm();
        assert_eq!(p[0], [200.0, 0.0, 300.0]);
        let want = [[160.0, -40.0, 260.0], [240.0, -40.0, 260.0], [240.0, 40.0, 340.0], [160.0, 40.0, 340.0]];
        for (got, want) in p[1..].iter().zip(want) {
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() < 1e-12, "{got:?} vs {want:?}");
            }
        }
        // P2–P4 = 0.8 × √3 × 100 = 138.564 mm; P2 is 10 % of the diagonal (17.32 mm) from C1
        assert!((cube().distance_p2_p4_mm() - 138.564_064_605_510_2).abs() < 1e-9);
        let c1 = Vector3::from(cube().plane_corners_mm()[0]);
        assert!(((Vector3::from(p[1]) - c1).norm() - 17.320_508_075_688_77).abs() < 1e-9);
    }

    #[test]
    fn every_pose_lies_on_the_diagonal_plane_with_the_cube_orientation() {
        let c = cube();
        let [_, _, n] = TestCube::plane_axes();
        for pose in c.poses() {
            let d = Vector3::from(pose.position_mm) - Vector3::from(c.center_mm);
            assert!(d.dot(&n).abs() < 1e-9, "{pose:?}");
            assert_eq!(pose.rpy_deg, [180.0, 0.0, 0.0]);
        }
        assert_eq!(c.plane_point_mm(10.0, 0.0), [210.0, 0.0, 300.0]);
    }

    #[test]
    fn corners_span_the_edge_and_bad_cubes_are_refused() {
        let c = cube().corners_mm();
        assert_eq!(c[0], [150.0, -50.0, 250.0]);
        assert_eq!(c[7], [250.0, 50.0, 350.0]);
        assert!(cube().validate().is_ok());
        let bad = TestCube { edge_mm: 0.0, ..cube() };
        assert_eq!(bad.validate(), Err(CubeError::Edge(0.0)));
        let nan = TestCube { center_mm: [f64::NAN, 0.0, 0.0], ..cube() };
        assert!(nan.validate().unwrap_err().to_string().contains("centre"));
    }

    #[test]
    fn pose_names_parse_with_or_without_the_p() {
        assert_eq!(pose_index("P1"), Some(0));
        assert_eq!(pose_index(" p5 "), Some(4));
        assert_eq!(pose_index("3"), Some(2));
        assert_eq!(pose_index("P6"), None);
        assert_eq!(pose_index("x"), None);
    }
}
