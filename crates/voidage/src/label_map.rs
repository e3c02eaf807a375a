//! A small open-addressing hash map from cell or face labels to values, cleared in time
//! proportional to its content: per-particle visited sets and face caches whose size does not
//! depend on the mesh size.

use foam::Label;

const EMPTY: Label = Label::MAX;

/// Map from labels (< `Label::MAX`) to `V`.
#[derive(Clone, Debug)]
pub(crate) struct LabelMap<V: Copy + Default> {
    keys: Vec<Label>,
    vals: Vec<V>,
    used: Vec<u32>,
    bits: u32,
}

impl<V: Copy + Default> Default for LabelMap<V> {
    fn default() -> Self {
        Self::with_bits(6)
    }
}

impl<V: Copy + Default> LabelMap<V> {
    fn with_bits(bits: u32) -> Self {
        LabelMap {
            keys: vec![EMPTY; 1 << bits],
            vals: vec![V::default(); 1 << bits],
            used: Vec::new(),
            bits,
        }
    }

    #[inline]
    fn home(&self, k: Label) -> usize {
        ((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - self.bits)) as usize
    }

    #[inline]
    fn find(&self, k: Label) -> (usize, bool) {
        let mask = (1usize << self.bits) - 1;
        let mut i = self.home(k);
        loop {
            let key = self.keys[i];
            if key == k {
                return (i, true);
            }
            if key == EMPTY {
                return (i, false);
            }
            i = (i + 1) & mask;
        }
    }

    /// Removes every entry.
    pub(crate) fn clear(&mut self) {
        for &i in &self.used {
            self.keys[i as usize] = EMPTY;
        }
        self.used.clear();
    }

    /// The value of `k`.
    #[inline]
    pub(crate) fn get(&self, k: Label) -> Option<V> {
        let (i, found) = self.find(k);
        found.then(|| self.vals[i])
    }

    /// Inserts `k` with `v` if absent; true when it was absent.
    #[inline]
    pub(crate) fn insert(&mut self, k: Label, v: V) -> bool {
        if 2 * (self.used.len() + 1) > self.keys.len() {
            self.grow();
        }
        let (i, found) = self.find(k);
        if found {
            return false;
        }
        self.keys[i] = k;
        self.vals[i] = v;
        self.used.push(i as u32);
        true
    }

    fn grow(&mut self) {
        let mut bigger = Self::with_bits(self.bits + 1);
        for &i in &self.used {
            bigger.insert(self.keys[i as usize], self.vals[i as usize]);
        }
        *self = bigger;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_get_clear_grow() {
        let mut m = LabelMap::<f64>::default();
        for k in 0..1000u32 {
            assert!(m.insert(k * 7919, k as f64));
            assert!(!m.insert(k * 7919, -1.0));
        }
        for k in 0..1000u32 {
            assert_eq!(m.get(k * 7919), Some(k as f64));
            assert_eq!(m.get(k * 7919 + 1), None);
        }
        m.clear();
        assert_eq!(m.get(7919), None);
        assert!(m.insert(7919, 2.0));
        assert_eq!(m.get(7919), Some(2.0));
    }
}
