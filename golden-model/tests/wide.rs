//! Compressed wide-BVH nodes (`golden_model::wide`) against an exact
//! reference: every decoded child box (origin + integer·2^scale, computed
//! here in big integers from the IEEE definitions, `common::exact`) contains
//! the exact child box, exceeds it by less than one step per side, and the
//! frame is the tightest the format allows (the largest origin, the smallest
//! scale). Random and adversarial boxes in binary32, e5m10 and bfloat16;
//! the checker itself is shown to reject looser quantisations; bad input
//! gives the error; the record packs and unpacks through the table of
//! `docs/wide.md`.

mod common;

use common::exact::{cmp, decode, sum, V};
use common::Rng;
use dashu::integer::UBig;
use golden_model::float::{nudge, to_f64, FloatFormat, RoundingMode};
use golden_model::wide::{
    encode, ChildBox, ChildKind, ChildRef, EncodeError, FieldKind, Node, WideFormat, MAX_CHILDREN,
};
use std::cmp::Ordering;

type Slots = Vec<Option<(ChildBox, ChildKind)>>;

/// `n · 2^e` exactly.
fn scaled(n: u64, e: i32) -> V {
    if n == 0 {
        V::Zero(false)
    } else {
        V::Fin {
            neg: false,
            mag: UBig::from(n),
            exp: e as i64,
        }
    }
}

fn add(a: &V, b: &V) -> V {
    sum(&[a.clone(), b.clone()], RoundingMode::NearestEven)
}

fn neg(a: &V) -> V {
    match a.clone() {
        V::Fin { neg, mag, exp } => V::Fin {
            neg: !neg,
            mag,
            exp,
        },
        V::Zero(s) => V::Zero(!s),
        v => v,
    }
}

fn f64v(x: f64) -> V {
    decode(FloatFormat::BINARY64, x.to_bits())
}

fn le(a: &V, b: &V) -> bool {
    cmp(a, b) != Some(Ordering::Greater)
}

fn lt(a: &V, b: &V) -> bool {
    cmp(a, b) == Some(Ordering::Less)
}

