//! The valid/ready handshake (`handshake=ready`, docs/handshake.md) of
//! several units in Verilator: with random stalls on both sides every
//! transaction comes out once and in order, equal to the golden model's
//! result; never stalled, the unit keeps its latency and takes one
//! transaction per cycle. Icarus (4-state): X on the data inputs while
//! `in_valid` is low never reaches a valid output, and reset leaves no X on
//! `in_ready` and `out_valid`.

mod common;

use rtl_flow::Generated;
use std::path::Path;

/// Units of different latencies: a combinational core (latency 0, the FIFO
/// of one entry), a short and a long pipeline.
const UNITS: [(&str, &[&str]); 3] = [
    ("fadd", &["exp_bits=5", "frac_bits=10", "stages=0"]),
    ("mulcmp", &["a_width=8", "b_width=8"]),
    (
        "silhouette",
        &["exp_bits=5", "frac_bits=6", "mode=ray", "stages=6"],
    ),
];

/// Reset cycles and idle cycles after the last result the harness clocks
/// (verilator/harness.cpp `RESET_CYCLES`, `DRAIN_EXTRA`).
const HARNESS_OVERHEAD: u64 = 4 + 4;

fn ready<'a>(params: &[&'a str]) -> Vec<&'a str> {
    params.iter().copied().chain(["handshake=ready"]).collect()
}

/// The golden outputs of vectors `0..n` of `seed`, flat, and their inputs.
fn golden(g: &Generated, n: u64, seed: u64) -> (Vec<Vec<u64>>, Vec<u64>) {
    let tb = g.testbench();
    let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
    let mut out = vec![0u64; g.ports.outputs.len()];
    for i in 0..n {
        let mut v = vec![0u64; g.ports.inputs.len()];
        tb.vector(seed, i, &mut v);
        tb.eval(&v, &mut out);
        outputs.extend_from_slice(&out);
        inputs.push(v);
    }
    (inputs, outputs)
}

#[test]
fn random_stalls_lose_reorder_or_duplicate_nothing_and_no_stall_keeps_full_rate() {
    const N: u64 = 20_000;
    for (unit, params) in UNITS {
        let (g, dir) = common::generate("handshake", unit, &ready(params));
        assert!(g.ports.ready.is_some(), "{unit}: no ready ports");
        // the check flow: its harness stalls both sides by default
        let report = common::cross_checked(&g, &dir, N, 5);
        assert!(report.bubbles > N / 10, "{unit}: {report}");
        let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).unwrap();
        let (inputs, want) = golden(&g, N, 7);
        let records = || inputs.iter().map(Vec::as_slice);
        for seed in [1, 2] {
            let opts = sim::RunOptions {
                stalls: Some(seed),
                stall_percent: Some(40),
                ..Default::default()
            };
            let stem = dir.join(format!("stalled{seed}"));
            let (stats, got) = h.run_records(records(), &stem, &opts).unwrap();
            assert!(
                stats.stalls > N / 10 && stats.bubbles > N / 10,
                "{unit}: {stats:?}"
            );
            // one result per transaction, in order, each the golden one
            assert!(
                got == want,
                "{unit}: results differ with stalls (seed {seed})"
            );
        }
        let never = sim::RunOptions {
            stall_percent: Some(0),
            ..Default::default()
        };
        let (stats, got) = h
            .run_records(records(), &dir.join("never"), &never)
            .unwrap();
        assert!(got == want, "{unit}: results differ without stalls");
        assert_eq!((stats.stalls, stats.bubbles), (0, 0), "{unit}");
        // one transaction a cycle: the harness also checked in_ready high
        // and out_valid exactly `latency` cycles after each transaction
        assert_eq!(
            stats.cycles,
            N + g.module.latency as u64 + HARNESS_OVERHEAD,
            "{unit}: {stats:?}"
        );
        eprintln!(
            "{}: latency {}, {N} vectors with stalls and without, full rate",
            g.module.name, g.module.latency
        );
    }
}

