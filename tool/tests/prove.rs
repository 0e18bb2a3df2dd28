//! `rtl-gen prove --property equiv` as a user runs it (issue 39): pipelined
//! units proved equal to their stages=0 reference in both placements, and
//! two planted bugs (a wrong comparison, a valid bit one stage early) found,
//! each with a vector file that `rtl-gen sim --verilog` replays in Verilator
//! to the same wrong answer. Both solvers: Boolector (the default, through
//! yowasp-sby; a planted bug's trace then comes from Yosys sat) and Yosys sat
//! (`--solver sat`); and the structural proof (`--solver structural`) on the
//! triangle's pipelines and the same planted bugs. Needs the pinned Yosys and
//! Boolector (scripts/setup.sh);
//! without them the test fails saying so.

use std::path::{Path, PathBuf};
mod common;

use common::{rtl_gen, text};

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("prove-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The last line of a run that must end with `proved:`.
fn assert_proved(args: &[&str]) -> String {
    let o = rtl_gen(args);
    let t = text(&o);
    let last = t.lines().last().unwrap_or("");
    assert!(
        o.status.success() && last.starts_with("proved: "),
        "rtl-gen {args:?}: exit {:?}\n{t}",
        o.status.code()
    );
    last.to_string()
}

#[test]
fn pipelines_are_proved_equal_to_their_reference() {
    let w = scratch("ok");
    let work = |n: &str| w.join(n).display().to_string();
    let boolector = assert_proved(&[
        "prove",
        "mulcmp",
        "-p",
        "a_width=6",
        "-p",
        "b_width=6",
        "-p",
        "stages=2",
        "--work",
        &work("mulcmp"),
    ]);
    assert!(boolector.contains("k-induction, Boolector"), "{boolector}");
    let sat = assert_proved(&[
        "prove",
        "mulcmp",
        "-p",
        "a_width=6",
        "-p",
        "b_width=6",
        "-p",
        "stages=2",
        "--solver",
        "sat",
        "--work",
        &work("mulcmp-sat"),
    ]);
    assert!(sat.contains("temporal induction"), "{sat}");
    assert_proved(&[
        "prove",
        "fadd",
        "-p",
        "exp_bits=3",
        "-p",
        "frac_bits=2",
        "-p",
        "stages=3",
        "-p",
        "pipeline=balanced",
        "--work",
        &work("fadd"),
    ]);
    assert_proved(&[
        "prove",
        "node_sort",
        "-p",
        "children=4",
        "-p",
        "box_bits=4",
        "-p",
        "stages=2",
        "--work",
        &work("node_sort"),
    ]);
    // the largest unit in CI: the node tester at e3m2, whole products, balanced
    let node_work = work("node");
    let mut node = vec!["prove", "node"];
    node.extend(NODE_SMALL);
    node.extend([
        "-p",
        "products=whole",
        "-p",
        "pipeline=balanced",
        "-p",
        "stages=2",
        "--work",
        &node_work,
    ]);
    assert_proved(&node);
}

/// The node tester's smallest build (e3m2, N = 2, q = 4, m = 4), as `-p` arguments.
const NODE_SMALL: [&str; 10] = [
    "-p",
    "exp_bits=3",
    "-p",
    "frac_bits=2",
    "-p",
    "children=2",
    "-p",
    "box_bits=4",
    "-p",
    "slope_bits=4",
];

/// Emits mulcmp (6x6, 2 stages) into a directory, applies `edit` to its top
/// file, proves the edited copy (with `solver`'s arguments) and replays the
/// counterexample.
fn planted(name: &str, from: &str, to: &str, port: &str, solver: &[&str]) {
    let d = scratch(name);
    let rtl = d.join("rtl");
    let params = ["-p", "a_width=6", "-p", "b_width=6", "-p", "stages=2"];
    let mut emit = vec!["emit", "mulcmp"];
    emit.extend(params);
    let rtl_s = rtl.display().to_string();
    emit.extend(["--out", &rtl_s]);
    assert!(rtl_gen(&emit).status.success());
    let top = rtl.join("mulcmp_a6_b6_s2.v");
    let v = std::fs::read_to_string(&top).unwrap();
    assert!(
        v.contains(from),
        "the planted bug's text `{from}` is not in {}",
        top.display()
    );
    std::fs::write(&top, v.replacen(from, to, 1)).unwrap();

    let work = d.join("job").display().to_string();
    let mut prove = vec!["prove", "mulcmp"];
    prove.extend(params);
    prove.extend(["--verilog", &rtl_s, "--work", &work]);
    prove.extend(solver);
    let o = rtl_gen(&prove);
    let t = text(&o);
    let line = t
        .lines()
        .find(|l| l.starts_with("counterexample: "))
        .unwrap_or_else(|| panic!("{name}: no counterexample:\n{t}"));
    assert_eq!(o.status.code(), Some(1), "{name}: {t}");
    let vectors = d.join("job/counterexample.txt");
    let file = std::fs::read_to_string(&vectors).unwrap();
    assert!(
        file.starts_with("a b c d\n") && file.lines().count() >= 2,
        "{file}"
    );
    // the trace the line names
    let trace = line
        .split("; trace ")
        .nth(1)
        .and_then(|s| s.split(';').next())
        .unwrap_or_else(|| panic!("{name}: no trace in {line}"));
    assert!(
        Path::new(trace).is_file() && trace.ends_with(".vcd"),
        "{line}"
    );
    if port == "out_valid" {
        // a valid bit out of step is a timing bug: the cycle-accurate trace shows it
        // (on out_valid, or on an output compared in a cycle it is not valid in);
        // a replay of the transactions alone would not
        assert!(line.contains(" at cycle "), "{line}");
        return;
    }
    // "... output lt = 0x1 where the reference gives 0x0 ..."
    let needle = format!("output {port} = ");
    let at = line
        .find(&needle)
        .unwrap_or_else(|| panic!("{name}: {line}"))
        + needle.len();
    let dut_value = line[at..].split_whitespace().next().unwrap();
    let reference = line[at..]
        .split("where the reference")
        .nth(1)
        .and_then(|s| s.split_whitespace().find(|w| w.starts_with("0x")))
        .unwrap();
    assert_ne!(dut_value, reference, "{line}");
    // the replay command the line prints, run as printed
    let replay = line
        .split("replay: rtl-gen ")
        .nth(1)
        .unwrap()
        .trim_end_matches(')');
    let args: Vec<&str> = replay.split_whitespace().collect();
    let o = rtl_gen(&args);
    let t = text(&o);
    let row = t
        .lines()
        .find(|l| l.trim_start().starts_with(port) && l.contains("<- differs"))
        .unwrap_or_else(|| panic!("{name}: the replay shows no mismatch on {port}:\n{t}"));
    assert!(
        row.contains(&format!("rtl {dut_value}")),
        "{name}: the replay's {port} is not the proof's {dut_value}: {row}"
    );
}

/// The default job directory is relative (`out/prove/<module>`): a proof run
/// from another directory with a relative `--work` (Boolector's wrapper and
/// its log once resolved against SBY's directory and the proof ended in
/// ERROR).
#[test]
fn a_relative_job_directory_proves() {
    let d = scratch("relative");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .current_dir(&d)
        .args([
            "prove",
            "mulcmp",
            "-p",
            "a_width=4",
            "-p",
            "b_width=4",
            "-p",
            "stages=2",
            "--work",
            "jobs/mulcmp",
        ])
        .output()
        .expect("rtl-gen runs");
    let t = text(&o);
    assert!(
        o.status.success() && t.lines().last().unwrap_or("").starts_with("proved: "),
        "{t}"
    );
    assert!(d.join("jobs/mulcmp/sby.log").is_file());
}

#[test]
fn a_wrong_comparison_is_found_and_replays() {
    planted(
        "compare",
        "assign ab_lt_cd = u_mul_ab_p < u_mul_cd_p;",
        "assign ab_lt_cd = u_mul_ab_p <= u_mul_cd_p;",
        "lt",
        &[],
    );
}

#[test]
fn a_valid_bit_one_stage_early_is_found() {
    planted(
        "valid",
        "assign out_valid = valid_s2;",
        "assign out_valid = valid_s1;",
        "out_valid",
        &[],
    );
}

/// `--solver structural` (no k-induction): the triangle's pipelines, which
/// k-induction does not finish, proved at e2m1 in both placements and two
/// depths, and the shipped binary32 node tester at 4 stages; the same two
/// planted bugs found on mulcmp (the wrong comparison by
/// the register-free miter, replayed in Verilator; the early valid bit by the
/// induction on out_valid); and a pipeline with one path a register short
/// refused, naming the cell where the stages meet.
#[test]
fn the_structural_proof_proves_the_triangle_pipelines_and_finds_planted_bugs() {
    let w = scratch("structural");
    for stages in ["stages=2", "stages=4"] {
        for pipeline in ["pipeline=plan", "pipeline=balanced"] {
            // one of the four behind the valid/ready wrapper: its core is the
            // same pipeline, proved first, then the wrapper around a stand-in
            let handshake = if (stages, pipeline) == ("stages=2", "pipeline=plan") {
                "handshake=ready"
            } else {
                "handshake=valid"
            };
            let work = w.join(format!("{stages}-{pipeline}")).display().to_string();
            let line = assert_proved(&[
                "prove",
                "triangle",
                "-p",
                "exp_bits=2",
                "-p",
                "frac_bits=1",
                "-p",
                stages,
                "-p",
                pipeline,
                "-p",
                handshake,
                "--solver",
                "structural",
                "--work",
                &work,
            ]);
            assert!(line.contains("both pipelines balanced"), "{line}");
            if handshake == "handshake=ready" {
                assert!(
                    line.contains("the wrapper around a stand-in core: no transaction lost")
                        && line.contains("its data inputs read by the core alone"),
                    "{line}"
                );
            }
        }
    }
    // the shipped binary32 node tester (N = 4, q = 8) at 4 stages, whole products
    let work = w.join("node-binary32").display().to_string();
    let line = assert_proved(&[
        "prove",
        "node",
        "-p",
        "stages=4",
        "-p",
        "products=whole",
        "--solver",
        "structural",
        "--work",
        &work,
    ]);
    assert!(line.contains("node_n4_q8_m9_e8m23_whole_s4"), "{line}");
    planted(
        "structural-compare",
        "assign ab_lt_cd = u_mul_ab_p < u_mul_cd_p;",
        "assign ab_lt_cd = u_mul_ab_p <= u_mul_cd_p;",
        "lt",
        &["--solver", "structural"],
    );
    planted(
        "structural-valid",
        "assign out_valid = valid_s2;",
        "assign out_valid = valid_s1;",
        "out_valid",
        &["--solver", "structural"],
    );
    // the sign of s_z read one register early
    let rtl = w.join("short");
    let rtl_s = rtl.display().to_string();
    let params = ["-p", "exp_bits=2", "-p", "frac_bits=1", "-p", "stages=2"];
    let mut emit = vec!["emit", "triangle"];
    emit.extend(params);
    emit.extend(["--out", &rtl_s]);
    assert!(rtl_gen(&emit).status.success());
    let top = rtl.join("triangle_e2m1_full_s2.v");
    let v = std::fs::read_to_string(&top).unwrap();
    let from = "assign u_widen_s_z_a_sign = s_z_s1[3];";
    assert!(v.contains(from), "`{from}` is not in {}", top.display());
    std::fs::write(
        &top,
        v.replacen(from, "assign u_widen_s_z_a_sign = s_z[3];", 1),
    )
    .unwrap();
    let work = w.join("short-job").display().to_string();
    let mut prove = vec!["prove", "triangle"];
    prove.extend(params);
    prove.extend([
        "--verilog",
        &rtl_s,
        "--work",
        &work,
        "--solver",
        "structural",
    ]);
    let o = rtl_gen(&prove);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let last = t.lines().last().unwrap_or("");
    assert!(
        last.starts_with("not proved: ")
            && last.contains("not a balanced pipeline")
            && last.contains("stage 0")
            && last.contains("stage 1"),
        "{t}"
    );
}

#[test]
fn bad_requests_are_errors() {
    let d = scratch("bad");
    let missing = d.join("nothing").display().to_string();
    for (args, says) in [
        (
            vec!["prove", "mulcmp", "--verilog", missing.as_str()],
            "no mulcmp_a16_b16_s2.v there",
        ),
        (vec!["prove", "mulcmp", "-p", "dsp=ecp5"], "dsp=ecp5"),
        (
            vec!["prove", "mulcmp", "-p", "handshake=ready", "-p", "stages=0"],
            "prove the wrapper at stages >= 1",
        ),
        (
            vec!["prove", "mulcmp", "-p", "handshake=ready", "--solver", "sat"],
            "proved by k-induction with Boolector",
        ),
        (
            vec!["prove", "mulcmp", "--solver", "structural", "--property", "sound"],
            "--solver structural proves pipelines",
        ),
        (vec!["prove", "nosuchunit"], "nosuchunit"),
        (
            vec!["prove", "mulcmp", "--reference", "stages=4"],
            "deeper than",
        ),
        (
            vec!["prove", "cull", "--property", "sound", "--plant", "flip"],
            "no plant `flip` for cull: the plants are cull --plant lt-for-le",
        ),
        (
            vec!["prove", "slab", "--plant", "lt-for-le"],
            "no plant `lt-for-le` for slab",
        ),
        (
            vec![
                "prove",
                "slab",
                "-p",
                "rounding=conservative",
                "--property",
                "sound",
                "--split",
                "--solver",
                "boolector",
            ],
            "--split is built for slab -p rounding=conservative, silhouette (mode=ray, or mode=bundle",
        ),
        (
            vec![
                "prove",
                "slab",
                "-p",
                "rounding=conservative",
                "--property",
                "sound",
                "--split",
                "--lemma",
                "lemma_combine",
            ],
            "--lemma picks lemmas of node and silhouette mode=bundle --property sound --split",
        ),
        (
            vec![
                "prove",
                "node",
                "--property",
                "sound",
                "--split",
                "--lemma",
                "lemma_nothing",
            ],
            "--lemma lemma_nothing: no such lemma",
        ),
        (
            vec!["prove", "slab", "--split"],
            "--split splits --property sound",
        ),
    ] {
        let o = rtl_gen(&args);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {t}");
        assert!(t.contains(says), "{args:?}: {t}");
    }
}

/// `--property sound`: the conservative slab proved never to miss a ray that
/// meets the box at e2m2 (inv_d = RTZ(1/d) assumed), and the silhouette
/// tester with rounding=nearest (known to miss hits) caught: its
/// counterexample is a hit for the exact test and a miss for the unit's
/// golden model.
#[test]
fn soundness_is_proved_and_a_nearest_rounding_miss_is_found() {
    let w = scratch("sound");
    let slab = w.join("slab").display().to_string();
    assert_proved(&[
        "prove",
        "slab",
        "-p",
        "rounding=conservative",
        "-p",
        "exp_bits=2",
        "-p",
        "frac_bits=2",
        "--property",
        "sound",
        "--work",
        &slab,
    ]);
    let near = w.join("near").display().to_string();
    let params = [
        "-p",
        "mode=ray",
        "-p",
        "exp_bits=2",
        "-p",
        "frac_bits=2",
        "-p",
        "rounding=nearest",
    ];
    let mut args = vec!["prove", "silhouette"];
    args.extend(params);
    args.extend(["--property", "sound", "--work", &near]);
    let o = rtl_gen(&args);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("counterexample: ") && t.contains("refuted: "),
        "{t}"
    );
    let cex = w.join("near/counterexample.txt");
    let file = std::fs::read_to_string(&cex).unwrap();
    let values: Vec<u64> = file
        .lines()
        .nth(1)
        .unwrap()
        .split_whitespace()
        .map(|v| u64::from_str_radix(v.trim_start_matches("0x"), 16).unwrap())
        .collect();
    let fmt = golden_model::float::FloatFormat::new(2, 2).unwrap();
    let exact = golden_model::exact::ray_box::ray_hits_box(
        fmt,
        &golden_model::exact::ray_box::BoxIn {
            p_min: [values[0], values[1], values[2]],
            p_max: [values[3], values[4], values[5]],
        },
        &golden_model::exact::ray_box::RayIn {
            o: [values[6], values[7], values[8]],
            d: [values[9], values[10], values[11]],
            t_min: values[12],
            t_max: values[13],
        },
    );
    assert!(
        exact.hit,
        "the counterexample is a hit for the exact test: {file}"
    );
    // the unit's golden model misses it too (the RTL is bit-exact with it)
    let res = w.join("near/golden.txt").display().to_string();
    let cex_s = cex.display().to_string();
    let mut g = vec!["golden", "silhouette"];
    g.extend(params);
    g.extend(["--in", &cex_s, "--out", &res]);
    assert!(rtl_gen(&g).status.success());
    let out = std::fs::read_to_string(&res).unwrap();
    let header: Vec<&str> = out.lines().nth(1).unwrap().split_whitespace().collect();
    let row: Vec<&str> = out.lines().nth(2).unwrap().split_whitespace().collect();
    let hit = header.iter().position(|h| h.starts_with("hit:")).unwrap();
    assert_eq!(row[hit], "0x0", "{out}");
}

