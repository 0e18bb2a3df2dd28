//! Compressed wide-BVH nodes (issue 36, step 1): a node of N = 2, 4 or 8
//! child slots whose boxes are stored as unsigned q-bit integers (q = 4..=16)
//! in a per-node frame, as in Ylitie, Karras and Laine (HPG 2017) and AMD
//! RDNA4's quantised boxes. The record and its proof are in `docs/wide.md`;
//! the table there is checked against [`WideFormat::fields`] by a test.
//!
//! **Frame**: per axis `a` an origin `o_a` (a finite value of the ray format
//! `fmt`) and a scale exponent `e_a` (the unbiased exponent of a normal power
//! of two of `fmt`, `emin ≤ e_a ≤ emax`). **Child box** of slot `i`: per axis
//! two integers `lo, hi ∈ [0, 2^q − 1]`; the decoded box is the exact value
//! `[o_a + lo·2^e_a, o_a + hi·2^e_a]` (an exact dyadic rational: nothing
//! rounds when decoding).
//!
//! **Encoding** ([`encode`]), from exact child boxes (any finite binary64
//! values), per axis:
//! 1. `o = RDN_fmt(min over valid children of min)`: the largest value of
//!    the format at or below every child (no larger origin can keep `lo ≥ 0`);
//! 2. `D = max over valid children of max − o` (exact, `D ≥ 0`); `e` is the
//!    smallest exponent in `[emin, emax]` with `D ≤ (2^q − 1)·2^e` (so the
//!    step `2^e` is the smallest the scale field allows);
//! 3. per child `lo = ⌊(min − o)/2^e⌋`, `hi = ⌈(max − o)/2^e⌉` (outward).
//!
//! Hence `o + lo·2^e ≤ min < o + (lo + 1)·2^e` and `o + (hi − 1)·2^e < max ≤
//! o + hi·2^e`: the decoded box contains the exact box and exceeds it by less
//! than one step `2^e` per side, with `2^e < 2·D/(2^q − 1)` unless `e = emin`.
//! The arithmetic is exact (big integers, `dashu`); every unencodable input
//! is an [`EncodeError`], never a panic.

use crate::float::{convert, FloatFormat, RoundingMode};
use dashu::base::BitTest;
use dashu::integer::{IBig, UBig};
use std::fmt;

/// The most child slots a node has (the arrays of [`Node`] are this long).
pub const MAX_CHILDREN: usize = 8;
/// Bits of a slot's primitive count (a leaf holds 1 to 7 primitives).
pub const COUNT_BITS: u32 = 3;
/// Bits of the node's first-inner-child index and of its first-primitive index.
pub const BASE_BITS: u32 = 32;
/// Bits of one binary32 coordinate in the uncompressed baseline record.
pub const BASELINE_COORD_BITS: u32 = 32;

/// The shape of a compressed node: ray format, slots, integer width.
/// Only [`WideFormat::new`] makes one, so every value is valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct WideFormat {
    fmt: FloatFormat,
    children: usize,
    box_bits: u32,
}

