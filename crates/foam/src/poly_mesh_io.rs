//! Reading and writing `constant/polyMesh` (`points`, `faces`, `owner`, `neighbour`,
//! `boundary`), ASCII or binary, as OpenFOAM v1912 lays them out. Binary `faces` are a
//! `faceCompactList` (offsets list, then labels list); ASCII `faces` a `faceList` of `n(…)`.

use crate::dict::{Item, Value};
use crate::error::{FoamError, Location, Result};
use crate::parser::{read_bytes, Elem, Format, Header, Parser};
use crate::poly_mesh::{FaceList, Label, Patch, PolyMesh};
use crate::writer::{write_atomic, Writer};
use crate::Arch;
use std::path::{Path, PathBuf};

/// A file of `constant/polyMesh` opened for reading, header parsed.
struct MeshFile {
    path: PathBuf,
    bytes: Vec<u8>,
}

impl MeshFile {
    fn open(dir: &Path, name: &str) -> Result<MeshFile> {
        let (path, bytes) = read_bytes(&dir.join(name))?;
        Ok(MeshFile { path, bytes })
    }

    fn parser(&self) -> Result<(Parser<'_>, Header)> {
        let mut p = Parser::new(&self.bytes, &self.path, 0);
        let h = p.parse_header()?.ok_or_else(|| {
            p.lex
                .error_at(Location { line: 1, byte: 0 }, "missing FoamFile header")
        })?;
        Ok((p, h))
    }
}

fn to_label(v: i64, p: &Parser, what: &str, i: usize) -> Result<Label> {
    Label::try_from(v).map_err(|_| {
        p.lex
            .error(format!("{what} {i}: label {v} is negative or too large"))
    })
}

fn labels_u32(values: Vec<i64>, p: &Parser, what: &str) -> Result<Vec<Label>> {
    values
        .into_iter()
        .enumerate()
        .map(|(i, v)| to_label(v, p, what, i))
        .collect()
}

fn expect_end(p: &mut Parser) -> Result<()> {
    let (t, at) = p.lex.next_located()?;
    if t != crate::lexer::Tok::Eof {
        return Err(p
            .lex
            .error_at(at, format!("unexpected {} after the list", t.describe())));
    }
    Ok(())
}

