//! The `rtlvec` vector format: binary streams and their text form.
//!
//! Binary: one ASCII header line `rtlvec 1 <name>:<width>,...\n`, then
//! records back to back, each port little-endian in `ceil(width/8)` bytes
//! with the bits above the width zero. Text: `#` comments, a header line of
//! port names (`name` or `name:width`), then one transaction a line with
//! values in `0x` hex, `0b` binary or decimal. See `docs/vectors.md`.
//!
//! Readers stream: they hold one buffer, never the whole file.

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};
use std::path::Path;

use crate::error::{Location, SimError};
use crate::ports::{is_identifier, width_mask, Port, MAX_WIDTH};

/// First word of every binary stream's header.
pub const MAGIC: &str = "rtlvec";
/// The binary format version this crate reads and writes.
pub const VERSION: u32 = 1;
/// Size of the I/O buffers: large enough that syscalls are rare per vector.
pub const BLOCK: usize = 1 << 20;
/// Longest accepted header line; a longer one means this is not a vector
/// stream, and reading on would buffer an arbitrary file.
pub const MAX_HEADER: usize = 64 * 1024;

/// Decoding may read up to 7 bytes past a record's end; buffers carry this
/// much slack so the per-field access is one 8-byte load.
const SLACK: usize = 8;

/// The binary header line for `ports`, newline included.
pub fn header_line(ports: &[Port]) -> String {
    let list: Vec<String> = ports
        .iter()
        .map(|p| format!("{}:{}", p.name, p.width))
        .collect();
    format!("{MAGIC} {VERSION} {}\n", list.join(","))
}

/// Parses a binary header line (without its newline); `stream` names the
/// source in errors.
pub fn parse_header(line: &str, stream: &str) -> Result<Vec<Port>, SimError> {
    let err = |field: Option<&str>, msg: String| {
        Err(SimError::format(stream, Location::Header, field, msg))
    };
    let Some(rest) = line.strip_prefix("rtlvec ") else {
        let shown: String = line.chars().take(40).collect();
        return err(
            None,
            format!("not an rtlvec stream: the first line must start with `{MAGIC} {VERSION} ` (found `{shown}`)"),
        );
    };
    let (version, list) = rest.split_once(' ').unwrap_or((rest, ""));
    if version != VERSION.to_string() {
        return err(
            None,
            format!("unsupported version `{version}` (this reader knows {VERSION})"),
        );
    }
    if list.is_empty() {
        return err(None, "the header lists no ports".into());
    }
    let mut ports = Vec::new();
    for (i, item) in list.split(',').enumerate() {
        let Some((name, width)) = item.split_once(':') else {
            return err(
                None,
                format!("port {i} `{item}` is not of the form name:width"),
            );
        };
        if !is_identifier(name) {
            return err(
                None,
                format!("port {i}: `{name}` is not a port name (letters, digits, `_`)"),
            );
        }
        let width = match width.parse::<u32>() {
            // Canonical decimal only, as writers produce it: the harness
            // compares header lines byte for byte.
            Ok(w)
                if (1..=MAX_WIDTH).contains(&w)
                    && width.bytes().all(|b| b.is_ascii_digit())
                    && !width.starts_with('0') =>
            {
                w
            }
            _ => {
                return err(
                    Some(name),
                    format!("width `{width}` is not a number in 1..={MAX_WIDTH}"),
                )
            }
        };
        if ports.iter().any(|p: &Port| p.name == name) {
            return err(Some(name), "port listed twice".into());
        }
        ports.push(Port::new(name, width));
    }
    Ok(ports)
}

/// Checks that a stream's ports are exactly `expected` (names, widths and
/// order), reporting the first difference.
pub fn check_ports(stream: &str, found: &[Port], expected: &[Port]) -> Result<(), SimError> {
    let err = |field: &str, msg: String| {
        Err(SimError::format(stream, Location::Header, Some(field), msg))
    };
    for p in found {
        match expected.iter().find(|e| e.name == p.name) {
            None => {
                let names: Vec<&str> = expected.iter().map(|e| e.name.as_str()).collect();
                return err(
                    &p.name,
                    format!("unknown port (expected ports: {})", names.join(", ")),
                );
            }
            Some(e) if e.width != p.width => {
                return err(
                    &p.name,
                    format!("width {} but the port is {} bits wide", p.width, e.width),
                )
            }
            Some(_) => {}
        }
    }
    for e in expected {
        if !found.iter().any(|p| p.name == e.name) {
            return err(&e.name, "missing port".into());
        }
    }
    if found != expected {
        return Err(SimError::format(
            stream,
            Location::Header,
            None,
            format!(
                "ports are in the wrong order: `{}` instead of `{}`",
                header_line(found).trim_end(),
                header_line(expected).trim_end()
            ),
        ));
    }
    Ok(())
}

