//! In-process LIGGGHTS (feature `link`, full tier): the state is ordered by tag whatever the
//! creation order and LIGGGHTS's local (spatially sorted) order, deleted tags are left out, and
//! each particle receives the force given for it.
#![cfg(feature = "link")]

use couple::ParticleSide;
use liggghts::LiggghtsDem;
use mesh::v3::V3;
use rand::seq::SliceRandom;
use rand::SeedableRng;

#[test]
fn particles_created_in_random_order_keep_their_tags_and_forces() {
    if !testkit::tool("liggghts") {
        return;
    }
    // 27 sites of a 3×3×3 grid (5 mm apart: no contacts), created in a shuffled order, so tag k
    // sits at sites[k − 1]; LIGGGHTS sorts its atoms spatially every step
    let mut sites: Vec<[f64; 3]> = (0..27)
        .map(|k| {
            let (i, j, l) = (k % 3, (k / 3) % 3, k / 9);
            [
                i as f64 * 0.005 - 0.005,
                j as f64 * 0.005 - 0.005,
                l as f64 * 0.005 - 0.005,
            ]
        })
        .collect();
    sites.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(7));
    let mut deck = String::from(
        "atom_style granular\natom_modify map array sort 1 0.002\ncommunicate single vel yes\n\
         boundary f f f\nnewton off\nunits si\n\
         region reg block -0.02 0.02 -0.02 0.02 -0.02 0.02 units box\ncreate_box 1 reg\n\
         neighbor 0.0005 bin\nneigh_modify delay 0\n\
         fix m1 all property/global youngsModulus peratomtype 5.e6\n\
         fix m2 all property/global poissonsRatio peratomtype 0.45\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         pair_style gran model hertz tangential history\npair_coeff * *\ntimestep 0.00001\n",
    );
    for s in &sites {
        deck.push_str(&format!(
            "create_atoms 1 single {} {} {} units box\n",
            s[0], s[1], s[2]
        ));
    }
    deck.push_str(
        "set group all diameter 0.001 density 2000\ngroup gone id 4 9\n\
         delete_atoms group gone compress no\n\
         fix cfd all couple/cfd couple_every 100 mpi\nfix cfd2 all couple/cfd/force/implicit\n\
         fix integr all nve/sphere\n",
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("in.tags");
    std::fs::write(&path, deck).unwrap();
    let universe = mpi::initialize().expect("MPI initialised once");
    let mut lig = LiggghtsDem::open(&universe.world(), &path, dir.path(), &[]).unwrap();
    assert!(lig.skipped_runs().is_empty());
    assert_eq!(lig.max_tag(), 27);
    let expected: Vec<u64> = (1..=27).filter(|t| *t != 4 && *t != 9).collect();
    let s = lig.state();
    assert_eq!(s.ids, expected);
    for (i, &t) in s.ids.iter().enumerate() {
        assert_eq!(s.position[i], V3::from(sites[t as usize - 1]), "tag {t}");
    }
    // a force that identifies the tag: F = (t, −2t, 3t)·1e-7 N, no drag, no gravity
    let n = s.len();
    let f: Vec<V3> = s
        .ids
        .iter()
        .map(|&t| {
            V3::new(
                t as f64 * 1e-7,
                -2.0 * t as f64 * 1e-7,
                3.0 * t as f64 * 1e-7,
            )
        })
        .collect();
    lig.set_forces(&f, &vec![0.0; n], &vec![V3::zeros(); n])
        .unwrap();
    lig.advance(100).unwrap();
    lig.advance(100).unwrap();
    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9;
    let t = 200.0 * 1e-5;
    let s = lig.state();
    assert_eq!(s.ids, expected);
    for (i, &tag) in s.ids.iter().enumerate() {
        for c in 0..3 {
            // constant force: velocity Verlet is exact, v = F t / m
            let v = f[i][c] / m * t;
            assert!(
                approx::abs_diff_eq!(s.velocity[i][c], v, epsilon = 1e-12 * v.abs()),
                "tag {tag}: {:?}",
                s.velocity[i]
            );
            let x = sites[tag as usize - 1][c] + 0.5 * f[i][c] / m * t * t;
            assert!(
                approx::abs_diff_eq!(s.position[i][c], x, epsilon = 1e-15),
                "tag {tag}: {:?}",
                s.position[i]
            );
        }
    }
}
