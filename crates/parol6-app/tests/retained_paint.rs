//! Retained painting (only changed rectangles redrawn) gives the same picture as drawing the
//! whole frame, frame after frame, while labels change, a window opens and closes, a widget
//! moves and the 3D view's arm turns. Needs a software or hardware adapter (lavapipe:
//! `mesa-vulkan-drivers`); with none it fails when `CI` is set and prints SKIPPED otherwise.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use eframe::egui;
use parol6_app::viewport::retained::{self, RetainedHandle};
use parol6_app::viewport::{
    DEPTH_FORMAT, OffscreenRenderer, RgbaImage, SceneFrame, Viewport, ViewportError, write_png,
};
use parol6_core::{RobotModel, parol6};

const W: u32 = 640;
const H: u32 = 400;

struct Painter {
    renderer: OffscreenRenderer,
    rs: eframe::egui_wgpu::RenderState,
    ctx: egui::Context,
    viewport: Viewport,
    retained: Option<RetainedHandle>,
}

fn painter(model: &RobotModel, retained_on: bool) -> Option<Painter> {
    let renderer = match OffscreenRenderer::with_sample_count(model, W, H, 1) {
        Ok(r) => r,
        Err(e @ (ViewportError::NoAdapter(_) | ViewportError::Device(_))) => {
            if std::env::var_os("CI").is_some() {
                panic!("no usable graphics adapter in CI: {e}");
            }
            parol6_tests::skip_notice(&format!("SKIPPED retained_paint: {e}"));
            return None;
        }
        Err(e) => panic!("{e}"),
    };
    let mut renderer = renderer;
    // as the window: with retained painting egui's own pass has no depth buffer (the 3D view
    // draws into the kept image, which has one)
    let rs = renderer.egui_render_state_with_depth(!retained_on);
    let viewport = Viewport::with_target(&rs, model, 1, Some(DEPTH_FORMAT)).expect("viewport");
    let ctx = egui::Context::default();
    // on whatever the adapter (the window turns it on for software rasterizers only)
    let retained =
        retained_on.then(|| retained::install(&ctx, &rs, egui::Color32::from_rgb(BG[0], BG[1], BG[2]), None));
    // the full frames compared with retained painting's: the same UI, without egui's animations
    // (as retained painting turns them off)
    if !retained_on {
        ctx.all_styles_mut(|style| style.animation_time = 0.0);
    }
    Some(Painter { renderer, rs, ctx, viewport, retained })
}

const BG: [u8; 3] = [27, 27, 27];
/// Pixels of the 3D view beside the 400-point side panel.
const VIEW_PX: f64 = ((W - 400) * H) as f64;

/// Frame `step` of a scripted UI: a side panel whose counter label changes, a button that moves
/// down one row every 4 steps, a window open for steps 3–5, and the arm turning in the 3D view
/// until step 6, then standing still; from step 8 a new grid each step (egui runs those frames
/// twice and draws the second pass).
fn frame(p: &mut Painter, model: &RobotModel, step: usize) -> RgbaImage {
    frame_turning(p, model, step, 0.05)
}

/// [`frame`] with the first joint turning by `j1_step_rad` a step.
fn frame_turning(p: &mut Painter, model: &RobotModel, step: usize, j1_step_rad: f64) -> RgbaImage {
    let mut q = parol6::standby_rad().to_vec();
    q[0] += j1_step_rad * step.min(6) as f64;
    let scene = SceneFrame::from_joints(model, &q, None);
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
        time: Some(step as f64 * 0.1),
        ..Default::default()
    };
    let vp = &mut p.viewport;
    let out = p.ctx.run_ui(input, |ui| {
        egui::Panel::left("side").exact_size(400.0).show(ui, |ui| {
            ui.label("joints");
            ui.label(format!("counter {step}"));
            for _ in 0..(step / 4) {
                ui.label("·");
            }
            let _ = ui.button("a button that moves");
            ui.label("static text at the bottom of the list");
            // a grid shown for the first time makes egui discard the pass and run another
            if step >= 8 {
                egui::Grid::new(("a grid from step 8", step)).show(ui, |ui| {
                    ui.label("x");
                    ui.label("1.00 mm");
                });
            }
        });
        if (3..=5).contains(&step) {
            egui::Window::new("popup").fixed_pos(egui::pos2(200.0, 100.0)).show(ui.ctx(), |ui| {
                ui.label(format!("open for a while ({step})"));
            });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            vp.ui(ui, &scene);
        });
    });
    let prims = p.ctx.tessellate(out.shapes, out.pixels_per_point);
    p.renderer.render_egui(&p.rs, &prims, &out.textures_delta, out.pixels_per_point, BG).expect("render")
}

