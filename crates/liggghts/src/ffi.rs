//! The few libliggghts functions foamgrain calls, declared by hand (no bindgen): the C library
//! interface of `library.h` and `liggghts_get_maxtag` of `library_cfd_coupling.h`, which
//! Debian's libliggghts.so.3.8.0 exports under its Itanium-mangled name (checked with
//! `nm -D`). Per-atom arrays are this rank's own (`nlocal` rows); CFDEM's
//! `data_liggghts_to_of`/`data_of_to_liggghts` are not used: they allreduce `[maxtag][len]`
//! buffers, so every rank would hold every particle.

use std::ffi::{c_char, c_int, c_void};

use mpi::ffi::MPI_Comm;

extern "C" {
    /// `void lammps_open(int argc, char **argv, MPI_Comm communicator, void **ptr)`.
    pub fn lammps_open(argc: c_int, argv: *mut *mut c_char, comm: MPI_Comm, ptr: *mut *mut c_void);
    /// `void lammps_close(void *ptr)`.
    pub fn lammps_close(ptr: *mut c_void);
    /// `void lammps_file(void *ptr, const char *file)`: runs an input file.
    pub fn lammps_file(ptr: *mut c_void, file: *const c_char);
    /// `char *lammps_command(void *ptr, const char *cmd)`: runs one command.
    pub fn lammps_command(ptr: *mut c_void, cmd: *const c_char) -> *mut c_char;
    /// `void *lammps_extract_global(void *ptr, const char *name)` (`dt`: double,
    /// `ntimestep`: int64).
    pub fn lammps_extract_global(ptr: *mut c_void, name: *const c_char) -> *mut c_void;
    /// `void *lammps_extract_atom(void *ptr, const char *name)`: this rank's per-atom array
    /// (`id`: the tags, int*, `x`/`v`: double**, `radius`/`density`: double*), or null.
    pub fn lammps_extract_atom(ptr: *mut c_void, name: *const c_char) -> *mut c_void;
    /// `void *lammps_extract_fix(void *ptr, const char *id, int style, int type, int i, int
    /// j)`: with style 1 (per-atom) the fix's `vector_atom` (type 1) or `array_atom` (type 2)
    /// of this rank's atoms, or null.
    pub fn lammps_extract_fix(
        ptr: *mut c_void,
        id: *const c_char,
        style: c_int,
        kind: c_int,
        i: c_int,
        j: c_int,
    ) -> *mut c_void;
    /// `int liggghts_get_maxtag(void *ptr)`: the largest tag over all ranks.
    #[link_name = "_Z19liggghts_get_maxtagPv"]
    pub fn liggghts_get_maxtag(ptr: *mut c_void) -> c_int;
    /// C's `atexit` (from the C library every Rust program links).
    pub fn atexit(cb: extern "C" fn()) -> c_int;
}
