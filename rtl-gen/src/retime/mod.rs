//! Register placement by delay: a module's pipeline registers moved to where
//! its logic is cut into stages of about equal delay.
//!
//! Units place their `stage()` calls by logical steps (after the alignment,
//! after the products, ...); a step that is long, or registers that meet at a
//! module boundary, set the clock. [`balance`] keeps a module's function and
//! ports, removes its pipeline registers and places the requested number
//! again where they cut the logic evenly (the flow's `pipeline=balanced`
//! hands it the unit's combinational build):
//!
//! 1. the module is flattened (instances inlined, their names prefixed with the
//!    instance name) and its pipeline registers removed, which leaves one
//!    combinational graph of the transaction; unsigned products wider than a
//!    DSP block's 18 bits are split into 18x18 blocks and a sum, so that
//!    registers can go between the blocks and the sum;
//! 2. each operation gets a delay from [`delay`], a model of an FPGA with
//!    4-input LUTs, carry chains and 18x18 multipliers (one LUT level = 1.0);
//! 3. the smallest period `P` whose as-soon-as-possible schedule fits in
//!    the requested latency is found by bisection (no stage longer than `P`
//!    except where one operation alone is longer); in it and in the
//!    as-late-as-possible schedule of the same `P`, each stage boundary is
//!    moved by a minimum cut to where the values crossing it are narrowest
//!    ([`registers`]), and the one that carries fewer register bits is kept;
//! 4. the graph is replayed through a [`ModuleBuilder`] stage by stage, so the
//!    registers that carry values, and the valid chain, are the builder's own.
//!
//! Only feed-forward pipelines are re-timed: a module with a register that has
//! an enable or reads a later value (state) is refused.

pub mod hard_dsp;
mod registers;

use crate::builder::{BuildErrors, ModuleBuilder, Sig};
use crate::ir::{Module, NodeId, Op, Port, Ty};
use std::collections::HashMap;

/// One operation of the flattened transaction graph; operands index the graph.
#[derive(Debug, Clone)]
struct FlatNode {
    op: Op,
    ty: Ty,
    name: String,
    /// the name was given, not derived ([`Node::named`])
    named: bool,
    /// the stage the unit's own plan computes it in (`None` for constants)
    built: Option<u32>,
    /// a same-bits cast standing for the route from a DSP block's output
    /// ([`DSP_ROUTE`]); it always starts a stage
    wire: bool,
}

/// The flattened, register-free graph of a module.
struct Flat {
    nodes: Vec<FlatNode>,
    /// data outputs (without `out_valid`) and the node driving each
    outputs: Vec<(Port, usize)>,
    /// node of `in_valid` when the module has the handshake
    in_valid: Option<usize>,
}

