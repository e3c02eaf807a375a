//! The Darcy pressure drop of a frozen bed (prescribed ε, Ksl, Us), the reference the solvers'
//! steady pressure drops are measured against.
//!
//! Model A, steady, inertia and viscous stress negligible in the bed (ADR 0004):
//! ε∇p = −(Ksl/ρ)(U − Us), U the interstitial velocity, so with the superficial flux q = εU
//! along the bed axis z:
//!
//!   −∂p/∂z = r q − s,   r = Ksl/(ρ ε²)  (1/s per m),   s = Ksl Us_z/(ρ ε)  (m/s²),
//!
//! p kinematic (m²/s²; times ρ gives Pa). On a heterogeneous bed the local q depends on how
//! the flow finds its way, and the exact drop lies between two bounds (Thomson's principle of
//! least dissipation and its dual, as in Cardwell & Parsons, Trans. AIME 160 (1945) 34):
//!
//! * `lower`: every row of cells at one pressure (cells of a row in parallel, rows in series):
//!   per row −∂p/∂z = (q − ⟨s/r⟩)/⟨1/r⟩;
//! * `upper`: no cross-flow (columns of cells in parallel, each a series of cells):
//!   Δp = (q − ⟨S/R⟩)/⟨1/R⟩ with R = Σ r Δz, S = Σ s Δz along a column;
//!
//! (⟨·⟩ the area-weighted mean across the bed) and `uniform_flux`, Δp = Σ_rows Δz (⟨r⟩q − ⟨s⟩),
//! the drop of a flux forced uniform across the bed (above `upper`; the 1-D formula). The
//! bounds are exact only for r without viscous terms and s = 0; with |Us| ≪ q/ε the s term is
//! a small correction.

use mesh::MeshGeometry;

/// The bed's cells sorted into axial rows and columns.
pub struct Bed {
    row: Vec<usize>,
    column: Vec<usize>,
    n_rows: usize,
    n_columns: usize,
    dz: f64,
    volume: Vec<f64>,
    r: Vec<f64>,
    s: Vec<f64>,
}

/// The three reference drops of [`Bed::bounds`] (kinematic, m²/s²).
#[derive(Clone, Copy, Debug)]
pub struct DarcyDrop {
    /// Rows of cells at uniform pressure: a lower bound.
    pub lower: f64,
    /// Columns of cells without cross-flow: an upper bound.
    pub upper: f64,
    /// The flux forced uniform across the bed (the 1-D formula, ≥ `upper`).
    pub uniform_flux: f64,
}

impl Bed {
    /// Sorts the cells of a mesh extruded along z with `n_rows` equal layers (as the Ergun
    /// case's blockMesh makes) into rows and columns; ε, Ksl (kg/(m³ s)), Us (m/s) per cell.
    pub fn new(
        geo: &MeshGeometry,
        eps: &[f64],
        ksl: &[f64],
        us: &[[f64; 3]],
        rho: f64,
        n_rows: usize,
    ) -> Bed {
        let (z0, z1) = (geo.bounds.min[2], geo.bounds.max[2]);
        let dz = (z1 - z0) / n_rows as f64;
        let row: Vec<usize> = geo
            .cell_centres
            .iter()
            .map(|c| (((c[2] - z0) / dz) as usize).min(n_rows - 1))
            .collect();
        // Columns: cells whose centres share x and y (to 0.1 µm).
        let key = |c: &mesh::v3::V3| ((c[0] * 1e7).round() as i64, (c[1] * 1e7).round() as i64);
        let mut keys: Vec<(i64, i64)> = geo.cell_centres.iter().map(key).collect();
        keys.sort_unstable();
        keys.dedup();
        let column = geo
            .cell_centres
            .iter()
            .map(|c| keys.binary_search(&key(c)).expect("key of a cell"))
            .collect();
        let r = eps
            .iter()
            .zip(ksl)
            .map(|(e, k)| k / (rho * e * e))
            .collect();
        let s = (0..eps.len())
            .map(|c| ksl[c] * us[c][2] / (rho * eps[c]))
            .collect();
        Bed {
            row,
            column,
            n_rows,
            n_columns: keys.len(),
            dz,
            volume: geo.cell_volumes.clone(),
            r,
            s,
        }
    }