/// Node bounds of the valid children, per axis.
fn node_bounds(slots: &Slots, a: usize) -> (f64, f64) {
    let boxes = slots.iter().flatten().map(|(b, _)| b);
    let lo = boxes
        .clone()
        .map(|b| b.min[a])
        .fold(f64::INFINITY, f64::min);
    let hi = boxes.map(|b| b.max[a]).fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

/// The exact checks of one encoded node (`Err` says which failed).
fn check_node(w: WideFormat, slots: &Slots, n: &Node) -> Result<(), String> {
    let fmt = w.fmt();
    let q_max = w.q_max() as u64;
    for a in 0..3 {
        let (lo, hi) = node_bounds(slots, a);
        let o = decode(fmt, n.frame.origin[a]);
        let e = n.frame.exp[a];
        // the frame: the largest origin of the format at or below every child
        if !le(&o, &f64v(lo)) {
            return Err(format!("axis {a}: origin above the children"));
        }
        if n.frame.origin[a] == fmt.zero(true) {
            return Err(format!("axis {a}: origin −0 (the encoding is +0)"));
        }
        let next = nudge(fmt, n.frame.origin[a], 1);
        if next != n.frame.origin[a] && le(&decode(fmt, next), &f64v(lo)) {
            return Err(format!("axis {a}: a larger origin fits"));
        }
        // the smallest scale: D ≤ (2^q − 1)·2^e, and (2^q − 1)·2^(e−1) < D
        // unless e is the format's smallest normal exponent
        let d = add(&f64v(hi), &neg(&o));
        if !(fmt.emin()..=fmt.emax()).contains(&e) {
            return Err(format!("axis {a}: scale 2^{e} outside the format"));
        }
        if !le(&d, &scaled(q_max, e)) {
            return Err(format!("axis {a}: the node does not fit 2^q − 1 steps"));
        }
        if e > fmt.emin() && !lt(&scaled(q_max, e - 1), &d) {
            return Err(format!("axis {a}: scale 2^{e} is not the smallest"));
        }
    }
    for (i, s) in slots.iter().enumerate() {
        let Some((b, kind)) = s else {
            if n.child(i) != ChildRef::Empty || n.decoded_outward(w, i, fmt).is_some() {
                return Err(format!("slot {i}: empty slot decodes to a child"));
            }
            continue;
        };
        match (kind, n.child(i)) {
            (ChildKind::Inner, ChildRef::Inner(_)) => {}
            (ChildKind::Leaf(c), ChildRef::Leaf { count, .. }) if *c == count => {}
            (k, r) => return Err(format!("slot {i}: {k:?} decodes as {r:?}")),
        }
        for a in 0..3 {
            let o = decode(fmt, n.frame.origin[a]);
            let e = n.frame.exp[a];
            let (ql, qh) = (n.lo[i][a] as u64, n.hi[i][a] as u64);
            if ql > qh || qh > q_max {
                return Err(format!(
                    "slot {i} axis {a}: integers {ql}, {qh} out of order"
                ));
            }
            let dec_lo = add(&o, &scaled(ql, e));
            let dec_hi = add(&o, &scaled(qh, e));
            let (min, max) = (f64v(b.min[a]), f64v(b.max[a]));
            // soundness: the decoded box contains the exact one
            if !le(&dec_lo, &min) || !le(&max, &dec_hi) {
                return Err(format!(
                    "slot {i} axis {a}: decoded box does not contain [{}, {}]",
                    b.min[a], b.max[a]
                ));
            }
            // tightness: less than one step of excess per side
            let step = scaled(1, e);
            if !lt(&min, &add(&dec_lo, &step)) || !lt(&add(&dec_hi, &neg(&step)), &max) {
                return Err(format!("slot {i} axis {a}: a whole step of excess"));
            }
            // the outward rounding to binary32 and to the ray format keeps it
            for out in [FloatFormat::BINARY32, fmt] {
                let (l, h) = n.decoded_outward(w, i, out).unwrap();
                if !le(&decode(out, l[a]), &dec_lo) || !le(&dec_hi, &decode(out, h[a])) {
                    return Err(format!("slot {i} axis {a}: {out} outward box too small"));
                }
            }
        }
    }
    Ok(())
}

/// Why a node must fail to encode, from the exact rules (`None`: it must encode).
fn expected_error(w: WideFormat, slots: &Slots) -> Option<&'static str> {
    let fmt = w.fmt();
    let boxes: Vec<&ChildBox> = slots.iter().flatten().map(|(b, _)| b).collect();
    if boxes.is_empty() {
        return Some("no children");
    }
    for b in &boxes {
        for a in 0..3 {
            if !b.min[a].is_finite() || !b.max[a].is_finite() {
                return Some("non-finite");
            }
            if b.min[a] > b.max[a] {
                return Some("inverted");
            }
        }
    }
    for a in 0..3 {
        let (lo, hi) = node_bounds(slots, a);
        let most_negative = to_f64(fmt, fmt.max_finite(true));
        if lo < most_negative {
            return Some("origin");
        }
        // the origin is the format's value at or below lo; D from it
        let mut o = fmt.max_finite(true);
        let mut step_up = 1i64 << 40;
        while step_up > 0 {
            let t = nudge(fmt, o, step_up);
            if t != o && to_f64(fmt, t) <= lo {
                o = t;
            } else {
                step_up /= 2;
            }
        }
        let d = add(&f64v(hi), &neg(&decode(fmt, o)));
        if !le(&d, &scaled(w.q_max() as u64, fmt.emax())) {
            return Some("scale");
        }
    }
    None
}

fn kind_of(err: &EncodeError) -> &'static str {
    match err {
        EncodeError::NoChildren => "no children",
        EncodeError::NonFinite { .. } => "non-finite",
        EncodeError::Inverted { .. } => "inverted",
        EncodeError::OriginOutOfRange { .. } => "origin",
        EncodeError::ScaleOutOfRange { .. } => "scale",
        _ => "other",
    }
}

/// A coordinate of one of several adversarial families.
fn coord(rng: &mut Rng, fmt: FloatFormat, family: u64) -> f64 {
    let max = to_f64(fmt, fmt.max_finite(false));
    let tiny = to_f64(fmt, fmt.min_subnormal(false));
    let sign = if rng.bool() { -1.0 } else { 1.0 };
    let pow = |e: i64| 2f64.powi(e as i32);
    match family {
        // scene-like: moderate magnitudes
        0 => sign * rng.range(1, 1 << 20) as f64 * pow(rng.range(-24, 4)),
        // far from the origin, near the top of the format
        1 => {
            sign * to_f64(
                fmt,
                fmt.max_finite(false) - rng.below(1 << 8.min(fmt.frac_bits())),
            )
        }
        // tiny: multiples of the smallest subnormal
        2 => sign * rng.range(0, 1 << 12) as f64 * tiny,
        // any finite value of the format
        3 => loop {
            let bits = rng.next() & fmt.mask();
            if fmt.is_finite(bits) {
                break to_f64(fmt, bits);
            }
        },
        // binary64 values that the format cannot hold, within its range
        4 => sign * (rng.next() >> 11) as f64 * pow(-53) * max * pow(-rng.range(0, 30)),
        // the ends of the range
        _ => [
            max,
            -max,
            tiny,
            -tiny,
            0.0,
            -0.0,
            to_f64(fmt, fmt.min_normal(false)),
        ][rng.below(7) as usize],
    }
}

