//! The messages between the coupler and grainPisoFoam's `mpi` coupling source
//! (`openfoam-cases/solver/grainPisoFoam/mpiCouplingSource.H` is the other half; the two must
//! change together, [`PROTOCOL_VERSION`] guards it).
//!
//! Every solver rank talks to the coupler's rank 0 over the spawn intercommunicator (the
//! handshake, commands and their replies) and, in the sparse exchange of several coupler ranks,
//! to every coupler rank. With n the rank's cells and m its non-processor patches (f64 =
//! MPI_DOUBLE, i32 = MPI_INT):
//!
//! | tag | direction | content |
//! |---|---|---|
//! | 1 [`tag::HELLO`] | rank → coupler | i32\[5\]: version, n, pid, m, rank |
//! | 2 [`tag::CELLS`] | rank → coupler | i32\[n\]: the global cell of each local cell |
//! | 3 [`tag::PATCHES`] | rank → coupler | the m patch names, each followed by `\n` |
//! | 4 [`tag::TIMES`] | rank → coupler | f64\[2\]: start time, controlDict deltaT (s) |
//! | 20 [`tag::STATE`] | rank → coupler | the start fields, laid out as an advance's reply |
//! | 10 [`tag::COMMAND`] | coupler → rank | f64\[4\]: [`Command::words`] |
//! | 11 [`tag::FIELDS`] | coupler → rank | f64\[9n\]: ε_old, ε_new, Ksl, Us (3n), f (3n) |
//! | 20 [`tag::STATE`] | rank → coupler | f64\[1+10n+3m\]: time, U (3n), p, ∇p (3n), ∇·τ (3n), Σp\|S\|, Σ\|S\|, Σφ per patch |
//! | 23 [`tag::PATCH_STATE`] | rank → coupler | f64\[1+3m\]: after [`Command::AdvanceHeld`]: time and the patch sums; after a [`Command::Watch`], then the watch block |
//! | 15 [`tag::WATCH_CELLS`] | coupler → rank | i32\[k\]: after [`Command::Watch`]: the local cells whose U rank 0 samples |
//! | 25 [`tag::WATCHED`] | rank → coupler | f64\[c+3k\]: the reply to [`Command::Watch`], the watch block of the current fluid: max over the rank's cells of \|U\|/∛V (1/s; c = 1 when the watch asked for it, else 0), then U of the k watched cells |
//! | 24 [`tag::WHOLE_STATE`] | rank → coupler | after [`Command::AdvanceHeld`] with `whole`: tag 20's message, then ε, Ksl (n each), Us, f (3n each) |
//! | 12 [`tag::SPARSE_CELLS`] | coupler rank q → rank | i32\[k\]: after [`Command::Exchange`]: the local cells q's particles touch |
//! | 13 [`tag::SPARSE_SOLID`] | q → rank | f64\[k\]: the solid volume q deposits in each, m³ |
//! | 22 [`tag::SPARSE_REPLY`] | rank → q | f64\[12k\]: per cell [`SPARSE_REPLY_WORDS`]: Σ_q solid volume, 1 if q is the lowest rank touching it, U, p, ∇p, ∇·τ |
//! | 14 [`tag::SPARSE_SUMS`] | q → rank | f64\[8k\]: per cell [`SPARSE_SUMS_WORDS`]: ε, Σ Ksl, Σ Ksl·Us, Σ f of q's particles |
//!
//! In the sparse exchange the solver rank goes through the coupler ranks in order (each sends
//! its two messages, possibly empty, then each gets its reply, then each sends its sums), so its
//! per-cell sums are formed in coupler-rank order, as the coupler's rank 0 forms them when it
//! holds the fluid ([`couple::ranks`]). It then holds ε_new (the touched cells' ε, 1 elsewhere),
//! ε_old (the last exchange's ε_new, 1 before the first), Ksl = Σ Ksl, Us = Σ Ksl·Us / Σ Ksl
//! (0 where Σ Ksl = 0) and f = Σ f for the next [`Command::AdvanceHeld`].
//!
//! The watch (version 3): in the sparse exchange no cell field reaches coupler rank 0 (it
//! holds a part of the mesh), so what it samples of U on the whole mesh (a conveyor's air
//! along the tube and the vented leg; `checkCouplingInterval`'s CFL) would be the start
//! fields'. [`Command::Watch`] names those cells once; each rank answers with their U now and
//! appends them to every later tag 23 reply. A run without a watch sends exactly what version
//! 2 sent.
//! | 21 [`tag::DONE`] | rank → coupler | f64\[1\]: time (after write or stop) |
//! | 30 [`tag::ERROR`] | rank → coupler | the text of an OpenFOAM FatalError |
//!
//! **Heat** (issue 27; the coupler asks for it with `FOAMGRAIN_HEAT=1` on the launch line,
//! `crate::SpawnOptions::heat`): the solver solves cfdemSolverPisoScalar's temperature
//! equation and three messages grow by whole blocks; without heat every message is exactly as
//! above.
//!
//! | tag | with heat |
//! |---|---|
//! | 1 [`tag::HELLO`] | i32\[6\]: the five words, then flags ([`HELLO_FLAG_HEAT`]) |
//! | 11 [`tag::FIELDS`] | f64\[10n\]: the nine blocks above, then Tsource (n), K/s |
//! | 20 [`tag::STATE`] | f64\[1+11n+4m\]: time, U, p, ∇p, ∇·τ, then T (n, K), then per patch Σp\|S\|, Σ\|S\|, Σφ and Σ φT_b (K m³/s, the same φ) |
//! | 23 [`tag::PATCH_STATE`] | f64\[1+4m\]: time, then per patch the four sums of tag 20 |
//! | 24 [`tag::WHOLE_STATE`] | tag 20's message with heat, then the held fields as above |
//! | 22 [`tag::SPARSE_REPLY`] | f64\[13k\]: per cell the twelve values above, then T (K) |
//! | 14 [`tag::SPARSE_SUMS`] | f64\[9k\]: per cell the eight values above, then q's share of Tsource, −Σ_p w q_p/(ρ c_p V) (K/s; the rank adds the shares in coupler-rank order into Tsource, 0 in cells no coupler rank touches) |
//!
//! **CFDEM's Ksl form** (issue 28; `crate::SpawnOptions::cfdem_ksl`, the launch line sets
//! `FOAMGRAIN_KSL='CFDEM <KslLimit> <maxAlpha>'`): tag 1 has the sixth word with
//! [`HELLO_FLAG_KSL_CFDEM`], and tag 14's records end (after the heat column, if any) with
//! [`KSL_SUMS_WORDS`] more: Σ w β (u_p − v) (3, N), Σ w, Σ w v (3, m/s) of q's particles. The
//! rank sums them in coupler-rank order and forms, per cell, Us = Σ w v / Σ w (0 where Σ w =
//! 0) and Ksl = |Σ w F| / (V |U − Us|) where |U − Us| > 10⁻¹⁵ and ε < maxAlpha, else 0, capped
//! at KslLimit (U of its last reply, ε the exchange's ε_new; [`couple::ksl`]) instead of
//! Σ Ksl and Σ Ksl·Us / Σ Ksl. Without it every message is as above.
//!
//! **Added mass and lift** (issue 28; `crate::SpawnOptions::vorticity` and
//! `crate::SpawnOptions::ddt_u`, the launch line sets `FOAMGRAIN_VORTICITY=1` and/or
//! `FOAMGRAIN_DDT_U=1`): tag 1 has the sixth word with [`HELLO_FLAG_VORTICITY`] and/or
//! [`HELLO_FLAG_DDT_U`], and the per-cell part of tag 20 (and so of tag 24) grows, after the
//! heat block if any, by ∇ × U (3n, 1/s) and then DU/Dt (3n, m/s²), each only when asked for.
//! The sparse exchange does not carry them (a sparse run with either is refused). Without
//! them every message is as above.
//!
//! ([`sparse_reply_words`], [`sparse_sums_words`]; the coupler's side is
//! [`couple::ranks::owner_reply_width`] and [`couple::ranks::owner_sums_width`].)
//!
//! Units are ADR 0004's: ε dimensionless, Ksl kg/(m³ s), Us m/s, f N/m³; U m/s, p m²/s²
//! (kinematic), ∇p and ∇·τ m/s², φ m³/s.

