//! LAMMPS data files for `atom_style granular` (`read_data`, `write_data`): a header with
//! `N atoms`, `N atom types`, `xlo xhi`, `ylo yhi`, `zlo zhi`, then the `Atoms` section
//! (`id type diameter density x y z [ix iy iz]`) and optionally `Velocities`
//! (`id vx vy vz omegax omegay omegaz`), as Debian's LIGGGHTS 3.8.0 writes them.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use mesh::v3::V3;

use crate::particles::{NewParticle, Particles};

/// Contents of a data file.
#[derive(Debug, Clone, PartialEq)]
pub struct DataFile {
    /// Number of atom types.
    pub ntypes: usize,
    /// Box lower corner (m).
    pub lo: V3,
    /// Box upper corner (m).
    pub hi: V3,
    /// The particles (with their ids).
    pub particles: Vec<NewParticle>,
}

/// Reads a data file; errors name the file and line.
pub fn read_data(path: &Path) -> Result<DataFile, String> {
    let src = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read data file {}: {e}", path.display()))?;
    parse_data(&src).map_err(|(line, m)| format!("{}:{line}: {m}", path.display()))
}

fn parse_data(src: &str) -> Result<DataFile, (usize, String)> {
    let lines: Vec<&str> = src.lines().collect();
    let mut natoms = None;
    let mut ntypes = None;
    let mut lo = V3::zeros();
    let mut hi = V3::zeros();
    let num = |k: usize, w: &str| -> Result<f64, (usize, String)> {
        w.parse::<f64>()
            .map_err(|_| (k + 1, format!("`{w}` is not a number")))
    };
    // header: from line 2 up to the first section name
    let mut k = 1;
    while k < lines.len() {
        let l = lines[k].split('#').next().unwrap_or("").trim();
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.is_empty() {
            k += 1;
            continue;
        }
        if w[0].chars().next().is_some_and(char::is_alphabetic) {
            break;
        }
        match &w[1..] {
            ["atoms"] => natoms = Some(num(k, w[0])? as usize),
            ["atom", "types"] => ntypes = Some(num(k, w[0])? as usize),
            [_, a, b] if a.len() == 3 && b.len() == 3 && a.ends_with("lo") && b.ends_with("hi") => {
                let axis = match &a[..1] {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    _ => return Err((k + 1, format!("unknown header line `{l}`"))),
                };
                lo[axis] = num(k, w[0])?;
                hi[axis] = num(k, w[1])?;
            }
            _ => return Err((k + 1, format!("unsupported header line `{l}`"))),
        }
        k += 1;
    }
    let natoms = natoms.ok_or((1, "no `N atoms` line".to_string()))?;
    let ntypes = ntypes.ok_or((1, "no `N atom types` line".to_string()))?;
    let mut particles: Vec<NewParticle> = Vec::with_capacity(natoms);
    let mut velocities: HashMap<u64, (V3, V3)> = HashMap::new();
    while k < lines.len() {
        let name = lines[k].split('#').next().unwrap_or("").trim().to_string();
        if name.is_empty() {
            k += 1;
            continue;
        }
        if name != "Atoms" && name != "Velocities" {
            return Err((k + 1, format!("unsupported section `{name}`")));
        }
        k += 1;
        let mut read = 0;
        while read < natoms {
            let l = lines
                .get(k)
                .ok_or((
                    k,
                    format!("section {name} ends after {read} of {natoms} lines"),
                ))?
                .split('#')
                .next()
                .unwrap_or("")
                .trim();
            k += 1;
            if l.is_empty() {
                continue;
            }
            let w: Vec<&str> = l.split_whitespace().collect();
            let v: Vec<f64> = w.iter().map(|s| num(k - 1, s)).collect::<Result<_, _>>()?;
            let id_ok = v[0] >= 1.0 && v[0].fract() == 0.0;
            if !id_ok {
                return Err((k, format!("bad atom id `{}`", w[0])));
            }
            if name == "Atoms" {
                if !(v.len() == 7 || v.len() == 10) {
                    return Err((
                        k,
                        format!(
                            "{} values: `id type diameter density x y z [ix iy iz]` expected \
                             (atom_style granular)",
                            v.len()
                        ),
                    ));
                }
                if v[1] < 1.0 || v[1].fract() != 0.0 {
                    return Err((k, format!("bad atom type `{}`", w[1])));
                }
                particles.push(NewParticle {
                    id: v[0] as u64,
                    atom_type: v[1] as u32,
                    x: V3::new(v[4], v[5], v[6]),
                    v: V3::zeros(),
                    omega: V3::zeros(),
                    radius: 0.5 * v[2],
                    density: v[3],
                });
            } else {
                if v.len() != 7 {
                    return Err((
                        k,
                        format!("{} values: `id vx vy vz wx wy wz` expected", v.len()),
                    ));
                }
                velocities.insert(
                    v[0] as u64,
                    (V3::new(v[1], v[2], v[3]), V3::new(v[4], v[5], v[6])),
                );
            }
            read += 1;
        }
    }
    if particles.len() != natoms {
        return Err((
            lines.len(),
            format!("{} atoms declared, {} read", natoms, particles.len()),
        ));
    }
    for p in &mut particles {
        if let Some(&(v, w)) = velocities.get(&p.id) {
            p.v = v;
            p.omega = w;
        }
    }
    Ok(DataFile {
        ntypes,
        lo,
        hi,
        particles,
    })
}