/// Checks a port list given to a writer: non-empty, unique valid names,
/// widths in range.
fn check_writer_ports(stream: &str, ports: &[Port]) -> Result<(), SimError> {
    // Round-tripping through the header parser applies exactly the rules a
    // reader will apply later.
    let line = header_line(ports);
    parse_header(line.trim_end(), stream).map(|_| ())
}

/// Precomputed field layout of one record.
#[derive(Clone, Debug)]
struct Codec {
    /// Per port: byte offset in the record, mask of its bytes, mask of its
    /// width.
    fields: Vec<(usize, u64, u64)>,
    record_bytes: usize,
}

impl Codec {
    fn new(ports: &[Port]) -> Codec {
        let mut offset = 0;
        let fields = ports
            .iter()
            .map(|p| {
                let f = (offset, width_mask(8 * p.bytes() as u32), p.mask());
                offset += p.bytes();
                f
            })
            .collect();
        Codec {
            fields,
            record_bytes: offset,
        }
    }

    /// Decodes one record; `rec` must extend `SLACK` bytes past the record.
    /// On a value wider than its port, returns that port's index.
    #[inline]
    fn decode(&self, rec: &[u8], out: &mut [u64]) -> Result<(), usize> {
        for (i, (&(off, bytes_mask, width_mask), o)) in self.fields.iter().zip(out).enumerate() {
            let raw = u64::from_le_bytes(rec[off..off + 8].try_into().expect("8 bytes"));
            let v = raw & bytes_mask;
            if v & !width_mask != 0 {
                return Err(i);
            }
            *o = v;
        }
        Ok(())
    }

    /// Encodes one record into `out`, which must extend `SLACK` bytes past
    /// the record. Each field is stored as 8 bytes; the high (zero) bytes
    /// are overwritten by the next field or fall into the slack. On a value
    /// wider than its port, returns that port's index.
    #[inline]
    fn encode(&self, vals: &[u64], out: &mut [u8]) -> Result<(), usize> {
        for (i, (&(off, _, width_mask), &v)) in self.fields.iter().zip(vals).enumerate() {
            if v & !width_mask != 0 {
                return Err(i);
            }
            out[off..off + 8].copy_from_slice(&v.to_le_bytes());
        }
        Ok(())
    }
}

/// Error for a value that does not fit its port.
fn too_wide(stream: &str, location: Location, port: &Port, value: u64) -> SimError {
    SimError::format(
        stream,
        location,
        Some(&port.name),
        format!(
            "value wider than port: {value:#x} does not fit {} bits",
            port.width
        ),
    )
}

fn check_len(what: &str, got: usize, want: usize) -> Result<(), SimError> {
    if got == want {
        Ok(())
    } else {
        Err(SimError::Invalid(format!(
            "{what}: slice of {got} values for {want} ports"
        )))
    }
}

/// Streaming reader of the binary format.
pub struct BinReader<R: Read> {
    inner: R,
    stream: String,
    ports: Vec<Port>,
    codec: Codec,
    buf: Vec<u8>,
    /// Capacity for data; `buf` has `SLACK` more bytes.
    cap: usize,
    pos: usize,
    len: usize,
    /// Stream offset of `buf[0]`.
    base: u64,
    records: u64,
}

impl BinReader<File> {
    /// Opens a binary vector file and reads its header.
    pub fn open(path: impl AsRef<Path>) -> Result<BinReader<File>, SimError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let f = File::open(path).map_err(|e| SimError::io(format!("opening {name}"), e))?;
        BinReader::new(f, name)
    }
}

impl<R: Read> BinReader<R> {
    /// Wraps a stream and reads its header; `stream` names it in errors.
    /// The reader does its own buffering: do not wrap `inner` in a
    /// `BufReader`.
    pub fn new(inner: R, stream: impl Into<String>) -> Result<BinReader<R>, SimError> {
        let mut r = BinReader {
            inner,
            stream: stream.into(),
            ports: Vec::new(),
            codec: Codec::new(&[]),
            buf: vec![0; BLOCK + SLACK],
            cap: BLOCK,
            pos: 0,
            len: 0,
            base: 0,
            records: 0,
        };
        let line = r.read_header_line()?;
        r.ports = parse_header(&line, &r.stream)?;
        r.codec = Codec::new(&r.ports);
        if r.codec.record_bytes > r.cap {
            // Only reachable with thousands of wide ports; keep whole
            // records in the buffer regardless.
            r.cap = r.codec.record_bytes;
            r.buf.resize(r.cap + SLACK, 0);
        }
        Ok(r)
    }

