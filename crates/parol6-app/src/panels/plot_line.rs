//! A plot line drawn as one mesh of plain quads, two triangles per segment, with no feathered
//! edges: [`ThinLine`], an [`egui_plot::PlotItem`].
//!
//! egui_plot's own `Line` goes through egui's path tessellator, which feathers every segment
//! (three vertices per point, four triangles per segment, all blended). On a software
//! rasterizer the plots of ten minutes of six joints (a few thousand segments per plot, mostly
//! steep min / max zig-zags from the decimation) then cost more than the rest of the window.
//! Here each segment is one opaque quad at least one pixel wide: half the triangles, a third of
//! the vertices, no tessellation work in egui, and the same look at one pixel width. Runs of
//! points within a quarter pixel of one segment are drawn as that segment ([`merge_collinear`]):
//! a smooth line of one point per pixel then takes a few dozen quads instead of hundreds, and
//! peaks, steps and min / max reversals are kept exactly.

use std::ops::RangeInclusive;

use eframe::egui;
use egui::epaint::{Mesh, Vertex, WHITE_UV};
use egui::{Color32, Pos2, Shape, Ui};
use egui_plot::{PlotBounds, PlotGeometry, PlotItem, PlotItemBase, PlotPoint, PlotTransform};

/// A polyline in plot coordinates drawn as unfeathered quads.
pub struct ThinLine {
    base: PlotItemBase,
    points: Vec<PlotPoint>,
    color: Color32,
    width_pt: f32,
}

impl ThinLine {
    /// A line named `name` (hover label) through `points` ([x, y] in plot units).
    pub fn new(name: impl Into<String>, points: &[[f64; 2]]) -> Self {
        Self {
            base: PlotItemBase::new(name.into()),
            points: points.iter().map(|p| PlotPoint::new(p[0], p[1])).collect(),
            color: Color32::WHITE,
            width_pt: 1.0,
        }
    }

    /// Line colour.
    pub fn color(mut self, color: Color32) -> Self {
        self.color = color;
        self
    }

    /// Line width, points (drawn at least one physical pixel wide).
    pub fn width(mut self, width_pt: f32) -> Self {
        self.width_pt = width_pt;
        self
    }
}

/// Appends the quads of the polyline `screen` (screen points) to `mesh`: `half_width` each side
/// of every segment, two triangles per segment, no feathering. Zero-length segments are skipped.
pub fn push_polyline_quads(mesh: &mut Mesh, screen: &[Pos2], half_width: f32, color: Color32) {
    mesh.reserve_vertices(4 * screen.len().saturating_sub(1));
    mesh.reserve_triangles(2 * screen.len().saturating_sub(1));
    for w in screen.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = b - a;
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            continue;
        }
        let n = egui::vec2(-d.y, d.x) * (half_width / len);
        // extend along the segment by the half width too, so joints between segments close
        let e = d * (half_width / len);
        let i = mesh.vertices.len() as u32;
        for p in [a - e + n, a - e - n, b + e + n, b + e - n] {
            mesh.vertices.push(Vertex { pos: p, uv: WHITE_UV, color });
        }
        mesh.add_triangle(i, i + 1, i + 2);
        mesh.add_triangle(i + 1, i + 2, i + 3);
    }
}

/// How far a point left out of a drawn line may lie from the line drawn instead, physical
/// pixels: well under the one-pixel line's half width, so nothing visible moves.
pub const MERGE_TOLERANCE_PX: f32 = 0.25;

/// Most points left out in a row (bounds the work per point of [`merge_collinear`]).
const MAX_MERGED_RUN: usize = 16;

/// The polyline `screen` with every point left out that lies within `tolerance` of the segment
/// drawn in its place (between the points kept before and after it). Straight and gently
/// curving stretches (most of a smooth signal, one point per pixel) become a few long
/// segments; a peak, a step or a reversal is kept exactly, since the points next to it do not
/// lie on a segment that cuts it off. First and last points are always kept.
pub fn merge_collinear(screen: &[Pos2], tolerance: f32) -> Vec<Pos2> {
    let n = screen.len();
    if n <= 2 {
        return screen.to_vec();
    }
    let mut out = Vec::with_capacity(n / 4 + 2);
    let mut anchor = 0;
    out.push(screen[0]);
    let mut end = 2;
    while end < n {
        let merged = end - anchor <= MAX_MERGED_RUN
            && screen[anchor + 1..end].iter().all(|&p| segment_distance(screen[anchor], screen[end], p) <= tolerance);
        if merged {
            end += 1;
        } else {
            anchor = end - 1;
            out.push(screen[anchor]);
            end = anchor + 2;
        }
    }
    out.push(screen[n - 1]);
    out
}

