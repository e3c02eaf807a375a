//! LIGGGHTS in-process (feature `link`): Debian's libliggghts driven through its library
//! interface on an MPI communicator the caller owns.
//!
//! [`LiggghtsDem::open`] checks the deck ([`crate::deck`]), writes a copy without its trailing
//! `run` commands (`<deck>.coupled` in the working directory, same line numbers), opens
//! LIGGGHTS on a duplicate of the communicator with `-log log.coupled -screen
//! screen.coupled` in the working directory (`-screen none` segfaults LIGGGHTS when it inserts
//! particles), runs the copy and `run 0` (so the coupling fix is initialised and the particles
//! can be read before the first step).
//!
//! Each exchange: [`ParticleSide::advance`] issues `run N` the first time and `run N pre no
//! post no` after; the state is then read from the atoms this rank owns (LIGGGHTS's `nlocal`
//! atoms: `id` (the tags), `x`, `v`, `radius`, `density` through `lammps_extract_atom`), ordered by tag.
//! No rank ever holds another rank's particles: on N ranks each coupler rank sees exactly the
//! particles its LIGGGHTS rank owns, and a particle is owned by one rank only (ghost copies are
//! not read), so nothing is deposited twice. [`ParticleSide::set_forces`] maps (F_ext, β, u_f)
//! onto the per-atom arrays `dragforce`, `Ksl`, `uf` of the coupling fix's `property/atom`
//! fixes ([`crate::forces`]), written in place for the owned atoms (`lammps_extract_fix`), so
//! nothing is communicated. Atoms do not move between the read and the write (both happen
//! between two runs), so the local indices stay valid; they are read again after every run.
//!
//! # Process-wide effects
//! LIGGGHTS resolves the deck's relative paths (read_data, dumps) against the process's
//! current directory, so every call into it runs with the current directory set to the
//! working directory and restored afterwards: no other thread may rely on the current
//! directory meanwhile. Any LIGGGHTS error calls `exit`: an `atexit` hook then prints the
//! tail of the screen file to stderr, so the run ends with LIGGGHTS's message.

use std::ffi::{c_char, c_void, CString};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, Once};

use couple::{ParticleSide, ParticleState, SideError};
use mesh::v3::V3;
use mpi::collective::CommunicatorCollectives;
use mpi::raw::AsRaw;
use mpi::topology::{Communicator, SimpleCommunicator};

use crate::deck::{CouplingDeck, DataCoupling, SkippedRun};
use crate::error::LiggghtsError;
use crate::ffi;
use crate::forces::{force_fields, ForceFields, ForceMode};
use crate::particles::Particles;
use crate::program::{absolute, log_tail, TAIL_LINES};

/// LIGGGHTS in this process (module docs).
pub struct LiggghtsDem {
    lmp: *mut c_void,
    comm: SimpleCommunicator,
    workdir: PathBuf,
    mode: ForceMode,
    skipped: Vec<SkippedRun>,
    ran: bool,
    dt: f64,
    step: i64,
    maxtag: usize,
    particles: Particles,
    /// LIGGGHTS's local index of each state entry (state order = tag order).
    local: Vec<usize>,
    fields: ForceFields,
    /// Whether the deck exchanges heat (`couple/cfd/convection`): `Temp` is read with the
    /// particles and `convectiveHeatFlux` written by [`ParticleSide::set_heat_flux`].
    heat: bool,
}

static EXIT_HOOK: Once = Once::new();
static IN_LIGGGHTS: AtomicBool = AtomicBool::new(false);
static SCREEN: Mutex<Option<PathBuf>> = Mutex::new(None);

extern "C" fn report_exit() {
    if IN_LIGGGHTS.load(Ordering::SeqCst) {
        if let Ok(Some(screen)) = SCREEN.lock().map(|s| s.clone()) {
            eprintln!(
                "error: LIGGGHTS ended the process; last lines of {}:\n{}",
                screen.display(),
                log_tail(&screen, TAIL_LINES)
            );
        }
    }
}

/// While alive: the current directory is the working directory and the exit hook is armed.
struct InLiggghts {
    previous: PathBuf,
}

impl InLiggghts {
    fn enter(workdir: &Path) -> Result<InLiggghts, LiggghtsError> {
        let previous = std::env::current_dir().map_err(|e| LiggghtsError::io(".", e))?;
        std::env::set_current_dir(workdir).map_err(|e| LiggghtsError::io(workdir, e))?;
        IN_LIGGGHTS.store(true, Ordering::SeqCst);
        Ok(InLiggghts { previous })
    }
}

impl Drop for InLiggghts {
    fn drop(&mut self) {
        IN_LIGGGHTS.store(false, Ordering::SeqCst);
        let _ = std::env::set_current_dir(&self.previous);
    }
}

