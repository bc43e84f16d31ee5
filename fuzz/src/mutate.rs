//! Mutations: how the driver makes a new case from the pool. One case is one to four
//! of these stacked on a copy of a pool entry:
//!
//! - bit flip, byte set (random or one of 0, 1, 0x7f, 0x80, 0xff), random bytes inserted;
//! - a range deleted, duplicated in place 1 to 1000 times (a line or record repeated:
//!   what count and amplification bugs need), copied elsewhere, or the input cut short;
//! - a splice: this input's head with another pool entry's tail, or a range of
//!   another entry inserted;
//! - an ASCII number (a run of digits, signs, points and exponents around a digit)
//!   replaced by an extreme one ([`NUMBERS`]: 0, -1, 1e308, nan, inf, 4294967296,
//!   1e-320, huge counts);
//! - a binary integer or float overwritten in place (1, 2, 4 or 8 bytes, little- or
//!   big-endian; [`INTEGERS`], the old value plus or minus a little, NaN, infinities),
//!   half the time within the first 128 bytes, where headers are;
//! - nesting: a bracket pair whose contents start with another bracket, as in
//!   `{ union = [ A, B ] }`, wrapped in its own opening and closing parts 2 to 3000
//!   times (`{ union = [{ union = [ A, B ] }] }` ...), which stays well-formed TOML and
//!   makes the deep trees recursion bugs need.
//!
//! Every result is cut to `max_len` bytes.

use crate::rng::Rng;

/// Numbers written over ASCII numbers.
pub const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "3",
    "21",
    "22",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999",
    "1e308",
    "-1e308",
    "1e400",
    "1e-320",
    "1e-300",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "0.0",
    "0.5",
    "1e10",
    "1000000",
];

/// Integers written over binary fields.
pub const INTEGERS: &[u64] = &[
    0,
    1,
    2,
    7,
    8,
    21,
    22,
    0x7f,
    0x80,
    0xff,
    0x100,
    0x7fff,
    0x8000,
    0xffff,
    0x1_0000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x1_0000_0000,
    0x7fff_ffff_ffff_ffff,
    0x8000_0000_0000_0000,
    u64::MAX,
];

/// Makes new cases from old ones.
pub struct Mutator {
    /// The random source (the only one: a seed fixes every case).
    pub rng: Rng,
    /// The longest case made.
    pub max_len: usize,
}

impl Mutator {
    /// A mutator from `seed`, cutting cases to `max_len` bytes.
    #[must_use]
    pub fn new(seed: u64, max_len: usize) -> Self {
        Mutator { rng: Rng::new(seed), max_len }
    }

    /// A new case: a copy of `pool[i]` for a random `i`, mutated one to four times
    /// (`pool` non-empty).
    pub fn case(&mut self, pool: &[Vec<u8>]) -> Vec<u8> {
        let mut data = self.rng.pick(pool).clone();
        let rounds = 1 + self.rng.below(4);
        for _ in 0..rounds {
            self.mutate(&mut data, pool);
        }
        data.truncate(self.max_len);
        data
    }

    /// One mutation of `data`; `pool` gives splices.
    pub fn mutate(&mut self, data: &mut Vec<u8>, pool: &[Vec<u8>]) {
        if data.is_empty() {
            data.push(self.rng.next_u64() as u8);
            return;
        }
        match self.rng.below(14) {
            0 => {
                let i = self.rng.below(data.len());
                data[i] ^= 1 << self.rng.below(8);
            }
            1 => {
                let (i, random) = (self.rng.below(data.len()), self.rng.next_u64() as u8);
                data[i] = *self.rng.pick(&[0, 1, 0x7f, 0x80, 0xff, random]);
            }
            2 => {
                let i = self.rng.below(data.len() + 1);
                let n = 1 + self.rng.below(8);
                let bytes: Vec<u8> = (0..n).map(|_| self.rng.next_u64() as u8).collect();
                data.splice(i..i, bytes);
            }
            3 => {
                let (a, b) = self.range(data.len());
                data.drain(a..b);
            }
            4 => {
                let (a, b) = self.range(data.len());
                let times = if self.rng.one_in(4) { 1 + self.rng.below(1000) } else { 1 + self.rng.below(4) };
                let times = times.min(self.max_len.saturating_sub(data.len()) / (b - a).max(1));
                let piece = data[a..b].repeat(times);
                data.splice(b..b, piece);
            }
            5 => {
                let (a, b) = self.range(data.len());
                let piece = data[a..b].to_vec();
                let i = self.rng.below(data.len() + 1);
                data.splice(i..i, piece);
            }
            6 => data.truncate(self.rng.below(data.len())),
            7 => {
                let other = self.rng.pick(pool);
                let head = self.rng.below(data.len() + 1);
                let tail = self.rng.below(other.len() + 1);
                data.truncate(head);
                data.extend_from_slice(&other[tail..]);
            }
            8 => {
                let other = self.rng.pick(pool);
                if !other.is_empty() {
                    let (a, b) = self.range(other.len());
                    let i = self.rng.below(data.len() + 1);
                    data.splice(i..i, other[a..b].iter().copied());
                }
            }
            9 | 10 => self.number(data),
            11 | 12 => self.binary(data),
            _ => self.nest(data),
        }
    }

