//! Preparing the OpenFOAM case for a linked run and the command that starts each solver rank:
//! `decomposePar` (writing a `simple` `system/decomposeParDict` when the case has none),
//! `reconstructPar`, the solver's log files and the shell line MPI_Comm_spawn runs.

use crate::LinkError;
use foam::{Case, PolyMesh};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The solver's log: `CASE/log.grainPisoFoam` serially, `CASE/log.grainPisoFoam.<rank>` on
/// several ranks (each rank writes its own stdout and stderr there).
pub fn log_path(case: &Path, ranks: usize, rank: usize) -> PathBuf {
    if ranks == 1 {
        case.join("log.grainPisoFoam")
    } else {
        case.join(format!("log.grainPisoFoam.{rank}"))
    }
}

/// The file in which the shell that becomes solver rank `rank` writes its pid (before it
/// execs the solver, so that a solver dying before its handshake is noticed too).
pub fn pid_path(case: &Path, rank: usize) -> PathBuf {
    case.join(format!(".foam-link.pid.{rank}"))
}

/// `'text'` for `/bin/sh`, with single quotes escaped.
pub fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// The `/bin/sh -c` script each spawned rank runs: it records its pid, exports
/// `WM_PROJECT_DIR` (Debian's OpenFOAM needs it) and `FOAMGRAIN_LINK=1` (selects the solver's
/// `mpi` coupling source), then execs the solver — the same process, so the pid and the MPI
/// identity stay — with stdout and stderr in the rank's log.
pub fn launch_script(solver: &Path, case: &Path, ranks: usize, wm_project_dir: &str) -> String {
    launch_script_with(solver, case, ranks, wm_project_dir, false, None)
}

/// `script` (a [`launch_script_with`] line) that also exports `FOAMGRAIN_VORTICITY=1` when
/// `vorticity` and `FOAMGRAIN_DDT_U=1` when `ddt_u`, just before its `exec`: the solver then
/// replies ∇ × U and DU/Dt ([`crate::protocol`]). Without either, `script` unchanged.
pub fn with_field_requests(script: &str, vorticity: bool, ddt_u: bool) -> String {
    let mut exports = String::new();
    if vorticity {
        exports.push_str("export FOAMGRAIN_VORTICITY=1; ");
    }
    if ddt_u {
        exports.push_str("export FOAMGRAIN_DDT_U=1; ");
    }
    match script.rfind("exec ") {
        Some(at) if !exports.is_empty() => format!("{}{exports}{}", &script[..at], &script[at..]),
        _ => script.to_string(),
    }
}

/// As [`launch_script`]; with `heat` it also exports `FOAMGRAIN_HEAT=1`, which makes the
/// solver read `0/T` and solve the temperature equation (the protocol's heat blocks,
/// [`crate::protocol`]). With `ksl` (CFDEM's Ksl form, [`couple::ksl`]) it exports
/// `FOAMGRAIN_KSL='CFDEM <KslLimit> <maxAlpha>'`: the solver ranks form Ksl and Us of the
/// sparse exchange as CFDEM does from the ranks' sums (the protocol's Ksl columns). Without
/// either the line is [`launch_script`]'s.
pub fn launch_script_with(
    solver: &Path,
    case: &Path,
    ranks: usize,
    wm_project_dir: &str,
    heat: bool,
    ksl: Option<couple::ksl::CfdemKsl>,
) -> String {
    let q = |p: &Path| shell_quote(&p.to_string_lossy());
    let rank = "${OMPI_COMM_WORLD_RANK:-0}";
    let log = if ranks == 1 {
        q(&log_path(case, 1, 0))
    } else {
        format!("{}.{rank}", q(&case.join("log.grainPisoFoam")))
    };
    let parallel = if ranks > 1 { " -parallel" } else { "" };
    format!(
        "echo $$ > {pid}.{rank}; export WM_PROJECT_DIR={wm}; export FOAMGRAIN_LINK=1; \
         {heat}{ksl}exec {solver}{parallel} -case {case} > {log} 2>&1",
        heat = if heat {
            "export FOAMGRAIN_HEAT=1; "
        } else {
            ""
        },
        ksl = match ksl {
            Some(k) => format!(
                "export FOAMGRAIN_KSL='CFDEM {:?} {:?}'; ",
                k.limit, k.max_voidage
            ),
            None => String::new(),
        },
        pid = q(&case.join(".foam-link.pid")),
        wm = shell_quote(wm_project_dir),
        solver = q(solver),
        case = q(case),
    )
}

