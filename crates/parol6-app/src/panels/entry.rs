//! Typed numeric entries and number formatting shared by the panels.
//!
//! An entry shows the value with a fixed number of decimals while it is not focused. Clicking
//! it selects the text; what the operator types is kept as typed (never re-parsed or rounded
//! while typing) and committed once, on Enter or when the focus leaves the field (Tab, a
//! click elsewhere); Esc, or leaving the shown text as it was, commits nothing. Nothing is sent while typing.

use eframe::egui;

/// Formats `v` with `decimals` decimals and never prints a negative zero ("-0.00" → "0.00").
pub fn fmt_fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// Parses what the operator typed into a field that shows `field_unit` (its suffix: `°`,
/// `rad`, `mm`, `s`, … or `""` for a plain number): a decimal number with `.` or `,` as the
/// decimal mark, optionally followed by a unit, surrounding blanks ignored. A unit that fits the
/// field is converted to the field's unit (`rad`, `deg`, `°` in an angle field; `mm`, `m`, `in`
/// in a millimetre field; `mA`, `A` in a current field; the field's own unit anywhere); one that does not is refused, saying
/// which units the field takes.
pub fn parse_in(text: &str, field_unit: &str) -> Result<f64, String> {
    let t = text.trim();
    let number_end = t.rfind(|c: char| c.is_ascii_digit() || c == '.' || c == ',').map_or(0, |i| i + 1);
    let (number, unit) = (t[..number_end].trim(), t[number_end..].trim());
    let v = match number.replace(',', ".").parse::<f64>() {
        Ok(v) if v.is_finite() => v,
        _ => return Err(format!("\"{t}\" is not a number")),
    };
    if unit.is_empty() {
        return Ok(v);
    }
    let field = field_unit.trim();
    let factor = match (field, unit) {
        (f, u) if f == u && !f.is_empty() => Some(Scale::Times(1.0)),
        ("°" | "deg", "°" | "deg") | ("rad", "rad") => Some(Scale::Times(1.0)),
        ("°" | "deg", "rad") => Some(Scale::Times(180.0 / std::f64::consts::PI)),
        ("rad", "°" | "deg") => Some(Scale::Times(std::f64::consts::PI / 180.0)),
        ("mm", "m") | ("mA", "A") => Some(Scale::TenTo(3)),
        ("A", "mA") => Some(Scale::TenTo(-3)),
        ("mm", "in") => Some(Scale::Times(25.4)),
        _ => None,
    };
    match factor {
        Some(Scale::Times(k)) => Ok(v * k),
        // the decimal point moved in the text: "1.001 A" is 1001 mA, not 1000.9999999999999
        Some(Scale::TenTo(e)) => {
            Ok(format!("{}e{e}", number.replace(',', ".")).parse::<f64>().unwrap_or(v * 10f64.powi(e)))
        }
        None => Err(format!("\"{t}\": {unit} does not fit this field; {}", accepts(field))),
    }
}

/// How a typed unit becomes the field's: a factor, or a power of ten (exact in decimal).
enum Scale {
    Times(f64),
    TenTo(i32),
}

/// What a field showing `unit` accepts, in words.
fn accepts(unit: &str) -> String {
    match unit {
        "°" | "deg" | "rad" => format!("it takes an angle: a plain number (in {unit}) or one ending in °, deg or rad"),
        "mm" => "it takes a length: a plain number (in mm) or one ending in mm, m or in".to_string(),
        "mA" | "A" => format!("it takes a current: a plain number (in {unit}) or one ending in mA or A"),
        "" => "it takes a plain number".to_string(),
        u => format!("it takes a plain number (in {u}) or one ending in {u}"),
    }
}

/// True when the keyboard left the field this frame: Enter or Tab, not a click elsewhere (nor the
/// window losing the keyboard). A field whose value moves the arm commits only so: a click on the
/// 3D view, a menu or a jog button never moves the arm (trials 25 m1, 26 m2).
pub fn left_by_key(ui: &egui::Ui) -> bool {
    ui.input(|i| {
        i.raw
            .events
            .iter()
            .any(|e| matches!(e, egui::Event::Key { key: egui::Key::Enter | egui::Key::Tab, pressed: true, .. }))
    })
}