    fn read_header_line(&mut self) -> Result<String, SimError> {
        loop {
            if let Some(nl) = self.buf[..self.len].iter().position(|&b| b == b'\n') {
                let line = std::str::from_utf8(&self.buf[..nl]).map_err(|_| {
                    SimError::format(
                        &self.stream,
                        Location::Header,
                        None,
                        "not an rtlvec stream: the header line is not ASCII",
                    )
                })?;
                let line = line.to_owned();
                self.pos = nl + 1;
                return Ok(line);
            }
            if self.len >= MAX_HEADER {
                return Err(SimError::format(
                    &self.stream,
                    Location::Header,
                    None,
                    format!("not an rtlvec stream: no header line within {MAX_HEADER} bytes"),
                ));
            }
            if self.read_more()? == 0 {
                let msg = if self.len == 0 {
                    "empty stream: expected an `rtlvec 1 ...` header line"
                } else {
                    "stream ends inside the header line (no newline)"
                };
                return Err(SimError::format(&self.stream, Location::Header, None, msg));
            }
        }
    }

    /// Reads once into the free part of the buffer; returns bytes read.
    fn read_more(&mut self) -> Result<usize, SimError> {
        loop {
            match self.inner.read(&mut self.buf[self.len..self.cap]) {
                Ok(n) => {
                    self.len += n;
                    return Ok(n);
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(SimError::io(format!("reading {}", self.stream), e)),
            }
        }
    }

    /// Makes at least one whole record available unless the stream ends;
    /// returns the bytes available.
    fn fill(&mut self) -> Result<usize, SimError> {
        let need = self.codec.record_bytes;
        if self.len - self.pos >= need {
            return Ok(self.len - self.pos);
        }
        self.buf.copy_within(self.pos..self.len, 0);
        self.base += self.pos as u64;
        self.len -= self.pos;
        self.pos = 0;
        while self.len < need {
            if self.read_more()? == 0 {
                break;
            }
        }
        Ok(self.len)
    }

    /// The stream's ports, in record order.
    pub fn ports(&self) -> &[Port] {
        &self.ports
    }

    /// The stream's name as used in errors.
    pub fn stream(&self) -> &str {
        &self.stream
    }

    /// Bytes per record.
    pub fn record_bytes(&self) -> usize {
        self.codec.record_bytes
    }

    /// Records read so far.
    pub fn records(&self) -> u64 {
        self.records
    }

    /// Fails unless the stream's ports are exactly `expected`.
    pub fn expect_ports(&self, expected: &[Port]) -> Result<(), SimError> {
        check_ports(&self.stream, &self.ports, expected)
    }

    /// Reads the next record into `values` (one per port); `Ok(false)` at a
    /// clean end of stream.
    #[inline]
    pub fn read_record(&mut self, values: &mut [u64]) -> Result<bool, SimError> {
        check_len("BinReader::read_record", values.len(), self.ports.len())?;
        let rb = self.codec.record_bytes;
        if self.len - self.pos < rb {
            let avail = self.fill()?;
            if avail == 0 {
                return Ok(false);
            }
            if avail < rb {
                return Err(SimError::format(
                    &self.stream,
                    self.location(),
                    None,
                    format!("truncated record at end of stream: {avail} of {rb} bytes"),
                ));
            }
        }
        let rec = &self.buf[self.pos..self.pos + rb + SLACK];
        if let Err(i) = self.codec.decode(rec, values) {
            let raw = u64::from_le_bytes(
                rec[self.codec.fields[i].0..][..8]
                    .try_into()
                    .expect("8 bytes"),
            ) & self.codec.fields[i].1;
            return Err(too_wide(&self.stream, self.location(), &self.ports[i], raw));
        }
        self.pos += rb;
        self.records += 1;
        Ok(true)
    }

    /// Reads up to `values.len() / ports` records into consecutive slots of
    /// `values`; returns how many (0 at the end of the stream).
    pub fn read_records(&mut self, values: &mut [u64]) -> Result<usize, SimError> {
        let n = self.ports.len();
        if !values.len().is_multiple_of(n) {
            return Err(SimError::Invalid(format!(
                "BinReader::read_records: {} values is not a multiple of {n} ports",
                values.len()
            )));
        }
        let mut count = 0;
        for chunk in values.chunks_exact_mut(n) {
            if !self.read_record(chunk)? {
                break;
            }
            count += 1;
        }
        Ok(count)
    }

    fn location(&self) -> Location {
        Location::Record {
            index: self.records,
            offset: self.base + self.pos as u64,
        }
    }
}

/// Streaming writer of the binary format.
pub struct BinWriter<W: Write> {
    inner: Option<W>,
    stream: String,
    ports: Vec<Port>,
    codec: Codec,
    buf: Vec<u8>,
    len: usize,
    header_bytes: u64,
    records: u64,
}

impl BinWriter<File> {
    /// Creates (truncates) a binary vector file and writes its header.
    pub fn create(path: impl AsRef<Path>, ports: &[Port]) -> Result<BinWriter<File>, SimError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let f = File::create(path).map_err(|e| SimError::io(format!("creating {name}"), e))?;
        BinWriter::new(f, name, ports)
    }
}

