//! GPU buffers of one scene: the static mesh vertices and indices and the grid (uploaded once),
//! and the per-frame uniform, instance and trail buffers (allocated once at their full size).

use eframe::wgpu;
use eframe::wgpu::util::DeviceExt;

use super::super::mesh::ModelMeshes;
use super::super::trail::Trail;
use super::frame_data::{Globals, Instance};
use super::{GRID_HALF_EXTENT_M, GRID_MAJOR_M, GRID_MINOR_M};
use crate::palette;

/// Bytes of one trail point (three `f32`).
pub(super) const TRAIL_POINT_BYTES: usize = 12;

/// One vertex of the grid lines.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct LineVertex {
    position_m: [f32; 3],
    rgba: [f32; 4],
}

/// The ground grid: thin and bold lines, and the +X / +Y axes in their own colours.
fn grid_vertices() -> Vec<LineVertex> {
    let mut v = Vec::new();
    let minor = palette::linear_rgba(palette::VIEW_GRID_MINOR);
    let major = palette::linear_rgba(palette::VIEW_GRID_MAJOR);
    let n = (GRID_HALF_EXTENT_M / GRID_MINOR_M).round() as i32;
    let per_major = (GRID_MAJOR_M / GRID_MINOR_M).round().max(1.0) as i32;
    let e = GRID_HALF_EXTENT_M;
    for i in -n..=n {
        let s = i as f32 * GRID_MINOR_M;
        let rgba = if i % per_major == 0 { major } else { minor };
        // Lines along x (at y = s) and along y (at x = s); the positive axes are drawn below.
        if i == 0 {
            v.push(LineVertex { position_m: [-e, 0.0, 0.0], rgba });
            v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba });
            v.push(LineVertex { position_m: [0.0, -e, 0.0], rgba });
            v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba });
            continue;
        }
        v.push(LineVertex { position_m: [-e, s, 0.0], rgba });
        v.push(LineVertex { position_m: [e, s, 0.0], rgba });
        v.push(LineVertex { position_m: [s, -e, 0.0], rgba });
        v.push(LineVertex { position_m: [s, e, 0.0], rgba });
    }
    let x_axis = palette::linear_rgba(palette::VIEW_GRID_AXIS_X);
    let y_axis = palette::linear_rgba(palette::VIEW_GRID_AXIS_Y);
    v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba: x_axis });
    v.push(LineVertex { position_m: [e, 0.0, 0.0], rgba: x_axis });
    v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba: y_axis });
    v.push(LineVertex { position_m: [0.0, e, 0.0], rgba: y_axis });
    v
}

/// The buffers of one scene.
pub(super) struct SceneBuffers {
    /// Per-frame uniforms ([`Globals`]).
    pub(super) globals: wgpu::Buffer,
    /// Mesh vertices of every link, collision shape and the axes triad.
    pub(super) vertices: wgpu::Buffer,
    /// Mesh indices.
    pub(super) indices: wgpu::Buffer,
    /// One [`Instance`] per draw, rewritten every frame.
    pub(super) instances: wgpu::Buffer,
    /// Grid line vertices.
    pub(super) grid: wgpu::Buffer,
    /// How many grid vertices.
    pub(super) grid_vertex_count: u32,
    /// Trail ring buffer plus one bridge slot (a copy of slot 0).
    pub(super) trail: wgpu::Buffer,
    /// Colours of the trail slots (same slots, linear RGB).
    pub(super) trail_color: wgpu::Buffer,
}

impl SceneBuffers {
    /// Uploads `meshes` and the grid, and allocates the per-frame buffers.
    pub(super) fn new(device: &wgpu::Device, meshes: &ModelMeshes) -> Self {
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 viewport globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 mesh vertices"),
            contents: bytemuck::cast_slice(&meshes.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 mesh indices"),
            contents: bytemuck::cast_slice(&meshes.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let instance_count = 4 * meshes.visual.len() + 1;
        let instances = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 instances"),
            size: (instance_count * std::mem::size_of::<Instance>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let grid_vertices = grid_vertices();
        let grid = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 grid"),
            contents: bytemuck::cast_slice(&grid_vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let trail_capacity = Trail::default().capacity();
        let trail = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 trail"),
            size: ((trail_capacity + 1) * TRAIL_POINT_BYTES) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let trail_color = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 trail colours"),
            size: ((trail_capacity + 1) * TRAIL_POINT_BYTES) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            globals,
            vertices,
            indices,
            instances,
            grid,
            grid_vertex_count: grid_vertices.len() as u32,
            trail,
            trail_color,
        }
    }
}
