//! ISO 9283 path figures: the commanded path is cut by `m` planes normal to it, evenly spaced
//! along its length; each cycle's attained path crosses each plane once (the crossing nearest
//! the commanded point). Path accuracy AT_p is the largest distance between a commanded point
//! and the barycentre of its attained points; path repeatability RT_p the largest l̄ + 3·S_l
//! of the attained points about their barycentre (S with n − 1). Besides these, every
//! attained sample's distance to the commanded path gives the max and RMS deviation.
//!
//! Cornering deviations ([`corner_deviations`], for a path with corners: the triangle) follow
//! ISO 9283's cornering round-off error CR (how far the attained path stays from the corner
//! point: the nearest attained sample) and cornering overshoot CO (how far the attained path
//! goes beyond the outgoing leg, on the side the incoming leg came from the far side of,
//! after passing the corner and within the first half of the outgoing leg); both the worst
//! over the cycles.

use nalgebra::Vector3;
use serde::Serialize;

use super::pose_figures::mean_and_sample_sd;

/// The path figures of one test.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathFigures {
    /// Path accuracy, mm.
    #[serde(rename = "AT_p_mm")]
    pub at_p_mm: f64,
    /// Path repeatability, mm.
    #[serde(rename = "RT_p_mm")]
    pub rt_p_mm: f64,
    /// Largest distance of an attained sample from the commanded path, mm.
    pub max_deviation_mm: f64,
    /// RMS distance of the attained samples from the commanded path, mm.
    pub rms_deviation_mm: f64,
    /// Cornering round-off error CR, mm: the worst over the path's corners and the cycles
    /// (none for a path without corners).
    #[serde(rename = "CR_mm", skip_serializing_if = "Option::is_none")]
    pub cr_mm: Option<f64>,
    /// Cornering overshoot CO, mm: the worst over the path's corners and the cycles.
    #[serde(rename = "CO_mm", skip_serializing_if = "Option::is_none")]
    pub co_mm: Option<f64>,
    /// Number of points along the path.
    pub points: usize,
    /// Number of cycles.
    pub cycles: usize,
}

/// Why path figures cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathFigureError {
    /// The commanded path has no length.
    #[error("the commanded path has fewer than two distinct points")]
    NoPath,
    /// Too few cycles for a standard deviation.
    #[error("{} recorded; path figures need at least 2", crate::plural::count(*.0, "cycle"))]
    TooFewCycles(usize),
    /// A cycle recorded fewer than two samples.
    #[error("cycle {0} recorded fewer than two samples")]
    EmptyCycle(usize),
    /// No point count.
    #[error("the number of points along the path must be at least 1")]
    NoPoints,
}

/// A point on the commanded path and the unit tangent there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Position, mm.
    pub position: Vector3<f64>,
    /// Unit tangent.
    pub tangent: Vector3<f64>,
}

fn to_vec(p: &[[f64; 3]]) -> Vec<Vector3<f64>> {
    p.iter().map(|v| Vector3::from(*v)).collect()
}

/// `m` points along `polyline` at arc lengths (i + ½)/m of its length, with the tangent of the
/// segment each falls on; `None` when it has no length.
pub fn points_along(polyline: &[[f64; 3]], m: usize) -> Option<Vec<PathPoint>> {
    let p = to_vec(polyline);
    let lengths: Vec<f64> = p.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    let total: f64 = lengths.iter().sum();
    if total.is_nan() || total <= 1e-9 || m == 0 {
        return None;
    }
    let mut out = Vec::with_capacity(m);
    let (mut seg, mut before) = (0usize, 0.0);
    for i in 0..m {
        let s = total * (i as f64 + 0.5) / m as f64;
        while seg + 1 < lengths.len() && (before + lengths[seg] < s || lengths[seg] <= 1e-12) {
            before += lengths[seg];
            seg += 1;
        }
        let len = lengths[seg].max(1e-12);
        let f = ((s - before) / len).clamp(0.0, 1.0);
        let tangent = (p[seg + 1] - p[seg]) / len;
        out.push(PathPoint { position: p[seg] + (p[seg + 1] - p[seg]) * f, tangent });
    }
    Some(out)
}

