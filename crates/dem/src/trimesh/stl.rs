//! STL files, ASCII and binary: the triangles `fix mesh/surface file FILE.stl` reads.
//!
//! Binary: an 80-byte header, a little-endian `u32` triangle count, then 50 bytes per
//! triangle (normal, three vertices as `f32` triples, a `u16` attribute). ASCII: `solid`,
//! then `facet normal …` / `outer loop` / three `vertex x y z` / `endloop` / `endfacet`
//! blocks, `endsolid`; several solids may follow one another. A file is binary when its size
//! is exactly 84 + 50·count (many binary files also begin with the word `solid`, so the first
//! word does not decide). The stored facet normals are ignored, as LIGGGHTS ignores them: the
//! normal of a triangle follows from its vertices.
//!
//! Errors name the file, and for ASCII the 1-based line.

use std::path::Path;

use mesh::v3::V3;

use crate::error::DemError;

/// Triangles read from a file, with where each came from.
#[derive(Debug, Clone, PartialEq)]
pub struct StlTriangles {
    /// Vertices (the file's units; `fix mesh/surface … scale` converts).
    pub triangles: Vec<[V3; 3]>,
    /// Per triangle: the 1-based line of its `facet` (ASCII) or its 1-based index (binary).
    pub origin: Vec<usize>,
    /// Whether the file was binary.
    pub binary: bool,
}

/// Reads an ASCII or binary STL file.
pub fn read_stl(path: &Path) -> Result<StlTriangles, DemError> {
    let bytes = std::fs::read(path).map_err(|e| DemError::Stl {
        file: path.to_path_buf(),
        line: None,
        message: format!("cannot read: {e}"),
    })?;
    parse_stl(&bytes, path)
}

/// Parses the bytes of an STL file (`path` only names it in errors).
pub fn parse_stl(bytes: &[u8], path: &Path) -> Result<StlTriangles, DemError> {
    let err = |line: Option<usize>, message: String| DemError::Stl {
        file: path.to_path_buf(),
        line,
        message,
    };
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() as u64 == 84 + 50 * n as u64 {
            return Ok(parse_binary(bytes, n));
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|_| {
        let detail = if bytes.len() >= 84 {
            let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
            format!(
                "; read as binary it would declare {n} triangles, {} bytes, but has {}",
                84 + 50 * n,
                bytes.len()
            )
        } else {
            format!(" ({} bytes, shorter than a binary header)", bytes.len())
        };
        err(
            None,
            format!("neither ASCII STL (not UTF-8 text) nor binary STL{detail}"),
        )
    })?;
    parse_ascii(text).map_err(|(line, message)| err(line, message))
}

fn parse_binary(bytes: &[u8], n: usize) -> StlTriangles {
    let f =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let mut triangles = Vec::with_capacity(n);
    for t in 0..n {
        let base = 84 + 50 * t + 12;
        let v = |k: usize| {
            let at = base + 12 * k;
            V3::new(f(at) as f64, f(at + 4) as f64, f(at + 8) as f64)
        };
        triangles.push([v(0), v(1), v(2)]);
    }
    StlTriangles {
        triangles,
        origin: (1..=n).collect(),
        binary: true,
    }
}

/// What the ASCII parser expects next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Expect {
    Solid,
    FacetOrEnd,
    OuterLoop,
    Vertex(usize),
    EndLoop,
    EndFacet,
}

