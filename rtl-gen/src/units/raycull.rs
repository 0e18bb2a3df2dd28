//! `raycull`: seed 002's depth-based ray culling and contribution check
//! (issue 38, `docs/raycull.md`), bit-exact with
//! `golden_model::raycull::cull`.
//!
//! One transaction: the tile's range `[tile_min, tile_max]` and its
//! drop-farther bit, the culling switch `enable`, and `G` slots, each a ray
//! tag (emitting depth, generation, primitive id) and its sample's state
//! (depth, generation, primitive id, drop-farther). Per slot: the tile stage
//! (ray depth beyond the tile's far end), the sample stage (sample closer, or
//! equal depth and another generation), the contribution check (same
//! primitive and generation) and the bad-depth flag (binary32 codes above
//! 1.0: NaN, negative, beyond far; unorm codes are all valid, so no logic is
//! built for them); for the group, its depth range against the tile's.
//! Depth codes compare as unsigned integers in every format. `stages`
//! registers are placed by the delay model ([`crate::retime::balance`]).

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `raycull` unit.
pub struct RayCull;

crate::choice! {
    /// The depth code format.
    pub enum Depth {
        /// 16-bit unsigned normalised
        Unorm16 = "unorm16",
        /// 24-bit unsigned normalised
        Unorm24 = "unorm24",
        /// IEEE binary32 in [+0, 1.0]
        Binary32 = "binary32",
    }
}

crate::choice! {
    /// The raster's depth compare mode.
    pub enum Compare {
        /// smaller code is closer
        Less = "less",
        /// smaller code is closer, equal replaces
        LEqual = "lequal",
        /// larger code is closer (reversed depth)
        Greater = "greater",
        /// larger code is closer, equal replaces
        GEqual = "gequal",
    }
}

crate::params! {
    /// The ray-cull unit's parameters.
    pub struct RayCullParams {
        /// depth code format: unorm16, unorm24 or binary32
        depth: Depth = Depth::Unorm24,
        /// compare mode (less, lequal: smaller is closer; greater, gequal: reversed depth)
        compare: Compare = Compare::Less,
        /// generation bits (FIG. 13/14: 3)
        gen_bits: u32 [1..=8] = 3,
        /// primitive id bits of the contribution check
        prim_bits: u32 [1..=32] = 20,
        /// rays per group G (claims 3-4: their depth range against the tile's)
        group: u32 [1..=8] = 4,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=4] = 1,
    }
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// depth format
    pub depth: Depth,
    /// compare mode
    pub compare: Compare,
    /// generation bits
    pub gen_bits: u32,
    /// primitive id bits
    pub prim_bits: u32,
    /// slots G
    pub group: u32,
    /// pipeline registers
    pub stages: u32,
}

impl Config {
    /// Bits of a depth code.
    pub fn depth_bits(&self) -> u32 {
        match self.depth {
            Depth::Unorm16 => 16,
            Depth::Unorm24 => 24,
            Depth::Binary32 => 32,
        }
    }
    /// The largest valid code (the far plane): `2^N − 1`, or 1.0.
    pub fn far_code(&self) -> u32 {
        match self.depth {
            Depth::Unorm16 => 0xFFFF,
            Depth::Unorm24 => 0xFF_FFFF,
            Depth::Binary32 => 0x3F80_0000,
        }
    }
    /// Larger codes are closer.
    pub fn reversed(&self) -> bool {
        matches!(self.compare, Compare::Greater | Compare::GEqual)
    }
    fn depth_ty(&self) -> Ty {
        Ty::UInt(self.depth_bits())
    }
}

/// The inputs: `enable`, `tile_min`, `tile_max`, `tile_drop_farther`, then
/// per slot `i` `slot{i}_valid`, `slot{i}_ray_depth`, `slot{i}_ray_gen`,
/// `slot{i}_ray_prim`, `slot{i}_sample_depth`, `slot{i}_sample_gen`,
/// `slot{i}_sample_prim`, `slot{i}_sample_drop_farther`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RayCullIn<T> {
    /// the culling switch
    pub enable: T,
    /// the tile's nearest-code end (smallest code)
    pub tile_min: T,
    /// the tile's largest code
    pub tile_max: T,
    /// every sample of the tile is opaque
    pub tile_drop_farther: T,
    /// per slot: holds a ray
    pub valid: Vec<T>,
    /// per slot: the ray's emitting depth
    pub ray_depth: Vec<T>,
    /// per slot: the ray's generation
    pub ray_gen: Vec<T>,
    /// per slot: the ray's primitive id
    pub ray_prim: Vec<T>,
    /// per slot: the sample's depth
    pub sample_depth: Vec<T>,
    /// per slot: the sample's generation
    pub sample_gen: Vec<T>,
    /// per slot: the sample's primitive id
    pub sample_prim: Vec<T>,
    /// per slot: the sample's surface is opaque
    pub sample_drop_farther: Vec<T>,
}