fn cstr(s: &str) -> CString {
    CString::new(s).expect("no NUL in LIGGGHTS names and commands")
}

impl LiggghtsDem {
    /// Opens LIGGGHTS on (a duplicate of) `comm`, runs `deck` up to its trailing `run`
    /// commands in `workdir` with the `-var` values `vars`, and reads the particles. Every
    /// rank of `comm` must call it (and every other method) together.
    pub fn open(
        comm: &SimpleCommunicator,
        deck: &Path,
        workdir: &Path,
        vars: &[(String, String)],
    ) -> Result<LiggghtsDem, LiggghtsError> {
        let d = CouplingDeck::read(deck, vars)?;
        if let DataCoupling::File(prefix) = &d.data_coupling {
            return Err(LiggghtsError::Deck {
                file: deck.to_path_buf(),
                line: d.couple_line,
                message: format!(
                    "`file {prefix}`: in-process coupling needs `mpi` (or use FileDem, which \
                     rewrites the line itself)"
                ),
            });
        }
        d.check_inputs(workdir)?;
        d.check_ranks(comm.size() as usize)?;
        let workdir = absolute(workdir)?;
        let name = deck
            .file_name()
            .map_or("deck".into(), |n| n.to_string_lossy().into_owned());
        let copy = workdir.join(format!("{name}.coupled"));
        if comm.rank() == 0 {
            std::fs::write(&copy, d.without_runs()).map_err(|e| LiggghtsError::io(&copy, e))?;
        }
        comm.barrier();
        let log = workdir.join("log.coupled");
        let screen = workdir.join("screen.coupled");
        let mut args = vec![
            "liggghts".to_string(),
            "-log".into(),
            log.display().to_string(),
            "-screen".into(),
            screen.display().to_string(),
            crate::program::SEED_TOLERANT.into(),
        ];
        for (k, v) in vars {
            args.extend(["-var".to_string(), k.clone(), v.clone()]);
        }
        let cargs: Vec<CString> = args.iter().map(|a| cstr(a)).collect();
        let mut argv: Vec<*mut c_char> = cargs.iter().map(|a| a.as_ptr() as *mut c_char).collect();
        *SCREEN.lock().unwrap_or_else(|e| e.into_inner()) = Some(screen.clone());
        EXIT_HOOK.call_once(|| unsafe {
            ffi::atexit(report_exit);
        });
        let comm = comm.duplicate();
        let mut lmp: *mut c_void = std::ptr::null_mut();
        let mode = if d.force.implicit {
            ForceMode::Implicit
        } else {
            ForceMode::FrozenAtExchange
        };
        let mut side = {
            let _in = InLiggghts::enter(&workdir)?;
            let copy_c = cstr(&copy.display().to_string());
            unsafe {
                ffi::lammps_open(
                    argv.len() as i32,
                    argv.as_mut_ptr(),
                    comm.as_raw(),
                    &mut lmp,
                );
                ffi::lammps_file(lmp, copy_c.as_ptr());
                ffi::lammps_command(lmp, cstr("run 0").as_ptr());
            }
            LiggghtsDem {
                lmp,
                comm,
                workdir,
                mode,
                skipped: d.skipped_runs.clone(),
                ran: false,
                dt: 0.0,
                step: 0,
                maxtag: 0,
                particles: Particles::default(),
                local: Vec::new(),
                fields: ForceFields::default(),
                heat: d.convection.is_some(),
            }
        };
        if side.heat {
            side.particles.temperature = Some(Vec::new());
        }
        side.refresh()?;
        Ok(side)
    }

    /// The `run` commands of the deck that were skipped (the coupler runs the steps).
    pub fn skipped_runs(&self) -> &[SkippedRun] {
        &self.skipped
    }

    /// How the deck's force fix takes the force.
    pub fn force_mode(&self) -> ForceMode {
        self.mode
    }

    /// This rank and the number of LIGGGHTS ranks.
    pub fn rank(&self) -> (usize, usize) {
        (self.comm.rank() as usize, self.comm.size() as usize)
    }

    /// The largest tag now, over all ranks.
    pub fn max_tag(&self) -> usize {
        self.maxtag
    }

    /// The DEM step counter of LIGGGHTS.
    pub fn step(&self) -> i64 {
        self.step
    }

    /// Runs one LIGGGHTS command (every rank must call it).
    pub fn command(&mut self, cmd: &str) -> Result<(), LiggghtsError> {
        let c = cstr(cmd);
        let _in = InLiggghts::enter(&self.workdir)?;
        unsafe { ffi::lammps_command(self.lmp, c.as_ptr()) };
        Ok(())
    }

