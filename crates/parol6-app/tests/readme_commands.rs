//! Every `parol6 …` command printed in the code blocks of README.md and of the user guide
//! (`docs/guide/*.md`) runs as printed, with the built
//! binary, from the repository root, and exits 0.
//!
//! Each line is classified by the app's own clap definition ([`Cli`]): a line clap refuses
//! (an unknown subcommand or option, a bad value) fails the test, so no line can slip through
//! untested. Then:
//! - a line with no subcommand, or with a subcommand that opens the window ([`WINDOW_SUBCOMMANDS`]),
//!   runs in the window under Xvfb (or the display there is) with the `sweep:1` test hook, which
//!   closes it after one second and prints frame statistics (JSON); with neither a display nor
//!   `xvfb-run` it falls back to clap's `--help` (SKIPPED, a failure when `CI` is set);
//! - any other line runs as printed; its stdout is JSON, except for a command that has a
//!   `--json` option the line does not give (then human-readable text) and `hw emulate`
//!   (the pseudo-terminal's path first; it gets `quit` on stdin); `serve` prints two JSON
//!   lines (listening, then its summary).
//!
//! A trailing `# comment` is not part of the command. A bare file name (no `/`) with a file
//! extension is a file the command writes or one an earlier line wrote: it is put into a
//! temporary folder, so nothing is written into the repository. The README's hardware examples
//! use `--fake-robot` (the built-in emulator), so they run without a PAROL6.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use clap::CommandFactory;
use parol6_app::cli::Cli;

/// Subcommands that open the window instead of printing (each must be one of clap's).
const WINDOW_SUBCOMMANDS: [&str; 1] = ["replay"];

/// Extensions of the files README lines name.
const FILE_EXTENSIONS: [&str; 8] = ["mcap", "csv", "html", "png", "gcode", "nc", "json", "txt"];

/// The `parol6 …` lines of the fenced code blocks of README.md and of the user guide
/// (`docs/guide/*.md`), without trailing comments.
fn readme_commands() -> Vec<String> {
    let root = cli_support::workspace_root();
    let mut files = vec![root.join("README.md")];
    let mut guide: Vec<_> = std::fs::read_dir(root.join("docs/guide"))
        .expect("docs/guide")
        .map(|e| e.expect("a guide entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    guide.sort();
    files.extend(guide);
    let mut commands = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        commands.extend(commands_in(&text));
    }
    commands
}

/// The `parol6 …` lines of the fenced code blocks of a Markdown text, without trailing comments.
fn commands_in(markdown: &str) -> Vec<String> {
    let mut in_block = false;
    let mut commands = Vec::new();
    for line in markdown.lines() {
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

/// What a README line does, as the app's clap definition reads it.
#[derive(Debug, PartialEq)]
enum Kind {
    /// Opens the window (no subcommand, or one of [`WINDOW_SUBCOMMANDS`]).
    Window,
    /// Prints its result: `json` when stdout is JSON; `path` is the subcommand chain (`["program", "check"]`).
    Prints { path: Vec<String>, json: bool },
}

/// Classifies one README line by parsing it with the app's clap [`Cli`]; `Err` names the line
/// and why it cannot be run as printed.
fn classify(line: &str) -> Result<Kind, String> {
    if line.contains(['…', '|', '[', '<', '"', '\'']) {
        return Err(format!("`{line}`: not runnable as printed (placeholder, pipe or quoting)"));
    }
    let words: Vec<&str> = line.split_whitespace().collect();
    if words.first() != Some(&"parol6") {
        return Err(format!("`{line}`: does not start with `parol6`"));
    }
    let matches = Cli::command()
        .try_get_matches_from(&words)
        .map_err(|e| format!("`{line}`: the parol6 command line refuses it: {}", e.render()))?;
    let root = Cli::command();
    let mut command = &root;
    let mut found = &matches;
    let mut path = Vec::new();
    while let Some((name, sub)) = found.subcommand() {
        command = command.find_subcommand(name).ok_or_else(|| format!("`{line}`: no subcommand {name}"))?;
        path.push(name.to_string());
        found = sub;
    }
    if path.first().is_none_or(|first| WINDOW_SUBCOMMANDS.contains(&first.as_str())) {
        return Ok(Kind::Window);
    }
    let has_json_option = command.get_arguments().any(|a| a.get_long() == Some("json"));
    let emulator = path == ["hw", "emulate"];
    let json = !emulator && (!has_json_option || words.contains(&"--json"));
    Ok(Kind::Prints { path, json })
}

/// The line's arguments (after `parol6`), with bare file names moved into `tmp`.
fn arguments(line: &str, tmp: &Path) -> Vec<String> {
    line.split_whitespace()
        .skip(1)
        .map(|word| {
            let is_file = !word.contains('/')
                && Path::new(word).extension().is_some_and(|e| FILE_EXTENSIONS.iter().any(|x| e == *x));
            if is_file { tmp.join(word).display().to_string() } else { word.to_string() }
        })
        .collect()
}

fn which(cmd: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(cmd).is_file()))
}

/// Runs a window line for one second (`sweep:1` test hook) under Xvfb, or the display there is;
/// `None` when there is neither (not allowed in CI).
fn run_window(args: &[String], tmp: &Path) -> Option<cli_support::Run> {
    let has_display = std::env::var_os("DISPLAY").is_some();
    if !has_display && !which("xvfb-run") {
        assert!(std::env::var_os("CI").is_none(), "xvfb-run is missing (install xvfb xauth) and CI is set");
        return None;
    }
    let runtime = tmp.join("xdg");
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700)).expect("chmod");
    }
    // `xvfb-run -a` can lose the race for a display number to a server that is still closing
    for _ in 0..3 {
        let mut command = if has_display {
            Command::new(cli_support::exe())
        } else {
            let mut c = Command::new("xvfb-run");
            c.args(["-a", "-s", "-screen 0 1280x800x24", cli_support::exe()]);
            c
        };
        command
            .args(args)
            .current_dir(cli_support::workspace_root())
            .env("PAROL6_TEST_SCRIPT", "sweep:1")
            .env("PAROL6_SETTINGS", tmp.join("settings.json"))
            .env("WINIT_X11_SCALE_FACTOR", "1")
            .env("XDG_RUNTIME_DIR", &runtime)
            .env_remove("WAYLAND_DISPLAY");
        let run = cli_support::run_command(command, Duration::from_secs(120));
        if !run.stderr.contains("Failed to open connection to X server") {
            return Some(run);
        }
    }
    panic!("no X server for {args:?} after 3 tries");
}

