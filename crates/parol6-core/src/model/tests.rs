use super::*;

fn load(xml: &str) -> Result<RobotModel, ModelError> {
    RobotModel::from_urdf_str(xml, &LoadOptions::default())
}

const LINK: &str = r#"<link name="{}"/>"#;

fn links(names: &[&str]) -> String {
    names.iter().map(|n| LINK.replace("{}", n)).collect()
}

fn rev(name: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
    )
}

#[test]
fn embedded_parol6_loads_cleanly() {
    let m = RobotModel::parol6();
    assert_eq!(m.dof(), 6);
    assert_eq!(m.joint_names(), ["J1", "J2", "J3", "J4", "J5", "J6"]);
    assert_eq!(m.root_link, "base_link");
    assert_eq!(m.tip_link, "L6");
    assert!(m.is_parol6);
    assert!(m.warnings.is_empty());
    assert_eq!(m.links.len(), 7);
    assert!(m.links.iter().all(|l| !l.visuals.is_empty() && !l.collisions.is_empty()));
    assert!(m.links.iter().all(|l| l.inertial.is_some()));
    for (l, (lo, hi)) in m.limits.iter().zip(crate::parol6::LIMITS_RAD) {
        // exactly the step limits (the URDF's rounded values are replaced)
        assert!((l.min - lo).abs() < 1e-15 && (l.max - hi).abs() < 1e-15, "{l:?}");
    }
}

#[test]
fn malformed_not_xml() {
    assert!(matches!(load("this is not xml"), Err(ModelError::NotUrdf(_))));
    assert!(matches!(load("<robot name='x'><link name="), Err(ModelError::XmlSyntax { line: 1, .. })));
}