/// Inlines `m` into `nodes`, its input ports read from `inputs` (node, and
/// the stage the value is in there); returns the same of each output.
fn inline(
    m: &Module,
    inputs: &[(usize, u32)],
    prefix: &str,
    nodes: &mut Vec<FlatNode>,
) -> Result<Vec<(usize, u32)>, String> {
    let mut map: Vec<(usize, u32)> = Vec::with_capacity(m.nodes.len());
    let mut inlined: HashMap<usize, Vec<(usize, u32)>> = HashMap::new();
    for (i, node) in m.nodes.iter().enumerate() {
        let flat = match &node.op {
            Op::Input(p) => inputs[*p],
            Op::Reg(r) => {
                let reg = &m.registers[*r];
                if reg.enable.is_some() || reg.next.0 as usize >= i {
                    return Err(format!(
                        "module {}: register {} holds state; only pipelines are re-timed",
                        m.name, reg.name
                    ));
                }
                // a pipeline register (or the valid chain) carries the same
                // transaction's value: in the graph it is that value, a stage later
                let (id, stage) = map[reg.next.0 as usize];
                (id, stage + 1)
            }
            Op::InstOut { inst, port } => {
                if !inlined.contains_key(inst) {
                    let instance = &m.instances[*inst];
                    let ins: Vec<(usize, u32)> = instance
                        .inputs
                        .iter()
                        .map(|id| map[id.0 as usize])
                        .collect();
                    let outs = inline(
                        &instance.module,
                        &ins,
                        &format!("{prefix}{}_", instance.name),
                        nodes,
                    )?;
                    inlined.insert(*inst, outs);
                }
                inlined[inst][*port]
            }
            op => {
                let operands = op.operands();
                let stage = operands
                    .iter()
                    .map(|o| map[o.0 as usize])
                    .filter(|(id, _)| nodes[*id].built.is_some())
                    .map(|(_, s)| s)
                    .max()
                    .unwrap_or(0);
                let op = op
                    .clone()
                    .map_operands(|id| NodeId(map[id.0 as usize].0 as u32));
                let first = nodes.len();
                let id = match op {
                    Op::Const(_) => push(nodes, op, node.ty, node.name.clone()),
                    Op::Mul(a, b) => split_product(
                        nodes,
                        a.0 as usize,
                        b.0 as usize,
                        node.ty,
                        &format!("{prefix}{}", node.name),
                    ),
                    op => push(nodes, op, node.ty, format!("{prefix}{}", node.name)),
                };
                for n in &mut nodes[first..] {
                    if !matches!(n.op, Op::Const(_)) {
                        n.built = Some(stage);
                    }
                }
                nodes[id].named |= node.named;
                (id, stage)
            }
        };
        map.push(flat);
    }
    Ok(m.outputs.iter().map(|(_, id)| map[id.0 as usize]).collect())
}

fn push(nodes: &mut Vec<FlatNode>, op: Op, ty: Ty, name: String) -> usize {
    nodes.push(FlatNode {
        op,
        ty,
        name,
        named: false,
        built: None,
        wire: false,
    });
    nodes.len() - 1
}

/// Operand width of one DSP block: ECP5's MULT18X18D, the device the model is
/// calibrated on (a 7-series DSP48E1 takes 25x18, so there a 24x24 product
/// may take more blocks split this way than whole).
const DSP_BITS: u32 = 18;

/// Delay of the route between the fabric and a DSP block on ECP5 (about
/// 3.2 ns: the blocks sit in rows of their own), in LUT levels.
const DSP_ROUTE: f64 = 1.8;

/// Widest remainder pieces of a split product whose block is summed in LUTs
/// instead of a DSP block: a 24x24 product's 6x6 corner is a few dozen LUT4s
/// of partial products, against a quarter of its four blocks (Yosys would
/// put a written `*` of it on a block).
const CORNER_BITS: u32 = 6;

/// True when a `wa x wb` product goes to a DSP block rather than LUTs.
fn on_dsp(wa: u32, wb: u32) -> bool {
    wa.min(wb) > 4
}

/// `a · b` on one DSP block, its product behind a [`DSP_ROUTE`] wire that
/// starts a stage: a register at the block's output pins (the block's own
/// output register, in effect), so no stage holds the route in, the block,
/// the route out and the logic after it. The route in is part of the block's
/// [`delay`].
fn dsp_block(nodes: &mut Vec<FlatNode>, a: usize, b: usize, ty: Ty, name: &str) -> usize {
    let p = push(
        nodes,
        Op::Mul(NodeId(a as u32), NodeId(b as u32)),
        ty,
        format!("{name}_dsp"),
    );
    if !on_dsp(nodes[a].ty.width(), nodes[b].ty.width()) {
        nodes[p].name = name.to_string();
        return p;
    }
    let w = push(nodes, Op::Cast(NodeId(p as u32)), ty, name.to_string());
    nodes[w].wire = true;
    w
}

