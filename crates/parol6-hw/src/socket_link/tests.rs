#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use super::*;
use crate::emulator::{EmulatorConfig, EmulatorHandle};
use crate::frame::{CommandCode, CommandFields, CommandFrame};
use crate::parser::StatusParser;
use crate::units::STANDBY_STEPS;

/// Waits this long at most for a reply (generous: a loaded CI host).
const WAIT: Duration = Duration::from_secs(5);

fn idle_bytes() -> [u8; crate::frame::COMMAND_FRAME_SIZE] {
    let fields = CommandFields { positions_steps: STANDBY_STEPS, ..CommandFields::default() };
    CommandFrame { command: CommandCode::Idle, fields }.encode().expect("encode")
}

/// Writes one IDLE frame and returns the status reply.
fn ask(port: &mut dyn SerialPort) -> crate::StatusFrame {
    port.write_all(&idle_bytes()).expect("write");
    let mut parser = StatusParser::new();
    let mut buf = [0u8; 256];
    let end = Instant::now() + WAIT;
    while Instant::now() < end {
        match port.read(&mut buf) {
            Ok(0) => panic!("the emulator hung up"),
            Ok(n) => parser.push(&buf[..n]),
            Err(e) if e.kind() == ErrorKind::TimedOut => {}
            Err(e) => panic!("read: {e}"),
        }
        if let Some(s) = parser.next_frame() {
            return s;
        }
    }
    panic!("no reply within {WAIT:?}");
}

#[test]
fn the_fake_robot_is_a_socket_that_opens_as_a_serial_port() {
    let emu = EmulatorHandle::spawn_socket(EmulatorConfig::homed_at_standby()).expect("emulator");
    assert!(is_socket(emu.path()), "{} is not a socket", emu.path());
    let mode = std::fs::metadata(emu.path()).expect("metadata").permissions().mode();
    assert_eq!(mode & 0o077, 0, "others may connect: mode {mode:o}");
    let mut port = crate::ports::open_port(emu.path()).expect("open");
    assert_eq!(port.name().as_deref(), Some(emu.path()));
    assert_eq!(port.baud_rate().expect("baud"), crate::ports::BAUD_RATE);
    let s = ask(port.as_mut());
    assert_eq!(s.positions_steps, STANDBY_STEPS);
    assert_eq!(emu.snapshot().frames_accepted, 1);
}

#[test]
fn a_read_with_nothing_waiting_times_out_and_counts_what_waits() {
    let emu = EmulatorHandle::spawn_socket(EmulatorConfig::homed_at_standby()).expect("emulator");
    let mut port = crate::ports::open_port(emu.path()).expect("open");
    port.set_timeout(Duration::from_millis(20)).expect("timeout");
    assert_eq!(port.timeout(), Duration::from_millis(20));
    let mut buf = [0u8; 64];
    let e = port.read(&mut buf).expect_err("nothing was asked");
    assert_eq!(e.kind(), ErrorKind::TimedOut);
    assert_eq!(port.bytes_to_read().expect("bytes"), 0);
    // a reply waits in the socket: counted, then cleared
    port.write_all(&idle_bytes()).expect("write");
    let end = Instant::now() + WAIT;
    while port.bytes_to_read().expect("bytes") < 60 && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(port.bytes_to_read().expect("bytes"), 60, "one 60-byte status frame waits");
    port.clear(ClearBuffer::Input).expect("clear");
    assert_eq!(port.bytes_to_read().expect("bytes"), 0);
}

#[test]
fn a_host_that_reopens_the_port_is_served_and_the_board_keeps_its_state() {
    let emu = EmulatorHandle::spawn_socket(EmulatorConfig::homed_at_standby()).expect("emulator");
    let mut first = crate::ports::open_port(emu.path()).expect("open");
    ask(first.as_mut());
    drop(first);
    let mut second = crate::ports::open_port(emu.path()).expect("re-open");
    let s = ask(second.as_mut());
    assert_eq!(s.positions_steps, STANDBY_STEPS);
    assert_eq!(emu.snapshot().frames_accepted, 2, "the same board answered both");
}

#[test]
fn a_stopped_fake_robot_hangs_up_and_its_path_is_gone() {
    let emu = EmulatorHandle::spawn_socket(EmulatorConfig::homed_at_standby()).expect("emulator");
    let path = emu.path().to_string();
    let mut port = crate::ports::open_port(&path).expect("open");
    ask(port.as_mut());
    emu.stop();
    port.set_timeout(WAIT).expect("timeout");
    let mut buf = [0u8; 64];
    // end of file, as a tty's hang-up: the session reports the link lost
    assert_eq!(port.read(&mut buf).expect("read after stop"), 0);
    assert!(!Path::new(&path).exists(), "{path} left behind");
    let err = match crate::ports::open_port(&path) {
        Ok(_) => panic!("opened a stopped fake robot"),
        Err(e) => e,
    };
    assert!(matches!(err, HwError::PortOpen { .. }), "{err:?}");
}

#[test]
fn a_serial_device_path_is_not_taken_for_a_socket() {
    // A real board's port (a character device) keeps the serial path and its rules.
    assert!(!is_socket("/dev/null"));
    assert!(!is_socket("/dev/does-not-exist-parol6"));
    let server = SocketServer::bind().expect("bind");
    assert!(is_socket(server.path().to_str().expect("utf-8")));
}

/// A crashed process left its socket file in the temporary folder for good (issue 32's last
/// trial). The first fake robot of a process removes the files of processes that no longer
/// run; a live process's socket and any other file stay.
#[test]
fn the_socket_files_of_ended_processes_are_removed() {
    let dir = std::env::temp_dir().join(format!("parol6-stale-sockets-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // no process has the largest id; ours runs
    let stale = dir.join(format!("{SOCKET_PREFIX}{}-0.sock", u32::MAX));
    let ours = dir.join(format!("{SOCKET_PREFIX}{}-7.sock", std::process::id()));
    let not_a_socket = dir.join(format!("{SOCKET_PREFIX}{}-1.sock", u32::MAX));
    let _stale = UnixListener::bind(&stale).unwrap();
    let _ours = UnixListener::bind(&ours).unwrap();
    std::fs::write(&not_a_socket, b"x").unwrap();
    remove_stale_sockets(&dir);
    assert!(!stale.exists(), "the ended process's socket is removed");
    assert!(ours.exists(), "a running process's socket stays");
    assert!(not_a_socket.exists(), "a file that is no socket stays");
    std::fs::remove_dir_all(&dir).unwrap();
}
