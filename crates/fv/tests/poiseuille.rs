//! Steady plane Poiseuille flow between no-slip plates driven by a fixed pressure drop
//! (inlet/outlet `fixedValue` p, `zeroGradient` U;
//! Δt at the diffusion number ν Δt/Δy² = 3.2 — PISO with 2 correctors diverges near 13), against the closed form
//! u(y) = G y (H − y) / (2ν), G = Δp/L (kinematic), u_max = G H²/(8ν).

mod common;
use common::{write_case, CaseSpec, PatchSpec};

/// Max |u − u_exact| / u_max over the cells, for `ny` cells across the channel.
fn poiseuille_error(ny: usize) -> f64 {
    let (h, l, nu, dp) = (1.0, 1.0, 1.0, 8.0);
    let dir = tempfile::tempdir().unwrap();
    let m = mesh::build::uniform_box([0.0; 3], [l, h, 0.1], [4, ny, 1]);
    let wall = "type noSlip;";
    let patches = [
        PatchSpec {
            name: "xMin",
            patch_type: "patch",
            u: "type zeroGradient;",
            p: &format!("type fixedValue; value uniform {dp};"),
        },
        PatchSpec {
            name: "xMax",
            patch_type: "patch",
            u: "type zeroGradient;",
            p: "type fixedValue; value uniform 0;",
        },
        PatchSpec {
            name: "yMin",
            patch_type: "wall",
            u: wall,
            p: "type zeroGradient;",
        },
        PatchSpec {
            name: "yMax",
            patch_type: "wall",
            u: wall,
            p: "type zeroGradient;",
        },
        PatchSpec {
            name: "zMin",
            patch_type: "empty",
            u: "type empty;",
            p: "type empty;",
        },
        PatchSpec {
            name: "zMax",
            patch_type: "empty",
            u: "type empty;",
            p: "type empty;",
        },
    ];
    let spec = CaseSpec {
        nu,
        rho: 1.0,
        delta_t: 3.2 / (ny * ny) as f64,
        end_time: 2.0,
        ddt: "Euler",
        div: "Gauss linear",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    write_case(dir.path(), m, &patches, &spec);
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    for _ in 0..(spec.end_time / spec.delta_t).round() as usize {
        fluid.advance(spec.delta_t).unwrap();
    }
    let g = fluid.geometry();
    let gpl = dp / l;
    let umax = gpl * h * h / (8.0 * nu);
    g.c.iter()
        .zip(fluid.u())
        .map(|(c, u)| {
            let exact = gpl * c[1] * (h - c[1]) / (2.0 * nu);
            (u[0] - exact).abs().max(u[1].abs()) / umax
        })
        .fold(0.0, f64::max)
}

#[test]
fn plane_poiseuille_matches_the_parabola_with_second_order_convergence() {
    let e: Vec<f64> = [6, 12, 24].iter().map(|&n| poiseuille_error(n)).collect();
    eprintln!(
        "Poiseuille max error / u_max: ny=6 {:.3e}, 12 {:.3e}, 24 {:.3e}",
        e[0], e[1], e[2]
    );
    assert!(e[2] < 2e-3, "{e:?}");
    let order = (e[1] / e[2]).log2();
    assert!(order > 1.9 || e[2] < 1e-10, "order {order} ({e:?})");
}
