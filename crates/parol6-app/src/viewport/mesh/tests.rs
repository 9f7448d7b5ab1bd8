use super::*;
use std::path::Path;

fn bounds(m: &CpuMesh) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for v in &m.vertices {
        for i in 0..3 {
            lo[i] = lo[i].min(v.position_m[i]);
            hi[i] = hi[i].max(v.position_m[i]);
        }
    }
    (lo, hi)
}

/// Signed volume by the divergence theorem: positive when the triangles wind outward.
fn volume(m: &CpuMesh) -> f64 {
    m.indices
        .chunks_exact(3)
        .map(|t| {
            let p = |i: u32| {
                let v = m.vertices[i as usize].position_m;
                Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)
            };
            p(t[0]).dot(&p(t[1]).cross(&p(t[2]))) / 6.0
        })
        .sum()
}

#[test]
fn primitives_have_the_right_size_volume_and_winding() {
    let c = [1.0; 4];
    let b = CpuMesh::cuboid([0.2, 0.1, 0.05], c);
    assert!((volume(&b) - 0.001).abs() < 1e-9);
    let (lo, hi) = bounds(&b);
    assert!((hi[0] - lo[0] - 0.2).abs() < 1e-6);
    let cyl = CpuMesh::cylinder(0.1, 0.3, c);
    let exact = std::f64::consts::PI * 0.01 * 0.3;
    assert!((volume(&cyl) - exact).abs() / exact < 0.01, "{}", volume(&cyl));
    let s = CpuMesh::sphere(0.1, c);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 1e-3;
    assert!((volume(&s) - exact).abs() / exact < 0.03, "{}", volume(&s));
    let cap = CpuMesh::capsule(0.1, 0.2, c);
    let exact = exact + std::f64::consts::PI * 0.01 * 0.2;
    assert!((volume(&cap) - exact).abs() / exact < 0.03, "{}", volume(&cap));
    let (lo, hi) = bounds(&cap);
    assert!((hi[2] - lo[2] - 0.4).abs() < 1e-6);
    assert!(CpuMesh::cone(0.1, 0.2, c).triangle_count() > 0);
    assert!(volume(&CpuMesh::axes_triad()) > 0.0);
}

#[test]
fn embedded_parol6_meshes_build_without_warnings() {
    let model = RobotModel::parol6();
    let m = ModelMeshes::build(&model);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert_eq!(m.visual.len(), model.links.len());
    assert!(m.visual.iter().all(|r| r.index_count > 0));
    let max = m.vertices.len() as i64;
    for r in m.visual.iter().chain(&m.collision).chain([&m.triad]) {
        for &i in &m.indices[r.first_index as usize..(r.first_index + r.index_count) as usize] {
            assert!((i as i64 + r.base_vertex as i64) < max);
        }
    }
}

#[test]
fn missing_and_broken_meshes_become_placeholders() {
    let dir = std::env::temp_dir().join(format!("parol6-mesh-test-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let broken = dir.join("broken.stl");
    let _ = std::fs::write(&broken, b"solid x\nfacet normal garbage\n");
    let urdf = format!(
        r#"<robot name="r">
          <link name="a"><visual><geometry><mesh filename="missing.stl"/></geometry></visual></link>
          <link name="b"><visual><geometry><mesh filename="{}"/></geometry></visual></link>
          <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        </robot>"#,
        broken.display()
    );
    let opts = parol6_core::model::LoadOptions { base_dir: Some(dir.clone()), ..Default::default() };
    let model = RobotModel::from_urdf_str(&urdf, &opts);
    let _ = std::fs::remove_dir_all(&dir);
    let model = match model {
        Ok(m) => m,
        Err(e) => panic!("test URDF must load: {e}"),
    };
    let m = ModelMeshes::build(&model);
    assert_eq!(m.warnings.len(), 2, "{:?}", m.warnings);
    assert!(m.visual.iter().all(|r| r.index_count == 36), "placeholders are cubes");
}

const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

const TRIANGLE_DAE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
<geometry id="tri" name="tri"><mesh>
  <source id="tri-pos"><float_array id="tri-pos-array" count="9">0 0 0 2 0 0 0 2 0</float_array>
    <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
      <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
    </accessor></technique_common></source>
  <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
  <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
</mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#tri"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##;

#[test]
fn obj_and_dae_files_load_scaled_with_normals() {
    let dir = std::env::temp_dir().join(format!("parol6-mesh-formats-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let obj = dir.join("tetra.obj");
    let dae = dir.join("tri.dae");
    let _ = std::fs::write(&obj, TETRA_OBJ);
    let _ = std::fs::write(&dae, TRIANGLE_DAE);
    let o = load_mesh_file(&obj, [0.001, 0.002, 0.003], [1.0; 4]);
    let d = load_mesh_file(&dae, [1.0, 1.0, 1.0], [1.0; 4]);
    let _ = std::fs::remove_dir_all(&dir);
    let o = o.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(o.triangle_count(), 4);
    let (lo, hi) = bounds(&o);
    assert!((hi[0] - 0.001).abs() < 1e-7 && (hi[1] - 0.002).abs() < 1e-7 && (hi[2] - 0.003).abs() < 1e-7);
    assert!(lo.iter().all(|v| v.abs() < 1e-9));
    for v in &o.vertices {
        let n = v.normal;
        assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-4, "{n:?}");
    }
    let d = d.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.triangle_count(), 1);
    let (_, hi) = bounds(&d);
    assert!((hi[0] - 2.0).abs() < 1e-6 && (hi[1] - 2.0).abs() < 1e-6);
}

#[test]
fn official_stl_urdf_loads_its_meshes_when_present() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/parol6/urdf/python-api/PAROL6.urdf");
    if !path.is_file() {
        parol6_tests::skip_notice(&format!("SKIPPED: {} not present", path.display()));
        return;
    }
    let model = match RobotModel::from_urdf_file(&path, None) {
        Ok(m) => m,
        Err(e) => panic!("official URDF must load: {e}"),
    };
    let m = ModelMeshes::build(&model);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert!(m.visual_triangle_count() > 10_000, "{}", m.visual_triangle_count());
    // STL in metres: the base fits in a 0.3 m box.
    let base = model.link_index("base_link").unwrap_or_else(|| panic!("no base_link"));
    let r = m.visual[base];
    let idx = &m.indices[r.first_index as usize..(r.first_index + r.index_count) as usize];
    let span = idx
        .iter()
        .map(|&i| m.vertices[(i as i64 + r.base_vertex as i64) as usize].position_m[0])
        .fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    assert!(span.1 - span.0 > 0.02 && span.1 - span.0 < 0.3, "{span:?}");
}