/// The result of one frame of an entry.
#[derive(Debug, Clone, PartialEq)]
pub enum EntryEvent {
    /// The operator committed this value (Enter or focus loss).
    Committed(f64),
    /// The operator committed text that is not a number (the message says why).
    Invalid(String),
}

/// A committed value checked against its field's range: `Ok(v)` inside `range` (and whole when
/// `whole`), else the message naming the field, the value and the range, e.g.
/// "Gripper speed: 300 is outside 0–255" or "cycles: 2.5 is not a whole number (2–1000)".
/// A typed value is never clamped or rounded without a word.
pub fn in_range(name: &str, v: f64, range: (f64, f64), unit: &str, whole: bool) -> Result<f64, String> {
    let u = if unit.is_empty() { String::new() } else { format!(" {unit}") };
    let (shown, lo, hi) = (plain(v), plain(range.0), plain(range.1));
    if !(range.0..=range.1).contains(&v) {
        Err(format!("{name}: {shown}{u} is outside {lo}–{hi}{u}"))
    } else if whole && v.fract() != 0.0 {
        Err(format!("{name}: {shown}{u} is not a whole number ({lo}–{hi}{u})"))
    } else {
        Ok(v)
    }
}

/// A numeric text entry `width` points wide showing `value` with `decimals` decimals (and
/// `suffix`, shown after the field). `name` is its accessible name (e.g. "J1 target") and its
/// id within `ui`, so it must be unique there. Returns the widget's response and the event of
/// this frame, if any.
pub fn numeric_entry(
    ui: &mut egui::Ui,
    name: &str,
    value: f64,
    decimals: usize,
    width: f32,
    suffix: &str,
) -> (egui::Response, Option<EntryEvent>) {
    unit_entry(ui, name, value, decimals, width, suffix, suffix)
}

/// [`numeric_entry`] for a field in `unit` that shows `suffix` (e.g. none in a table whose
/// header names the unit): typed units are converted to `unit` (see [`parse_in`]).
pub fn unit_entry(
    ui: &mut egui::Ui,
    name: &str,
    value: f64,
    decimals: usize,
    width: f32,
    suffix: &str,
    unit: &str,
) -> (egui::Response, Option<EntryEvent>) {
    entry(ui, name, value, (decimals, width), (suffix, unit), None)
}

/// [`unit_entry`] for a field that takes values in `range` (checked by the caller, e.g. with
/// [`in_range`]): its one hover hint names the range.
pub fn ranged_entry(
    ui: &mut egui::Ui,
    name: &str,
    value: f64,
    (decimals, width): (usize, f32),
    (suffix, unit): (&str, &str),
    range: (f64, f64),
) -> (egui::Response, Option<EntryEvent>) {
    entry(ui, name, value, (decimals, width), (suffix, unit), Some(range))
}

/// A slider whose value box reads typed text as the entries do ([`parse_in`]: `.` or `,` as
/// the decimal mark, the field's `unit` or none) and only once Enter, Tab or a click elsewhere
/// commits it. A typed value outside `range`, or text that is no number, is refused, never
/// clamped: the value stays, and the message (naming `name`, the range and the value kept) is
/// returned for a notice. Dragging moves within the range as on any slider. (egui's own box
/// read every keystroke and clamped it: "0,5" became its minimum, 0.05, without a word.)
pub fn typed_slider(
    ui: &mut egui::Ui,
    name: &str,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    (suffix, unit): (&str, &str),
    decimals: usize,
) -> (egui::Response, Option<String>) {
    let (lo, hi) = (*range.start(), *range.end());
    let before = *value;
    let refusal = std::cell::RefCell::new(None);
    let parse = |text: &str| {
        let typed = parse_in(text, unit)
            .map_err(|e| format!("{name}: {e}"))
            .and_then(|v| in_range(name, v, (lo, hi), unit, false));
        match typed {
            Ok(v) => Some(v),
            Err(e) => {
                let u = if unit.is_empty() { String::new() } else { format!(" {unit}") };
                refusal.replace(Some(format!("{e}; it stays {}{u}", fmt_fixed(before, decimals))));
                None
            }
        }
    };
    let slider = egui::Slider::new(value, range)
        .suffix(suffix)
        .max_decimals(decimals)
        .update_while_editing(false)
        .custom_parser(parse);
    let u = if unit.is_empty() { String::new() } else { format!(" {unit}") };
    let response = ui
        .add(slider)
        .on_hover_text(format!("{name}: drag, or click the value and type one ({lo}–{hi}{u}), then Enter or Tab"));
    (response, refusal.into_inner())
}