/// Why a node cannot be encoded (or a record not decoded).
#[derive(Debug, Clone, PartialEq)]
pub enum EncodeError {
    /// `children` is not 2, 4 or 8.
    Children(usize),
    /// `box_bits` is outside `4..=16`.
    BoxBits(u32),
    /// the ray format has more than 10 exponent bits (decoded coordinates
    /// must stay inside binary64's range)
    Format(FloatFormat),
    /// more children than slots
    TooManyChildren {
        /// children given
        given: usize,
        /// slots of the format
        slots: usize,
    },
    /// no valid child: a node needs at least one
    NoChildren,
    /// a NaN or infinite coordinate
    NonFinite {
        /// slot
        slot: usize,
        /// axis 0..3
        axis: usize,
        /// the coordinate
        value: f64,
    },
    /// `min > max`
    Inverted {
        /// slot
        slot: usize,
        /// axis 0..3
        axis: usize,
        /// lower bound
        min: f64,
        /// upper bound
        max: f64,
    },
    /// the children's lower bound is below the format's most negative
    /// finite value: no origin at or below it
    OriginOutOfRange {
        /// axis 0..3
        axis: usize,
        /// the lowest child coordinate
        min: f64,
    },
    /// the node's extent needs a scale above `2^emax` of the format
    ScaleOutOfRange {
        /// axis 0..3
        axis: usize,
        /// the smallest exponent that would fit
        exp: i32,
        /// the format's largest
        emax: i32,
    },
    /// a leaf slot with 0 or more than `2^COUNT_BITS − 1` primitives
    LeafCount {
        /// slot
        slot: usize,
        /// primitives
        count: u32,
    },
    /// a record whose bytes do not decode to a node (wrong length, an
    /// origin that is NaN or infinite, a reserved scale exponent, a valid
    /// slot with `lo > hi`, a bit set in an unused slot)
    Record(String),
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EncodeError::Children(n) => write!(f, "children = {n}: expected 2, 4 or 8"),
            EncodeError::BoxBits(q) => write!(f, "box bits = {q}: expected 4..=16"),
            EncodeError::Format(x) => write!(
                f,
                "ray format {x}: at most 10 exponent bits (decoded boxes must fit binary64)"
            ),
            EncodeError::TooManyChildren { given, slots } => {
                write!(f, "{given} children for a node of {slots} slots")
            }
            EncodeError::NoChildren => write!(f, "a node needs at least one valid child"),
            EncodeError::NonFinite { slot, axis, value } => write!(
                f,
                "child {slot}, axis {axis}: coordinate {value} is not finite"
            ),
            EncodeError::Inverted {
                slot,
                axis,
                min,
                max,
            } => write!(f, "child {slot}, axis {axis}: min {min} above max {max}"),
            EncodeError::OriginOutOfRange { axis, min } => write!(
                f,
                "axis {axis}: lowest coordinate {min} is below the ray format's range (no origin)"
            ),
            EncodeError::ScaleOutOfRange { axis, exp, emax } => write!(
                f,
                "axis {axis}: the node's extent needs scale 2^{exp}, above the format's 2^{emax}"
            ),
            EncodeError::LeafCount { slot, count } => write!(
                f,
                "child {slot}: a leaf of {count} primitives (1..={} fit the record)",
                (1u32 << COUNT_BITS) - 1
            ),
            EncodeError::Record(what) => write!(f, "bad node record: {what}"),
        }
    }
}

impl std::error::Error for EncodeError {}

/// One field of the packed record: bits `offset .. offset + width`,
/// counted from bit 0 of byte 0 (little-endian bit order).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// what the field holds
    pub kind: FieldKind,
    /// first bit
    pub offset: u32,
    /// bits
    pub width: u32,
}

/// What a record field holds (axes 0..3 = x, y, z; slots 0..N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    /// the frame origin of an axis, bits of the ray format
    Origin(usize),
    /// the scale of an axis: biased exponent of the power of two in the
    /// ray format, `1 ..= 2^E − 2`
    Exp(usize),
    /// bit i set: slot i holds a child
    Valid,
    /// bit i set: slot i is a leaf (primitive range), else an inner node
    Leaf,
    /// node index of the first inner child (inner children are stored
    /// consecutively in slot order)
    ChildBase,
    /// index of the first primitive of the leaf slots (their ranges follow
    /// each other in slot order)
    PrimBase,
    /// primitives of a leaf slot (0 for inner and empty slots)
    Count(usize),
    /// the lower integer of a slot on an axis
    Lo(usize, usize),
    /// the upper integer of a slot on an axis
    Hi(usize, usize),
}

impl FieldKind {
    /// The name the docs' table uses, e.g. `lo[2].y`.
    pub fn name(self) -> String {
        const AX: [&str; 3] = ["x", "y", "z"];
        match self {
            FieldKind::Origin(a) => format!("origin.{}", AX[a]),
            FieldKind::Exp(a) => format!("exp.{}", AX[a]),
            FieldKind::Valid => "valid".into(),
            FieldKind::Leaf => "leaf".into(),
            FieldKind::ChildBase => "child_base".into(),
            FieldKind::PrimBase => "prim_base".into(),
            FieldKind::Count(s) => format!("count[{s}]"),
            FieldKind::Lo(s, a) => format!("lo[{s}].{}", AX[a]),
            FieldKind::Hi(s, a) => format!("hi[{s}].{}", AX[a]),
        }
    }
}

