//! One DSP48E1 for a 24x24 product on 7-series FPGAs (`dsp=xc7`).
//!
//! Why: a DSP48E1 multiplies 25x18 signed bits, 24x17 unsigned, so Yosys
//! puts a 24x24 unsigned product on two blocks. Here the block takes
//! `a·signed(b[17:0])` and adds, in its post-adder, the rest
//! `R = a·(b[23:18] + b[17])`, computed in fabric as `32a` plus three
//! radix-4 Booth rows (digits from `b[17..=23]`, the top one reading
//! `¬b[23]` so that `32a` stands for its missing weight and no row needs
//! masking), one hand-placed LUT per bit feeding a `CARRY4` chain: 87 LUT per
//! block saved, where Yosys maps the same rest written as Verilog to 192
//! (docs/triangle.md §7). `a·signed(b[17:0]) + 2^18·R = a·b` exactly, for
//! every `a`, `b`.
//!
//! The product stays a product node in the IR (the evaluator, the retimer
//! and Verilator read it); the cells are written under `` `ifdef
//! SYNTHESIS `` as for `dsp=ecp5` ([`super::hard_dsp`]).

use crate::ir::*;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Operand width the structure takes (both operands, unsigned).
pub const OPERAND_BITS: u32 = 24;
/// Width of the rest `R = a·(b[23:18] + b[17]) < 2^30`.
const REST_BITS: u32 = 30;
/// Low bits of `b` the block multiplies (as a signed 18-bit number).
const BLOCK_B_BITS: u32 = 18;

/// What [`xc7_hand_map`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HandMapped {
    /// products now on one DSP48E1 each (two before)
    pub products: usize,
    /// modelled DSP48E1 blocks of the unit before and after
    pub blocks_before: u32,
    /// after
    pub blocks_after: u32,
}

/// Modelled DSP48E1 blocks of an unsigned `wa × wb` product as Yosys maps
/// it (24x17 unsigned per block; products Yosys leaves in fabric take none).
pub fn xc7_blocks(wa: u32, wb: u32) -> u32 {
    if !super::on_dsp(wa, wb) {
        return 0;
    }
    let (long, short) = (wa.max(wb), wa.min(wb));
    long.div_ceil(OPERAND_BITS) * short.div_ceil(17)
}

/// A product the structure takes: both operands unsigned and 24 bits wide.
fn fits(m: &Module, a: NodeId, b: NodeId) -> bool {
    let (ta, tb) = (m.node(a).ty, m.node(b).ty);
    matches!(ta, Ty::UInt(OPERAND_BITS)) && matches!(tb, Ty::UInt(OPERAND_BITS))
}

/// Puts 24x24 unsigned products of the flat module `m` on one DSP48E1 each,
/// earliest in the datapath first, until its modelled blocks are at most
/// `budget` (`None`: every such product). `Err` when the budget cannot be
/// met. Same ports, latency and function. (The order is measured, not
/// derived: the binary32 `tnum` triangle at 24 blocks maps to 11,918 xc7
/// LUT with its six shear and two edge products here, 12,011 with its four
/// `T` and four edge products, the latest.)
pub fn xc7_hand_map(m: &Module, budget: Option<u32>) -> Result<(Module, HandMapped), String> {
    if !m.instances.is_empty() {
        return Err(format!(
            "dsp=xc7: `{}` is hierarchical; its products are placed once the datapath is flat \
             (pipeline=balanced, or a unit that retimes its own datapath)",
            m.name
        ));
    }
    let mut blocks = 0;
    let mut candidates = Vec::new();
    for (i, node) in m.nodes.iter().enumerate() {
        if let Op::Mul(a, b) = node.op {
            let (wa, wb) = (m.node(a).ty.width(), m.node(b).ty.width());
            blocks += xc7_blocks(wa, wb);
            if fits(m, a, b) {
                candidates.push(i);
            }
        }
    }
    let before = blocks;
    let want = match budget {
        None => candidates.len(),
        Some(b) => {
            let need = blocks.saturating_sub(b) as usize;
            if need > candidates.len() {
                return Err(format!(
                    "dsp=xc7: `{}` needs {blocks} DSP48E1 blocks as Yosys maps it and at least \
                     {} with every 24x24 product on one block; dsp_blocks={b} is fewer",
                    m.name,
                    blocks - candidates.len() as u32
                ));
            }
            need
        }
    };
    let mut out = m.clone();
    let product = Arc::new(product_module());
    for &i in candidates.iter().take(want) {
        let Op::Mul(a, b) = out.nodes[i].op else {
            unreachable!("a candidate is a product")
        };
        out.instances.push(Instance {
            name: format!("{}_dsp48", out.nodes[i].name),
            module: Arc::clone(&product),
            inputs: vec![a, b],
        });
        out.nodes[i].op = Op::InstOut {
            inst: out.instances.len() - 1,
            port: 0,
        };
        blocks -= 1;
    }
    Ok((
        out,
        HandMapped {
            products: want,
            blocks_before: before,
            blocks_after: blocks,
        },
    ))
}

