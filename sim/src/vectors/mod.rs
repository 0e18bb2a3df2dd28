//! The `rtlvec` vector format: binary streams and their text form.
//!
//! Binary: one ASCII header line `rtlvec 1 <name>:<width>,...\n`, then
//! records back to back, each port little-endian in `ceil(width/8)` bytes
//! with the bits above the width zero. Text: `#` comments, a header line of
//! port names (`name` or `name:width`), then one transaction a line with
//! values in `0x` hex, `0b` binary or decimal. See `docs/vectors.md`.
//!
//! Readers stream: they hold one buffer, never the whole file.

use crate::error::{Location, SimError};
use crate::ports::{is_identifier, width_mask, Port, MAX_WIDTH};

mod binary;
mod files;
mod text;

pub use binary::{BinReader, BinWriter};
pub use files::{
    binary_to_text, convert_file, detect_format, output_problem, temp_beside, text_to_binary,
    through_links, write_atomically, VecFormat,
};
pub use text::{parse_value, TextReader, TextWriter};

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
pub(super) const SLACK: usize = 8;

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
        let width = match port_width(width) {
            Some(w) => w,
            None => {
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
pub(super) fn check_writer_ports(stream: &str, ports: &[Port]) -> Result<(), SimError> {
    // Round-tripping through the header parser applies exactly the rules a
    // reader will apply later.
    let line = header_line(ports);
    parse_header(line.trim_end(), stream).map(|_| ())
}

/// Precomputed field layout of one record.
#[derive(Clone, Debug)]
pub(super) struct Codec {
    /// Per port: byte offset in the record, mask of its bytes, mask of its
    /// width.
    pub(super) fields: Vec<(usize, u64, u64)>,
    pub(super) record_bytes: usize,
}

impl Codec {
    pub(super) fn new(ports: &[Port]) -> Codec {
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
    pub(super) fn decode(&self, rec: &[u8], out: &mut [u64]) -> Result<(), usize> {
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
    pub(super) fn encode(&self, vals: &[u64], out: &mut [u8]) -> Result<(), usize> {
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
pub(super) fn too_wide(stream: &str, location: Location, port: &Port, value: u64) -> SimError {
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

pub(super) fn check_len(what: &str, got: usize, want: usize) -> Result<(), SimError> {
    if got == want {
        Ok(())
    } else {
        Err(SimError::Invalid(format!(
            "{what}: slice of {got} values for {want} ports"
        )))
    }
}

/// A port width as a header states it: canonical decimal in `1..=MAX_WIDTH`
/// (no sign, no leading zero), as writers produce it: the harness compares
/// header lines byte for byte, and text and binary headers read one way.
pub(crate) fn port_width(text: &str) -> Option<u32> {
    let canonical = text.bytes().all(|b| b.is_ascii_digit()) && !text.starts_with('0');
    let w = text.parse::<u32>().ok()?;
    (canonical && (1..=MAX_WIDTH).contains(&w)).then_some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Text and binary headers read a width one way: canonical decimal
    /// (the text header took `+16` and `016`, the binary one refused them).
    #[test]
    fn a_port_width_is_canonical_decimal() {
        for (text, width) in [("1", Some(1)), ("16", Some(16)), ("64", Some(MAX_WIDTH))] {
            assert_eq!(port_width(text), width, "{text}");
        }
        for bad in ["+16", "016", "0", "", "65", "16\r", "-1", "0x10", " 16"] {
            assert_eq!(port_width(bad), None, "{bad:?}");
        }
    }

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
