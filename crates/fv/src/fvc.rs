//! Explicit finite-volume operators on cell fields with given boundary-face values (what a
//! `foam::VolField` holds once its boundary conditions are evaluated).
//!
//! Conventions (OpenFOAM's): the gradient of a vector field is the tensor
//! `G_ij = ∂U_j/∂x_i` (row = derivative direction), the divergence of a tensor field `A` is
//! `(∇·A)_j = ∂_i A_ij`. Face sums run over each cell's faces in face order and skip `empty`
//! patches. Units: a gradient has the field's unit per metre.
//!
//! Accuracy (reference: Jasak 1996, PhD thesis, Imperial College, §3.3): the Gauss linear
//! gradient is exact for a linear field when every face centre lies on the line between the two
//! cell centres (orthogonal or sheared-but-unskewed meshes, e.g. affine images of a uniform
//! grid) and the faces are planar; on skewed meshes it carries the skewness error
//! (O(|m|·|∇²φ|) plus a term in |C_f − x_w|·|∇φ| / h) exactly as OpenFOAM's `Gauss linear`.
//! [`grad_least_squares`] is exact for linear fields on any mesh.

use crate::geometry::{FvGeometry, V3};
use rayon::prelude::*;

/// A 3×3 tensor, row-major.
/// A second-rank tensor (∇U: `t[(i, j)]` = ∂U_j/∂x_i, OpenFOAM's row-major `xx xy xz …`).
pub type Tensor = nalgebra::Matrix3<f64>;

/// A cell field together with its boundary-face values.
#[derive(Clone, Copy, Debug)]
pub struct Field<'a, T> {
    /// One value per cell.
    pub cells: &'a [T],
    /// One value per boundary face (index `face − n_internal`); values on `empty` faces are
    /// ignored.
    pub boundary: &'a [T],
}

impl<'a, T> Field<'a, T> {
    /// Pairs cell and boundary values.
    pub fn new(cells: &'a [T], boundary: &'a [T]) -> Self {
        Field { cells, boundary }
    }

    fn check(&self, g: &FvGeometry) {
        assert_eq!(self.cells.len(), g.n_cells, "cell values: one per cell");
        assert_eq!(
            self.boundary.len(),
            g.n_boundary(),
            "boundary values: one per boundary face"
        );
    }
}

/// Linear combination helpers for the value types the operators work on.
pub trait Value: Copy + Send + Sync + Default {
    /// `a + s·b`.
    fn axpy(a: Self, s: f64, b: Self) -> Self;
    /// `a − b`.
    fn minus(a: Self, b: Self) -> Self;
    /// The outer product `S ⊗ self` as the rows of the gradient: for a scalar φ the vector
    /// S φ, for a vector U the tensor `S_i U_j`.
    type Grad: Copy + Send + Sync + Default;
    /// `acc + s (S ⊗ self)`.
    fn add_outer(acc: Self::Grad, s: V3, v: Self) -> Self::Grad;
    /// `g / v`.
    fn grad_div(g: Self::Grad, v: f64) -> Self::Grad;
}

impl Value for f64 {
    fn axpy(a: Self, s: f64, b: Self) -> Self {
        a + s * b
    }
    fn minus(a: Self, b: Self) -> Self {
        a - b
    }
    type Grad = V3;
    fn add_outer(acc: V3, s: V3, v: f64) -> V3 {
        V3::new(acc[0] + s[0] * v, acc[1] + s[1] * v, acc[2] + s[2] * v)
    }
    fn grad_div(g: V3, v: f64) -> V3 {
        V3::new(g[0] / v, g[1] / v, g[2] / v)
    }
}

impl Value for V3 {
    fn axpy(a: Self, s: f64, b: Self) -> Self {
        V3::new(a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2])
    }
    fn minus(a: Self, b: Self) -> Self {
        a - b
    }
    type Grad = Tensor;
    fn add_outer(mut acc: Tensor, s: V3, v: V3) -> Tensor {
        for i in 0..3 {
            for j in 0..3 {
                acc[(i, j)] += s[i] * v[j];
            }
        }
        acc
    }
    fn grad_div(mut g: Tensor, v: f64) -> Tensor {
        for x in g.iter_mut() {
            *x /= v;
        }
        g
    }
}

