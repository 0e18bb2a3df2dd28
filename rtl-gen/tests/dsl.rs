//! The DSL's checks, the evaluator against the golden model, and the emitter's
//! determinism and small-construct output.

use rtl_gen::builder::ModuleBuilder;
use rtl_gen::emit::emit;
use rtl_gen::eval::Evaluator;
use rtl_gen::ir::Ty;

#[test]
fn width_errors_name_the_signal_and_the_rust_line() {
    let mut m = ModuleBuilder::new("bad");
    let a = m.input("a", Ty::UInt(8));
    let b = m.input("b", Ty::SInt(8));
    let line = line!() + 1;
    let _ = m.add(a, b);
    let c = m.input("c", Ty::UInt(4));
    let _ = m.and(a, c);
    let _ = m.slice(a, 8, 0);
    let errors = m.finish().unwrap_err();
    assert_eq!(errors.0.len(), 3, "{errors}");
    let text = errors.to_string();
    assert!(text.contains(&format!("dsl.rs:{line}:")), "{text}");
    assert!(
        text.contains(
            "signal `a, b`: add needs two UInt or two SInt operands, got UInt<8> and SInt<8>"
        ),
        "{text}"
    );
    assert!(
        text.contains("bitwise operation needs operands of one type, got UInt<8> and UInt<4>"),
        "{text}"
    );
    assert!(
        text.contains("signal `a`: slice [8:0] of UInt<8>"),
        "{text}"
    );
}

#[test]
fn bad_names_and_unfinished_registers_are_reported() {
    let mut m = ModuleBuilder::new("bad");
    m.input("wire", Ty::Bool);
    m.input("9lives", Ty::Bool);
    let x = m.input("x", Ty::UInt(3));
    m.output("x", x);
    m.reg("state", Ty::UInt(2), Some(0));
    let text = m.finish().unwrap_err().to_string();
    for want in [
        "`wire`: port name is not a Verilog identifier",
        "`9lives`: port name",
        "`x`: port name already used",
        "`state`: register was never given a next value",
    ] {
        assert!(text.contains(want), "missing {want:?} in\n{text}");
    }
}

#[test]
fn reading_a_value_before_its_stage_is_an_error() {
    let mut m = ModuleBuilder::new("early");
    let a = m.input("a", Ty::UInt(8));
    let sub = {
        let mut s = ModuleBuilder::new("delay2");
        let x = s.input("x", Ty::UInt(8));
        s.stage();
        s.stage();
        s.output("y", x);
        std::sync::Arc::new(s.finish().unwrap())
    };
    let y = m.instance("u", &sub, &[("x", a)]).all()[0];
    let _ = m.add(y, a);
    let text = m.finish().unwrap_err().to_string();
    assert!(
        text.contains("value of stage 2 read in earlier stage 0"),
        "{text}"
    );
}

#[test]
fn signed_operations_evaluate_and_emit_with_explicit_extension() {
    let mut m = ModuleBuilder::new("signed_ops");
    let a = m.input("a", Ty::SInt(8));
    let b = m.input("b", Ty::SInt(4));
    let s = m.add(a, b);
    let lt = m.lt(a, b);
    let p = m.mul(a, b);
    let sh = m.input("n", Ty::UInt(3));
    let sra = m.shr(a, sh);
    m.output("s", s);
    m.output("lt", lt);
    m.output("p", p);
    m.output("sra", sra);
    let module = m.finish().unwrap();
    let mut ev = Evaluator::new(&module);
    // a = -100, b = -3, n = 2
    let out = ev.eval(&[(-100i128 as u128) & 0xff, 0xd, 2]);
    assert_eq!(out[0], (-103i128 as u128) & 0x1ff);
    assert_eq!(out[1], 1);
    assert_eq!(out[2], 300);
    assert_eq!(out[3], (-25i128 as u128) & 0xff);
    let text = &emit(&module, "test")[0].text;
    for want in [
        "assign add_a_b = {a[7], a} + {{5{b[3]}}, b};",
        // a comparison read once is written where it is read
        "assign lt = $signed(a) < $signed({{4{b[3]}}, b});",
        "assign mul_a_b = $signed(a) * $signed(b);",
        "assign shr_a_n = $signed(a) >>> n;",
        "wire signed [8:0] add_a_b;",
    ] {
        assert!(text.contains(want), "missing {want:?} in\n{text}");
    }
}