use crate::ranks::RankMap;
use mesh::v3::V3;

/// The version both sides must agree on.
pub const PROTOCOL_VERSION: i32 = 3;

/// Message tags.
pub mod tag {
    /// Handshake: version, cells, pid, patches, rank.
    pub const HELLO: i32 = 1;
    /// Handshake: local → global cells.
    pub const CELLS: i32 = 2;
    /// Handshake: patch names.
    pub const PATCHES: i32 = 3;
    /// Handshake: start time and deltaT.
    pub const TIMES: i32 = 4;
    /// A command.
    pub const COMMAND: i32 = 10;
    /// The exchange fields of an advance.
    pub const FIELDS: i32 = 11;
    /// Sparse exchange: the cells a coupler rank touches (local to the solver rank).
    pub const SPARSE_CELLS: i32 = 12;
    /// Sparse exchange: the solid volume per touched cell.
    pub const SPARSE_SOLID: i32 = 13;
    /// Sparse exchange: ε and the force sums per touched cell.
    pub const SPARSE_SUMS: i32 = 14;
    /// The watch: the local cells whose U rank 0 samples.
    pub const WATCH_CELLS: i32 = 15;
    /// The watch's reply: the watch block of the current fluid.
    pub const WATCHED: i32 = 25;
    /// Sparse exchange: the summed solid volume and the fluid per touched cell.
    pub const SPARSE_REPLY: i32 = 22;
    /// Time and patch sums after an advance with held fields.
    pub const PATCH_STATE: i32 = 23;
    /// The whole state and the held exchange fields after an advance with held fields.
    pub const WHOLE_STATE: i32 = 24;
    /// The fluid after an advance.
    pub const STATE: i32 = 20;
    /// Acknowledges write and stop.
    pub const DONE: i32 = 21;
    /// A FatalError's message.
    pub const ERROR: i32 = 30;
}

/// Doubles per cell sent with an advance (ε_old, ε_new, Ksl, Us, f).
pub const FIELD_WORDS_PER_CELL: usize = 9;
/// Doubles per cell that heat adds to [`tag::FIELDS`] (Tsource) and to [`tag::STATE`] (T).
pub const HEAT_WORDS_PER_CELL: usize = 1;
/// Bit of the handshake's sixth word: the solver solves the temperature equation.
pub const HELLO_FLAG_HEAT: i32 = 1;
/// Bit of the handshake's sixth word: the solver forms CFDEM's Ksl in the sparse exchange.
pub const HELLO_FLAG_KSL_CFDEM: i32 = 2;
/// Bit of the handshake's sixth word: the replies carry the vorticity ∇ × U.
pub const HELLO_FLAG_VORTICITY: i32 = 4;
/// Bit of the handshake's sixth word: the replies carry DU/Dt = ∂U/∂t + ∇·(φU).
pub const HELLO_FLAG_DDT_U: i32 = 8;
/// Doubles per cell each of ∇ × U and DU/Dt adds to [`tag::STATE`].
pub const VECTOR_WORDS_PER_CELL: usize = 3;
/// Doubles per cell in the reply (U, p, ∇p, ∇·τ).
pub const STATE_WORDS_PER_CELL: usize = 10;
/// Doubles per patch in the reply (Σ p|S|, Σ |S|, Σ φ).
pub const PATCH_WORDS: usize = 3;
/// Doubles per cell of [`tag::SPARSE_REPLY`]: Σ solid volume, lowest-rank flag, U (3), p,
/// ∇p (3), ∇·τ (3).
pub const SPARSE_REPLY_WORDS: usize = 12;
/// Doubles per cell of [`tag::SPARSE_SUMS`]: ε, Σ Ksl, Σ Ksl·Us (3), Σ f (3).
pub const SPARSE_SUMS_WORDS: usize = 8;