    /// A per-atom array of LIGGGHTS (`lammps_extract_atom`); null if LIGGGHTS has none.
    fn atom_array(&self, name: &str) -> *mut c_void {
        let n = cstr(name);
        unsafe { ffi::lammps_extract_atom(self.lmp, n.as_ptr()) }
    }

    /// The per-atom array of a `property/atom` fix (`lammps_extract_fix`, per-atom style;
    /// `vector` for a per-atom vector, else a scalar): an error naming the fix if absent.
    fn fix_array(&self, id: &str, vector: bool) -> Result<*mut c_void, LiggghtsError> {
        let n = cstr(id);
        let ptr = unsafe {
            ffi::lammps_extract_fix(self.lmp, n.as_ptr(), 1, if vector { 2 } else { 1 }, 0, 0)
        };
        if ptr.is_null() {
            return Err(LiggghtsError::Coupling(format!(
                "LIGGGHTS has no per-atom fix `{id}` (the coupling fix `couple/cfd/force` creates \
                 `dragforce`, and with `/implicit` `Ksl` and `uf`; `heat/gran` creates `Temp` and \
                 `heatFlux`, `couple/cfd/convection` `convectiveHeatFlux`)"
            )));
        }
        Ok(ptr)
    }

    /// Reads dt, the step, maxtag and this rank's own particles, ordered by tag;
    /// [`ParticleSide::advance`] does it after each run.
    pub fn refresh(&mut self) -> Result<(), LiggghtsError> {
        let _in = InLiggghts::enter(&self.workdir)?;
        let nlocal;
        unsafe {
            self.dt = *(ffi::lammps_extract_global(self.lmp, cstr("dt").as_ptr()) as *const f64);
            self.step =
                *(ffi::lammps_extract_global(self.lmp, cstr("ntimestep").as_ptr()) as *const i64);
            self.maxtag = ffi::liggghts_get_maxtag(self.lmp).max(0) as usize;
            nlocal = *(ffi::lammps_extract_global(self.lmp, cstr("nlocal").as_ptr()) as *const i32)
                .max(&0) as usize;
        }
        self.particles.clear();
        self.local.clear();
        if nlocal == 0 {
            return Ok(());
        }
        let tag = self.atom_array("id") as *const i32;
        let x = self.atom_array("x") as *const *const f64;
        let v = self.atom_array("v") as *const *const f64;
        let radius = self.atom_array("radius") as *const f64;
        let density = self.atom_array("density") as *const f64;
        if [
            tag as *const c_void,
            x as _,
            v as _,
            radius as _,
            density as _,
        ]
        .iter()
        .any(|p| p.is_null())
        {
            return Err(LiggghtsError::Coupling(
                "LIGGGHTS's atoms lack tag, x, v, radius or density (the coupling needs \
                 `atom_style granular` with `atom_modify map array`)"
                    .into(),
            ));
        }
        // SAFETY: LIGGGHTS owns `nlocal` atoms; each array has at least that many rows (x and v
        // rows of 3 doubles) until the next command changes the atoms.
        unsafe {
            self.local.extend(0..nlocal);
            self.local.sort_unstable_by_key(|&i| *tag.add(i));
            for &i in &self.local {
                let row = |a: *const *const f64| {
                    let r = *a.add(i);
                    V3::new(*r, *r.add(1), *r.add(2))
                };
                self.particles.push(
                    *tag.add(i) as u64,
                    row(x),
                    row(v),
                    *radius.add(i),
                    *density.add(i),
                );
            }
        }
        if let Some(t) = self.particles.temperature.as_mut() {
            let temp = {
                let n = cstr("Temp");
                unsafe { ffi::lammps_extract_fix(self.lmp, n.as_ptr(), 1, 1, 0, 0) as *const f64 }
            };
            if temp.is_null() {
                return Err(LiggghtsError::Coupling(
                    "LIGGGHTS has no per-atom `Temp` although the deck declares \
                     `couple/cfd/convection` (is `fix heat/gran` defined before the first run?)"
                        .into(),
                ));
            }
            // SAFETY: `Temp` is a per-atom scalar with a value for every local atom.
            t.extend(self.local.iter().map(|&i| unsafe { *temp.add(i) }));
        }
        Ok(())
    }

