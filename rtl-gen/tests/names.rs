//! The emitted Verilog's names (issue 18): no cut or numbered names where a
//! role or a scope can say what a wire is, and names that do not move when
//! an unrelated value is added.

use rtl_gen::arith::float::compare::compare;
use rtl_gen::arith::float::Format;
use rtl_gen::builder::ModuleBuilder;
use rtl_gen::emit::{emit, lower::name_counts, lower::NameCounts};
use rtl_gen::ir::{Module, Ty};
use rtl_gen::params::Params;
use rtl_gen::units::silhouette::Silhouette;
use rtl_gen::units::Unit;

fn silhouette_e5m4(mode: &str) -> Module {
    let given = [("mode", mode), ("exp_bits", "5"), ("frac_bits", "4")];
    let p = Params::check("silhouette", Silhouette.params(), given).expect("parameters");
    Silhouette.build(&p).expect("silhouette builds")
}

/// The counts of every module below and including `top`.
fn counts(top: &Module) -> NameCounts {
    top.hierarchy()
        .into_iter()
        .map(name_counts)
        .fold(NameCounts::default(), |a, c| NameCounts {
            names: a.names + c.names,
            numbered: a.numbered + c.numbered,
            longest: a.longest.max(c.longest),
        })
}

#[test]
fn silhouette_e5m4_names_are_whole_and_rarely_numbered() {
    for mode in ["bundle", "ray"] {
        let c = counts(&silhouette_e5m4(mode));
        println!(
            "silhouette {mode} e5m4: {} names, {} numbered ({:.1} %), longest {} characters",
            c.names,
            c.numbered,
            100.0 * c.numbered as f64 / c.names as f64,
            c.longest
        );
        assert!(
            c.numbered * 20 <= c.names,
            "{mode}: {} of {} names numbered (more than 5 %)",
            c.numbered,
            c.names
        );
        // derived names stop at 40 characters; a register adds `_s<stage>`
        assert!(
            c.longest <= 44,
            "{mode}: a name of {} characters",
            c.longest
        );
    }
}

/// Two comparisons in their scopes; `extra` adds an unrelated one first.
fn two_comparisons(extra: bool) -> Module {
    let f = Format::new(5, 4).unwrap();
    let mut m = ModuleBuilder::new("names");
    let ty = Ty::UInt(f.width());
    let [a, b, c] = ["a", "b", "c"].map(|n| m.input(n, ty));
    if extra {
        let (lt, _, _) = m.scope("unrelated", |m| compare(m, f, c, a));
        m.output("unrelated_lt", lt);
    }
    let (ab, _, _) = m.scope("ab", |m| compare(m, f, a, b));
    let (bc, _, _) = m.scope("bc", |m| compare(m, f, b, c));
    m.output("ab_lt", ab);
    m.output("bc_lt", bc);
    m.finish().expect("well formed")
}

fn wire_names(m: &Module) -> Vec<String> {
    let text = &emit(m, "test")[0].text;
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("wire "))
        .map(|l| {
            l.trim_end_matches(';')
                .rsplit(' ')
                .next()
                .unwrap()
                .to_string()
        })
        .collect()
}

#[test]
fn an_unrelated_value_does_not_rename_the_others() {
    let plain = wire_names(&two_comparisons(false));
    let with = wire_names(&two_comparisons(true));
    assert!(plain.len() > 4, "{plain:?}");
    let missing: Vec<&String> = plain.iter().filter(|n| !with.contains(n)).collect();
    assert!(
        missing.is_empty(),
        "renamed: {missing:?}\nbefore {plain:?}\nafter {with:?}"
    );
    assert!(with.len() > plain.len());
}
