//! The 3D viewport: our own wgpu pipeline drawn inside egui through a paint callback, and the
//! same scene rendered headless ([`OffscreenRenderer`]) for `parol6 screenshot` and image tests.
//!
//! * [`mesh`]: primitive tessellation and STL / OBJ / DAE loading (mesh-loader) into one static
//!   vertex/index buffer per model.
//! * [`renderer`]: the wgpu pipelines, per-frame buffer updates (`queue.write_buffer` into
//!   preallocated buffers only) and the egui-wgpu [`CallbackTrait`](eframe::egui_wgpu::CallbackTrait).
//! * [`camera`]: the Z-up orbit camera.
//! * [`trail`]: the TCP trail ring buffer.
//! * [`offscreen`]: the headless renderer.
//! * [`setup`]: which adapter, sample count, depth buffer and painting the window and the
//!   offscreen renderer use.
//!
//! The egui path draws into egui's own render pass, so the app must create its window with
//! [`MSAA_SAMPLES`] and [`DEPTH_BUFFER_BITS`] (see [`configure_native_options`]).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use eframe::egui;
use eframe::egui_wgpu;
use parol6_core::na::{Isometry3, Point3};
use parol6_core::{LimitZone, RobotModel, ZoneThresholds};
use serde::{Deserialize, Serialize};

use crate::palette;

pub mod camera;
pub mod mesh;
pub mod offscreen;
pub mod path_overlay;
pub mod renderer;
pub mod retained;
pub mod setup;
pub mod trail;
pub mod trail_color;
pub mod view_damage;

pub use camera::OrbitCamera;
pub use offscreen::{OffscreenRenderer, RgbaImage, write_png};
pub use path_overlay::{PathOverlay, PathPointStatus};
pub use setup::{
    DEPTH_BUFFER_BITS, DEPTH_FORMAT, MSAA_SAMPLES, MSAA_SAMPLES_CPU_ADAPTER, WindowSetup, configure_native_options,
    configure_tessellation, feathering_for, headless_adapter, msaa_for, msaa_from_env, probe_window,
};
pub use trail::DEFAULT_TRAIL_CAPACITY;

use renderer::{FrameData, SceneGpu, SharedFrame, ViewportCallback, ViewportGpuResources};

/// Errors of the viewport and the offscreen renderer.
#[derive(Debug, thiserror::Error)]
pub enum ViewportError {
    /// No GPU or software adapter could be opened.
    #[error("no graphics adapter found ({0}); install a Vulkan or GL driver (e.g. mesa-vulkan-drivers for lavapipe)")]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("could not create a graphics device: {0}")]
    Device(String),
    /// An image size that cannot be rendered.
    #[error("invalid image size {width_px}x{height_px} (each side must be 1…{max_px})")]
    InvalidSize {
        /// Requested width.
        width_px: u32,
        /// Requested height.
        height_px: u32,
        /// Largest side the device supports.
        max_px: u32,
    },
    /// Reading the rendered image back from the GPU failed.
    #[error("reading the rendered image back failed: {0}")]
    Readback(String),
    /// Writing a PNG file failed.
    #[error("writing {path}: {message}")]
    Png {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// What to draw this frame; built by the app from the simulation snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFrame {
    /// World pose of every link, same order as [`RobotModel::links`].
    pub link_poses: Vec<Isometry3<f64>>,
    /// Tint of every link (`None` = no tint); the colours come from [`LimitZone::rgba`].
    pub link_zones: Vec<Option<LimitZone>>,
    /// World pose of the TCP (axes are drawn there; the trail follows its origin).
    pub tcp: Isometry3<f64>,
    /// Link poses of the target pose, drawn as a translucent ghost.
    pub ghost_link_poses: Option<Vec<Isometry3<f64>>>,
    /// TCP speed and tracking error now, for a trail coloured by them.
    pub trail_sample: trail_color::TrailSample,
    /// The planned TCP path of the loaded program, coloured by its pre-flight.
    pub planned_path: Option<Arc<PathOverlay>>,
}

impl SceneFrame {
    /// The scene for joint values `q_rad`: link poses by forward kinematics, each link tinted by
    /// the position zone of the joint that moves it (links that no joint moves, and joints in
    /// the safe zone, get no tint), and an optional ghost at `ghost_q_rad`.
    pub fn from_joints(model: &RobotModel, q_rad: &[f64], ghost_q_rad: Option<&[f64]>) -> Self {
        let zones = model.limits.zones(q_rad, &ZoneThresholds::default());
        Self::with_zones(model, q_rad, &zones, ghost_q_rad)
    }

