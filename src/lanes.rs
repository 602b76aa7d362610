//! Four pairs at once: [`Lanes`], four `f64` lanes, and `V4`, four
//! 3-vectors as three lanes of components, for the pair kernels of the
//! moving bodies' pair pass and of the mesh Ewald sum's real space.
//!
//! Each operation acts lane by lane with the same rounding as the scalar
//! operation (no fused multiply-add), so a lane holds the bits the scalar
//! formula would give for its pair, whichever implementation computes it:
//! `F4`, plain arrays for any machine, or `Avx`, AVX registers, which the
//! passes use on x86-64 CPUs that have AVX2 (its operations are inlined into
//! the passes compiled for AVX2, and only there).

use nalgebra::Vector3;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// The number of lanes.
pub(crate) const LANES: usize = 4;

/// The machine code of a pass that takes lanes: its AVX2 code compiled
/// with AVX-512 VL too (the same instructions but for the encoding, with
/// 32 registers instead of 16: fewer values spilled to the stack), its AVX2
/// code, or plain arrays ([`F4`]); the same operations rounded alike on
/// each, so the same bits. The default is the first this CPU has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Path {
    Avx512,
    Avx2,
    Arrays,
}

impl Path {
    /// Whether this CPU has the path's instructions.
    pub(crate) fn runs(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            match self {
                Path::Avx512 => has!("avx2") && has!("avx512f") && has!("avx512vl"),
                Path::Avx2 => has!("avx2"),
                Path::Arrays => true,
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Path::Arrays
        }
    }

    /// Every path this CPU has, the fastest first.
    pub(crate) fn available() -> Vec<Path> {
        [Path::Avx512, Path::Avx2, Path::Arrays]
            .into_iter()
            .filter(|p| p.runs())
            .collect()
    }
}

impl Default for Path {
    fn default() -> Path {
        Path::available()[0]
    }
}

/// Four `f64` lanes. A mask is a value with all bits set in the lanes where
/// it holds and none elsewhere.
pub(crate) trait Lanes:
    Copy
    + Default
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<f64, Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
{
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
    fn from_array(lanes: [f64; LANES]) -> Self;
    fn to_array(self) -> [f64; LANES];
    /// The lanes' square roots.
    fn sqrt(self) -> Self;
    /// The mask of the lanes below `other`'s.
    fn lt(self, other: Self) -> Self;
    /// The lanes' bits and `mask`'s: each lane where the mask holds, else
    /// zero (a NaN or infinity of an unused lane does not pass).
    fn keep(self, mask: Self) -> Self;

    /// The mask of the lanes where `holds`.
    #[inline(always)]
    fn mask(holds: [bool; LANES]) -> Self {
        Self::from_array(holds.map(|h| f64::from_bits(if h { u64::MAX } else { 0 })))
    }

    /// The sum of the lanes, `(l0 + l1) + (l2 + l3)`.
    #[inline(always)]
    fn total(self) -> f64 {
        let [a, b, c, d] = self.to_array();
        (a + b) + (c + d)
    }
}

/// Four `f64` lanes as an array (any machine).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct F4(pub [f64; LANES]);

/// Lane-by-lane arithmetic of `F4`.
macro_rules! lanewise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, other: F4) -> F4 {
                F4(std::array::from_fn(|l| self.0[l] $op other.0[l]))
            }
        }
    };
}

lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Mul<f64> for F4 {
    type Output = F4;
    #[inline(always)]
    fn mul(self, x: f64) -> F4 {
        F4(self.0.map(|a| a * x))
    }
}

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        F4(self.0.map(|x| -x))
    }
}

impl AddAssign for F4 {
    #[inline(always)]
    fn add_assign(&mut self, other: F4) {
        *self = *self + other;
    }
}