/// Linear interpolation to internal faces, φ_f = w(φ_P − φ_N) + φ_N (OpenFOAM's operation
/// order), and the given values on boundary faces: one value per face.
pub fn interpolate<T: Value>(g: &FvGeometry, phi: Field<'_, T>) -> Vec<T> {
    phi.check(g);
    // Room for the boundary values from the start: no copy of the internal ones.
    let mut out: Vec<T> = Vec::with_capacity(g.n_faces());
    crate::gather::over(0..g.n_internal)
        .map(|f| {
            let (p, n) = (
                phi.cells[g.owner[f] as usize],
                phi.cells[g.neighbour[f] as usize],
            );
            T::axpy(n, g.weight[f], T::minus(p, n))
        })
        .collect_into(&mut out);
    out.extend_from_slice(phi.boundary);
    out
}

/// Σ over the faces of each cell of `S_f ⊗ face_values[f]` (with the sign of S_f out of the
/// cell), divided by the cell volume: the Gauss theorem for face values given on every face.
pub fn gauss_sum<T: Value>(g: &FvGeometry, face_values: &[T]) -> Vec<T::Grad> {
    assert_eq!(face_values.len(), g.n_faces(), "one value per face");
    gauss_sum_of(g, |f| face_values[f])
}

/// [`gauss_sum`] with the value of face `f` given by `value(f)`, taken where the cell loop
/// reaches the face.
fn gauss_sum_of<T: Value>(g: &FvGeometry, value: impl Fn(usize) -> T + Sync) -> Vec<T::Grad> {
    crate::gather::over(0..g.n_cells)
        .map(|c| {
            let mut acc = T::Grad::default();
            for &f in g.faces_of(c) {
                let f = f as usize;
                let s = if g.owner[f] as usize == c {
                    g.sf[f]
                } else {
                    -1.0 * g.sf[f]
                };
                acc = T::add_outer(acc, s, value(f));
            }
            T::grad_div(acc, g.v[c])
        })
        .collect()
}

/// Gauss linear gradient (OpenFOAM `Gauss linear`, cell values):
/// `∇φ_c = (1/V_c) Σ_f S_f φ_f` with φ_f linearly interpolated (Jasak 1996 eq. 3.21).
/// For a scalar field in units u the result is in u/m; for a vector field `G_ij = ∂U_j/∂x_i`.
///
/// [`gauss_sum`] of [`interpolate`] without the face array: each cell interpolates its
/// faces' values itself, with the same operations in the same order, so the bits are the
/// same (`grad_is_gauss_sum_of_interpolate_bit_for_bit`) and a face pass and its memory
/// traffic are saved (an internal face's value is computed on both of its sides).
pub fn grad<T: Value>(g: &FvGeometry, phi: Field<'_, T>) -> Vec<T::Grad> {
    phi.check(g);
    let ni = g.n_internal;
    gauss_sum_of(g, |f| {
        if f < ni {
            let (p, q) = (
                phi.cells[g.owner[f] as usize],
                phi.cells[g.neighbour[f] as usize],
            );
            T::axpy(q, g.weight[f], T::minus(p, q))
        } else {
            phi.boundary[f - ni]
        }
    })
}

/// Gauss linear gradient of a scalar field (u/m); see [`grad`].
pub fn grad_scalar(g: &FvGeometry, cells: &[f64], boundary: &[f64]) -> Vec<V3> {
    grad(g, Field::new(cells, boundary))
}

/// Gauss linear gradient of a vector field, `G_ij = ∂U_j/∂x_i` (1/s for a velocity); see
/// [`grad`].
pub fn grad_vector(g: &FvGeometry, cells: &[V3], boundary: &[V3]) -> Vec<Tensor> {
    grad(g, Field::new(cells, boundary))
}