/// The values `name=0x..` of a counterexample line after `after`.
fn named_values(line: &str, after: &str) -> std::collections::BTreeMap<String, u64> {
    line.split(after)
        .nth(1)
        .unwrap_or_else(|| panic!("no `{after}` in {line}"))
        .split_whitespace()
        .map_while(|w| w.split_once("=0x"))
        .map(|(n, v)| (n.to_string(), u64::from_str_radix(v, 16).unwrap()))
        .collect()
}

/// Runs a proof that must be refuted (exit 1); its `counterexample:` line.
fn refuted(args: &[&str]) -> String {
    let o = rtl_gen(args);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {t}");
    t.lines()
        .find(|l| l.starts_with("counterexample: "))
        .unwrap_or_else(|| panic!("no counterexample:\n{t}"))
        .to_string()
}

/// Runs the replay a counterexample line prints, as printed (with the
/// planted Verilog); the report's row of the first output `differs` accepts
/// that differs.
fn replayed_mismatch(line: &str, differs: impl Fn(&str) -> bool) -> String {
    let replay = line
        .split("replay: rtl-gen ")
        .nth(1)
        .unwrap()
        .trim_end_matches(')');
    assert!(replay.contains("--verilog "), "{replay}");
    let args: Vec<&str> = replay.split_whitespace().collect();
    let t = text(&rtl_gen(&args));
    t.lines()
        .find(|l| l.contains("<- differs") && l.split_whitespace().next().is_some_and(&differs))
        .unwrap_or_else(|| panic!("the replay shows no such mismatch:\n{t}"))
        .to_string()
}

