//! Seed 002: the asynchronous hybrid render (shading and ray emission during
//! rasterisation, depth-based culling with tile ranges, sample depths and
//! generation ids, contribution check, every decision by the golden model of
//! the `raycull` unit on quantised depth codes) gives the same image as the
//! synchronous one (which rasterises the same codes) for every primitive
//! order and ray-processor interleaving tested, on three scenes and five
//! shuffle seeds; and each cull stage acts (floors below).

use golden_model::raycull::DepthFormat;
use scene::bvh::Accel;
use scene::hybrid::{orders, render_async, render_sync, HybridCounts, HybridOpts};
use scene::render::Frame;
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::TraceOpts;
use std::path::Path;

const W: u32 = 24;
const H: u32 = 24;

/// Cornell (2 AO rays), its acceleration structure and its synchronous render
/// at W×H, the reference of every asynchronous one.
fn cornell_sync() -> (Scene, Accel, Frame) {
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 2;
    let acc = Accel::build(&s, true);
    let sync = render_sync(
        &s,
        &acc,
        &Golden::default(),
        TraceOpts::default(),
        W,
        H,
        &HybridOpts {
            depth: DepthFormat::Unorm24,
            ..Default::default()
        },
    );
    (s, acc, sync)
}

/// The asynchronous render has the synchronous one's surfaces, depths and
/// colour bits.
fn assert_same_image(f: &Frame, sync: &Frame, what: &str) {
    assert_eq!(f.ids, sync.ids, "{what}: visible surfaces");
    assert_eq!(f.t, sync.t, "{what}: depths");
    for p in 0..f.color.len() {
        assert_eq!(f.color_bits(p), sync.color_bits(p), "{what}: pixel {p}");
    }
}

#[test]
fn async_equals_sync_for_several_orders() {
    let (s, acc, sync) = cornell_sync();
    let (w, h) = (W, H);
    let g = Golden::default();
    let opts = TraceOpts::default();
    let used: u64 = sync.stats.total().rays;
    let mut culled_any = false;
    for (name, order) in orders(&s, &acc, 5) {
        for step in [0usize, 16, 1] {
            if step == 1 && name != "shuffled" {
                continue;
            }
            let (f, c) = render_async(
                &s,
                &acc,
                &g,
                opts,
                w,
                h,
                &HybridOpts {
                    order: order.clone(),
                    rays_per_step: step,
                    result_latency: 0,
                    ..HybridOpts::default()
                },
            );
            assert_same_image(&f, &sync, &format!("{name}/{step}"));
            assert_eq!(
                c.used, used,
                "{name}/{step}: rays used = rays of the synchronous render"
            );
            assert_eq!(
                c.emitted,
                c.culled_tile + c.culled_depth + c.culled_generation + c.traced,
                "{name}/{step}: every emitted ray is culled or traced"
            );
            assert!(c.traced >= c.used);
            culled_any |= c.culled_tile + c.culled_depth + c.culled_generation > 0;
            eprintln!("{name:>14} step {step:>2}: {c:?}");
        }
    }
    assert!(culled_any, "some order culls rays");
}

/// The contribution check (seed 002's verification logic) exercised: with
/// results in flight while later primitives are rasterised, rays culled
/// against one depth buffer come back after their sample's surface changed
/// (including generation wrap-arounds: a sample can change surface 8 times
/// within the latency, so its 3-bit generation matches again). Every such
/// stale result must be discarded (`discarded > 0`) and the image must still
/// be the synchronous one, bit for bit.
#[test]
fn stale_results_are_discarded_by_the_contribution_check() {
    let (s, acc, sync) = cornell_sync();
    let (w, h) = (W, H);
    let g = Golden::default();
    let opts = TraceOpts::default();
    let used: u64 = sync.stats.total().rays;
    let mut discarded = 0;
    for (name, order) in orders(&s, &acc, 5) {
        for latency in [1usize, 8, 64] {
            let (f, c) = render_async(
                &s,
                &acc,
                &g,
                opts,
                w,
                h,
                &HybridOpts {
                    order: order.clone(),
                    rays_per_step: 16,
                    result_latency: latency,
                    ..HybridOpts::default()
                },
            );
            assert_same_image(&f, &sync, &format!("{name}/{latency}"));
            assert_eq!(c.used, used, "{name}/{latency}");
            eprintln!(
                "{name:>14} latency {latency:>2}: discarded {} of {} traced",
                c.discarded, c.traced
            );
            discarded += c.discarded;
        }
    }
    assert!(
        discarded > 0,
        "no stale result reached the contribution check"
    );
}