/// Weighted least-squares gradient of a scalar field (u/m): minimises
/// Σ_f w_f (φ_f' − φ_c − d_f·∇φ)² over the cell's neighbours (φ_f' the neighbour value at
/// d_f = C_N − C_c) and boundary faces (the face value at d_f = C_f − C_c), w_f = 1/|d_f|².
/// Exact for linear fields on any mesh (the normal equations are solved exactly); in 2-D cases
/// (`empty` patches) the normal equations are singular in the empty direction, and the gradient
/// component along it is set to zero. Reference: Barth & Jespersen 1989, AIAA 89-0366;
/// OpenFOAM's `leastSquares` uses the same weights but the patch-normal d_f on boundaries.
pub fn grad_least_squares(g: &FvGeometry, cells: &[f64], boundary: &[f64]) -> Vec<V3> {
    Field::new(cells, boundary).check(g);
    crate::gather::over(0..g.n_cells)
        .map(|c| {
            let mut m = Tensor::zeros();
            let mut r = V3::zeros();
            for &f in g.faces_of(c) {
                let f = f as usize;
                let (d, dphi) = if f < g.n_internal {
                    let n = g.other(c, f);
                    (g.to_other(c, f), cells[n] - cells[c])
                } else {
                    ((g.cf[f] - g.c[c]), boundary[f - g.n_internal] - cells[c])
                };
                let w = 1.0 / d.dot(&d);
                for i in 0..3 {
                    for j in 0..3 {
                        m[(i, j)] += w * d[i] * d[j];
                    }
                    r[i] += w * d[i] * dphi;
                }
            }
            solve_sym3(m, r)
        })
        .collect()
}

/// The cell vector whose face fluxes best match the face fluxes `phi` (OpenFOAM's
/// `fvc::reconstruct`): x_c = T⁻¹ Σ_f n̂_f φ_f with T = Σ_f n̂_f ⊗ S_f over the cell's faces
/// (`empty` faces left out; a direction in which T is singular, the normal of a 2-D case, gets
/// 0). Exact for a uniform vector field (φ_f = a·S_f gives a) and for a linear one on cells
/// symmetric about their centre. For φ in m³/s the result is in m/s.
pub fn reconstruct(g: &FvGeometry, phi: &[f64]) -> Vec<V3> {
    assert_eq!(phi.len(), g.n_faces(), "one flux per face");
    crate::gather::over(0..g.n_cells)
        .map(|c| {
            let mut t = Tensor::zeros();
            let mut v = V3::zeros();
            for &f in g.faces_of(c) {
                let f = f as usize;
                let s = g.sf[f];
                let n = 1.0 / g.mag_sf[f] * s;
                for i in 0..3 {
                    for j in 0..3 {
                        t[(i, j)] += n[i] * s[j];
                    }
                    v[i] += n[i] * phi[f];
                }
            }
            solve_sym3(t, v)
        })
        .collect()
}

/// Solves the symmetric positive semi-definite 3×3 system `m x = r`; directions in which `m`
/// is singular (relative pivot below 1e-12) get a zero component.
fn solve_sym3(m: Tensor, r: V3) -> V3 {
    let scale_m = m[(0, 0)].max(m[(1, 1)]).max(m[(2, 2)]);
    if scale_m <= 0.0 {
        return V3::zeros();
    }
    let active: Vec<usize> = (0..3).filter(|&i| m[(i, i)] > 1e-12 * scale_m).collect();
    let mut x = V3::zeros();
    match active.len() {
        3 => {
            let det = m[(0, 0)] * (m[(1, 1)] * m[(2, 2)] - m[(1, 2)] * m[(2, 1)])
                - m[(0, 1)] * (m[(1, 0)] * m[(2, 2)] - m[(1, 2)] * m[(2, 0)])
                + m[(0, 2)] * (m[(1, 0)] * m[(2, 1)] - m[(1, 1)] * m[(2, 0)]);
            let inv = |a: usize, b: usize, c: usize, d: usize| {
                m[(a, c)] * m[(b, d)] - m[(a, d)] * m[(b, c)]
            };
            let adj = [
                [inv(1, 2, 1, 2), -inv(0, 2, 1, 2), inv(0, 1, 1, 2)],
                [-inv(1, 2, 0, 2), inv(0, 2, 0, 2), -inv(0, 1, 0, 2)],
                [inv(1, 2, 0, 1), -inv(0, 2, 0, 1), inv(0, 1, 0, 1)],
            ];
            for i in 0..3 {
                x[i] = (adj[i][0] * r[0] + adj[i][1] * r[1] + adj[i][2] * r[2]) / det;
            }
        }
        2 => {
            let (a, b) = (active[0], active[1]);
            let det = m[(a, a)] * m[(b, b)] - m[(a, b)] * m[(b, a)];
            x[a] = (m[(b, b)] * r[a] - m[(a, b)] * r[b]) / det;
            x[b] = (m[(a, a)] * r[b] - m[(b, a)] * r[a]) / det;
        }
        1 => x[active[0]] = r[active[0]] / m[(active[0], active[0])],
        _ => {}
    }
    x
}