impl<T: Copy> Record<T> for RayCullIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let (d, g, p) = (
            cfg.depth_ty(),
            Ty::UInt(cfg.gen_bits),
            Ty::UInt(cfg.prim_bits),
        );
        let enable = w.one("enable", Ty::Bool, |r| r.enable);
        let tile_min = w.one("tile_min", d, |r| r.tile_min);
        let tile_max = w.one("tile_max", d, |r| r.tile_max);
        let tile_drop_farther = w.one("tile_drop_farther", Ty::Bool, |r| r.tile_drop_farther);
        let mut x = RayCullIn {
            enable,
            tile_min,
            tile_max,
            tile_drop_farther,
            valid: Vec::new(),
            ray_depth: Vec::new(),
            ray_gen: Vec::new(),
            ray_prim: Vec::new(),
            sample_depth: Vec::new(),
            sample_gen: Vec::new(),
            sample_prim: Vec::new(),
            sample_drop_farther: Vec::new(),
        };
        for i in 0..cfg.group as usize {
            x.valid
                .push(w.one(format_args!("slot{i}_valid"), Ty::Bool, move |r| r.valid[i]));
            x.ray_depth
                .push(w.one(format_args!("slot{i}_ray_depth"), d, move |r| {
                    r.ray_depth[i]
                }));
            x.ray_gen
                .push(w.one(format_args!("slot{i}_ray_gen"), g, move |r| r.ray_gen[i]));
            x.ray_prim
                .push(w.one(format_args!("slot{i}_ray_prim"), p, move |r| r.ray_prim[i]));
            x.sample_depth
                .push(w.one(format_args!("slot{i}_sample_depth"), d, move |r| {
                    r.sample_depth[i]
                }));
            x.sample_gen
                .push(w.one(format_args!("slot{i}_sample_gen"), g, move |r| {
                    r.sample_gen[i]
                }));
            x.sample_prim
                .push(w.one(format_args!("slot{i}_sample_prim"), p, move |r| {
                    r.sample_prim[i]
                }));
            x.sample_drop_farther.push(w.one(
                format_args!("slot{i}_sample_drop_farther"),
                Ty::Bool,
                move |r| r.sample_drop_farther[i],
            ));
        }
        x
    }
}

/// The outputs: `group_cull`, `group_bad` (binary32), then per slot
/// `slot{i}_tile_cull`, `slot{i}_depth_cull`, `slot{i}_generation_cull`,
/// `slot{i}_cull`, `slot{i}_current`, `slot{i}_bad` (binary32: a unorm code is
/// never bad, so the flags exist only for binary32).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RayCullOut<T> {
    /// the group's depth range is beyond the tile's far end
    pub group_cull: T,
    /// some valid slot has a bad depth code (binary32)
    pub group_bad: Option<T>,
    /// per slot: culled by the tile stage
    pub tile_cull: Vec<T>,
    /// per slot: culled by the sample depth
    pub depth_cull: Vec<T>,
    /// per slot: culled by the generation at equal depth
    pub generation_cull: Vec<T>,
    /// per slot: culled
    pub cull: Vec<T>,
    /// per slot: the contribution check passes
    pub current: Vec<T>,
    /// per slot: a depth code is bad (binary32)
    pub bad: Option<Vec<T>>,
}

