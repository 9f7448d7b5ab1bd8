//! The `parol6` binary: a thin shell over `parol6_app`.

fn main() -> std::process::ExitCode {
    parol6_app::cli::main()
}
