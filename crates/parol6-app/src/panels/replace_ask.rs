//! Writing to a typed path that already exists asks first, the same way wherever a typed path
//! is written (a recording, the plots' CSV and SVG, the ISO 9283 report): the first click names
//! the file and says that the same click again replaces it; the second click on the unchanged
//! path writes. Before, each of them replaced the file without a word.

use std::path::{Path, PathBuf};

/// The path the operator was last told exists (the next click on it replaces it).
#[derive(Debug, Default, Clone)]
pub struct ReplaceAsk {
    asked: Option<PathBuf>,
}

impl ReplaceAsk {
    /// `true` when `path` may be written now: it is no existing file, or the operator was told
    /// at the last click that it exists and clicked again. Otherwise remembers the question and
    /// returns `false`: [`Self::question`] then says it. A path that exists but is no regular
    /// file (a folder, `/dev/full`) is not asked about: the writer refuses it at once, saying
    /// why (trial17 m1: "full exists: … replaces it" came first).
    pub fn may_write(&mut self, path: &Path) -> bool {
        if path.is_file() && self.asked.as_deref() != Some(path) {
            self.asked = Some(path.to_path_buf());
            false
        } else {
            self.asked = None;
            true
        }
    }

    /// While the question about `path` stands (the typed path unchanged since): "NAME exists:
    /// `again` replaces it".
    pub fn question(&self, path: &Path, again: &str) -> Option<String> {
        (self.asked.as_deref() == Some(path)).then(|| {
            let name =
                path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
            format!("{name} exists: {again} replaces it")
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_existing_file_is_written_on_the_second_click_only_and_a_new_one_at_once() {
        let dir = std::env::temp_dir().join(format!("parol6-replace-ask-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
        let (old, new) = (dir.join("old.csv"), dir.join("new.csv"));
        std::fs::write(&old, "kept").unwrap_or_else(|e| panic!("{e}"));
        let mut ask = ReplaceAsk::default();
        assert!(ask.may_write(&new), "a new file is written at once");
        assert!(!ask.may_write(&old), "the first click on an existing file asks");
        assert_eq!(ask.question(&old, "Save again").as_deref(), Some("old.csv exists: Save again replaces it"));
        assert_eq!(ask.question(&new, "Save again"), None, "another typed path: no question");
        assert!(ask.may_write(&old), "the second click replaces");
        assert!(!ask.may_write(&old), "a later write of the same file asks again");
        assert!(ask.may_write(&dir), "a folder is not asked about: its writer refuses it");
        #[cfg(unix)]
        assert!(ask.may_write(Path::new("/dev/full")), "nor a device");
        std::fs::remove_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
    }
}
