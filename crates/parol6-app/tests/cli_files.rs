//! Files in and out through the built binary (issue 29 items 1, 2, 8 and `--record -` of 14):
//! every output is written atomically (a failed save keeps the old file and leaves no temporary
//! file; a FIFO or device target is refused, not replaced), `mcap csv` never empties its input
//! or an existing CSV, and every input is a regular file read through a bound (a FIFO, a device
//! or a symlink to one is refused at once, naming the file).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use cli_support::{Run, exe, run_in, workspace_root};

const LIMIT: Duration = Duration::from_secs(60);

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-cli-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

/// A G-code program of the committed corpus.
fn gcode_fixture() -> PathBuf {
    workspace_root().join("tests/fixtures/gcode/valid/full_circle_inch.gcode")
}

/// A one-second recording of the simulation moving (`record --demo`), made in `dir`.
fn recording(dir: &Path) -> PathBuf {
    let r = run_in(dir, &["record", "--seconds", "1", "--demo", "-o", "rec.mcap"], LIMIT);
    assert_eq!(r.code(), Some(0), "{r:?}");
    dir.join("rec.mcap")
}

/// Runs `parol6 args…` in `dir` with files limited to 512 bytes (`ulimit -f 1`, SIGXFSZ
/// ignored): a write past that fails with EFBIG as on a full disk.
fn run_with_small_disk(dir: &Path, args: &[&str]) -> Run {
    let mut all = vec!["-c", "ulimit -f 1; trap '' XFSZ; exec \"$0\" \"$@\"", exe()];
    all.extend_from_slice(args);
    let started = std::time::Instant::now();
    let out = Command::new("sh").args(&all).current_dir(dir).output().unwrap();
    Run {
        status: Some(out.status),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        elapsed: started.elapsed(),
    }
}

