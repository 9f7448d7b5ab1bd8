//! TCP paths in Cartesian space, parameterised by arc length: straight lines, circular arcs
//! (through a via point, or by centre and plane, full circles included), Catmull–Rom splines
//! through waypoints, and polylines whose corners are rounded with a blend radius.
//!
//! A [`TcpPath`] gives the TCP pose at a path parameter `s` in metres of TCP travel (for a
//! pure re-orientation with no travel, `s` runs over an equivalent length, see
//! [`ROTATION_LENGTH_M_PER_RAD`]). Orientation is slerped between the poses that define each
//! piece. Time scaling and IK live in [`super::cartesian`].

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

/// Length a rotation counts as when it is compared with travel, m per rad: 0.1 m per rad
/// (a 90° wrist turn weighs like 157 mm of travel), so pure re-orientations get a duration.
pub const ROTATION_LENGTH_M_PER_RAD: f64 = 0.1;

/// Why a path cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// Three points of an arc lie on one line (or two coincide).
    #[error("arc points are collinear or coincide: no circle passes through them")]
    DegenerateArc,
    /// A radius, angle or length that is not a positive finite number.
    #[error("{0}")]
    Invalid(String),
    /// A spline or polyline with too few waypoints.
    #[error("{what} needs at least {min} waypoints, got {got}")]
    TooFewWaypoints {
        /// Path kind.
        what: &'static str,
        /// Minimum.
        min: usize,
        /// Given.
        got: usize,
    },
}

/// One piece of a path.
#[derive(Debug, Clone, PartialEq)]
enum Piece {
    Line {
        from: Point3<f64>,
        to: Point3<f64>,
    },
    Arc {
        center: Point3<f64>,
        u: Vector3<f64>,
        v: Vector3<f64>,
        radius: f64,
        sweep_rad: f64,
    },
    /// Catmull–Rom segment between p1 and p2, with an arc-length table.
    Spline {
        p: [Point3<f64>; 4],
        table: Vec<(f64, f64)>,
    },
}

impl Piece {
    fn length(&self) -> f64 {
        match self {
            Piece::Line { from, to } => (to - from).norm(),
            Piece::Arc { radius, sweep_rad, .. } => radius * sweep_rad.abs(),
            Piece::Spline { table, .. } => table.last().map_or(0.0, |e| e.0),
        }
    }

    /// Position at `d` metres along the piece.
    fn point(&self, d: f64) -> Point3<f64> {
        match self {
            Piece::Line { from, to } => {
                let len = (to - from).norm();
                if len <= 0.0 { *from } else { from + (to - from) * (d / len).clamp(0.0, 1.0) }
            }
            Piece::Arc { center, u, v, radius, sweep_rad } => {
                let a = if *radius > 0.0 { (d / radius).clamp(0.0, sweep_rad.abs()) * sweep_rad.signum() } else { 0.0 };
                center + (u * a.cos() + v * a.sin()) * *radius
            }
            Piece::Spline { p, table } => catmull_rom(p, spline_u(table, d)),
        }
    }
}

fn catmull_rom(p: &[Point3<f64>; 4], u: f64) -> Point3<f64> {
    let (u2, u3) = (u * u, u * u * u);
    let c = |a: f64, b: f64, c: f64, d: f64| {
        0.5 * ((2.0 * b) + (-a + c) * u + (2.0 * a - 5.0 * b + 4.0 * c - d) * u2 + (-a + 3.0 * b - 3.0 * c + d) * u3)
    };
    Point3::new(c(p[0].x, p[1].x, p[2].x, p[3].x), c(p[0].y, p[1].y, p[2].y, p[3].y), c(p[0].z, p[1].z, p[2].z, p[3].z))
}

