use super::*;
use crate::model::{LoadOptions, ModelError, PAROL6_URDF, RobotModel};

fn nested(levels: usize) -> String {
    let mut s = String::from("<robot name=\"deep\">");
    s.push_str(&"<a>".repeat(levels));
    s.push_str(&"</a>".repeat(levels));
    s.push_str("</robot>");
    s
}

#[test]
fn deeply_nested_urdf_is_refused_not_a_crash() {
    // The reported file: 50 000 nested elements, about 350 KB. Before the check this aborted
    // the process with a stack overflow inside the URDF parser.
    let xml = nested(50_000);
    assert!(xml.len() > 350_000);
    let err = RobotModel::from_urdf_str(&xml, &LoadOptions::default()).unwrap_err();
    let ModelError::InputRefused(UrdfInputError::TooDeep { line, column, limit_depth }) = &err else {
        panic!("expected TooDeep, got {err:?}");
    };
    assert_eq!((*line, *limit_depth), (1, MAX_URDF_NESTING_DEPTH));
    // `<robot ...>` is 19 characters, then `<a>` × 63 reach depth 64; the 64th `<a>` is too deep.
    assert_eq!(*column, 20 + 3 * 63);
    let msg = err.to_string();
    assert!(msg.contains("deeper than 64 levels at line 1, column 209"), "{msg}");
}

#[test]
fn nesting_at_the_limit_reaches_the_parser_and_one_more_is_refused() {
    let at_limit = nested(MAX_URDF_NESTING_DEPTH - 1);
    assert_eq!(xml_nesting_depth(&at_limit), MAX_URDF_NESTING_DEPTH);
    // Allowed through the check; the parser then finds no links.
    let r = RobotModel::from_urdf_str(&at_limit, &LoadOptions::default());
    assert!(matches!(r, Err(ModelError::NoLinks(_))), "{r:?}");
    let over = nested(MAX_URDF_NESTING_DEPTH);
    assert!(matches!(check_urdf_input(&over), Err(UrdfInputError::TooDeep { .. })));
}

#[test]
fn oversized_urdf_is_refused_with_the_limit_in_the_message() {
    let mut xml = String::from("<robot name=\"big\"><!--");
    xml.push_str(&" ".repeat(MAX_URDF_BYTES));
    xml.push_str("--></robot>");
    let err = RobotModel::from_urdf_str(&xml, &LoadOptions::default()).unwrap_err();
    assert_eq!(
        err,
        ModelError::InputRefused(UrdfInputError::TooLarge { size_bytes: xml.len(), limit_bytes: MAX_URDF_BYTES })
    );
    assert!(err.to_string().contains("limit is 8388608 bytes (8 MiB)"), "{err}");
    // Exactly at the limit is allowed through.
    let mut at_limit = String::from("<robot/>");
    at_limit.push_str(&" ".repeat(MAX_URDF_BYTES - at_limit.len()));
    assert_eq!(check_urdf_input(&at_limit), Ok(()));
}

#[test]
fn embedded_parol6_passes_the_check_and_loads() {
    assert_eq!(check_urdf_input(PAROL6_URDF), Ok(()));
    let depth = xml_nesting_depth(PAROL6_URDF);
    assert!((3..10).contains(&depth), "{depth}");
    assert_eq!(RobotModel::parol6().dof(), 6);
}

#[test]
fn scan_skips_quotes_comments_cdata_and_instructions() {
    let xml = r#"<?xml version="1.0"?>
<!DOCTYPE robot [ <!ELEMENT robot ANY> <!ENTITY x "<a><a>"> ]>
<robot name="q<a>">
  <!-- <a><a><a> -->
  <link name='x>y'><![CDATA[<a><a><a>]]><?pi <a><a> ?></link>
  <link name="self" />
</robot>"#;
    assert_eq!(xml_nesting_depth(xml), 2);
}

#[test]
fn scan_counts_unreadable_markup_as_opening() {
    // `< b` is not a tag for XML, but counting it errs on the side of refusing.
    assert_eq!(xml_nesting_depth("<a>< b>< c>"), 3);
    assert_eq!(xml_nesting_depth("<a></a><b/><c></c>"), 1);
    // Stray end tags never make the depth negative.
    assert_eq!(xml_nesting_depth("</a></a><b><c>"), 2);
}

#[test]
fn unterminated_constructs_stop_the_scan_without_panic() {
    for text in ["<a", "<a b=\"", "<!--", "<![CDATA[", "<?x", "<!DOCTYPE [", "</", "<", ""] {
        assert_eq!(check_urdf_input(text), Ok(()), "{text:?}");
    }
}

#[test]
fn too_deep_reports_line_and_character_column() {
    let mut xml = String::from("<robot>\n  <link name=\"é\">\n");
    xml.push_str(&"<x>".repeat(MAX_URDF_NESTING_DEPTH));
    let err = check_urdf_input(&xml).unwrap_err();
    // robot and link are levels 1 and 2; the 63rd `<x>` on line 3 is level 65.
    assert_eq!(err, UrdfInputError::TooDeep { line: 3, column: 1 + 3 * 62, limit_depth: MAX_URDF_NESTING_DEPTH });
}
