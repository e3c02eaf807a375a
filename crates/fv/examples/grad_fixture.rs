//! Writes the smooth test fields `0/p` (volScalarField) and `0/U` (volVectorField) of
//! `tests/fixtures/fv/grad/README.md` into a case, with `fixedValue` boundary values at the face
//! centres, so that OpenFOAM's `postProcess -func "grad(p)"` can be compared with `fv::fvc`.
//!
//! `cargo run -p fv --example grad_fixture -- CASE`

use foam::{Case, Dict, FieldValues, Item, Value, VolField};
use fv::FvGeometry;
use mesh::v3::V3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).ok_or("usage: grad_fixture CASE")?;
    let case = Case::open(&dir)?;
    let mesh = case.read_mesh()?;
    let g = FvGeometry::new(&mesh)?;
    let scale = fv::testfields::length_scale(&g);
    let p = |x: V3| fv::testfields::smooth_scalar(x, scale);
    let u = |x: V3| -> [f64; 3] { fv::testfields::smooth_vector(x, scale).into() };
    let mut bp = Dict::new();
    let mut bu = Dict::new();
    for patch in &g.patches {
        let mut ep = Dict::new();
        let mut eu = Dict::new();
        if patch.is_empty() {
            ep.set_item("type", Item::Word("empty".into()));
            eu.set_item("type", Item::Word("empty".into()));
        } else {
            let cf = &g.cf[patch.faces.clone()];
            ep.set_item("type", Item::Word("fixedValue".into()));
            ep.set(
                "value",
                nonuniform("scalar", Item::Scalars(cf.iter().map(|&x| p(x)).collect())),
            );
            eu.set_item("type", Item::Word("fixedValue".into()));
            eu.set(
                "value",
                nonuniform("vector", Item::Vectors(cf.iter().map(|&x| u(x)).collect())),
            );
        }
        bp.set(&patch.name, Value::Dict(ep));
        bu.set(&patch.name, Value::Dict(eu));
    }
    let cells_p = FieldValues::Scalar(g.c.iter().map(|&x| p(x)).collect());
    let cells_u = FieldValues::Vector(g.c.iter().map(|&x| u(x)).collect());
    let time = case.time_path("0");
    std::fs::create_dir_all(&time)?;
    VolField::new("p", "0", [0, 2, -2, 0, 0, 0, 0], cells_p, bp)
        .write(&time.join("p"), foam::Format::Ascii)?;
    VolField::new("U", "0", [0, 1, -1, 0, 0, 0, 0], cells_u, bu)
        .write(&time.join("U"), foam::Format::Ascii)?;
    Ok(())
}

fn nonuniform(kind: &str, list: Item) -> Value {
    Value::Stream(vec![
        Item::Word("nonuniform".into()),
        Item::Word(format!("List<{kind}>")),
        list,
    ])
}
