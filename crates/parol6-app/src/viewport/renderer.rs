//! The wgpu side of the viewport: pipelines, static mesh buffers (uploaded once), per-frame
//! updates with `queue.write_buffer` into preallocated buffers, and the egui-wgpu paint
//! callback.
//!
//! Draw order in one render pass: opaque links (one draw per link, instance = its pose and
//! tint), translucent ghost and collision overlays, grid and trail lines (depth-tested, not
//! written), then the TCP and link-frame axes on top.

use std::ops::Range;
use std::sync::{Arc, Mutex};

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;
use eframe::wgpu::util::DeviceExt;
use parol6_core::LimitZone;
use parol6_core::na::{Isometry3, Matrix4, Vector3};

use super::camera::OrbitCamera;
use super::mesh::{MeshRange, MeshVertex, ModelMeshes, srgb_to_linear};
use super::trail::Trail;
use super::{SceneFrame, ViewportOptions};

/// Background of the 3D view (sRGB), as an egui colour.
pub const BACKGROUND_EGUI: egui::Color32 =
    egui::Color32::from_rgb(BACKGROUND_SRGB[0], BACKGROUND_SRGB[1], BACKGROUND_SRGB[2]);
/// Background of the 3D view, sRGB bytes.
pub const BACKGROUND_SRGB: [u8; 3] = [38, 42, 50];
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
/// How strongly a limit zone colours a link (0 = not at all, 1 = flat zone colour).
fn zone_tint_strength(zone: LimitZone) -> f32 {
    match zone {
        LimitZone::Safe => 0.35,
        LimitZone::Warning => 0.6,
        LimitZone::Critical => 0.75,
    }
}
/// Ghost colour (sRGB) and opacity.
const GHOST_SRGB: [f32; 3] = [0.45, 0.8, 1.0];
const GHOST_ALPHA: f32 = 0.33;
/// A ghost link closer than this to the real one is not drawn, m / rad.
const GHOST_MIN_OFFSET_M: f64 = 1e-4;
const GHOST_MIN_ANGLE_RAD: f64 = 1e-3;
/// Collision overlay colour (sRGB) and opacity.
const COLLISION_SRGB: [f32; 3] = [1.0, 0.55, 0.1];
const COLLISION_ALPHA: f32 = 0.4;
/// Trail colour (sRGB) and opacity of the newest point.
const TRAIL_SRGB: [f32; 3] = [1.0, 0.85, 0.2];
const TRAIL_ALPHA: f32 = 0.95;

const SHADER: &str = r#"
struct Globals {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_dir: vec4<f32>,
    // x: 1 = encode linear → sRGB here (non-sRGB target); y: grid fade radius, m
    params: vec4<f32>,
    // x: newest trail slot, y: trail points, z: trail capacity
    trail: vec4<u32>,
    trail_rgba: vec4<f32>,
    // The view's background, already in the target's encoding.
    background: vec4<f32>,
};
@group(0) @binding(0) var<uniform> g: Globals;

// Background: one triangle covering the viewport, a constant colour (cheap on software
// rasterizers, unlike a textured egui rectangle).
@vertex
fn vs_background(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(vi & 1u) * 4 - 1);
    let y = f32(i32(vi >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 1.0, 1.0);
}

@fragment
fn fs_background() -> @location(0) vec4<f32> {
    return g.background;
}

// Linear → sRGB with three square roots instead of pow (within ~0.5 % of the exact curve;
// pow is expensive on software rasterizers).
fn encode(c: vec3<f32>) -> vec3<f32> {
    if (g.params.x > 0.5) {
        let s1 = sqrt(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)));
        let s2 = sqrt(s1);
        let s3 = sqrt(s2);
        return clamp(0.585122381 * s1 + 0.783140355 * s2 - 0.368262736 * s3, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    return c;
}

struct MeshIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) m0: vec4<f32>,
    @location(4) m1: vec4<f32>,
    @location(5) m2: vec4<f32>,
    @location(6) m3: vec4<f32>,
    @location(7) tint: vec4<f32>,
    @location(8) style: vec4<f32>,
};
struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    let m = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let w = m * vec4<f32>(v.pos, 1.0);
    var o: MeshOut;
    o.clip = g.view_proj * w;
    o.world = w.xyz;
    o.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    o.color = vec4<f32>(mix(v.color.rgb, v.tint.rgb, v.tint.a), v.color.a * v.style.x);
    return o;
}

