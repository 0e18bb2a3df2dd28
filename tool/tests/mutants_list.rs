//! The mutation check (`scripts/mutants.sh`, not in CI) stays runnable: every
//! mutant of `scripts/mutants.txt` names a file that exists, its text occurs
//! there exactly once, its replacement differs, and its test is a cargo test
//! selection. A generator edit that moves a mutated line fails here, not
//! months later in a release run.

use std::path::Path;

#[test]
fn every_mutant_applies_exactly_once() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let list = std::fs::read_to_string(root.join("scripts/mutants.txt"))
        .expect("scripts/mutants.txt is readable");
    let mut mutants = 0;
    for (n, line) in list.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        let at = format!("scripts/mutants.txt line {}", n + 1);
        let fields: Vec<&str> = line.split(" ||| ").collect();
        assert_eq!(
            fields.len(),
            5,
            "{at}: unit ||| file ||| text ||| replacement ||| test"
        );
        let (file, text, replacement, test) = (fields[1], fields[2], fields[3], fields[4]);
        let source = std::fs::read_to_string(root.join(file))
            .unwrap_or_else(|e| panic!("{at}: {file}: {e}"));
        assert_eq!(
            source.matches(text).count(),
            1,
            "{at}: `{text}` must occur exactly once in {file}"
        );
        assert_ne!(text, replacement, "{at}: the replacement changes nothing");
        assert!(
            test.starts_with("-p "),
            "{at}: the test is a cargo selection: {test}"
        );
        mutants += 1;
    }
    assert!(mutants >= 12, "{mutants} mutants listed");
}
