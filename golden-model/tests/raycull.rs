//! `golden_model::raycull` against a reference that recomputes visibility
//! from scratch (issue 38): every fragment ever rasterised into a tile is
//! kept; the visible surface of a sample is the winner of all of them under
//! the compare mode, computed anew for every question. A cull is false when
//! the ray's own fragment is that winner, or when the winner is translucent;
//! the contribution check must say "current" exactly when the ray's fragment
//! is the winner (never a stale result, never a rejected current one).
//!
//! Adversarial episodes: tiles of 1-8 samples, depths drawn mostly from a
//! handful of codes (0, 1, the far code and its neighbours, one middle
//! value) so equal depths, range ends and ties are the common case; 1- and
//! 3-bit generations so they wrap; some translucent surfaces; the switch off
//! in some episodes; all formats and compare modes, groups of 1-4.
//! Floors make sure each stage acts: a change that disables the tile stage,
//! group culling, generation culls or the contribution check fails here.

use golden_model::raycull::{
    cull, Compare, Config, CullIn, DepthFormat, RayTag, SampleState, Slot, TileBuffer, TileRange,
};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// A fragment of the history.
#[derive(Clone, Copy)]
struct Frag {
    sample: usize,
    depth: u32,
    prim: u32,
    translucent: bool,
}

/// A ray: the history index of its emitting fragment and its tag.
#[derive(Clone, Copy)]
struct Ray {
    frag: usize,
    sample: usize,
    tag: RayTag,
}

/// The visible fragment of a sample, recomputed from every fragment
/// rasterised into it (in order).
fn visible(cmp: Compare, history: &[Frag], sample: usize) -> Option<usize> {
    let mut best: Option<usize> = None;
    for (i, f) in history.iter().enumerate() {
        if f.sample != sample {
            continue;
        }
        let wins = match best {
            None => true,
            Some(b) => {
                let b = history[b];
                let nearer = if matches!(cmp, Compare::Greater | Compare::GEqual) {
                    f.depth > b.depth
                } else {
                    f.depth < b.depth
                };
                let tie = f.depth == b.depth;
                match cmp {
                    Compare::Less | Compare::Greater => nearer || (tie && f.prim < b.prim),
                    Compare::LEqual | Compare::GEqual => nearer || tie,
                }
            }
        };
        if wins {
            best = Some(i);
        }
    }
    best
}

#[derive(Default, Debug)]
struct Counts {
    slots: u64,
    tile: u64,
    depth: u64,
    generation: u64,
    group: u64,
    stale: u64,
    /// stale, not culled, caught by the contribution check
    discarded: u64,
    /// of those, the generation had wrapped to the ray's
    discarded_wrapped: u64,
    current: u64,
    bad: u64,
}

fn depth_pool(f: DepthFormat, rng: &mut Rng) -> u32 {
    let far = f.far_code();
    let mid = match f {
        DepthFormat::Binary32 => 0.5f32.to_bits(),
        _ => far / 2,
    };
    match rng.below(10) {
        0 => 0,
        1 => 1,
        2 => far - 1,
        3 => far,
        4 | 5 => mid,
        6 => mid + 1,
        7 => mid - 1,
        _ => rng.below(far as u64 + 1) as u32,
    }
}

fn bad_code(f: DepthFormat, rng: &mut Rng) -> Option<u32> {
    match f {
        DepthFormat::Binary32 => Some(
            [
                f32::NAN.to_bits(),
                (-0.0f32).to_bits(),
                (-0.25f32).to_bits(),
                1.0000001f32.to_bits(),
                f32::INFINITY.to_bits(),
            ][rng.below(5) as usize],
        ),
        _ => Some(f.far_code() + 1 + rng.below(3) as u32),
    }
}

