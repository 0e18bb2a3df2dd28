//! Pipeline stages and registers: the stage a value is computed in, the
//! registers that carry it into later stages (made once per value and
//! stage), and the explicit registers of a state machine.

use super::*;

impl ModuleBuilder {
    /// The stage new operations are computed in (= cycles since the inputs).
    pub fn current_stage(&self) -> u32 {
        self.current_stage
    }

    /// Brings `id` into stage `stage`, inserting or reusing pipeline registers.
    #[track_caller]
    pub(super) fn at_stage(&mut self, id: NodeId, stage: u32) -> NodeId {
        let Some(from) = self.stage_of[id.0 as usize] else {
            return id;
        };
        if from == stage {
            return id;
        }
        if from > stage {
            let name = self.name_of(id).to_string();
            self.error(
                name,
                format!("value of stage {from} read in earlier stage {stage}"),
            );
            return id;
        }
        if let Some(&c) = self.carried.get(&(id, stage)) {
            return c;
        }
        let prev = self.at_stage(id, stage - 1);
        let ty = self.nodes[id.0 as usize].ty;
        let name = format!("{}_s{stage}", self.name_of(id));
        let index = self.registers.len();
        self.registers.push(Register {
            name: name.clone(),
            ty,
            next: prev,
            reset: None,
            enable: None,
        });
        let q = self.push(Op::Reg(index), ty, name, Some(stage));
        self.carried.insert((id, stage), q.id);
        q.id
    }

    /// Closes the current pipeline stage: later operations are one cycle later.
    pub fn stage(&mut self) {
        self.current_stage += 1;
        let stage = self.current_stage;
        if let Some(valid) = &self.valid {
            let prev = *valid.last().expect("valid starts with in_valid");
            let index = self.registers.len();
            let name = format!("valid_s{stage}");
            self.registers.push(Register {
                name: name.clone(),
                ty: Ty::Bool,
                next: prev,
                reset: Some(0),
                enable: None,
            });
            let q = self.push(Op::Reg(index), Ty::Bool, name, Some(stage));
            self.valid.as_mut().unwrap().push(q.id);
        }
    }

    /// A register of the current stage, reset to `reset` if given. Its next value
    /// is set with [`ModuleBuilder::set_next`].
    #[track_caller]
    pub fn reg(&mut self, name: &str, ty: Ty, reset: Option<u128>) -> RegHandle {
        if !is_identifier(name) {
            self.error(name, "register name is not a Verilog identifier");
        }
        if reset.is_some_and(|r| ty.width() < 128 && r >> ty.width() != 0) {
            self.error(name, format!("reset value does not fit {ty}"));
        }
        let index = self.registers.len();
        let placeholder = NodeId(0);
        self.registers.push(Register {
            name: name.to_string(),
            ty,
            next: placeholder,
            reset,
            enable: None,
        });
        self.pending_regs.push((index, Location::caller()));
        let q = self.push(
            Op::Reg(index),
            ty,
            name.to_string(),
            Some(self.current_stage),
        );
        RegHandle { index, q }
    }

    /// Sets the value a register loads at each rising edge (when `enable` is true, if given).
    #[track_caller]
    pub fn set_next(&mut self, reg: RegHandle, next: Sig, enable: Option<Sig>) {
        let name = self.registers[reg.index].name.clone();
        if next.ty != reg.q.ty {
            self.error(
                name.clone(),
                format!("next value is {}, register is {}", next.ty, reg.q.ty),
            );
        }
        if enable.is_some_and(|e| e.ty != Ty::Bool) {
            self.error(name.clone(), "register enable must be Bool");
        }
        let Some(pos) = self.pending_regs.iter().position(|(i, _)| *i == reg.index) else {
            self.error(name, "next value set twice");
            return;
        };
        self.pending_regs.remove(pos);
        let stage = self.current_stage;
        let next = self.at_stage(next.id, stage);
        let enable = enable.map(|e| self.at_stage(e.id, stage));
        let r = &mut self.registers[reg.index];
        r.next = next;
        r.enable = enable;
    }
}
