//! The Super key's state read from a real X server (Xvfb, started here): the hand trial found
//! that Super+D jogged +X under Xvfb, because egui reports Super only on macOS. The window now
//! reads Super from the X server (`app::super_key`); this presses and releases Super_L through
//! the server's XTEST extension and checks that the probe sees both.
//!
//! Needs `Xvfb` (package `xvfb`): without it the test fails when `CI` is set, else prints
//! SKIPPED.

#![cfg(target_os = "linux")]
#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::io::Read;
use std::process::{Command, Stdio};

use parol6_app::app::super_key::{SUPER_AFTERGLOW, SuperKeyProbe};
use x11rb::connection::Connection;
use x11rb::protocol::xproto::{ConnectionExt, KEY_PRESS_EVENT, KEY_RELEASE_EVENT};
use x11rb::protocol::xtest::ConnectionExt as _;

/// X keysym of the left Super key.
const SUPER_L: u32 = 0xffeb;

fn which(cmd: &str) -> bool {
    std::env::var_os("PATH").map(|paths| std::env::split_paths(&paths).any(|d| d.join(cmd).is_file())).unwrap_or(false)
}

/// Kills the X server when the test ends, however it ends.
struct Server(std::process::Child);

impl Drop for Server {
    fn drop(&mut self) {
        if let Err(e) = self.0.kill() {
            eprintln!("Xvfb already gone: {e}");
        }
        if let Err(e) = self.0.wait() {
            eprintln!("Xvfb not reaped: {e}");
        }
    }
}

/// Starts Xvfb on a free display; its name (":N").
fn start_xvfb() -> (Server, String) {
    let mut child = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "64x64x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start Xvfb");
    let mut out = child.stdout.take().expect("Xvfb's stdout");
    let server = Server(child);
    let mut number = String::new();
    let mut byte = [0u8; 1];
    while out.read(&mut byte).expect("read Xvfb's display number") == 1 && byte[0] != b'\n' {
        number.push(char::from(byte[0]));
    }
    assert!(!number.is_empty() && number.chars().all(|c| c.is_ascii_digit()), "display number {number:?}");
    (server, format!(":{number}"))
}

#[test]
fn the_probe_sees_super_pressed_and_released_on_the_x_server() {
    if !which("Xvfb") {
        if std::env::var_os("CI").is_some() {
            panic!("Xvfb is missing (install xvfb) and CI is set");
        }
        parol6_tests::skip_notice("SKIPPED: no Xvfb");
        return;
    }
    let (_server, display) = start_xvfb();
    let mut probe = SuperKeyProbe::connect_to(&display).expect("the probe connects");
    assert!(!probe.held().expect("query"), "Super is up at the start");

    // a second client, as the keyboard: find Super_L's keycode and press it through XTEST
    let (conn, screen) = x11rb::connect(Some(&display)).expect("the keyboard client connects");
    let root = conn.setup().roots[screen].root;
    let (min, max) = (conn.setup().min_keycode, conn.setup().max_keycode);
    let map = conn.get_keyboard_mapping(min, max - min + 1).expect("request").reply().expect("keyboard mapping");
    let per = usize::from(map.keysyms_per_keycode);
    let code = map
        .keysyms
        .chunks(per)
        .position(|syms| syms.contains(&SUPER_L))
        .map(|i| min + u8::try_from(i).expect("keycode"))
        .expect("Super_L has a keycode");
    let key = |kind: u8| {
        // check() waits for the server's answer: the key has been pressed when it returns
        let cookie = conn.xtest_fake_input(kind, code, x11rb::CURRENT_TIME, root, 0, 0, 0).expect("fake input");
        cookie.check().expect("the server took the key");
    };
    key(KEY_PRESS_EVENT);
    assert!(probe.held().expect("query"), "Super held");
    key(KEY_RELEASE_EVENT);
    std::thread::sleep(SUPER_AFTERGLOW + std::time::Duration::from_millis(50));
    assert!(!probe.held().expect("query"), "Super let go");

    // a chord faster than a frame (`xdotool key super+d`): Super is up again when the frame
    // that handles D looks, but the server reported it down in between
    std::thread::sleep(SUPER_AFTERGLOW);
    probe.observe().expect("events");
    key(KEY_PRESS_EVENT);
    key(KEY_RELEASE_EVENT);
    assert!(probe.held().expect("query"), "a Super press that is already over still counts");
    std::thread::sleep(SUPER_AFTERGLOW + std::time::Duration::from_millis(50));
    assert!(!probe.held().expect("query"), "and stops counting after the afterglow");
}
