//! The wgpu side of the viewport: a scene's GPU resources ([`SceneGpu`]) and the egui-wgpu
//! paint callback. Jobs: `pipelines` (shader and pipelines; the WGSL is in
//! `viewport.wgsl`), `buffers` (static mesh / grid buffers, preallocated per-frame buffers),
//! `frame_data` (per-frame uniforms, instances and trail, and their upload).
//!
//! Draw order in one render pass: opaque links (one draw per link, instance = its pose and
//! tint), translucent ghost and collision overlays, grid and trail lines (depth-tested, not
//! written), then the TCP and link-frame axes on top. Colours come from [`crate::palette`].

use std::ops::Range;

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;

use super::mesh::{MeshRange, ModelMeshes};

mod buffers;
mod frame_data;
mod pipelines;

use buffers::SceneBuffers;
pub use frame_data::{DrawFlags, FrameData, Globals, Instance, SharedFrame};
use pipelines::Pipelines;

/// Background of the 3D view, sRGB bytes (the palette's [`crate::palette::VIEW_BACKGROUND`]).
pub const BACKGROUND_SRGB: [u8; 3] = crate::palette::VIEW_BACKGROUND;
/// Background of the 3D view, as an egui colour.
pub const BACKGROUND_EGUI: egui::Color32 = crate::palette::rgb(BACKGROUND_SRGB);
/// Grid spacing of the thin lines, m.
pub const GRID_MINOR_M: f32 = 0.1;
/// Grid spacing of the bold lines, m.
pub const GRID_MAJOR_M: f32 = 0.5;
/// Half width of the grid, m.
pub const GRID_HALF_EXTENT_M: f32 = 1.5;
/// Length of the TCP axes, m.
pub const TCP_AXES_LENGTH_M: f32 = 0.06;
/// Length of the link-frame axes, m.
pub const LINK_AXES_LENGTH_M: f32 = 0.04;

/// GPU resources of one viewport's scene. Created once; `prepare` only writes into its
/// buffers.
pub struct SceneGpu {
    pipelines: Pipelines,
    buffers: SceneBuffers,
    visual: Vec<MeshRange>,
    collision: Vec<MeshRange>,
    triad: MeshRange,
    draw: DrawFlags,
    ghost_visible: Vec<bool>,
    trail_ranges: [Option<Range<u32>>; 2],
}

