//! The crate's one error type.

use std::fmt;
use std::io;

/// Where in a file or stream a problem was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// The file or stream as a whole.
    Whole,
    /// The header line of a vector stream.
    Header,
    /// A 1-based line of a text file.
    Line(u64),
    /// A 1-based line and column, as JSON parsers report them.
    LineColumn(u64, u64),
    /// A 0-based record of a binary stream (the vector index) and the byte
    /// offset of its first byte in the stream, header included.
    Record {
        /// 0-based record number.
        index: u64,
        /// Byte offset of the record in the stream.
        offset: u64,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Whole => Ok(()),
            Location::Header => write!(f, "header"),
            Location::Line(l) => write!(f, "line {l}"),
            Location::LineColumn(l, c) => write!(f, "line {l}, column {c}"),
            Location::Record { index, offset } => {
                write!(f, "record {index} (byte offset {offset})")
            }
        }
    }
}

/// Everything that can go wrong in this crate.
#[derive(Debug)]
pub enum SimError {
    /// An operating-system I/O failure; `context` says on what.
    Io {
        /// What was being done, naming the file or stream.
        context: String,
        /// The underlying error.
        source: io::Error,
    },
    /// Malformed content of a port list or a vector file or stream.
    Format {
        /// The file or stream name.
        stream: String,
        /// Where in it.
        location: Location,
        /// The port or JSON field concerned, if any.
        field: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A required external program is not installed or not on `PATH`.
    ToolMissing {
        /// The program name.
        tool: String,
        /// What to do about it.
        hint: String,
    },
    /// Verilating or compiling the harness failed.
    Build {
        /// Top module and what failed.
        message: String,
        /// The last lines of Verilator's and the compiler's output.
        output_tail: String,
    },
    /// `verilator --lint-only -Wall` reported warnings or errors.
    Lint {
        /// Top module.
        top: String,
        /// Verilator's complete report.
        warnings: String,
    },
    /// The harness process failed or its output broke the protocol.
    Harness {
        /// What went wrong.
        message: String,
        /// The harness's standard error (possibly shortened at the front).
        stderr: String,
    },
    /// A caller-supplied value is unusable: wrong slice length, a stimulus or
    /// golden model value wider than its port, and the like.
    Invalid(String),
}

impl SimError {
    /// Shorthand for a [`SimError::Format`].
    pub fn format(
        stream: impl Into<String>,
        location: Location,
        field: Option<&str>,
        message: impl Into<String>,
    ) -> SimError {
        SimError::Format {
            stream: stream.into(),
            location,
            field: field.map(str::to_owned),
            message: message.into(),
        }
    }

    /// Shorthand for a [`SimError::Io`].
    pub fn io(context: impl Into<String>, source: io::Error) -> SimError {
        SimError::Io {
            context: context.into(),
            source,
        }
    }
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Io { context, source } => write!(f, "{context}: {source}"),
            SimError::Format {
                stream,
                location,
                field,
                message,
            } => {
                write!(f, "{stream}")?;
                if *location != Location::Whole {
                    write!(f, ": {location}")?;
                }
                if let Some(field) = field {
                    let sep = if *location == Location::Whole {
                        ": "
                    } else {
                        ", "
                    };
                    write!(f, "{sep}field `{field}`")?;
                }
                write!(f, ": {message}")
            }
            SimError::ToolMissing { tool, hint } => {
                write!(f, "`{tool}` was not found on PATH: {hint}")
            }
            SimError::Build {
                message,
                output_tail,
            } => write!(f, "{message}\n--- end of build output ---\n{output_tail}"),
            SimError::Lint { top, warnings } => {
                write!(f, "verilator lint of `{top}` failed:\n{warnings}")
            }
            SimError::Harness { message, stderr } => {
                write!(f, "{message}")?;
                let stderr = stderr.trim_end();
                if !stderr.is_empty() {
                    write!(f, "\n--- harness stderr ---\n{stderr}")?;
                }
                Ok(())
            }
            SimError::Invalid(message) => write!(f, "{message}"),
        }
    }
}

impl std::error::Error for SimError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SimError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_errors_name_stream_location_and_field() {
        let e = SimError::format(
            "in.rtlvec",
            Location::Record {
                index: 12,
                offset: 400,
            },
            Some("a"),
            "value wider than port",
        );
        assert_eq!(
            e.to_string(),
            "in.rtlvec: record 12 (byte offset 400), field `a`: value wider than port"
        );
        let e = SimError::format("p.json", Location::Whole, Some("inputs[1].width"), "bad");
        assert_eq!(e.to_string(), "p.json: field `inputs[1].width`: bad");
    }
}