/// Doubles per cell of [`tag::SPARSE_REPLY`]: [`SPARSE_REPLY_WORDS`], and T when `heat`.
pub const fn sparse_reply_words(heat: bool) -> usize {
    SPARSE_REPLY_WORDS + if heat { HEAT_WORDS_PER_CELL } else { 0 }
}

/// Doubles per cell that CFDEM's Ksl form adds to [`tag::SPARSE_SUMS`] (after the heat
/// column): Σ w β (u_p − v) (3, N), Σ w, Σ w v (3, m/s).
pub const KSL_SUMS_WORDS: usize = 7;

/// Doubles per cell of [`tag::SPARSE_SUMS`]: [`SPARSE_SUMS_WORDS`], the Tsource share when
/// `heat`, and [`KSL_SUMS_WORDS`] when `cfdem_ksl`.
pub const fn sparse_sums_words(heat: bool, cfdem_ksl: bool) -> usize {
    SPARSE_SUMS_WORDS
        + if heat { HEAT_WORDS_PER_CELL } else { 0 }
        + if cfdem_ksl { KSL_SUMS_WORDS } else { 0 }
}
/// Doubles per cell that [`tag::WHOLE_STATE`] adds to [`tag::STATE`]'s message: ε, Ksl, Us
/// (3), f (3).
pub const HELD_WORDS_PER_CELL: usize = 8;

/// What the coupler asks of the solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// `steps` PISO steps of `step_length` seconds; `first` makes ε_old ε's old time too (the
    /// first interval, as the native solver does).
    Advance {
        /// Number of steps (≥ 1).
        steps: u64,
        /// Step length, s.
        step_length: f64,
        /// The first interval of the run.
        first: bool,
    },
    /// Write all fields now (runTime.writeNow()).
    Write,
    /// Leave the time loop and exit.
    Stop,
    /// The sparse exchange with every coupler rank (module docs); no reply to rank 0 beyond
    /// the exchange's own messages.
    Exchange,
    /// As [`Command::Advance`], with the fields of the last [`Command::Exchange`]; the reply is
    /// [`tag::PATCH_STATE`], or [`tag::WHOLE_STATE`] when `whole`.
    AdvanceHeld {
        /// Number of steps (≥ 1).
        steps: u64,
        /// Step length, s.
        step_length: f64,
        /// The first interval of the run.
        first: bool,
        /// Reply with the whole state and the held fields.
        whole: bool,
    },
    /// The cells whose U the [`tag::PATCH_STATE`] replies carry from now on (sent after it,
    /// [`tag::WATCH_CELLS`]); answered with [`tag::WATCHED`] (module docs).
    Watch {
        /// The replies also carry max |U|/∛V over the rank's cells.
        cfl: bool,
    },
}

impl Command {
    /// The four doubles of the message.
    pub fn words(&self) -> [f64; 4] {
        match *self {
            Command::Advance {
                steps,
                step_length,
                first,
            } => [1.0, steps as f64, step_length, f64::from(u8::from(first))],
            Command::Write => [2.0, 0.0, 0.0, 0.0],
            Command::Stop => [3.0, 0.0, 0.0, 0.0],
            Command::Exchange => [4.0, 0.0, 0.0, 0.0],
            Command::AdvanceHeld {
                steps,
                step_length,
                first,
                whole,
            } => [
                5.0,
                steps as f64,
                step_length,
                f64::from(u8::from(first) + 2 * u8::from(whole)),
            ],
            Command::Watch { cfl } => [6.0, f64::from(u8::from(cfl)), 0.0, 0.0],
        }
    }
}

/// The first handshake message of a rank.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hello {
    /// The solver's protocol version.
    pub version: i32,
    /// Cells on the rank.
    pub n_cells: usize,
    /// The solver process id.
    pub pid: u32,
    /// Non-processor patches.
    pub n_patches: usize,
    /// The rank in the solver's own MPI_COMM_WORLD.
    pub rank: usize,
    /// The solver solves the temperature equation (a sixth word with [`HELLO_FLAG_HEAT`]).
    pub heat: bool,
    /// The solver forms CFDEM's Ksl (a sixth word with [`HELLO_FLAG_KSL_CFDEM`]).
    pub cfdem_ksl: bool,
    /// The replies carry ∇ × U (a sixth word with [`HELLO_FLAG_VORTICITY`]).
    pub vorticity: bool,
    /// The replies carry DU/Dt (a sixth word with [`HELLO_FLAG_DDT_U`]).
    pub ddt_u: bool,
}

