//! Where a new frame of the 3D view differs from the last one, for retained painting
//! ([`super::retained::CallbackDamage`]): while only the scene moves (same rectangle, camera
//! and options), the background and the grid are the same picture, and what changes lies inside
//! the screen boxes of what moved: each link's mesh (with its collision overlay, ghost and frame
//! axes when shown) at the last pose and at this one, the TCP axes, and the trail while it grows
//! (every new point moves the fading of all the others).

use eframe::egui;
use egui::Rect;
use parol6_core::na::{Isometry3, Matrix4, Point3};

use super::camera::project_to_rect;
use super::mesh::{MeshRange, ModelMeshes};
use super::renderer::{LINK_AXES_LENGTH_M, TCP_AXES_LENGTH_M};
use super::trail::Trail;
use super::{SceneFrame, ViewportOptions};

/// Added around every box on screen, points: lines drawn one pixel wide and the rasterizer's
/// rounding.
const MARGIN_PT: f32 = 3.0;

/// A box in a link frame, m: its two corners.
type LocalBox = [[f32; 3]; 2];

/// The link-frame boxes of a model's meshes, found once.
#[derive(Debug, Clone, Default)]
pub struct SceneBounds {
    visual: Vec<Option<LocalBox>>,
    collision: Vec<Option<LocalBox>>,
}

