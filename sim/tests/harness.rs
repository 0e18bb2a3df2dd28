//! End-to-end tests of the harness build cache, the C++ harness and the
//! cross-check, on the hand-written fixtures in `tests/fixtures`. They need
//! `verilator` on PATH and fail (not skip) without it.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{mpsc, OnceLock};
use std::time::Duration;

use sim::harness::RunOptions;
use sim::{
    cross_check, default_cache_root, lint, replay, BinReader, BinWriter, CheckOptions, Harness,
    PortList, RandomStimulus, SimError, Stimulus,
};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn port_list(top: &str) -> PortList {
    PortList::load(fixtures().join(format!("{top}.ports.json"))).unwrap()
}

/// A fresh directory under the target dir, unique to this test run.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "sim-{name}-{}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos()
    ));
    fs::create_dir_all(&d).unwrap();
    d
}

fn build(ports: &PortList) -> Harness {
    Harness::build(ports, &fixtures(), &default_cache_root())
        .unwrap_or_else(|e| panic!("building {}: {e}", ports.top))
}

/// Shared across tests so the fixture is built once per test binary.
fn addpipe() -> &'static Harness {
    static H: OnceLock<Harness> = OnceLock::new();
    H.get_or_init(|| build(&port_list("addpipe")))
}

/// The behaviour `addpipe.v` implements.
fn addpipe_golden(i: &[u64], o: &mut [u64]) {
    o[0] = i[0] + i[1];
    o[1] = (i[0] == i[1]) as u64;
}

#[test]
fn second_build_is_a_cache_hit_and_the_key_tracks_the_verilog() {
    let cache = scratch("cache");
    let ports = port_list("addpipe");
    let first = Harness::build(&ports, &fixtures(), &cache).unwrap();
    assert!(!first.was_cached(), "fresh cache root must build");
    assert!(first.binary().starts_with(&cache));
    let mtime = fs::metadata(first.binary()).unwrap().modified().unwrap();

    let second = Harness::build(&ports, &fixtures(), &cache).unwrap();
    assert!(second.was_cached());
    assert_eq!(second.binary(), first.binary());
    assert_eq!(
        fs::metadata(second.binary()).unwrap().modified().unwrap(),
        mtime
    );
    assert!(
        second.build_time().as_secs_f64() < 1.0,
        "cache hit took {:?}",
        second.build_time()
    );
    // Only the finished entry is left: no temporary build directories.
    let entries: Vec<String> = fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(entries, vec![first.key().to_owned()]);

    // A comment-only change to the Verilog, or a different latency, is a
    // different key.
    let dir = scratch("edited");
    let mut text = fs::read_to_string(fixtures().join("addpipe.v")).unwrap();
    text.push_str("// edited\n");
    fs::write(dir.join("addpipe.v"), text).unwrap();
    let key = Harness::cache_key(&ports, &dir).unwrap();
    assert_ne!(key, first.key());
    let mut other = ports.clone();
    other.latency = 3;
    assert_ne!(
        Harness::cache_key(&other, &fixtures()).unwrap(),
        first.key()
    );
    assert_eq!(
        Harness::cache_key(&ports, &fixtures()).unwrap(),
        first.key()
    );
    fs::remove_dir_all(&cache).unwrap();
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_million_vectors_match_the_golden_model() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    let opts = CheckOptions {
        vectors: 1_000_000,
        seed: 0x5eed,
        ..CheckOptions::default()
    };
    let r = cross_check(h, &addpipe_golden, &stim, &opts).unwrap();
    println!("{r}");
    assert!(r.passed(), "{r}");
    assert_eq!(r.vectors, 1_000_000);
    assert_eq!(r.mismatches, 0);
    assert!(r.first_mismatch.is_none());
    // 4 reset cycles, one cycle per vector, latency + 4 drain cycles.
    assert_eq!(r.cycles, 4 + 1_000_000 + 2 + 4);
    assert_eq!(r.bubbles, 0);
}

