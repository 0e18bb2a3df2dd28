//! The text form of `rtlvec`: a header of port names, one transaction a line.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use super::*;
use crate::error::{Location, SimError};
use crate::ports::{is_identifier, Port, MAX_WIDTH};

/// Parses a text value: `0x` hex, `0b` binary or decimal, `_` allowed
/// between digits.
pub fn parse_value(token: &str) -> Result<u64, String> {
    let (digits, radix, what) = if let Some(h) = token
        .strip_prefix("0x")
        .or_else(|| token.strip_prefix("0X"))
    {
        (h, 16, "hex")
    } else if let Some(b) = token
        .strip_prefix("0b")
        .or_else(|| token.strip_prefix("0B"))
    {
        (b, 2, "binary")
    } else {
        (token, 10, "decimal")
    };
    if digits.is_empty() || digits.starts_with('_') || digits.ends_with('_') {
        return Err(format!("`{token}` is not a {what} number"));
    }
    let mut v: u64 = 0;
    for c in digits.chars() {
        if c == '_' {
            continue;
        }
        let d = c
            .to_digit(radix)
            .ok_or_else(|| format!("`{token}` is not a {what} number (bad digit `{c}`)"))?;
        v = v
            .checked_mul(radix as u64)
            .and_then(|v| v.checked_add(d as u64))
            .ok_or_else(|| format!("`{token}` does not fit 64 bits"))?;
    }
    Ok(v)
}

/// Streaming reader of the text form.
pub struct TextReader<R: BufRead> {
    inner: R,
    stream: String,
    /// Ports in output order (the expected order when one was given).
    ports: Vec<Port>,
    /// For each text column, its slot in the output.
    slot_of_column: Vec<usize>,
    line: String,
    line_no: u64,
}

impl TextReader<BufReader<File>> {
    /// Opens a text vector file and reads its header.
    pub fn open(path: impl AsRef<Path>, expected: Option<&[Port]>) -> Result<Self, SimError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let f = File::open(path).map_err(|e| SimError::io(format!("opening {name}"), e))?;
        TextReader::new(BufReader::with_capacity(BLOCK, f), name, expected)
    }
}

impl<R: BufRead> TextReader<R> {
    /// Wraps a text stream and reads its header line. With `expected`, the
    /// columns must be exactly those ports (in any order; records come out
    /// in `expected` order) and widths may be omitted from the header;
    /// without, every header entry needs `name:width`.
    pub fn new(
        inner: R,
        stream: impl Into<String>,
        expected: Option<&[Port]>,
    ) -> Result<Self, SimError> {
        let mut r = TextReader {
            inner,
            stream: stream.into(),
            ports: Vec::new(),
            slot_of_column: Vec::new(),
            line: String::new(),
            line_no: 0,
        };
        if !r.next_content_line()? {
            return Err(SimError::format(
                &r.stream,
                Location::Whole,
                None,
                "no header line (a line of port names) found",
            ));
        }
        let at = Location::Line(r.line_no);
        let content = strip_comment(&r.line);
        let mut columns: Vec<(String, Option<u32>)> = Vec::new();
        for tok in content.split_ascii_whitespace() {
            let (name, width) = match tok.split_once(':') {
                Some((n, w)) => {
                    let width = match super::port_width(w) {
                        Some(w) => w,
                        None => {
                            return Err(SimError::format(
                                &r.stream,
                                at,
                                Some(n),
                                format!("width `{w}` is not a number in 1..={MAX_WIDTH}"),
                            ))
                        }
                    };
                    (n, Some(width))
                }
                None => (tok, None),
            };
            if !is_identifier(name) {
                return Err(SimError::format(
                    &r.stream,
                    at,
                    None,
                    format!("header: `{tok}` is not a port name (or name:width)"),
                ));
            }
            if columns.iter().any(|(n, _)| n == name) {
                return Err(SimError::format(
                    &r.stream,
                    at,
                    Some(name),
                    "port listed twice in the header",
                ));
            }
            columns.push((name.to_owned(), width));
        }
        match expected {
            Some(expected) => {
                for (name, width) in &columns {
                    let Some(slot) = expected.iter().position(|p| &p.name == name) else {
                        let names: Vec<&str> = expected.iter().map(|p| p.name.as_str()).collect();
                        return Err(SimError::format(
                            &r.stream,
                            at,
                            Some(name),
                            format!("unknown port (expected ports: {})", names.join(", ")),
                        ));
                    };
                    if let Some(w) = width {
                        if *w != expected[slot].width {
                            return Err(SimError::format(
                                &r.stream,
                                at,
                                Some(name),
                                format!(
                                    "width {w} but the port is {} bits wide",
                                    expected[slot].width
                                ),
                            ));
                        }
                    }
                    r.slot_of_column.push(slot);
                }
                if let Some(missing) = expected
                    .iter()
                    .find(|p| !columns.iter().any(|(n, _)| *n == p.name))
                {
                    return Err(SimError::format(
                        &r.stream,
                        at,
                        Some(&missing.name),
                        "missing port",
                    ));
                }
                r.ports = expected.to_vec();
            }
            None => {
                for (i, (name, width)) in columns.iter().enumerate() {
                    let Some(width) = width else {
                        return Err(SimError::format(
                            &r.stream,
                            at,
                            Some(name),
                            "no width: write `name:width` in the header or supply the port list",
                        ));
                    };
                    r.ports.push(Port::new(name.clone(), *width));
                    r.slot_of_column.push(i);
                }
            }
        }
        if r.ports.is_empty() {
            return Err(SimError::format(
                &r.stream,
                at,
                None,
                "the header lists no ports",
            ));
        }
        Ok(r)
    }