impl WideFormat {
    /// A node shape: ray format `fmt` (at most 10 exponent bits), `children`
    /// slots (2, 4, 8), `box_bits` bits per integer (4..=16).
    pub fn new(fmt: FloatFormat, children: usize, box_bits: u32) -> Result<Self, EncodeError> {
        if ![2, 4, 8].contains(&children) {
            return Err(EncodeError::Children(children));
        }
        if !(4..=16).contains(&box_bits) {
            return Err(EncodeError::BoxBits(box_bits));
        }
        if fmt.exp_bits() > 10 {
            return Err(EncodeError::Format(fmt));
        }
        Ok(WideFormat {
            fmt,
            children,
            box_bits,
        })
    }
    /// The ray format (of the origins and scales).
    pub fn fmt(self) -> FloatFormat {
        self.fmt
    }
    /// Child slots N.
    pub fn children(self) -> usize {
        self.children
    }
    /// Bits q of each box integer.
    pub fn box_bits(self) -> u32 {
        self.box_bits
    }
    /// The largest box integer, `2^q − 1`.
    pub fn q_max(self) -> u32 {
        (1 << self.box_bits) - 1
    }

    /// Every field of the packed record in bit order: origins, scales,
    /// valid and leaf masks, the two bases, the counts, then per slot its
    /// six integers (lo x y z, hi x y z).
    pub fn fields(self) -> Vec<Field> {
        let n = self.children;
        let mut kinds: Vec<(FieldKind, u32)> = Vec::new();
        for a in 0..3 {
            kinds.push((FieldKind::Origin(a), self.fmt.width()));
        }
        for a in 0..3 {
            kinds.push((FieldKind::Exp(a), self.fmt.exp_bits()));
        }
        kinds.push((FieldKind::Valid, n as u32));
        kinds.push((FieldKind::Leaf, n as u32));
        kinds.push((FieldKind::ChildBase, BASE_BITS));
        kinds.push((FieldKind::PrimBase, BASE_BITS));
        for s in 0..n {
            kinds.push((FieldKind::Count(s), COUNT_BITS));
        }
        for s in 0..n {
            for a in 0..3 {
                kinds.push((FieldKind::Lo(s, a), self.box_bits));
            }
            for a in 0..3 {
                kinds.push((FieldKind::Hi(s, a), self.box_bits));
            }
        }
        let mut offset = 0;
        kinds
            .into_iter()
            .map(|(kind, width)| {
                let f = Field {
                    kind,
                    offset,
                    width,
                };
                offset += width;
                f
            })
            .collect()
    }

    /// Bits of the packed record: `3·W + 3·E + 2·N + 64 + N·(3 + 6·q)`.
    pub fn record_bits(self) -> u32 {
        self.fields().iter().map(|f| f.width).sum()
    }
    /// Bytes of the packed record (bits rounded up to whole bytes).
    pub fn record_bytes(self) -> u32 {
        self.record_bits().div_ceil(8)
    }
    /// Bytes of the same node with N exact binary32 child boxes instead of
    /// the frame and the integers: `2·N + 64 + N·(3 + 6·32)` bits, rounded
    /// up to bytes (the baseline of `docs/wide.md`).
    pub fn baseline_bytes(self) -> u32 {
        let n = self.children as u32;
        (2 * n + 2 * BASE_BITS + n * (COUNT_BITS + 6 * BASELINE_COORD_BITS)).div_ceil(8)
    }
}

/// An exact child box: any finite binary64 values with `min ≤ max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChildBox {
    /// lower corner
    pub min: [f64; 3],
    /// upper corner
    pub max: [f64; 3],
}

