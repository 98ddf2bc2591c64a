//! Places in a linear store for sets that each live only between two steps of a sweep: a
//! span freed by one set is given to a later one (best fit, free neighbours merged), so the
//! store is as long as the most entries live at once instead of the sum over all sets.

use std::collections::{BTreeMap, BTreeSet};

/// Best-fit allocator of spans `[start, start + len)` of a store of `u32`-indexed entries.
#[derive(Debug, Default)]
pub(super) struct Slots {
    /// Free spans by `(len, start)` (best fit) and by `start → len` (merging).
    by_len: BTreeSet<(u32, u32)>,
    by_start: BTreeMap<u32, u32>,
    /// End of the used part of the store.
    end: u32,
    /// Largest `end` so far: the store length needed.
    peak: u32,
}

impl Slots {
    /// Start of a span of `len` entries (0 for an empty span).
    pub(super) fn alloc(&mut self, len: u32) -> u32 {
        if len == 0 {
            return 0;
        }
        if let Some(&(free_len, start)) = self.by_len.range((len, 0)..).next() {
            self.remove(start, free_len);
            if free_len > len {
                self.insert(start + len, free_len - len);
            }
            return start;
        }
        let start = self.end;
        self.end += len;
        self.peak = self.peak.max(self.end);
        start
    }

    /// Gives back the span `[start, start + len)` of an earlier [`Slots::alloc`].
    pub(super) fn free(&mut self, start: u32, len: u32) {
        if len == 0 {
            return;
        }
        let (mut start, mut len) = (start, len);
        if let Some(&next) = self.by_start.get(&(start + len)) {
            self.remove(start + len, next);
            len += next;
        }
        if let Some((&prev_start, &prev_len)) = self.by_start.range(..start).next_back() {
            if prev_start + prev_len == start {
                self.remove(prev_start, prev_len);
                start = prev_start;
                len += prev_len;
            }
        }
        if start + len == self.end {
            self.end = start;
        } else {
            self.insert(start, len);
        }
    }

    /// Store length that holds every span ever allocated.
    pub(super) fn peak(&self) -> u32 {
        self.peak
    }

    fn insert(&mut self, start: u32, len: u32) {
        self.by_len.insert((len, start));
        self.by_start.insert(start, len);
    }

    fn remove(&mut self, start: u32, len: u32) {
        self.by_len.remove(&(len, start));
        self.by_start.remove(&start);
    }
}

#[cfg(test)]
mod tests {
    use super::Slots;

    /// Live spans never overlap, freed space is reused and merged, and the peak is the
    /// largest live total for a stack-like sequence.
    #[test]
    fn spans_are_disjoint_and_reused() {
        let mut s = Slots::default();
        let a = s.alloc(10);
        let b = s.alloc(5);
        let c = s.alloc(7);
        assert_eq!((a, b, c), (0, 10, 15));
        s.free(b, 5);
        // best fit: a 4-entry span goes into the 5-entry hole
        let d = s.alloc(4);
        assert_eq!(d, 10);
        s.free(a, 10);
        s.free(d, 4);
        // [0, 15) is one free span again (a, d and the 1-entry rest merged)
        assert_eq!(s.alloc(15), 0);
        assert_eq!(s.peak(), 22);
        // freeing the last span shrinks the used end: the next span starts there
        s.free(c, 7);
        assert_eq!(s.alloc(3), 15);
        assert_eq!(s.alloc(0), 0);
        assert_eq!(s.peak(), 22);
    }

    /// Random alloc/free sequences: every live span lies inside the peak and overlaps no
    /// other live span.
    #[test]
    fn random_sequences_keep_live_spans_apart() {
        let mut seed = 12345u64;
        let mut next = |m: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) % m
        };
        let mut s = Slots::default();
        let mut live: Vec<(u32, u32)> = Vec::new();
        for _ in 0..2000 {
            if live.is_empty() || next(3) > 0 {
                let len = 1 + next(50) as u32;
                live.push((s.alloc(len), len));
            } else {
                let i = next(live.len() as u64) as usize;
                let (st, len) = live.swap_remove(i);
                s.free(st, len);
            }
            let mut sorted = live.clone();
            sorted.sort();
            for w in sorted.windows(2) {
                assert!(w[0].0 + w[0].1 <= w[1].0, "overlap {w:?}");
            }
            if let Some(&(st, len)) = sorted.last() {
                assert!(st + len <= s.peak());
            }
        }
    }
}
