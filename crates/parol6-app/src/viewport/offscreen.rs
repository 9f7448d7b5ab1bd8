//! Headless rendering: its own wgpu instance, adapter, device and target textures; no window
//! and no display. Renders the 3D scene (or, through [`OffscreenRenderer::render_egui`], a
//! whole egui frame with the viewport's paint callback in it) and reads the pixels back as
//! RGBA8.

use std::path::Path;

use eframe::egui;
use eframe::egui_wgpu;
use eframe::wgpu;
use parol6_core::RobotModel;

use super::camera::OrbitCamera;
use super::mesh::ModelMeshes;
use super::renderer::{FrameData, SceneGpu};
use super::{DEPTH_FORMAT, SceneFrame, ViewportError, ViewportOptions};
use crate::palette;

/// Colour format of the offscreen target on `backend`: gamma-space bytes in the order a window
/// gets there, so that `bench render` draws what the window draws (egui takes the first
/// non-sRGB 8-bit format a surface offers: BGRA8 from Vulkan on X11, where llvmpipe copies a
/// BGRA8 image without shading it, RGBA8 from wgpu's GL). Images are read back as RGBA.
pub fn offscreen_format(backend: wgpu::Backend) -> wgpu::TextureFormat {
    match backend {
        wgpu::Backend::Gl | wgpu::Backend::BrowserWebGpu => wgpu::TextureFormat::Rgba8Unorm,
        _ => wgpu::TextureFormat::Bgra8Unorm,
    }
}

/// An RGBA8 image, rows top to bottom, no padding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl RgbaImage {
    /// The pixel at (`x`, `y`), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = ((y * self.width + x) * 4) as usize;
        self.pixels.get(i..i + 4).and_then(|p| p.try_into().ok())
    }
}

struct Targets {
    width: u32,
    height: u32,
    /// Multisampled colour (None when the sample count is 1).
    msaa_view: Option<wgpu::TextureView>,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row_bytes: u32,
    format: wgpu::TextureFormat,
}

impl Targets {
    fn new(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32, samples: u32) -> Self {
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let tex = |label, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let msaa_view = (samples > 1).then(|| {
            tex("parol6 offscreen msaa", format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT)
                .create_view(&Default::default())
        });
        let resolve = tex(
            "parol6 offscreen colour",
            format,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let resolve_view = resolve.create_view(&Default::default());
        let depth_view = tex("parol6 offscreen depth", DEPTH_FORMAT, samples, wgpu::TextureUsages::RENDER_ATTACHMENT)
            .create_view(&Default::default());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let padded_row_bytes = (width * 4).div_ceil(align) * align;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("parol6 offscreen readback"),
            size: padded_row_bytes as u64 * height as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Self { width, height, msaa_view, resolve, resolve_view, depth_view, readback, padded_row_bytes, format }
    }
}

/// Where the time of the last [`OffscreenRenderer::render_egui`] went, ms (wall clock).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EguiPassTiming {
    /// Texture and vertex / index / uniform uploads, including the 3D view's `prepare`.
    pub upload_ms: f64,
    /// The one render pass (clear, 3D view, every egui mesh) submitted and waited for.
    pub draw_ms: f64,
    /// Copy of the image into the read-back buffer, mapping it and copying the rows out.
    pub readback_ms: f64,
}

/// Headless renderer of the robot scene.
pub struct OffscreenRenderer {
    instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    samples: u32,
    scene: SceneGpu,
    frame: FrameData,
    targets: Targets,
    /// The camera used by [`Self::render`].
    pub camera: OrbitCamera,
    warnings: Vec<String>,
    last_egui_timing: EguiPassTiming,
    /// Whether [`Self::render_egui`]'s pass has a depth attachment (see
    /// [`Self::egui_render_state_with_depth`]).
    egui_pass_depth: bool,
}

impl OffscreenRenderer {
    /// Opens a headless device (any backend wgpu finds; `WGPU_BACKEND` and `WGPU_ADAPTER_NAME`
    /// narrow it), uploads the model's meshes and creates `width`×`height` targets with
    /// the adapter's sample count ([`super::msaa_for`]: `PAROL6_MSAA`, else [`super::MSAA_SAMPLES`] on
    /// a GPU and 1 on a software rasterizer).
    pub fn new(model: &RobotModel, width: u32, height: u32) -> Result<Self, ViewportError> {
        Self::with_sample_count(model, width, height, 0)
    }