/// Distance from `p` to the segment `a`–`b` (NaN for non-finite points: never merged).
fn segment_distance(a: Pos2, b: Pos2, p: Pos2) -> f32 {
    let d = b - a;
    let len2 = d.length_sq();
    let t = if len2 > 0.0 { ((p - a).dot(d) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + d * t - p).length()
}

/// The mesh of the polyline `screen` (screen points) `width_pt` wide (at least one physical
/// pixel) at `ppp` pixels per point: its nearly collinear runs merged ([`merge_collinear`]; a
/// software rasterizer pays per triangle, and a smooth line of one point per pixel is mostly
/// such runs), then one quad per segment.
pub fn line_mesh(screen: &[Pos2], width_pt: f32, ppp: f32, color: Color32) -> Mesh {
    let merged = merge_collinear(screen, MERGE_TOLERANCE_PX / ppp);
    let mut mesh = Mesh::default();
    push_polyline_quads(&mut mesh, &merged, 0.5 * width_pt.max(1.0 / ppp), color);
    mesh
}

impl PlotItem for ThinLine {
    fn shapes(&self, ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let color = if self.highlighted() { self.color.gamma_multiply(1.3) } else { self.color };
        let screen: Vec<Pos2> = self.points.iter().map(|p| transform.position_from_point(p)).collect();
        let mesh = line_mesh(&screen, self.width_pt, ui.ctx().pixels_per_point(), color);
        if !mesh.is_empty() {
            shapes.push(Shape::mesh(mesh));
        }
    }

    fn initialize(&mut self, _x_range: RangeInclusive<f64>) {}

    fn color(&self) -> Color32 {
        self.color
    }

    fn geometry(&self) -> PlotGeometry<'_> {
        PlotGeometry::Points(&self.points)
    }

    fn bounds(&self) -> PlotBounds {
        let mut b = PlotBounds::NOTHING;
        for p in &self.points {
            b.extend_with(p);
        }
        b
    }

    fn base(&self) -> &PlotItemBase {
        &self.base
    }

    fn base_mut(&mut self) -> &mut PlotItemBase {
        &mut self.base
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_segment_is_one_quad_and_degenerate_ones_are_skipped() {
        let mut mesh = Mesh::default();
        let pts = [egui::pos2(0.0, 0.0), egui::pos2(10.0, 0.0), egui::pos2(10.0, 0.0), egui::pos2(10.0, 5.0)];
        push_polyline_quads(&mut mesh, &pts, 0.5, Color32::RED);
        assert_eq!(mesh.vertices.len(), 8, "two real segments, the zero-length one skipped");
        assert_eq!(mesh.indices.len(), 12);
        // the horizontal segment spans y = ±0.5 and x from −0.5 to 10.5
        let ys: Vec<f32> = mesh.vertices[..4].iter().map(|v| v.pos.y).collect();
        assert!(ys.iter().all(|y| (y.abs() - 0.5).abs() < 1e-6), "{ys:?}");
        let xs: Vec<f32> = mesh.vertices[..4].iter().map(|v| v.pos.x).collect();
        assert!(xs.contains(&-0.5) && xs.contains(&10.5), "{xs:?}");
        assert!(mesh.vertices.iter().all(|v| v.color == Color32::RED && v.uv == WHITE_UV));
    }

    /// Distance from `p` to the polyline `line`.
    fn distance_to(line: &[Pos2], p: Pos2) -> f32 {
        line.windows(2).map(|w| segment_distance(w[0], w[1], p)).fold(f32::INFINITY, f32::min)
    }

    #[test]
    fn a_smooth_line_is_drawn_with_few_quads_and_within_a_quarter_pixel_of_every_point() {
        // one point per pixel over 600 px: two periods of a 100 px sine
        let pts: Vec<Pos2> = (0..600)
            .map(|i| egui::pos2(i as f32, 200.0 + 100.0 * (i as f32 * std::f32::consts::TAU / 300.0).sin()))
            .collect();
        let mesh = line_mesh(&pts, 1.0, 1.0, Color32::RED);
        let quads = mesh.vertices.len() / 4;
        assert!(quads <= 120, "{quads} quads for 599 segments");
        let kept = merge_collinear(&pts, MERGE_TOLERANCE_PX);
        assert_eq!((kept[0], kept[kept.len() - 1]), (pts[0], pts[599]), "the ends are kept");
        for p in &pts {
            assert!(distance_to(&kept, *p) <= MERGE_TOLERANCE_PX + 1e-4, "{p:?} is {} px off", distance_to(&kept, *p));
        }
    }

    #[test]
    fn peaks_steps_and_min_max_reversals_are_kept_exactly() {
        // flat, a one-sample spike, flat, a step, then min / max pairs of a noisy stretch
        let mut pts: Vec<Pos2> = (0..100).map(|i| egui::pos2(i as f32, 50.0)).collect();
        pts[40].y = 10.0;
        for p in pts.iter_mut().skip(70) {
            p.y = 80.0;
        }
        pts.extend((100..140).map(|i| egui::pos2(i as f32, if i % 2 == 0 { 60.0 } else { 90.0 })));
        let kept = merge_collinear(&pts, MERGE_TOLERANCE_PX);
        for must in [pts[39], pts[40], pts[41], pts[69], pts[70]] {
            assert!(kept.contains(&must), "{must:?} dropped: {kept:?}");
        }
        assert!(pts[100..].iter().all(|p| kept.contains(p)), "every reversal is kept");
        assert!(kept.len() < 60, "the flat stretches merge: {} points", kept.len());
        for p in &pts {
            assert!(distance_to(&kept, *p) <= MERGE_TOLERANCE_PX + 1e-4);
        }
    }

    #[test]
    fn bounds_cover_the_points() {
        let line = ThinLine::new("J1", &[[0.0, -1.0], [2.0, 3.0]]);
        let b = line.bounds();
        assert_eq!((b.min(), b.max()), ([0.0, -1.0], [2.0, 3.0]));
    }
}