/// What a valid slot references.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChildKind {
    /// an inner node (its index follows from the node's `child_base`)
    Inner,
    /// a leaf of `count` primitives (its range follows from `prim_base`)
    Leaf(u32),
}

/// A slot's reference, decoded from the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChildRef {
    /// no child (valid bit clear): the test answers the miss sentinel
    Empty,
    /// inner node index
    Inner(u32),
    /// primitives `first .. first + count`
    Leaf {
        /// first primitive
        first: u32,
        /// primitives
        count: u32,
    },
}

/// The per-node frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    /// origin per axis, bits of the ray format (finite, never −0)
    pub origin: [u64; 3],
    /// unbiased scale exponent per axis, `emin ..= emax` of the ray format
    pub exp: [i32; 3],
}

/// One compressed node. Slots at and above the format's N are empty and
/// all-zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Node {
    /// origins and scales
    pub frame: Frame,
    /// bit i: slot i holds a child
    pub valid: u8,
    /// bit i: slot i is a leaf
    pub leaf: u8,
    /// node index of the first inner child
    pub child_base: u32,
    /// first primitive of the leaf slots
    pub prim_base: u32,
    /// primitives per leaf slot (0 otherwise)
    pub count: [u8; MAX_CHILDREN],
    /// per slot and axis the lower integer (0 in empty slots)
    pub lo: [[u16; 3]; MAX_CHILDREN],
    /// per slot and axis the upper integer (0 in empty slots)
    pub hi: [[u16; 3]; MAX_CHILDREN],
}

/// A binary64 value as `m · 2^e` (exact).
fn dyadic(v: f64) -> (IBig, i32) {
    let bits = v.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    let (mag, e) = if biased == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, biased - 1075)
    };
    let m = IBig::from(mag);
    (if v < 0.0 { -m } else { m }, e)
}

/// `(x − o) / 2^e` as an exact non-negative dyadic `n · 2^(k − e)`, returned
/// as `(n, s)` with `s = e − k ≥ 0`: the quotient is `n / 2^s`. `None` when
/// `x < o` (the caller has ordered them).
fn scaled_gap(x: f64, o: f64, e: i32) -> Option<(UBig, usize)> {
    let (mx, ex) = dyadic(x);
    let (mo, eo) = dyadic(o);
    let k = ex.min(eo).min(e);
    let n = (mx << (ex - k) as usize) - (mo << (eo - k) as usize);
    UBig::try_from(n).ok().map(|n| (n, (e - k) as usize))
}

/// `⌊(x − o)/2^e⌋` and `⌈(x − o)/2^e⌉` for `x ≥ o`.
fn floor_ceil(x: f64, o: f64, e: i32) -> Option<(UBig, UBig)> {
    let (n, s) = scaled_gap(x, o, e)?;
    let fl = &n >> s;
    let exact = (&fl << s) == n;
    let ce = if exact { fl.clone() } else { &fl + UBig::ONE };
    Some((fl, ce))
}