/// Boundary-face values of a vector gradient as OpenFOAM's `gaussGrad::correctBoundaryConditions`
/// sets them: the owner-cell gradient with its normal part replaced by the face's snGrad,
/// `G_b = G_P + n̂ ⊗ (snGrad_b − n̂·G_P)`, snGrad_b = (U_b − U_P)·delta_coeff_b.
pub fn boundary_grad(g: &FvGeometry, u: Field<'_, V3>, grad_cells: &[Tensor]) -> Vec<Tensor> {
    // Each face on its own (in parallel on large boundaries — a 2-D case's `empty` patches
    // hold two faces per cell —, the same bits).
    let nb = g.n_faces() - g.n_internal;
    crate::gather::cells(nb, |b| {
        let f = g.n_internal + b;
        let p = g.owner[f] as usize;
        let n = g.nhat(f);
        let gp = grad_cells[p];
        let sn = g.delta_coeff[f] * (u.boundary[f - g.n_internal] - u.cells[p]);
        let ngp: V3 = V3::from_fn(|j, _| (0..3).map(|i| n[i] * gp[(i, j)]).sum());
        let mut gb = gp;
        for i in 0..3 {
            for j in 0..3 {
                gb[(i, j)] += n[i] * (sn[j] - ngp[j]);
            }
        }
        gb
    })
}

/// Face normal gradient with non-orthogonal correction (`Gauss linear corrected`):
/// internal faces `delta_coeff (φ_N − φ_P) + k·(∇φ)_f` with (∇φ)_f linearly interpolated,
/// boundary faces `delta_coeff (φ_b − φ_P)` (Jasak 1996 eq. 3.39–3.44). Units: u/m.
pub fn sn_grad_vector(g: &FvGeometry, u: Field<'_, V3>, grad_cells: &[Tensor]) -> Vec<V3> {
    let mut out: Vec<V3> = Vec::with_capacity(g.n_faces());
    crate::gather::over(0..g.n_internal)
        .map(|f| {
            let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            let w = g.weight[f];
            let k = g.corr_vec[f];
            let mut s = g.delta_coeff[f] * (u.cells[n] - u.cells[p]);
            for j in 0..3 {
                for i in 0..3 {
                    let gf =
                        w * (grad_cells[p][(i, j)] - grad_cells[n][(i, j)]) + grad_cells[n][(i, j)];
                    s[j] += k[i] * gf;
                }
            }
            s
        })
        .collect_into(&mut out);
    crate::gather::over(g.n_internal..g.n_faces())
        .map(|f| {
            let p = g.owner[f] as usize;
            g.delta_coeff[f] * (u.boundary[f - g.n_internal] - u.cells[p])
        })
        .collect_into(&mut out);
    out
}

/// The linear interpolation w(T_P − T_N) + T_N of a cell tensor field to the internal face `f`
/// (OpenFOAM's operation order, entry by entry).
fn interpolate_tensor(g: &FvGeometry, f: usize, t: &[Tensor]) -> Tensor {
    let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
    let w = g.weight[f];
    Tensor::from_fn(|i, j| w * (t[p][(i, j)] - t[n][(i, j)]) + t[n][(i, j)])
}

