//! A small typed Verilog-2005 tree: just the constructs the lowering needs.

/// A Verilog expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Expr {
    /// a net, variable or port
    Ident(String),
    /// a sized literal; `value` holds the low `width` bits
    Literal {
        /// width in bits
        width: u32,
        /// value
        value: u128,
    },
    /// `{a, b, ...}`
    Concat(Vec<Expr>),
    /// `{n{a}}`
    Replicate(u32, Box<Expr>),
    /// `name[hi:lo]`, or `name[hi]` when hi == lo
    Select(String, u32, u32),
    /// `$signed(a)`
    Signed(Box<Expr>),
    /// `op a`
    Unary(&'static str, Box<Expr>),
    /// `a op b`
    Binary(&'static str, Box<Expr>, Box<Expr>),
    /// `c ? t : f`
    Ternary(Box<Expr>, Box<Expr>, Box<Expr>),
}

/// Port direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dir {
    /// `input wire`
    Input,
    /// `output wire`
    Output,
}

/// A net or variable declaration (ports included).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decl {
    /// identifier
    pub name: String,
    /// width in bits (1 declares a scalar)
    pub width: u32,
    /// declared `signed`
    pub signed: bool,
    /// why some bits are not read, if so: the declaration gets a narrow
    /// `UNUSEDSIGNAL` lint waiver carrying this reason
    pub unused: Option<String>,
}

/// A statement in an `always @(posedge clk)` block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stmt {
    /// `lhs <= rhs;`
    NonBlocking(String, Expr),
    /// `if (c) begin ... end [else begin ... end]`
    If(Expr, Vec<Stmt>, Vec<Stmt>),
}

/// A module item.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Item {
    /// `// text`
    Comment(String),
    /// `wire ...;`
    Wire(Decl),
    /// `reg ...;`
    Reg(Decl),
    /// `assign lhs = rhs;`
    Assign(String, Expr),
    /// `always @(posedge clock) begin ... end`
    AlwaysPosedge(String, Vec<Stmt>),
    /// `module_name #(.param("value"), ...) instance_name (.port(expr), ...);`
    Instance {
        /// module instantiated
        module: String,
        /// parameters, each value a Verilog constant as written (none for
        /// generated modules)
        params: Vec<(String, String)>,
        /// instance name
        name: String,
        /// port connections in port order
        connections: Vec<(String, Expr)>,
    },
    /// `` `ifdef symbol `` items `` `else `` items `` `endif ``
    Ifdef {
        /// the macro tested
        symbol: String,
        /// items when it is defined
        then: Vec<Item>,
        /// items when it is not
        otherwise: Vec<Item>,
    },
    /// an empty line between groups
    Blank,
}

/// A whole module, with its header comment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VModule {
    /// comment lines written before `module`
    pub header: Vec<String>,
    /// module name
    pub name: String,
    /// ports in order
    pub ports: Vec<(Dir, Decl)>,
    /// body
    pub items: Vec<Item>,
}