impl Frame {
    /// The frame of a node with these children (each `(slot, box)`): the
    /// origin is the largest format value at or below every child, the
    /// scale the smallest power of two that keeps the node within `2^q − 1`
    /// steps (module doc, steps 1 and 2). The boxes must be checked
    /// (finite, `min ≤ max`) and at least one.
    fn fit(w: WideFormat, boxes: &[ChildBox]) -> Result<Frame, EncodeError> {
        let fmt = w.fmt;
        let mut origin = [0u64; 3];
        let mut exp = [0i32; 3];
        for a in 0..3 {
            let lo = boxes.iter().map(|b| b.min[a]).fold(f64::INFINITY, f64::min);
            let hi = boxes
                .iter()
                .map(|b| b.max[a])
                .fold(f64::NEG_INFINITY, f64::max);
            let o = convert(FloatFormat::BINARY64, fmt, lo.to_bits(), RoundingMode::Down);
            if !fmt.is_finite(o) {
                return Err(EncodeError::OriginOutOfRange { axis: a, min: lo });
            }
            // one encoding per origin: +0, never −0
            let o = if o == fmt.zero(true) {
                fmt.zero(false)
            } else {
                o
            };
            let o64 = f64::from_bits(convert(fmt, FloatFormat::BINARY64, o, RoundingMode::Down));
            // D = n / 2^s relative to scale 2^0: find the smallest e with
            // ⌈D / 2^e⌉ ≤ 2^q − 1, starting from D's leading bit
            let (n, s) = scaled_gap(hi, o64, 0).expect("o ≤ hi by construction");
            let e = if n == UBig::ZERO {
                fmt.emin()
            } else {
                // 2^(L−1) ≤ n < 2^L, D in [2^(L−1−s), 2^(L−s)): the smallest
                // e is L − s − q or one above (docs/wide.md)
                let top = n.bit_len() as i32 - s as i32;
                let mut e = top - w.box_bits as i32;
                while floor_ceil(hi, o64, e).expect("o ≤ hi").1 > UBig::from(w.q_max()) {
                    e += 1;
                }
                e.max(fmt.emin())
            };
            if e > fmt.emax() {
                return Err(EncodeError::ScaleOutOfRange {
                    axis: a,
                    exp: e,
                    emax: fmt.emax(),
                });
            }
            origin[a] = o;
            exp[a] = e;
        }
        Ok(Frame { origin, exp })
    }

    /// The origin of axis `a` as binary64 (exact).
    pub fn origin_f64(&self, fmt: FloatFormat, a: usize) -> f64 {
        f64::from_bits(convert(
            fmt,
            FloatFormat::BINARY64,
            self.origin[a],
            RoundingMode::Down,
        ))
    }
}

/// Checks one child box: finite, `min ≤ max`.
fn check_box(slot: usize, b: &ChildBox) -> Result<(), EncodeError> {
    for a in 0..3 {
        for value in [b.min[a], b.max[a]] {
            if !value.is_finite() {
                return Err(EncodeError::NonFinite {
                    slot,
                    axis: a,
                    value,
                });
            }
        }
        if b.min[a] > b.max[a] {
            return Err(EncodeError::Inverted {
                slot,
                axis: a,
                min: b.min[a],
                max: b.max[a],
            });
        }
    }
    Ok(())
}

/// Encodes a node: `slots[i]` is slot i's child (box and kind) or `None`
/// (an empty slot); at most N slots, at least one child. `child_base` and
/// `prim_base` are the indices the inner and leaf slots count from (module
/// doc and `docs/wide.md`).
pub fn encode(
    w: WideFormat,
    slots: &[Option<(ChildBox, ChildKind)>],
    child_base: u32,
    prim_base: u32,
) -> Result<Node, EncodeError> {
    if slots.len() > w.children {
        return Err(EncodeError::TooManyChildren {
            given: slots.len(),
            slots: w.children,
        });
    }
    let mut boxes = Vec::with_capacity(slots.len());
    for (i, s) in slots.iter().enumerate() {
        if let Some((b, kind)) = s {
            check_box(i, b)?;
            if let ChildKind::Leaf(count) = *kind {
                if count == 0 || count >= 1 << COUNT_BITS {
                    return Err(EncodeError::LeafCount { slot: i, count });
                }
            }
            boxes.push(*b);
        }
    }
    if boxes.is_empty() {
        return Err(EncodeError::NoChildren);
    }
    let frame = Frame::fit(w, &boxes)?;
    let mut node = Node {
        frame,
        valid: 0,
        leaf: 0,
        child_base,
        prim_base,
        count: [0; MAX_CHILDREN],
        lo: [[0; 3]; MAX_CHILDREN],
        hi: [[0; 3]; MAX_CHILDREN],
    };
    let q_max = UBig::from(w.q_max());
    for (i, s) in slots.iter().enumerate() {
        let Some((b, kind)) = s else { continue };
        node.valid |= 1 << i;
        if let ChildKind::Leaf(count) = *kind {
            node.leaf |= 1 << i;
            node.count[i] = count as u8;
        }
        for a in 0..3 {
            let o = frame.origin_f64(w.fmt, a);
            let e = frame.exp[a];
            let lo = floor_ceil(b.min[a], o, e).expect("o ≤ min").0;
            let hi = floor_ceil(b.max[a], o, e).expect("o ≤ max").1;
            // the frame was fitted to these boxes: both are within 2^q − 1
            debug_assert!(lo <= hi && hi <= q_max);
            node.lo[i][a] = u16::try_from(&lo).map_err(|_| record("lo overflow"))?;
            node.hi[i][a] = u16::try_from(&hi).map_err(|_| record("hi overflow"))?;
        }
    }
    Ok(node)
}

