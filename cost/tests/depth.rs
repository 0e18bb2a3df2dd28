//! `rtl-gen depth` end to end on a small unit, so that the Fmax-against-depth
//! flow (synth_ecp5 and nextpnr-ecp5 of the timing shell, both register
//! placements) cannot rot. Needs the toolchain of `bash scripts/setup.sh`.

#[test]
fn depth_sweep_routes_both_placements_of_fadd_e5m4() {
    let params = vec!["exp_bits=5".to_string(), "frac_bits=4".to_string()];
    let pipelines = vec!["plan".to_string(), "balanced".to_string()];
    let rows = cost::depth::sweep("fadd", &params, &[3], &pipelines, 100.0, None, 1)
        .unwrap_or_else(|e| panic!("rtl-gen depth (run `bash scripts/setup.sh`): {e}"));
    let table = cost::depth::table("fadd", &params, &rows, None, 1);
    eprintln!("{table}");
    assert_eq!(rows.len(), 2);
    let fmax = |r: &cost::depth::DepthRow| {
        r.report
            .pnr_ecp5
            .as_ref()
            .and_then(|p| p.fmax_mhz)
            .unwrap_or_else(|| panic!("{} routed: {table}", r.pipeline))
    };
    for r in &rows {
        assert_eq!(r.report.latency, 3);
        assert!(
            r.report.ecp5.as_ref().is_some_and(|e| e.luts > 0),
            "{table}"
        );
    }
    let (plan, balanced) = (&rows[0], &rows[1]);
    assert!(balanced.report.top.ends_with("_bal"), "{table}");
    assert!(
        balanced.model_period < plan.model_period,
        "the balanced placement has the shorter modelled period:\n{table}"
    );
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("depth_chart");
    std::fs::create_dir_all(&dir).unwrap();
    let files = cost::depth::chart("fadd", &params, &rows, "depth_fadd", &dir).unwrap();
    assert!(
        files
            .iter()
            .all(|f| f.metadata().is_ok_and(|m| m.len() > 1000)),
        "{files:?}"
    );
    // routing noise aside, the balanced adder is not slower than the plan's
    assert!(
        fmax(balanced) >= 0.9 * fmax(plan),
        "balanced {:.1} MHz against plan {:.1} MHz:\n{table}",
        fmax(balanced),
        fmax(plan)
    );
}
