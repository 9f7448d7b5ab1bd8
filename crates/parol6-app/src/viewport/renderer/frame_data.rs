//! Frame upload: what changes every frame (uniforms, one instance per draw, the TCP trail),
//! filled on the UI thread into preallocated vectors ([`FrameData::update`]) and written into
//! the preallocated GPU buffers ([`FrameData::upload`]); nothing is allocated per frame.

use std::ops::Range;
use std::sync::{Arc, Mutex};

use eframe::wgpu;
use parol6_core::LimitZone;
use parol6_core::na::{Isometry3, Matrix4, Vector3};

use super::super::camera::OrbitCamera;
use super::super::mesh::ModelMeshes;
use super::super::trail::Trail;
use super::super::{SceneFrame, ViewportOptions};
use super::buffers::{SceneBuffers, TRAIL_POINT_BYTES};
use super::{GRID_HALF_EXTENT_M, LINK_AXES_LENGTH_M, TCP_AXES_LENGTH_M};
use crate::palette;

/// How strongly a limit zone colours a link (0 = not at all, 1 = flat zone colour).
fn zone_tint_strength(zone: LimitZone) -> f32 {
    match zone {
        LimitZone::Safe => 0.35,
        LimitZone::Warning => 0.6,
        LimitZone::Critical => 0.75,
    }
}
/// Instance tint that leaves the mesh colours as they are (strength 0).
const NO_TINT: [f32; 4] = [0.0; 4];
/// A ghost link closer than this to the real one is not drawn, m / rad.
const GHOST_MIN_OFFSET_M: f64 = 1e-4;
const GHOST_MIN_ANGLE_RAD: f64 = 1e-3;

/// Per-frame uniforms (128 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Globals {
    pub(super) view_proj: [[f32; 4]; 4],
    pub(super) eye: [f32; 4],
    pub(super) light_dir: [f32; 4],
    pub(super) params: [f32; 4],
    pub(super) trail: [u32; 4],
    pub(super) trail_rgba: [f32; 4],
    pub(super) background: [f32; 4],
}

/// Per-draw instance: model matrix (columns), tint (rgb linear, a = strength), style (x = alpha).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Instance {
    pub(super) model: [[f32; 4]; 4],
    pub(super) tint: [f32; 4],
    pub(super) style: [f32; 4],
}

impl Instance {
    pub(super) const HIDDEN: Instance = Instance { model: [[0.0; 4]; 4], tint: [0.0; 4], style: [0.0; 4] };

    pub(super) fn new(pose: &Isometry3<f64>, scale: f32, tint: [f32; 4], alpha: f32) -> Self {
        let m: Matrix4<f32> = pose.to_homogeneous().cast::<f32>() * Matrix4::new_scaling(scale);
        Self { model: m.into(), tint, style: [alpha, 0.0, 0.0, 0.0] }
    }
}

/// What to draw (decided each frame from the options and the scene).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DrawFlags {
    pub(super) ghost: bool,
    pub(super) collision: bool,
    pub(super) link_frames: bool,
    pub(super) grid: bool,
    pub(super) trail: bool,
}

/// Everything that changes per frame, filled on the UI thread and uploaded in `prepare`.
/// Its vectors are allocated once; updating it allocates nothing.
#[derive(Debug)]
pub struct FrameData {
    pub(super) globals: Globals,
    /// `[0, L)` links, `[L, 2L)` ghost, `[2L, 3L)` collision, `[3L, 4L)` link frames, `4L` TCP.
    pub(super) instances: Vec<Instance>,
    pub(super) link_count: usize,
    /// Per link: whether its ghost differs from the actual pose enough to be drawn.
    pub(super) ghost_visible: Vec<bool>,
    pub(super) draw: DrawFlags,
    /// TCP trail (ring buffer).
    pub trail: Trail,
    pub(super) encode_srgb: bool,
}

/// Frame data shared between the [`crate::viewport::Viewport`] and its paint callback.
pub type SharedFrame = Arc<Mutex<FrameData>>;

impl FrameData {
    /// Empty frame data sized for `meshes`.
    pub fn new(meshes: &ModelMeshes) -> Self {
        let l = meshes.visual.len();
        Self {
            globals: bytemuck::Zeroable::zeroed(),
            instances: vec![Instance::HIDDEN; 4 * l + 1],
            link_count: l,
            ghost_visible: vec![false; l],
            draw: DrawFlags::default(),
            trail: Trail::default(),
            encode_srgb: true,
        }
    }

    /// Whether the shader must encode linear → sRGB (true for non-sRGB targets).
    pub fn set_encode_srgb(&mut self, encode: bool) {
        self.encode_srgb = encode;
    }

