//! Three f64 lanes (x, y, z) for the walk's per-axis arithmetic, in three builds that
//! give the same bits: AVX2 (one 256-bit register, the fourth lane idle), SSE2 (x and
//! y in one 128-bit register, z in another; part of the x86-64 baseline) and scalar
//! (other targets, and the tests' oracle). The walk is written once over [`Lanes`]
//! and compiled for each; [`Isa::detect`] picks AVX2 at run time where the CPU has
//! it, so one binary runs on every x86-64 machine.
//!
//! Why the bits agree: every lane operation is the scalar IEEE operation on that lane
//! (add, subtract, multiply, compare), and the horizontal minimum is taken in the
//! scalar order `earlier(earlier(x, y), z)` with `earlier(p, q) = if p < q { p } else
//! { q }`, which is what `minpd(p, q)` does (it returns `q` unless `p < q`). No fused
//! multiply-add is ever formed: the intrinsics name each operation.
//!
//! The idle fourth lane (AVX2) is kept at `+inf` by the walk's inputs (see
//! `walk::RayLanes`), so it is never crossed and never the minimum.

/// The smaller of two times that are not NaN, `if x < y { x } else { y }` (so of two
/// zeros, `y`): the order every minimum of plane times is taken in.
#[inline(always)]
pub(super) fn earlier(x: f64, y: f64) -> f64 {
    if x < y { x } else { y }
}

/// The instruction sets the walk is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Isa {
    /// x86-64 with AVX2 (checked at run time).
    Avx2,
    /// The x86-64 baseline.
    Sse2,
    /// Plain f64 arithmetic.
    Scalar,
}

impl Isa {
    /// The build the walk runs: the best this CPU has (detected once, then cached), or
    /// the one the environment variable `OCTSOLID_ISA` names (`avx2`, `sse2`, `scalar`;
    /// one the CPU lacks is ignored), to measure or rule out a build.
    #[must_use]
    pub(crate) fn detect() -> Isa {
        use std::sync::OnceLock;
        static ISA: OnceLock<Isa> = OnceLock::new();
        *ISA.get_or_init(|| {
            let available = Isa::available();
            let named = std::env::var("OCTSOLID_ISA").ok().and_then(|v| match v.to_ascii_lowercase().as_str() {
                "avx2" => Some(Isa::Avx2),
                "sse2" => Some(Isa::Sse2),
                "scalar" => Some(Isa::Scalar),
                _ => None,
            });
            named.filter(|isa| available.contains(isa)).unwrap_or(available[0])
        })
    }

    /// Every build this CPU can run, best first.
    #[must_use]
    pub(crate) fn available() -> Vec<Isa> {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") {
                vec![Isa::Avx2, Isa::Sse2, Isa::Scalar]
            } else {
                vec![Isa::Sse2, Isa::Scalar]
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            vec![Isa::Scalar]
        }
    }
}

/// Three f64 lanes and the operations the walk needs, each lane by lane.
pub(crate) trait Lanes: Copy {
    /// `[x, y, z]` (the idle lane, where there is one, gets `pad`).
    fn new(v: [f64; 3], pad: f64) -> Self;
    /// The same value in every lane.
    fn splat(v: f64) -> Self;
    /// Lane by lane `self + o`.
    fn add(self, o: Self) -> Self;
    /// Lane by lane `self - o`.
    fn sub(self, o: Self) -> Self;
    /// Lane by lane `self * o`.
    fn mul(self, o: Self) -> Self;
    /// A mask: all ones in the lanes where `self <= t`.
    fn le(self, t: Self) -> Self;
    /// Bit `a` set when lane `a` of the mask is set (`a` in `0..3`).
    fn bits(self) -> usize;
    /// Lane by lane bitwise `self & o`.
    fn and(self, o: Self) -> Self;
    /// Lane by lane bitwise `self ^ o`.
    fn xor(self, o: Self) -> Self;
    /// `mask ? a : b`, lane by lane.
    fn select(mask: Self, a: Self, b: Self) -> Self;
    /// The lanes turned one place: `[y, z, x]` (the idle lane, where there is one, kept).
    fn rotate(self) -> Self;
    /// `earlier(earlier(x, y), z)`.
    fn min3(self) -> f64;
    /// The lanes `[x, y, z]`.
    fn to_array(self) -> [f64; 3];
}

/// The scalar build.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scalar([f64; 3]);

