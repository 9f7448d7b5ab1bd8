//! Every keyboard shortcut of the window, in one table ([`SHORTCUTS`]): the key, the
//! modifiers, what it does, where it applies and its help text. The panels ask this module
//! whether an action's key was pressed ([`pressed`]) or is held ([`held`]); the F1 help lists
//! the same table ([`help_rows`]).
//!
//! Safety rules, kept here for every key:
//! - a key that moves the arm acts only while no text field, menu or popup has the keyboard;
//!   a Cartesian jog key (A D S W Q E, letters of typed text) only with the pointer over the
//!   3D view, too;
//! - a shortcut without Ctrl / Alt / Cmd in the table does nothing while one of them is held
//!   (Ctrl+S saves, it never jogs along S);
//! - a held key (jog) counts only when it went down while nothing of the above was true, and
//!   stops counting for good (until pressed again) as soon as a modifier is held, a text field,
//!   menu or popup takes the keyboard, or the window loses focus. A key pressed with Ctrl and
//!   held on after Ctrl is let go therefore never jogs;
//! - a held key keeps the chord it went down with: it stops counting for good when Shift comes
//!   up or goes down under it. Shift+D (turn about X) with Shift let go a moment before D never
//!   becomes D (move along X): that moved the TCP 0.11 mm in an orientation jog.
//!
//! Esc (STOP) is the exception: it acts whatever has the keyboard and whatever is held. Where
//! nothing moves, the pointer is off the 3D view and no docked panel's control has the keyboard,
//! it closes the topmost dialog, menu or window instead (`app::escape`).
//! egui reports the Super key only on macOS (as Cmd); on X11 the window reads it from the X
//! server and passes it on as `mac_cmd` (`app::super_key`), so Super counts as a modifier here
//! too (Super+D jogged +X before).

use std::collections::HashMap;

use eframe::egui::{self, Key, Modifiers};
use parol6_core::motion::CartesianAxis;

/// What a shortcut does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    /// STOP: hold the arm where it is, end a running program.
    Stop,
    /// HOME: profiled move to the standby pose.
    Home,
    /// Close the window.
    Quit,
    /// Show or hide the help window.
    ToggleHelp,
    /// Program editor: undo the last edit.
    Undo,
    /// Program editor: redo.
    Redo,
    /// Program editor: duplicate the selected step.
    DuplicateStep,
    /// Program editor: delete the selected step.
    DeleteStep,
    /// Program editor: move the selected step up.
    MoveStepUp,
    /// Program editor: move the selected step down.
    MoveStepDown,
    /// Program editor: save the program.
    SaveProgram,
    /// Run or resume the program.
    RunProgram,
    /// Pause the running program.
    PauseProgram,
    /// Run one step of the program.
    SingleStep,
    /// Robot connection: select joint N (0-based) for the key jog.
    SelectJoint(usize),
    /// Robot connection: jog the selected joint in this direction while held.
    JogJoint(i8),
    /// Cartesian jog along (translation) or about (rotation) the axis while held.
    JogCartesian(CartesianAxis, i8),
    /// 3D view: orbit left / right / up / down while held (yaw, pitch sign).
    Orbit(i8, i8),
    /// 3D view: zoom in (+1) or out (−1) while held.
    Zoom(i8),
    /// 3D view: reset the camera.
    ResetView,
}

impl Action {
    /// True when a key held down acts once, not on each of its repeats: the keys that move the
    /// arm, and the program edits that add or remove a step (trial16: Ctrl+D held 0.8 s made
    /// six copies of the step). Undo / Redo and moving a step up or down repeat, as in editors.
    pub fn once_per_press(self) -> bool {
        self.moves_arm() || matches!(self, Action::DuplicateStep | Action::DeleteStep | Action::SaveProgram)
    }

    /// True when the action sets the arm in motion (STOP does not: it holds it).
    pub fn moves_arm(self) -> bool {
        matches!(
            self,
            Action::Home | Action::RunProgram | Action::SingleStep | Action::JogJoint(_) | Action::JogCartesian(..)
        )
    }
}