impl Hello {
    /// Decodes the five integers (six with heat: the flags); `Err` says what is wrong.
    pub fn parse(words: &[i32]) -> Result<Hello, String> {
        let wrong = || {
            format!(
                "handshake of {} integers, expected 5 (6 with heat)",
                words.len()
            )
        };
        let (head, flags) = match words {
            [head @ .., flags] if words.len() == 6 => (head, *flags),
            _ => (words, 0),
        };
        let &[version, n_cells, pid, n_patches, rank] = head else {
            return Err(wrong());
        };
        let known =
            HELLO_FLAG_HEAT | HELLO_FLAG_KSL_CFDEM | HELLO_FLAG_VORTICITY | HELLO_FLAG_DDT_U;
        if flags & !known != 0 {
            return Err(format!("unknown handshake flags {flags}"));
        }
        if version != PROTOCOL_VERSION {
            return Err(format!(
                "protocol version {version}, this coupler speaks {PROTOCOL_VERSION} \
                 (rebuild grainPisoFoam with openfoam-cases/solver/build.sh)"
            ));
        }
        let count = |v: i32, what: &str| {
            usize::try_from(v).map_err(|_| format!("negative {what} ({v}) in the handshake"))
        };
        Ok(Hello {
            version,
            n_cells: count(n_cells, "cell count")?,
            pid: u32::try_from(pid).map_err(|_| format!("bad pid {pid} in the handshake"))?,
            n_patches: count(n_patches, "patch count")?,
            rank: count(rank, "rank")?,
            heat: flags & HELLO_FLAG_HEAT != 0,
            cfdem_ksl: flags & HELLO_FLAG_KSL_CFDEM != 0,
            vorticity: flags & HELLO_FLAG_VORTICITY != 0,
            ddt_u: flags & HELLO_FLAG_DDT_U != 0,
        })
    }
}

/// The patch names of the handshake (`name\n` each).
pub fn parse_patch_names(bytes: &[u8]) -> Result<Vec<String>, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("patch names: {e}"))?;
    if !text.is_empty() && !text.ends_with('\n') {
        return Err("patch names: the list does not end with a newline".into());
    }
    Ok(text.lines().map(str::to_owned).collect())
}

/// The fields one rank receives for an advance, in its local cell order (ADR 0004 units).
#[derive(Clone, Copy, Debug)]
pub struct FieldsIn<'a> {
    /// ε at the start of the interval.
    pub eps_old: &'a [f64],
    /// ε at its end.
    pub eps_new: &'a [f64],
    /// Ksl, kg/(m³ s).
    pub ksl: &'a [f64],
    /// Us, m/s.
    pub us: &'a [V3],
    /// f, N/m³.
    pub f: &'a [V3],
}

/// Packs the global fields of `cells` (a rank's global cell ids, in its local order) into the
/// [`tag::FIELDS`] message `out` (cleared first).
pub fn pack_fields(cells: &[u32], fields: &FieldsIn<'_>, out: &mut Vec<f64>) {
    let n = cells.len();
    out.clear();
    out.resize(FIELD_WORDS_PER_CELL * n, 0.0);
    let (eps_old, rest) = out.split_at_mut(n);
    let (eps_new, rest) = rest.split_at_mut(n);
    let (ksl, rest) = rest.split_at_mut(n);
    let (us, f) = rest.split_at_mut(3 * n);
    for (i, &c) in cells.iter().enumerate() {
        let c = c as usize;
        eps_old[i] = fields.eps_old[c];
        eps_new[i] = fields.eps_new[c];
        ksl[i] = fields.ksl[c];
        us[3 * i..3 * i + 3].copy_from_slice(fields.us[c].as_slice());
        f[3 * i..3 * i + 3].copy_from_slice(fields.f[c].as_slice());
    }
}

/// Appends the heat source Tsource (K/s per global cell) of `cells` to a packed
/// [`tag::FIELDS`] message (after [`pack_fields`]), as the protocol's heat block.
pub fn pack_heat_source(cells: &[u32], heat_source: &[f64], out: &mut Vec<f64>) {
    out.extend(cells.iter().map(|&c| heat_source[c as usize]));
}

/// The fluid on the whole mesh, assembled from the ranks' replies.
#[derive(Clone, Debug, Default)]
pub struct GlobalState {
    /// Simulated time, s.
    pub time: f64,
    /// U per global cell, m/s.
    pub u: Vec<V3>,
    /// Kinematic p per global cell, m²/s².
    pub p: Vec<f64>,
    /// ∇p per global cell, m/s².
    pub grad_p: Vec<V3>,
    /// ∇·τ per global cell, m/s².
    pub div_tau: Vec<V3>,
    /// Per patch: Σ p|S| (m⁴/s²), Σ |S| (m²), Σ φ (m³/s), summed over the ranks.
    pub patch_sums: Vec<[f64; 3]>,
    /// T per global cell, K, when heat is on ([`GlobalState::with_heat`]); the replies then
    /// carry the heat block.
    pub temperature: Option<Vec<f64>>,
    /// Per patch with heat on: Σ φ T_b (K m³/s) with the φ of `patch_sums`, summed over the
    /// ranks.
    pub patch_t_flux: Option<Vec<f64>>,
    /// ∇ × U per global cell, 1/s, when the replies carry it ([`GlobalState::with_fields`]).
    pub vorticity: Option<Vec<V3>>,
    /// DU/Dt per global cell, m/s², when the replies carry it ([`GlobalState::with_fields`]).
    pub ddt_u: Option<Vec<V3>>,
}

impl GlobalState {
    /// Zeroed arrays for `n_cells` cells and `n_patches` patches.
    pub fn new(n_cells: usize, n_patches: usize) -> GlobalState {
        GlobalState {
            time: 0.0,
            u: vec![V3::zeros(); n_cells],
            p: vec![0.0; n_cells],
            grad_p: vec![V3::zeros(); n_cells],
            div_tau: vec![V3::zeros(); n_cells],
            patch_sums: vec![[0.0; 3]; n_patches],
            temperature: None,
            patch_t_flux: None,
            vorticity: None,
            ddt_u: None,
        }
    }

