//! Headless image tests of the 3D view: the robot is in the picture, two poses give different
//! pictures, a joint at its limit shows the critical tint, the official STL description
//! renders. They need a software or hardware adapter (lavapipe: `mesa-vulkan-drivers`); with
//! none they fail when `CI` is set and print SKIPPED otherwise.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_app::viewport::renderer::BACKGROUND_SRGB;
use parol6_app::viewport::{
    DEPTH_FORMAT, OffscreenRenderer, RgbaImage, SceneFrame, Viewport, ViewportError, ViewportOptions, write_png,
};
use parol6_core::{LimitZone, RobotModel, parol6};

const W: u32 = 480;
const H: u32 = 300;

/// The renderer, or `None` (after printing SKIPPED) when no adapter exists outside CI.
fn renderer(model: &RobotModel, test: &str) -> Option<OffscreenRenderer> {
    match OffscreenRenderer::new(model, W, H) {
        Ok(r) => {
            eprintln!("{test}: adapter {}", r.adapter_info());
            Some(r)
        }
        Err(e @ (ViewportError::NoAdapter(_) | ViewportError::Device(_))) => {
            if std::env::var_os("CI").is_some() {
                panic!("{test}: no usable graphics adapter in CI: {e}");
            }
            parol6_tests::skip_notice(&format!("SKIPPED {test}: {e}"));
            None
        }
        Err(e) => panic!("{test}: {e}"),
    }
}

fn render(r: &mut OffscreenRenderer, scene: &SceneFrame, options: &ViewportOptions) -> RgbaImage {
    match r.render(scene, options) {
        Ok(img) => img,
        Err(e) => panic!("render failed: {e}"),
    }
}

fn save(img: &RgbaImage, name: &str) {
    let dir = std::env::temp_dir().join("parol6-render-tests");
    let _ = std::fs::create_dir_all(&dir);
    if let Err(e) = write_png(&dir.join(name), img) {
        eprintln!("could not save {name}: {e}");
    }
}

fn standby() -> Vec<f64> {
    parol6::standby_rad().to_vec()
}

fn is_background(p: [u8; 4]) -> bool {
    (0..3).all(|i| (p[i] as i32 - BACKGROUND_SRGB[i] as i32).abs() <= 3)
}

fn differing_pixels(a: &RgbaImage, b: &RgbaImage) -> usize {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels.chunks_exact(4).zip(b.pixels.chunks_exact(4)).filter(|(p, q)| p != q).count()
}

/// Bounding box (x0, y0, x1, y1) and count of the pixels of `img` that differ from `bg`.
fn changed_region(img: &RgbaImage, bg: &RgbaImage) -> (u32, u32, u32, u32, usize) {
    let (mut x0, mut y0, mut x1, mut y1, mut n) = (u32::MAX, u32::MAX, 0, 0, 0);
    for y in 0..img.height {
        for x in 0..img.width {
            if img.pixel(x, y) != bg.pixel(x, y) {
                x0 = x0.min(x);
                y0 = y0.min(y);
                x1 = x1.max(x);
                y1 = y1.max(y);
                n += 1;
            }
        }
    }
    (x0, y0, x1, y1, n)
}

/// Everything hidden except the robot (no grid, trail, ghost, axes are always drawn).
fn robot_only() -> ViewportOptions {
    ViewportOptions { show_grid: false, show_trail: false, show_ghost: false, ..ViewportOptions::default() }
}

/// A scene with no link at all in view (poses far behind the camera), to isolate the robot.
fn empty_scene(model: &RobotModel) -> SceneFrame {
    let far = parol6_core::na::Isometry3::translation(0.0, 0.0, -1000.0);
    SceneFrame {
        link_poses: vec![far; model.links.len()],
        link_zones: vec![None; model.links.len()],
        tcp: far,
        ghost_link_poses: None,
        planned_path: None,
        trail_sample: Default::default(),
    }
}

