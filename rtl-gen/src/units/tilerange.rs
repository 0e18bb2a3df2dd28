//! `tilerange`: a tile's depth range for seed 002's ray culling
//! (US 10,068,367 B2 claim 1: "update the depth range for the tile", issue
//! 38): the smallest and largest depth code over the tile's samples and
//! whether every sample's surface is opaque, the `tile_min`, `tile_max` and
//! `tile_drop_farther` inputs of `raycull`. Bit-exact twin of
//! `golden_model::raycull::tile_range`; spec in `docs/raycull.md` §3.
//!
//! It reads the tile's sample depths (the depth buffer the raster writes)
//! and reduces them in a balanced tree of pairwise min/max (`log2 N`
//! comparator levels): after a write the range is recomputed, because a
//! sample that gets closer can lower the far end, which no update from the
//! written depth alone can tell. Codes are compared as unsigned integers in
//! every format (a valid binary32 code is non-negative, so its bits order
//! as its value); a bad binary32 code is carried, `raycull` flags it.
//! Pipeline registers are placed by the delay model
//! ([`crate::retime::balance`]).

use super::ports::{self, Record, Visit, Walk};
use super::raycull::Depth;
use super::Description;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `tilerange` unit.
pub struct TileRange;

crate::params! {
    /// The tile-range unit's parameters.
    pub struct TileRangeParams {
        /// depth code format: unorm16, unorm24 or binary32
        depth: Depth = Depth::Unorm24,
        /// samples per tile (8x8 tile: 64)
        samples: u32 [1..=64] = 64,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=4] = 1,
    }
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// depth format
    pub depth: Depth,
    /// samples N
    pub samples: u32,
    /// pipeline registers
    pub stages: u32,
}

impl Config {
    fn depth_ty(&self) -> Ty {
        Ty::UInt(match self.depth {
            Depth::Unorm16 => 16,
            Depth::Unorm24 => 24,
            Depth::Binary32 => 32,
        })
    }
}

/// The inputs: per sample `i` `sample{i}_depth` and `sample{i}_drop_farther`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TileRangeIn<T> {
    /// per sample: its current depth code
    pub depth: Vec<T>,
    /// per sample: its surface is opaque
    pub drop_farther: Vec<T>,
}

impl<T: Copy> Record<T> for TileRangeIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let d = cfg.depth_ty();
        let mut x = TileRangeIn {
            depth: Vec::new(),
            drop_farther: Vec::new(),
        };
        for i in 0..cfg.samples as usize {
            x.depth
                .push(w.one(format_args!("sample{i}_depth"), d, move |r| r.depth[i]));
            x.drop_farther.push(w.one(
                format_args!("sample{i}_drop_farther"),
                Ty::Bool,
                move |r| r.drop_farther[i],
            ));
        }
        x
    }
}

/// The outputs: `tile_min`, `tile_max`, `tile_drop_farther` (`raycull`'s
/// tile inputs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TileRangeOut<T> {
    /// the smallest code
    pub tile_min: T,
    /// the largest code
    pub tile_max: T,
    /// every sample is opaque
    pub tile_drop_farther: T,
}

impl<T: Copy> Record<T> for TileRangeOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let d = cfg.depth_ty();
        TileRangeOut {
            tile_min: w.one("tile_min", d, |r| r.tile_min),
            tile_max: w.one("tile_max", d, |r| r.tile_max),
            tile_drop_farther: w.one("tile_drop_farther", Ty::Bool, |r| r.tile_drop_farther),
        }
    }
}

/// Module name: `tilerange_{u16|u24|f32}_n{samples}_s{stages}`.
pub fn tilerange_name(cfg: &Config) -> String {
    let d = match cfg.depth {
        Depth::Unorm16 => "u16",
        Depth::Unorm24 => "u24",
        Depth::Binary32 => "f32",
    };
    format!("tilerange_{d}_n{}_s{}", cfg.samples, cfg.stages)
}

/// Builds `tilerange` for a configuration.
pub fn build(cfg: &Config) -> Module {
    let mut m = ModuleBuilder::with_handshake(tilerange_name(cfg));
    m.describe(
        "Seed 002 tile depth range: min and max depth code over the tile's samples, all samples opaque.",
    );
    let x: TileRangeIn<Sig> = ports::declare_inputs(&mut m, cfg);
    // (min, max, all opaque) of each subtree; a level pairs neighbours and
    // passes an odd last one up unchanged
    let mut level: Vec<(Sig, Sig, Sig)> = (0..x.depth.len())
        .map(|i| (x.depth[i], x.depth[i], x.drop_farther[i]))
        .collect();
    let mut l = 0;
    while level.len() > 1 {
        l += 1;
        let mut next = Vec::with_capacity(level.len().div_ceil(2));
        for (j, pair) in level.chunks(2).enumerate() {
            let [a, b] = pair else {
                next.push(pair[0]);
                continue;
            };
            next.push(m.scope(&format!("level{l}_pair{j}"), |m| {
                let b_lower = m.lt(b.0, a.0);
                let lo = m.mux(b_lower, b.0, a.0);
                let b_higher = m.gt(b.1, a.1);
                let hi = m.mux(b_higher, b.1, a.1);
                let opaque = m.and(a.2, b.2);
                (
                    m.name(lo, "min"),
                    m.name(hi, "max"),
                    m.name(opaque, "opaque"),
                )
            }));
        }
        level = next;
    }
    let (lo, hi, opaque) = level[0];
    let out = TileRangeOut {
        tile_min: lo,
        tile_max: hi,
        tile_drop_farther: opaque,
    };
    ports::declare_outputs(&mut m, cfg, &out);
    let datapath = m.finish().expect("tilerange datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance(&datapath, cfg.stages)
        .expect("the tilerange datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

impl Description for TileRange {
    type Params = TileRangeParams;
    type Config = Config;
    const NAME: &'static str = "tilerange";
    const SUMMARY: &'static str =
        "seed 002 tile depth range: min/max depth code and all-opaque over a tile's samples";
    fn config(&self, p: &TileRangeParams) -> Result<Config, ParamError> {
        Ok(Config {
            depth: p.depth,
            samples: p.samples,
            stages: p.stages,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamSet;

    /// Each level of the reduction tree names its pairs by its own number
    /// (`level1_pair0` ... `level3_pair0` for 8 samples), so the Verilog says
    /// where in the tree a wire is.
    #[test]
    fn every_level_of_the_tree_has_its_own_name() {
        let p = TileRangeParams {
            samples: 8,
            stages: 0,
            ..TileRangeParams::defaults()
        };
        let cfg = TileRange.config(&p).expect("a valid tilerange");
        let files = crate::emit::emit(&build(&cfg), "test");
        let text: String = files.iter().map(|f| f.text.as_str()).collect();
        for name in ["level1_pair3", "level2_pair1", "level3_pair0"] {
            assert!(text.contains(name), "no {name} in the emitted Verilog");
        }
        assert!(!text.contains("level0_"), "a level numbered 0");
    }
}
