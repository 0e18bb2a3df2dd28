//! The intermediate representation: a module is an arena of nodes in
//! topological order, plus ports, registers and instances.
//!
//! Everything above this file (builder, operators, units) produces it; the
//! emitter and the evaluator read it and nothing above it.

pub mod identifier;

pub use identifier::is_identifier;
use std::collections::BTreeMap;
use std::fmt;
use std::panic::Location;
use std::sync::Arc;

/// Widest value the IR carries (constants, evaluator); wider values are built
/// by concatenation and never needed by the units so far.
pub const MAX_WIDTH: u32 = 128;

/// The type of a hardware value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Ty {
    /// One bit used as a truth value.
    Bool,
    /// Unsigned bit vector of the given width.
    UInt(u32),
    /// Two's complement bit vector of the given width.
    SInt(u32),
}

impl Ty {
    /// Number of bits.
    pub fn width(self) -> u32 {
        match self {
            Ty::Bool => 1,
            Ty::UInt(w) | Ty::SInt(w) => w,
        }
    }

    /// True for two's complement values.
    pub fn is_signed(self) -> bool {
        matches!(self, Ty::SInt(_))
    }

    /// The same signedness at another width (`Bool` widens to `UInt`).
    pub fn with_width(self, w: u32) -> Ty {
        match self {
            Ty::SInt(_) => Ty::SInt(w),
            Ty::Bool | Ty::UInt(_) => Ty::UInt(w),
        }
    }
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ty::Bool => write!(f, "Bool"),
            Ty::UInt(w) => write!(f, "UInt<{w}>"),
            Ty::SInt(w) => write!(f, "SInt<{w}>"),
        }
    }
}

/// Index of a node in its module's arena.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeId(pub u32);

/// Reduction operators (the result is `Bool`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReduceOp {
    /// all bits set
    And,
    /// any bit set
    Or,
    /// odd number of bits set
    Xor,
}

/// Bitwise operators on two operands of the same type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BitOp {
    /// a & b
    And,
    /// a | b
    Or,
    /// a ^ b
    Xor,
}

/// Comparisons; the operands share signedness and are extended to the wider width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    /// a == b
    Eq,
    /// a < b
    Lt,
    /// a <= b
    Le,
}

/// Every operation of the IR. Matched without a `_` arm by the emitter and the
/// evaluator, so a new operation does not compile until both handle it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Op {
    /// Data input port number `n` of the module.
    Input(usize),
    /// A constant; the bits above the node's width are zero.
    Const(u128),
    /// The output of register `n` of the module.
    Reg(usize),
    /// Output port `port` of instance `inst`.
    InstOut {
        /// instance index
        inst: usize,
        /// output port index of the instantiated module
        port: usize,
    },
    /// a + b, one bit wider than the wider operand (never wraps).
    Add(NodeId, NodeId),
    /// a − b as a signed value one bit wider than the wider operand (never wraps).
    Sub(NodeId, NodeId),
    /// a · b, full product: width is the sum of the operand widths.
    Mul(NodeId, NodeId),
    /// Bitwise complement, same type.
    Not(NodeId),
    /// Bitwise operation, same type as the operands.
    Bit(BitOp, NodeId, NodeId),
    /// Comparison, `Bool`.
    Cmp(CmpOp, NodeId, NodeId),
    /// a << b, width of a (bits shifted out are lost); b unsigned.
    Shl(NodeId, NodeId),
    /// a >> b, width of a; logical for unsigned a, arithmetic for signed a.
    Shr(NodeId, NodeId),
    /// sel ? t : f, type of t and f.
    Mux(NodeId, NodeId, NodeId),
    /// Concatenation, first operand most significant; unsigned, sum of widths.
    Concat(Vec<NodeId>),
    /// Bits hi..=lo of a, unsigned, hi − lo + 1 wide.
    Slice(NodeId, u32, u32),
    /// Reduction of all bits, `Bool`.
    Reduce(ReduceOp, NodeId),
    /// The same bits read as the node's type (same width, other signedness or Bool).
    Cast(NodeId),
}

