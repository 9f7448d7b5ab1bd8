//! `parol6 hw …`: the serial controller from the command line (owned by the hardware work).

use super::CliResult;

/// Arguments of `parol6 hw`.
#[derive(Debug, clap::Args)]
pub struct HwArgs {}

/// Runs `parol6 hw`.
pub fn run(_args: &HwArgs) -> CliResult {
    Err(super::CliError::runtime("the hw commands are not built yet"))
}
