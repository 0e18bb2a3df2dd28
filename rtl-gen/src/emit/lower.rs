//! Lowers an IR module to the Verilog tree.
//!
//! A live operation becomes a named wire and an `assign`, unless its value is
//! derived (not named by the generator), read once, and small: then it is
//! written inside its reader's expression ([`inlined`]), so a wire name is a
//! value someone named or a value read more than once. Semantics never depend
//! on Verilog's context-dependent widths or signedness: operands are extended
//! explicitly, signed operations wrap their operands in `$signed(...)`, and an
//! expression is written inside another only where every context-determined
//! operand has the reader's width.

use super::vast::*;
use crate::eval::mask;
use crate::ir::*;
use std::collections::{HashMap, HashSet};

/// Which nodes, registers and instances are read, and which bits of each node.
struct Liveness {
    live: Vec<bool>,
    used_bits: Vec<u128>,
    regs: Vec<bool>,
    instances: Vec<bool>,
}

fn liveness(m: &Module) -> Liveness {
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
fn same_expressions(m: &Module, live: &[bool]) -> Vec<NodeId> {
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
fn name_sources(m: &Module, same: &[NodeId]) -> Vec<NodeId> {
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
const INLINE_OPERATORS: u32 = 6;

/// How an expression may be written in one operand slot of its reader.
#[derive(Clone, Copy, PartialEq)]
enum Slot {
    /// the slot needs an identifier (a slice, a product's operand, a cast)
    Identifier,
    /// the operand's width is its own (a concatenation, a reduction, a
    /// comparison's operand, a select, a shift amount)
    SelfDetermined,
    /// the operand takes the reader's width: fine when it has that width
    Context(u32),
}

fn slots(node: &Node) -> Vec<(NodeId, Slot)> {
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
fn inlined(m: &Module, lv: &Liveness, same: &[NodeId]) -> Vec<bool> {
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

/// Describes the unused bits of a value of width `w` whose read bits are `used`.
fn unused_reason(w: u32, used: u128, what: &str) -> Option<String> {
    let full = mask(u128::MAX, w);
    if used & full == full {
        return None;
    }
    if used == 0 {
        return Some(format!("{what} not read in this configuration"));
    }
    let mut ranges = Vec::new();
    let mut b = 0;
    while b < w {
        if (used >> b) & 1 == 0 {
            let lo = b;
            while b < w && (used >> b) & 1 == 0 {
                b += 1;
            }
            ranges.push(if b - 1 == lo {
                format!("{lo}")
            } else {
                format!("{}:{lo}", b - 1)
            });
        } else {
            b += 1;
        }
    }
    ranges.reverse();
    Some(format!(
        "bits [{}] of this {what} are not read by design",
        ranges.join(", ")
    ))
}

/// Gives every port, register, instance and wire a unique identifier, in a
/// fixed order so the same module always gets the same names.
struct Names {
    taken: HashSet<String>,
    node: HashMap<NodeId, String>,
    reg: Vec<String>,
    instance: Vec<String>,
    /// (instance, output port) → the wire of an output no live node reads
    /// (an instance port still needs something to connect to)
    dead_outputs: HashMap<(usize, usize), String>,
    /// identifiers claimed, and how many of them needed a number to be unique
    claimed: usize,
    numbered: usize,
}

impl Names {
    fn claim(&mut self, want: &str) -> String {
        // a derived name can happen to be a reserved word (e.g. a slice of `in`)
        let want = if crate::ir::is_identifier(want) {
            want.to_string()
        } else {
            format!("{want}_w")
        };
        let want = want.as_str();
        let mut name = want.to_string();
        let mut k = 1;
        while !self.taken.insert(name.clone()) {
            name = format!("{want}_{k}");
            k += 1;
        }
        self.claimed += 1;
        self.numbered += usize::from(k > 1);
        name
    }
}

/// How a module's identifiers came out: a figure the naming tests bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NameCounts {
    /// wires, registers and instances named (ports not included)
    pub names: usize,
    /// of them, names that needed a number to be unique (`lt_3`)
    pub numbered: usize,
    /// length of the longest identifier
    pub longest: usize,
}

/// Names every identifier of `m` as [`lower`] does and counts them.
pub fn name_counts(m: &Module) -> NameCounts {
    let (lv, same) = used_values(m);
    let inline = inlined(m, &lv, &same);
    let names = assign_names(m, &lv, &same, &inline);
    let longest = names.taken.iter().map(|n| n.len()).max().unwrap_or(0);
    NameCounts {
        names: names.claimed,
        numbered: names.numbered,
        longest,
    }
}

/// Liveness and hash-consing, with the read bits of a copy of an
/// expression carried by the one emitted.
fn used_values(m: &Module) -> (Liveness, Vec<NodeId>) {
    let mut lv = liveness(m);
    let same = same_expressions(m, &lv.live);
    for (i, s) in same.iter().enumerate() {
        if s.0 as usize != i {
            let bits = lv.used_bits[i];
            lv.used_bits[s.0 as usize] |= bits;
        }
    }
    (lv, same)
}

/// Every identifier: ports as declared, then instances, registers and
/// wires in node order (so the same module always gets the same names).
fn assign_names(m: &Module, lv: &Liveness, same: &[NodeId], inline: &[bool]) -> Names {
    let mut names = Names {
        taken: HashSet::new(),
        node: HashMap::new(),
        reg: vec![],
        instance: vec![],
        dead_outputs: HashMap::new(),
        claimed: 0,
        numbered: 0,
    };
    for c in [control::CLOCK, control::RESET] {
        names.taken.insert(c.to_string());
    }
    for p in m.inputs.iter().chain(m.outputs.iter().map(|(p, _)| p)) {
        names.taken.insert(p.name.clone());
    }
    names.instance = m.instances.iter().map(|i| names.claim(&i.name)).collect();
    names.reg = m.registers.iter().map(|r| names.claim(&r.name)).collect();
    let drives = port_values(m, lv, same, inline);
    let source = name_sources(m, same);
    for (i, node) in m.nodes.iter().enumerate() {
        let id = NodeId(i as u32);
        match node.op {
            Op::Input(p) => {
                names.node.insert(id, m.inputs[p].name.clone());
            }
            Op::Reg(r) => {
                names.node.insert(id, names.reg[r].clone());
            }
            Op::Const(_) | Op::Cast(_) => {}
            _ if drives.contains_key(&id) => {
                names.node.insert(id, drives[&id].clone());
            }
            _ if lv.live[i] && same[i].0 as usize == i && !inline[i] => {
                let n = names.claim(&m.node(source[i]).name);
                names.node.insert(id, n);
            }
            _ => {}
        }
    }
    for (ii, inst) in m
        .instances
        .iter()
        .enumerate()
        .filter(|(ii, _)| lv.instances[*ii])
    {
        for (port, (p, _)) in inst.module.outputs.iter().enumerate() {
            let live = m
                .nodes
                .iter()
                .enumerate()
                .any(|(k, n)| n.op == Op::InstOut { inst: ii, port } && lv.live[k]);
            if !live {
                let w = names.claim(&format!("{}_{}", names.instance[ii], p.name));
                names.dead_outputs.insert((ii, port), w);
            }
        }
    }
    names
}

/// The computed values named like an output port they drive: such a value
/// is the port (`assign hit = ...`), not a wire `hit_1` copied into it.
fn port_values(
    m: &Module,
    lv: &Liveness,
    same: &[NodeId],
    inline: &[bool],
) -> HashMap<NodeId, String> {
    let mut drives = HashMap::new();
    let source = name_sources(m, same);
    for (p, id) in &m.outputs {
        let c = same[id.0 as usize];
        let node = m.node(c);
        let computed = !matches!(
            node.op,
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::Cast(_) | Op::InstOut { .. }
        );
        let emitted = lv.live[c.0 as usize] && !inline[c.0 as usize];
        let named_as = &m.node(source[c.0 as usize]).name;
        if computed && emitted && *named_as == p.name && !drives.contains_key(&c) {
            drives.insert(c, p.name.clone());
        }
    }
    drives
}

fn decl(name: &str, ty: Ty, unused: Option<String>) -> Decl {
    Decl {
        name: name.to_string(),
        width: ty.width(),
        signed: ty.is_signed(),
        unused,
    }
}

/// The parameter list as `k=v, ...`.
pub fn params_line(params: &std::collections::BTreeMap<String, String>) -> String {
    if params.is_empty() {
        return "(none)".into();
    }
    params
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn header(m: &Module, generator: &str, is_top: bool) -> Vec<String> {
    let mut h = vec![
        format!("Generated by {generator}. Do not edit: regenerate instead."),
        format!("Module: {}", m.name),
    ];
    if !m.description.is_empty() {
        h.push(m.description.clone());
    }
    h.push(format!("Parameters: {}", params_line(&m.params)));
    match m.handshake {
        Some(hs) => {
            h.push(format!(
                "Latency: {} cycle(s) from in_valid to out_valid; one transaction per clock (II = 1); no backpressure.",
                hs.latency
            ));
            h.push("Clock: clk, rising edge. Reset: rst, synchronous, active high; clears the valid pipeline only.".into());
        }
        None if m.is_sequential() => h.push(format!(
            "Latency: {} cycle(s) from inputs to outputs, fixed; no valid ports (the instantiating module tracks validity).",
            m.latency
        )),
        None => h.push("Combinational.".into()),
    }
    if is_top {
        h.push(
            "Data registers are not reset: outputs are meaningful only while out_valid is high."
                .into(),
        );
    }
    h
}

/// Writes the expressions of one module: a reference to a node is its
/// identifier, its literal, its operand's (for casts) or, for an inlined
/// node, its own expression.
struct Writer<'a> {
    m: &'a Module,
    names: &'a Names,
    same: &'a [NodeId],
    inline: &'a [bool],
    lv: &'a Liveness,
}

impl Writer<'_> {
    fn reference(&self, id: NodeId) -> Expr {
        let id = self.same[id.0 as usize];
        match self.m.node(id).op {
            Op::Const(v) => Expr::Literal {
                width: self.m.node(id).ty.width(),
                value: v,
            },
            Op::Cast(a) => self.reference(a),
            _ if self.inline[id.0 as usize] => self.expression(id),
            _ => Expr::Ident(self.names.node[&id].clone()),
        }
    }

    /// The reference to `id` extended to `w` bits (zeros, or copies of the
    /// sign bit when signed).
    fn extended(&self, id: NodeId, w: u32) -> Expr {
        let ty = self.m.node(id).ty;
        let wi = ty.width();
        let e = self.reference(id);
        if wi == w {
            return e;
        }
        match (&e, ty.is_signed()) {
            (Expr::Literal { value, .. }, signed) => {
                let v = if signed && (value >> (wi - 1)) & 1 == 1 {
                    value | !mask(u128::MAX, wi)
                } else {
                    *value
                };
                Expr::Literal {
                    width: w,
                    value: mask(v, w),
                }
            }
            (_, false) => Expr::Concat(vec![
                Expr::Literal {
                    width: w - wi,
                    value: 0,
                },
                e,
            ]),
            (Expr::Ident(name), true) => {
                let msb = if wi == 1 {
                    e.clone()
                } else {
                    Expr::Select(name.clone(), wi - 1, wi - 1)
                };
                let fill = if w - wi == 1 {
                    msb
                } else {
                    Expr::Replicate(w - wi, Box::new(msb))
                };
                Expr::Concat(vec![fill, e.clone()])
            }
            _ => unreachable!("signed values are never inlined"),
        }
    }

    /// What node `id` computes, as one expression over its operands.
    fn expression(&self, id: NodeId) -> Expr {
        let m = self.m;
        let node = m.node(id);
        let r = |id: NodeId| self.reference(id);
        let ext = |id: NodeId, w: u32| self.extended(id, w);
        let signed_if = |signed: bool, e: Expr| if signed { Expr::Signed(Box::new(e)) } else { e };
        let bin = |op: &'static str, a: Expr, b: Expr| Expr::Binary(op, Box::new(a), Box::new(b));
        match &node.op {
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::Cast(_) | Op::InstOut { .. } => {
                unreachable!("sources and casts are referenced, not computed")
            }
            Op::Add(a, b) => bin("+", ext(*a, node.ty.width()), ext(*b, node.ty.width())),
            Op::Sub(a, b) => bin("-", ext(*a, node.ty.width()), ext(*b, node.ty.width())),
            Op::Mul(a, b) => {
                let s = m.node(*a).ty.is_signed();
                bin("*", signed_if(s, r(*a)), signed_if(s, r(*b)))
            }
            Op::Not(a) => Expr::Unary("~", Box::new(r(*a))),
            Op::Bit(op, a, b) => {
                let o = match op {
                    BitOp::And => "&",
                    BitOp::Or => "|",
                    BitOp::Xor => "^",
                };
                bin(o, r(*a), r(*b))
            }
            Op::Cmp(op, a, b) => {
                let w = m.node(*a).ty.width().max(m.node(*b).ty.width());
                let s = m.node(*a).ty.is_signed();
                let o = match op {
                    CmpOp::Eq => "==",
                    CmpOp::Lt => "<",
                    CmpOp::Le => "<=",
                };
                let signed = s && *op != CmpOp::Eq;
                bin(
                    o,
                    signed_if(signed, ext(*a, w)),
                    signed_if(signed, ext(*b, w)),
                )
            }
            Op::Shl(a, b) => bin("<<", r(*a), r(*b)),
            Op::Shr(a, b) if m.node(*a).ty.is_signed() => bin(">>>", signed_if(true, r(*a)), r(*b)),
            Op::Shr(a, b) => bin(">>", r(*a), r(*b)),
            Op::Mux(s, t, f) => Expr::Ternary(Box::new(r(*s)), Box::new(r(*t)), Box::new(r(*f))),
            Op::Concat(parts) => Expr::Concat(parts.iter().map(|p| r(*p)).collect()),
            Op::Slice(a, hi, lo) => match r(*a) {
                Expr::Ident(name) => Expr::Select(name, *hi, *lo),
                _ => unreachable!("slices of constants are folded by the builder"),
            },
            Op::Reduce(op, a) => {
                let o = match op {
                    ReduceOp::And => "&",
                    ReduceOp::Or => "|",
                    ReduceOp::Xor => "^",
                };
                Expr::Unary(o, Box::new(r(*a)))
            }
        }
    }
}

/// Lowers `m` to a Verilog module. A top-level module always has `clk` and
/// `rst` ports (one interface for every configuration); a submodule has them
/// only when it uses them.
pub fn lower(m: &Module, generator: &str, is_top: bool, options: super::EmitOptions) -> VModule {
    let (lv, same) = used_values(m);
    let inline = inlined(m, &lv, &same);
    let names = assign_names(m, &lv, &same, &inline);
    let writer = Writer {
        m,
        names: &names,
        same: &same,
        inline: &inline,
        lv: &lv,
    };
    let mut items = writer.declarations_and_assigns(options);
    items.extend(writer.register_blocks());
    writer.instances(&mut items);
    if let Some(cell) = &m.vendor_cell {
        items = vec![writer.vendor_cell(cell, items)];
    }
    VModule {
        header: header(m, generator, is_top),
        name: m.name.clone(),
        ports: writer.ports(is_top),
        items,
    }
}

impl Writer<'_> {
    /// The port list: `clk` and `rst` (always on a top module), the inputs
    /// in their order, the outputs.
    fn ports(&self, is_top: bool) -> Vec<(Dir, Decl)> {
        let m = self.m;
        let sequential = m.is_sequential();
        let needs_reset = m.uses_reset();
        let mut ports = Vec::new();
        let no_regs =
            "clk and rst keep one interface for every configuration; this one has no registers";
        if sequential || is_top {
            let unused = (!sequential).then(|| no_regs.to_string());
            ports.push((Dir::Input, decl(control::CLOCK, Ty::Bool, unused)));
        }
        if needs_reset || is_top {
            let unused = (!needs_reset).then(|| no_regs.to_string());
            ports.push((Dir::Input, decl(control::RESET, Ty::Bool, unused)));
        }
        for (i, node) in m.nodes.iter().enumerate() {
            if let Op::Input(p) = node.op {
                let unused = unused_reason(node.ty.width(), self.lv.used_bits[i], "input");
                ports.push((Dir::Input, decl(&m.inputs[p].name, node.ty, unused)));
            }
        }
        for (p, _) in &m.outputs {
            ports.push((Dir::Output, decl(&p.name, p.ty, None)));
        }
        ports
    }

    /// The wire and register declarations, then the continuous assignments
    /// of the named values and of the outputs.
    fn declarations_and_assigns(&self, options: super::EmitOptions) -> Vec<Item> {
        let (m, lv, names) = (self.m, self.lv, self.names);
        let mut items = Vec::new();
        let mut assigns = Vec::new();
        for (i, node) in m.nodes.iter().enumerate() {
            let id = NodeId(i as u32);
            if !lv.live[i] || self.same[i].0 as usize != i {
                continue;
            }
            let rhs = match &node.op {
                Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::Cast(_) => continue,
                Op::InstOut { .. } => {
                    let unused = unused_reason(node.ty.width(), lv.used_bits[i], "instance output");
                    items.push(Item::Wire(decl(&names.node[&id], node.ty, unused)));
                    continue;
                }
                _ if self.inline[i] => continue,
                _ => self.expression(id),
            };
            let name = names.node[&id].clone();
            let is_port = m.outputs.iter().any(|(p, _)| p.name == name);
            if !is_port {
                let unused = unused_reason(node.ty.width(), lv.used_bits[i], "wire");
                items.push(Item::Wire(decl(&name, node.ty, unused)));
            }
            if options.source_lines {
                let at = node.location;
                assigns.push(Item::Comment(format!("src: {}:{}", at.file(), at.line())));
            }
            assigns.push(Item::Assign(name, rhs));
        }
        for (ri, reg) in m.registers.iter().enumerate() {
            if !lv.regs[ri] {
                continue;
            }
            let q = m
                .nodes
                .iter()
                .position(|n| n.op == Op::Reg(ri))
                .unwrap_or(0);
            let unused = unused_reason(reg.ty.width(), lv.used_bits[q], "register");
            items.push(Item::Reg(decl(&names.reg[ri], reg.ty, unused)));
        }
        items.push(Item::Blank);
        items.extend(assigns);
        for (p, id) in &m.outputs {
            let value = self.reference(*id);
            // a value named like its port was assigned to the port above
            if value != Expr::Ident(p.name.clone()) {
                items.push(Item::Assign(p.name.clone(), value));
            }
        }
        items
    }

    /// The clocked blocks: registers with a reset value in one block under
    /// `rst`, the others in a block of their own.
    fn register_blocks(&self) -> Vec<Item> {
        let names = self.names;
        let load = |reg: &Register, ri: usize| {
            let set = Stmt::NonBlocking(names.reg[ri].clone(), self.reference(reg.next));
            match reg.enable {
                Some(e) => Stmt::If(self.reference(e), vec![set], vec![]),
                None => set,
            }
        };
        let (mut resets, mut loads_after_reset, mut plain) = (Vec::new(), Vec::new(), Vec::new());
        for (ri, reg) in self
            .m
            .registers
            .iter()
            .enumerate()
            .filter(|(ri, _)| self.lv.regs[*ri])
        {
            match reg.reset {
                Some(v) => {
                    resets.push(Stmt::NonBlocking(
                        names.reg[ri].clone(),
                        Expr::Literal {
                            width: reg.ty.width(),
                            value: v,
                        },
                    ));
                    loads_after_reset.push(load(reg, ri));
                }
                None => plain.push(load(reg, ri)),
            }
        }
        let mut items = Vec::new();
        if !resets.is_empty() {
            items.push(Item::Blank);
            let rst = Expr::Ident(control::RESET.into());
            items.push(Item::AlwaysPosedge(
                control::CLOCK.into(),
                vec![Stmt::If(rst, resets, loads_after_reset)],
            ));
        }
        if !plain.is_empty() {
            items.push(Item::Blank);
            items.push(Item::AlwaysPosedge(control::CLOCK.into(), plain));
        }
        items
    }

    /// The submodule instances, appended to `items`; a wire for each
    /// instance output nothing reads goes first.
    fn instances(&self, items: &mut Vec<Item>) {
        let (m, names) = (self.m, self.names);
        for (ii, inst) in m.instances.iter().enumerate() {
            if !self.lv.instances[ii] {
                continue;
            }
            let sub = &inst.module;
            let mut connections = Vec::new();
            if sub.is_sequential() {
                connections.push((
                    control::CLOCK.to_string(),
                    Expr::Ident(control::CLOCK.into()),
                ));
            }
            if sub.uses_reset() {
                connections.push((
                    control::RESET.to_string(),
                    Expr::Ident(control::RESET.into()),
                ));
            }
            for (p, id) in sub.inputs.iter().zip(&inst.inputs) {
                connections.push((p.name.clone(), self.reference(*id)));
            }
            for (port, (p, _)) in sub.outputs.iter().enumerate() {
                let wire = match names.dead_outputs.get(&(ii, port)) {
                    Some(w) => {
                        items.insert(
                            0,
                            Item::Wire(decl(w, p.ty, Some("instance output not used here".into()))),
                        );
                        w.clone()
                    }
                    None => {
                        // the builder creates exactly one node per instance output, live here
                        let k = m
                            .nodes
                            .iter()
                            .position(|n| n.op == Op::InstOut { inst: ii, port });
                        names.node[&NodeId(k.expect("instance output node") as u32)].clone()
                    }
                };
                connections.push((p.name.clone(), Expr::Ident(wire)));
            }
            items.push(Item::Blank);
            items.push(Item::Instance {
                module: sub.name.clone(),
                params: Vec::new(),
                name: names.instance[ii].clone(),
                connections,
            });
        }
    }

    /// The module body for synthesis: the vendor cell on its ports, wired
    /// pin by pin; `items` (the generic logic) stays for simulation.
    fn vendor_cell(&self, cell: &VendorCell, items: Vec<Item>) -> Item {
        let m = self.m;
        let bit = |name: &str, ty: Ty, bit: u32| match ty.width() {
            1 => Expr::Ident(name.to_string()),
            _ => Expr::Select(name.to_string(), bit, bit),
        };
        let connections = cell
            .pins
            .iter()
            .map(|(pin, c)| {
                let e = match *c {
                    CellPin::Clock => Expr::Ident(control::CLOCK.into()),
                    CellPin::Const(v) => Expr::Literal {
                        width: 1,
                        value: v as u128,
                    },
                    CellPin::Input { port, bit: b } => {
                        bit(&m.inputs[port].name, m.inputs[port].ty, b)
                    }
                    CellPin::Output { port, bit: b } => {
                        let p = &m.outputs[port].0;
                        bit(&p.name, p.ty, b)
                    }
                };
                (pin.clone(), e)
            })
            .collect();
        let hard = Item::Instance {
            module: cell.cell.clone(),
            params: cell.params.clone(),
            name: "hard_block".into(),
            connections,
        };
        Item::Ifdef {
            symbol: "SYNTHESIS".into(),
            then: vec![hard],
            otherwise: items,
        }
    }
}
