//! Bad input to the scene commands from the command line: every case is an error
//! naming what is wrong, exit status 2, within seconds, and leaves no output file
//! behind (an image size or AO count out of range, an output that cannot be
//! written, a scene whose values would loop for hours). A good render leaves only
//! its outputs (no temporary files).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The smallest valid scene: 8x8, a quad, a point light.
const SCENE: &str = include_str!("../../scene/tests/data/lit.toml");

/// A fresh folder holding `B.toml` (`SCENE` with `extra` appended).
fn folder(tag: &str, extra: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("scene-errors-{tag}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("B.toml"), format!("{SCENE}{extra}")).unwrap();
    dir
}

/// `rtl-gen args` run in `dir`, killed after a minute (a bad value once looped for hours).
fn rtl_gen_in(dir: &Path, args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("rtl-gen runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("rtl-gen {args:?} still runs after 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The files in `dir` besides the scene.
fn left_behind(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "B.toml")
        .collect();
    names.sort();
    names
}

/// `args` in a fresh folder fail with exit 2 and an error containing `says`, writing nothing.
fn refused(tag: &str, extra: &str, args: &[&str], says: &str) {
    let dir = folder(tag, extra);
    let o = rtl_gen_in(&dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(
        err.contains("error: ") && err.contains(says),
        "{args:?}: {err}"
    );
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert_eq!(left_behind(&dir), Vec::<String>::new(), "{args:?}");
}

#[test]
fn image_sizes_out_of_range_are_errors_for_every_command() {
    let out = ["-o", "o.png"];
    for (cmd, extra) in [
        ("render", &out[..]),
        ("hybrid", &out[..]),
        ("bench", &[][..]),
        ("wide", &[][..]),
        ("fit", &["--no-synth", "--out", "d"][..]),
    ] {
        for size in [["--width", "100000"], ["--width", "0"]] {
            let mut args = vec![cmd, "B.toml"];
            args.extend(extra);
            args.extend(size);
            refused(
                cmd,
                "",
                &args,
                &format!("{} {} is not in 1..=16384", size[0], size[1]),
            );
        }
    }
    refused(
        "fit-wide",
        "",
        &[
            "fit",
            "B.toml",
            "--no-synth",
            "--out",
            "d",
            "--wide",
            "--width",
            "0",
        ],
        "--width 0 is not in 1..=16384",
    );
    refused(
        "height",
        "",
        &["render", "B.toml", "-o", "o.png", "--height", "16385"],
        "--height 16385 is not in 1..=16384",
    );
}

#[test]
fn a_bundle_size_beside_wide_is_an_error() {
    // the wide traversal is single-ray: a --bundle it would ignore is refused, on both
    // commands that trace over the wide BVH (the default bundle size is not a request)
    for (cmd, out) in [("render", &["-o", "o.png"][..]), ("rtl-loop", &[][..])] {
        let mut args = vec![cmd, "B.toml", "--wide", "4", "--bundle", "64"];
        args.extend(out);
        refused(
            &format!("wide-bundle-{cmd}"),
            "",
            &args,
            "--wide 4 traces single rays: no --bundle (given 64)",
        );
    }
}

#[test]
fn ao_rays_out_of_range_are_errors() {
    refused(
        "ao",
        "",
        &["render", "B.toml", "-o", "o.png", "--ao", "4000000000"],
        "--ao 4000000000 is not in 0..=256",
    );
    let toml_ao = SCENE.replace("height = 8", "height = 8\nao_rays = 4000000000");
    let dir = folder("ao-toml", "");
    std::fs::write(dir.join("B.toml"), toml_ao).unwrap();
    let o = rtl_gen_in(&dir, &["render", "B.toml", "-o", "o.png"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("field `render.ao_rays`"), "{err}");
    assert_eq!(left_behind(&dir), Vec::<String>::new());
}

#[test]
fn outputs_are_checked_before_the_work_and_a_failure_leaves_none() {
    refused(
        "jpg",
        "",
        &["render", "B.toml", "-o", "o.jpg"],
        "o.jpg: the image is written as PNG",
    );
    refused(
        "hybrid-jpg",
        "",
        &["hybrid", "B.toml", "-o", "o.jpg"],
        "o.jpg: the image is written as PNG",
    );
    refused(
        "dump-nodir",
        "",
        &[
            "render",
            "B.toml",
            "-o",
            "o.png",
            "--dump-hits",
            "nodir/h.txt",
        ],
        "nodir/h.txt: no such directory for this output",
    );
    refused(
        "png-nodir",
        "",
        &["render", "B.toml", "-o", "nodir/o.png"],
        "nodir/o.png: no such directory for this output",
    );
    // a folder as the hits file (the folder is the test's own, left as it was)
    let dir = folder("dump-dir", "");
    std::fs::create_dir(dir.join("sub")).unwrap();
    let o = rtl_gen_in(
        &dir,
        &["render", "B.toml", "-o", "o.png", "--dump-hits", "sub"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("sub: is a directory, not an output file"),
        "{err}"
    );
    assert_eq!(left_behind(&dir), ["sub"]);
}

#[test]
fn a_good_render_leaves_only_its_outputs() {
    let dir = folder("good", "");
    let o = rtl_gen_in(
        &dir,
        &["render", "B.toml", "-o", "o.png", "--dump-hits", "h.txt"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(left_behind(&dir), ["h.txt", "o.png"]);
    assert!(std::fs::read(dir.join("o.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    let o = rtl_gen_in(&dir, &["hybrid", "B.toml", "-o", "y.png"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(left_behind(&dir), ["h.txt", "o.png", "y.png"]);
}

#[test]
fn scene_values_that_would_run_for_hours_are_errors() {
    let render = ["render", "B.toml", "-o", "o.png"];
    refused(
        "grid-wrap",
        "[[grids]]\nmesh = \"q\"\ncount = [65536, 65536]\nspacing = 1.0\n",
        &render,
        "field `grids[0].count`",
    );
    refused(
        "grass-segments",
        "[meshes.m]\nprocedural = \"grass\"\nblades = 10\nsegments = 4000000000\n",
        &render,
        "field `meshes.m.segments`",
    );
    refused(
        "light-color",
        "[[lights]]\nkind = \"point\"\nposition = [0.0, 3.0, 0.0]\ncolor = \"white\"\n",
        &render,
        "field `lights[1].color`",
    );
    refused(
        "tiny-scale",
        "[[instances]]\nmesh = \"q\"\nscale = [0.5, 0.5, 1e-39]\n",
        &render,
        "field `instances[1].transform`",
    );
}