/// Which modifiers a shortcut takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mods {
    /// Exactly these (Shift and Alt must match too; Ctrl is Cmd on macOS).
    Exactly(Modifiers),
    /// Any (STOP).
    Any,
}

/// Whether the key acts once per press or for as long as it is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trigger {
    /// Once per press.
    Press,
    /// While held (a jog, a camera orbit).
    Hold,
}

/// Where a shortcut applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Always, whatever has the keyboard.
    Always,
    /// While no text field, menu or popup has the keyboard.
    NoField,
    /// The program panel, while no text field, menu or popup has the keyboard.
    Program,
    /// The robot connection panel with a robot connected, no text field, menu or popup.
    Robot,
    /// The Cartesian jog panel in hold mode, the pointer over the 3D view, no text field, menu
    /// or popup: the letters A D S W Q E come in typed text ("0.5rad"), so they jog only where
    /// nothing can be typed.
    CartesianJog,
    /// The pointer over the 3D view, no text field, menu or popup: the camera's keys (the 3D
    /// view reads them only while the pointer is over it).
    View,
    /// A letter that moves the arm, H (HOME): it comes in typed text ("/home/…") as the jog
    /// letters do, so it acts only with the pointer over the 3D view (the app tells the table
    /// where the pointer is), no text field, menu or popup.
    ViewArm,
}

impl Scope {
    /// Where, in the help's words.
    pub fn describe(self) -> &'static str {
        match self {
            Scope::Always => "anywhere",
            Scope::NoField => "no field typed in",
            Scope::Program => "program panel",
            Scope::Robot => "robot connected",
            Scope::CartesianJog => "pointer over the 3D view, Cartesian jog in hold mode",
            Scope::View | Scope::ViewArm => "pointer over the 3D view",
        }
    }
}

/// One shortcut.
#[derive(Debug, Clone, Copy)]
pub struct Shortcut {
    /// The key.
    pub key: Key,
    /// The modifiers it takes.
    pub mods: Mods,
    /// Press or hold.
    pub trigger: Trigger,
    /// What it does.
    pub action: Action,
    /// Where it applies.
    pub scope: Scope,
    /// The help's text; consecutive rows with the same text are listed as one.
    pub help: &'static str,
}

const NONE: Mods = Mods::Exactly(Modifiers::NONE);
const SHIFT: Mods = Mods::Exactly(Modifiers::SHIFT);
const ALT: Mods = Mods::Exactly(Modifiers::ALT);
const CMD: Mods = Mods::Exactly(Modifiers::COMMAND);
const CMD_SHIFT: Mods =
    Mods::Exactly(Modifiers { alt: false, ctrl: false, shift: true, mac_cmd: false, command: true });

const fn press(key: Key, mods: Mods, action: Action, scope: Scope, help: &'static str) -> Shortcut {
    Shortcut { key, mods, trigger: Trigger::Press, action, scope, help }
}

const fn hold(key: Key, mods: Mods, action: Action, scope: Scope, help: &'static str) -> Shortcut {
    Shortcut { key, mods, trigger: Trigger::Hold, action, scope, help }
}

const X: CartesianAxis = CartesianAxis::X;
const Y: CartesianAxis = CartesianAxis::Y;
const Z: CartesianAxis = CartesianAxis::Z;
const RX: CartesianAxis = CartesianAxis::Rx;
const RY: CartesianAxis = CartesianAxis::Ry;
const RZ: CartesianAxis = CartesianAxis::Rz;
const JOG_XYZ: &str = "Cartesian jog −X / +X, −Y / +Y, −Z / +Z while held";
const JOG_RXYZ: &str = "Cartesian jog −Rx / +Rx, −Ry / +Ry, −Rz / +Rz while held";
const SELECT: &str = "select the joint that Page Up / Page Down jog";
const ORBIT: &str = "orbit the camera";
const ESC: &str = "STOP (also cancels a demo). With nothing moving, the pointer off the 3D view and no panel \
                   control typed into: closes the topmost question, menu, file dialog, point table or help instead";

