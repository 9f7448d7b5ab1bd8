//! Random argument vectors for every subcommand (never the GUI), run through the built binary:
//! no panic, no signal or abort, no hang, exit status in {0, 1, 2}, and exit 0 only when every
//! option was given a valid value. Valid values are small (short benchmarks, tiny pictures);
//! `hw` commands get `--fake-robot` or a port that does not exist, never auto-detection (a
//! real arm may be plugged in).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::time::Duration;

use proptest::prelude::*;

/// Values no numeric or list option accepts.
const GARBAGE: &[&str] = &["", "abc", "NaN", "inf", "-inf", "1e400", "18446744073709551616", "0x10"];
const BAD_COUNTS: &[&str] = &["0", "-1", "18446744073709551615", "100000000000", "1e3", "1.5", ""];
const JOINTS_OK: &[&str] = &["90,-90,180,0,0,180", "0,0,0,0,0,0", "1e3,-2,0.5,0,0,0", "1.5,-1.5,3,0,0,3"];
const LIST_BAD: &[&str] = &["", "1,2,3", "1,2,abc,4,5,6", "NaN,0,0,0,0,0", "1e400,0,0,0,0,0", "0,0,0,0,0,0,0"];

/// How the generator treats an option.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// A flag without a value.
    Flag,
    /// May be left out.
    Optional,
    /// Leaving it out is invalid.
    Required,
    /// Always given (valid or not), to keep runs short.
    Always,
}

struct Opt {
    name: &'static str,
    kind: Kind,
    valid: &'static [&'static str],
    invalid: &'static [&'static str],
}