/// `--property sound` for the cull tester: the planted `<` for `<=`
/// (`--plant lt-for-le`) refuted at e2m2 (one e2m2 plane): the
/// counterexample's geometry meets the region for the exact Rust reference,
/// and its replay in Verilator (the planted Verilog) culls where the golden
/// model keeps. (The proofs themselves take 20 s at e2m1 and minutes at e2m2:
/// documented commands, docs/proofs.md.)
#[test]
fn a_planted_wrongful_cull_is_found_and_replays() {
    let w = scratch("cull-plant");
    let job = w.join("plant").display().to_string();
    let args = [
        "prove",
        "cull",
        "-p",
        "exp_bits=2",
        "-p",
        "frac_bits=2",
        "-p",
        "plane_exp_bits=2",
        "-p",
        "plane_frac_bits=2",
        "-p",
        "k=1",
        "--property",
        "sound",
        "--plant",
        "lt-for-le",
        "--work",
        &job,
    ];
    let line = refuted(&args);
    let g = named_values(&line, "with the geometry ");
    let v3 = |n: &str| ["x", "y", "z"].map(|a| g[&format!("{n}_{a}")]);
    let ray = golden_model::float::FloatFormat::new(2, 2).unwrap();
    let exact = golden_model::cull::exact::region_hit(
        ray,
        ray,
        &golden_model::cull::exact::RegionIn {
            p_min: v3("p_min"),
            p_max: v3("p_max"),
            o: v3("o"),
            d: v3("d"),
            t_min: g["t_min"],
            t_max: g["t_max"],
            r: v3("r"),
            normals: vec![v3("n0")],
            w: vec![g["w0"]],
        },
    );
    assert!(
        exact.region_hit,
        "the counterexample's segment meets the region exactly: {line}"
    );
    // the planted RTL culls, the golden model keeps
    let row = replayed_mismatch(&line, |port| port == "keep");
    assert!(
        row.contains("golden 0x1") && row.contains("rtl 0x0"),
        "{row}"
    );
}