/// `a · b` as one node, or, for unsigned operands wider than [`DSP_BITS`],
/// as the products of their 18-bit pieces summed with their weights: the
/// same exact product, with places for registers between blocks and sums.
fn split_product(nodes: &mut Vec<FlatNode>, a: usize, b: usize, ty: Ty, name: &str) -> usize {
    let (ta, tb) = (nodes[a].ty, nodes[b].ty);
    let unsigned = |t: Ty| matches!(t, Ty::UInt(_));
    if !unsigned(ta) || !unsigned(tb) || ta.width().max(tb.width()) <= DSP_BITS {
        return dsp_block(nodes, a, b, ty, name);
    }
    let pieces = |nodes: &mut Vec<FlatNode>, x: usize, tag: &str| -> Vec<(usize, u32)> {
        let w = nodes[x].ty.width();
        (0..w.div_ceil(DSP_BITS))
            .map(|i| {
                let lo = i * DSP_BITS;
                let hi = (lo + DSP_BITS).min(w) - 1;
                let op = Op::Slice(NodeId(x as u32), hi, lo);
                (
                    push(nodes, op, Ty::UInt(hi - lo + 1), format!("{name}_{tag}{i}")),
                    lo,
                )
            })
            .collect()
    };
    let pa = pieces(nodes, a, "a");
    let pb = pieces(nodes, b, "b");
    // (node, weight): every block product, then pairwise sums of equal-width terms
    let mut terms: Vec<(usize, u32)> = Vec::new();
    for &(x, wx) in &pa {
        for &(y, wy) in &pb {
            let (xw, yw) = (nodes[x].ty.width(), nodes[y].ty.width());
            let block = format!("{name}_block{}x{}", wx / DSP_BITS, wy / DSP_BITS);
            let p = if xw.max(yw) <= CORNER_BITS {
                lut_product(nodes, x, y, Ty::UInt(xw + yw), &block)
            } else {
                dsp_block(nodes, x, y, Ty::UInt(xw + yw), &block)
            };
            terms.push((p, wx + wy));
        }
    }
    sum_terms(nodes, terms, ty, name)
}

/// The sum of `terms` (node, weight in bits) as a `ty` value: pairwise, each
/// heavier term shifted onto the lighter one's weight; the lightest term has
/// weight 0 and the sum fits `ty`.
fn sum_terms(nodes: &mut Vec<FlatNode>, mut terms: Vec<(usize, u32)>, ty: Ty, name: &str) -> usize {
    let total = ty.width();
    let mut level = 0;
    while terms.len() > 1 {
        level += 1;
        let mut next = Vec::new();
        for (i, pair) in terms.chunks(2).enumerate() {
            if let [(x, wx), (y, wy)] = *pair {
                // align the heavier term onto the lighter one's weight
                let ((lo, wlo), (hi, whi)) = if wx <= wy {
                    ((x, wx), (y, wy))
                } else {
                    ((y, wy), (x, wx))
                };
                let shifted = if whi > wlo {
                    let z = push(
                        nodes,
                        Op::Const(0),
                        Ty::UInt(whi - wlo),
                        format!("k0_w{}", whi - wlo),
                    );
                    let w = nodes[hi].ty.width() + whi - wlo;
                    push(
                        nodes,
                        Op::Concat(vec![NodeId(hi as u32), NodeId(z as u32)]),
                        Ty::UInt(w),
                        format!("{name}_l{level}_shift{i}"),
                    )
                } else {
                    hi
                };
                let w = nodes[lo].ty.width().max(nodes[shifted].ty.width()) + 1;
                // the partial sums never exceed the product: keep at most its width
                let keep = total.saturating_sub(wlo);
                let sum_name = format!("{name}_l{level}_sum{i}");
                let sum = push(
                    nodes,
                    Op::Add(NodeId(lo as u32), NodeId(shifted as u32)),
                    Ty::UInt(w),
                    match w > keep {
                        true => format!("{sum_name}_carry"),
                        false => sum_name.clone(),
                    },
                );
                let sum = if w > keep {
                    push(
                        nodes,
                        Op::Slice(NodeId(sum as u32), keep - 1, 0),
                        Ty::UInt(keep),
                        sum_name,
                    )
                } else {
                    sum
                };
                next.push((sum, wlo));
            } else {
                next.push(pair[0]);
            }
        }
        terms = next;
    }
    let (p, weight) = terms[0];
    debug_assert_eq!(weight, 0, "the lowest block has weight 0");
    let w = nodes[p].ty.width();
    match w.cmp(&total) {
        std::cmp::Ordering::Equal => p,
        std::cmp::Ordering::Greater => push(
            nodes,
            Op::Slice(NodeId(p as u32), total - 1, 0),
            ty,
            name.to_string(),
        ),
        std::cmp::Ordering::Less => {
            let z = push(
                nodes,
                Op::Const(0),
                Ty::UInt(total - w),
                format!("k0_w{}", total - w),
            );
            push(
                nodes,
                Op::Concat(vec![NodeId(z as u32), NodeId(p as u32)]),
                ty,
                name.to_string(),
            )
        }
    }
}

