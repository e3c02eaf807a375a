//! Independent references for the voidage tests: a seeded RNG, Monte Carlo with binomial error
//! bars, Gauss–Legendre quadrature, and the circle ∩ rectangle area by chord integration.
#![allow(dead_code)]

use mesh::v3::V3;
use std::f64::consts::PI;

/// xoshiro256** (Blackman & Vigna), seeded by SplitMix64: reproducible random numbers.
pub struct Rng([u64; 4]);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        let mut x = seed;
        let mut s = [0u64; 4];
        for v in &mut s {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            *v = z ^ (z >> 31);
        }
        Rng(s)
    }
    pub fn next(&mut self) -> u64 {
        let s = &mut self.0;
        let out = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        out
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn point(&mut self, lo: impl Into<V3>, hi: impl Into<V3>) -> V3 {
        let (lo, hi) = (lo.into(), hi.into());
        V3::from_fn(|a, _| self.uniform(lo[a], hi[a]))
    }
}

/// Whether `m` is defined on `vm`: every method is, except `trilinear` on a mesh that is not a
/// grid of equal axis-aligned cells, which must be refused with [`voidage::VoidageError::UnsupportedMesh`].
pub fn defined_on(vm: &voidage::VoidageMesh, m: voidage::Method) -> bool {
    match vm.check_method(m) {
        Ok(()) => true,
        Err(e) => {
            assert_eq!(m, voidage::Method::Trilinear, "{e}");
            assert!(
                matches!(e, voidage::VoidageError::UnsupportedMesh { .. }),
                "{e}"
            );
            false
        }
    }
}

/// A Monte Carlo estimate of vol{x ∈ box : inside(x)} with `n` uniform samples in the box:
/// (estimate, standard error) from the binomial variance.
pub fn monte_carlo(
    rng: &mut Rng,
    lo: impl Into<V3>,
    hi: impl Into<V3>,
    n: usize,
    inside: impl Fn(V3) -> bool,
) -> (f64, f64) {
    let (lo, hi) = (lo.into(), hi.into());
    let vol: f64 = (0..3).map(|a| hi[a] - lo[a]).product();
    let hits = (0..n).filter(|_| inside(rng.point(lo, hi))).count();
    let p = hits as f64 / n as f64;
    // Never let the error bar collapse to zero (p = 0 or 1): use one pseudo-count.
    let q = p.clamp(0.5 / n as f64, 1.0 - 0.5 / n as f64);
    (p * vol, vol * (q * (1.0 - q) / n as f64).sqrt())
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton iteration on P_n).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// ∫_a^b f by Gauss–Legendre with `nodes`, after the substitution u = 3s² − 2s³ that makes
/// square-root endpoint behaviour smooth.
pub fn integrate(nodes: &[(f64, f64)], a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let mut sum = 0.0;
    for &(x, w) in nodes {
        let s = 0.5 * (x + 1.0);
        let u = s * s * (3.0 - 2.0 * s);
        let du = 6.0 * s * (1.0 - s);
        sum += 0.5 * w * du * f(a + (b - a) * u);
    }
    sum * (b - a)
}

