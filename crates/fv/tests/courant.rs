//! The Courant number from face fluxes against the line Debian's pisoFoam v1912 prints
//! (`Courant Number mean: … max: …`) when it continues `tests/fixtures/fv/channel-keps` from
//! its time 5 one step (`log.pisoFoam-courant`, computed from `5/phi` with Δt 0.05 s).

#[test]
fn channel_courant_number_is_pisofoams() {
    let case = testkit::fixture("fv/channel-keps");
    let mesh = foam::Case::open(&case).unwrap().read_mesh().unwrap();
    let g = fv::geometry::FvGeometry::new(&mesh).unwrap();
    let phi = fv::fields::read_phi(&case.join("5/phi"), &g).unwrap();
    let co = fv::courant::courant(&g, &phi, 0.05);
    let log = std::fs::read_to_string(case.join("log.pisoFoam-courant")).unwrap();
    let line = log
        .lines()
        .find(|l| l.starts_with("Courant Number mean:"))
        .unwrap();
    let words: Vec<&str> = line.split_whitespace().collect();
    let (mean, max): (f64, f64) = (words[3].parse().unwrap(), words[5].parse().unwrap());
    // Sums over the same faces in another order: round-off only.
    assert!(
        (co.mean - mean).abs() <= 1e-12 * mean,
        "{} vs {mean}",
        co.mean
    );
    assert!((co.max - max).abs() <= 1e-12 * max, "{} vs {max}", co.max);
}
