//! Every registered unit (`rtl_flow::catalog()`), so that registering a unit
//! is enough to bring it under test: with its default parameters and with
//! `pipeline=balanced`, every emitted module lints clean with
//! `verilator --lint-only -Wall` as its own top, and the IR evaluator agrees
//! with the golden model on corner and random vectors. (The Verilator
//! cross-checks of chosen configurations are the units' own test files.)

mod common;

use rtl_flow::{catalog, Generated, Skipped};
use std::path::Path;

/// Lints the design with each of its modules as the top.
fn lint_every_module(g: &Generated, dir: &Path) {
    for file in &g.files {
        let mut ports = g.ports.clone();
        ports.top = file.module.clone();
        sim::lint(&ports, dir).unwrap_or_else(|e| panic!("{} as top: {e}", file.module));
    }
}

#[test]
fn every_registered_unit_lints_and_matches_its_golden_model() {
    let mut checked = Vec::new();
    for entry in catalog() {
        let unit = entry.unit.name();
        for given in [&[][..], &["pipeline=balanced"][..]] {
            let (g, dir) = common::generate("catalog", unit, given);
            lint_every_module(&g, &dir);
            let tb = g.testbench();
            for first in [0, 1_000_000] {
                let r = g.evaluate(
                    &Skipped {
                        of: tb.as_ref(),
                        first,
                    },
                    1_000,
                    3,
                );
                assert_eq!(
                    (r.vectors, r.mismatches),
                    (1_000, 0),
                    "{unit} {given:?} from vector {first}: {r}"
                );
            }
            checked.push(format!("{} ({} modules)", g.module.name, g.files.len()));
        }
    }
    eprintln!("checked: {}", checked.join(", "));
    // the 18 units of today (a shorter catalog means a unit was dropped)
    assert!(checked.len() >= 2 * 18, "{} configurations", checked.len());
}