impl SceneGpu {
    /// Creates the pipelines for a `color_format` target with `sample_count` samples and an
    /// optional depth buffer, and uploads `meshes` once. With `draw_background` the scene
    /// paints its own background (inside egui); without, the caller clears to
    /// [`BACKGROUND_SRGB`].
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        sample_count: u32,
        depth_format: Option<wgpu::TextureFormat>,
        meshes: &ModelMeshes,
        draw_background: bool,
    ) -> Self {
        let buffers = SceneBuffers::new(device, meshes);
        let pipelines =
            Pipelines::new(device, color_format, sample_count, depth_format, &buffers.globals, draw_background);
        Self {
            pipelines,
            buffers,
            visual: meshes.visual.clone(),
            collision: meshes.collision.clone(),
            triad: meshes.triad,
            draw: DrawFlags::default(),
            ghost_visible: vec![false; meshes.visual.len()],
            trail_ranges: [None, None],
        }
    }

    /// Uploads this frame's uniforms, instances and new trail points (writes only, no
    /// allocation of GPU resources).
    pub fn prepare(&mut self, queue: &wgpu::Queue, frame: &mut FrameData) {
        self.trail_ranges = frame.upload(queue, &self.buffers);
        self.draw = frame.draw;
        if self.ghost_visible.len() == frame.ghost_visible.len() {
            self.ghost_visible.copy_from_slice(&frame.ghost_visible);
        }
    }

    fn draw_mesh(pass: &mut wgpu::RenderPass<'_>, r: &MeshRange, instance: u32) {
        if r.index_count > 0 {
            pass.draw_indexed(r.first_index..r.first_index + r.index_count, r.base_vertex, instance..instance + 1);
        }
    }

    /// Records the draws into `pass` (whose viewport and scissor the caller has set).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        let l = self.visual.len() as u32;
        pass.set_bind_group(0, &self.pipelines.bind_group, &[]);
        if let Some(bg) = &self.pipelines.background {
            pass.set_pipeline(bg);
            pass.draw(0..3, 0..1);
        }
        pass.set_vertex_buffer(0, self.buffers.vertices.slice(..));
        pass.set_vertex_buffer(1, self.buffers.instances.slice(..));
        pass.set_index_buffer(self.buffers.indices.slice(..), wgpu::IndexFormat::Uint32);

        pass.set_pipeline(&self.pipelines.mesh);
        for (i, r) in self.visual.iter().enumerate() {
            Self::draw_mesh(pass, r, i as u32);
        }

        if self.draw.grid {
            pass.set_pipeline(&self.pipelines.line);
            pass.set_vertex_buffer(0, self.buffers.grid.slice(..));
            pass.draw(0..self.buffers.grid_vertex_count, 0..1);
        }
        if self.draw.trail {
            pass.set_pipeline(&self.pipelines.trail);
            pass.set_vertex_buffer(0, self.buffers.trail.slice(..));
            pass.set_vertex_buffer(1, self.buffers.trail_color.slice(..));
            for r in self.trail_ranges.iter().flatten() {
                if r.end > r.start + 1 {
                    pass.draw(r.clone(), 0..1);
                }
            }
            // slot 1 held the trail colours: the instances again for the meshes below
            pass.set_vertex_buffer(1, self.buffers.instances.slice(..));
        }

        pass.set_vertex_buffer(0, self.buffers.vertices.slice(..));
        if self.draw.ghost || self.draw.collision {
            pass.set_pipeline(&self.pipelines.overlay);
            if self.draw.collision {
                for (i, r) in self.collision.iter().enumerate() {
                    Self::draw_mesh(pass, r, 2 * l + i as u32);
                }
            }
            if self.draw.ghost {
                for (i, (r, &visible)) in self.visual.iter().zip(&self.ghost_visible).enumerate() {
                    if visible {
                        Self::draw_mesh(pass, r, l + i as u32);
                    }
                }
            }
        }

        pass.set_pipeline(&self.pipelines.axes);
        let r = &self.triad;
        if self.draw.link_frames && l > 0 {
            pass.draw_indexed(r.first_index..r.first_index + r.index_count, r.base_vertex, 3 * l..4 * l);
        }
        Self::draw_mesh(pass, r, 4 * l);
    }
}

/// The scenes of all live viewports, kept in egui-wgpu's callback resources.
#[derive(Default)]
pub struct ViewportGpuResources {
    /// Scene per viewport id.
    pub scenes: std::collections::HashMap<u64, SceneGpu>,
}

/// The paint callback added to egui each frame.
pub struct ViewportCallback {
    /// Which scene in [`ViewportGpuResources`].
    pub id: u64,
    /// This frame's data.
    pub frame: SharedFrame,
}

impl egui_wgpu::CallbackTrait for ViewportCallback {
    fn prepare(
        &self,
        _device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen_descriptor: &egui_wgpu::ScreenDescriptor,
        _egui_encoder: &mut wgpu::CommandEncoder,
        callback_resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(res) = callback_resources.get_mut::<ViewportGpuResources>()
            && let Some(scene) = res.scenes.get_mut(&self.id)
            && let Ok(mut frame) = self.frame.lock()
        {
            scene.prepare(queue, &mut frame);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        callback_resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(res) = callback_resources.get::<ViewportGpuResources>()
            && let Some(scene) = res.scenes.get(&self.id)
        {
            scene.paint(render_pass);
        }
    }
}