    /// Like [`Self::new`] with `samples` MSAA samples (1, 2 or 4; falls back to 1 where the
    /// adapter cannot; 0 = the adapter's default). [`Self::sample_count`] tells what was used.
    pub fn with_sample_count(model: &RobotModel, width: u32, height: u32, samples: u32) -> Result<Self, ViewportError> {
        let (instance, adapter) = super::headless_adapter();
        let adapter = adapter.map_err(|e| ViewportError::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("parol6 offscreen"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| ViewportError::Device(e.to_string()))?;
        let max = device.limits().max_texture_dimension_2d;
        check_size(width, height, max)?;
        let format = offscreen_format(adapter.get_info().backend);
        let flags = adapter.get_texture_format_features(format).flags;
        let depth_flags = adapter.get_texture_format_features(DEPTH_FORMAT).flags;
        let samples = if samples == 0 { super::msaa_for(adapter.get_info().device_type) } else { samples };
        let supported = flags.sample_count_supported(samples) && depth_flags.sample_count_supported(samples);
        let samples = if samples > 1 && supported { samples } else { 1 };
        let meshes = ModelMeshes::build(model);
        let scene = SceneGpu::new(&device, format, samples, Some(DEPTH_FORMAT), &meshes, false);
        let mut frame = FrameData::new(&meshes);
        frame.set_encode_srgb(!format.is_srgb());
        let targets = Targets::new(&device, format, width, height, samples);
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            samples,
            scene,
            frame,
            targets,
            camera: OrbitCamera::default(),
            warnings: meshes.warnings,
            last_egui_timing: EguiPassTiming::default(),
            egui_pass_depth: true,
        })
    }

    /// Adapter name, backend and driver, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, …)".
    pub fn adapter_info(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?}, {} {})", i.name, i.backend, i.device_type, i.driver, i.driver_info)
    }

    /// Mesh problems found while loading (each replaced by a placeholder).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The wgpu device (for drawing egui on top, see [`Self::egui_render_state`]).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The wgpu queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// MSAA samples of the targets ([`super::MSAA_SAMPLES`], or 1 where the adapter cannot).
    pub fn sample_count(&self) -> u32 {
        self.samples
    }

    /// The kind of adapter (GPU or software rasterizer).
    pub fn device_type(&self) -> wgpu::DeviceType {
        self.adapter.get_info().device_type
    }

    /// Current image size, px.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }

    /// Recreates the targets for another image size (no-op when unchanged).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), ViewportError> {
        if (width, height) != self.size() {
            check_size(width, height, self.device.limits().max_texture_dimension_2d)?;
            self.targets = Targets::new(&self.device, self.targets.format, width, height, self.samples);
        }
        Ok(())
    }

    /// Phase timings of the last [`Self::render_egui`].
    pub fn last_egui_timing(&self) -> EguiPassTiming {
        self.last_egui_timing
    }

    /// Empties the TCP trail of [`Self::render`] (each render adds the TCP to it).
    pub fn clear_trail(&mut self) {
        self.frame.trail.clear();
    }

    /// Number of points in the trail.
    pub fn trail_len(&self) -> usize {
        self.frame.trail.len()
    }

    /// Renders the 3D scene alone and reads it back.
    pub fn render(&mut self, scene: &SceneFrame, options: &ViewportOptions) -> Result<RgbaImage, ViewportError> {
        let aspect = self.targets.width as f32 / self.targets.height as f32;
        self.frame.update(scene, options, &self.camera, aspect);
        self.scene.prepare(&self.queue, &mut self.frame);
        let bg = palette::srgb_unit(palette::VIEW_BACKGROUND).map(f64::from);
        let mut encoder =
            self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("parol6 offscreen") });
        {
            let mut pass = self.begin_pass(&mut encoder, wgpu::Color { r: bg[0], g: bg[1], b: bg[2], a: 1.0 }, true);
            self.scene.paint(&mut pass);
        }
        self.finish_and_read(encoder)
    }

    fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        clear: wgpu::Color,
        depth: bool,
    ) -> wgpu::RenderPass<'e> {
        let t = &self.targets;
        // With MSAA only the resolved image is needed: the samples are discarded.
        let (view, resolve_target, store) = match &t.msaa_view {
            Some(msaa) => (msaa, Some(&t.resolve_view), wgpu::StoreOp::Discard),
            None => (&t.resolve_view, None, wgpu::StoreOp::Store),
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("parol6 offscreen pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store },
            })],
            depth_stencil_attachment: depth.then_some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    fn finish_and_read(&self, mut encoder: wgpu::CommandEncoder) -> Result<RgbaImage, ViewportError> {
        let t = &self.targets;
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &t.resolve,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &t.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(t.padded_row_bytes),
                    rows_per_image: Some(t.height),
                },
            },
            wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
        );
        self.queue.submit([encoder.finish()]);
        let slice = t.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| ViewportError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| ViewportError::Readback(e.to_string()))?
            .map_err(|e| ViewportError::Readback(e.to_string()))?;
        let row = (t.width * 4) as usize;
        let mut pixels = Vec::with_capacity(row * t.height as usize);
        {
            let data = slice.get_mapped_range().map_err(|e| ViewportError::Readback(e.to_string()))?;
            for y in 0..t.height as usize {
                let start = y * t.padded_row_bytes as usize;
                pixels.extend_from_slice(&data[start..start + row]);
            }
        }
        if t.format == wgpu::TextureFormat::Bgra8Unorm {
            bgra_to_rgba(&mut pixels);
        }
        t.readback.unmap();
        Ok(RgbaImage { width: t.width, height: t.height, pixels })
    }

    /// An egui-wgpu render state on this device whose egui renderer matches the targets
    /// (format, samples, depth), for building a [`super::Viewport`] and drawing a whole egui
    /// frame with [`Self::render_egui`].
    pub fn egui_render_state(&mut self) -> egui_wgpu::RenderState {
        self.egui_render_state_with_depth(true)
    }

    /// Like [`Self::egui_render_state`]; without `depth` egui's pass in [`Self::render_egui`]
    /// has no depth attachment, as the window's has with retained painting (which draws the 3D
    /// view into its own target): a paint callback drawn straight into that pass must not use
    /// depth.
    pub fn egui_render_state_with_depth(&mut self, depth: bool) -> egui_wgpu::RenderState {
        self.egui_pass_depth = depth;
        let renderer = egui_wgpu::Renderer::new(
            &self.device,
            self.targets.format,
            egui_wgpu::RendererOptions {
                msaa_samples: self.samples,
                depth_stencil_format: depth.then_some(DEPTH_FORMAT),
                dithering: false,
                // Filtering in egui's shader: reproducible images, and on llvmpipe about half
                // the cost of its sRGB hardware sampling (measured on a full-window panel).
                predictable_texture_filtering: true,
            },
        );
        egui_wgpu::RenderState {
            adapter: self.adapter.clone(),
            available_adapters: vec![self.adapter.clone()],
            instance: self.instance.clone(),
            device: self.device.clone(),
            queue: self.queue.clone(),
            target_format: self.targets.format,
            renderer: std::sync::Arc::new(egui::mutex::RwLock::new(renderer)),
        }
    }

    /// Draws a tessellated egui frame (`primitives` from `ctx.tessellate`, with the frame's
    /// `textures_delta`) through `render_state`'s renderer — including the paint callbacks of
    /// any [`super::Viewport`] built on that render state — and reads it back. The image size
    /// is the renderer's current size; `pixels_per_point` must match the egui context.
    pub fn render_egui(
        &mut self,
        render_state: &egui_wgpu::RenderState,
        primitives: &[egui::ClippedPrimitive],
        textures_delta: &egui::TexturesDelta,
        pixels_per_point: f32,
        clear_srgb: [u8; 3],
    ) -> Result<RgbaImage, ViewportError> {
        let screen =
            egui_wgpu::ScreenDescriptor { size_in_pixels: [self.targets.width, self.targets.height], pixels_per_point };
        let t0 = std::time::Instant::now();
        let mut renderer = render_state.renderer.write();
        for (id, deltas) in &textures_delta.set {
            for delta in deltas {
                renderer.update_texture(&self.device, &self.queue, *id, delta);
            }
        }
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("parol6 offscreen egui") });
        let extra = renderer.update_buffers(&self.device, &self.queue, &mut encoder, primitives, &screen);
        let t1 = std::time::Instant::now();
        let bg = clear_srgb.map(|c| c as f64 / 255.0);
        {
            let clear = wgpu::Color { r: bg[0], g: bg[1], b: bg[2], a: 1.0 };
            let pass = self.begin_pass(&mut encoder, clear, self.egui_pass_depth);
            let mut pass = pass.forget_lifetime();
            renderer.render(&mut pass, primitives, &screen);
        }
        for id in &textures_delta.free {
            renderer.free_texture(id);
        }
        drop(renderer);
        // The draw is submitted and waited for on its own, so that the read-back is timed apart.
        self.queue.submit(extra.into_iter().chain([encoder.finish()]));
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| ViewportError::Readback(e.to_string()))?;
        let t2 = std::time::Instant::now();
        let copy = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("parol6 offscreen read-back") });
        let img = self.finish_and_read(copy)?;
        let ms = |a: std::time::Instant, b: std::time::Instant| (b - a).as_secs_f64() * 1e3;
        self.last_egui_timing = EguiPassTiming {
            upload_ms: ms(t0, t1),
            draw_ms: ms(t1, t2),
            readback_ms: ms(t2, std::time::Instant::now()),
        };
        Ok(img)
    }
}

