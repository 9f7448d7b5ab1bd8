//! Issue 30: the window's *Share live* toggle (File menu and status bar) starts the Foxglove
//! WebSocket server on the active backend (the address shown while it is on, a client can
//! connect) and stops it; *Allow remote control* shows its banner while on, and each change is
//! an `/events` entry. Both start off.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use std::net::TcpStream;
use std::time::Duration;

use eframe::egui;
use egui_kittest::kittest::Queryable;
use ui_support::{app_harness, has_label, until};

/// True when something listens at `ws://HOST:PORT`.
fn listening(url: &str) -> bool {
    let addr = url.trim_start_matches("ws://").parse().expect("an address");
    TcpStream::connect_timeout(&addr, Duration::from_millis(500)).is_ok()
}

#[test]
fn share_live_starts_the_foxglove_server_shows_its_address_and_stops_it() {
    let mut h = app_harness(egui::vec2(1400.0, 900.0));
    assert_eq!(h.state().sharing_live(), None, "off at start");
    assert!(has_label(&h, "Share live"));
    // a free port (several tests run at once)
    h.state_mut().settings_mut().share_live_address = "127.0.0.1:0".into();
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Share live (Foxglove WebSocket)").click();
    until(&mut h, "the address in the status bar", 10.0, |h| has_label(h, "LIVE ws://127.0.0.1:"));
    let url = h.state().sharing_live().expect("sharing");
    assert!(url.starts_with("ws://127.0.0.1:") && !url.ends_with(":0"), "{url}");
    assert!(has_label(&h, &format!("sharing at {url}")), "the File menu shows it too");
    assert!(listening(&url), "nothing listens at {url}");
    // the status bar's toggle stops it
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    h.get_by_label(&format!("LIVE {url}")).click();
    until(&mut h, "sharing stopped", 10.0, |h| h.state().sharing_live().is_none());
    h.run_steps(2);
    assert!(!has_label(&h, "LIVE ws://"));
    assert!(!listening(&url), "{url} still listens");
    // and it starts again from the status bar
    h.get_by_label("Share live").click();
    until(&mut h, "sharing again", 10.0, |h| has_label(h, "LIVE ws://"));
    h.get_by_label(&format!("LIVE {}", h.state().sharing_live().unwrap())).click();
    until(&mut h, "sharing stopped again", 10.0, |h| h.state().sharing_live().is_none());
}

#[test]
fn remote_control_shows_a_banner_and_is_logged() {
    let mut h = app_harness(egui::vec2(1400.0, 900.0));
    assert!(!h.state().remote_control().allowed(), "off at start");
    assert!(!has_label(&h, "REMOTE CONTROL ON"));
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Allow remote control").click();
    until(&mut h, "the banner", 10.0, |h| has_label(h, "REMOTE CONTROL ON"));
    assert!(h.state().remote_control().allowed());
    until(&mut h, "the /events entry", 10.0, |h| {
        h.state().live_view().events.iter().any(|e| e.message == "remote control turned on")
    });
    // the banner turns it off
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    h.get_by_label_contains("REMOTE CONTROL ON").click();
    until(&mut h, "remote control off", 10.0, |h| !h.state().remote_control().allowed());
    h.run_steps(2);
    assert!(!has_label(&h, "REMOTE CONTROL ON"));
}
