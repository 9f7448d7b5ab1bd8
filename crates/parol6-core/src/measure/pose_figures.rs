//! ISO 9283 pose figures from attained poses: per pose the accuracy AP (mean attained minus
//! commanded) and the repeatability RP (l̄ + 3·S_l for position, 3·S for each angle, S with
//! n − 1), and the distance accuracy AD and repeatability RD between P2 and P4.
//!
//! Angles a, b, c are the rotations about x, y, z: our URDF roll, pitch, yaw. Each attained
//! angle is taken relative to the commanded one and wrapped to ±180°, so a pose near roll =
//! 180° (tool down) gives small numbers, not 360° jumps.

use nalgebra::Vector3;
use serde::Serialize;

use super::cube::POSE_NAMES;
use crate::program::PoseMm;

/// One attained pose: which cycle and test pose, what was commanded and what was reached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PoseSample {
    /// 1-based cycle.
    pub cycle: u32,
    /// Test pose index (0 = P1 … 4 = P5).
    pub pose: usize,
    /// Commanded pose.
    pub commanded: PoseMm,
    /// Attained pose.
    pub attained: PoseMm,
}

/// The figures of one test pose. Serialises to the JSON of `parol6 iso9283 --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseFigures {
    /// "P1" … "P5".
    pub name: String,
    /// Position accuracy |mean attained − commanded|, mm.
    #[serde(rename = "AP_p_mm")]
    pub ap_p_mm: f64,
    /// Position accuracy along x, mm.
    #[serde(rename = "AP_x_mm")]
    pub ap_x_mm: f64,
    /// Position accuracy along y, mm.
    #[serde(rename = "AP_y_mm")]
    pub ap_y_mm: f64,
    /// Position accuracy along z, mm.
    #[serde(rename = "AP_z_mm")]
    pub ap_z_mm: f64,
    /// Orientation accuracy about x (roll), deg.
    #[serde(rename = "AP_a_deg")]
    pub ap_a_deg: f64,
    /// Orientation accuracy about y (pitch), deg.
    #[serde(rename = "AP_b_deg")]
    pub ap_b_deg: f64,
    /// Orientation accuracy about z (yaw), deg.
    #[serde(rename = "AP_c_deg")]
    pub ap_c_deg: f64,
    /// Position repeatability l̄ + 3·S_l, mm.
    #[serde(rename = "RP_l_mm")]
    pub rp_l_mm: f64,
    /// Orientation repeatability about x, 3·S_a, deg.
    #[serde(rename = "RP_a_deg")]
    pub rp_a_deg: f64,
    /// Orientation repeatability about y, 3·S_b, deg.
    #[serde(rename = "RP_b_deg")]
    pub rp_b_deg: f64,
    /// Orientation repeatability about z, 3·S_c, deg.
    #[serde(rename = "RP_c_deg")]
    pub rp_c_deg: f64,
    /// Number of cycles.
    #[serde(skip)]
    pub cycles: usize,
    /// Commanded position, mm.
    #[serde(skip)]
    pub commanded_mm: [f64; 3],
    /// Barycentre of the attained positions, mm.
    #[serde(skip)]
    pub mean_mm: [f64; 3],
}

/// The figures of a whole pose test. Serialises to the JSON of `parol6 iso9283 --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseTestFigures {
    /// Per test pose, in pose order.
    pub poses: Vec<PoseFigures>,
    /// Distance accuracy P2–P4: mean attained distance − commanded, mm (`None` without
    /// P2 and P4 in at least two cycles).
    #[serde(rename = "AD_p_mm")]
    pub ad_p_mm: Option<f64>,
    /// Distance repeatability P2–P4: 3·S_D, mm.
    #[serde(rename = "RD_mm")]
    pub rd_mm: Option<f64>,
}

/// Why figures cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    /// No attained poses at all.
    #[error("no attained poses")]
    Empty,
    /// A pose has fewer than two cycles (the standard deviation needs n ≥ 2).
    #[error("{pose} has {}; the figures need at least 2", crate::plural::count(*.cycles, "cycle"))]
    TooFewCycles {
        /// Pose name.
        pose: &'static str,
        /// Cycles found.
        cycles: usize,
    },
    /// A value is not finite.
    #[error("cycle {cycle}, {pose}: a value is not a finite number")]
    NotFinite {
        /// Cycle.
        cycle: u32,
        /// Pose name.
        pose: &'static str,
    },
}

