//! Reads the settings of OpenFOAM cases as the native fluid would (`system/controlDict`,
//! `fvSchemes`, `fvSolution`, `constant/transportProperties`, `turbulenceProperties`) and
//! prints what it would run, or why it refuses the case (the file and the key).
//!
//! `cargo run -p fv --example check_settings -- CASE…` (a case is the folder holding
//! `system/` and `constant/`, e.g. a CFDEM tutorial's `CFD/`).

fn main() {
    let mut refused = 0;
    for dir in std::env::args().skip(1) {
        let result = foam::Case::open(std::path::Path::new(&dir))
            .map_err(fv::FvError::from)
            .and_then(|case| fv::settings::Settings::read(&case));
        match result {
            Ok(s) => println!(
                "ok       {dir}: div(phi,U) {}{:?}; p {:?}, pFinal {:?}, U {:?}; PISO {} correctors, {} non-orthogonal",
                if s.bounded_convection { "bounded " } else { "" },
                s.convection,
                s.p_solver.method,
                s.p_final.method,
                s.u_solver.method,
                s.n_correctors,
                s.n_non_orth
            ),
            Err(e) => {
                refused += 1;
                println!("refused  {dir}: {e}");
            }
        }
    }
    std::process::exit(if refused > 0 { 1 } else { 0 });
}