/// `a · b` (unsigned) as its partial products `a · b_i · 2^i` summed in the
/// fabric ([`CORNER_BITS`]).
fn lut_product(nodes: &mut Vec<FlatNode>, a: usize, b: usize, ty: Ty, name: &str) -> usize {
    let wa = nodes[a].ty.width();
    let wb = nodes[b].ty.width();
    let terms = (0..wb)
        .map(|i| {
            // (a one-bit piece is its own bit: Verilog cannot select from a scalar)
            let bit = if wb == 1 {
                b
            } else {
                push(
                    nodes,
                    Op::Slice(NodeId(b as u32), i, i),
                    Ty::UInt(1),
                    format!("{name}_b{i}"),
                )
            };
            let spread = push(
                nodes,
                Op::Concat(vec![NodeId(bit as u32); wa as usize]),
                Ty::UInt(wa),
                format!("{name}_b{i}_all"),
            );
            let pp = push(
                nodes,
                Op::Bit(
                    crate::ir::BitOp::And,
                    NodeId(a as u32),
                    NodeId(spread as u32),
                ),
                Ty::UInt(wa),
                format!("{name}_pp{i}"),
            );
            (pp, i)
        })
        .collect();
    sum_terms(nodes, terms, ty, name)
}

fn flatten(m: &Module) -> Result<Flat, String> {
    let mut nodes = Vec::new();
    let inputs: Vec<(usize, u32)> = m
        .inputs
        .iter()
        .enumerate()
        .map(|(p, port)| {
            nodes.push(FlatNode {
                op: Op::Input(p),
                ty: port.ty,
                name: port.name.clone(),
                named: true,
                built: Some(0),
                wire: false,
            });
            (p, 0)
        })
        .collect();
    let outs = inline(m, &inputs, "", &mut nodes)?;
    let skip = usize::from(m.handshake.is_some());
    let outputs = m.outputs[skip..]
        .iter()
        .zip(&outs[skip..])
        .map(|((port, _), &(n, _))| (port.clone(), n))
        .collect();
    Ok(Flat {
        nodes,
        outputs,
        in_valid: m.handshake.map(|_| 0),
    })
}

