//! URDF input bounds end to end: the deep-nesting defect stays fixed for every entry point
//! (text and file), and real robot descriptions still load.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_core::model::{LoadOptions, ModelError, RobotModel};
use parol6_core::urdf_input::{MAX_URDF_BYTES, MAX_URDF_NESTING_DEPTH, UrdfInputError, xml_nesting_depth};
use parol6_tests::shared_dir;

/// The reported file: 50 000 nested elements inside `<robot>`, about 350 KB.
fn deeply_nested_urdf() -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"deep\">\n");
    s.push_str(&"<link>".repeat(25_000));
    s.push_str("<visual/>");
    s.push_str(&"</link>".repeat(25_000));
    s.push_str(&"<x>".repeat(25_000));
    s.push_str(&"</x>".repeat(25_000));
    s.push_str("</robot>\n");
    s
}

#[test]
fn deeply_nested_urdf_is_refused_not_a_crash() {
    let xml = deeply_nested_urdf();
    assert!(xml.len() > 340_000, "{}", xml.len());
    let err = RobotModel::from_urdf_str(&xml, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(err, ModelError::InputRefused(UrdfInputError::TooDeep { line: 3, limit_depth: 64, .. })),
        "{err:?}"
    );
    // Through a file too, on a thread with a small stack (the parser would overflow it).
    let path = std::env::temp_dir().join(format!("parol6-deep-{}.urdf", std::process::id()));
    std::fs::write(&path, &xml).unwrap();
    let from_file = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn({
            let path = path.clone();
            move || RobotModel::from_urdf_file(&path, None).map(|m| m.dof())
        })
        .unwrap()
        .join()
        .unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(from_file.unwrap_err(), err);
    assert!(err.to_string().contains("nest deeper than 64 levels at line 3"), "{err}");
}

#[test]
fn oversized_urdf_file_is_refused_with_the_limit() {
    let mut xml = String::from("<robot name=\"big\">");
    xml.push_str(&"<link name=\"l\"/>".repeat(MAX_URDF_BYTES / 16 + 1));
    xml.push_str("</robot>");
    let err = RobotModel::from_urdf_str(&xml, &LoadOptions::default()).unwrap_err();
    assert_eq!(
        err,
        ModelError::InputRefused(UrdfInputError::TooLarge { size_bytes: xml.len(), limit_bytes: MAX_URDF_BYTES })
    );
    assert!(err.to_string().contains("8 MiB"), "{err}");
}

#[test]
fn embedded_parol6_still_loads() {
    let m = RobotModel::parol6();
    assert_eq!(m.dof(), 6);
    assert!(xml_nesting_depth(parol6_core::model::PAROL6_URDF) < 10);
}

#[test]
fn official_urdfs_pass_the_bounds_and_load() {
    let Some(shared) = shared_dir() else { return };
    let mut files = Vec::new();
    let mut dirs = vec![shared.join("urdf")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "urdf") {
                files.push(p);
            }
        }
    }
    assert!(!files.is_empty(), "no .urdf under {}", shared.join("urdf").display());
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let depth = xml_nesting_depth(&text);
        assert!(depth < 10, "{}: depth {depth} (limit {MAX_URDF_NESTING_DEPTH})", path.display());
        let m = RobotModel::from_urdf_file(&path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(m.dof(), 6, "{}", path.display());
    }
}

#[test]
fn nesting_at_the_limit_parses_on_a_small_stack() {
    // The deepest text the bounds let through reaches the parser without exhausting even a
    // 256 KiB thread stack (the default for spawned threads is 2 MiB), so no caller needs a
    // special stack.
    let inner = MAX_URDF_NESTING_DEPTH - 3;
    let xml = format!(
        "<robot name=\"r\"><link name=\"a\"><visual>{}{}</visual></link><link name=\"b\"/>{}</robot>",
        "<x>".repeat(inner),
        "</x>".repeat(inner),
        r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
    );
    assert_eq!(xml_nesting_depth(&xml), MAX_URDF_NESTING_DEPTH);
    let loaded = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(move || RobotModel::from_urdf_str(&xml, &LoadOptions::default()).map(|m| m.dof()))
        .unwrap()
        .join()
        .unwrap();
    // Unknown elements inside <visual> are ignored by the parser; the geometry is missing.
    assert!(
        loaded.is_ok() || matches!(loaded, Err(ModelError::NotUrdf(_) | ModelError::XmlSyntax { .. })),
        "{loaded:?}"
    );
}
