//! `check --shard K/N --jobs N --report --junit` and `merge-reports`, run as
//! a CI matrix would.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rtl_gen_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("rtl-gen runs")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn json(path: PathBuf) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn check(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "check",
        "mulcmp",
        "-p",
        "stages=2",
        "--vectors",
        "200001",
        "--seed",
        "5",
        "--out",
        "gen",
    ];
    args.extend_from_slice(extra);
    rtl_gen_in(dir, &args)
}

#[test]
fn four_shards_merge_into_the_unsharded_verdict_with_json_and_junit() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_shards");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    let o = check(
        &dir,
        &[
            "--jobs",
            "2",
            "--report",
            "whole.json",
            "--junit",
            "whole.xml",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("2 workers, M vectors/s each"),
        "{}",
        text(&o)
    );
    let whole = json(dir.join("whole.json"));
    for key in [
        "unit",
        "module",
        "params",
        "generator",
        "verilog_hash",
        "seed",
        "shard",
        "vectors",
        "mismatches",
        "first_mismatch",
        "vectors_per_sec",
        "wall_time_s",
        "workers",
    ] {
        assert!(whole.get(key).is_some(), "report lacks {key}: {whole}");
    }
    assert_eq!(whole["unit"], "mulcmp");
    assert_eq!(whole["params"]["stages"], "2");
    assert_eq!(whole["params"]["a_width"], "16", "defaults are recorded");
    assert_eq!(whole["seed"], 5);
    assert_eq!(whole["vectors"], 200_001);
    assert_eq!(whole["workers"].as_array().unwrap().len(), 2);
    assert_eq!(whole["verilog_hash"].as_str().unwrap().len(), 32);
    assert_eq!(whole["passed"], true);
    let junit = std::fs::read_to_string(dir.join("whole.xml")).unwrap();
    assert!(
        junit.starts_with("<?xml") && junit.contains("<testcase classname=\"rtl-gen.mulcmp\""),
        "{junit}"
    );
    assert!(junit.contains("failures=\"0\" errors=\"0\""), "{junit}");
    assert!(
        junit.contains("<property name=\"seed\" value=\"5\"/>"),
        "{junit}"
    );

    let mut reports = Vec::new();
    for k in 1..=4 {
        let shard = format!("{k}/4");
        let report = format!("shard{k}.json");
        let o = check(
            &dir,
            &["--shard", &shard, "--jobs", "1", "--report", &report],
        );
        assert!(o.status.success(), "{}", text(&o));
        assert!(
            text(&o).contains(&format!("shard       {k}/4")),
            "{}",
            text(&o)
        );
        let r = json(dir.join(&report));
        assert_eq!(r["shard"]["index"], k);
        assert_eq!(r["shard"]["count"], 4);
        assert_eq!(r["verilog_hash"], whole["verilog_hash"]);
        reports.push(report);
    }
    let mut args = vec!["merge-reports"];
    args.extend(reports.iter().map(String::as_str));
    args.extend(["--out", "merged.json", "--junit", "merged.xml"]);
    let o = rtl_gen_in(&dir, &args);
    assert!(o.status.success(), "{}", text(&o));
    let merged = json(dir.join("merged.json"));
    assert_eq!(merged["vectors"], whole["vectors"]);
    assert_eq!(merged["mismatches"], whole["mismatches"]);
    assert_eq!(merged["passed"], whole["passed"]);
    assert_eq!(
        merged["evaluator"]["vectors"],
        whole["evaluator"]["vectors"]
    );
    assert!(std::fs::read_to_string(dir.join("merged.xml"))
        .unwrap()
        .contains("tests=\"1\" failures=\"0\""));

    // Three of four shards: no verdict.
    let o = rtl_gen_in(
        &dir,
        &["merge-reports", "shard1.json", "shard2.json", "shard4.json"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("shard(s) 3/4 missing"), "{}", text(&o));

    // Bad --shard and --jobs values are usage errors.
    for bad in [
        &["--shard", "5/4"][..],
        &["--shard", "0/4"],
        &["--jobs", "0"],
    ] {
        let o = check(&dir, bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", text(&o));
    }
}

#[test]
fn a_progress_bar_is_drawn_on_a_terminal_only() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_progress");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let bin = env!("CARGO_BIN_EXE_rtl-gen");
    let cmd = format!("{bin} check mulcmp -p stages=2 --vectors 3000000 --jobs 1 --out gen");
    // `script` gives the command a pseudo-terminal.
    let tty = |extra: &str| {
        let o = Command::new("script")
            .args(["-qfec", &format!("{cmd}{extra}"), "/dev/null"])
            .current_dir(&dir)
            .output()
            .expect("`script` (util-linux) runs");
        assert!(o.status.success(), "{}", text(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let drawn = tty("");
    assert!(
        drawn.contains("/3,000,000 vectors") && drawn.contains("M vectors/s"),
        "{drawn}"
    );
    assert!(!tty(" --no-progress").contains("/3,000,000 vectors"));
    // Piped stderr: no bar and no progress lines at all.
    let o = check(&dir, &[]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
