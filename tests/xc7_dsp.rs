//! `dsp=xc7`: the cells Yosys synthesises (the `SYNTHESIS` branch, which
//! Verilator never compiles) simulated in Icarus against Yosys's own
//! 7-series cell models and compared with `a·b`; and the budget of blocks
//! a unit is given.

mod common;

use common::generate;
use std::path::Path;

/// Yosys's simulation models of the 7-series cells (`LUT6`, `CARRY4`,
/// `DSP48E1`), beside the `yosys` the set-up installs
/// (`<prefix>/bin/yosys`, `<prefix>/share/yosys/xilinx/cells_sim.v`).
fn xc7_cell_models() -> std::path::PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let yosys = std::env::split_paths(&path)
        .map(|d| d.join("yosys"))
        .find(|y| y.is_file())
        .unwrap_or_else(|| panic!("yosys is needed for this test (its 7-series cell models)"));
    let prefix = yosys.canonicalize().unwrap_or(yosys);
    let prefix = prefix
        .parent()
        .and_then(Path::parent)
        .expect("<prefix>/bin/yosys");
    let models = prefix.join("share/yosys/xilinx/cells_sim.v");
    assert!(
        models.is_file(),
        "Yosys's 7-series cell models are needed for this test: no {}",
        models.display()
    );
    models
}

/// Every `a` against every pattern of `b`'s top seven bits (the Booth
/// digits), with random low bits, then random and extreme operands: the
/// synthesised structure gives `a·b` exactly.
#[test]
fn the_hand_placed_product_is_a_times_b_in_the_cell_models() {
    let (g, dir) = generate(
        "xc7_product",
        "triangle",
        &[
            "outputs=tnum",
            "products=whole",
            "stages=8",
            "dsp=xc7",
            "dsp_blocks=24",
        ],
    );
    let product = g
        .files
        .iter()
        .find(|f| f.module.starts_with("xc7_umul_24x24"))
        .expect("the unit instantiates the xc7 product");
    assert!(product.text.contains("`ifdef SYNTHESIS"));
    let bench = "`timescale 1ns/1ps
module tb;
    reg [23:0] a, b;
    wire [47:0] p;
    xc7_umul_24x24_dsp1 dut (.a(a), .b(b), .p(p));
    integer i, wrong, seed;
    task check;
        begin
            #1;
            if (p !== a * b) begin
                wrong = wrong + 1;
                if (wrong < 5)
                    $display(\"MISMATCH a=%h b=%h cells=%h a*b=%h\", a, b, p, {24'd0, a} * {24'd0, b});
            end
        end
    endtask
    initial begin
        wrong = 0; seed = 42;
        for (i = 0; i < 128 * 16; i = i + 1) begin
            a = (i % 16 == 0) ? 24'hffffff : (i % 16 == 1) ? 24'd0 : $random(seed);
            b = {i[10:4], 17'd0} | ($random(seed) & 24'h01ffff);
            check;
        end
        for (i = 0; i < 4000; i = i + 1) begin
            a = $random(seed);
            b = $random(seed);
            if (i % 7 == 0) a = 24'hffffff;
            if (i % 11 == 0) b = 24'hffffff;
            if (i % 13 == 0) b = 24'h800000;
            check;
        end
        $display(\"DONE wrong=%0d\", wrong);
        $finish;
    end
endmodule
";
    let sources = [dir.join(&product.file_name), xc7_cell_models()];
    let log = common::icarus(
        &dir,
        "tb_xc7_product",
        bench,
        &sources,
        &["-g2012", "-DSYNTHESIS"],
    );
    assert!(log.contains("DONE wrong=0"), "{log}");
}

/// The budget: the unit's modelled blocks go down to it, one product at a
/// time, and one it cannot meet is refused with the least it can.
#[test]
fn dsp_blocks_is_met_or_refused_with_what_the_unit_needs() {
    let base = ["outputs=tnum", "products=whole", "stages=8"];
    let with = |extra: &[&str]| {
        let mut p: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        p.extend(extra.iter().map(|s| s.to_string()));
        rtl_flow::generate("triangle", &p)
    };
    let products = |g: &rtl_flow::Generated| {
        g.module
            .instances
            .iter()
            .filter(|i| i.module.name.starts_with("xc7_umul"))
            .count()
    };
    let plain = with(&[]).unwrap();
    assert_eq!(products(&plain), 0);
    let g = with(&["dsp=xc7", "dsp_blocks=30"]).unwrap();
    let every = with(&["dsp=xc7"]).unwrap();
    let all = products(&every);
    assert!(all >= 12, "{all} products of 24x24 bits");
    assert_eq!(products(&g), 2 * all - 30, "{}", g.module.description);
    assert!(g.module.description.contains("30 blocks"));
    let err = with(&["dsp=xc7", &format!("dsp_blocks={}", all - 1)])
        .err()
        .expect("fewer blocks than products is refused");
    assert!(
        err.to_string().contains(&format!("at least {all}")),
        "{err}"
    );
    let err = with(&["dsp_blocks=24"]).err().expect("dsp_blocks alone");
    assert!(err.to_string().contains("dsp=xc7"), "{err}");
}
