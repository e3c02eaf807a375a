//! Boundary conditions of the temperature T (K) and of the turbulent thermal diffusivity α_t
//! (m²/s, `alphat`), read from their files' `boundaryField` with OpenFOAM v1912's names, in the
//! value/gradient-coefficient form of [`crate::turbulence::scalar_bc`].
//!
//! T: `fixedValue`, `zeroGradient`, `fixedGradient` (`gradient` in K/m, along the outward
//! normal), `inletOutlet` (`inletValue` where the flux enters, zero gradient where it leaves),
//! `empty`, `symmetryPlane`/`symmetry` (zero gradient), `cyclic`. α_t: `zeroGradient`,
//! `calculated` (ν_t/Prt of the face), `fixedValue`, `empty`, `symmetryPlane`/`symmetry`,
//! `cyclic`, and the wall functions `alphatJayatillekeWallFunction` and
//! `compressible::alphatWallFunction` only on patches where T is `zeroGradient`: there the
//! face's diffusivity multiplies a zero gradient and never reaches T, so the wall function's
//! value need not be computed (the face takes ν_t/Prt, which is what `alphat` is then written
//! with); where T has a value or a gradient it would set the wall heat flux, and the wall
//! functions are refused. Anything else is an error naming the file and
//! `boundaryField.<patch>.type`.

use crate::bc::read_all;
use crate::error::Result;
use crate::geometry::FvGeometry;
use crate::turbulence::scalar_bc::ScalarBc;
use foam::Item;
use std::path::Path;

const T_SUPPORTED: &str = "fixedValue, zeroGradient, fixedGradient, inletOutlet, empty, \
                           symmetryPlane, symmetry, cyclic";
const ALPHAT_SUPPORTED: &str = "zeroGradient, calculated, fixedValue, \
                                alphatJayatillekeWallFunction and \
                                compressible::alphatWallFunction where T is zeroGradient, \
                                empty, symmetryPlane, symmetry, cyclic";

/// Reads the conditions of T of every patch (the parsed file `field` at `file`).
pub(crate) fn read_temperature(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<ScalarBc>> {
    read_all(file, field, mesh, g, |e, t| {
        let bc = match t {
            "fixedValue" => {
                ScalarBc::FixedValue(e.values("value", Item::as_f64, Item::as_f64_list)?)
            }
            "zeroGradient" | "symmetryPlane" | "symmetry" => ScalarBc::ZeroGradient,
            "fixedGradient" => {
                let grad = e.values("gradient", Item::as_f64, Item::as_f64_list)?;
                let p = &g.patches[g.patch_index(&e.name).expect("the entry of a patch")];
                // the face value's increment over the owner: gradient/δ (K)
                ScalarBc::FixedGradient(
                    p.faces
                        .clone()
                        .zip(grad)
                        .map(|(f, gr)| gr / g.delta_coeff[f])
                        .collect(),
                )
            }
            "inletOutlet" => {
                ScalarBc::InletOutlet(e.values("inletValue", Item::as_f64, Item::as_f64_list)?)
            }
            "empty" => ScalarBc::Empty,
            "cyclic" => ScalarBc::Cyclic,
            _ => return Err(e.unsupported(t, T_SUPPORTED)),
        };
        let empty = bc == ScalarBc::Empty;
        Ok((bc, empty))
    })
}

/// Reads the conditions of α_t of every patch (the parsed file `field` at `file`), given T's
/// conditions `t_bcs` (the wall functions need T zeroGradient on their patch).
pub(crate) fn read_alphat(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
    t_bcs: &[ScalarBc],
) -> Result<Vec<ScalarBc>> {
    read_all(file, field, mesh, g, |e, t| {
        let bc = match t {
            "zeroGradient" | "symmetryPlane" | "symmetry" => ScalarBc::ZeroGradient,
            "calculated" => ScalarBc::Calculated,
            "fixedValue" => {
                ScalarBc::FixedValue(e.values("value", Item::as_f64, Item::as_f64_list)?)
            }
            "alphatJayatillekeWallFunction" | "compressible::alphatWallFunction" => {
                let pi = g.patch_index(&e.name).expect("the entry of a patch");
                if t_bcs[pi] != ScalarBc::ZeroGradient {
                    return Err(e.err(
                        "type",
                        format!(
                            "`{t}` is supported only on patches where T is zeroGradient (its \
                             wall heat flux is not implemented; with T zeroGradient the wall \
                             diffusivity has no effect)"
                        ),
                    ));
                }
                ScalarBc::Calculated
            }
            "empty" => ScalarBc::Empty,
            "cyclic" => ScalarBc::Cyclic,
            _ => return Err(e.unsupported(t, ALPHAT_SUPPORTED)),
        };
        let empty = bc == ScalarBc::Empty;
        Ok((bc, empty))
    })
}
