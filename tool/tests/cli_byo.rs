//! Bring-your-own vectors through the CLI: the README's script, the worked
//! examples of docs/flow.md, `sim`, `golden`, `vectors`, `convert`, bad input
//! files, reports.

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

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A document of the repository, by its path from the workspace root.
fn doc(path: &str) -> String {
    let full = format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

/// The first fenced block after `marker` in the document at `path`.
fn block_after(path: &str, marker: &str) -> String {
    let r = doc(path);
    let at = r
        .find(marker)
        .unwrap_or_else(|| panic!("{path} lacks {marker}"));
    let rest = &r[at..];
    let start = rest.find("```").unwrap();
    let body = &rest[start..];
    let body = &body[body.find('\n').unwrap() + 1..];
    body[..body.find("```").unwrap()].to_string()
}

/// The fenced block after `marker` in the README.
fn readme_block(marker: &str) -> String {
    block_after("README.md", marker)
}

/// The fenced block after `marker` in docs/flow.md (the worked examples).
fn flow_block_after(marker: &str) -> String {
    block_after("docs/flow.md", marker)
}

#[test]
fn the_readme_script_writes_vectors_that_run_through_sim_and_golden() {
    let dir = scratch("cli_byo_script");
    let script = readme_block("<!-- script:write-vectors -->");
    assert_eq!(
        script.lines().count(),
        5,
        "the README promises five lines:\n{script}"
    );
    std::fs::write(dir.join("write_vectors.py"), &script).unwrap();
    let py = Command::new("python3")
        .arg("write_vectors.py")
        .current_dir(&dir)
        .output()
        .expect("python3 runs");
    assert!(py.status.success(), "{}", text(&py));

    let o = rtl_gen_in(
        &dir,
        &[
            "sim",
            "mulcmp",
            "--in",
            "mulcmp_in.txt",
            "--out",
            "results.txt",
            "--dir",
            "gen",
            "--report",
            "sim.json",
            "--junit",
            "sim.xml",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("1000 vectors, 0 mismatches"),
        "{}",
        text(&o)
    );
    let o = rtl_gen_in(
        &dir,
        &[
            "golden",
            "mulcmp",
            "--in",
            "mulcmp_in.txt",
            "--out",
            "golden.txt",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let sim_out = std::fs::read_to_string(dir.join("results.txt")).unwrap();
    let golden_out = std::fs::read_to_string(dir.join("golden.txt")).unwrap();
    assert_eq!(sim_out, golden_out, "RTL and golden results agree");
    let lines: Vec<&str> = sim_out.lines().collect();
    assert_eq!(lines.len(), 2 + 1000);
    assert!(
        lines[1].starts_with("a:16") && lines[1].contains("ab:32"),
        "{}",
        lines[1]
    );

    // The inputs are echoed: the first record is the script's first line.
    let input = std::fs::read_to_string(dir.join("mulcmp_in.txt")).unwrap();
    let first_in: Vec<u64> = input.lines().nth(1).unwrap().split(' ').map(hex).collect();
    let first_out: Vec<u64> = lines[2].split_ascii_whitespace().map(hex).collect();
    assert_eq!(first_in[..], first_out[..4]);
    let (a, b, c, d) = (first_in[0], first_in[1], first_in[2], first_in[3]);
    assert_eq!(
        first_out[4..],
        [(a * b < c * d) as u64, (a * b == c * d) as u64, a * b]
    );

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sim.json")).unwrap()).unwrap();
    assert_eq!(report["kind"], "sim");
    assert_eq!(report["vectors"], 1000);
    assert_eq!(report["passed"], true);
    assert_eq!(report["input"], "mulcmp_in.txt");
    let junit = std::fs::read_to_string(dir.join("sim.xml")).unwrap();
    assert!(junit.contains("failures=\"0\" errors=\"0\""), "{junit}");
}

fn hex(s: &str) -> u64 {
    u64::from_str_radix(s.trim_start_matches("0x"), 16).unwrap()
}

#[test]
fn the_readme_worked_examples_give_the_results_shown() {
    let dir = scratch("cli_byo_examples");
    std::fs::write(
        dir.join("mulcmp_in.txt"),
        flow_block_after("`mulcmp_in.txt`:"),
    )
    .unwrap();
    let o = rtl_gen_in(
        &dir,
        &[
            "golden",
            "mulcmp",
            "--in",
            "mulcmp_in.txt",
            "--out",
            "results.txt",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        std::fs::read_to_string(dir.join("results.txt")).unwrap(),
        flow_block_after("--out results.txt` writes:")
    );
    std::fs::write(
        dir.join("fadd_in.txt"),
        flow_block_after("(`fadd`, binary32 by default"),
    )
    .unwrap();
    let o = rtl_gen_in(
        &dir,
        &[
            "golden",
            "fadd",
            "--in",
            "fadd_in.txt",
            "--out",
            "fadd_out.txt",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let out = std::fs::read_to_string(dir.join("fadd_out.txt")).unwrap();
    let rows: Vec<Vec<u64>> = out
        .lines()
        .skip(2)
        .map(|l| l.split_ascii_whitespace().map(hex).collect())
        .collect();
    assert_eq!(rows[0][2], 0x4040_0000, "1 + 2 = 3");
    assert_eq!(rows[1][2], 0x7f80_0000, "overflow to +inf");
}

#[test]
fn every_unit_writes_an_example_that_its_golden_model_accepts() {
    let dir = scratch("cli_byo_every_unit");
    let list = text(&rtl_gen_in(&dir, &["list"]));
    let units: Vec<&str> = list
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with(' '))
        .filter_map(|l| l.split(':').next())
        .collect();
    assert!(units.contains(&"mulcmp"), "{list}");
    for u in units {
        let (file, out) = (format!("{u}.txt"), format!("{u}.out.rtlvec"));
        let o = rtl_gen_in(&dir, &["vectors", u, "--count", "20", "--out", &file]);
        assert!(o.status.success(), "{u}: {}", text(&o));
        let o = rtl_gen_in(&dir, &["golden", u, "--in", &file, "--out", &out]);
        assert!(o.status.success(), "{u}: {}", text(&o));
        assert!(
            text(&o).contains("(rtlvec, 20 records)"),
            "{u}: {}",
            text(&o)
        );
    }
}

#[test]
fn bad_input_files_name_file_line_and_field_and_leave_no_results() {
    let dir = scratch("cli_byo_bad");
    let cases: &[(&str, &str, &str)] = &[
        (
            "count.txt",
            "a b c d\n1 2 3 4\n1 2 3\n",
            "count.txt: line 3: wrong field count: 3 values but the header has 4 ports",
        ),
        (
            "port.txt",
            "a b c e\n1 2 3 4\n",
            "port.txt: line 1, field `e`: unknown port (expected ports: a, b, c, d)",
        ),
        (
            "wide.txt",
            "# comment\na b c d\n1 2 3 4\n1 0x10000 3 4\n",
            "wide.txt: line 4, field `b`: value wider than port: 0x10000 does not fit 16 bits",
        ),
        (
            "digit.txt",
            "a b c d\n1 2 3 0xg\n",
            "digit.txt: line 2, field `d`: `0xg` is not a hex number",
        ),
    ];
    for &(file, content, want) in cases {
        std::fs::write(dir.join(file), content).unwrap();
        for cmd in ["sim", "golden"] {
            let out = format!("{file}.{cmd}.txt");
            let mut args = vec![cmd, "mulcmp", "--in", file, "--out", &out];
            if cmd == "sim" {
                args.extend(["--dir", "gen"]);
            }
            let o = rtl_gen_in(&dir, &args);
            assert_eq!(o.status.code(), Some(2), "{cmd} {file}: {}", text(&o));
            let t = text(&o);
            assert!(t.contains(want), "{cmd} {file}: {t}");
            assert!(
                t.contains(&format!("no results file written: {out}")),
                "{t}"
            );
            assert!(!dir.join(&out).exists(), "{cmd} {file}: {out} exists");
        }
    }

    // A binary file cut in its last record, and an existing results file
    // that must survive the failed run.
    let o = rtl_gen_in(
        &dir,
        &["vectors", "mulcmp", "--count", "3", "--out", "three.rtlvec"],
    );
    assert!(o.status.success(), "{}", text(&o));
    let mut bytes = std::fs::read(dir.join("three.rtlvec")).unwrap();
    bytes.pop();
    std::fs::write(dir.join("cut.rtlvec"), bytes).unwrap();
    std::fs::write(dir.join("old.txt"), "precious").unwrap();
    let o = rtl_gen_in(
        &dir,
        &[
            "sim",
            "mulcmp",
            "--in",
            "cut.rtlvec",
            "--out",
            "old.txt",
            "--dir",
            "gen",
            "--report",
            "bad.json",
            "--junit",
            "bad.xml",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains(
            "cut.rtlvec: record 2 (byte offset 45): truncated record at end of stream: 7 of 8 bytes"
        ),
        "{}",
        text(&o)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("old.txt")).unwrap(),
        "precious"
    );
    // The reports of a failed run say why.
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("bad.json")).unwrap()).unwrap();
    assert_eq!(report["passed"], false);
    assert!(report["error"]
        .as_str()
        .unwrap()
        .contains("truncated record"));
    let junit = std::fs::read_to_string(dir.join("bad.xml")).unwrap();
    assert!(junit.contains("<error type=\"error\""), "{junit}");
    let leftovers: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn convert_goes_both_ways_and_checks_ports_against_a_unit() {
    let dir = scratch("cli_byo_convert");
    std::fs::write(dir.join("in.txt"), "d c b a\n4 3 2 1\n0x10 0 0 0xffff\n").unwrap();
    // Without a unit, the text header needs widths.
    let o = rtl_gen_in(&dir, &["convert", "in.txt", "in.rtlvec"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("field `d`: no width"), "{}", text(&o));
    let o = rtl_gen_in(
        &dir,
        &["convert", "in.txt", "in.rtlvec", "--unit", "mulcmp"],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("(rtlvec, 2 records)"), "{}", text(&o));
    let o = rtl_gen_in(&dir, &["convert", "in.rtlvec", "back.txt"]);
    assert!(o.status.success(), "{}", text(&o));
    let back = std::fs::read_to_string(dir.join("back.txt")).unwrap();
    // Records come out in the port list's order.
    assert!(back.contains("0x0001 0x0002 0x0003 0x0004"), "{back}");
    assert!(back.contains("0xffff 0x0000 0x0000 0x0010"), "{back}");
    // A binary input runs through `golden` just like text.
    let o = rtl_gen_in(
        &dir,
        &["golden", "mulcmp", "--in", "in.rtlvec", "--out", "r.txt"],
    );
    assert!(o.status.success(), "{}", text(&o));
}

#[test]
fn a_port_the_mode_does_not_have_is_named_with_the_mode() {
    let dir = scratch("cli_byo_mode_port");
    // a bundle file (d_hi_x) given to the ray-mode silhouette tester
    let header =
        "p_min_x p_min_y p_min_z p_max_x p_max_y p_max_z o_x o_y o_z d_hi_x d_y d_z t_min t_max";
    std::fs::write(
        dir.join("bundle.txt"),
        format!("{header}\n0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"),
    )
    .unwrap();
    for cmd in ["golden", "sim"] {
        let out = format!("bundle.{cmd}.txt");
        let mut args = vec![
            cmd,
            "silhouette",
            "-p",
            "mode=ray",
            "--in",
            "bundle.txt",
            "--out",
            &out,
        ];
        if cmd == "sim" {
            args.extend(["--dir", "gen"]);
        }
        let o = rtl_gen_in(&dir, &args);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {t}");
        assert!(t.contains("field `d_hi_x`: unknown port"), "{cmd}: {t}");
        assert!(
            t.contains("mode=ray"),
            "{cmd}: the error names the mode: {t}"
        );
        assert!(!dir.join(&out).exists(), "{cmd}: {out} exists");
    }
}