/// Spline parameter u at arc length `d`, by interpolation in the table of (length, u).
fn spline_u(table: &[(f64, f64)], d: f64) -> f64 {
    let k = table.partition_point(|e| e.0 < d);
    if k == 0 {
        return 0.0;
    }
    if k >= table.len() {
        return 1.0;
    }
    let (l0, u0) = table[k - 1];
    let (l1, u1) = table[k];
    if l1 > l0 { u0 + (u1 - u0) * (d - l0) / (l1 - l0) } else { u1 }
}

/// Samples per spline segment for its arc-length table.
const SPLINE_TABLE: usize = 256;

/// A TCP path: pieces in order, with the orientation at each piece boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct TcpPath {
    pieces: Vec<Piece>,
    /// Orientation at the start of each piece, and one more at the end.
    orientations: Vec<UnitQuaternion<f64>>,
    /// Cumulative length at the start of each piece, and the total at the end.
    starts: Vec<f64>,
    /// Equivalent length of the largest re-orientation of a piece, m.
    rotation_length_m: f64,
}

impl TcpPath {
    fn build(pieces: Vec<Piece>, orientations: Vec<UnitQuaternion<f64>>) -> Self {
        let mut starts = Vec::with_capacity(pieces.len() + 1);
        let mut acc = 0.0;
        for p in &pieces {
            starts.push(acc);
            acc += p.length();
        }
        starts.push(acc);
        let rotation_length_m =
            orientations.windows(2).map(|w| w[0].angle_to(&w[1]) * ROTATION_LENGTH_M_PER_RAD).fold(0.0, f64::max);
        Self { pieces, orientations, starts, rotation_length_m }
    }

    /// A straight line from `from` to `to`, orientation slerped.
    pub fn line(from: &Isometry3<f64>, to: &Isometry3<f64>) -> Self {
        Self::build(
            vec![Piece::Line { from: from.translation.vector.into(), to: to.translation.vector.into() }],
            vec![from.rotation, to.rotation],
        )
    }

    /// A circular arc from `from` through `via` to `to` (orientation slerped from `from` to `to`).
    pub fn arc_through(from: &Isometry3<f64>, via: &Point3<f64>, to: &Isometry3<f64>) -> Result<Self, PathError> {
        let a: Point3<f64> = from.translation.vector.into();
        let c: Point3<f64> = to.translation.vector.into();
        let (center, normal) = circle_through(&a, via, &c).ok_or(PathError::DegenerateArc)?;
        let radius = (a - center).norm();
        // far-off or nearly collinear points give an overflowing or zero radius
        if !(radius.is_finite() && radius > 1e-9 && center.coords.iter().all(|x| x.is_finite())) {
            return Err(PathError::DegenerateArc);
        }
        let u = (a - center) / radius;
        let v = normal.cross(&u);
        let angle_of = |p: &Point3<f64>| {
            let d = p - center;
            let ang = d.dot(&v).atan2(d.dot(&u));
            if ang < 0.0 { ang + std::f64::consts::TAU } else { ang }
        };
        // the arc goes from a (angle 0) through via to c in the positive sense about `normal`
        let (av, ac) = (angle_of(via), angle_of(&c));
        let sweep = if av <= ac { ac } else { ac - std::f64::consts::TAU };
        let sweep = if sweep.abs() < 1e-12 { std::f64::consts::TAU } else { sweep };
        if !sweep.is_finite() {
            return Err(PathError::DegenerateArc);
        }
        Ok(Self::build(vec![Piece::Arc { center, u, v, radius, sweep_rad: sweep }], vec![from.rotation, to.rotation]))
    }