/// Where `path` crosses the plane through `at` normal to its tangent, nearest `at`; the
/// nearest point of `path` when it does not cross.
pub fn crossing(path: &[Vector3<f64>], at: &PathPoint) -> Vector3<f64> {
    let side = |v: &Vector3<f64>| (v - at.position).dot(&at.tangent);
    let mut best: Option<(f64, Vector3<f64>)> = None;
    for w in path.windows(2) {
        let (a, b) = (side(&w[0]), side(&w[1]));
        if (a <= 0.0 && b >= 0.0) || (a >= 0.0 && b <= 0.0) {
            let f = if (b - a).abs() > 1e-15 { a / (a - b) } else { 0.0 };
            let x = w[0] + (w[1] - w[0]) * f;
            let d = (x - at.position).norm();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, x));
            }
        }
    }
    best.map_or_else(|| nearest_on(path, &at.position).1, |(_, x)| x)
}

/// Distance from `p` to the polyline `path` and the nearest point on it.
pub fn nearest_on(path: &[Vector3<f64>], p: &Vector3<f64>) -> (f64, Vector3<f64>) {
    let mut best = (f64::INFINITY, path.first().copied().unwrap_or_else(Vector3::zeros));
    if path.len() == 1 {
        return ((p - path[0]).norm(), path[0]);
    }
    for w in path.windows(2) {
        let d = w[1] - w[0];
        let len2 = d.norm_squared();
        let f = if len2 > 0.0 { ((p - w[0]).dot(&d) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let x = w[0] + d * f;
        let dist = (p - x).norm();
        if dist < best.0 {
            best = (dist, x);
        }
    }
    best
}

/// Path figures of the attained paths (one polyline per cycle, mm) against `commanded` (mm)
/// at `m` points.
pub fn compute(commanded: &[[f64; 3]], attained: &[Vec<[f64; 3]>], m: usize) -> Result<PathFigures, PathFigureError> {
    if m == 0 {
        return Err(PathFigureError::NoPoints);
    }
    let points = points_along(commanded, m).ok_or(PathFigureError::NoPath)?;
    if attained.len() < 2 {
        return Err(PathFigureError::TooFewCycles(attained.len()));
    }
    let cycles: Vec<Vec<Vector3<f64>>> = attained.iter().map(|c| to_vec(c)).collect();
    if let Some(i) = cycles.iter().position(|c| c.len() < 2) {
        return Err(PathFigureError::EmptyCycle(i + 1));
    }
    let (mut at_p, mut rt_p) = (0.0f64, 0.0f64);
    for point in &points {
        let hits: Vec<Vector3<f64>> = cycles.iter().map(|c| crossing(c, point)).collect();
        let bary = hits.iter().sum::<Vector3<f64>>() / hits.len() as f64;
        at_p = at_p.max((bary - point.position).norm());
        let l: Vec<f64> = hits.iter().map(|h| (h - bary).norm()).collect();
        let (l_mean, s_l) = mean_and_sample_sd(&l);
        rt_p = rt_p.max(l_mean + 3.0 * s_l);
    }
    let reference = to_vec(commanded);
    let (mut max_dev, mut sum2, mut count) = (0.0f64, 0.0, 0usize);
    for p in cycles.iter().flatten() {
        let d = nearest_on(&reference, p).0;
        max_dev = max_dev.max(d);
        sum2 += d * d;
        count += 1;
    }
    Ok(PathFigures {
        at_p_mm: at_p,
        rt_p_mm: rt_p,
        max_deviation_mm: max_dev,
        rms_deviation_mm: (sum2 / count.max(1) as f64).sqrt(),
        cr_mm: None,
        co_mm: None,
        points: m,
        cycles: cycles.len(),
    })
}

/// ISO 9283 cornering deviations at one corner of the path, the worst over the cycles, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CornerFigures {
    /// Cornering round-off error CR: the attained path's nearest approach to the corner point.
    #[serde(rename = "CR_mm")]
    pub cr_mm: f64,
    /// Cornering overshoot CO: the attained path's largest excursion beyond the outgoing leg.
    #[serde(rename = "CO_mm")]
    pub co_mm: f64,
}

/// The cornering deviations of the attained paths (one time-ordered polyline per cycle, mm) at
/// each inner vertex of the commanded polyline `legs_mm` (vertices in order, e.g. the triangle
/// A, B, C, A: corners B and C; the ends are where the arm starts and stops, not corners).
/// Vertices where the path turns by less than 1° are not corners.
pub fn corner_deviations(legs_mm: &[[f64; 3]], attained: &[Vec<[f64; 3]>]) -> Vec<CornerFigures> {
    let v = to_vec(legs_mm);
    let cycles: Vec<Vec<Vector3<f64>>> = attained.iter().filter(|c| !c.is_empty()).map(|c| to_vec(c)).collect();
    let mut out = Vec::new();
    for w in v.windows(3) {
        let (a, c, b) = (w[0], w[1], w[2]);
        let (Some(d_in), Some(d_out)) = ((c - a).try_normalize(1e-9), (b - c).try_normalize(1e-9)) else { continue };
        if d_in.dot(&d_out) > 1f64.to_radians().cos() {
            continue;
        }
        // the side of the outgoing leg the arm would overshoot to: the incoming direction's
        // part across the outgoing leg
        let Some(beyond) = (d_in - d_out * d_in.dot(&d_out)).try_normalize(1e-9) else { continue };
        let half_leg = 0.5 * (b - c).norm();
        let (mut cr, mut co) = (0.0f64, 0.0f64);
        for cycle in &cycles {
            // the attained polyline's nearest approach (not the nearest sample: at 100 Hz and
            // 250 mm/s the samples are 2.5 mm apart), and the sample it is reached after
            let (d_min, nearest) = nearest_segment(cycle, &c);
            cr = cr.max(d_min);
            for p in &cycle[nearest..] {
                let along = (p - c).dot(&d_out);
                if along > half_leg {
                    break;
                }
                co = co.max((p - c).dot(&beyond));
            }
        }
        out.push(CornerFigures { cr_mm: cr, co_mm: co });
    }
    out
}

/// Distance from `p` to the polyline `path`, and the index of the first sample of the nearest
/// segment (0 for a single sample).
fn nearest_segment(path: &[Vector3<f64>], p: &Vector3<f64>) -> (f64, usize) {
    let mut best = (path.first().map_or(f64::INFINITY, |q| (p - q).norm()), 0);
    for (i, w) in path.windows(2).enumerate() {
        let d = w[1] - w[0];
        let len2 = d.norm_squared();
        let f = if len2 > 0.0 { ((p - w[0]).dot(&d) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let dist = (p - (w[0] + d * f)).norm();
        if dist < best.0 {
            best = (dist, i);
        }
    }
    best
}

impl PathFigures {
    /// Adds the worst cornering deviations of `corners` (none: the path has no corner).
    pub fn with_corners(mut self, corners: &[CornerFigures]) -> Self {
        if !corners.is_empty() {
            self.cr_mm = Some(corners.iter().map(|c| c.cr_mm).fold(0.0, f64::max));
            self.co_mm = Some(corners.iter().map(|c| c.co_mm).fold(0.0, f64::max));
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn two_parallel_attained_lines_give_the_hand_computed_figures() {
        // commanded x = 0…100 along y = 0; attained at y = 1 and y = 3. Points at x = 25, 75:
        // barycentres at y = 2 → AT_p = 2; l = 1, 1 → l̄ = 1, S = 0 → RT_p = 1. Sample
        // deviations 1, 1, 3, 3 → max 3, RMS √5.
        let cmd = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]];
        let att = vec![vec![[0.0, 1.0, 0.0], [100.0, 1.0, 0.0]], vec![[0.0, 3.0, 0.0], [100.0, 3.0, 0.0]]];
        let f = compute(&cmd, &att, 2).unwrap();
        assert!(close(f.at_p_mm, 2.0), "{f:?}");
        assert!(close(f.rt_p_mm, 1.0), "{f:?}");
        assert!(close(f.max_deviation_mm, 3.0));
        assert!(close(f.rms_deviation_mm, 5f64.sqrt()));
        assert_eq!((f.points, f.cycles), (2, 2));
    }

    #[test]
    fn points_are_evenly_spaced_along_a_bent_path() {
        // an L: 0→(10,0,0)→(10,10,0), 20 mm; 4 points at 2.5, 7.5, 12.5, 17.5 mm
        let p = points_along(&[[0.0; 3], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]], 4).unwrap();
        let want = [[2.5, 0.0, 0.0], [7.5, 0.0, 0.0], [10.0, 2.5, 0.0], [10.0, 7.5, 0.0]];
        for (got, want) in p.iter().zip(want) {
            assert!((got.position - Vector3::from(want)).norm() < 1e-12, "{got:?}");
        }
        assert_eq!(p[2].tangent, Vector3::y());
        assert!(points_along(&[[1.0; 3], [1.0; 3]], 3).is_none());
    }

    #[test]
    fn the_crossing_is_on_the_normal_plane_and_nearest_the_point() {
        // a closed square path crosses the plane x = 2 twice (y = 0 and y = 4): the one near
        // the commanded point (2, 0.5) is taken
        let sq: Vec<Vector3<f64>> =
            [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 4.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 0.0]]
                .iter()
                .map(|v| Vector3::from(*v))
                .collect();
        let at = PathPoint { position: Vector3::new(2.0, 0.5, 0.0), tangent: Vector3::x() };
        assert!((crossing(&sq, &at) - Vector3::new(2.0, 0.0, 0.0)).norm() < 1e-12);
        // no crossing (the plane lies beyond the path): the nearest point
        let far = PathPoint { position: Vector3::new(9.0, 1.0, 0.0), tangent: Vector3::x() };
        assert!((crossing(&sq, &far) - Vector3::new(4.0, 1.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn corner_deviations_of_a_cut_and_an_overshooting_corner() {
        // commanded L: (0,0,0) → (10,0,0) → (10,10,0). Cycle 1 cuts the corner along the chord
        // (8,0,0)–(10,2,0) (samples 2 mm apart along it would not matter): the chord's nearest
        // point to the corner is (9,1,0), CR = √2, no overshoot. Cycle 2 runs 2 mm past the
        // corner along x, to (12,0,0), then back up through (11,3,0): it passes through the
        // corner (CR 0) and goes 2 mm beyond the outgoing leg x = 10: the worst over both
        // cycles is CR = √2, CO = 2.
        let legs = [[0.0; 3], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]];
        let cut = vec![[0.0; 3], [8.0, 0.0, 0.0], [10.0, 2.0, 0.0], [10.0, 10.0, 0.0]];
        let over = vec![[0.0; 3], [11.0, 0.0, 0.0], [12.0, 0.0, 0.0], [11.0, 3.0, 0.0], [10.0, 10.0, 0.0]];
        let c = corner_deviations(&legs, std::slice::from_ref(&cut));
        assert_eq!(c.len(), 1);
        assert!(close(c[0].cr_mm, 2f64.sqrt()) && close(c[0].co_mm, 0.0), "{c:?}");
        let c = corner_deviations(&legs, &[cut, over]);
        assert!(close(c[0].cr_mm, 2f64.sqrt()) && close(c[0].co_mm, 2.0), "{c:?}");
        // a straight path has no corner; a path through its corner exactly has CR = CO = 0
        assert!(corner_deviations(&[[0.0; 3], [5.0, 0.0, 0.0], [10.0, 0.0, 0.0]], &[cut_free()]).is_empty());
        let exact = corner_deviations(&legs, &[legs.to_vec(), legs.to_vec()]);
        assert!(close(exact[0].cr_mm, 0.0) && close(exact[0].co_mm, 0.0));
        let f = compute(&legs, &[legs.to_vec(), legs.to_vec()], 4).unwrap().with_corners(&exact);
        assert_eq!((f.cr_mm, f.co_mm), (Some(0.0), Some(0.0)));
    }

    fn cut_free() -> Vec<[f64; 3]> {
        vec![[0.0; 3], [10.0, 0.0, 0.0]]
    }

    #[test]
    fn bad_inputs_are_errors() {
        let cmd = [[0.0; 3], [1.0, 0.0, 0.0]];
        let one = vec![vec![[0.0; 3], [1.0, 0.0, 0.0]]];
        assert_eq!(compute(&cmd, &one, 5), Err(PathFigureError::TooFewCycles(1)));
        let short = vec![one[0].clone(), vec![[0.0; 3]]];
        assert_eq!(compute(&cmd, &short, 5), Err(PathFigureError::EmptyCycle(2)));
        assert_eq!(compute(&[[0.0; 3]], &short, 5), Err(PathFigureError::NoPath));
        assert_eq!(compute(&cmd, &short, 0), Err(PathFigureError::NoPoints));
    }
}
