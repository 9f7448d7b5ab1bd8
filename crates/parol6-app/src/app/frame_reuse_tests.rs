use super::*;
use egui::{Color32, Pos2, Shape};

const SCREEN: Rect = Rect { min: Pos2::ZERO, max: Pos2 { x: 1280.0, y: 800.0 } };

fn clipped(clip: Rect, color: Color32) -> ClippedShape {
    ClippedShape {
        clip_rect: clip,
        shape: Shape::rect_filled(clip.shrink(1.0), 0.0, color),
        transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
    }
}

#[test]
fn the_3d_views_shapes_are_swapped_in_their_place() {
    let central = Rect::from_min_max(Pos2::new(300.0, 20.0), Pos2::new(900.0, 500.0));
    let side = Rect::from_min_max(Pos2::new(0.0, 20.0), Pos2::new(300.0, 780.0));
    let lower = Rect::from_min_max(Pos2::new(300.0, 500.0), Pos2::new(900.0, 780.0));
    let kept = vec![
        clipped(side, Color32::RED),
        clipped(central, Color32::BLUE),
        clipped(central.shrink(10.0), Color32::BLUE),
        clipped(lower, Color32::GREEN),
        clipped(SCREEN, Color32::WHITE),
    ];
    let fresh = vec![clipped(central, Color32::YELLOW), clipped(central.shrink(4.0), Color32::BLACK)];
    let out = splice(&kept, central, fresh.clone());
    let colors: Vec<_> = out
        .iter()
        .map(|s| match &s.shape {
            Shape::Rect(r) => r.fill,
            _ => Color32::TRANSPARENT,
        })
        .collect();
    assert_eq!(colors, [Color32::RED, Color32::YELLOW, Color32::BLACK, Color32::GREEN, Color32::WHITE]);
    // nothing of the view kept: the fresh shapes go last
    let out = splice(&kept[..1], central, fresh);
    assert_eq!(out.len(), 3);
}

/// What the pointer can hit: every widget's id, rectangles, sense and state.
fn widget_set(ctx: &egui::Context) -> Vec<(Id, [i32; 8], bool, bool)> {
    let mut v: Vec<_> = ctx.viewport(|v| {
        v.prev_pass
            .widgets
            .layers()
            .flat_map(|(_, ws)| ws.iter().copied())
            .map(|w| {
                let r = [w.rect, w.interact_rect].map(|r| [r.min.x, r.min.y, r.max.x, r.max.y]);
                let r = r.as_flattened().iter().map(|x| (x * 4.0).round() as i32).collect::<Vec<_>>();
                let mut a = [0; 8];
                a.copy_from_slice(&r);
                (w.id, a, w.enabled, w.sense.senses_click())
            })
            .collect()
    });
    v.sort_by_key(|w| w.0.value());
    v
}

/// Where the text `label` is painted in `out`.
fn text_at(out: &egui::FullOutput, label: &str) -> Option<Rect> {
    fn find(shape: &Shape, label: &str) -> Option<Rect> {
        match shape {
            Shape::Text(t) if t.galley.text() == label => Some(t.visual_bounding_rect()),
            Shape::Vec(v) => v.iter().find_map(|s| find(s, label)),
            _ => None,
        }
    }
    out.shapes.iter().find_map(|s| find(&s.shape, label).map(|r| r.intersect(s.clip_rect)))
}

struct Run {
    app: Parol6App,
    ctx: egui::Context,
    handle: FrameReuse,
}

impl Run {
    fn new() -> Self {
        let ctx = egui::Context::default();
        let handle = install_on(&ctx);
        let mut app = crate::app::tests::launch(None);
        assert!(app.start_program("Joint sweep", true), "the built-in sweep runs");
        Run { app, ctx, handle }
    }