/// Area of the disk of radius `rho` centred at the origin ∩ the rectangle [x0,x1]×[y0,y1], by
/// integrating the chord length |[y0, y1] ∩ [−h, h]|, h = √(ρ² − x²), piece by piece in closed
/// form (∫h dx = ½(x h + ρ² asin(x/ρ))).
pub fn disk_rect_area(rho: f64, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    if rho <= 0.0 {
        return 0.0;
    }
    let (a, b) = (x0.max(-rho), x1.min(rho));
    if b <= a {
        return 0.0;
    }
    let h = |x: f64| (rho * rho - x * x).max(0.0).sqrt();
    let s = |x: f64| 0.5 * (x * h(x) + rho * rho * (x / rho).clamp(-1.0, 1.0).asin());
    // Breakpoints where h(x) = |y0| or |y1|.
    let mut xs = vec![a, b];
    for y in [y0, y1] {
        if y.abs() < rho {
            let x = (rho * rho - y * y).sqrt();
            for x in [-x, x] {
                if x > a && x < b {
                    xs.push(x);
                }
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    let mut area = 0.0;
    for w in xs.windows(2) {
        let (p, q) = (w[0], w[1]);
        if q <= p {
            continue;
        }
        let m = 0.5 * (p + q);
        let hm = h(m);
        let top_is_h = hm < y1;
        let bottom_is_h = -hm > y0;
        let len_m = hm.min(y1) - (-hm).max(y0);
        if len_m <= 0.0 {
            continue;
        }
        let top = if top_is_h { s(q) - s(p) } else { y1 * (q - p) };
        let bottom = if bottom_is_h {
            -(s(q) - s(p))
        } else {
            y0 * (q - p)
        };
        area += top - bottom;
    }
    area
}

/// Volume of the ball (centre 0, radius r) ∩ box by Gauss–Legendre quadrature over z of the
/// cross-section areas [`disk_rect_area`], split at every z where the cross-section changes
/// form (the disk radius passes a rectangle corner or edge line).
pub fn ball_box_by_quadrature(r: f64, lo: V3, hi: V3, nodes: &[(f64, f64)]) -> f64 {
    let (za, zb) = (lo[2].max(-r), hi[2].min(r));
    if zb <= za {
        return 0.0;
    }
    let mut zs = vec![za, zb, 0.0];
    let mut radii = vec![];
    for x in [lo[0], hi[0]] {
        radii.push(x.abs());
        for y in [lo[1], hi[1]] {
            radii.push((x * x + y * y).sqrt());
        }
    }
    radii.extend([lo[1].abs(), hi[1].abs()]);
    for rr in radii {
        if rr < r {
            let z = (r * r - rr * rr).sqrt();
            zs.extend([z, -z]);
        }
    }
    zs.retain(|&z| z >= za && z <= zb);
    zs.sort_by(f64::total_cmp);
    zs.windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            integrate(nodes, w[0], w[1], |z| {
                disk_rect_area((r * r - z * z).max(0.0).sqrt(), lo[0], hi[0], lo[1], hi[1])
            })
        })
        .sum()
}

/// Relative difference |a − b| / max(|b|, floor).
pub fn rel(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / b.abs().max(floor)
}

/// `x` rounded to `d` decimals.
pub fn round_to(x: f64, d: i32) -> f64 {
    let s = 10f64.powi(d);
    (x * s).round() / s
}

/// Checks the exact shares of one particle (centre `c`, radius `r`) on `vm` against `n` Monte
/// Carlo points uniform in the ball, located in the mesh: per cell and outside, within 4.5
/// binomial standard errors.
pub fn check_exact_against_monte_carlo(
    vm: &voidage::VoidageMesh,
    rng: &mut Rng,
    c: V3,
    r: f64,
    n: usize,
) {
    let set = voidage::ParticleSet::new(std::slice::from_ref(&c), std::slice::from_ref(&r));
    let d = vm.deposit(voidage::Method::Exact, &set).unwrap();
    let v = voidage::ball_volume(r);
    let cells = vm.n_cells();
    let mut counts = vec![0usize; cells + 1];
    let mut k = 0;
    while k < n {
        let p = rng.point(c.map(|x| x - r), c.map(|x| x + r));
        if (0..3).map(|a| (p[a] - c[a]).powi(2)).sum::<f64>() < r * r {
            counts[vm.locator().locate(p).map_or(cells, |c| c as usize)] += 1;
            k += 1;
        }
    }
    for (cell, &cnt) in counts.iter().enumerate() {
        let exact = if cell < cells {
            d.solid[cell]
        } else {
            d.outside_volume
        };
        let p = cnt as f64 / n as f64;
        let q = p.clamp(0.5 / n as f64, 1.0 - 0.5 / n as f64);
        let se = v * (q * (1.0 - q) / n as f64).sqrt();
        assert!(
            approx::abs_diff_eq!(exact, p * v, epsilon = 4.5 * se),
            "cell {cell}: {exact} vs {}",
            p * v
        );
    }
}

/// Σ ball ∩ tet over the tets of `cell` in the mesh's tet decomposition: the exact share of
/// the cell by the tet kernel alone.
pub fn tet_sum(vm: &voidage::VoidageMesh, cell: usize, c: V3, r: f64) -> f64 {
    vm.locator()
        .tets()
        .cell_tets(cell as u32)
        .map(|t| voidage::sphere_tet_volume(c, r, &t.points))
        .sum()
}

/// Volume of the box `lo`..`hi` ∩ the tet `t` by clipping the tet with the six half-spaces
/// (a kept part is a tet or a prism split into three tets): an independent reference for the
/// face-term kernel of `voidage::clip`. Signed like the tet's volume.
pub fn box_tet_by_clipping(lo: V3, hi: V3, t: &[V3; 4]) -> f64 {
    let vol = |t: &[V3; 4]| (t[1] - t[0]).dot(&(t[2] - t[0]).cross(&(t[3] - t[0]))) / 6.0;
    let sign = vol(t).signum();
    let mut pieces = vec![*t];
    for a in 0..3 {
        for (value, s) in [(lo[a], -1.0), (hi[a], 1.0)] {
            let mut next = Vec::new();
            for t in &pieces {
                let d = t.map(|p| s * (p[a] - value));
                let keep: Vec<usize> = (0..4).filter(|&i| d[i] <= 0.0).collect();
                let drop: Vec<usize> = (0..4).filter(|&i| d[i] > 0.0).collect();
                let cut = |i: usize, j: usize| t[i] + (t[j] - t[i]) * (d[i] / (d[i] - d[j]));
                let prism = |p: [V3; 6], next: &mut Vec<[V3; 4]>| {
                    next.push([p[0], p[1], p[2], p[3]]);
                    next.push([p[1], p[2], p[3], p[4]]);
                    next.push([p[2], p[3], p[4], p[5]]);
                };
                match keep.len() {
                    4 => next.push(*t),
                    0 => {}
                    1 => {
                        let i = keep[0];
                        next.push([t[i], cut(i, drop[0]), cut(i, drop[1]), cut(i, drop[2])]);
                    }
                    3 => {
                        let l = drop[0];
                        let [i, j, k] = [keep[0], keep[1], keep[2]];
                        prism(
                            [t[i], t[j], t[k], cut(i, l), cut(j, l), cut(k, l)],
                            &mut next,
                        );
                    }
                    _ => {
                        let [i, j] = [keep[0], keep[1]];
                        let [k, l] = [drop[0], drop[1]];
                        prism(
                            [t[i], cut(i, k), cut(i, l), t[j], cut(j, k), cut(j, l)],
                            &mut next,
                        );
                    }
                }
            }
            pieces = next;
        }
    }
    sign * pieces.iter().map(|t| vol(t).abs()).sum::<f64>()
}

/// The unit box as an 8³ grid (the grid path and, without it, the general path) and a graded
/// 4³ hex mesh: the meshes the per-particle conservation tests walk.
pub fn grid_general_graded() -> [(&'static str, voidage::VoidageMesh); 3] {
    use mesh::build::{hex_grid, uniform_box};
    use voidage::{MeshOptions, VoidageMesh};
    let graded = hex_grid(
        &[0.0, 0.1, 0.3, 0.6, 1.0],
        &[0.0, 0.25, 0.5, 0.75, 1.0],
        &[0.0, 0.5, 0.7, 0.9, 1.0],
    );
    let uniform = uniform_box([0.0; 3], [1.0; 3], [8, 8, 8]);
    let no_grid = MeshOptions {
        axis_aligned_fast_path: false,
    };
    [
        ("grid", VoidageMesh::new(&uniform).unwrap()),
        (
            "general",
            VoidageMesh::with_options(&uniform, no_grid).unwrap(),
        ),
        ("graded", VoidageMesh::new(&graded).unwrap()),
    ]
}