#[test]
fn a_flipped_output_bit_is_reported_with_a_working_replay() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    // Wrong in bit 4 of `sum` whenever a's low nibble is 0xf.
    let wrong = |i: &[u64], o: &mut [u64]| {
        addpipe_golden(i, o);
        if i[0] & 0xf == 0xf {
            o[0] ^= 1 << 4;
        }
    };
    let dir = scratch("mismatch");
    let opts = CheckOptions {
        vectors: 20_000,
        seed: 42,
        replay_hint: Some("rtl-gen replay addpipe --seed {seed} --index {index}".into()),
        mismatch_dir: Some(dir.clone()),
        ..CheckOptions::default()
    };
    let r = cross_check(h, &wrong, &stim, &opts).unwrap();
    println!("{r}");

    let mut v = [0u64; 2];
    let failing: Vec<u64> = (0..opts.vectors)
        .filter(|&i| {
            stim.vector(42, i, &mut v);
            v[0] & 0xf == 0xf
        })
        .collect();
    assert!(!failing.is_empty());
    assert!(!r.passed());
    assert_eq!(r.mismatches, failing.len() as u64);
    let m = r.first_mismatch.as_ref().unwrap();
    assert_eq!(m.index, failing[0]);
    assert_eq!(r.more_mismatches.len(), 9);
    assert_eq!(r.more_mismatches[8].index, failing[9]);
    assert_eq!(m.expected[0].1 ^ m.got[0].1, 1 << 4);
    assert_eq!(m.expected[1], m.got[1]);
    assert_eq!(m.got[0].1, m.inputs[0].1 + m.inputs[1].1);

    let text = r.to_string();
    assert!(text.starts_with("FAIL: `addpipe`, 20000 vectors"), "{text}");
    assert!(text.contains("<- differs in bits 0x10"), "{text}");
    let hint = format!("rtl-gen replay addpipe --seed 42 --index {}", m.index);
    assert!(
        m.replay.lines().next() == Some(hint.as_str()),
        "{}",
        m.replay
    );
    let direct = m.replay.lines().nth(1).unwrap();
    assert!(
        direct.contains(" --vcd ") && direct.contains(" < "),
        "{direct}"
    );

    // The direct command really replays that vector, with a trace.
    let out = Command::new("sh").arg("-c").arg(direct).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut rd = BinReader::new(&out.stdout[..], "replay").unwrap();
    let mut got = [0u64; 2];
    assert!(rd.read_record(&mut got).unwrap());
    assert_eq!(got, [m.got[0].1, m.got[1].1]);
    let vcd = m.vector_file.as_ref().unwrap().with_extension("vcd");
    let trace = fs::read_to_string(&vcd).unwrap();
    assert!(trace.contains("$var") && trace.contains(" sum "), "{vcd:?}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn replay_returns_outputs_and_writes_a_trace() {
    let h = addpipe();
    let dir = scratch("replay");
    let vcd = dir.join("one.vcd");
    assert_eq!(
        replay(h, &[0xffff, 0xffff], Some(&vcd)).unwrap(),
        [0x1fffe, 1]
    );
    assert!(fs::read_to_string(&vcd).unwrap().contains("out_valid"));
    assert_eq!(replay(h, &[7, 9], None).unwrap(), [16, 0]);
    let e = replay(h, &[1], None).unwrap_err().to_string();
    assert!(e.contains("1 input values for 2 input ports"), "{e}");
    let e = replay(h, &[0x10000, 0], None).unwrap_err().to_string();
    assert!(e.contains("field `a`: value wider than port"), "{e}");
    // No vectors at all: reset and drain only.
    let stim = RandomStimulus::new(&h.ports().inputs);
    let opts = CheckOptions {
        vectors: 0,
        ..CheckOptions::default()
    };
    let r = cross_check(h, &addpipe_golden, &stim, &opts).unwrap();
    assert!(r.passed() && r.vectors == 0 && r.cycles == 4 + 2 + 4, "{r}");
    fs::remove_dir_all(&dir).unwrap();
}

fn latency_error(latency: u32) -> String {
    let mut ports = port_list("addpipe");
    ports.latency = latency;
    let h = build(&ports);
    let stim = RandomStimulus::new(&ports.inputs);
    let opts = CheckOptions {
        vectors: 1000,
        ..CheckOptions::default()
    };
    match cross_check(&h, &addpipe_golden, &stim, &opts) {
        Ok(r) => panic!("latency {latency} accepted: {r}"),
        Err(e @ SimError::Harness { .. }) => e.to_string(),
        Err(e) => panic!("wrong error kind: {e}"),
    }
}

