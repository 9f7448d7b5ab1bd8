//! A sampled TCP path → `G1` lines within a tolerance (Ramer–Douglas–Peucker on position and
//! orientation), with the feed of each line from the samples' timing; and the same for the
//! `/tcp_pose` topic of one of our MCAP recordings.

use nalgebra::{Isometry3, Point3, UnitQuaternion};

use super::export::{GcodeExportError, axis_words, preamble};
use super::{AbcConvention, format_number};
use crate::program::PoseMm;
use crate::program::compile::{MAX_TCP_SPEED_MM_S, MIN_TCP_SPEED_MM_S};
use crate::telemetry::reader::read_recording;

/// How far simplified `G1` lines may leave a sampled path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathTolerance {
    /// Position, mm (at least 0.001).
    pub position_mm: f64,
    /// Orientation, deg (at least 0.001).
    pub orientation_deg: f64,
}

impl Default for PathTolerance {
    /// 0.1 mm and 0.5°.
    fn default() -> Self {
        Self { position_mm: 0.1, orientation_deg: 0.5 }
    }
}

impl PathTolerance {
    pub(crate) fn check(&self) -> Result<(), GcodeExportError> {
        let valid = |v: f64| v.is_finite() && v >= 0.001;
        if !valid(self.position_mm) || !valid(self.orientation_deg) {
            return Err(GcodeExportError::Input(format!(
                "the tolerance must be at least 0.001 mm and 0.001°, got {} mm and {}°",
                self.position_mm, self.orientation_deg
            )));
        }
        Ok(())
    }
}

/// Most samples one path may have.
pub const MAX_PATH_SAMPLES: usize = 2_000_000;
/// A dwell shorter than this is left out, s.
const MIN_DWELL_S: f64 = 0.001;
/// The TCP stands still while slower than this (a quarter of the slowest feed), mm/s…
const STILL_MM_S: f64 = 0.5;
/// … and turning slower than this, deg/s.
const STILL_DEG_S: f64 = 0.5;
/// A stretch standing still this long is a dwell, s.
const STOP_S: f64 = 0.1;

/// The stops of a sampled path: `(first, last)` sample of each stretch standing still for at
/// least [`STOP_S`].
fn stops(times: &[f64], poses: &[Isometry3<f64>]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from: Option<usize> = None;
    for k in 0..poses.len() {
        let still = k + 1 < poses.len() && {
            let dt = times[k + 1] - times[k];
            let moved_mm = (poses[k + 1].translation.vector - poses[k].translation.vector).norm() * 1000.0;
            let turned_deg = poses[k].rotation.angle_to(&poses[k + 1].rotation).to_degrees();
            moved_mm < STILL_MM_S * dt && turned_deg < STILL_DEG_S * dt
        };
        match (still, from) {
            (true, None) => from = Some(k),
            (false, Some(i)) => {
                if times[k] - times[i] >= STOP_S {
                    out.push((i, k));
                }
                from = None;
            }
            _ => {}
        }
    }
    out
}

/// The indices of `poses` a polyline through them keeps within `tol` (first and last always).
pub(crate) fn simplify(poses: &[Isometry3<f64>], tol: &PathTolerance) -> Vec<usize> {
    let n = poses.len();
    if n <= 2 {
        return (0..n).collect();
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0usize, n - 1)];
    let tol_rad = tol.orientation_deg.to_radians();
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (a, b) = (Point3::from(poses[i].translation.vector), Point3::from(poses[j].translation.vector));
        let ab = b - a;
        let len2 = ab.norm_squared();
        let mut worst = (0.0, 0usize);
        for (k, pose) in poses.iter().enumerate().take(j).skip(i + 1) {
            let p = Point3::from(pose.translation.vector);
            let f =
                if len2 > 1e-18 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { (k - i) as f64 / (j - i) as f64 };
            let pos_err = (p - (a + ab * f)).norm() * 1000.0 / tol.position_mm;
            let q = slerp(&poses[i].rotation, &poses[j].rotation, f);
            let ang_err = pose.rotation.angle_to(&q) / tol_rad;
            let err = pos_err.max(ang_err);
            if err > worst.0 {
                worst = (err, k);
            }
        }
        if worst.0 > 1.0 {
            keep[worst.1] = true;
            stack.push((i, worst.1));
            stack.push((worst.1, j));
        }
    }
    keep.iter().enumerate().filter(|(_, k)| **k).map(|(i, _)| i).collect()
}

pub(crate) fn slerp(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, f: f64) -> UnitQuaternion<f64> {
    a.try_slerp(b, f, 1e-12).unwrap_or(*a)
}

