//! The hostile-board modes of the fault peer ([`crate::fault_peer`]): what a lying or broken
//! controller reports about its joints, applied to every well-formed status frame before the
//! peer's transport faults (bit flips, drops, stalls …).
//!
//! - [`BoardMode::FarOutside`]: positions far outside the step limits (J1 = 100 000,
//!   J3 = −200 000 steps: [`IMPOSSIBLE_STEPS`]), from the first frame on;
//! - [`BoardMode::Stale`]: the first status frame repeated unchanged (a board that never moves);
//! - [`BoardMode::JumpAfter`]: honest for `frames`, then the positions jump to impossible values;
//! - [`BoardMode::SilentAfter`]: honest for `frames`, then no status at all;
//! - [`BoardMode::Erratic`]: every other frame impossible (a board that answers, but never
//!   with a usable position).

use parol6_hw::frame::StatusFrame;

/// Joints of the arm.
const JOINTS: usize = 6;

/// Positions no PAROL6 can be at: J1 = 100 000 and J3 = −200 000 steps (the limits are
/// −14 000…14 000 and 34 700…92 605), the other joints at standby.
pub const IMPOSSIBLE_STEPS: [i32; JOINTS] = [100_000, -32_000, -200_000, 0, 0, 32_000];

/// What the board says about its joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoardMode {
    /// The controller's own status, unchanged.
    #[default]
    Honest,
    /// Every status reports [`IMPOSSIBLE_STEPS`].
    FarOutside,
    /// The first status frame, repeated unchanged for ever.
    Stale,
    /// Honest for this many status frames, then [`IMPOSSIBLE_STEPS`].
    JumpAfter(u64),
    /// Honest for this many status frames, then silence.
    SilentAfter(u64),
    /// Every other status frame reports [`IMPOSSIBLE_STEPS`].
    Erratic,
}

impl BoardMode {
    /// Every mode, with `frames` for the ones that change after a number of frames.
    pub fn all(frames: u64) -> [BoardMode; 6] {
        [Self::Honest, Self::FarOutside, Self::Stale, Self::JumpAfter(frames), Self::SilentAfter(frames), Self::Erratic]
    }

    /// A short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Honest => "honest",
            Self::FarOutside => "far outside the limits",
            Self::Stale => "stale",
            Self::JumpAfter(_) => "jumps to impossible positions",
            Self::SilentAfter(_) => "silent after N frames",
            Self::Erratic => "erratic",
        }
    }
}

/// Applies a [`BoardMode`] frame by frame.
#[derive(Debug, Clone, Default)]
pub struct BoardRewriter {
    mode: BoardMode,
    frames: u64,
    first: Option<StatusFrame>,
}

impl BoardRewriter {
    /// A rewriter for `mode`.
    pub fn new(mode: BoardMode) -> Self {
        Self { mode, frames: 0, first: None }
    }

    /// What the board sends instead of `frame` (`None`: nothing).
    pub fn rewrite(&mut self, frame: StatusFrame) -> Option<StatusFrame> {
        self.frames = self.frames.saturating_add(1);
        let first = *self.first.get_or_insert(frame);
        match self.mode {
            BoardMode::Honest => Some(frame),
            BoardMode::FarOutside => Some(StatusFrame { positions_steps: IMPOSSIBLE_STEPS, ..frame }),
            BoardMode::Stale => Some(first),
            BoardMode::JumpAfter(n) if self.frames > n => {
                Some(StatusFrame { positions_steps: IMPOSSIBLE_STEPS, ..frame })
            }
            BoardMode::SilentAfter(n) if self.frames > n => None,
            BoardMode::Erratic if self.frames.is_multiple_of(2) => {
                Some(StatusFrame { positions_steps: IMPOSSIBLE_STEPS, ..frame })
            }
            BoardMode::Erratic => Some(frame),
            BoardMode::JumpAfter(_) | BoardMode::SilentAfter(_) => Some(frame),
        }
    }
}