fn record(what: &str) -> EncodeError {
    EncodeError::Record(what.into())
}

/// `a + b` rounded down and up in binary64 (TwoSum: the error of the
/// rounded sum is exact), for finite sums.
fn add_down_up_f64(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let err = (a - (s - bb)) + (b - bb);
    if err > 0.0 {
        (s, s.next_up())
    } else if err < 0.0 {
        (s.next_down(), s)
    } else {
        (s, s)
    }
}

impl Node {
    /// What slot `i` references (inner children count from `child_base` in
    /// slot order, leaf ranges follow each other from `prim_base`); a slot
    /// past the last is empty.
    pub fn child(&self, i: usize) -> ChildRef {
        if i >= MAX_CHILDREN || self.valid >> i & 1 == 0 {
            return ChildRef::Empty;
        }
        let below = (1u8 << i) - 1;
        if self.leaf >> i & 1 == 1 {
            let skip: u32 = (0..i)
                .filter(|&j| (self.valid & self.leaf) >> j & 1 == 1)
                .map(|j| self.count[j] as u32)
                .sum();
            ChildRef::Leaf {
                first: self.prim_base + skip,
                count: self.count[i] as u32,
            }
        } else {
            let rank = (self.valid & !self.leaf & below).count_ones();
            ChildRef::Inner(self.child_base + rank)
        }
    }

    /// Slot `i`'s decoded box, each coordinate `o + n·2^e` rounded outward
    /// (min down, max up) to binary64 and then to `out`; `None` for an empty
    /// slot. Contains the exact decoded box, hence the exact child box.
    pub fn decoded_outward(
        &self,
        w: WideFormat,
        i: usize,
        out: FloatFormat,
    ) -> Option<([u64; 3], [u64; 3])> {
        if i >= MAX_CHILDREN || self.valid >> i & 1 == 0 {
            return None;
        }
        let mut lo = [0u64; 3];
        let mut hi = [0u64; 3];
        for a in 0..3 {
            let o = self.frame.origin_f64(w.fmt, a);
            // n < 2^16 and 2^e normal in binary64 (E ≤ 10): the product is exact
            let step = f64::from_bits(((self.frame.exp[a] + 1023) as u64) << 52);
            let down = add_down_up_f64(o, self.lo[i][a] as f64 * step).0;
            let up = add_down_up_f64(o, self.hi[i][a] as f64 * step).1;
            let to = |v: f64, m| convert(FloatFormat::BINARY64, out, v.to_bits(), m);
            lo[a] = to(down, RoundingMode::Down);
            hi[a] = to(up, RoundingMode::Up);
        }
        Some((lo, hi))
    }

    /// The value of one field (for [`Node::pack`]).
    fn get(&self, w: WideFormat, k: FieldKind) -> u64 {
        match k {
            FieldKind::Origin(a) => self.frame.origin[a],
            FieldKind::Exp(a) => (self.frame.exp[a] + w.fmt.bias()) as u64,
            FieldKind::Valid => self.valid as u64,
            FieldKind::Leaf => self.leaf as u64,
            FieldKind::ChildBase => self.child_base as u64,
            FieldKind::PrimBase => self.prim_base as u64,
            FieldKind::Count(s) => self.count[s] as u64,
            FieldKind::Lo(s, a) => self.lo[s][a] as u64,
            FieldKind::Hi(s, a) => self.hi[s][a] as u64,
        }
    }