impl<W: Write> BinWriter<W> {
    /// Wraps a sink and writes the header; `stream` names it in errors. The
    /// writer does its own buffering: do not wrap `inner` in a `BufWriter`.
    pub fn new(inner: W, stream: impl Into<String>, ports: &[Port]) -> Result<Self, SimError> {
        let stream = stream.into();
        check_writer_ports(&stream, ports)?;
        let codec = Codec::new(ports);
        let header = header_line(ports);
        let cap = BLOCK.max(header.len()) + codec.record_bytes + SLACK;
        let mut buf = vec![0; cap];
        buf[..header.len()].copy_from_slice(header.as_bytes());
        Ok(BinWriter {
            inner: Some(inner),
            stream,
            ports: ports.to_vec(),
            codec,
            buf,
            len: header.len(),
            header_bytes: header.len() as u64,
            records: 0,
        })
    }

    /// Appends one record (one value per port).
    #[inline]
    pub fn write_record(&mut self, values: &[u64]) -> Result<(), SimError> {
        check_len("BinWriter::write_record", values.len(), self.ports.len())?;
        let rb = self.codec.record_bytes;
        if self.len + rb + SLACK > self.buf.len() {
            self.flush_buf()?;
        }
        if let Err(i) = self.codec.encode(values, &mut self.buf[self.len..]) {
            let location = Location::Record {
                index: self.records,
                offset: self.header_bytes + self.records * rb as u64,
            };
            return Err(too_wide(&self.stream, location, &self.ports[i], values[i]));
        }
        self.len += rb;
        self.records += 1;
        Ok(())
    }

    /// Records written so far.
    pub fn records(&self) -> u64 {
        self.records
    }

    fn flush_buf(&mut self) -> Result<(), SimError> {
        if let Some(w) = self.inner.as_mut() {
            w.write_all(&self.buf[..self.len])
                .map_err(|e| SimError::io(format!("writing {}", self.stream), e))?;
        }
        self.len = 0;
        Ok(())
    }

    /// Flushes everything and returns the sink. Dropping the writer instead
    /// also flushes, but cannot report errors.
    pub fn finish(mut self) -> Result<W, SimError> {
        self.flush_buf()?;
        let mut w = self.inner.take().expect("finish runs once");
        w.flush()
            .map_err(|e| SimError::io(format!("flushing {}", self.stream), e))?;
        Ok(w)
    }
}

