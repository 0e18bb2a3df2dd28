//! Fewer register bits at the same period and latency: each stage boundary is
//! moved, by a minimum cut, to where the values crossing it are narrowest.
//!
//! For the boundary between stages `k` and `k + 1`, the nodes of those two
//! stages may trade places (a node's operands stay at or before it, its users
//! at or after it). Every path then stays within the period if a node goes to
//! `k` only when its longest path from the start of `k` (through nodes of the
//! two stages) fits, and to `k + 1` only when its longest path to the end of
//! `k + 1` fits: both lengths are fixed whatever the cut, because the
//! predecessors of a node in `k` are in `k` and the successors of a node in
//! `k + 1` are in `k + 1`. Only the register bits at that one boundary change:
//! a value is registered there when it is computed at or before `k` and read
//! after it. That is a minimum cut with one extra vertex per value (Leiserson
//! and Saxe's fanout construction), so a value read by several later nodes is
//! counted once. The boundaries are visited in turn until none improves.

use super::{period_of, register_bits, Graph, Schedule};
use crate::ir::Op;

/// Moves the boundaries of `s` (built for `period`, outputs at `last`) to
/// carry fewer register bits; never lengthens the modelled period.
pub(super) fn minimise(g: &Graph, s: &mut Schedule, last: u32, period: f64, force: bool) {
    let mut bits = register_bits(g, s, last);
    for _round in 0..6 {
        let before = bits;
        for k in 0..last {
            let Some(moved) = cut_boundary(g, s, k, last, period, force) else {
                continue;
            };
            let old = std::mem::replace(&mut s.stage, moved);
            let now = register_bits(g, s, last);
            // the construction guarantees both; checked so a flaw costs bits, not timing
            if now < bits && period_of(g, s) <= period + 1e-9 {
                bits = now;
            } else {
                s.stage = old;
            }
        }
        if bits == before {
            break;
        }
    }
}

const INFINITE: u64 = 1 << 60;

/// The stages after the best cut between `k` and `k + 1`, or `None` when
/// nothing can move.
fn cut_boundary(
    g: &Graph,
    s: &Schedule,
    k: u32,
    last: u32,
    period: f64,
    force: bool,
) -> Option<Vec<Option<u32>>> {
    let nodes = &g.flat.nodes;
    let n = nodes.len();
    let movable = |i: usize| {
        g.live[i]
            && !matches!(nodes[i].op, Op::Const(_) | Op::Input(_))
            && matches!(s.stage[i], Some(x) if x == k || x == k + 1)
    };
    let region: Vec<usize> = (0..n).filter(|&i| movable(i)).collect();
    if region.is_empty() {
        return None;
    }
    let starts_stage = |i: usize| force && nodes[i].wire;
    let mut local = vec![usize::MAX; n];
    for (l, &i) in region.iter().enumerate() {
        local[i] = l;
    }
    let in_region = |i: usize| local[i] != usize::MAX;
    // longest paths from the start of k (arrive) and to the end of k + 1 (tail)
    let mut arrive = vec![0.0f64; region.len()];
    for (l, &i) in region.iter().enumerate() {
        let before = match starts_stage(i) {
            true => 0.0,
            false => nodes[i]
                .op
                .operands()
                .iter()
                .map(|o| o.0 as usize)
                .filter(|&o| in_region(o))
                .map(|o| arrive[local[o]])
                .fold(0.0, f64::max),
        };
        arrive[l] = before + g.delay[i];
    }
    let mut tail = vec![0.0f64; region.len()];
    for (l, &i) in region.iter().enumerate().rev() {
        let after = g.users[i]
            .iter()
            .filter(|&&u| in_region(u) && !starts_stage(u))
            .map(|&u| tail[local[u]])
            .fold(0.0, f64::max);
        tail[l] = after + g.delay[i];
    }

    // vertices: source, sink, the region, one fanout vertex per value
    const SOURCE: usize = 0;
    const SINK: usize = 1;
    let vertex = |l: usize| 2 + l;
    let mut net = Network::new(2 + region.len());
    let slack = period + 1e-9;
    for (l, &i) in region.iter().enumerate() {
        if arrive[l] > slack {
            net.edge(vertex(l), SINK, INFINITE);
        }
        if tail[l] > slack {
            net.edge(SOURCE, vertex(l), INFINITE);
        }
        for o in nodes[i].op.operands() {
            let o = o.0 as usize;
            if !in_region(o) {
                continue;
            }
            // an operand never after its user
            net.edge(vertex(l), vertex(local[o]), INFINITE);
            if starts_stage(i) {
                net.edge(SOURCE, vertex(local[o]), INFINITE);
                net.edge(vertex(l), SINK, INFINITE);
            }
        }
    }
    // the values whose register at this boundary depends on the cut
    let mut any_choice = false;
    for v in 0..n {
        let Some(sv) = s.stage[v] else { continue };
        if !g.live[v] || sv > k + 1 {
            continue;
        }
        let users_here: Vec<usize> = g.users[v]
            .iter()
            .copied()
            .filter(|&u| in_region(u))
            .collect();
        let read_later = (g.is_output[v] && last > k)
            || g.users[v]
                .iter()
                .any(|&u| matches!(s.stage[u], Some(su) if su > k + 1));
        if in_region(v) {
            if users_here.is_empty() && !read_later {
                continue;
            }
        } else if read_later || users_here.is_empty() {
            // registered at k whatever the cut, or not read near it
            continue;
        }
        any_choice = true;
        let fan = net.vertex();
        let width = u64::from(nodes[v].ty.width());
        match in_region(v) {
            true => net.edge(vertex(local[v]), fan, width),
            false => net.edge(SOURCE, fan, width),
        }
        for u in users_here {
            net.edge(fan, vertex(local[u]), INFINITE);
        }
        if read_later {
            net.edge(fan, SINK, INFINITE);
        }
    }
    if !any_choice {
        return None;
    }
    if net.max_flow(SOURCE, SINK) >= INFINITE {
        // the timing and order constraints contradict each other (cannot
        // happen from a valid schedule); keep the boundary where it is
        return None;
    }
    let early = net.reachable(SOURCE);
    let mut stage = s.stage.clone();
    for (l, &i) in region.iter().enumerate() {
        stage[i] = Some(if early[vertex(l)] { k } else { k + 1 });
    }
    Some(stage)
}

