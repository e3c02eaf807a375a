//! `GaussVoidFraction` with normalised weights (`Method::Gauss`): every particle's volume in a
//! cell or counted outside, to round-off; the kernel's moments on a fine mesh against the
//! closed form of a Gaussian of σ = r truncated at 3σ; the `alphaMin` clipping accounted.

mod common;

use common::*;
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::*;

/// Every particle's volume is in a cell (the shares sum to it to round-off) or counted
/// outside (centre outside the mesh), on the grid path, the general path and a graded mesh,
/// for particles from a tenth of a cell to several cells wide, some beyond the walls.
#[test]
fn every_particle_volume_is_in_a_cell_or_counted_outside() {
    let mut rng = Rng::new(2828);
    let n = 300;
    let pos: Vec<V3> = (0..n).map(|_| rng.point([-0.2; 3], [1.2; 3])).collect();
    let rad: Vec<f64> = (0..n).map(|_| rng.uniform(0.01, 0.3)).collect();
    let vol: f64 = rad.iter().map(|&r| ball_volume(r)).sum();
    assert!(vol > 0.0);
    for (name, vm) in grid_general_graded() {
        let (shares, d) = vm
            .shares(Method::Gauss, &ParticleSet::new(&pos, &rad))
            .unwrap();
        assert!(d.conservation_error() < 1e-13, "{name}");
        let located = vm.locator().locate_all(&pos);
        for (i, cell) in located.iter().enumerate() {
            let (cells, vols) = shares.of(i);
            match cell {
                None => assert!(cells.is_empty()),
                Some(c) => {
                    assert_eq!(cells[0], *c, "{name}: the centre's cell first");
                    let v = ball_volume(rad[i]);
                    let sum: f64 = vols.iter().sum();
                    assert!(
                        (sum - v).abs() <= 4e-16 * v * vols.len() as f64,
                        "{name} {i}"
                    );
                    assert!(vols.iter().all(|&x| x >= 0.0));
                }
            }
        }
    }
}

/// A particle of r = σ = 0.1 on a mesh of h = σ/6 (48³ cells of a 0.8 m box, the 3σ sphere
/// well inside): the shares' mean is the particle centre, and their second moment
/// Σ V_c |C_c − x|² / V is the Gaussian's truncated at 3σ, σ²·I₄/I₂ with
/// I_n = ∫₀³ tⁿ e^(−t²/2) dt: I₂ = −3e^(−4.5) + √(π/2) erf(3/√2) = 1.2166034551268203,
/// I₄ = −27e^(−4.5) + 3I₂ = 3.349867458847919, I₄/I₂ = 2.7534587746988803 (Python's math.erf;
/// an untruncated Gaussian has 3), 0.9178195915662934 σ² along each axis. The midpoint sum over
/// the cells and the cells' in-or-out at the 3σ sphere make it differ by O(h²/σ²) and by the
/// boundary layer's mass (weights there are e^(−4.5) ≈ 1 % of the peak): within 0.2 % (measured
/// 2.753978 σ², +0.019 %).
#[test]
fn second_moment_is_the_truncated_gaussians() {
    let (n, side) = (48, 0.8);
    let m = uniform_box([0.0; 3], [side; 3], [n, n, n]);
    let vm = VoidageMesh::new(&m).unwrap();
    let centres = &vm.geometry().cell_centres;
    let sigma = 0.1;
    let x = V3::new(0.4031, 0.3987, 0.4123);
    let (shares, d) = vm
        .shares(Method::Gauss, &ParticleSet::new(&[x], &[sigma]))
        .unwrap();
    assert!(d.conservation_error() < 1e-13);
    let v = ball_volume(sigma);
    let (cells, vols) = shares.of(0);
    let mut mean = V3::zeros();
    let mut second = 0.0;
    let mut axes = V3::zeros();
    for (&c, &w) in cells.iter().zip(vols) {
        let r = centres[c as usize] - x;
        mean += r * (w / v);
        second += r.norm_squared() * w / v;
        axes += r.component_mul(&r) * (w / v);
    }
    assert!(mean.norm() < 1e-3 * sigma, "mean offset {mean:?}");
    let want = 2.7534587746988803 * sigma * sigma;
    println!(
        "second moment {:.6} σ² (truncated Gaussian 2.753459 σ²), mean offset {:.2e} σ",
        second / (sigma * sigma),
        mean.norm() / sigma
    );
    assert!(
        (second - want).abs() < 2e-3 * want,
        "{second} vs {want}: {:+.3} %",
        100.0 * (second / want - 1.0)
    );
    for k in 0..3 {
        let want = 0.9178195915662934 * sigma * sigma;
        assert!(
            (axes[k] - want).abs() < 1e-2 * want,
            "axis {k}: {}",
            axes[k]
        );
    }
    // the cells reached are those whose centre is within 3σ, and the centre's cell
    let home = vm.locator().locate_all(&[x])[0].unwrap();
    let want = (0..centres.len() as u32)
        .filter(|&k| k == home || (centres[k as usize] - x).norm() < 3.0 * sigma)
        .count();
    assert_eq!(cells.len(), want);
}

/// A particle much smaller than its cell (σ < cell half-width / 3: no other centre within 3σ)
/// puts its whole volume into its centre's cell.
#[test]
fn small_particle_stays_in_its_cell() {
    let m = uniform_box([0.0; 3], [1.0; 3], [4, 4, 4]);
    let vm = VoidageMesh::new(&m).unwrap();
    let x = V3::new(0.61, 0.37, 0.88);
    let r = 0.02;
    let (shares, _) = vm
        .shares(Method::Gauss, &ParticleSet::new(&[x], &[r]))
        .unwrap();
    let (cells, vols) = shares.of(0);
    assert_eq!(cells, &[vm.locator().locate_all(&[x])[0].unwrap()]);
    assert_eq!(vols, &[ball_volume(r)]);
}

/// `alphaMin` clips ε as for the other methods and the solid volume it removes is reported:
/// ε_c + clipped volume per cell restores Σ V (1 − ε) to the particles' volume.
#[test]
fn alpha_min_clipping_is_accounted() {
    let m = uniform_box([0.0; 3], [1.0; 3], [10, 10, 10]);
    let vm = VoidageMesh::new(&m).unwrap();
    // a dense cluster: the centre cells' solid exceeds 1 − 0.4
    let pos: Vec<V3> = (0..40)
        .map(|i| V3::new(0.5 + 0.001 * i as f64, 0.5, 0.5))
        .collect();
    let rad = vec![0.05; pos.len()];
    let dep = vm
        .deposit(Method::Gauss, &ParticleSet::new(&pos, &rad))
        .unwrap();
    let free = vm.voidage(&dep, None).unwrap();
    let clipped = vm.voidage(&dep, Some(0.4)).unwrap();
    assert!(clipped.clipped_cells > 0);
    let solid = |e: &[f64]| {
        e.iter()
            .zip(vm.cell_volumes())
            .map(|(e, v)| (1.0 - e) * v)
            .sum::<f64>()
    };
    let total: f64 = rad.iter().map(|&r| ball_volume(r)).sum();
    assert!((solid(&free.epsilon) - total).abs() < 1e-12 * total);
    let restored = solid(&clipped.epsilon) + clipped.clipped_volume;
    assert!(
        (restored - total).abs() < 1e-12 * total,
        "{restored} vs {total}"
    );
    assert!(clipped.epsilon.iter().all(|&e| e >= 0.4));
}