/// The face flux of the transposed stress part, `ν_f (G_f · S_f)` with the vector
/// `(G_f·S_f)_j = Σ_i S_i G_f,ji` (G = ∇U, face values linearly interpolated, boundary faces from
/// [`boundary_grad`]); with `dev2` the flux of `ν dev2(∇Uᵀ) = ν (∇Uᵀ − ⅔ tr(∇U) I)` as in
/// OpenFOAM's laminar `divDevReff`. One vector per face (m⁴/s² for ν in m²/s).
pub fn transpose_stress_flux(
    g: &FvGeometry,
    nu_f: &[f64],
    u: Field<'_, V3>,
    grad_u: &[Tensor],
    dev2: bool,
) -> Vec<V3> {
    let grad_b = boundary_grad(g, u, grad_u);
    crate::gather::over(0..g.n_faces())
        .map(|f| {
            let gf = if f < g.n_internal {
                interpolate_tensor(g, f, grad_u)
            } else {
                grad_b[f - g.n_internal]
            };
            let s = g.sf[f];
            let mut v: V3 = V3::from_fn(|j, _| (0..3).map(|i| s[i] * gf[(j, i)]).sum());
            if dev2 {
                let tr = gf[(0, 0)] + gf[(1, 1)] + gf[(2, 2)];
                v -= 2.0 / 3.0 * tr * s;
            }
            nu_f[f] * v
        })
        .collect()
}

/// The face flux of OpenFOAM's `fvc::div(nuEff*dev2(T(fvc::grad(U))))` (Gauss linear): the
/// tensor a dev2(∇Uᵀ) = a (∇Uᵀ − ⅔ tr(∇U) I) formed at cells (a per cell) and on boundary faces
/// (a per boundary face, ∇U from [`boundary_grad`]), interpolated linearly to the faces and
/// dotted with S_f: one vector per face (m⁴/s² for a in m²/s). The product is interpolated,
/// not a and ∇U apart, as pisoFoam's, grainPisoFoam's and CFDEM's solvers do (a = ε νeff in
/// the volume-averaged stress).
pub fn dev2_transpose_flux(
    g: &FvGeometry,
    a: Field<'_, f64>,
    u: Field<'_, V3>,
    grad_u: &[Tensor],
) -> Vec<V3> {
    a.check(g);
    let dev2t = |t: &Tensor, s: f64| {
        let mut m = t.transpose();
        let tr = m[(0, 0)] + m[(1, 1)] + m[(2, 2)];
        for i in 0..3 {
            m[(i, i)] -= 2.0 / 3.0 * tr;
        }
        s * m
    };
    let cells: Vec<Tensor> = (0..g.n_cells)
        .map(|c| dev2t(&grad_u[c], a.cells[c]))
        .collect();
    let grad_b = boundary_grad(g, u, grad_u);
    crate::gather::over(0..g.n_faces())
        .map(|f| {
            let t = if f < g.n_internal {
                interpolate_tensor(g, f, &cells)
            } else {
                let b = f - g.n_internal;
                dev2t(&grad_b[b], a.boundary[b])
            };
            let s = g.sf[f];
            V3::from_fn(|j, _| s[0] * t[(0, j)] + s[1] * t[(1, j)] + s[2] * t[(2, j)])
        })
        .collect()
}

/// Divergence of the kinematic viscous stress at cells (m/s²):
/// `∇·(ν_eff (∇U + ∇Uᵀ))` by the Gauss theorem,
/// `(1/V) Σ_f ν_f [ |S_f| snGrad(U)_f + (∇U)_f · S_f ]` ([`transpose_stress_flux`] for the
/// second part, [`sn_grad_vector`] for the first).
/// `nu` (m²/s) gives ν_eff per cell and per boundary face (e.g. ε ν for the volume-averaged
/// stress ∇·(ετ) of seed 002 eq. 3), interpolated linearly to faces.
/// Second-order accurate on smooth meshes; exact for quadratic U on uniform orthogonal grids
/// in cells away from the boundary.
pub fn div_viscous_stress(g: &FvGeometry, nu: Field<'_, f64>, u: Field<'_, V3>) -> Vec<V3> {
    u.check(g);
    let grad_u = grad(g, u);
    let sn = sn_grad_vector(g, u, &grad_u);
    let nu_f = interpolate(g, nu);
    let mut flux = transpose_stress_flux(g, &nu_f, u, &grad_u, false);
    crate::gather::each_mut(&mut flux, |f, v| {
        *v += nu_f[f] * g.mag_sf[f] * sn[f];
    });
    surface_integrate(g, &flux)
}

