//! Settings on disk: where they live, loading with defaults, saving.

use std::path::{Path, PathBuf};

use anyhow::Context as _;

use crate::panels::Settings;

/// The default settings file: `$PAROL6_SETTINGS`, else `$XDG_CONFIG_HOME/parol6-studio/settings.json`,
/// else `~/.config/parol6-studio/settings.json`.
pub fn settings_path() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("PAROL6_SETTINGS") {
        return Some(PathBuf::from(p));
    }
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(base.join("parol6-studio").join("settings.json"))
}

/// The largest settings file read, bytes (a real one is about 2 KiB).
const MAX_SETTINGS_BYTES: u64 = 1 << 20;

/// Loads settings; defaults when the file is missing or unreadable (reported on stderr).
pub fn load_settings(path: Option<&Path>) -> Settings {
    let Some(path) = path else {
        return Settings::default();
    };
    match parol6_core::fsio::read_regular_bounded_string(path, MAX_SETTINGS_BYTES) {
        Ok(text) => serde_json::from_str(&text).unwrap_or_else(|e| {
            tracing::warn!("ignoring settings file {}: {e}", path.display());
            Settings::default()
        }),
        Err(_) => Settings::default(),
    }
}

pub(super) fn save_settings(path: &Path, settings: &Settings) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let text = serde_json::to_string_pretty(settings)?;
    Ok(parol6_core::fsio::write_atomic_bytes(path, text.as_bytes())?)
}
