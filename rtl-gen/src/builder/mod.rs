//! The DSL: a module builder that records typed operations into the IR.
//!
//! Operations check their operand types when the generator runs. A type or
//! width error does not stop the build: it is recorded with the signal name
//! and the Rust source line (`#[track_caller]`), and [`ModuleBuilder::finish`]
//! returns all of them.
//!
//! Pipelining is first class: [`ModuleBuilder::stage`] closes a pipeline
//! stage. Every value lives in the stage it was computed in; reading it in a
//! later stage inserts (and shares) the registers that carry it there, so
//! exactly the values live across a boundary are registered, together with
//! the `valid` bit. The latency of the module is the number of stages closed.

mod names;
mod ops;
mod pipeline;

use crate::eval::eval_op;
use crate::ir::*;
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::panic::Location;
use std::sync::Arc;

/// A typed handle to a value in the module being built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sig {
    id: NodeId,
    ty: Ty,
}

impl Sig {
    /// The value's type.
    pub fn ty(self) -> Ty {
        self.ty
    }
    /// The value's width in bits.
    pub fn width(self) -> u32 {
        self.ty.width()
    }
    /// The IR node.
    pub fn id(self) -> NodeId {
        self.id
    }
}

/// A generator error: what went wrong, on which signal, and the Rust line that built it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DslError {
    /// module being built
    pub module: String,
    /// the signal concerned (derived or given name)
    pub signal: String,
    /// what is wrong
    pub message: String,
    /// Rust source location of the offending call
    pub location: &'static Location<'static>,
}

impl fmt::Display for DslError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: module `{}`, signal `{}`: {}",
            self.location.file(),
            self.location.line(),
            self.location.column(),
            self.module,
            self.signal,
            self.message
        )
    }
}

/// All errors of one build.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BuildErrors(pub Vec<DslError>);

impl fmt::Display for BuildErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{e}")?;
        }
        Ok(())
    }
}

impl std::error::Error for BuildErrors {}

/// A register created with [`ModuleBuilder::reg`], to be given its next value.
#[derive(Debug, Clone, Copy)]
pub struct RegHandle {
    index: usize,
    /// the register's current value
    pub q: Sig,
}

/// Outputs of an instance, looked up by port name.
#[derive(Debug, Clone)]
pub struct InstanceOutputs {
    names: Vec<String>,
    sigs: Vec<Sig>,
}

/// An instance's outputs in port order. Read them through the module's
/// output record ([`crate::ports::instance`]); a wrapper that mirrors any
/// module walks them by [`InstanceOutputs::named`]. There is no look-up by
/// name: a port named in two places could drift.
impl InstanceOutputs {
    /// Every output with its port name, in port order.
    pub fn named(&self) -> impl Iterator<Item = (&str, Sig)> {
        self.names
            .iter()
            .map(String::as_str)
            .zip(self.sigs.iter().copied())
    }
    /// All outputs in port order.
    pub fn all(&self) -> &[Sig] {
        &self.sigs
    }
}

/// Builds one [`Module`].
pub struct ModuleBuilder {
    name: String,
    description: String,
    params: BTreeMap<String, String>,
    inputs: Vec<Port>,
    outputs: Vec<(Port, NodeId)>,
    nodes: Vec<Node>,
    /// stage each node is computed in; `None` for constants (valid in every stage)
    stage_of: Vec<Option<u32>>,
    registers: Vec<Register>,
    /// registers created by `reg` that still lack a next value
    pending_regs: Vec<(usize, &'static Location<'static>)>,
    instances: Vec<Instance>,
    errors: Vec<DslError>,
    current_stage: u32,
    /// (node, stage) -> the node carried into that stage by pipeline registers
    carried: HashMap<(NodeId, u32), NodeId>,
    constants: HashMap<(Ty, u128), NodeId>,
    /// valid bit per stage, when the module has a handshake
    valid: Option<Vec<NodeId>>,
    /// the valid/ready handshake's latency and, once given, its outputs
    /// (`out_valid`, `in_ready`) ([`ModuleBuilder::with_ready_handshake`])
    ready: Option<(u32, Option<(NodeId, NodeId)>)>,
    /// the naming scopes open now, outermost first ([`ModuleBuilder::scope`])
    scopes: Vec<String>,
}

