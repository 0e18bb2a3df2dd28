//! Seed 002's hybrid render beyond the default raster: translucent surfaces
//! (cornell's tall block has opacity 0.5; the unit's "OK to drop farther"
//! rule keeps the rays of the opaque surface behind it), partial renders and
//! deferred shading (`Mode`), and reversed depth (`greater`, `gequal`): the
//! image equals the synchronous render in every order, and the rule's
//! figures reach their floors (a unit that ignores the rule loses rays).

use golden_model::raycull::{cull, Compare, DepthFormat};
use scene::bvh::Accel;
use scene::hybrid::{
    orders, render_async, render_async_with, render_sync, world_triangles, HybridCounts,
    HybridOpts, Mode,
};
use scene::render::Frame;
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::TraceOpts;
use std::path::Path;

const W: u32 = 24;

fn cornell() -> (Scene, Accel) {
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 1;
    assert!(
        s.instances.iter().any(|i| i.translucent()),
        "cornell has a translucent surface"
    );
    let acc = Accel::build(&s, false);
    (s, acc)
}

fn same(f: &Frame, sync: &Frame) -> bool {
    f.same_image(sync)
}

/// Every order (four fixed, two shuffles) with `base`'s raster and mode:
/// the image is the synchronous render's (in the same order for `lequal`,
/// `gequal`), no final ray is lost, and each emitted ray is culled or
/// traced; returns the summed counts.
fn every_order(s: &Scene, acc: &Accel, base: &HybridOpts) -> HybridCounts {
    let (g, opts) = (Golden::default(), TraceOpts::default());
    let mut sync = render_sync(s, acc, &g, opts, W, W, base);
    let mut t = HybridCounts::default();
    for seed in 1..=2u64 {
        for (name, order) in orders(s, acc, seed) {
            if seed > 1 && name != "shuffled" {
                continue;
            }
            let h = HybridOpts {
                order,
                ..base.clone()
            };
            if matches!(base.compare, Compare::LEqual | Compare::GEqual) {
                sync = render_sync(s, acc, &g, opts, W, W, &h);
            }
            for step in [0usize, 8] {
                let h = HybridOpts {
                    rays_per_step: step,
                    ..h.clone()
                };
                let (f, c) = render_async(s, acc, &g, opts, W, W, &h);
                let what = format!(
                    "{:?} {:?} {name} {seed} step {step}",
                    base.compare, base.mode
                );
                assert!(same(&f, &sync), "{what}: image differs");
                assert_eq!(c.lost, 0, "{what}: {c:?}");
                assert_eq!(c.used, sync.stats.total().rays, "{what}");
                assert_eq!(
                    c.emitted,
                    c.culled_tile + c.culled_depth + c.culled_generation + c.traced,
                    "{what}"
                );
                t.emitted += c.emitted;
                t.shaded += c.shaded;
                t.used += c.used;
                t.culled_tile += c.culled_tile;
                t.culled_depth += c.culled_depth;
                t.culled_generation += c.culled_generation;
                t.kept_translucent += c.kept_translucent;
            }
        }
    }
    t
}

/// Translucency: the rays of the opaque surface behind the translucent
/// block are kept while it is the front surface (their results are
/// blended), and culls still happen elsewhere. A unit that ignores the rule
/// (drop-farther forced to 1) culls rays the image needs: they are lost and
/// the image differs, so the floor below is what the rule must reach.
#[test]
fn translucent_surfaces_keep_their_rays_behind_and_the_image() {
    let (s, acc) = cornell();
    let t = every_order(&s, &acc, &HybridOpts::default());
    eprintln!("translucent: {t:?}");
    assert!(t.kept_translucent >= 1_000, "{t:?}");
    assert!(
        t.culled_tile + t.culled_depth + t.culled_generation >= 500,
        "{t:?}"
    );

    let (g, opts) = (Golden::default(), TraceOpts::default());
    let base = HybridOpts::default();
    let sync = render_sync(&s, &acc, &g, opts, W, W, &base);
    let cfg = base.unit_config(world_triangles(&s, &acc).len());
    let order = orders(&s, &acc, 1).remove(0).1;
    let h = HybridOpts {
        order,
        rays_per_step: 0,
        ..base
    };
    let (f, c) = render_async_with(&s, &acc, &g, opts, W, W, &h, &mut |x| {
        let mut x = x.clone();
        x.tile.drop_farther = true;
        for s in &mut x.slots {
            s.sample.drop_farther = true;
        }
        cull(&cfg, &x)
    });
    eprintln!("rule ignored: {c:?}");
    assert!(c.lost >= 100, "ignoring the rule loses needed rays: {c:?}");
    assert!(!same(&f, &sync), "ignoring the rule changes the image");
}

/// Partial renders (HSR over 16 or 256 primitives before shading) and
/// deferred shading: identical images; deferred shades only final surfaces
/// (nothing to cull, every emitted ray used); partial renders shade fewer
/// surfaces than immediate mode and still cull.
#[test]
fn partial_and_deferred_modes_are_identical() {
    let (s, acc) = cornell();
    let imm = every_order(&s, &acc, &HybridOpts::default());
    let def = every_order(
        &s,
        &acc,
        &HybridOpts {
            mode: Mode::Deferred,
            ..HybridOpts::default()
        },
    );
    eprintln!("immediate: {imm:?}\ndeferred: {def:?}");
    assert_eq!(def.emitted, def.used, "deferred emits only final rays");
    assert_eq!(
        def.culled_tile + def.culled_depth + def.culled_generation,
        0
    );
    for n in [16, 256] {
        let p = every_order(
            &s,
            &acc,
            &HybridOpts {
                mode: Mode::Partial(n),
                ..HybridOpts::default()
            },
        );
        eprintln!("partial:{n}: {p:?}");
        assert!(
            p.shaded < imm.shaded && p.shaded > def.shaded,
            "partial:{n}: {p:?}"
        );
        assert!(
            p.culled_tile + p.culled_depth + p.culled_generation >= 100,
            "partial:{n}: {p:?}"
        );
    }
}

/// Reversed depth (1 at near): `greater` and `gequal` in every order, each
/// with culls; unorm16 so that equal codes (ties) are common.
#[test]
fn reversed_depth_is_identical() {
    let (s, acc) = cornell();
    for compare in [Compare::Greater, Compare::GEqual] {
        let t = every_order(
            &s,
            &acc,
            &HybridOpts {
                compare,
                depth: DepthFormat::Unorm16,
                ..HybridOpts::default()
            },
        );
        eprintln!("{compare:?}: {t:?}");
        assert!(
            t.culled_tile + t.culled_depth + t.culled_generation >= 500,
            "{compare:?}: {t:?}"
        );
    }
}
