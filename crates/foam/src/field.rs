//! `volScalarField` and `volVectorField` files: read, modify the internal field, write back
//! (ASCII or binary) with every other entry — `dimensions`, `boundaryField`, extra keywords —
//! preserved as read.

use crate::dict::{Dict, Item, Value};
use crate::error::{FoamError, Result};
use crate::parser::{parse_file, Format, Header};
use crate::poly_mesh::Patch;
use crate::writer::write_dict_file;
use crate::Arch;
use std::path::Path;

/// Whether a field holds scalars or vectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    /// `volScalarField`.
    Scalar,
    /// `volVectorField`.
    Vector,
}

impl FieldKind {
    /// The OpenFOAM class name.
    pub fn class(self) -> &'static str {
        match self {
            FieldKind::Scalar => "volScalarField",
            FieldKind::Vector => "volVectorField",
        }
    }

    fn list_word(self) -> &'static str {
        match self {
            FieldKind::Scalar => "List<scalar>",
            FieldKind::Vector => "List<vector>",
        }
    }
}

/// Cell values of a field.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldValues {
    /// One scalar per cell.
    Scalar(Vec<f64>),
    /// One vector per cell.
    Vector(Vec<[f64; 3]>),
}

impl FieldValues {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            FieldValues::Scalar(v) => v.len(),
            FieldValues::Vector(v) => v.len(),
        }
    }

    /// True when there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The kind of the values.
    pub fn kind(&self) -> FieldKind {
        match self {
            FieldValues::Scalar(_) => FieldKind::Scalar,
            FieldValues::Vector(_) => FieldKind::Vector,
        }
    }
}

/// A volume field file: header and body (`dimensions`, `internalField`, `boundaryField`, …).
#[derive(Clone, Debug, PartialEq)]
pub struct VolField {
    /// The header as read (format, class, object, location).
    pub header: Header,
    /// Every entry of the file in order.
    pub body: Dict,
}

impl VolField {
    /// Reads a field file. Its class must be `volScalarField` or `volVectorField`.
    pub fn read(path: &Path) -> Result<VolField> {
        let f = parse_file(path)?;
        let header = f
            .header
            .ok_or_else(|| FoamError::invalid(path, "missing FoamFile header"))?;
        let field = VolField {
            header,
            body: f.body,
        };
        field.kind().map_err(|m| FoamError::invalid(path, m))?;
        for key in ["internalField", "boundaryField"] {
            if !field.body.contains(key) {
                return Err(FoamError::invalid(path, format!("missing entry `{key}`")));
            }
        }
        Ok(field)
    }

    /// A new field with `dimensions` (the 7 SI exponents), cell values and a boundaryField.
    pub fn new(
        name: &str,
        location: &str,
        dimensions: [i32; 7],
        values: FieldValues,
        boundary: Dict,
    ) -> VolField {
        let kind = values.kind();
        let mut body = Dict::new();
        body.set_item(
            "dimensions",
            Item::Dims(dimensions.iter().map(|&d| Item::Label(d.into())).collect()),
        );
        body.set("internalField", Value::Stream(Vec::new()));
        body.set("boundaryField", Value::Dict(boundary));
        let mut f = VolField {
            header: Header {
                format: Format::Ascii,
                arch: Arch::default(),
                class: kind.class().into(),
                object: name.into(),
                location: location.into(),
                note: None,
            },
            body,
        };
        f.set_internal(values)
            .expect("kind matches by construction");
        f
    }

    /// Scalar or vector, from the header's class.
    pub fn kind(&self) -> Result<FieldKind, String> {
        match self.header.class.as_str() {
            "volScalarField" => Ok(FieldKind::Scalar),
            "volVectorField" => Ok(FieldKind::Vector),
            c => Err(format!(
                "class `{c}` is not supported (volScalarField or volVectorField)"
            )),
        }
    }