#[test]
fn robot_is_in_the_picture_and_output_is_deterministic() {
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "robot_is_in_the_picture") else { return };
    let scene = SceneFrame::from_joints(&model, &standby(), None);
    let img = render(&mut r, &scene, &ViewportOptions::default());
    save(&img, "standby.png");
    assert_eq!((img.width, img.height), (W, H));
    assert_eq!(img.pixels.len(), (W * H * 4) as usize);
    // The top-left corner is sky: plain background.
    assert!(img.pixel(2, 2).is_some_and(is_background), "corner {:?}", img.pixel(2, 2));

    // The robot alone, against the same render without the robot.
    let only = render(&mut r, &scene, &robot_only());
    let bg = render(&mut r, &empty_scene(&model), &robot_only());
    assert!(
        bg.pixels.chunks_exact(4).all(|p| is_background([p[0], p[1], p[2], p[3]])),
        "the empty scene is plain background"
    );
    let (x0, y0, x1, y1, n) = changed_region(&only, &bg);
    let frac = n as f64 / (W * H) as f64;
    eprintln!("robot covers {:.1}% of the image, box ({x0},{y0})–({x1},{y1})", frac * 100.0);
    assert!(frac > 0.03 && frac < 0.6, "robot coverage {frac}");
    // It stands roughly in the middle: its box contains the image centre column and reaches
    // from the upper half into the lower half.
    assert!(x0 < W / 2 && x1 > W / 2 && y0 < H / 2 && y1 > H / 2, "box ({x0},{y0})–({x1},{y1})");
    // Lit: the robot shows many distinct shades, not a flat silhouette.
    let mut shades: Vec<[u8; 3]> = only
        .pixels
        .chunks_exact(4)
        .zip(bg.pixels.chunks_exact(4))
        .filter(|(p, q)| p != q)
        .map(|(p, _)| [p[0], p[1], p[2]])
        .collect();
    shades.sort_unstable();
    shades.dedup();
    assert!(shades.len() > 200, "only {} distinct colours on the robot", shades.len());

    // Same input → the same bytes.
    let again = render(&mut r, &scene, &robot_only());
    assert_eq!(differing_pixels(&only, &again), 0);
}

#[test]
fn two_poses_give_different_pictures() {
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "two_poses_give_different_pictures") else { return };
    let a = render(&mut r, &SceneFrame::from_joints(&model, &standby(), None), &robot_only());
    let mut q = standby();
    q[1] += 0.6; // J2: lean the upper arm
    q[4] += 0.8; // J5: bend the wrist
    let b = render(&mut r, &SceneFrame::from_joints(&model, &q, None), &robot_only());
    save(&a, "pose_a.png");
    save(&b, "pose_b.png");
    let n = differing_pixels(&a, &b);
    eprintln!("{n} pixels differ");
    assert!(n > (W * H) as usize / 50, "only {n} pixels differ between two poses");
}

#[test]
fn joint_at_limit_shows_the_critical_tint() {
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "joint_at_limit_shows_the_critical_tint") else { return };
    // J3 at its upper limit, the other joints away from theirs.
    let mut q = standby();
    q[0] = 0.0;
    let j3 = 2;
    q[j3] = match model.limits.get(j3) {
        Some(l) => l.max,
        None => panic!("the PAROL6 has a J3"),
    };
    let scene = SceneFrame::from_joints(&model, &q, None);
    let l3 = model.links.iter().position(|l| l.frame == j3 + 1);
    let l3 = l3.unwrap_or_else(|| panic!("no link rides on J3"));
    assert_eq!(scene.link_zones[l3], Some(LimitZone::Critical));
    assert_eq!(scene.link_zones.iter().filter(|z| z.is_some()).count(), 1, "{:?}", scene.link_zones);

    let tinted = render(&mut r, &scene, &robot_only());
    let mut plain_scene = scene.clone();
    plain_scene.link_zones.iter_mut().for_each(|z| *z = None);
    let plain = render(&mut r, &plain_scene, &robot_only());
    // The warning tint on the same link, to tell the zones apart.
    let mut warn_scene = scene.clone();
    warn_scene.link_zones[l3] = Some(LimitZone::Warning);
    let warned = render(&mut r, &warn_scene, &robot_only());
    save(&tinted, "critical.png");
    save(&plain, "critical_plain.png");
    save(&warned, "warning.png");

    let shift = |img: &RgbaImage| {
        let (mut n, mut dr, mut dg, mut db) = (0usize, 0i64, 0i64, 0i64);
        for (p, q) in img.pixels.chunks_exact(4).zip(plain.pixels.chunks_exact(4)) {
            if p != q {
                n += 1;
                dr += p[0] as i64 - q[0] as i64;
                dg += p[1] as i64 - q[1] as i64;
                db += p[2] as i64 - q[2] as i64;
            }
        }
        let m = n.max(1) as f64;
        (n, dr as f64 / m, dg as f64 / m, db as f64 / m)
    };
    let (n, dr, dg, db) = shift(&tinted);
    eprintln!("critical: {n} px changed, mean shift r {dr:.1} g {dg:.1} b {db:.1}");
    assert!(n > 500, "the tinted link covers only {n} px");
    // Towards LimitZone::Critical's red: green and blue fall, red much less.
    assert!(dg < -25.0 && db < -15.0 && dr - dg > 25.0, "shift r {dr:.1} g {dg:.1} b {db:.1} is not towards red");
    let (nw, wr, wg, wb) = shift(&warned);
    eprintln!("warning: {nw} px changed, mean shift r {wr:.1} g {wg:.1} b {wb:.1}");
    // Amber keeps more green than red does.
    assert!(wg > dg + 15.0, "warning and critical tints look alike (g {wg:.1} vs {dg:.1})");
}