    /// As [`GlobalState::new`], for replies with the heat block when `heat`, then ∇ × U when
    /// `vorticity` and DU/Dt when `ddt_u` (the protocol's added-mass-and-lift blocks).
    pub fn with_fields(
        n_cells: usize,
        n_patches: usize,
        heat: bool,
        vorticity: bool,
        ddt_u: bool,
    ) -> GlobalState {
        let base = match heat {
            true => GlobalState::with_heat(n_cells, n_patches),
            false => GlobalState::new(n_cells, n_patches),
        };
        GlobalState {
            vorticity: vorticity.then(|| vec![V3::zeros(); n_cells]),
            ddt_u: ddt_u.then(|| vec![V3::zeros(); n_cells]),
            ..base
        }
    }

    /// Doubles per cell of this state's [`tag::STATE`] reply: [`STATE_WORDS_PER_CELL`], the
    /// heat block's T, and 3 each for ∇ × U and DU/Dt when carried.
    pub fn cell_words(&self) -> usize {
        let vectors = usize::from(self.vorticity.is_some()) + usize::from(self.ddt_u.is_some());
        STATE_WORDS_PER_CELL + self.heat_words() + VECTOR_WORDS_PER_CELL * vectors
    }

    /// As [`GlobalState::new`], for replies with the heat block (T per cell).
    pub fn with_heat(n_cells: usize, n_patches: usize) -> GlobalState {
        GlobalState {
            temperature: Some(vec![0.0; n_cells]),
            patch_t_flux: Some(vec![0.0; n_patches]),
            ..GlobalState::new(n_cells, n_patches)
        }
    }

    /// Starts assembling a new reply: the patch sums are zeroed (the cell arrays are
    /// overwritten cell by cell).
    pub fn clear_sums(&mut self) {
        self.patch_sums.fill([0.0; 3]);
        if let Some(t) = self.patch_t_flux.as_mut() {
            t.fill(0.0);
        }
    }

    /// Adds one rank's [`tag::PATCH_STATE`] reply (time, then the patch sums, with heat Σ φ T_b
    /// after each patch's three) to the patch sums; returns the rank's time. `Err` when the
    /// length does not fit the patches.
    pub fn add_patch_sums(&mut self, msg: &[f64]) -> Result<f64, String> {
        let m = self.patch_sums.len();
        let per_patch = PATCH_WORDS + self.heat_words();
        if msg.len() != 1 + per_patch * m {
            return Err(format!(
                "patch reply of {} values, expected {} ({m} patches)",
                msg.len(),
                1 + per_patch * m
            ));
        }
        for (j, s) in msg[1..].chunks_exact(per_patch).enumerate() {
            for (acc, x) in self.patch_sums[j].iter_mut().zip(s) {
                *acc += x;
            }
            if let Some(acc) = self.patch_t_flux.as_mut() {
                acc[j] += s[PATCH_WORDS];
            }
        }
        Ok(msg[0])
    }

    /// Doubles per cell and per patch the heat block adds to the replies (0 without heat).
    pub fn heat_words(&self) -> usize {
        if self.temperature.is_some() {
            HEAT_WORDS_PER_CELL
        } else {
            0
        }
    }

    /// Scatters one rank's [`tag::STATE`] reply into the global arrays and adds its patch sums;
    /// returns the rank's time. `Err` when the length does not fit the rank's cells.
    pub fn scatter(&mut self, cells: &[u32], msg: &[f64]) -> Result<f64, String> {
        let n = cells.len();
        let m = self.patch_sums.len();
        let heat = self.heat_words();
        let per_patch = PATCH_WORDS + heat;
        let expected = 1 + self.cell_words() * n + per_patch * m;
        if msg.len() != expected {
            return Err(format!(
                "state reply of {} values, expected {expected} ({n} cells, {m} patches)",
                msg.len()
            ));
        }
        let (u, rest) = msg[1..].split_at(3 * n);
        let (p, rest) = rest.split_at(n);
        let (grad_p, rest) = rest.split_at(3 * n);
        let (div_tau, rest) = rest.split_at(3 * n);
        let (temperature, rest) = rest.split_at(heat * n);
        let (vorticity, rest) = rest.split_at(self.vorticity.as_ref().map_or(0, |_| 3 * n));
        let (ddt_u, sums) = rest.split_at(self.ddt_u.as_ref().map_or(0, |_| 3 * n));
        let v = |s: &[f64], i: usize| -> V3 { V3::new(s[3 * i], s[3 * i + 1], s[3 * i + 2]) };
        for (i, &c) in cells.iter().enumerate() {
            let c = c as usize;
            self.u[c] = v(u, i);
            self.p[c] = p[i];
            self.grad_p[c] = v(grad_p, i);
            self.div_tau[c] = v(div_tau, i);
        }
        if let Some(t) = self.temperature.as_mut() {
            for (&c, &value) in cells.iter().zip(temperature) {
                t[c as usize] = value;
            }
        }
        for (field, block) in [(&mut self.vorticity, vorticity), (&mut self.ddt_u, ddt_u)] {
            if let Some(w) = field.as_mut() {
                for (i, &c) in cells.iter().enumerate() {
                    w[c as usize] = v(block, i);
                }
            }
        }
        for (j, s) in sums.chunks_exact(per_patch).enumerate() {
            for (acc, x) in self.patch_sums[j].iter_mut().zip(s) {
                *acc += x;
            }
            if let Some(acc) = self.patch_t_flux.as_mut() {
                acc[j] += s[PATCH_WORDS];
            }
        }
        Ok(msg[0])
    }
}