/// G-code for a sampled TCP path `(t_s, pose)`: a `G0` to the first pose, then `G1` lines
/// through the poses Ramer–Douglas–Peucker keeps within `tolerance`, each with the feed that
/// takes it as long as the samples did (limited to the PAROL6's 2–200 mm/s); a stretch of at
/// least 0.1 s standing still (under 0.5 mm/s and 0.5°/s) becomes a `G4` dwell of its
/// duration, as does a kept line shorter than the tolerance. Times must increase. `A B C` are
/// written in `abc`, named in the file's header line.
pub fn tcp_path_to_gcode(
    samples: &[(f64, PoseMm)],
    tolerance: &PathTolerance,
    abc: AbcConvention,
) -> Result<String, GcodeExportError> {
    tolerance.check()?;
    if samples.is_empty() {
        return Err(GcodeExportError::Input("the path has no samples".into()));
    }
    if samples.len() > MAX_PATH_SAMPLES {
        return Err(GcodeExportError::Input(format!("the path has more than {MAX_PATH_SAMPLES} samples")));
    }
    for (k, (t, p)) in samples.iter().enumerate() {
        let finite = t.is_finite() && p.position_mm.iter().chain(&p.rpy_deg).all(|v| v.is_finite());
        if !finite {
            return Err(GcodeExportError::Input(format!("sample {k}: not a finite number")));
        }
        if k > 0 && *t <= samples[k - 1].0 {
            return Err(GcodeExportError::Input(format!("sample {k}: its time {t} s does not increase")));
        }
    }
    let poses: Vec<Isometry3<f64>> = samples.iter().map(|(_, p)| p.isometry()).collect();
    let times: Vec<f64> = samples.iter().map(|(t, _)| *t).collect();
    let stops = stops(&times, &poses);
    // simplify the stretches between stops; a stop's first and last samples stay
    let mut kept = Vec::new();
    let mut from = 0;
    for &(i, j) in stops.iter().chain([(poses.len() - 1, poses.len() - 1)].iter()) {
        for k in simplify(&poses[from..=i], tolerance) {
            if kept.last() != Some(&(from + k)) {
                kept.push(from + k);
            }
        }
        if kept.last() != Some(&j) {
            kept.push(j);
        }
        from = j;
    }
    let duration_s = samples[samples.len() - 1].0 - samples[0].0;
    let mut out = format!(
        "{}; TCP path: {} samples over {} s, {} lines within {} mm and {}°\nG21 G90 G17\n",
        preamble(abc),
        samples.len(),
        format_number(duration_s),
        kept.len(),
        format_number(tolerance.position_mm),
        format_number(tolerance.orientation_deg)
    );
    out.push_str(&format!("G0 {}\n", axis_words(&samples[kept[0]].1, abc)));
    let mut feed = None;
    for w in kept.windows(2) {
        let (i, j) = (w[0], w[1]);
        let dt = samples[j].0 - samples[i].0;
        let chord_mm = (poses[j].translation.vector - poses[i].translation.vector).norm() * 1000.0;
        let turn_deg = poses[i].rotation.angle_to(&poses[j].rotation).to_degrees();
        let stop = stops.iter().any(|&(a, b)| a == i && b == j);
        if stop || (chord_mm < tolerance.position_mm && turn_deg < tolerance.orientation_deg) {
            if dt >= MIN_DWELL_S {
                out.push_str(&format!("G4 P{}\n", format_number(dt * 1000.0)));
            }
            continue;
        }
        let speed_mm_s = (chord_mm / dt).clamp(MIN_TCP_SPEED_MM_S, MAX_TCP_SPEED_MM_S);
        // whole mm/min: the feed need not be finer
        let f = (speed_mm_s * 60.0).round().clamp(MIN_TCP_SPEED_MM_S * 60.0, MAX_TCP_SPEED_MM_S * 60.0);
        let f_word = if feed == Some(f) { String::new() } else { format!(" F{}", format_number(f)) };
        feed = Some(f);
        out.push_str(&format!("G1 {}{f_word}\n", axis_words(&samples[j].1, abc)));
    }
    out.push_str("M30\n");
    Ok(out)
}

/// G-code for the TCP path of one of our MCAP recordings (its `/tcp_pose` topic, at most
/// 100 Hz), as [`tcp_path_to_gcode`]. Samples with a time that does not increase are dropped.
pub fn recording_to_gcode(
    bytes: &[u8],
    tolerance: &PathTolerance,
    abc: AbcConvention,
) -> Result<String, GcodeExportError> {
    let rec = read_recording(bytes).map_err(|e| GcodeExportError::Input(format!("the recording: {e}")))?;
    let mut samples: Vec<(f64, PoseMm)> = Vec::with_capacity(rec.tcp_path.len());
    let t0 = rec.tcp_path.first().map_or(0, |p| p.timestamp.as_ns());
    for m in &rec.tcp_path {
        let t = m.timestamp.as_ns().saturating_sub(t0) as f64 * 1e-9;
        let (p, o) = (m.pose.position, m.pose.orientation);
        let q = nalgebra::Quaternion::new(o.w, o.x, o.y, o.z);
        if q.norm() < 1e-9 || !q.coords.iter().all(|v| v.is_finite()) {
            continue;
        }
        let iso = Isometry3::from_parts(nalgebra::Translation3::new(p.x, p.y, p.z), UnitQuaternion::from_quaternion(q));
        if samples.last().is_none_or(|(last, _)| t > *last) {
            samples.push((t, PoseMm::from_isometry(&iso)));
        }
    }
    if samples.is_empty() {
        return Err(GcodeExportError::Input("the recording has no /tcp_pose messages".into()));
    }
    tcp_path_to_gcode(&samples, tolerance, abc)
}
