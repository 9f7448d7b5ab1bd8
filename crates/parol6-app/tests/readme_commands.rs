//! Every `parol6 …` command printed in README.md's code blocks runs as printed, with the built
//! binary, from the repository root, and exits 0.
//!
//! Rules: a trailing `# comment` is not part of the command; lines with no subcommand start
//! the GUI, which cannot open a window here, so they are checked with `--help` appended (their
//! options must parse); `screenshot` writes its picture into a temporary folder instead of the
//! file name printed, and `record`, `mcap`, `--record`, `iso9283`, `path-test` and `bench render
//! --last-frame` their `.mcap` / `.csv` / `.html` / `.png` files there too;
//! `hw emulate` gets `quit` on stdin. The README's hardware examples use
//! `--fake-robot` (the built-in emulator), so they run without a PAROL6.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::time::Duration;

const SUBCOMMANDS: [&str; 10] =
    ["fk", "ik", "dynamics", "screenshot", "hw", "bench", "record", "mcap", "iso9283", "path-test"];

/// The `parol6 …` lines of the README's fenced code blocks, without trailing comments.
fn readme_commands() -> Vec<String> {
    let readme = std::fs::read_to_string(cli_support::workspace_root().join("README.md")).expect("README.md");
    let mut in_block = false;
    let mut commands = Vec::new();
    for line in readme.lines() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        let line = line.trim();
        if in_block && (line == "parol6" || line.starts_with("parol6 ")) {
            let command = line.split(" #").next().unwrap_or(line).trim();
            commands.push(command.to_string());
        }
    }
    commands
}

#[test]
fn readme_commands_run_as_printed() {
    let commands = readme_commands();
    assert!(commands.len() >= 20, "the README's command-line section lists its commands: {commands:?}");
    for sub in SUBCOMMANDS {
        assert!(commands.iter().any(|c| c.split_whitespace().any(|w| w == sub)), "README shows `parol6 {sub}`");
    }
    let tmp = std::env::temp_dir().join(format!("parol6-readme-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("temp dir");
    for command in &commands {
        assert!(!command.contains(['…', '|', '[', '<', '"', '\'']), "not runnable as printed: {command}");
        let mut args: Vec<String> = command.split_whitespace().skip(1).map(str::to_string).collect();
        let gui = !args.iter().any(|a| SUBCOMMANDS.contains(&a.as_str()));
        if gui {
            args.push("--help".into());
        }
        if let Some(i) = args.iter().position(|a| a == "screenshot")
            && let Some(out) = args.get_mut(i + 1)
        {
            *out = tmp.join(out.as_str()).display().to_string();
        }
        for arg in args
            .iter_mut()
            .filter(|a| a.ends_with(".mcap") || a.ends_with(".csv") || a.ends_with(".html") || a.ends_with(".png"))
        {
            *arg = tmp.join(arg.as_str()).display().to_string();
        }
        let run = cli_support::run_in(cli_support::workspace_root(), &args, Duration::from_secs(180));
        run.assert_no_panic(command);
        if (command.contains("screenshot") || command.contains("bench render"))
            && cli_support::no_adapter(&run, command)
        {
            continue;
        }
        assert_eq!(run.code(), Some(0), "`{command}` (ran as {args:?}) failed: {run:?}");
        if gui {
            assert!(run.stdout.contains("Usage"), "{command}: {run:?}");
        } else if command.contains("hw emulate") {
            assert!(run.stdout.lines().next().is_some_and(|l| l.starts_with("/dev/")), "{command}: {run:?}");
        } else {
            run.json(command);
        }
        eprintln!("ok ({:.1} s): {command}", run.elapsed.as_secs_f64());
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn readme_hardware_examples_use_the_fake_robot() {
    for command in readme_commands().iter().filter(|c| c.starts_with("parol6 hw ")) {
        let talks = !(command.contains(" ports") || command.contains(" emulate"));
        assert!(!talks || command.contains("--fake-robot"), "{command}");
    }
}
