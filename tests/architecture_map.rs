//! ARCHITECTURE.md stays a true map: its Modules table has one row for every top-level module of
//! each crate (`crates/*/src/lib.rs`) and no row for a module that is gone, and every file or
//! folder its "Where to change X" list names exists.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn architecture() -> String {
    std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md")
}

/// The text of the section that starts with `heading`, up to the next `## ` heading.
fn section<'a>(text: &'a str, heading: &str) -> &'a str {
    let start = text.find(heading).unwrap_or_else(|| panic!("ARCHITECTURE.md has no {heading:?}"));
    let rest = &text[start + heading.len()..];
    &rest[..rest.find("\n## ").unwrap_or(rest.len())]
}

/// `(crate, module)` of every `pub mod` / `mod` line in the crates' `lib.rs`.
fn crate_modules() -> Vec<(String, String)> {
    let mut modules = Vec::new();
    for (short, dir) in [("core", "parol6-core"), ("hw", "parol6-hw"), ("app", "parol6-app")] {
        let lib = std::fs::read_to_string(root().join("crates").join(dir).join("src/lib.rs")).expect("lib.rs");
        for line in lib.lines() {
            let line = line.trim();
            let name = line.strip_prefix("pub mod ").or_else(|| line.strip_prefix("mod "));
            if let Some(name) = name.and_then(|n| n.strip_suffix(';')) {
                modules.push((short.to_string(), name.to_string()));
            }
        }
    }
    modules
}

/// `(crate, module)` of every row of the Modules table.
fn table_rows(modules: &str) -> Vec<(String, String)> {
    modules
        .lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            match cells.as_slice() {
                ["", krate, module, _, ""] if module.starts_with('`') => {
                    Some((krate.to_string(), module.trim_matches('`').to_string()))
                }
                _ => None,
            }
        })
        .collect()
}

#[test]
fn the_module_table_has_one_row_per_crate_module() {
    let text = architecture();
    let rows = table_rows(section(&text, "## Modules"));
    let modules = crate_modules();
    assert!(modules.len() >= 30, "{modules:?}");
    for m in &modules {
        assert_eq!(rows.iter().filter(|r| *r == m).count(), 1, "ARCHITECTURE.md, Modules: one row for {m:?}");
    }
    for r in &rows {
        assert!(modules.contains(r), "ARCHITECTURE.md, Modules: {r:?} is not a module of that crate");
    }
}

/// Every file under `dir` (recursively), relative to the repository root.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read_dir").flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if name == "target" || name == ".git" || name == "corpus" || name == "corpus-min" {
            continue;
        }
        if path.is_dir() {
            out.push(path.clone());
            files_under(&path, out);
        } else {
            out.push(path);
        }
    }
}

#[test]
fn every_path_in_where_to_change_x_exists() {
    let text = architecture();
    let list = section(&text, "## Where to change X");
    let mut all = Vec::new();
    for dir in ["crates", "tests", "docs", "fuzz"] {
        files_under(&root().join(dir), &mut all);
    }
    all.push(root().join("README.md"));
    let mut checked = 0;
    for span in list.split('`').skip(1).step_by(2) {
        let looks_like_path = span.contains('/') || span.ends_with(".rs") || span.ends_with(".md");
        if !looks_like_path || span.contains(['*', ' ']) || span.contains("NAME") {
            continue;
        }
        let want = span.trim_end_matches('/');
        assert!(all.iter().any(|f| f.ends_with(want)), "ARCHITECTURE.md, Where to change X: {span} does not exist");
        checked += 1;
    }
    assert!(checked >= 25, "the list names its files ({checked} found)");
}

/// The sibling files of `crates/parol6-app/src/cli/` that `file` imports (`super::X` or
/// `crate::cli::X`, grouped imports included).
fn cli_imports(dir: &Path, file: &str, files: &[String]) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join(format!("{file}.rs"))).expect("cli file");
    let mut found = Vec::new();
    for prefix in ["super::", "crate::cli::"] {
        for (at, _) in text.match_indices(prefix) {
            let rest = &text[at + prefix.len()..];
            let names: Vec<&str> = match rest.strip_prefix('{') {
                Some(group) => group.split('}').next().unwrap_or("").split(',').collect(),
                None => vec![rest],
            };
            for name in names {
                let name: String = name.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if files.contains(&name) && name != file && !found.contains(&name) {
                    found.push(name);
                }
            }
        }
    }
    found
}

/// No import circle among the CLI's files: shared helpers live in `cli/common.rs`, not in
/// whichever subcommand needed them first (issue 33: an 8-file circle).
#[test]
fn cli_files_import_no_circle() {
    let dir = root().join("crates/parol6-app/src/cli");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("cli dir")
        .filter_map(|e| e.ok()?.file_name().to_str()?.strip_suffix(".rs").map(str::to_string))
        .filter(|f| f != "mod")
        .collect();
    files.sort();
    let edges: Vec<(String, Vec<String>)> = files.iter().map(|f| (f.clone(), cli_imports(&dir, f, &files))).collect();
    // a file on a circle reaches itself
    let reaches = |from: &str| {
        let mut seen: Vec<String> = Vec::new();
        let mut todo = vec![from.to_string()];
        while let Some(f) = todo.pop() {
            for next in edges.iter().filter(|(g, _)| *g == f).flat_map(|(_, to)| to) {
                if !seen.contains(next) {
                    seen.push(next.clone());
                    todo.push(next.clone());
                }
            }
        }
        seen
    };
    let circled: Vec<&String> = files.iter().filter(|f| reaches(f).contains(f)).collect();
    assert!(circled.is_empty(), "cli files on an import circle: {circled:?}");
}

/// The app owns the runs a panel starts (issue 33 item 2): no panel holds a program runner or a
/// measurement; a panel reads them through `PanelContext::app` and changes them by `AppCommand`.
#[test]
fn panels_hold_no_program_run_and_no_measurement() {
    let mut files = Vec::new();
    files_under(&root().join("crates/parol6-app/src/panels"), &mut files);
    let mut checked = 0;
    for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "rs")) {
        let text = std::fs::read_to_string(f).expect("read panel file");
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for owned in ["MeasureRun", "ProgramRunner"] {
                assert!(!code.contains(owned), "{}:{}: a panel holds a {owned}: {line}", f.display(), n + 1);
            }
        }
        checked += 1;
    }
    assert!(checked >= 20, "panel files read: {checked}");
}
