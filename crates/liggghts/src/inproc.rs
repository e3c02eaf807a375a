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
//! post no` after; the state is then pulled (`id`, `x`, `v`, `radius`, `density`, each an
//! allreduce over LIGGGHTS's ranks into `[maxtag][len]` buffers, maxtag re-queried after every
//! run) and ordered by tag, absent tags (deleted particles) left out.
//! [`ParticleSide::set_forces`] maps (F_ext, β, u_f) onto `dragforce`, `Ksl`, `uf`
//! ([`crate::forces`]) and pushes them with `data_of_to_liggghts`, which SUMS the buffers of
//! all ranks: each rank fills only its share ([`Share`]) and leaves zeros elsewhere.
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

/// Which particles (indices into [`ParticleSide::state`]) a rank's coupler fills when forces
/// are pushed; the others are sent as zeros (LIGGGHTS sums over ranks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Share {
    /// Contiguous blocks: rank r of s fills indices `r·n/s .. (r+1)·n/s` (all on one rank).
    Blocks,
    /// Only rank 0 fills, with all particles (the others' forces are ignored).
    Rank0,
}

impl Share {
    /// The index range rank `rank` of `size` fills among `n` particles.
    pub fn range(self, n: usize, rank: usize, size: usize) -> std::ops::Range<usize> {
        match self {
            Share::Blocks => (rank * n / size)..((rank + 1) * n / size),
            Share::Rank0 if rank == 0 => 0..n,
            Share::Rank0 => 0..0,
        }
    }
}

