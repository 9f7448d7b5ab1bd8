//! The planned TCP path of a program, drawn over the 3D view as line strips coloured by the
//! pre-flight result (green ok, amber warning, red error). Drawn with the egui painter after
//! the 3D pass, projected with the view's camera; points closer than a pixel to the previous
//! drawn point are skipped, so a long program costs a few hundred segments.

use eframe::egui;
use parol6_core::na::{Matrix4, Point3};

use super::camera;
use crate::palette;

/// Pre-flight status of a path point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PathPointStatus {
    /// No problem.
    #[default]
    Ok,
    /// A warning (e.g. near a singularity).
    Warning,
    /// An error: the program is refused.
    Error,
}

impl PathPointStatus {
    /// Its colour (from the palette).
    pub fn color(self) -> egui::Color32 {
        palette::rgb(match self {
            PathPointStatus::Ok => palette::PATH_OK,
            PathPointStatus::Warning => palette::PATH_WARNING,
            PathPointStatus::Error => palette::PATH_ERROR,
        })
    }
}

/// A planned TCP path: points in the world frame (m) with their status, in strips.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathOverlay {
    points_m: Vec<[f32; 3]>,
    status: Vec<PathPointStatus>,
    /// Index of the first point of every strip after the first.
    breaks: Vec<usize>,
}

/// Width of the drawn path, px.
const PATH_WIDTH_PX: f32 = 2.0;
/// Points closer than this to the last drawn point are skipped, px.
const MIN_SEGMENT_PX: f32 = 1.5;

impl PathOverlay {
    /// Appends a point to the current strip.
    pub fn push(&mut self, p_m: [f32; 3], status: PathPointStatus) {
        self.points_m.push(p_m);
        self.status.push(status);
    }

    /// Starts a new strip (the next point is not joined to the previous one).
    pub fn break_strip(&mut self) {
        if !self.points_m.is_empty() {
            self.breaks.push(self.points_m.len());
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points_m.len()
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.points_m.is_empty()
    }

    /// The worst status on the path.
    pub fn worst(&self) -> Option<PathPointStatus> {
        self.status.iter().copied().max_by_key(|s| *s as u8)
    }

    /// Paints the path into `rect`; returns the number of segments drawn.
    pub fn paint(&self, painter: &egui::Painter, rect: egui::Rect, view_proj: &Matrix4<f32>) -> usize {
        let mut drawn = 0;
        let mut last: Option<egui::Pos2> = None;
        let mut next_break = self.breaks.iter().peekable();
        for (i, (p, s)) in self.points_m.iter().zip(&self.status).enumerate() {
            if next_break.peek().is_some_and(|b| **b == i) {
                next_break.next();
                last = None;
            }
            let Some(here) = camera::project_to_rect(view_proj, &Point3::new(p[0], p[1], p[2]), rect) else {
                last = None;
                continue;
            };
            match last {
                Some(prev) if prev.distance(here) < MIN_SEGMENT_PX => continue,
                Some(prev) => {
                    painter.line_segment([prev, here], egui::Stroke::new(PATH_WIDTH_PX, s.color()));
                    drawn += 1;
                }
                None => {}
            }
            last = Some(here);
        }
        drawn
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_break_and_the_worst_status_wins() {
        let mut o = PathOverlay::default();
        o.break_strip();
        o.push([0.0; 3], PathPointStatus::Ok);
        o.push([0.1, 0.0, 0.0], PathPointStatus::Warning);
        o.break_strip();
        o.push([0.2, 0.0, 0.0], PathPointStatus::Error);
        assert_eq!(o.len(), 3);
        assert_eq!(o.breaks, vec![2]);
        assert_eq!(o.worst(), Some(PathPointStatus::Error));
    }
}