    /// Writes the convective heat flux (W per particle, in the state's order) into LIGGGHTS's
    /// per-atom `convectiveHeatFlux` of this rank's atoms; `fix couple/cfd/convection` adds it
    /// to `heatFlux` every step until the next exchange.
    fn push_heat_flux(&mut self, q: &[f64]) -> Result<(), LiggghtsError> {
        if !self.heat {
            return Err(LiggghtsError::Coupling(
                "the coupling computes a particle heat flux, but the deck has no \
                 `fix ID all couple/cfd/convection T0 …` (and `fix heat/gran`) to receive it"
                    .into(),
            ));
        }
        let n = self.local.len();
        if q.len() != n {
            return Err(LiggghtsError::Length {
                what: "heat fluxes",
                expected: n,
                found: q.len(),
            });
        }
        if let Some(i) = q.iter().position(|x| !x.is_finite()) {
            return Err(LiggghtsError::Particle {
                tag: self.particles.ids[i],
                message: format!("heat flux {} W (a finite value needed)", q[i]),
            });
        }
        let _in = InLiggghts::enter(&self.workdir)?;
        if n == 0 {
            return Ok(());
        }
        let flux = self.fix_array("convectiveHeatFlux", false)? as *mut f64;
        // SAFETY: one double per local atom.
        unsafe {
            for (s, &i) in self.local.iter().enumerate() {
                *flux.add(i) = q[s];
            }
        }
        Ok(())
    }

    /// Writes the force fields into LIGGGHTS's per-atom arrays of this rank's atoms.
    fn push_fields(&mut self) -> Result<(), LiggghtsError> {
        let _in = InLiggghts::enter(&self.workdir)?;
        if self.local.is_empty() {
            return Ok(());
        }
        let write_vectors = |arr: *mut c_void, src: &[V3], local: &[usize]| {
            let rows = arr as *mut *mut f64;
            // SAFETY: the fix's per-atom array has a 3-vector row for every local atom.
            unsafe {
                for (s, &i) in local.iter().enumerate() {
                    let r = *rows.add(i);
                    for (k, x) in src[s].iter().enumerate() {
                        *r.add(k) = *x;
                    }
                }
            }
        };
        write_vectors(
            self.fix_array("dragforce", true)?,
            &self.fields.dragforce,
            &self.local,
        );
        if self.mode == ForceMode::Implicit {
            let ksl = self.fix_array("Ksl", false)? as *mut f64;
            // SAFETY: one double per local atom.
            unsafe {
                for (s, &i) in self.local.iter().enumerate() {
                    *ksl.add(i) = self.fields.ksl[s];
                }
            }
            write_vectors(self.fix_array("uf", true)?, &self.fields.uf, &self.local);
        }
        Ok(())
    }
}

impl Drop for LiggghtsDem {
    fn drop(&mut self) {
        let _in = InLiggghts::enter(&self.workdir);
        unsafe { ffi::lammps_close(self.lmp) };
    }
}

impl ParticleSide for LiggghtsDem {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        if steps == 0 {
            return Ok(());
        }
        let cmd = if self.ran {
            format!("run {steps} pre no post no")
        } else {
            format!("run {steps}")
        };
        self.command(&cmd)?;
        self.ran = true;
        self.refresh()?;
        Ok(())
    }

    fn time_step(&self) -> f64 {
        self.dt
    }

    fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    fn state(&self) -> ParticleState<'_> {
        self.particles.view()
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        let p = &self.particles;
        force_fields(
            self.mode,
            &p.ids,
            &p.velocity,
            f_ext,
            beta,
            u_f,
            &mut self.fields,
        )?;
        self.push_fields()?;
        Ok(())
    }

    fn set_heat_flux(&mut self, q: &[f64]) -> Result<(), SideError> {
        self.push_heat_flux(q)?;
        Ok(())
    }

    fn command(&mut self, cmd: &str) -> Result<(), SideError> {
        LiggghtsDem::command(self, cmd)?;
        if cmd.split_whitespace().next() == Some("write_restart") {
            // the next interval begins as a run continued from this file begins (`run N`
            // with LIGGGHTS's setup: its first half kick uses the forces of the exchange just
            // made, not the previous interval's last ones, which no restart file holds), so
            // that a run restarted from here continues this one (crate::forces)
            self.ran = false;
        }
        // a command may change the particles (CFDEM's `set … property/atom Temp`, `run`)
        self.refresh()?;
        Ok(())
    }

    /// The coupler's copies of the particles' state (tags, centres, velocities, radii,
    /// densities, temperatures), their local indices and the force fields handed to LIGGGHTS;
    /// LIGGGHTS's own atom arrays (in the same process) are not counted.
    fn held_bytes(&self) -> Option<usize> {
        fn flat<T: Copy>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let p = &self.particles;
        let f = &self.fields;
        Some(
            flat(&p.ids)
                + flat(&p.position)
                + flat(&p.velocity)
                + flat(&p.radius)
                + flat(&p.density)
                + p.temperature.as_ref().map_or(0, flat)
                + flat(&self.local)
                + flat(&f.dragforce)
                + flat(&f.ksl)
                + flat(&f.uf),
        )
    }
}
