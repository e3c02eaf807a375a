//! What the co-simulation tests share (`mod common;` in each).

/// Whether a co-simulation test can run: the programs `tools` and grainPisoFoam
/// (`openfoam-cases/solver/build.sh`). Without them the test is skipped with a note, but under
/// `FOAMGRAIN_FULL=1` a missing one fails it (`testkit::tool`).
#[allow(dead_code)]
pub fn cosim_ready(tools: &[&str]) -> bool {
    for tool in tools {
        if !testkit::tool(tool) {
            return false;
        }
    }
    let solver = runner::backend::solver_path().map(|p| p.is_file());
    if !matches!(solver, Ok(true)) {
        assert!(
            !testkit::full_tier(),
            "FOAMGRAIN_FULL=1 but grainPisoFoam is not built ({solver:?}; \
             openfoam-cases/solver/build.sh)"
        );
        eprintln!("note: grainPisoFoam not built: skipping");
        return false;
    }
    true
}

/// `command` with the environment a co-simulation needs: Debian's OpenFOAM
/// (`WM_PROJECT_DIR`, unless set) and Open MPI as root with oversubscription. (`dying_rank`
/// sets its own, with its log files.)
#[allow(dead_code)]
pub fn cosim_env(command: &mut std::process::Command) -> &mut std::process::Command {
    command
        .env(
            "WM_PROJECT_DIR",
            std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into()),
        )
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
}

/// Coupler rank 0's cells held and parts cut in a run's `postProcessing/ranks.csv` (the
/// first row, which must be rank 0's; a panic with the file otherwise).
#[allow(dead_code)]
pub fn rank_0_part(case: &std::path::Path) -> (usize, u64, String) {
    let file = case.join("postProcessing/ranks.csv");
    let text = std::fs::read_to_string(&file).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(row[col("rank")], "0", "{text}");
    let held = row[col("cells_held")].parse().unwrap();
    let cuts = row[col("mesh_cuts")].parse().unwrap_or(0);
    (held, cuts, text)
}
