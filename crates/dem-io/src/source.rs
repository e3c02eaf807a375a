//! A buffered input that knows its name, length, byte position and line number.

use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use crate::error::{DumpError, ErrorKind, Location};

/// Lines longer than this are rejected, so garbage without newlines cannot fill memory.
pub(crate) const MAX_LINE: usize = 1 << 20;

const BUFFER: usize = 1 << 16;

pub(crate) struct Source<R> {
    inner: BufReader<R>,
    name: PathBuf,
    /// Byte offset of the next unread byte.
    pos: u64,
    /// Total length of the stream.
    len: u64,
    /// Number of lines consumed (so the line just read is `line`).
    line: u64,
}

impl<R: Read + Seek> Source<R> {
    pub(crate) fn new(mut reader: R, name: PathBuf) -> Result<Self, DumpError> {
        let io_err = |e| DumpError::new(name.clone(), Location::Unknown, ErrorKind::Io(e));
        let pos = reader.stream_position().map_err(io_err)?;
        let len = reader.seek(SeekFrom::End(0)).map_err(io_err)?;
        reader.seek(SeekFrom::Start(pos)).map_err(io_err)?;
        Ok(Source {
            inner: BufReader::with_capacity(BUFFER, reader),
            name,
            pos,
            len,
            line: 0,
        })
    }

    pub(crate) fn name(&self) -> &Path {
        &self.name
    }

    pub(crate) fn pos(&self) -> u64 {
        self.pos
    }

    pub(crate) fn line(&self) -> u64 {
        self.line
    }

    pub(crate) fn remaining(&self) -> u64 {
        self.len.saturating_sub(self.pos)
    }

    pub(crate) fn err(&self, location: Location, kind: ErrorKind) -> DumpError {
        DumpError::at(&self.name, location, kind)
    }

    /// Error at the current line (text).
    pub(crate) fn line_err(&self, kind: ErrorKind) -> DumpError {
        self.err(Location::Line(self.line), kind)
    }

    /// Error at byte `offset` (binary).
    pub(crate) fn byte_err(&self, offset: u64, kind: ErrorKind) -> DumpError {
        self.err(Location::Byte(offset), kind)
    }

    /// Reads one line (with its `\n`, if any) into `buf`. Returns `false` at end of file.
    pub(crate) fn read_line(&mut self, buf: &mut Vec<u8>) -> Result<bool, DumpError> {
        buf.clear();
        let n = (&mut self.inner)
            .take(MAX_LINE as u64)
            .read_until(b'\n', buf)
            .map_err(|e| self.err(Location::Line(self.line + 1), ErrorKind::Io(e)))?;
        if n == 0 {
            return Ok(false);
        }
        self.pos += n as u64;
        self.line += 1;
        if n == MAX_LINE && buf.last() != Some(&b'\n') {
            return Err(self.line_err(ErrorKind::LineTooLong(MAX_LINE)));
        }
        Ok(true)
    }

    /// Fills `buf` completely; on a short read reports how many bytes were there.
    pub(crate) fn read_exact(&mut self, buf: &mut [u8]) -> Result<Result<(), usize>, DumpError> {
        let mut got = 0;
        while got < buf.len() {
            match self.inner.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.byte_err(self.pos + got as u64, ErrorKind::Io(e))),
            }
        }
        self.pos += got as u64;
        Ok(if got == buf.len() { Ok(()) } else { Err(got) })
    }

    /// Skips `n` bytes, which the caller has checked to be within the file.
    pub(crate) fn skip(&mut self, n: u64) -> Result<(), DumpError> {
        debug_assert!(n <= self.remaining());
        let offset = i64::try_from(n).map_err(|_| {
            self.byte_err(
                self.pos,
                ErrorKind::BadChunk(format!("cannot skip {n} bytes")),
            )
        })?;
        self.inner
            .seek_relative(offset)
            .map_err(|e| self.byte_err(self.pos, ErrorKind::Io(e)))?;
        self.pos += n;
        Ok(())
    }

    /// Moves to byte `pos`, which is the start of line `line + 1`.
    pub(crate) fn seek_to(&mut self, pos: u64, line: u64) -> Result<(), DumpError> {
        self.inner
            .seek(SeekFrom::Start(pos))
            .map_err(|e| self.byte_err(pos, ErrorKind::Io(e)))?;
        self.pos = pos;
        self.line = line;
        Ok(())
    }
}
