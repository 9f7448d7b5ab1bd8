//! The planned TCP path of a program, drawn over the 3D view as line strips coloured by the
//! pre-flight result (green ok, amber warning, red error). Drawn with the egui painter after
//! the 3D pass, projected with the view's camera; points closer than a pixel to the previous
//! drawn point are skipped, and the segments of one colour are one line shape, so a long
//! program costs a few shapes.

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

    /// Paints the path into `rect`; returns the number of segments drawn. Consecutive
    /// segments of one status are one line shape, so a long path is a handful of shapes.
    pub fn paint(&self, painter: &egui::Painter, rect: egui::Rect, view_proj: &Matrix4<f32>) -> usize {
        let mut drawn = 0;
        let mut last: Option<egui::Pos2> = None;
        let mut run: Vec<egui::Pos2> = Vec::new();
        let mut run_status = PathPointStatus::Ok;
        let flush = |run: &mut Vec<egui::Pos2>, status: PathPointStatus| {
            if run.len() >= 2 {
                painter.add(egui::Shape::line(std::mem::take(run), egui::Stroke::new(PATH_WIDTH_PX, status.color())));
            }
            run.clear();
        };
        let mut next_break = self.breaks.iter().peekable();
        for (i, (p, &s)) in self.points_m.iter().zip(&self.status).enumerate() {
            if next_break.peek().is_some_and(|b| **b == i) {
                next_break.next();
                flush(&mut run, run_status);
                last = None;
            }
            let Some(here) = camera::project_to_rect(view_proj, &Point3::new(p[0], p[1], p[2]), rect) else {
                flush(&mut run, run_status);
                last = None;
                continue;
            };
            match last {
                Some(prev) if prev.distance(here) < MIN_SEGMENT_PX => continue,
                Some(prev) => {
                    // a segment takes the status of the point it ends at
                    if run.is_empty() || s != run_status {
                        flush(&mut run, run_status);
                        run.push(prev);
                        run_status = s;
                    }
                    run.push(here);
                    drawn += 1;
                }
                None => {}
            }
            last = Some(here);
        }
        flush(&mut run, run_status);
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

    /// A 1 000-point path of two statuses in two strips is four line shapes, every segment drawn.
    #[test]
    fn a_long_path_is_a_few_line_shapes() {
        let mut o = PathOverlay::default();
        for k in 0..1000 {
            if k == 500 {
                o.break_strip();
            }
            let a = k as f32 * 0.006;
            let status = if k % 500 < 250 { PathPointStatus::Ok } else { PathPointStatus::Warning };
            o.push([0.4 * a.cos(), 0.4 * a.sin(), -0.5], status);
        }
        let view_proj = Matrix4::new_orthographic(-0.5, 0.5, -0.5, 0.5, -1.0, 1.0);
        let ctx = egui::Context::default();
        let mut drawn = 0;
        let mut out = ctx.run_pass(egui::RawInput::default(), |ctx| {
            let painter = ctx.layer_painter(egui::LayerId::background());
            drawn =
                o.paint(&painter, egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(800.0, 800.0)), &view_proj);
        });
        out.textures_delta.clear();
        let lines: Vec<usize> = out
            .shapes
            .iter()
            .filter_map(|c| match &c.shape {
                egui::Shape::Path(p) => Some(p.points.len()),
                _ => None,
            })
            .collect();
        assert_eq!(lines.len(), 4, "{lines:?}");
        // 998 segments (one lost at the strip break), one point more per line shape
        assert_eq!((drawn, lines.iter().sum::<usize>()), (998, 998 + 4));
    }
}
