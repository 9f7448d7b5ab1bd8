//! Arc geometry shared by import and export: the three G-code planes, centres from `R`, sweeps.

use std::f64::consts::TAU;

/// An arc plane (`G17` / `G18` / `G19`). Its first and second axes and its normal form a
/// right-handed frame, so `G3` (counter-clockwise seen from the normal) is a positive turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Plane {
    /// `G17`: X, Y; normal +Z.
    Xy,
    /// `G18`: Z, X; normal +Y.
    Zx,
    /// `G19`: Y, Z; normal +X.
    Yz,
}

impl Plane {
    pub const ALL: [Plane; 3] = [Plane::Xy, Plane::Zx, Plane::Yz];

    /// Indices of the first axis, the second axis and the normal (0 = X).
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }

    /// The G code selecting it.
    pub fn code(self) -> &'static str {
        match self {
            Plane::Xy => "G17",
            Plane::Zx => "G18",
            Plane::Yz => "G19",
        }
    }

    /// Its axes as letters (`XY`).
    pub fn name(self) -> &'static str {
        match self {
            Plane::Xy => "XY",
            Plane::Zx => "ZX",
            Plane::Yz => "YZ",
        }
    }

    /// Unit normal.
    pub fn normal(self) -> [f64; 3] {
        let mut n = [0.0; 3];
        n[self.axes().2] = 1.0;
        n
    }
}

/// 2-D point in a plane's (first, second) axes.
pub(crate) type P2 = [f64; 2];

pub(crate) fn in_plane(p: &[f64], plane: Plane) -> P2 {
    let (a, b, _) = plane.axes();
    [p[a], p[b]]
}

/// The centre of the arc of radius `r` (negative: the arc over 180°) from `s` to `e`, turning
/// counter-clockwise when `ccw`; `None` when the radius is shorter than half the chord by more
/// than `tolerance` (a little short is taken as exactly half).
pub(crate) fn centre_from_radius(s: P2, e: P2, r: f64, ccw: bool, tolerance: f64) -> Option<P2> {
    let (du, dv) = (e[0] - s[0], e[1] - s[1]);
    let d = du.hypot(dv);
    let half = 0.5 * d;
    let h2 = r * r - half * half;
    let h = if h2 >= 0.0 {
        h2.sqrt()
    } else if half - r.abs() <= tolerance {
        0.0
    } else {
        return None;
    };
    // the left of the chord holds the centre of a short counter-clockwise arc
    let sign = if ccw { 1.0 } else { -1.0 } * if r > 0.0 { 1.0 } else { -1.0 };
    let (lu, lv) = (-dv / d, du / d);
    Some([s[0] + 0.5 * du + sign * h * lu, s[1] + 0.5 * dv + sign * h * lv])
}

/// The signed turn from `s` to `e` about `c`, rad: in (0, 2π] counter-clockwise, [−2π, 0)
/// clockwise; a full turn when `full`.
pub(crate) fn sweep(s: P2, e: P2, c: P2, ccw: bool, full: bool) -> f64 {
    let (su, sv) = (s[0] - c[0], s[1] - c[1]);
    let (eu, ev) = (e[0] - c[0], e[1] - c[1]);
    let theta = (su * ev - sv * eu).atan2(su * eu + sv * ev);
    match (ccw, full) {
        (true, true) => TAU,
        (false, true) => -TAU,
        (true, false) if theta <= 0.0 => theta + TAU,
        (false, false) if theta >= 0.0 => theta - TAU,
        _ => theta,
    }
}

/// `s` turned by `angle` rad about `c`.
pub(crate) fn rotate(s: P2, c: P2, angle: f64) -> P2 {
    let (u, v) = (s[0] - c[0], s[1] - c[1]);
    let (sin, cos) = angle.sin_cos();
    [c[0] + u * cos - v * sin, c[1] + u * sin + v * cos]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: P2, b: P2) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9
    }

    #[test]
    fn radius_centres_follow_the_direction_and_the_sign() {
        // quarter circle from (10, 0) to (0, 10): centre (0, 0) counter-clockwise, short arc
        assert!(close(centre_from_radius([10.0, 0.0], [0.0, 10.0], 10.0, true, 0.01).expect("fits"), [0.0, 0.0]));
        // clockwise short arc: the centre on the other side
        assert!(close(centre_from_radius([10.0, 0.0], [0.0, 10.0], 10.0, false, 0.01).expect("fits"), [10.0, 10.0]));
        // negative radius: the long arc, centre flipped
        assert!(close(centre_from_radius([10.0, 0.0], [0.0, 10.0], -10.0, true, 0.01).expect("fits"), [10.0, 10.0]));
        assert!(centre_from_radius([0.0, 0.0], [10.0, 0.0], 4.0, true, 0.01).is_none());
        // a hair short of half the chord: a half circle
        assert!(close(centre_from_radius([0.0, 0.0], [10.0, 0.0], 4.995, true, 0.01).expect("fits"), [5.0, 0.0]));
    }

    #[test]
    fn sweeps_by_direction() {
        let (s, e, c) = ([10.0, 0.0], [0.0, 10.0], [0.0, 0.0]);
        assert!((sweep(s, e, c, true, false) - TAU / 4.0).abs() < 1e-12);
        assert!((sweep(s, e, c, false, false) + 3.0 * TAU / 4.0).abs() < 1e-12);
        assert_eq!(sweep(s, s, c, false, true), -TAU);
        assert!(close(rotate(s, c, TAU / 4.0), e));
    }
}
