//! Reading a written field and comparing it with a reference file.
#![allow(dead_code)]

use foam::{FieldValues, VolField};
use std::path::Path;

/// The `n` cell values of a volScalarField file.
pub fn scalars(path: &Path, n: usize) -> Vec<f64> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Scalar(v) => v,
        FieldValues::Vector(_) => panic!("{}: scalar field expected", path.display()),
    }
}

/// The `n` cell values of a volVectorField file, components one after the other.
pub fn vectors(path: &Path, n: usize) -> Vec<f64> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Vector(v) => v.into_iter().flatten().collect(),
        FieldValues::Scalar(_) => panic!("{}: vector field expected", path.display()),
    }
}

/// max |a − b| / max |b|.
pub fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}
