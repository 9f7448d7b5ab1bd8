//! The whole app in egui's kittest harness, shared by the UI tests: the embedded PAROL6 in
//! simulation, no settings file, MSAA 1, accessibility check off, three frames run.

#![allow(dead_code)]

use std::time::Instant;

use eframe::egui;
use egui_kittest::Harness;

use parol6_app::app::{LaunchOptions, Parol6App};
use parol6_core::RobotModel;

/// The app in a harness of `size` points.
pub fn app_harness(size: egui::Vec2) -> Harness<'static, Parol6App> {
    let opts = LaunchOptions {
        model: RobotModel::parol6(),
        connect: None,
        settings_path: None,
        test_script: None,
        started: Instant::now(),
        msaa_samples: 1,
        record: None,
        replay: None,
        recording_info: Default::default(),
    };
    let app = Parol6App::new(opts, None).expect("app");
    let mut h = Harness::builder()
        .with_size(size)
        .with_accessibility_check(false)
        .build_ui_state(|ui, app: &mut Parol6App| app.frame(ui), app);
    h.run_steps(3);
    h
}