/// Reads `points`.
pub fn read_points(dir: &Path) -> Result<Vec<[f64; 3]>> {
    let f = MeshFile::open(dir, "points")?;
    let (mut p, _) = f.parser()?;
    let mut values = Vec::new();
    p.read_typed(Elem::Vector, &mut Vec::new(), &mut values)?;
    expect_end(&mut p)?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(FoamError::invalid(
            &f.path,
            format!("point {} is not finite", i / 3),
        ));
    }
    Ok(values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Reads a `labelList` file (`owner`, `neighbour`); returns the labels and the header.
pub fn read_label_list(dir: &Path, name: &str) -> Result<(Vec<Label>, Header)> {
    read_label_file(dir, name, false)
}

/// Reads `neighbour`. Some meshes list a neighbour for every face, with -1 for boundary faces;
/// as OpenFOAM does, the internal faces are those before the first -1, and every later entry
/// must be -1.
pub fn read_neighbour(dir: &Path) -> Result<Vec<Label>> {
    Ok(read_label_file(dir, "neighbour", true)?.0)
}

/// A `labelList` file as labels; with `minus_one_tail`, a tail of -1 entries is cut off.
fn read_label_file(dir: &Path, name: &str, minus_one_tail: bool) -> Result<(Vec<Label>, Header)> {
    let f = MeshFile::open(dir, name)?;
    let (mut p, h) = f.parser()?;
    let mut labels = Vec::new();
    p.read_typed(Elem::Label, &mut labels, &mut Vec::new())?;
    expect_end(&mut p)?;
    if minus_one_tail {
        let internal = labels.iter().position(|&l| l < 0).unwrap_or(labels.len());
        if let Some(k) = labels[internal..].iter().position(|&l| l != -1) {
            return Err(FoamError::invalid(
                &f.path,
                format!(
                    "{name} {}: label {} after the first -1 (at {internal}); only -1 may follow",
                    internal + k,
                    labels[internal + k]
                ),
            ));
        }
        labels.truncate(internal);
    }
    Ok((labels_u32(labels, &p, name)?, h))
}

/// Reads `faces` (`faceList` or `faceCompactList`).
pub fn read_faces(dir: &Path) -> Result<FaceList> {
    let f = MeshFile::open(dir, "faces")?;
    let (mut p, h) = f.parser()?;
    let faces = if h.class == "faceCompactList" {
        let mut offsets = Vec::new();
        p.read_typed(Elem::Label, &mut offsets, &mut Vec::new())?;
        let offsets = labels_u32(offsets, &p, "face offset")?;
        let mut labels = Vec::new();
        p.read_typed(Elem::Label, &mut labels, &mut Vec::new())?;
        let labels = labels_u32(labels, &p, "face point label")?;
        // An empty mesh writes an empty offsets list.
        let offsets = if offsets.is_empty() { vec![0] } else { offsets };
        FaceList::from_compact(offsets, labels).map_err(|m| FoamError::invalid(&f.path, m))?
    } else {
        read_face_list(&mut p)?
    };
    expect_end(&mut p)?;
    Ok(faces)
}

/// ASCII `faceList`: `N ( k(a b c …) … )`.
fn read_face_list(p: &mut Parser) -> Result<FaceList> {
    use crate::lexer::Tok;
    let (t, at) = p.lex.next_located()?;
    let n = match t {
        Tok::Label(n) => p.count(n, at)?,
        other => {
            return Err(p.lex.error_at(
                at,
                format!("expected the number of faces, found {}", other.describe()),
            ))
        }
    };
    p.lex.expect_punct(b'(', "to open the face list")?;
    let mut faces = FaceList::with_capacity(n, 4 * n);
    let mut scratch = Vec::with_capacity(16);
    for i in 0..n {
        scratch.clear();
        let at = p.lex.here();
        if p.lex.peek()? == &Tok::Punct(b')') {
            return Err(p
                .lex
                .error_at(at, format!("face list declares {n} faces but holds {i}")));
        }
        p.read_typed(Elem::Label, &mut scratch, &mut Vec::new())
            .map_err(|e| match e {
                FoamError::Parse { path, at, msg } => FoamError::Parse {
                    path,
                    at,
                    msg: format!("face {i}: {msg}"),
                },
                e => e,
            })?;
        let mut face = Vec::with_capacity(scratch.len());
        for &v in &scratch {
            face.push(to_label(v, p, "face", i)?);
        }
        faces.push(&face);
    }
    let (t, at) = p.lex.next_located()?;
    if t != Tok::Punct(b')') {
        return Err(p.lex.error_at(
            at,
            format!(
                "face list declares {n} faces but continues with {}",
                t.describe()
            ),
        ));
    }
    Ok(faces)
}

/// Reads `boundary`.
pub fn read_boundary(dir: &Path) -> Result<Vec<Patch>> {
    let f = MeshFile::open(dir, "boundary")?;
    let (mut p, _) = f.parser()?;
    let mut items = Vec::new();
    let mut scopes = vec![crate::Dict::new()];
    while p.lex.peek()? != &crate::lexer::Tok::Eof {
        let (t, at) = p.lex.next_located()?;
        p.parse_item(t, at, &mut scopes, &mut items)?;
    }
    let list = match items.as_slice() {
        [Item::List(l)] => l,
        [Item::Label(n), Item::List(l)] if *n as usize == l.len() => l,
        [Item::Label(n), Item::List(l)] => {
            return Err(FoamError::invalid(
                &f.path,
                format!("the patch list declares {n} patches but holds {}", l.len()),
            ))
        }
        _ => return Err(FoamError::invalid(&f.path, "expected one list of patches")),
    };
    let mut patches = Vec::with_capacity(list.len());
    for (i, it) in list.iter().enumerate() {
        let Item::Named(name, d) = it else {
            return Err(FoamError::invalid(
                &f.path,
                format!("patch {i} is a {}, expected `name {{ … }}`", it.kind()),
            ));
        };
        let bad = |m: crate::LookupError| FoamError::invalid(&f.path, format!("patch {name}: {m}"));
        let count = |k: &str| -> Result<usize> {
            let v = d.label(k).map_err(bad)?;
            usize::try_from(v).map_err(|_| {
                FoamError::invalid(&f.path, format!("patch {name}: {k} {v} is negative"))
            })
        };
        let mut extra = Vec::new();
        for e in d.entries() {
            if matches!(e.keyword.as_str(), "type" | "nFaces" | "startFace") {
                continue;
            }
            let mut w = Writer::new(Format::Ascii, Arch::default());
            match &e.value {
                Value::Stream(s) => w.items(s, 0),
                Value::Dict(sub) => w.item(&Item::Dict(sub.clone()), 0),
            }
            .map_err(|m| FoamError::invalid(&f.path, m))?;
            extra.push((
                e.keyword.clone(),
                String::from_utf8_lossy(&w.into_bytes()).trim().to_string(),
            ));
        }
        patches.push(Patch {
            name: name.clone(),
            patch_type: d.word("type").map_err(bad)?.to_string(),
            n_faces: count("nFaces")?,
            start_face: count("startFace")?,
            extra,
        });
    }
    Ok(patches)
}

/// Reads a whole polyMesh directory (e.g. `case/constant/polyMesh` or
/// `case/processor0/constant/polyMesh`) and checks its structure.
pub fn read_poly_mesh(dir: &Path) -> Result<PolyMesh> {
    // The four files side by side on the thread pool; an error is the first file's in this
    // order, as when they were read one after another.
    let ((points, faces), (owner, neighbour)) = rayon::join(
        || rayon::join(|| read_points(dir), || read_faces(dir)),
        || rayon::join(|| read_label_list(dir, "owner"), || read_neighbour(dir)),
    );
    let (points, faces) = (points?, faces?);
    let ((owner, oh), neighbour) = (owner?, neighbour?);
    let boundary = read_boundary(dir)?;
    let counted = PolyMesh::count_cells(&owner, &neighbour);
    let n_cells = oh
        .note
        .as_deref()
        .and_then(|n| note_value(n, "nCells"))
        .unwrap_or(counted);
    if n_cells < counted {
        return Err(FoamError::invalid(
            dir.join("owner"),
            format!(
                "note says nCells:{n_cells} but owner/neighbour name cell {}",
                counted - 1
            ),
        ));
    }
    let mesh = PolyMesh {
        points,
        faces,
        owner,
        neighbour,
        boundary,
        n_cells,
    };
    mesh.check().map_err(|e| FoamError::invalid(dir, e.0))?;
    Ok(mesh)
}

/// Extracts `key:value` from an owner note such as `nPoints:8 nCells:1 …`.
fn note_value(note: &str, key: &str) -> Option<usize> {
    note.split_whitespace()
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix(':')?.parse().ok())
}

