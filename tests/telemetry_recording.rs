//! Telemetry end to end: the 1 kHz simulation and the 100 Hz controller session (emulator),
//! each tapped into a recorder that writes an MCAP file, at the same time. Checks: no sample
//! dropped (the backends' tick numbers are contiguous in the files), every channel present
//! with its exact schema name and encodings, chunk CRCs valid (the `mcap` crate's own reader),
//! a summary with statistics and a chunk index, every JSON message carrying the fields its
//! JSON schema names with the right types, and a truncated copy still readable.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use parol6_core::RobotModel;
use parol6_core::model::PAROL6_URDF;
use parol6_core::motion::RobotBackend;
use parol6_core::sim::{SimConfig, SimHandle};
use parol6_core::telemetry::schema::schema_text;
use parol6_core::telemetry::{
    LinkHealth, Recorder, RecorderConfig, RecordingInfo, load_replay, load_whole_replay, read_recording,
};
use parol6_hw::session::{Session, SessionConfig};
use parol6_hw::{EmulatorConfig, EmulatorHandle};

const RECORD_S: f64 = 3.0;

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("parol6-telemetry-it-{}-{name}", std::process::id()))
}

fn info() -> RecordingInfo {
    RecordingInfo {
        app_version: "test".into(),
        tool: "none".into(),
        program: "integration".into(),
        urdf_text: PAROL6_URDF.into(),
        tracking: String::new(),
    }
}

/// Every property the JSON schema names is in the message, with the schema's type.
fn check_against_schema(schema: &serde_json::Value, msg: &serde_json::Value, at: &str) {
    if let Some(t) = schema.get("type") {
        let types: Vec<&str> = match t {
            serde_json::Value::String(s) => vec![s.as_str()],
            serde_json::Value::Array(a) => a.iter().filter_map(|v| v.as_str()).collect(),
            _ => panic!("{at}: bad type in schema"),
        };
        let ok = types.iter().any(|t| match *t {
            "object" => msg.is_object(),
            "array" => msg.is_array(),
            "string" => msg.is_string(),
            "number" => msg.is_number(),
            "integer" => msg.is_u64() || msg.is_i64(),
            "boolean" => msg.is_boolean(),
            "null" => msg.is_null(),
            _ => false,
        });
        assert!(ok, "{at}: {msg} is not {types:?}");
    }
    if let Some(one_of) = schema.get("oneOf").and_then(|v| v.as_array()) {
        assert!(one_of.iter().any(|alt| alt.get("const") == Some(msg)), "{at}: {msg} is none of {one_of:?}");
    }
    if let (Some(props), Some(obj)) = (schema.get("properties").and_then(|p| p.as_object()), msg.as_object()) {
        for (name, sub) in props {
            match obj.get(name) {
                Some(v) => check_against_schema(sub, v, &format!("{at}.{name}")),
                // our optional extras may be absent; Foxglove's fields never are
                None => assert!(
                    ["steps_per_s", "program_step", "worst_zone"].contains(&name.as_str()),
                    "{at}: field {name} missing in {msg}"
                ),
            }
        }
    }
    if let (Some(items), Some(arr)) = (schema.get("items"), msg.as_array()) {
        for (i, v) in arr.iter().enumerate() {
            check_against_schema(items, v, &format!("{at}[{i}]"));
        }
    }
}