/// Every keyboard shortcut of the window.
pub const SHORTCUTS: &[Shortcut] = &[
    press(Key::Escape, Mods::Any, Action::Stop, Scope::Always, ESC),
    press(Key::H, NONE, Action::Home, Scope::ViewArm, "HOME (profiled move to standby)"),
    press(Key::H, CMD, Action::Home, Scope::ViewArm, "HOME (as H)"),
    press(Key::F1, NONE, Action::ToggleHelp, Scope::Always, "this help"),
    press(Key::Q, CMD, Action::Quit, Scope::Always, "quit (asks first when a program has unsaved edits)"),
    press(Key::F5, NONE, Action::RunProgram, Scope::Program, "run the program, or resume it"),
    press(Key::F6, Mods::Any, Action::PauseProgram, Scope::Program, "pause the program (with any modifier held too)"),
    press(Key::F10, NONE, Action::SingleStep, Scope::Program, "run one step of the program"),
    press(Key::S, CMD, Action::SaveProgram, Scope::Program, "save the program"),
    press(Key::Z, CMD, Action::Undo, Scope::Program, "undo an edit of the program (also Edit menu)"),
    press(Key::Z, CMD_SHIFT, Action::Redo, Scope::Program, "redo (also Edit menu)"),
    press(Key::Y, CMD, Action::Redo, Scope::Program, "redo (also Edit menu)"),
    press(Key::D, CMD, Action::DuplicateStep, Scope::Program, "duplicate the selected step (also Edit menu)"),
    press(Key::Delete, NONE, Action::DeleteStep, Scope::Program, "delete the selected step (also Edit menu)"),
    press(Key::ArrowUp, ALT, Action::MoveStepUp, Scope::Program, "move the selected step up / down (also Edit menu)"),
    press(
        Key::ArrowDown,
        ALT,
        Action::MoveStepDown,
        Scope::Program,
        "move the selected step up / down (also Edit menu)",
    ),
    hold(Key::A, NONE, Action::JogCartesian(X, -1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::D, NONE, Action::JogCartesian(X, 1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::S, NONE, Action::JogCartesian(Y, -1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::W, NONE, Action::JogCartesian(Y, 1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::Q, NONE, Action::JogCartesian(Z, -1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::E, NONE, Action::JogCartesian(Z, 1), Scope::CartesianJog, JOG_XYZ),
    hold(Key::A, SHIFT, Action::JogCartesian(RX, -1), Scope::CartesianJog, JOG_RXYZ),
    hold(Key::D, SHIFT, Action::JogCartesian(RX, 1), Scope::CartesianJog, JOG_RXYZ),
    hold(Key::S, SHIFT, Action::JogCartesian(RY, -1), Scope::CartesianJog, JOG_RXYZ),
    hold(Key::W, SHIFT, Action::JogCartesian(RY, 1), Scope::CartesianJog, JOG_RXYZ),
    hold(Key::Q, SHIFT, Action::JogCartesian(RZ, -1), Scope::CartesianJog, JOG_RXYZ),
    hold(Key::E, SHIFT, Action::JogCartesian(RZ, 1), Scope::CartesianJog, JOG_RXYZ),
    press(Key::Num1, NONE, Action::SelectJoint(0), Scope::Robot, SELECT),
    press(Key::Num2, NONE, Action::SelectJoint(1), Scope::Robot, SELECT),
    press(Key::Num3, NONE, Action::SelectJoint(2), Scope::Robot, SELECT),
    press(Key::Num4, NONE, Action::SelectJoint(3), Scope::Robot, SELECT),
    press(Key::Num5, NONE, Action::SelectJoint(4), Scope::Robot, SELECT),
    press(Key::Num6, NONE, Action::SelectJoint(5), Scope::Robot, SELECT),
    hold(Key::PageUp, NONE, Action::JogJoint(1), Scope::Robot, "jog the selected joint + / − while held"),
    hold(Key::PageDown, NONE, Action::JogJoint(-1), Scope::Robot, "jog the selected joint + / − while held"),
    hold(Key::ArrowLeft, NONE, Action::Orbit(-1, 0), Scope::View, ORBIT),
    hold(Key::ArrowRight, NONE, Action::Orbit(1, 0), Scope::View, ORBIT),
    hold(Key::ArrowUp, NONE, Action::Orbit(0, 1), Scope::View, ORBIT),
    hold(Key::ArrowDown, NONE, Action::Orbit(0, -1), Scope::View, ORBIT),
    hold(Key::Plus, NONE, Action::Zoom(1), Scope::View, "zoom in"),
    hold(Key::Equals, NONE, Action::Zoom(1), Scope::View, "zoom in"),
    hold(Key::Minus, NONE, Action::Zoom(-1), Scope::View, "zoom out"),
    press(Key::R, NONE, Action::ResetView, Scope::View, "reset the camera"),
    press(Key::Home, NONE, Action::ResetView, Scope::View, "reset the camera"),
];

/// True while a text field, a menu or a popup has the keyboard, or had it when this frame began.
pub fn keyboard_taken(ctx: &egui::Context) -> bool {
    ctx.memory(|m| m.focused().is_some()) || menu_open(ctx) || at_pass_start(ctx).taken
}

/// True while a text field has the keyboard (the focused widget keeps a text edit's state), or
/// had it when this frame began: typed text, where the program editor's Ctrl / Alt keys would
/// act on the field's text.
pub fn text_field_has_keyboard(ctx: &egui::Context) -> bool {
    text_field_focused(ctx) || at_pass_start(ctx).typing
}

/// True while a text field has the keyboard (the focused widget keeps a text edit's state).
pub fn text_field_focused(ctx: &egui::Context) -> bool {
    ctx.memory(|m| m.focused()).is_some_and(|id| egui::text_edit::TextEditState::load(ctx, id).is_some())
}

/// Who had the keyboard when this frame began ([`note_pass_start`]).
#[derive(Debug, Clone, Copy, Default)]
struct PassStart {
    /// The pass this was noted in, plus one (0: never).
    pass: u64,
    taken: bool,
    typing: bool,
}

fn pass_start_id() -> egui::Id {
    egui::Id::unique("parol6_shortcuts_pass_start")
}

/// Notes who has the keyboard as this frame begins; the app calls it before any panel draws.
/// In a slow frame (a busy machine, ~10 FPS) the keys typed into a field and the click that
/// takes the field's keyboard away come together, and egui gives the focus away before the
/// frame's keys are read: those keys were typed into the field, and act as no shortcut (trial
/// 29: a `5` typed into a joint field picked J5 for the keyboard jog).
pub fn note_pass_start(ctx: &egui::Context) {
    let noted = PassStart {
        pass: ctx.cumulative_pass_nr() + 1,
        taken: ctx.memory(|m| m.focused().is_some()) || menu_open(ctx),
        typing: text_field_focused(ctx) || menu_open(ctx),
    };
    ctx.data_mut(|d| d.insert_temp(pass_start_id(), noted));
}

fn at_pass_start(ctx: &egui::Context) -> PassStart {
    let now = ctx.cumulative_pass_nr() + 1;
    ctx.data(|d| d.get_temp::<PassStart>(pass_start_id())).filter(|p| p.pass == now).unwrap_or_default()
}

/// True when `s` is a program-editing key with Ctrl / Alt (Ctrl+S, Ctrl+Z, Alt+↑…): it moves
/// nothing, so a focused button (after Tab) does not hold it back; only a text field or a menu
/// does (trial14 m2: Ctrl+S did nothing while Tab's ring sat on a button).
fn acts_beside_a_focused_button(s: &Shortcut) -> bool {
    s.scope == Scope::Program && !s.action.moves_arm() && matches!(s.mods, Mods::Exactly(m) if command_modifier(m))
}

/// True when a key of `action` was pressed this frame, where the table would let it act but for
/// a text field having the keyboard (Ctrl+S while a step's number is being typed); the press is
/// left for the field.
pub fn pressed_in_text_field(ctx: &egui::Context, action: Action) -> bool {
    if !text_field_has_keyboard(ctx) || menu_open(ctx) {
        return false;
    }
    SHORTCUTS.iter().filter(|s| s.action == action && acts_beside_a_focused_button(s)).any(|s| {
        ctx.input(|i| {
            i.events.iter().any(|e| {
                matches!(e, egui::Event::Key { key, pressed: true, repeat: false, modifiers, .. }
                    if *key == s.key && mods_match(s.mods, *modifiers))
            })
        })
    })
}

/// True while a menu or popup is open.
fn menu_open(ctx: &egui::Context) -> bool {
    egui::Popup::is_any_open(ctx) || ctx.any_popup_open()
}

/// True when Ctrl, Alt or Cmd is held in `m` (Shift is part of some shortcuts).
fn command_modifier(m: Modifiers) -> bool {
    m.ctrl || m.alt || m.command || m.mac_cmd
}

fn scope_open(ctx: &egui::Context, scope: Scope, taken: bool) -> bool {
    match scope {
        Scope::Always => true,
        Scope::CartesianJog | Scope::ViewArm => !taken && pointer_over_view(ctx),
        _ => !taken,
    }
}

fn view_hover_id() -> egui::Id {
    egui::Id::unique("parol6_shortcuts_pointer_over_view")
}

/// Tells the table whether the pointer is over the 3D view (no window covering it there) this
/// frame; the app calls it before [`update_held`]. Until it is told, the Cartesian jog keys do
/// nothing.
pub fn set_pointer_over_view(ctx: &egui::Context, over: bool) {
    ctx.data_mut(|d| d.insert_temp(view_hover_id(), over));
}

fn pointer_over_view(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(view_hover_id())).unwrap_or(false)
}

/// True for a key held to jog the arm in Cartesian space.
fn is_cartesian_jog_key(key: Key) -> bool {
    SHORTCUTS.iter().any(|s| s.trigger == Trigger::Hold && s.scope == Scope::CartesianJog && s.key == key)
}

fn mods_match(mods: Mods, held: Modifiers) -> bool {
    match mods {
        Mods::Any => true,
        Mods::Exactly(want) => {
            held.matches_exact(want) && (want.command || !(held.ctrl || held.command || held.mac_cmd))
        }
    }
}

/// True (once) when a key of `action` was pressed this frame where the table lets it act; the
/// key press is consumed. Key repeats count only for actions not [`Action::once_per_press`].
pub fn pressed(ctx: &egui::Context, action: Action) -> bool {
    let taken = keyboard_taken(ctx);
    let typing = text_field_has_keyboard(ctx) || menu_open(ctx);
    let mut hit = false;
    for s in SHORTCUTS.iter().filter(|s| s.action == action && s.trigger == Trigger::Press) {
        let taken = if acts_beside_a_focused_button(s) { typing } else { taken };
        if !scope_open(ctx, s.scope, taken) {
            continue;
        }
        ctx.input_mut(|i| {
            let at = i.events.iter().position(|e| {
                matches!(e, egui::Event::Key { key, pressed: true, repeat, modifiers, .. }
                    if *key == s.key && mods_match(s.mods, *modifiers) && !(*repeat && action.once_per_press()))
            });
            if let Some(at) = at {
                i.events.remove(at);
                hit = true;
            }
        });
    }
    hit
}

/// The jog keys that went down cleanly and are still held (see the module's rules).
#[derive(Debug, Clone, Default)]
struct HeldKeys {
    /// The pass these were last brought up to date in, plus one (0: never).
    pass: u64,
    /// Keys that count as held, each with whether Shift was down when it went down: a held key
    /// acts as the chord it went down with, and stops when Shift changes (Shift+D let go of
    /// Shift first never becomes D's linear jog).
    armed: HashMap<Key, bool>,
}

fn held_keys_id() -> egui::Id {
    egui::Id::unique("parol6_shortcuts_held_keys")
}

fn is_hold_key(key: Key) -> bool {
    SHORTCUTS.iter().any(|s| s.trigger == Trigger::Hold && s.key == key)
}

/// Brings the held keys up to date with this frame's input (once per frame). The app calls it
/// before any panel consumes input; [`held`] calls it too.
pub fn update_held(ctx: &egui::Context) {
    let next = ctx.cumulative_pass_nr() + 1;
    if ctx.data(|d| d.get_temp::<HeldKeys>(held_keys_id()).is_some_and(|h| h.pass == next)) {
        return;
    }
    let taken = keyboard_taken(ctx);
    let over_view = pointer_over_view(ctx);
    let (events, modifiers, down) = ctx.input(|i| (i.events.clone(), i.modifiers, i.keys_down.clone()));
    ctx.data_mut(|d| {
        let h = d.get_temp_mut_or_default::<HeldKeys>(held_keys_id());
        h.pass = next;
        for e in &events {
            match e {
                egui::Event::Key { key, pressed, repeat, modifiers, .. } if is_hold_key(*key) => {
                    if !*pressed || command_modifier(*modifiers) || taken {
                        h.armed.remove(key);
                    } else if !*repeat {
                        h.armed.insert(*key, modifiers.shift);
                    }
                }
                egui::Event::WindowFocused(false) => h.armed.clear(),
                _ => {}
            }
        }
        if taken || command_modifier(modifiers) {
            h.armed.clear();
        }
        // a Cartesian jog key counts only while the pointer stays over the 3D view: pressed
        // elsewhere, or the pointer gone off the view, it stops for good (until pressed again)
        if !over_view {
            h.armed.retain(|k, _| !is_cartesian_jog_key(*k));
        }
        h.armed.retain(|k, shift| down.contains(k) && *shift == modifiers.shift);
    });
}

/// Forgets every held key that moves the arm (the jog keys): after STOP, or while manual
/// motion is refused, a key still held does not jog again until it is let go and pressed anew
/// (trial15 D1: Esc with Q held, the arm went on down). The camera's keys stay held: orbiting
/// the view while a program runs or a replay plays goes on.
pub fn disarm_held(ctx: &egui::Context) {
    update_held(ctx);
    ctx.data_mut(|d| d.get_temp_mut_or_default::<HeldKeys>(held_keys_id()).armed.retain(|k, _| !moves_arm_held(*k)));
}

/// [`disarm_held`] for the keys of the actions `which` picks: the joint jog's Page Up / Down while
/// its buttons are not drawn (no robot, the section folded), so that a key held then does not jog
/// the moment they are (the simulation's Cartesian keys stay held).
pub fn disarm_held_of(ctx: &egui::Context, which: impl Fn(Action) -> bool) {
    update_held(ctx);
    let keys: Vec<Key> =
        SHORTCUTS.iter().filter(|s| s.trigger == Trigger::Hold && which(s.action)).map(|s| s.key).collect();
    ctx.data_mut(|d| d.get_temp_mut_or_default::<HeldKeys>(held_keys_id()).armed.retain(|k, _| !keys.contains(k)));
}

/// True for a key that moves the arm while held (a jog key).
fn moves_arm_held(key: Key) -> bool {
    SHORTCUTS.iter().any(|s| s.trigger == Trigger::Hold && s.key == key && s.action.moves_arm())
}

/// True while a key of `action` is held where the table lets it act (see the module's rules);
/// Shift must match the table's row (Shift+A turns about X, A moves along it).
pub fn held(ctx: &egui::Context, action: Action) -> bool {
    update_held(ctx);
    let taken = keyboard_taken(ctx);
    let modifiers = ctx.input(|i| i.modifiers);
    let armed = ctx.data(|d| d.get_temp::<HeldKeys>(held_keys_id()).map(|h| h.armed).unwrap_or_default());
    SHORTCUTS
        .iter()
        .filter(|s| s.action == action && s.trigger == Trigger::Hold)
        .any(|s| scope_open(ctx, s.scope, taken) && mods_match(s.mods, modifiers) && armed.contains_key(&s.key))
}

/// The name of a key as the help shows it.
fn key_name(key: Key) -> &'static str {
    match key {
        Key::Plus => "+",
        Key::Minus => "−",
        Key::Equals => "=",
        Key::ArrowLeft => "Left",
        Key::ArrowRight => "Right",
        Key::ArrowUp => "Up",
        Key::ArrowDown => "Down",
        Key::Escape => "Esc",
        Key::PageUp => "Page Up",
        Key::PageDown => "Page Down",
        Key::Num1 => "1",
        Key::Num2 => "2",
        Key::Num3 => "3",
        Key::Num4 => "4",
        Key::Num5 => "5",
        Key::Num6 => "6",
        k => k.name(),
    }
}

/// The chord as the help shows it ("Ctrl+S", "Shift+A").
pub fn chord(s: &Shortcut) -> String {
    let mut out = String::new();
    if let Mods::Exactly(m) = s.mods {
        if m.command || m.ctrl {
            out.push_str(if cfg!(target_os = "macos") { "Cmd+" } else { "Ctrl+" });
        }
        if m.alt {
            out.push_str("Alt+");
        }
        if m.shift {
            out.push_str("Shift+");
        }
    }
    out.push_str(key_name(s.key));
    out
}

/// Every chord bound to `action`, as a menu shows them ("Ctrl+Shift+Z, Ctrl+Y").
pub fn chords(action: Action) -> String {
    SHORTCUTS.iter().filter(|s| s.action == action).map(chord).collect::<Vec<_>>().join(", ")
}

/// The help's rows (keys, what, where): the table in order, consecutive rows with the same
/// text and scope as one row.
pub fn help_rows() -> Vec<(String, &'static str, &'static str)> {
    let mut rows: Vec<(String, &'static str, &'static str)> = Vec::new();
    let mut last: Option<(&str, Scope)> = None;
    for s in SHORTCUTS {
        match (rows.last_mut(), last) {
            (Some(row), Some((help, scope))) if help == s.help && scope == s.scope => {
                row.0.push_str(", ");
                row.0.push_str(&chord(s));
            }
            _ => rows.push((chord(s), s.help, s.scope.describe())),
        }
        last = Some((s.help, s.scope));
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_shortcuts_share_a_chord_in_overlapping_places() {
        for (i, a) in SHORTCUTS.iter().enumerate() {
            for b in &SHORTCUTS[i + 1..] {
                let same_keys = a.key == b.key && a.mods == b.mods;
                let overlap =
                    a.scope == b.scope || matches!(a.scope, Scope::Always) || matches!(b.scope, Scope::Always);
                assert!(!(same_keys && overlap), "{} is bound twice: {:?} and {:?}", chord(a), a.action, b.action);
            }
        }
    }

    #[test]
    fn only_home_moves_the_arm_with_a_command_modifier() {
        for s in SHORTCUTS.iter().filter(|s| s.action.moves_arm()) {
            if let Mods::Exactly(m) = s.mods
                && command_modifier(m)
            {
                assert_eq!(s.action, Action::Home, "{} moves the arm with a modifier", chord(s));
            }
        }
    }

    #[test]
    fn help_rows_merge_the_jog_keys() {
        let rows = help_rows();
        assert!(rows.iter().any(|r| r.0 == "A, D, S, W, Q, E" && r.1 == JOG_XYZ), "{rows:?}");
        assert!(rows.iter().any(|r| r.0.ends_with("+S") && r.1 == "save the program"));
        assert!(rows.iter().any(|r| r.0 == "F5") && rows.iter().any(|r| r.0 == "F10"));
    }

    #[test]
    fn the_edit_menu_shows_the_tables_chords() {
        let ctrl = if cfg!(target_os = "macos") { "Cmd" } else { "Ctrl" };
        assert_eq!(chords(Action::Undo), format!("{ctrl}+Z"));
        assert_eq!(chords(Action::Redo), format!("{ctrl}+Shift+Z, {ctrl}+Y"));
        assert_eq!(chords(Action::DeleteStep), "Delete");
    }
}