/// Bytes of one advance for a mesh of `n_cells` cells on `ranks` ranks with `n_patches`
/// patches: (coupler → solver, solver → coupler), the message payloads only.
pub fn advance_bytes(n_cells: usize, ranks: usize, n_patches: usize) -> (usize, usize) {
    advance_bytes_with(n_cells, ranks, n_patches, false)
}

/// As [`advance_bytes`], with the heat blocks when `heat`.
pub fn advance_bytes_with(
    n_cells: usize,
    ranks: usize,
    n_patches: usize,
    heat: bool,
) -> (usize, usize) {
    let f = std::mem::size_of::<f64>();
    let h = if heat { HEAT_WORDS_PER_CELL } else { 0 };
    let sent = f * (4 * ranks + (FIELD_WORDS_PER_CELL + h) * n_cells);
    let received =
        f * (ranks * (1 + (PATCH_WORDS + h) * n_patches) + (STATE_WORDS_PER_CELL + h) * n_cells);
    (sent, received)
}

/// Checks the heat source before it goes to the solver: one finite value (K/s) per cell of the
/// mesh; the error names the global cell.
pub fn check_heat_source(map: &RankMap, heat_source: &[f64]) -> Result<(), crate::LinkError> {
    if heat_source.len() != map.n_cells() {
        return Err(couple::CoupleError::Length {
            what: "Tsource",
            expected: map.n_cells(),
            found: heat_source.len(),
        }
        .into());
    }
    if let Some(c) = heat_source.iter().position(|x| !x.is_finite()) {
        return Err(crate::LinkError::Value {
            what: "Tsource",
            cell: c,
            message: format!("{} K/s is not finite", heat_source[c]),
        });
    }
    Ok(())
}

