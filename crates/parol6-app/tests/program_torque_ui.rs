//! Run confirmation: a program whose pre-flight warns of joint torque over the motor limits
//! (here on a PAROL6 with links four times as heavy) does not start on Run / F5 without a
//! question; Cancel leaves the arm still, "Run anyway" starts it. The bare PAROL6 runs the same
//! program without asking.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::time::Duration;

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui_support::{harness_with, has_label, launch_options, until};

use parol6_app::app::{LaunchOptions, Parol6App};
use parol6_core::RobotModel;

/// The app on `model` in a harness.
fn harness(model: RobotModel) -> Harness<'static, Parol6App> {
    harness_with(LaunchOptions { model, ..launch_options() }, egui::vec2(1280.0, 1400.0))
}

/// The embedded PAROL6 with every link four times as heavy.
fn heavy() -> RobotModel {
    let mut m = RobotModel::parol6();
    for l in &mut m.links {
        if let Some(i) = &mut l.inertial {
            i.mass_kg *= 4.0;
            i.inertia_kg_m2 *= 4.0;
        }
    }
    m
}

fn runs(h: &Harness<'_, Parol6App>) -> bool {
    has_label(h, "Draw: step") || has_label(h, "Draw: checking")
}

#[test]
fn a_run_over_the_motor_torque_asks_for_confirmation() {
    let mut h = harness(heavy());
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 20.0, |h| has_label(h, "pre-flight: ok,"));
    assert!(has_label(&h, "exceeds its motor limit"), "the torque warning is listed");
    // F5 (with the 3D view's focus, no field) asks first, and nothing moves
    h.get_by_label("Run (F5)").click();
    h.run_steps(3);
    assert!(h.state().program_panel().run_confirmation_open(), "no question");
    assert!(has_label(&h, "Joint torque over the motor limits"));
    assert!(has_label(&h, "Run anyway") && has_label(&h, "Cancel"));
    h.get_by_label("Cancel").click();
    h.run_steps(3);
    std::thread::sleep(Duration::from_millis(300));
    h.run_steps(2);
    assert!(!h.state().program_panel().run_confirmation_open());
    assert!(!runs(&h) && !h.state().backend().state().moving, "Cancel runs nothing");
    // asked again, "Run anyway" starts it
    h.key_press(egui::Key::F5);
    h.run_steps(3);
    assert!(h.state().program_panel().run_confirmation_open(), "F5 asks too");
    h.get_by_label("Run anyway").click();
    until(&mut h, "the run", 10.0, runs);
    h.get_by_label("Stop program").click();
    until(&mut h, "stopped", 10.0, |h| has_label(h, "stopped after"));
}

#[test]
fn a_run_within_the_motor_torque_starts_without_a_question() {
    let mut h = harness(RobotModel::parol6());
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 20.0, |h| has_label(h, "pre-flight: ok"));
    h.get_by_label("Run (F5)").click();
    h.run_steps(2);
    assert!(!h.state().program_panel().run_confirmation_open());
    until(&mut h, "the run", 10.0, runs);
    h.get_by_label("Stop program").click();
    until(&mut h, "stopped", 10.0, |h| has_label(h, "stopped after"));
}