fn check_counts(c: &HybridCounts, used: u64, what: &str) {
    assert_eq!(
        c.used, used,
        "{what}: rays used = rays of the synchronous render"
    );
    assert_eq!(
        c.emitted,
        c.culled_tile + c.culled_depth + c.culled_generation + c.traced,
        "{what}: every emitted ray is culled or traced"
    );
    assert!(
        c.culled_group_rays <= c.culled_tile,
        "{what}: a group cull is a tile cull"
    );
    assert_eq!(c.lost, 0, "{what}: a final surface's ray was culled");
}

/// Every order (stored, reversed, front-to-back, back-to-front and five
/// shuffles) on three scenes, each in another depth format, and two
/// ray-processor paces: the asynchronous image is the synchronous one.
#[test]
fn every_order_identical_on_three_scenes_and_five_shuffles() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for (name, w, depth) in [
        ("cornell", 24, DepthFormat::Unorm16),
        ("field", 16, DepthFormat::Unorm24),
        ("grass", 12, DepthFormat::Binary32),
    ] {
        let mut s = Scene::load(&dir.join(format!("{name}.toml"))).unwrap();
        s.render.ao_rays = 1;
        let acc = Accel::build(&s, false);
        let (g, opts) = (Golden::default(), TraceOpts::default());
        let sync = render_sync(
            &s,
            &acc,
            &g,
            opts,
            w,
            w,
            &HybridOpts {
                depth,
                ..Default::default()
            },
        );
        let used = sync.stats.total().rays;
        let mut runs = Vec::new();
        for seed in 1..=5u64 {
            for (order_name, order) in orders(&s, &acc, seed) {
                if seed > 1 && order_name != "shuffled" {
                    continue;
                }
                runs.push((format!("{order_name} {seed}"), order));
            }
        }
        for (what, order) in runs {
            for step in [0usize, 8] {
                let (f, c) = render_async(
                    &s,
                    &acc,
                    &g,
                    opts,
                    w,
                    w,
                    &HybridOpts {
                        order: order.clone(),
                        rays_per_step: step,
                        depth,
                        ..HybridOpts::default()
                    },
                );
                let what = format!("{name} {what} step {step}");
                assert_same_image(&f, &sync, &what);
                check_counts(&c, used, &what);
            }
        }
    }
}

/// Each stage of the unit acts in the renderer, so losing one fails here
/// (the image alone would not: a later stage or the contribution check
/// catches what an earlier one misses). Cornell 48x48, unorm16, 16 rays
/// per primitive or all at the end: the tile stage culls with the sample
/// stage on, whole groups are
/// culled, the generation culls at equal depth (reversed order), and with
/// results in flight the contribution check discards stale results; with
/// the switch off nothing is culled and the image is still the same.
#[test]
fn every_cull_stage_acts_in_the_renderer() {
    let (s, acc, _) = cornell_sync();
    let (g, opts) = (Golden::default(), TraceOpts::default());
    // 48x48: at 24x24 every 8x8 tile holds a sample of the back wall, the
    // farthest final surface, and nothing lies beyond a tile's far end
    const W2: u32 = 48;
    let sync = render_sync(
        &s,
        &acc,
        &g,
        opts,
        W2,
        W2,
        &HybridOpts {
            depth: DepthFormat::Unorm16,
            ..Default::default()
        },
    );
    let used = sync.stats.total().rays;
    let mut total = HybridCounts::default();
    for (name, order) in orders(&s, &acc, 5) {
        for (step, latency, cull) in [
            (16, 0usize, true),
            (16, 8, true),
            (0, 0, true),
            (16, 8, false),
        ] {
            let (f, c) = render_async(
                &s,
                &acc,
                &g,
                opts,
                W2,
                W2,
                &HybridOpts {
                    order: order.clone(),
                    rays_per_step: step,
                    result_latency: latency,
                    depth: DepthFormat::Unorm16,
                    cull,
                    ..HybridOpts::default()
                },
            );
            let what = format!("{name} step {step} latency {latency} cull {cull}");
            assert_same_image(&f, &sync, &what);
            check_counts(&c, used, &what);
            eprintln!("{what}: {c:?}");
            if !cull {
                assert_eq!(c.traced, c.emitted, "{what}: the switch is off");
                continue;
            }
            total.culled_tile += c.culled_tile;
            total.culled_depth += c.culled_depth;
            total.culled_generation += c.culled_generation;
            total.culled_groups += c.culled_groups;
            total.discarded += c.discarded;
        }
    }
    eprintln!("totals: {total:?}");
    assert!(total.culled_tile >= 100, "tile stage: {total:?}");
    assert!(total.culled_depth >= 100, "sample depth: {total:?}");
    assert!(total.culled_generation >= 10, "generation: {total:?}");
    assert!(total.culled_groups >= 10, "groups: {total:?}");
    assert!(total.discarded >= 10, "contribution check: {total:?}");
}