/// A random node: children from one family (sometimes mixed), some
/// flat, some straddling zero, empty slots, inner and leaf kinds.
fn random_slots(rng: &mut Rng, w: WideFormat) -> Slots {
    let fmt = w.fmt();
    let n = 1 + rng.below(w.children() as u64) as usize;
    let family = rng.below(6);
    let far = to_f64(fmt, fmt.max_finite(false)) * 2f64.powi(-(rng.range(1, 8) as i32));
    (0..n)
        .map(|_| {
            if rng.below(6) == 0 {
                return None;
            }
            let f = if rng.below(4) == 0 {
                rng.below(6)
            } else {
                family
            };
            let mut min = [0.0; 3];
            let mut max = [0.0; 3];
            for a in 0..3 {
                let mut x = coord(rng, fmt, f);
                let mut y = match rng.below(5) {
                    0 => x,                       // flat
                    1 => -x,                      // symmetric about zero
                    2 => coord(rng, fmt, f),      // independent
                    3 if f == 1 => x - far / 1e6, // a small box far out
                    _ => x + (x.abs() + 1.0) * 2f64.powi(-(rng.range(0, 40) as i32)),
                };
                if !y.is_finite() {
                    y = x;
                }
                if x > y {
                    std::mem::swap(&mut x, &mut y);
                }
                min[a] = x;
                max[a] = y;
            }
            let kind = if rng.bool() {
                ChildKind::Inner
            } else {
                ChildKind::Leaf(1 + rng.below(7) as u32)
            };
            Some((ChildBox { min, max }, kind))
        })
        .collect()
}

fn formats() -> [FloatFormat; 3] {
    [
        FloatFormat::BINARY32,
        FloatFormat::BINARY16, // e5m10
        FloatFormat::BFLOAT16,
    ]
}

#[test]
fn decoded_boxes_contain_the_exact_boxes_and_are_tight() {
    let mut rng = Rng::new(36);
    let (mut nodes, mut errors, mut children) = (0u64, 0u64, 0u64);
    for fmt in formats() {
        for n in [2, 4, 8] {
            for q in [4, 5, 8, 12, 16] {
                let w = WideFormat::new(fmt, n, q).unwrap();
                for _ in 0..4000 {
                    let slots = random_slots(&mut rng, w);
                    let want = expected_error(w, &slots);
                    match (encode(w, &slots, 0, 0), want) {
                        (Ok(node), None) => {
                            if let Err(e) = check_node(w, &slots, &node) {
                                panic!("{fmt} N={n} q={q}: {e}\nslots {slots:?}\nnode {node:?}");
                            }
                            assert_eq!(Node::unpack(w, &node.pack(w)), Ok(node));
                            nodes += 1;
                            children += slots.iter().flatten().count() as u64;
                        }
                        (Err(e), Some(k)) if kind_of(&e) == k => errors += 1,
                        (got, want) => panic!(
                            "{fmt} N={n} q={q}: got {got:?}, expected error {want:?}\nslots {slots:?}"
                        ),
                    }
                }
            }
        }
    }
    println!("{nodes} nodes ({children} children) checked exactly, {errors} rightly refused");
    // the families reach both outcomes, and mostly encode
    assert!(
        nodes > 150_000 && errors > 1000,
        "{nodes} nodes, {errors} errors"
    );
}

