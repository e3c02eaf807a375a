//! Data arrays and their encoding as `<DataArray>` XML elements.
//!
//! Binary arrays follow VTK's "inline binary" rule for `header_type="UInt64"` without
//! compression: one little-endian `u64` holding the number of data bytes, immediately followed by
//! the little-endian data, the whole base64-encoded as one stream.

use std::borrow::Cow;
use std::io::{self, Write};

use base64::engine::general_purpose::STANDARD;
use base64::write::EncoderWriter;

/// How array values are stored in the XML file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Inline base64 (`format="binary"`), exact and compact. The default.
    #[default]
    Binary,
    /// Human-readable text (`format="ascii"`), for debugging. Floats are written with Rust's
    /// shortest round-trip representation, so values survive exactly, but NaN and infinities
    /// are written as `NaN`/`inf`, which VTK's ASCII parser does not accept.
    Ascii,
}

/// The values of one named array: one tuple per point (or per cell).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Values<'a> {
    /// One `f64` per tuple (written as Float64).
    Scalar(&'a [f64]),
    /// Three `f64` per tuple (written as Float64, `NumberOfComponents="3"`).
    Vector(&'a [[f64; 3]]),
    /// One `i64` per tuple (written as Int64), e.g. particle ids.
    Int64(&'a [i64]),
    /// One `i32` per tuple (written as Int32), e.g. particle types.
    Int32(&'a [i32]),
}

/// A named array of point or cell data, borrowing its values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DataArray<'a> {
    /// Array name as ParaView shows it.
    pub name: &'a str,
    /// The values.
    pub values: Values<'a>,
}

impl<'a> DataArray<'a> {
    /// A scalar (one `f64` per tuple) array.
    pub fn scalar(name: &'a str, values: &'a [f64]) -> Self {
        Self {
            name,
            values: Values::Scalar(values),
        }
    }

    /// A 3-vector array.
    pub fn vector(name: &'a str, values: &'a [[f64; 3]]) -> Self {
        Self {
            name,
            values: Values::Vector(values),
        }
    }

    /// A 64-bit integer array.
    pub fn int64(name: &'a str, values: &'a [i64]) -> Self {
        Self {
            name,
            values: Values::Int64(values),
        }
    }

    /// A 32-bit integer array.
    pub fn int32(name: &'a str, values: &'a [i32]) -> Self {
        Self {
            name,
            values: Values::Int32(values),
        }
    }

    /// Number of tuples (points or cells covered).
    pub fn len(&self) -> usize {
        match self.values {
            Values::Scalar(v) => v.len(),
            Values::Vector(v) => v.len(),
            Values::Int64(v) => v.len(),
            Values::Int32(v) => v.len(),
        }
    }

    /// True when the array has no tuples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub(crate) fn write<W: Write>(&self, w: &mut W, enc: Encoding) -> io::Result<()> {
        match self.values {
            Values::Scalar(v) => write_array(w, self.name, v, 1, enc),
            Values::Vector(v) => write_array(w, self.name, v.as_flattened(), 3, enc),
            Values::Int64(v) => write_array(w, self.name, v, 1, enc),
            Values::Int32(v) => write_array(w, self.name, v, 1, enc),
        }
    }
}

/// A value type VTK knows by name.
pub(crate) trait Element: Copy {
    /// VTK's type name (`type="..."`).
    const VTK_TYPE: &'static str;
    /// Size in bytes.
    const SIZE: usize;
    /// Appends the little-endian bytes.
    fn extend_le(self, out: &mut Vec<u8>);
    /// Writes the ASCII form.
    fn write_ascii<W: Write>(self, w: &mut W) -> io::Result<()>;
}

macro_rules! element {
    ($t:ty, $name:literal, $fmt:literal) => {
        impl Element for $t {
            const VTK_TYPE: &'static str = $name;
            const SIZE: usize = std::mem::size_of::<$t>();
            fn extend_le(self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
            fn write_ascii<W: Write>(self, w: &mut W) -> io::Result<()> {
                write!(w, $fmt, self)
            }
        }
    };
}

element!(f64, "Float64", "{:?}");
element!(i64, "Int64", "{}");
element!(i32, "Int32", "{}");
element!(u8, "UInt8", "{}");

/// Bytes converted per chunk before they go to the base64 encoder.
const CHUNK_BYTES: usize = 1 << 16;

/// Writes one `<DataArray>` element (on its own lines, indented for a `Piece` child).
pub(crate) fn write_array<W: Write, T: Element>(
    w: &mut W,
    name: &str,
    values: &[T],
    components: usize,
    enc: Encoding,
) -> io::Result<()> {
    write!(
        w,
        "        <DataArray type=\"{}\" Name=\"{}\"",
        T::VTK_TYPE,
        escape_attr(name)
    )?;
    if components != 1 {
        write!(w, " NumberOfComponents=\"{components}\"")?;
    }
    match enc {
        Encoding::Binary => {
            w.write_all(b" format=\"binary\">\n          ")?;
            let mut b64 = EncoderWriter::new(&mut *w, &STANDARD);
            let bytes = (values.len() * T::SIZE) as u64;
            b64.write_all(&bytes.to_le_bytes())?;
            let mut buf = Vec::with_capacity(CHUNK_BYTES);
            for chunk in values.chunks(CHUNK_BYTES / T::SIZE) {
                buf.clear();
                for &v in chunk {
                    v.extend_le(&mut buf);
                }
                b64.write_all(&buf)?;
            }
            b64.finish()?;
        }
        Encoding::Ascii => {
            w.write_all(b" format=\"ascii\">")?;
            for (i, &v) in values.iter().enumerate() {
                w.write_all(if i % 6 == 0 { b"\n          " } else { b" " })?;
                v.write_ascii(w)?;
            }
        }
    }
    w.write_all(b"\n        </DataArray>\n")
}

/// Escapes text for use inside a double-quoted XML attribute.
pub(crate) fn escape_attr(s: &str) -> Cow<'_, str> {
    if !s.contains(['&', '<', '>', '"', '\'']) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::Engine;

    fn body(xml: &str) -> &str {
        let start = xml.find('>').unwrap() + 1;
        let end = xml.rfind("</DataArray>").unwrap();
        xml[start..end].trim()
    }

    #[test]
    fn binary_array_is_u64_byte_count_then_little_endian_data() {
        let mut out = Vec::new();
        DataArray::vector("U", &[[1.0, -2.5, 3.0], [4.0, 5.0, 1e-300]])
            .write(&mut out, Encoding::Binary)
            .unwrap();
        let xml = String::from_utf8(out).unwrap();
        assert!(xml.contains(r#"type="Float64" Name="U" NumberOfComponents="3" format="binary""#));
        let raw = STANDARD.decode(body(&xml)).unwrap();
        assert_eq!(raw.len(), 8 + 6 * 8);
        assert_eq!(u64::from_le_bytes(raw[..8].try_into().unwrap()), 48);
        let vals: Vec<f64> = raw[8..]
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(vals, [1.0, -2.5, 3.0, 4.0, 5.0, 1e-300]);
    }

    #[test]
    fn binary_array_spans_several_chunks() {
        let v: Vec<i32> = (0..(CHUNK_BYTES as i32)).map(|i| i * 7 - 3).collect();
        let mut out = Vec::new();
        DataArray::int32("type", &v)
            .write(&mut out, Encoding::Binary)
            .unwrap();
        let xml = String::from_utf8(out).unwrap();
        let raw = STANDARD.decode(body(&xml)).unwrap();
        assert_eq!(
            u64::from_le_bytes(raw[..8].try_into().unwrap()),
            4 * v.len() as u64
        );
        let back: Vec<i32> = raw[8..]
            .chunks(4)
            .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(back, v);
    }

    #[test]
    fn ascii_array_round_trips_floats_exactly() {
        let v = [0.1, 1.0 / 3.0, -7e-12, 6.02e23, 0.0];
        let mut out = Vec::new();
        DataArray::scalar("p", &v)
            .write(&mut out, Encoding::Ascii)
            .unwrap();
        let xml = String::from_utf8(out).unwrap();
        assert!(xml.contains(r#"format="ascii""#));
        let back: Vec<f64> = body(&xml)
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(back, v);
    }

    #[test]
    fn names_are_escaped() {
        assert_eq!(escape_attr("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&apos;");
        assert!(matches!(escape_attr("alpha.water"), Cow::Borrowed(_)));
    }
}