/// Checks one recorded file; returns its `/joint_states` tick numbers.
fn check_file(path: &PathBuf, expect_link: bool) -> Vec<u64> {
    let bytes = std::fs::read(path).expect("file");
    // the mcap crate's own reader, chunk CRCs checked
    let stream =
        mcap::MessageStream::new_with_options(&bytes, mcap::read::Options::ValidateChunkCrcs.into()).expect("stream");
    let mut counts: BTreeMap<String, u64> = BTreeMap::new();
    let mut seqs = Vec::new();
    for m in stream {
        let m = m.expect("a valid message (CRC checked)");
        let schema = m.channel.schema.as_ref().expect("every channel has a schema");
        assert_eq!(m.channel.message_encoding, "json");
        assert_eq!(schema.encoding, "jsonschema");
        let expected_schema = match m.channel.topic.as_str() {
            "/tf" => "foxglove.FrameTransforms",
            "/tcp_pose" => "foxglove.PoseInFrame",
            "/events" => "foxglove.Log",
            "/joint_states" | "/joint_commands" => "parol6.JointState",
            "/robot_description" => "std_msgs/String",
            "/link" => "parol6.LinkHealth",
            other => panic!("unexpected topic {other}"),
        };
        assert_eq!(schema.name, expected_schema, "{}", m.channel.topic);
        let schema_json: serde_json::Value = serde_json::from_slice(&schema.data).expect("schema is JSON");
        assert_eq!(
            schema_json,
            serde_json::from_str::<serde_json::Value>(&schema_text(&schema.name).unwrap()).unwrap()
        );
        let msg: serde_json::Value = serde_json::from_slice(&m.data).expect("message is JSON");
        check_against_schema(&schema_json, &msg, &m.channel.topic);
        if m.channel.topic == "/tf" {
            let tfs = msg["transforms"].as_array().unwrap();
            assert_eq!(tfs.len(), 6);
            assert_eq!(tfs[0]["parent_frame_id"], "base_link");
            assert_eq!(tfs[5]["child_frame_id"], "L6");
        }
        if m.channel.topic == "/joint_states" {
            seqs.push(msg["seq"].as_u64().unwrap());
            assert_eq!(msg["name"].as_array().unwrap().len(), 6);
            assert_eq!(msg["position"].as_array().unwrap().len(), 6);
        }
        *counts.entry(m.channel.topic.clone()).or_default() += 1;
    }
    for topic in ["/robot_description", "/joint_states", "/joint_commands", "/tf", "/tcp_pose"] {
        assert!(counts.get(topic).copied().unwrap_or(0) > 0, "{}: no {topic} in {counts:?}", path.display());
    }
    assert_eq!(counts.contains_key("/link"), expect_link, "{counts:?}");
    assert_eq!(counts["/joint_states"], counts["/joint_commands"]);
    // summary: statistics and a chunk index (the file seeks)
    let summary = mcap::Summary::read(&bytes).expect("summary").expect("has a summary");
    let stats = summary.stats.expect("statistics");
    assert_eq!(stats.message_count, counts.values().sum::<u64>());
    assert!(!summary.chunk_indexes.is_empty());
    assert!(summary.chunk_indexes.iter().all(|c| c.compression == "zstd"));
    seqs
}

fn assert_contiguous(seqs: &[u64], what: &str) {
    assert!(seqs.windows(2).all(|w| w[1] == w[0] + 1), "{what}: tick numbers not contiguous");
}