#[test]
fn adversarial_nodes_at_the_ends_of_the_formats() {
    for fmt in formats() {
        let max = to_f64(fmt, fmt.max_finite(false));
        let tiny = to_f64(fmt, fmt.min_subnormal(false));
        let min_normal = to_f64(fmt, fmt.min_normal(false));
        let cases: Vec<[(f64, f64); 2]> = vec![
            [(-max, max), (0.0, 0.0)],         // the whole range: largest scale
            [(max, max), (max, max)],          // flat at the top
            [(-max, -max), (-max, -max)],      // flat at the bottom
            [(0.0, tiny), (tiny, 2.0 * tiny)], // subnormal boxes: scale 2^emin
            [(-tiny, tiny), (-0.0, 0.0)],      // straddling zero, tiny
            [(min_normal, min_normal * 3.0), (min_normal, min_normal)],
            [
                (max / 2.0, max / 2.0 + max / 1024.0),
                (max / 2.0, max / 2.0),
            ], // far, narrow
            [(-1.0, 1.0), (0.5, 0.5)],
            [(-3.0 * tiny, -tiny), (-2.0 * tiny, -2.0 * tiny)],
        ];
        for n in [2, 4, 8] {
            for q in 4..=16 {
                let w = WideFormat::new(fmt, n, q).unwrap();
                for c in &cases {
                    let slots: Slots = c
                        .iter()
                        .enumerate()
                        .map(|(k, &(lo, hi))| {
                            // the pair on one axis, its mirror and a mix on the others
                            let b = ChildBox {
                                min: [lo, -hi, lo.min(-hi)],
                                max: [hi, -lo, hi.max(-lo)],
                            };
                            Some((b, ChildKind::Leaf(1 + k as u32)))
                        })
                        .collect();
                    let node = encode(w, &slots, 3, 9).unwrap_or_else(|e| panic!("{c:?}: {e}"));
                    check_node(w, &slots, &node).unwrap_or_else(|e| panic!("{fmt} {c:?}: {e}"));
                }
            }
        }
    }
}

/// The checker is not vacuous: a node quantised one step looser, with a
/// larger scale, or with an integer moved inward fails it.
#[test]
fn looser_or_unsound_nodes_fail_the_checker() {
    let mut rng = Rng::new(7);
    let w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let (mut looser, mut coarser, mut inward) = (0, 0, 0);
    for _ in 0..2000 {
        let slots = random_slots(&mut rng, w);
        let Ok(node) = encode(w, &slots, 0, 0) else {
            continue;
        };
        let Some(i) = slots.iter().position(Option::is_some) else {
            continue;
        };
        let a = rng.below(3) as usize;
        // one more step of excess on the upper side (still sound)
        if node.hi[i][a] < w.q_max() as u16 {
            let mut m = node;
            m.hi[i][a] += 1;
            assert!(check_node(w, &slots, &m).is_err());
            looser += 1;
        }
        // a twice larger scale with the integers re-rounded outward (still sound)
        if node.frame.exp[a] < FloatFormat::BINARY32.emax() {
            let mut m = node;
            m.frame.exp[a] += 1;
            for s in 0..MAX_CHILDREN {
                m.lo[s][a] /= 2;
                m.hi[s][a] = m.hi[s][a].div_ceil(2);
            }
            assert!(check_node(w, &slots, &m).is_err());
            coarser += 1;
        }
        // an integer moved inward: the decoded box misses part of the child
        let b = slots[i].unwrap().0;
        if b.min[a] < b.max[a] && node.lo[i][a] < node.hi[i][a] {
            let mut m = node;
            m.lo[i][a] += 1;
            assert!(check_node(w, &slots, &m).is_err());
            inward += 1;
        }
    }
    assert!(looser > 100 && coarser > 100 && inward > 100);
}

