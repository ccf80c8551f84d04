//! Exact welding: vertices whose keys are bit-for-bit equal (after mapping -0.0 to +0.0, so
//! equality is IEEE `==` for finite values) share one id. Ids are dense and numbered in order of
//! first appearance, so the result does not depend on hashing or thread count.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// The f32 bit pattern used as a weld key: `-0.0` becomes `+0.0`.
#[inline]
pub fn key_bits(x: f32) -> u32 {
    if x == 0.0 { 0 } else { x.to_bits() }
}

/// Welds `n` vertices by the key `key(i)`. Returns the id of every vertex and the number of ids.
pub fn weld<const N: usize>(n: usize, key: impl Fn(usize) -> [u32; N]) -> (Vec<u32>, usize) {
    let mut map: HashMap<[u32; N], u32, BuildHasherDefault<FxHasher>> =
        HashMap::with_capacity_and_hasher(n, BuildHasherDefault::default());
    let ids = (0..n)
        .map(|i| {
            let next = map.len() as u32;
            *map.entry(key(i)).or_insert(next)
        })
        .collect();
    (ids, map.len())
}

/// The multiply-rotate hash of rustc (`FxHasher`): fast for small integer keys, not DoS-proof,
/// which does not matter for mesh data.
#[derive(Default, Clone, Copy)]
pub struct FxHasher(u64);

impl Hasher for FxHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }

    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut w = [0u8; 8];
            w[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(w));
        }
    }

    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.write_u64(u64::from(i));
    }

    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_keys_share_ids_in_first_seen_order() {
        let keys = [[3u32], [1], [3], [2], [1]];
        let (ids, n) = weld(keys.len(), |i| keys[i]);
        assert_eq!(ids, vec![0, 1, 0, 2, 1]);
        assert_eq!(n, 3);
    }

    #[test]
    fn negative_zero_welds_with_zero() {
        assert_eq!(key_bits(-0.0), key_bits(0.0));
        assert_ne!(key_bits(1.0), key_bits(-1.0));
    }
}