/// `a − b` wrapped to (−180°, 180°].
pub fn angle_difference_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 { d - 360.0 } else { d }
}

/// Mean and sample standard deviation (n − 1) of `values` (at least two).
pub fn mean_and_sample_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// Figures of one pose from its samples (all of the same pose, at least two).
fn pose_figures(pose: usize, samples: &[&PoseSample]) -> PoseFigures {
    let commanded = samples[0].commanded;
    let c = Vector3::from(commanded.position_mm);
    let positions: Vec<Vector3<f64>> = samples.iter().map(|s| Vector3::from(s.attained.position_mm)).collect();
    let mean = positions.iter().sum::<Vector3<f64>>() / positions.len() as f64;
    let ap = mean - c;
    let l: Vec<f64> = positions.iter().map(|p| (p - mean).norm()).collect();
    let (l_mean, s_l) = mean_and_sample_sd(&l);
    let angle = |k: usize| {
        let d: Vec<f64> =
            samples.iter().map(|s| angle_difference_deg(s.attained.rpy_deg[k], s.commanded.rpy_deg[k])).collect();
        mean_and_sample_sd(&d)
    };
    let [(ap_a, s_a), (ap_b, s_b), (ap_c, s_c)] = [angle(0), angle(1), angle(2)];
    PoseFigures {
        name: POSE_NAMES[pose].to_string(),
        ap_p_mm: ap.norm(),
        ap_x_mm: ap.x,
        ap_y_mm: ap.y,
        ap_z_mm: ap.z,
        ap_a_deg: ap_a,
        ap_b_deg: ap_b,
        ap_c_deg: ap_c,
        rp_l_mm: l_mean + 3.0 * s_l,
        rp_a_deg: 3.0 * s_a,
        rp_b_deg: 3.0 * s_b,
        rp_c_deg: 3.0 * s_c,
        cycles: samples.len(),
        commanded_mm: commanded.position_mm,
        mean_mm: mean.into(),
    }
}

/// The figures of every pose that has samples, and AD / RD between P2 and P4.
pub fn compute(samples: &[PoseSample]) -> Result<PoseTestFigures, FigureError> {
    if samples.is_empty() {
        return Err(FigureError::Empty);
    }
    for s in samples {
        let values = s.commanded.position_mm.iter().chain(&s.commanded.rpy_deg);
        if !values.chain(&s.attained.position_mm).chain(&s.attained.rpy_deg).all(|v| v.is_finite()) {
            return Err(FigureError::NotFinite { cycle: s.cycle, pose: POSE_NAMES[s.pose.min(4)] });
        }
    }
    let mut poses = Vec::new();
    for (pose, name) in POSE_NAMES.iter().enumerate() {
        let of_pose: Vec<&PoseSample> = samples.iter().filter(|s| s.pose == pose).collect();
        match of_pose.len() {
            0 => continue,
            1 => return Err(FigureError::TooFewCycles { pose: name, cycles: 1 }),
            _ => poses.push(pose_figures(pose, &of_pose)),
        }
    }
    let (ad_p_mm, rd_mm) = distance_figures(samples).unzip();
    Ok(PoseTestFigures { poses, ad_p_mm, rd_mm })
}

/// AD_p and RD between P2 and P4 over the cycles that have both.
fn distance_figures(samples: &[PoseSample]) -> Option<(f64, f64)> {
    let find = |cycle: u32, pose: usize| samples.iter().find(|s| s.cycle == cycle && s.pose == pose);
    let mut commanded = None;
    let mut attained = Vec::new();
    let mut cycles: Vec<u32> = samples.iter().map(|s| s.cycle).collect();
    cycles.sort_unstable();
    cycles.dedup();
    for cycle in cycles {
        if let (Some(p2), Some(p4)) = (find(cycle, 1), find(cycle, 3)) {
            let d = |a: &PoseMm, b: &PoseMm| (Vector3::from(a.position_mm) - Vector3::from(b.position_mm)).norm();
            commanded.get_or_insert(d(&p2.commanded, &p4.commanded));
            attained.push(d(&p2.attained, &p4.attained));
        }
    }
    if attained.len() < 2 {
        return None;
    }
    let (mean, sd) = mean_and_sample_sd(&attained);
    Some((mean - commanded?, 3.0 * sd))
}

#[cfg(test)]
mod tests;
