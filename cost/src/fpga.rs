//! `rtl-gen fpga`: a unit's bring-up bitstream (scripts/fpga.sh) that meets
//! the board clock by itself, and the stage search it shares with
//! `fit --device`.
//!
//! With `stages` given, `rtl-gen fpga` runs the script once, as told. Without
//! it (for a unit that has stages), it takes `pipeline=balanced` (unless a
//! `pipeline` is given) and searches the stages ([`search_stages`]): the
//! delay model's guess first (the fewest stages whose modelled period fits
//! the board's clock period), two more while the whole bitstream (wrapper
//! included) fails the board clock, then down to the fewest a met build's
//! Fmax suggests; at most [`TRIES`] builds, each in its own folder, the
//! chosen one moved to the script's `$OUT`. It prints each try and the
//! choice, and ends with the chosen build's timing line.

use rtl_gen::params::ParamKind;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

/// ECP5 nanoseconds per level of the delay model (`rtl_gen::retime`), from
/// routed units (docs/cost.md): the first guess of the stages to route.
pub const NS_PER_LEVEL_ECP5: f64 = 1.9;

/// iCE40 (UP5K) nanoseconds per level: a rough figure (its LUTs and routing
/// are about 2.5x slower than the ECP5-6's); the routes decide.
pub const NS_PER_LEVEL_ICE40: f64 = 4.5;

/// Routes a search tries at most.
pub const TRIES: u32 = 4;

/// The fewest stages in `0..=max` whose modelled period (LUT levels of the
/// delay model) times `ns_per_level` fits a `target_mhz` clock; `max` if none.
pub fn first_guess(
    unit: &str,
    params: &dyn Fn(u32) -> Vec<String>,
    target_mhz: f64,
    ns_per_level: f64,
    max: u32,
) -> Result<u32, Box<dyn std::error::Error>> {
    let budget = 1000.0 / target_mhz / ns_per_level;
    for k in 0..=max {
        let g = rtl_flow::generate(unit, &params(k))?;
        if g.modelled_period()? <= budget {
            return Ok(k);
        }
    }
    Ok(max)
}

/// The stage search of `fit --device` and `rtl-gen fpga`: the fewest
/// stages that `route` (which places and routes the unit at the given stages
/// and returns its Fmax, `None` if it has none) meets `target_mhz` with,
/// from `first`, at most [`TRIES`] routes and `max` stages.
///
/// A route that fails adds two stages (or one, below a depth that met). A
/// route that meets tries the fewest stages its Fmax suggests (the period
/// falls about as 1/(stages + 1)), above any depth that failed; the search
/// ends when that is no fewer. Returns the fewest stages that met, or the
/// last tried with `false` when none did.
pub fn search_stages<E>(
    first: u32,
    max: u32,
    target_mhz: f64,
    route: &mut dyn FnMut(u32) -> Result<Option<f64>, E>,
) -> Result<(u32, bool), E> {
    let mut s = first.min(max);
    let mut last = s;
    let (mut best, mut failed): (Option<u32>, Option<u32>) = (None, None);
    for _ in 0..TRIES {
        last = s;
        let fmax = route(s)?.filter(|f| *f > 0.0);
        let next = match fmax {
            Some(f) if f >= target_mhz => {
                best = Some(s);
                let suggested = ((s + 1) as f64 * target_mhz / f).ceil() as u32;
                let floor = failed.map_or(0, |x| x + 1);
                suggested.saturating_sub(1).max(floor)
            }
            _ => {
                failed = Some(s);
                match best {
                    Some(_) => s + 1,
                    None if s < max => (s + 2).min(max),
                    None => break,
                }
                .min(best.unwrap_or(u32::MAX))
            }
        };
        if Some(next) == best || next == s || best.is_some_and(|b| next > b) {
            break;
        }
        s = next;
    }
    Ok(best.map_or((last, false), |b| (b, true)))
}

/// The checkout's root (scripts/fpga.sh, constraints/).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A board as scripts/fpga.sh describes it (`FPGA_BOARD_INFO=1`): the boards
/// live in the script alone.
struct Board {
    name: String,
    family: String,
    mhz: f64,
}