/// The truth table of a LUT of `n` inputs computing `f` (input `k` is bit
/// `k` of the table's index), as a Verilog constant.
fn lut_init(n: u32, f: impl Fn(&[bool]) -> bool) -> String {
    let mut v = 0u64;
    for i in 0..1u64 << n {
        let bits: Vec<bool> = (0..n).map(|k| i >> k & 1 == 1).collect();
        if f(&bits) {
            v |= 1 << i;
        }
    }
    let width = 1u32 << n;
    format!(
        "{width}'h{v:0digits$x}",
        digits = (width as usize).div_ceil(4)
    )
}

/// Bit `j` of the Booth row `d·a` (two's complement before its carry-in):
/// `d = −2·x2 + x1 + x0` in −2..=2, `a_j`, `a_{j−1}` the multiplicand's bits.
fn booth_bit(a_j: bool, a_jm1: bool, [x0, x1, x2]: [bool; 3]) -> bool {
    let d = -2 * x2 as i32 + x1 as i32 + x0 as i32;
    let magnitude = match d.abs() {
        1 => a_j,
        2 => a_jm1,
        _ => false,
    };
    magnitude ^ (d < 0)
}

/// The product module: `p = a·b` (24x24 unsigned), one DSP48E1 and the rest
/// in LUTs and `CARRY4`s in synthesis.
fn product_module() -> Module {
    let node = super::cell_node;
    let operand = Ty::UInt(OPERAND_BITS);
    let product = Ty::UInt(2 * OPERAND_BITS);
    let nodes = vec![
        node(Op::Input(0), operand, "a"),
        node(Op::Input(1), operand, "b"),
        node(Op::Mul(NodeId(0), NodeId(1)), product, "product"),
    ];
    let port = |name: &str, ty: Ty| Port {
        name: name.into(),
        ty,
    };
    Module {
        name: format!("xc7_umul_{OPERAND_BITS}x{OPERAND_BITS}_dsp1"),
        description: "a*b, 24x24 unsigned, on one DSP48E1 in synthesis (SYNTHESIS defined, as \
                      by Yosys): the block computes a*signed(b[17:0]) and adds the rest \
                      a*(b[23:18] + b[17]), 32a plus three radix-4 Booth rows in LUTs and \
                      CARRY4 chains; the same product in fabric logic otherwise (simulation)."
            .into(),
        params: BTreeMap::new(),
        inputs: vec![port("a", operand), port("b", operand)],
        outputs: vec![(port("p", product), NodeId(2))],
        nodes,
        registers: Vec::new(),
        instances: Vec::new(),
        latency: 0,
        handshake: None,
        vendor: Some(cells()),
    }
}

