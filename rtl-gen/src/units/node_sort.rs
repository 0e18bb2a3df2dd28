//! `node_sort`: the sort network of the node tester (`docs/node.md` §1,
//! issue 36 step 2), bit-exact with `golden_model::node::sort`.
//!
//! Inputs per slot `i` (in slot order): `hit`, `entry` (`K + 1` bits,
//! `K = q + 4`, the model's default grid). Outputs per position: `hit`,
//! `entry`, `child` (the slot index, `log2 N` bits), sorted by the key
//! `(miss, entry, child)` ascending: hits first, smaller entry first, ties
//! by slot index. The key holds the slot index, so every key is distinct
//! and Batcher's odd-even merge network (1, 5, 19 comparators at N = 2, 4,
//! 8) gives the one sorted order whatever its comparator order. A
//! comparator is one `<` on a `K + 3 + log2 N`-bit key and two
//! multiplexers. `stages` registers are placed by the delay model
//! ([`crate::retime::balance`]).

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `node_sort` unit.
pub struct NodeSort;

crate::params! {
    /// The node sort network's parameters.
    pub struct NodeSortParams {
        /// child slots per node N: 2, 4 or 8
        children: u32 [2..=8] = 4,
        /// bits per box integer q (the entry has q + 5 bits: the model's grid K = q + 4)
        box_bits: u32 [4..=16] = 8,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=4] = 1,
    }
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// slots N (2, 4 or 8)
    pub children: u32,
    /// box integer bits q
    pub box_bits: u32,
    /// pipeline registers
    pub stages: u32,
}

impl Config {
    /// Bits of an entry: `K + 1` with the grid `K = q + 4`.
    pub fn entry_bits(&self) -> u32 {
        self.box_bits + 5
    }
    /// Bits of a slot index: `log2 N`.
    pub fn index_bits(&self) -> u32 {
        self.children.trailing_zeros()
    }
}

/// The inputs: per slot in slot order `slot{i}_hit`, `slot{i}_entry`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeSortIn<T> {
    /// per slot: the child's box test hit
    pub hit: Vec<T>,
    /// per slot: the entry in grid steps (the miss sentinel on a miss)
    pub entry: Vec<T>,
}

impl<T: Copy> Record<T> for NodeSortIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let entry_ty = Ty::UInt(cfg.entry_bits());
        let (mut hit, mut entry) = (Vec::new(), Vec::new());
        for i in 0..cfg.children as usize {
            hit.push(w.one(format_args!("slot{i}_hit"), Ty::Bool, move |r| r.hit[i]));
            entry.push(w.one(format_args!("slot{i}_entry"), entry_ty, move |r| r.entry[i]));
        }
        NodeSortIn { hit, entry }
    }
}

/// The outputs: per sorted position `j` `out{j}_hit`, `out{j}_entry`,
/// `out{j}_child`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeSortOut<T> {
    /// per position: hit
    pub hit: Vec<T>,
    /// per position: entry
    pub entry: Vec<T>,
    /// per position: the slot index
    pub child: Vec<T>,
}

impl<T: Copy> Record<T> for NodeSortOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let (entry_ty, index_ty) = (Ty::UInt(cfg.entry_bits()), Ty::UInt(cfg.index_bits()));
        let (mut hit, mut entry, mut child) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..cfg.children as usize {
            hit.push(w.one(format_args!("out{j}_hit"), Ty::Bool, move |r| r.hit[j]));
            entry.push(w.one(format_args!("out{j}_entry"), entry_ty, move |r| r.entry[j]));
            child.push(w.one(format_args!("out{j}_child"), index_ty, move |r| r.child[j]));
        }
        NodeSortOut { hit, entry, child }
    }
}

/// Module name: `node_sort_n{N}_q{q}_s{stages}`.
pub fn node_sort_name(cfg: &Config) -> String {
    format!(
        "node_sort_n{}_q{}_s{}",
        cfg.children, cfg.box_bits, cfg.stages
    )
}

/// Batcher's odd-even merge sort network for `n` (a power of two) inputs:
/// the comparators `(a, b)`, `a < b`, in layer order (Knuth 5.3.4).
pub fn batcher_network(n: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut p = 1;
    while p < n {
        let mut k = p;
        while k >= 1 {
            for j in (k % p..n - k).step_by(2 * k) {
                for i in 0..k.min(n - j - k) {
                    if (i + j) / (2 * p) == (i + j + k) / (2 * p) {
                        out.push((i + j, i + j + k));
                    }
                }
            }
            k /= 2;
        }
        p *= 2;
    }
    out
}