/// Runs scripts/fpga.sh with `args`; each line of its output goes to
/// `line` as it comes. Returns the exit code (2 when it cannot be run).
fn script(
    args: &[String],
    env: &[(&str, &str)],
    line: &mut dyn FnMut(&str),
) -> Result<i32, String> {
    let path = root().join("scripts/fpga.sh");
    if !path.is_file() {
        return Err(format!(
            "{} not found (rtl-gen fpga runs in its checkout)",
            path.display()
        ));
    }
    let mut cmd = Command::new("bash");
    cmd.arg(&path)
        .args(args)
        .current_dir(root())
        .stdout(Stdio::piped());
    if let Ok(me) = std::env::current_exe() {
        cmd.env("RTL_GEN", me);
    }
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("running {}: {e}", path.display()))?;
    let out = child.stdout.take().expect("piped stdout");
    for l in BufReader::new(out).lines() {
        line(&l.map_err(|e| format!("reading fpga.sh's output: {e}"))?);
    }
    let status = child
        .wait()
        .map_err(|e| format!("waiting for {}: {e}", path.display()))?;
    Ok(status.code().unwrap_or(2))
}

fn board_info(args: &[String]) -> Result<Board, String> {
    let mut info = String::new();
    let code = script(args, &[("FPGA_BOARD_INFO", "1")], &mut |l| {
        info = l.to_string()
    })?;
    let w: Vec<&str> = info.split_whitespace().collect();
    match (code, w.as_slice()) {
        (0, [name, family, mhz]) => Ok(Board {
            name: name.to_string(),
            family: family.to_string(),
            mhz: mhz
                .parse()
                .map_err(|_| format!("fpga.sh: board clock {mhz}"))?,
        }),
        _ => Err(format!("fpga.sh did not describe the board (got `{info}`)")),
    }
}

/// `rtl-gen fpga [BOARD] [UNIT [-p KEY=VALUE]...]`: exit 0 (timing met),
/// 3 (timing failed, the bitstream is still written) or 2 (an error).
pub fn main(args: &[String]) -> ExitCode {
    match run(args) {
        Ok(code) => ExitCode::from(code.clamp(0, 255) as u8),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// The unit and `-p` parameters after the board; `None` for the script's default.
fn unit_and_params(args: &[String]) -> Option<(String, Vec<String>)> {
    let (unit, rest) = args.split_first()?;
    let mut params = Vec::new();
    let mut it = rest.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "-p" | "--param" => params.extend(it.next().cloned()),
            p => params.extend(p.strip_prefix("--param=").map(str::to_string)),
        }
    }
    Some((unit.clone(), params))
}