/// `deltaT` of `system/controlDict`, s.
pub fn control_delta_t(case: &Case) -> Result<f64, LinkError> {
    let dict = case.control_dict()?;
    let config = |message: String| LinkError::Config {
        path: case.root().join("system/controlDict"),
        message,
    };
    let dt = dict.f64("deltaT").map_err(|e| config(e.to_string()))?;
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(config(format!("deltaT {dt} must be > 0")));
    }
    Ok(dt)
}

/// The `simple` decomposition this crate writes when a case has no decomposeParDict: the
/// mesh's longest bounding-box axis cut into `ranks` slabs of equal cell counts.
pub fn simple_decomposition(points: &[[f64; 3]], ranks: usize) -> String {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let mut n = [1usize; 3];
    n[axis] = ranks;
    format!(
        "{}// Written by foamgrain's foam-link: {ranks} slabs along the longest axis.\n\
         numberOfSubdomains {ranks};\nmethod          simple;\n\
         coeffs          {{ n ({} {} {}); }}\n",
        foam::writer::ascii_header("dictionary", "system", "decomposeParDict"),
        n[0],
        n[1],
        n[2]
    )
}

/// What [`decompose`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decomposition {
    /// True when `system/decomposeParDict` was missing and this crate wrote one
    /// ([`simple_decomposition`]).
    pub wrote_dict: bool,
}

/// `numberOfSubdomains` of the case's `system/decomposeParDict` (`case` is the case root), or
/// `None` without that file; a dictionary without a valid count is an error naming it.
pub fn decomposed_ranks(case: &Path) -> Result<Option<usize>, LinkError> {
    let path = case.join("system/decomposeParDict");
    if !path.is_file() {
        return Ok(None);
    }
    let dict = foam::parse_file(&path)?.body;
    let config = |message: String| LinkError::Config {
        path: path.clone(),
        message,
    };
    let n = dict
        .label("numberOfSubdomains")
        .map_err(|e| config(e.to_string()))?;
    if n < 1 {
        return Err(config(format!(
            "numberOfSubdomains {n} is not a rank count"
        )));
    }
    Ok(Some(n as usize))
}

/// Decomposes `case` for `ranks` ranks with `decomposePar -force` (existing `processor*`
/// directories are replaced). A `system/decomposeParDict` with another `numberOfSubdomains`
/// is an error naming the file; without one, a `simple` one is written.
pub fn decompose(case: &Case, mesh: &PolyMesh, ranks: usize) -> Result<Decomposition, LinkError> {
    let path = case.root().join("system/decomposeParDict");
    let wrote_dict = if let Some(n) = decomposed_ranks(case.root())? {
        if n != ranks {
            return Err(LinkError::Config {
                path,
                message: format!(
                    "numberOfSubdomains {n}, but the link was asked for {ranks} ranks (give \
                     --np {n}, or leave --np out to use the dictionary's count)"
                ),
            });
        }
        false
    } else {
        foam::write_atomic(&path, simple_decomposition(&mesh.points, ranks).as_bytes())?;
        true
    };
    run_tool(case.root(), "decomposePar", &["-force"])?;
    Ok(Decomposition { wrote_dict })
}

/// `reconstructPar -time <the times in processor0/ that the case root lacks>`: the time
/// directories the decomposed run wrote, back into the case (about a second per written time
/// for the Ergun mesh). Nothing to do when there are none.
pub fn reconstruct(case: &Path) -> Result<(), LinkError> {
    let root: Vec<String> = Case::open(case)?
        .times()?
        .into_iter()
        .map(|t| t.name)
        .collect();
    let written: Vec<String> = Case::open(case.join("processor0"))?
        .times()?
        .into_iter()
        .map(|t| t.name)
        .filter(|name| !root.contains(name))
        .collect();
    if written.is_empty() {
        return Ok(());
    }
    run_tool(case, "reconstructPar", &["-time", &written.join(",")])
}

