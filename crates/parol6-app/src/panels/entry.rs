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

/// Parses what the operator typed: a decimal number with `.` or `,` as the decimal mark,
/// optionally followed by a unit (`°`, `deg`, `rad`, `mm`), surrounding blanks ignored.
pub fn parse_number(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let t = ["°", "deg", "rad", "mm"].iter().fold(t, |t, unit| t.strip_suffix(unit).unwrap_or(t)).trim();
    let t = t.replace(',', ".");
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("\"{}\" is not a number", text.trim())),
    }
}

/// The result of one frame of an entry.
#[derive(Debug, Clone, PartialEq)]
pub enum EntryEvent {
    /// The operator committed this value (Enter or focus loss).
    Committed(f64),
    /// The operator committed text that is not a number (the message says why).
    Invalid(String),
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
            let r = r.on_hover_text(format!("{name}: type a value, then Enter or Tab"));
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
        event = Some(match parse_number(&text) {
            Ok(v) => EntryEvent::Committed(v),
            Err(e) => EntryEvent::Invalid(e),
        });
    }
    (response, event)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(parse_number("12.34"), Ok(12.34));
        assert_eq!(parse_number(" -32.73 "), Ok(-32.73));
        assert_eq!(parse_number("0,5"), Ok(0.5));
        assert_eq!(parse_number("45°"), Ok(45.0));
        assert_eq!(parse_number("0.5 rad"), Ok(0.5));
        assert_eq!(parse_number("-120 mm"), Ok(-120.0));
        assert!(parse_number("abc").is_err());
        assert!(parse_number("").is_err());
        assert!(parse_number("inf").is_err());
    }
}