/// Swaps the blue and red bytes of every pixel, in place: as whole words where the buffer is
/// aligned for them (a loop the compiler turns into byte shuffles, ~0.1 ms at 1280×800 instead
/// of ~1 ms byte by byte), else byte by byte.
fn bgra_to_rgba(pixels: &mut [u8]) {
    match bytemuck::try_cast_slice_mut::<u8, u32>(pixels) {
        Ok(words) => {
            for w in words {
                let v = u32::from_le(*w);
                *w = u32::to_le((v & 0xff00_ff00) | ((v >> 16) & 0xff) | ((v & 0xff) << 16));
            }
        }
        Err(_) => {
            for p in pixels.chunks_exact_mut(4) {
                p.swap(0, 2);
            }
        }
    }
}

fn check_size(width: u32, height: u32, max: u32) -> Result<(), ViewportError> {
    if width == 0 || height == 0 || width > max || height > max {
        return Err(ViewportError::InvalidSize { width_px: width, height_px: height, max_px: max });
    }
    Ok(())
}

/// Writes `img` as an 8-bit RGBA PNG.
pub fn write_png(path: &Path, img: &RgbaImage) -> Result<(), ViewportError> {
    let err = |m: String| ViewportError::Png { path: path.display().to_string(), message: m };
    if img.pixels.len() != img.width as usize * img.height as usize * 4 {
        return Err(err(format!("{} bytes do not make a {}x{} RGBA image", img.pixels.len(), img.width, img.height)));
    }
    parol6_core::fsio::write_atomic(path, |out| {
        let mut enc = png::Encoder::new(out, img.width, img.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        let mut writer = enc.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&img.pixels).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
    .map_err(|e| err(e.to_string()))
}

/// Reads an 8-bit RGB or RGBA PNG.
pub fn read_png(path: &Path) -> Result<RgbaImage, ViewportError> {
    let err = |m: String| ViewportError::Png { path: path.display().to_string(), message: m };
    let file = parol6_core::fsio::open_regular(path).map_err(|e| err(e.to_string()))?;
    let dec = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = dec.read_info().map_err(|e| err(e.to_string()))?;
    let size = reader.output_buffer_size().ok_or_else(|| err("image too large".into()))?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(|e| err(e.to_string()))?;
    if info.bit_depth != png::BitDepth::Eight {
        return Err(err(format!("unsupported bit depth {:?}", info.bit_depth)));
    }
    let data = &buf[..info.buffer_size()];
    let pixels = match info.color_type {
        png::ColorType::Rgba => data.to_vec(),
        png::ColorType::Rgb => data.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        other => return Err(err(format!("unsupported colour type {other:?}"))),
    };
    Ok(RgbaImage { width: info.width, height: info.height, pixels })
}

#[cfg(test)]
mod tests {
    use super::bgra_to_rgba;

    #[test]
    fn bgra_pixels_come_back_as_rgba() {
        let mut px = vec![1, 2, 3, 4, 10, 20, 30, 40];
        bgra_to_rgba(&mut px);
        assert_eq!(px, [3, 2, 1, 4, 30, 20, 10, 40]);
        // one byte in: not aligned for words, swapped byte by byte
        let mut shifted = vec![0, 1, 2, 3, 4, 10, 20, 30, 40];
        bgra_to_rgba(&mut shifted[1..]);
        assert_eq!(shifted, [0, 3, 2, 1, 4, 30, 20, 10, 40]);
    }
}