    /// Sets one field (for [`Node::unpack`]; the value fits its width).
    fn set(&mut self, w: WideFormat, k: FieldKind, v: u64) {
        match k {
            FieldKind::Origin(a) => self.frame.origin[a] = v,
            FieldKind::Exp(a) => self.frame.exp[a] = v as i32 - w.fmt.bias(),
            FieldKind::Valid => self.valid = v as u8,
            FieldKind::Leaf => self.leaf = v as u8,
            FieldKind::ChildBase => self.child_base = v as u32,
            FieldKind::PrimBase => self.prim_base = v as u32,
            FieldKind::Count(s) => self.count[s] = v as u8,
            FieldKind::Lo(s, a) => self.lo[s][a] = v as u16,
            FieldKind::Hi(s, a) => self.hi[s][a] = v as u16,
        }
    }

    /// The packed record, [`WideFormat::record_bytes`] bytes, fields at the
    /// offsets of [`WideFormat::fields`] (unused high bits of the last byte
    /// zero).
    pub fn pack(&self, w: WideFormat) -> Vec<u8> {
        let mut out = vec![0u8; w.record_bytes() as usize];
        for f in w.fields() {
            let v = self.get(w, f.kind);
            for b in 0..f.width {
                if v >> b & 1 == 1 {
                    let at = f.offset + b;
                    out[(at / 8) as usize] |= 1 << (at % 8);
                }
            }
        }
        out
    }