fn mesh_box(meshes: &ModelMeshes, r: &MeshRange) -> Option<LocalBox> {
    let indices = meshes.indices.get(r.first_index as usize..(r.first_index + r.index_count) as usize)?;
    let mut b: Option<LocalBox> = None;
    for &i in indices {
        let v = meshes.vertices.get(usize::try_from(r.base_vertex).ok()? + i as usize)?;
        let p = v.position_m;
        let [lo, hi] = b.get_or_insert([p, p]);
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    b
}

impl SceneBounds {
    /// The boxes of `meshes`' visual and collision meshes, per link.
    pub fn new(meshes: &ModelMeshes) -> Self {
        Self {
            visual: meshes.visual.iter().map(|r| mesh_box(meshes, r)).collect(),
            collision: meshes.collision.iter().map(|r| mesh_box(meshes, r)).collect(),
        }
    }

    /// The screen rectangle inside `rect` (the view, points) that `scene`'s moving parts cover
    /// as `options` show them through `view_proj`; the whole view when a box reaches behind
    /// the camera.
    pub fn scene_rect(
        &self,
        scene: &SceneFrame,
        options: &ViewportOptions,
        view_proj: &Matrix4<f32>,
        rect: Rect,
    ) -> Rect {
        let mut out = Rect::NOTHING;
        let mut add = |pose: &Isometry3<f64>, b: &LocalBox| match box_on_screen(pose, b, view_proj, rect) {
            Some(r) => out = out.union(r),
            None => out = rect,
        };
        let link_poses = scene.link_poses.iter();
        for (pose, b) in link_poses.clone().zip(&self.visual) {
            if let Some(b) = b {
                add(pose, b);
            }
        }
        if options.show_collision {
            for (pose, b) in link_poses.clone().zip(&self.collision) {
                if let Some(b) = b {
                    add(pose, b);
                }
            }
        }
        if options.show_ghost
            && let Some(ghost) = &scene.ghost_link_poses
        {
            for (pose, b) in ghost.iter().zip(&self.visual) {
                if let Some(b) = b {
                    add(pose, b);
                }
            }
        }
        let axes = |len: f32| [[-len; 3], [len; 3]];
        if options.show_link_frames {
            for pose in link_poses {
                add(pose, &axes(LINK_AXES_LENGTH_M));
            }
        }
        add(&scene.tcp, &axes(TCP_AXES_LENGTH_M));
        out.expand(MARGIN_PT).intersect(rect)
    }
}

/// The screen rectangle of box `b` placed at `pose`, or `None` when a corner does not project
/// (behind the camera).
fn box_on_screen(pose: &Isometry3<f64>, b: &LocalBox, view_proj: &Matrix4<f32>, rect: Rect) -> Option<Rect> {
    let pose = pose.cast::<f32>();
    let mut out = Rect::NOTHING;
    for corner in 0..8 {
        let pick = |axis: usize| b[(corner >> axis) & 1][axis];
        let p = pose * Point3::new(pick(0), pick(1), pick(2));
        out.extend_with(project_to_rect(view_proj, &p, rect)?);
    }
    Some(out)
}

/// The screen rectangle of the trail's points inside `rect`: nothing for an empty trail, the
/// whole view when a point does not project.
pub fn trail_rect(trail: &Trail, view_proj: &Matrix4<f32>, rect: Rect) -> Rect {
    let mut out = Rect::NOTHING;
    let slots = trail.slots();
    for range in trail.draw_ranges().into_iter().flatten() {
        // (the range may end at the bridge slot after the last, a copy of slot 0)
        let end = (range.end as usize).min(slots.len());
        for p in slots.get(range.start as usize..end).unwrap_or(&[]) {
            match project_to_rect(view_proj, &Point3::new(p[0], p[1], p[2]), rect) {
                Some(s) => out.extend_with(s),
                None => return rect,
            }
        }
    }
    if out == Rect::NOTHING { out } else { out.expand(MARGIN_PT).intersect(rect) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::viewport::OrbitCamera;
    use parol6_core::parol6;

    fn setup() -> (parol6_core::RobotModel, SceneBounds, Matrix4<f32>, Rect) {
        let model = parol6_core::RobotModel::parol6();
        let bounds = SceneBounds::new(&ModelMeshes::build(&model));
        let rect = Rect::from_min_size(egui::pos2(100.0, 50.0), egui::vec2(600.0, 400.0));
        (model, bounds, OrbitCamera::default().view_proj(1.5), rect)
    }

    #[test]
    fn the_arm_covers_part_of_the_view_and_every_link_vertex_lies_inside() {
        let (model, bounds, vp, rect) = setup();
        let q = parol6::standby_rad();
        let scene = SceneFrame::from_joints(&model, &q, None);
        let r = bounds.scene_rect(&scene, &ViewportOptions::default(), &vp, rect);
        assert!(r.is_positive() && r.area() < 0.6 * rect.area(), "{r:?} of {rect:?}");
        // every vertex of every link mesh, posed, projects inside
        let meshes = ModelMeshes::build(&model);
        for (range, pose) in meshes.visual.iter().zip(&scene.link_poses) {
            let base = range.base_vertex as usize;
            for &i in &meshes.indices[range.first_index as usize..(range.first_index + range.index_count) as usize] {
                let p = meshes.vertices[base + i as usize].position_m;
                let w = pose.cast::<f32>() * Point3::new(p[0], p[1], p[2]);
                let s = project_to_rect(&vp, &w, rect).expect("in front of the camera");
                assert!(r.contains(s), "{s:?} outside {r:?}");
            }
        }
    }

    #[test]
    fn a_box_behind_the_camera_makes_the_whole_view() {
        let (model, bounds, vp, rect) = setup();
        let mut scene = SceneFrame::from_joints(&model, &parol6::standby_rad(), None);
        let eye = OrbitCamera::default().eye_m();
        scene.tcp = Isometry3::translation(f64::from(eye.x), f64::from(eye.y), f64::from(eye.z));
        assert_eq!(bounds.scene_rect(&scene, &ViewportOptions::default(), &vp, rect), rect);
    }

    #[test]
    fn the_trail_rectangle_holds_its_points() {
        let (_, _, vp, rect) = setup();
        let mut trail = Trail::new(16);
        assert_eq!(trail_rect(&trail, &vp, rect), Rect::NOTHING);
        for i in 0..40 {
            let a = i as f32 * 0.2;
            trail.push([0.2 * a.cos(), 0.2 * a.sin(), 0.3], [1.0; 3]);
        }
        let r = trail_rect(&trail, &vp, rect);
        for p in trail.slots() {
            let s = project_to_rect(&vp, &Point3::new(p[0], p[1], p[2]), rect).expect("in view");
            assert!(r.contains(s));
        }
        assert!(r.area() < rect.area());
    }
}