/// `--property sound` for the node tester: the planted `<` for `<=`
/// (`--plant lt-for-le`, slot 0's entry against the window end) refuted at e3m2
/// (N = 2, q = 4): the counterexample's ray meets slot 0's decoded box from
/// `max(t_min, t_start)` for the exact Rust test (binary64, exact at these
/// sizes), and its replay in Verilator (the planted Verilog) misses where
/// the golden model hits. (The proof of the unplanted unit did not finish
/// in 25 minutes: docs/proofs.md.)
#[test]
fn a_planted_node_miss_is_found_and_replays() {
    use golden_model::exact::ray_box::{decode, ray_hits_box, BoxIn, Exact, RayIn};
    let w = scratch("node-plant");
    let job = w.join("plant").display().to_string();
    let mut args = vec!["prove", "node"];
    args.extend(NODE_SMALL);
    args.extend([
        "--property",
        "sound",
        "--plant",
        "lt-for-le",
        "--work",
        &job,
    ]);
    let line = refuted(&args);
    let g = named_values(&line, "refuted: ");
    let fmt = golden_model::float::FloatFormat::new(3, 2).unwrap();
    let value = |bits: u64| match decode(fmt, bits) {
        Exact::Fin { m, e } => m as f64 * 2f64.powi(e),
        Exact::PosInf => f64::INFINITY,
        Exact::NegInf => f64::NEG_INFINITY,
        Exact::NaN => panic!("NaN in the counterexample: {line}"),
    };
    let axes = ["x", "y", "z"];
    let corner = |end: &str| {
        axes.map(|a| {
            let e = g[&format!("frame_exp_{a}")];
            let e = ((e ^ 4) as i64 - 4) as i32; // 3-bit signed
            let int = g[&format!("slot0_{end}_{a}")] as f64;
            (value(g[&format!("frame_origin_{a}")]) + int * 2f64.powi(e)).to_bits()
        })
    };
    let ray3 = |n: &str| axes.map(|a| value(g[&format!("{n}_{a}")]).to_bits());
    assert_eq!(g["valid"] & 1, 1, "{line}");
    let exact = ray_hits_box(
        golden_model::float::FloatFormat::new(11, 52).unwrap(),
        &BoxIn {
            p_min: corner("lo"),
            p_max: corner("hi"),
        },
        &RayIn {
            o: ray3("o"),
            d: ray3("d"),
            t_min: value(g["t_min"]).max(value(g["t_start"])).to_bits(),
            t_max: value(g["t_max"]).to_bits(),
        },
    );
    assert!(
        exact.hit,
        "the counterexample's ray meets slot 0's box exactly: {line}"
    );
    // the planted RTL misses, the golden model hits
    let row = replayed_mismatch(&line, |port| {
        port.starts_with("out") && port.ends_with("_hit")
    });
    assert!(
        row.contains("golden 0x1") && row.contains("rtl 0x0"),
        "{row}"
    );
}

