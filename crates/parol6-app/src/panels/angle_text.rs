//! The core's messages (planner refusals, pre-flight findings, IK failures, jog stops) in the
//! window's angle unit.
//!
//! The core writes its angles in degrees, which the command line prints as they are. The window
//! passes every such message through [`in_unit`] before it shows it: with radians chosen, each
//! `N°` (also `N°/s`, `N°/s²`, `N°/mm` and a bracketed list `(a, b, c)°`) becomes radians, with
//! two more decimals than the degrees had, and a `(… rad)` the core already wrote after a
//! degree value is not repeated. (Its cases are tested in `tests/wording_ui.rs`.)

use std::borrow::Cow;

use super::AngleUnit;

/// `text` with its degree values in `unit` (unchanged for degrees, or when it has none).
pub fn in_unit(text: &str, unit: AngleUnit) -> Cow<'_, str> {
    if unit == AngleUnit::Deg || !text.contains('°') {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 16);
    let mut rest = text;
    while let Some(at) = rest.find('°') {
        let (before, after) = rest.split_at(at);
        let after = &after['°'.len_utf8()..];
        out.push_str(before);
        rest = convert_before(&mut out, after);
    }
    out.push_str(rest);
    Cow::Owned(out)
}

/// Rewrites what ends `out` (a number, or a bracketed list of numbers, just before a `°`) into
/// radians, writes the unit that replaces the `°` (with what follows it: `/s`, `/mm`, `/°`) and
/// returns the text after what it used.
fn convert_before<'a>(out: &mut String, after: &'a str) -> &'a str {
    // a ratio of angles (°/°) is the same number in rad/rad
    if let Some(rest) = after.strip_prefix("/°") {
        out.push_str(" rad/rad");
        return rest;
    }
    let converted = if out.ends_with(')') || out.ends_with(']') { convert_list(out) } else { convert_number(out) };
    if !converted {
        // not a number before it (a stray degree sign): keep it
        out.push('°');
        return after;
    }
    out.push_str(" rad");
    // the core's "X° (Y rad)": the radians are said once
    if let Some(inner) = after.strip_prefix(" (")
        && let Some(end) = inner.find(')')
        && inner[..end].ends_with(" rad")
        && inner[..end].trim_end_matches(" rad").parse::<f64>().is_ok()
    {
        return &inner[end + 1..];
    }
    after
}

/// The number that ends `out`, in degrees, replaced by radians; false when none ends it.
fn convert_number(out: &mut String) -> bool {
    let start = number_start(out);
    let Some((value, decimals)) = parse_degrees(&out[start..]) else { return false };
    out.truncate(start);
    out.push_str(&format_rad(value, decimals));
    true
}

/// The bracketed list of numbers that ends `out` (`(a, b, c)` or `[a, b]`) converted; false
/// unless every item is a number.
fn convert_list(out: &mut String) -> bool {
    let (open, close) = if out.ends_with(')') { ('(', ')') } else { ('[', ']') };
    let Some(start) = out.rfind(open) else { return false };
    let inner = &out[start + 1..out.len() - 1];
    let items: Option<Vec<String>> =
        inner.split(',').map(|item| parse_degrees(item.trim()).map(|(v, d)| format_rad(v, d))).collect();
    let Some(items) = items else { return false };
    out.truncate(start);
    out.push(open);
    out.push_str(&items.join(", "));
    out.push(close);
    true
}

/// Where the number at the end of `s` starts (a sign, digits and one point).
fn number_start(s: &str) -> usize {
    let digits = s.trim_end_matches(|c: char| c.is_ascii_digit() || c == '.');
    let signed = digits.strip_suffix(['-', '−', '+']).unwrap_or(digits);
    signed.len()
}

/// A number in degrees (ASCII or Unicode minus) and its decimals.
fn parse_degrees(s: &str) -> Option<(f64, usize)> {
    let plain = s.replace('−', "-");
    if plain.is_empty() || !plain.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    let value: f64 = plain.parse().ok()?;
    let decimals = plain.split_once('.').map_or(0, |(_, d)| d.len());
    Some((value, decimals))
}

/// Degrees in radians with two more decimals (a degree is about a 57th of a radian).
fn format_rad(deg: f64, decimals: usize) -> String {
    let text = format!("{:.*}", decimals + 2, deg.to_radians());
    // no "-0.000"
    if text.trim_start_matches('-').bytes().all(|b| b == b'0' || b == b'.') {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}