impl<W: Write> Drop for BinWriter<W> {
    fn drop(&mut self) {
        if self.inner.is_some() {
            let _ = self.flush_buf();
        }
    }
}

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
                    let width = match w.parse::<u32>() {
                        Ok(w) if (1..=MAX_WIDTH).contains(&w) => w,
                        _ => {
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

/// Converts a text stream to a binary one; returns the record count. With
/// `expected`, the text must have exactly those ports and the binary
/// records follow their order.
pub fn text_to_binary<R: BufRead, W: Write>(
    input: R,
    input_name: &str,
    output: W,
    output_name: &str,
    expected: Option<&[Port]>,
) -> Result<u64, SimError> {
    let mut r = TextReader::new(input, input_name, expected)?;
    let mut w = BinWriter::new(output, output_name, r.ports())?;
    let mut values = vec![0; r.ports().len()];
    while r.read_record(&mut values)? {
        w.write_record(&values)?;
    }
    let n = w.records();
    w.finish()?;
    Ok(n)
}

/// Converts a binary stream to text; returns the record count. With
/// `expected`, the stream's ports must be exactly those.
pub fn binary_to_text<R: Read, W: Write>(
    input: R,
    input_name: &str,
    output: W,
    output_name: &str,
    expected: Option<&[Port]>,
) -> Result<u64, SimError> {
    let mut r = BinReader::new(input, input_name)?;
    if let Some(expected) = expected {
        r.expect_ports(expected)?;
    }
    let mut w = TextWriter::new(output, output_name, r.ports())?;
    let mut values = vec![0; r.ports().len()];
    while r.read_record(&mut values)? {
        w.write_record(&values)?;
    }
    let n = r.records();
    w.finish()?;
    Ok(n)
}

/// The two encodings of a vector file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VecFormat {
    /// The `rtlvec 1` binary stream.
    Binary,
    /// The text form.
    Text,
}

/// Tells a file's format from its first bytes: binary streams start with
/// `rtlvec 1 `, anything else is taken as text.
pub fn detect_format(path: &Path) -> Result<VecFormat, SimError> {
    let name = path.display().to_string();
    let mut f = File::open(path).map_err(|e| SimError::io(format!("opening {name}"), e))?;
    let prefix = format!("{MAGIC} {VERSION} ");
    let mut head = vec![0; prefix.len()];
    let mut got = 0;
    while got < head.len() {
        match f.read(&mut head[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(SimError::io(format!("reading {name}"), e)),
        }
    }
    Ok(if head[..got] == *prefix.as_bytes() {
        VecFormat::Binary
    } else {
        VecFormat::Text
    })
}

/// Writes `dst` all or nothing: `write` gets a temporary file beside `dst`
/// (and `dst`'s name for messages); on success the temporary file is
/// renamed to `dst`, on failure it is removed and `dst` is left as it was,
/// so a reader never sees a half-written file.
pub fn write_atomically<T>(
    dst: &Path,
    write: impl FnOnce(File, &str) -> Result<T, SimError>,
) -> Result<T, SimError> {
    let dst_name = dst.display().to_string();
    let file_name = dst
        .file_name()
        .ok_or_else(|| SimError::Invalid(format!("{dst_name}: not a file name")))?;
    let tmp = dst.with_file_name(format!(
        ".{}.tmp-{}",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let f = File::create(&tmp).map_err(|e| SimError::io(format!("creating {dst_name}"), e))?;
    let result = write(f, &dst_name).and_then(|v| {
        std::fs::rename(&tmp, dst)
            .map(|()| v)
            .map_err(|e| SimError::io(format!("renaming the finished {dst_name} into place"), e))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Converts `src` to the other format into `dst`; returns the format
/// written and the record count. `dst` is written all or nothing
/// ([`write_atomically`]).
pub fn convert_file(
    src: &Path,
    dst: &Path,
    expected: Option<&[Port]>,
) -> Result<(VecFormat, u64), SimError> {
    let src_name = src.display().to_string();
    let open = |p: &Path| File::open(p).map_err(|e| SimError::io(format!("opening {src_name}"), e));
    match detect_format(src)? {
        VecFormat::Binary => {
            let input = open(src)?;
            let n = write_atomically(dst, |out, dst_name| {
                binary_to_text(input, &src_name, out, dst_name, expected)
            })?;
            Ok((VecFormat::Text, n))
        }
        VecFormat::Text => {
            let input = BufReader::with_capacity(BLOCK, open(src)?);
            let n = write_atomically(dst, |out, dst_name| {
                text_to_binary(input, &src_name, out, dst_name, expected)
            })?;
            Ok((VecFormat::Binary, n))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ports() -> Vec<Port> {
        vec![
            Port::new("a", 16),
            Port::new("flag", 1),
            Port::new("wide", 64),
            Port::new("odd", 33),
        ]
    }

    fn encode(records: &[[u64; 4]]) -> Vec<u8> {
        let mut w = BinWriter::new(Vec::new(), "mem", &ports()).unwrap();
        for r in records {
            w.write_record(r).unwrap();
        }
        w.finish().unwrap()
    }

    fn read_all(bytes: &[u8]) -> Result<Vec<[u64; 4]>, SimError> {
        let mut r = BinReader::new(bytes, "in.rtlvec")?;
        let mut out = Vec::new();
        let mut v = [0; 4];
        while r.read_record(&mut v)? {
            out.push(v);
        }
        Ok(out)
    }

    const RECORDS: [[u64; 4]; 3] = [
        [0x1234, 1, u64::MAX, (1 << 33) - 1],
        [0, 0, 0, 0],
        [0xffff, 0, 0x0123_4567_89ab_cdef, 0x1_0000_0001],
    ];

    #[test]
    fn binary_layout_is_little_endian_byte_padded() {
        let bytes = encode(&RECORDS[..1]);
        let header = b"rtlvec 1 a:16,flag:1,wide:64,odd:33\n";
        assert_eq!(&bytes[..header.len()], header);
        let rec = &bytes[header.len()..];
        // a: 2 bytes, flag: 1, wide: 8, odd: 5 -> 16 bytes.
        assert_eq!(
            rec,
            [
                0x34, 0x12, 0x01, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff,
                0xff, 0x01
            ]
        );
    }

    #[test]
    fn binary_round_trip_across_buffer_boundaries() {
        // Enough records that the reader refills mid-record at least once
        // (16-byte records do not divide the buffer after the header).
        let n = 3 * BLOCK / 16 + 7;
        let recs: Vec<[u64; 4]> = (0..n as u64)
            .map(|i| {
                [
                    i & 0xffff,
                    i & 1,
                    i.wrapping_mul(0x9e37_79b9_7f4a_7c15),
                    (i * 3) & ((1 << 33) - 1),
                ]
            })
            .collect();
        let bytes = encode(&recs);
        assert_eq!(read_all(&bytes).unwrap(), recs);
    }

    #[test]
    fn truncated_record_says_how_many_bytes() {
        let bytes = encode(&RECORDS);
        let cut = &bytes[..bytes.len() - 5];
        let e = read_all(cut).unwrap_err().to_string();
        let header = 36;
        assert_eq!(
            e,
            format!(
                "in.rtlvec: record 2 (byte offset {}): truncated record at end of stream: 11 of 16 bytes",
                header + 32
            )
        );
    }

    #[test]
    fn value_wider_than_port_is_rejected_with_record_and_field() {
        let mut bytes = encode(&RECORDS);
        // Set bit 1 of `flag` in record 1.
        let header = 36;
        bytes[header + 16 + 2] = 0x02;
        let e = read_all(&bytes).unwrap_err().to_string();
        assert_eq!(
            e,
            "in.rtlvec: record 1 (byte offset 52), field `flag`: value wider than port: 0x2 does not fit 1 bits"
        );
        // Bit 33 of `odd` (a 33-bit port in 5 bytes) in record 2.
        let mut bytes = encode(&RECORDS);
        bytes[header + 32 + 11 + 4] |= 0x02;
        let e = read_all(&bytes).unwrap_err().to_string();
        assert!(e.contains("record 2") && e.contains("field `odd`"), "{e}");
    }

    #[test]
    fn writer_rejects_values_wider_than_port() {
        let mut w = BinWriter::new(Vec::new(), "out.rtlvec", &ports()).unwrap();
        w.write_record(&RECORDS[0]).unwrap();
        let e = w
            .write_record(&[0x1_0000, 0, 0, 0])
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "out.rtlvec: record 1 (byte offset 52), field `a`: value wider than port: 0x10000 does not fit 16 bits"
        );
    }

    #[test]
    fn malformed_headers_are_rejected() {
        let cases: &[(&[u8], &str)] = &[
            (b"", "empty stream"),
            (b"rtlvec 1 a:16", "ends inside the header"),
            (b"RTLVEC 1 a:16\n", "not an rtlvec stream"),
            (b"rtlvec 2 a:16\n", "unsupported version `2`"),
            (b"rtlvec 1 \n", "lists no ports"),
            (b"rtlvec 1 a16\n", "not of the form name:width"),
            (b"rtlvec 1 a:0\n", "field `a`: width `0`"),
            (b"rtlvec 1 a:65\n", "field `a`: width `65`"),
            (b"rtlvec 1 a:016\n", "field `a`: width `016`"),
            (b"rtlvec 1 a:+16\n", "field `a`: width `+16`"),
            (b"rtlvec 1 a:16,a:8\n", "field `a`: port listed twice"),
            (b"rtlvec 1 a b:16\n", "not a port name"),
            (b"rtlvec 1 a:16, b:16\n", "not a port name"),
        ];
        for (bytes, want) in cases {
            let e = match BinReader::new(*bytes, "h.rtlvec") {
                Ok(_) => panic!("accepted {:?}", String::from_utf8_lossy(bytes)),
                Err(e) => e.to_string(),
            };
            assert!(e.starts_with("h.rtlvec: header"), "{e}");
            assert!(e.contains(want), "{e} lacks {want}");
        }
        let junk = vec![b'x'; MAX_HEADER + 10];
        let e = BinReader::new(&junk[..], "j").err().unwrap().to_string();
        assert!(e.contains("no header line within"), "{e}");
    }

    #[test]
    fn expected_ports_are_enforced() {
        let bytes = encode(&RECORDS);
        let r = BinReader::new(&bytes[..], "s").unwrap();
        r.expect_ports(&ports()).unwrap();
        let mut other = ports();
        other[3].name = "odd2".into();
        let e = r.expect_ports(&other).unwrap_err().to_string();
        assert!(e.contains("field `odd`: unknown port"), "{e}");
        let e = r.expect_ports(&ports()[..3]).unwrap_err().to_string();
        assert!(e.contains("field `odd`: unknown port"), "{e}");
        let mut more = ports();
        more.push(Port::new("extra", 3));
        let e = r.expect_ports(&more).unwrap_err().to_string();
        assert!(e.contains("field `extra`: missing port"), "{e}");
        let mut narrow = ports();
        narrow[0].width = 15;
        let e = r.expect_ports(&narrow).unwrap_err().to_string();
        assert!(e.contains("field `a`: width 16 but the port is 15"), "{e}");
        let mut swapped = ports();
        swapped.swap(0, 1);
        let e = r.expect_ports(&swapped).unwrap_err().to_string();
        assert!(e.contains("wrong order"), "{e}");
    }

    #[test]
    fn text_round_trip_through_binary() {
        let bin = encode(&RECORDS);
        let mut text = Vec::new();
        let n = binary_to_text(&bin[..], "in", &mut text, "out.txt", None).unwrap();
        assert_eq!(n, 3);
        let text_s = String::from_utf8(text.clone()).unwrap();
        assert!(
            text_s.contains("0x1234 0x1    0xffffffffffffffff 0x1ffffffff"),
            "{text_s}"
        );
        let mut back = Vec::new();
        let n = text_to_binary(&text[..], "out.txt", &mut back, "back", None).unwrap();
        assert_eq!(n, 3);
        assert_eq!(back, bin);
    }

    #[test]
    fn text_reader_accepts_comments_radixes_and_reordering() {
        let text = "\
# a comment line

odd flag:1  a wide   # header, widths optional with a port list
0b1_0001 1 0x1234 18446744073709551615
8589934591 0 65_535 0x0123_4567_89AB_CDEF  # trailing comment
";
        let mut r = TextReader::new(text.as_bytes(), "t.txt", Some(&ports())).unwrap();
        let mut v = [0; 4];
        assert!(r.read_record(&mut v).unwrap());
        assert_eq!(v, [0x1234, 1, u64::MAX, 0b10001]);
        assert!(r.read_record(&mut v).unwrap());
        assert_eq!(v, [0xffff, 0, 0x0123_4567_89ab_cdef, (1 << 33) - 1]);
        assert!(!r.read_record(&mut v).unwrap());
        assert_eq!(r.line(), 5);
    }

    #[test]
    fn text_reader_skips_a_byte_order_mark_and_names_bad_bytes() {
        let text = "\u{feff}a flag wide odd\n1 0 2 3\n";
        let mut r = TextReader::new(text.as_bytes(), "t.txt", Some(&ports())).unwrap();
        let mut v = [0; 4];
        assert!(r.read_record(&mut v).unwrap());
        assert_eq!(v, [1, 0, 2, 3]);
        // a NUL byte: named by code point and column, never echoed raw
        let e = text_error("a flag wide odd\n1 0\u{0}2 3\n", Some(&ports()));
        assert_eq!(e, "t.txt: line 2: control or invisible character U+0000 at column 4 (text vector files hold printable text)");
        assert!(!e.contains('\u{0}'));
        // binary garbage: the line and the column of the first bad byte
        let mut bytes = b"a flag wide odd\n1 0 ".to_vec();
        bytes.extend([0xff, 0xfe, b'\n']);
        let e = match TextReader::new(&bytes[..], "t.txt", Some(&ports())) {
            Ok(mut r) => r.read_record(&mut v).unwrap_err().to_string(),
            Err(e) => e.to_string(),
        };
        assert!(
            e.starts_with("t.txt: line 2: not UTF-8 text: byte 0xff at column 5"),
            "{e}"
        );
        // a mark after the first line is no mark: an error, not a silent skip
        let e = text_error("a flag wide odd\n\u{feff}1 0 2 3\n", Some(&ports()));
        assert!(
            e.contains("line 2: control or invisible character U+FEFF at column 1"),
            "{e}"
        );
    }

    fn text_error(text: &str, expected: Option<&[Port]>) -> String {
        let mut r = match TextReader::new(text.as_bytes(), "t.txt", expected) {
            Ok(r) => r,
            Err(e) => return e.to_string(),
        };
        let mut v = vec![0; r.ports().len()];
        loop {
            match r.read_record(&mut v) {
                Ok(true) => {}
                Ok(false) => panic!("no error in {text:?}"),
                Err(e) => return e.to_string(),
            }
        }
    }

    #[test]
    fn text_errors_name_line_and_field() {
        let p = ports();
        assert_eq!(
            text_error("a b:2\n1 2\n3 4 5\n", None),
            "t.txt: line 1, field `a`: no width: write `name:width` in the header or supply the port list"
        );
        assert_eq!(
            text_error("a:4 b:2\n1 2\n\n# c\n3 4 5\n", None),
            "t.txt: line 5: wrong field count: 3 values but the header has 2 ports"
        );
        assert_eq!(
            text_error("a:4 b:2\n1 2\n3\n", None),
            "t.txt: line 3: wrong field count: 1 values but the header has 2 ports"
        );
        assert_eq!(
            text_error("a:4 b:2\n1 4\n", None),
            "t.txt: line 2, field `b`: value wider than port: 0x4 does not fit 2 bits"
        );
        assert_eq!(
            text_error("a:4 b:2\n0xg 1\n", None),
            "t.txt: line 2, field `a`: `0xg` is not a hex number (bad digit `g`)"
        );
        assert!(text_error("a:4 b:2\n-1 1\n", None).contains("line 2, field `a`"));
        assert!(text_error("a:64\n18446744073709551616\n", None).contains("does not fit 64 bits"));
        assert!(text_error("a:4 a:4\n", None).contains("line 1, field `a`: port listed twice"));
        assert!(text_error("a:0\n", None).contains("line 1, field `a`: width `0`"));
        assert!(text_error("# only comments\n", None).contains("no header line"));
        assert!(text_error("a flag wide odd bogus\n", Some(&p))
            .contains("line 1, field `bogus`: unknown port"));
        assert!(text_error("a flag wide\n", Some(&p)).contains("field `odd`: missing port"));
        assert!(text_error("a:8 flag wide odd\n", Some(&p))
            .contains("field `a`: width 8 but the port is 16 bits wide"));
    }

    #[test]
    fn values_parse_in_all_radixes() {
        assert_eq!(
            parse_value("0x_1").err().unwrap(),
            "`0x_1` is not a hex number"
        );
        assert_eq!(parse_value("0XfF").unwrap(), 255);
        assert_eq!(parse_value("0b101").unwrap(), 5);
        assert_eq!(parse_value("1_000").unwrap(), 1000);
        assert_eq!(parse_value("0xffffffffffffffff").unwrap(), u64::MAX);
        assert!(parse_value("0x1_0000_0000_0000_0000").is_err());
        assert!(parse_value("").is_err());
        assert!(parse_value("0x").is_err());
        assert!(parse_value("12a").is_err());
    }

    #[test]
    fn convert_file_goes_both_ways() {
        let dir = std::env::temp_dir().join(format!("sim-vectors-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bin = dir.join("v.rtlvec");
        std::fs::write(&bin, encode(&RECORDS)).unwrap();
        let txt = dir.join("v.txt");
        assert_eq!(
            convert_file(&bin, &txt, Some(&ports())).unwrap(),
            (VecFormat::Text, 3)
        );
        assert_eq!(detect_format(&txt).unwrap(), VecFormat::Text);
        let bin2 = dir.join("v2.rtlvec");
        assert_eq!(
            convert_file(&txt, &bin2, None).unwrap(),
            (VecFormat::Binary, 3)
        );
        assert_eq!(std::fs::read(&bin2).unwrap(), encode(&RECORDS));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_conversion_leaves_no_output_file() {
        let dir = std::env::temp_dir().join(format!("sim-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bin = dir.join("cut.rtlvec");
        let mut bytes = encode(&RECORDS);
        bytes.pop();
        std::fs::write(&bin, bytes).unwrap();
        let txt = dir.join("cut.txt");
        let e = convert_file(&bin, &txt, None).unwrap_err().to_string();
        assert!(e.contains("truncated record"), "{e}");
        assert!(!txt.exists());
        // An existing destination is kept as it was.
        std::fs::write(&txt, "old").unwrap();
        convert_file(&bin, &txt, None).unwrap_err();
        assert_eq!(std::fs::read_to_string(&txt).unwrap(), "old");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 2, "no temporary file left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
