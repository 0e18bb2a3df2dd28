//! Seed 002's hybrid render with every cull and contribution check answered
//! by the Verilated `raycull` unit (`scene::hybrid_rtl`): three scenes, each
//! in another depth format, compare mode and shading mode (cornell with its
//! translucent block, `less`, immediate; field `greater` in partial renders
//! of 8 primitives; grass `gequal`, compared with the synchronous render in
//! the same order), the four fixed primitive orders and five shuffles; every
//! RTL output equals the golden model's, the replayed render equals the
//! recorded one, and its image equals the synchronous render.

use golden_model::raycull::{Compare, DepthFormat};
use scene::bvh::Accel;
use scene::hybrid::{orders, render_sync, HybridOpts, Mode};
use scene::hybrid_rtl::{hybrid_rtl, RtlTally};
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::TraceOpts;
use std::path::Path;

#[test]
fn hybrid_culls_through_rtl_identical_in_every_order() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hybrid_rtl");
    let mut tally = RtlTally::default();
    for (name, w, depth, compare, mode) in [
        (
            "cornell",
            24,
            DepthFormat::Unorm16,
            Compare::Less,
            Mode::Immediate,
        ),
        (
            "field",
            12,
            DepthFormat::Unorm24,
            Compare::Greater,
            Mode::Partial(8),
        ),
        (
            "grass",
            12,
            DepthFormat::Binary32,
            Compare::GEqual,
            Mode::Immediate,
        ),
    ] {
        let mut s = Scene::load(&dir.join(format!("{name}.toml"))).unwrap();
        s.render.ao_rays = 1;
        let acc = Accel::build(&s, false);
        let (g, opts) = (Golden::default(), TraceOpts::default());
        let base = HybridOpts {
            rays_per_step: 8,
            result_latency: 4,
            depth,
            compare,
            mode,
            ..HybridOpts::default()
        };
        let mut sync = render_sync(&s, &acc, &g, opts, w, w, &base);
        for seed in 1..=5u64 {
            for (order_name, order) in orders(&s, &acc, seed) {
                if seed > 1 && order_name != "shuffled" {
                    continue;
                }
                let hopts = HybridOpts {
                    order,
                    ..base.clone()
                };
                if compare == Compare::GEqual {
                    // the last of equal-depth fragments wins: same order
                    sync = render_sync(&s, &acc, &g, opts, w, w, &hopts);
                }
                let (f, c) = hybrid_rtl(&s, &acc, &g, opts, w, w, &hopts, &work, &mut tally)
                    .unwrap_or_else(|e| panic!("{name} {order_name} {seed}: {e}"));
                let what = format!("{name} {order_name} {seed}");
                assert_eq!(f.ids, sync.ids, "{what}");
                assert_eq!(f.t, sync.t, "{what}");
                for p in 0..f.color.len() {
                    assert_eq!(f.color_bits(p), sync.color_bits(p), "{what}: pixel {p}");
                }
                assert_eq!(c.used, sync.stats.total().rays, "{what}");
                assert_eq!(c.lost, 0, "{what}");
            }
        }
    }
    eprintln!("{tally:?}");
    assert_eq!(
        tally.mismatches, 0,
        "RTL outputs differ from the golden model"
    );
    assert_eq!(tally.renders_differ, 0, "a replayed render differs");
    assert!(tally.tests > 10_000, "{tally:?}");
}
