//! Paths the operator types (the Program file field, the File menu's recording fields, a name
//! typed in a file dialog): a leading `~` or `~/` is the home directory, as in a shell. One
//! place, so every typed path reads alike.

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
        (Some(rest), Some(home)) => home.join(rest),
        _ => PathBuf::from(text),
    }
}

/// A file dialog's pick: the dialog puts a typed name in the folder it shows, so `~/x` typed there
/// arrives as `FOLDER/~/x`; from its last `~` part on it is a path in the home directory.
pub fn picked_path(path: &Path) -> PathBuf {
    let parts: Vec<Component<'_>> = path.components().collect();
    let Some(at) = parts.iter().rposition(|c| c.as_os_str() == "~") else { return path.to_path_buf() };
    match home() {
        Some(home) => parts[at + 1..].iter().fold(home, |p, c| p.join(c)),
        None => path.to_path_buf(),
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
    }
}