/// The cells of [`product_module`].
fn cells() -> VendorBody {
    let zero = CellPin::Const(false);
    let one = CellPin::Const(true);
    let a = |bit: u32| CellPin::Input { port: 0, bit };
    let b = |bit: u32| CellPin::Input { port: 1, bit };
    // bit j of the multiplicand (zero above its 24 bits)
    let a_or_zero = |j: i64| {
        if (0..OPERAND_BITS as i64).contains(&j) {
            a(j as u32)
        } else {
            zero
        }
    };
    let mut nets: Vec<(String, u32)> = Vec::new();
    let mut net = |name: String, width: u32| {
        nets.push((name, width));
        nets.len() - 1
    };
    let mut cells = Vec::new();
    // (x0, x1, x2) of row k: b[17 + 2k], b[18 + 2k], b[19 + 2k]; the top
    // row's x2 is ¬b[23], folded into its LUTs' tables
    let digit = |k: u32| [b(17 + 2 * k), b(18 + 2 * k), b(19 + 2 * k)];
    let top = |k: u32| k == 2;
    let xs = |k: u32, x: &[bool]| [x[0], x[1], x[2] ^ top(k)];
    // the rest so far: bit i of 32a, then of each row's sum
    let mut rest: Vec<Option<CellPin>> = (0..REST_BITS)
        .map(|i| (5..5 + OPERAND_BITS).contains(&i).then(|| a(i - 5)))
        .collect();
    let negative = net("booth_negative".into(), 3);
    for k in 0..3u32 {
        // the row's carry-in: +1 completes the two's complement of a
        // negative digit
        let init = lut_init(3, |x| {
            let d = xs(k, x);
            d[2] && !(d[1] && d[0])
        });
        let pins = digit(k);
        cells.push(VendorCell {
            cell: "LUT3".into(),
            name: format!("row{k}_negative"),
            params: vec![("INIT".into(), init)],
            pins: vec![
                (
                    "O".into(),
                    vec![CellPin::Net {
                        net: negative,
                        bit: k,
                    }],
                ),
                ("I0".into(), vec![pins[0]]),
                ("I1".into(), vec![pins[1]]),
                ("I2".into(), vec![pins[2]]),
            ],
        });
        let offset = 2 * k;
        let row_bits = REST_BITS - offset;
        let chains = row_bits.div_ceil(4);
        let sum = net(format!("row{k}_sum"), 4 * chains);
        let out = net(format!("row{k}_out"), 4 * chains);
        let carry = net(format!("row{k}_carry"), 4 * chains);
        let mut keep = vec![zero; 4 * chains as usize];
        for j in 0..4 * chains {
            let s_bit = CellPin::Net { net: sum, bit: j };
            if j >= row_bits {
                continue;
            }
            let i = (offset + j) as usize;
            let (a_j, a_jm1) = (a_or_zero(j as i64), a_or_zero(j as i64 - 1));
            let mut pins = vec![
                ("O".to_string(), vec![s_bit]),
                ("I0".into(), vec![a_j]),
                ("I1".into(), vec![a_jm1]),
                ("I2".into(), vec![digit(k)[0]]),
                ("I3".into(), vec![digit(k)[1]]),
                ("I4".into(), vec![digit(k)[2]]),
            ];
            let (cell, init) = match rest[i] {
                // nothing to add yet: the row's bit alone
                None => (
                    "LUT5",
                    lut_init(5, |x| booth_bit(x[0], x[1], xs(k, &x[2..5]))),
                ),
                // the row's bit xor the sum so far: the carry chain adds them
                Some(prev) => {
                    pins.push(("I5".into(), vec![prev]));
                    keep[j as usize] = prev;
                    (
                        "LUT6",
                        lut_init(6, |x| x[5] ^ booth_bit(x[0], x[1], xs(k, &x[2..5]))),
                    )
                }
            };
            cells.push(VendorCell {
                cell: cell.into(),
                name: format!("row{k}_bit{j}"),
                params: vec![("INIT".into(), init)],
                pins,
            });
        }
        for c in 0..chains {
            let bits = |n: usize| (4 * c..4 * c + 4).map(move |bit| CellPin::Net { net: n, bit });
            let select: Vec<CellPin> = (4 * c..4 * c + 4)
                .map(|j| {
                    if j < row_bits {
                        CellPin::Net { net: sum, bit: j }
                    } else {
                        zero
                    }
                })
                .collect();
            let carry_in = match c {
                0 => zero,
                _ => CellPin::Net {
                    net: carry,
                    bit: 4 * c - 1,
                },
            };
            let init = match c {
                0 => CellPin::Net {
                    net: negative,
                    bit: k,
                },
                _ => zero,
            };
            cells.push(VendorCell {
                cell: "CARRY4".into(),
                name: format!("row{k}_chain{c}"),
                params: Vec::new(),
                pins: vec![
                    ("CI".into(), vec![carry_in]),
                    ("CYINIT".into(), vec![init]),
                    (
                        "DI".into(),
                        keep[4 * c as usize..4 * c as usize + 4].to_vec(),
                    ),
                    ("S".into(), select),
                    ("O".into(), bits(out).collect()),
                    ("CO".into(), bits(carry).collect()),
                ],
            });
        }
        for j in 0..row_bits {
            rest[(offset + j) as usize] = Some(CellPin::Net { net: out, bit: j });
        }
    }
    // the block: P = A·B + C, A = a (25-bit signed, top bit 0), B = b[17:0]
    // (18-bit signed), C = R·2^18; no register, X = Y = M, Z = C
    let mut a_pin: Vec<CellPin> = (0..OPERAND_BITS).map(a).collect();
    a_pin.resize(30, zero);
    let b_pin: Vec<CellPin> = (0..BLOCK_B_BITS).map(b).collect();
    let mut c_pin = vec![zero; BLOCK_B_BITS as usize];
    c_pin.extend(
        rest.iter()
            .map(|r| r.expect("every bit of the rest is summed")),
    );
    let constant = |value: u32, width: u32| -> Vec<CellPin> {
        (0..width)
            .map(|i| if value >> i & 1 == 1 { one } else { zero })
            .collect()
    };
    let opmode = 0b0110101; // Z = C (011), Y = M (01), X = M (01)
    let mut pins = vec![
        ("A".to_string(), a_pin),
        ("B".into(), b_pin),
        ("C".into(), c_pin),
        ("D".into(), vec![zero; 25]),
        ("OPMODE".into(), constant(opmode, 7)),
        ("ALUMODE".into(), constant(0, 4)),
        ("INMODE".into(), constant(0, 5)),
        ("CARRYIN".into(), vec![zero]),
        ("CARRYINSEL".into(), constant(0, 3)),
        ("ACIN".into(), vec![zero; 30]),
        ("BCIN".into(), vec![zero; 18]),
        ("PCIN".into(), vec![zero; 48]),
        ("CARRYCASCIN".into(), vec![zero]),
        ("MULTSIGNIN".into(), vec![zero]),
        ("CLK".into(), vec![zero]),
    ];
    for ce in [
        "CEA1",
        "CEA2",
        "CEAD",
        "CEALUMODE",
        "CEB1",
        "CEB2",
        "CEC",
        "CECARRYIN",
        "CECTRL",
        "CED",
        "CEINMODE",
        "CEM",
        "CEP",
    ] {
        pins.push((ce.into(), vec![zero]));
    }
    for rst in [
        "RSTA",
        "RSTALLCARRYIN",
        "RSTALUMODE",
        "RSTB",
        "RSTC",
        "RSTCTRL",
        "RSTD",
        "RSTINMODE",
        "RSTM",
        "RSTP",
    ] {
        pins.push((rst.into(), vec![zero]));
    }
    pins.push((
        "P".into(),
        (0..2 * OPERAND_BITS)
            .map(|bit| CellPin::Output { port: 0, bit })
            .collect(),
    ));
    let mut params: Vec<(String, String)> = [
        "AREG",
        "BREG",
        "CREG",
        "DREG",
        "MREG",
        "PREG",
        "ACASCREG",
        "BCASCREG",
        "ADREG",
        "ALUMODEREG",
        "CARRYINREG",
        "CARRYINSELREG",
        "INMODEREG",
        "OPMODEREG",
    ]
    .iter()
    .map(|p| (p.to_string(), "0".to_string()))
    .collect();
    for (p, v) in [
        ("USE_MULT", "MULTIPLY"),
        ("USE_DPORT", "FALSE"),
        ("USE_SIMD", "ONE48"),
        ("USE_PATTERN_DETECT", "NO_PATDET"),
    ] {
        params.push((p.into(), format!("\"{v}\"")));
    }
    cells.push(VendorCell {
        cell: "DSP48E1".into(),
        name: "block".into(),
        params,
        pins,
    });
    VendorBody {
        library: CellLibrary::Xc7,
        nets,
        cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The LUT tables, the digits and the carry-ins give `R` exactly: the
    /// structure's arithmetic evaluated bit by bit as the cells compute it.
    #[test]
    fn the_rows_sum_to_the_rest_for_every_digit_pattern() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for step in 0..20_000u64 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let a = match step % 4 {
                0 => 0xff_ffff,
                1 => 0,
                _ => x & 0xff_ffff,
            };
            let b = (x >> 24 & 0xff_ffff) as u32;
            let bit = |v: u64, i: i64| (0..64).contains(&i) && v >> i & 1 == 1;
            let mut sum = 32 * a;
            for k in 0..3u32 {
                let d = [
                    b >> (17 + 2 * k) & 1 == 1,
                    b >> (18 + 2 * k) & 1 == 1,
                    (b >> (19 + 2 * k) & 1 == 1) ^ (k == 2),
                ];
                let neg = d[2] && !(d[1] && d[0]);
                let mut row = 0u64;
                for j in 0..(REST_BITS - 2 * k) as i64 {
                    if booth_bit(bit(a, j), bit(a, j - 1), d) {
                        row |= 1 << j;
                    }
                }
                let mask = (1u64 << REST_BITS) - 1;
                sum = (sum + ((row + neg as u64) << (2 * k))) & mask;
            }
            let rest = a * ((b as u64 >> 18) + (b as u64 >> 17 & 1));
            assert_eq!(sum, rest, "a {a:#x} b {b:#x}");
            let low = (b & 0x3_ffff) as i64 - ((b as i64 >> 17 & 1) << 18);
            assert_eq!(a as i64 * low + ((rest as i64) << 18), a as i64 * b as i64);
        }
    }

    #[test]
    fn lut_tables_are_written_as_verilog_constants() {
        assert_eq!(lut_init(3, |x| x[2] && !(x[1] && x[0])), "8'h70");
        assert_eq!(lut_init(6, |x| x[5]), "64'hffffffff00000000");
    }
}
