//! Keys typed into a text field reach it before a click that takes its keyboard away.
//!
//! In a slow frame (a busy machine, ~10 FPS) the keys typed into a field and the click on *Go*,
//! *Open* or another field arrive together, and egui gives the focus away at the click before the
//! field reads the frame's keys: the last characters were lost (trial 29 D1: a typed 55 moved J1
//! to 5°; trial 31 m1: `rec1.mcap` opened as `rec1.mca`). While a text field has the keyboard, a
//! frame whose events hold typing and then a pointer press is split: the typing is handled this
//! frame, the press and what follows it the next.

use eframe::egui;

/// The events held back for the next frame (the press that followed typing, and after).
#[derive(Debug, Default)]
pub(super) struct ClickAfterTyping {
    held: Vec<egui::Event>,
}

impl ClickAfterTyping {
    /// Puts the events held from the last frame before `events`, then, when `typing_into_field`
    /// (a text field has the keyboard) and the events type something before the first pointer
    /// press, holds that press and every event after it for the next frame. True while events
    /// are held (the window must draw the next frame soon).
    pub(super) fn apply(&mut self, events: &mut Vec<egui::Event>, typing_into_field: bool) -> bool {
        if !self.held.is_empty() {
            let newer = std::mem::take(events);
            events.append(&mut self.held);
            events.extend(newer);
        }
        let press = events.iter().position(is_press);
        if let Some(press) = press
            && typing_into_field
            && events[..press].iter().any(is_typing)
        {
            self.held = events.split_off(press);
        }
        !self.held.is_empty()
    }
}

fn is_press(e: &egui::Event) -> bool {
    matches!(e, egui::Event::PointerButton { pressed: true, .. })
}

fn is_typing(e: &egui::Event) -> bool {
    matches!(e, egui::Event::Text(_) | egui::Event::Paste(_) | egui::Event::Key { pressed: true, .. })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(t: &str) -> egui::Event {
        egui::Event::Text(t.to_string())
    }

    fn button(pressed: bool) -> egui::Event {
        let (button, modifiers) = (egui::PointerButton::Primary, egui::Modifiers::NONE);
        egui::Event::PointerButton { pos: egui::pos2(10.0, 20.0), button, pressed, modifiers }
    }

    #[test]
    fn typing_then_a_click_in_one_frame_takes_two_frames() {
        let mut c = ClickAfterTyping::default();
        let moved = egui::Event::PointerMoved(egui::pos2(10.0, 20.0));
        let mut events = vec![text("5"), text("5"), moved.clone(), button(true), button(false)];
        assert!(c.apply(&mut events, true), "held");
        assert_eq!(events, [text("5"), text("5"), moved]);
        let mut next = vec![text("7")];
        assert!(!c.apply(&mut next, false));
        assert_eq!(next, [button(true), button(false), text("7")], "the press comes first, then the newer events");
    }

    #[test]
    fn a_click_without_typing_before_it_or_no_field_typed_into_is_not_held() {
        let mut c = ClickAfterTyping::default();
        let mut events = vec![button(true), button(false), text("5")];
        assert!(!c.apply(&mut events, true));
        assert_eq!(events.len(), 3);
        let mut events = vec![text("5"), button(true)];
        assert!(!c.apply(&mut events, false));
        assert_eq!(events.len(), 2);
    }

    #[test]
    fn held_events_are_not_held_again() {
        let mut c = ClickAfterTyping::default();
        let mut events = vec![text("5"), button(true), button(false)];
        assert!(c.apply(&mut events, true));
        // the next frame starts with the held press: typing after it stays after it
        let mut next = vec![text("6")];
        assert!(!c.apply(&mut next, true));
        assert_eq!(next, [button(true), button(false), text("6")]);
    }
}