    /// An arc about `center` in the plane with normal `normal` (right-hand sense), starting at
    /// `from` and sweeping `sweep_rad` (±2π is a full circle). The orientation is kept.
    pub fn arc_about(
        from: &Isometry3<f64>,
        center: &Point3<f64>,
        normal: &Vector3<f64>,
        sweep_rad: f64,
    ) -> Result<Self, PathError> {
        if !(sweep_rad.is_finite() && sweep_rad != 0.0 && sweep_rad.abs() <= std::f64::consts::TAU + 1e-9) {
            return Err(PathError::Invalid(format!("arc sweep {sweep_rad} rad must lie in (0, 2π] by size")));
        }
        let n = Unit::try_new(*normal, 1e-12).ok_or_else(|| PathError::Invalid("arc plane normal is zero".into()))?;
        let a: Point3<f64> = from.translation.vector.into();
        let d = a - center;
        let radial = d - n.into_inner() * d.dot(&n);
        let radius = radial.norm();
        if radius < 1e-6 {
            return Err(PathError::Invalid("the start lies on the arc's axis: radius 0".into()));
        }
        if (d - radial).norm() > 1e-6 {
            return Err(PathError::Invalid("the start does not lie in the arc's plane".into()));
        }
        let u = radial / radius;
        let v = n.cross(&u);
        Ok(Self::build(
            vec![Piece::Arc { center: center + (d - radial), u, v, radius, sweep_rad }],
            vec![from.rotation, from.rotation],
        ))
    }

    /// A Catmull–Rom spline through every waypoint's position (end tangents by mirrored points),
    /// orientation slerped between consecutive waypoints.
    pub fn spline(waypoints: &[Isometry3<f64>]) -> Result<Self, PathError> {
        if waypoints.len() < 2 {
            return Err(PathError::TooFewWaypoints { what: "a spline", min: 2, got: waypoints.len() });
        }
        let pts: Vec<Point3<f64>> = waypoints.iter().map(|w| w.translation.vector.into()).collect();
        let n = pts.len();
        let at = |i: isize| -> Point3<f64> {
            if i < 0 {
                pts[0] + (pts[0] - pts[1])
            } else if i as usize >= n {
                pts[n - 1] + (pts[n - 1] - pts[n - 2])
            } else {
                pts[i as usize]
            }
        };
        let mut pieces = Vec::with_capacity(n - 1);
        for i in 0..n - 1 {
            let p = [at(i as isize - 1), at(i as isize), at(i as isize + 1), at(i as isize + 2)];
            let mut table = Vec::with_capacity(SPLINE_TABLE + 1);
            let mut prev = p[1];
            let mut len = 0.0;
            table.push((0.0, 0.0));
            for k in 1..=SPLINE_TABLE {
                let u = k as f64 / SPLINE_TABLE as f64;
                let q = catmull_rom(&p, u);
                len += (q - prev).norm();
                prev = q;
                table.push((len, u));
            }
            pieces.push(Piece::Spline { p, table });
        }
        Ok(Self::build(pieces, waypoints.iter().map(|w| w.rotation).collect()))
    }

    /// Straight lines through the waypoints with every inner corner rounded by a circular arc
    /// tangent to both lines, starting `blend_radius_m` before the corner (reduced to half of
    /// the shorter neighbouring line where needed). Orientation is slerped along each line and
    /// held on the blend arcs.
    pub fn blended_polyline(waypoints: &[Isometry3<f64>], blend_radius_m: f64) -> Result<Self, PathError> {
        if waypoints.len() < 2 {
            return Err(PathError::TooFewWaypoints { what: "a polyline", min: 2, got: waypoints.len() });
        }
        if !(blend_radius_m.is_finite() && blend_radius_m >= 0.0) {
            return Err(PathError::Invalid(format!("blend radius {blend_radius_m} m must be ≥ 0")));
        }
        let pts: Vec<Point3<f64>> = waypoints.iter().map(|w| w.translation.vector.into()).collect();
        let mut pieces = Vec::new();
        let mut orient = vec![waypoints[0].rotation];
        let mut cursor = pts[0];
        for i in 1..pts.len() {
            let corner = pts[i];
            let last = i + 1 == pts.len();
            let blend = if last { None } else { corner_blend(&pts[i - 1], &corner, &pts[i + 1], blend_radius_m) };
            match blend {
                Some((enter, arc)) => {
                    pieces.push(Piece::Line { from: cursor, to: enter });
                    orient.push(waypoints[i].rotation);
                    let exit = arc.point(arc.length());
                    pieces.push(arc);
                    orient.push(waypoints[i].rotation);
                    cursor = exit;
                }
                None => {
                    pieces.push(Piece::Line { from: cursor, to: corner });
                    orient.push(waypoints[i].rotation);
                    cursor = corner;
                }
            }
        }
        Ok(Self::build(pieces, orient))
    }

