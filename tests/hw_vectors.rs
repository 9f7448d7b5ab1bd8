//! Byte-exact checks of `parol6-hw` frames and parsers against the reference vectors
//! (`../shared/parol6/vectors/*.json`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use parol6_hw::frame::{CommandCode, CommandFields, CommandFrame, GripperCommand, ReceivedCommand, StatusFrame};
use parol6_hw::parser::{CommandParser, StatusParser};
use parol6_tests::{read_json, shared_dir};
use serde_json::Value;

fn hex(s: &str) -> Vec<u8> {
    let s: String = s.chars().filter(|c| !c.is_whitespace()).collect();
    (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex")).collect()
}

fn i32s(v: &Value) -> [i32; 6] {
    let a = v.as_array().expect("array");
    std::array::from_fn(|i| a[i].as_i64().expect("int") as i32)
}

fn int(v: &Value, key: &str) -> i64 {
    v[key].as_i64().unwrap_or_else(|| panic!("field {key}"))
}

fn vectors(name: &str) -> Option<Value> {
    let dir = shared_dir()?;
    Some(read_json(&dir.join("vectors").join(name)))
}

#[test]
fn command_frames_encode_and_decode_byte_exact() {
    let Some(doc) = vectors("command_frames.json") else { return };
    let list = doc["vectors"].as_array().expect("vectors");
    assert!(list.len() >= 9);
    for v in list {
        let name = v["name"].as_str().unwrap_or("?");
        let bytes = hex(v["hex"].as_str().expect("hex"));
        let f = &v["fields"];
        let fields = CommandFields {
            positions_steps: i32s(&f["positions_steps"]),
            speeds_steps_s: i32s(&f["speeds_steps_per_s"]),
            affected_joints: int(f, "affected_joint_byte") as u8,
            io_bits: int(f, "inout_byte") as u8,
            timeout: int(f, "timeout") as u8,
            gripper: GripperCommand {
                position: int(f, "gripper_position") as i16,
                speed: int(f, "gripper_speed") as i16,
                current_ma: int(f, "gripper_current") as i16,
                command_bits: int(f, "gripper_command") as u8,
                mode: int(f, "gripper_mode") as u8,
                id: int(f, "gripper_id") as u8,
            },
        };
        let code = CommandCode::from_byte(int(f, "command") as u8).expect("sendable code");
        // Encode.
        let encoded = CommandFrame { command: code, fields }.encode().expect("encode");
        assert_eq!(encoded.to_vec(), bytes, "encode {name}");
        // Decode.
        let d = ReceivedCommand::decode(&bytes).expect("decode");
        assert_eq!(d.code, code.byte(), "{name}");
        assert_eq!(d.fields, fields, "decode {name}");
        assert_eq!(d.crc_byte, int(f, "crc_byte") as u8);
        assert_eq!(d.out1(), int(f, "out1") == 1, "{name}");
        assert_eq!(d.out2(), int(f, "out2") == 1, "{name}");
        // The firmware-parser emulation decodes the same fields.
        let fw = CommandParser::new().feed(&bytes);
        assert_eq!(fw.len(), 1, "{name}");
        assert_eq!(fw[0].fields, fields, "fw decode {name}");
        let fwd = &v["firmware_decoded"];
        assert_eq!(fw[0].fields.positions_steps, i32s(&fwd["positions"]));
        assert_eq!(fw[0].fields.speeds_steps_s, i32s(&fwd["speeds"]));
    }
}

#[test]
fn status_frames_encode_and_decode_byte_exact() {
    let Some(doc) = vectors("status_frames.json") else { return };
    let list = doc["vectors"].as_array().expect("vectors");
    assert!(list.len() >= 5);
    for v in list {
        let name = v["name"].as_str().unwrap_or("?");
        let bytes = hex(v["hex"].as_str().expect("hex"));
        let f = &v["fields"];
        let s = StatusFrame::decode(&bytes).expect("decode");
        assert_eq!(s.positions_steps, i32s(&f["positions_steps"]), "{name}");
        assert_eq!(s.speeds_steps_s, i32s(&f["speeds_steps_per_s"]), "{name}");
        assert_eq!(i64::from(s.homed_bits), int(f, "homed_byte"));
        let homed: Vec<bool> = f["homed_joints"].as_array().expect("homed").iter().map(|b| b == 1).collect();
        assert_eq!(s.homed_joints().to_vec(), homed, "{name}");
        assert_eq!(i64::from(s.io_bits), int(f, "io_byte"));
        assert_eq!(s.in1(), int(f, "in1") == 1);
        assert_eq!(s.in2(), int(f, "in2") == 1);
        assert_eq!(s.out1(), int(f, "out1") == 1);
        assert_eq!(s.out2(), int(f, "out2") == 1);
        assert_eq!(s.estop_pressed(), f["estop_pressed"].as_bool().expect("estop"), "{name}");
        let temp: Vec<bool> = f["temperature_error_joints"].as_array().expect("t").iter().map(|b| b == 1).collect();
        assert_eq!(s.temperature_error_joints().to_vec(), temp);
        let pos: Vec<bool> = f["position_error_joints"].as_array().expect("p").iter().map(|b| b == 1).collect();
        assert_eq!(s.position_error_joints().to_vec(), pos);
        assert_eq!(i64::from(s.timing_ticks), int(f, "timing_ticks"));
        assert!((s.timing_s() - f["timing_seconds"].as_f64().expect("t")).abs() < 1e-8);
        assert_eq!(i64::from(s.timeout_error), int(f, "timeout_error"));
        assert_eq!(i64::from(s.echoed_command), int(f, "echoed_command"));
        assert_eq!(i64::from(s.gripper_id), int(f, "gripper_id"));
        assert_eq!(i64::from(s.gripper_position), int(f, "gripper_position"));
        assert_eq!(i64::from(s.gripper_speed), int(f, "gripper_speed"));
        assert_eq!(i64::from(s.gripper_current_ma), int(f, "gripper_current"));
        assert_eq!(i64::from(s.gripper_status), int(f, "gripper_status"));
        assert_eq!(i64::from(s.gripper_object_byte), int(f, "gripper_object_detection_byte"));
        assert_eq!(i64::from(s.gripper_object_code()), int(f, "gripper_object_code_msb_bits_0x20_0x10"));
        // Encode back: byte-exact.
        assert_eq!(s.encode().to_vec(), bytes, "re-encode {name}");
    }
}

#[test]
fn status_stream_matches_recommended_parser() {
    let Some(doc) = vectors("stream_controller_to_host.json") else { return };
    let Some(status_doc) = vectors("status_frames.json") else { return };
    let stream = hex(doc["stream_hex"].as_str().expect("stream"));
    let by_name = |n: &str| -> StatusFrame {
        let v = status_doc["vectors"]
            .as_array()
            .expect("vectors")
            .iter()
            .find(|v| v["name"] == n)
            .unwrap_or_else(|| panic!("vector {n}"));
        StatusFrame::decode(&hex(v["hex"].as_str().expect("hex"))).expect("decode")
    };
    let expected: Vec<StatusFrame> = doc["recommended_parser_frames"]
        .as_array()
        .expect("frames")
        .iter()
        .map(|n| by_name(n.as_str().expect("name")))
        .collect();
    assert_eq!(expected.len(), 4);
    // Whole, byte by byte and in odd chunks: same frames.
    for chunk in [stream.len(), 1, 7, 61] {
        let mut p = StatusParser::new();
        let mut got = Vec::new();
        for c in stream.chunks(chunk) {
            got.extend(p.feed(c));
        }
        assert_eq!(got, expected, "chunk {chunk}");
        assert!(p.stats().invalid_frames >= 1, "the corrupted frame is counted");
    }
}

#[test]
fn command_stream_matches_firmware_parser() {
    let Some(doc) = vectors("stream_host_to_controller.json") else { return };
    let stream = hex(doc["stream_hex"].as_str().expect("stream"));
    let expected: Vec<u8> = doc["firmware_accepted_command_codes"]
        .as_array()
        .expect("codes")
        .iter()
        .map(|c| c.as_u64().expect("code") as u8)
        .collect();
    for chunk in [stream.len(), 1, 13] {
        let mut p = CommandParser::new();
        let mut got = Vec::new();
        for c in stream.chunks(chunk) {
            got.extend(p.feed(c).into_iter().map(|c| c.code));
        }
        assert_eq!(got, expected, "chunk {chunk}");
    }
}