    /// Reads lines until one with content; false at end of input.
    /// Reads the next line that is not blank or a comment into `self.line`.
    /// A UTF-8 byte-order mark before the first line is skipped (editors on
    /// Windows write one); bytes that are not UTF-8 and control characters
    /// other than tab and CR are errors naming the line and the column, so
    /// nothing invisible is echoed into a message.
    fn next_content_line(&mut self) -> Result<bool, SimError> {
        let mut bytes = Vec::new();
        loop {
            self.line.clear();
            bytes.clear();
            let n = self
                .inner
                .read_until(b'\n', &mut bytes)
                .map_err(|e| SimError::io(format!("reading {}", self.stream), e))?;
            if n == 0 {
                return Ok(false);
            }
            self.line_no += 1;
            let mut b: &[u8] = &bytes;
            if self.line_no == 1 {
                b = b.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(b);
            }
            let at = || Location::Line(self.line_no);
            let text = std::str::from_utf8(b).map_err(|e| {
                let k = e.valid_up_to();
                SimError::format(
                    &self.stream,
                    at(),
                    None,
                    format!(
                        "not UTF-8 text: byte {:#04x} at column {} (a binary rtlvec stream is read \
                         as binary, not as text)",
                        b[k],
                        k + 1
                    ),
                )
            })?;
            if let Some((col, c)) = text.chars().enumerate().find(|(_, c)| {
                (c.is_control() && !matches!(c, '\t' | '\r' | '\n')) || *c == '\u{feff}'
            }) {
                return Err(SimError::format(
                    &self.stream,
                    at(),
                    None,
                    format!(
                        "control or invisible character U+{:04X} at column {} (text vector files hold printable text)",
                        c as u32,
                        col + 1
                    ),
                ));
            }
            self.line.push_str(text);
            if !strip_comment(&self.line).trim().is_empty() {
                return Ok(true);
            }
        }
    }

    /// The ports of each record, in record order.
    pub fn ports(&self) -> &[Port] {
        &self.ports
    }

    /// Line number of the last line read (1-based).
    pub fn line(&self) -> u64 {
        self.line_no
    }

