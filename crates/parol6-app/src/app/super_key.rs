//! The Super (Windows / Meta) key on X11. egui reports Super only on macOS (as Cmd), so on
//! Linux Super+D reached the jog keys as a bare D and jogged +X (hand trial under Xvfb, where no
//! desktop keeps Super+key for itself). In the window, the app asks the X server for the
//! keyboard's modifier state in each frame a key can act in ([`needs_look`];
//! [`SuperKeyProbe::held`]: one round trip on the local socket; the modifier changes the server
//! reported since, so that a chord faster than a frame counts too) and, while Super is down,
//! marks it as egui's `mac_cmd` in the frame's raw input ([`apply_super`]); every shortcut rule in `panels::shortcuts` treats `mac_cmd` as a modifier, so
//! no jog key acts and a key pressed with Super never arms a jog.
//!
//! Super is the X server's `Mod4`, as every stock keymap maps it. Under Wayland (no `DISPLAY`)
//! the compositor keeps Super+key for itself, and on Windows the system takes Win+key.

use eframe::egui;

/// Passes Super's state (`held`) into one frame's input as egui's `mac_cmd`, with egui's
/// modifiers at `current` (last frame's): while held, the frame's modifiers and every key
/// event's carry it; when it is let go, the modifiers drop it again.
pub fn apply_super(raw: &mut egui::RawInput, held: bool, current: egui::Modifiers) {
    if !held && !current.mac_cmd {
        return;
    }
    raw.events.insert(0, egui::Event::ModifiersChanged(egui::Modifiers { mac_cmd: held, ..current }));
    if held {
        for e in &mut raw.events {
            match e {
                egui::Event::Key { modifiers, .. } | egui::Event::ModifiersChanged(modifiers) => {
                    modifiers.mac_cmd = true
                }
                _ => {}
            }
        }
    }
}

/// True when this frame needs Super's state: it carries a key event, a key is held, or Super
/// was held at the last look (to see it let go). Other frames (the arm moving, the pointer
/// moving) skip the X round trip: without a key, Super changes nothing.
pub fn needs_look(raw: &egui::RawInput, any_key_down: bool, current: egui::Modifiers) -> bool {
    current.mac_cmd || any_key_down || raw.events.iter().any(|e| matches!(e, egui::Event::Key { .. }))
}

/// How long after Super was last seen down a key still counts as pressed with it. A chord
/// typed faster than a frame (Super down, D down, D up, Super up, as `xdotool key super+d`
/// sends it) is over before the frame that handles D asks the X server; the key state changes
/// the server reported since then say Super was down.
pub const SUPER_AFTERGLOW: std::time::Duration = std::time::Duration::from_millis(250);

/// A connection to the X server the window is on, to read the Super key's state.
#[cfg(target_os = "linux")]
pub struct SuperKeyProbe {
    conn: x11rb::rust_connection::RustConnection,
    root: u32,
    /// The server reports each change of the keyboard's modifiers (XKB `StateNotify`): false
    /// where it has no XKB (then only the state at each look counts).
    watching_changes: bool,
    /// When Super was last seen down (a look, or a reported change).
    last_down: Option<std::time::Instant>,
}

#[cfg(target_os = "linux")]
impl SuperKeyProbe {
    /// Connects to `$DISPLAY`; `None` without one (Wayland) or when it cannot be reached (said
    /// in the log).
    pub fn connect() -> Option<Self> {
        let display = std::env::var("DISPLAY").ok()?;
        Self::connect_to(&display).map_err(|e| tracing::info!("Super key not watched: {e}")).ok()
    }

    /// Connects to the X server at `display` (e.g. `:0`) and asks it to report modifier changes.
    pub fn connect_to(display: &str) -> Result<Self, String> {
        let (conn, screen) = x11rb::connect(Some(display)).map_err(|e| format!("X server at {display:?}: {e}"))?;
        let root = x11rb::connection::Connection::setup(&conn)
            .roots
            .get(screen)
            .ok_or_else(|| format!("X server at {display:?} has no screen {screen}"))?
            .root;
        let watching_changes = match watch_modifier_changes(&conn) {
            Ok(()) => true,
            Err(e) => {
                let server = display;
                tracing::info!("Super key: only its state at each look (X server at {server:?}: {e})");
                false
            }
        };
        Ok(SuperKeyProbe { conn, root, watching_changes, last_down: None })
    }

    /// Takes the modifier changes the server has reported so far (no round trip): call it every
    /// frame, so that a change is stamped with about the time it happened.
    pub fn observe(&mut self) -> Result<(), String> {
        use x11rb::connection::Connection;
        use x11rb::protocol::Event;
        use x11rb::protocol::xproto::ModMask;
        while let Some(event) = self.conn.poll_for_event().map_err(|e| e.to_string())? {
            if let Event::XkbStateNotify(state) = event
                && state.mods.contains(ModMask::M4)
            {
                self.last_down = Some(std::time::Instant::now());
            }
        }
        Ok(())
    }

