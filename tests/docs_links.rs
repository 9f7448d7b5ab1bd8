//! Every relative link and picture in the project's Markdown (README, ARCHITECTURE, CONTRIBUTING,
//! `docs/`, `fuzz/README.md`) points at a file that is in the repository. A picture the manual shows
//! but git ignores would pass on the machine that made it and be broken in every clone, so the
//! target must also be tracked by git, not just present in this work tree.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::collections::BTreeSet;
use std::path::{Component, Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).canonicalize().expect("repository root")
}

/// The Markdown files whose links are checked, relative to the root.
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> =
        ["README.md", "ARCHITECTURE.md", "CONTRIBUTING.md", "fuzz/README.md"].iter().map(PathBuf::from).collect();
    let mut dirs = vec![PathBuf::from("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(root.join(&dir)).expect("docs folder") {
            let name = entry.expect("docs entry").file_name();
            let rel = dir.join(&name);
            if root.join(&rel).is_dir() {
                dirs.push(rel);
            } else if rel.extension().is_some_and(|e| e == "md") {
                files.push(rel);
            }
        }
    }
    files.retain(|f| root.join(f).is_file());
    files.sort();
    files
}

/// The targets of `[text](target)` and `![alt](target)` outside fenced code blocks and inline code.
fn link_targets(markdown: &str) -> Vec<(usize, String)> {
    let mut targets = Vec::new();
    let mut fenced = false;
    for (n, line) in markdown.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // drop inline code spans: a `](x)` inside backticks is an example, not a link
        let mut prose = String::new();
        for (i, part) in line.split('`').enumerate() {
            if i % 2 == 0 {
                prose.push_str(part);
            }
        }
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].trim().trim_start_matches('<').trim_end_matches('>');
            let target = target.split_whitespace().next().unwrap_or("");
            targets.push((n + 1, target.to_string()));
            rest = &after[end..];
        }
    }
    targets
}

/// `path` with `.` and `..` resolved lexically, relative to the root.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

fn tracked_files(root: &Path) -> Option<BTreeSet<PathBuf>> {
    let out = Command::new("git").arg("-C").arg(root).args(["ls-files", "-z"]).output().ok()?;
    if !out.status.success() {
        return None;
    }
    Some(
        out.stdout
            .split(|b| *b == 0)
            .filter(|s| !s.is_empty())
            .map(|s| PathBuf::from(String::from_utf8_lossy(s).as_ref()))
            .collect(),
    )
}

#[test]
fn every_relative_link_in_the_docs_points_at_a_tracked_file() {
    let root = root();
    let tracked = tracked_files(&root);
    if tracked.is_none() {
        eprintln!("docs_links: not a git work tree (or no git): checking that link targets exist only");
    }
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in markdown_files(&root) {
        let text = std::fs::read_to_string(root.join(&file)).expect("markdown");
        let dir = file.parent().unwrap_or(Path::new(""));
        for (line, target) in link_targets(&text) {
            let path_part = target.split('#').next().unwrap_or("");
            if path_part.is_empty() || path_part.contains("://") || path_part.starts_with("mailto:") {
                continue;
            }
            let rel = normalise(&dir.join(path_part));
            checked += 1;
            let present = root.join(&rel).exists();
            // a folder link is fine when the folder holds a tracked file
            let is_tracked = match &tracked {
                None => present,
                Some(t) => t.contains(&rel) || t.iter().any(|f| f.starts_with(&rel) && f != &rel),
            };
            if !present || !is_tracked {
                let why = if present { "exists here but git does not track it" } else { "no such file" };
                broken.push(format!("{}:{line}: {target} ({why})", file.display()));
            }
        }
    }
    assert!(checked > 20, "only {checked} relative links found: the link scanner is broken");
    assert!(broken.is_empty(), "{} broken link(s) in the docs:\n{}", broken.len(), broken.join("\n"));
}

#[test]
fn the_link_scanner_finds_links_and_pictures_but_not_code() {
    let md = "See [the guide](docs/guide/README.md#top) and ![a picture](images/a.png).\n\
              `not [a](link.md)` here\n```\n[also](not.md)\n```\n[web](https://example.com)\n";
    let found: Vec<String> = link_targets(md).into_iter().map(|(_, t)| t).collect();
    assert_eq!(found, ["docs/guide/README.md#top", "images/a.png", "https://example.com"]);
    assert_eq!(normalise(Path::new("docs/guide/../images/a.png")), PathBuf::from("docs/images/a.png"));
}
