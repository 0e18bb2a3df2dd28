//! Register placement by delay: a module's pipeline registers moved to where
//! its logic is cut into stages of about equal delay.
//!
//! Units place their `stage()` calls by logical steps (after the alignment,
//! after the products, ...); a step that is long, or registers that meet at a
//! module boundary, set the clock. [`balance`] keeps the unit's function and
//! latency and re-places every pipeline register:
//!
//! 1. the module is flattened (instances inlined, their names prefixed with the
//!    instance name) and its pipeline registers removed, which leaves one
//!    combinational graph of the transaction;
//! 2. each operation gets a delay from [`delay`], a model of an FPGA with
//!    4-input LUTs, carry chains and 18x18 multipliers (one LUT level = 1.0);
//! 3. the smallest period `P` whose as-soon-as-possible schedule fits in
//!    `latency` registers is found by bisection (no stage longer than `P`
//!    except where one operation alone is longer); the as-late-as-possible
//!    schedule of the same `P` is built too and the one that carries fewer
//!    register bits is kept;
//! 4. the graph is replayed through a [`ModuleBuilder`] stage by stage, so the
//!    registers that carry values, and the valid chain, are the builder's own.
//!
//! Only feed-forward pipelines are re-timed: a module with a register that has
//! an enable or reads a later value (state) is refused.

use crate::builder::{BuildErrors, ModuleBuilder, Sig};
use crate::ir::{Module, NodeId, Op, Port, Ty};
use std::collections::HashMap;

/// One operation of the flattened transaction graph; operands index the graph.
#[derive(Debug, Clone)]
struct FlatNode {
    op: Op,
    ty: Ty,
    name: String,
}

/// The flattened, register-free graph of a module.
struct Flat {
    nodes: Vec<FlatNode>,
    /// data outputs (without `out_valid`) and the node driving each
    outputs: Vec<(Port, usize)>,
    /// node of `in_valid` when the module has the handshake
    in_valid: Option<usize>,
}

/// Inlines `m` into `nodes`, its input ports read from `inputs`; returns the
/// node of each of its outputs.
fn inline(
    m: &Module,
    inputs: &[usize],
    prefix: &str,
    nodes: &mut Vec<FlatNode>,
) -> Result<Vec<usize>, String> {
    let mut map: Vec<usize> = Vec::with_capacity(m.nodes.len());
    let mut inlined: HashMap<usize, Vec<usize>> = HashMap::new();
    let operand = |map: &Vec<usize>, id: NodeId| map[id.0 as usize];
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
                // transaction's value: in the graph it is that value
                operand(&map, reg.next)
            }
            Op::InstOut { inst, port } => {
                if !inlined.contains_key(inst) {
                    let instance = &m.instances[*inst];
                    let ins: Vec<usize> =
                        instance.inputs.iter().map(|&id| operand(&map, id)).collect();
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
                let op = remap(op.clone(), |id| NodeId(operand(&map, id) as u32));
                let name = match op {
                    Op::Const(_) => node.name.clone(),
                    _ => format!("{prefix}{}", node.name),
                };
                nodes.push(FlatNode {
                    op,
                    ty: node.ty,
                    name,
                });
                nodes.len() - 1
            }
        };
        map.push(flat);
    }
    Ok(m.outputs.iter().map(|(_, id)| map[id.0 as usize]).collect())
}

fn flatten(m: &Module) -> Result<Flat, String> {
    let mut nodes = Vec::new();
    let inputs: Vec<usize> = m
        .inputs
        .iter()
        .enumerate()
        .map(|(p, port)| {
            nodes.push(FlatNode {
                op: Op::Input(p),
                ty: port.ty,
                name: port.name.clone(),
            });
            p
        })
        .collect();
    let outs = inline(m, &inputs, "", &mut nodes)?;
    let skip = usize::from(m.handshake.is_some());
    let outputs = m.outputs[skip..]
        .iter()
        .zip(&outs[skip..])
        .map(|((port, _), &n)| (port.clone(), n))
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
            if x.min(y) <= 4.0 {
                // a few partial products: an adder tree of LUTs
                1.0 + carry(x.max(y)) * x.min(y).log2().max(1.0)
            } else {
                // 18x18 blocks, partial products summed by carry chains
                let blocks = (x / 18.0).ceil() * (y / 18.0).ceil();
                4.0 + blocks.log2() * carry(ty.width() as f64)
            }
        }
    }
}