#[test]
fn malformed_no_links() {
    assert!(matches!(load(r#"<robot name="empty"></robot>"#), Err(ModelError::NoLinks(n)) if n == "empty"));
}

#[test]
fn malformed_duplicate_link() {
    let x = format!(r#"<robot name="r">{}</robot>"#, links(&["a", "a"]));
    assert!(matches!(load(&x), Err(ModelError::DuplicateLink(n)) if n == "a"));
}

#[test]
fn malformed_missing_link() {
    let x = format!(r#"<robot name="r">{}{}</robot>"#, links(&["a"]), rev("j", "a", "ghost"));
    assert!(matches!(load(&x), Err(ModelError::MissingLink { link, role: "child", .. }) if link == "ghost"));
}

#[test]
fn malformed_several_roots() {
    let x = format!(r#"<robot name="r">{}{}</robot>"#, links(&["a", "b", "c"]), rev("j", "a", "b"));
    assert!(matches!(load(&x), Err(ModelError::SeveralRoots(r)) if r == ["a", "c"]));
}

#[test]
fn malformed_cycle() {
    let x = format!(
        r#"<robot name="r">{}{}{}{}</robot>"#,
        links(&["a", "b", "c"]),
        rev("j1", "a", "b"),
        rev("j2", "b", "c"),
        rev("j3", "c", "b")
    );
    assert!(matches!(load(&x), Err(ModelError::Cycle(_))));
    let loop_only =
        format!(r#"<robot name="r">{}{}{}</robot>"#, links(&["a", "b"]), rev("j1", "a", "b"), rev("j2", "b", "a"));
    assert!(matches!(load(&loop_only), Err(ModelError::Cycle(_))));
}

#[test]
fn malformed_no_movable_joint() {
    let x = format!(
        r#"<robot name="r">{}<joint name="f" type="fixed"><parent link="a"/><child link="b"/></joint></robot>"#,
        links(&["a", "b"])
    );
    assert!(matches!(load(&x), Err(ModelError::NoMovableJoint { .. })));
}

#[test]
fn malformed_tip_not_found_and_ambiguous_tip() {
    let x =
        format!(r#"<robot name="r">{}{}{}</robot>"#, links(&["a", "b", "c"]), rev("j1", "a", "b"), rev("j2", "a", "c"));
    assert!(matches!(load(&x), Err(ModelError::AmbiguousTip(_))));
    let opts = LoadOptions { tip: Some("nope".into()), ..Default::default() };
    assert!(matches!(RobotModel::from_urdf_str(&x, &opts), Err(ModelError::TipNotFound(t)) if t == "nope"));
    let opts = LoadOptions { tip: Some("c".into()), ..Default::default() };
    let m = RobotModel::from_urdf_str(&x, &opts).expect("explicit tip");
    assert_eq!(m.joint_names(), ["j2"]);
    assert_eq!(m.links.len(), 3, "the side branch is kept for display");
}

#[test]
fn malformed_inverted_limits_and_zero_axis() {
    let x = format!(
        r#"<robot name="r">{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/></joint></robot>"#,
        links(&["a", "b"])
    );
    assert!(matches!(load(&x), Err(ModelError::InvalidLimits { .. })));
    let y = x.replace(r#"lower="1" upper="-1""#, r#"lower="-1" upper="1""#).replace(r#"xyz="0 0 1""#, r#"xyz="0 0 0""#);
    assert!(matches!(load(&y), Err(ModelError::InvalidAxis(_))));
}

#[test]
fn malformed_unsupported_joint_type() {
    let x = format!(
        r#"<robot name="r">{}<joint name="j" type="floating"><parent link="a"/><child link="b"/></joint></robot>"#,
        links(&["a", "b"])
    );
    assert!(matches!(load(&x), Err(ModelError::UnsupportedJoint { .. })));
}

#[test]
fn missing_mesh_is_a_warning_with_resolved_path() {
    let x = format!(
        r#"<robot name="r"><link name="a"><visual><geometry><mesh filename="package://pkg/meshes/gone.stl"/></geometry></visual></link>{}{}</robot>"#,
        links(&["b"]),
        rev("j", "a", "b")
    );
    let opts = LoadOptions { base_dir: Some(PathBuf::from("/tmp/nowhere")), ..Default::default() };
    let m = RobotModel::from_urdf_str(&x, &opts).expect("kinematics still load");
    assert_eq!(m.dof(), 1);
    match m.warnings.as_slice() {
        [ModelError::MeshNotFound { resolved, uri, .. }] => {
            assert_eq!(resolved, &PathBuf::from("/tmp/nowhere/meshes/gone.stl"));
            assert_eq!(uri, "package://pkg/meshes/gone.stl");
        }
        other => panic!("unexpected warnings {other:?}"),
    }
    assert!(m.warnings[0].to_string().contains("/tmp/nowhere/meshes/gone.stl"));
}

#[test]
fn prismatic_and_continuous_joints() {
    let x = format!(
        r#"<robot name="r">{}<joint name="p" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint><joint name="c" type="continuous"><origin xyz="0 0 1"/><parent link="b"/><child link="c"/><axis xyz="0 1 0"/></joint></robot>"#,
        links(&["a", "b", "c"])
    );
    let m = load(&x).expect("loads");
    assert_eq!(m.joints[0].kind, JointKind::Prismatic);
    assert_eq!(m.joints[1].kind, JointKind::Continuous);
    assert!(m.limits.get(1).is_some_and(|l| !l.is_bounded()));
    let p = m.fk(&[0.3, 0.0]);
    assert!((p.position_m[0] - 0.3).abs() < 1e-12 && (p.position_m[2] - 1.0).abs() < 1e-12);
}

#[test]
fn srdf_pairs_are_read() {
    let mut m = RobotModel::parol6();
    let n = m.apply_srdf(r#"<robot><disable_collisions link1="base_link" link2="L4" reason="Never"/><disable_collisions link1="L1" link2="L5"/></robot>"#);
    assert_eq!(n, 2);
    assert_eq!(m.disabled_collision_pairs[1], ("L1".to_string(), "L5".to_string()));
}

#[test]
fn urdf_syntax_errors_name_the_line_and_column() {
    let xml = "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\">\n<joint name=\"j\" type=\"revolute\">\n<parent link=\"a\"/></joint></robot>\n";
    let e = load(xml).expect_err("not nested properly").to_string();
    assert!(e.contains("line 5, column"), "{e}");
    let xml = "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n<origin xyz=\"0 0 abc\"/></joint></robot>\n";
    let e = load(xml).expect_err("bad vector").to_string();
    assert!(e.contains("line 5:") && e.contains("0 0 abc"), "{e}");
}

#[test]
fn a_fifo_mesh_blocked_forever_and_was_called_not_found() {
    let dir = std::env::temp_dir().join(format!("parol6-fifo-mesh-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let fifo = dir.join("mesh.stl");
    let c = std::ffi::CString::new(fifo.to_string_lossy().as_bytes()).expect("path");
    // SAFETY: `c` is a valid NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let x = format!(
        r#"<robot name="r"><link name="a"><collision><geometry><mesh filename="mesh.stl"/></geometry></collision><visual><geometry><mesh filename="/dev/zero"/></geometry></visual></link>{}{}</robot>"#,
        links(&["b"]),
        rev("j", "a", "b")
    );
    let opts = LoadOptions { base_dir: Some(dir.clone()), ..Default::default() };
    let t0 = std::time::Instant::now();
    let m = RobotModel::from_urdf_str(&x, &opts).expect("kinematics still load");
    let text: Vec<String> = m.warnings.iter().map(ToString::to_string).collect();
    assert!(
        matches!(m.warnings.as_slice(), [ModelError::MeshRefused { .. }, ModelError::MeshRefused { .. }]),
        "{text:?}"
    );
    assert!(text[1].contains("mesh.stl: refused, it is a FIFO, not a regular file"), "{text:?}");
    assert!(text[0].contains("/dev/zero: refused, it is a character device"), "{text:?}");
    // Building the collision shapes reads the mesh files: refused at once, not blocked on.
    let guard = crate::collision::CollisionGuard::new(&m);
    drop(guard);
    assert!(read_mesh_file(&fifo).is_err());
    assert!(t0.elapsed() < std::time::Duration::from_secs(2), "took {:?}", t0.elapsed());
    let _ = std::fs::remove_dir_all(&dir);
}