/// Delay of one operation in LUT levels of a 4-input-LUT FPGA with carry
/// chains and 18x18 multipliers (ECP5, iCE40, 7-series alike to first order).
/// Wiring (slices, concatenations, casts) and constants cost nothing.
pub fn delay(op: &Op, ty: Ty, operand_ty: impl Fn(NodeId) -> Ty) -> f64 {
    let w = |id: NodeId| operand_ty(id).width() as f64;
    let carry = |bits: f64| 1.0 + bits / 16.0;
    let tree = |bits: f64| bits.max(2.0).log(4.0).ceil();
    match op {
        Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => 0.0,
        Op::Not(_) | Op::Slice(..) | Op::Concat(_) | Op::Cast(_) => 0.0,
        Op::Bit(..) => 0.5,
        Op::Mux(..) => 0.7,
        Op::Reduce(_, a) => tree(w(*a)),
        Op::Add(a, b) | Op::Sub(a, b) => carry(w(*a).max(w(*b))),
        Op::Cmp(crate::ir::CmpOp::Eq, a, b) => 1.0 + tree(w(*a).max(w(*b))),
        Op::Cmp(_, a, b) => carry(w(*a).max(w(*b))),
        Op::Shl(a, k) | Op::Shr(a, k) => {
            // one 4:1 mux level per two amount bits, at most what the width needs
            let levels = w(*k).min(w(*a).log2().ceil() + 1.0);
            (levels / 2.0).ceil() * 1.2
        }
        Op::Mul(a, b) => {
            let (x, y) = (w(*a), w(*b));
            if !on_dsp(x as u32, y as u32) {
                // a few partial products: an adder tree of LUTs
                1.0 + carry(x.max(y)) * x.min(y).log2().max(1.0)
            } else {
                // 18x18 blocks: the route in and the block (3.2 + 3.9 ns on
                // ECP5-6; the route out is a wire of its own), the blocks of a
                // wider signed product summed by carry chains
                let blocks = (x / 18.0).ceil() * (y / 18.0).ceil();
                DSP_ROUTE + 2.3 + blocks.log2() * carry(ty.width() as f64)
            }
        }
    }
}

/// A stage per node (`None` for constants) and the period it was built for.
struct Schedule {
    stage: Vec<Option<u32>>,
}

/// Every node as early as the period allows.
fn as_soon_as_possible(g: &Graph, period: f64, force: bool) -> Schedule {
    let (flat, live, d) = (&g.flat, &g.live, &g.delay);
    let n = flat.nodes.len();
    let mut stage: Vec<Option<u32>> = vec![None; n];
    let mut arrival = vec![0.0f64; n];
    for i in 0..n {
        if !live[i] {
            continue;
        }
        match flat.nodes[i].op {
            Op::Const(_) => continue,
            Op::Input(_) => {
                stage[i] = Some(0);
                continue;
            }
            _ => {}
        }
        let ops = flat.nodes[i].op.operands();
        let s = ops
            .iter()
            .filter_map(|o| stage[o.0 as usize])
            .max()
            .unwrap_or(0);
        let before = ops
            .iter()
            .filter(|o| stage[o.0 as usize] == Some(s))
            .map(|o| arrival[o.0 as usize])
            .fold(0.0, f64::max);
        if (force && flat.nodes[i].wire) || (before > 0.0 && before + d[i] > period) {
            stage[i] = Some(s + 1);
            arrival[i] = d[i];
        } else {
            stage[i] = Some(s);
            arrival[i] = before + d[i];
        }
    }
    Schedule { stage }
}

/// The mirror image: every node as late as its users allow, outputs at `last`.
fn as_late_as_possible(g: &Graph, period: f64, last: u32, force: bool) -> Option<Schedule> {
    let (flat, live, users, is_output, d) = (&g.flat, &g.live, &g.users, &g.is_output, &g.delay);
    let n = flat.nodes.len();
    // stages counted back from the last one, and delay from the node to its stage's end
    let mut back: Vec<Option<u32>> = vec![None; n];
    let mut after = vec![0.0f64; n];
    for i in (0..n).rev() {
        if !live[i] || matches!(flat.nodes[i].op, Op::Const(_) | Op::Input(_)) {
            continue;
        }
        // a wire starts a stage: its operand is one stage earlier, at the stage's end
        let at = |u: usize| match force && flat.nodes[u].wire {
            true => back[u].map(|r| (r + 1, 0.0)),
            false => back[u].map(|r| (r, after[u])),
        };
        let mut r = if is_output[i] { Some(0) } else { None };
        for &u in &users[i] {
            r = r.max(at(u).map(|(r, _)| r));
        }
        let r = r.unwrap_or(0);
        let behind = users[i]
            .iter()
            .filter_map(|&u| at(u))
            .filter(|&(ru, _)| ru == r)
            .map(|(_, a)| a)
            .fold(0.0, f64::max);
        if behind > 0.0 && behind + d[i] > period {
            back[i] = Some(r + 1);
            after[i] = d[i];
        } else {
            back[i] = Some(r);
            after[i] = behind + d[i];
        }
    }
    let mut stage = vec![None; n];
    for i in 0..n {
        if !live[i] {
            continue;
        }
        match flat.nodes[i].op {
            Op::Const(_) => {}
            Op::Input(_) => stage[i] = Some(0),
            _ => stage[i] = Some(last.checked_sub(back[i]?)?),
        }
    }
    Some(Schedule { stage })
}