/// A stage per node (`None` for constants) and the period it was built for.
struct Schedule {
    stage: Vec<Option<u32>>,
}

/// Longest chain of delays inside one stage if node `n` starts it.
fn as_soon_as_possible(flat: &Flat, live: &[bool], d: &[f64], period: f64) -> Schedule {
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
        if before > 0.0 && before + d[i] > period {
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
fn as_late_as_possible(
    flat: &Flat,
    live: &[bool],
    users: &[Vec<usize>],
    is_output: &[bool],
    d: &[f64],
    period: f64,
    last: u32,
) -> Option<Schedule> {
    let n = flat.nodes.len();
    // stages counted back from the last one, and delay from the node to its stage's end
    let mut back: Vec<Option<u32>> = vec![None; n];
    let mut after = vec![0.0f64; n];
    for i in (0..n).rev() {
        if !live[i] || matches!(flat.nodes[i].op, Op::Const(_) | Op::Input(_)) {
            continue;
        }
        let mut r = if is_output[i] { Some(0) } else { None };
        for &u in &users[i] {
            r = r.max(back[u]);
        }
        let r = r.unwrap_or(0);
        let behind = users[i]
            .iter()
            .filter(|&&u| back[u] == Some(r))
            .map(|&u| after[u])
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
fn register_bits(flat: &Flat, s: &Schedule, users: &[Vec<usize>], is_output: &[bool], last: u32) -> u64 {
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

/// What [`balance`] did, for the Verilog header and the reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Balance {
    /// longest register-to-register chain of the model before, LUT levels
    pub period_before: f64,
    /// the same after
    pub period_after: f64,
    /// pipeline register bits after
    pub register_bits: u64,
}

/// The longest in-stage chain of `flat` under the stages of `s`.
fn period_of(flat: &Flat, live: &[bool], d: &[f64], s: &Schedule) -> f64 {
    let n = flat.nodes.len();
    let mut arrival = vec![0.0f64; n];
    let mut worst = 0.0f64;
    for i in 0..n {
        let Some(si) = s.stage[i] else { continue };
        if !live[i] {
            continue;
        }
        let before = flat.nodes[i]
            .op
            .operands()
            .iter()
            .filter(|o| s.stage[o.0 as usize] == Some(si))
            .map(|o| arrival[o.0 as usize])
            .fold(0.0, f64::max);
        arrival[i] = before + d[i];
        worst = worst.max(arrival[i]);
    }
    worst
}

/// Stage of every node of the flattened graph as the unit placed it: the
/// number of registers between the inputs and the node.
fn stages_as_built(m: &Module, flat_len: usize) -> Option<Schedule> {
    // walks the same order as `inline`, counting registers instead of removing them
    fn walk(
        m: &Module,
        inputs: &[(usize, u32)],
        out: &mut Vec<Option<u32>>,
    ) -> Vec<(usize, u32)> {
        let mut map: Vec<(usize, u32)> = Vec::with_capacity(m.nodes.len());
        let mut inlined: HashMap<usize, Vec<(usize, u32)>> = HashMap::new();
        for node in &m.nodes {
            let v = match &node.op {
                Op::Input(p) => inputs[*p],
                Op::Reg(r) => {
                    let (id, s) = map[m.registers[*r].next.0 as usize];
                    (id, s + 1)
                }
                Op::InstOut { inst, port } => {
                    if !inlined.contains_key(inst) {
                        let instance = &m.instances[*inst];
                        let ins: Vec<(usize, u32)> =
                            instance.inputs.iter().map(|id| map[id.0 as usize]).collect();
                        let outs = walk(&instance.module, &ins, out);
                        inlined.insert(*inst, outs);
                    }
                    inlined[inst][*port]
                }
                op => {
                    let s = op
                        .operands()
                        .iter()
                        .map(|o| map[o.0 as usize])
                        .filter(|(id, _)| out[*id].is_some())
                        .map(|(_, s)| s)
                        .max()
                        .unwrap_or(0);
                    let konst = matches!(op, Op::Const(_));
                    out.push(if konst { None } else { Some(s) });
                    (out.len() - 1, s)
                }
            };
            map.push(v);
        }
        m.outputs.iter().map(|(_, id)| map[id.0 as usize]).collect()
    }
    let mut out: Vec<Option<u32>> = (0..m.inputs.len()).map(|_| Some(0)).collect();
    let inputs: Vec<(usize, u32)> = (0..m.inputs.len()).map(|p| (p, 0)).collect();
    walk(m, &inputs, &mut out);
    (out.len() == flat_len).then_some(Schedule { stage: out })
}

/// Re-places the pipeline registers of `m` (see the module documentation).
/// The result has the same ports, latency and function, and no instances.
pub fn balance(m: &Module) -> Result<(Module, Balance), String> {
    if m.instances.iter().any(|i| has_handshake_below(&i.module)) {
        return Err(format!("module {}: a submodule has its own handshake", m.name));
    }
    let flat = flatten(m)?;
    let n = flat.nodes.len();
    let last = m.latency;
    // live nodes: those an output reads
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
    let d: Vec<f64> = flat
        .nodes
        .iter()
        .map(|node| delay(&node.op, node.ty, |id| flat.nodes[id.0 as usize].ty))
        .collect();
    let before = stages_as_built(m, n)
        .map(|s| period_of(&flat, &live, &d, &s))
        .unwrap_or(f64::NAN);
    // bisection on the period: the shortest whose ASAP schedule fits the latency
    let longest = period_of(&flat, &live, &d, &as_soon_as_possible(&flat, &live, &d, f64::INFINITY));
    let (mut lo, mut hi) = (d.iter().copied().fold(0.0, f64::max), longest.max(1e-9));
    if last_stage(&as_soon_as_possible(&flat, &live, &d, lo)) <= last {
        hi = lo;
    }
    for _ in 0..48 {
        if hi - lo < 1e-3 {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if last_stage(&as_soon_as_possible(&flat, &live, &d, mid)) <= last {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let period = hi;
    let asap = as_soon_as_possible(&flat, &live, &d, period);
    let mut best = asap;
    let mut bits = register_bits(&flat, &best, &users, &is_output, last);
    if let Some(alap) = as_late_as_possible(&flat, &live, &users, &is_output, &d, period, last) {
        let alap_bits = register_bits(&flat, &alap, &users, &is_output, last);
        if alap_bits < bits {
            best = alap;
            bits = alap_bits;
        }
    }
    let after = period_of(&flat, &live, &d, &best);
    let module = replay(m, &flat, &live, &best, last).map_err(|e| e.to_string())?;
    Ok((
        module,
        Balance {
            period_before: before,
            period_after: after,
            register_bits: bits,
        },
    ))
}

fn has_handshake_below(m: &Module) -> bool {
    m.handshake.is_some() || m.instances.iter().any(|i| has_handshake_below(&i.module))
}

/// Builds the module again from the graph, stage by stage.
fn replay(
    m: &Module,
    flat: &Flat,
    live: &[bool],
    s: &Schedule,
    last: u32,
) -> Result<Module, BuildErrors> {
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
                let op = remap(op.clone(), |id| {
                    sig[id.0 as usize].expect("operands precede users").id()
                });
                b.replay(op, node.ty, &node.name)
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

fn remap(op: Op, f: impl FnMut(NodeId) -> NodeId) -> Op {
    op.map_operands(f)
}
