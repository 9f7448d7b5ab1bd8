//! The GPU side of retained painting: a window-sized colour target that keeps the last frame,
//! an egui renderer of our own that redraws only the changed rectangles into it (paint
//! callbacks such as the 3D view included), and a copy of the target into egui's render pass.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;
use egui::epaint::{ClippedPrimitive, Mesh, Primitive};
use egui::{Color32, Rect, TexturesDelta};

use super::RetainedStats;
use crate::viewport::DEPTH_FORMAT;

/// One frame handed from the UI pass to the painter.
pub(super) struct RetainedFrame {
    /// The rectangles to redraw, points.
    pub rects: Vec<Rect>,
    /// The frame's shapes that reach into them, tessellated.
    pub primitives: Vec<ClippedPrimitive>,
    /// The rectangles are the whole window.
    pub full: bool,
    /// Frames after this one that a spread change still needs (0–2, [`super::spread`]).
    pub frames_left: usize,
}

/// The paint callback that stands for the whole UI in egui's output.
pub(super) struct RetainedFrameCallback {
    pub frame: Mutex<Option<RetainedFrame>>,
}

/// State shared by the plugin and the painter.
pub(super) struct Shared {
    /// Texture changes not yet applied to the painter's renderer, oldest first.
    pub pending_textures: Mutex<Vec<TexturesDelta>>,
    /// Numbers of the last painted frame.
    pub stats: Mutex<RetainedStats>,
    /// The painter could not keep the last image (a new target): the next frame must be whole.
    pub need_full: AtomicBool,
    /// To ask for that frame.
    pub ctx: egui::Context,
}

struct Target {
    size_px: [u32; 2],
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    blit_bind_group: wgpu::BindGroup,
}

/// Kept in egui-wgpu's callback resources.
pub(super) struct RetainedPainter {
    renderer: egui_wgpu::Renderer,
    format: wgpu::TextureFormat,
    blit_layout: wgpu::BindGroupLayout,
    blit_sampler: wgpu::Sampler,
    blit_pipeline: wgpu::RenderPipeline,
    /// Fills a scissor rectangle with the background (cheaper than an egui mesh on a CPU).
    fill_pipeline: wgpu::RenderPipeline,
    target: Option<Target>,
    shared: Arc<Shared>,
}