@fragment
fn fs_mesh(i: MeshOut) -> @location(0) vec4<f32> {
    var n = normalize(i.normal);
    let view = normalize(g.eye.xyz - i.world);
    // Two-sided lighting: mesh files do not always wind their triangles consistently.
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    let l = normalize(g.light_dir.xyz);
    let key = max(dot(n, l), 0.0);
    let rim = max(n.z, 0.0);
    let ambient = mix(0.16, 0.32, n.z * 0.5 + 0.5);
    let h = normalize(l + view);
    // Specular power 40 by squaring (x^32 · x^8).
    let x = max(dot(n, h), 0.0);
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let x32 = x8 * x8 * x8 * x8;
    let spec = x32 * x8 * 0.22;
    let c = i.color.rgb * (ambient + 0.75 * key + 0.12 * rim) + vec3<f32>(spec);
    return vec4<f32>(encode(c), i.color.a);
}

struct LineIn {
    @location(0) pos: vec3<f32>,
    @location(1) color: vec4<f32>,
};
struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    var o: LineOut;
    o.clip = g.view_proj * vec4<f32>(v.pos, 1.0);
    o.world = v.pos;
    o.color = v.color;
    return o;
}

@fragment
fn fs_line(i: LineOut) -> @location(0) vec4<f32> {
    let r = length(i.world.xy) / max(g.params.y, 1e-3);
    let fade = clamp(1.3 - r * 1.3, 0.0, 1.0);
    return vec4<f32>(encode(i.color.rgb), i.color.a * fade);
}

@vertex
fn vs_trail(@builtin(vertex_index) vi: u32, @location(0) pos: vec3<f32>) -> LineOut {
    let cap = max(g.trail.z, 1u);
    var slot = vi;
    if (slot >= cap) {
        slot = 0u;
    }
    let age = (g.trail.x + cap - slot) % cap;
    let t = 1.0 - f32(age) / f32(max(g.trail.y, 1u));
    var o: LineOut;
    o.clip = g.view_proj * vec4<f32>(pos, 1.0);
    o.world = pos;
    o.color = vec4<f32>(g.trail_rgba.rgb, g.trail_rgba.a * t * t);
    return o;
}

@fragment
fn fs_trail(i: LineOut) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(i.color.rgb), i.color.a);
}
"#;

/// Per-frame uniforms (128 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light_dir: [f32; 4],
    params: [f32; 4],
    trail: [u32; 4],
    trail_rgba: [f32; 4],
    background: [f32; 4],
}

/// Per-draw instance: model matrix (columns), tint (rgb linear, a = strength), style (x = alpha).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Instance {
    model: [[f32; 4]; 4],
    tint: [f32; 4],
    style: [f32; 4],
}

impl Instance {
    const HIDDEN: Instance = Instance { model: [[0.0; 4]; 4], tint: [0.0; 4], style: [0.0; 4] };

    fn new(pose: &Isometry3<f64>, scale: f32, tint: [f32; 4], alpha: f32) -> Self {
        let m: Matrix4<f32> = pose.to_homogeneous().cast::<f32>() * Matrix4::new_scaling(scale);
        Self { model: m.into(), tint, style: [alpha, 0.0, 0.0, 0.0] }
    }
}

/// One vertex of the grid lines.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LineVertex {
    position_m: [f32; 3],
    rgba: [f32; 4],
}

/// What to draw (decided each frame from the options and the scene).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DrawFlags {
    ghost: bool,
    collision: bool,
    link_frames: bool,
    grid: bool,
    trail: bool,
}

