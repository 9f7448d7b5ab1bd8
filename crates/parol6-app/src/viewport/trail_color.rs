//! The colour of each TCP trail point: the palette's trail colour, or a blue → green → red
//! scale ([`palette::VIEW_TRAIL_SCALE`]) of the TCP speed or of the tracking error at the
//! moment the point was added. Linear RGB, as the trail's vertex buffer holds it.

use serde::{Deserialize, Serialize};

use crate::palette;

/// Top of the speed scale, m/s: the PAROL6's Cartesian speed limit, 200 mm/s (ROBOT.md §5).
pub const SPEED_FULL_SCALE_M_S: f64 = 0.2;
/// Top of the tracking-error scale (largest |commanded − measured| over the joints), rad: 1°.
pub const TRACKING_ERROR_FULL_SCALE_RAD: f64 = std::f64::consts::PI / 180.0;

/// What colours the trail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum TrailColoring {
    /// One colour ([`palette::VIEW_TRAIL`]).
    #[default]
    Plain,
    /// TCP speed, 0 to [`SPEED_FULL_SCALE_M_S`].
    Speed,
    /// Tracking error, 0 to [`TRACKING_ERROR_FULL_SCALE_RAD`].
    TrackingError,
}

impl TrailColoring {
    /// Every choice, for the View menu.
    pub const ALL: [TrailColoring; 3] = [TrailColoring::Plain, TrailColoring::Speed, TrailColoring::TrackingError];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            TrailColoring::Plain => "Trail: one colour",
            TrailColoring::Speed => "Trail: TCP speed (0–200 mm/s)",
            TrailColoring::TrackingError => "Trail: tracking error (0–1°)",
        }
    }
}

/// What the trail's colouring reads at the moment a point is added.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrailSample {
    /// TCP speed, m/s.
    pub tcp_speed_m_s: f64,
    /// Largest |commanded − measured| over the joints, rad.
    pub tracking_error_rad: f64,
}

/// Linear RGB of a point under `coloring`.
pub fn trail_rgb(coloring: TrailColoring, sample: TrailSample) -> [f32; 3] {
    let x = match coloring {
        TrailColoring::Plain => return palette::linear_rgb(palette::VIEW_TRAIL),
        TrailColoring::Speed => sample.tcp_speed_m_s / SPEED_FULL_SCALE_M_S,
        TrailColoring::TrackingError => sample.tracking_error_rad / TRACKING_ERROR_FULL_SCALE_RAD,
    };
    scale_rgb(x)
}

/// The scale at `x` (0 = low, 1 = top; clamped, NaN reads as 0), linear RGB.
pub fn scale_rgb(x: f64) -> [f32; 3] {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else if x > 0.0 {
        1.0
    } else {
        0.0
    } as f32;
    let [lo, mid, hi] = palette::VIEW_TRAIL_SCALE.map(palette::linear_rgb);
    let (a, b, f) = if x <= 0.5 { (lo, mid, x * 2.0) } else { (mid, hi, (x - 0.5) * 2.0) };
    std::array::from_fn(|i| a[i] * (1.0 - f) + b[i] * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_runs_from_low_through_middle_to_top_and_clamps() {
        let [lo, mid, hi] = palette::VIEW_TRAIL_SCALE.map(palette::linear_rgb);
        assert_eq!(scale_rgb(0.0), lo);
        assert_eq!(scale_rgb(0.5), mid);
        assert_eq!(scale_rgb(1.0), hi);
        assert_eq!(scale_rgb(-3.0), lo);
        assert_eq!(scale_rgb(7.0), hi);
        assert_eq!(scale_rgb(f64::NAN), lo);
        assert_eq!(scale_rgb(f64::INFINITY), hi);
        // between stops: between their channels
        let q = scale_rgb(0.25);
        for i in 0..3 {
            assert!(q[i] >= lo[i].min(mid[i]) && q[i] <= lo[i].max(mid[i]));
        }
    }

    #[test]
    fn speed_and_error_map_onto_their_full_scales() {
        let s = |v, e| TrailSample { tcp_speed_m_s: v, tracking_error_rad: e };
        assert_eq!(trail_rgb(TrailColoring::Plain, s(9.0, 9.0)), palette::linear_rgb(palette::VIEW_TRAIL));
        assert_eq!(trail_rgb(TrailColoring::Speed, s(0.1, 9.0)), scale_rgb(0.5));
        assert_eq!(trail_rgb(TrailColoring::Speed, s(0.4, 0.0)), scale_rgb(1.0));
        let half = trail_rgb(TrailColoring::TrackingError, s(9.0, 0.5f64.to_radians()));
        assert!(half.iter().zip(scale_rgb(0.5)).all(|(a, b)| (a - b).abs() < 1e-5), "{half:?}");
        assert_eq!(trail_rgb(TrailColoring::TrackingError, s(9.0, 0.0)), scale_rgb(0.0));
    }
}
