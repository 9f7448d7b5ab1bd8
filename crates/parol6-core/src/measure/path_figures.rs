//! ISO 9283 path figures: the commanded path is cut by `m` planes normal to it, evenly spaced
//! along its length; each cycle's attained path crosses each plane once (the crossing nearest
//! the commanded point). Path accuracy AT_p is the largest distance between a commanded point
//! and the barycentre of its attained points; path repeatability RT_p the largest l̄ + 3·S_l
//! of the attained points about their barycentre (S with n − 1). Besides these, every
//! attained sample's distance to the commanded path gives the max and RMS deviation.

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
    #[error("{0} cycle(s) recorded; path figures need at least 2")]
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
        points: m,
        cycles: cycles.len(),
    })
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
