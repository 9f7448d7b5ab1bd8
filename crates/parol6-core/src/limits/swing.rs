//! The swing bound of Cartesian motion: how far any joint may turn per unit of TCP travel on a
//! Cartesian jog, a Cartesian step or a Cartesian move (MoveL, MoveC, spline) before the motion
//! stops (a jog) or is refused (a move, and so pre-flight, which plans every move).
//!
//! Near a singular pose the joints needed to keep the TCP on a straight path grow without bound:
//! at the PAROL6's wrist singularity (J5 = 0, J4 and J6 in line) a lateral jog of 1.5 mm turned
//! J4 by 90° and J6 by 90°. Rather than swing, the motion stops with the reason and asks for a
//! joint move.
//!
//! The bound over an interval of the motion is
//! `MAX_SWING_DEG_PER_MM × TCP travel (mm) + MAX_SWING_DEG_PER_DEG × tool rotation (deg)`,
//! so a pure translation, a pure rotation and a mix are all covered by one rule. On the PAROL6
//! away from singular poses a joint turns at most about 1°/mm and 2°/° (the arm is 200–300 mm
//! long, the wrist turns one-for-one); near the wrist singularity J4 turns about
//! `57.3 / (r_mm · sin J5)` °/mm (r the TCP's distance from the base axis), so 5°/mm is passed
//! within about 3° of J5 = 0, and `1 / sin J5` °/° passes 10°/° within about 6°.

use serde::{Deserialize, Serialize};

/// Most a joint may turn per mm of TCP travel on a Cartesian motion, deg/mm.
pub const MAX_SWING_DEG_PER_MM: f64 = 5.0;

/// Most a joint may turn per degree of tool rotation on a Cartesian motion, deg/deg.
pub const MAX_SWING_DEG_PER_DEG: f64 = 10.0;

/// Slack on the comparison, rad (IK rounding of a motion that does not move).
const SWING_SLACK_RAD: f64 = 1e-9;

/// A joint turning faster than the swing bound allows over an interval of a Cartesian motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SwingOverBound {
    /// 0-based joint that turns most beyond its allowance.
    pub joint: usize,
    /// How far it turns over the interval, deg (absolute).
    pub turn_deg: f64,
    /// TCP travel over the interval, mm.
    pub travel_mm: f64,
    /// Tool rotation over the interval, deg.
    pub rotation_deg: f64,
    /// The wrist is near its singularity: a six-joint arm with J5 within
    /// [`WRIST_SINGULAR_J5_DEG`] of 0 (J4 and J6 nearly in line, as on the PAROL6); otherwise
    /// the arm is stretched, folded or overhead.
    pub wrist: bool,
}

/// Within this of J5 = 0 a six-joint arm's swing is called a singular wrist, deg.
pub const WRIST_SINGULAR_J5_DEG: f64 = 10.0;

impl SwingOverBound {
    /// The joint's turn per unit of TCP motion: deg/mm for a translation, deg/deg for a pure
    /// rotation.
    pub fn ratio(&self) -> f64 {
        if self.travel_mm > 0.0 {
            self.turn_deg / self.travel_mm
        } else {
            self.turn_deg / self.rotation_deg.max(f64::MIN_POSITIVE)
        }
    }

    /// One short line: what to do instead first, then which joint, how fast, and the bound.
    pub fn message(&self) -> String {
        let near = if self.wrist { "a singular wrist" } else { "a singular pose" };
        let rate = if self.travel_mm > 0.0 {
            format!("{:.0}°/mm, bound {MAX_SWING_DEG_PER_MM}°/mm", self.ratio())
        } else {
            format!("{:.0}°/° of rotation, bound {MAX_SWING_DEG_PER_DEG}°/°", self.ratio())
        };
        format!("near {near}: use a joint move (J{} would turn {rate})", self.joint + 1)
    }
}

/// The joint that overruns the swing bound between joint values `a` and `b` while the TCP
/// travels `travel_m` and the tool turns `rotation_rad`, if any.
pub fn swing_over_bound(a: &[f64], b: &[f64], travel_m: f64, rotation_rad: f64) -> Option<SwingOverBound> {
    let travel_mm = travel_m.abs() * 1000.0;
    let rotation_deg = rotation_rad.abs().to_degrees();
    let allowed_rad = (MAX_SWING_DEG_PER_MM * travel_mm + MAX_SWING_DEG_PER_DEG * rotation_deg).to_radians();
    let (joint, turn) = a.iter().zip(b).map(|(x, y)| (y - x).abs()).enumerate().max_by(|x, y| x.1.total_cmp(&y.1))?;
    (turn > allowed_rad + SWING_SLACK_RAD).then(|| SwingOverBound {
        joint,
        turn_deg: turn.to_degrees(),
        travel_mm,
        rotation_deg,
        wrist: b.len() == 6 && b[4].abs().to_degrees() < WRIST_SINGULAR_J5_DEG,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_is_per_mm_and_per_degree() {
        let a = [0.0; 6];
        let mut b = [0.0; 6];
        b[3] = 4.9f64.to_radians();
        assert!(swing_over_bound(&a, &b, 0.001, 0.0).is_none(), "4.9° over 1 mm");
        b[3] = 5.1f64.to_radians();
        let s = swing_over_bound(&a, &b, 0.001, 0.0).expect("5.1° over 1 mm");
        assert_eq!(s.joint, 3);
        assert!(s.message().contains("singular wrist") && s.message().contains("J4"), "{}", s.message());
        b[3] = 9.9f64.to_radians();
        assert!(swing_over_bound(&a, &b, 0.0, 1f64.to_radians()).is_none(), "9.9° over 1° of rotation");
        b[3] = 10.1f64.to_radians();
        assert!(swing_over_bound(&a, &b, 0.0, 1f64.to_radians()).is_some());
        assert!(swing_over_bound(&a, &a, 0.0, 0.0).is_none(), "no motion, no swing");
        b[3] = 0.0;
        b[4] = 0.5;
        let s = swing_over_bound(&a, &b, 0.001, 0.0).expect("J5 away from 0: the arm");
        assert!(s.message().contains("near a singular pose: use a joint move"), "{}", s.message());
    }
}