/// Fails when `a` (drawn whole) and `b` (retained) differ in any pixel, and leaves both as
/// `{name}_direct_{step}.png` / `{name}_retained_{step}.png` in the temporary directory.
fn assert_same_image(a: &RgbaImage, b: &RgbaImage, name: &str, step: usize, stats: &retained::RetainedStats) {
    let differing: Vec<usize> = a
        .pixels
        .chunks_exact(4)
        .zip(b.pixels.chunks_exact(4))
        .enumerate()
        .filter(|(_, (x, y))| x != y)
        .map(|(i, _)| i)
        .collect();
    if let Some(&first) = differing.first() {
        let dir = std::env::temp_dir().join("parol6-render-tests");
        let _ = std::fs::create_dir_all(&dir);
        let _ = write_png(&dir.join(format!("{name}_direct_{step}.png")), a);
        let _ = write_png(&dir.join(format!("{name}_retained_{step}.png")), b);
        panic!(
            "step {step}: {} px differ, first at ({}, {}); stats {stats:?}; images in {}",
            differing.len(),
            first % W as usize,
            first / W as usize,
            dir.display()
        );
    }
}

#[test]
fn a_swinging_arm_is_redrawn_where_it_was_and_where_it_is() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    // no trail: its rectangle would cover the arm's last place anyway
    direct.viewport.options.show_trail = false;
    retained.viewport.options.show_trail = false;
    let mut hinted = 0;
    // J1 by 0.8 rad a frame: the arm leaves its last place
    for step in 0..4 {
        let a = frame_turning(&mut direct, &model, step, 0.8);
        let b = frame_turning(&mut retained, &model, step, 0.8);
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        if step > 0 && stats.redrawn_px < 0.9 * VIEW_PX {
            hinted += 1;
        }
        assert_same_image(&a, &b, "swing", step, &stats);
    }
    assert!(hinted >= 1, "no frame redrew less than the view");
}

#[test]
fn retained_frames_match_full_frames_pixel_for_pixel() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    let mut partial_frames = 0;
    let mut small_redraws = 0;
    let mut hinted_redraws = 0;
    for step in 0..10 {
        let a = frame(&mut direct, &model, step);
        let b = frame(&mut retained, &model, step);
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        if !stats.full_redraw && stats.redrawn_px < stats.screen_px {
            partial_frames += 1;
        }
        // with the arm still, the 3D view (240 × 400 px) is not redrawn: only the counter is
        if stats.redrawn_px < 20_000.0 {
            small_redraws += 1;
        }
        // egui discards the first pass of a frame with a new grid: the pass it shows is
        // compared with the last frame drawn, not with the discarded one (which painted nothing)
        if step >= 8 {
            assert!(stats.redrawn_px < 20_000.0, "step {step}: the pass after a discarded one redrew {stats:?}");
        }
        // while the arm turns (no window open) only the part of the view it sweeps, with the
        // trail, is redrawn besides the counter (the view's hint to retained painting)
        if (1..=2).contains(&step) && stats.redrawn_px > 2_000.0 && stats.redrawn_px < 0.5 * VIEW_PX {
            hinted_redraws += 1;
        }
        assert_same_image(&a, &b, "retained", step, &stats);
    }
    assert!(partial_frames >= 5, "only {partial_frames} of 10 frames were partial redraws");
    assert!(small_redraws >= 2, "the still 3D view was redrawn: only {small_redraws} small redraws");
    assert_eq!(hinted_redraws, 2, "the turning arm's frames redrew more than its part of the view");
}