fn parse_ascii(text: &str) -> Result<StlTriangles, (Option<usize>, String)> {
    let mut triangles = Vec::new();
    let mut origin = Vec::new();
    let mut state = Expect::Solid;
    let mut tri = [V3::zeros(); 3];
    let mut facet_line = 0;
    let mut last = 0;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let mut words = raw.split_whitespace();
        let Some(first) = words.next() else { continue };
        last = line;
        let bad = |what: &str| {
            Err((
                Some(line),
                format!("expected {what}, found `{}`", raw.trim()),
            ))
        };
        match (state, first) {
            (Expect::Solid, "solid") => state = Expect::FacetOrEnd,
            (Expect::Solid, _) => return bad("`solid`"),
            (Expect::FacetOrEnd, "facet") => {
                facet_line = line;
                state = Expect::OuterLoop;
            }
            (Expect::FacetOrEnd, "endsolid") => state = Expect::Solid,
            (Expect::FacetOrEnd, _) => return bad("`facet` or `endsolid`"),
            (Expect::OuterLoop, "outer") if words.next() == Some("loop") => {
                state = Expect::Vertex(0)
            }
            (Expect::OuterLoop, _) => return bad("`outer loop`"),
            (Expect::Vertex(j), "vertex") => {
                let c: Vec<&str> = words.collect();
                let xyz: Option<Vec<f64>> = c
                    .iter()
                    .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
                    .collect();
                match xyz {
                    Some(v) if v.len() == 3 => tri[j] = V3::new(v[0], v[1], v[2]),
                    _ => return bad("`vertex x y z` with three finite numbers"),
                }
                state = if j == 2 {
                    Expect::EndLoop
                } else {
                    Expect::Vertex(j + 1)
                };
            }
            (Expect::Vertex(j), _) => return bad(&format!("vertex {} of 3", j + 1)),
            (Expect::EndLoop, "endloop") => state = Expect::EndFacet,
            (Expect::EndLoop, _) => return bad("`endloop` (a facet has three vertices)"),
            (Expect::EndFacet, "endfacet") => {
                triangles.push(tri);
                origin.push(facet_line);
                state = Expect::FacetOrEnd;
            }
            (Expect::EndFacet, _) => return bad("`endfacet`"),
        }
    }
    match state {
        Expect::Solid if !triangles.is_empty() || last > 0 => {}
        Expect::Solid => return Err((None, "empty file (no `solid`)".into())),
        // a missing final `endsolid` is tolerated (LIGGGHTS's reader stops at the end)
        Expect::FacetOrEnd => {}
        _ => {
            return Err((
                Some(last),
                "the file ends inside a facet (truncated?)".into(),
            ))
        }
    }
    if triangles.is_empty() {
        return Err((None, "no facets".into()));
    }
    Ok(StlTriangles {
        triangles,
        origin,
        binary: false,
    })
}

/// Writes triangles as ASCII STL text (facet normals from the vertex order), for tests and
/// generated geometries.
pub fn ascii_stl(name: &str, triangles: &[[V3; 3]]) -> String {
    use std::fmt::Write;
    let mut s = format!("solid {name}\n");
    for t in triangles {
        let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
        let n = if n.norm() > 0.0 { n / n.norm() } else { n };
        let _ = writeln!(
            s,
            "  facet normal {:e} {:e} {:e}\n    outer loop",
            n[0], n[1], n[2]
        );
        for v in t {
            let _ = writeln!(s, "      vertex {:e} {:e} {:e}", v[0], v[1], v[2]);
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    let _ = writeln!(s, "endsolid {name}");
    s
}

/// Binary STL bytes of the triangles (vertices rounded to `f32`), for tests.
pub fn binary_stl(triangles: &[[V3; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        b.extend_from_slice(&[0u8; 12]);
        for v in t {
            for k in 0..3 {
                b.extend_from_slice(&(v[k] as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<[V3; 3]> {
        let p = |x, y| V3::new(x, y, 0.5);
        vec![
            [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)],
            [p(0.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
        ]
    }

    #[test]
    fn ascii_and_binary_round_trip() {
        let path = Path::new("sq.stl");
        let a = parse_stl(ascii_stl("sq", &square()).as_bytes(), path).unwrap();
        assert_eq!(a.triangles, square());
        assert_eq!(a.origin, vec![2, 9]);
        assert!(!a.binary);
        let b = parse_stl(&binary_stl(&square()), path).unwrap();
        assert_eq!(b.triangles, square());
        assert!(b.binary);
        // a binary file whose header starts with `solid` is still binary
        let mut bytes = binary_stl(&square());
        bytes[..5].copy_from_slice(b"solid");
        assert_eq!(parse_stl(&bytes, path).unwrap().triangles, square());
    }

    #[test]
    fn errors_name_file_and_line() {
        let path = Path::new("dir/bad.stl");
        let text = ascii_stl("sq", &square()).replace("vertex 1e0 0e0 5e-1", "vertex 1 zero 0.5");
        let e = parse_stl(text.as_bytes(), path).unwrap_err().to_string();
        assert!(
            e.starts_with("dir/bad.stl:5: expected `vertex x y z`"),
            "{e}"
        );
        let mut text = ascii_stl("sq", &square());
        text.truncate(text.find("endloop").unwrap());
        let e = parse_stl(text.as_bytes(), path).unwrap_err().to_string();
        assert!(e.contains("bad.stl:6: the file ends inside a facet"), "{e}");
        // a binary file cut short
        let mut bytes = binary_stl(&square());
        bytes.truncate(120);
        let e = parse_stl(&bytes, path).unwrap_err().to_string();
        assert!(
            e.contains("declare 2 triangles, 184 bytes, but has 120"),
            "{e}"
        );
        let e = parse_stl(b"", path).unwrap_err().to_string();
        assert!(e.contains("empty file"), "{e}");
        let e = read_stl(Path::new("/nonexistent/x.stl"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("/nonexistent/x.stl: cannot read"), "{e}");
    }
}