impl RetainedPainter {
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        pass_depth: Option<wgpu::TextureFormat>,
        background: Color32,
        shared: Arc<Shared>,
    ) -> Self {
        let renderer = egui_wgpu::Renderer::new(
            device,
            format,
            egui_wgpu::RendererOptions {
                msaa_samples: 1,
                depth_stencil_format: Some(DEPTH_FORMAT),
                dithering: false,
                // filtering in egui's shader: on llvmpipe about half the cost of its sampler
                predictable_texture_filtering: true,
            },
        );
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("parol6 retained blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
        });
        let blit_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("parol6 retained blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        // nearest and 1:1: the copy changes no pixel
        let blit_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("parol6 retained blit"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("parol6 retained blit"),
            bind_group_layouts: &[Some(&blit_layout)],
            immediate_size: 0,
        });
        let [r, g, b, _] = background.to_normalized_gamma_f32();
        let fill_constants =
            [("background_r", f64::from(r)), ("background_g", f64::from(g)), ("background_b", f64::from(b))];
        let pipeline = |label,
                        layout: Option<&wgpu::PipelineLayout>,
                        (vs, fs),
                        depth: Option<wgpu::TextureFormat>,
                        constants: &[(&str, f64)]| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout,
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: depth.map(|format| wgpu::DepthStencilState {
                    format,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let blit_pipeline = pipeline("parol6 retained blit", Some(&layout), ("vs_copy", "fs_copy"), pass_depth, &[]);
        let empty_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("parol6 retained fill"),
            bind_group_layouts: &[],
            immediate_size: 0,
        });
        let fill_pipeline = pipeline(
            "parol6 retained fill",
            Some(&empty_layout),
            ("vs_full_screen", "fs_fill"),
            Some(DEPTH_FORMAT),
            &fill_constants,
        );
        Self { renderer, format, blit_layout, blit_sampler, blit_pipeline, fill_pipeline, target: None, shared }
    }

    fn make_target(&self, device: &wgpu::Device, size_px: [u32; 2]) -> Target {
        let size = wgpu::Extent3d { width: size_px[0], height: size_px[1], depth_or_array_layers: 1 };
        let tex = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = tex(
            "parol6 retained colour",
            self.format,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
        );
        let depth = tex("parol6 retained depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
        let blit_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("parol6 retained blit"),
            layout: &self.blit_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&color_view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.blit_sampler) },
            ],
        });
        Target {
            size_px,
            color,
            color_view,
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            blit_bind_group,
        }
    }

    /// Applies pending texture changes and redraws the frame's rectangles into the target.
    fn draw(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &egui_wgpu::ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        frame: RetainedFrame,
    ) -> Vec<wgpu::CommandBuffer> {
        let started = std::time::Instant::now();
        let deltas = self.shared.pending_textures.lock().map(|mut p| std::mem::take(&mut *p)).unwrap_or_default();
        for d in &deltas {
            for (id, deltas) in &d.set {
                for delta in deltas {
                    self.renderer.update_texture(device, queue, *id, delta);
                }
            }
        }
        let ppp = screen.pixels_per_point;
        if self.target.as_ref().map(|t| t.size_px) != Some(screen.size_in_pixels) {
            let new = self.make_target(device, screen.size_in_pixels);
            match self.target.take() {
                // a new size drawn over two or three frames: until then, the part not yet drawn
                // shows the last image (where it fits) instead of an empty one
                Some(old) if !frame.full => {
                    let [w, h] = [old.size_px[0].min(new.size_px[0]), old.size_px[1].min(new.size_px[1])];
                    encoder.copy_texture_to_texture(
                        old.color.as_image_copy(),
                        new.color.as_image_copy(),
                        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                    );
                }
                Some(_) => {}
                None if !frame.full => {
                    // a new, empty image and only part of the frame to draw into it
                    self.shared.need_full.store(true, Ordering::Relaxed);
                    self.shared.ctx.request_repaint();
                }
                None => {}
            }
            self.target = Some(new);
        }
        let [w, h] = screen.size_in_pixels;
        let (full, rects, frames_left) = (frame.full, frame.rects, frame.frames_left);
        let (jobs, fills) = self.jobs(&frame.primitives, &rects);
        let mut cmds = Vec::new();
        if let Some(target) = &self.target
            && !jobs.is_empty()
        {
            cmds = self.renderer.update_buffers(device, queue, encoder, &jobs, screen);
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("parol6 retained redraw"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
            pass.set_pipeline(&self.fill_pipeline);
            for r in &fills {
                let (x, y) = ((r.min.x * ppp).round() as u32, (r.min.y * ppp).round() as u32);
                let (rw, rh) = ((r.width() * ppp).round() as u32, (r.height() * ppp).round() as u32);
                if rw > 0 && rh > 0 && x + rw <= w && y + rh <= h {
                    pass.set_scissor_rect(x, y, rw, rh);
                    pass.draw(0..3, 0..1);
                }
            }
            self.renderer.render(&mut pass, &jobs, screen);
        }
        for d in deltas {
            for id in &d.free {
                self.renderer.free_texture(id);
            }
        }
        if let Ok(mut s) = self.shared.stats.lock() {
            let mut triangles = 0;
            for j in &jobs {
                if let Primitive::Mesh(m) = &j.primitive {
                    triangles += m.indices.len() / 3;
                }
            }
            *s = RetainedStats {
                frames: s.frames + 1,
                rects: rects.len(),
                redrawn_px: rects.iter().map(|r| f64::from(r.area() * ppp * ppp)).sum(),
                screen_px: f64::from(w) * f64::from(h),
                jobs: jobs.len(),
                triangles,
                full_redraw: full,
                frames_left,
                prepare_ms: started.elapsed().as_secs_f64() * 1e3,
            };
        }
        cmds
    }

    /// The draw list: for each rectangle the part of every primitive that reaches into it
    /// (meshes cut down to the triangles that touch it), clipped to it, in paint order; and the
    /// rectangles whose background must be filled first (those not wholly under an opaque
    /// paint callback, i.e. the 3D view, which paints its own).
    fn jobs(&self, primitives: &[ClippedPrimitive], rects: &[Rect]) -> (Vec<ClippedPrimitive>, Vec<Rect>) {
        let mut jobs = Vec::new();
        let mut fills = Vec::new();
        for &r in rects {
            let mut covered = false;
            for p in primitives {
                let clip = p.clip_rect.intersect(r);
                if !clip.is_positive() {
                    continue;
                }
                let primitive = match &p.primitive {
                    Primitive::Mesh(m) => match triangles_within(m, clip) {
                        Some(part) => Primitive::Mesh(part),
                        None => continue,
                    },
                    Primitive::Callback(c) => {
                        let shown = c.rect.intersect(p.clip_rect);
                        if !shown.intersects(r) {
                            continue;
                        }
                        covered |= shown.contains_rect(r);
                        Primitive::Callback(c.clone())
                    }
                };
                push_job(&mut jobs, ClippedPrimitive { clip_rect: clip, primitive }, p.clip_rect, r);
            }
            if !covered {
                fills.push(r);
            }
        }
        (jobs, fills)
    }
}