/// A scripted UI whose side panel (40 labels) and arm change all at once at step 2: a change over
/// most of the window.
fn frame_all_changing(p: &mut Painter, model: &RobotModel, step: usize) -> RgbaImage {
    let mut q = parol6::standby_rad().to_vec();
    let changed = step >= 2;
    if changed {
        q[0] += 0.8;
        q[1] += 0.3;
    }
    let scene = SceneFrame::from_joints(model, &q, None);
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
        time: Some(step as f64 * 0.1),
        ..Default::default()
    };
    let vp = &mut p.viewport;
    let out = p.ctx.run_ui(input, |ui| {
        egui::Panel::left("side").exact_size(400.0).show(ui, |ui| {
            // the whole column changes colour (a theme or a mode switch)
            let fill = if changed { egui::Color32::from_rgb(40, 30, 60) } else { egui::Color32::from_rgb(30, 40, 30) };
            ui.painter().rect_filled(ui.max_rect(), 0.0, fill);
            for k in 0..20 {
                let v = if changed { 1000 + k } else { k };
                ui.label(format!("read-out {k}: {v} mm, and more text {v} {v} {v}"));
            }
        });
        egui::CentralPanel::no_frame().show(ui, |ui| {
            vp.ui(ui, &scene);
        });
    });
    let prims = p.ctx.tessellate(out.shapes, out.pixels_per_point);
    p.renderer.render_egui(&p.rs, &prims, &out.textures_delta, out.pixels_per_point, BG).expect("render")
}

/// A change over most of the window is redrawn over two frames (`retained::spread`):
/// the frame after it shows every pixel as a full frame does.
#[test]
fn a_window_wide_change_is_drawn_over_two_frames_and_then_matches_a_full_frame() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    for step in 0..5 {
        let a = frame_all_changing(&mut direct, &model, step);
        let b = frame_all_changing(&mut retained, &model, step);
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        match step {
            2 => {
                assert!(!stats.full_redraw && stats.redrawn_px < stats.screen_px, "spread: {stats:?}");
                assert!(stats.redrawn_px > 0.2 * stats.screen_px, "a whole column now: {stats:?}");
            }
            3 => {
                assert!(stats.redrawn_px > 0.2 * stats.screen_px, "the rest of the window next: {stats:?}");
                assert_same_image(&a, &b, "spread", step, &stats);
            }
            _ => assert_same_image(&a, &b, "spread", step, &stats),
        }
    }
}

/// Frame `step` of a UI of `w` × `h` px: a side panel and the 3D view, and from step 2 a window
/// holding a mesh of 9 600 small triangles, which costs a software rasterizer more than
/// the threshold of `retained::spread` (a table of text fields appearing).
fn frame_window_appearing(p: &mut Painter, model: &RobotModel, step: usize, (w, h): (u32, u32)) -> RgbaImage {
    let scene = SceneFrame::from_joints(model, &parol6::standby_rad(), None);
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(w as f32, h as f32))),
        time: Some(step as f64 * 0.1),
        ..Default::default()
    };
    let vp = &mut p.viewport;
    let out = p.ctx.run_ui(input, |ui| {
        egui::Panel::left("side").exact_size(200.0).show(ui, |ui| {
            for k in 0..12 {
                ui.label(format!("read-out {k}: {} mm", 10 * k));
            }
        });
        if step >= 2 {
            egui::Window::new("table").fixed_pos(egui::pos2(120.0, 40.0)).fade_in(false).show(ui.ctx(), |ui| {
                let (rect, _) = ui.allocate_exact_size(egui::vec2(400.0, 240.0), egui::Sense::hover());
                let mut mesh = egui::Mesh::default();
                for row in 0..60 {
                    for col in 0..80 {
                        let min = rect.min + egui::vec2(5.0 * col as f32, 4.0 * row as f32);
                        let shade = ((row * 7 + col * 3) % 200) as u8 + 40;
                        mesh.add_colored_rect(
                            egui::Rect::from_min_size(min, egui::vec2(4.0, 3.0)),
                            egui::Color32::from_gray(shade),
                        );
                    }
                }
                ui.painter().add(egui::Shape::mesh(mesh));
            });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            vp.ui(ui, &scene);
        });
    });
    let prims = p.ctx.tessellate(out.shapes, out.pixels_per_point);
    p.renderer.render_egui(&p.rs, &prims, &out.textures_delta, out.pixels_per_point, BG).expect("render")
}

