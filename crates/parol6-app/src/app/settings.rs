//! UI settings that survive a restart ([`Settings`], saved by `app/settings_store.rs` to
//! [`crate::app::settings_path`]): the angle unit, panels shown, speeds, the profile, the last
//! port, the 3D view's toggles, recent programs, the lower panel's height and tab, tracking, the live
//! sharing address, and what the panels hold that survives a restart (`app/remembered.rs`: the
//! last program, the Cartesian jog's frame, mode and increments, the forward-dynamics form, the
//! camera). Every field has a default: a file from an older version, without the newer keys,
//! loads. The app owns them; panels change them through `PanelContext::settings`.

use parol6_core::profile::ProfileKind;
use serde::{Deserialize, Serialize};

use super::remembered::{CameraSetting, CartesianJogSetting, LastProgram, TorqueFormSetting};
use crate::panels::{AbcConvention, AngleConvention, AngleUnit};

/// UI settings that survive a restart (see [`crate::app::settings_path`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Angle unit.
    pub unit: AngleUnit,
    /// Left (joints) panel shown.
    pub show_left: bool,
    /// Right (TCP / Cartesian jog / target) panel shown.
    pub show_right: bool,
    /// Speed fraction (0–1] of profiled moves.
    pub speed_fraction: f64,
    /// Profile shape of profiled moves.
    pub profile: ProfileKindSetting,
    /// Last serial port connected to.
    pub last_port: String,
    /// 3D view display toggles.
    pub view: crate::viewport::ViewportOptions,
    /// Jog speed fraction (0–1] for the hardware jog buttons.
    pub jog_speed_fraction: f64,
    /// Cartesian jog speed fraction (0–1] of the 1–160 mm/s, 1–80 °/s range.
    pub cartesian_jog_fraction: f64,
    /// How TCP orientations are shown and typed: our roll/pitch/yaw or the official PAROL6
    /// tools' RX/RY/RZ (so a user reads the same numbers as in the official GUI and API).
    pub angle_convention: AngleConvention,
    /// How G-code `A B C` are read (files without a `; parol6: abc=…` header) and written.
    pub gcode_abc: AbcConvention,
    /// Program files opened or saved, newest first (at most [`RECENT_PROGRAMS`]).
    pub recent_programs: Vec<String>,
    /// The folder the program file dialog last showed (also after Cancel); it opens there next.
    pub program_folder: Option<String>,
    /// Plots panel shown (under the 3D view).
    pub show_plots: bool,
    /// Dynamics panel shown (under the 3D view).
    pub show_dynamics: bool,
    /// Height of the panel under the 3D view (plots, dynamics, replay timeline) as last
    /// dragged, points.
    pub lower_panel_height_pt: f32,
    /// The panel in front (its title) where the plots and the dynamics share the lower panel
    /// as tabs.
    pub lower_tab: String,
    /// Tracking mode of motion on the robot and in the simulation (`parol6_core::motion::tracking`).
    pub tracking: parol6_core::motion::tracking::TrackingMode,
    /// Where File → Share live serves (Foxglove WebSocket; `crate::live::bind_address`). Sharing
    /// itself is never remembered: it is off at every start.
    pub share_live_address: String,
    /// The Zenoh router File → *Share over ROS 2* connects to (`tcp/ADDRESS:PORT`; rmw_zenoh's
    /// `rmw_zenohd` listens on tcp/127.0.0.1:7447). Off at every start, as sharing is.
    pub ros2_router: String,
    /// ROS domain id of the node (ROS_DOMAIN_ID of the other nodes), 0–232.
    pub ros2_domain: u32,
    /// The program reopened at start: the file last opened or saved, or the built-in last
    /// picked (`None`: the first built-in).
    #[serde(deserialize_with = "or_default")]
    pub last_program: Option<LastProgram>,
    /// The Cartesian jog's frame, mode and increments.
    #[serde(deserialize_with = "or_default")]
    pub cartesian_jog: CartesianJogSetting,
    /// The forward-dynamics form (`None`: as a fresh form).
    #[serde(deserialize_with = "or_default")]
    pub torque_form: Option<TorqueFormSetting>,
    /// The 3D view's camera (`None`: the default view).
    #[serde(deserialize_with = "or_default")]
    pub camera: Option<CameraSetting>,
}

