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

/// A Zenoh peer of the test's own listening on a free loopback port, as the router would.
#[cfg(feature = "ros2")]
fn test_router() -> (zenoh::Session, String) {
    use zenoh::Wait;
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let endpoint = format!("tcp/127.0.0.1:{port}");
    let mut c = zenoh::Config::default();
    c.insert_json5("mode", "\"peer\"").unwrap();
    c.insert_json5("listen/endpoints", &format!("[\"{endpoint}\"]")).unwrap();
    c.insert_json5("scouting/multicast/enabled", "false").unwrap();
    (zenoh::open(c).wait().expect("the test's Zenoh session"), endpoint)
}

/// File → *Share over ROS 2* starts the node in the background (the window keeps drawing), a
/// Zenoh peer at the router's address sees its liveliness token and its `/joint_states`, and
/// the status bar's toggle stops it (the token goes).
#[cfg(feature = "ros2")]
#[test]
fn share_over_ros2_starts_the_node_a_zenoh_peer_sees_it_and_the_toggle_stops_it() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use zenoh::Wait;

    let (router, endpoint) = test_router();
    let states = Arc::new(AtomicUsize::new(0));
    let counted = Arc::clone(&states);
    let _sub = router
        .declare_subscriber("0/joint_states/**")
        .callback(move |_| {
            counted.fetch_add(1, Ordering::Relaxed);
        })
        .wait()
        .unwrap();
    let node_token = |router: &zenoh::Session| {
        let replies = router.liveliness().get("@ros2_lv/0/**").timeout(Duration::from_secs(2)).wait().unwrap();
        let mut keys = Vec::new();
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result() {
                keys.push(sample.key_expr().to_string());
            }
        }
        keys.iter().any(|k| k.contains("/NN/") && k.contains("/parol6"))
    };

    let mut h = app_harness(egui::vec2(1400.0, 900.0));
    assert_eq!(h.state().sharing_ros2(), None, "off at start");
    h.state_mut().settings_mut().ros2_router = endpoint.clone();
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Share over ROS 2 (Zenoh)").click();
    until(&mut h, "the node up", 20.0, |h| h.state().sharing_ros2().is_some());
    let address = h.state().sharing_ros2().unwrap();
    assert!(address.contains(&endpoint), "{address}");
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    assert!(has_label(&h, "ROS 2 ON"), "the status bar says so");
    until(&mut h, "joint states at the peer", 20.0, |_| states.load(Ordering::Relaxed) >= 10);
    assert!(node_token(&router), "the peer sees the node parol6's liveliness token");

    h.get_by_label("ROS 2 ON").click();
    until(&mut h, "the node stopped", 10.0, |h| h.state().sharing_ros2().is_none());
    h.run_steps(2);
    assert!(has_label(&h, "ROS 2") && !has_label(&h, "ROS 2 ON"));
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while node_token(&router) {
        assert!(std::time::Instant::now() < deadline, "the node's token is still declared");
    }
}

/// A router address that is not `tcp/ADDRESS:PORT` is refused with a notice; nothing starts.
#[test]
fn share_over_ros2_with_a_bad_router_address_says_why() {
    let mut h = app_harness(egui::vec2(1400.0, 900.0));
    h.state_mut().settings_mut().ros2_router = "udp/127.0.0.1:7447".into();
    h.get_by_label("ROS 2").click();
    until(&mut h, "the refusal", 10.0, |h| {
        h.state().notices().iter().any(|n| n.error && n.text.contains("udp/127.0.0.1:7447: only tcp/ADDRESS:PORT"))
    });
    h.run_steps(5);
    assert_eq!(h.state().sharing_ros2(), None);
    assert!(!has_label(&h, "ROS 2 starting…") && !has_label(&h, "ROS 2 ON"));
}
