//! Translational `cyclic` patch pairs of a polyMesh: which patches couple, which faces match,
//! and the checks OpenFOAM v1912's `cyclicPolyPatch` makes before it treats a pair as coupled.
//!
//! A `cyclic` patch names its partner with `neighbourPatch`; face i of one patch couples with
//! face i of the other (OpenFOAM's ordering of cyclic faces). Only translational pairs are
//! supported: `transform translational` with a `separationVector` (the vector from a face of
//! this patch to its partner face, m), or `unknown`/`noOrdering`/`coincidentFullMatch`/no
//! `transform`, where the separation comes from the face centres as v1912's
//! `coupledPolyPatch::calcTransformTensors` finds it (every pair of faces the same
//! translation). Each pair of faces must have opposite unit normals and equal areas, and
//! the partner's centre must be this face's centre plus the separation, all to OpenFOAM's
//! default `matchTolerance` (1e-4) times the face's length scale √|S|. `rotational`
//! transforms, non-parallel pairs and the other coupled types (`cyclicAMI`, `cyclicACMI`,
//! `cyclicSlip`, `processorCyclic`, `nonConformalCyclic`) are errors naming the boundary file
//! and the patch ([`MeshError::Patch`]).
//!
//! The pairs are topology and geometry only: the native solver (`fv::cyclic`) solves each pair
//! of faces as an internal face, and the coupler (`couple::periodic`) wraps particle centres
//! by the separations.

use crate::error::MeshError;
use crate::geometry::MeshGeometry;
use crate::v3::V3;
use foam::PolyMesh;
use std::path::Path;

/// Results of this module.
type Result<T> = std::result::Result<T, MeshError>;

/// The file named by errors about patches (relative to the case).
pub const BOUNDARY_FILE: &str = "constant/polyMesh/boundary";

/// OpenFOAM's default `matchTolerance` of coupled patches (relative to √|S|).
pub const MATCH_TOLERANCE: f64 = 1e-4;

/// Patch types that couple faces in ways the native solver does not support.
const UNSUPPORTED_COUPLED: &[&str] = &[
    "cyclicAMI",
    "cyclicACMI",
    "cyclicSlip",
    "processorCyclic",
    "nonConformalCyclic",
    "cyclicRepeatAMI",
];

/// One translational pair of cyclic patches.
#[derive(Clone, Debug, PartialEq)]
pub struct CyclicPair {
    /// The patch listed first in `boundary` (its faces give the pair faces' S and centre).
    pub first: usize,
    /// Its `neighbourPatch`.
    pub second: usize,
    /// The translation from a face of `first` to its partner on `second` (m).
    pub separation: V3,
}

fn patch_file_err(patch: &str, key: &str, msg: impl Into<String>) -> MeshError {
    MeshError::Patch {
        file: Path::new(BOUNDARY_FILE).to_path_buf(),
        key: format!("{patch}.{key}"),
        msg: msg.into(),
    }
}

fn extra<'a>(p: &'a foam::Patch, key: &str) -> Option<&'a str> {
    p.extra
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.trim_end_matches(';').trim())
}

fn parse_vector(text: &str) -> Option<V3> {
    let inner = text.trim().strip_prefix('(')?.strip_suffix(')')?;
    let v: Vec<f64> = inner
        .split_whitespace()
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .ok()?;
    (v.len() == 3 && v.iter().all(|x| x.is_finite())).then(|| V3::new(v[0], v[1], v[2]))
}

/// The cyclic pairs of `mesh` (geometry `g`), each once, ordered by their first patch; an
/// error naming [`BOUNDARY_FILE`] and the patch for anything not translational or not
/// matching (see the module doc).
pub fn pairs(mesh: &PolyMesh, g: &MeshGeometry) -> Result<Vec<CyclicPair>> {
    let mut out = Vec::new();
    for (i, p) in mesh.boundary.iter().enumerate() {
        if UNSUPPORTED_COUPLED.contains(&p.patch_type.as_str()) {
            return Err(patch_file_err(
                &p.name,
                "type",
                format!(
                    "`{}` is not supported by the native solver (translational `cyclic` only)",
                    p.patch_type
                ),
            ));
        }
        if p.patch_type != "cyclic" {
            continue;
        }
        let nbr_name = extra(p, "neighbourPatch")
            .ok_or_else(|| patch_file_err(&p.name, "neighbourPatch", "missing"))?;
        let j = mesh
            .boundary
            .iter()
            .position(|q| q.name == nbr_name)
            .ok_or_else(|| {
                patch_file_err(
                    &p.name,
                    "neighbourPatch",
                    format!("there is no patch `{nbr_name}`"),
                )
            })?;
        let q = &mesh.boundary[j];
        if j == i || q.patch_type != "cyclic" || extra(q, "neighbourPatch") != Some(&p.name) {
            return Err(patch_file_err(
                &p.name,
                "neighbourPatch",
                format!(
                    "`{nbr_name}` must be another cyclic patch whose neighbourPatch is `{}`",
                    p.name
                ),
            ));
        }
        if q.n_faces != p.n_faces {
            return Err(patch_file_err(
                &p.name,
                "nFaces",
                format!(
                    "{} faces, but its neighbourPatch `{}` has {}",
                    p.n_faces, q.name, q.n_faces
                ),
            ));
        }
        if j < i {
            continue;
        }
        let separation = separation(mesh, g, i, j)?;
        out.push(CyclicPair {
            first: i,
            second: j,
            separation,
        });
    }
    Ok(out)
}