/// Checks exchange fields before they go to the solver (which would stop on a NaN with a
/// floating-point trap, or on ε outside (0, 1]); the error names the field and global cell.
pub fn check_fields(map: &RankMap, fields: &FieldsIn<'_>) -> Result<(), crate::LinkError> {
    use crate::LinkError;
    let n = map.n_cells();
    for (what, len) in [
        ("voidage_old", fields.eps_old.len()),
        ("voidage_new", fields.eps_new.len()),
        ("Ksl", fields.ksl.len()),
        ("Us", fields.us.len()),
        ("f", fields.f.len()),
    ] {
        if len != n {
            return Err(couple::CoupleError::Length {
                what,
                expected: n,
                found: len,
            }
            .into());
        }
    }
    for (what, eps) in [
        ("voidage_old", fields.eps_old),
        ("voidage_new", fields.eps_new),
    ] {
        if let Some(c) = eps.iter().position(|&e| !(e > 0.0 && e <= 1.0)) {
            return Err(LinkError::Value {
                what,
                cell: c,
                message: format!("ε = {} is not in (0, 1]", eps[c]),
            });
        }
    }
    if let Some(c) = fields
        .ksl
        .iter()
        .position(|&k| !(k.is_finite() && k >= 0.0))
    {
        return Err(LinkError::Value {
            what: "Ksl",
            cell: c,
            message: format!("{} is not a finite value ≥ 0", fields.ksl[c]),
        });
    }
    for (what, v) in [("Us", fields.us), ("f", fields.f)] {
        if let Some(c) = v.iter().position(|x| !x.iter().all(|y| y.is_finite())) {
            return Err(LinkError::Value {
                what,
                cell: c,
                message: format!("{:?} is not finite", v[c]),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_packed_in_each_ranks_local_order_by_block() {
        // 3 global cells; this rank holds global cells 2 and 0 (in that local order).
        let eps_old = [0.1, 0.2, 0.3];
        let eps_new = [0.4, 0.5, 0.6];
        let ksl = [7.0, 8.0, 9.0];
        let us = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]].map(V3::from);
        let f = [[-1.0, -2.0, -3.0], [-4.0, -5.0, -6.0], [-7.0, -8.0, -9.0]].map(V3::from);
        let fields = FieldsIn {
            eps_old: &eps_old,
            eps_new: &eps_new,
            ksl: &ksl,
            us: &us,
            f: &f,
        };
        let mut out = vec![99.0; 5];
        pack_fields(&[2, 0], &fields, &mut out);
        let expected = [
            0.3, 0.1, // ε_old
            0.6, 0.4, // ε_new
            9.0, 7.0, // Ksl
            7.0, 8.0, 9.0, 1.0, 2.0, 3.0, // Us
            -7.0, -8.0, -9.0, -1.0, -2.0, -3.0, // f
        ];
        assert_eq!(out, expected);
    }

    #[test]
    fn replies_scatter_to_global_cells_and_patch_sums_add_over_ranks() {
        let mut s = GlobalState::new(3, 1);
        // Rank 0 holds global cells 1 and 2, rank 1 holds cell 0.
        let r0 = [
            0.5, // time
            1.0, 0.0, 0.0, 2.0, 0.0, 0.0, // U
            10.0, 20.0, // p
            0.0, 1.0, 0.0, 0.0, 2.0, 0.0, // ∇p
            0.0, 0.0, 1.0, 0.0, 0.0, 2.0, // ∇·τ
            3.0, 1.5, -0.25, // patch sums
        ];
        let r1 = [
            0.5, 3.0, 0.0, 0.0, 30.0, 0.0, 3.0, 0.0, 0.0, 0.0, 3.0, 1.0, 0.5, -0.75,
        ];
        s.clear_sums();
        assert_eq!(s.scatter(&[1, 2], &r0), Ok(0.5));
        assert_eq!(s.scatter(&[0], &r1), Ok(0.5));
        assert_eq!(
            s.u,
            [[3.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]].map(V3::from)
        );
        assert_eq!(s.p, [30.0, 10.0, 20.0]);
        assert_eq!(s.grad_p[0], V3::new(0.0, 3.0, 0.0));
        assert_eq!(s.div_tau[2], V3::new(0.0, 0.0, 2.0));
        assert_eq!(s.patch_sums, [[4.0, 2.0, -1.0]]);
        let err = s.scatter(&[0], &r1[..10]).unwrap_err();
        assert!(err.contains("10 values, expected 14"), "{err}");
    }

    #[test]
    fn handshake_checks_version_and_signs() {
        assert_eq!(
            Hello::parse(&[3, 4480, 1234, 3, 1]),
            Ok(Hello {
                version: 3,
                n_cells: 4480,
                pid: 1234,
                n_patches: 3,
                rank: 1,
                heat: false,
                cfdem_ksl: false,
                vorticity: false,
                ddt_u: false,
            })
        );
        assert!(Hello::parse(&[1, 1, 1, 1, 0])
            .unwrap_err()
            .contains("build.sh"));
        // a solver built before the watch (version 2) is asked to be rebuilt
        assert!(Hello::parse(&[2, 1, 1, 1, 0])
            .unwrap_err()
            .contains("build.sh"));
        assert!(Hello::parse(&[3, -1, 1, 1, 0])
            .unwrap_err()
            .contains("cell count"));
        assert!(Hello::parse(&[1, 1, 1]).is_err());
        assert_eq!(
            parse_patch_names(b"inlet\noutlet\nwalls\n").unwrap(),
            ["inlet", "outlet", "walls"]
        );
        assert!(parse_patch_names(b"inlet").is_err());
    }

    #[test]
    fn heat_adds_a_handshake_flag_a_tsource_block_and_a_t_block() {
        let hello = Hello::parse(&[3, 10, 7, 1, 0, HELLO_FLAG_HEAT]).unwrap();
        assert!(hello.heat && !hello.cfdem_ksl);
        // CFDEM's Ksl form (issue 28): flag 2, alone or with heat
        let hello = Hello::parse(&[3, 10, 7, 1, 0, HELLO_FLAG_KSL_CFDEM]).unwrap();
        assert!(!hello.heat && hello.cfdem_ksl);
        let hello = Hello::parse(&[3, 10, 7, 1, 0, 3]).unwrap();
        assert!(hello.heat && hello.cfdem_ksl);
        assert!(!Hello::parse(&[3, 10, 7, 1, 0]).unwrap().heat);
        // 4 and 8 are the lift fields' flags since issue 28; 16 is unknown
        assert!(Hello::parse(&[3, 10, 7, 1, 0, 16])
            .unwrap_err()
            .contains("flags"));
        assert!(Hello::parse(&[3, 10, 7, 1, 0, 1, 1])
            .unwrap_err()
            .contains("6 with heat"));

        // Tsource follows the nine blocks, in the rank's local order (global cells 1, 0).
        let one = [1.0, 1.0];
        let v = [V3::zeros(); 2];
        let fields = FieldsIn {
            eps_old: &one,
            eps_new: &one,
            ksl: &one,
            us: &v,
            f: &v,
        };
        let mut out = Vec::new();
        pack_fields(&[1, 0], &fields, &mut out);
        pack_heat_source(&[1, 0], &[-3.0, 4.0], &mut out);
        assert_eq!(out.len(), (FIELD_WORDS_PER_CELL + HEAT_WORDS_PER_CELL) * 2);
        assert_eq!(out[18..], [4.0, -3.0]);

        // The reply: time, U, p, ∇p, ∇·τ, T, then the patch sums.
        let mut s = GlobalState::with_heat(2, 1);
        let mut msg = vec![0.5];
        msg.extend([0.0; 20]);
        msg.extend([310.0, 320.0]);
        msg.extend([1.0, 2.0, 3.0, 930.0]);
        assert_eq!(s.scatter(&[1, 0], &msg), Ok(0.5));
        assert_eq!(s.temperature.as_deref(), Some(&[320.0, 310.0][..]));
        assert_eq!(s.patch_sums, [[1.0, 2.0, 3.0]]);
        assert_eq!(s.patch_t_flux.as_deref(), Some(&[930.0][..]));
        // A reply without the T block is refused when heat is on.
        let err = s.scatter(&[1, 0], &msg[..21 + 4 - 2]).unwrap_err();
        assert!(err.contains("expected 27"), "{err}");
        assert_eq!(
            advance_bytes_with(4480, 2, 3, true),
            (8 * (8 + 10 * 4480), 8 * (2 * 13 + 11 * 4480))
        );
    }

    #[test]
    fn heat_grows_the_sparse_records_by_one_and_the_patch_reply_by_one_per_patch() {
        // the solver's records as mpiCouplingSource.H documents them: 12 + T, 8 + Tsource
        assert_eq!(
            (sparse_reply_words(false), sparse_reply_words(true)),
            (12, 13)
        );
        assert_eq!(
            (
                sparse_sums_words(false, false),
                sparse_sums_words(true, false)
            ),
            (8, 9)
        );
        for heat in [false, true] {
            assert_eq!(
                sparse_reply_words(heat),
                couple::ranks::owner_reply_width(heat)
            );
            assert_eq!(
                sparse_sums_words(heat, false),
                couple::ranks::owner_sums_width(heat, false)
            );
            // CFDEM's Ksl form: seven more, after the heat column
            assert_eq!(
                sparse_sums_words(heat, true),
                couple::ranks::owner_sums_width(heat, true)
            );
        }
        // tag 23 with heat: time, then Σp|S|, Σ|S|, Σφ, Σφ T_b per patch, added over ranks
        let mut s = GlobalState::with_heat(2, 2);
        let rank0 = [0.5, 1.0, 2.0, 3.0, 30.0, 4.0, 5.0, 6.0, 60.0];
        let rank1 = [0.5, 0.5, 0.5, 0.5, 5.0, 1.0, 1.0, 1.0, 10.0];
        assert_eq!(s.add_patch_sums(&rank0), Ok(0.5));
        assert_eq!(s.add_patch_sums(&rank1), Ok(0.5));
        assert_eq!(s.patch_sums, [[1.5, 2.5, 3.5], [5.0, 6.0, 7.0]]);
        assert_eq!(s.patch_t_flux.as_deref(), Some(&[35.0, 70.0][..]));
        // the cold reply is refused with heat on, and the hot one without
        let err = s
            .add_patch_sums(&[0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
            .unwrap_err();
        assert!(err.contains("expected 9"), "{err}");
        let mut cold = GlobalState::new(2, 2);
        assert!(cold.add_patch_sums(&rank0).is_err());
        assert_eq!(
            cold.add_patch_sums(&[0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            Ok(0.5)
        );
        assert_eq!(cold.patch_sums, [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
    }

    #[test]
    fn vorticity_and_ddt_u_are_flags_and_blocks_after_the_heat_block() {
        let hello = Hello::parse(&[3, 10, 7, 1, 0, HELLO_FLAG_VORTICITY]).unwrap();
        assert!(hello.vorticity && !hello.ddt_u && !hello.heat && !hello.cfdem_ksl);
        let hello = Hello::parse(&[3, 10, 7, 1, 0, 1 | 4 | 8]).unwrap();
        assert!(hello.heat && hello.vorticity && hello.ddt_u && !hello.cfdem_ksl);
        assert!(Hello::parse(&[3, 10, 7, 1, 0, 16])
            .unwrap_err()
            .contains("flags"));
        // two cells (global 1, 0), one patch, heat, ω and DU/Dt: time, U, p, ∇p, ∇·τ, T, ω,
        // DU/Dt, then the patch's four sums
        let mut s = GlobalState::with_fields(2, 1, true, true, true);
        assert_eq!(s.cell_words(), 17);
        let mut msg = vec![0.25];
        msg.extend([0.0; 20]);
        msg.extend([300.0, 301.0]);
        msg.extend([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        msg.extend([-1.0, -2.0, -3.0, -4.0, -5.0, -6.0]);
        msg.extend([1.0, 2.0, 3.0, 4.0]);
        assert_eq!(s.scatter(&[1, 0], &msg), Ok(0.25));
        assert_eq!(
            s.vorticity.as_deref(),
            Some(&[V3::new(4.0, 5.0, 6.0), V3::new(1.0, 2.0, 3.0)][..])
        );
        assert_eq!(
            s.ddt_u.as_deref(),
            Some(&[V3::new(-4.0, -5.0, -6.0), V3::new(-1.0, -2.0, -3.0)][..])
        );
        assert_eq!(s.temperature.as_deref(), Some(&[301.0, 300.0][..]));
        assert_eq!(s.patch_sums, [[1.0, 2.0, 3.0]]);
        // ω alone, without heat: 13 per cell, 3 per patch
        let mut s = GlobalState::with_fields(1, 1, false, true, false);
        assert_eq!(s.cell_words(), 13);
        let msg = [
            0.5, 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 7.0, 8.0, 9.0, 1., 2., 3.,
        ];
        assert_eq!(s.scatter(&[0], &msg), Ok(0.5));
        assert_eq!(s.vorticity.as_deref(), Some(&[V3::new(7.0, 8.0, 9.0)][..]));
        assert!(s.ddt_u.is_none());
        // a reply without the block is refused
        let err = s.scatter(&[0], &msg[..14]).unwrap_err();
        assert!(err.contains("expected 17"), "{err}");
        // and the plain state is the plain state
        assert_eq!(
            GlobalState::with_fields(3, 1, false, false, false).cell_words(),
            10
        );
    }

    #[test]
    fn commands_encode_as_documented() {
        let c = Command::Advance {
            steps: 5,
            step_length: 1e-4,
            first: true,
        };
        assert_eq!(c.words(), [1.0, 5.0, 1e-4, 1.0]);
        assert_eq!(Command::Write.words()[0], 2.0);
        assert_eq!(Command::Stop.words()[0], 3.0);
        assert_eq!(Command::Exchange.words(), [4.0, 0.0, 0.0, 0.0]);
        let held = |first, whole| Command::AdvanceHeld {
            steps: 2,
            step_length: 5e-4,
            first,
            whole,
        };
        assert_eq!(held(false, false).words(), [5.0, 2.0, 5e-4, 0.0]);
        assert_eq!(held(true, false).words()[3], 1.0);
        assert_eq!(held(false, true).words()[3], 2.0);
        assert_eq!(held(true, true).words()[3], 3.0);
        assert_eq!(Command::Watch { cfl: false }.words(), [6.0, 0.0, 0.0, 0.0]);
        assert_eq!(Command::Watch { cfl: true }.words(), [6.0, 1.0, 0.0, 0.0]);
        // 4480 cells on 2 ranks, 3 patches: 8 (8 + 9·4480) and 8 (2·10 + 10·4480) bytes.
        assert_eq!(advance_bytes(4480, 2, 3), (322_624, 358_560));
    }
}