#[test]
fn ghost_trail_and_toggles_change_the_picture() {
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "ghost_trail_and_toggles") else { return };
    let q = standby();
    let mut g = standby();
    g[0] += 0.7;
    let scene = SceneFrame::from_joints(&model, &q, Some(&g));
    let base = render(&mut r, &scene, &robot_only());
    let ghost = render(&mut r, &scene, &ViewportOptions { show_ghost: true, ..robot_only() });
    assert!(differing_pixels(&base, &ghost) > 1000, "the ghost is not visible");
    let grid = render(&mut r, &scene, &ViewportOptions { show_grid: true, ..robot_only() });
    assert!(differing_pixels(&base, &grid) > 1000, "the grid is not visible");
    let frames = render(&mut r, &scene, &ViewportOptions { show_link_frames: true, ..robot_only() });
    assert!(differing_pixels(&base, &frames) > 100, "the link frames are not visible");
    let coll = render(&mut r, &scene, &ViewportOptions { show_collision: true, ..robot_only() });
    assert!(differing_pixels(&base, &coll) > 1000, "the collision geometry is not visible");

    // Trail: sweep J1 and draw the trail.
    r.clear_trail();
    let mut qq = standby();
    for i in 0..150 {
        qq[0] = 1.5 - i as f64 * 0.02;
        let _ = render(&mut r, &SceneFrame::from_joints(&model, &qq, None), &robot_only());
    }
    assert_eq!(r.trail_len(), 150);
    let no_trail = render(&mut r, &SceneFrame::from_joints(&model, &qq, None), &robot_only());
    let trail = render(
        &mut r,
        &SceneFrame::from_joints(&model, &qq, None),
        &ViewportOptions { show_trail: true, ..robot_only() },
    );
    save(&trail, "trail.png");
    save(&ghost, "ghost.png");
    save(&coll, "collision.png");
    save(&frames, "frames.png");
    assert!(differing_pixels(&no_trail, &trail) > 100, "the trail is not visible");
    r.clear_trail();
    assert_eq!(r.trail_len(), 0);
    let cleared = render(
        &mut r,
        &SceneFrame::from_joints(&model, &qq, None),
        &ViewportOptions { show_trail: true, ..robot_only() },
    );
    assert_eq!(differing_pixels(&no_trail, &cleared), 0, "a cleared trail must not draw");
}

#[test]
fn a_trail_coloured_by_speed_shows_slow_and_fast_apart() {
    use parol6_app::viewport::trail_color::{TrailColoring, TrailSample};
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "trail_by_speed") else { return };
    let sweep = |r: &mut OffscreenRenderer, speed_m_s: f64, coloring: TrailColoring| {
        r.clear_trail();
        let mut qq = standby();
        let mut last = None;
        for i in 0..150 {
            qq[0] = 1.5 - i as f64 * 0.02;
            let mut scene = SceneFrame::from_joints(&model, &qq, None);
            scene.trail_sample = TrailSample { tcp_speed_m_s: speed_m_s, tracking_error_rad: 0.0 };
            let opts = ViewportOptions { show_trail: true, trail_coloring: coloring, ..robot_only() };
            last = Some(render(r, &scene, &opts));
        }
        last.expect("rendered")
    };
    let slow = sweep(&mut r, 0.0, TrailColoring::Speed);
    let fast = sweep(&mut r, 0.2, TrailColoring::Speed);
    let plain = sweep(&mut r, 0.2, TrailColoring::Plain);
    save(&fast, "trail_fast.png");
    assert!(differing_pixels(&slow, &fast) > 100, "slow and fast trails look alike");
    assert!(differing_pixels(&plain, &fast) > 100, "a speed-coloured trail looks like the plain one");
    // blue at rest, red at full speed: where the pictures differ, the fast one is redder
    let (mut red_fast, mut red_slow) = (0u64, 0u64);
    for (a, b) in fast.pixels.chunks_exact(4).zip(slow.pixels.chunks_exact(4)) {
        if a != b {
            red_fast += u64::from(a[0]);
            red_slow += u64::from(b[0]);
        }
    }
    assert!(red_fast > red_slow, "red {red_fast} vs {red_slow}");
}