#[test]
fn bad_input_is_an_error() {
    let f32w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let unit = ChildBox {
        min: [0.0; 3],
        max: [1.0; 3],
    };
    let with = |a: usize, lo: f64, hi: f64| {
        let mut b = unit;
        b.min[a] = lo;
        b.max[a] = hi;
        vec![Some((unit, ChildKind::Inner)), Some((b, ChildKind::Inner))]
    };
    let err = |w, s: &Slots| encode(w, s, 0, 0).unwrap_err();
    assert!(matches!(
        err(f32w, &with(1, f64::NAN, 1.0)),
        EncodeError::NonFinite {
            slot: 1,
            axis: 1,
            ..
        }
    ));
    assert!(matches!(
        err(f32w, &with(2, 0.0, f64::INFINITY)),
        EncodeError::NonFinite {
            slot: 1,
            axis: 2,
            ..
        }
    ));
    assert!(matches!(
        err(f32w, &with(0, 2.0, 1.0)),
        EncodeError::Inverted {
            slot: 1,
            axis: 0,
            ..
        }
    ));
    // below binary32's range: no origin
    assert!(matches!(
        err(f32w, &with(0, -1e39, 0.0)),
        EncodeError::OriginOutOfRange { axis: 0, .. }
    ));
    // e5m10, q = 4: an extent of 10^7 needs 2^20 > 2^15
    let h = WideFormat::new(FloatFormat::BINARY16, 2, 4).unwrap();
    assert!(matches!(
        err(h, &with(2, 0.0, 1e7)),
        EncodeError::ScaleOutOfRange {
            axis: 2,
            exp: 20,
            emax: 15
        }
    ));
    assert!(matches!(
        err(f32w, &vec![None, None]),
        EncodeError::NoChildren
    ));
    assert!(matches!(
        err(f32w, &vec![Some((unit, ChildKind::Inner)); 5]),
        EncodeError::TooManyChildren { given: 5, slots: 4 }
    ));
    for count in [0, 8] {
        assert!(matches!(
            err(f32w, &vec![Some((unit, ChildKind::Leaf(count)))]),
            EncodeError::LeafCount { slot: 0, .. }
        ));
    }
    let b32 = FloatFormat::BINARY32;
    assert_eq!(WideFormat::new(b32, 3, 8), Err(EncodeError::Children(3)));
    assert_eq!(WideFormat::new(b32, 4, 3), Err(EncodeError::BoxBits(3)));
    assert_eq!(WideFormat::new(b32, 4, 17), Err(EncodeError::BoxBits(17)));
    assert!(matches!(
        WideFormat::new(FloatFormat::BINARY64, 4, 8),
        Err(EncodeError::Format(_))
    ));
    // every message names what is wrong
    assert!(err(f32w, &with(0, 2.0, 1.0))
        .to_string()
        .contains("above max"));
}

#[test]
fn corrupted_records_are_refused() {
    let w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let unit = ChildBox {
        min: [0.0; 3],
        max: [1.0; 3],
    };
    let node = encode(
        w,
        &[
            Some((unit, ChildKind::Inner)),
            None,
            Some((unit, ChildKind::Leaf(2))),
        ],
        5,
        11,
    )
    .unwrap();
    let bytes = node.pack(w);
    assert_eq!(bytes.len(), w.record_bytes() as usize);
    assert_eq!(Node::unpack(w, &bytes), Ok(node));
    let field = |k: FieldKind| w.fields().into_iter().find(|f| f.kind == k).unwrap();
    let flip = |k: FieldKind, bit: u32| {
        let f = field(k);
        let mut b = bytes.clone();
        let at = f.offset + bit;
        b[(at / 8) as usize] ^= 1 << (at % 8);
        Node::unpack(w, &b)
    };
    let bad = |r: Result<Node, EncodeError>| matches!(r, Err(EncodeError::Record(_)));
    assert!(bad(Node::unpack(w, &bytes[1..])));
    // origin exponent all ones: infinity or NaN
    let mut b = bytes.clone();
    let o = field(FieldKind::Origin(0));
    for bit in 23..31 {
        let at = o.offset + bit;
        b[(at / 8) as usize] |= 1 << (at % 8);
    }
    assert!(bad(Node::unpack(w, &b)));
    // scale exponent field 0 is reserved (e = −7 + 127 = 120 = 0b1111000)
    let mut b = bytes.clone();
    let e = field(FieldKind::Exp(1));
    for bit in 0..8 {
        let at = e.offset + bit;
        b[(at / 8) as usize] &= !(1 << (at % 8));
    }
    assert!(bad(Node::unpack(w, &b)));
    // slot 1 made valid is a well-formed inner slot (lo = hi = 0): accepted
    assert!(flip(FieldKind::Valid, 1).is_ok());
    assert!(bad(flip(FieldKind::Leaf, 0))); // an inner slot marked leaf has count 0
    assert!(bad(flip(FieldKind::Count(0), 0))); // a count on an inner slot
    assert!(bad(flip(FieldKind::Count(2), 1))); // leaf count 2 -> 0 is refused
    assert!(bad(flip(FieldKind::Lo(1, 0), 0))); // a bit in the empty slot
    assert!(bad(flip(FieldKind::Leaf, 3))); // leaf bit of an empty slot
                                            // lo = 129 above hi = 128
    let mut b = bytes.clone();
    let l = field(FieldKind::Lo(0, 2));
    for bit in [0, 7] {
        let at = l.offset + bit;
        b[(at / 8) as usize] |= 1 << (at % 8);
    }
    assert!(bad(Node::unpack(w, &b)));
    // a padding bit above the record (608 bits fill 76 bytes: pad a 4-slot record)
    let last = w.record_bits();
    if !last.is_multiple_of(8) {
        let mut b = bytes.clone();
        b[(last / 8) as usize] |= 1 << (last % 8);
        assert!(bad(Node::unpack(w, &b)));
    }
}
