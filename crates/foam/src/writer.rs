//! Writing FoamFiles: header, dictionaries and lists in OpenFOAM's layout, ASCII or binary.
//!
//! Numbers are written in Rust's shortest round-trip form (`{:?}`: `0.1`, `1.0`, `1e-20`), so
//! reading back gives bit-identical values. Non-finite numbers are refused (OpenFOAM cannot
//! read them and would trap on them). Files are written to a temporary name in the same
//! directory and renamed, so a failure never leaves a half-written file.

use crate::binary::Arch;
use crate::dict::{Dict, Item, Value};
use crate::error::{FoamError, Result};
use crate::parser::{Format, Header};
use std::io::Write;
use std::path::Path;

/// Serialises dictionaries and items into bytes.
pub struct Writer {
    out: Vec<u8>,
    format: Format,
    arch: Arch,
    context: Vec<String>,
}

/// Keyword column width in OpenFOAM's output.
const KEY_WIDTH: usize = 16;

impl Writer {
    /// A writer for the given format and binary layout.
    pub fn new(format: Format, arch: Arch) -> Self {
        Writer {
            out: Vec::new(),
            format,
            arch,
            context: Vec::new(),
        }
    }

    /// The bytes written so far.
    pub fn into_bytes(self) -> Vec<u8> {
        self.out
    }

    fn bad(&self, what: String) -> String {
        if self.context.is_empty() {
            what
        } else {
            format!("entry `{}`: {what}", self.context.join("."))
        }
    }

    /// Writes the banner and the `FoamFile` header.
    pub fn header(&mut self, h: &Header) {
        let o = &mut self.out;
        o.extend_from_slice(
            b"/*--------------------------------*- C++ -*----------------------------------*\\\n\
              | Written by foamgrain: OpenFOAM v1912 file format                           |\n\
              \\*---------------------------------------------------------------------------*/\n",
        );
        o.extend_from_slice(b"FoamFile\n{\n");
        let mut line = |k: &str, v: &str| {
            o.extend_from_slice(format!("    {k:<11} {v};\n").as_bytes());
        };
        line("version", "2.0");
        line("format", h.format.as_str());
        if h.format == Format::Binary {
            line("arch", &format!("\"{}\"", h.arch.to_arch_string()));
        }
        line("class", &h.class);
        if !h.location.is_empty() {
            line("location", &format!("\"{}\"", h.location));
        }
        if let Some(n) = &h.note {
            line("note", &format!("\"{n}\""));
        }
        line("object", &h.object);
        o.extend_from_slice(
            b"}\n// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //\n\n",
        );
    }

    fn indent(&mut self, level: usize) {
        for _ in 0..level {
            self.out.extend_from_slice(b"    ");
        }
    }

    /// Writes all entries of `d` at indentation `level`.
    pub fn dict_body(&mut self, d: &Dict, level: usize) -> Result<(), String> {
        for e in d.entries() {
            self.context.push(e.keyword.clone());
            let key = if e.pattern {
                format!("\"{}\"", e.keyword)
            } else {
                e.keyword.clone()
            };
            self.indent(level);
            match &e.value {
                Value::Dict(sub) => {
                    self.out.extend_from_slice(key.as_bytes());
                    self.out.push(b'\n');
                    self.block(sub, level)?;
                }
                Value::Stream(items) => {
                    if items.is_empty() {
                        self.out.extend_from_slice(key.as_bytes());
                    } else {
                        self.out
                            .extend_from_slice(format!("{key:<KEY_WIDTH$} ").as_bytes());
                        self.items(items, level)?;
                    }
                    self.out.extend_from_slice(b";\n");
                }
            }
            self.context.pop();
            if level == 0 {
                self.out.push(b'\n');
            }
        }
        Ok(())
    }

    fn block(&mut self, d: &Dict, level: usize) -> Result<(), String> {
        self.indent(level);
        self.out.extend_from_slice(b"{\n");
        self.dict_body(d, level + 1)?;
        self.indent(level);
        self.out.extend_from_slice(b"}\n");
        Ok(())
    }

    /// Writes a stream of items separated by spaces.
    pub fn items(&mut self, items: &[Item], level: usize) -> Result<(), String> {
        for (i, it) in items.iter().enumerate() {
            if i > 0 && !self.out.ends_with(b"\n") {
                self.out.push(b' ');
            }
            self.item(it, level)?;
        }
        Ok(())
    }

    fn scalar(&mut self, v: f64) -> Result<(), String> {
        if !v.is_finite() {
            return Err(self.bad(format!("cannot write non-finite number {v}")));
        }
        write!(self.out, "{v:?}").unwrap();
        Ok(())
    }