fn last_stage(s: &Schedule) -> u32 {
    s.stage.iter().flatten().copied().max().unwrap_or(0)
}

/// Register bits a schedule carries: each value from its stage to its last user's.
fn register_bits(g: &Graph, s: &Schedule, last: u32) -> u64 {
    let (flat, users, is_output) = (&g.flat, &g.users, &g.is_output);
    let mut bits = 0u64;
    for (i, node) in flat.nodes.iter().enumerate() {
        let Some(own) = s.stage[i] else { continue };
        let mut until = if is_output[i] { last } else { own };
        for &u in &users[i] {
            if let Some(su) = s.stage[u] {
                until = until.max(su);
            }
        }
        bits += u64::from(until - own) * u64::from(node.ty.width());
    }
    bits
}

/// What [`balance`] did, for the reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Balance {
    /// longest register-to-register chain of the delay model, LUT levels
    pub period: f64,
}

/// The longest in-stage chain of `flat` under the stages of `s`.
fn period_of(g: &Graph, s: &Schedule) -> f64 {
    let n = g.flat.nodes.len();
    let mut arrival = vec![0.0f64; n];
    let mut worst = 0.0f64;
    for i in 0..n {
        let Some(si) = s.stage[i] else { continue };
        if !g.live[i] {
            continue;
        }
        let before = g.flat.nodes[i]
            .op
            .operands()
            .iter()
            .filter(|o| s.stage[o.0 as usize] == Some(si))
            .map(|o| arrival[o.0 as usize])
            .fold(0.0, f64::max);
        arrival[i] = before + g.delay[i];
        worst = worst.max(arrival[i]);
    }
    worst
}

/// The flattened graph with what scheduling needs.
struct Graph {
    flat: Flat,
    /// read (through other nodes) by an output
    live: Vec<bool>,
    /// drives an output
    is_output: Vec<bool>,
    /// the live nodes reading each node
    users: Vec<Vec<usize>>,
    /// [`delay`] of each node
    delay: Vec<f64>,
}

fn analyse(m: &Module) -> Result<Graph, String> {
    if m.instances.iter().any(|i| has_handshake_below(&i.module)) {
        return Err(format!(
            "module {}: a submodule has its own handshake",
            m.name
        ));
    }
    let flat = flatten(m)?;
    let n = flat.nodes.len();
    let mut live = vec![false; n];
    let mut is_output = vec![false; n];
    for (_, o) in &flat.outputs {
        live[*o] = true;
        is_output[*o] = true;
    }
    for i in (0..n).rev() {
        if live[i] {
            for o in flat.nodes[i].op.operands() {
                live[o.0 as usize] = true;
            }
        }
    }
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        if live[i] {
            for o in flat.nodes[i].op.operands() {
                users[o.0 as usize].push(i);
            }
        }
    }
    let delay: Vec<f64> = flat
        .nodes
        .iter()
        .map(|node| match node.wire {
            true => DSP_ROUTE,
            false => delay(&node.op, node.ty, |id| flat.nodes[id.0 as usize].ty),
        })
        .collect();
    Ok(Graph {
        flat,
        live,
        is_output,
        users,
        delay,
    })
}

/// The delay model's clock period of `m` as it is pipelined: the longest
/// chain of [`delay`]s between two registers, in LUT levels.
pub fn modelled_period(m: &Module) -> Result<f64, String> {
    let g = analyse(m)?;
    let built = Schedule {
        stage: g.flat.nodes.iter().map(|n| n.built).collect(),
    };
    Ok(period_of(&g, &built))
}

