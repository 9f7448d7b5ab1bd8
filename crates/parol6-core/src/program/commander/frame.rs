//! Commander poses ↔ our TCP poses, and the commander's number format.
//!
//! The commander's poses are poses of its frame `D` (DH frame 6), fixed to the flange:
//! `D = flange · K₀` with `K₀ = inv(L6)·DH6` ([`crate::frames`]). Our poses are poses of the TCP
//! `X = flange · T` (`T`: the tool in the flange frame). So `D = X · K` with `K = T⁻¹ · K₀`:
//!
//! - a pose: `X = D · K⁻¹` on import, `D = X · K` on export;
//! - a tool-frame move `D' = D · M` (`M = Trans(d) · Rx(a)·Ry(b)·Rz(c)`, as the commander
//!   applies `MoveCartRelTRF`) is the move `X' = X · (K · M · K⁻¹)` of our TCP. With a tool
//!   without rotation (every PAROL6 tool) `K`'s rotation is Rx(π), so the rotations become
//!   exactly Rx(a)·Ry(−b)·Rz(−c) and the offset `K·M·K⁻¹`'s translation (the commander turns
//!   about its own frame's origin, we about the TCP: the offset carries the difference).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::super::PoseMm;
use crate::angles::{abc_deg_from_rotation, rotation_from_abc_deg};
use crate::frames::commander_frame_in_flange;

/// How many decimals export writes: the commander's readout rounds to 3 (`round(x, 3)`).
pub const COMMANDER_DECIMALS: i32 = 3;

/// The conversions for one tool.
pub(super) struct CommanderFrame {
    /// The commander's frame in our TCP frame: `K = T⁻¹ · inv(L6)·DH6`.
    k: Isometry3<f64>,
    /// `K`'s rotation is exactly Rx(π) (the tool does not turn): tool-frame angles map by sign.
    rx_pi: bool,
}

impl CommanderFrame {
    /// For the tool `tool` (the TCP in the `L6` frame).
    pub(super) fn new(tool: &Isometry3<f64>) -> Self {
        let k = tool.inverse() * commander_frame_in_flange();
        let rx_pi = tool.rotation.angle() == 0.0;
        Self { k, rx_pi }
    }

    /// Commander `x, y, z` (mm), `rx, ry, rz` (deg, `R = Rx(rz)·Ry(ry)·Rz(rx)`) → our TCP pose.
    pub(super) fn pose_in(&self, v: [f64; 6]) -> PoseMm {
        let d = Isometry3::from_parts(
            Translation3::new(v[0] / 1000.0, v[1] / 1000.0, v[2] / 1000.0),
            UnitQuaternion::from_rotation_matrix(&rotation_from_abc_deg([v[3], v[4], v[5]])),
        );
        PoseMm::from_isometry(&(d * self.k.inverse()))
    }

    /// Our TCP pose → the commander's six numbers.
    pub(super) fn pose_out(&self, pose: &PoseMm) -> [f64; 6] {
        let d = pose.isometry() * self.k;
        let p = d.translation.vector * 1000.0;
        let abc = abc_deg_from_rotation(&d.rotation.to_rotation_matrix());
        // At ry = ±90° as written only rx − rz (or rx + rz) is defined, and reading the rounded
        // angles back gives the canonical split: write that split, so that reading and writing
        // again keeps the text.
        let [a, b, c] = if rounded(abc[1]).abs() == 90.0 {
            abc_deg_from_rotation(&rotation_from_abc_deg(abc.map(rounded)))
        } else {
            abc
        };
        [p.x, p.y, p.z, a, b, c]
    }

