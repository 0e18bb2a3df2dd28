//! The FPGA bring-up wrapper in Verilator: vectors of the unit's own stimulus
//! go in as UART frames on `rx` (bringup_tb.cpp drives the line and decodes
//! `tx`), and every answer is checked against the unit's golden model.

use cost::bringup::{pack, record_bytes, unpack, Bringup};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Builds the wrapper of `unit` with the stand-alone UART test bench;
/// returns the executable.
fn build(b: &Bringup, dir: &Path) -> PathBuf {
    let tb = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bringup_tb.cpp");
    b.build_testbench(dir, &tb)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Sends `vectors` vectors of seed `seed` through the wrapper of `unit` at
/// `cycles_per_bit` and compares every answer with the golden model.
fn check(unit: &str, params: &[&str], cycles_per_bit: u32, vectors: u64, seed: u64) {
    let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    let g = rtl_flow::generate(unit, &params).unwrap();
    let b = Bringup::new(&g, cycles_per_bit);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(&b.module.name);
    let exe = build(&b, &dir);

    let tb = g.testbench();
    let (n_in, n_out) = (b.in_widths.len(), b.out_widths.len());
    let (in_bytes, out_bytes) = (
        record_bytes(b.in_widths.iter().copied()),
        record_bytes(b.out_widths.iter().copied()),
    );
    let mut inputs = vec![0u64; n_in];
    let mut stream = Vec::new();
    let mut records = Vec::new();
    for i in 0..vectors {
        tb.vector(seed, i, &mut inputs);
        pack(&inputs, &b.in_widths, &mut stream);
        records.push(inputs.clone());
    }
    let (in_file, out_file) = (dir.join("in.bin"), dir.join("out.bin"));
    std::fs::write(&in_file, &stream).unwrap();
    let run = Command::new(&exe)
        .arg(&in_file)
        .arg(&out_file)
        .args([in_bytes, out_bytes, cycles_per_bit as usize].map(|n| n.to_string()))
        .output()
        .unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(run.status.success(), "{}: {log}", b.module.name);
    let got = std::fs::read(&out_file).unwrap();
    assert_eq!(
        got.len(),
        vectors as usize * out_bytes,
        "{}: answers received",
        b.module.name
    );

    let hex = |v: &[u64]| {
        v.iter()
            .map(|x| format!("{x:#x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut expected = vec![0u64; n_out];
    let mut mismatches = 0;
    for (i, (inp, answer)) in records.iter().zip(got.chunks_exact(out_bytes)).enumerate() {
        tb.eval(inp, &mut expected);
        let rtl = unpack(answer, &b.out_widths);
        if rtl != expected {
            if mismatches == 0 {
                eprintln!(
                    "{}: vector {i}: inputs {} golden {} over UART {}",
                    b.module.name,
                    hex(inp),
                    hex(&expected),
                    hex(&rtl)
                );
            }
            mismatches += 1;
        }
    }
    assert_eq!(mismatches, 0, "{} of {vectors} vectors differ", mismatches);
    println!(
        "{}: {vectors} vectors over UART, all match; {log}",
        b.module.name
    );
}

#[test]
fn mulcmp_8x8_over_uart() {
    check("mulcmp", &["a_width=8", "b_width=8", "stages=2"], 8, 500, 1);
}

#[test]
fn mulcmp_8x8_with_the_ready_handshake_over_uart() {
    check(
        "mulcmp",
        &["a_width=8", "b_width=8", "stages=2", "handshake=ready"],
        8,
        200,
        3,
    );
}

#[test]
fn mulcmp_odd_widths_combinational_odd_bit_time() {
    // 11-bit a/c (two bytes, upper bits padded), 3-bit b/d, latency 0, 5 cycles a bit
    check(
        "mulcmp",
        &["a_width=11", "b_width=3", "stages=0"],
        5,
        300,
        2,
    );
}

#[test]
fn slab_e5m7_over_uart() {
    check(
        "slab",
        &["exp_bits=5", "frac_bits=7", "stages=2"],
        4,
        300,
        3,
    );
}
