//! The README against the command it describes: every `rtl-gen <command>` it
//! names exists in `rtl-gen --help`, its unit table lists exactly the units of
//! `rtl-gen list`, its links resolve, it keeps the two commands CI and the main
//! job run, and it stays a first read (at most 250 lines and 2,500 words).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

const MAX_LINES: usize = 250;
const MAX_WORDS: usize = 2_500;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).expect("README.md is readable")
}

fn rtl_gen(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .output()
        .expect("rtl-gen runs");
    assert!(o.status.success(), "rtl-gen {args:?} failed");
    String::from_utf8(o.stdout).expect("utf-8 output")
}

/// The subcommands listed under `Commands:` in `rtl-gen --help`.
fn help_commands() -> BTreeSet<String> {
    let help = rtl_gen(&["--help"]);
    let at = help.find("Commands:").expect("--help lists its commands");
    help[at..]
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_string)
        .collect()
}

/// The units of `rtl-gen list`: its unindented lines, `name: summary`.
fn listed_units() -> BTreeSet<String> {
    rtl_gen(&["list"])
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with(' '))
        .filter_map(|l| l.split(':').next())
        .map(str::to_string)
        .collect()
}

/// Every word that follows `rtl-gen ` or `rtl-gen -- ` in `text` and starts
/// with a lower-case letter: the subcommands the text names.
fn named_commands(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (at, _) in text.match_indices("rtl-gen ") {
        let mut rest = &text[at + "rtl-gen ".len()..];
        if let Some(r) = rest.strip_prefix("-- ") {
            rest = r;
        }
        let word: String = rest
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-')
            .collect();
        if word.starts_with(|c: char| c.is_ascii_lowercase()) {
            out.insert(word);
        }
    }
    out
}

/// The back-quoted names in the first column of the table under `## The units`.
fn table_units(text: &str) -> BTreeSet<String> {
    let at = text
        .find("\n## The units")
        .expect("the README has a section `## The units`");
    let section = &text[at + 1..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    let rows = section
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2); // the header and its separator
    let mut units = BTreeSet::new();
    for row in rows {
        let first = row.split('|').nth(1).expect("a table row has cells");
        units.extend(
            first
                .split('`')
                .skip(1)
                .step_by(2)
                .map(|u| u.split_whitespace().next().unwrap_or("").to_string()),
        );
    }
    units
}

#[test]
fn every_command_the_readme_names_exists() {
    let known = help_commands();
    assert!(
        known.contains("check") && known.contains("list"),
        "{known:?}"
    );
    let named = named_commands(&readme());
    assert!(
        named.contains("emit"),
        "the parser finds commands: {named:?}"
    );
    let unknown: Vec<_> = named.difference(&known).collect();
    assert!(
        unknown.is_empty(),
        "the README names `rtl-gen` commands that `rtl-gen --help` does not list: {unknown:?} \
         (known: {known:?})"
    );
}

#[test]
fn the_unit_table_lists_exactly_the_units_of_rtl_gen_list() {
    let listed = listed_units();
    assert!(listed.contains("mulcmp"), "{listed:?}");
    let table = table_units(&readme());
    let missing: Vec<_> = listed.difference(&table).collect();
    let extra: Vec<_> = table.difference(&listed).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "README unit table against `rtl-gen list`: missing {missing:?}, not a unit {extra:?}"
    );
}

#[test]
fn the_readme_stays_a_first_read() {
    let text = readme();
    let lines = text.lines().count();
    let words = text.split_whitespace().count();
    assert!(
        lines <= MAX_LINES,
        "README.md has {lines} lines (at most {MAX_LINES}): move detail to docs/"
    );
    assert!(
        words <= MAX_WORDS,
        "README.md has {words} words (at most {MAX_WORDS}): move detail to docs/"
    );
}

#[test]
fn the_readme_keeps_the_two_commands_ci_runs() {
    let text = readme();
    let tests = "bash scripts/setup.sh && cargo test --release --workspace";
    assert!(text.contains("bash scripts/main.sh"), "the main job");
    assert!(text.contains(tests), "the test command");
    let ci = std::fs::read_to_string(root().join(".ci/run")).expect(".ci/run is readable");
    assert!(
        ci.lines().any(|l| l.trim() == tests),
        ".ci/run runs the README's test command exactly"
    );
    let mutants = "bash scripts/mutants.sh --in-diff";
    assert!(
        text.contains(mutants) && ci.lines().any(|l| l.trim() == mutants),
        "the README and .ci/run both run the last change's mutants"
    );
    assert!(root().join("scripts/main.sh").is_file());
}

#[test]
fn the_readme_links_resolve() {
    let text = readme();
    let mut broken = Vec::new();
    for (at, _) in text.match_indices("](") {
        let rest = &text[at + 2..];
        let target = &rest[..rest.find(')').expect("a link is closed")];
        if target.starts_with("http") || target.starts_with('#') {
            continue;
        }
        let path = target.split('#').next().unwrap();
        if !root().join(path).exists() {
            broken.push(target.to_string());
        }
    }
    assert!(
        broken.is_empty(),
        "README links to missing files: {broken:?}"
    );
}

#[test]
fn the_parsers_see_drift() {
    // A command that does not exist and a unit row that is not a unit are seen.
    let text = "run `rtl-gen frobnicate x` or `cargo run --bin rtl-gen -- emit`\n\
                \n## The units\n\n| unit | what |\n|---|---|\n| `mulcmp`, `nounit` | x |\n\n## Next\n";
    let named = named_commands(text);
    assert_eq!(
        named,
        ["emit", "frobnicate"]
            .into_iter()
            .map(String::from)
            .collect()
    );
    assert!(!help_commands().contains("frobnicate"));
    assert_eq!(
        table_units(text),
        ["mulcmp", "nounit"].into_iter().map(String::from).collect()
    );
}