impl<T: Copy> Record<T> for RayCullOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let group_cull = w.one("group_cull", Ty::Bool, |r| r.group_cull);
        let flags = cfg.depth == Depth::Binary32;
        let group_bad =
            flags.then(|| w.one("group_bad", Ty::Bool, |r| r.group_bad.expect("binary32")));
        let mut x = RayCullOut {
            group_cull,
            group_bad,
            tile_cull: Vec::new(),
            depth_cull: Vec::new(),
            generation_cull: Vec::new(),
            cull: Vec::new(),
            current: Vec::new(),
            bad: flags.then(Vec::new),
        };
        let b = Ty::Bool;
        for i in 0..cfg.group as usize {
            x.tile_cull
                .push(w.one(format_args!("slot{i}_tile_cull"), b, move |r| {
                    r.tile_cull[i]
                }));
            x.depth_cull
                .push(w.one(format_args!("slot{i}_depth_cull"), b, move |r| {
                    r.depth_cull[i]
                }));
            x.generation_cull
                .push(w.one(format_args!("slot{i}_generation_cull"), b, move |r| {
                    r.generation_cull[i]
                }));
            x.cull
                .push(w.one(format_args!("slot{i}_cull"), b, move |r| r.cull[i]));
            x.current
                .push(w.one(format_args!("slot{i}_current"), b, move |r| r.current[i]));
            if let Some(bad) = x.bad.as_mut() {
                bad.push(w.one(format_args!("slot{i}_bad"), b, move |r| {
                    r.bad.as_ref().expect("binary32")[i]
                }));
            }
        }
        x
    }
}

/// Module name: `raycull_{u16|u24|f32}_{less|lequal|greater|gequal}_g{gen}_p{prim}_x{G}_s{stages}`.
pub fn raycull_name(cfg: &Config) -> String {
    let d = match cfg.depth {
        Depth::Unorm16 => "u16",
        Depth::Unorm24 => "u24",
        Depth::Binary32 => "f32",
    };
    let c = match cfg.compare {
        Compare::Less => "less",
        Compare::LEqual => "lequal",
        Compare::Greater => "greater",
        Compare::GEqual => "gequal",
    };
    format!(
        "raycull_{d}_{c}_g{}_p{}_x{}_s{}",
        cfg.gen_bits, cfg.prim_bits, cfg.group, cfg.stages
    )
}

/// `code <= far` for binary32 (not NaN, not negative, not beyond 1.0); no
/// logic for unorm, whose every code is valid.
fn depth_ok(m: &mut ModuleBuilder, cfg: &Config, code: Sig, role: &str) -> Option<Sig> {
    if cfg.depth != Depth::Binary32 {
        return None;
    }
    let far = m.constant(cfg.depth_ty(), u128::from(cfg.far_code()));
    let ok = m.le(code, far);
    Some(m.name(ok, role))
}

/// `a` is strictly closer than `b`.
fn closer(m: &mut ModuleBuilder, cfg: &Config, a: Sig, b: Sig) -> Sig {
    if cfg.reversed() {
        m.gt(a, b)
    } else {
        m.lt(a, b)
    }
}

fn and_all(m: &mut ModuleBuilder, xs: &[Sig]) -> Sig {
    let mut acc = xs[0];
    for &x in &xs[1..] {
        acc = m.and(acc, x);
    }
    acc
}

fn or_all(m: &mut ModuleBuilder, xs: &[Sig]) -> Sig {
    let mut acc = xs[0];
    for &x in &xs[1..] {
        acc = m.or(acc, x);
    }
    acc
}