impl Lanes for F4 {
    #[inline(always)]
    fn splat(x: f64) -> F4 {
        F4([x; LANES])
    }
    #[inline(always)]
    fn from_array(lanes: [f64; LANES]) -> F4 {
        F4(lanes)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; LANES] {
        self.0
    }
    #[inline(always)]
    fn sqrt(self) -> F4 {
        F4(self.0.map(f64::sqrt))
    }
    #[inline(always)]
    fn lt(self, other: F4) -> F4 {
        let below: [bool; LANES] = std::array::from_fn(|l| self.0[l] < other.0[l]);
        F4::mask(below)
    }
    #[inline(always)]
    fn keep(self, mask: F4) -> F4 {
        F4(std::array::from_fn(|l| {
            f64::from_bits(self.0[l].to_bits() & mask.0[l].to_bits())
        }))
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::Avx;

#[cfg(target_arch = "x86_64")]
mod avx {
    use super::{Lanes, LANES};
    use std::arch::x86_64::*;
    use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

    /// Four `f64` lanes in an AVX register: to be used only in code
    /// compiled with AVX2 enabled and run on a CPU that has it.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx(__m256d);

    impl Default for Avx {
        #[inline(always)]
        fn default() -> Avx {
            Avx::splat(0.0)
        }
    }

    /// The AVX instruction `$f` on two lanes' registers.
    macro_rules! avx {
        ($trait:ident, $method:ident, $f:ident) => {
            impl $trait for Avx {
                type Output = Avx;
                #[inline(always)]
                fn $method(self, other: Avx) -> Avx {
                    // SAFETY: `Avx` exists only where the CPU has AVX2 (type doc).
                    Avx(unsafe { $f(self.0, other.0) })
                }
            }
        };
    }

    avx!(Add, add, _mm256_add_pd);
    avx!(Sub, sub, _mm256_sub_pd);
    avx!(Mul, mul, _mm256_mul_pd);
    avx!(Div, div, _mm256_div_pd);

    impl Mul<f64> for Avx {
        type Output = Avx;
        #[inline(always)]
        fn mul(self, x: f64) -> Avx {
            self * Avx::splat(x)
        }
    }

    impl Neg for Avx {
        type Output = Avx;
        #[inline(always)]
        fn neg(self) -> Avx {
            // SAFETY: as for the arithmetic.
            Avx(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
        }
    }

    impl AddAssign for Avx {
        #[inline(always)]
        fn add_assign(&mut self, other: Avx) {
            *self = *self + other;
        }
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn splat(x: f64) -> Avx {
            // SAFETY: as for the arithmetic.
            Avx(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn from_array(lanes: [f64; LANES]) -> Avx {
            // SAFETY: as for the arithmetic; the load reads the four lanes.
            Avx(unsafe { _mm256_loadu_pd(lanes.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f64; LANES] {
            let mut lanes = [0.0; LANES];
            // SAFETY: as for the arithmetic; the store writes the four lanes.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), self.0) };
            lanes
        }
        #[inline(always)]
        fn sqrt(self) -> Avx {
            // SAFETY: as for the arithmetic.
            Avx(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn lt(self, other: Avx) -> Avx {
            // SAFETY: as for the arithmetic.
            Avx(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn keep(self, mask: Avx) -> Avx {
            // SAFETY: as for the arithmetic.
            Avx(unsafe { _mm256_and_pd(self.0, mask.0) })
        }
    }
}

/// Four 3-vectors by component.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct V4<T> {
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Lanes> V4<T> {
    /// Every lane `v`.
    #[inline(always)]
    pub fn splat(v: &Vector3<f64>) -> Self {
        V4 {
            x: T::splat(v.x),
            y: T::splat(v.y),
            z: T::splat(v.z),
        }
    }

    /// The vectors of four lanes.
    #[inline(always)]
    pub fn gather(lanes: [&Vector3<f64>; LANES]) -> Self {
        V4 {
            x: T::from_array(lanes.map(|v| v.x)),
            y: T::from_array(lanes.map(|v| v.y)),
            z: T::from_array(lanes.map(|v| v.z)),
        }
    }

    /// The four lanes as vectors.
    #[inline(always)]
    pub fn to_vectors(self) -> [Vector3<f64>; LANES] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|l| Vector3::new(x[l], y[l], z[l]))
    }

    /// The dot products, `(x x' + y y') + z z'`.
    #[inline(always)]
    pub fn dot(&self, other: &Self) -> T {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// Each lane where `mask` holds, else zero.
    #[inline(always)]
    pub fn keep(self, mask: T) -> Self {
        V4 {
            x: self.x.keep(mask),
            y: self.y.keep(mask),
            z: self.z.keep(mask),
        }
    }

    /// The sum of the lanes ([`Lanes::total`] of each component).
    #[inline(always)]
    pub fn total(&self) -> Vector3<f64> {
        Vector3::new(self.x.total(), self.y.total(), self.z.total())
    }
}

impl<T: Lanes> Add for V4<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V4 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl<T: Lanes> Sub for V4<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V4 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl<T: Lanes> Neg for V4<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V4 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl<T: Lanes> AddAssign for V4<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

/// Each vector times its lane of a scalar.
impl<T: Lanes> Mul<T> for V4<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        V4 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each lane of an expression holds the scalar expression's bits (with
    /// AVX too where the CPU has it), and `keep` drops non-finite lanes.
    #[test]
    fn lanes_are_the_scalar_operations() {
        fn check<T: Lanes>() {
            let (a, b) = ([0.3, -1.7, 2.5e-3, 9.0], [1.1, 0.2, -4.0, 3.0]);
            let (ta, tb) = (T::from_array(a), T::from_array(b));
            let lanes = ((ta * tb + ta) / tb - ta * 2.0).sqrt().to_array();
            let v = V4 {
                x: ta,
                y: tb,
                z: -(ta * tb),
            };
            let (dots, vectors) = (v.dot(&v).to_array(), v.to_vectors());
            for l in 0..LANES {
                let scalar = ((a[l] * b[l] + a[l]) / b[l] - a[l] * 2.0).sqrt();
                assert_eq!(lanes[l].to_bits(), scalar.to_bits(), "lane {l}");
                let u = vectors[l];
                let dot = u.x * u.x + u.y * u.y + u.z * u.z;
                assert_eq!(dots[l].to_bits(), dot.to_bits(), "lane {l}");
            }
            let inverse = T::splat(1.0) / T::from_array([0.0, 1.0, 0.0, 2.0]);
            let kept = inverse.keep(T::from_array([1.0, 0.5, 3.0, 1.0]).lt(T::splat(1.0)));
            assert_eq!(kept.to_array(), [0.0, 1.0, 0.0, 0.0]);
            let holds = T::mask([true, false, true, true]);
            assert_eq!(T::splat(2.0).keep(holds).to_array(), [2.0, 0.0, 2.0, 2.0]);
            assert_eq!(T::from_array([1.0, 2.0, 3.0, 4.0]).total(), 10.0);
        }
        check::<F4>();
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            check::<Avx>();
        }
    }
}
