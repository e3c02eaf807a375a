//! Bytes a structure holds on the heap ([`HeapBytes`]): what a coupler rank's mesh part and
//! its per-particle buffers cost (`docs/scaling.md`, issue 29), measured on the structures
//! themselves instead of inferred from the process's resident memory.
//!
//! The count is capacity-based: a `Vec<T>` counts `capacity × size_of::<T>()` bytes (what it
//! asked the allocator for), plus what its elements hold in turn. It leaves out the
//! allocator's own bookkeeping (8–16 bytes per allocation with glibc's malloc) and the
//! structure's inline size (`size_of_val`), which lives wherever the structure does.

use crate::poly_mesh::{FaceList, Patch, PolyMesh};

/// Bytes held on the heap (module docs).
pub trait HeapBytes {
    /// Bytes this value's allocations hold (capacity-based; not its inline size).
    fn heap_bytes(&self) -> usize;
}

/// The bytes of a vector of plain values (`Copy`: they own no allocation of their own).
pub fn flat<T: Copy>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

impl<T: HeapBytes> HeapBytes for Vec<T> {
    fn heap_bytes(&self) -> usize {
        self.capacity() * std::mem::size_of::<T>()
            + self.iter().map(HeapBytes::heap_bytes).sum::<usize>()
    }
}

impl<T: HeapBytes> HeapBytes for Option<T> {
    fn heap_bytes(&self) -> usize {
        self.as_ref().map_or(0, HeapBytes::heap_bytes)
    }
}

impl<A: HeapBytes, B: HeapBytes> HeapBytes for (A, B) {
    fn heap_bytes(&self) -> usize {
        self.0.heap_bytes() + self.1.heap_bytes()
    }
}

impl HeapBytes for String {
    fn heap_bytes(&self) -> usize {
        self.capacity()
    }
}

impl HeapBytes for FaceList {
    fn heap_bytes(&self) -> usize {
        flat(&self.offsets) + flat(&self.labels)
    }
}

impl HeapBytes for Patch {
    fn heap_bytes(&self) -> usize {
        self.name.heap_bytes() + self.patch_type.heap_bytes() + self.extra.heap_bytes()
    }
}

impl HeapBytes for PolyMesh {
    fn heap_bytes(&self) -> usize {
        flat(&self.points)
            + self.faces.heap_bytes()
            + flat(&self.owner)
            + flat(&self.neighbour)
            + self.boundary.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_counts_its_arrays_from_their_lengths() {
        // two hexahedra side by side: 12 points, 11 faces of 4 points, one internal
        let points: Vec<[f64; 3]> = (0..12)
            .map(|i| [(i % 3) as f64, ((i / 3) % 2) as f64, (i / 6) as f64])
            .collect();
        let mut offsets = vec![0];
        let mut labels = Vec::new();
        for f in 0..11 {
            labels.extend_from_slice(&[f, f + 1, 0, 1]);
            offsets.push(labels.len() as crate::Label);
        }
        let (offsets, labels) = (offsets.to_vec(), labels.to_vec());
        let faces = FaceList::from_compact(offsets, labels).unwrap();
        let patch = Patch {
            name: "walls".to_string(),
            patch_type: "wall".to_string(),
            n_faces: 10,
            start_face: 1,
            extra: vec![("inGroups".to_string(), "List<word> 1(wall)".to_string())],
        };
        let mesh = PolyMesh {
            points,
            faces,
            owner: vec![0; 11],
            neighbour: vec![1],
            boundary: vec![patch],
            n_cells: 2,
        };
        // by hand: points 12 × 24, offsets 12 × 4, labels 44 × 4, owner 11 × 4, neighbour 4,
        // one Patch record, its strings 5 + 4 + 8 + 18 bytes and one (String, String) record
        let patch_record = std::mem::size_of::<Patch>();
        let pair = 2 * std::mem::size_of::<String>();
        let by_hand = 12 * 24 + 12 * 4 + 44 * 4 + 11 * 4 + 4 + patch_record + 5 + 4 + pair + 8 + 18;
        assert_eq!(mesh.heap_bytes(), by_hand);
    }
}
