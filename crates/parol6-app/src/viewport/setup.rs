//! Which adapter, sample count, depth buffer and painting the window and the offscreen
//! renderer use: decided once, before the window exists, from the adapter wgpu would give it.

use eframe::egui;
use eframe::egui_wgpu;

use super::retained;

/// MSAA sample count of the 3D view on a GPU. The egui window must use the same
/// (`NativeOptions::multisampling`), because the view draws into egui's render pass.
pub const MSAA_SAMPLES: u32 = 4;

/// MSAA sample count on a software rasterizer (lavapipe, llvmpipe). There 4× MSAA costs about
/// 14 ms per 1280×800 frame for the clear and resolve alone, more than a third of the frame
/// budget, so CPU adapters render without it unless `PAROL6_MSAA` asks for it.
pub const MSAA_SAMPLES_CPU_ADAPTER: u32 = 1;

/// The sample count for an adapter of `device_type`: `PAROL6_MSAA` when set, else
/// [`MSAA_SAMPLES`] on GPUs and [`MSAA_SAMPLES_CPU_ADAPTER`] on software rasterizers.
pub fn msaa_for(device_type: eframe::wgpu::DeviceType) -> u32 {
    msaa_from_env().unwrap_or(if device_type == eframe::wgpu::DeviceType::Cpu {
        MSAA_SAMPLES_CPU_ADAPTER
    } else {
        MSAA_SAMPLES
    })
}

/// A wgpu instance and adapter without a window (Vulkan, Metal or DX12 when one has an
/// adapter, else GL; `WGPU_BACKEND`, `WGPU_ADAPTER_NAME` and `WGPU_POWER_PREF` narrow it).
pub fn headless_adapter() -> (eframe::wgpu::Instance, Result<eframe::wgpu::Adapter, eframe::wgpu::RequestAdapterError>)
{
    use eframe::wgpu;
    let open = |backends: Option<wgpu::Backends>| {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if let Some(b) = backends {
            descriptor.backends = b;
        }
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance),
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }));
        (instance, adapter)
    };
    if wgpu::Backends::from_env().is_some() {
        return open(None);
    }
    // Vulkan / Metal / DX12 first, GL only where none of them has an adapter: asking every
    // backend at once loads the GL driver as well (~6 MB resident on Mesa) for nothing.
    match open(Some(wgpu::Backends::PRIMARY)) {
        (instance, Ok(adapter)) => (instance, Ok(adapter)),
        (_, Err(_)) => open(None),
    }
}

/// How the window draws, fixed before it exists ([`configure_native_options`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindowSetup {
    /// MSAA samples of egui's pass and the 3D view.
    pub samples: u32,
    /// Retained painting ([`retained::retained_for`]): egui's pass then has no depth buffer
    /// and the 3D view draws into the retained image.
    pub retained: bool,
    /// The adapter is Vulkan, Metal or DX12: the window's instance then leaves GL out
    /// ([`configure_native_options`]).
    pub primary_backend: bool,
}

/// Asks wgpu which adapter a window would get (same environment rules) and decides its sample
/// count ([`msaa_for`]) and retained painting ([`retained::retained_for`]).
pub fn probe_window() -> WindowSetup {
    match headless_adapter().1 {
        Ok(a) => {
            let info = a.get_info();
            let samples = msaa_for(info.device_type);
            let retained = retained::retained_for(info.device_type, samples);
            let primary_backend = eframe::wgpu::Backends::PRIMARY.contains(info.backend.into());
            WindowSetup { samples, retained, primary_backend }
        }
        Err(_) => {
            WindowSetup { samples: msaa_from_env().unwrap_or(MSAA_SAMPLES), retained: false, primary_backend: false }
        }
    }
}

/// Depth buffer bits the egui window must request (`NativeOptions::depth_buffer`); egui-wgpu
/// turns 32 into [`DEPTH_FORMAT`].
pub const DEPTH_BUFFER_BITS: u8 = 32;

/// Depth format of the 3D pass (egui-wgpu's format for `depth_buffer: 32`).
pub const DEPTH_FORMAT: eframe::wgpu::TextureFormat = eframe::wgpu::TextureFormat::Depth32Float;

/// Whether egui feathers (anti-aliases) its shapes on an adapter of `device_type`:
/// `PAROL6_FEATHERING=0|1` when set, else on GPUs only. Feathering gives every filled shape a
/// blended rim and every line three vertices per point: on a software rasterizer the UI's
/// triangles roughly double and its render pass costs several milliseconds more at
/// 1280×800, for edges that are one pixel softer.
pub fn feathering_for(device_type: eframe::wgpu::DeviceType) -> bool {
    match std::env::var("PAROL6_FEATHERING").ok().as_deref().map(str::trim) {
        Some("0") => false,
        Some("1") => true,
        _ => device_type != eframe::wgpu::DeviceType::Cpu,
    }
}

/// Sets egui's feathering on `ctx` for the adapter of `render_state` ([`feathering_for`]).
pub fn configure_tessellation(ctx: &egui::Context, render_state: &egui_wgpu::RenderState) {
    let on = feathering_for(render_state.adapter.get_info().device_type);
    ctx.tessellation_options_mut(|o| o.feathering = on);
}

/// `PAROL6_MSAA=1|2|4` overrides [`MSAA_SAMPLES`] (1 is much cheaper on software
/// rasterizers). [`super::OffscreenRenderer::new`] honours it; a window must use the same value.
pub fn msaa_from_env() -> Option<u32> {
    std::env::var("PAROL6_MSAA").ok().and_then(|v| v.trim().parse::<u32>().ok()).filter(|m| matches!(m, 1 | 2 | 4))
}

/// Sets the window options the viewport needs ([`probe_window`]): the sample count, and a
/// [`DEPTH_BUFFER_BITS`] depth buffer unless retained painting is used. Call it on the
/// `NativeOptions` before `eframe::run_native`; the [`super::Viewport`] must be built with the
/// returned sample count, and retained painting installed ([`retained::install`], without a
/// pass depth) when it says so.
pub fn configure_native_options(options: &mut eframe::NativeOptions) -> WindowSetup {
    let setup = probe_window();
    options.multisampling = setup.samples as u16;
    options.depth_buffer = if setup.retained { 0 } else { DEPTH_BUFFER_BITS };
    // Dithering costs per-pixel noise math in egui's shader for a barely visible gain; on
    // software rasterizers it is a measurable part of the frame.
    options.dithering = false;
    // eframe asks Vulkan / Metal / DX12 and GL at once, which loads the GL driver too (~6.5 MB
    // resident with Mesa's llvmpipe) that a window on a Vulkan adapter never uses
    if setup.primary_backend
        && eframe::wgpu::Backends::from_env().is_none()
        && let egui_wgpu::WgpuSetup::CreateNew(create) = &mut options.wgpu_options.wgpu_setup
    {
        create.instance_descriptor.backends = eframe::wgpu::Backends::PRIMARY;
    }
    setup
}