    fn frame(&mut self, events: Vec<egui::Event>) -> egui::FullOutput {
        let input = egui::RawInput { screen_rect: Some(SCREEN), events, ..Default::default() };
        let app = &mut self.app;
        let mut out = self.ctx.run_ui(input, |ui| app.frame(ui));
        out.textures_delta.clear();
        out
    }

    /// Frames (10 ms apart) until one is reused; its output.
    fn until_reused(&mut self) -> egui::FullOutput {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let before = self.handle.stats().reused_frames;
            let out = self.frame(Vec::new());
            if self.handle.stats().reused_frames > before {
                return out;
            }
            assert!(Instant::now() < deadline, "no frame reused while the arm moves: {:?}", self.handle.stats());
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

#[test]
fn a_reused_frame_shows_and_hits_what_the_full_frame_did() {
    let mut run = Run::new();
    run.until_reused();
    // the next full frame (a read-out refresh), then a reused one right after it
    let full = loop {
        let before = run.handle.stats().full_frames;
        let out = run.frame(Vec::new());
        if run.handle.stats().full_frames > before {
            break out;
        }
    };
    let full_widgets = widget_set(&run.ctx);
    let central = run.handle.with(|k| k.central).flatten().expect("the view's rectangle");
    let reused = run.until_reused();
    assert!(run.app.robot_state().moving, "the arm moves all along");
    let reused_widgets = widget_set(&run.ctx);
    let missing: Vec<_> = full_widgets.iter().filter(|w| !reused_widgets.contains(w)).collect();
    assert!(missing.is_empty(), "the reused frame registers the full frame's widgets; missing {missing:?}");
    // besides them only the hosts that registered them: no area, no sense of clicks
    for w in reused_widgets.iter().filter(|w| !full_widgets.contains(w)) {
        assert!(!w.3 && w.1[0] == w.1[2] && w.1[1] == w.1[3], "unexpected widget {w:?}");
    }
    // the same panels, drawn from the kept shapes; the view's own drawn again
    let outside = |o: &egui::FullOutput| -> Vec<String> {
        o.shapes.iter().filter(|s| !central.expand(0.5).contains_rect(s.clip_rect)).map(|s| format!("{s:?}")).collect()
    };
    assert_eq!(outside(&reused), outside(&full));
    assert!(reused.shapes.len() > 100, "the panels are painted: {} shapes", reused.shapes.len());
}

#[test]
fn a_click_right_after_reused_frames_lands() {
    let mut run = Run::new();
    run.frame(Vec::new());
    let out = run.frame(Vec::new());
    // the joints panel's unit switch: no tooltip (one would keep the frames full)
    let rad = text_at(&out, "rad").expect("the rad/deg switch");
    assert!(rad.is_positive(), "rad on screen: {rad:?}");
    let at = rad.center();
    assert_eq!(run.app.settings.unit, crate::panels::AngleUnit::Deg);
    // the pointer comes to rest on the button, frames are reused, then it clicks without moving
    run.frame(vec![egui::Event::PointerMoved(at)]);
    run.until_reused();
    run.until_reused();
    // the press comes right after a reused frame
    let button = |pressed| egui::Event::PointerButton {
        pos: at,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    run.frame(vec![button(true)]);
    run.frame(vec![button(false)]);
    assert_eq!(run.app.settings.unit, crate::panels::AngleUnit::Rad, "the click switched to rad");
    assert!(run.app.robot_state().moving, "the arm moved all along");
}

#[test]
fn nothing_is_reused_while_the_arm_stands_still() {
    let ctx = egui::Context::default();
    let handle = install_on(&ctx);
    let mut app = crate::app::tests::launch(None);
    for _ in 0..40 {
        let input = egui::RawInput { screen_rect: Some(SCREEN), ..Default::default() };
        ctx.run_ui(input, |ui| app.frame(ui)).textures_delta.clear();
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(handle.stats().reused_frames, 0);
    // (egui may run a frame twice, e.g. to size a new panel)
    assert!(handle.stats().full_frames >= 40, "{:?}", handle.stats());
}