    /// Reads the next transaction into `values`; `Ok(false)` at the end.
    pub fn read_record(&mut self, values: &mut [u64]) -> Result<bool, SimError> {
        check_len("TextReader::read_record", values.len(), self.ports.len())?;
        if !self.next_content_line()? {
            return Ok(false);
        }
        let at = Location::Line(self.line_no);
        let content = strip_comment(&self.line);
        let count = content.split_ascii_whitespace().count();
        if count != self.ports.len() {
            return Err(SimError::format(
                &self.stream,
                at,
                None,
                format!(
                    "wrong field count: {count} values but the header has {} ports",
                    self.ports.len()
                ),
            ));
        }
        for (col, tok) in content.split_ascii_whitespace().enumerate() {
            let slot = self.slot_of_column[col];
            let port = &self.ports[slot];
            let v = parse_value(tok)
                .map_err(|m| SimError::format(&self.stream, at.clone(), Some(&port.name), m))?;
            if v & !port.mask() != 0 {
                return Err(too_wide(&self.stream, at, port, v));
            }
            values[slot] = v;
        }
        Ok(true)
    }
}

fn strip_comment(line: &str) -> &str {
    match line.find('#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Streaming writer of the text form: a comment, a `name:width` header and
/// one line of zero-padded hex per transaction, in aligned columns.
pub struct TextWriter<W: Write> {
    inner: BufWriter<W>,
    stream: String,
    ports: Vec<Port>,
    columns: Vec<usize>,
    line: String,
    records: u64,
}

impl TextWriter<File> {
    /// Creates (truncates) a text vector file and writes its header.
    pub fn create(path: impl AsRef<Path>, ports: &[Port]) -> Result<Self, SimError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let f = File::create(path).map_err(|e| SimError::io(format!("creating {name}"), e))?;
        TextWriter::new(f, name, ports)
    }
}

impl<W: Write> TextWriter<W> {
    /// Wraps a sink and writes the header; `stream` names it in errors.
    pub fn new(inner: W, stream: impl Into<String>, ports: &[Port]) -> Result<Self, SimError> {
        let stream = stream.into();
        check_writer_ports(&stream, ports)?;
        let heads: Vec<String> = ports
            .iter()
            .map(|p| format!("{}:{}", p.name, p.width))
            .collect();
        let columns: Vec<usize> = ports
            .iter()
            .zip(&heads)
            .map(|(p, h)| h.len().max(2 + p.width.div_ceil(4) as usize))
            .collect();
        let mut w = TextWriter {
            inner: BufWriter::with_capacity(BLOCK, inner),
            stream,
            ports: ports.to_vec(),
            columns,
            line: String::new(),
            records: 0,
        };
        w.line
            .push_str("# rtlvec text: one transaction a line, values in hex\n");
        for (i, h) in heads.iter().enumerate() {
            w.push_cell(i, h);
        }
        w.end_line()?;
        Ok(w)
    }

    fn push_cell(&mut self, col: usize, text: &str) {
        if col > 0 {
            self.line.push(' ');
        }
        self.line.push_str(text);
        if col + 1 < self.columns.len() {
            for _ in text.len()..self.columns[col] {
                self.line.push(' ');
            }
        }
    }

    fn end_line(&mut self) -> Result<(), SimError> {
        self.line.push('\n');
        self.inner
            .write_all(self.line.as_bytes())
            .map_err(|e| SimError::io(format!("writing {}", self.stream), e))?;
        self.line.clear();
        Ok(())
    }

    /// Appends one transaction (one value per port).
    pub fn write_record(&mut self, values: &[u64]) -> Result<(), SimError> {
        check_len("TextWriter::write_record", values.len(), self.ports.len())?;
        for (i, &v) in values.iter().enumerate() {
            let p = &self.ports[i];
            if v & !p.mask() != 0 {
                // Header comment and header are lines 1 and 2.
                let at = Location::Line(self.records + 3);
                return Err(too_wide(&self.stream, at, p, v));
            }
            let digits = p.width.div_ceil(4) as usize;
            let cell = format!("{v:#0width$x}", width = digits + 2);
            self.push_cell(i, &cell);
        }
        self.end_line()?;
        self.records += 1;
        Ok(())
    }

    /// Flushes and returns the sink.
    pub fn finish(self) -> Result<W, SimError> {
        let stream = self.stream;
        self.inner
            .into_inner()
            .map_err(|e| SimError::io(format!("flushing {stream}"), e.into_error()))
    }
}