#[test]
fn constants_fold_and_derived_names_are_unique_and_stable() {
    let build = || {
        let mut m = ModuleBuilder::new("names");
        let a = m.input("a", Ty::UInt(4));
        let k = m.uint(4, 3);
        let k2 = m.uint(4, 4);
        let folded = m.add(k, k2); // 7, no hardware
        let x = m.add(a, folded);
        let y = m.add(a, folded);
        m.output("x", x);
        m.output("y", y);
        m.finish().unwrap()
    };
    let (m1, m2) = (build(), build());
    let (t1, t2) = (
        emit(&m1, "g")[0].text.clone(),
        emit(&m2, "g")[0].text.clone(),
    );
    assert_eq!(t1, t2, "same module, same bytes");
    // the same expression twice is one wire (hash-consing in the emitter), read by both
    assert_eq!(t1.matches("{2'd0, a} + 6'd7").count(), 1, "{t1}");
    // derived names leave constants out
    assert!(t1.contains("assign add_a = {2'd0, a} + 6'd7;"), "{t1}");
    assert!(t1.contains("assign x = add_a;"), "{t1}");
    assert!(t1.contains("assign y = add_a;"), "{t1}");
    assert!(!t1.contains("add_a_1"), "no counter for a copy: {t1}");
}

#[test]
fn pipeline_registers_only_live_values_and_reports_latency() {
    let mut m = ModuleBuilder::with_handshake("pipe");
    let a = m.input("a", Ty::UInt(8));
    let b = m.input("b", Ty::UInt(8));
    let s = m.add(a, b);
    let s = m.name(s, "sum");
    m.stage();
    m.stage();
    m.output("sum", s);
    let module = m.finish().unwrap();
    assert_eq!(module.latency, 2);
    let text = &emit(&module, "g")[0].text;
    // a and b die in stage 0: only the sum and the valid bit cross the boundaries
    assert!(
        text.contains("reg [8:0] sum_s1;") && text.contains("reg [8:0] sum_s2;"),
        "{text}"
    );
    assert!(!text.contains("a_s1") && !text.contains("b_s1"), "{text}");
    assert!(text.contains("valid_s2 <= valid_s1;"), "{text}");
    let mut ev = Evaluator::new(&module);
    ev.set_reset(true);
    ev.step(&[0, 0, 0]);
    ev.set_reset(false);
    let outs: Vec<Vec<u128>> = [[1, 200, 100], [0, 0, 0], [0, 0, 0], [0, 0, 0]]
        .iter()
        .map(|i| ev.step(i))
        .collect();
    assert_eq!(
        outs[2],
        vec![1, 300],
        "valid and sum two cycles after the input"
    );
    assert_eq!(outs[1][0], 0);
    assert_eq!(outs[3][0], 0);
}

#[test]
fn mulcmp_evaluator_matches_golden_model_for_every_stage_count() {
    let mut seed = 0x1234_5678_9abc_def0u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for (aw, bw) in [(16, 16), (7, 13), (1, 1), (32, 32)] {
        for stages in 0..=5 {
            let module = rtl_gen::units::mulcmp::build(&rtl_gen::units::mulcmp::Config {
                a_width: aw,
                b_width: bw,
                stages,
            });
            assert_eq!(module.latency, stages);
            let mut ev = Evaluator::new(&module);
            ev.set_reset(true);
            ev.step(&[0; 5]);
            ev.set_reset(false);
            let mask = |w: u32, v: u64| if w == 64 { v } else { v & ((1 << w) - 1) };
            let vectors: Vec<[u64; 4]> = (0..200)
                .map(|_| {
                    [
                        mask(aw, next()),
                        mask(bw, next()),
                        mask(aw, next()),
                        mask(bw, next()),
                    ]
                })
                .collect();
            let mut got = Vec::new();
            for cycle in 0..vectors.len() + stages as usize {
                let v = vectors.get(cycle);
                let inp = match v {
                    Some(v) => [1, v[0] as u128, v[1] as u128, v[2] as u128, v[3] as u128],
                    None => [0; 5],
                };
                let out = ev.step(&inp);
                if out[0] == 1 {
                    got.push(out);
                }
            }
            assert_eq!(got.len(), vectors.len(), "aw={aw} bw={bw} stages={stages}");
            for (v, out) in vectors.iter().zip(&got) {
                let g = golden_model::mulcmp::eval(v[0], v[1], v[2], v[3]);
                assert_eq!(
                    (out[1], out[2], out[3]),
                    (g.lt as u128, g.eq as u128, g.ab),
                    "{v:?} aw={aw} bw={bw} stages={stages}"
                );
            }
        }
    }
}