#[test]
fn declaring_the_wrong_latency_is_an_error_naming_the_cycle() {
    // Reset occupies cycles 0-3, so transaction 0 is presented at cycle 4.
    let e = latency_error(1);
    assert!(
        e.contains("exited with code 3 (latency/handshake violation)"),
        "{e}"
    );
    assert!(
        e.contains(
            "cycle 5: out_valid=0 but transaction 0, presented at cycle 4, is due (declared latency 1)"
        ),
        "{e}"
    );
    let e = latency_error(3);
    assert!(
        e.contains(
            "cycle 6: out_valid=1 but no transaction was presented at cycle 3 (declared latency 3)"
        ),
        "{e}"
    );
}

fn random_input_file(ports: &PortList, path: &Path, n: u64, seed: u64) {
    let stim = RandomStimulus::new(&ports.inputs);
    let mut w = BinWriter::create(path, &ports.inputs).unwrap();
    let mut v = vec![0; ports.inputs.len()];
    for i in 0..n {
        stim.vector(seed, i, &mut v);
        w.write_record(&v).unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn bubbles_do_not_change_the_results() {
    let h = addpipe();
    let dir = scratch("bubbles");
    let input = dir.join("in.rtlvec");
    random_input_file(h.ports(), &input, 100_000, 9);
    let plain = h
        .run(&input, &dir.join("plain.rtlvec"), &RunOptions::default())
        .unwrap();
    let bubbly_opts = RunOptions {
        bubbles: Some(1234),
        ..RunOptions::default()
    };
    let bubbly = h
        .run(&input, &dir.join("bubbly.rtlvec"), &bubbly_opts)
        .unwrap();
    assert_eq!(plain.transactions, 100_000);
    assert_eq!(bubbly.transactions, 100_000);
    assert_eq!(plain.bubbles, 0);
    // 30% idle chance per slot: about 43k bubbles; far from 0 either way.
    assert!(bubbly.bubbles > 20_000, "{bubbly:?}");
    assert_eq!(bubbly.cycles, plain.cycles + bubbly.bubbles);
    let a = fs::read(dir.join("plain.rtlvec")).unwrap();
    let b = fs::read(dir.join("bubbly.rtlvec")).unwrap();
    assert_eq!(a.len(), "rtlvec 1 sum:17,eq:1\n".len() + 4 * 100_000);
    assert!(a == b, "outputs differ with bubbles");

    // And the cross-check passes with bubbles too.
    let stim = RandomStimulus::new(&h.ports().inputs);
    let opts = CheckOptions {
        vectors: 100_000,
        bubbles: Some(77),
        ..CheckOptions::default()
    };
    let r = cross_check(h, &addpipe_golden, &stim, &opts).unwrap();
    assert!(r.passed() && r.bubbles > 20_000, "{r}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn combinational_unit_with_every_port_width_class() {
    let ports = port_list("widecomb");
    assert_eq!(ports.latency, 0);
    let h = build(&ports);
    let golden = |i: &[u64], o: &mut [u64]| {
        let (x, y, z, w) = (i[0], i[1], i[2], i[3]);
        o[0] = x.wrapping_add(y);
        o[1] = ((z & 0xf) << 33) | y;
        o[2] = (w.count_ones() & 1) as u64;
        o[3] =
            (((w ^ (x >> 56)) & 0xff) << 4) | ((z >> 4) & 1) << 3 | ((y >> 32) & 1) << 2 | (z & 3);
    };
    let stim = RandomStimulus::new(&ports.inputs);
    let opts = CheckOptions {
        vectors: 300_000,
        seed: 3,
        ..CheckOptions::default()
    };
    let r = cross_check(&h, &golden, &stim, &opts).unwrap();
    assert!(r.passed(), "{r}");
    assert_eq!(r.cycles, 4 + 300_000 + 4);
    // Corner vector 1 drives every input to all ones.
    assert_eq!(
        replay(&h, &[u64::MAX, (1 << 33) - 1, 31, 255], None).unwrap(),
        [(1 << 33) - 2, (1 << 37) - 1, 0, 0xfff & !(0xff << 4)]
    );
}

/// Runs the built harness directly on `input`, returning (exit code, stderr).
fn run_raw(h: &Harness, input: &[u8]) -> (Option<i32>, String) {
    let mut child = h
        .command()
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    let _ = child.stdin.take().unwrap().write_all(input);
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn harness_rejects_bad_input_streams_with_exit_code_2() {
    let h = addpipe();
    let (code, err) = run_raw(h, b"rtlvec 1 a:16,c:16\n\x01\x00\x02\x00");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("expected: rtlvec 1 a:16,b:16")
            && err.contains("got:      rtlvec 1 a:16,c:16"),
        "{err}"
    );
    let (code, err) = run_raw(h, b"hello\n");
    assert_eq!(code, Some(2));
    assert!(err.contains("not an rtlvec stream"), "{err}");
    let (code, err) = run_raw(h, b"");
    assert_eq!(code, Some(2));
    assert!(err.contains("empty input"), "{err}");
    // Second record has 3 of 4 bytes.
    let (code, err) = run_raw(h, b"rtlvec 1 a:16,b:16\n\x01\x00\x02\x00\x01\x00\x02");
    assert_eq!(code, Some(2));
    assert!(
        err.contains("record 1 (byte offset 23) is truncated: 3 of 4 bytes"),
        "{err}"
    );
    // A well-formed record runs: 4 reset + 1 + latency 2 + 4 drain cycles.
    let (code, err) = run_raw(h, b"rtlvec 1 a:16,b:16\n\x01\x00\x02\x00");
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("cycles=11 transactions=1 bubbles=0"), "{err}");
    // 16-bit ports fill their bytes, so use the widecomb 5-bit port `z`.
    let wide = build(&port_list("widecomb"));
    let mut rec = b"rtlvec 1 x:64,y:33,z:5,w:8\n".to_vec();
    rec.extend_from_slice(&[0; 8 + 5]);
    rec.extend_from_slice(&[0x20, 0]);
    let (code, err) = run_raw(&wide, &rec);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("record 0 (byte offset 27), field z: value 0x20 wider than port (5 bits)"),
        "{err}"
    );
}

/// A stand-in harness: a shell script with the given body.
fn fake_harness(dir: &Path, body: &str) -> Harness {
    let path = dir.join("fake_harness.sh");
    fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    Harness::from_parts(port_list("addpipe"), path).unwrap()
}

#[test]
fn result_count_and_exit_status_are_checked() {
    let dir = scratch("fake");
    let stim = RandomStimulus::new(&port_list("addpipe").inputs);
    let opts = CheckOptions {
        vectors: 3,
        ..CheckOptions::default()
    };
    // Vector 0 is all zeros: sum 0, eq 1 -> bytes 00 00 00 01.
    let rec0 = r"\000\000\000\001";
    let check = |body: &str| {
        let h = fake_harness(&dir, body);
        cross_check(&h, &addpipe_golden, &stim, &opts)
            .map(|r| r.to_string())
            .unwrap_or_else(|e| e.to_string())
    };
    let e = check(&format!(
        "cat >/dev/null; printf 'rtlvec 1 sum:17,eq:1\\n{rec0}'; echo cycles=9 transactions=3 bubbles=0 >&2"
    ));
    assert!(e.contains("returned 1 results for 3 vectors"), "{e}");
    let e = check(&format!(
        "cat >/dev/null; printf 'rtlvec 1 sum:17,eq:1\\n{rec0}{rec0}{rec0}{rec0}'"
    ));
    assert!(e.contains("more results than the 3 vectors sent"), "{e}");
    let e = check("cat >/dev/null; echo 'harness: simulated failure' >&2; exit 3");
    assert!(e.contains("exited with code 3"), "{e}");
    assert!(
        e.contains("--- harness stderr ---\nharness: simulated failure"),
        "{e}"
    );
    let e = check("cat >/dev/null; printf 'rtlvec 1 sum:17,ok:1\\n'");
    assert!(e.contains("field `ok`: unknown port"), "{e}");
    // A harness that stops reading early must not hang the check.
    let e = check("exit 4");
    assert!(e.contains("exited with code 4 (I/O error)"), "{e}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stimulus_and_golden_values_wider_than_their_port_are_errors() {
    let h = addpipe();
    let bad_stim = |_seed: u64, index: u64, v: &mut [u64]| {
        v[0] = if index == 5 { 0x1_0000 } else { 1 };
        v[1] = 2;
    };
    let opts = CheckOptions {
        vectors: 100,
        ..CheckOptions::default()
    };
    let e = cross_check(h, &addpipe_golden, &bad_stim, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("vector 5, input `a`: value wider than port: 0x10000 does not fit 16 bits"),
        "{e}"
    );
    let stim = RandomStimulus::new(&h.ports().inputs);
    let bad_golden = |i: &[u64], o: &mut [u64]| {
        addpipe_golden(i, o);
        o[1] |= 2;
    };
    let e = cross_check(h, &bad_golden, &stim, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("golden model returned 0x3 for output `eq` (1 bits) at vector 0"),
        "{e}"
    );
}

#[test]
fn lint_passes_clean_fixtures_and_reports_warnings() {
    for top in ["addpipe", "mulcmp16", "widecomb"] {
        lint(&port_list(top), &fixtures()).unwrap_or_else(|e| panic!("{e}"));
    }
    let dir = scratch("lint");
    let mut ports = port_list("addpipe");
    let text = fs::read_to_string(fixtures().join("addpipe.v"))
        .unwrap()
        .replace("reg        e1;", "reg        e1;\n    wire [3:0] stray;");
    fs::write(dir.join("addpipe.v"), text).unwrap();
    let e = lint(&ports, &dir).unwrap_err();
    assert!(matches!(e, SimError::Lint { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("%Warning-UNUSED") && msg.contains("stray"),
        "{msg}"
    );
    ports.files = vec!["missing.v".into()];
    let e = lint(&ports, &dir).unwrap_err().to_string();
    assert!(
        e.contains("missing.v (files[0] of the port list of `addpipe`)"),
        "{e}"
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_failed_build_reports_verilators_output() {
    let dir = scratch("broken");
    let cache = scratch("broken-cache");
    let text = fs::read_to_string(fixtures().join("addpipe.v"))
        .unwrap()
        .replace("e1  <= a == b;", "e1  <= a === ;");
    fs::write(dir.join("addpipe.v"), text).unwrap();
    let e = Harness::build(&port_list("addpipe"), &dir, &cache).unwrap_err();
    let SimError::Build { output_tail, .. } = &e else {
        panic!("wrong error: {e}");
    };
    assert!(output_tail.contains("%Error: src/addpipe.v:"), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("building the Verilator harness for `addpipe` failed"),
        "{msg}"
    );
    assert!(msg.contains("build directory kept at"), "{msg}");
    // Nothing half-built is left where a cache hit would find it.
    let key = Harness::cache_key(&port_list("addpipe"), &dir).unwrap();
    assert!(!cache.join(&key).exists());
    assert!(cache
        .join(format!("{key}.failed"))
        .join("build.log")
        .is_file());
    fs::remove_dir_all(&dir).unwrap();
    fs::remove_dir_all(&cache).unwrap();
}

#[test]
fn a_panicking_golden_model_panics_instead_of_hanging() {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let h = addpipe();
        let stim = RandomStimulus::new(&h.ports().inputs);
        let golden = |_: &[u64], _: &mut [u64]| panic!("deliberate golden-model bug");
        // Far more vectors than the pipes hold, so a checker that stopped
        // reading without ending the harness would block the feeder.
        let opts = CheckOptions {
            vectors: 20_000_000,
            ..CheckOptions::default()
        };
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            cross_check(h, &golden, &stim, &opts)
        }));
        tx.send(r.is_err()).unwrap();
    });
    assert_eq!(rx.recv_timeout(Duration::from_secs(120)), Ok(true));
}

/// A valid/ready unit that ignores `out_ready` (tests/fixtures/noskid.v):
/// never stalled it passes, with the latency and full-rate checks; with the
/// harness's default stalls the lost result is a handshake violation.
#[test]
fn a_ready_unit_that_drops_a_stalled_result_is_a_handshake_violation() {
    let ports = port_list("noskid");
    assert!(ports
        .ports_inc()
        .contains("#define RTL_OUT_READY out_ready\n"));
    let h = build(&ports);
    let dir = scratch("noskid");
    let input = dir.join("in.rtlvec");
    random_input_file(&ports, &input, 1000, 3);
    let never = RunOptions {
        stall_percent: Some(0),
        ..RunOptions::default()
    };
    let s = h.run(&input, &dir.join("never.rtlvec"), &never).unwrap();
    assert_eq!(
        (s.transactions, s.stalls, s.cycles),
        (1000, 0, 1000 + 1 + 8)
    );
    let e = h
        .run(&input, &dir.join("stalled.rtlvec"), &RunOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("exited with code 3") && e.contains("waited for out_ready"),
        "{e}"
    );
}
