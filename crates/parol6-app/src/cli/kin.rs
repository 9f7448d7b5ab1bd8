//! `parol6 fk` and `parol6 ik`.

use super::CliResult;

/// Arguments of `parol6 fk`.
#[derive(Debug, clap::Args)]
pub struct FkArgs {}

/// Arguments of `parol6 ik`.
#[derive(Debug, clap::Args)]
pub struct IkArgs {}

/// Runs `parol6 fk`.
pub fn run_fk(_a: &FkArgs) -> CliResult {
    Ok(())
}

/// Runs `parol6 ik`.
pub fn run_ik(_a: &IkArgs) -> CliResult {
    Ok(())
}

/// `parol6 bench fk`.
pub fn bench_fk(_n: usize) -> CliResult {
    Ok(())
}

/// `parol6 bench ik`.
pub fn bench_ik(_n: usize) -> CliResult {
    Ok(())
}