/// A remembered panel state as read, or its default when it does not read (a NaN written as
/// `null`, a key of another version): one entry that does not fit never costs the others.
fn or_default<'de, D, T>(d: D) -> Result<T, D::Error>
where
    D: serde::Deserializer<'de>,
    T: serde::de::DeserializeOwned + Default,
{
    let value = serde_json::Value::deserialize(d)?;
    Ok(serde_json::from_value(value).unwrap_or_else(|e| {
        tracing::warn!("settings: an entry is ignored ({e}); its default is used");
        T::default()
    }))
}

/// Height of the area under the 3D view (replay timeline, plots) when it first opens, points.
pub const LOWER_DEFAULT_HEIGHT: f32 = 360.0;

/// Recent program files remembered.
pub const RECENT_PROGRAMS: usize = 8;

impl Settings {
    /// A TCP orientation (URDF roll/pitch/yaw, rad) as shown in the chosen convention, rad.
    pub fn shown_angles_rad(&self, rpy_rad: [f64; 3]) -> [f64; 3] {
        self.angle_convention.from_rpy_deg(rpy_rad.map(f64::to_degrees)).map(f64::to_radians)
    }

    /// Where the arm's TCP points (URDF roll/pitch/yaw, rad) as a read-out shows it in the chosen
    /// convention, rad: the one spelling at gimbal lock that the simulation and the robot share
    /// (`AngleConvention::readout_deg`). A program's own angles use [`Self::shown_angles_rad`].
    pub fn tcp_readout_rad(&self, rpy_rad: [f64; 3]) -> [f64; 3] {
        self.angle_convention.readout_deg(rpy_rad.map(f64::to_degrees)).map(f64::to_radians)
    }

    /// The tooltip of a read-out's orientation angle: the chosen convention and how it is
    /// spelled at gimbal lock.
    pub fn readout_angle_hover(&self) -> String {
        format!("{}\n{}", self.angle_convention.describe(), self.angle_convention.gimbal_lock_rule())
    }

    /// Angles typed in the chosen convention (rad) → URDF roll/pitch/yaw, rad.
    pub fn rpy_from_shown_rad(&self, shown_rad: [f64; 3]) -> [f64; 3] {
        self.angle_convention.to_rpy_deg(shown_rad.map(f64::to_degrees)).map(f64::to_radians)
    }

    /// Labels of the three orientation angles in the chosen convention.
    pub fn angle_labels(&self) -> [&'static str; 3] {
        self.angle_convention.labels()
    }

    /// Puts `path` first in the recent program files; it is the program reopened at start.
    pub fn remember_program(&mut self, path: &str) {
        self.last_program = Some(LastProgram::File(path.to_string()));
        self.recent_programs.retain(|p| p != path);
        self.recent_programs.insert(0, path.to_string());
        self.recent_programs.truncate(RECENT_PROGRAMS);
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            unit: AngleUnit::Deg,
            show_left: true,
            show_right: true,
            speed_fraction: 0.5,
            profile: ProfileKindSetting::Trapezoidal,
            last_port: String::new(),
            view: crate::viewport::ViewportOptions::default(),
            jog_speed_fraction: 0.2,
            cartesian_jog_fraction: 0.25,
            angle_convention: AngleConvention::UrdfRpy,
            gcode_abc: AbcConvention::default(),
            recent_programs: Vec::new(),
            program_folder: None,
            show_plots: false,
            show_dynamics: false,
            lower_panel_height_pt: LOWER_DEFAULT_HEIGHT,
            lower_tab: "Plots".into(),
            tracking: parol6_core::motion::tracking::TrackingMode::default(),
            share_live_address: format!("127.0.0.1:{}", crate::live::FOXGLOVE_DEFAULT_PORT),
            ros2_router: "tcp/127.0.0.1:7447".into(),
            ros2_domain: 0,
            last_program: None,
            cartesian_jog: CartesianJogSetting::default(),
            torque_form: None,
            camera: None,
        }
    }
}

/// Serializable mirror of [`ProfileKind`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ProfileKindSetting {
    /// Trapezoidal velocity.
    #[default]
    Trapezoidal,
    /// Jerk-limited (quintic).
    JerkLimited,
}

impl ProfileKindSetting {
    /// The core profile kind.
    pub fn kind(self) -> ProfileKind {
        match self {
            ProfileKindSetting::Trapezoidal => ProfileKind::Trapezoidal,
            ProfileKindSetting::JerkLimited => ProfileKind::JerkLimited,
        }
    }

    /// Label for menus.
    pub fn label(self) -> &'static str {
        match self {
            ProfileKindSetting::Trapezoidal => "trapezoidal",
            ProfileKindSetting::JerkLimited => "jerk-limited",
        }
    }
}