fn episode(cfg: &Config, rng: &mut Rng, c: &mut Counts) {
    let n = [1usize, 2, 4, 8][rng.below(4) as usize];
    let mut buf = TileBuffer::new(*cfg, n);
    let mut history: Vec<Frag> = Vec::new();
    let mut rays: Vec<Ray> = Vec::new();
    let enable = rng.below(8) != 0;
    let translucency = rng.below(4) == 0;
    // unique primitive ids in a random order, so ties go either way; or a
    // staircase: one depth, ids decreasing, so every write replaces the
    // surface at equal depth in every mode and the generation wraps
    let staircase = rng.below(4) == 0;
    let stair_depth = depth_pool(cfg.format, rng);
    let (prim_step, mut prim) = if staircase {
        (0xFFFF - 2 * rng.below(8) as u32, 0xFFF0)
    } else {
        (2 * rng.below(1 << 14) as u32 + 1, rng.below(1 << 16) as u32)
    };
    for _ in 0..48 {
        if rng.below(5) < 3 || rays.is_empty() {
            let sample = rng.below(n as u64) as usize;
            let depth = if staircase {
                stair_depth
            } else {
                depth_pool(cfg.format, rng)
            };
            let translucent = translucency && rng.below(3) == 0;
            prim = prim.wrapping_add(prim_step) & 0xFFFF;
            history.push(Frag {
                sample,
                depth,
                prim,
                translucent,
            });
            let written = buf
                .write(sample, depth, prim, translucent)
                .expect("a valid fragment");
            assert_eq!(
                written.is_some(),
                visible(cfg.compare, &history, sample) == Some(history.len() - 1),
                "the buffer's depth test is the reference's"
            );
            if let Some(gen) = written {
                for _ in 0..1 + rng.below(2) {
                    rays.push(Ray {
                        frag: history.len() - 1,
                        sample,
                        tag: RayTag { depth, gen, prim },
                    });
                }
            }
            continue;
        }
        // a question: G slots from this tile, some empty, some bad
        let mut slots = vec![Slot::default(); cfg.group];
        let mut which = vec![None; cfg.group];
        for (k, s) in slots.iter_mut().enumerate() {
            if rng.below(6) == 0 {
                continue;
            }
            let r = rays[rng.below(rays.len() as u64) as usize];
            let st = buf.samples[r.sample].state;
            *s = Slot {
                valid: true,
                ray: r.tag,
                sample: st,
            };
            if rng.below(64) == 0 {
                s.ray.depth = bad_code(cfg.format, rng).unwrap();
                c.bad += 1;
            }
            which[k] = Some(r);
        }
        let tile: TileRange = buf.range;
        let out = cull(
            cfg,
            &CullIn {
                enable,
                tile,
                slots: slots.clone(),
            },
        );
        let mut all_tile = slots.iter().any(|s| s.valid);
        for (k, r) in which.iter().enumerate() {
            let v = out.slots[k];
            let Some(r) = r else {
                assert_eq!(v, Default::default(), "an empty slot says nothing");
                continue;
            };
            c.slots += 1;
            all_tile &= v.tile_cull;
            let vis = visible(cfg.compare, &history, r.sample).expect("a ray's sample is covered");
            let is_current = vis == r.frag;
            let may_cull = !is_current && !history[vis].translucent;
            assert!(
                !v.cull || may_cull,
                "false cull: {cfg:?} slot {k} {:?} sample {:?} tile {tile:?} -> {v:?}",
                slots[k].ray,
                slots[k].sample
            );
            assert!(!v.cull || enable, "culled with the switch off");
            assert!(!v.cull || !v.bad, "a bad slot culled");
            assert_eq!(
                v.current,
                is_current,
                "contribution check: {cfg:?} {r:?}",
                r = r.tag
            );
            assert_eq!(v.cull, v.tile_cull || v.depth_cull || v.generation_cull);
            c.tile += v.tile_cull as u64;
            c.depth += v.depth_cull as u64;
            c.generation += v.generation_cull as u64;
            c.current += is_current as u64;
            if !is_current {
                c.stale += 1;
                if !v.cull {
                    c.discarded += 1;
                    if slots[k].sample.gen == r.tag.gen {
                        c.discarded_wrapped += 1;
                    }
                }
            }
        }
        assert_eq!(out.group_cull, all_tile, "group range = every slot outside");
        c.group += out.group_cull as u64;
    }
}

