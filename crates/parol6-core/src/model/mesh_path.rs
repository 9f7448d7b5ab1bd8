//! Mesh path resolution: where the file a URDF `<mesh filename=…>` names lies on disk.

use std::path::PathBuf;

use super::LoadOptions;

/// Resolves a URDF mesh filename to a path: absolute paths as they are, `file://` stripped,
/// `package://NAME/rest` → `<urdf folder>/rest`, relative paths against the URDF folder, then
/// the search path. Returns the first candidate and whether a file exists there.
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
    match candidates.iter().find(|c| c.is_file()) {
        Some(c) => (c.clone(), true),
        None => (candidates.into_iter().next().unwrap_or_default(), false),
    }
}