/// The translation of the pair (`i` listed first), checked face by face.
fn separation(mesh: &PolyMesh, g: &MeshGeometry, i: usize, j: usize) -> Result<V3> {
    let (p, q) = (&mesh.boundary[i], &mesh.boundary[j]);
    // The transform as either side states it (both must agree when both do).
    let stated = |pa: &foam::Patch| -> Result<Option<V3>> {
        match extra(pa, "transform").unwrap_or("unknown") {
            "translational" => {
                let v = extra(pa, "separationVector").ok_or_else(|| {
                    patch_file_err(
                        &pa.name,
                        "separationVector",
                        "missing (transform translational)",
                    )
                })?;
                parse_vector(v).map(Some).ok_or_else(|| {
                    patch_file_err(
                        &pa.name,
                        "separationVector",
                        format!("`{v}` is not a vector (x y z)"),
                    )
                })
            }
            "coincidentFullMatch" => Ok(Some(V3::zeros())),
            "unknown" | "noOrdering" => Ok(None),
            "rotational" => Err(patch_file_err(
                &pa.name,
                "transform",
                "rotational cyclics are not supported by the native solver (translational only)",
            )),
            other => Err(patch_file_err(
                &pa.name,
                "transform",
                format!("`{other}` is not supported (translational, coincidentFullMatch, unknown)"),
            )),
        }
    };
    let sep_p = stated(p)?;
    let sep_q = stated(q)?.map(|v| -v);
    // The patch's own `matchTolerance` (blockMesh writes it), else OpenFOAM's default.
    let rel_tol = extra(p, "matchTolerance")
        .and_then(|t| t.parse::<f64>().ok())
        .filter(|t| *t > 0.0)
        .unwrap_or(MATCH_TOLERANCE);
    let tol_of = |f: usize| rel_tol * g.face_areas[f].norm().sqrt();
    if let (Some(a), Some(b)) = (sep_p, sep_q) {
        if (a - b).norm() > tol_of(p.start_face) {
            return Err(patch_file_err(
                &p.name,
                "separationVector",
                format!(
                    "({} {} {}) is not minus the separationVector of `{}`",
                    a[0], a[1], a[2], q.name
                ),
            ));
        }
    }
    let fa0 = p.start_face;
    let fb0 = q.start_face;
    let sep = sep_p
        .or(sep_q)
        .unwrap_or_else(|| g.face_centres[fb0] - g.face_centres[fa0]);
    for k in 0..p.n_faces {
        let (fa, fb) = (fa0 + k, fb0 + k);
        let (sa, sb) = (g.face_areas[fa], g.face_areas[fb]);
        let tol = tol_of(fa);
        let (ma, mb) = (sa.norm(), sb.norm());
        if (ma - mb).abs() > rel_tol * ma || (sa / ma + sb / mb).norm() > rel_tol {
            return Err(patch_file_err(
                &p.name,
                "transform",
                format!(
                    "face {k} and face {k} of `{}` are not parallel faces of equal area \
                     (rotational and non-conformal cyclics are not supported)",
                    q.name
                ),
            ));
        }
        let miss = (g.face_centres[fa] + sep - g.face_centres[fb]).norm();
        if miss > tol {
            return Err(patch_file_err(
                &p.name,
                "separationVector",
                format!(
                    "face {k} moved by ({} {} {}) misses face {k} of `{}` by {miss:e} m \
                     (tolerance {tol:e} m)",
                    sep[0], sep[1], sep[2], q.name
                ),
            ));
        }
    }
    Ok(sep)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_parse_as_the_boundary_file_writes_them() {
        assert_eq!(parse_vector("(-0.4 0 0)"), Some(V3::new(-0.4, 0.0, 0.0)));
        assert_eq!(parse_vector("(1 2)"), None);
        assert_eq!(parse_vector("1 2 3"), None);
    }
}
