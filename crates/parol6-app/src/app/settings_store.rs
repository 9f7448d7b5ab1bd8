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

/// How long the settings must stay unchanged before they are written (a dragged panel edge or
/// slider changes them every frame).
const AUTOSAVE_AFTER_S: f64 = 0.5;

/// Writes the settings whenever they change, off the UI thread, so that a crash loses nothing
/// the operator set. The window's last settings are written at exit by [`SettingsAutosave::finish`].
pub(super) struct SettingsAutosave {
    saved: Settings,
    last_seen: Settings,
    stable_since: std::time::Instant,
    tx: Option<std::sync::mpsc::SyncSender<Settings>>,
    writer: Option<std::thread::JoinHandle<()>>,
}

impl SettingsAutosave {
    /// A writer thread for `path`; `loaded` is what the file holds now.
    pub(super) fn start(path: PathBuf, loaded: &Settings) -> std::io::Result<Self> {
        let (tx, rx) = std::sync::mpsc::sync_channel::<Settings>(1);
        let writer = crate::background::spawn("parol6-settings", move || {
            for settings in rx {
                if let Err(e) = save_settings(&path, &settings) {
                    tracing::warn!("settings not saved: {e:#}");
                }
            }
        })?;
        Ok(Self {
            saved: loaded.clone(),
            last_seen: loaded.clone(),
            stable_since: std::time::Instant::now(),
            tx: Some(tx),
            writer: Some(writer),
        })
    }

    /// Once a frame: queues `current` for writing once it has changed and then stayed the same
    /// for [`AUTOSAVE_AFTER_S`]. Never waits: a write still under way is caught up next frame.
    pub(super) fn frame(&mut self, current: &Settings) {
        if *current != self.last_seen {
            self.last_seen = current.clone();
            self.stable_since = std::time::Instant::now();
            return;
        }
        if *current == self.saved || self.stable_since.elapsed().as_secs_f64() < AUTOSAVE_AFTER_S {
            return;
        }
        if let Some(tx) = &self.tx
            && tx.try_send(current.clone()).is_ok()
        {
            self.saved = current.clone();
        }
    }

    /// At exit: writes `current` after any write under way, and waits for it (so an older write
    /// can never land last).
    pub(super) fn finish(&mut self, current: &Settings) {
        if let Some(tx) = self.tx.take()
            && tx.send(current.clone()).is_err()
        {
            tracing::warn!("settings not saved: the writer thread has ended");
        }
        if let Some(writer) = self.writer.take()
            && writer.join().is_err()
        {
            tracing::warn!("settings not saved: the writer thread panicked");
        }
    }
}

impl super::Parol6App {
    /// Saves the settings now, after any write under way (they are also saved whenever they
    /// change, on a writer thread: `SettingsAutosave`).
    pub fn save_settings(&mut self) {
        if let Some(autosave) = &mut self.autosave {
            autosave.finish(&self.settings);
            self.autosave = None;
        } else if let Some(p) = &self.settings_path
            && let Err(e) = save_settings(p, &self.settings)
        {
            tracing::warn!("settings not saved: {e:#}");
        }
    }
}