/// `v` for a message: at most 6 decimals, without the float noise of a unit conversion
/// ("1000000000.0000001" → "1000000000", "0.30000000000000004" → "0.3") and never "-0".
fn plain(v: f64) -> String {
    let rounded = (v * 1e6).round() / 1e6;
    if rounded.is_finite() && rounded != 0.0 {
        format!("{rounded}")
    } else if v.is_finite() {
        "0".into()
    } else {
        format!("{v}")
    }
}

/// The hover hint of an entry (the only one: a caller adds none of its own, or two tooltips
/// stack): what to type and, for a field with a range, the range.
fn hint(name: &str, unit: &str, range: Option<(f64, f64)>) -> String {
    match range {
        None => format!("{name}: type a value, then Enter or Tab"),
        Some((lo, hi)) => {
            let u = if unit.is_empty() { String::new() } else { format!(" {unit}") };
            format!("{name}: type a value ({lo}–{hi}{u}), then Enter or Tab")
        }
    }
}

fn entry(
    ui: &mut egui::Ui,
    name: &str,
    value: f64,
    (decimals, width): (usize, f32),
    (suffix, unit): (&str, &str),
    range: Option<(f64, f64)>,
) -> (egui::Response, Option<EntryEvent>) {
    let id = ui.make_persistent_id(name);
    let buffer_id = id.with("typed");
    let typed: Option<String> = ui.data(|d| d.get_temp(buffer_id));
    let editing = typed.is_some();
    let mut text = typed.unwrap_or_else(|| fmt_fixed(value, decimals));
    let response = ui
        .horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = 2.0;
            let r = ui.add_sized(
                [width, ui.spacing().interact_size.y],
                egui::TextEdit::singleline(&mut text).id(id).align(egui::Align2::RIGHT_CENTER),
            );
            let shown = text.clone();
            let r = r.on_hover_text(hint(name, unit, range));
            r.widget_info(|| {
                let mut info = egui::WidgetInfo::text_edit(true, &shown, &shown, "");
                info.label = Some(name.to_string());
                info
            });
            if !suffix.is_empty() {
                ui.label(suffix);
            }
            r
        })
        .inner;
    let mut event = None;
    if response.gained_focus() || (response.has_focus() && !editing) {
        // Start from the shown value, all selected: typing replaces it.
        let start = fmt_fixed(value, decimals);
        if let Some(mut state) = egui::TextEdit::load_state(ui.ctx(), id) {
            state.cursor.set_char_range(Some(egui::text::CCursorRange::select_all_str(&start)));
            state.store(ui.ctx(), id);
        }
        if text != start && !editing {
            text = start;
        }
        ui.data_mut(|d| d.insert_temp(buffer_id, text));
        ui.ctx().request_repaint();
    } else if response.has_focus() {
        ui.data_mut(|d| d.insert_temp(buffer_id, text));
    } else if editing {
        // Focus left the field (Enter, Tab, click elsewhere): commit what was typed; Esc (which
        // is STOP as well) drops it, so nothing moves after the STOP. Esc is looked for in the
        // raw input: the STOP shortcut consumed it already.
        ui.data_mut(|d| d.remove::<String>(buffer_id));
        let esc = ui.input(|i| {
            i.raw.events.iter().any(|e| matches!(e, egui::Event::Key { key: egui::Key::Escape, pressed: true, .. }))
        });
        // text left as shown: nothing was typed, nothing moves (not even by the rounding)
        if esc || text == fmt_fixed(value, decimals) {
            return (response, None);
        }
        event = Some(match parse_in(&text, unit) {
            Ok(v) => EntryEvent::Committed(v),
            Err(e) => EntryEvent::Invalid(e),
        });
    }
    (response, event)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Trial 9: a step angle typed in radians was refused as "1000000000.0000001 is outside
    /// 0.01–90 °" (the conversion's float noise).
    #[test]
    fn a_refusal_shows_its_numbers_without_float_noise() {
        let e = in_range("step", 1e9 * (1.0 + f64::EPSILON), (0.01, 90.0), "°", false).unwrap_err();
        assert_eq!(e, "step: 1000000000 ° is outside 0.01–90 °");
        let e = in_range("speed", 0.1 + 0.2 + 1.0, (0.0, 1.0), "", false).unwrap_err();
        assert_eq!(e, "speed: 1.3 is outside 0–1");
        let e = in_range("cycles", -0.5, (2.0, 1000.0), "", true).unwrap_err();
        assert_eq!(e, "cycles: -0.5 is outside 2–1000");
        assert_eq!(plain(-1e-9), "0");
    }

    #[test]
    fn fixed_format_has_no_negative_zero() {
        assert_eq!(fmt_fixed(-0.0001, 2), "0.00");
        assert_eq!(fmt_fixed(-0.0, 4), "0.0000");
        assert_eq!(fmt_fixed(-0.006, 2), "-0.01");
        assert_eq!(fmt_fixed(90.0, 2), "90.00");
        assert_eq!(fmt_fixed(-32.73, 2), "-32.73");
    }

    #[test]
    fn parses_decimals_signs_commas_and_units() {
        assert_eq!(parse_in("12.34", "°"), Ok(12.34));
        assert_eq!(parse_in(" -32.73 ", "mm"), Ok(-32.73));
        assert_eq!(parse_in("0,5", ""), Ok(0.5));
        assert_eq!(parse_in("45°", "°"), Ok(45.0));
        assert_eq!(parse_in("0.5 rad", "rad"), Ok(0.5));
        assert_eq!(parse_in("-120 mm", "mm"), Ok(-120.0));
        assert_eq!(parse_in("1e3", ""), Ok(1000.0));
        assert_eq!(parse_in("2,5 s", "s"), Ok(2.5));
        assert_eq!(parse_in("0.2N·m", "N·m"), Ok(0.2));
        assert!(parse_in("abc", "°").is_err());
        assert!(parse_in("", "°").is_err());
        assert!(parse_in("inf", "").is_err());
        assert!(parse_in("-", "mm").is_err());
    }

    /// Issue 32 major 2: "0.5rad" in a degree field was 0.50°, "10mm" was accepted as an angle.
    #[test]
    fn a_typed_unit_is_converted_or_refused() {
        let close = |a: Result<f64, String>, b: f64| a.as_ref().is_ok_and(|a| (a - b).abs() < 1e-9);
        assert!(close(parse_in("0.5rad", "°"), 28.64788975654116));
        assert!(close(parse_in("90 deg", "rad"), std::f64::consts::FRAC_PI_2));
        assert!(close(parse_in("90°", "rad"), std::f64::consts::FRAC_PI_2));
        assert!(close(parse_in("-1,5 deg", "°"), -1.5));
        assert!(close(parse_in("0.25 m", "mm"), 250.0));
        assert!(close(parse_in("2in", "mm"), 50.8));
        assert!(close(parse_in("3 mm", "mm"), 3.0));
        let e = parse_in("10mm", "°").unwrap_err();
        assert!(e.contains("mm does not fit") && e.contains("°, deg or rad"), "{e}");
        let e = parse_in("10 rad", "mm").unwrap_err();
        assert!(e.contains("rad does not fit") && e.contains("mm, m or in"), "{e}");
        let e = parse_in("3 mm", "s").unwrap_err();
        assert!(e.contains("in s"), "{e}");
        assert!(parse_in("5 xyz", "°").is_err());
        assert!(parse_in("1 m", "").is_err());
    }
}