fn mesh_header(format: Format, class: &str, object: &str, note: Option<String>) -> Header {
    Header {
        format,
        arch: Arch::default(),
        class: class.into(),
        object: object.into(),
        location: "constant/polyMesh".into(),
        note,
    }
}

fn write_list_file(
    dir: &Path,
    header: Header,
    body: impl FnOnce(&mut Writer) -> Result<(), String>,
) -> Result<()> {
    let path = dir.join(&header.object);
    let mut w = Writer::new(header.format, header.arch);
    w.header(&header);
    body(&mut w).map_err(|m| FoamError::invalid(&path, m))?;
    w.text("\n\n// ************************************************************************* //\n");
    write_atomic(&path, &w.into_bytes())
}

fn labels_i64(l: &[Label]) -> Item {
    Item::Labels(l.iter().map(|&x| i64::from(x)).collect())
}

/// Writes a polyMesh directory (creating it), ASCII or binary, each file atomically.
pub fn write_poly_mesh(dir: &Path, mesh: &PolyMesh, format: Format) -> Result<()> {
    let note = format!(
        "nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}",
        mesh.n_points(),
        mesh.n_cells,
        mesh.n_faces(),
        mesh.n_internal_faces()
    );
    write_list_file(
        dir,
        mesh_header(format, "vectorField", "points", None),
        |w| w.item(&Item::Vectors(mesh.points.clone()), 0),
    )?;
    match format {
        Format::Binary => write_list_file(
            dir,
            mesh_header(format, "faceCompactList", "faces", None),
            |w| {
                w.item(&labels_i64(mesh.faces.offsets()), 0)?;
                w.item(&labels_i64(mesh.faces.labels()), 0)
            },
        )?,
        Format::Ascii => {
            write_list_file(dir, mesh_header(format, "faceList", "faces", None), |w| {
                use std::fmt::Write;
                let mut s = String::with_capacity(mesh.faces.labels().len() * 8);
                write!(s, "\n{}\n(\n", mesh.faces.len()).unwrap();
                for f in mesh.faces.iter() {
                    write!(s, "{}(", f.len()).unwrap();
                    for (k, p) in f.iter().enumerate() {
                        if k > 0 {
                            s.push(' ');
                        }
                        write!(s, "{p}").unwrap();
                    }
                    s.push_str(")\n");
                }
                s.push(')');
                w.text(&s);
                Ok(())
            })?
        }
    }
    write_list_file(
        dir,
        mesh_header(format, "labelList", "owner", Some(note.clone())),
        |w| w.item(&labels_i64(&mesh.owner), 0),
    )?;
    write_list_file(
        dir,
        mesh_header(format, "labelList", "neighbour", Some(note)),
        |w| w.item(&labels_i64(&mesh.neighbour), 0),
    )?;
    write_list_file(
        dir,
        mesh_header(Format::Ascii, "polyBoundaryMesh", "boundary", None),
        |w| {
            use std::fmt::Write;
            let mut s = String::new();
            write!(s, "\n{}\n(\n", mesh.boundary.len()).unwrap();
            for p in &mesh.boundary {
                write!(s, "    {}\n    {{\n", p.name).unwrap();
                writeln!(s, "        {:<15} {};", "type", p.patch_type).unwrap();
                for (k, v) in &p.extra {
                    writeln!(s, "        {k:<15} {v};").unwrap();
                }
                writeln!(s, "        {:<15} {};", "nFaces", p.n_faces).unwrap();
                writeln!(s, "        {:<15} {};", "startFace", p.start_face).unwrap();
                s.push_str("    }\n");
            }
            s.push(')');
            w.text(&s);
            Ok(())
        },
    )
}
