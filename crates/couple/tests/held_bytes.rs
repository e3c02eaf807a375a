//! What a coupler says it holds (`foam::HeapBytes`, `Coupler::held_bytes`) against the
//! allocator: this test binary counts every byte allocated and freed (a counting global
//! allocator, the independent reference), so the bytes a structure keeps after it is built are
//! the live bytes it added. One test function, so no other test allocates meanwhile.
//!
//! A whole mesh and a part of it must match to the byte (every allocation they keep is a
//! vector or string they count; they are built on the test's own thread, so these two are
//! counted by that thread's allocations alone: rayon's workers, still settling after the
//! voidage mesh built before them, allocated 3.7 kB during the whole mesh's build in one run
//! of three); the voidage mesh and what a coupler's exchanges add within
//! 4 kB (they run on rayon's pool, whose queues may keep a block of their own); a new coupler
//! within 64 bytes (its `Box<dyn Ranks>`, which it does not count).
//! Measured when written: the voidage mesh of 24,000 cells 75,117,752 B both ways; the coupler
//! on the part 5,051,584 B counted against 5,051,592 B; two exchanges of 2,000 particles
//! 785,160 B both ways.

use closures::DragLaw;
use couple::memory::MemoryFluid;
use couple::{Coupler, FluidSide, Interpolation};
use foam::HeapBytes;
use mesh::build::hex_grid;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicIsize, Ordering};
use voidage::{Method, VoidageMesh};

mod common;

/// The system allocator, counting the bytes it holds.
struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

thread_local! {
    /// The bytes this thread's allocations hold (const-initialised: no allocation of its own).
    static MINE: Cell<isize> = const { Cell::new(0) };
}

/// Adds `d` to the calling thread's count (not during the thread's teardown).
fn mine(d: isize) {
    let _ = MINE.try_with(|m| m.set(m.get() + d));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::SeqCst);
        mine(layout.size() as isize);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::SeqCst);
        mine(-(layout.size() as isize));
        System.dealloc(ptr, layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::SeqCst);
        mine(layout.size() as isize);
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_add(new_size as isize - layout.size() as isize, Ordering::SeqCst);
        mine(new_size as isize - layout.size() as isize);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static A: Counting = Counting;

/// What rayon's pool may keep between calls, B (module docs).
const RAYON: usize = 4096;

/// The live bytes `build` adds on the calling thread alone, and what it built.
fn added_here<T>(build: impl FnOnce() -> T) -> (usize, T) {
    let before = MINE.with(|m| m.get());
    let t = build();
    let after = MINE.with(|m| m.get());
    ((after - before) as usize, t)
}

/// The live bytes `build` adds, and what it built.
fn added<T>(build: impl FnOnce() -> T) -> (usize, T) {
    let before = LIVE.load(Ordering::SeqCst);
    let t = build();
    let after = LIVE.load(Ordering::SeqCst);
    ((after - before) as usize, t)
}

#[test]
fn what_the_structures_say_they_hold_is_what_the_allocator_gave_them() {
    let planes = |n: usize| (0..=n).map(|i| i as f64 / n as f64).collect::<Vec<_>>();
    // rayon's pool and the first call's lazy statics, before anything is measured
    drop(VoidageMesh::new(&hex_grid(&planes(3), &planes(3), &planes(3))).unwrap());

    let (bytes, whole) = added_here(|| hex_grid(&planes(40), &planes(30), &planes(20)));
    assert_eq!(whole.heap_bytes(), bytes);
    // 24,000 cells: at least the points (41·31·21 × 24 B) and the faces' labels (4 per face)
    assert!(bytes > 41 * 31 * 21 * 24 + 4 * 4 * whole.faces.len());

    let region = Aabb {
        min: V3::new(0.2, 0.2, 0.2),
        max: V3::new(0.5, 0.4, 0.6),
    };
    let (bytes, part) = added_here(|| MeshPart::around(&whole, &region).unwrap());
    assert_eq!(part.heap_bytes(), bytes);
    assert!(part.mesh.n_cells < whole.n_cells / 4);

    let (bytes, vm) = added(|| VoidageMesh::new(&whole).unwrap());
    let counted = vm.heap_bytes();
    println!("voidage mesh: counted {counted} B, allocator {bytes} B");
    assert!(counted.abs_diff(bytes) <= RAYON, "{counted} vs {bytes}");
    drop(vm);

    // a coupler on the part, then after an exchange of 2,000 particles (divided: its memo)
    let settings = common::drag_settings(
        Method::Divided,
        DragLaw::DiFelice,
        Interpolation::Cell,
        1.2,
        1.5e-5,
    );
    let fluid = MemoryFluid::uniform(part.mesh.clone(), V3::new(0.0, 0.0, 0.1));
    let (bytes, mut coupler) = added(|| Coupler::new(&part.mesh, settings).unwrap());
    let held = coupler.held_bytes();
    println!("coupler: counted {held:?}, allocator {bytes} B");
    assert_eq!(held.particles, 0);
    assert!(
        held.mesh <= bytes && bytes - held.mesh <= 64,
        "{held:?} vs {bytes}"
    );

    let n = 2000;
    let x: Vec<V3> = (0..n)
        .map(|k| {
            let s = k as f64;
            V3::new(
                0.25 + 0.2 * (s * 0.37).fract(),
                0.25 + 0.1 * (s * 0.71).fract(),
                0.3,
            ) + V3::new(0.0, 0.0, 0.25 * (s * 0.13).fract())
        })
        .collect();
    let particles = common::Particles::new(x, vec![V3::zeros(); n]);
    let before = LIVE.load(Ordering::SeqCst) as usize;
    for _ in 0..2 {
        let step = coupler
            .exchange(&particles.state(), &fluid.state())
            .unwrap();
        coupler.recycle(step);
    }
    let bytes = LIVE.load(Ordering::SeqCst) as usize - before;
    let grown = coupler.held_bytes();
    let counted = grown.mesh + grown.particles - held.mesh - held.particles;
    println!("coupler after the exchanges: counted {grown:?}, allocator {bytes} B more");
    assert!(grown.particles > n * (8 + 8 + 4 * 8));
    assert!(counted.abs_diff(bytes) <= RAYON, "{counted} vs {bytes}");
}