impl ModuleBuilder {
    /// Starts a module without valid ports (a datapath meant to be instantiated).
    pub fn new(name: impl Into<String>) -> Self {
        ModuleBuilder {
            name: name.into(),
            description: String::new(),
            params: BTreeMap::new(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            nodes: Vec::new(),
            stage_of: Vec::new(),
            registers: Vec::new(),
            pending_regs: Vec::new(),
            instances: Vec::new(),
            errors: Vec::new(),
            current_stage: 0,
            carried: HashMap::new(),
            constants: HashMap::new(),
            valid: None,
            ready: None,
            scopes: Vec::new(),
        }
    }

    /// `name` inside the open scopes.
    fn scoped(&self, name: &str) -> String {
        match self.scopes.is_empty() {
            true => name.to_string(),
            false => format!("{}_{name}", self.scopes.join("_")),
        }
    }

    /// Starts a module with the `in_valid`/`out_valid` handshake (a top-level unit).
    #[track_caller]
    pub fn with_handshake(name: impl Into<String>) -> Self {
        let mut b = Self::new(name);
        let v = b.input(control::IN_VALID, Ty::Bool);
        b.valid = Some(vec![v.id]);
        b
    }

    /// Starts a module with the valid/ready handshake: inputs `in_valid` and
    /// `out_ready` (returned in that order), outputs `out_valid` and
    /// `in_ready` given by [`ModuleBuilder::ready_outputs`]. The module keeps
    /// its own time with explicit registers (no pipeline stages); `latency`
    /// is the cycles from `in_valid` to `out_valid` while `out_ready` stays
    /// high, written in its header and port list.
    #[track_caller]
    pub fn with_ready_handshake(name: impl Into<String>, latency: u32) -> (Self, Sig, Sig) {
        let mut b = Self::new(name);
        let in_valid = b.input(control::IN_VALID, Ty::Bool);
        let out_ready = b.input(control::OUT_READY, Ty::Bool);
        b.ready = Some((latency, None));
        (b, in_valid, out_ready)
    }

    /// The `out_valid` and `in_ready` outputs of a module started with
    /// [`ModuleBuilder::with_ready_handshake`].
    #[track_caller]
    pub fn ready_outputs(&mut self, out_valid: Sig, in_ready: Sig) {
        match &mut self.ready {
            Some((_, outs @ None)) if out_valid.ty == Ty::Bool && in_ready.ty == Ty::Bool => {
                *outs = Some((out_valid.id, in_ready.id))
            }
            Some((_, None)) => self.error(control::OUT_VALID, "out_valid and in_ready are Bool"),
            Some((_, Some(_))) => self.error(control::OUT_VALID, "ready outputs given twice"),
            None => self.error(
                control::OUT_VALID,
                "ready outputs of a module without the valid/ready handshake",
            ),
        }
    }

    /// Sets the one-paragraph description written in the Verilog header.
    pub fn describe(&mut self, text: impl Into<String>) -> &mut Self {
        self.description = text.into();
        self
    }

    /// Records a parameter for the header and the port list.
    pub fn param(&mut self, key: impl Into<String>, value: impl ToString) -> &mut Self {
        self.params.insert(key.into(), value.to_string());
        self
    }

    #[track_caller]
    fn error(&mut self, signal: impl Into<String>, message: impl Into<String>) {
        self.errors.push(DslError {
            module: self.name.clone(),
            signal: signal.into(),
            message: message.into(),
            location: Location::caller(),
        });
    }

    fn sig(&self, id: NodeId) -> Sig {
        Sig {
            id,
            ty: self.nodes[id.0 as usize].ty,
        }
    }

    #[track_caller]
    fn push(&mut self, op: Op, ty: Ty, name: String, stage: Option<u32>) -> Sig {
        let id = NodeId(self.nodes.len() as u32);
        let named = matches!(op, Op::Input(_) | Op::Reg(_) | Op::InstOut { .. });
        self.nodes.push(Node {
            op,
            ty,
            name,
            named,
            location: Location::caller(),
        });
        self.stage_of.push(stage);
        Sig { id, ty }
    }

    /// A placeholder returned after an error so that building can go on.
    fn poison(&mut self, ty: Ty) -> Sig {
        let ty = if ty.width() == 0 || ty.width() > MAX_WIDTH {
            Ty::Bool
        } else {
            ty
        };
        self.constant_unchecked(ty, 0)
    }

    fn constant_unchecked(&mut self, ty: Ty, value: u128) -> Sig {
        if let Some(&id) = self.constants.get(&(ty, value)) {
            return self.sig(id);
        }
        let name = format!("k{value:x}");
        let s = self.push(Op::Const(value), ty, name, None);
        self.constants.insert((ty, value), s.id);
        s
    }

    /// Declares a data input port.
    #[track_caller]
    pub fn input(&mut self, name: &str, ty: Ty) -> Sig {
        if !is_identifier(name) {
            self.error(name, "port name is not a Verilog identifier");
        } else if self.inputs.iter().any(|p| p.name == name) {
            self.error(name, "input port declared twice");
        }
        if ty.width() == 0 || ty.width() > MAX_WIDTH {
            self.error(
                name,
                format!("port width {} outside 1..={MAX_WIDTH}", ty.width()),
            );
            return self.poison(ty);
        }
        let index = self.inputs.len();
        self.inputs.push(Port {
            name: name.to_string(),
            ty,
        });
        self.push(Op::Input(index), ty, name.to_string(), Some(0))
    }

    /// Declares a data output port driven by `value`, taken at the last stage.
    #[track_caller]
    pub fn output(&mut self, name: &str, value: Sig) {
        if !is_identifier(name) {
            self.error(name, "port name is not a Verilog identifier");
        } else if self.outputs.iter().any(|(p, _)| p.name == name)
            || self.inputs.iter().any(|p| p.name == name)
            || name == control::OUT_VALID
            || (self.ready.is_some() && name == control::IN_READY)
        {
            self.error(name, "port name already used");
        }
        self.outputs.push((
            Port {
                name: name.to_string(),
                ty: value.ty,
            },
            value.id,
        ));
    }

    /// Gives `value` the name `name` as it is (no scope added).
    #[track_caller]
    fn rename(&mut self, value: Sig, name: &str) -> Sig {
        if !is_identifier(name) {
            self.error(name, "signal name is not a Verilog identifier");
            return value;
        }
        // a cast is written as its source: a derived source takes the name
        let mut id = value.id;
        while let Op::Cast(src) = self.nodes[id.0 as usize].op {
            // ports and registers are named; constants keep their literal
            let source = &self.nodes[src.0 as usize];
            if source.named || matches!(source.op, Op::Const(_)) {
                break;
            }
            id = src;
        }
        let node = &mut self.nodes[id.0 as usize];
        match node.op {
            // ports and registers keep their declared names
            Op::Input(_) | Op::Reg(_) | Op::Const(_) => {}
            _ => {
                node.name = name.to_string();
                node.named = true;
            }
        }
        value
    }

    /// A constant of type `ty`.
    #[track_caller]
    pub fn constant(&mut self, ty: Ty, value: u128) -> Sig {
        let w = ty.width();
        if w == 0 || w > MAX_WIDTH {
            self.error(
                format!("{value:#x}"),
                format!("constant width {w} outside 1..={MAX_WIDTH}"),
            );
            return self.poison(Ty::Bool);
        }
        if w < 128 && value >> w != 0 {
            self.error(format!("{value:#x}"), format!("constant does not fit {ty}"));
            return self.poison(ty);
        }
        self.constant_unchecked(ty, value)
    }

    /// An unsigned constant of width `w`.
    #[track_caller]
    pub fn uint(&mut self, w: u32, value: u128) -> Sig {
        self.constant(Ty::UInt(w), value)
    }

    /// A signed constant of width `w`.
    #[track_caller]
    pub fn sint(&mut self, w: u32, value: i128) -> Sig {
        let fits = w >= 128 || (value >= -(1i128 << (w - 1)) && value < (1i128 << (w - 1)));
        if w == 0 || w > MAX_WIDTH || !fits {
            self.error(
                format!("{value}"),
                format!("constant does not fit SInt<{w}>"),
            );
            return self.poison(Ty::SInt(w.clamp(1, MAX_WIDTH)));
        }
        self.constant_unchecked(Ty::SInt(w), crate::eval::mask(value as u128, w))
    }

    /// A `Bool` constant.
    pub fn bool(&mut self, value: bool) -> Sig {
        self.constant_unchecked(Ty::Bool, value as u128)
    }

    /// Adds an operation in the current stage, after aligning its operands.
    #[track_caller]
    fn op(&mut self, op: Op, ty: Ty) -> Sig {
        if ty.width() == 0 || ty.width() > MAX_WIDTH {
            let name = self.derived_name(&op);
            self.error(
                name,
                format!("result width {} outside 1..={MAX_WIDTH}", ty.width()),
            );
            return self.poison(ty);
        }
        let operands = op.operands();
        if operands
            .iter()
            .all(|o| matches!(self.nodes[o.0 as usize].op, Op::Const(_)))
            && !operands.is_empty()
        {
            let vals: Vec<(u128, Ty)> = operands
                .iter()
                .map(|o| {
                    let n = &self.nodes[o.0 as usize];
                    let Op::Const(v) = n.op else { unreachable!() };
                    (v, n.ty)
                })
                .collect();
            let v = eval_op(&op, ty, &vals);
            return self.constant_unchecked(ty, v);
        }
        let stage = self.current_stage;
        let op = op.map_operands(|id| self.at_stage(id, stage));
        let name = self.derived_name(&op);
        self.push(op, ty, name, Some(stage))
    }

    /// Instantiates `module`, connecting its data inputs by name (`&str` or
    /// `String`). Its outputs belong to the stage `latency` cycles after the
    /// current one.
    #[track_caller]
    pub fn instance(
        &mut self,
        name: &str,
        module: &Arc<Module>,
        inputs: &[(impl AsRef<str>, Sig)],
    ) -> InstanceOutputs {
        self.instance_at(name, module, inputs, module.latency)
    }

    /// Instantiates `module` like [`ModuleBuilder::instance`], but its
    /// outputs belong to the current stage: for a module that keeps the
    /// instance's latency itself with explicit registers (the valid/ready
    /// wrapper counts credits) instead of pipeline stages.
    #[track_caller]
    pub fn instance_unstaged(
        &mut self,
        name: &str,
        module: &Arc<Module>,
        inputs: &[(impl AsRef<str>, Sig)],
    ) -> InstanceOutputs {
        self.instance_at(name, module, inputs, 0)
    }

    /// An instance whose outputs belong to the stage `after` cycles after the
    /// current one.
    #[track_caller]
    fn instance_at(
        &mut self,
        name: &str,
        module: &Arc<Module>,
        inputs: &[(impl AsRef<str>, Sig)],
        after: u32,
    ) -> InstanceOutputs {
        if !is_identifier(name) {
            self.error(name, "instance name is not a Verilog identifier");
        }
        let stage = self.current_stage;
        let mut connected = Vec::with_capacity(module.inputs.len());
        for port in &module.inputs {
            let found = inputs.iter().find(|(n, _)| n.as_ref() == port.name);
            let id = match found {
                Some((_, s)) if s.ty == port.ty => self.at_stage(s.id, stage),
                Some((_, s)) => {
                    self.error(
                        format!("{name}.{}", port.name),
                        format!("port is {}, connected to {}", port.ty, s.ty),
                    );
                    self.poison(port.ty).id
                }
                None => {
                    self.error(format!("{name}.{}", port.name), "input port not connected");
                    self.poison(port.ty).id
                }
            };
            connected.push(id);
        }
        for (n, _) in inputs {
            let n = n.as_ref();
            if !module.inputs.iter().any(|p| p.name == n) {
                self.error(
                    format!("{name}.{n}"),
                    format!("module {} has no such input", module.name),
                );
            }
        }
        let inst = self.instances.len();
        self.instances.push(Instance {
            name: name.to_string(),
            module: module.clone(),
            inputs: connected,
        });
        let out_stage = stage + after;
        let mut names = Vec::new();
        let mut sigs = Vec::new();
        for (port, (p, _)) in module.outputs.iter().enumerate() {
            let s = self.push(
                Op::InstOut { inst, port },
                p.ty,
                format!("{name}_{}", p.name),
                Some(out_stage),
            );
            names.push(p.name.clone());
            sigs.push(s);
        }
        InstanceOutputs { names, sigs }
    }

    /// The `in_valid` input of a module built with the handshake.
    pub(crate) fn in_valid(&self) -> Option<Sig> {
        self.valid.as_ref().map(|v| self.sig(v[0]))
    }

    /// Adds `op`, whose operands are nodes of this builder, in the current
    /// stage under `name` (constants fold as usual): the retiming pass
    /// replays a flattened module through this.
    #[track_caller]
    pub(crate) fn replay(&mut self, op: Op, ty: Ty, name: &str, named: bool) -> Sig {
        if let Op::Const(value) = op {
            // constants belong to no stage: never carried by registers
            return self.constant_unchecked(ty, value);
        }
        let s = self.op(op, ty);
        let node = &mut self.nodes[s.id.0 as usize];
        if !matches!(node.op, Op::Const(_)) {
            node.name = name.to_string();
            node.named = named;
        }
        s
    }

    /// Finishes the module: outputs are carried to the last stage, whose number
    /// is the latency. Returns every error recorded while building.
    #[track_caller]
    pub fn finish(mut self) -> Result<Module, BuildErrors> {
        for (index, loc) in std::mem::take(&mut self.pending_regs) {
            self.errors.push(DslError {
                module: self.name.clone(),
                signal: self.registers[index].name.clone(),
                message: "register was never given a next value".into(),
                location: loc,
            });
        }
        let last = self.current_stage;
        let mut outputs = std::mem::take(&mut self.outputs);
        for (port, id) in outputs.iter_mut() {
            let value = *id;
            *id = self.at_stage(value, last);
            // a value named like its port and carried there by registers
            // (`hit_s1`, `hit_s2`) is the port's value in its own stage
            let node = &self.nodes[value.0 as usize];
            let computed = !matches!(
                node.op,
                Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. }
            );
            if let Some(stage) = self.stage_of[value.0 as usize].filter(|s| *s < last) {
                if computed && node.named && node.name == port.name {
                    self.nodes[value.0 as usize].name = format!("{}_s{stage}", port.name);
                }
            }
        }
        let handshake = self.valid.as_ref().map(|v| {
            let out_valid = *v.last().unwrap();
            outputs.insert(
                0,
                (
                    Port {
                        name: control::OUT_VALID.into(),
                        ty: Ty::Bool,
                    },
                    out_valid,
                ),
            );
            Handshake {
                latency: last,
                ready: false,
            }
        });
        let mut latency = last;
        let mut handshake = handshake;
        if let Some((declared, given)) = self.ready {
            match given {
                Some((out_valid, in_ready)) if last == 0 => {
                    let port = |name: &str| Port {
                        name: name.into(),
                        ty: Ty::Bool,
                    };
                    outputs.insert(0, (port(control::OUT_VALID), out_valid));
                    outputs.insert(1, (port(control::IN_READY), in_ready));
                    latency = declared;
                    handshake = Some(Handshake {
                        latency,
                        ready: true,
                    });
                }
                Some(_) => self.errors.push(DslError {
                    module: self.name.clone(),
                    signal: String::new(),
                    message: "a valid/ready module keeps its time with registers, not stages"
                        .into(),
                    location: Location::caller(),
                }),
                None => self.errors.push(DslError {
                    module: self.name.clone(),
                    signal: control::OUT_VALID.into(),
                    message: "out_valid and in_ready were never given (ready_outputs)".into(),
                    location: Location::caller(),
                }),
            }
        }
        if !self.errors.is_empty() {
            return Err(BuildErrors(self.errors));
        }
        let module = Module {
            name: self.name,
            description: self.description,
            params: self.params,
            inputs: self.inputs,
            outputs,
            nodes: self.nodes,
            registers: self.registers,
            instances: self.instances,
            latency,
            handshake,
            vendor: None,
        };
        module.check_well_formed().map_err(|message| {
            BuildErrors(vec![DslError {
                module: module.name.clone(),
                signal: String::new(),
                message,
                location: Location::caller(),
            }])
        })?;
        Ok(module)
    }
}