/// Writes the particles as a granular data file (full precision).
pub fn write_data(
    path: &Path,
    p: &Particles,
    ntypes: usize,
    lo: V3,
    hi: V3,
    step: u64,
) -> std::io::Result<()> {
    let mut s = String::new();
    let _ = writeln!(s, "LAMMPS data file via foamgrain dem, timestep = {step}\n");
    let _ = writeln!(s, "{} atoms\n{} atom types\n", p.len(), ntypes);
    for (k, a) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(s, "{:e} {:e} {a}lo {a}hi", lo[k], hi[k]);
    }
    s.push_str("\nAtoms\n\n");
    for i in 0..p.len() {
        let x = p.x[i];
        let _ = writeln!(
            s,
            "{} {} {:e} {:e} {:e} {:e} {:e} 0 0 0",
            p.id[i],
            p.atom_type[i],
            2.0 * p.radius[i],
            p.density[i],
            x[0],
            x[1],
            x[2]
        );
    }
    s.push_str("\nVelocities\n\n");
    for i in 0..p.len() {
        let (v, w) = (p.v[i], p.omega[i]);
        let _ = writeln!(
            s,
            "{} {:e} {:e} {:e} {:e} {:e} {:e}",
            p.id[i], v[0], v[1], v[2], w[0], w[1], w[2]
        );
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    atomic_write::write_atomically(path, |w| std::io::Write::write_all(w, s.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The file Debian's LIGGGHTS 3.8.0 wrote with `write_data` (two atoms after 10 steps).
    const LIGGGHTS: &str = "LAMMPS data file via write_data, version Version LIGGGHTS-PUBLIC 3.8.0, timestep = 10

2 atoms
2 atom types

0.0000000000000000e+00 1.0000000000000000e-02 xlo xhi
0.0000000000000000e+00 1.0000000000000000e-02 ylo yhi
0.0000000000000000e+00 1.0000000000000000e-02 zlo zhi

Atoms

2 2 1.0000000000000000e-04 3.0000000000000000e+03 2.0100000000000014e-03 5.0000000000000001e-03 5.0000000000000001e-03 0 0 0
1 1 1.0000000000000000e-04 3.0000000000000000e+03 5.0100000000000014e-03 5.0000000000000001e-03 5.0000000000000001e-03 0 0 0

Velocities

2 1.0000000000000001e-01 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00
1 1.0000000000000001e-01 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00
";

    #[test]
    fn reads_liggghts_and_round_trips() {
        let d = parse_data(LIGGGHTS).unwrap();
        assert_eq!(d.ntypes, 2);
        assert_eq!(d.hi, V3::repeat(0.01));
        assert_eq!(d.particles[0].id, 2);
        assert_eq!(d.particles[0].atom_type, 2);
        assert_eq!(d.particles[0].radius, 5e-5);
        assert_eq!(
            d.particles[1].x[0],
            "5.0100000000000014e-03".parse::<f64>().unwrap()
        );
        assert_eq!(d.particles[1].v, V3::new(0.1, 0.0, 0.0));
        let mut p = Particles::default();
        for q in &d.particles {
            p.push(*q, 2).unwrap();
        }
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("a/b.data");
        write_data(&f, &p, 2, d.lo, d.hi, 10).unwrap();
        assert_eq!(read_data(&f).unwrap(), d);
        let e = parse_data(&LIGGGHTS.replace("2 atoms", "3 atoms")).unwrap_err();
        assert!(e.1.contains("Velocities") || e.1.contains("3"), "{e:?}");
    }
}
