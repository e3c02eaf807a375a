//! Property tests of the exact kernels: bounds, additivity under splitting a box, agreement of
//! the corner form with the face-flux form, and tets of a split box.

use mesh::v3::V3;
use proptest::prelude::*;
use voidage::*;

fn coord() -> impl Strategy<Value = f64> {
    -2.0..2.0f64
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn box_share_is_bounded_and_additive(
        c in prop::array::uniform3(coord()),
        r in 0.01..2.0f64,
        lo in prop::array::uniform3(coord()),
        size in prop::array::uniform3(0.01..3.0f64),
        axis in 0usize..3,
        t in 0.0..1.0f64,
    ) {
        let hi: V3 = V3::from_fn(|a, _| lo[a] + size[a]);
        let v = sphere_box_volume(c, r, lo, hi);
        let vb = ball_volume(r);
        // The kernel forms the box in unit-ball coordinates, (lo − c)/r: for a box much smaller
        // than its distance from the centre, its edges carry a relative rounding of about
        // 1e-16·|lo − c|/size (≤ 1e-14 here), so the box-volume bound holds to 1e-13 (a fixed
        // 1e-15 failed on c = (−1.68, 1.24, 1.48), r = 0.92, a 0.01 box inside the ball:
        // 1.0000000000000027e-6 vs 1.0000000000000002e-6).
        prop_assert!(v >= 0.0 && v <= vb.min(size.iter().product()) * (1.0 + 1e-13));
        // Split the box at a plane: the halves add up.
        let cut = lo[axis] + t * size[axis];
        let mut hi1 = hi;
        hi1[axis] = cut;
        let mut lo2 = lo;
        lo2[axis] = cut;
        let parts = sphere_box_volume(c, r, lo, hi1) + sphere_box_volume(c, r, lo2, hi);
        prop_assert!((parts - v).abs() < 1e-13 * vb, "{} vs {}", parts, v);
    }

    #[test]
    fn tet_kernel_tiles_a_box(
        c in prop::array::uniform3(coord()),
        r in 0.05..2.0f64,
        lo in prop::array::uniform3(coord()),
        size in prop::array::uniform3(0.05..3.0f64),
    ) {
        // Five-tet split of the box (corner tets around the central one).
        let p = |i: usize| V3::from_fn(|a, _| lo[a] + size[a] * ((i >> a) & 1) as f64);
        let tets = [[0, 1, 2, 4], [3, 1, 2, 7], [5, 1, 4, 7], [6, 2, 4, 7], [1, 2, 4, 7]];
        let mut sum = 0.0;
        let mut vol = 0.0;
        for t in tets {
            let mut q: [V3; 4] = t.map(p);
            if mesh::tet_volume(&q) < 0.0 {
                q.swap(2, 3);
            }
            vol += mesh::tet_volume(&q);
            sum += sphere_tet_volume(c, r, &q);
        }
        let bv: f64 = size.iter().product();
        prop_assert!((vol - bv).abs() < 1e-13 * bv);
        let hi: V3 = V3::from_fn(|a, _| lo[a] + size[a]);
        let reference = sphere_box_volume(c, r, lo, hi);
        prop_assert!((sum - reference).abs() < 1e-13 * ball_volume(r), "{} vs {}", sum, reference);
    }
}
