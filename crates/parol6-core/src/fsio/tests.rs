#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::ffi::CString;
use std::os::unix::ffi::OsStrExt;
use std::time::{Duration, Instant};

use super::*;

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-fsio-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names in `dir` other than `keep`.
fn leftovers(dir: &Path, keep: &[&str]) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !keep.contains(&n.as_str()))
        .collect()
}

fn mkfifo(path: &Path) {
    let c = CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: `c` is a valid NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0, "mkfifo {}", path.display());
}

#[test]
fn writes_a_new_file_and_replaces_an_old_one_leaving_no_temp_file() {
    let dir = scratch("replace");
    let p = dir.join("out.gcode");
    write_atomic_bytes(&p, b"first").unwrap();
    assert_eq!(std::fs::read(&p).unwrap(), b"first");
    write_atomic(&p, |w| w.write_all(b"second, longer")).unwrap();
    assert_eq!(std::fs::read(&p).unwrap(), b"second, longer");
    assert!(leftovers(&dir, &["out.gcode"]).is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_full_disk_keeps_the_old_file() {
    let dir = scratch("enospc");
    let p = dir.join("prog.json");
    let new = vec![b'n'; 20_000];
    for at in [0_u64, 1, 4095, 4096, 8192, 19_999] {
        std::fs::write(&p, b"old content").unwrap();
        let faults = Faults { enospc_at_byte: Some(at), ..Faults::default() };
        let err = write_atomic_with_faults(&p, faults, |w| w.write_all(&new)).unwrap_err();
        assert_eq!(err.io_error().and_then(io::Error::raw_os_error), Some(libc::ENOSPC), "{err}");
        assert!(err.to_string().contains("nothing was replaced"), "{err}");
        assert_eq!(std::fs::read(&p).unwrap(), b"old content", "ENOSPC at byte {at}");
        assert!(leftovers(&dir, &["prog.json"]).is_empty(), "temp left at byte {at}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn short_writes_still_write_everything() {
    let dir = scratch("short");
    let p = dir.join("a.csv");
    let new: Vec<u8> = (0..50_000_u32).map(|i| (i % 251) as u8).collect();
    let faults = Faults { max_write_bytes: Some(7), ..Faults::default() };
    write_atomic_with_faults(&p, faults, |w| w.write_all(&new)).unwrap();
    assert_eq!(std::fs::read(&p).unwrap(), new);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_rename_or_sync_or_encoder_keeps_the_old_file_and_removes_the_temp_file() {
    let dir = scratch("rename");
    let p = dir.join("r.svg");
    std::fs::write(&p, b"old").unwrap();
    for faults in [Faults { fail_rename: true, ..Faults::default() }, Faults { fail_sync: true, ..Faults::default() }] {
        assert!(write_atomic_with_faults(&p, faults, |w| w.write_all(b"new")).is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert!(leftovers(&dir, &["r.svg"]).is_empty());
    }
    let err = write_atomic(&p, |w| {
        w.write_all(b"half")?;
        Err(io::Error::other("encoder failed"))
    })
    .unwrap_err();
    assert!(err.to_string().contains("encoder failed"), "{err}");
    assert_eq!(std::fs::read(&p).unwrap(), b"old");
    assert!(leftovers(&dir, &["r.svg"]).is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_panic_while_writing_leaves_no_temp_file() {
    let dir = scratch("panic");
    let p = dir.join("x.txt");
    let caught = std::panic::catch_unwind(|| {
        let _ = write_atomic(&p, |w| {
            w.write_all(b"abc")?;
            panic!("encoder bug");
        });
    });
    assert!(caught.is_err());
    assert!(leftovers(&dir, &[]).is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_device_fifo_or_directory_target_is_refused_not_replaced() {
    let dir = scratch("device");
    let fifo = dir.join("pipe.gcode");
    mkfifo(&fifo);
    let sub = dir.join("sub.csv");
    std::fs::create_dir(&sub).unwrap();
    for (p, kind) in [(Path::new("/dev/full"), "a character device"), (&fifo, "a FIFO"), (&sub, "a directory")] {
        let err = write_atomic_bytes(p, b"x").unwrap_err();
        assert!(matches!(err, FsioError::NotRegular { kind: k, .. } if k == kind), "{p:?}: {err}");
        assert!(err.is_refusal());
    }
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device());
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(leftovers(&dir, &["pipe.gcode", "sub.csv"]).is_empty());
    // Under a path that is not a directory: an I/O error, nothing created.
    assert!(matches!(write_atomic_bytes(Path::new("/dev/full/x.gcode"), b"x"), Err(FsioError::Write { .. })));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_symlink_target_keeps_the_link_and_replaces_the_file_with_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("symlink");
    let real = dir.join("real.json");
    std::fs::write(&real, b"old").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    write_atomic_bytes(&link, b"new").unwrap();
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(std::fs::read(&real).unwrap(), b"new");
    assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o640);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn reading_refuses_fifos_devices_and_directories_promptly() {
    let dir = scratch("read");
    let fifo = dir.join("mesh.stl");
    mkfifo(&fifo);
    let zero_link = dir.join("prog.gcode");
    std::os::unix::fs::symlink("/dev/zero", &zero_link).unwrap();
    let t0 = Instant::now();
    for p in [fifo.as_path(), Path::new("/dev/zero"), Path::new("/dev/urandom"), &zero_link, &dir] {
        let err = read_regular_bounded(p, 1 << 20).unwrap_err();
        assert!(matches!(err, FsioError::NotRegular { .. }), "{p:?}: {err}");
        assert!(err.to_string().contains(&p.display().to_string()), "{err}");
        assert!(open_regular(p).is_err());
    }
    assert!(t0.elapsed() < Duration::from_secs(1));
    assert!(matches!(read_regular_bounded(&dir.join("missing"), 10), Err(FsioError::Read { .. })));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn reading_is_bounded() {
    let dir = scratch("bound");
    let p = dir.join("big.csv");
    std::fs::write(&p, vec![b'a'; 1000]).unwrap();
    assert_eq!(read_regular_bounded(&p, 1000).unwrap().len(), 1000);
    assert!(matches!(read_regular_bounded(&p, 999), Err(FsioError::TooLarge { max_bytes: 999, .. })));
    std::fs::write(&p, [b'a', 0xff]).unwrap();
    let err = read_regular_bounded_string(&p, 10).unwrap_err();
    assert!(err.to_string().contains("offset 1"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
