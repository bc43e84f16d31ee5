//! A sharded job's identity: 16 bytes every part file and the index carry, and the
//! name of the staging folder its tasks write into (`OUT.partial/job-HEX/`), so that
//! the tasks of two different jobs writing the same output never meet in one join.
//!
//! The identity is the 128-bit FNV-1a hash of what makes the job: a version tag, the
//! caller's description of the job ([`super::StreamOptions::source`]; the command
//! line passes its arguments without `--cells`), the domain (its floats' bits), the
//! metadata codes, the cell level, and for meshes and set operations the input
//! itself (the mesh's vertices and triangles, the operands' indexes). Every task of
//! one job computes it alike on any machine; a different shape, depth, domain, level
//! or input gives another. FNV-1a is not a cryptographic hash: the identity tells
//! jobs apart by accident, not against someone forging parts (who could as well
//! forge shards).

use std::fmt;

use crate::io::oct::Metadata;
use crate::octree::Domain;

/// The identity of a sharded job (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct JobId(pub [u8; 16]);

impl fmt::Display for JobId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.iter().try_for_each(|b| write!(f, "{b:02x}"))
    }
}

impl JobId {
    /// The identity of an index written before jobs had one (format version 1).
    pub const NONE: JobId = JobId([0; 16]);

    /// Parses the 32 hexadecimal digits [`JobId`]'s `Display` writes.
    #[must_use]
    pub fn parse(hex: &str) -> Option<JobId> {
        if hex.len() != 32 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let mut id = [0u8; 16];
        for (i, byte) in id.iter_mut().enumerate() {
            *byte = u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).ok()?;
        }
        Some(JobId(id))
    }
}

/// 128-bit FNV-1a.
pub(crate) struct JobHasher(u128);

impl JobHasher {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;

    /// A hasher over the parts every job shares.
    pub(crate) fn new(source: &[u8], domain: Domain, meta: Metadata, level: u8) -> JobHasher {
        let mut h = JobHasher(Self::OFFSET);
        h.bytes(b"octsolid sharded job 1\0");
        h.u64(source.len() as u64);
        h.bytes(source);
        for v in [domain.min().x, domain.min().y, domain.min().z, domain.edge()] {
            h.u64(v.to_bits());
        }
        h.bytes(&[domain.depth(), level]);
        h.bytes(&meta.codes());
        h
    }

    pub(crate) fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u128::from(b)).wrapping_mul(Self::PRIME);
        }
    }

    pub(crate) fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    pub(crate) fn finish(&self) -> JobId {
        JobId(self.0.to_le_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_128_matches_its_published_test_vector_and_ids_round_trip_through_hex() {
        // FNV-1a 128 of "a" (the reference implementation's test suite).
        let mut h = JobHasher(JobHasher::OFFSET);
        h.bytes(b"a");
        assert_eq!(h.0, 0xd228_cb69_6f1a_8caf_7891_2b70_4e4a_8964);
        let id = h.finish();
        assert_eq!(JobId::parse(&id.to_string()), Some(id));
        assert_eq!(JobId::parse("zz"), None);
    }
}