    /// The node of a packed record, checked: the right length, finite
    /// origins, scale exponents of normal powers of two, every valid slot
    /// with `lo ≤ hi` and a leaf count in 1..=7, nothing set in empty or
    /// unused slots and bits.
    pub fn unpack(w: WideFormat, bytes: &[u8]) -> Result<Node, EncodeError> {
        if bytes.len() != w.record_bytes() as usize {
            return Err(EncodeError::Record(format!(
                "{} bytes, expected {}",
                bytes.len(),
                w.record_bytes()
            )));
        }
        let bits = w.record_bits();
        if (bits..bytes.len() as u32 * 8).any(|at| bytes[(at / 8) as usize] >> (at % 8) & 1 == 1) {
            return Err(record("a padding bit is set"));
        }
        let mut n = Node {
            frame: Frame {
                origin: [0; 3],
                exp: [0; 3],
            },
            valid: 0,
            leaf: 0,
            child_base: 0,
            prim_base: 0,
            count: [0; MAX_CHILDREN],
            lo: [[0; 3]; MAX_CHILDREN],
            hi: [[0; 3]; MAX_CHILDREN],
        };
        for f in w.fields() {
            let mut v = 0u64;
            for b in 0..f.width {
                let at = f.offset + b;
                v |= ((bytes[(at / 8) as usize] >> (at % 8) & 1) as u64) << b;
            }
            n.set(w, f.kind, v);
        }
        let fmt = w.fmt;
        for a in 0..3 {
            if !fmt.is_finite(n.frame.origin[a]) {
                return Err(EncodeError::Record(format!(
                    "origin of axis {a} not finite"
                )));
            }
            if !(fmt.emin()..=fmt.emax()).contains(&n.frame.exp[a]) {
                return Err(EncodeError::Record(format!(
                    "scale field of axis {a} is reserved (0 or all ones)"
                )));
            }
        }
        if n.valid == 0 {
            return Err(record("no valid slot"));
        }
        if n.leaf & !n.valid != 0 {
            return Err(record("leaf bit of an empty slot"));
        }
        for i in 0..w.children {
            let valid_leaf = (n.valid & n.leaf) >> i & 1 == 1;
            if valid_leaf != (n.count[i] != 0) {
                return Err(EncodeError::Record(format!(
                    "slot {i}: count {} for a {} slot",
                    n.count[i],
                    if valid_leaf { "leaf" } else { "non-leaf" }
                )));
            }
            if n.valid >> i & 1 == 0 {
                if n.lo[i] != [0; 3] || n.hi[i] != [0; 3] {
                    return Err(EncodeError::Record(format!("empty slot {i} not zero")));
                }
            } else if (0..3).any(|a| n.lo[i][a] > n.hi[i][a]) {
                return Err(EncodeError::Record(format!("slot {i}: lo above hi")));
            }
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sign of `a + b − x`, exactly.
    fn sum_vs(a: f64, b: f64, x: f64) -> std::cmp::Ordering {
        let terms = [dyadic(a), dyadic(b), dyadic(-x)];
        let low = terms.iter().map(|t| t.1).min().expect("three terms");
        let total: IBig = terms
            .iter()
            .map(|(m, e)| m.clone() << (e - low) as usize)
            .sum();
        total.cmp(&IBig::ZERO)
    }

    /// `add_down_up_f64` brackets the exact sum by adjacent doubles, and
    /// gives the sum twice when it is exact: values of both signs from 2^-1074
    /// to 2^1000, neighbours and far apart.
    #[test]
    fn the_sum_rounded_down_and_up_brackets_the_exact_sum() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let pick = |next: &mut dyn FnMut() -> u64| {
            let e = (next() % 2000) as i32 - 1000;
            let m = 1.0 + (next() >> 12) as f64 / (1u64 << 52) as f64;
            let v = m * 2f64.powi(e);
            if next().is_multiple_of(2) {
                -v
            } else {
                v
            }
        };
        let mut inexact = 0;
        for i in 0..20_000 {
            let a = pick(&mut next);
            let b = match i % 4 {
                0 => a * 3.0,
                1 => -a + f64::MIN_POSITIVE,
                _ => pick(&mut next),
            };
            let (lo, hi) = add_down_up_f64(a, b);
            assert_ne!(
                sum_vs(a, b, lo),
                std::cmp::Ordering::Less,
                "{a:e} + {b:e}: {lo:e}"
            );
            assert_ne!(
                sum_vs(a, b, hi),
                std::cmp::Ordering::Greater,
                "{a:e} + {b:e}: {hi:e}"
            );
            if lo != hi {
                assert_eq!(lo.next_up(), hi, "{a:e} + {b:e}");
                inexact += 1;
            } else {
                assert_eq!(sum_vs(a, b, lo), std::cmp::Ordering::Equal, "{a:e} + {b:e}");
            }
        }
        assert!(inexact > 5_000, "{inexact} inexact sums");
    }

    fn b(min: [f64; 3], max: [f64; 3]) -> ChildBox {
        ChildBox { min, max }
    }

    #[test]
    fn a_unit_node_quantises_to_the_expected_integers() {
        let w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
        let n = encode(
            w,
            &[
                Some((b([0.0; 3], [1.0; 3]), ChildKind::Inner)),
                Some((b([0.25, 0.5, 0.0], [0.5, 0.75, 0.1]), ChildKind::Leaf(3))),
                None,
            ],
            7,
            40,
        )
        .unwrap();
        // D = 1: the smallest e with 255·2^e ≥ 1 is −7 (255/128 ≥ 1 > 255/256)
        assert_eq!(n.frame.exp, [-7; 3]);
        assert_eq!(n.frame.origin, [0; 3]);
        assert_eq!(n.lo[0], [0; 3]);
        assert_eq!(n.hi[0], [128; 3]);
        assert_eq!(n.lo[1], [32, 64, 0]);
        // 0.1·128 = 12.8 rounds up to 13
        assert_eq!(n.hi[1], [64, 96, 13]);
        assert_eq!(n.child(0), ChildRef::Inner(7));
        assert_eq!(
            n.child(1),
            ChildRef::Leaf {
                first: 40,
                count: 3
            }
        );
        assert_eq!(n.child(2), ChildRef::Empty);
        assert_eq!(n.child(MAX_CHILDREN), ChildRef::Empty);
        assert_eq!(Node::unpack(w, &n.pack(w)), Ok(n));
    }

    #[test]
    fn record_sizes() {
        let w = |n, q| WideFormat::new(FloatFormat::BINARY32, n, q).unwrap();
        // 96 + 24 + 16 + 64 + 24 + 8·48 = 608 bits
        assert_eq!(w(8, 8).record_bytes(), 76);
        assert_eq!(w(4, 8).record_bytes(), 50);
        assert_eq!(w(8, 8).baseline_bytes(), 205);
    }
}