/// Adds `job` (clipped to its own `clip` and the redrawn rectangle `rect`) to `jobs`. A mesh
/// lying wholly inside its own clip is clipped by `rect` alone, and joins the mesh before it
/// when that one is clipped the same way and samples the same texture: one draw instead of
/// one per clip rectangle (a table's cells, each its own clip), which a software rasterizer
/// pays for in state changes. The pixels are the same: the scissor of a clip covers exactly
/// the pixels whose centres lie inside it, and no triangle of such a mesh reaches outside.
fn push_job(jobs: &mut Vec<ClippedPrimitive>, job: ClippedPrimitive, clip: Rect, rect: Rect) {
    if let Primitive::Mesh(m) = &job.primitive
        && clip.contains_rect(m.calc_bounds())
    {
        if let Some(ClippedPrimitive { clip_rect, primitive: Primitive::Mesh(last) }) = jobs.last_mut()
            && *clip_rect == rect
            && last.texture_id == m.texture_id
        {
            last.append_ref(m);
            return;
        }
        jobs.push(ClippedPrimitive { clip_rect: rect, primitive: job.primitive });
        return;
    }
    jobs.push(job);
}

/// The triangles of `mesh` whose bounding box meets `rect`, with only the vertices they use;
/// `None` when there are none. The scissor would discard the others, but a software
/// rasterizer still pays each triangle's set-up.
fn triangles_within(mesh: &Mesh, rect: Rect) -> Option<Mesh> {
    let mut part = Mesh::with_texture(mesh.texture_id);
    let mut remap = vec![u32::MAX; mesh.vertices.len()];
    for tri in mesh.indices.chunks_exact(3) {
        let (Some(a), Some(b), Some(c)) = (
            mesh.vertices.get(tri[0] as usize),
            mesh.vertices.get(tri[1] as usize),
            mesh.vertices.get(tri[2] as usize),
        ) else {
            continue;
        };
        if !Rect::from_points(&[a.pos, b.pos, c.pos]).intersects(rect) {
            continue;
        }
        for (&i, vertex) in tri.iter().zip([a, b, c]) {
            let slot = &mut remap[i as usize];
            if *slot == u32::MAX {
                *slot = part.vertices.len() as u32;
                part.vertices.push(*vertex);
            }
            part.indices.push(*slot);
        }
    }
    (!part.indices.is_empty()).then_some(part)
}

impl egui_wgpu::CallbackTrait for RetainedFrameCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &egui_wgpu::ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(frame) = self.frame.lock().ok().and_then(|mut f| f.take()) else { return Vec::new() };
        let Some(mut painter) = resources.remove::<RetainedPainter>() else { return Vec::new() };
        // the paint callbacks inside the UI (the 3D view) keep their GPU state in egui-wgpu's
        // resources: lend those to our renderer while it draws
        std::mem::swap(resources, &mut painter.renderer.callback_resources);
        let cmds = painter.draw(device, queue, screen, encoder, frame);
        std::mem::swap(resources, &mut painter.renderer.callback_resources);
        resources.insert(painter);
        cmds
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(p) = resources.get::<RetainedPainter>()
            && let Some(t) = &p.target
        {
            // the whole target, whatever rectangle egui gave the callback: a 1:1 copy
            let [w, h] = t.size_px;
            render_pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
            render_pass.set_pipeline(&p.blit_pipeline);
            render_pass.set_bind_group(0, &t.blit_bind_group, &[]);
            render_pass.draw(0..6, 0..1);
        }
    }
}
