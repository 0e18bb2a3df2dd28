//! Prints the Verilog tree as text: four-space indentation, one item a line.

use super::vast::*;
use std::fmt::Write;

const INDENT: &str = "    ";

/// Width a line is filled to before it breaks (at a space, so an identifier
/// or literal is never split): long expressions and comments stay readable.
const LINE_WIDTH: usize = 100;

/// Writes `text` after `first` as lines of at most [`LINE_WIDTH`] characters
/// where spaces allow, each continuation line starting with `next`. Every
/// space of a printed expression separates two tokens, so a break there
/// keeps the Verilog's meaning.
fn wrapped(out: &mut String, first: &str, next: &str, text: &str) {
    let mut line = first.to_string();
    let mut empty = true;
    for word in text.split(' ') {
        if !empty && line.len() + 1 + word.len() > LINE_WIDTH {
            let _ = writeln!(out, "{}", line.trim_end());
            line = next.to_string();
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line.push_str(word);
        empty = false;
    }
    let _ = writeln!(out, "{line}");
}

/// A sized literal: decimal when short, hexadecimal otherwise.
fn literal(width: u32, value: u128) -> String {
    if width == 1 {
        format!("1'b{value}")
    } else if value < 10 {
        format!("{width}'d{value}")
    } else {
        format!("{width}'h{value:x}")
    }
}

/// True if the expression prints as one token (no parentheses needed).
fn is_atom(e: &Expr) -> bool {
    matches!(
        e,
        Expr::Ident(_)
            | Expr::Literal { .. }
            | Expr::Concat(_)
            | Expr::Replicate(..)
            | Expr::Select(..)
            | Expr::Signed(_)
    )
}

/// Prints an expression.
pub fn expr(e: &Expr) -> String {
    let operand = |x: &Expr| {
        if is_atom(x) {
            expr(x)
        } else {
            format!("({})", expr(x))
        }
    };
    match e {
        Expr::Ident(n) => n.clone(),
        Expr::Literal { width, value } => literal(*width, *value),
        Expr::Concat(parts) => format!(
            "{{{}}}",
            parts.iter().map(expr).collect::<Vec<_>>().join(", ")
        ),
        Expr::Replicate(n, x) => format!("{{{n}{{{}}}}}", expr(x)),
        Expr::Select(n, hi, lo) if hi == lo => format!("{n}[{hi}]"),
        Expr::Select(n, hi, lo) => format!("{n}[{hi}:{lo}]"),
        Expr::Signed(x) => format!("$signed({})", expr(x)),
        Expr::Unary(op, x) => format!("{op}{}", operand(x)),
        Expr::Binary(op, a, b) => format!("{} {op} {}", operand(a), operand(b)),
        Expr::Ternary(c, t, f) => format!("{} ? {} : {}", operand(c), operand(t), operand(f)),
    }
}

fn range(d: &Decl) -> String {
    let signed = if d.signed { "signed " } else { "" };
    if d.width == 1 {
        signed.to_string()
    } else {
        format!("{signed}[{}:0] ", d.width - 1)
    }
}

fn waived(out: &mut String, indent: &str, d: &Decl, line: &str) {
    match &d.unused {
        Some(reason) => {
            let (first, next) = (format!("{indent}// "), format!("{indent}//     "));
            wrapped(out, &first, &next, reason);
            let _ = writeln!(out, "{indent}/* verilator lint_off UNUSEDSIGNAL */");
            let _ = writeln!(out, "{indent}{line}");
            let _ = writeln!(out, "{indent}/* verilator lint_on UNUSEDSIGNAL */");
        }
        None => {
            let _ = writeln!(out, "{indent}{line}");
        }
    }
}

fn stmts(out: &mut String, depth: usize, body: &[Stmt]) {
    let ind = INDENT.repeat(depth);
    for s in body {
        match s {
            Stmt::NonBlocking(l, r) => {
                let next = format!("{ind}{INDENT}");
                wrapped(out, &ind, &next, &format!("{l} <= {};", expr(r)));
            }
            Stmt::If(c, t, f) => {
                let _ = writeln!(out, "{ind}if ({}) begin", expr(c));
                stmts(out, depth + 1, t);
                if f.is_empty() {
                    let _ = writeln!(out, "{ind}end");
                } else {
                    let _ = writeln!(out, "{ind}end else begin");
                    stmts(out, depth + 1, f);
                    let _ = writeln!(out, "{ind}end");
                }
            }
        }
    }
}

/// Prints a whole module, header first.
pub fn module(m: &VModule) -> String {
    let mut out = String::new();
    for h in &m.header {
        if h.is_empty() {
            out.push_str("//\n");
        } else {
            wrapped(&mut out, "// ", "//     ", h);
        }
    }
    out.push_str("`default_nettype none\n\n");
    let _ = writeln!(out, "module {} (", m.name);
    let n = m.ports.len();
    for (i, (dir, d)) in m.ports.iter().enumerate() {
        let kw = match dir {
            Dir::Input => "input",
            Dir::Output => "output",
        };
        let comma = if i + 1 < n { "," } else { "" };
        let line = format!("{kw} wire {}{}{comma}", range(d), d.name);
        waived(&mut out, INDENT, d, &line);
    }
    out.push_str(");\n");
    items(&mut out, &m.items);
    out.push_str("endmodule\n\n`default_nettype wire\n");
    out
}

fn items(out: &mut String, items_: &[Item]) {
    for item in items_ {
        match item {
            Item::Comment(c) => {
                wrapped(out, &format!("{INDENT}// "), &format!("{INDENT}//     "), c)
            }
            Item::Wire(d) => waived(out, INDENT, d, &format!("wire {}{};", range(d), d.name)),
            Item::Reg(d) => waived(out, INDENT, d, &format!("reg {}{};", range(d), d.name)),
            Item::Assign(l, r) => {
                let text = format!("assign {l} = {};", expr(r));
                wrapped(out, INDENT, &INDENT.repeat(2), &text);
            }
            Item::AlwaysPosedge(clk, body) => {
                let _ = writeln!(out, "{INDENT}always @(posedge {clk}) begin");
                stmts(out, 2, body);
                let _ = writeln!(out, "{INDENT}end");
            }
            Item::Instance {
                module,
                params,
                name,
                connections,
            } => {
                if params.is_empty() {
                    let _ = writeln!(out, "{INDENT}{module} {name} (");
                } else {
                    let _ = writeln!(out, "{INDENT}{module} #(");
                    let k = params.len();
                    for (i, (p, v)) in params.iter().enumerate() {
                        let comma = if i + 1 < k { "," } else { "" };
                        let _ = writeln!(out, "{INDENT}{INDENT}.{p}({v}){comma}");
                    }
                    let _ = writeln!(out, "{INDENT}) {name} (");
                }
                let k = connections.len();
                for (i, (p, e)) in connections.iter().enumerate() {
                    let comma = if i + 1 < k { "," } else { "" };
                    let _ = writeln!(out, "{INDENT}{INDENT}.{p}({}){comma}", expr(e));
                }
                let _ = writeln!(out, "{INDENT});");
            }
            Item::Ifdef {
                symbol,
                then,
                otherwise,
            } => {
                let _ = writeln!(out, "`ifdef {symbol}");
                items(out, then);
                out.push_str("`else\n");
                items(out, otherwise);
                out.push_str("`endif\n");
            }
            Item::Blank => out.push('\n'),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_print_with_minimal_parentheses() {
        let a = Expr::Ident("a".into());
        let sum = Expr::Binary(
            "+",
            Box::new(a.clone()),
            Box::new(Expr::Literal {
                width: 8,
                value: 200,
            }),
        );
        assert_eq!(expr(&sum), "a + 8'hc8");
        let t = Expr::Ternary(
            Box::new(Expr::Select("s".into(), 3, 3)),
            Box::new(sum),
            Box::new(a.clone()),
        );
        assert_eq!(expr(&t), "s[3] ? (a + 8'hc8) : a");
        let ext = Expr::Concat(vec![
            Expr::Replicate(4, Box::new(Expr::Select("b".into(), 7, 7))),
            Expr::Ident("b".into()),
        ]);
        assert_eq!(
            expr(&Expr::Signed(Box::new(ext))),
            "$signed({{4{b[7]}}, b})"
        );
    }
}