/// LIGGGHTS in this process (module docs).
pub struct LiggghtsDem {
    lmp: *mut c_void,
    comm: SimpleCommunicator,
    workdir: PathBuf,
    mode: ForceMode,
    share: Share,
    skipped: Vec<SkippedRun>,
    ran: bool,
    dt: f64,
    step: i64,
    maxtag: usize,
    particles: Particles,
    /// State index + 1 per tag − 1 (0: absent).
    slot: Vec<u32>,
    fields: ForceFields,
    ibuf: Vec<i32>,
    buf3: Vec<f64>,
    buf1: Vec<f64>,
    buf1b: Vec<f64>,
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
                share: Share::Blocks,
                skipped: d.skipped_runs.clone(),
                ran: false,
                dt: 0.0,
                step: 0,
                maxtag: 0,
                particles: Particles::default(),
                slot: Vec::new(),
                fields: ForceFields::default(),
                ibuf: Vec::new(),
                buf3: Vec::new(),
                buf1: Vec::new(),
                buf1b: Vec::new(),
            }
        };
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

    /// Sets which particles this rank fills when forces are pushed (default [`Share::Blocks`]).
    pub fn set_share(&mut self, share: Share) {
        self.share = share;
    }

    /// The particles this rank fills (indices into the state).
    pub fn share_range(&self) -> std::ops::Range<usize> {
        self.share.range(
            self.particles.len(),
            self.comm.rank() as usize,
            self.comm.size() as usize,
        )
    }

    /// The largest tag now.
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

    /// Pulls `name` (LIGGGHTS → coupler) into `buf` (`maxtag × len` values).
    fn pull_double(&mut self, name: &str, kind: &str, len: usize, which: u8) {
        let buf = match which {
            3 => &mut self.buf3,
            1 => &mut self.buf1,
            _ => &mut self.buf1b,
        };
        buf.clear();
        buf.resize(self.maxtag.max(1) * len, 0.0);
        let mut rows: [*mut f64; 1] = [buf.as_mut_ptr()];
        let mut data = rows.as_mut_ptr() as *mut c_void;
        let (n, k, t) = (cstr(name), cstr(kind), cstr("double"));
        unsafe {
            ffi::data_liggghts_to_of(n.as_ptr(), k.as_ptr(), self.lmp, &mut data, t.as_ptr())
        };
    }

    /// Reads dt, the step, maxtag and the particles again (every rank gets all of them);
    /// [`ParticleSide::advance`] does it after each run.
    pub fn refresh(&mut self) -> Result<(), LiggghtsError> {
        let _in = InLiggghts::enter(&self.workdir)?;
        unsafe {
            self.dt = *(ffi::lammps_extract_global(self.lmp, cstr("dt").as_ptr()) as *const f64);
            self.step =
                *(ffi::lammps_extract_global(self.lmp, cstr("ntimestep").as_ptr()) as *const i64);
            self.maxtag = ffi::liggghts_get_maxtag(self.lmp).max(0) as usize;
        }
        let m = self.maxtag;
        self.ibuf.clear();
        self.ibuf.resize(m.max(1), 0);
        {
            let mut rows: [*mut i32; 1] = [self.ibuf.as_mut_ptr()];
            let mut data = rows.as_mut_ptr() as *mut c_void;
            let (n, k, t) = (cstr("id"), cstr("scalar-atom"), cstr("int"));
            unsafe {
                ffi::data_liggghts_to_of(n.as_ptr(), k.as_ptr(), self.lmp, &mut data, t.as_ptr())
            };
        }
        self.particles.clear();
        self.slot.clear();
        self.slot.resize(m, 0);
        if m == 0 {
            return Ok(());
        }
        self.pull_double("radius", "scalar-atom", 1, 1);
        self.pull_double("density", "scalar-atom", 1, 2);
        // positions first into buf3, copied out before the velocities overwrite it
        self.pull_double("x", "vector-atom", 3, 3);
        for t in 0..m {
            if self.ibuf[t] as usize == t + 1 {
                let x = V3::new(self.buf3[3 * t], self.buf3[3 * t + 1], self.buf3[3 * t + 2]);
                self.slot[t] = self.particles.len() as u32 + 1;
                self.particles
                    .push(t as u64 + 1, x, V3::zeros(), self.buf1[t], self.buf1b[t]);
            }
        }
        self.pull_double("v", "vector-atom", 3, 3);
        for t in 0..m {
            if let Some(s) = self.slot[t].checked_sub(1) {
                self.particles.velocity[s as usize] =
                    V3::new(self.buf3[3 * t], self.buf3[3 * t + 1], self.buf3[3 * t + 2]);
            }
        }
        Ok(())
    }

    /// Pushes `name` (coupler → LIGGGHTS) from `buf`.
    fn push_double(&self, name: &str, kind: &str, buf: &mut [f64]) {
        let mut rows: [*mut f64; 1] = [buf.as_mut_ptr()];
        let (n, k, t) = (cstr(name), cstr(kind), cstr("double"));
        unsafe {
            ffi::data_of_to_liggghts(
                n.as_ptr(),
                k.as_ptr(),
                self.lmp,
                rows.as_mut_ptr() as *mut c_void,
                t.as_ptr(),
            )
        };
    }

    fn push_fields(&mut self) -> Result<(), LiggghtsError> {
        let m = self.maxtag.max(1);
        let range = self.share_range();
        let ids = &self.particles.ids;
        let vec3 = |src: &[V3]| {
            let mut b = vec![0.0; 3 * m];
            for s in range.clone() {
                let t = ids[s] as usize - 1;
                b[3 * t..3 * t + 3].copy_from_slice(src[s].as_slice());
            }
            b
        };
        let mut drag = vec3(&self.fields.dragforce);
        let implicit = (self.mode == ForceMode::Implicit).then(|| {
            let mut ksl = vec![0.0; m];
            for s in range.clone() {
                ksl[ids[s] as usize - 1] = self.fields.ksl[s];
            }
            (ksl, vec3(&self.fields.uf))
        });
        let _in = InLiggghts::enter(&self.workdir)?;
        self.push_double("dragforce", "vector-atom", &mut drag);
        if let Some((mut ksl, mut uf)) = implicit {
            self.push_double("Ksl", "scalar-atom", &mut ksl);
            self.push_double("uf", "vector-atom", &mut uf);
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

    fn command(&mut self, cmd: &str) -> Result<(), SideError> {
        LiggghtsDem::command(self, cmd)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_are_disjoint_and_cover_all() {
        for n in [0, 1, 7, 100] {
            for size in 1..5 {
                let mut covered = vec![0; n];
                for r in 0..size {
                    for i in Share::Blocks.range(n, r, size) {
                        covered[i] += 1;
                    }
                }
                assert!(covered.iter().all(|&c| c == 1), "n {n} size {size}");
            }
            assert_eq!(Share::Rank0.range(n, 0, 3), 0..n);
            assert!(Share::Rank0.range(n, 2, 3).is_empty());
        }
    }
}
