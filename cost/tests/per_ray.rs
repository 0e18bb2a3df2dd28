//! `rtl-gen per-ray`'s workload side: the transactions per unit of a
//! golden render follow the switches (no cull tests without planes, no
//! bundle tests without bundles) and every unit of the sum is exercised.

use cost::per_ray::{cost_per_ray, markdown, workloads, Area, ROLES};
use std::path::Path;

#[test]
fn workloads_follow_planes_and_bundles_and_exercise_every_unit() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml");
    let loads = workloads(&scene, 24, false).expect("cornell renders");
    assert_eq!(loads.len(), 4);
    for w in &loads {
        assert!(w.rays > 0);
        let [single, bundle, cull, interval, recip, cull_ray, transforms, tris] = w.tests;
        assert!(single > 0 && transforms > 0 && tris > 0, "{w:?}");
        assert_eq!(cull > 0, w.planes, "{w:?}");
        // every cull test needs the child's box interval; the interval, three
        // reciprocals per instance entry
        assert_eq!(interval, cull, "{w:?}");
        assert_eq!(recip, if w.planes { 3 * transforms } else { 0 }, "{w:?}");
        assert_eq!(cull_ray > 0, w.planes, "{w:?}");
        assert!(cull_ray <= cull, "terms once per ray and parent: {w:?}");
        assert_eq!(bundle > 0, w.bundles, "{w:?}");
    }
    // the planes remove triangle tests; their own tests cost area: both show
    let on = &loads[0];
    let off = &loads[2];
    assert!(on.tests[7] < off.tests[7], "planes remove triangle tests");
    let areas = [Area {
        luts: 1000,
        dsps: 2,
    }; 8];
    let (luts, dsps) = cost_per_ray(on, &areas);
    assert!(
        luts > 0.0 && (dsps - luts / 500.0).abs() < 1e-6,
        "{luts} {dsps}"
    );
    let t = markdown(Some(&areas), &loads);
    assert_eq!(t.lines().filter(|l| l.starts_with("| cornell")).count(), 4);
    assert!(!markdown(None, &loads).contains("LUT-cycles / ray |"));
    assert_eq!(ROLES.len(), 8);
    assert!(t.contains("DSP-cycles / ray"));
}

/// `--by-kind`: one workload per ray type and configuration, whose rays and
/// transactions add up to the all-rays workload's.
#[test]
fn workloads_by_kind_add_up_to_all_rays() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml");
    let all = workloads(&scene, 16, false).expect("cornell renders");
    let kinds = workloads(&scene, 16, true).expect("cornell renders");
    assert_eq!(kinds.len(), 3 * all.len());
    for (w, k) in all.iter().zip(kinds.chunks(3)) {
        assert_eq!(k.iter().map(|x| x.rays).sum::<u64>(), w.rays);
        for r in 0..8 {
            assert_eq!(k.iter().map(|x| x.tests[r]).sum::<u64>(), w.tests[r]);
        }
        assert!(k[0].scene.ends_with("primary") && k[1].scene.ends_with("shadow"));
        assert!(k.iter().all(|x| x.rays > 0), "{k:?}");
    }
}