/// Re-places the pipeline registers of `m` so that it has `latency` of them
/// (see the module documentation). The result has the same ports and
/// function, `latency` cycles of latency, and no instances.
pub fn balance(m: &Module, latency: u32) -> Result<(Module, Balance), String> {
    let g = analyse(m)?;
    let last = latency;
    // with the DSP output routes starting a stage (a register at every
    // block's pins) where the latency allows it, else as plain logic
    let mut best: Option<(f64, Schedule)> = None;
    for force in [true, false] {
        let asap = |period: f64| as_soon_as_possible(&g, period, force);
        if last_stage(&asap(f64::INFINITY)) > last {
            continue;
        }
        // bisection on the period: the shortest whose ASAP schedule fits the latency
        let longest = period_of(&g, &asap(f64::INFINITY));
        let (mut lo, mut hi) = (
            g.delay.iter().copied().fold(0.0, f64::max),
            longest.max(1e-9),
        );
        if last_stage(&asap(lo)) <= last {
            hi = lo;
        }
        for _ in 0..48 {
            if hi - lo < 1e-3 {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if last_stage(&asap(mid)) <= last {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let period = hi;
        // from both ends of the schedules of this period, the boundaries moved
        // to narrow values; the one with fewer register bits is kept
        let mut schedule: Option<(u64, Schedule)> = None;
        let alap = as_late_as_possible(&g, period, last, force);
        for mut s in std::iter::once(asap(period)).chain(alap) {
            let within = period.max(period_of(&g, &s));
            registers::minimise(&g, &mut s, last, within, force);
            let bits = register_bits(&g, &s, last);
            if schedule.as_ref().is_none_or(|(b, _)| bits < *b) {
                schedule = Some((bits, s));
            }
        }
        let (_, schedule) = schedule.expect("the ASAP schedule");
        let achieved = period_of(&g, &schedule);
        if best.as_ref().is_none_or(|(p, _)| achieved < *p - 1e-6) {
            best = Some((achieved, schedule));
        }
    }
    let (period, best) = best.expect("without forced registers every latency fits");
    let module = replay(m, &g, &best, last).map_err(|e| e.to_string())?;
    Ok((module, Balance { period }))
}

fn has_handshake_below(m: &Module) -> bool {
    m.handshake.is_some() || m.instances.iter().any(|i| has_handshake_below(&i.module))
}

/// Builds the module again from the graph, stage by stage.
fn replay(m: &Module, g: &Graph, s: &Schedule, last: u32) -> Result<Module, BuildErrors> {
    let (flat, live) = (&g.flat, &g.live);
    let mut b = match m.handshake {
        Some(_) => ModuleBuilder::with_handshake(m.name.clone()),
        None => ModuleBuilder::new(m.name.clone()),
    };
    b.describe(m.description.clone());
    for (k, v) in &m.params {
        b.param(k, v);
    }
    let mut order: Vec<usize> = (0..flat.nodes.len())
        .filter(|&i| live[i] || matches!(flat.nodes[i].op, Op::Input(_)))
        .collect();
    order.sort_by_key(|&i| (s.stage[i].unwrap_or(0), i));
    let mut sig: Vec<Option<Sig>> = vec![None; flat.nodes.len()];
    for i in order {
        let node = &flat.nodes[i];
        while b.current_stage() < s.stage[i].unwrap_or(0) {
            b.stage();
        }
        let new = match &node.op {
            Op::Input(_) if Some(i) == flat.in_valid => b.in_valid().expect("handshake"),
            Op::Input(_) => b.input(&node.name, node.ty),
            op => {
                let op = op
                    .clone()
                    .map_operands(|id| sig[id.0 as usize].expect("operands precede users").id());
                b.replay(op, node.ty, &node.name, node.named)
            }
        };
        sig[i] = Some(new);
    }
    while b.current_stage() < last {
        b.stage();
    }
    for (port, o) in &flat.outputs {
        b.output(&port.name, sig[*o].expect("outputs are live"));
    }
    b.finish()
}
