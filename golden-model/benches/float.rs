//! Throughput of the float golden model on binary32, per operator.
//! `cargo bench -p golden-model --bench float`; divan prints items/s
//! (one item = one operation on operands from a pre-generated pool that
//! mixes random bit patterns with structured finite values).

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use golden_model::float::{self as fp, ExactProductFormat, FloatFormat, RoundingMode};

const F32: FloatFormat = FloatFormat::BINARY32;
const N: usize = 4096;
const RNE: RoundingMode = RoundingMode::NearestEven;

fn main() {
    divan::main();
}

/// Deterministic operands: finite values with random exponents (mostly
/// normal) and fractions, with some raw random patterns (specials, NaN).
fn pool(seed: u64) -> Vec<u64> {
    let mut s = seed;
    let mut next = move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    (0..N)
        .map(|i| {
            let r = next();
            if i % 16 == 0 {
                r & 0xffff_ffff
            } else {
                let exp = 64 + (r >> 40) % 128;
                (r & 0x8000_0000) | (exp << 23) | (r & 0x7f_ffff)
            }
        })
        .collect()
}

fn bench2(b: Bencher, op: impl Fn(u64, u64) -> u64 + Sync) {
    let (x, y) = (pool(1), pool(2));
    b.counter(ItemsCount::new(N)).bench(|| {
        let mut acc = 0u64;
        for i in 0..N {
            acc ^= op(black_box(x[i]), black_box(y[i]));
        }
        acc
    });
}

/// unpack + the shared rounder, and nothing else.
#[divan::bench]
fn convert_to_self(b: Bencher) {
    bench2(b, |a, _| fp::convert(F32, F32, a, RNE));
}

#[divan::bench]
fn add(b: Bencher) {
    bench2(b, |a, c| fp::add(F32, a, c, RNE));
}

#[divan::bench]
fn sub_rdn(b: Bencher) {
    bench2(b, |a, c| fp::sub(F32, a, c, RoundingMode::Down));
}

#[divan::bench]
fn add_down_up(b: Bencher) {
    bench2(b, |a, c| {
        let r = fp::add_down_up(F32, a, c);
        r.down ^ r.up
    });
}

#[divan::bench]
fn mul(b: Bencher) {
    bench2(b, |a, c| fp::mul(F32, a, c, RNE));
}

#[divan::bench]
fn mul_exact(b: Bencher) {
    let p = ExactProductFormat::new(F32).unwrap();
    bench2(b, move |a, c| fp::mul_exact(p, a, c));
}

#[divan::bench]
fn lt_le_eq(b: Bencher) {
    bench2(b, |a, c| {
        fp::lt(F32, a, c) as u64 ^ (fp::le(F32, a, c) as u64) << 1 ^ (fp::eq(F32, a, c) as u64) << 2
    });
}

#[divan::bench]
fn lt_on_exact_products(b: Bencher) {
    let w = ExactProductFormat::new(F32).unwrap().wide();
    bench2(b, move |a, c| fp::lt(w, a << 20, c << 20) as u64);
}

#[divan::bench]
fn min_max(b: Bencher) {
    bench2(b, |a, c| fp::min(F32, a, c) ^ fp::max(F32, a, c));
}

#[divan::bench]
fn fma(b: Bencher) {
    let z = pool(3);
    bench2(b, move |a, c| fp::fma(F32, a, c, z[(a as usize) % N], RNE));
}

#[divan::bench]
fn dot3(b: Bencher) {
    let (x, y) = (pool(4), pool(5));
    b.counter(ItemsCount::new(N / 3)).bench(|| {
        let mut acc = 0u64;
        for i in (0..N - 2).step_by(3) {
            let a = black_box([x[i], x[i + 1], x[i + 2]]);
            let c = black_box([y[i], y[i + 1], y[i + 2]]);
            acc ^= fp::dot3(F32, a, c, RNE);
        }
        acc
    });
}

#[divan::bench]
fn convert_to_bf16(b: Bencher) {
    bench2(b, |a, _| fp::convert(F32, FloatFormat::BFLOAT16, a, RNE));
}

#[divan::bench]
fn convert_to_f64(b: Bencher) {
    bench2(b, |a, _| fp::convert(F32, FloatFormat::BINARY64, a, RNE));
}
