//! Kensler's hashed permutation (*Correlated Multi-Jittered Sampling*,
//! Pixar 2013): a pseudo-random bijection of `[0, len)` chosen by a key,
//! by cycle walking over rounds on `[0, 2^k)`. The strata samplers shuffle
//! each dimension's strata with it, sixteen dimensions at a time
//! ([`permute_block`]).

/// Kensler's hashed permutation: the image of `i` under a pseudo-random
/// bijection of `[0, len)` chosen by `key`. For `len ≤ 1` it returns 0;
/// an `i ≥ len` is taken modulo `len`.
///
/// ```
/// use strata::sampler::permute;
/// let mut hit = [false; 10];
/// for i in 0..10 {
///     hit[permute(i, 10, 0xdead_beef) as usize] = true;
/// }
/// assert!(hit.iter().all(|&h| h)); // a bijection of 0..10
/// ```
#[inline]
#[must_use]
pub const fn permute(i: u32, len: u32, key: u32) -> u32 {
    if len <= 1 {
        return 0;
    }
    // Outside [0, len) the cycle walk need not come back: fold first.
    let i = if i >= len { i % len } else { i };
    permute_in(i, len, permute_mask(len), key, key % len)
}

/// The smallest `2^k − 1 ≥ len − 1`: the domain of one permutation round.
#[inline]
pub(super) const fn permute_mask(len: u32) -> u32 {
    let mut w = len.saturating_sub(1);
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w | w >> 16
}

/// [`permute`] of an `i < len` (`len ≥ 1`), with `w = permute_mask(len)`
/// and `key_mod = key % len` given, so callers that hold `len` or `key`
/// fixed compute them once. For `len = 1` it returns 0 like `permute`.
#[inline]
const fn permute_in(mut i: u32, len: u32, w: u32, key: u32, key_mod: u32) -> u32 {
    // Each step is a bijection of [0, w]; cycle walking restricts it to
    // [0, len), and len > w / 2 bounds the expected walk by two rounds.
    loop {
        i = permute_round(i, w, key);
        if i < len {
            break;
        }
    }
    // (i + key) mod len without overflow: both terms are below len, so
    // one subtraction.
    let r = i.wrapping_add(key_mod);
    if r >= len || r < i {
        r.wrapping_sub(len)
    } else {
        r
    }
}
/// Dimensions whose strata a strata sampler evaluates at once.
pub(super) const STRATA_BLOCK: usize = 16;

/// One round of Kensler's permutation of `[0, w]` keyed by `p` (see
/// [`permute_in`]).
#[inline(always)]
const fn permute_round(i: u32, w: u32, p: u32) -> u32 {
    permute_round_keyed::<false>(i, w, RoundKey::new(p))
}

/// What one round of Kensler's permutation takes from its key `p`,
/// derived once per key: the shifted key words, and the two multipliers
/// the round applies back to back folded into one (products mod 2³² do not
/// depend on grouping, so the bits are the same).
#[derive(Clone, Copy, Debug)]
pub(super) struct RoundKey {
    pub(super) p: u32,
    pub(super) p16: u32,
    pub(super) p8: u32,
    pub(super) p23: u32,
    pub(super) m: u32,
}

impl RoundKey {
    /// The derived words of key `p`.
    #[inline(always)]
    pub(super) const fn new(p: u32) -> Self {
        Self {
            p,
            p16: p >> 16,
            p8: p >> 8,
            p23: p >> 23,
            m: (1 | p >> 27).wrapping_mul(0x6935_fa69),
        }
    }
}

/// [`permute_round`] from a derived key. With `SMALL` (only for `w < 16`)
/// the steps `(i & w) >> 4`, `(i & w) >> 11` and the final `i >> 5` are
/// left out: they see at most `w ≤ 15` and xor zero, so the bits are the
/// same.
#[inline(always)]
const fn permute_round_keyed<const SMALL: bool>(mut i: u32, w: u32, k: RoundKey) -> u32 {
    debug_assert!(!SMALL || w < 16);
    i ^= k.p;
    i = i.wrapping_mul(0xe170_893d);
    i ^= k.p16;
    if !SMALL {
        i ^= (i & w) >> 4;
    }
    i ^= k.p8;
    i = i.wrapping_mul(0x0929_eb3f);
    i ^= k.p23;
    i ^= (i & w) >> 1;
    i = i.wrapping_mul(k.m);
    if !SMALL {
        i ^= (i & w) >> 11;
    }
    i = i.wrapping_mul(0x74dc_b303);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0x9e50_1cc3);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0xc860_a3df);
    i &= w;
    if SMALL { i } else { i ^ i >> 5 }
}
/// The permutation keys of one block of [`STRATA_BLOCK`] dimensions, lane
/// by lane (structure of arrays, for SIMD): each round key's words and the
/// key's residue mod the stratum count.
#[derive(Clone, Copy, Debug)]
pub(super) struct BlockKeys {
    pub(super) p: [u32; STRATA_BLOCK],
    pub(super) p16: [u32; STRATA_BLOCK],
    pub(super) p8: [u32; STRATA_BLOCK],
    pub(super) p23: [u32; STRATA_BLOCK],
    pub(super) m: [u32; STRATA_BLOCK],
    pub(super) key_mod: [u32; STRATA_BLOCK],
}