    /// Fills the uniforms and instances for `scene` seen by `camera` in a view of `aspect`
    /// (width / height), and adds the TCP to the trail.
    pub fn update(&mut self, scene: &SceneFrame, options: &ViewportOptions, camera: &OrbitCamera, aspect: f32) {
        let l = self.link_count;
        let identity = Isometry3::identity();
        for i in 0..l {
            let pose = scene.link_poses.get(i).unwrap_or(&identity);
            let tint = match scene.link_zones.get(i).copied().flatten() {
                Some(z) => {
                    let c = z.rgba();
                    let rgb = palette::linear_rgb([c[0], c[1], c[2]]);
                    [rgb[0], rgb[1], rgb[2], zone_tint_strength(z)]
                }
                None => NO_TINT,
            };
            self.instances[i] = Instance::new(pose, 1.0, tint, 1.0);
        }
        let ghost = match (&scene.ghost_link_poses, options.show_ghost) {
            (Some(g), true) if g.len() == l => {
                let c = palette::linear_rgb(palette::VIEW_GHOST);
                let mut any = false;
                for (i, pose) in g.iter().enumerate() {
                    self.instances[l + i] = Instance::new(
                        pose,
                        1.0,
                        [c[0], c[1], c[2], palette::VIEW_GHOST_TINT_STRENGTH],
                        palette::VIEW_GHOST_OPACITY,
                    );
                    // A ghost link that sits on the real one (the base, a joint not moving)
                    // would only wash its colours out.
                    let actual = scene.link_poses.get(i).unwrap_or(&identity);
                    let moved = (pose.translation.vector - actual.translation.vector).norm() > GHOST_MIN_OFFSET_M
                        || pose.rotation.angle_to(&actual.rotation) > GHOST_MIN_ANGLE_RAD;
                    self.ghost_visible[i] = moved;
                    any |= moved;
                }
                any
            }
            _ => false,
        };
        if options.show_collision {
            let c = palette::linear_rgb(palette::VIEW_COLLISION);
            for i in 0..l {
                let pose = scene.link_poses.get(i).unwrap_or(&identity);
                self.instances[2 * l + i] =
                    Instance::new(pose, 1.0, [c[0], c[1], c[2], 1.0], palette::VIEW_COLLISION_OPACITY);
            }
        }
        if options.show_link_frames {
            for i in 0..l {
                let pose = scene.link_poses.get(i).unwrap_or(&identity);
                self.instances[3 * l + i] = Instance::new(pose, LINK_AXES_LENGTH_M, NO_TINT, 1.0);
            }
        }
        self.instances[4 * l] = Instance::new(&scene.tcp, TCP_AXES_LENGTH_M, NO_TINT, 1.0);

        let t = scene.tcp.translation.vector;
        let rgb = super::super::trail_color::trail_rgb(options.trail_coloring, scene.trail_sample);
        self.trail.push([t.x as f32, t.y as f32, t.z as f32], rgb);

        let eye = camera.eye_m();
        let to_eye = (eye - camera.target_m).try_normalize(1e-9).unwrap_or_else(Vector3::z);
        let right = to_eye.cross(&Vector3::z()).try_normalize(1e-6).unwrap_or_else(Vector3::x);
        let light = (to_eye * 0.8 + Vector3::z() * 0.6 + right * 0.35).normalize();
        let tr = palette::linear_rgb(palette::VIEW_TRAIL);
        self.globals = Globals {
            view_proj: camera.view_proj(aspect).into(),
            eye: [eye.x, eye.y, eye.z, 1.0],
            light_dir: [light.x, light.y, light.z, 0.0],
            params: [if self.encode_srgb { 1.0 } else { 0.0 }, GRID_HALF_EXTENT_M, 0.0, 0.0],
            trail: [self.trail.newest_slot() as u32, self.trail.len() as u32, self.trail.capacity() as u32, 0],
            trail_rgba: [tr[0], tr[1], tr[2], palette::VIEW_TRAIL_OPACITY],
            background: {
                let c = if self.encode_srgb {
                    palette::srgb_unit(palette::VIEW_BACKGROUND)
                } else {
                    palette::linear_rgb(palette::VIEW_BACKGROUND)
                };
                [c[0], c[1], c[2], 1.0]
            },
        };
        self.draw = DrawFlags {
            ghost,
            collision: options.show_collision,
            link_frames: options.show_link_frames,
            grid: options.show_grid,
            trail: options.show_trail,
        };
    }
}

impl FrameData {
    /// Writes this frame's uniforms, instances and new trail points into `buffers` (writes
    /// only, no allocation of GPU resources). Returns the trail ranges to draw.
    pub(super) fn upload(&mut self, queue: &wgpu::Queue, buffers: &SceneBuffers) -> [Option<Range<u32>>; 2] {
        queue.write_buffer(&buffers.globals, 0, bytemuck::bytes_of(&self.globals));
        queue.write_buffer(&buffers.instances, 0, bytemuck::cast_slice(&self.instances));
        let cap = self.trail.capacity();
        for range in self.trail.take_pending().into_iter().flatten() {
            for (buffer, slots) in [(&buffers.trail, self.trail.slots()), (&buffers.trail_color, self.trail.colors())] {
                let pts = &slots[range.clone()];
                if range.end <= cap {
                    queue.write_buffer(buffer, (range.start * TRAIL_POINT_BYTES) as u64, bytemuck::cast_slice(pts));
                }
                // The bridge slot after the last one mirrors slot 0.
                if range.start == 0
                    && let Some(first) = pts.first()
                {
                    queue.write_buffer(buffer, (cap * TRAIL_POINT_BYTES) as u64, bytemuck::cast_slice(&[*first]));
                }
            }
        }
        self.trail.draw_ranges()
    }
}