#[test]
fn simulation_and_robot_record_every_sample_to_valid_mcap_files() {
    let model = RobotModel::parol6();
    let sim_rec = Recorder::start(model.clone(), RecorderConfig::default()).expect("recorder");
    let hw_rec = Recorder::start(model.clone(), RecorderConfig::default()).expect("recorder");
    let (sim_path, hw_path) = (temp("sim.mcap"), temp("hw.mcap"));
    sim_rec.start_recording(&sim_path, &info()).expect("sim file");
    hw_rec.start_recording(&hw_path, &info()).expect("hw file");

    let sim = SimHandle::spawn_with_tap(model, SimConfig::default(), Some(sim_rec.tap())).expect("sim");
    let emu = EmulatorHandle::spawn(EmulatorConfig::homed_at_standby()).expect("emulator");
    let cfg = SessionConfig { status_timeout: Duration::from_millis(500), ..SessionConfig::default() };
    let session = Session::open_with_tap(emu.path(), cfg, Some(hw_rec.tap())).expect("session");
    session.wait_until(Duration::from_secs(5), |s| s.status_frames >= 5).expect("status");
    session.jog(0, -0.3).expect("jog");
    let t0 = std::time::Instant::now();
    while t0.elapsed().as_secs_f64() < RECORD_S {
        sim_rec.observe_state(sim.state());
        hw_rec.observe_state(session.robot_state());
        let s = session.snapshot();
        hw_rec.set_link_health(LinkHealth {
            state: format!("{:?}", s.link),
            loop_rate_hz: s.loop_rate_hz,
            missing_replies: s.missing_replies,
            link_losses: s.link_losses,
            estop_pressed: s.estop_pressed,
        });
        if t0.elapsed().as_secs_f64() < 2.0 {
            let _ = session.jog(0, -0.3);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    drop(session);
    sim.shutdown();
    std::thread::sleep(Duration::from_millis(100));
    let (sim_stats, hw_stats) = (sim_rec.stats(), hw_rec.stats());
    let sim_summary = sim_rec.finish().expect("finish").expect("was recording");
    let hw_summary = hw_rec.finish().expect("finish").expect("was recording");
    eprintln!("simulation: {sim_stats:?}\nrobot: {hw_stats:?}");

    assert_eq!(sim_stats.missing_samples, 0, "simulation samples dropped");
    assert_eq!(hw_stats.missing_samples, 0, "robot samples dropped");
    assert_eq!(sim_stats.control_dropped + hw_stats.control_dropped, 0);
    // the simulation holds still here: every step while it settles, then every tenth (100 Hz)
    assert!(sim_summary.samples as f64 >= 0.8 * RECORD_S * 100.0, "{sim_summary:?}");
    assert!(hw_summary.samples as f64 >= 0.8 * RECORD_S * 100.0, "{hw_summary:?}");

    let sim_seqs = check_file(&sim_path, false);
    let hw_seqs = check_file(&hw_path, true);
    assert_eq!(sim_seqs.len() as u64, sim_summary.samples);
    assert_eq!(hw_seqs.len() as u64, hw_summary.samples);
    assert_contiguous(&sim_seqs, "simulation");
    assert_contiguous(&hw_seqs, "robot");

    // our reader agrees, and the robot's recording has step rates and no efforts
    let rec = read_recording(&std::fs::read(&hw_path).unwrap()).expect("read");
    assert!(rec.warnings.is_empty(), "{:?}", rec.warnings);
    assert!(rec.measured.iter().all(|m| m.effort.is_empty() && m.steps_per_s.as_ref().is_some_and(|s| s.len() == 6)));
    assert!(rec.measured.iter().any(|m| m.velocity[0] < -0.01), "the jog shows in the measured velocities");
    rec.check_robot(&RobotModel::parol6()).expect("PAROL6");

    // a copy cut short (a crash) reads as far as its complete chunks
    let bytes = std::fs::read(&sim_path).unwrap();
    let cut = read_recording(&bytes[..bytes.len() * 3 / 4]).expect("readable in part");
    assert!(cut.truncated && !cut.warnings.is_empty());
    assert!(!cut.measured.is_empty() && (cut.measured.len() as u64) < sim_summary.samples);
    assert!(cut.measured.iter().zip(&sim_seqs).all(|(m, &s)| m.seq == s), "a prefix of the samples");

    let _ = std::fs::remove_file(&sim_path);
    let _ = std::fs::remove_file(&hw_path);
}

/// The MCAP reader's fuzz seeds and every input that once failed (`fuzz/regressions/mcap_reader/`)
/// give a recording or a named error, never a panic, from the linear reader and from the
/// replay's parallel one (from memory and from a reader, which agree).
#[test]
fn fuzz_inputs_of_the_mcap_reader_read_without_panic() {
    let fuzz = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join("fuzz");
    let mut n = 0;
    for dir in ["seeds", "regressions"] {
        let Ok(entries) = std::fs::read_dir(fuzz.join(dir).join("mcap_reader")) else { continue };
        for e in entries.flatten() {
            let bytes = std::fs::read(e.path()).unwrap();
            let outcome = std::panic::catch_unwind(|| read_recording(&bytes).map(|r| r.measured.len()));
            assert!(outcome.is_ok(), "{} panics the reader", e.path().display());
            let model = RobotModel::parol6();
            let replay = std::panic::catch_unwind(|| {
                let in_memory = load_replay(&bytes, &model).map(|r| r.store.len());
                let from_reader = load_whole_replay(bytes.as_slice(), bytes.len() as u64, &model);
                (in_memory, from_reader.map(|r| r.map(|r| r.store.len())))
            });
            match replay {
                Ok((Ok(a), Some(Ok(b)))) => assert_eq!(a, b, "{}: memory and reader disagree", e.path().display()),
                Ok(_) => {}
                Err(_) => panic!("{} panics the replay", e.path().display()),
            }
            n += 1;
        }
    }
    assert!(n >= 5, "{n} inputs");
}