    /// TCP travel along the path, m.
    pub fn length_m(&self) -> f64 {
        self.starts.last().copied().unwrap_or(0.0)
    }

    /// The path parameter's range, m: the travel, or the equivalent length of the largest
    /// re-orientation when that is longer.
    pub fn parameter_length_m(&self) -> f64 {
        self.length_m().max(self.rotation_length_m)
    }

    /// Pose at parameter `s` ∈ [0, [`TcpPath::parameter_length_m`]].
    pub fn pose(&self, s: f64) -> Isometry3<f64> {
        let total = self.parameter_length_m();
        let frac = if total > 0.0 { (s / total).clamp(0.0, 1.0) } else { 1.0 };
        let d = frac * self.length_m();
        let (k, local, piece_frac) = self.locate(d, frac);
        let Some(piece) = self.pieces.get(k) else {
            let last = self.orientations.last().copied().unwrap_or_else(UnitQuaternion::identity);
            return Isometry3::from_parts(Translation3::identity(), last);
        };
        let p = piece.point(local);
        let q = self.orientations[k].slerp(&self.orientations[k + 1], piece_frac);
        Isometry3::from_parts(Translation3::from(p.coords), q)
    }

    /// Piece index, distance into it and fraction of it at travel `d` (by `frac` of the whole
    /// when the path has no travel).
    fn locate(&self, d: f64, frac: f64) -> (usize, f64, f64) {
        let n = self.pieces.len();
        if n == 0 {
            return (0, 0.0, 1.0);
        }
        if self.length_m() <= 0.0 {
            let x = frac * n as f64;
            let k = (x.floor() as usize).min(n - 1);
            return (k, 0.0, (x - k as f64).clamp(0.0, 1.0));
        }
        let k = self.starts[1..].partition_point(|e| *e < d).min(n - 1);
        let local = (d - self.starts[k]).max(0.0);
        let len = self.pieces[k].length();
        (k, local, if len > 0.0 { (local / len).clamp(0.0, 1.0) } else { 1.0 })
    }
}