#[test]
fn official_stl_description_renders_with_its_meshes() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/parol6/urdf/python-api/PAROL6.urdf");
    if !path.is_file() {
        parol6_tests::skip_notice(&format!("SKIPPED official_stl_description: {} not present", path.display()));
        return;
    }
    let model = match RobotModel::from_urdf_file(&path, None) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let Some(mut r) = renderer(&model, "official_stl_description") else { return };
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
    let q = vec![0.0; model.dof()];
    let img = render(&mut r, &SceneFrame::from_joints(&model, &q, None), &robot_only());
    let bg = render(&mut r, &empty_scene(&model), &robot_only());
    save(&img, "official_stl.png");
    let (_, _, _, _, n) = changed_region(&img, &bg);
    let frac = n as f64 / (W * H) as f64;
    eprintln!("official STL robot covers {:.1}%", frac * 100.0);
    assert!(frac > 0.02, "the STL robot covers only {frac}");
}

#[test]
fn bad_sizes_are_errors_not_panics() {
    let model = RobotModel::parol6();
    match OffscreenRenderer::new(&model, 0, 10) {
        Err(ViewportError::InvalidSize { .. }) => {}
        Err(e @ (ViewportError::NoAdapter(_) | ViewportError::Device(_))) => {
            if std::env::var_os("CI").is_some() {
                panic!("no usable graphics adapter in CI: {e}");
            }
            parol6_tests::skip_notice(&format!("SKIPPED bad_sizes: {e}"));
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("a 0-pixel-wide image must be refused"),
    }
}

/// The egui path: a [`Viewport`] inside an egui frame, drawn through egui-wgpu's renderer and
/// the viewport's paint callback (the same code the window runs), read back offscreen.
#[test]
fn viewport_paint_callback_draws_the_robot_inside_egui() {
    use eframe::egui;
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "viewport_paint_callback") else { return };
    let rs = r.egui_render_state();
    let mut vp = match Viewport::with_target(&rs, &model, r.sample_count(), Some(DEPTH_FORMAT)) {
        Ok(v) => v,
        Err(e) => panic!("{e}"),
    };
    assert!(vp.warnings().is_empty());
    vp.options.show_link_names = true;
    let ctx = egui::Context::default();
    let mut frame = |q: &[f64], vp: &mut Viewport| {
        let scene = SceneFrame::from_joints(&model, q, None);
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
            ..Default::default()
        };
        let out = ctx.run_ui(input, |ui| {
            egui::Panel::left("side").exact_size(120.0).show(ui, |ui| {
                ui.label("panel");
            });
            egui::CentralPanel::no_frame().show(ui, |ui| {
                vp.ui(ui, &scene);
            });
        });
        let prims = ctx.tessellate(out.shapes, out.pixels_per_point);
        match r.render_egui(&rs, &prims, &out.textures_delta, out.pixels_per_point, [10, 10, 10]) {
            Ok(img) => img,
            Err(e) => panic!("{e}"),
        }
    };
    let a = frame(&standby(), &mut vp);
    let mut q = standby();
    q[0] -= 0.8;
    let b = frame(&q, &mut vp);
    save(&a, "egui_a.png");
    save(&b, "egui_b.png");
    // The 3D view fills the central area: its background colour is there…
    let bg_px = a.pixels.chunks_exact(4).filter(|p| is_background([p[0], p[1], p[2], p[3]])).count();
    assert!(bg_px > (W * H) as usize / 3, "3D background covers only {bg_px} px");
    // …with the robot in it (lit pixels that are neither the 3D background nor the clear colour).
    let robot_px = a
        .pixels
        .chunks_exact(4)
        .filter(|p| !is_background([p[0], p[1], p[2], p[3]]) && p[0].max(p[1]).max(p[2]) > 120)
        .count();
    assert!(robot_px > 2000, "robot pixels {robot_px}");
    assert!(differing_pixels(&a, &b) > 2000, "moving J1 must change the picture");
    assert_eq!(vp.trail_len(), 2);
    vp.clear_trail();
    assert_eq!(vp.trail_len(), 0);
}

