//! # parol6-app
//!
//! The PAROL6 Studio desktop application (eframe/egui with our own wgpu 3D pipeline) and the
//! `parol6` command line. This crate owns presentation and user interaction only: it reads
//! robot facts from `parol6-core` and talks to the controller through `parol6-hw`.
//! It must not implement kinematics, physics or protocol logic itself.

pub mod app;
pub mod artifacts;
pub mod background;
pub mod cli;
pub mod live;
pub mod palette;
pub mod panels;
pub mod report;
pub mod theme;
pub mod typed_path;
pub mod ui_screenshot;
pub mod viewport;
