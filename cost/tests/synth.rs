//! The synthesis runner on one tiny design (a 4x4 multiply-compare): every
//! flow reports, the numbers are plausible, and place and route gives a
//! real Fmax on an iCE40UP5K.

use cost::synth::{self, SynthOptions};

#[test]
fn tiny_mulcmp_through_yosys_and_nextpnr() {
    let g = rtl_gen::flow::generate(
        "mulcmp",
        &["a_width=4".into(), "b_width=4".into(), "stages=1".into()],
    )
    .unwrap();
    let o = SynthOptions {
        cache: None,
        ..Default::default()
    };
    let r = synth::run(&g, &o).expect("yosys and nextpnr-ice40 run (scripts/setup.sh)");
    assert_eq!(r.latency, 1);
    assert_eq!(r.throughput, 1.0);
    let gen = r.generic.as_ref().unwrap();
    assert!(gen.cells > 20 && gen.depth > 3, "{gen:?}");
    let ice = r.ice40.as_ref().unwrap();
    // ab (8 bits), lt, eq, out_valid registered at least: 11 flip-flops
    assert!(ice.luts > 10 && ice.dffs >= 11 && ice.depth > 2, "{ice:?}");
    let ecp = r.ecp5.as_ref().unwrap();
    assert!(ecp.dsps + ecp.luts > 0, "{ecp:?}");
    let p = r.pnr.as_ref().unwrap();
    assert_eq!(p.device, "up5k");
    let f = p.fmax_mhz.expect("nextpnr reports an Fmax");
    assert!(f > 5.0 && f < 500.0, "{p:?}");
    assert!(p.lcs_used > 0 && p.lcs_total == 5280, "{p:?}");
    let row = synth::table_row(&r);
    assert!(
        row.starts_with("| mulcmp |") && row.contains("up5k"),
        "{row}"
    );
}

#[test]
fn log_parsers() {
    let log = "Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 38.02 MHz (PASS at 12.00 MHz)\n\
               Info:     ICESTORM_LC:   123/ 5280     2%\n\
               Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 41.50 MHz (PASS at 12.00 MHz)\n";
    assert_eq!(synth::parse_fmax(log), Some(41.5));
    assert_eq!(synth::parse_lcs(log), Some((123, 5280)));
    assert_eq!(
        synth::parse_ltp("Longest topological path in top (length=17):"),
        Some(17)
    );
}

#[test]
fn fit_suzanne_format_without_synthesis() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/suzanne.obj");
    let (mesh, _) = cost::fit::load(&path).expect("../shared/scenes beside the clone");
    let o = cost::fit::FitOptions {
        target_rate: 0.01,
        target_mhz: 20.0,
        rays: 100,
        synth: false,
        seed: 1,
    };
    let f = cost::fit::fit(&mesh, "suzanne", &o).unwrap();
    assert!(
        (4..=8).contains(&f.exp_bits) && (4..=23).contains(&f.frac_bits),
        "{}",
        f.report
    );
    assert!(f.report.contains("meets the target"));
    rtl_gen::flow::generate("silhouette", &f.params).unwrap();
}

#[test]
fn pareto_front_keeps_undominated_points() {
    let f = cost::charts::pareto_front(&[(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0)]);
    assert_eq!(f, vec![(1.0, 5.0), (2.0, 3.0), (4.0, 1.0)]);
}
