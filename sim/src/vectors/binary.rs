//! The binary form of `rtlvec`: a header line, then fixed-size records.

use std::fs::File;
use std::io::{self, Read, Write};
use std::path::Path;

use super::*;
use crate::error::{Location, SimError};
use crate::ports::Port;

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