fn run(args: &[String]) -> Result<i32, String> {
    let board = board_info(args)?;
    let after_board = if args.first() == Some(&board.name) {
        &args[1..]
    } else {
        args
    };
    let max_stages = unit_and_params(after_board).and_then(|(unit, params)| {
        let entry = rtl_flow::find(&unit).ok()?;
        let stages = rtl_flow::param_specs(&entry)
            .into_iter()
            .find(|p| p.name == "stages")?;
        let told = params.iter().any(|p| p.starts_with("stages="));
        match stages.kind {
            ParamKind::Int { max, .. } if !told => Some((unit, params, max.min(64) as u32)),
            _ => None,
        }
    });
    let Some((unit, mut params, max)) = max_stages else {
        // stages given (or a unit without them, or the default unit): as told
        return script(args, &[], &mut |l| println!("{l}"));
    };
    if !params.iter().any(|p| p.starts_with("pipeline=")) {
        params.push("pipeline=balanced".into());
    }
    let with = |s: u32| {
        let mut p = params.clone();
        p.push(format!("stages={s}"));
        p
    };
    let ns = if board.family == "ice40" {
        NS_PER_LEVEL_ICE40
    } else {
        NS_PER_LEVEL_ECP5
    };
    let first = first_guess(&unit, &with, board.mhz, ns, max).map_err(|e| e.to_string())?;
    println!(
        "fpga: no stages given: {} on {} at {} MHz; first guess {first} stages (delay model, {ns} ns a level); +2 while the bitstream fails the board clock, then down to the fewest a met build's Fmax suggests (at most {TRIES} builds)",
        params.join(" "),
        board.name,
        board.mhz
    );
    // each try builds in its own folder; the chosen one becomes the script's $OUT
    let out = std::env::var_os("OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("out/fpga").join(&board.name));
    let out = if out.is_absolute() {
        out
    } else {
        root().join(out)
    };
    let tries = out.with_file_name(format!(
        "{}-tries",
        out.file_name()
            .map_or("fpga".into(), |n| n.to_string_lossy())
    ));
    let _ = std::fs::remove_dir_all(&tries);
    let start = Instant::now();
    let mut timing: Vec<(u32, String)> = Vec::new();
    let mut route = |s: u32| -> Result<Option<f64>, String> {
        let mut a = vec![board.name.clone(), unit.clone()];
        for p in with(s) {
            a.extend(["-p".to_string(), p]);
        }
        println!("fpga: try stages={s}");
        let t = Instant::now();
        let dir = tries.join(format!("s{s}"));
        let dir_text = dir.to_string_lossy().to_string();
        let mut line_of_try = String::new();
        let code = script(&a, &[("OUT", &dir_text)], &mut |l| {
            if l.starts_with("timing:") {
                line_of_try = l.to_string();
            } else {
                println!("{l}");
            }
        })?;
        if code != 0 && code != 3 {
            return Err(format!(
                "scripts/fpga.sh {} exited with {code}",
                a.join(" ")
            ));
        }
        // `timing: met|FAILED at <MHz> MHz (target ...)`
        let fmax = line_of_try
            .split_whitespace()
            .nth(3)
            .and_then(|m| m.parse::<f64>().ok());
        println!(
            "fpga: stages={s}: {} ({:.0} s)",
            line_of_try.trim_start_matches("timing: "),
            t.elapsed().as_secs_f64()
        );
        timing.push((s, line_of_try));
        // the script's verdict: exit 0 is timing met
        Ok(fmax.filter(|_| code == 0))
    };
    let (stages, met) = search_stages(first, max, board.mhz, &mut route)?;
    let kept = tries.join(format!("s{stages}"));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::rename(&kept, &out)
        .map_err(|e| format!("moving {} to {}: {e}", kept.display(), out.display()))?;
    let _ = std::fs::remove_dir_all(&tries);
    println!(
        "fpga: chose {} for {} MHz ({}; {:.0} s in all); its build is in {}",
        with(stages).join(" "),
        board.mhz,
        if met {
            "the fewest stages that routed"
        } else {
            "the clock is NOT met"
        },
        start.elapsed().as_secs_f64(),
        out.display()
    );
    let line = timing.iter().rev().find(|(k, _)| *k == stages);
    println!("{}", line.map_or("", |(_, l)| l.as_str()));
    Ok(if met { 0 } else { 3 })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A route whose Fmax is 10 MHz per stage plus 5 (0 stages: 5 MHz).
    fn linear(tried: &mut Vec<u32>) -> impl FnMut(u32) -> Result<Option<f64>, ()> + '_ {
        move |s| {
            tried.push(s);
            Ok(Some(10.0 * s as f64 + 5.0))
        }
    }

    #[test]
    fn search_steps_up_by_two_then_down_to_the_fewest_that_meet() {
        let mut tried = Vec::new();
        // 1 fails (15 MHz), 3 meets (35), 2 meets (25): the fewest is 2
        assert_eq!(
            search_stages(1, 32, 25.0, &mut linear(&mut tried)),
            Ok((2, true))
        );
        assert_eq!(tried, [1, 3, 2]);
    }

    #[test]
    fn a_first_guess_that_meets_easily_is_lowered_by_its_fmax() {
        let mut tried = Vec::new();
        // 8 meets at 85 MHz: 9 x 25 / 85 suggests 2 stages (3 x period), which meets
        assert_eq!(
            search_stages(8, 32, 25.0, &mut linear(&mut tried)),
            Ok((2, true))
        );
        assert_eq!(tried, [8, 2]);
    }

    #[test]
    fn a_search_that_never_meets_says_so() {
        let mut never = |_: u32| -> Result<Option<f64>, ()> { Ok(None) };
        assert_eq!(search_stages(30, 32, 50.0, &mut never), Ok((32, false)));
        assert_eq!(search_stages(0, 32, 50.0, &mut never), Ok((6, false)));
    }
}
