//! Whole streams and files: conversion both ways, format detection, writing
//! a file only when it is complete.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

use super::*;
use crate::error::SimError;
use crate::ports::Port;

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

/// The file a write to `path` should replace: `path` itself, or when it is a
/// symbolic link the file at the end of its links (followed as the shell's `>`
/// follows them: relative links against the link's folder, a dangling one to
/// the file it names). An output renamed into place onto the link itself would
/// replace the link by a file and leave the file it points to stale.
pub fn through_links(path: &Path) -> PathBuf {
    let mut at = path.to_path_buf();
    // a loop of links ends here, and the write then fails on the link, naming it
    for _ in 0..40 {
        match std::fs::read_link(&at) {
            Ok(to) => {
                at = match at.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                }
            }
            Err(_) => break,
        }
    }
    at
}

/// Why `path` cannot take a command's output, if it cannot: its folder is
/// missing, it is a folder, or it is a device, FIFO or socket (outputs are
/// written beside and renamed into place, which would replace such a file by
/// a regular one instead of writing to it). Links are followed. The one check
/// of every command's output paths, made before the command's work.
pub fn output_problem(path: &Path) -> Option<String> {
    let shown = path.display();
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if dir.is_some_and(|d| !d.is_dir()) {
        Some(format!("{shown}: no such directory for this output"))
    } else if path.is_dir() {
        Some(format!("{shown}: is a directory, not an output file"))
    } else if path.exists() && !path.is_file() {
        Some(format!("{shown}: not a regular file"))
    } else {
        None
    }
}

/// The temporary file an output `dst` is written to before it is renamed into
/// place: beside it (a rename stays on one file system), hidden, named for the
/// process and numbered, so that two outputs of one run never share one; `None`
/// when `dst` has no file name.
pub fn temp_beside(dst: &Path) -> Option<PathBuf> {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    let name = dst.file_name()?;
    let serial = NEXT.fetch_add(1, Ordering::Relaxed);
    let mut temp = std::ffi::OsString::from(".");
    temp.push(name);
    temp.push(format!(".tmp-{}-{serial}", std::process::id()));
    Some(dst.with_file_name(temp))
}

/// Writes `dst` all or nothing: `write` gets a temporary file beside `dst`
/// (and `dst`'s name for messages); on success the temporary file is
/// renamed to `dst` (through its links, [`through_links`]), on failure it is
/// removed and `dst` is left as it was, so a reader never sees a half-written
/// file.
pub fn write_atomically<T>(
    dst: &Path,
    write: impl FnOnce(File, &str) -> Result<T, SimError>,
) -> Result<T, SimError> {
    let dst_name = dst.display().to_string();
    let dst = &through_links(dst);
    let tmp = temp_beside(dst)
        .ok_or_else(|| SimError::Invalid(format!("{dst_name}: not a file name")))?;
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
