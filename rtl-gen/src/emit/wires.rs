//! Which values become wires: liveness (what is read, and which bits),
//! equal expressions emitted once, and the small values read once that are
//! written inside their reader instead ([`inlined`]).

use crate::eval::mask;
use crate::ir::*;
use std::collections::HashMap;

/// Which nodes, registers and instances are read, and which bits of each node.
pub(super) struct Liveness {
    pub(super) live: Vec<bool>,
    pub(super) used_bits: Vec<u128>,
    pub(super) regs: Vec<bool>,
    pub(super) instances: Vec<bool>,
}

pub(super) fn liveness(m: &Module) -> Liveness {
    let n = m.nodes.len();
    let mut live = vec![false; n];
    let mut regs = vec![false; m.registers.len()];
    let mut instances = vec![false; m.instances.len()];
    let mut work: Vec<NodeId> = m.outputs.iter().map(|(_, id)| *id).collect();
    while let Some(id) = work.pop() {
        if std::mem::replace(&mut live[id.0 as usize], true) {
            continue;
        }
        let node = m.node(id);
        work.extend(node.op.operands());
        match node.op {
            Op::Reg(r) if !regs[r] => {
                regs[r] = true;
                work.push(m.registers[r].next);
                work.extend(m.registers[r].enable);
            }
            Op::InstOut { inst, .. } if !instances[inst] => {
                instances[inst] = true;
                work.extend(m.instances[inst].inputs.iter().copied());
            }
            _ => {}
        }
    }
    let all = |id: NodeId| mask(u128::MAX, m.node(id).ty.width());
    let mut used_bits = vec![0u128; n];
    let read = |used_bits: &mut Vec<u128>, id: NodeId| used_bits[id.0 as usize] |= all(id);
    m.outputs
        .iter()
        .for_each(|(_, id)| read(&mut used_bits, *id));
    for (reg, _) in m.registers.iter().zip(&regs).filter(|(_, live)| **live) {
        read(&mut used_bits, reg.next);
        reg.enable.into_iter().for_each(|e| read(&mut used_bits, e));
    }
    for (inst, _) in m
        .instances
        .iter()
        .zip(&instances)
        .filter(|(_, live)| **live)
    {
        inst.inputs.iter().for_each(|id| read(&mut used_bits, *id));
    }
    // users come after their operands: walking backwards, a node's own read
    // bits are complete before they are passed on (casts are transparent)
    for (i, node) in m.nodes.iter().enumerate().rev() {
        if !live[i] {
            continue;
        }
        match node.op {
            Op::Slice(a, hi, lo) => used_bits[a.0 as usize] |= mask(u128::MAX, hi - lo + 1) << lo,
            Op::Cast(a) => used_bits[a.0 as usize] |= used_bits[i],
            _ => {
                for o in node.op.operands() {
                    read(&mut used_bits, o);
                }
            }
        }
    }
    Liveness {
        live,
        used_bits,
        regs,
        instances,
    }
}

/// Hash-consing: for every node, the first live node that computes the same
/// operation on the same operands (after the same mapping) with the same
/// type, itself when it is the first. Sources (inputs, registers, instance
/// outputs) and constants stay themselves. Only the first of equal
/// expressions is emitted, and every read of the others reads it.
pub(super) fn same_expressions(m: &Module, live: &[bool]) -> Vec<NodeId> {
    let mut same: Vec<NodeId> = (0..m.nodes.len() as u32).map(NodeId).collect();
    let mut first: HashMap<(Op, Ty), NodeId> = HashMap::new();
    for (i, node) in m.nodes.iter().enumerate() {
        let id = NodeId(i as u32);
        let op = node.op.clone().map_operands(|o| same[o.0 as usize]);
        match op {
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => {}
            _ if live[i] => same[i] = *first.entry((op, node.ty)).or_insert(id),
            _ => {}
        }
    }
    same
}

/// For every node, the node whose name it is emitted under: of equal
/// expressions (see [`same_expressions`]) the first one named by the
/// generator, else the first one, so hash-consing never drops a given name
/// for a derived one.
pub(super) fn name_sources(m: &Module, same: &[NodeId]) -> Vec<NodeId> {
    let mut source = same.to_vec();
    for (i, node) in m.nodes.iter().enumerate() {
        let c = same[i].0 as usize;
        if node.named && !m.nodes[source[c].0 as usize].named {
            source[c] = NodeId(i as u32);
        }
    }
    source
}

/// Operators in one inlined expression at most, so a line stays readable.
pub(super) const INLINE_OPERATORS: u32 = 6;

