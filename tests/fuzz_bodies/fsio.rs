//! Fuzz body of the atomic writer (`atomic_writer`): `parol6_core::fsio::write_atomic_with_faults`
//! under injected I/O errors (short writes, a full disk at any byte, a failed fsync, a failed
//! rename, the caller's encoder failing part-way). Whatever happens, the target holds either
//! its old content intact or the whole new content, never part of it, and no temporary file is
//! left beside it.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use parol6_core::fsio::{Faults, write_atomic_with_faults};

/// One scratch folder per process, on tmpfs where there is one (the writer fsyncs).
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let shm = Path::new("/dev/shm");
        let base = if shm.is_dir() { shm.to_path_buf() } else { std::env::temp_dir() };
        let dir = base.join(format!("parol6-fuzz-atomic-writer-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
        dir
    })
}

/// Names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()).unwrap_or_default())
        .collect();
    v.sort();
    v
}

/// Input layout: byte 0 flags (old file exists, fsync fails, rename fails, the encoder fails
/// after its writes, a full disk, short writes), bytes 1–2 the byte at which the disk is full
/// (big-endian), byte 3 the longest write the disk takes, byte 4 the size of the encoder's
/// writes, byte 5 how many times the new content is written (1–8, so that it outgrows the
/// 8 KiB buffer), byte 6 where the rest splits into old and new content.
pub fn atomic_writer(data: &[u8]) {
    let Some((head, rest)) = data.split_at_checked(7) else { return };
    let flags = head[0];
    let faults = Faults {
        max_write_bytes: (flags & 0x20 != 0).then_some(usize::from(head[3])),
        enospc_at_byte: (flags & 0x10 != 0).then_some(u64::from(u16::from_be_bytes([head[1], head[2]]))),
        fail_sync: flags & 0x02 != 0,
        fail_rename: flags & 0x04 != 0,
    };
    let encoder_fails = flags & 0x08 != 0;
    let chunk = usize::from(head[4]).max(1);
    let repeat = usize::from(head[5] % 8) + 1;
    let split = usize::from(head[6]).min(rest.len());
    let (old, one) = rest.split_at(split);
    let new: Vec<u8> = one.repeat(repeat);

    let dir = scratch();
    let target = dir.join("target.bin");
    if flags & 0x01 != 0 {
        std::fs::write(&target, old).unwrap_or_else(|e| panic!("cannot set up the old file: {e}"));
    } else if target.exists() {
        std::fs::remove_file(&target).unwrap_or_else(|e| panic!("cannot remove the old file: {e}"));
    }
    let had_old = flags & 0x01 != 0;

    let result = write_atomic_with_faults(&target, faults, |w| {
        for part in new.chunks(chunk) {
            w.write_all(part)?;
        }
        if encoder_fails { Err(io::Error::other("encoder failed")) } else { Ok(()) }
    });

    let after = names(dir);
    let full = faults.enospc_at_byte.is_some_and(|at| at < new.len() as u64);
    match &result {
        Ok(()) => {
            assert!(
                !encoder_fails && !faults.fail_sync && !faults.fail_rename && !full,
                "a save with a fault succeeded"
            );
            assert_eq!(std::fs::read(&target).ok().as_deref(), Some(new.as_slice()), "saved content differs");
            assert_eq!(after, ["target.bin"], "temporary file left after a save");
        }
        Err(e) => {
            assert!(encoder_fails || faults.fail_sync || faults.fail_rename || full, "unexpected failure: {e}");
            if had_old {
                assert_eq!(std::fs::read(&target).ok().as_deref(), Some(old), "old file changed by a failed save");
                assert_eq!(after, ["target.bin"], "temporary file left after a failed save: {e}");
            } else {
                assert!(after.is_empty(), "a failed save left {after:?}: {e}");
            }
        }
    }
}