/// A costly window appearing over part of the window is drawn in two bands over two frames
/// (`retained::spread`): the first frame draws its top band only, the next one shows every
/// pixel as a full frame does.
#[test]
fn a_costly_window_appearing_is_drawn_over_two_frames_and_then_matches_a_full_frame() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    for step in 0..6 {
        let a = frame_window_appearing(&mut direct, &model, step, (W, H));
        let b = frame_window_appearing(&mut retained, &model, step, (W, H));
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        // egui sizes a new window in an invisible first frame: it shows from step 3
        match step {
            3 => {
                assert!(stats.triangles < 7_200, "about half of the mesh now: {stats:?}");
                assert!(a != b, "the bottom band waits a frame");
            }
            4 => {
                assert!(stats.triangles > 2_400, "the rest of the mesh next: {stats:?}");
                assert_same_image(&a, &b, "band", step, &stats);
            }
            _ => assert_same_image(&a, &b, "band", step, &stats),
        }
    }
}

/// A new window size is drawn over two frames by columns, and what is not yet drawn shows the
/// last image, not an empty one; the frame after shows every pixel as a full frame does.
#[test]
fn a_new_window_size_is_drawn_over_two_frames_and_then_matches_a_full_frame() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    let sizes = [(W, H), (W, H), (W - 80, H - 40), (W - 80, H - 40), (W - 80, H - 40)];
    for (step, &(w, h)) in sizes.iter().enumerate() {
        for p in [&mut direct, &mut retained] {
            p.renderer.resize(w, h).expect("resize");
        }
        let a = frame_window_appearing(&mut direct, &model, 0, (w, h));
        let b = frame_window_appearing(&mut retained, &model, 0, (w, h));
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step} at {w}x{h}: {stats:?}");
        match step {
            2 => {
                assert!(!stats.full_redraw && stats.redrawn_px < stats.screen_px, "spread: {stats:?}");
                // the columns not drawn yet hold the last image: the side panel's background
                // and labels, never an empty (zero) image
                assert!(b.pixels.chunks_exact(4).all(|px| px[3] == 255), "no empty pixel");
            }
            3 => assert_same_image(&a, &b, "resize", step, &stats),
            _ => assert_same_image(&a, &b, "resize", step, &stats),
        }
    }
}

/// Frame `step` of a UI with a side panel on each side of the 3D view, each holding a mesh of
/// 4 800 small triangles whose shades all change at step 2 (with the arm): a window-wide change
/// of more work than two frames should take (`retained::spread::FRAME_PART_US`).
fn frame_three_columns_changing(p: &mut Painter, model: &RobotModel, step: usize) -> RgbaImage {
    let mut q = parol6::standby_rad().to_vec();
    let changed = step >= 2;
    if changed {
        q[0] += 0.8;
    }
    let scene = SceneFrame::from_joints(model, &q, None);
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
        time: Some(step as f64 * 0.1),
        ..Default::default()
    };
    let shades = |ui: &mut egui::Ui| {
        let rect = ui.max_rect();
        let mut mesh = egui::Mesh::default();
        for row in 0..60 {
            for col in 0..40 {
                let min = rect.min + egui::vec2(5.0 * col as f32, 6.0 * row as f32);
                let shade = ((row * 7 + col * 3 + if changed { 50 } else { 0 }) % 200) as u8 + 40;
                mesh.add_colored_rect(
                    egui::Rect::from_min_size(min, egui::vec2(4.0, 5.0)),
                    egui::Color32::from_gray(shade),
                );
            }
        }
        ui.painter().add(egui::Shape::mesh(mesh));
    };
    let vp = &mut p.viewport;
    let out = p.ctx.run_ui(input, |ui| {
        egui::Panel::left("left").exact_size(200.0).show(ui, shades);
        egui::Panel::right("right").exact_size(200.0).show(ui, shades);
        egui::CentralPanel::no_frame().show(ui, |ui| {
            vp.ui(ui, &scene);
        });
    });
    let prims = p.ctx.tessellate(out.shapes, out.pixels_per_point);
    p.renderer.render_egui(&p.rs, &prims, &out.textures_delta, out.pixels_per_point, BG).expect("render")
}

