//! Issue 32's last minor items of the window's wording, driven headless through egui's kittest
//! harness on the full app: counts say "1 error" / "2 warnings" (never "error(s)").

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use ui_support::{app_harness, open_program_file, until};

use parol6_app::app::Parol6App;

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-wording-ui-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every label of the window (and text value) that contains `part`.
fn labels_with(h: &Harness<'_, Parol6App>, part: &str) -> Vec<String> {
    h.query_all_by_label_contains(part).filter_map(|n| n.accesskit_node().label().or_else(|| n.value())).collect()
}

/// "1 error" / "2 errors": the noun agrees with the number before it.
fn agrees(text: &str, noun: &str) -> bool {
    let words: Vec<&str> = text.split([' ', ',', '·', ':', ';', '(']).filter(|w| !w.is_empty()).collect();
    words.windows(2).filter(|w| w[1].starts_with(noun)).all(|w| match w[0].parse::<usize>() {
        Ok(1) => w[1] == noun,
        Ok(_) => w[1] == format!("{noun}s"),
        Err(_) => true,
    })
}

/// A program whose two Cartesian moves reach far outside the workspace: the pre-flight finds
/// errors.
const FAR: &str = "{\"format\": \"parol6-program\", \"version\": 1, \"name\": \"Too far\",\n \"steps\": [\n  \
                   {\"type\": \"move_l\", \"pose\": {\"position_mm\": [0, 900, 300], \"rpy_deg\": [180, 0, 90]}},\n  \
                   {\"type\": \"move_l\", \"pose\": {\"position_mm\": [0, 950, 300], \"rpy_deg\": [180, 0, 90]}}\n ]}";

/// Issue 32 minor: "1 solution(s)", "error(s)", "warning(s)": a count is followed by the
/// singular or the plural, as the number wants.
#[test]
fn counts_are_followed_by_the_singular_or_the_plural_never_by_s_in_brackets() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    let far = temp_dir("plural").join("far.json");
    std::fs::write(&far, FAR).unwrap();
    open_program_file(&mut h, &far);
    until(&mut h, "the pre-flight's verdict", 30.0, |h| !labels_with(h, "pre-flight: ").is_empty());
    h.run_steps(2);
    let verdict = labels_with(&h, "pre-flight: ");
    assert!(verdict.iter().any(|v| v.contains(" error")), "{verdict:?}");
    for v in &verdict {
        assert!(agrees(v, "error") && agrees(v, "warning"), "{v}");
    }
    let solutions = labels_with(&h, "within the limits; pick a configuration");
    assert_eq!(solutions.len(), 1, "the Cartesian target lists its solutions: {solutions:?}");
    assert!(agrees(&solutions[0], "solution"), "{}", solutions[0]);
    for bracketed in ["(s)", "(es)"] {
        let found: Vec<String> = labels_with(&h, bracketed).into_iter().filter(|l| !l.contains("time (s)")).collect();
        assert!(found.is_empty(), "{bracketed} in {found:?}");
    }
}