impl BlockKeys {
    /// All keys 0 (a placeholder until a block's keys are written).
    pub(super) const ZERO: Self = Self {
        p: [0; STRATA_BLOCK],
        p16: [0; STRATA_BLOCK],
        p8: [0; STRATA_BLOCK],
        p23: [0; STRATA_BLOCK],
        m: [0; STRATA_BLOCK],
        key_mod: [0; STRATA_BLOCK],
    };

    /// Lane `l`'s round key.
    #[inline(always)]
    fn lane(&self, l: usize) -> RoundKey {
        RoundKey {
            p: self.p[l],
            p16: self.p16[l],
            p8: self.p8[l],
            p23: self.p23[l],
            m: self.m[l],
        }
    }
}

/// [`permute_in`] of one `i < len` under `STRATA_BLOCK` keys at once, into
/// `out`: lanes are independent and branch-free (a lane that has reached
/// `[0, len)` keeps its value while the others walk on), so a compiler
/// turns them into SIMD.
#[inline]
pub(super) fn permute_block(
    i: u32,
    len: u32,
    w: u32,
    keys: &BlockKeys,
    out: &mut [u32; STRATA_BLOCK],
) {
    if w < 16 {
        permute_block_in::<true>(i, len, w, keys, out);
    } else {
        permute_block_in::<false>(i, len, w, keys, out);
    }
}

/// [`permute_block`] with rounds of one kind (see [`permute_round_keyed`]).
#[inline(always)]
fn permute_block_in<const SMALL: bool>(
    i: u32,
    len: u32,
    w: u32,
    keys: &BlockKeys,
    out: &mut [u32; STRATA_BLOCK],
) {
    if w.wrapping_add(1) == len {
        // A power of two: one round stays in [0, len), nothing walks, and
        // (x + key) mod len is a mask.
        for (l, o) in out.iter_mut().enumerate() {
            *o = permute_round_keyed::<SMALL>(i, w, keys.lane(l)).wrapping_add(keys.key_mod[l]) & w;
        }
        return;
    }
    let mut x = [i; STRATA_BLOCK];
    // All ones while a lane still walks.
    let mut walking = [u32::MAX; STRATA_BLOCK];
    loop {
        let mut any = 0;
        for l in 0..STRATA_BLOCK {
            let y = permute_round_keyed::<SMALL>(x[l], w, keys.lane(l));
            x[l] = (y & walking[l]) | (x[l] & !walking[l]);
            walking[l] &= 0u32.wrapping_sub((y >= len) as u32);
            any |= walking[l];
        }
        if any == 0 {
            break;
        }
    }
    for l in 0..STRATA_BLOCK {
        // (x + key) mod len without overflow, as permute_in.
        let r = x[l].wrapping_add(keys.key_mod[l]);
        let wrap = (r >= len) | (r < x[l]);
        out[l] = r.wrapping_sub(len & 0u32.wrapping_sub(wrap as u32));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use rand_core::Rng;

    #[test]
    fn permute_is_a_bijection() {
        for len in [1u32, 2, 3, 5, 16, 17, 31, 100, 1000] {
            for key in [0u32, 1, 0xdead_beef, u32::MAX] {
                let mut seen = [false; 1000];
                for i in 0..len {
                    let j = permute(i, len, key);
                    assert!(j < len);
                    assert!(!seen[j as usize], "len {len} key {key}: {j} twice");
                    seen[j as usize] = true;
                }
            }
        }
        assert_eq!(permute(0, 0, 5), 0);
        // Out-of-range inputs fold instead of walking forever.
        assert_eq!(permute(3, 3, 0), permute(0, 3, 0));
        assert!(permute(u32::MAX, 1000, 7) < 1000);
    }

    /// One round of Kensler's permutation as published (Kensler 2013,
    /// *Correlated Multi-Jittered Sampling*), for the derived forms.
    fn kensler_round(mut i: u32, w: u32, p: u32) -> u32 {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^ i >> 5
    }

    #[test]
    fn derived_rounds_equal_the_published_one() {
        // The folded multiplier, and the steps left out below 16, give the
        // bits of the round as published.
        let mut rng = Pcg32::new(3, 5);
        for _ in 0..20_000 {
            let p = rng.next_u32();
            let small = (1u32 << (rng.next_u32() % 5)) - 1;
            let i = rng.next_u32() & small;
            let want = kensler_round(i, small, p);
            assert_eq!(
                permute_round_keyed::<true>(i, small, RoundKey::new(p)),
                want
            );
            assert_eq!(permute_round(i, small, p), want);
            let w = u32::MAX >> (rng.next_u32() % 32);
            let j = rng.next_u32() & w;
            assert_eq!(permute_round(j, w, p), kensler_round(j, w, p), "w {w:#x}");
        }
    }
}