    fn is_simple(it: &Item) -> bool {
        matches!(
            it,
            Item::Word(_) | Item::Str(_) | Item::Label(_) | Item::Scalar(_) | Item::Punct(_)
        )
    }

    /// Writes one item.
    pub fn item(&mut self, it: &Item, level: usize) -> Result<(), String> {
        match it {
            Item::Word(w) => self.out.extend_from_slice(w.as_bytes()),
            Item::Str(s) => {
                self.out.push(b'"');
                self.out
                    .extend_from_slice(s.replace('"', "\\\"").as_bytes());
                self.out.push(b'"');
            }
            Item::Label(l) => write!(self.out, "{l}").unwrap(),
            Item::Scalar(v) => self.scalar(*v)?,
            Item::Punct(c) => write!(self.out, "{c}").unwrap(),
            Item::Verbatim(v) => write!(self.out, "#{{{v}#}}").unwrap(),
            Item::Dims(d) => {
                self.out.push(b'[');
                self.items(d, level)?;
                self.out.push(b']');
            }
            Item::List(v) if v.len() <= 10 && v.iter().all(Self::is_simple) => {
                self.out.push(b'(');
                self.items(v, level)?;
                self.out.push(b')');
            }
            Item::List(v) => {
                // No count: an integer before a list stays a separate item when read back.
                self.out.push(b'\n');
                self.indent(level);
                self.out.extend_from_slice(b"(\n");
                for x in v {
                    if !matches!(x, Item::Named(..) | Item::Dict(_)) {
                        self.indent(level + 1);
                    }
                    self.item(x, level + 1)?;
                    if !self.out.ends_with(b"\n") {
                        self.out.push(b'\n');
                    }
                }
                self.indent(level);
                self.out.push(b')');
            }
            Item::Named(name, d) => {
                self.indent(level);
                self.out.extend_from_slice(name.as_bytes());
                self.out.push(b'\n');
                self.block(d, level)?;
            }
            Item::Dict(d) => {
                self.out.push(b'\n');
                self.block(d, level)?;
            }
            Item::Scalars(v) => self.typed(v.len(), 1, v, None)?,
            Item::Vectors(v) => self.typed(v.len(), 3, v.as_flattened(), None)?,
            Item::Tuples {
                components, values, ..
            } => self.typed(values.len() / components, *components, values, None)?,
            Item::Labels(v) => self.typed(v.len(), 1, &[], Some(v))?,
        }
        Ok(())
    }

    /// Writes a contiguous list of `n` elements of `comps` scalars (or labels).
    fn typed(
        &mut self,
        n: usize,
        comps: usize,
        values: &[f64],
        labels: Option<&[i64]>,
    ) -> Result<(), String> {
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.bad(format!(
                "cannot write non-finite number {} (element {})",
                values[i],
                i / comps
            )));
        }
        match self.format {
            Format::Binary => {
                write!(self.out, "{n}(").unwrap();
                match labels {
                    Some(l) => self.raw_labels(l)?,
                    None => self.raw_scalars(values),
                }
                self.out.push(b')');
            }
            Format::Ascii => {
                write!(self.out, "\n{n}\n(\n").unwrap();
                match labels {
                    Some(l) => {
                        for x in l {
                            writeln!(self.out, "{x}").unwrap();
                        }
                    }
                    None => ascii_values(&mut self.out, values, comps),
                }
                self.out.extend_from_slice(b")\n");
            }
        }
        Ok(())
    }

    /// Appends scalars as raw bytes in this writer's arch.
    pub fn raw_scalars(&mut self, values: &[f64]) {
        let a = self.arch;
        self.out.reserve(values.len() * a.scalar_bytes);
        for &v in values {
            match (a.scalar_bytes, a.little_endian) {
                (8, true) => self.out.extend_from_slice(&v.to_le_bytes()),
                (8, false) => self.out.extend_from_slice(&v.to_be_bytes()),
                (_, true) => self.out.extend_from_slice(&(v as f32).to_le_bytes()),
                (_, false) => self.out.extend_from_slice(&(v as f32).to_be_bytes()),
            }
        }
    }

    /// Appends labels as raw bytes in this writer's arch; a label that does not fit is an error.
    pub fn raw_labels(&mut self, labels: &[i64]) -> Result<(), String> {
        let a = self.arch;
        self.out.reserve(labels.len() * a.label_bytes);
        for &l in labels {
            if a.label_bytes == 4 {
                let v = i32::try_from(l)
                    .map_err(|_| self.bad(format!("label {l} does not fit in 32 bits")))?;
                if a.little_endian {
                    self.out.extend_from_slice(&v.to_le_bytes());
                } else {
                    self.out.extend_from_slice(&v.to_be_bytes());
                }
            } else if a.little_endian {
                self.out.extend_from_slice(&l.to_le_bytes());
            } else {
                self.out.extend_from_slice(&l.to_be_bytes());
            }
        }
        Ok(())
    }

    /// Appends raw text.
    pub fn text(&mut self, s: &str) {
        self.out.extend_from_slice(s.as_bytes());
    }
}