/// Centre and unit normal of the circle through three points (None when collinear).
pub(crate) fn circle_through(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Option<(Point3<f64>, Vector3<f64>)> {
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(&ac);
    let n2 = n.norm_squared();
    if n2 < 1e-18 {
        return None;
    }
    let center = a + (n.cross(&ab) * ac.norm_squared() + ac.cross(&n) * ab.norm_squared()) / (2.0 * n2);
    Some((center, n / n2.sqrt()))
}

/// The blend of the corner at `b` between lines a→b and b→c: where the path leaves the first
/// line, and the tangent arc. None when the corner is straight or the radius is 0.
fn corner_blend(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, radius: f64) -> Option<(Point3<f64>, Piece)> {
    let (d1, d2) = (b - a, c - b);
    let (l1, l2) = (d1.norm(), d2.norm());
    if radius <= 0.0 || l1 < 1e-9 || l2 < 1e-9 {
        return None;
    }
    let (t1, t2) = (d1 / l1, d2 / l2);
    let turn = t1.dot(&t2).clamp(-1.0, 1.0).acos();
    if !(1e-6..=std::f64::consts::PI - 1e-6).contains(&turn) {
        return None;
    }
    // distance from the corner where the arc starts, limited to half of each line
    let set_back = radius.min(0.5 * l1).min(0.5 * l2);
    let r = set_back / (0.5 * turn).tan();
    let enter = b - t1 * set_back;
    let normal = t1.cross(&t2).normalize();
    let inward = normal.cross(&t1);
    let center = enter + inward * r;
    let u = (enter - center) / r;
    let v = normal.cross(&u);
    Some((enter, Piece::Arc { center, u, v, radius: r, sweep_rad: turn }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn at(x: f64, y: f64, z: f64) -> Isometry3<f64> {
        Isometry3::translation(x, y, z)
    }

    #[test]
    fn a_line_is_straight_and_slerps_orientation() {
        let a = at(0.1, 0.2, 0.3);
        let mut b = at(0.2, 0.2, 0.1);
        b.rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.0);
        let p = TcpPath::line(&a, &b);
        assert!((p.length_m() - (0.01f64 + 0.04).sqrt()).abs() < 1e-12);
        let mid = p.pose(p.parameter_length_m() / 2.0);
        assert!((mid.translation.vector - Vector3::new(0.15, 0.2, 0.2)).norm() < 1e-12);
        assert!((mid.rotation.angle() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn an_arc_through_three_points_passes_through_them() {
        let a = at(0.2, 0.0, 0.2);
        let via = Point3::new(0.25, 0.05, 0.2);
        let c = at(0.3, 0.0, 0.2);
        let p = TcpPath::arc_through(&a, &via, &c).expect("arc");
        // half circle of radius 50 mm
        assert!((p.length_m() - std::f64::consts::PI * 0.05).abs() < 1e-9);
        let mid = p.pose(p.length_m() / 2.0);
        assert!((mid.translation.vector - via.coords).norm() < 1e-9);
        assert!((p.pose(p.length_m()).translation.vector - c.translation.vector).norm() < 1e-9);
        assert!(TcpPath::arc_through(&a, &Point3::new(0.25, 0.0, 0.2), &c).is_err());
    }

    #[test]
    fn a_full_circle_returns_to_its_start() {
        let a = at(0.25, 0.0, 0.2);
        let p =
            TcpPath::arc_about(&a, &Point3::new(0.2, 0.0, 0.2), &Vector3::z(), std::f64::consts::TAU).expect("circle");
        assert!((p.length_m() - std::f64::consts::TAU * 0.05).abs() < 1e-9);
        assert!((p.pose(p.length_m()).translation.vector - a.translation.vector).norm() < 1e-9);
        let quarter = p.pose(p.length_m() / 4.0);
        assert!((quarter.translation.vector - Vector3::new(0.2, 0.05, 0.2)).norm() < 1e-9);
    }

    #[test]
    fn a_spline_passes_through_its_waypoints() {
        let w = [at(0.0, 0.0, 0.0), at(0.1, 0.05, 0.0), at(0.2, 0.0, 0.05), at(0.3, 0.02, 0.0)];
        let p = TcpPath::spline(&w).expect("spline");
        for (k, wp) in w.iter().enumerate() {
            let d = p.starts[k.min(p.pieces.len())];
            assert!((p.pose(d).translation.vector - wp.translation.vector).norm() < 1e-9, "waypoint {k}");
        }
    }

    #[test]
    fn a_blended_corner_is_tangent_and_stays_near_the_corner() {
        let w = [at(0.0, 0.0, 0.0), at(0.1, 0.0, 0.0), at(0.1, 0.1, 0.0)];
        let p = TcpPath::blended_polyline(&w, 0.02).expect("blend");
        assert_eq!(p.pieces.len(), 3);
        // quarter circle of radius 20 mm replaces 40 mm of corner
        let expect = 0.08 + 0.08 + std::f64::consts::FRAC_PI_2 * 0.02;
        assert!((p.length_m() - expect).abs() < 1e-9, "{}", p.length_m());
        // continuous positions at the piece boundaries
        for k in 1..p.pieces.len() {
            let s = p.starts[k];
            let (a, b) = (p.pose(s - 1e-9), p.pose(s + 1e-9));
            assert!((a.translation.vector - b.translation.vector).norm() < 1e-6);
        }
        assert!((p.pose(p.length_m()).translation.vector - Vector3::new(0.1, 0.1, 0.0)).norm() < 1e-12);
    }
}