#[test]
fn registers_reset_synchronously_and_hold_without_enable() {
    let mut m = ModuleBuilder::new("counter");
    let en = m.input("en", Ty::Bool);
    let count = m.reg("count_q", Ty::UInt(3), Some(5));
    let one = m.uint(3, 1);
    let next = m.add(count.q, one);
    let next = rtl_gen::arith::int::zext(&mut m, next, 3);
    m.set_next(count, next, Some(en));
    m.output("count", count.q);
    let module = m.finish().unwrap();
    let mut ev = Evaluator::new(&module);
    ev.set_reset(true);
    ev.step(&[1]);
    ev.set_reset(false);
    let seen: Vec<u128> = [1, 1, 0, 1, 1, 1]
        .iter()
        .map(|&e| ev.step(&[e])[0])
        .collect();
    assert_eq!(
        seen,
        vec![5, 6, 7, 7, 0, 1],
        "reset to 5, count when enabled, wrap at 8"
    );
    let text = &emit(&module, "g")[0].text;
    assert!(text.contains("if (rst) begin\n            count_q <= 3'd5;\n        end else begin\n            if (en) begin"), "{text}");
}

#[test]
fn systemverilog_keywords_are_not_names() {
    let mut m = ModuleBuilder::new("kw");
    let a = m.input("class", Ty::Bool);
    m.output("packed", a);
    let text = m.finish().unwrap_err().to_string();
    assert!(
        text.contains("`class`: port name is not a Verilog identifier"),
        "{text}"
    );
    assert!(
        text.contains("`packed`: port name is not a Verilog identifier"),
        "{text}"
    );
}

/// Words Verilator's C++ model reserves (SYMRSVDWORD under `-Wall`) are not
/// names either: `near`/`far` were ports of the slab's axis block once.
#[test]
fn cpp_words_verilator_reserves_are_not_names() {
    let mut m = ModuleBuilder::new("cpp");
    let a = m.input("near", Ty::Bool);
    m.output("far", a);
    let text = m.finish().unwrap_err().to_string();
    for port in ["near", "far"] {
        assert!(
            text.contains(&format!("`{port}`: port name is not a Verilog identifier")),
            "{text}"
        );
    }
}

#[test]
fn bits_left_unread_through_a_cast_get_the_narrow_waiver() {
    let mut m = ModuleBuilder::new("cast_slice");
    let a = m.input("a", Ty::SInt(8));
    let b = m.input("b", Ty::SInt(8));
    let d = m.sub(a, b); // SInt<9>
    let d = m.name(d, "diff");
    let u = m.as_uint(d);
    let low = m.slice(u, 3, 0);
    m.output("low", low);
    let module = m.finish().unwrap();
    let text = &emit(&module, "g")[0].text;
    assert!(text.contains("// bits [8:4] of this wire are not read by design\n    /* verilator lint_off UNUSEDSIGNAL */\n    wire signed [8:0] diff;"), "{text}");
    // the inputs' bits are all read by the subtraction: no waiver there
    assert!(text.contains("    input wire signed [7:0] a,\n"), "{text}");
}

#[test]
fn unsigned_comparisons_with_zero_that_are_constant_fold_away() {
    let mut m = ModuleBuilder::new("cmp_zero");
    let a = m.input("a", Ty::UInt(8));
    let zero = m.uint(8, 0);
    let never = m.lt(a, zero);
    let always = m.ge(a, zero);
    let positive = m.gt(a, zero);
    m.output("never", never);
    m.output("at_least_zero", always);
    m.output("positive", positive);
    let module = m.finish().unwrap();
    let text = &emit(&module, "g")[0].text;
    assert!(
        text.contains("assign never = 1'b0;") && text.contains("assign at_least_zero = 1'b1;"),
        "{text}"
    );
    assert!(text.contains("8'd0 < a"), "{text}");
}

#[test]
fn evaluator_handles_deep_hierarchies_in_linear_time() {
    // a chain of 12 nested modules around one register: each instance is
    // evaluated once per cycle (re-evaluating per read or per clock took 2^12)
    let mut inner = {
        let mut b = ModuleBuilder::new("leaf");
        let x = b.input("x", Ty::UInt(8));
        b.stage();
        b.output("y", x);
        std::sync::Arc::new(b.finish().unwrap())
    };
    for level in 0..12 {
        let mut b = ModuleBuilder::new(format!("wrap{level}"));
        let x = b.input("x", Ty::UInt(8));
        let outs = b.instance("u", &inner, &[("x", x)]);
        let y = outs.all()[0];
        for _ in 0..inner.latency {
            b.stage();
        }
        b.output("y", y);
        inner = std::sync::Arc::new(b.finish().unwrap());
    }
    assert_eq!(inner.latency, 1);
    let mut ev = Evaluator::new(&inner);
    let outs: Vec<u128> = (0..2000u128).map(|i| ev.step(&[i & 0xff])[0]).collect();
    assert!(
        (1..2000).all(|i| outs[i] == (i as u128 - 1) & 0xff),
        "one cycle of latency"
    );
}