    /// True while Super (`Mod4`) is held on the X server's keyboard, or was within
    /// [`SUPER_AFTERGLOW`]. One round trip: every change the server made before it is taken too.
    pub fn held(&mut self) -> Result<bool, String> {
        use x11rb::protocol::xproto::{ConnectionExt, KeyButMask};
        let reply =
            self.conn.query_pointer(self.root).map_err(|e| e.to_string())?.reply().map_err(|e| e.to_string())?;
        if reply.mask.contains(KeyButMask::MOD4) {
            self.last_down = Some(std::time::Instant::now());
        }
        if self.watching_changes {
            self.observe()?;
        }
        Ok(self.last_down.is_some_and(|t| t.elapsed() <= SUPER_AFTERGLOW))
    }
}

/// Asks for XKB `StateNotify` events of the core keyboard's modifier state.
#[cfg(target_os = "linux")]
fn watch_modifier_changes(conn: &x11rb::rust_connection::RustConnection) -> Result<(), String> {
    use x11rb::protocol::xkb::{
        self, ConnectionExt as _, EventType, MapPart, SelectEventsAux, SelectEventsAuxStateNotify, StatePart,
    };
    let version = conn.xkb_use_extension(1, 0).map_err(|e| e.to_string())?.reply().map_err(|e| e.to_string())?;
    if !version.supported {
        return Err("no XKB 1.0".into());
    }
    let details = SelectEventsAux::new().state_notify(SelectEventsAuxStateNotify {
        affect_state: StatePart::MODIFIER_STATE,
        state_details: StatePart::MODIFIER_STATE,
    });
    conn.xkb_select_events(
        xkb::ID::USE_CORE_KBD.into(),
        EventType::from(0u16),
        EventType::from(0u16),
        MapPart::from(0u16),
        MapPart::from(0u16),
        &details,
    )
    .map_err(|e| e.to_string())?
    .check()
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn super_is_looked_at_only_in_frames_a_key_can_act_in() {
        let none = egui::RawInput::default();
        assert!(!needs_look(&none, false, egui::Modifiers::NONE), "an idle frame costs no round trip");
        let pointer =
            egui::RawInput { events: vec![egui::Event::PointerMoved(egui::pos2(1.0, 2.0))], ..Default::default() };
        assert!(!needs_look(&pointer, false, egui::Modifiers::NONE));
        let typed = egui::RawInput { events: vec![key(egui::Key::D)], ..Default::default() };
        assert!(needs_look(&typed, false, egui::Modifiers::NONE), "a key event");
        assert!(needs_look(&none, true, egui::Modifiers::NONE), "a key held (a jog)");
        let held_super = egui::Modifiers { mac_cmd: true, ..egui::Modifiers::NONE };
        assert!(needs_look(&none, false, held_super), "Super held at the last look: watch it let go");
    }

    fn key(key: egui::Key) -> egui::Event {
        egui::Event::Key { key, physical_key: None, pressed: true, repeat: false, modifiers: egui::Modifiers::NONE }
    }

    /// The modifiers egui sees after one frame of `events` from `before`.
    fn after(ctx: &egui::Context, events: Vec<egui::Event>) -> egui::Modifiers {
        let raw = egui::RawInput { events, ..Default::default() };
        let mut seen = egui::Modifiers::NONE;
        let _ = ctx.run_ui(raw, |ui| seen = ui.input(|i| i.modifiers));
        seen
    }

    #[test]
    fn super_is_mac_cmd_on_every_key_event_while_held_and_dropped_when_let_go() {
        let ctx = egui::Context::default();
        let mut raw =
            egui::RawInput { events: vec![key(egui::Key::D), egui::Event::Text("d".into())], ..Default::default() };
        apply_super(&mut raw, true, egui::Modifiers::NONE);
        assert!(matches!(raw.events[1], egui::Event::Key { modifiers, .. } if modifiers.mac_cmd));
        assert!(after(&ctx, raw.events).mac_cmd, "held: egui's modifiers say so");
        // Ctrl pressed while Super is held: winit's event says ctrl only; Super stays
        let mut raw =
            egui::RawInput { events: vec![egui::Event::ModifiersChanged(egui::Modifiers::CTRL)], ..Default::default() };
        apply_super(&mut raw, true, egui::Modifiers { mac_cmd: true, ..Default::default() });
        let m = after(&ctx, raw.events);
        assert!(m.mac_cmd && m.ctrl);
        // let go
        let mut raw = egui::RawInput::default();
        apply_super(&mut raw, false, m);
        let m = after(&ctx, raw.events);
        assert!(!m.mac_cmd && m.ctrl, "{m:?}");
        // never held: nothing added
        let mut raw = egui::RawInput::default();
        apply_super(&mut raw, false, egui::Modifiers::NONE);
        assert!(raw.events.is_empty());
    }
}
