use super::*;
use crate::app::panel_groups::PanelGroup;
use egui::{Color32, Pos2, Shape};

const SCREEN: Rect = Rect { min: Pos2::ZERO, max: Pos2 { x: 1280.0, y: 800.0 } };

fn clipped(clip: Rect, color: Color32) -> ClippedShape {
    ClippedShape {
        clip_rect: clip,
        shape: Shape::rect_filled(clip.shrink(1.0), 0.0, color),
        transform_after_tessellation: egui::emath::TSTransform::IDENTITY,
    }
}

fn colors(out: &[ClippedShape]) -> Vec<Color32> {
    out.iter()
        .map(|s| match &s.shape {
            Shape::Rect(r) => r.fill,
            _ => Color32::TRANSPARENT,
        })
        .collect()
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
    let out = splice(&kept, &[central], fresh.clone());
    assert_eq!(colors(&out), [Color32::RED, Color32::YELLOW, Color32::BLACK, Color32::GREEN, Color32::WHITE]);
    // nothing of the view kept: the fresh shapes go last
    let out = splice(&kept[..1], &[central], fresh);
    assert_eq!(out.len(), 3);
}

#[test]
fn a_wave_step_swaps_in_its_groups_and_drops_what_the_stand_ins_and_separators_paint() {
    let central = Rect::from_min_max(Pos2::new(300.0, 20.0), Pos2::new(900.0, 500.0));
    let left = Rect::from_min_max(Pos2::new(0.0, 20.0), Pos2::new(300.0, 780.0));
    let right = Rect::from_min_max(Pos2::new(900.0, 20.0), Pos2::new(1280.0, 780.0));
    let kept = vec![
        clipped(left, Color32::RED),
        clipped(left.shrink(20.0), Color32::RED),
        clipped(right, Color32::GREEN),
        clipped(SCREEN, Color32::WHITE), // a separator line, painted by the parent
        clipped(central, Color32::BLUE),
    ];
    let fresh = vec![
        clipped(left, Color32::BROWN),
        clipped(SCREEN, Color32::GRAY),      // the laid-out panel's separator again
        clipped(right, Color32::DARK_GREEN), // a stand-in would paint nothing; dropped if it did
        clipped(central, Color32::YELLOW),
        clipped(left.shrink(30.0), Color32::GOLD),
    ];
    let out = splice(&kept, &[central, left], fresh);
    assert_eq!(
        colors(&out),
        [Color32::BROWN, Color32::GOLD, Color32::GREEN, Color32::WHITE, Color32::YELLOW],
        "the left column's new shapes where its old ones were, in their own order; the rest kept"
    );
}

#[test]
fn the_wave_steps_take_turns_and_a_refresh_makes_every_group_stale() {
    let mut k = Kept::default();
    assert!(k.next_wave_step().is_empty(), "nothing stale, nothing to lay out");
    k.stale = GroupSet::ALL;
    let steps: Vec<GroupSet> = (0..=WAVE.len()).map(|_| k.next_wave_step()).collect();
    assert_eq!(&steps[..WAVE.len()], &WAVE[..]);
    assert!(steps[WAVE.len()].is_empty(), "each step once per refresh");
    // a refresh in the middle of a wave: the step after goes on, the ones before come again
    k.stale = GroupSet::ALL;
    assert_eq!(k.next_wave_step(), WAVE[0]);
    k.stale = GroupSet::ALL;
    assert_eq!(k.next_wave_step(), WAVE[1]);
    assert_eq!(k.next_wave_step(), WAVE[0]);
    assert!(k.next_wave_step().is_empty());
}