/// How an expression may be written in one operand slot of its reader.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Slot {
    /// the slot needs an identifier (a slice, a product's operand, a cast)
    Identifier,
    /// the operand's width is its own (a concatenation, a reduction, a
    /// comparison's operand, a select, a shift amount)
    SelfDetermined,
    /// the operand takes the reader's width: fine when it has that width
    Context(u32),
}

pub(super) fn slots(node: &Node) -> Vec<(NodeId, Slot)> {
    let w = node.ty.width();
    let ctx = Slot::Context(w);
    match node.op {
        Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => vec![],
        Op::Slice(a, ..) | Op::Cast(a) => vec![(a, Slot::Identifier)],
        Op::Mul(a, b) => vec![(a, Slot::Identifier), (b, Slot::Identifier)],
        Op::Add(a, b) | Op::Sub(a, b) | Op::Bit(_, a, b) => vec![(a, ctx), (b, ctx)],
        Op::Not(a) => vec![(a, ctx)],
        Op::Shl(a, b) | Op::Shr(a, b) => vec![(a, ctx), (b, Slot::SelfDetermined)],
        Op::Mux(s, t, f) => vec![(s, Slot::SelfDetermined), (t, ctx), (f, ctx)],
        Op::Concat(ref parts) => parts.iter().map(|p| (*p, Slot::SelfDetermined)).collect(),
        Op::Reduce(_, a) => vec![(a, Slot::SelfDetermined)],
        // the operands take the wider one's width; a narrower one (unsigned:
        // nothing signed is inlined) is zero-extended by a concatenation
        Op::Cmp(_, a, b) => vec![(a, Slot::SelfDetermined), (b, Slot::SelfDetermined)],
    }
}

/// Which live, emitted nodes are written inside their one reader's
/// expression instead of as a wire: derived names only, unsigned values
/// only (a signed operator's meaning depends on its context), no products
/// (their operands are extended to the product's width), at most
/// [`INLINE_OPERATORS`] operators per expression.
pub(super) fn inlined(m: &Module, lv: &Liveness, same: &[NodeId]) -> Vec<bool> {
    let n = m.nodes.len();
    let canon = |id: NodeId| same[id.0 as usize].0 as usize;
    let emitted = |i: usize| lv.live[i] && same[i].0 as usize == i;
    let source = name_sources(m, same);
    let mut readers = vec![0u32; n];
    for (_, node) in m.nodes.iter().enumerate().filter(|(i, _)| emitted(*i)) {
        node.op
            .operands()
            .into_iter()
            .for_each(|o| readers[canon(o)] += 1);
    }
    let mut sinks: Vec<NodeId> = m.outputs.iter().map(|(_, id)| *id).collect();
    for (reg, _) in m.registers.iter().zip(&lv.regs).filter(|(_, l)| **l) {
        sinks.push(reg.next);
        sinks.extend(reg.enable);
    }
    for (inst, _) in m.instances.iter().zip(&lv.instances).filter(|(_, l)| **l) {
        sinks.extend(inst.inputs.iter().copied());
    }
    sinks.iter().for_each(|o| readers[canon(*o)] += 1);

    let candidate = |c: usize| {
        let node = &m.nodes[c];
        emitted(c)
            && !m.node(source[c]).named
            && readers[c] == 1
            && !node.ty.is_signed()
            && !matches!(
                node.op,
                Op::Input(_)
                    | Op::Const(_)
                    | Op::Reg(_)
                    | Op::InstOut { .. }
                    | Op::Cast(_)
                    | Op::Mul(..)
            )
    };
    let mut inline = vec![false; n];
    let mut size = vec![1u32; n];
    let take = |slots: Vec<(NodeId, Slot)>, inline: &mut Vec<bool>, size: &[u32]| {
        let mut total = 1;
        for (o, slot) in slots {
            let c = canon(o);
            let fits = match slot {
                Slot::Identifier => false,
                Slot::SelfDetermined => true,
                Slot::Context(w) => m.nodes[c].ty.width() == w,
            };
            if fits && candidate(c) && total + size[c] <= INLINE_OPERATORS {
                inline[c] = true;
                total += size[c];
            }
        }
        total
    };
    for (i, node) in m.nodes.iter().enumerate() {
        if emitted(i) {
            size[i] = take(slots(node), &mut inline, &size);
        }
    }
    for o in sinks {
        let w = m.node(o).ty.width();
        take(vec![(o, Slot::Context(w))], &mut inline, &size);
    }
    inline
}