impl Op {
    /// The nodes this operation reads.
    pub fn operands(&self) -> Vec<NodeId> {
        match self {
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => vec![],
            Op::Not(a) | Op::Slice(a, _, _) | Op::Reduce(_, a) | Op::Cast(a) => vec![*a],
            Op::Add(a, b)
            | Op::Sub(a, b)
            | Op::Mul(a, b)
            | Op::Bit(_, a, b)
            | Op::Cmp(_, a, b)
            | Op::Shl(a, b)
            | Op::Shr(a, b) => vec![*a, *b],
            Op::Mux(s, t, f) => vec![*s, *t, *f],
            Op::Concat(v) => v.clone(),
        }
    }
}

impl Op {
    /// The same operation with every operand passed through `f`.
    pub fn map_operands(self, mut f: impl FnMut(NodeId) -> NodeId) -> Op {
        match self {
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => self,
            Op::Add(a, b) => Op::Add(f(a), f(b)),
            Op::Sub(a, b) => Op::Sub(f(a), f(b)),
            Op::Mul(a, b) => Op::Mul(f(a), f(b)),
            Op::Not(a) => Op::Not(f(a)),
            Op::Bit(o, a, b) => Op::Bit(o, f(a), f(b)),
            Op::Cmp(o, a, b) => Op::Cmp(o, f(a), f(b)),
            Op::Shl(a, b) => Op::Shl(f(a), f(b)),
            Op::Shr(a, b) => Op::Shr(f(a), f(b)),
            Op::Mux(s, t, e) => Op::Mux(f(s), f(t), f(e)),
            Op::Concat(v) => Op::Concat(v.into_iter().map(f).collect()),
            Op::Slice(a, h, l) => Op::Slice(f(a), h, l),
            Op::Reduce(o, a) => Op::Reduce(o, f(a)),
            Op::Cast(a) => Op::Cast(f(a)),
        }
    }
}

/// One node: an operation, its result type, its name (given by the generator
/// code, or derived from the operation and its operands' names; the emitter
/// makes names unique), and where in the Rust source it was built.
#[derive(Debug, Clone)]
pub struct Node {
    /// what the node computes
    pub op: Op,
    /// result type
    pub ty: Ty,
    /// name given or derived
    pub name: String,
    /// true when the name was given (a port, a register, `name()`), false
    /// when derived from the operation: the emitter may write a derived,
    /// once-read value inside its reader's expression instead of as a wire
    pub named: bool,
    /// the Rust source line that built it
    pub location: &'static Location<'static>,
}

/// A port of a module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Port {
    /// port name (a Verilog identifier)
    pub name: String,
    /// port type
    pub ty: Ty,
}

/// A register: rising edge of `clk`, optional synchronous active-high reset
/// and optional enable.
#[derive(Debug, Clone)]
pub struct Register {
    /// register name
    pub name: String,
    /// type
    pub ty: Ty,
    /// value loaded at each enabled rising edge
    pub next: NodeId,
    /// value loaded while `rst` is high; `None` means the register is not reset
    pub reset: Option<u128>,
    /// load only when this `Bool` is true; `None` means every cycle
    pub enable: Option<NodeId>,
}

/// An instance of another module.
#[derive(Debug, Clone)]
pub struct Instance {
    /// instance name
    pub name: String,
    /// the instantiated module
    pub module: Arc<Module>,
    /// one node per data input port of `module`
    pub inputs: Vec<NodeId>,
}

/// Pipeline handshake of a module built with valid ports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Handshake {
    /// cycles from `in_valid` to `out_valid` (with `ready`: while `out_ready`
    /// stays high)
    pub latency: u32,
    /// true for valid/ready: `out_ready` is data input 1 and `in_ready` data
    /// output 1 (docs/handshake.md); false for valid only (no backpressure)
    pub ready: bool,
}

impl Handshake {
    /// How many ports of each direction the handshake takes: in_valid (and
    /// out_ready) in, out_valid (and in_ready) out.
    pub fn control_ports(self) -> usize {
        1 + usize::from(self.ready)
    }
}

/// A generated module.
#[derive(Debug, Clone)]
pub struct Module {
    /// module name; carries its parameters (e.g. `umul_16x16_s1`)
    pub name: String,
    /// human-readable description for the header
    pub description: String,
    /// parameters that produced it, for the header and the port list
    pub params: BTreeMap<String, String>,
    /// data inputs (clock, reset and valid are implicit)
    pub inputs: Vec<Port>,
    /// data outputs and the node each is driven by
    pub outputs: Vec<(Port, NodeId)>,
    /// node arena in topological order (operands precede users)
    pub nodes: Vec<Node>,
    /// registers
    pub registers: Vec<Register>,
    /// submodule instances
    pub instances: Vec<Instance>,
    /// cycles from inputs to outputs
    pub latency: u32,
    /// `Some` when the module has `in_valid`/`out_valid` ports; the valid
    /// input is data input 0 and the valid output is data output 0 in the IR,
    /// named `in_valid`/`out_valid`
    pub handshake: Option<Handshake>,
    /// `Some` when a vendor's cells implement this module in synthesis
    pub vendor: Option<VendorBody>,
}

