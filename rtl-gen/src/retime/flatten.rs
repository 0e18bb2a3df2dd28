//! Flattening: a module's instances inlined and its pipeline registers
//! removed, which leaves one combinational graph of the transaction; wide
//! products are split on the way ([`split_product`]).

use super::split::split_product;
use super::Products;
use crate::ir::{Module, NodeId, Op, Port, Ty};
use std::collections::HashMap;

/// One operation of the flattened transaction graph; operands index the graph.
#[derive(Debug, Clone)]
pub(super) struct FlatNode {
    pub(super) op: Op,
    pub(super) ty: Ty,
    pub(super) name: String,
    /// the name was given, not derived ([`Node::named`])
    pub(super) named: bool,
    /// the stage the unit's own plan computes it in (`None` for constants)
    pub(super) built: Option<u32>,
    /// a same-bits cast standing for the route from a DSP block's output
    /// ([`DSP_ROUTE`]); it always starts a stage
    pub(super) wire: bool,
}

/// The flattened, register-free graph of a module.
pub(super) struct Flat {
    pub(super) nodes: Vec<FlatNode>,
    /// data outputs (without `out_valid`) and the node driving each
    pub(super) outputs: Vec<(Port, usize)>,
    /// node of `in_valid` when the module has the handshake
    pub(super) in_valid: Option<usize>,
}

/// Inlines `m` into `nodes`, its input ports read from `inputs` (node, and
/// the stage the value is in there); returns the same of each output.
fn inline(
    m: &Module,
    inputs: &[(usize, u32)],
    prefix: &str,
    nodes: &mut Vec<FlatNode>,
    products: Products,
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
                        products,
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
                    Op::Mul(a, b) if products == Products::Split => split_product(
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

pub(super) fn push(nodes: &mut Vec<FlatNode>, op: Op, ty: Ty, name: String) -> usize {
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

pub(super) fn flatten(m: &Module, products: Products) -> Result<Flat, String> {
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
    let outs = inline(m, &inputs, "", &mut nodes, products)?;
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
