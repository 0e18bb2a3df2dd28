//! `rtl-gen check <float unit> --testfloat -`: TestFloat-format cases piped
//! in, written here from an independent oracle (the machine's binary32
//! arithmetic through Rust's `f32`, round to nearest even), with a few
//! wrong expected results planted in chosen classes.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn rtl_gen_piped(dir: &Path, args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("rtl-gen runs");
    let mut pipe = child.stdin.take().unwrap();
    let input = stdin.to_owned();
    let writer = std::thread::spawn(move || pipe.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    match writer.join().unwrap() {
        // the child may exit before reading everything (a rejected option):
        // its status and output are what the tests check
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => panic!("writing stdin: {e}"),
        _ => {}
    }
    out
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Deterministic operand bits: random, special and subnormal values.
fn operand(i: u64, k: u64) -> u32 {
    let mut z = (i * 2 + k).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 31)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z ^= z >> 29;
    let r = z as u32;
    match (z >> 40) % 16 {
        0 => [
            0,
            0x8000_0000,
            0x7f80_0000,
            0xff80_0000,
            0x7fc0_0000,
            0x7f7f_ffff,
            1,
        ][(z >> 48) as usize % 7],
        1 => r & 0x807f_ffff,                 // subnormal or zero
        2 => (r & 0x80ff_ffff) | 0x7e00_0000, // huge: overflow
        _ => r,
    }
}

/// A TestFloat line `a b result flags` for `op`.
fn line(a: u32, b: u32, r: u32) -> String {
    format!("{a:08X} {b:08X} {r:08X} 00")
}

#[test]
fn piped_cases_are_checked_against_rtl_and_golden_model_and_grouped_by_class() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_testfloat");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let f = f32::from_bits;
    let mut lines: Vec<String> = (0..20_000)
        .map(|i| {
            let (a, b) = (operand(i, 0), operand(i, 1));
            line(a, b, (f(a) + f(b)).to_bits())
        })
        .collect();
    // The machine's default NaN is not ours: only --nan-exact tells.
    let nan_lines = lines.iter().filter(|l| {
        let r = u32::from_str_radix(&l[18..26], 16).unwrap();
        f(r).is_nan() && r != 0x7fc0_0000
    });
    let foreign_nans = nan_lines.count();
    assert!(foreign_nans > 100, "the oracle's NaNs are x86's 0xFFC00000");
    // Planted: wrong expected results in four classes.
    lines[3] = line(0x3f80_0000, 0x4000_0000, 0x4040_0001); // 1 + 2 != 3 + ulp: other
    lines[10] = line(0x7f7f_ffff, 0x7f7f_ffff, 0x7f7f_ffff); // max + max is inf: overflow
    lines[11] = line(0x0000_0001, 0x0000_0001, 0x0000_0001); // 2 ulp: subnormal input
    lines[12] = line(0x00c0_0000, 0x8080_0000, 0x0040_0001); // is 0x40_0000: subnormal result
    let input = format!("# fadd binary32 rne, from f32\n{}\n", lines.join("\n"));
    let args = [
        "check",
        "fadd",
        "-p",
        "exp_bits=8",
        "-p",
        "frac_bits=23",
        "-p",
        "round=rne",
        "--testfloat",
        "-",
        "--out",
        "gen",
        "--report",
        "tf.json",
        "--junit",
        "tf.xml",
    ];
    let o = rtl_gen_piped(&dir, &args, &input);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("20000 TestFloat cases: RTL differs from the file in 4, golden model in 4, RTL from golden model in 0"),
        "{t}"
    );
    for (class, line_no) in [
        ("overflow", 12),
        ("subnormal input", 13),
        ("subnormal result", 14),
        ("other", 5),
    ] {
        assert!(
            t.contains(&format!("  {class}: RTL 1 golden 1")),
            "{class}: {t}"
        );
        assert!(t.contains(&format!("    line {line_no}: ")), "{class}: {t}");
    }
    assert!(t.contains("flags ignored"), "{t}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("tf.json")).unwrap()).unwrap();
    assert_eq!(r["kind"], "testfloat");
    assert_eq!(r["input"], "<stdin>");
    assert_eq!(r["vectors"], 20_000);
    assert_eq!(r["mismatches"], 4);
    assert_eq!(r["mismatch_classes"]["overflow (rtl)"], 1);
    assert_eq!(r["first_mismatch"]["location"], "<stdin> line 5");
    assert!(r["notes"]
        .to_string()
        .contains("any NaN result matches any expected NaN"));
    let junit = std::fs::read_to_string(dir.join("tf.xml")).unwrap();
    assert!(junit.contains("failures=\"1\""), "{junit}");

    // Without the planted lines: a pass, unless NaNs must match exactly.
    let clean: Vec<&String> = lines
        .iter()
        .enumerate()
        .filter(|(i, _)| ![3, 10, 11, 12].contains(i))
        .map(|(_, l)| l)
        .collect();
    let clean = clean
        .iter()
        .map(|s| s.as_str())
        .collect::<Vec<_>>()
        .join("\n");
    let o = rtl_gen_piped(&dir, &args[..12], &clean);
    assert!(o.status.success(), "{}", text(&o));
    let mut exact = args[..12].to_vec();
    exact.push("--nan-exact");
    let o = rtl_gen_piped(&dir, &exact, &clean);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains(&format!("  NaN: RTL {foreign_nans} golden {foreign_nans}")),
        "{}",
        text(&o)
    );
}

