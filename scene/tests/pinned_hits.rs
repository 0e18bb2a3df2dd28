//! The renderer's rays keep their bits. The primary hits of two shipped
//! scenes (cornell: an area light, walls meeting at shared edges; field:
//! rotated and scaled instances, a point light) equal the dumps in
//! `tests/data/`, written by `rtl-gen render SCENE --width 24 --dump-hits`
//! before the renderer's math moved to glam, and the colours hash to what
//! they were then. A change of rounding in the camera basis, the instance
//! transforms or the shading frame fails here: with glam's `normalize` (a
//! multiplication by the reciprocal length) 533 of cornell's and 153 of
//! field's lines differ.

use scene::bvh::Accel;
use scene::render::render;
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::TraceOpts;
use std::path::Path;

/// FNV-1a over the binary32 bits of every pixel's colour, row-major.
fn colour_digest(f: &scene::render::Frame) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for p in 0..f.color.len() {
        for c in f.color_bits(p) {
            for b in c.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
            }
        }
    }
    h
}

/// Renders `name` as `rtl-gen render` does by default, at the size of its
/// pinned dump, and compares hits and colours.
fn pinned(name: &str, colours: u64) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pinned = std::fs::read_to_string(dir.join(format!("tests/data/{name}_24.hits"))).unwrap();
    let size: Vec<u32> = pinned
        .lines()
        .find_map(|l| l.strip_prefix("# width "))
        .expect("dump header: width and height")
        .split(" height ")
        .map(|x| x.parse().unwrap())
        .collect();
    let s = Scene::load(&dir.join(format!("../scenes/{name}.toml"))).unwrap();
    let acc = Accel::build(&s, true);
    let opts = TraceOpts::default();
    let f = render(&s, &acc, &Golden::default(), opts, size[0], size[1], false);
    let body = |t: &str| -> Vec<String> {
        t.lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    let (want, got) = (body(&pinned), body(&f.hits_text("")));
    assert_eq!(want.len(), got.len(), "{name}: pixel count");
    let wrong: Vec<_> = want.iter().zip(&got).filter(|(a, b)| a != b).collect();
    assert!(
        wrong.is_empty(),
        "{name}: {} of {} pixels differ from the pinned dump, first: pinned `{}`, now `{}`",
        wrong.len(),
        want.len(),
        wrong[0].0,
        wrong[0].1
    );
    assert_eq!(colour_digest(&f), colours, "{name}: colour bits changed");
}

#[test]
fn cornell_hits_and_colours_are_pinned() {
    pinned("cornell", 0xaa80_16eb_52de_d1b1);
}

#[test]
fn field_hits_and_colours_are_pinned() {
    pinned("field", 0xb5ac_d94f_e337_4baa);
}