#[test]
fn convert_to_a_full_disk_keeps_the_old_file() {
    let dir = scratch("full-disk");
    let rec = recording(&dir);
    std::fs::write(dir.join("out.gcode"), "; the old program\n").unwrap();
    let r = run_with_small_disk(&dir, &["program", "convert", rec.to_str().unwrap(), "out.gcode"]);
    r.assert_no_panic("convert on a full disk");
    assert_eq!(std::fs::read_to_string(dir.join("out.gcode")).unwrap(), "; the old program\n", "{r:?}");
    assert_eq!(r.code(), Some(1), "an I/O failure: {r:?}");
    assert!(r.stderr.contains("out.gcode") && r.stderr.contains("nothing was replaced"), "{r:?}");
    assert_eq!(names(&dir), ["out.gcode", "rec.mcap"], "no temporary file left");
    // With room, the same command replaces it.
    let r = run_in(&dir, &["program", "convert", "rec.mcap", "out.gcode"], LIMIT);
    assert_eq!(r.code(), Some(0), "{r:?}");
    assert!(std::fs::read_to_string(dir.join("out.gcode")).unwrap().contains("G1"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_save_left_a_saving_file() {
    let dir = scratch("saving");
    std::fs::write(dir.join("out.json"), "{}\n").unwrap();
    let fixture = gcode_fixture();
    let r = run_with_small_disk(&dir, &["program", "convert", fixture.to_str().unwrap(), "out.json"]);
    r.assert_no_panic("convert to JSON on a full disk");
    assert_eq!(r.code(), Some(1), "{r:?}");
    assert_eq!(std::fs::read_to_string(dir.join("out.json")).unwrap(), "{}\n");
    assert_eq!(names(&dir), ["out.json"], "no temporary file left");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn convert_to_a_device_or_fifo_is_refused_not_replaced() {
    let dir = scratch("device");
    // A device node named like a program (as /dev/full.gcode would be), and a FIFO.
    assert!(Command::new("mknod").arg(dir.join("full.gcode")).args(["c", "1", "7"]).status().unwrap().success());
    mkfifo(&dir.join("fifo.gcode"));
    std::fs::create_dir(dir.join("folder.gcode")).unwrap();
    let fixture = gcode_fixture();
    for (out, kind) in [("full.gcode", "a character device"), ("fifo.gcode", "a FIFO"), ("folder.gcode", "a directory")]
    {
        let r = run_in(&dir, &["program", "convert", fixture.to_str().unwrap(), out], LIMIT);
        r.assert_refused(out, &format!("{out}: refused, it is {kind}, not a regular file"));
    }
    let rec = recording(&dir);
    let r = run_in(&dir, &["program", "convert", rec.to_str().unwrap(), "fifo.gcode"], LIMIT);
    r.assert_refused("recording to a FIFO", "it is a FIFO");
    assert!(std::fs::metadata(dir.join("full.gcode")).unwrap().file_type().is_char_device());
    assert!(std::fs::metadata(dir.join("fifo.gcode")).unwrap().file_type().is_fifo());
    assert_eq!(names(&dir), ["fifo.gcode", "folder.gcode", "full.gcode", "rec.mcap"], "no temporary file left");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mcap_csv_onto_its_own_recording_emptied_it() {
    let dir = scratch("csv-self");
    let rec = recording(&dir);
    let before = std::fs::read(&rec).unwrap();
    std::fs::hard_link(&rec, dir.join("same.mcap")).unwrap();
    std::os::unix::fs::symlink(&rec, dir.join("link.csv")).unwrap();
    for out in ["rec.mcap", "./rec.mcap", "same.mcap", "link.csv"] {
        let r = run_in(&dir, &["mcap", "csv", "rec.mcap", "-o", out], LIMIT);
        r.assert_refused(out, "that is the recording being read");
        assert_eq!(std::fs::read(&rec).unwrap(), before, "{out}: the recording changed");
    }
    let r = run_in(&dir, &["mcap", "csv", "rec.mcap", "-o", "rec.csv"], LIMIT);
    assert!(r.json("csv")["rows"].as_u64().unwrap() > 100, "{r:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mcap_csv_of_a_bad_recording_emptied_the_existing_csv() {
    let dir = scratch("csv-bad");
    std::fs::write(dir.join("existing.csv"), "t_s,seq\n0,1\n").unwrap();
    std::fs::write(dir.join("bad.mcap"), b"\x89MCAP0\r\n but then garbage").unwrap();
    std::fs::write(dir.join("empty.mcap"), b"").unwrap();
    for input in ["bad.mcap", "empty.mcap", "missing.mcap"] {
        let r = run_in(&dir, &["mcap", "csv", input, "-o", "existing.csv"], LIMIT);
        r.assert_no_panic(input);
        assert_ne!(r.code(), Some(0), "{input}: {r:?}");
        assert_eq!(std::fs::read_to_string(dir.join("existing.csv")).unwrap(), "t_s,seq\n0,1\n", "{input}");
    }
    assert_eq!(names(&dir), ["bad.mcap", "empty.mcap", "existing.csv"], "no temporary file left");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_program_symlinked_to_dev_zero_is_refused_promptly() {
    let dir = scratch("zero");
    for name in ["zero.gcode", "zero.json", "zero.csv", "zero.txt"] {
        std::os::unix::fs::symlink("/dev/zero", dir.join(name)).unwrap();
        let r = run_in(&dir, &["program", "check", name], Duration::from_secs(20));
        r.assert_refused(name, &format!("{name}: refused, it is a character device, not a regular file"));
        assert!(r.elapsed < Duration::from_secs(5), "{name}: took {:?}", r.elapsed);
    }
    mkfifo(&dir.join("fifo.gcode"));
    let r = run_in(&dir, &["program", "check", "fifo.gcode"], Duration::from_secs(20));
    r.assert_refused("FIFO program", "fifo.gcode: refused, it is a FIFO");
    let r = run_in(&dir, &["mcap", "info", "/dev/zero"], Duration::from_secs(20));
    r.assert_refused("mcap info /dev/zero", "/dev/zero: refused, it is a character device");
    let r = run_in(&dir, &["--urdf", "/dev/zero", "fk", "--joints", "0"], Duration::from_secs(20));
    r.assert_refused("--urdf /dev/zero", "it is a character device, not a regular file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_fifo_mesh_blocked_the_simulation_forever() {
    let dir = scratch("fifo-mesh");
    mkfifo(&dir.join("mesh.stl"));
    let urdf = r#"<robot name="r">
 <link name="base"><visual><geometry><mesh filename="mesh.stl"/></geometry></visual>
  <collision><geometry><mesh filename="mesh.stl"/></geometry></collision></link>
 <link name="tip"><collision><geometry><mesh filename="/dev/zero"/></geometry></collision>
  <visual><geometry><mesh filename="/dev/urandom"/></geometry></visual></link>
 <joint name="j1" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#;
    std::fs::write(dir.join("r.urdf"), urdf).unwrap();
    // `record` builds the simulation with its collision shapes from the mesh files.
    let r = run_in(&dir, &["--urdf", "r.urdf", "record", "--seconds", "0.2", "-o", "r.mcap"], Duration::from_secs(30));
    r.assert_no_panic("record with a FIFO mesh");
    assert_eq!(r.code(), Some(0), "{r:?}");
    assert!(r.elapsed < Duration::from_secs(10), "took {:?}", r.elapsed);
    assert!(r.stderr.contains("mesh \"mesh.stl\" not read") && r.stderr.contains("it is a FIFO"), "{r:?}");
    assert!(r.stderr.contains("/dev/zero: refused, it is a character device"), "{r:?}");
    assert!(!r.stderr.contains("not found"), "the file is there, and is not read: {r:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn record_to_dash_wrote_a_file_named_dash() {
    let dir = scratch("dash");
    let rec = recording(&dir);
    let program = workspace_root().join("tests/fixtures/gcode/valid/full_circle_inch.gcode");
    let cases: Vec<Vec<&str>> = vec![
        vec!["record", "--seconds", "0.1", "-o", "-"],
        vec!["program", "run", program.to_str().unwrap(), "--record", "-"],
        vec!["--fake-robot", "hw", "jog", "--joint", "1", "--speed", "0.1", "--seconds", "0.1", "--record", "-"],
        vec!["--fake-robot", "hw", "move", "--joints", "90,-90,180,0,0,180", "--deg", "--record", "-"],
        vec!["--record", "-"],
        vec!["mcap", "csv", rec.to_str().unwrap(), "-o", "-"],
        vec!["bench", "replay", "--keep", "-"],
        vec!["screenshot", "-"],
    ];
    for args in &cases {
        let r = run_in(&dir, args, LIMIT);
        r.assert_refused(&format!("{args:?}"), "\"-\" is refused");
    }
    assert_eq!(names(&dir), ["rec.mcap"], "no file named -");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 29 item 1, the last in-place write: `record -o` over an existing recording truncated it
/// before the first sample, so a crash lost the old recording; a FIFO as the output blocked the
/// start until a reader came, and a device node was written. Now the new recording is made
/// beside the old one and replaces it only when finished, and a FIFO or device is refused.
#[test]
fn a_recording_over_an_existing_one_lost_it_on_a_crash() {
    let dir = scratch("record-over");
    let rec = recording(&dir);
    let old = std::fs::read(&rec).unwrap();
    let mut child = Command::new(exe())
        .args(["record", "--seconds", "60", "--demo", "-o", "rec.mcap"])
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let beside = dir.join("rec.mcap.recording");
    let started = std::time::Instant::now();
    while std::fs::metadata(&beside).map_or(0, |m| m.len()) < 20_000 {
        assert!(started.elapsed() < LIMIT, "the recording did not start beside the old one");
        std::thread::sleep(Duration::from_millis(50));
    }
    child.kill().unwrap(); // SIGKILL: a crash
    child.wait().unwrap();
    assert_eq!(std::fs::read(&rec).unwrap(), old, "the old recording is whole");
    let r = run_in(&dir, &["mcap", "info", "rec.mcap.recording"], LIMIT);
    assert_eq!(r.code(), Some(0), "the new one is readable: {r:?}");
    // finished normally, the new recording replaces the old one and nothing is left beside it
    std::fs::remove_file(&beside).unwrap();
    let r = run_in(&dir, &["record", "--seconds", "0.5", "--demo", "-o", "rec.mcap"], LIMIT);
    assert_eq!(r.code(), Some(0), "{r:?}");
    assert_ne!(std::fs::read(&rec).unwrap(), old);
    assert_eq!(names(&dir), ["rec.mcap"]);
    // a FIFO or a device node is refused at once (exit 2) and left as it was
    mkfifo(&dir.join("fifo.mcap"));
    assert!(Command::new("mknod").arg(dir.join("full.mcap")).args(["c", "1", "7"]).status().unwrap().success());
    for (out, kind) in [("fifo.mcap", "a FIFO"), ("full.mcap", "a character device")] {
        let r = run_in(&dir, &["record", "--seconds", "0.5", "--demo", "-o", out], LIMIT);
        r.assert_refused(out, &format!("{out}: refused, it is {kind}, not a regular file"));
    }
    assert!(std::fs::metadata(dir.join("fifo.mcap")).unwrap().file_type().is_fifo());
    assert!(std::fs::metadata(dir.join("full.mcap")).unwrap().file_type().is_char_device());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 32 minor: "Save as `.gcode` of Pick & place refers to an option ("export with the
/// electric gripper") that the dialog lacks. Save as `.txt` silently writes electric-gripper
/// commands." The `.txt` conversion says what it wrote; the `.gcode` refusal names what to
/// change (the program's tool), an option that exists.
#[test]
fn converting_pick_and_place_says_what_it_made_of_the_gripper_steps() {
    let dir = scratch("gripper-words");
    let pick = workspace_root().join("assets/programs/pick_place.json");
    let pick = pick.to_str().unwrap();
    let r = run_in(&dir, &["program", "convert", pick, "pick.txt"], LIMIT);
    assert_eq!(r.code(), Some(0), "{r:?}");
    assert!(std::fs::read_to_string(dir.join("pick.txt")).unwrap().contains("Gripper("));
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    let notes = v["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{v}");
    assert!(notes[0].as_str().unwrap().contains("commands for the electric gripper"), "{v}");
    let r = run_in(&dir, &["program", "convert", pick, "pick.gcode"], LIMIT);
    assert_ne!(r.code(), Some(0), "{r:?}");
    assert!(!r.stderr.contains("export with the electric gripper"), "an option nobody offers: {r:?}");
    assert!(r.stderr.contains("program's tool") && r.stderr.contains("\"Ssg48\""), "{r:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