const fn opt(name: &'static str, kind: Kind, valid: &'static [&'static str], invalid: &'static [&'static str]) -> Opt {
    Opt { name, kind, valid, invalid }
}

const fn flag(name: &'static str) -> Opt {
    Opt { name, kind: Kind::Flag, valid: &[], invalid: &[] }
}

struct Sub {
    path: &'static [&'static str],
    /// Valid with valid options (false: the path alone is incomplete).
    complete: bool,
    /// Uses --urdf/--tip/--tool.
    robot: bool,
    /// Uses --port/--fake-robot.
    connect: bool,
    /// The output file, when it takes one.
    positional: bool,
    opts: &'static [Opt],
}

const RATE: Opt = opt("--rate", Kind::Optional, &["50", "100", "500"], &["49", "501", "0", "-1", "abc", ""]);

const SUBS: &[Sub] = &[
    Sub {
        path: &["fk"],
        complete: true,
        robot: true,
        connect: false,
        positional: false,
        opts: &[opt("--joints", Kind::Required, JOINTS_OK, LIST_BAD), flag("--deg")],
    },
    Sub {
        path: &["ik"],
        complete: true,
        robot: true,
        connect: false,
        positional: false,
        opts: &[
            opt(
                "--pose",
                Kind::Required,
                &["0,236.77,334,90,-90,0", "0.2,-0.15,0.18,60,45,150", "200,100,300,180,0,0", "-1e9,0,0,0,0,0"],
                &["", "1,2,3", "inf,0,0,0,0,0", "0,0,0,0,0,x", "0,0,0,0,0,0,0"],
            ),
            opt("--seed", Kind::Optional, JOINTS_OK, LIST_BAD),
            flag("--deg"),
            flag("--mm"),
            flag("--all"),
        ],
    },
    Sub {
        path: &["dynamics"],
        complete: true,
        robot: true,
        connect: false,
        positional: false,
        opts: &[
            opt("--joints", Kind::Required, JOINTS_OK, LIST_BAD),
            opt("--velocities", Kind::Optional, &["0,0,0,0,0,0", "10,0,0,0,0,0", "-1e6,0,0,0,0,0"], LIST_BAD),
            opt("--accelerations", Kind::Optional, &["0,50,0,0,0,0", "0,0,0,0,0,-1e6"], LIST_BAD),
            flag("--deg"),
        ],
    },
    Sub {
        path: &["screenshot"],
        complete: true,
        robot: true,
        connect: false,
        positional: true,
        opts: &[
            opt("--size", Kind::Always, &["32x24", "48x32"], &["0x0", "99999x1", "abc", "", "64", "-1x5"]),
            opt("--repeat", Kind::Optional, &["1", "2"], BAD_COUNTS),
            opt("--joints", Kind::Optional, JOINTS_OK, LIST_BAD),
            flag("--deg"),
            flag("--ui"),
        ],
    },
    Sub {
        path: &["bench", "fk"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[opt("--n", Kind::Always, &["1", "50"], BAD_COUNTS)],
    },
    Sub {
        path: &["bench", "ik"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[opt("--n", Kind::Always, &["1", "20"], BAD_COUNTS)],
    },
    Sub {
        path: &["bench", "physics"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[
            opt("--n", Kind::Always, &["1", "100"], BAD_COUNTS),
            opt("--cpu-seconds", Kind::Always, &["0", "0.1"], &["-1", "601", "1e300", "NaN", "abc", ""]),
        ],
    },
    Sub {
        path: &["bench", "latency"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[
            opt("--n", Kind::Always, &["1", "50"], BAD_COUNTS),
            opt(
                "--interval-us",
                Kind::Optional,
                &["0", "200", "1000"],
                &["100001", "18446744073709551615", "-1", "abc"],
            ),
        ],
    },
    Sub {
        path: &["bench", "serial"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[
            opt("--seconds", Kind::Always, &["0.2"], &["0", "-1", "601", "1e300", "NaN", ""]),
            RATE,
            opt("--presses", Kind::Always, &["1", "2"], &["0", "1001", "18446744073709551615", "-1", "abc"]),
        ],
    },
    Sub {
        path: &["bench", "render"],
        complete: true,
        robot: true,
        connect: false,
        positional: false,
        opts: &[
            opt("--seconds", Kind::Always, &["0.1"], &["0", "-1", "601", "NaN", ""]),
            opt("--size", Kind::Always, &["64x48"], &["0x0", "abc", "99999x2"]),
            flag("--check"),
        ],
    },
    Sub { path: &["hw", "ports"], complete: true, robot: false, connect: false, positional: false, opts: &[] },
    Sub { path: &["hw", "status"], complete: true, robot: false, connect: true, positional: false, opts: &[RATE] },
    Sub { path: &["hw", "enable"], complete: true, robot: false, connect: true, positional: false, opts: &[RATE] },
    Sub { path: &["hw", "disable"], complete: true, robot: false, connect: true, positional: false, opts: &[RATE] },
    Sub { path: &["hw", "home"], complete: true, robot: false, connect: true, positional: false, opts: &[RATE] },
    Sub {
        path: &["hw", "jog"],
        complete: true,
        robot: false,
        connect: true,
        positional: false,
        opts: &[
            opt("--joint", Kind::Required, &["1", "6"], &["0", "7", "-1", "18446744073709551615", "abc", ""]),
            opt(
                "--speed",
                Kind::Required,
                &["0.5", "-0.5", "0", "1"],
                &["2", "-1.5", "NaN", "inf", "", "abc", "1e400"],
            ),
            opt("--seconds", Kind::Required, &["0.1", "0.3"], &["0", "-1", "61", "1e300", "NaN", ""]),
            RATE,
        ],
    },
    Sub {
        path: &["hw", "move"],
        complete: true,
        robot: false,
        connect: true,
        positional: false,
        opts: &[
            opt("--joints", Kind::Required, &["90,-90,180,0,0,170", "1.5,-1.5,3,0,0,3"], LIST_BAD),
            opt("--speed", Kind::Optional, &["0.5", "1", "0.05"], &["5", "1e-4", "1e-300", "0", "-1", "NaN", ""]),
            flag("--deg"),
            flag("--smooth"),
            RATE,
        ],
    },
    Sub {
        path: &["hw", "emulate"],
        complete: true,
        robot: false,
        connect: false,
        positional: false,
        opts: &[flag("--homed"), opt("--home-seconds", Kind::Optional, &["0.5", "60"], &["0", "61", "-1", "NaN", ""])],
    },
    Sub { path: &["bench"], complete: false, robot: false, connect: false, positional: false, opts: &[] },
    Sub { path: &["hw"], complete: false, robot: false, connect: false, positional: false, opts: &[] },
];

/// Builds one argument vector from random numbers; returns it and whether it is valid input.
fn build(sub: &Sub, random: &[u32], out_png: &str) -> (Vec<String>, bool) {
    let mut k = 0usize;
    let mut next = |m: usize| -> usize {
        let v = random[k % random.len()] as usize;
        k += 1;
        v % m.max(1)
    };
    let mut valid = sub.complete;
    let mut local: Vec<String> = Vec::new();
    if sub.positional {
        match next(8) {
            0 => valid = false,
            1 => {
                local.push(["-", ""][next(2)].into());
                valid = false;
            }
            _ => local.push(out_png.into()),
        }
    }
    // Per option: 1 in 8 left out, 1 in 8 invalid, else valid (optional ones left out more).
    for o in sub.opts {
        let choice = next(8);
        match (o.kind, choice) {
            (Kind::Flag, 0..4) => local.push(o.name.into()),
            (Kind::Flag, _) => {}
            (Kind::Required, 0) => valid = false,
            (Kind::Optional, 0 | 2 | 3) => {}
            (_, 1) => {
                let pool: Vec<&str> =
                    o.invalid.iter().chain(if o.name == "--size" { &[][..] } else { GARBAGE }).copied().collect();
                local.push(o.name.into());
                local.push(pool[next(pool.len())].into());
                valid = false;
            }
            _ => {
                local.push(o.name.into());
                local.push(o.valid[next(o.valid.len())].into());
            }
        }
    }
    let mut global: Vec<String> = Vec::new();
    match next(8) {
        0 => global.extend(["--tool", "ssg48"].map(String::from)),
        1 => global.extend(["--urdf", "assets/parol6/parol6.urdf", "--tip", "L6"].map(String::from)),
        2 => {
            let bad = [["--tool", "hammer"], ["--urdf", "/nonexistent/robot.urdf"], ["--tip", "L9"]][next(3)];
            global.extend(bad.map(String::from));
            valid = false;
        }
        _ => {}
    }
    if !global.is_empty() && !sub.robot {
        valid = false;
    }
    if sub.connect {
        // Never auto-detect: a real arm may be plugged into this machine.
        match next(8) {
            0 => global.extend(["--port", "/nonexistent/ttyACM9"].map(String::from)),
            1 => {
                global.extend(["--port", "/nonexistent/ttyACM9", "--fake-robot"].map(String::from));
                valid = false;
            }
            _ => global.push("--fake-robot".into()),
        }
    } else if next(8) == 0 {
        global.push("--fake-robot".into());
        valid = false;
    }
    // An option of another subcommand.
    if next(8) == 0 {
        let all: Vec<&str> = SUBS.iter().flat_map(|s| s.opts.iter().map(|o| o.name)).collect();
        let foreign: Vec<&str> = all.into_iter().filter(|n| !sub.opts.iter().any(|o| o.name == *n)).collect();
        local.push(foreign[next(foreign.len())].into());
        local.push("1".into());
        valid = false;
    }
    let path = sub.path.iter().map(|s| s.to_string());
    let args = if next(2) == 0 {
        global.into_iter().chain(path).chain(local).collect()
    } else {
        path.chain(local).chain(global).collect()
    };
    (args, valid)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_argument_vectors_never_panic_and_exit_0_only_when_valid(
        sub_index in 0..SUBS.len(),
        random in proptest::collection::vec(any::<u32>(), 24),
    ) {
        let tmp = std::env::temp_dir().join(format!("parol6-prop-{}", std::process::id()));
        std::fs::create_dir_all(&tmp).expect("temp dir");
        let out_png = tmp.join("shot.png").display().to_string();
        let (args, valid) = build(&SUBS[sub_index], &random, &out_png);
        let run = cli_support::run_in(cli_support::workspace_root(), &args, Duration::from_secs(60));
        let what = format!("parol6 {}", args.join(" "));
        prop_assert!(!run.stderr.contains("panicked at"), "{}: panicked: {:?}", what, run);
        prop_assert!(run.code().is_some(), "{}: signal, abort or hang: {:?}", what, run);
        prop_assert!(matches!(run.code(), Some(0..=2)), "{}: exit {:?}: {:?}", what, run.code(), run);
        prop_assert!(run.code() != Some(0) || valid, "{}: invalid input accepted: {:?}", what, run);
        eprintln!("valid={valid} exit={:?} {:.2} s: {what}", run.code(), run.elapsed.as_secs_f64());
    }
}

/// The generator is not lopsided: a fair share of its vectors are valid input (so exit 0 is
/// exercised), and every subcommand gets valid vectors.
#[test]
fn generator_yields_valid_and_invalid_vectors_for_every_subcommand() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    for sub in SUBS {
        let valid = (0..400)
            .filter(|_| {
                let random: Vec<u32> = (0..24).map(|_| rng.random()).collect();
                build(sub, &random, "/tmp/x.png").1
            })
            .count();
        let want_valid = if sub.complete { 20..=380 } else { 0..=0 };
        assert!(want_valid.contains(&valid), "{:?}: {valid} of 400 valid", sub.path);
    }
}