/// Everything that changes per frame, filled on the UI thread and uploaded in `prepare`.
/// Its vectors are allocated once; updating it allocates nothing.
#[derive(Debug)]
pub struct FrameData {
    globals: Globals,
    /// `[0, L)` links, `[L, 2L)` ghost, `[2L, 3L)` collision, `[3L, 4L)` link frames, `4L` TCP.
    instances: Vec<Instance>,
    link_count: usize,
    /// Per link: whether its ghost differs from the actual pose enough to be drawn.
    ghost_visible: Vec<bool>,
    draw: DrawFlags,
    /// TCP trail (ring buffer).
    pub trail: Trail,
    encode_srgb: bool,
}

/// Frame data shared between the [`super::Viewport`] and its paint callback.
pub type SharedFrame = Arc<Mutex<FrameData>>;

fn srgb3_to_linear(c: [f32; 3]) -> [f32; 3] {
    [srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2])]
}

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
                    let rgb = srgb3_to_linear([c[0] as f32 / 255.0, c[1] as f32 / 255.0, c[2] as f32 / 255.0]);
                    [rgb[0], rgb[1], rgb[2], zone_tint_strength(z)]
                }
                None => [0.0; 4],
            };
            self.instances[i] = Instance::new(pose, 1.0, tint, 1.0);
        }
        let ghost = match (&scene.ghost_link_poses, options.show_ghost) {
            (Some(g), true) if g.len() == l => {
                let c = srgb3_to_linear(GHOST_SRGB);
                let mut any = false;
                for (i, pose) in g.iter().enumerate() {
                    self.instances[l + i] = Instance::new(pose, 1.0, [c[0], c[1], c[2], 0.85], GHOST_ALPHA);
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
            let c = srgb3_to_linear(COLLISION_SRGB);
            for i in 0..l {
                let pose = scene.link_poses.get(i).unwrap_or(&identity);
                self.instances[2 * l + i] = Instance::new(pose, 1.0, [c[0], c[1], c[2], 1.0], COLLISION_ALPHA);
            }
        }
        if options.show_link_frames {
            for i in 0..l {
                let pose = scene.link_poses.get(i).unwrap_or(&identity);
                self.instances[3 * l + i] = Instance::new(pose, LINK_AXES_LENGTH_M, [0.0; 4], 1.0);
            }
        }
        self.instances[4 * l] = Instance::new(&scene.tcp, TCP_AXES_LENGTH_M, [0.0; 4], 1.0);

        let t = scene.tcp.translation.vector;
        self.trail.push([t.x as f32, t.y as f32, t.z as f32]);

        let eye = camera.eye_m();
        let to_eye = (eye - camera.target_m).try_normalize(1e-9).unwrap_or_else(Vector3::z);
        let right = to_eye.cross(&Vector3::z()).try_normalize(1e-6).unwrap_or_else(Vector3::x);
        let light = (to_eye * 0.8 + Vector3::z() * 0.6 + right * 0.35).normalize();
        let tr = c_trail();
        self.globals = Globals {
            view_proj: camera.view_proj(aspect).into(),
            eye: [eye.x, eye.y, eye.z, 1.0],
            light_dir: [light.x, light.y, light.z, 0.0],
            params: [if self.encode_srgb { 1.0 } else { 0.0 }, GRID_HALF_EXTENT_M, 0.0, 0.0],
            trail: [self.trail.newest_slot() as u32, self.trail.len() as u32, self.trail.capacity() as u32, 0],
            trail_rgba: [tr[0], tr[1], tr[2], TRAIL_ALPHA],
            background: {
                let c = BACKGROUND_SRGB.map(|v| v as f32 / 255.0);
                let c = if self.encode_srgb { c } else { srgb3_to_linear(c) };
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

fn c_trail() -> [f32; 3] {
    srgb3_to_linear(TRAIL_SRGB)
}

/// GPU resources of one viewport's scene. Created once; `prepare` only writes into its
/// buffers.
pub struct SceneGpu {
    /// Draws the background itself (inside egui); `None` when the render pass clears to it.
    background_pipeline: Option<wgpu::RenderPipeline>,
    mesh_pipeline: wgpu::RenderPipeline,
    overlay_pipeline: wgpu::RenderPipeline,
    axes_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    trail_pipeline: wgpu::RenderPipeline,
    globals_buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    vertex_buffer: wgpu::Buffer,
    index_buffer: wgpu::Buffer,
    instance_buffer: wgpu::Buffer,
    grid_buffer: wgpu::Buffer,
    grid_vertex_count: u32,
    trail_buffer: wgpu::Buffer,
    visual: Vec<MeshRange>,
    collision: Vec<MeshRange>,
    triad: MeshRange,
    draw: DrawFlags,
    ghost_visible: Vec<bool>,
    trail_ranges: [Option<Range<u32>>; 2],
}

fn grid_vertices() -> Vec<LineVertex> {
    let mut v = Vec::new();
    let minor = srgb3_to_linear([0.42, 0.45, 0.5]);
    let major = srgb3_to_linear([0.62, 0.65, 0.7]);
    let n = (GRID_HALF_EXTENT_M / GRID_MINOR_M).round() as i32;
    let per_major = (GRID_MAJOR_M / GRID_MINOR_M).round().max(1.0) as i32;
    let e = GRID_HALF_EXTENT_M;
    for i in -n..=n {
        let s = i as f32 * GRID_MINOR_M;
        let (c, a) = if i % per_major == 0 { (major, 0.75) } else { (minor, 0.45) };
        let rgba = [c[0], c[1], c[2], a];
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
    let red = srgb3_to_linear([0.95, 0.25, 0.2]);
    let green = srgb3_to_linear([0.3, 0.9, 0.3]);
    v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba: [red[0], red[1], red[2], 1.0] });
    v.push(LineVertex { position_m: [e, 0.0, 0.0], rgba: [red[0], red[1], red[2], 1.0] });
    v.push(LineVertex { position_m: [0.0, 0.0, 0.0], rgba: [green[0], green[1], green[2], 1.0] });
    v.push(LineVertex { position_m: [0.0, e, 0.0], rgba: [green[0], green[1], green[2], 1.0] });
    v
}

struct PipelineKind {
    label: &'static str,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    blend: Option<wgpu::BlendState>,
    cull: Option<wgpu::Face>,
}

const ALPHA_BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::SrcAlpha,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

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
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("parol6 viewport shader"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let globals_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 viewport globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("parol6 viewport globals layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("parol6 viewport globals"),
            layout: &bgl,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: globals_buffer.as_entire_binding() }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("parol6 viewport layout"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });

        let mesh_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let inst_attrs = wgpu::vertex_attr_array![3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4, 7 => Float32x4, 8 => Float32x4];
        let mesh_buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<MeshVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &mesh_attrs,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Instance>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &inst_attrs,
            }),
        ];
        let line_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4];
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &line_attrs,
        })];
        let trail_attrs = wgpu::vertex_attr_array![0 => Float32x3];
        let trail_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &trail_attrs,
        })];

        let make = |k: PipelineKind,
                    vs: &str,
                    fs: &str,
                    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                    topology: wgpu::PrimitiveTopology| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(k.label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState { topology, cull_mode: k.cull, ..Default::default() },
                depth_stencil: depth_format.map(|format| wgpu::DepthStencilState {
                    format,
                    depth_write_enabled: Some(k.depth_write),
                    depth_compare: Some(k.depth_compare),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState { count: sample_count, mask: !0, alpha_to_coverage_enabled: false },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: color_format,
                        blend: k.blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        use wgpu::CompareFunction as Cmp;
        use wgpu::PrimitiveTopology as Topo;
        let mesh_pipeline = make(
            PipelineKind { label: "parol6 mesh", depth_write: true, depth_compare: Cmp::Less, blend: None, cull: None },
            "vs_mesh",
            "fs_mesh",
            &mesh_buffers,
            Topo::TriangleList,
        );
        let overlay_pipeline = make(
            PipelineKind {
                label: "parol6 translucent mesh",
                depth_write: false,
                depth_compare: Cmp::LessEqual,
                blend: Some(ALPHA_BLEND),
                cull: Some(wgpu::Face::Back),
            },
            "vs_mesh",
            "fs_mesh",
            &mesh_buffers,
            Topo::TriangleList,
        );
        let axes_pipeline = make(
            PipelineKind {
                label: "parol6 axes",
                depth_write: false,
                depth_compare: Cmp::Always,
                blend: None,
                cull: Some(wgpu::Face::Back),
            },
            "vs_mesh",
            "fs_mesh",
            &mesh_buffers,
            Topo::TriangleList,
        );
        let line_pipeline = make(
            PipelineKind {
                label: "parol6 grid",
                depth_write: false,
                depth_compare: Cmp::LessEqual,
                blend: Some(ALPHA_BLEND),
                cull: None,
            },
            "vs_line",
            "fs_line",
            &line_buffers,
            Topo::LineList,
        );
        let trail_pipeline = make(
            PipelineKind {
                label: "parol6 trail",
                depth_write: false,
                depth_compare: Cmp::LessEqual,
                blend: Some(ALPHA_BLEND),
                cull: None,
            },
            "vs_trail",
            "fs_trail",
            &trail_buffers,
            Topo::LineStrip,
        );

        let background_pipeline = draw_background.then(|| {
            make(
                PipelineKind {
                    label: "parol6 background",
                    depth_write: false,
                    depth_compare: Cmp::Always,
                    blend: None,
                    cull: None,
                },
                "vs_background",
                "fs_background",
                &[],
                Topo::TriangleList,
            )
        });
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 mesh vertices"),
            contents: bytemuck::cast_slice(&meshes.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 mesh indices"),
            contents: bytemuck::cast_slice(&meshes.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let instance_count = 4 * meshes.visual.len() + 1;
        let instance_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 instances"),
            size: (instance_count * std::mem::size_of::<Instance>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let grid = grid_vertices();
        let grid_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("parol6 grid"),
            contents: bytemuck::cast_slice(&grid),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let trail_capacity = Trail::default().capacity();
        let trail_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 trail"),
            size: ((trail_capacity + 1) * 12) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            background_pipeline,
            mesh_pipeline,
            overlay_pipeline,
            axes_pipeline,
            line_pipeline,
            trail_pipeline,
            globals_buffer,
            bind_group,
            vertex_buffer,
            index_buffer,
            instance_buffer,
            grid_buffer,
            grid_vertex_count: grid.len() as u32,
            trail_buffer,
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
        queue.write_buffer(&self.globals_buffer, 0, bytemuck::bytes_of(&frame.globals));
        queue.write_buffer(&self.instance_buffer, 0, bytemuck::cast_slice(&frame.instances));
        let cap = frame.trail.capacity();
        for range in frame.trail.take_pending().into_iter().flatten() {
            let pts = &frame.trail.slots()[range.clone()];
            if range.end <= cap {
                queue.write_buffer(&self.trail_buffer, (range.start * 12) as u64, bytemuck::cast_slice(pts));
            }
            if range.start == 0 {
                // The bridge slot after the last one mirrors slot 0.
                queue.write_buffer(&self.trail_buffer, (cap * 12) as u64, bytemuck::cast_slice(&pts[..1]));
            }
        }
        self.trail_ranges = frame.trail.draw_ranges();
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
        pass.set_bind_group(0, &self.bind_group, &[]);
        if let Some(bg) = &self.background_pipeline {
            pass.set_pipeline(bg);
            pass.draw(0..3, 0..1);
        }
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_vertex_buffer(1, self.instance_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);

        pass.set_pipeline(&self.mesh_pipeline);
        for (i, r) in self.visual.iter().enumerate() {
            Self::draw_mesh(pass, r, i as u32);
        }

        if self.draw.grid {
            pass.set_pipeline(&self.line_pipeline);
            pass.set_vertex_buffer(0, self.grid_buffer.slice(..));
            pass.draw(0..self.grid_vertex_count, 0..1);
        }
        if self.draw.trail {
            pass.set_pipeline(&self.trail_pipeline);
            pass.set_vertex_buffer(0, self.trail_buffer.slice(..));
            for r in self.trail_ranges.iter().flatten() {
                if r.end > r.start + 1 {
                    pass.draw(r.clone(), 0..1);
                }
            }
        }

        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        if self.draw.ghost || self.draw.collision {
            pass.set_pipeline(&self.overlay_pipeline);
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

        pass.set_pipeline(&self.axes_pipeline);
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
