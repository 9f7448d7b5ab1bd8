//! Mesh path resolution: where the file a URDF `<mesh filename=…>` names lies on disk, and
//! the one bounded reader of mesh files ([`read_mesh_file`], at most [`MAX_MESH_FILE_BYTES`]).

use std::path::{Path, PathBuf};

use super::LoadOptions;
use crate::fsio::{self, FsioError};

/// The largest mesh file read, bytes (64 MiB: a detailed STL of a robot link is a few MiB).
/// A larger file, a FIFO or a device is not read; the model warns and the link is drawn as a
/// placeholder.
pub const MAX_MESH_FILE_BYTES: u64 = 64 << 20;

/// Reads a mesh file: a regular file only, at most [`MAX_MESH_FILE_BYTES`].
pub fn read_mesh_file(path: &Path) -> Result<Vec<u8>, FsioError> {
    fsio::read_regular_bounded(path, MAX_MESH_FILE_BYTES)
}

/// [`read_mesh_file`] in the shape `mesh_loader`'s custom reader takes (also used for the
/// material files an OBJ names).
pub fn mesh_reader(path: &Path) -> std::io::Result<Vec<u8>> {
    read_mesh_file(path).map_err(|e| std::io::Error::other(e.to_string()))
}

/// Why the mesh file at `path` (which exists) will not be read: not a regular file, or
/// larger than [`MAX_MESH_FILE_BYTES`]. `None` when it can be read.
pub fn mesh_file_refusal(path: &Path) -> Option<String> {
    match fsio::check_regular(path) {
        Err(e) => Some(e.to_string()),
        Ok(m) if m.len() > MAX_MESH_FILE_BYTES => Some(format!(
            "{}: refused, it is {} bytes, larger than the {} MiB a mesh file may have",
            path.display(),
            m.len(),
            MAX_MESH_FILE_BYTES >> 20
        )),
        Ok(_) => None,
    }
}

/// Resolves a URDF mesh filename to a path: absolute paths as they are, `file://` stripped,
/// `package://NAME/rest` → `<urdf folder>/rest`, relative paths against the URDF folder, then
/// the search path. Returns the first candidate where something exists (a file, or a FIFO or
/// device that [`read_mesh_file`] then refuses) and `true`, else the first candidate and `false`.
pub fn resolve_mesh(uri: &str, opts: &LoadOptions) -> (PathBuf, bool) {
    let mut candidates: Vec<PathBuf> = Vec::new();
    let base = opts.base_dir.clone().unwrap_or_else(|| PathBuf::from("."));
    if let Some(rest) = uri.strip_prefix("package://") {
        let (pkg, rel) = rest.split_once('/').unwrap_or((rest, ""));
        candidates.push(base.join(rel));
        candidates.push(base.join("..").join(rel));
        for d in &opts.mesh_search_path {
            candidates.push(d.join(rel));
            candidates.push(d.join(pkg).join(rel));
        }
    } else {
        let plain = uri.strip_prefix("file://").unwrap_or(uri);
        let p = PathBuf::from(plain);
        if p.is_absolute() {
            candidates.push(p);
        } else {
            candidates.push(base.join(&p));
            for d in &opts.mesh_search_path {
                candidates.push(d.join(&p));
            }
        }
    }
    match candidates.iter().find(|c| c.exists()) {
        Some(c) => (c.clone(), true),
        None => (candidates.into_iter().next().unwrap_or_default(), false),
    }
}