/// A vendor's cells (FPGA primitives) that implement a module in synthesis.
/// The module's own nodes and registers stay its behaviour: the evaluator,
/// the re-timer and simulation read them, and the emitter writes both, the
/// cells under `` `ifdef SYNTHESIS `` (which Yosys defines and Verilator and
/// Icarus do not).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VendorBody {
    /// whose cell library the cells come from (synthesis reads it)
    pub library: CellLibrary,
    /// nets between cells, with their widths
    pub nets: Vec<(String, u32)>,
    /// the cells, in the order written
    pub cells: Vec<VendorCell>,
}

/// An FPGA family whose primitives a [`VendorBody`] instantiates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellLibrary {
    /// Lattice ECP5 (`MULT18X18D`)
    Ecp5,
    /// AMD/Xilinx 7-series (`DSP48E1`, `LUT6`, `CARRY4`)
    Xc7,
}

/// One vendor cell.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VendorCell {
    /// cell type, e.g. `MULT18X18D`
    pub cell: String,
    /// instance name
    pub name: String,
    /// parameters, each value a Verilog constant as written (`"CLK0"` with
    /// its quotes, `64'h8000000000000000`, `0`)
    pub params: Vec<(String, String)>,
    /// the connected pins, in order, each its bits from the least
    /// significant (one bit: a scalar); a pin not listed is left open
    pub pins: Vec<(String, Vec<CellPin>)>,
}

/// What one pin bit of a [`VendorCell`] connects to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellPin {
    /// the module's clock
    Clock,
    /// a constant bit
    Const(bool),
    /// bit `bit` of data input `port`
    Input {
        /// index into the module's inputs
        port: usize,
        /// bit of that input
        bit: u32,
    },
    /// drives bit `bit` of data output `port`
    Output {
        /// index into the module's outputs
        port: usize,
        /// bit of that output
        bit: u32,
    },
    /// bit `bit` of the body's net `net`
    Net {
        /// index into [`VendorBody::nets`]
        net: usize,
        /// bit of that net
        bit: u32,
    },
}

/// Names of the implicit control ports.
pub mod control {
    /// rising-edge clock
    pub const CLOCK: &str = "clk";
    /// synchronous, active-high reset
    pub const RESET: &str = "rst";
    /// a transaction is presented this cycle
    pub const IN_VALID: &str = "in_valid";
    /// results of a transaction are presented this cycle
    pub const OUT_VALID: &str = "out_valid";
    /// valid/ready only: the module takes a transaction at this edge if `in_valid` is high
    pub const IN_READY: &str = "in_ready";
    /// valid/ready only: the consumer takes the result at this edge if `out_valid` is high
    pub const OUT_READY: &str = "out_ready";
}