/// Builds `raycull` for a configuration.
pub fn build(cfg: &Config) -> Module {
    let mut m = ModuleBuilder::with_handshake(raycull_name(cfg));
    m.describe(
        "Seed 002 ray culling: tile depth range (per ray and per group), sample depth and generation, contribution check.",
    );
    let x: RayCullIn<Sig> = ports::declare_inputs(&mut m, cfg);
    let tile_ok = m.scope("tile", |m| {
        let lo = depth_ok(m, cfg, x.tile_min, "min_ok");
        let hi = depth_ok(m, cfg, x.tile_max, "max_ok");
        match (lo, hi) {
            (Some(lo), Some(hi)) => {
                let ok = m.and(lo, hi);
                Some(m.name(ok, "range_ok"))
            }
            _ => None,
        }
    });
    let n = cfg.group as usize;
    let mut out = RayCullOut {
        group_cull: x.enable,
        group_bad: None,
        tile_cull: Vec::new(),
        depth_cull: Vec::new(),
        generation_cull: Vec::new(),
        cull: Vec::new(),
        current: Vec::new(),
        bad: tile_ok.map(|_| Vec::new()),
    };
    // per slot: the depth the group range sees (an empty slot stands at the
    // code that never decides: all ones, or 0 when reversed)
    let mut group_depth = Vec::new();
    for i in 0..n {
        m.scope(&format!("slot{i}"), |m| {
            let valid = x.valid[i];
            let (rd, sd) = (x.ray_depth[i], x.sample_depth[i]);
            let ray_ok = depth_ok(m, cfg, rd, "ray_depth_ok");
            let sample_ok = depth_ok(m, cfg, sd, "sample_depth_ok");
            let bad = match (ray_ok, sample_ok, tile_ok) {
                (Some(r), Some(s), Some(t)) => {
                    let ok = and_all(m, &[r, s, t]);
                    let not_ok = m.not(ok);
                    let bad = m.and(valid, not_ok);
                    Some(m.name(bad, "is_bad"))
                }
                _ => None,
            };
            let mut may = vec![x.enable, valid];
            if let Some(bad) = bad {
                may.push(m.not(bad));
            }
            let may = and_all(m, &may);
            let may = m.name(may, "may_cull");
            let far_side = if cfg.reversed() {
                m.lt(rd, x.tile_min)
            } else {
                m.gt(rd, x.tile_max)
            };
            let far_side = m.name(far_side, "beyond_tile");
            let tile_cull = and_all(m, &[may, x.tile_drop_farther, far_side]);
            let tile_cull = m.name(tile_cull, "tile_culled");
            let kept = m.not(tile_cull);
            let sample_may = and_all(m, &[may, kept, x.sample_drop_farther[i]]);
            let sample_may = m.name(sample_may, "sample_may_cull");
            let nearer = closer(m, cfg, sd, rd);
            let nearer = m.name(nearer, "sample_closer");
            let depth_cull = m.and(sample_may, nearer);
            let depth_cull = m.name(depth_cull, "depth_culled");
            let same_depth = m.eq(sd, rd);
            let same_depth = m.name(same_depth, "same_depth");
            let other_gen = m.ne(x.sample_gen[i], x.ray_gen[i]);
            let other_gen = m.name(other_gen, "other_generation");
            let generation_cull = and_all(m, &[sample_may, same_depth, other_gen]);
            let generation_cull = m.name(generation_cull, "generation_culled");
            let cull = or_all(m, &[tile_cull, depth_cull, generation_cull]);
            let cull = m.name(cull, "culled");
            let same_prim = m.eq(x.sample_prim[i], x.ray_prim[i]);
            let same_prim = m.name(same_prim, "same_prim");
            let same_gen = m.not(other_gen);
            let current = and_all(m, &[valid, same_prim, same_gen]);
            let current = m.name(current, "is_current");
            let idle = if cfg.reversed() { 0 } else { u128::MAX };
            let idle = m.constant(cfg.depth_ty(), idle & ((1u128 << cfg.depth_bits()) - 1));
            let gd = m.mux(valid, rd, idle);
            group_depth.push(m.name(gd, "group_depth"));
            out.tile_cull.push(tile_cull);
            out.depth_cull.push(depth_cull);
            out.generation_cull.push(generation_cull);
            out.cull.push(cull);
            out.current.push(current);
            if let (Some(all), Some(bad)) = (out.bad.as_mut(), bad) {
                all.push(bad);
            }
        });
    }
    m.scope("group", |m| {
        let mut edge = group_depth[0];
        for &d in &group_depth[1..] {
            let take = if cfg.reversed() {
                m.gt(d, edge)
            } else {
                m.lt(d, edge)
            };
            edge = m.mux(take, d, edge);
        }
        let edge = m.name(edge, "near_end");
        let outside = if cfg.reversed() {
            m.lt(edge, x.tile_min)
        } else {
            m.gt(edge, x.tile_max)
        };
        let outside = m.name(outside, "beyond_tile");
        let any_valid = or_all(m, &x.valid);
        let any_valid = m.name(any_valid, "any_valid");
        let mut terms = vec![x.enable, x.tile_drop_farther, any_valid, outside];
        if let Some(bad) = out.bad.as_ref() {
            let bad = or_all(m, bad);
            let bad = m.name(bad, "any_bad");
            terms.push(m.not(bad));
            out.group_bad = Some(bad);
        }
        let cull = and_all(m, &terms);
        out.group_cull = m.name(cull, "culled");
    });
    ports::declare_outputs(&mut m, cfg, &out);
    let datapath = m.finish().expect("raycull datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance(&datapath, cfg.stages)
        .expect("the raycull datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

impl Description for RayCull {
    type Params = RayCullParams;
    type Config = Config;
    const NAME: &'static str = "raycull";
    const SUMMARY: &'static str =
        "seed 002 ray culling: tile/group depth range, sample depth and generation, contribution check";
    fn config(&self, p: &RayCullParams) -> Result<Config, ParamError> {
        Ok(Config {
            depth: p.depth,
            compare: p.compare,
            gen_bits: p.gen_bits,
            prim_bits: p.prim_bits,
            group: p.group,
            stages: p.stages,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}