    /// Like [`Self::from_joints`] with zones already computed (one per joint, e.g. the
    /// predictive zones of the simulation).
    pub fn with_zones(
        model: &RobotModel,
        q_rad: &[f64],
        joint_zones: &[LimitZone],
        ghost_q_rad: Option<&[f64]>,
    ) -> Self {
        let link_zones = model
            .links
            .iter()
            .map(|l| {
                if l.frame == 0 {
                    return None;
                }
                match joint_zones.get(l.frame - 1) {
                    Some(LimitZone::Safe) | None => None,
                    Some(z) => Some(*z),
                }
            })
            .collect();
        Self {
            link_poses: model.link_poses(q_rad),
            link_zones,
            tcp: model.tcp_isometry(q_rad),
            ghost_link_poses: ghost_q_rad.map(|g| model.link_poses(g)),
            planned_path: None,
            trail_sample: trail_color::TrailSample::default(),
        }
    }
}

/// Display toggles of the viewport (persisted with the app settings).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct ViewportOptions {
    /// Draw small axes at every link frame.
    pub show_link_frames: bool,
    /// Write the link names next to their frames.
    pub show_link_names: bool,
    /// Draw the collision geometry as translucent overlay.
    pub show_collision: bool,
    /// Draw the TCP trail.
    pub show_trail: bool,
    /// Draw the translucent target pose.
    pub show_ghost: bool,
    /// Draw the ground grid.
    pub show_grid: bool,
    /// What colours the TCP trail.
    pub trail_coloring: trail_color::TrailColoring,
}

impl Default for ViewportOptions {
    fn default() -> Self {
        Self {
            show_link_frames: false,
            show_link_names: false,
            show_collision: false,
            show_trail: true,
            show_ghost: true,
            show_grid: true,
            trail_coloring: trail_color::TrailColoring::Plain,
        }
    }
}

static NEXT_VIEWPORT_ID: AtomicU64 = AtomicU64::new(1);

/// Keyboard orbit speed, rad/s.
const KEY_ORBIT_RAD_S: f32 = 1.5;
/// Keyboard zoom speed, factor per second.
const KEY_ZOOM_PER_S: f32 = 2.5;

/// The interactive 3D view inside egui.
pub struct Viewport {
    /// Display toggles.
    pub options: ViewportOptions,
    id: u64,
    camera: OrbitCamera,
    shared: SharedFrame,
    link_names: Vec<String>,
    warnings: Vec<String>,
    egui_renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    /// The last frame's inputs and its paint callback: an unchanged view hands egui the same
    /// callback again, so retained painting sees nothing to redraw there.
    last_drawn: Option<LastDrawn>,
    /// The meshes' boxes, to tell retained painting which part of the view a moving arm changes.
    bounds: view_damage::SceneBounds,
}

struct LastDrawn {
    scene: SceneFrame,
    options: ViewportOptions,
    camera: OrbitCamera,
    rect: egui::Rect,
    callback: egui::PaintCallback,
    /// Where the scene's moving parts and the trail were on screen.
    scene_rect: egui::Rect,
    trail_rect: egui::Rect,
}

