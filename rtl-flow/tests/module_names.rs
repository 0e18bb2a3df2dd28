//! A module's name identifies its Verilog: the emitter writes one file per
//! module name and keeps the first module of a name it meets
//! (`Module::hierarchy`), so two different modules under one name would
//! silently lose one of them, in one design or in a project that generates
//! several configurations into one directory. Every unit of the catalog, at a
//! few configurations each: one name, one text.

use rtl_gen::emit::{lower::lower, print, EmitOptions};
use rtl_gen::params::Params;
use std::collections::BTreeMap;

/// Parameter variants tried on every unit (a unit refuses the ones it has
/// no parameter for, or cannot build: those are skipped).
const VARIANTS: &[&[(&str, &str)]] = &[
    &[("exp_bits", "5"), ("frac_bits", "4")],
    &[("exp_bits", "5"), ("frac_bits", "4"), ("stages", "2")],
    &[("exp_bits", "4"), ("frac_bits", "3"), ("stages", "1")],
    &[("exp_bits", "5"), ("frac_bits", "4"), ("mode", "ray")],
    &[("exp_bits", "5"), ("frac_bits", "4"), ("mode", "bundle")],
    &[("exp_bits", "5"), ("frac_bits", "4"), ("children", "2")],
    &[
        ("exp_bits", "5"),
        ("frac_bits", "4"),
        ("pipeline", "balanced"),
        ("stages", "2"),
    ],
];

#[test]
fn a_module_name_names_one_module_across_units_and_configurations() {
    // name -> (text, the unit and parameters that first built it)
    let mut seen: BTreeMap<String, (String, String)> = BTreeMap::new();
    let mut built = 0;
    for entry in rtl_flow::catalog() {
        let unit = entry.unit;
        for given in VARIANTS {
            let Ok(p) = Params::check(unit.name(), unit.params(), given.iter().copied()) else {
                continue;
            };
            let Ok(top) = unit.build(&p) else { continue };
            built += 1;
            let origin = format!("{} {given:?}", unit.name());
            for m in top.hierarchy() {
                // as a submodule: no top header, so a unit's top and the same
                // module inside another unit compare equal
                let text = print::module(&lower(m, "test", false, EmitOptions::default()));
                match seen.get(&m.name) {
                    None => {
                        seen.insert(m.name.clone(), (text, origin.clone()));
                    }
                    Some((first, first_origin)) => assert!(
                        *first == text,
                        "two different modules named {}: from {first_origin} and from {origin}",
                        m.name
                    ),
                }
            }
        }
    }
    // every unit built at least once, and submodules shared by name
    assert!(built >= rtl_flow::catalog().len(), "{built} builds");
    assert!(seen.len() > built, "{} names in {built} builds", seen.len());
}
