//! Paths the operator types (the Program file field, the File menu's recording fields, a name
//! typed in a file dialog): a leading `~` or `~/` is the home directory, as in a shell, and `.`
//! and `..` parts are resolved as a shell's `cd` does (by the text, not following links), so the
//! recent-files list and the settings keep the path a person would write. One place, so every
//! typed path reads alike.

use std::path::{Component, Path, PathBuf};

/// The home directory (`$HOME`), if set and not empty.
fn home() -> Option<PathBuf> {
    std::env::var_os("HOME").filter(|h| !h.is_empty()).map(PathBuf::from)
}

/// A typed path: blanks around it trimmed, a leading `~` or `~/…` in the home directory. `~user`
/// and a `~` anywhere else are left as typed.
pub fn typed_path(text: &str) -> PathBuf {
    let text = text.trim();
    let rest = match text.strip_prefix('~') {
        Some("") => Some(""),
        Some(rest) => rest.strip_prefix('/'),
        None => None,
    };
    match (rest, home()) {
        (Some(rest), Some(home)) => lexical(&home.join(rest)),
        _ => lexical(Path::new(text)),
    }
}

/// `path` with its `.` parts left out and each `..` taking away the part before it (trial 22
/// m10: `~/../tmp/x` was kept as `/root/../tmp/x`). A `..` with nothing before it stays (a
/// relative path), and at the root it is the root.
fn lexical(path: &Path) -> PathBuf {
    let mut out: Vec<Component<'_>> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.last() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                Some(Component::RootDir | Component::Prefix(_)) => {}
                _ => out.push(c),
            },
            other => out.push(other),
        }
    }
    if out.is_empty() {
        // nothing typed stays nothing; `a/..` is here
        return if path.as_os_str().is_empty() { PathBuf::new() } else { PathBuf::from(".") };
    }
    out.iter().collect()
}

/// A file dialog's pick: the dialog puts a typed name in the folder it shows, so `~/x` typed there
/// arrives as `FOLDER/~/x`; from its last `~` part on it is a path in the home directory.
pub fn picked_path(path: &Path) -> PathBuf {
    let parts: Vec<Component<'_>> = path.components().collect();
    let Some(at) = parts.iter().rposition(|c| c.as_os_str() == "~") else { return lexical(path) };
    match home() {
        Some(home) => lexical(&parts[at + 1..].iter().fold(home, |p, c| p.join(c))),
        None => lexical(path),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_leading_tilde_is_the_home_directory() {
        let Some(home) = home() else { return };
        assert_eq!(typed_path(" ~/a/b.gcode "), home.join("a/b.gcode"));
        assert_eq!(typed_path("~"), home);
        assert_eq!(typed_path("~user/x"), PathBuf::from("~user/x"));
        assert_eq!(typed_path("/tmp/~/x"), PathBuf::from("/tmp/~/x"));
        assert_eq!(picked_path(Path::new("/tmp/t/~/saved draw.gcode")), home.join("saved draw.gcode"));
        assert_eq!(picked_path(Path::new("/tmp/t/draw.gcode")), PathBuf::from("/tmp/t/draw.gcode"));
        assert_eq!(typed_path("~/../tmp/x.txt"), home.parent().unwrap_or(&home).join("tmp/x.txt"));
        assert_eq!(picked_path(Path::new("/tmp/t/~/../x.txt")), home.parent().unwrap_or(&home).join("x.txt"));
    }

    #[test]
    fn dot_and_dot_dot_parts_are_resolved_by_the_text() {
        assert_eq!(typed_path("/root/../tmp/./a/b/../c.gcode"), PathBuf::from("/tmp/a/c.gcode"));
        assert_eq!(typed_path("/.."), PathBuf::from("/"));
        assert_eq!(typed_path("../x.json"), PathBuf::from("../x.json"));
        assert_eq!(typed_path("a/../../x.json"), PathBuf::from("../x.json"));
        assert_eq!(typed_path("./x.json"), PathBuf::from("x.json"));
        assert_eq!(typed_path("a/.."), PathBuf::from("."));
        assert_eq!(typed_path("  "), PathBuf::new());
        assert_eq!(picked_path(Path::new("/tmp/t/../draw.gcode")), PathBuf::from("/tmp/draw.gcode"));
    }
}