impl Viewport {
    /// Loads the model's meshes onto the GPU and registers the paint-callback resources with
    /// egui's renderer. Missing or broken meshes become placeholders listed in
    /// [`Self::warnings`]; this never panics on bad files.
    ///
    /// The window must have been created with [`configure_native_options`] (both honour
    /// `PAROL6_MSAA`, see [`msaa_from_env`]).
    pub fn new(render_state: &egui_wgpu::RenderState, model: &RobotModel) -> Result<Self, ViewportError> {
        Self::with_target(render_state, model, msaa_from_env().unwrap_or(MSAA_SAMPLES), Some(DEPTH_FORMAT))
    }

    /// Like [`Self::new`] for a window with another sample count or depth format
    /// (`depth_format: None` = the window has no depth buffer; the view then draws without
    /// depth testing, which only looks right for simple scenes).
    pub fn with_target(
        render_state: &egui_wgpu::RenderState,
        model: &RobotModel,
        sample_count: u32,
        depth_format: Option<eframe::wgpu::TextureFormat>,
    ) -> Result<Self, ViewportError> {
        let meshes = mesh::ModelMeshes::build(model);
        let bounds = view_damage::SceneBounds::new(&meshes);
        let warnings = meshes.warnings.clone();
        for w in &warnings {
            tracing::warn!("viewport: {w}");
        }
        let gpu = SceneGpu::new(
            &render_state.device,
            render_state.target_format,
            sample_count.max(1),
            depth_format,
            &meshes,
            true,
        );
        let mut frame = FrameData::new(&meshes);
        frame.set_encode_srgb(!render_state.target_format.is_srgb());
        let id = NEXT_VIEWPORT_ID.fetch_add(1, Ordering::Relaxed);
        {
            let mut renderer = render_state.renderer.write();
            let res = &mut renderer.callback_resources;
            if res.get::<ViewportGpuResources>().is_none() {
                res.insert(ViewportGpuResources::default());
            }
            if let Some(r) = res.get_mut::<ViewportGpuResources>() {
                r.scenes.insert(id, gpu);
            }
        }
        Ok(Self {
            options: ViewportOptions::default(),
            id,
            camera: OrbitCamera::default(),
            shared: Arc::new(std::sync::Mutex::new(frame)),
            link_names: model.links.iter().map(|l| l.name.clone()).collect(),
            warnings,
            egui_renderer: Arc::clone(&render_state.renderer),
            last_drawn: None,
            bounds,
        })
    }

    /// Mesh problems found while loading (each replaced by a placeholder).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The camera (read-only).
    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    /// Puts the camera where `camera` is (a view remembered from the last session).
    pub fn set_camera(&mut self, camera: OrbitCamera) {
        self.camera = camera;
    }

    /// Empties the TCP trail.
    pub fn clear_trail(&mut self) {
        if let Ok(mut f) = self.shared.lock() {
            f.trail.clear();
        }
        self.last_drawn = None;
    }

    /// Puts the camera back to its default view.
    pub fn reset_view(&mut self) {
        self.camera.reset();
    }

    /// Number of points in the TCP trail.
    pub fn trail_len(&self) -> usize {
        self.shared.lock().map(|f| f.trail.len()).unwrap_or(0)
    }

    /// Checkboxes for the display toggles plus "Reset view" and "Clear trail", for a panel or
    /// menu of the app.
    pub fn options_ui(&mut self, ui: &mut egui::Ui) {
        let o = &mut self.options;
        ui.checkbox(&mut o.show_grid, "Grid");
        ui.checkbox(&mut o.show_trail, "TCP trail");
        for c in trail_color::TrailColoring::ALL {
            ui.radio_value(&mut o.trail_coloring, c, c.label());
        }
        ui.checkbox(&mut o.show_ghost, "Target ghost");
        ui.checkbox(&mut o.show_link_frames, "Link frames");
        ui.checkbox(&mut o.show_link_names, "Link names");
        ui.checkbox(&mut o.show_collision, "Collision geometry");
        ui.horizontal(|ui| {
            if ui.button("Reset view").clicked() {
                self.reset_view();
            }
            let n = self.trail_len();
            if ui.button(format!("Clear trail ({n})")).clicked() {
                self.clear_trail();
            }
        });
    }