/// The banner and `FoamFile` header of an ASCII file, as every file this crate writes starts:
/// the one writer of FoamFile headers. A crate that writes a file body by hand (CFDEM's
/// `basicIO` clouds, a `decomposeParDict`) starts the file with this.
pub fn ascii_header(class: &str, location: &str, object: &str) -> String {
    let mut w = Writer::new(Format::Ascii, Arch::default());
    w.header(&Header {
        format: Format::Ascii,
        arch: Arch::default(),
        class: class.to_owned(),
        object: object.to_owned(),
        location: location.to_owned(),
        note: None,
    });
    String::from_utf8(w.into_bytes()).expect("a FoamFile header is UTF-8 when its words are")
}

/// Serialises a whole dictionary file (header + body).
pub fn dict_file_bytes(header: &Header, body: &Dict) -> Result<Vec<u8>, String> {
    let mut w = Writer::new(header.format, header.arch);
    w.header(header);
    w.dict_body(body, 0)?;
    w.text("\n// ************************************************************************* //\n");
    Ok(w.into_bytes())
}

/// Appends `values` as ASCII list elements of `comps` components each (one per line; several
/// components in parentheses), Rust's shortest round-trip form of each number. Long lists are
/// formatted in pieces on the thread pool and appended in order: the same bytes.
fn ascii_values(out: &mut Vec<u8>, values: &[f64], comps: usize) {
    use rayon::prelude::*;
    /// Elements per piece; shorter lists are formatted in one piece.
    const PIECE: usize = 16_384;
    let piece = |values: &[f64]| {
        let mut out = Vec::with_capacity(values.len() * 24);
        for c in values.chunks_exact(comps) {
            if comps == 1 {
                writeln!(out, "{:?}", c[0]).unwrap();
                continue;
            }
            out.push(b'(');
            for (k, x) in c.iter().enumerate() {
                if k > 0 {
                    out.push(b' ');
                }
                write!(out, "{x:?}").unwrap();
            }
            out.extend_from_slice(b")\n");
        }
        out
    };
    if values.len() <= PIECE * comps {
        out.extend_from_slice(&piece(values));
        return;
    }
    let pieces: Vec<Vec<u8>> = values.par_chunks(PIECE * comps).map(piece).collect();
    for p in pieces {
        out.extend_from_slice(&p);
    }
}

/// Writes a dictionary file atomically.
pub fn write_dict_file(path: &Path, header: &Header, body: &Dict) -> Result<()> {
    let bytes = dict_file_bytes(header, body).map_err(|m| FoamError::invalid(path, m))?;
    write_atomic(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename
/// (`atomic_write`), so that readers never see a partial file. Creates missing directories
/// (a new time directory, say).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| FoamError::io(dir, e))?;
    atomic_write::write_atomically(path, |w| w.write_all(bytes)).map_err(|e| FoamError::io(path, e))
}

#[cfg(test)]
mod tests {
    /// Long lists, formatted in pieces on several threads, are the bytes of one sequential
    /// pass: each number's `{:?}` form, one element per line, vectors in parentheses.
    #[test]
    fn long_ascii_lists_are_the_bytes_of_one_pass() {
        let values: Vec<f64> = (0..3 * 40_001)
            .map(|i| ((i * 7919) % 10_007) as f64 * 1.37e-3 - 5.0)
            .collect();
        for comps in [1, 3] {
            let mut want = String::new();
            for c in values.chunks_exact(comps) {
                let parts: Vec<String> = c.iter().map(|x| format!("{x:?}")).collect();
                if comps == 1 {
                    want += &format!("{}\n", parts[0]);
                } else {
                    want += &format!("({})\n", parts.join(" "));
                }
            }
            let got = rayon::ThreadPoolBuilder::new()
                .num_threads(3)
                .build()
                .unwrap()
                .install(|| {
                    let mut out = b"x".to_vec();
                    super::ascii_values(&mut out, &values, comps);
                    out
                });
            assert_eq!(got[0], b'x');
            assert!(got[1..] == *want.as_bytes(), "{comps} components");
        }
    }
}