/// The `WM_PROJECT_DIR` for Debian's OpenFOAM (the environment's, else `/usr/share/openfoam`).
pub fn wm_project_dir() -> String {
    std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into())
}

fn run_tool(case: &Path, program: &str, args: &[&str]) -> Result<(), LinkError> {
    let out = Command::new(program)
        .env("WM_PROJECT_DIR", wm_project_dir())
        .arg("-case")
        .arg(case)
        .args(args)
        .output()
        .map_err(|e| LinkError::Parameter(format!("cannot run {program}: {e}")))?;
    if out.status.success() {
        return Ok(());
    }
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    Err(LinkError::Tool {
        program: program.into(),
        case: case.to_owned(),
        status: out.status.to_string(),
        output: tail(&text, 20),
    })
}

/// The last `lines` lines of `text`.
pub fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_launch_line_quotes_paths_and_logs_per_rank() {
        let s = launch_script(
            Path::new("/opt/bin/grainPisoFoam"),
            Path::new("/tmp/it's a case"),
            2,
            "/usr/share/openfoam",
        );
        assert_eq!(
            s,
            "echo $$ > '/tmp/it'\\''s a case/.foam-link.pid'.${OMPI_COMM_WORLD_RANK:-0}; \
             export WM_PROJECT_DIR='/usr/share/openfoam'; export FOAMGRAIN_LINK=1; \
             exec '/opt/bin/grainPisoFoam' -parallel -case '/tmp/it'\\''s a case' \
             > '/tmp/it'\\''s a case/log.grainPisoFoam'.${OMPI_COMM_WORLD_RANK:-0} 2>&1"
        );
        let plain = launch_script_with(Path::new("/s"), Path::new("/c"), 1, "/w", false, None);
        assert_eq!(with_field_requests(&plain, false, false), plain);
        let both = with_field_requests(&plain, true, true);
        assert!(both.contains(
            "export FOAMGRAIN_LINK=1; export FOAMGRAIN_VORTICITY=1; export FOAMGRAIN_DDT_U=1; \
             exec '/s'"
        ));
        assert!(with_field_requests(&plain, false, true)
            .contains("export FOAMGRAIN_LINK=1; export FOAMGRAIN_DDT_U=1; exec '/s'"));
        let heat = launch_script_with(Path::new("/s"), Path::new("/c"), 1, "/w", true, None);
        assert!(heat.contains("export FOAMGRAIN_LINK=1; export FOAMGRAIN_HEAT=1; exec '/s'"));
        let ksl = couple::ksl::CfdemKsl {
            limit: 1e4,
            max_voidage: 0.999,
            averaging: couple::ksl::UsAveraging::Dense,
        };
        let s = launch_script_with(Path::new("/s"), Path::new("/c"), 1, "/w", false, Some(ksl));
        assert!(
            s.contains("export FOAMGRAIN_LINK=1; export FOAMGRAIN_KSL='CFDEM 10000.0 0.999'; exec"),
            "{s}"
        );
        let serial = launch_script(Path::new("/s"), Path::new("/c"), 1, "/w");
        assert!(serial.ends_with("exec '/s' -case '/c' > '/c/log.grainPisoFoam' 2>&1"));
        assert_eq!(
            log_path(Path::new("/c"), 2, 1),
            Path::new("/c/log.grainPisoFoam.1")
        );
        assert_eq!(
            pid_path(Path::new("/c"), 1),
            Path::new("/c/.foam-link.pid.1")
        );
    }

    #[test]
    fn the_written_decomposition_cuts_the_longest_axis() {
        let points = [[0.0, 0.0, 0.0], [0.01, 0.05, 0.02]];
        let text = simple_decomposition(&points, 3);
        assert!(text.contains("numberOfSubdomains 3;"), "{text}");
        assert!(text.contains("n (1 3 1);"), "{text}");
        let dict = foam::parse_bytes(text.as_bytes(), Path::new("decomposeParDict"))
            .unwrap()
            .body;
        assert_eq!(dict.word("method").unwrap(), "simple");
    }

    #[test]
    fn tail_keeps_the_last_lines() {
        assert_eq!(tail("a\nb\nc\n", 2), "b\nc");
        assert_eq!(tail("a", 5), "a");
    }
}