#[test]
fn a_discarded_pass_leaves_the_wave_to_the_pass_egui_runs_next() {
    let ctx = egui::Context::default();
    let handle = FrameReuse { kept: Arc::new(Mutex::new(Kept::default())) };
    let mut plugin = ReusePlugin { handle: handle.clone() };
    let kept_shapes = vec![clipped(SCREEN, Color32::RED)];
    handle.with(|k| {
        k.shapes = kept_shapes.clone();
        k.next_step = 0;
        k.stale = GroupSet::ALL.without(WAVE[0]);
        k.this_frame = Some(FrameKind::Partial { regions: vec![SCREEN], lay_out: WAVE[0] });
    });
    let mut output = egui::FullOutput::default();
    output.platform_output.request_discard_reasons.push(egui::RepaintCause::new());
    output.platform_output.num_completed_passes = 1;
    egui::Plugin::output_hook(&mut plugin, &ctx, &mut output);
    handle
        .with(|k| {
            assert_eq!(k.stale, GroupSet::ALL, "the step is stale again");
            assert_eq!(k.next_step, 0, "and comes next");
            assert_eq!(k.shapes, kept_shapes, "the kept frame is not the discarded pass's");
            assert_eq!(k.stats, ReuseStats::default());
        })
        .expect("the kept state");
    // the pass egui shows lays out that step again
    handle.with(|k| assert_eq!(k.next_wave_step(), WAVE[0]));
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

impl Run {
    /// Frames until one reuses every panel right after a wave laid them all out again since
    /// the last read-out refresh; that frame's output, with waves seen before it.
    fn after_a_wave(&mut self) -> egui::FullOutput {
        let deadline = Instant::now() + Duration::from_secs(20);
        let waves_at_start = self.handle.stats().wave_frames;
        loop {
            let before = self.handle.stats();
            let out = self.frame(Vec::new());
            let after = self.handle.stats();
            // once the panels are reused, a read-out refresh makes a wave, not a full frame
            let waving = before.wave_frames > waves_at_start;
            assert!(!waving || after.full_frames == before.full_frames, "a full frame during the waves: {after:?}");
            let stale = self.handle.with(|k| k.stale).expect("the kept frame");
            if after.reused_frames > before.reused_frames
                && stale.is_empty()
                && after.wave_frames >= waves_at_start + 2 * WAVE.len() as u64
            {
                return out;
            }
            assert!(Instant::now() < deadline, "no wave while the arm moves: {after:?}");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn readout_at(&self) -> Option<Instant> {
        self.app.readout.as_ref().map(|r| r.0)
    }
}

#[test]
fn after_a_wave_the_frame_shows_and_hits_what_a_full_frame_does() {
    let mut run = Run::new();
    run.until_reused();
    let deadline = Instant::now() + Duration::from_secs(30);
    // a frame after a wave, then a full one at once with the same read-out (the frames before
    // it were not full: no input)
    let (reused, reused_widgets, full) = loop {
        let reused = run.after_a_wave();
        let reused_widgets = widget_set(&run.ctx);
        let readout = run.readout_at();
        let fulls = run.handle.stats().full_frames;
        run.app.input_at = Instant::now();
        let full = run.frame(Vec::new());
        assert_eq!(run.handle.stats().full_frames, fulls + 1, "input makes the frame full");
        if run.readout_at() == readout {
            break (reused, reused_widgets, full);
        }
        assert!(Instant::now() < deadline, "the read-out refreshed between every pair");
    };
    let full_widgets = widget_set(&run.ctx);
    let central = run.handle.with(|k| k.central).flatten().expect("the view's rectangle");
    assert!(run.app.robot_state().moving, "the arm moves all along");
    let missing: Vec<_> = full_widgets.iter().filter(|w| !reused_widgets.contains(w)).collect();
    assert!(missing.is_empty(), "the frame after the wave registers the full frame's widgets; missing {missing:?}");
    // besides them only the hosts that registered them: no area, no sense of clicks
    for w in reused_widgets.iter().filter(|w| !full_widgets.contains(w)) {
        assert!(!w.3 && w.1[0] == w.1[2] && w.1[1] == w.1[3], "unexpected widget {w:?}");
    }
    // the same panels, drawn from the shapes the wave kept; the view's own drawn anew. Some
    // panels show live values (the nearest limit), laid out a few frames apart here: so each
    // shape's kind, clip rectangle and place, not its text or its length; a shape clipped to
    // nothing (below the left panel's fold) draws nothing, wherever it sits in the list
    let outside = |o: &egui::FullOutput| -> Vec<String> {
        o.shapes
            .iter()
            .filter(|s| !central.expand(0.5).contains_rect(s.clip_rect))
            .filter(|s| s.clip_rect.is_positive())
            .map(|s| {
                let place = match &s.shape {
                    Shape::Text(t) => format!("text at {:?}", t.pos),
                    Shape::Vec(v) => format!("{} shapes", v.len()),
                    other => format!("{:?}", std::mem::discriminant(other)),
                };
                format!("{:?} {place}", s.clip_rect)
            })
            .collect()
    };
    let (a, b) = (outside(&reused), outside(&full));
    let first_difference = a.iter().zip(&b).position(|(x, y)| x != y);
    assert!(
        a.len() == b.len() && first_difference.is_none(),
        "{} shapes against {}; first difference: {:?}",
        a.len(),
        b.len(),
        first_difference.map(|i| (&a[i], &b[i]))
    );
    assert!(reused.shapes.len() > 100, "the panels are painted: {} shapes", reused.shapes.len());
}

#[test]
fn a_panel_that_goes_without_input_makes_the_next_frame_full() {
    let mut run = Run::new();
    run.until_reused();
    let left = run.handle.with(|k| k.groups.get(PanelGroup::Left)).flatten().expect("the left column");
    let fulls = run.handle.stats().full_frames;
    // as a script or a loaded setting would: no input, so the frames stay partial until the
    // left column's step finds it gone
    run.app.settings.show_left = false;
    let deadline = Instant::now() + Duration::from_secs(10);
    while run.handle.stats().full_frames == fulls {
        run.frame(Vec::new());
        assert!(Instant::now() < deadline, "no full frame after the column went: {:?}", run.handle.stats());
        std::thread::sleep(Duration::from_millis(5));
    }
    let central = run.handle.with(|k| k.central).flatten().expect("the view's rectangle");
    assert!(central.left() < left.right() - 100.0, "the 3D view took the column's place: {central:?}");
    assert_eq!(run.handle.with(|k| k.groups.get(PanelGroup::Left)).flatten(), None);
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