    /// `MoveCartRelTRF(dx, dy, dz, a, b, c)` → our `move_rel_tool` offset (mm) and rotations (deg).
    pub(super) fn rel_in(&self, v: [f64; 6]) -> ([f64; 3], [f64; 3]) {
        let m = tool_move([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let ours = self.k * m * self.k.inverse();
        let rotation = if self.rx_pi { [v[3], -v[4], -v[5]] } else { xyz_angles_deg(&ours.rotation) };
        (mm(&ours.translation.vector), rotation)
    }

    /// Our `move_rel_tool` → `MoveCartRelTRF`'s six numbers.
    pub(super) fn rel_out(&self, offset_mm: &[f64; 3], rotation_deg: &[f64; 3]) -> [f64; 6] {
        let ours = tool_move(*offset_mm, *rotation_deg);
        let m = self.k.inverse() * ours * self.k;
        let [a, b, c] = if self.rx_pi {
            [rotation_deg[0], -rotation_deg[1], -rotation_deg[2]]
        } else {
            xyz_angles_deg(&m.rotation)
        };
        let d = mm(&m.translation.vector);
        [d[0], d[1], d[2], a, b, c]
    }
}

/// `Trans(offset) · Rx(a)·Ry(b)·Rz(c)` (mm, deg), the move both programs apply in the tool frame.
pub(super) fn tool_move(offset_mm: [f64; 3], rotation_deg: [f64; 3]) -> Isometry3<f64> {
    let [a, b, c] = rotation_deg.map(f64::to_radians);
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), a)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), b)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), c);
    Isometry3::from_parts(Translation3::from(Vector3::from(offset_mm) / 1000.0), rotation)
}

/// The angles (deg) of `R = Rx(a)·Ry(b)·Rz(c)`: the official A/B/C (`Rx(C)·Ry(B)·Rz(A)`) reversed.
fn xyz_angles_deg(rotation: &UnitQuaternion<f64>) -> [f64; 3] {
    let [a, b, c] = abc_deg_from_rotation(&rotation.to_rotation_matrix());
    [c, b, a]
}

fn mm(v: &Vector3<f64>) -> [f64; 3] {
    [v.x * 1000.0, v.y * 1000.0, v.z * 1000.0]
}

/// `x` rounded to [`COMMANDER_DECIMALS`] decimals.
fn rounded(x: f64) -> f64 {
    let scale = 10f64.powi(COMMANDER_DECIMALS);
    (x * scale).round() / scale
}

/// A number as export writes it: rounded to [`COMMANDER_DECIMALS`] decimals, the shortest
/// text that reads back as that value, no exponent and no `-0` (`-80.00001816331088` → `-80`,
/// `0.1 + 0.2` → `0.3`). `None` for a value that is not finite.
pub(super) fn number_text(x: f64) -> Option<String> {
    let r = rounded(x);
    if !r.is_finite() {
        return None;
    }
    // `+ 0.0` turns −0 into +0; f64's Display never writes an exponent.
    Some(format!("{}", r + 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_rounded_to_three_decimals_without_noise_or_minus_zero() {
        let cases = [
            (-80.00001816331088, "-80"),
            (0.1 + 0.2, "0.3"),
            (-0.0, "0"),
            (-0.0004, "0"),
            (262.5700000001, "262.57"),
            (123456.78951, "123456.79"),
            (-12.5, "-12.5"),
        ];
        for (x, want) in cases {
            assert_eq!(number_text(x).as_deref(), Some(want), "{x}");
        }
        assert_eq!(number_text(f64::NAN), None);
        assert_eq!(number_text(f64::INFINITY), None);
    }

    #[test]
    fn a_tool_that_turns_uses_the_general_decomposition() {
        // a tool turned 30° about z: the rotations no longer map by sign; import then export
        // still gives the same numbers
        let tool = Isometry3::from_parts(
            Translation3::new(0.01, 0.0, -0.05),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 30f64.to_radians()),
        );
        let frame = CommanderFrame::new(&tool);
        assert!(!frame.rx_pi);
        let v = [5.0, -3.0, 12.0, 10.0, -20.0, 30.0];
        let (offset, rotation) = frame.rel_in(v);
        let back = frame.rel_out(&offset, &rotation);
        for (x, y) in v.iter().zip(back) {
            assert!((x - y).abs() < 1e-9, "{v:?} → {back:?}");
        }
        let pose = frame.pose_in(v);
        let out = frame.pose_out(&pose);
        for (x, y) in v.iter().zip(out) {
            assert!((x - y).abs() < 1e-9, "{v:?} → {out:?}");
        }
    }
}
