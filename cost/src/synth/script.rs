//! The Yosys scripts of each flow and what is read back from them (cells by
//! type, logic depth).

use super::*;
use rtl_gen::ir::CellLibrary;

pub(super) fn coarse_without_share(flow: &str) -> &'static str {
    // The `coarse` label of synth_ice40 / synth_ecp5 (synth_lattice -family
    // ecp5) in Yosys 0.70 minus `share`, as `echo on` lists its commands.
    // ice40 runs `begin` and `flatten` before it; ecp5's `coarse` starts with
    // proc and flatten. Checked against the tool by the test
    // `coarse_scripts_match_yosys` (cost/tests/synth.rs).
    match flow {
        "ice40" => {
            "opt_expr\ncheck\nopt_clean\nopt -nodffe -nosdff\nfsm\nopt\nwreduce\npeepopt\nopt_clean\n\
             techmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\nalumacc\nopt\nmemory -nomap\n\
             opt_clean\n"
        }
        _ => {
            "proc -latches error\ncheck\nflatten\ntribuf -logic\ndeminout\nopt_expr\ncheck\nopt_clean\n\
             opt -nodffe -nosdff\nfsm\nopt\nwreduce\npeepopt\nopt_clean\n\
             techmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\n\
             techmap -map +/mul2dsp.v -D DSP_A_MAXWIDTH=18 -D DSP_B_MAXWIDTH=18 \
             -D DSP_A_MINWIDTH=2 -D DSP_B_MINWIDTH=2 -D DSP_NAME=$__MUL18X18\n\
             chtype -set $mul t:$__soft_mul\ntechmap -map +/lattice/dsp_map_18x18.v\n\
             alumacc\nopt\nmemory -nomap\nopt_clean\n"
        }
    }
}

/// The commands of [`coarse_without_share`] for `flow` (`ice40` or `ecp5`), one a line.
pub fn coarse_commands(flow: &str) -> Vec<String> {
    coarse_without_share(flow)
        .lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

/// The FPGA family whose cells the unit instantiates, if any (`dsp=ecp5`,
/// `dsp=xc7`).
pub(super) fn cell_library(g: &Generated) -> Option<CellLibrary> {
    g.module
        .hierarchy()
        .iter()
        .find_map(|m| m.vendor.as_ref().map(|v| v.library))
}

/// True when the unit instantiates ECP5 cells (`dsp=ecp5`).
pub(super) fn has_ecp5_cells(g: &Generated) -> bool {
    cell_library(g) == Some(CellLibrary::Ecp5)
}

/// Yosys's ECP5 cell declarations, read before a design that instantiates
/// them so that `hierarchy -check` knows them.
pub(super) const ECP5_CELLS: &str = "read_verilog -lib +/lattice/cells_bb_ecp5.v\n";

/// Yosys's declarations of a family's cells, read before a design that
/// instantiates them so that `hierarchy -check` knows them.
fn cell_declarations(library: CellLibrary) -> &'static str {
    match library {
        CellLibrary::Ecp5 => ECP5_CELLS,
        CellLibrary::Xc7 => "read_verilog -lib +/xilinx/cells_sim.v\n",
    }
}

/// The Yosys script for the unit `top` whose files are `files`
/// (`cells`: the family whose cells the unit instantiates).
pub fn yosys_script(
    top: &str,
    files: &[String],
    o: &SynthOptions,
    cells: Option<CellLibrary>,
) -> String {
    let mut s = String::new();
    if let Some(library) = cells {
        s += cell_declarations(library);
    }
    s += &format!("read_verilog {}\n", files.join(" "));
    s += &format!("hierarchy -check -top {top}\ndesign -save orig\n");
    let nf = if o.flat { "" } else { " -noflatten" };
    if o.generic {
        let flat = if o.flat { " -flatten -noshare" } else { "" };
        s += &format!(
            "design -load orig\nsynth -top {top}{flat}\nflatten\nopt_clean -purge\n\
             tee -q -o generic.stat.json stat -json\ntee -q -o generic.ltp ltp -noff\n"
        );
    }
    if o.ice40 {
        s += "design -load orig\n";
        if o.flat {
            s += &format!("synth_ice40 -top {top} -run begin:coarse\n");
            s += coarse_without_share("ice40");
            s += &format!("synth_ice40 -top {top} -run map_ram:\n");
        } else {
            s += &format!("synth_ice40{nf} -top {top}\n");
        }
        // `-noff` drops Yosys's own flip-flop cells only; after mapping they are SB_DFF*,
        // left out by the selection, so the path is one stage's, not the pipeline's
        s += "flatten\nopt_clean -purge\ntee -q -o ice40.stat.json stat -json\n\
              tee -q -o ice40.ltp ltp -noff t:SB_DFF* %n\n";
    }
    if o.ecp5 {
        s += "design -load orig\n";
        if o.flat {
            s += &format!("synth_ecp5 -top {top} -run begin:coarse\n");
            s += coarse_without_share("ecp5");
            s += &format!("synth_ecp5 -top {top} -run map_ram:\n");
        } else {
            s += &format!("synth_ecp5{nf} -top {top}\n");
        }
        s += "flatten\nopt_clean -purge\ntee -q -o ecp5.stat.json stat -json\n";
    }
    if o.xilinx {
        s += &format!(
            "design -load orig\nsynth_xilinx -flatten -top {top}\ntee -q -o xilinx.stat.json stat -json\n"
        );
    }
    s
}

pub(super) fn cells_by_type(json_path: &Path) -> Result<BTreeMap<String, u64>, SynthError> {
    let text = std::fs::read_to_string(json_path).map_err(io("stat json"))?;
    // `tee -o` may prepend the command echo; the JSON starts at the first brace.
    let start = text
        .find('{')
        .ok_or_else(|| SynthError("stat: no JSON".into()))?;
    let v: serde_json::Value =
        serde_json::from_str(&text[start..]).map_err(io("stat json parse"))?;
    let mut out = BTreeMap::new();
    if let Some(types) = v["design"]["num_cells_by_type"].as_object() {
        for (k, n) in types {
            // `flatten` leaves one `$scopeinfo` (no logic) per instance
            if k == "$scopeinfo" {
                continue;
            }
            out.insert(k.clone(), n.as_u64().unwrap_or(0));
        }
    }
    Ok(out)
}

/// Parses `length=N` from the output of `ltp`.
pub fn parse_ltp(text: &str) -> Option<u64> {
    let i = text.find("(length=")?;
    let rest = &text[i + 8..];
    let end = rest.find(')')?;
    rest[..end].trim().parse().ok()
}

pub(super) fn sum_prefix(m: &BTreeMap<String, u64>, prefix: &str) -> u64 {
    m.iter()
        .filter(|(k, _)| k.starts_with(prefix))
        .map(|(_, v)| *v)
        .sum()
}