impl Module {
    /// The node with this id.
    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.0 as usize]
    }

    /// True if the module (or any submodule) holds state, so it needs `clk`.
    pub fn is_sequential(&self) -> bool {
        !self.registers.is_empty() || self.instances.iter().any(|i| i.module.is_sequential())
    }

    /// True if some register (here or below) is reset, so it needs `rst`.
    pub fn uses_reset(&self) -> bool {
        self.registers.iter().any(|r| r.reset.is_some())
            || self.instances.iter().any(|i| i.module.uses_reset())
    }

    /// Data inputs without the handshake's (`in_valid`, `out_ready`).
    pub fn data_inputs(&self) -> &[Port] {
        match self.handshake {
            Some(hs) => &self.inputs[hs.control_ports()..],
            None => &self.inputs,
        }
    }

    /// Data outputs without the handshake's (`out_valid`, `in_ready`).
    pub fn data_outputs(&self) -> &[(Port, NodeId)] {
        match self.handshake {
            Some(hs) => &self.outputs[hs.control_ports()..],
            None => &self.outputs,
        }
    }

    /// Every module in the hierarchy below and including this one, each once,
    /// submodules before the modules that instantiate them.
    pub fn hierarchy(&self) -> Vec<&Module> {
        fn walk<'a>(m: &'a Module, out: &mut Vec<&'a Module>) {
            for inst in &m.instances {
                walk(&inst.module, out);
            }
            if !out.iter().any(|seen| seen.name == m.name) {
                out.push(m);
            }
        }
        let mut out = Vec::new();
        walk(self, &mut out);
        out
    }

    /// Checks the structural invariants the emitter and evaluator rely on.
    pub fn check_well_formed(&self) -> Result<(), String> {
        let n = self.nodes.len();
        for (i, node) in self.nodes.iter().enumerate() {
            for op in node.op.operands() {
                if op.0 as usize >= i {
                    return Err(format!(
                        "module {}: node {i} reads node {} which does not precede it",
                        self.name, op.0
                    ));
                }
            }
            let w = node.ty.width();
            if w == 0 || w > MAX_WIDTH {
                return Err(format!("module {}: node {i} has width {w}", self.name));
            }
            match node.op {
                Op::Input(p) if p >= self.inputs.len() => {
                    return Err(format!("module {}: node {i} reads input {p}", self.name))
                }
                Op::Reg(r) if r >= self.registers.len() => {
                    return Err(format!("module {}: node {i} reads register {r}", self.name))
                }
                _ => {}
            }
        }
        let names = std::iter::once(("module", self.name.as_str()))
            .chain(self.inputs.iter().map(|p| ("input", p.name.as_str())))
            .chain(
                self.outputs
                    .iter()
                    .map(|(p, _)| ("output", p.name.as_str())),
            )
            .chain(self.registers.iter().map(|r| ("register", r.name.as_str())))
            .chain(self.instances.iter().map(|i| ("instance", i.name.as_str())));
        for (what, name) in names {
            if !is_identifier(name) {
                return Err(format!(
                    "module {}: {what} `{name}` is not a Verilog identifier Verilator accepts",
                    self.name
                ));
            }
        }
        let in_range = |id: NodeId| (id.0 as usize) < n;
        for r in &self.registers {
            if !in_range(r.next) || r.enable.is_some_and(|e| !in_range(e)) {
                return Err(format!(
                    "module {}: register {} reads a missing node",
                    self.name, r.name
                ));
            }
        }
        for (p, id) in &self.outputs {
            if !in_range(*id) {
                return Err(format!(
                    "module {}: output {} reads a missing node",
                    self.name, p.name
                ));
            }
        }
        if let Some(body) = &self.vendor {
            for cell in &body.cells {
                for (pin, bits) in &cell.pins {
                    let fits = |c: &CellPin| match *c {
                        CellPin::Clock | CellPin::Const(_) => true,
                        CellPin::Input { port, bit } => {
                            self.inputs.get(port).is_some_and(|p| bit < p.ty.width())
                        }
                        CellPin::Output { port, bit } => self
                            .outputs
                            .get(port)
                            .is_some_and(|(p, _)| bit < p.ty.width()),
                        CellPin::Net { net, bit } => body.nets.get(net).is_some_and(|n| bit < n.1),
                    };
                    if bits.is_empty() || !bits.iter().all(fits) {
                        return Err(format!(
                            "module {}: pin {pin} of its {} {} connects to a missing bit",
                            self.name, cell.cell, cell.name
                        ));
                    }
                }
            }
        }
        for inst in &self.instances {
            if inst.inputs.len() != inst.module.inputs.len() {
                return Err(format!(
                    "module {}: instance {} connects {} of {} inputs",
                    self.name,
                    inst.name,
                    inst.inputs.len(),
                    inst.module.inputs.len()
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::builder::ModuleBuilder;
    use crate::ir::Ty;

    /// A name the builder would refuse, written into the IR directly, is
    /// caught before emission: `near` is a C++ word Verilator rejects.
    #[test]
    fn well_formed_modules_have_identifiers_for_names() {
        let mut m = ModuleBuilder::new("names");
        let a = m.input("a", Ty::UInt(4));
        m.output("z", a);
        let mut module = m.finish().unwrap();
        assert_eq!(module.check_well_formed(), Ok(()));
        module.inputs[0].name = "near".into();
        let e = module.check_well_formed().unwrap_err();
        assert!(e.contains("input `near`"), "{e}");
        module.inputs[0].name = "a".into();
        module.name = "module".into();
        assert!(module.check_well_formed().is_err());
    }
}