impl Lanes for Scalar {
    #[inline(always)]
    fn new(v: [f64; 3], _pad: f64) -> Self {
        Scalar(v)
    }
    #[inline(always)]
    fn splat(v: f64) -> Self {
        Scalar([v; 3])
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Scalar([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Scalar([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Scalar([self.0[0] * o.0[0], self.0[1] * o.0[1], self.0[2] * o.0[2]])
    }
    #[inline(always)]
    fn le(self, t: Self) -> Self {
        let m = |a: usize| f64::from_bits(if self.0[a] <= t.0[a] { u64::MAX } else { 0 });
        Scalar([m(0), m(1), m(2)])
    }
    #[inline(always)]
    fn bits(self) -> usize {
        (0..3).fold(0, |b, a| b | usize::from(self.0[a].to_bits() >> 63 == 1) << a)
    }
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        Scalar(std::array::from_fn(|a| f64::from_bits(self.0[a].to_bits() & o.0[a].to_bits())))
    }
    #[inline(always)]
    fn xor(self, o: Self) -> Self {
        Scalar(std::array::from_fn(|a| f64::from_bits(self.0[a].to_bits() ^ o.0[a].to_bits())))
    }
    #[inline(always)]
    fn select(mask: Self, a: Self, b: Self) -> Self {
        Scalar(std::array::from_fn(|i| if mask.0[i].to_bits() >> 63 == 1 { a.0[i] } else { b.0[i] }))
    }
    #[inline(always)]
    fn rotate(self) -> Self {
        Scalar([self.0[1], self.0[2], self.0[0]])
    }
    #[inline(always)]
    fn min3(self) -> f64 {
        earlier(earlier(self.0[0], self.0[1]), self.0[2])
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 3] {
        self.0
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{Avx2, Sse2};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::{
        __m128d, __m256d, _CMP_LE_OQ, _mm_add_pd, _mm_and_pd, _mm_andnot_pd, _mm_cmple_pd, _mm_cvtsd_f64, _mm_min_sd,
        _mm_movemask_pd, _mm_mul_pd, _mm_or_pd, _mm_set_pd, _mm_set1_pd, _mm_shuffle_pd, _mm_sub_pd, _mm_unpackhi_pd,
        _mm_xor_pd, _mm256_add_pd, _mm256_and_pd, _mm256_blendv_pd, _mm256_castpd256_pd128, _mm256_cmp_pd,
        _mm256_extractf128_pd, _mm256_movemask_pd, _mm256_mul_pd, _mm256_permute4x64_pd, _mm256_set_pd, _mm256_set1_pd,
        _mm256_storeu_pd, _mm256_sub_pd, _mm256_xor_pd,
    };

    use super::Lanes;

    /// The AVX2 build: x, y, z and an idle lane in one register. Only called from
    /// code compiled with AVX2 enabled after [`super::Isa::detect`] found it.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx2(__m256d);

    // SAFETY (every method): the walk instantiated with `Avx2` runs only inside a
    // `#[target_feature(enable = "avx2")]` function called after run-time detection.
    impl Lanes for Avx2 {
        #[inline(always)]
        fn new(v: [f64; 3], pad: f64) -> Self {
            unsafe { Avx2(_mm256_set_pd(pad, v[2], v[1], v[0])) }
        }
        #[inline(always)]
        fn splat(v: f64) -> Self {
            unsafe { Avx2(_mm256_set1_pd(v)) }
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_add_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_sub_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_mul_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn le(self, t: Self) -> Self {
            unsafe { Avx2(_mm256_cmp_pd::<_CMP_LE_OQ>(self.0, t.0)) }
        }
        #[inline(always)]
        fn bits(self) -> usize {
            unsafe { (_mm256_movemask_pd(self.0) & 7) as usize }
        }
        #[inline(always)]
        fn and(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_and_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn xor(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_xor_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn select(mask: Self, a: Self, b: Self) -> Self {
            unsafe { Avx2(_mm256_blendv_pd(b.0, a.0, mask.0)) }
        }
        #[inline(always)]
        fn rotate(self) -> Self {
            unsafe { Avx2(_mm256_permute4x64_pd::<0b11_00_10_01>(self.0)) }
        }
        #[inline(always)]
        fn min3(self) -> f64 {
            unsafe {
                let xy = _mm256_castpd256_pd128(self.0);
                let zw = _mm256_extractf128_pd::<1>(self.0);
                let x_y = _mm_min_sd(xy, _mm_unpackhi_pd(xy, xy));
                _mm_cvtsd_f64(_mm_min_sd(x_y, zw))
            }
        }
        #[inline(always)]
        fn to_array(self) -> [f64; 3] {
            let mut out = [0.0; 4];
            unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
            [out[0], out[1], out[2]]
        }
    }

    /// The SSE2 build: x and y in one register, z (and an idle lane) in another.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Sse2 {
        xy: __m128d,
        z: __m128d,
    }

    // SAFETY (every method): SSE2 is part of the x86-64 baseline.
    impl Lanes for Sse2 {
        #[inline(always)]
        fn new(v: [f64; 3], pad: f64) -> Self {
            unsafe { Sse2 { xy: _mm_set_pd(v[1], v[0]), z: _mm_set_pd(pad, v[2]) } }
        }
        #[inline(always)]
        fn splat(v: f64) -> Self {
            unsafe { Sse2 { xy: _mm_set1_pd(v), z: _mm_set1_pd(v) } }
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { Sse2 { xy: _mm_add_pd(self.xy, o.xy), z: _mm_add_pd(self.z, o.z) } }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { Sse2 { xy: _mm_sub_pd(self.xy, o.xy), z: _mm_sub_pd(self.z, o.z) } }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { Sse2 { xy: _mm_mul_pd(self.xy, o.xy), z: _mm_mul_pd(self.z, o.z) } }
        }
        #[inline(always)]
        fn le(self, t: Self) -> Self {
            unsafe { Sse2 { xy: _mm_cmple_pd(self.xy, t.xy), z: _mm_cmple_pd(self.z, t.z) } }
        }
        #[inline(always)]
        fn bits(self) -> usize {
            unsafe { (_mm_movemask_pd(self.xy) | (_mm_movemask_pd(self.z) & 1) << 2) as usize }
        }
        #[inline(always)]
        fn and(self, o: Self) -> Self {
            unsafe { Sse2 { xy: _mm_and_pd(self.xy, o.xy), z: _mm_and_pd(self.z, o.z) } }
        }
        #[inline(always)]
        fn xor(self, o: Self) -> Self {
            unsafe { Sse2 { xy: _mm_xor_pd(self.xy, o.xy), z: _mm_xor_pd(self.z, o.z) } }
        }
        #[inline(always)]
        fn select(mask: Self, a: Self, b: Self) -> Self {
            let pick = |m: __m128d, a: __m128d, b: __m128d| unsafe { _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b)) };
            Sse2 { xy: pick(mask.xy, a.xy, b.xy), z: pick(mask.z, a.z, b.z) }
        }
        #[inline(always)]
        fn rotate(self) -> Self {
            // (y, z) and (x, idle).
            unsafe { Sse2 { xy: _mm_shuffle_pd::<0b01>(self.xy, self.z), z: _mm_shuffle_pd::<0b10>(self.xy, self.z) } }
        }
        #[inline(always)]
        fn min3(self) -> f64 {
            unsafe {
                let x_y = _mm_min_sd(self.xy, _mm_unpackhi_pd(self.xy, self.xy));
                _mm_cvtsd_f64(_mm_min_sd(x_y, self.z))
            }
        }
        #[inline(always)]
        fn to_array(self) -> [f64; 3] {
            unsafe { [_mm_cvtsd_f64(self.xy), _mm_cvtsd_f64(_mm_unpackhi_pd(self.xy, self.xy)), _mm_cvtsd_f64(self.z)] }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every build's operations give the scalar build's bits on awkward values.
    #[test]
    fn builds_agree_with_scalar() {
        let values = [f64::NEG_INFINITY, -2.5, -0.0, 0.0, 1.0, 3.25, f64::MAX, f64::INFINITY];
        for &x in &values {
            for &y in &values {
                for &z in &values {
                    for &t in &values {
                        let s = Scalar::new([x, y, z], f64::INFINITY);
                        let st = Scalar::splat(t);
                        let want = (s.le(st).bits(), s.min3().to_bits(), s.sub(st).mul(st).add(s.rotate()).to_array());
                        for isa in Isa::available() {
                            let got = match isa {
                                #[cfg(target_arch = "x86_64")]
                                Isa::Avx2 => unsafe { avx2_ops([x, y, z], t) },
                                #[cfg(target_arch = "x86_64")]
                                Isa::Sse2 => ops::<Sse2>([x, y, z], t),
                                _ => ops::<Scalar>([x, y, z], t),
                            };
                            assert_eq!(got.0, want.0, "{isa:?} le {x} {y} {z} {t}");
                            assert_eq!(got.1, want.1, "{isa:?} min3 {x} {y} {z}");
                            for a in 0..3 {
                                assert_eq!(got.2[a].to_bits(), want.2[a].to_bits(), "{isa:?} arithmetic");
                            }
                        }
                    }
                }
            }
        }
    }

    fn ops<L: Lanes>(v: [f64; 3], t: f64) -> (usize, u64, [f64; 3]) {
        let s = L::new(v, f64::INFINITY);
        let st = L::splat(t);
        let m = s.le(st);
        // select and xor/and round trip: (m ? s : t) with m built both ways.
        let sel = L::select(m.xor(L::splat(0.0)).and(m), s, st).to_array();
        let direct = L::select(m, s, st).to_array();
        assert_eq!(sel.map(f64::to_bits), direct.map(f64::to_bits));
        (m.bits(), s.min3().to_bits(), s.sub(st).mul(st).add(s.rotate()).to_array())
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn avx2_ops(v: [f64; 3], t: f64) -> (usize, u64, [f64; 3]) {
        ops::<Avx2>(v, t)
    }
}
