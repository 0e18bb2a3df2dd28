//! How values are named: the scopes a generator opens, the names it gives
//! (`name`, `name_after`), and the names derived for the values it does not
//! name (the operation and its operands' roles, shortened by a rule).

use super::*;

/// Longest name derived from an operation and its operands' names; a longer
/// one is shortened by [`shortened`].
pub(super) const DERIVED_NAME_MAX: usize = 40;

/// A derived name `full` made short: each of its [`tokens`] said once
/// (`or_a_x_is_nan_a_x_is_inf` becomes `or_a_x_is_nan_inf`); when that is
/// still longer than [`DERIVED_NAME_MAX`], `head` (the scoped operation, or
/// a slice's source role) followed by the last token of each of `parts`,
/// said once (`lzc_mux_zero_count`, `sum_b10_11_0`). Never the bare
/// operation: an operand's role stays in the name.
pub(super) fn shortened(full: &str, head: &str, parts: &[&str]) -> String {
    // the last token (the role, a slice's range) always stays last
    let once = |mut tokens: Vec<String>| {
        let last = tokens.pop().unwrap_or_default();
        let mut said: Vec<String> = Vec::new();
        for t in tokens {
            if !said.contains(&t) && t != last {
                said.push(t);
            }
        }
        said.push(last);
        said.join("_")
    };
    let short = once(tokens(full));
    if short.len() <= DERIVED_NAME_MAX {
        return short;
    }
    let roles = parts.iter().filter_map(|p| tokens(p).pop());
    once(tokens(head).into_iter().chain(roles).collect())
}

/// The words of a name, a number staying with the word before it
/// (`a_x_9_0_lt` is `a`, `x_9_0`, `lt`): the last one is a value's role.
pub(super) fn tokens(name: &str) -> Vec<String> {
    let mut tokens: Vec<String> = Vec::new();
    for w in name.split('_') {
        match tokens.last_mut() {
            Some(last) if w.bytes().all(|b| b.is_ascii_digit()) => *last = format!("{last}_{w}"),
            _ => tokens.push(w.to_string()),
        }
    }
    tokens
}

/// The short word for an operation in derived names.
pub(super) fn verb(op: &Op) -> &'static str {
    match op {
        Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } | Op::Cast(_) => "n",
        Op::Add(..) => "add",
        Op::Sub(..) => "sub",
        Op::Mul(..) => "mul",
        Op::Not(_) => "not",
        Op::Bit(BitOp::And, ..) => "and",
        Op::Bit(BitOp::Or, ..) => "or",
        Op::Bit(BitOp::Xor, ..) => "xor",
        Op::Cmp(CmpOp::Eq, ..) => "eq",
        Op::Cmp(CmpOp::Lt, ..) => "lt",
        Op::Cmp(CmpOp::Le, ..) => "le",
        Op::Shl(..) => "shl",
        Op::Shr(..) => "shr",
        Op::Mux(..) => "mux",
        Op::Concat(_) => "cat",
        Op::Slice(..) => "bits",
        Op::Reduce(ReduceOp::And, _) => "all",
        Op::Reduce(ReduceOp::Or, _) => "any",
        Op::Reduce(ReduceOp::Xor, _) => "par",
    }
}

impl ModuleBuilder {
    /// Runs `body` in the naming scope `scope`: a name given inside
    /// ([`ModuleBuilder::name`]) becomes `scope_name`, scopes nest
    /// (`a_x_lzc_hi`), and a value left unnamed whose derived name would be
    /// too long is shortened by a rule (`shortened`): never a bare operation.
    /// Helpers open a scope and name their results after their role, so two
    /// uses of one helper get different names without counters.
    #[track_caller]
    pub fn scope<T>(&mut self, scope: &str, body: impl FnOnce(&mut Self) -> T) -> T {
        if !is_identifier(scope) {
            self.error(scope, "scope name is not a Verilog identifier");
        }
        self.scopes.push(scope.to_string());
        let out = body(self);
        self.scopes.pop();
        out
    }

    /// The name of a value; an unnamed cast goes by its source's (current) name.
    pub(super) fn name_of(&self, id: NodeId) -> &str {
        let node = &self.nodes[id.0 as usize];
        match node.op {
            Op::Cast(src) if !node.named => self.name_of(src),
            _ => &node.name,
        }
    }

    /// The name of an unnamed value: the operation and its operands' names
    /// (`not_a_x_zero`, `a_x_8_4` for a slice), constants left out. A name
    /// longer than [`DERIVED_NAME_MAX`] is shortened by [`shortened`].
    pub(super) fn derived_name(&self, op: &Op) -> String {
        if let Op::Slice(a, h, l) = *op {
            let (source, h, l) = self.slice_source(a, h, l);
            let range = match h == l {
                true => format!("b{h}"),
                false => format!("{h}_{l}"),
            };
            let full = format!("{source}_{range}");
            if full.len() <= DERIVED_NAME_MAX {
                return full;
            }
            let role = tokens(source).pop().unwrap_or_default();
            return shortened(&full, &self.scoped(&role), &[&range]);
        }
        let operands: Vec<&str> = op
            .operands()
            .into_iter()
            .filter(|o| !matches!(self.nodes[o.0 as usize].op, Op::Const(_)))
            .map(|o| self.name_of(o))
            .collect();
        let full = match op {
            Op::Cast(_) => operands.first().copied().unwrap_or("k").to_string(),
            _ => std::iter::once(verb(op))
                .chain(operands.iter().copied())
                .collect::<Vec<_>>()
                .join("_"),
        };
        if full.len() <= DERIVED_NAME_MAX {
            return full;
        }
        shortened(&full, &self.scoped(verb(op)), &operands)
    }

    /// The name bits `h..=l` of `a` are read from: a slice of an unnamed
    /// slice reads its source (`x_8_0` of `x_9_0` is `x_8_0` of `x`), so
    /// ranges do not pile up in a name.
    pub(super) fn slice_source(&self, a: NodeId, h: u32, l: u32) -> (&str, u32, u32) {
        let node = &self.nodes[a.0 as usize];
        match node.op {
            Op::Slice(src, _, lo) if !node.named => self.slice_source(src, h + lo, l + lo),
            Op::Cast(src) if !node.named => self.slice_source(src, h, l),
            _ => (self.name_of(a), h, l),
        }
    }

    /// Gives a value the name it will carry in the Verilog.
    #[track_caller]
    pub fn name(&mut self, value: Sig, name: &str) -> Sig {
        let name = self.scoped(name);
        self.rename(value, &name)
    }

    /// Names `value` after the value `of` it describes and its `role`
    /// (`t_lo_is_nan` for `role` `is_nan`), for a helper that computes one
    /// property of its operand. Left to the derived name when `of` has none
    /// to give (a constant) or the name would pass [`DERIVED_NAME_MAX`].
    #[track_caller]
    pub fn name_after(&mut self, value: Sig, of: Sig, role: &str) -> Sig {
        if matches!(self.nodes[of.id.0 as usize].op, Op::Const(_)) {
            return value;
        }
        let name = format!("{}_{role}", self.name_of(of.id));
        match name.len() <= DERIVED_NAME_MAX {
            // the operand's name already carries its scope
            true => self.rename(value, &name),
            false => value,
        }
    }
}