    /// Draws the view into all the space `ui` has left: handles orbit (left drag, arrow keys),
    /// pan (right or middle drag, shift + left drag), zoom (wheel, pinch, +/−), reset (R, Home,
    /// double-click); adds the TCP to the trail; paints the 3D scene and the overlays.
    pub fn ui(&mut self, ui: &mut egui::Ui, scene: &SceneFrame) -> egui::Response {
        let size = ui.available_size().max(egui::vec2(64.0, 64.0));
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click_and_drag());
        self.handle_input(ui, &response, rect);

        let aspect = (rect.width() / rect.height().max(1.0)).max(1e-3);
        let view_proj = self.camera.view_proj(aspect);
        let unchanged = self.last_drawn.as_ref().is_some_and(|l| {
            l.rect == rect && l.camera == self.camera && l.options == self.options && l.scene == *scene
        });
        if !unchanged {
            // the same view of another scene: only what moved changes (worked out only for
            // retained painting, which takes the hint)
            let hinting = retained::CallbackDamage::wanted(ui.ctx());
            let same_view = self
                .last_drawn
                .as_ref()
                .filter(|l| hinting && l.rect == rect && l.camera == self.camera && l.options == self.options);
            let last = same_view.map(|l| (l.callback.clone(), l.scene_rect, l.trail_rect));
            let mut trail_rect = last.as_ref().map_or(egui::Rect::NOTHING, |l| l.2);
            let mut trail_changed = true;
            if let Ok(mut frame) = self.shared.lock() {
                let before = (frame.trail.len(), frame.trail.newest_slot());
                frame.update(scene, &self.options, &self.camera, aspect);
                trail_changed = before != (frame.trail.len(), frame.trail.newest_slot());
                if hinting && (last.is_none() || trail_changed) {
                    trail_rect = if self.options.show_trail {
                        view_damage::trail_rect(&frame.trail, &view_proj, rect)
                    } else {
                        egui::Rect::NOTHING
                    };
                }
            }
            let scene_rect =
                if hinting { self.bounds.scene_rect(scene, &self.options, &view_proj, rect) } else { rect };
            let callback = egui_wgpu::Callback::new_paint_callback(
                rect,
                ViewportCallback { id: self.id, frame: Arc::clone(&self.shared) },
            );
            if let Some((last_callback, last_scene_rect, last_trail_rect)) = last {
                let mut dirty = last_scene_rect.union(scene_rect);
                if trail_changed {
                    dirty = dirty.union(last_trail_rect).union(trail_rect);
                }
                retained::CallbackDamage::new(&last_callback, &callback, dirty).publish(ui.ctx());
            }
            self.last_drawn = Some(LastDrawn {
                scene: scene.clone(),
                options: self.options,
                camera: self.camera,
                rect,
                callback,
                scene_rect,
                trail_rect,
            });
        }