#[test]
fn comparisons_select_their_output_and_bad_lines_are_errors() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_testfloat_cmp");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let f = f32::from_bits;
    let lines: Vec<String> = (0..5_000)
        .map(|i| {
            let (a, b) = (operand(i, 0), operand(i, 1));
            format!("{a:08X} {b:08X} {} 00", (f(a) < f(b)) as u8)
        })
        .collect();
    let file = dir.join("f32_lt.txt");
    std::fs::write(&file, lines.join("\n")).unwrap();
    let base = ["check", "fcmp", "--testfloat", "f32_lt.txt", "--out", "gen"];
    let o = rtl_gen_piped(&dir, &base, "");
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("--result lt"), "{}", text(&o));
    let mut with_result = base.to_vec();
    with_result.extend(["--result", "lt"]);
    let o = rtl_gen_piped(&dir, &with_result, "");
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("5000 TestFloat cases: RTL differs from the file in 0"),
        "{}",
        text(&o)
    );

    // A binary64 case for a binary32 unit, a short line, a non-hex field.
    for (content, want) in [
        (
            "3FF0000000000000 3FF0000000000000 0 00\n",
            "<stdin>: line 1, field `a`: `3FF0000000000000` is not 8 hex digit(s)",
        ),
        (
            "3F800000 0\n",
            "<stdin>: line 1: wrong field count: 2 fields",
        ),
        (
            "\n3F800000 3F800000 x 00\n",
            "<stdin>: line 2, field `result lt`: `x` is not 1 hex digit(s)",
        ),
        ("# nothing\n", "no TestFloat cases"),
    ] {
        let mut args = with_result.clone();
        args[3] = "-";
        let o = rtl_gen_piped(&dir, &args, content);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(want), "{want}: {}", text(&o));
    }
}

#[test]
fn testfloat_spelling_of_format_and_rounding_mode_is_accepted() {
    let dir = std::env::temp_dir().join("rtl-gen-cli-testfloat-spelling");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // a + b rounded toward -inf, from f64 (exact for these binary32 operands) with
    // the rounding done by hand: 1 + 2^-30 lies between 1 and 1 + 2^-23
    let cases = [
        line(0x3f80_0000, 0x4000_0000, 0x4040_0000), // 1 + 2 = 3 exactly
        line(0x3f80_0000, 0x3080_0000, 0x3f80_0000), // 1 + 2^-30 -> 1 (down)
        line(0xbf80_0000, 0xb080_0000, 0xbf80_0001), // -1 - 2^-30 -> -(1 + 2^-23) (down)
    ]
    .join("\n");
    let args = [
        "check",
        "fadd",
        "--format",
        "binary32",
        "--round",
        "down",
        "--testfloat",
        "-",
    ];
    let o = rtl_gen_piped(&dir, &args, &cases);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("fadd_e8m23_rdn"), "{}", text(&o));
    let o = rtl_gen_piped(
        &dir,
        &[
            "check",
            "fadd",
            "--format",
            "e8m23",
            "--round",
            "near_maxMag",
            "--testfloat",
            "-",
        ],
        &cases,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("near_maxMag and odd rounding are not implemented"),
        "{}",
        text(&o)
    );
}

#[test]
fn nan_exact_without_testfloat_is_a_usage_error() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(["check", "fadd", "--nan-exact"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--testfloat"), "{err}");
}
