//! Stimulus and golden-model adapter for `node_sort`, the node tester's
//! sort network (`golden_model::node::sort`).

use super::stimulus::{mask, VectorRng};
use super::Testbench;
use golden_model::float::FloatFormat;
use golden_model::node::{sort, NodeParams, SlotOut};
use rtl_gen::units::node_sort::{Config, NodeSortIn, NodeSortOut};
use rtl_gen::units::ports;

/// Vectors: first every hit pattern with every slot's entry at 0 (all ties,
/// the model's bad-input output) and at the largest hit entry `2^K`; then
/// seeded random vectors of the shapes the node tester sends (misses with
/// the sentinel, hits with entries in `0..=2^K`, many ties from a small
/// entry range) and arbitrary ones (a miss with any entry, which the model
/// orders by entry too).
pub struct NodeSortBench {
    unit: Config,
    /// the model's miss sentinel, all ones in `K + 1` bits
    miss_entry: u64,
}

impl NodeSortBench {
    /// The testbench of a `node_sort` configuration.
    pub fn new(u: &Config) -> Self {
        let p = NodeParams::new(FloatFormat::BINARY32, u.children as usize, u.box_bits)
            .expect("node_sort accepts only configurations of the model");
        let miss_entry = u64::from(p.miss_entry());
        assert_eq!(
            miss_entry,
            mask(u.entry_bits()),
            "the entry width is the model's"
        );
        NodeSortBench {
            unit: *u,
            miss_entry,
        }
    }

    fn corner_count(&self) -> u64 {
        2 << self.unit.children
    }

    fn slots(&self, f: impl FnMut(usize) -> (bool, u64)) -> NodeSortIn<u64> {
        let (hit, entry) = (0..self.unit.children as usize)
            .map(f)
            .map(|(h, e)| (h as u64, e))
            .unzip();
        NodeSortIn { hit, entry }
    }
}

impl sim::Golden for NodeSortBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let r: NodeSortIn<u64> = ports::unpack(&self.unit, inputs);
        let mut slots: Vec<SlotOut> = (0..self.unit.children as usize)
            .map(|i| SlotOut {
                hit: r.hit[i] != 0,
                entry: r.entry[i] as u32,
                child: i as u8,
            })
            .collect();
        sort(&mut slots);
        let out = NodeSortOut {
            hit: slots.iter().map(|s| s.hit as u64).collect(),
            entry: slots.iter().map(|s| u64::from(s.entry)).collect(),
            child: slots.iter().map(|s| u64::from(s.child)).collect(),
        };
        ports::pack(&self.unit, &out, outputs)
    }
}

impl sim::Stimulus for NodeSortBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let top = 1u64 << (self.unit.box_bits + 4);
        let miss = self.miss_entry;
        if index < self.corner_count() {
            let pattern = index >> 1;
            let e = if index & 1 == 0 { 0 } else { top };
            let r = self.slots(|i| {
                let h = pattern >> i & 1 == 1;
                (h, if h { e } else { miss })
            });
            return ports::pack(&self.unit, &r, v);
        }
        let mut rng = VectorRng::new(seed, index);
        let shape = rng.below(8);
        let range = match rng.below(4) {
            0 => 4,
            1 => 16,
            _ => top + 1,
        };
        let r = self.slots(|_| {
            let h = rng.below(4) != 0;
            match shape {
                // arbitrary: any hit bit with any entry
                0 => (h, rng.bits(self.unit.entry_bits())),
                // the node tester's shape: hits in 0..=2^K, misses with the sentinel
                _ => (h, if h { rng.below(range) } else { miss }),
            }
        });
        ports::pack(&self.unit, &r, v)
    }
}

impl Testbench for NodeSortBench {}
