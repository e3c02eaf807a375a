//! Heat from the walls into the fluid of a bed: CFDEM-PFM's `wallHeatTransferYagi`
//! (`energyModel/wallHeatTransferYagi`, explicit form), Yagi & Wakao (1959) / Yagi & Kunii's
//! wall-to-bed heat transfer coefficient ([`yagi_coefficient`]).
//!
//! For each face of a wall patch on which the wall-temperature field (`wallTempName`, a file
//! of the start time) is `fixedValue` — the fluid's T must be `zeroGradient` there — with c the
//! face's cell, in the cell (PFM's fields, all per cell):
//! * d_p the mean particle diameter, the voidage-share-weighted average Σ w d / Σ w of the
//!   particles in the cell (0 without particles; PFM's `dpField` by its averaging model);
//! * G = ρ ε U (kg/(m²·s)), the superficial mass flux, μ = ρ ν;
//! * Re = d_p |G| / μ, Pr = c_p μ / λ;
//! * j_H = 0.20 (Re + 10⁻¹⁵)^(−0.20) where ε ≤ `voidfractionMax`, else 0 (Yagi, PFM's
//!   eq. 6a);
//! * h = j_H c_p |G| / (Pr^0.666 + 10⁻¹⁵) (W/(m²·K); PFM's exponent 0.666);
//! * Q = h A (T_wall − T_c), W into the fluid of c, A the face area.
//!
//! Per cell the faces' Q add up; |Q|/V above `maxSource` (W/m³) is cut to it (PFM's explicit
//! limit), the cut counted ([`WallFlow::clipped`]). The coupler adds Q/(ρ c_p V) to Tsource
//! (K/s, [`crate::heat`]) and counts Σ Q in [`crate::HeatAccount::from_wall`]: the heat
//! entering through the walls is in the heat account of every step.

use crate::error::CoupleError;
use crate::interpolate::Placement;
use foam::{Dict, Item, PolyMesh, Value, VolField};
use mesh::v3::V3;
use std::path::Path;

/// PFM's `SMALL` in Re and Pr.
const SMALL: f64 = 1e-15;

/// Yagi's heat transfer coefficient h (W/(m²·K)) for the particle Reynolds number `re`
/// (d_p |G|/μ), Prandtl number `pr`, the fluid's c_p `cp` (J/(kg·K)) and superficial mass
/// flux `g` (kg/(m²·s)): h = 0.20 (Re + 10⁻¹⁵)^(−0.2) c_p |G| / (Pr^0.666 + 10⁻¹⁵).
pub fn yagi_coefficient(re: f64, pr: f64, cp: f64, g: f64) -> f64 {
    let jh = 0.20 * (re + SMALL).powf(-0.20);
    jh * cp * g / (pr.powf(0.666) + SMALL)
}

/// One wall face: its cell, area (m²) and wall temperature (K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFace {
    /// The face's cell.
    pub cell: usize,
    /// Its area, m².
    pub area: f64,
    /// T_wall, K.
    pub t_wall: f64,
}

/// The wall heat model: the faces and its parameters (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct WallHeat {
    /// The heated faces.
    pub faces: Vec<WallFace>,
    /// ε above which j_H = 0 (`voidfractionMax`).
    pub eps_max: f64,
    /// Bound on |Q|/V per cell, W/m³ (`maxSource`), if any.
    pub max_source: Option<f64>,
}

/// The fluid as the wall heat reads it, per cell.
#[derive(Clone, Copy, Debug)]
pub struct WallFluid<'a> {
    /// ε.
    pub eps: &'a [f64],
    /// U (interstitial), m/s.
    pub u: &'a [V3],
    /// T, K.
    pub t: &'a [f64],
    /// Mean particle diameter d_p, m.
    pub dp: &'a [f64],
    /// Cell volumes, m³.
    pub volumes: &'a [f64],
}

