use parol6_app::viewport::*;
use parol6_core::RobotModel;
#[test]
fn tmp_bench() {
    let model = RobotModel::parol6();
    for samples in [4u32, 1] {
        let mut r = OffscreenRenderer::with_sample_count(&model, 1280, 800, samples).unwrap();
        let far = parol6_core::na::Isometry3::translation(0.0, 0.0, -1000.0);
        let empty = SceneFrame { link_poses: vec![far; model.links.len()], link_zones: vec![None; model.links.len()], tcp: far, ghost_link_poses: None };
        let q = parol6_core::parol6::standby_rad();
        let full = SceneFrame::from_joints(&model, &q, None);
        let none = ViewportOptions { show_grid: false, show_trail: false, show_ghost: false, ..Default::default() };
        for (name, scene, opt) in [("empty", &empty, none), ("robot", &full, none), ("robot+grid", &full, ViewportOptions::default())] {
            let mut v = vec![];
            for _ in 0..15 { let t = std::time::Instant::now(); r.render(scene, &opt).unwrap(); v.push(t.elapsed().as_secs_f64()*1e3); }
            v.sort_by(f64::total_cmp);
            eprintln!("samples {samples} {name}: {:.1} ms", v[7]);
        }
    }
}
