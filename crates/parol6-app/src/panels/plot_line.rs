//! A plot line drawn as one mesh of plain quads, two triangles per segment, with no feathered
//! edges: [`ThinLine`], an [`egui_plot::PlotItem`].
//!
//! egui_plot's own `Line` goes through egui's path tessellator, which feathers every segment
//! (three vertices per point, four triangles per segment, all blended). On a software
//! rasterizer the plots of ten minutes of six joints (a few thousand segments per plot, mostly
//! steep min / max zig-zags from the decimation) then cost more than the rest of the window.
//! Here each segment is one opaque quad at least one pixel wide: half the triangles, a third of
//! the vertices, no tessellation work in egui, and the same look at one pixel width.

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

impl PlotItem for ThinLine {
    fn shapes(&self, ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let color = if self.highlighted() { self.color.gamma_multiply(1.3) } else { self.color };
        let screen: Vec<Pos2> = self.points.iter().map(|p| transform.position_from_point(p)).collect();
        let half_width = 0.5 * self.width_pt.max(1.0 / ui.ctx().pixels_per_point());
        let mut mesh = Mesh::default();
        push_polyline_quads(&mut mesh, &screen, half_width, color);
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

    #[test]
    fn bounds_cover_the_points() {
        let line = ThinLine::new("J1", &[[0.0, -1.0], [2.0, 3.0]]);
        let b = line.bounds();
        assert_eq!((b.min(), b.max()), ([0.0, -1.0], [2.0, 3.0]));
    }
}