/// The fluid's properties: ρ (kg/m³), ν (m²/s), λ (W/(m·K)), c_p (J/(kg·K)).
#[derive(Clone, Copy, Debug)]
pub struct WallProperties {
    /// ρ.
    pub rho: f64,
    /// ν.
    pub nu: f64,
    /// λ.
    pub lambda: f64,
    /// c_p.
    pub cp: f64,
}

/// One step's wall heat.
#[derive(Clone, Debug, PartialEq)]
pub struct WallFlow {
    /// Q per cell after the cut, W into the fluid.
    pub per_cell: Vec<f64>,
    /// Σ Q after the cut, W.
    pub total: f64,
    /// Σ (Q before − after the cut), W: heat the cut kept out of the fluid.
    pub clipped: f64,
}

impl WallHeat {
    /// The wall heat of one step (module docs); an error naming the cell if a face's Q is not
    /// finite.
    pub fn flow(
        &self,
        fluid: WallFluid<'_>,
        props: WallProperties,
    ) -> Result<WallFlow, CoupleError> {
        let mu = props.rho * props.nu;
        let pr = props.cp * mu / props.lambda;
        let mut per_cell = vec![0.0; fluid.eps.len()];
        for f in &self.faces {
            let c = f.cell;
            let g = props.rho * fluid.eps[c] * fluid.u[c].norm();
            let h = match fluid.eps[c] <= self.eps_max {
                true => yagi_coefficient(fluid.dp[c] * g / mu, pr, props.cp, g),
                false => 0.0,
            };
            let q = h * f.area * (f.t_wall - fluid.t[c]);
            if !q.is_finite() {
                return Err(CoupleError::Parameter(format!(
                    "wallHeatTransferYagi: the wall heat into cell {c} is {q} (T {}, ε {}, U {})",
                    fluid.t[c], fluid.eps[c], fluid.u[c]
                )));
            }
            per_cell[c] += q;
        }
        let (mut total, mut clipped) = (0.0, 0.0);
        for (q, v) in per_cell.iter_mut().zip(fluid.volumes) {
            if let Some(max) = self.max_source.filter(|m| q.abs() / v > *m) {
                let cut = (max * v).copysign(*q);
                clipped += *q - cut;
                *q = cut;
            }
            total += *q;
        }
        Ok(WallFlow {
            per_cell,
            total,
            clipped,
        })
    }

    /// Reads the faces of the wall-temperature field `<dir>/<name>` on `mesh` (module docs):
    /// its `fixedValue` patches, whose T (`<dir>/T`) must be `zeroGradient`. An error names the
    /// file and patch: a missing file, a patch missing from it, a value that is not a
    /// temperature per face, or T not zeroGradient there.
    pub fn read(
        dir: &Path,
        name: &str,
        mesh: &PolyMesh,
        eps_max: f64,
        max_source: Option<f64>,
    ) -> Result<WallHeat, CoupleError> {
        let path = dir.join(name);
        let err = |file: &Path, key: &str, m: String| CoupleError::Config {
            file: file.to_path_buf(),
            key: key.to_string(),
            message: m,
        };
        if !path.is_file() {
            return Err(err(
                &path,
                "wallTempName",
                "missing: wallHeatTransferYagi needs the wall temperature field with \
                 fixedValue walls (PFM: `must be defined`)"
                    .into(),
            ));
        }
        let field = VolField::read(&path)?;
        let t_path = dir.join("T");
        let t_field = VolField::read(&t_path)?;
        let geometry = mesh::geometry::MeshGeometry::compute(mesh)
            .map_err(|e| err(&path, "mesh", e.to_string()))?;
        let mut faces = Vec::new();
        for p in &mesh.boundary {
            let key = format!("boundaryField/{}", p.name);
            let entry = patch_entry(field.boundary(), &p.name)
                .ok_or_else(|| err(&path, &key, "missing".into()))?;
            if patch_type(entry) != Some("fixedValue") {
                continue;
            }
            let n = p.n_faces;
            let values = patch_values(entry, n).ok_or_else(|| {
                err(
                    &path,
                    &format!("{key}/value"),
                    format!("expected `uniform T` or {n} temperatures"),
                )
            })?;
            let t_type = patch_entry(t_field.boundary(), &p.name).and_then(patch_type);
            if t_type != Some("zeroGradient") {
                return Err(err(
                    &t_path,
                    &key,
                    format!(
                        "`{}`: wallHeatTransferYagi heats the fluid through this patch by a \
                         source and requires T zeroGradient here (as PFM does)",
                        t_type.unwrap_or("no type")
                    ),
                ));
            }
            for (k, t_wall) in values.into_iter().enumerate() {
                let face = p.start_face + k;
                faces.push(WallFace {
                    cell: mesh.owner[face] as usize,
                    area: geometry.face_areas[face].norm(),
                    t_wall,
                });
            }
        }
        Ok(WallHeat {
            faces,
            eps_max,
            max_source,
        })
    }
}

