//! One vector run again alone, with an optional VCD trace.

use super::*;

/// Runs one vector through the harness, tracing into `vcd` if given, and
/// returns its outputs in port-list order.
pub fn replay(h: &Harness, inputs: &[u64], vcd: Option<&Path>) -> Result<Vec<u64>, SimError> {
    let ports: &PortList = h.ports();
    let mut w = BinWriter::new(Vec::new(), "replay vector", &ports.inputs)?;
    if inputs.len() != ports.inputs.len() {
        return Err(SimError::Invalid(format!(
            "replay: {} input values for {} input ports of `{}`",
            inputs.len(),
            ports.inputs.len(),
            ports.top
        )));
    }
    w.write_record(inputs)?;
    let bytes = w.finish()?;
    let traced;
    let h = match vcd {
        Some(_) if !h.is_traced() => {
            traced = h.traced()?;
            &traced
        }
        _ => h,
    };
    let mut cmd = h.command();
    if let Some(v) = vcd {
        cmd.arg("--vcd").arg(v);
    }
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| SimError::io(format!("starting {}", h.binary().display()), e))?;
    // One record is far below the pipe capacity, so writing before reading
    // cannot deadlock.
    let mut stdin = child.stdin.take().expect("piped stdin");
    let wrote = io::Write::write_all(&mut stdin, &bytes);
    drop(stdin);
    let out = child
        .wait_with_output()
        .map_err(|e| SimError::io("waiting for the harness", e))?;
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if !out.status.success() {
        return Err(SimError::Harness {
            message: format!(
                "replay on `{}`: harness {}",
                ports.top,
                describe_exit(out.status)
            ),
            stderr,
        });
    }
    wrote.map_err(|e| SimError::io("writing the replay vector to the harness", e))?;
    let parse = || -> Result<Vec<u64>, SimError> {
        let mut rd = BinReader::new(&out.stdout[..], "harness stdout")?;
        rd.expect_ports(&ports.outputs)?;
        let mut values = vec![0; ports.outputs.len()];
        let mut extra = values.clone();
        if !rd.read_record(&mut values)? || rd.read_record(&mut extra)? {
            return Err(SimError::Invalid(format!(
                "expected exactly one result, got {}",
                rd.records()
            )));
        }
        Ok(values)
    };
    parse().map_err(|e| SimError::Harness {
        message: format!("replay on `{}`: {e}", ports.top),
        stderr,
    })
}