/// An Icarus testbench for a valid/ready unit: reset, then cycles with
/// in_valid low and X on every data input, and out_ready toggling; every
/// cycle after reset `in_ready` and `out_valid` must be 0 or 1 and
/// `out_valid` must be 0 (no transaction was given). Then one transaction
/// with known inputs, X again on the inputs after it: its outputs must carry
/// no X when out_valid rises.
fn icarus_bench(g: &Generated) -> String {
    let top = &g.module.name;
    let decls: String = g
        .ports
        .inputs
        .iter()
        .map(|p| format!("    reg [{}:0] {};\n", p.width - 1, p.name))
        .chain(
            g.ports
                .outputs
                .iter()
                .map(|p| format!("    wire [{}:0] {};\n", p.width - 1, p.name)),
        )
        .collect();
    let conns: String = g
        .ports
        .inputs
        .iter()
        .chain(&g.ports.outputs)
        .map(|p| format!(", .{0}({0})", p.name))
        .collect();
    let set_x: String = g
        .ports
        .inputs
        .iter()
        .map(|p| format!("{} = {}'bx; ", p.name, p.width))
        .collect();
    let set_known: String = g
        .ports
        .inputs
        .iter()
        .map(|p| format!("{} = {}'d1; ", p.name, p.width))
        .collect();
    let outs_x: Vec<String> = g
        .ports
        .outputs
        .iter()
        .map(|p| format!("(^{} === 1'bx)", p.name))
        .collect();
    format!(
        "`timescale 1ns/1ps
module tb;
    reg clk = 0, rst = 1, in_valid = 0, out_ready = 0;
    wire out_valid, in_ready;
{decls}    {top} dut(.clk(clk), .rst(rst), .in_valid(in_valid), .out_ready(out_ready),
        .out_valid(out_valid), .in_ready(in_ready){conns});
    always #5 clk = ~clk;
    integer i, seen;
    initial begin
        {set_x}
        repeat (3) @(posedge clk);
        #1 rst = 0;
        for (i = 0; i < 40; i = i + 1) begin
            out_ready = i[0] ^ i[2];
            {set_x}
            #3;
            if (in_ready !== 1'b1 && in_ready !== 1'b0) begin $display(\"FAIL: in_ready is X at cycle %0d\", i); $finish; end
            if (out_valid !== 1'b0) begin $display(\"FAIL: out_valid=%b with no transaction at cycle %0d\", out_valid, i); $finish; end
            @(posedge clk); #1;
        end
        {set_known}in_valid = 1; out_ready = 1;
        seen = 0;
        for (i = 0; i < {wait} && seen == 0; i = i + 1) begin
            #3;
            if (i == 0 && in_ready !== 1'b1) begin $display(\"FAIL: in_ready=%b after reset\", in_ready); $finish; end
            if (out_valid === 1'b1) begin
                seen = 1;
                if ({outs_x}) begin $display(\"FAIL: X on a valid output\"); $finish; end
            end else if (out_valid !== 1'b0) begin $display(\"FAIL: out_valid is X\"); $finish; end
            @(posedge clk); #1 in_valid = 0;
            {set_x}
        end
        if (seen == 0) begin $display(\"FAIL: the transaction never came out\"); $finish; end
        $display(\"PASS\");
        $finish;
    end
endmodule
",
        wait = g.module.latency + 4,
        outs_x = outs_x.join(" || "),
    )
}

/// Compiles `bench` with the unit's files in Icarus and runs it.
fn icarus(g: &Generated, dir: &Path, bench: &str) -> String {
    let sources: Vec<_> = g.files.iter().map(|f| dir.join(&f.file_name)).collect();
    common::icarus(dir, "tb_x", bench, &sources, &["-g2005"])
}

#[test]
fn icarus_x_on_idle_inputs_never_reaches_a_valid_output_and_reset_leaves_no_x() {
    for (unit, params) in UNITS {
        let (g, dir) = common::generate("handshake_x", unit, &ready(params));
        let log = icarus(&g, &dir, &icarus_bench(&g));
        assert!(log.contains("PASS"), "{unit}: {log}");
        assert!(!log.contains("FAIL"), "{unit}: {log}");
    }
}