/// The slots `(hit[i], entry[i])` (entries of one width) in sorted order,
/// with their slot indices: the network of [`build`], also the last step of
/// the `node` unit.
pub fn sort_slots(m: &mut ModuleBuilder, hit: &[Sig], entry: &[Sig]) -> NodeSortOut<Sig> {
    let n = hit.len();
    let (eb, ib) = (entry[0].width(), n.trailing_zeros());
    // key = {miss, entry, index}: distinct keys, ascending is the model's order
    let mut keys: Vec<Sig> = (0..n)
        .map(|i| {
            m.scope(&format!("slot{i}"), |m| {
                let miss = m.not(hit[i]);
                let index = m.constant(Ty::UInt(ib), i as u128);
                let key = m.cat(&[miss, entry[i], index]);
                m.name(key, "key")
            })
        })
        .collect();
    for (a, b) in batcher_network(n) {
        let (ka, kb) = (keys[a], keys[b]);
        let (lo, hi) = m.scope(&format!("cmp{a}{b}"), |m| {
            let swap = m.lt(kb, ka);
            let swap = m.name(swap, "swap");
            let lo = m.mux(swap, kb, ka);
            let hi = m.mux(swap, ka, kb);
            (m.name(lo, "lo_key"), m.name(hi, "hi_key"))
        });
        keys[a] = lo;
        keys[b] = hi;
    }
    let key_bits = 1 + eb + ib;
    let mut out = NodeSortOut {
        hit: Vec::new(),
        entry: Vec::new(),
        child: Vec::new(),
    };
    for (j, &key) in keys.iter().enumerate() {
        m.scope(&format!("out{j}"), |m| {
            let miss = m.bit_at(key, key_bits - 1);
            let hit = m.not(miss);
            out.hit.push(m.name(hit, "is_hit"));
            let entry = m.slice(key, key_bits - 2, ib);
            out.entry.push(m.name(entry, "entry_field"));
            let child = m.slice(key, ib - 1, 0);
            out.child.push(m.name(child, "index_field"));
        });
    }
    out
}

/// Builds `node_sort` for a configuration.
pub fn build(cfg: &Config) -> Module {
    let mut m = ModuleBuilder::with_handshake(node_sort_name(cfg));
    m.describe(
        "Sorts the node tester's slots: hits first, smaller entry first, ties by slot index.",
    );
    let NodeSortIn { hit, entry } = ports::declare_inputs(&mut m, cfg);
    let out = sort_slots(&mut m, &hit, &entry);
    ports::declare_outputs(&mut m, cfg, &out);
    let datapath = m.finish().expect("node_sort datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance(&datapath, cfg.stages)
        .expect("the node_sort datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

impl Description for NodeSort {
    type Params = NodeSortParams;
    type Config = Config;
    const NAME: &'static str = "node_sort";
    const SUMMARY: &'static str =
        "node tester's sort network: N slots (hit, entry) sorted hits first, nearer first, ties by index";
    fn config(&self, p: &NodeSortParams) -> Result<Config, ParamError> {
        if ![2, 4, 8].contains(&p.children) {
            return Err(ParamError::Combination(format!(
                "node_sort: children must be 2, 4 or 8, not {}",
                p.children
            )));
        }
        Ok(Config {
            children: p.children,
            box_bits: p.box_bits,
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

    /// The network sorts every 0/1 input (the 0-1 principle) with the
    /// known comparator counts.
    #[test]
    fn batcher_network_sorts_every_binary_input() {
        for (n, count) in [(2, 1), (4, 5), (8, 19)] {
            let net = batcher_network(n);
            assert_eq!(net.len(), count, "n = {n}");
            for x in 0..1u32 << n {
                let mut v: Vec<u32> = (0..n).map(|i| x >> i & 1).collect();
                for &(a, b) in &net {
                    if v[b] < v[a] {
                        v.swap(a, b);
                    }
                }
                assert!(v.windows(2).all(|w| w[0] <= w[1]), "n = {n}, x = {x:b}");
            }
        }
    }

    #[test]
    fn children_other_than_2_4_8_are_refused() {
        for children in [3, 5, 6, 7] {
            let p = NodeSortParams {
                children,
                ..NodeSortParams::defaults()
            };
            assert!(NodeSort.config(&p).is_err(), "{children}");
        }
    }
}
