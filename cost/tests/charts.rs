//! The pure parts of the charts and tables (no synthesis, no workloads).

use cost::accuracy::RayStats;
use cost::charts::{log_ticks, sound_front, tick_label, Point};
use cost::sweep::{self, BoxAccuracy, Sweep};
use cost::synth::{SynthReport, Xilinx};

#[test]
fn tick_labels_are_short() {
    for (v, want) in [
        (10_000.0, "10k"),
        (20_000.0, "20k"),
        (50_000.0, "50k"),
        (1_500.0, "1.5k"),
        (1_000.0, "1k"),
        (2e6, "2M"),
        (500.0, "500"),
        (1.0, "1"),
        (0.5, "0.5"),
        (0.02, "0.02"),
        (1e-3, "1e-3"),
        (2e-5, "2e-5"),
        (1e-6, "1e-6"),
        (0.0, "0"),
    ] {
        assert_eq!(tick_label(v), want, "{v}");
    }
}

#[test]
fn log_ticks_label_one_two_five() {
    // the range of the old chart whose labels overlapped (30000.0 40000.0 ...)
    let (bold, light) = log_ticks(3_000.0, 60_000.0, 12);
    let labels: Vec<String> = bold.iter().map(|v| tick_label(*v)).collect();
    assert_eq!(labels, ["5k", "10k", "20k", "50k"]);
    for v in [3_000.0, 4_000.0, 30_000.0, 40_000.0, 60_000.0] {
        assert!(
            light.iter().any(|l| (l / v - 1.0).abs() < 1e-9),
            "{v} unlabelled tick"
        );
        assert!(
            !bold.iter().any(|b| (b / v - 1.0).abs() < 1e-9),
            "{v} not labelled"
        );
    }
}

#[test]
fn log_ticks_thin_out_wide_ranges() {
    // eight decades of rates: 1-2-5 would be 22 labels, powers of ten are 8
    let (bold, _) = log_ticks(3e-7, 3.0, 12);
    let labels: Vec<String> = bold.iter().map(|v| tick_label(*v)).collect();
    assert_eq!(labels, ["1e-6", "1e-5", "1e-4", "1e-3", "0.01", "0.1", "1"]);
    // still too many: every second power
    let (bold, _) = log_ticks(1e-12, 1e12, 12);
    assert!(bold.len() <= 13, "{bold:?}");
    // a range of less than a decade also gets its 3s
    let (bold, _) = log_ticks(2_020.0, 17_000.0, 12);
    assert_eq!(bold, [3_000.0, 5_000.0, 10_000.0]);
    // a narrow range without 1, 2 or 5 still gets labels
    let (bold, _) = log_ticks(6_100.0, 9_500.0, 12);
    assert_eq!(bold, [7_000.0, 8_000.0, 9_000.0]);
    assert_eq!(log_ticks(0.0, 1.0, 12), (vec![], vec![]));
}

#[test]
fn front_excludes_designs_with_false_misses() {
    let p = |x: f64, y: f64, fm: u64| Point {
        x,
        y,
        label: String::new(),
        false_misses: fm,
    };
    let pts = [
        // cheapest and (at the floor) fewest false hits, but loses hits
        p(1_000.0, 0.0, 400),
        p(5_000.0, 2e-3, 0),
        p(9_000.0, 1e-3, 0),
        p(10_000.0, 5e-3, 0),
        p(20_000.0, 0.0, 0),
    ];
    assert_eq!(
        sound_front(&pts, 1e-6),
        vec![(5_000.0, 2e-3), (9_000.0, 1e-3), (20_000.0, 1e-6)]
    );
    // without the rule the missing tester would dominate everything
    let all: Vec<(f64, f64)> = pts.iter().map(|q| (q.x, q.y.max(1e-6))).collect();
    assert_eq!(cost::charts::pareto_front(&all), vec![(1_000.0, 1e-6)]);
}

#[test]
fn sweep_has_both_modes_and_both_slabs_at_every_format() {
    let cfgs = sweep::configurations();
    for f in sweep::FRACS {
        let frac = format!("frac_bits={f}");
        for (unit, extra) in [
            ("silhouette", "mode=ray"),
            ("silhouette", "mode=bundle"),
            ("slab", "rounding=conservative"),
            ("slab", "rounding=nearest"),
        ] {
            assert!(
                cfgs.iter().any(|(u, p)| u == unit
                    && p.contains(&frac)
                    && p.iter().any(|x| x == extra)
                    && p.iter().any(|x| x == "stages=4")),
                "{unit} {extra} e8m{f}"
            );
        }
    }
}

fn report(unit: &str, kv: &[(&str, &str)], luts: u64) -> SynthReport {
    SynthReport {
        unit: unit.into(),
        params: kv
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        xilinx: Some(Xilinx {
            luts,
            ffs: 10,
            dsps: 2,
            ..Default::default()
        }),
        ..Default::default()
    }
}

#[test]
fn designs_found_and_false_misses_kept_apart() {
    let stats = |hits, fh, fm| RayStats {
        n: 100,
        hits,
        false_hits: fh,
        false_misses: fm,
        uncertain: 0,
    };
    let s = Sweep {
        cost: vec![
            report(
                "silhouette",
                &[("frac_bits", "7"), ("mode", "bundle"), ("origin", "shared")],
                9_000,
            ),
            report("silhouette", &[("frac_bits", "7"), ("mode", "ray")], 4_000),
            report(
                "slab",
                &[("frac_bits", "7"), ("rounding", "nearest")],
                2_800,
            ),
            report(
                "slab",
                &[("frac_bits", "7"), ("rounding", "conservative")],
                3_500,
            ),
        ],
        boxes: ["scene", "grazing"]
            .iter()
            .map(|wl| BoxAccuracy {
                frac_bits: 7,
                exp_bits: 8,
                workload: wl.to_string(),
                silhouette: stats(50, 5, 0),
                slab: stats(50, 1, 3),
                slab_conservative: stats(50, 8, 0),
                ..Default::default()
            })
            .collect(),
        ..Default::default()
    };
    let lut = |l: &str| {
        sweep::find_design(&s, l, 7)
            .and_then(|r| r.xilinx.as_ref())
            .map(|x| x.luts)
    };
    assert_eq!(lut("silhouette ray"), Some(4_000));
    assert_eq!(lut("silhouette bundle"), Some(9_000));
    assert_eq!(lut("slab RNE"), Some(2_800));
    assert_eq!(lut("slab conservative"), Some(3_500));
    assert_eq!(sweep::false_misses(&s, "slab RNE", 7), (6, 100));
    assert_eq!(sweep::false_misses(&s, "slab conservative", 7), (0, 100));
    assert_eq!(sweep::false_misses(&s, "silhouette ray", 7), (0, 100));
    let t = sweep::box_table(&s);
    assert!(t.contains("synthesis estimate"), "{t}");
    assert!(t.contains("| slab RNE | e8m7 | 2,800 | 10 | 2 |"), "{t}");
    assert!(t.contains("6 (6.00e-2 of hits)"), "{t}");
    assert!(t.contains("RAABB m=7 (published reference: Xilinx XST estimates, exponent 11 bits"));
    assert!(t.contains("| e11m23 | 17,561 | 10,686 | 36 |"), "{t}");
    assert_eq!(sweep::thousands(9_338), "9,338");
    assert_eq!(sweep::thousands(999), "999");
    assert_eq!(sweep::thousands(1_000_000), "1,000,000");
}