#[test]
fn readme_commands_run_as_printed() {
    let commands = readme_commands();
    assert!(commands.len() >= 20, "the README's command-line section lists its commands: {commands:?}");
    for sub in Cli::command().get_subcommands() {
        let name = sub.get_name();
        assert!(
            commands.iter().any(|c| c.split_whitespace().nth(1) == Some(name)),
            "README shows `parol6 {name}` (each subcommand of the command line)"
        );
    }
    for sub in WINDOW_SUBCOMMANDS {
        assert!(Cli::command().find_subcommand(sub).is_some(), "{sub} is a subcommand");
    }
    let kinds: Vec<Kind> = commands.iter().map(|c| classify(c).unwrap_or_else(|e| panic!("{e}"))).collect();
    let tmp = std::env::temp_dir().join(format!("parol6-readme-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("temp dir");
    for (command, kind) in commands.iter().zip(&kinds) {
        let args = arguments(command, &tmp);
        let run = match kind {
            Kind::Window => match run_window(&args, &tmp) {
                Some(run) => run,
                None => {
                    parol6_tests::skip_notice(&format!("SKIPPED in the window (no display, no xvfb-run): {command}"));
                    let mut help = args.clone();
                    help.push("--help".into());
                    let run = cli_support::run_in(cli_support::workspace_root(), &help, Duration::from_secs(60));
                    assert_eq!(run.code(), Some(0), "`{command}` --help: {run:?}");
                    continue;
                }
            },
            Kind::Prints { .. } => cli_support::run_in(cli_support::workspace_root(), &args, Duration::from_secs(180)),
        };
        run.assert_no_panic(command);
        if (command.contains("screenshot") || command.contains("bench render"))
            && cli_support::no_adapter(&run, command)
        {
            continue;
        }
        assert_eq!(run.code(), Some(0), "`{command}` (ran as {args:?}) failed: {run:?}");
        match kind {
            Kind::Window => {
                let line = run.stdout.lines().find(|l| l.contains("\"frames\"")).unwrap_or_default();
                let stats: serde_json::Value = serde_json::from_str(line)
                    .unwrap_or_else(|e| panic!("{command}: no frame statistics ({e}): {run:?}"));
                assert!(stats["frames"].as_u64().is_some_and(|n| n > 0), "{command}: no frame drawn: {run:?}");
            }
            Kind::Prints { path, json: true } if path == &["serve"] => {
                // a JSON line when it listens, another when it ends
                let lines: Vec<&str> = run.stdout.lines().collect();
                assert_eq!(lines.len(), 2, "{command}: {run:?}");
                for line in lines {
                    let v: serde_json::Value =
                        serde_json::from_str(line).unwrap_or_else(|e| panic!("{command}: {line}: {e}"));
                    assert!(v.is_object(), "{command}: {line}");
                }
            }
            Kind::Prints { path, json: true } => {
                // one JSON value a line (`serve` prints one when listening and one at the end)
                for line in run.stdout.lines().filter(|l| !l.trim().is_empty()) {
                    serde_json::from_str::<serde_json::Value>(line)
                        .unwrap_or_else(|e| panic!("{command}: a stdout line is not JSON ({e}): {run:?}"));
                }
                assert!(!run.stdout.trim().is_empty(), "{command}: prints JSON: {run:?}");
                assert!(!path.is_empty());
            }
            Kind::Prints { path, json: false } if path == &["hw", "emulate"] => {
                assert!(run.stdout.lines().next().is_some_and(|l| l.starts_with("/dev/")), "{command}: {run:?}");
            }
            Kind::Prints { json: false, .. } => {
                assert!(!run.stdout.trim().is_empty(), "{command}: prints its result: {run:?}");
            }
        }
        eprintln!("ok ({:.1} s): {command}", run.elapsed.as_secs_f64());
    }
    if let Err(e) = std::fs::remove_dir_all(&tmp) {
        eprintln!("cannot remove {}: {e}", tmp.display());
    }
}

#[test]
fn readme_line_with_an_unknown_subcommand_is_not_classified() {
    let readme = "```\nparol6 fk --joints 0,0,0,0,0,0\nparol6 frobnicate --n 3   # no such subcommand\n```\n";
    let commands = commands_in(readme);
    assert_eq!(commands, ["parol6 fk --joints 0,0,0,0,0,0", "parol6 frobnicate --n 3"]);
    assert_eq!(classify(&commands[0]), Ok(Kind::Prints { path: vec!["fk".into()], json: true }));
    let err = classify(&commands[1]).expect_err("an unknown subcommand is refused");
    assert!(err.contains("frobnicate"), "{err}");
    // an unknown option or a bad value of a known subcommand is refused too
    assert!(classify("parol6 program check draw.json --bogus").is_err());
    assert!(classify("parol6 replay").is_err(), "replay needs its file");
    assert!(classify("parol6 bench fk --n many").is_err());
}

#[test]
fn readme_lines_are_classified_by_the_command_line() {
    let kind = |line| classify(line).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(kind("parol6 --tool ssg48"), Kind::Window);
    assert_eq!(kind("parol6 replay sim.mcap"), Kind::Window);
    let check = |json| Kind::Prints { path: vec!["program".into(), "check".into()], json };
    assert_eq!(kind("parol6 program check assets/programs/draw.json"), check(false));
    assert_eq!(kind("parol6 program check assets/programs/draw.json --json"), check(true));
    assert_eq!(kind("parol6 hw emulate"), Kind::Prints { path: vec!["hw".into(), "emulate".into()], json: false });
    let tmp = Path::new("/tmp/x");
    assert_eq!(
        arguments("parol6 program convert assets/programs/draw.json draw.gcode --speed 0.5", tmp),
        ["program", "convert", "assets/programs/draw.json", "/tmp/x/draw.gcode", "--speed", "0.5"]
    );
}

#[test]
fn readme_hardware_examples_use_the_fake_robot() {
    for command in readme_commands().iter().filter(|c| c.starts_with("parol6 hw ")) {
        let talks = !(command.contains(" ports") || command.contains(" emulate"));
        assert!(!talks || command.contains("--fake-robot"), "{command}");
    }
}