        let painter = ui.painter_at(rect);
        if let Some(l) = &self.last_drawn {
            painter.add(l.callback.clone());
        }
        self.paint_overlays(&painter, rect, scene, &view_proj);
        response
    }

    fn handle_input(&mut self, ui: &egui::Ui, response: &egui::Response, rect: egui::Rect) {
        let shift = ui.input(|i| i.modifiers.shift);
        let delta = response.drag_delta();
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            self.camera.orbit(-delta.x * 0.008, delta.y * 0.008);
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            self.camera.pan_px(delta.x, delta.y, rect.width(), rect.height());
        }
        if response.double_clicked() {
            self.camera.reset();
        }
        if response.hovered() {
            let (scroll, pinch) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            if scroll != 0.0 {
                self.camera.zoom((-scroll * 0.002).exp());
            }
            if pinch != 1.0 {
                self.camera.zoom(1.0 / pinch);
            }
            // the keys' table (`panels::shortcuts`) keeps them off while a field has the keyboard
            self.handle_keys(ui);
        }
    }

    fn handle_keys(&mut self, ui: &egui::Ui) {
        use crate::panels::shortcuts::{Action, held, pressed};
        let ctx = ui.ctx();
        let dt = ui.input(|i| i.stable_dt.min(0.1));
        let (left, right) = (held(ctx, Action::Orbit(-1, 0)), held(ctx, Action::Orbit(1, 0)));
        let (up, down) = (held(ctx, Action::Orbit(0, 1)), held(ctx, Action::Orbit(0, -1)));
        let (zin, zout) = (held(ctx, Action::Zoom(1)), held(ctx, Action::Zoom(-1)));
        let reset = pressed(ctx, Action::ResetView);
        let step = KEY_ORBIT_RAD_S * dt;
        let mut active = false;
        let mut orbit = |yaw: f32, pitch: f32| {
            self.camera.orbit(yaw, pitch);
            active = true;
        };
        if left {
            orbit(-step, 0.0);
        }
        if right {
            orbit(step, 0.0);
        }
        if up {
            orbit(0.0, step);
        }
        if down {
            orbit(0.0, -step);
        }
        if zin {
            self.camera.zoom(1.0 / KEY_ZOOM_PER_S.powf(dt));
            active = true;
        }
        if zout {
            self.camera.zoom(KEY_ZOOM_PER_S.powf(dt));
            active = true;
        }
        if reset {
            self.camera.reset();
        }
        if active {
            ui.ctx().request_repaint();
        }
    }

    fn paint_overlays(
        &self,
        painter: &egui::Painter,
        rect: egui::Rect,
        scene: &SceneFrame,
        view_proj: &parol6_core::na::Matrix4<f32>,
    ) {
        let font = egui::FontId::proportional(12.0);
        if let Some(path) = &scene.planned_path {
            path.paint(painter, rect, view_proj);
        }
        if self.options.show_link_names {
            for (name, pose) in self.link_names.iter().zip(&scene.link_poses) {
                let t = pose.translation.vector;
                let p = Point3::new(t.x as f32, t.y as f32, t.z as f32);
                if let Some(s) = camera::project_to_rect(view_proj, &p, rect) {
                    painter.circle_filled(s, 2.5, palette::rgb(palette::VIEW_LINK_LABEL_DOT));
                    painter.text(
                        s + egui::vec2(5.0, -5.0),
                        egui::Align2::LEFT_BOTTOM,
                        name,
                        font.clone(),
                        palette::rgb(palette::VIEW_LINK_LABEL_TEXT),
                    );
                }
            }
        }
        let hint = palette::rgb(palette::VIEW_HINT_TEXT);
        if self.options.show_grid {
            painter.text(
                rect.left_bottom() + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                format!(
                    "grid {:.0} mm, bold {:.0} mm · X red, Y green, Z blue",
                    renderer::GRID_MINOR_M * 1000.0,
                    renderer::GRID_MAJOR_M * 1000.0
                ),
                font.clone(),
                hint,
            );
        }
        if !self.warnings.is_empty() {
            let text =
                format!("{}: {}", parol6_core::plural::count(self.warnings.len(), "mesh problem"), self.warnings[0]);
            painter.text(
                rect.left_top() + egui::vec2(8.0, 8.0),
                egui::Align2::LEFT_TOP,
                text,
                font,
                palette::rgb(palette::VIEW_WARNING_TEXT),
            );
        }
    }
}

impl Drop for Viewport {
    /// Frees this view's GPU buffers in egui's callback resources (e.g. when the app loads
    /// another robot and builds a new viewport).
    fn drop(&mut self) {
        let mut renderer = self.egui_renderer.write();
        if let Some(r) = renderer.callback_resources.get_mut::<ViewportGpuResources>() {
            r.scenes.remove(&self.id);
        }
    }
}

/// Reads a PNG back into an [`RgbaImage`] (used by tests and tools).
pub fn read_png(path: &Path) -> Result<RgbaImage, ViewportError> {
    offscreen::read_png(path)
}
