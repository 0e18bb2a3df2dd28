//! Stimulus and golden-model adapter for `tilerange`, the tile depth range
//! of seed 002's ray culling (`golden_model::raycull::tile_range`).

use super::raycull::depth_code;
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::raycull::{self as model, SampleState};
use rtl_gen::units::ports;
use rtl_gen::units::raycull::Depth;
use rtl_gen::units::tilerange::{Config, TileRangeIn, TileRangeOut};

/// Vectors: first, for each sample position, every sample at one code of
/// {0, the middle, far} but that position at a code below or above it (so
/// each position is the min and the max once, and ties are everywhere);
/// then seeded random vectors whose codes come mostly from a handful of
/// values (equal codes common; binary32 bad codes too), half with every
/// sample opaque and half with some translucent ones.
pub struct TileRangeBench {
    unit: Config,
    format: model::DepthFormat,
}

impl TileRangeBench {
    /// The testbench of a `tilerange` configuration.
    pub fn new(u: &Config) -> Self {
        TileRangeBench {
            unit: *u,
            format: match u.depth {
                Depth::Unorm16 => model::DepthFormat::Unorm16,
                Depth::Unorm24 => model::DepthFormat::Unorm24,
                Depth::Binary32 => model::DepthFormat::Binary32,
            },
        }
    }
}

impl sim::Golden for TileRangeBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let r: TileRangeIn<u64> = ports::unpack(&self.unit, inputs);
        let samples: Vec<SampleState> = r
            .depth
            .iter()
            .zip(&r.drop_farther)
            .map(|(&d, &o)| SampleState {
                depth: d as u32,
                drop_farther: o != 0,
                ..SampleState::default()
            })
            .collect();
        let t = model::tile_range(&samples);
        let out = TileRangeOut {
            tile_min: u64::from(t.min),
            tile_max: u64::from(t.max),
            tile_drop_farther: t.drop_farther as u64,
        };
        ports::pack(&self.unit, &out, outputs)
    }
}

impl sim::Stimulus for TileRangeBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let n = self.unit.samples as usize;
        let far = self.format.far_code();
        let mut x = TileRangeIn {
            depth: vec![0u64; n],
            drop_farther: vec![1u64; n],
        };
        if index < 6 * n as u64 {
            let (pos, case) = ((index / 6) as usize, index % 6);
            let base = [0, far / 2, far][(case / 2) as usize];
            let field_max = (u64::MAX >> (64 - self.format.bits())) as u32;
            let odd = if case % 2 == 0 {
                base.saturating_sub(1)
            } else {
                base.saturating_add(1).min(field_max)
            };
            x.depth.fill(u64::from(base));
            x.depth[pos] = u64::from(odd);
            x.drop_farther[pos] = (case / 2 != 1) as u64;
            return ports::pack(&self.unit, &x, v);
        }
        let mut rng = VectorRng::new(seed, index);
        let some_translucent = rng.below(2) == 0;
        for i in 0..n {
            x.depth[i] = u64::from(depth_code(self.format, &mut rng));
            x.drop_farther[i] = !(some_translucent && rng.below(16) == 0) as u64;
        }
        ports::pack(&self.unit, &x, v)
    }
}

impl Testbench for TileRangeBench {}