fn run(cfg: Config, episodes: u64, seed: u64) -> Counts {
    let mut rng = Rng(seed);
    let mut c = Counts::default();
    for _ in 0..episodes {
        episode(&cfg, &mut rng, &mut c);
    }
    c
}

const FORMATS: [DepthFormat; 3] = [
    DepthFormat::Unorm16,
    DepthFormat::Unorm24,
    DepthFormat::Binary32,
];
const MODES: [Compare; 4] = [
    Compare::Less,
    Compare::LEqual,
    Compare::Greater,
    Compare::GEqual,
];

/// 0 false culls, exact contribution checks, on at least 10^6 slots; every
/// stage acts in every format and mode.
#[test]
fn no_false_cull_against_a_from_scratch_reference() {
    let mut total = 0;
    for (fi, &format) in FORMATS.iter().enumerate() {
        for (mi, &compare) in MODES.iter().enumerate() {
            for (gi, &gen_bits) in [1u32, 3].iter().enumerate() {
                let cfg = Config {
                    format,
                    compare,
                    gen_bits,
                    prim_bits: 16,
                    group: 1 + (fi + mi + gi) % 4,
                };
                let c = run(cfg, 2_600, (fi * 8 + mi * 2 + gi) as u64);
                eprintln!(
                    "{format:?} {compare:?} gen {gen_bits} G {}: {c:?}",
                    cfg.group
                );
                total += c.slots;
                let floor = c.slots / 200;
                assert!(c.tile > floor, "tile stage culls: {c:?}");
                assert!(c.depth > floor, "sample depth culls: {c:?}");
                assert!(c.generation > floor, "generation culls: {c:?}");
                assert!(c.discarded > floor, "contribution-check discards: {c:?}");
                assert!(c.discarded_wrapped > 0, "wrapped generations caught: {c:?}");
                assert!(c.bad > 0);
                if cfg.group > 1 {
                    assert!(c.group > c.slots / 2000, "group culls: {c:?}");
                }
            }
        }
    }
    eprintln!("{total} slots checked");
    assert!(total >= 1_000_000, "{total} slots");
}

/// With the switch off nothing is culled, and the contribution check alone
/// still gives every current result and no stale one.
#[test]
fn the_switch_turns_culling_off() {
    let cfg = Config {
        format: DepthFormat::Unorm16,
        compare: Compare::Less,
        gen_bits: 3,
        prim_bits: 16,
        group: 2,
    };
    let s = Slot {
        valid: true,
        ray: RayTag {
            depth: 10,
            gen: 1,
            prim: 1,
        },
        sample: SampleState {
            depth: 5,
            gen: 2,
            prim: 2,
            drop_farther: true,
        },
    };
    let tile = TileRange {
        min: 5,
        max: 5,
        drop_farther: true,
    };
    for enable in [true, false] {
        let o = cull(
            &cfg,
            &CullIn {
                enable,
                tile,
                slots: vec![s, s],
            },
        );
        assert_eq!(o.group_cull, enable);
        assert_eq!(o.slots[0].tile_cull, enable);
        assert!(!o.slots[0].current);
    }
    // translucent tile and sample: kept, whatever the depths
    let mut t = s;
    t.sample.drop_farther = false;
    let o = cull(
        &cfg,
        &CullIn {
            enable: true,
            tile: TileRange {
                drop_farther: false,
                ..tile
            },
            slots: vec![t, t],
        },
    );
    assert!(!o.group_cull && !o.slots[0].cull);
}