/// A window-wide change of much work is redrawn over three frames, a column each
/// (`retained::spread`): no frame draws more than one column, and the third shows every pixel
/// as a full frame does.
#[test]
fn a_window_wide_change_of_much_work_is_drawn_over_three_frames_and_then_matches_a_full_frame() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    for step in 0..6 {
        let a = frame_three_columns_changing(&mut direct, &model, step);
        let b = frame_three_columns_changing(&mut retained, &model, step);
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        match step {
            2 | 3 => {
                assert!(!stats.full_redraw, "spread: {stats:?}");
                assert_eq!(stats.frames_left, 4 - step, "frames still needed: {stats:?}");
                assert!(
                    stats.redrawn_px > 0.2 * stats.screen_px && stats.redrawn_px < 0.45 * stats.screen_px,
                    "one column a frame: {stats:?}"
                );
                assert!(b.pixels.chunks_exact(4).all(|px| px[3] == 255), "no empty pixel");
            }
            _ => {
                assert_eq!(stats.frames_left, 0, "{stats:?}");
                assert_same_image(&a, &b, "three parts", step, &stats);
            }
        }
    }
}

/// Frame `step` (at 60 Hz) of a UI whose window (egui's default: fading in) opens at step 2.
fn frame_dialog_opening(p: &mut Painter, model: &RobotModel, step: usize) -> RgbaImage {
    let scene = SceneFrame::from_joints(model, &parol6::standby_rad(), None);
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
        time: Some(step as f64 / 60.0),
        predicted_dt: 1.0 / 60.0,
        ..Default::default()
    };
    let vp = &mut p.viewport;
    let out = p.ctx.run_ui(input, |ui| {
        if step >= 2 {
            egui::Window::new("dialog").fixed_pos(egui::pos2(60.0, 60.0)).show(ui.ctx(), |ui| {
                for k in 0..6 {
                    ui.label(format!("file {k}.gcode"));
                }
            });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            vp.ui(ui, &scene);
        });
    });
    let prims = p.ctx.tessellate(out.shapes, out.pixels_per_point);
    p.renderer.render_egui(&p.rs, &prims, &out.textures_delta, out.pixels_per_point, BG).expect("render")
}

/// A window opening is drawn once, whole (no fade-in redrawing it frame after frame on a
/// software rasterizer: a file dialog's five fade frames took ~35 ms each on llvmpipe).
#[test]
fn a_window_opening_is_drawn_whole_at_once_and_not_again_while_it_stands() {
    let model = RobotModel::parol6();
    let Some(mut direct) = painter(&model, false) else { return };
    let Some(mut retained) = painter(&model, true) else { return };
    let mut drawn_px = 0.0;
    for step in 0..9 {
        let a = frame_dialog_opening(&mut direct, &model, step);
        let b = frame_dialog_opening(&mut retained, &model, step);
        let stats = retained.retained.as_ref().map(RetainedHandle::stats).expect("stats");
        eprintln!("step {step}: {stats:?}");
        if (2..=3).contains(&step) {
            // egui sizes a new window in its first frame and shows it in the next
            drawn_px += stats.redrawn_px;
        }
        if step == 3 {
            assert!(drawn_px > 0.0, "the window is drawn: {stats:?}");
        }
        if step >= 4 {
            assert_eq!(stats.redrawn_px, 0.0, "a standing window is not redrawn (step {step}): {stats:?}");
        }
        assert_same_image(&a, &b, "dialog", step, &stats);
    }
}