    /// A random non-empty range `a..b` of `0..len` (`len > 0`), usually short.
    fn range(&mut self, len: usize) -> (usize, usize) {
        let a = self.rng.below(len);
        let most = if self.rng.one_in(8) { len - a } else { (len - a).min(64) };
        (a, a + 1 + self.rng.below(most))
    }

    /// Replaces the ASCII number at or after a random place (else the first one) by
    /// one of [`NUMBERS`].
    fn number(&mut self, data: &mut Vec<u8>) {
        let start = self.rng.below(data.len());
        let digit = |from: usize| data[from..].iter().take(4096).position(u8::is_ascii_digit).map(|p| from + p);
        let Some(d) = digit(start).or_else(|| digit(0)) else { return };
        let part = |b: &u8| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E');
        let a = data[..d].iter().rposition(|b| !part(b)).map_or(0, |p| p + 1);
        let b = data[d..].iter().position(|b| !part(b)).map_or(data.len(), |p| d + p);
        let new = self.rng.pick(NUMBERS).as_bytes();
        data.splice(a..b, new.iter().copied());
    }

    /// Overwrites a binary field with an extreme integer, a nudged value or a
    /// special float.
    fn binary(&mut self, data: &mut [u8]) {
        let width = *self.rng.pick(&[1usize, 2, 4, 4, 8]);
        if data.len() < width {
            return;
        }
        let room = data.len() - width + 1;
        let at = if self.rng.one_in(2) { self.rng.below(room.min(128)) } else { self.rng.below(room) };
        let field = &mut data[at..at + width];
        let big_endian = self.rng.one_in(5);
        let mut old = [0u8; 8];
        old[..width].copy_from_slice(field);
        if big_endian {
            old[..width].reverse();
        }
        let old = u64::from_le_bytes(old);
        let value = match self.rng.below(4) {
            0 | 1 => *self.rng.pick(INTEGERS),
            2 => {
                let delta = 1 + self.rng.below(16) as u64;
                if self.rng.one_in(2) { old.wrapping_add(delta) } else { old.wrapping_sub(delta) }
            }
            _ if width == 4 => {
                u64::from(self.rng.pick(&[f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, 1e-45, -0.0]).to_bits())
            }
            _ if width == 8 => {
                self.rng.pick(&[f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, 5e-324, -0.0, 1e300]).to_bits()
            }
            _ => *self.rng.pick(INTEGERS),
        };
        let mut bytes = value.to_le_bytes();
        if big_endian {
            bytes[..width].reverse();
        }
        field.copy_from_slice(&bytes[..width]);
    }

    /// Wraps a bracket pair whose contents open with another bracket in copies of its
    /// own opening and closing parts (module doc).
    fn nest(&mut self, data: &mut Vec<u8>) {
        let start = self.rng.below(data.len());
        let Some(i) = data[start..].iter().take(4096).position(|b| matches!(b, b'{' | b'[' | b'(')).map(|p| start + p)
        else {
            return;
        };
        let Some(j) = matching(data, i) else { return };
        let Some(m) = data[i + 1..j].iter().position(|b| matches!(b, b'{' | b'[' | b'(')).map(|p| i + 1 + p) else {
            return;
        };
        let Some(k) = matching(data, m) else { return };
        let (open, close) = (data[i..=m].to_vec(), data[k..=j].to_vec());
        let each = open.len() + close.len();
        let most = if self.rng.one_in(3) { 3000 } else { 30 };
        let times = (1 + self.rng.below(most)).min(self.max_len.saturating_sub(data.len()) / each);
        data.splice(j + 1..j + 1, close.repeat(times));
        data.splice(i..i, open.repeat(times));
    }
}

/// The index of the bracket closing the one at `open`, counting all three kinds
/// alike (good enough for mutation), if any.
fn matching(data: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, b) in data.iter().enumerate().skip(open) {
        match b {
            b'{' | b'[' | b'(' => depth += 1,
            b'}' | b']' | b')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_wraps_the_outer_pair_in_its_own_parts() {
        let mut m = Mutator::new(1, 1 << 20);
        let text = b"shape = { union = [ A, B ] }".to_vec();
        for seed in 0..200 {
            m.rng = Rng::new(seed);
            let mut data = text.clone();
            m.nest(&mut data);
            let s = String::from_utf8(data).unwrap();
            let opens = s.matches("{ union = [").count();
            assert_eq!(s.matches("] }").count(), opens, "{s}");
            assert!(s.starts_with("shape = ") && s.contains("[ A, B ]"), "{s}");
        }
    }

    #[test]
    fn a_number_is_replaced_whole() {
        let mut m = Mutator::new(7, 1 << 20);
        for _ in 0..100 {
            let mut data = b"depth = 12.5e3\n".to_vec();
            m.number(&mut data);
            let s = String::from_utf8(data).unwrap();
            let value = s.trim_start_matches("depth = ").trim_end();
            assert!(NUMBERS.contains(&value), "{s:?}");
        }
    }

    #[test]
    fn cases_respect_the_length_limit_and_the_seed() {
        let pool = vec![b"v 1 2 3\nf 1 2 3\n".to_vec(), vec![0u8; 300]];
        let run = |seed| {
            let mut m = Mutator::new(seed, 256);
            (0..500).map(|_| m.case(&pool)).collect::<Vec<_>>()
        };
        let a = run(3);
        assert!(a.iter().all(|c| c.len() <= 256));
        assert_eq!(a, run(3));
        assert_ne!(a, run(4));
    }
}
