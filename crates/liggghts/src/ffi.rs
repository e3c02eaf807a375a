//! The few libliggghts functions foamgrain calls, declared by hand (no bindgen): the C library
//! interface of `library.h` and the C++-only functions of `library_cfd_coupling.h`, which
//! Debian's libliggghts.so.3.8.0 exports under their Itanium-mangled names (checked with
//! `nm -D`). Buffers of the coupling functions are `T**` whose `[0]` points to one contiguous
//! `[maxtag][len]` block indexed by tag − 1.

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
    /// `int liggghts_get_maxtag(void *ptr)`: the largest tag over all ranks.
    #[link_name = "_Z19liggghts_get_maxtagPv"]
    pub fn liggghts_get_maxtag(ptr: *mut c_void) -> c_int;
    /// `void data_liggghts_to_of(const char *name, const char *type, void *ptr, void *&data,
    /// const char *datatype)`: LIGGGHTS → coupler, an allreduce over LIGGGHTS's ranks, so
    /// every rank gets all particles.
    #[link_name = "_Z19data_liggghts_to_ofPKcS0_PvRS1_S0_"]
    pub fn data_liggghts_to_of(
        name: *const c_char,
        kind: *const c_char,
        ptr: *mut c_void,
        data: *mut *mut c_void,
        datatype: *const c_char,
    );
    /// `void data_of_to_liggghts(const char *name, const char *type, void *ptr, void *data,
    /// const char *datatype)`: coupler → LIGGGHTS, SUMMED over ranks before use.
    #[link_name = "_Z19data_of_to_liggghtsPKcS0_PvS1_S0_"]
    pub fn data_of_to_liggghts(
        name: *const c_char,
        kind: *const c_char,
        ptr: *mut c_void,
        data: *mut c_void,
        datatype: *const c_char,
    );
    /// C's `atexit` (from the C library every Rust program links).
    pub fn atexit(cb: extern "C" fn()) -> c_int;
}
