//! Byte-level mutations of fuzz inputs: bit flips, byte changes, insertions, deletions,
//! duplications of a chunk (deeper nesting, longer lists), dictionary tokens, interesting
//! numbers and splices with another corpus entry.

/// A small, fast pseudo-random generator (xorshift64*).
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed (any value; 0 is replaced).
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A random index below `n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }
}

/// Numbers that often hit edge cases of numeric parsing and range checks.
const NUMBERS: [&str; 12] = [
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "18446744073709551616",
    "-1",
    "0.000000000000000000001",
];

/// Mutate `data` with 1–8 stacked mutations, keeping it at most `max_len` bytes; `dict`
/// holds tokens to insert and `other` another corpus entry to splice with.
pub fn mutate(data: &mut Vec<u8>, rng: &mut Rng, dict: &[&str], other: &[u8], max_len: usize) {
    let rounds = 1 + rng.below(8);
    for _ in 0..rounds {
        one(data, rng, dict, other);
    }
    data.truncate(max_len);
}

fn insert(data: &mut Vec<u8>, at: usize, bytes: &[u8]) {
    let at = at.min(data.len());
    data.splice(at..at, bytes.iter().copied());
}

/// A random range of `data` of at most `max` bytes.
fn range(data: &[u8], rng: &mut Rng, max: usize) -> std::ops::Range<usize> {
    let start = rng.below(data.len() + 1);
    let len = rng.below(max.min(data.len() - start) + 1);
    start..start + len
}

fn one(data: &mut Vec<u8>, rng: &mut Rng, dict: &[&str], other: &[u8]) {
    let n = data.len();
    match rng.below(10) {
        0 if n > 0 => {
            let i = rng.below(n);
            data[i] ^= 1 << rng.below(8);
        }
        1 if n > 0 => {
            let i = rng.below(n);
            data[i] = rng.next_u64() as u8;
        }
        2 => {
            let b = [rng.next_u64() as u8; 1];
            insert(data, rng.below(n + 1), &b);
        }
        3 if n > 0 => {
            let r = range(data, rng, 64);
            data.drain(r);
        }
        4 if n > 0 => {
            // duplicate a chunk, possibly many times (nesting, long lists)
            let r = range(data, rng, 256);
            let chunk = data[r].to_vec();
            let times = if rng.below(8) == 0 {
                1 + rng.below(2000)
            } else {
                1
            };
            insert(data, rng.below(n + 1), &chunk.repeat(times));
        }
        5 | 6 if !dict.is_empty() => {
            let t = dict[rng.below(dict.len())];
            insert(data, rng.below(n + 1), t.as_bytes());
        }
        7 => {
            // replace a run of digits (or insert) with an interesting number
            let t = NUMBERS[rng.below(NUMBERS.len())].as_bytes();
            let at = rng.below(n + 1);
            let end = data[at..]
                .iter()
                .position(|b| !(b.is_ascii_digit() || *b == b'.' || *b == b'-'))
                .map_or(n, |p| at + p);
            data.splice(at..end, t.iter().copied());
        }
        8 if !other.is_empty() => {
            // splice: a chunk of another corpus entry
            let r = range(other, rng, 4096);
            insert(data, rng.below(n + 1), &other[r]);
        }
        _ if n > 1 => {
            // swap two bytes
            let (i, j) = (rng.below(n), rng.below(n));
            data.swap(i, j);
        }
        _ => data.push(rng.next_u64() as u8),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutations_respect_the_length_bound_and_change_inputs() {
        let mut rng = Rng::new(7);
        let mut changed = 0;
        for _ in 0..2000 {
            let mut d = b"<a><b>1.5</b></a>".to_vec();
            mutate(&mut d, &mut rng, &["<c>"], b"xyz", 64);
            assert!(d.len() <= 64);
            changed += usize::from(d != b"<a><b>1.5</b></a>");
        }
        assert!(changed > 1900, "{changed}");
    }
}