/// The boundaryField entry of `patch` (exact name, else a pattern key).
fn patch_entry<'a>(boundary: &'a Dict, patch: &str) -> Option<&'a Dict> {
    match boundary.resolve(patch, &[]).map(|e| &e.value) {
        Some(Value::Dict(d)) => Some(d),
        _ => None,
    }
}

/// A patch entry's `type`.
fn patch_type(entry: &Dict) -> Option<&str> {
    match entry.stream("type") {
        Ok([item]) => item.as_word(),
        _ => None,
    }
}

/// A patch entry's `value`: `uniform x` for every face or `nonuniform List<scalar> n (…)`.
fn patch_values(entry: &Dict, n: usize) -> Option<Vec<f64>> {
    let values = match entry.stream("value").ok()? {
        [Item::Word(u), x] if u == "uniform" => vec![x.as_f64()?; n],
        [Item::Word(u), rest @ ..] if u == "nonuniform" => rest.last()?.as_f64_list()?,
        _ => return None,
    };
    (values.len() == n && values.iter().all(|t| t.is_finite())).then_some(values)
}

/// The mean particle diameter per cell of `n_cells` (m): Σ w_pc d_p / Σ w_pc over the
/// particles' voidage shares, 0 in cells without particles.
pub fn mean_diameter(placement: &Placement, radius: &[f64], n_cells: usize) -> Vec<f64> {
    let (mut wd, mut w) = (vec![0.0; n_cells], vec![0.0; n_cells]);
    for (i, r) in radius.iter().enumerate() {
        placement.for_each_weight(i, |c, s| {
            wd[c as usize] += s * 2.0 * r;
            w[c as usize] += s;
        });
    }
    wd.iter()
        .zip(&w)
        .map(|(&a, &b)| if b > 0.0 { a / b } else { 0.0 })
        .collect()
}

/// Where the particles are: their placement and radii (m), for the cells' mean diameter.
#[derive(Clone, Copy)]
pub struct At<'a> {
    /// The step's placement.
    pub placement: &'a Placement,
    /// The particles' radii, m.
    pub radius: &'a [f64],
}

impl WallHeat {
    /// Adds this step's wall heat to the heat step `h` of one coupler rank (whole Tsource):
    /// Q/(ρ c_p V) to each cell's Tsource, Σ Q to `from_wall` and the cut to `wall_clipped`.
    pub fn add_to(
        &self,
        h: &mut crate::HeatStep,
        at: At<'_>,
        cells: crate::heat::CellFields<'_>,
        volumes: &[f64],
        props: WallProperties,
    ) -> Result<(), CoupleError> {
        let dp = mean_diameter(at.placement, at.radius, volumes.len());
        let fluid = WallFluid {
            eps: cells.eps,
            u: cells.u,
            t: cells.t,
            dp: &dp,
            volumes,
        };
        let flow = self.flow(fluid, props)?;
        let rho_cp = props.rho * props.cp;
        for ((s, q), v) in h.tsource.iter_mut().zip(&flow.per_cell).zip(volumes) {
            *s += q / (rho_cp * v);
        }
        h.account.from_wall = flow.total;
        h.account.wall_clipped = flow.clipped;
        Ok(())
    }
}
