//! Ray files: how the harness hands its ray sets to peers outside Rust (embreex through
//! `benches/peers/embreex_ray_files.py`, Embree 3 from C through
//! `benches/peers/embree3_rays.sh`), the format `benches/peers/embree_rays.py --dump`
//! already writes.
//!
//! A file `NAME.rays` is a bare array of records, one a ray, no header: seven
//! little-endian IEEE-754 `f64`s, 56 bytes: origin x, y, z; unit direction x, y, z;
//! `t_max` (`+inf` for an unbounded ray). The query is in the name: `shadow.rays` asks
//! "anything before `t_max`?", every other set the closest hit. In numpy:
//! `np.fromfile(path, "<f8").reshape(-1, 7)`.

use std::io::Write;
use std::path::Path;

use octsolid::io::write_atomic;
use octsolid::{Error, Ray, Result};

/// Bytes of one record.
pub const RECORD: usize = 56;

/// Writes `rays` to `path` (atomically).
pub fn write_rays(path: &Path, rays: &[Ray]) -> Result<()> {
    let mut bytes = Vec::with_capacity(rays.len() * RECORD);
    for r in rays {
        for v in [r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.t_max] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    write_atomic(path, |w: &mut dyn Write| w.write_all(&bytes))?;
    Ok(())
}

/// Reads the rays of `path`; a length that is not a whole number of records is an error
/// naming the file and the byte where the partial record starts.
pub fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    if !bytes.len().is_multiple_of(RECORD) {
        return Err(Error::Format {
            path: path.to_path_buf(),
            offset: (bytes.len() - bytes.len() % RECORD) as u64,
            reason: format!("{} bytes is not a whole number of {RECORD}-byte ray records", bytes.len()),
        });
    }
    Ok(bytes
        .chunks_exact(RECORD)
        .map(|record| {
            let v: Vec<f64> =
                record.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))).collect();
            Ray { origin: glam::DVec3::new(v[0], v[1], v[2]), dir: glam::DVec3::new(v[3], v[4], v[5]), t_max: v[6] }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rays_come_back_bit_for_bit_and_a_torn_file_is_named() {
        let dir = std::env::temp_dir().join(format!("octsolid-ray-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bounce.rays");
        let rays = vec![
            Ray { origin: DVec3::new(1.0, -2.5, 1e-300), dir: DVec3::new(0.0, 0.6, -0.8), t_max: f64::INFINITY },
            Ray { origin: DVec3::new(-0.0, 3.0, 7.0), dir: DVec3::X, t_max: 2.25 },
        ];
        write_rays(&path, &rays).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), 2 * RECORD);
        // The format by hand: the second record's t_max is bytes 104..112.
        assert_eq!(f64::from_le_bytes(bytes[104..112].try_into().unwrap()), 2.25);
        let back = read_rays(&path).unwrap();
        assert_eq!(back.len(), 2);
        for (a, b) in rays.iter().zip(&back) {
            assert_eq!(a.origin.to_array().map(f64::to_bits), b.origin.to_array().map(f64::to_bits));
            assert_eq!(a.dir, b.dir);
            assert_eq!(a.t_max, b.t_max);
        }
        std::fs::write(&path, &bytes[..RECORD + 10]).unwrap();
        let e = read_rays(&path).unwrap_err().to_string();
        assert!(e.contains("bounce.rays") && e.contains("byte 56"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