/// `lemma_test_<prefix><t> proved` for the silhouette's twelve tests `t`, in
/// the order a split proof lists them.
fn test_lemmas(prefix: &str) -> String {
    let edges = ["xy", "xz", "yx", "yz", "zx", "zy"].map(|e| format!("edge_{e}"));
    let axes = |kind: &str| ["x", "y", "z"].map(|a| format!("{kind}_{a}"));
    edges
        .into_iter()
        .chain(axes("dist"))
        .chain(axes("dir"))
        .map(|t| format!("lemma_test_{prefix}{t} proved"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `--split`: the conservative slab's, the cull tester's and the silhouette
/// ray and bundle testers' soundness as lemmas (bounds on the unit's own
/// per-axis or per-plane results, then their combination over free results)
/// proved (e2m2; the silhouette e2m1), and each kind of lemma refuted when the
/// unit breaks what it states (at e2m1, quicker): the slab's and the
/// silhouettes' y instance fed the x origin and plane 0's `rcp_hi` fed
/// `rcp_lo` (a bound), the slab's final comparison without its `=` case and the cull
/// plant `lt-for-le` (the combination), and the bundle's tests and AllHit
/// broken one at a time (its test and combination lemmas). So the lemmas
/// read the unit's real wires and are not vacuous.
#[test]
fn the_split_soundness_proofs_prove_and_their_lemmas_bite() {
    let w = scratch("split");
    let slab = |e: &'static str| ["-p", "rounding=conservative", "-p", "exp_bits=2", "-p", e];
    let silhouette = |e: &'static str| ["-p", "mode=ray", "-p", "exp_bits=2", "-p", e];
    let bundle = |e: &'static str| ["-p", "mode=bundle", "-p", "exp_bits=2", "-p", e];
    let cull = |e: &'static str| {
        [
            "-p",
            "exp_bits=2",
            "-p",
            e,
            "-p",
            "plane_exp_bits=2",
            "-p",
            "plane_frac_bits=1",
            "-p",
            "k=1",
        ]
    };
    let run = |unit: &str, params: &[&str], extra: &[&str], job: &str| {
        let job = w.join(job).display().to_string();
        let mut args = vec!["prove", unit];
        args.extend(params);
        args.extend(["--property", "sound", "--split", "--work", &job]);
        args.extend(extra);
        let o = rtl_gen(&args);
        (o.status.code(), text(&o))
    };
    for (unit, params, lemmas) in [
        (
            "slab",
            slab("frac_bits=2").to_vec(),
            "lemma_bounded_x proved, lemma_bounded_y proved, lemma_bounded_z proved, lemma_combine proved"
                .to_string(),
        ),
        (
            "cull",
            cull("frac_bits=2").to_vec(),
            "lemma_plane0 proved, lemma_combine proved".to_string(),
        ),
        (
            "silhouette",
            silhouette("frac_bits=1").to_vec(),
            format!(
                "lemma_bounded_z proved, {}, lemma_combine proved",
                test_lemmas("")
            ),
        ),
        (
            "silhouette",
            bundle("frac_bits=1").to_vec(),
            format!(
                "lemma_bounded_z proved, {}, {}, lemma_box_order proved, lemma_combine_any proved, \
                 lemma_all_basic proved, lemma_combine_all proved",
                test_lemmas("any_"),
                test_lemmas("all_")
            ),
        ),
    ] {
        let job = format!("{unit}{}", if params.contains(&"mode=bundle") { "-bundle" } else { "" });
        let (code, t) = run(unit, &params, &[], &job);
        assert!(
            code == Some(0) && t.contains("proved: ") && t.contains(&lemmas),
            "{unit}: {t}"
        );
    }
    // the lemmas bite: a hand-edited top (--verilog) or a plant
    let edits = [
        (
            "slab",
            "slab_e2m1_cons_s0.v",
            ".o(o_y)",
            ".o(o_x)",
            "lemma_bounded_y refuted",
        ),
        (
            "slab",
            "slab_e2m1_cons_s0.v",
            "assign hit = order_lt | order_eq;",
            "assign hit = order_lt;",
            "lemma_combine refuted",
        ),
        (
            "silhouette",
            "silhouette_e2m1_ray_cons_s0.v",
            ".o(o_y)",
            ".o(o_x)",
            "lemma_bounded_y refuted",
        ),
        (
            "cull",
            "cull_e2m1_pe2m1_k1_s0.v",
            ".rcp_hi(rcp_hi0)",
            ".rcp_hi(rcp_lo0)",
            "lemma_plane0 refuted",
        ),
        // the bundle tester: an axis fed another's origin (a bound), one AnyHit test that
        // never passes and one AllHit test that always does (a test lemma each), AllHit
        // from the AnyHit tests (the combination)
        (
            "bundle",
            "silhouette_e2m1_shared_cons_s0.v",
            ".o_lo(o_lo_y)",
            ".o_lo(o_lo_x)",
            "lemma_bounded_y refuted",
        ),
        (
            "bundle",
            "silhouette_tests_bundle_e2m1_n0_p0_c0.v",
            "assign dist_any_y_ok = ",
            "assign dist_any_y_ok = 1'b0 & ",
            "lemma_test_any_dist_y refuted",
        ),
        (
            "bundle",
            "silhouette_tests_bundle_e2m1_n0_p0_c0.v",
            "assign edge_all_xy_ok = ",
            "assign edge_all_xy_ok = 1'b1 | ",
            "lemma_test_all_edge_xy refuted",
        ),
        (
            "bundle",
            "silhouette_e2m1_shared_cons_s0.v",
            "& u_tests_pass_all;",
            "& u_tests_pass_any;",
            "lemma_all_basic refuted",
        ),
    ];
    for (i, (unit, top, from, to, refuted)) in edits.into_iter().enumerate() {
        let params = match unit {
            "slab" => slab("frac_bits=1").to_vec(),
            "silhouette" => silhouette("frac_bits=1").to_vec(),
            "bundle" => bundle("frac_bits=1").to_vec(),
            _ => cull("frac_bits=1").to_vec(),
        };
        let unit = if unit == "bundle" { "silhouette" } else { unit };
        let src = w.join(format!("edit{i}"));
        let src_s = src.display().to_string();
        let mut e = vec!["emit", unit];
        e.extend(&params);
        e.extend(["-p", "stages=0", "--out", &src_s]);
        assert!(rtl_gen(&e).status.success());
        let file = src.join(top);
        let v = std::fs::read_to_string(&file).unwrap();
        assert!(v.contains(from), "{from} not in {top}");
        std::fs::write(&file, v.replacen(from, to, 1)).unwrap();
        let (code, t) = run(
            unit,
            &params,
            &["--verilog", &src_s],
            &format!("edit{i}-proof"),
        );
        assert!(
            code == Some(1) && t.contains("not proved: ") && t.contains(refuted),
            "{from} -> {to}: {t}"
        );
    }
    let (code, t) = run(
        "cull",
        &cull("frac_bits=1"),
        &["--plant", "lt-for-le"],
        "plant",
    );
    assert!(
        code == Some(1) && t.contains("lemma_combine refuted"),
        "cull --plant lt-for-le: {t}"
    );
}

/// `--split` for the node tester at its smallest format (e3m2, N = 2, q = 4,
/// m = 4), some lemmas a run (`--lemma`; the whole split proof, every lemma,
/// takes minutes and is a documented command, docs/proofs.md): the
/// combination over the cut per-node terms (`lemma_child0`) and two per-node
/// lemmas proved on the unit, then each refuted on one hand-edited copy
/// that breaks what it states: the planted `<` for `<=` (`--plant
/// lt-for-le`, the combination), the x slope rounded up fed the rounded-down
/// significand (`lemma_slope_x`), the window sum's term 0 on x aligned by
/// term 1's gap (`lemma_term0_x`). So the lemmas read the unit's real wires,
/// and a run of some lemmas never claims the property.
#[test]
fn the_node_split_lemmas_prove_and_bite() {
    let w = scratch("node-split");
    let lemmas = ["lemma_child0", "lemma_slope_x", "lemma_term0_x"];
    let run = |extra: &[&str], job: &str| {
        let job = w.join(job).display().to_string();
        let mut args = vec!["prove", "node"];
        args.extend(NODE_SMALL);
        args.extend(["--property", "sound", "--split", "--work", &job]);
        for l in lemmas {
            args.extend(["--lemma", l]);
        }
        args.extend(extra);
        let o = rtl_gen(&args);
        (o.status.code(), text(&o))
    };
    let (code, t) = run(&[], "unit");
    assert!(
        code == Some(1)
            && t.contains(
                "split: lemma_term0_x proved, lemma_slope_x proved, lemma_child0 proved)"
            )
            && t.contains("only some of the split's lemmas were run"),
        "{t}"
    );
    let top = "node_n2_q4_m4_e3m2_s0.v";
    let src = w.join("edited");
    let src_s = src.display().to_string();
    emit_stage0("node", &NODE_SMALL, &src);
    let file = src.join(top);
    let mut v = std::fs::read_to_string(&file).unwrap();
    for (from, to) in [
        (
            "assign slope_x_sig_up_used = slope_x_inv_d_at_max ? 5'd8 : axis_x_slope_sig_up;",
            "assign slope_x_sig_up_used = slope_x_inv_d_at_max ? 5'd8 : {1'b0, axis_x_slope_sig_down};",
        ),
        (
            "assign axis_x_term0_kept = axis_x_term0_aligned_to_top >> axis_x_term0_gap;",
            "assign axis_x_term0_kept = axis_x_term0_aligned_to_top >> axis_x_term1_gap;",
        ),
    ] {
        assert!(v.contains(from), "{from} not in {top}");
        v = v.replacen(from, to, 1);
    }
    std::fs::write(&file, v).unwrap();
    let (code, t) = run(&["--verilog", &src_s, "--plant", "lt-for-le"], "edited");
    assert!(
        code == Some(1)
            && ["lemma_term0_x", "lemma_slope_x", "lemma_child0"]
                .iter()
                .all(|l| t.contains(&format!("{l} refuted"))),
        "{t}"
    );
}

/// `--property sound` for the triangle unit (docs/proofs.md): on rays from
/// the origin along an axis (ray space exact) the unit never misses a
/// triangle the line crosses without flagging it, proved at e2m1 for every
/// vertex, axis and `s_z`, whole and `--split`; with the flag for three zero
/// edge functions cut (a hand edit of the generated Verilog, the unit before
/// 2026-12-07) the proof is refuted, the counterexample's line crosses the
/// triangle for the exact Rust test, and its replay in Verilator reports
/// neither hit nor `invalid` where the golden model flags it; split, the cut
/// flag breaks `lemma_combine` and an edge function with its products
/// swapped (the wrong sign) `lemma_edge_u`, each alone.
#[test]
fn the_triangle_is_proved_silent_on_no_crossed_triangle_and_a_cut_flag_is_found() {
    let w = scratch("triangle-sound");
    let params = ["-p", "exp_bits=2", "-p", "frac_bits=1", "-p", "outputs=hit"];
    let job = w.join("proof").display().to_string();
    let mut args = vec!["prove", "triangle"];
    args.extend(params);
    args.extend(["--property", "sound", "--work", &job]);
    let proved = assert_proved(&args);
    assert!(
        proved.contains("a crossed triangle flagged") && proved.contains("are reachable"),
        "{proved}"
    );
    let job = w.join("split").display().to_string();
    let mut args = vec!["prove", "triangle"];
    args.extend(params);
    args.extend(["--property", "sound", "--split", "--work", &job]);
    let proved = assert_proved(&args);
    for lemma in triangle_lemmas(None) {
        assert!(proved.contains(&lemma), "{lemma}: {proved}");
    }
    // the flag cut
    let rtl = w.join("rtl");
    let rtl_s = rtl.display().to_string();
    emit_stage0("triangle", &params, &rtl);
    let top = rtl.join("triangle_e2m1_hit_s0.v");
    let v = std::fs::read_to_string(&top).unwrap();
    let flag = "assign edges_all_zero = and_not_invalid_input_inside_edges & det_is_zero;";
    assert!(v.contains(flag), "no `{flag}` in {}", top.display());
    std::fs::write(&top, v.replace(flag, "assign edges_all_zero = 1'b0;")).unwrap();
    let job = w.join("cut").display().to_string();
    let mut args = vec!["prove", "triangle"];
    args.extend(params);
    args.extend(["--property", "sound", "--verilog", &rtl_s, "--work", &job]);
    let line = refuted(&args);
    let g = named_values(&line, "refuted: ");
    let fmt = golden_model::float::FloatFormat::new(2, 1).unwrap();
    let kz = g["kz"] as usize;
    let mut d = [0u64; 3];
    d[kz] = fmt.one(false);
    let vertex = |p: &str| ["x", "y", "z"].map(|a| g[&format!("{p}_{a}")]);
    let crossed = golden_model::triangle::exact::intersect(
        fmt,
        [0; 3],
        d,
        [vertex("a"), vertex("b"), vertex("c")],
        fmt.inf(true),
        fmt.inf(false),
    );
    assert!(
        crossed.is_some(),
        "the counterexample's line crosses the triangle exactly: {line}"
    );
    let row = replayed_mismatch(&line, |port| port == "invalid");
    assert!(
        row.contains("golden 0x1") && row.contains("rtl 0x0"),
        "{row}"
    );
    // split: each edit breaks its own lemma
    let swapped = (
        ".a(u_edge_bc_qx_py_z),\n        .b(u_edge_bc_qy_px_z),",
        ".a(u_edge_bc_qy_px_z),\n        .b(u_edge_bc_qx_py_z),",
    );
    for (edit, broken) in [(None, "lemma_combine"), (Some(swapped), "lemma_edge_u")] {
        if let Some((from, to)) = edit {
            std::fs::write(&top, v.replace(from, to)).unwrap();
            assert_ne!(
                std::fs::read_to_string(&top).unwrap(),
                v,
                "no `{from}` in the unit"
            );
        }
        let job = w.join(format!("split-{broken}")).display().to_string();
        let mut args = vec!["prove", "triangle"];
        args.extend(params);
        args.extend([
            "--property",
            "sound",
            "--split",
            "--verilog",
            &rtl_s,
            "--work",
            &job,
        ]);
        let o = rtl_gen(&args);
        let t = text(&o);
        assert!(!o.status.success(), "{t}");
        for lemma in triangle_lemmas(Some(broken)) {
            assert!(t.contains(&lemma), "{lemma}: {t}");
        }
    }
}

/// Emits `unit` with `params` at stages=0 into `out` (a copy to edit by hand).
fn emit_stage0(unit: &str, params: &[&str], out: &Path) {
    let out_s = out.display().to_string();
    let mut args = vec!["emit", unit];
    args.extend(params);
    args.extend(["-p", "stages=0", "--out", &out_s]);
    let o = rtl_gen(&args);
    assert!(o.status.success(), "rtl-gen {args:?}: {}", text(&o));
}

/// The triangle split's four lemmas' results as its summary gives them: each
/// proved, or `broken` refuted.
fn triangle_lemmas(broken: Option<&str>) -> [String; 4] {
    [
        "lemma_edge_u",
        "lemma_edge_v",
        "lemma_edge_w",
        "lemma_combine",
    ]
    .map(|l| {
        if Some(l) == broken {
            format!("{l} refuted")
        } else {
            format!("{l} proved")
        }
    })
}

/// A `handshake=ready` unit (issue 39's wrapper property): mulcmp's valid/ready
/// wrapper at 1 and 2 stages proved (no transaction lost, duplicated or
/// reordered, results the reference's, credits and latency as documented,
/// k-induction), and three planted wrapper bugs found: the FIFO's
/// read pointer wrapping one slot early, no credit limit, and a result both
/// delivered and pushed into the FIFO.
/// `rtl-gen prove` of a valid/ready unit (`unit`: its name and parameters)
/// whose wrapper file `wrapper` was emitted into `dir/rtl` and edited
/// (`edit`: the text and its replacement), with `extra` arguments: the exit
/// code and the output.
fn prove_edited_wrapper(
    dir: &Path,
    unit: &[&str],
    wrapper: &str,
    edit: (&str, &str),
    extra: &[&str],
) -> (Option<i32>, String) {
    let rtl = dir.join("rtl");
    let rtl_s = rtl.display().to_string();
    let mut emit = vec!["emit"];
    emit.extend(unit);
    emit.extend(["--out", &rtl_s]);
    assert!(rtl_gen(&emit).status.success());
    let top = rtl.join(wrapper);
    let v = std::fs::read_to_string(&top).unwrap();
    assert!(
        v.contains(edit.0),
        "`{}` is not in {}",
        edit.0,
        top.display()
    );
    std::fs::write(&top, v.replacen(edit.0, edit.1, 1)).unwrap();
    let work = dir.join("job").display().to_string();
    let mut prove = vec!["prove"];
    prove.extend(unit);
    prove.extend(["--verilog", &rtl_s, "--work", &work]);
    prove.extend(extra);
    let o = rtl_gen(&prove);
    (o.status.code(), text(&o))
}

/// The wrapper around a stand-in core (`--solver structural`, docs/proofs.md):
/// planted wrapper bugs are still found, a wrapper that reads a data input
/// outside its core is not proved this way, and a unit with too few input
/// bits for a stand-in is refused (exit 2).
#[test]
fn the_wrapper_around_a_stand_in_core_finds_planted_bugs() {
    let w = scratch("stand-in");
    let params = [
        "-p",
        "mode=ray",
        "-p",
        "exp_bits=2",
        "-p",
        "frac_bits=1",
        "-p",
        "stages=2",
        "-p",
        "handshake=ready",
    ];
    let plants = [
        (
            "push",
            "assign push = u_core_out_valid & (~(fifo_empty & out_ready));",
            "assign push = u_core_out_valid;",
            "counterexample: ",
        ),
        (
            "data-read",
            "assign has_credit = ~(occupancy == 2'd3);",
            "assign has_credit = ~(occupancy == 2'd3) & ~o_x[0];",
            "not proved: ",
        ),
    ];
    for (name, from, to, verdict) in plants {
        let mut unit = vec!["silhouette"];
        unit.extend(params);
        let (code, t) = prove_edited_wrapper(
            &w.join(name),
            &unit,
            "silhouette_e2m1_ray_cons_s2_rdy.v",
            (from, to),
            &["--solver", "structural"],
        );
        assert_eq!(code, Some(1), "{name}: {t}");
        let last = t.lines().last().unwrap_or("");
        assert!(last.starts_with(verdict), "{name}: {t}");
        if name == "data-read" {
            assert!(
                last.contains("reads a data input outside its core") && last.contains("o_x"),
                "{t}"
            );
        } else {
            assert!(
                last.contains("stand-in core") && last.contains(" fails at cycle "),
                "{t}"
            );
        }
    }
    let o = rtl_gen(&[
        "prove",
        "mulcmp",
        "-p",
        "handshake=ready",
        "--solver",
        "structural",
        "--work",
        &w.join("mulcmp").display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("twice as many input bits"),
        "{}",
        text(&o)
    );
}

#[test]
fn the_valid_ready_wrapper_is_checked_and_planted_wrapper_bugs_are_found() {
    let w = scratch("handshake");
    let params = [
        "-p",
        "a_width=4",
        "-p",
        "b_width=4",
        "-p",
        "handshake=ready",
    ];
    for stages in ["stages=1", "stages=2"] {
        let work = w.join(stages).display().to_string();
        let mut args = vec!["prove", "mulcmp", "-p", stages];
        args.extend(params);
        args.extend(["--work", &work]);
        let line = assert_proved(&args);
        assert!(
            line.contains("no transaction lost, duplicated or reordered")
                && line.contains("k-induction"),
            "{line}"
        );
    }
    let plants = [
        (
            "read_at",
            "assign read_at_at_end = read_at == 2'd2;",
            "assign read_at_at_end = read_at == 2'd1;",
        ),
        (
            "credit",
            "assign has_credit = ~(occupancy == 2'd3);",
            "assign has_credit = 1'b1;",
        ),
        (
            "push",
            "assign push = u_core_out_valid & (~(fifo_empty & out_ready));",
            "assign push = u_core_out_valid;",
        ),
    ];
    for (name, from, to) in plants {
        let mut unit = vec!["mulcmp", "-p", "stages=2"];
        unit.extend(params);
        let (code, t) = prove_edited_wrapper(
            &w.join(name),
            &unit,
            "mulcmp_a4_b4_s2_rdy.v",
            (from, to),
            &[],
        );
        assert_eq!(code, Some(1), "{name}: {t}");
        let last = t.lines().last().unwrap_or("");
        assert!(
            last.starts_with("counterexample: ") && last.contains(" fails at cycle "),
            "{name}: {t}"
        );
        let trace = w.join(name).join("job/sby/engine_0/trace.vcd");
        assert!(trace.is_file(), "{name}: no trace {}", trace.display());
    }
}