    /// Volume-weighted row means of a cell field.
    pub fn row_means(&self, values: &[f64]) -> Vec<f64> {
        let mut sum = vec![0.0; self.n_rows];
        let mut vol = vec![0.0; self.n_rows];
        for (c, v) in values.iter().enumerate() {
            sum[self.row[c]] += v * self.volume[c];
            vol[self.row[c]] += self.volume[c];
        }
        sum.iter().zip(&vol).map(|(s, v)| s / v).collect()
    }

    /// Per-row drop (Pa) with the flux `q` (m/s) forced uniform: ρ Δz (⟨r⟩q − ⟨s⟩).
    pub fn row_drops(&self, q: f64, rho: f64) -> Vec<f64> {
        let r = self.row_means(&self.r);
        let s = self.row_means(&self.s);
        r.iter()
            .zip(&s)
            .map(|(r, s)| rho * self.dz * (r * q - s))
            .collect()
    }

    /// The drops (kinematic) at superficial velocity `q` (m/s).
    pub fn bounds(&self, q: f64) -> DarcyDrop {
        let uniform_flux = self.row_drops(q, 1.0).iter().sum();
        // Rows in series, cells of a row in parallel; a row with a clear cell (r = 0) carries
        // any flux without a gradient.
        let mut lower = 0.0;
        for row in 0..self.n_rows {
            let cells: Vec<usize> = (0..self.r.len()).filter(|&c| self.row[c] == row).collect();
            if cells.iter().any(|&c| self.r[c] == 0.0) {
                continue;
            }
            let vol: f64 = cells.iter().map(|&c| self.volume[c]).sum();
            let mean = |f: &dyn Fn(usize) -> f64| {
                cells.iter().map(|&c| f(c) * self.volume[c]).sum::<f64>() / vol
            };
            let conductance = mean(&|c| 1.0 / self.r[c]);
            let driven = mean(&|c| self.s[c] / self.r[c]);
            lower += self.dz * (q - driven) / conductance;
        }
        // Columns in parallel, cells of a column in series.
        let mut resistance = vec![0.0; self.n_columns];
        let mut source = vec![0.0; self.n_columns];
        let mut area = vec![0.0; self.n_columns];
        for c in 0..self.r.len() {
            let k = self.column[c];
            resistance[k] += self.r[c] * self.dz;
            source[k] += self.s[c] * self.dz;
            area[k] += self.volume[c] / self.dz / self.n_rows as f64;
        }
        let total: f64 = area.iter().sum();
        let (mut conductance, mut driven) = (0.0, 0.0);
        for k in 0..self.n_columns {
            conductance += area[k] / resistance[k] / total;
            driven += area[k] * source[k] / resistance[k] / total;
        }
        DarcyDrop {
            lower,
            upper: (q - driven) / conductance,
            uniform_flux,
        }
    }
}

/// The area-weighted mean of `values` (one per face) over faces with area vectors `areas`.
pub fn area_mean(areas: &[mesh::v3::V3], values: &[f64]) -> f64 {
    assert_eq!(areas.len(), values.len(), "one value per face");
    let total: f64 = areas.iter().map(|a| a.norm()).sum();
    areas
        .iter()
        .zip(values)
        .map(|(a, v)| a.norm() * v)
        .sum::<f64>()
        / total
}

/// The face values of a patch of a written volScalarField: its `value` entry (`uniform` or
/// `nonuniform List<scalar>`), `n_faces` of them; `None` when the patch has no `value` entry
/// (zeroGradient: the face values are the owner cells').
pub fn patch_values(path: &std::path::Path, patch: &str, n_faces: usize) -> Option<Vec<f64>> {
    use foam::Item;
    let field = foam::VolField::read(path).unwrap_or_else(|e| panic!("{e}"));
    let patch_dict = field
        .boundary()
        .dict(patch)
        .unwrap_or_else(|e| panic!("{}: {patch}: {e}", path.display()));
    let entry = patch_dict.stream("value").ok()?;
    Some(match entry {
        [Item::Word(w), v] if w == "uniform" => {
            vec![v.as_f64().expect("uniform scalar"); n_faces]
        }
        [Item::Word(w), _, Item::Scalars(v)] if w == "nonuniform" && v.len() == n_faces => {
            v.clone()
        }
        other => panic!("{}: {patch}: value {other:?}", path.display()),
    })
}