/// `(1/V_c) Σ_f ± flux_f` over each cell's faces (+ for the owner): the divergence of a face
/// flux field (OpenFOAM `fvc::surfaceIntegrate`). Units: flux unit per m³.
pub fn surface_integrate<T: Value>(g: &FvGeometry, flux: &[T]) -> Vec<T> {
    assert_eq!(flux.len(), g.n_faces(), "one flux per face");
    crate::gather::over(0..g.n_cells)
        .map(|c| {
            let mut acc = T::default();
            for &f in g.faces_of(c) {
                let f = f as usize;
                acc = T::axpy(acc, g.sign(c, f), flux[f]);
            }
            T::axpy(T::default(), 1.0 / g.v[c], acc)
        })
        .collect()
}

/// The curl ∇ × U of a vector field (1/s for a velocity in m/s): OpenFOAM's `fvc::curl(U)`,
/// 2·*skew(∇U), from the Gauss linear gradient with the boundary face values ([`grad_vector`],
/// `G_ij = ∂U_j/∂x_i`): ω = (G_yz − G_zy, G_zx − G_xz, G_xy − G_yx). Exact for a linear field
/// whose boundary values are the field's at the face centres (the Gauss sum of a linear field
/// is exact on any closed cell).
pub fn curl(g: &FvGeometry, cells: &[V3], boundary: &[V3]) -> Vec<V3> {
    grad_vector(g, cells, boundary)
        .into_par_iter()
        .map(|t| {
            V3::new(
                t[(1, 2)] - t[(2, 1)],
                t[(2, 0)] - t[(0, 2)],
                t[(0, 1)] - t[(1, 0)],
            )
        })
        .collect()
}

/// The convective term (1/V_c) Σ_f φ_f U_f of OpenFOAM's `fvc::div(phi, U)` (m/s² for φ in
/// m³/s and U in m/s), with linearly interpolated face values ([`interpolate`]; OpenFOAM uses
/// the `div(phi,U)` scheme of fvSchemes) and the boundary values on boundary faces.
pub fn div_flux_linear(g: &FvGeometry, phi: &[f64], cells: &[V3], boundary: &[V3]) -> Vec<V3> {
    let faces = interpolate(g, Field::new(cells, boundary));
    let flux: Vec<V3> = faces.iter().zip(phi).map(|(u, f)| *u * *f).collect();
    surface_integrate(g, &flux)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `grad` interpolates inside its cell loop; the bits must be those of the two passes it
    /// replaces, on a distorted mesh (weights ≠ ½, non-orthogonal faces), for scalars and
    /// vectors, on 1 and 3 threads.
    #[test]
    fn grad_is_gauss_sum_of_interpolate_bit_for_bit() {
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.7, 0.4], [12, 9, 7]);
        let m = mesh::build::map_points(&m, |[x, y, z]| {
            [
                x + 0.05 * (3.0 * y).sin(),
                y * (1.0 + 0.3 * x),
                z + 0.02 * x * y,
            ]
        });
        let g = FvGeometry::new(&m).unwrap();
        let s: Vec<f64> =
            g.c.iter()
                .map(|c| (7.0 * c[0]).sin() * c[1].exp() + c[2])
                .collect();
        let sb: Vec<f64> = g.cf[g.n_internal..].iter().map(|c| c[0] * c[1]).collect();
        let u: Vec<V3> = s
            .iter()
            .map(|&a| V3::new(a, a * a, 1.0 / (2.0 + a)))
            .collect();
        let ub: Vec<V3> = sb.iter().map(|&a| V3::new(a, -a, 3.0 * a)).collect();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let fs = Field::new(&s, &sb);
                assert_eq!(grad(&g, fs), gauss_sum(&g, &interpolate(&g, fs)));
                let fu = Field::new(&u, &ub);
                assert_eq!(grad(&g, fu), gauss_sum(&g, &interpolate(&g, fu)));
            });
        }
    }
}