/// A flow network for Dinic's maximum flow.
struct Network {
    /// per edge: head, remaining capacity; edge `e ^ 1` is its reverse
    head: Vec<usize>,
    capacity: Vec<u64>,
    out: Vec<Vec<usize>>,
}

impl Network {
    fn new(vertices: usize) -> Network {
        Network {
            head: Vec::new(),
            capacity: Vec::new(),
            out: vec![Vec::new(); vertices],
        }
    }

    fn vertex(&mut self) -> usize {
        self.out.push(Vec::new());
        self.out.len() - 1
    }

    fn edge(&mut self, from: usize, to: usize, capacity: u64) {
        self.out[from].push(self.head.len());
        self.head.push(to);
        self.capacity.push(capacity);
        self.out[to].push(self.head.len());
        self.head.push(from);
        self.capacity.push(0);
    }

    fn levels(&self, source: usize) -> Vec<u32> {
        let mut level = vec![u32::MAX; self.out.len()];
        level[source] = 0;
        let mut queue = std::collections::VecDeque::from([source]);
        while let Some(v) = queue.pop_front() {
            for &e in &self.out[v] {
                let w = self.head[e];
                if self.capacity[e] > 0 && level[w] == u32::MAX {
                    level[w] = level[v] + 1;
                    queue.push_back(w);
                }
            }
        }
        level
    }

    fn max_flow(&mut self, source: usize, sink: usize) -> u64 {
        let mut total = 0u64;
        loop {
            let level = self.levels(source);
            if level[sink] == u32::MAX {
                return total;
            }
            let mut next = vec![0usize; self.out.len()];
            loop {
                let pushed = self.augment(source, sink, INFINITE, &level, &mut next);
                if pushed == 0 {
                    break;
                }
                total += pushed;
            }
        }
    }

    /// One blocking-flow path search, iterative so deep graphs do not
    /// overflow the stack.
    fn augment(
        &mut self,
        source: usize,
        sink: usize,
        limit: u64,
        level: &[u32],
        next: &mut [usize],
    ) -> u64 {
        let mut path: Vec<usize> = Vec::new();
        let mut v = source;
        loop {
            if v == sink {
                let pushed = path.iter().map(|&e| self.capacity[e]).fold(limit, u64::min);
                for &e in &path {
                    self.capacity[e] -= pushed;
                    self.capacity[e ^ 1] += pushed;
                }
                return pushed;
            }
            let mut advanced = false;
            while next[v] < self.out[v].len() {
                let e = self.out[v][next[v]];
                let w = self.head[e];
                if self.capacity[e] > 0 && level[w] == level[v] + 1 {
                    path.push(e);
                    v = w;
                    advanced = true;
                    break;
                }
                next[v] += 1;
            }
            if !advanced {
                // dead end: retreat and skip the edge that led here
                let Some(e) = path.pop() else { return 0 };
                v = self.head[e ^ 1];
                next[v] += 1;
            }
        }
    }

    fn reachable(&self, source: usize) -> Vec<bool> {
        let level = self.levels(source);
        level.iter().map(|&l| l != u32::MAX).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::Network;

    #[test]
    fn max_flow_of_a_small_network() {
        // two paths of 3 and 2 that meet before a last edge of 4
        let mut n = Network::new(5);
        n.edge(0, 2, 3);
        n.edge(0, 3, 2);
        n.edge(2, 4, 4);
        n.edge(3, 4, 4);
        n.edge(4, 1, 4);
        assert_eq!(n.max_flow(0, 1), 4);
        let early = n.reachable(0);
        // the cut is the last edge: everything but the sink is on the source side
        assert!(early[0] && early[2] && early[3] && early[4] && !early[1]);
    }
}