    /// The cell values, expanding `uniform` to `n_cells` values; a nonuniform list of another
    /// length is an error.
    pub fn internal(&self, n_cells: usize) -> Result<FieldValues, String> {
        let kind = self.kind()?;
        let s = self
            .body
            .stream("internalField")
            .map_err(|e| e.to_string())?;
        let bad = |what: &str| Err(format!("internalField: {what}"));
        match (s.first().and_then(Item::as_word), kind) {
            (Some("uniform"), FieldKind::Scalar) => match s.get(1).and_then(Item::as_f64) {
                Some(v) if s.len() == 2 => Ok(FieldValues::Scalar(vec![v; n_cells])),
                _ => bad("`uniform` needs one number for a volScalarField"),
            },
            (Some("uniform"), FieldKind::Vector) => match s.get(1).and_then(Item::as_vector) {
                Some(v) if s.len() == 2 => Ok(FieldValues::Vector(vec![v; n_cells])),
                _ => bad("`uniform` needs a vector (x y z) for a volVectorField"),
            },
            (Some("nonuniform"), _) => {
                let values = match (s.get(2), kind) {
                    (Some(Item::Scalars(v)), FieldKind::Scalar) => FieldValues::Scalar(v.clone()),
                    (Some(Item::Vectors(v)), FieldKind::Vector) => FieldValues::Vector(v.clone()),
                    (Some(Item::List(l)), FieldKind::Scalar) if l.is_empty() => {
                        FieldValues::Scalar(Vec::new())
                    }
                    _ => {
                        return bad(&format!(
                            "`nonuniform` needs `{} N(…)` for a {}",
                            kind.list_word(),
                            kind.class()
                        ))
                    }
                };
                if values.len() != n_cells {
                    return bad(&format!(
                        "has {} values but the mesh has {n_cells} cells",
                        values.len()
                    ));
                }
                Ok(values)
            }
            _ => bad("expected `uniform` or `nonuniform`"),
        }
    }

    /// Replaces the cell values (always written `nonuniform`). The kind must match the class.
    pub fn set_internal(&mut self, values: FieldValues) -> Result<(), String> {
        let kind = self.kind()?;
        if values.kind() != kind {
            return Err(format!(
                "cannot put {:?} values into a {}",
                values.kind(),
                kind.class()
            ));
        }
        let list = match values {
            FieldValues::Scalar(v) => Item::Scalars(v),
            FieldValues::Vector(v) => Item::Vectors(v),
        };
        self.body.set(
            "internalField",
            Value::Stream(vec![
                Item::Word("nonuniform".into()),
                Item::Word(kind.list_word().into()),
                list,
            ]),
        );
        Ok(())
    }

    /// The `boundaryField` dictionary.
    pub fn boundary(&self) -> &Dict {
        self.body
            .opt_dict("boundaryField")
            .expect("checked on read")
    }

    /// Writes the field to `path` in `format` (atomically). The header's `object` becomes the
    /// file name and its `location` the directory name (the time, as OpenFOAM writes it).
    pub fn write(&self, path: &Path, format: Format) -> Result<()> {
        let mut h = self.header.clone();
        h.format = format;
        if let Some(name) = path.file_name() {
            h.object = name.to_string_lossy().into_owned();
        }
        if let Some(dir) = path.parent().and_then(Path::file_name) {
            h.location = dir.to_string_lossy().into_owned();
        }
        write_dict_file(path, &h, &self.body)
    }
}

/// A boundaryField for `patches` where every ordinary patch gets `default_type` (e.g.
/// `zeroGradient` or `calculated` with `value`), and constraint patches (`empty`, `wedge`,
/// `symmetryPlane`, `symmetry`, `cyclic`, `processor`, …) get their own type.
pub fn default_boundary(patches: &[Patch], default_type: &str, value: Option<Item>) -> Dict {
    let mut d = Dict::new();
    for p in patches {
        let mut e = Dict::new();
        let constraint = matches!(
            p.patch_type.as_str(),
            "empty"
                | "wedge"
                | "symmetryPlane"
                | "symmetry"
                | "cyclic"
                | "cyclicAMI"
                | "processor"
                | "processorCyclic"
        );
        if constraint {
            e.set_item("type", Item::Word(p.patch_type.clone()));
            if p.patch_type.starts_with("processor") {
                if let Some(v) = &value {
                    e.set(
                        "value",
                        Value::Stream(vec![Item::Word("uniform".into()), v.clone()]),
                    );
                }
            }
        } else {
            e.set_item("type", Item::Word(default_type.into()));
            if let Some(v) = &value {
                e.set(
                    "value",
                    Value::Stream(vec![Item::Word("uniform".into()), v.clone()]),
                );
            }
        }
        d.set(&p.name, Value::Dict(e));
    }
    d
}