/// Mouse and keyboard reach the camera: left drag orbits, right drag pans, the wheel zooms,
/// R resets.
#[test]
fn viewport_input_orbits_pans_zooms_and_resets() {
    use eframe::egui;
    let model = RobotModel::parol6();
    let Some(mut r) = renderer(&model, "viewport_input") else { return };
    let rs = r.egui_render_state();
    let mut vp = match Viewport::with_target(&rs, &model, r.sample_count(), Some(DEPTH_FORMAT)) {
        Ok(v) => v,
        Err(e) => panic!("{e}"),
    };
    let ctx = egui::Context::default();
    let scene = SceneFrame::from_joints(&model, &standby(), None);
    let mut t = 0.0;
    let mut step = |events: Vec<egui::Event>, vp: &mut Viewport| {
        t += 1.0 / 60.0;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(W as f32, H as f32))),
            time: Some(t),
            focused: true,
            events,
            ..Default::default()
        };
        let out = ctx.run_ui(input, |ui| {
            egui::CentralPanel::no_frame().show(ui, |ui| {
                vp.ui(ui, &scene);
            });
        });
        let _ = ctx.tessellate(out.shapes, out.pixels_per_point);
    };
    let c = egui::pos2(W as f32 / 2.0, H as f32 / 2.0);
    let button =
        |pos, button, pressed| egui::Event::PointerButton { pos, button, pressed, modifiers: Default::default() };
    let drag = |step: &mut dyn FnMut(Vec<egui::Event>, &mut Viewport), vp: &mut Viewport, b| {
        step(vec![egui::Event::PointerMoved(c)], vp);
        step(vec![button(c, b, true)], vp);
        for i in 1..=5 {
            step(vec![egui::Event::PointerMoved(c + egui::vec2(12.0 * i as f32, 6.0 * i as f32))], vp);
        }
        step(vec![button(c + egui::vec2(60.0, 30.0), b, false)], vp);
    };
    let cam0 = *vp.camera();
    drag(&mut step, &mut vp, egui::PointerButton::Primary);
    let cam1 = *vp.camera();
    assert!((cam1.yaw_rad - cam0.yaw_rad).abs() > 0.1, "left drag must orbit: {cam0:?} → {cam1:?}");
    assert!((cam1.pitch_rad - cam0.pitch_rad).abs() > 0.05);
    assert_eq!(cam1.target_m, cam0.target_m, "orbiting keeps the target");

    drag(&mut step, &mut vp, egui::PointerButton::Secondary);
    let cam2 = *vp.camera();
    assert!((cam2.target_m - cam1.target_m).norm() > 0.01, "right drag must pan");
    assert_eq!(cam2.yaw_rad, cam1.yaw_rad, "panning keeps the orientation");

    for _ in 0..10 {
        let wheel = egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, 40.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: Default::default(),
        };
        step(vec![egui::Event::PointerMoved(c), wheel], &mut vp);
    }
    // Let egui's smooth scrolling run out.
    for _ in 0..90 {
        step(vec![], &mut vp);
    }
    let cam3 = *vp.camera();
    assert!(
        cam3.distance_m < cam2.distance_m * 0.95,
        "wheel up must zoom in: {} → {}",
        cam2.distance_m,
        cam3.distance_m
    );

    let key = |pressed| egui::Event::Key {
        key: egui::Key::R,
        physical_key: None,
        pressed,
        repeat: false,
        modifiers: Default::default(),
    };
    step(vec![egui::Event::PointerMoved(c), key(true)], &mut vp);
    step(vec![key(false)], &mut vp);
    assert_eq!(*vp.camera(), cam0, "R must reset the view");
}
