//! The mutation testing (`scripts/mutants.sh`, cargo-mutants; its `--in-diff`
//! mode runs in CI) stays pointed at real code and real tests: every glob of
//! `.cargo/mutants.toml` matches a file, and every integration test target
//! that `scripts/mutants-cargo.sh` runs exists and holds a test whose name
//! contains `evaluator` (the filter it runs them with). A renamed target or
//! test fails here, not as a mutation run that quietly tests nothing.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The quoted strings of the TOML array `key = [ ... ]`.
fn toml_list(text: &str, key: &str) -> Vec<String> {
    let start = text
        .find(&format!("{key} = ["))
        .unwrap_or_else(|| panic!(".cargo/mutants.toml has no `{key} = [`"));
    let body = &text[start..];
    let body = &body[..body.find(']').expect("the array closes")];
    body.split('"')
        .skip(1)
        .step_by(2)
        .map(String::from)
        .collect()
}

/// The files under `dir` (relative to the root) whose path matches `glob`
/// (only the two forms the config uses: `dir/**/*.rs` and a plain path).
fn matches(glob: &str) -> usize {
    match glob.strip_suffix("/**/*.rs") {
        Some(dir) => {
            let mut n = 0;
            let mut stack = vec![root().join(dir)];
            while let Some(d) = stack.pop() {
                for e in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{glob}: {e}")) {
                    let p = e.expect("a directory entry").path();
                    if p.is_dir() {
                        stack.push(p);
                    } else if p.extension().is_some_and(|x| x == "rs") {
                        n += 1;
                    }
                }
            }
            n
        }
        None => {
            assert!(!glob.contains('*'), "{glob}: only dir/**/*.rs or a path");
            usize::from(root().join(glob).is_file())
        }
    }
}

#[test]
fn every_glob_of_the_config_matches_a_file() {
    let config = read(".cargo/mutants.toml");
    let examined = toml_list(&config, "examine_globs");
    let excluded = toml_list(&config, "exclude_globs");
    assert!(examined.len() >= 3, "{examined:?}");
    for glob in examined.iter().chain(&excluded) {
        assert!(
            matches(glob) > 0,
            ".cargo/mutants.toml: `{glob}` matches no file"
        );
    }
}

#[test]
fn every_evaluator_target_exists_and_holds_an_evaluator_test() {
    let wrapper = read("scripts/mutants-cargo.sh");
    let line = wrapper
        .lines()
        .find(|l| l.starts_with("evaluator_targets=("))
        .expect("scripts/mutants-cargo.sh names its evaluator_targets");
    let targets: Vec<&str> = line
        .trim_start_matches("evaluator_targets=(")
        .trim_end_matches(')')
        .split_whitespace()
        .collect();
    assert!(targets.len() >= 5, "{targets:?}");
    let manifest = read("tests/Cargo.toml");
    for t in targets {
        assert!(
            manifest.contains(&format!("name = \"{t}\"")),
            "scripts/mutants-cargo.sh: no test target {t} in tests/Cargo.toml"
        );
        let source = read(&format!("tests/{t}.rs"));
        let evaluators = source
            .lines()
            .filter(|l| l.starts_with("fn ") && l.contains("evaluator"))
            .count();
        assert!(
            evaluators > 0,
            "tests/{t}.rs has no test named *evaluator*: scripts/mutants-cargo.sh would run none of it"
        );
    }
}
