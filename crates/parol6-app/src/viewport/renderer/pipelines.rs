//! Render pipelines of the 3D view: one WGSL module (`viewport.wgsl`), one uniform bind group,
//! and a pipeline per kind of draw (opaque meshes, translucent overlays, axes on top, grid
//! lines, trail, background).

use eframe::wgpu;

use super::super::mesh::MeshVertex;
use super::buffers::{LineVertex, TRAIL_POINT_BYTES};
use super::frame_data::Instance;

/// The viewport's shader source.
const SHADER_WGSL: &str = include_str!("viewport.wgsl");

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

/// The pipelines and the uniform bind group of one scene.
pub(super) struct Pipelines {
    /// Draws the background itself (inside egui); `None` when the render pass clears to it.
    pub(super) background: Option<wgpu::RenderPipeline>,
    pub(super) mesh: wgpu::RenderPipeline,
    pub(super) overlay: wgpu::RenderPipeline,
    pub(super) axes: wgpu::RenderPipeline,
    pub(super) line: wgpu::RenderPipeline,
    pub(super) trail: wgpu::RenderPipeline,
    /// Binds the `globals` uniform buffer.
    pub(super) bind_group: wgpu::BindGroup,
}

impl Pipelines {
    /// Creates the pipelines for a `color_format` target with `sample_count` samples and an
    /// optional depth buffer, bound to the `globals` uniform buffer.
    pub(super) fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        sample_count: u32,
        depth_format: Option<wgpu::TextureFormat>,
        globals: &wgpu::Buffer,
        draw_background: bool,
    ) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("parol6 viewport shader"),
            source: wgpu::ShaderSource::Wgsl(SHADER_WGSL.into()),
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
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: globals.as_entire_binding() }],
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
        let trail_color_attrs = wgpu::vertex_attr_array![1 => Float32x3];
        let trail_buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: TRAIL_POINT_BYTES as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &trail_attrs,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: TRAIL_POINT_BYTES as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &trail_color_attrs,
            }),
        ];

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
                    depth_write: true,
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
        Self {
            background: background_pipeline,
            mesh: mesh_pipeline,
            overlay: overlay_pipeline,
            axes: axes_pipeline,
            line: line_pipeline,
            trail: trail_pipeline,
            bind_group,
        }
    }
}
