//! Structure-of-arrays sphere sets and 8-ray packets, and the 8-wide twins
//! of [`super::closest_hit`] and [`super::any_hit`].
//!
//! # The lane contract
//!
//! - A lane of a mask is all ones (set) or all zeros.
//! - Lanes never mix: a NaN or infinite lane changes only its own result.
//! - Inactive packet lanes are never written: [`closest_hit_x8`] leaves
//!   their entries of the [`HitPacket8`] exactly as the caller passed them,
//!   and [`any_hit_x8`] reports them as not occluded.
//! - No kernel panics and none allocates.

use glam::Vec3;

use super::{Hit, Ray, Sphere, sphere_t};
use crate::lanes::{
    Lanes, RayLanes, SphereLanes, V3, f32x8, i32x8, lanes_bitmask, lanes_lt, lanes_lt_i32,
    lanes_select, lanes_select_i32, mask_from_bits, mask_from_bools,
};

/// Eight spheres as structure of arrays: one 8-lane vector per coordinate
/// and one for the radius. Unused lanes have radius 0 and can never be
/// hit. The vectors are private (the SIMD backend is not part of the API);
/// lanes go in and out as [`Sphere`]s.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Sphere, SphereChunk8};
/// let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.5);
/// let mut lanes = [Sphere::new(Vec3::ZERO, 0.0); 8];
/// lanes[2] = s;
/// let chunk = SphereChunk8::from_spheres(lanes);
/// assert_eq!(chunk.sphere(2), s);
/// assert_eq!(chunk.sphere(0).radius, 0.0); // padding
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SphereChunk8 {
    /// Centre x of each lane.
    pub(crate) cx: f32x8,
    /// Centre y of each lane.
    pub(crate) cy: f32x8,
    /// Centre z of each lane.
    pub(crate) cz: f32x8,
    /// Radius of each lane; 0 in padding lanes.
    pub(crate) r: f32x8,
}

// One chunk is four 32-byte vectors, aligned for 256-bit loads.
const _: () = assert!(core::mem::size_of::<SphereChunk8>() == 128);
const _: () = assert!(core::mem::align_of::<SphereChunk8>() >= 16);

impl SphereChunk8 {
    /// The chunk's eight spheres as lanes.
    #[inline(always)]
    pub(crate) fn lanes(&self) -> SphereLanes<f32x8> {
        SphereLanes {
            center: V3::new(self.cx, self.cy, self.cz),
            radius: self.r,
        }
    }

    /// A chunk holding exactly these eight lanes (a lane meant as padding
    /// must have radius 0; [`SphereSet::from_chunks`] checks that).
    #[inline]
    #[must_use]
    pub fn from_spheres(lanes: [Sphere; 8]) -> Self {
        let get = |f: fn(&Sphere) -> f32| f32x8::new(lanes.each_ref().map(f));
        Self {
            cx: get(|s| s.center.x),
            cy: get(|s| s.center.y),
            cz: get(|s| s.center.z),
            r: get(|s| s.radius),
        }
    }

    /// The sphere in `lane` (0–7; taken modulo 8), padding included.
    #[inline]
    #[must_use]
    pub fn sphere(&self, lane: usize) -> Sphere {
        let l = lane % 8;
        let g = |v: &f32x8| v.as_array()[l];
        Sphere::new(Vec3::new(g(&self.cx), g(&self.cy), g(&self.cz)), g(&self.r))
    }

    /// A chunk of eight padding lanes (radius 0: never hit).
    pub const EMPTY: SphereChunk8 = SphereChunk8 {
        cx: f32x8::ZERO,
        cy: f32x8::ZERO,
        cz: f32x8::ZERO,
        r: f32x8::ZERO,
    };
}

/// How many [`SphereChunk8`] a set of `n` spheres needs: `⌈n / 8⌉`.
///
/// ```
/// assert_eq!(strata::trace::chunks_for(0), 0);
/// assert_eq!(strata::trace::chunks_for(9), 2);
/// ```
#[inline]
#[must_use]
pub const fn chunks_for(n: usize) -> usize {
    n.div_ceil(8)
}

/// Why a [`SphereSet`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SphereSetError {
    /// The storage slice holds fewer chunks than [`chunks_for`] requires.
    StorageTooSmall {
        /// Chunks required.
        needed: usize,
        /// Chunks provided.
        provided: usize,
    },
    /// More spheres than a 32-bit signed lane index can name (`2³¹ − 1`).
    TooManySpheres,
    /// A padding lane of the last chunk has a radius other than 0, so it
    /// could be hit.
    Padding,
}

impl core::fmt::Display for SphereSetError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SphereSetError::StorageTooSmall { needed, provided } => write!(
                f,
                "sphere storage too small: {needed} chunks needed, {provided} given"
            ),
            SphereSetError::TooManySpheres => {
                f.write_str("more spheres than a 32-bit lane index can name")
            }
            SphereSetError::Padding => {
                f.write_str("a padding lane of the last sphere chunk has a non-zero radius")
            }
        }
    }
}

impl core::error::Error for SphereSetError {}

/// A read-only view of spheres stored as [`SphereChunk8`]s in
/// caller-provided storage. Sphere `i` is lane `i % 8` of chunk `i / 8`.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{chunks_for, closest_hit_1x8, Ray, Sphere, SphereChunk8, SphereSet};
/// let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0); 3];
/// let mut storage = [SphereChunk8::EMPTY; 1];
/// assert_eq!(chunks_for(spheres.len()), storage.len());
/// let set = SphereSet::build(&spheres, &mut storage).unwrap();
/// let hit = closest_hit_1x8(&set, &Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
/// assert_eq!((hit.sphere, hit.t), (0, 2.0)); // ties go to the lowest index
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SphereSet<'a> {
    chunks: &'a [SphereChunk8],
    len: usize,
}

impl<'a> SphereSet<'a> {
    /// Writes `spheres` into the first [`chunks_for`]`(spheres.len())`
    /// chunks of `storage`, padding the last chunk, and returns a view of
    /// them. On error nothing is written.
    #[inline]
    pub fn build(
        spheres: &[Sphere],
        storage: &'a mut [SphereChunk8],
    ) -> Result<SphereSet<'a>, SphereSetError> {
        if spheres.len() > i32::MAX as usize {
            return Err(SphereSetError::TooManySpheres);
        }
        let needed = chunks_for(spheres.len());
        if storage.len() < needed {
            return Err(SphereSetError::StorageTooSmall {
                needed,
                provided: storage.len(),
            });
        }
        let storage = &mut storage[..needed];
        for (chunk, group) in storage.iter_mut().zip(spheres.chunks(8)) {
            let mut a = [[0.0f32; 8]; 4];
            for (lane, s) in group.iter().enumerate() {
                a[0][lane] = s.center.x;
                a[1][lane] = s.center.y;
                a[2][lane] = s.center.z;
                a[3][lane] = s.radius;
            }
            *chunk = SphereChunk8 {
                cx: f32x8::new(a[0]),
                cy: f32x8::new(a[1]),
                cz: f32x8::new(a[2]),
                r: f32x8::new(a[3]),
            };
        }
        Ok(SphereSet {
            chunks: storage,
            len: spheres.len(),
        })
    }

    /// A view of `len` spheres in chunks built earlier (by
    /// [`SphereSet::build`], then kept, e.g. in a struct that owns its
    /// storage). Checks what `build` guarantees: exactly
    /// [`chunks_for`]`(len)` chunks, and radius 0 in every padding lane so
    /// padding can never be hit.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::{chunks_for, Sphere, SphereChunk8, SphereSet};
    /// let spheres = [Sphere::new(Vec3::ZERO, 1.0); 3];
    /// let mut storage = vec![SphereChunk8::EMPTY; chunks_for(3)];
    /// SphereSet::build(&spheres, &mut storage).unwrap();
    /// let view = SphereSet::from_chunks(&storage, 3).unwrap();
    /// assert_eq!(view.sphere(2), Some(spheres[2]));
    /// assert!(SphereSet::from_chunks(&storage, 2).is_err()); // lane 2 is not padding
    /// ```
    #[inline]
    pub fn from_chunks(chunks: &'a [SphereChunk8], len: usize) -> Result<Self, SphereSetError> {
        if len > i32::MAX as usize {
            return Err(SphereSetError::TooManySpheres);
        }
        let needed = chunks_for(len);
        if chunks.len() != needed {
            return Err(SphereSetError::StorageTooSmall {
                needed,
                provided: chunks.len(),
            });
        }
        if let Some(last) = chunks.last() {
            let used = len - 8 * (needed - 1);
            if last.r.as_array()[used..].iter().any(|&r| r != 0.0) {
                return Err(SphereSetError::Padding);
            }
        }
        Ok(SphereSet { chunks, len })
    }

    /// The number of spheres.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the set has no spheres.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The chunks, the last one padded.
    #[inline]
    #[must_use]
    pub fn chunks(&self) -> &'a [SphereChunk8] {
        self.chunks
    }

    /// Sphere `i`, or `None` past the end.
    #[inline]
    #[must_use]
    pub fn sphere(&self, i: usize) -> Option<Sphere> {
        if i >= self.len {
            return None;
        }
        let c = &self.chunks[i / 8];
        let l = i % 8;
        Some(Sphere::new(
            Vec3::new(c.cx.as_array()[l], c.cy.as_array()[l], c.cz.as_array()[l]),
            c.r.as_array()[l],
        ))
    }
}

/// The closest hit of one ray against a [`SphereSet`], eight spheres per
/// step: the 1×8 twin of [`super::closest_hit`], with the same result bit
/// for bit (ties to the lowest index).
#[inline]
#[must_use]
pub fn closest_hit_1x8(set: &SphereSet<'_>, ray: &Ray) -> Option<Hit> {
    let lanes = ray.lanes_x8();
    let mut best_t = f32x8::splat(f32::INFINITY);
    let mut best_i = i32x8::splat(-1);
    let mut index = i32x8::new([0, 1, 2, 3, 4, 5, 6, 7]);
    for c in set.chunks {
        let t = sphere_t(&lanes, &c.lanes());
        // Strict: an earlier chunk keeps a tie, as in the scalar loop.
        let closer = t.lt(best_t);
        best_t = lanes_select(closer, t, best_t);
        best_i = lanes_select_i32(closer, index, best_i);
        index += i32x8::splat(8);
    }
    // Lowest t, then the lowest index among equal t (−0.0 equals 0.0, as
    // in the scalar loop's strict `<`), over the lanes that hit: most rays
    // hit one sphere or none.
    let mut hits = lanes_bitmask(best_t.lt(f32x8::splat(f32::INFINITY)));
    if hits == 0 {
        return None;
    }
    let ts = best_t.to_array();
    let is = best_i.to_array();
    let mut best = Hit {
        t: f32::INFINITY,
        sphere: u32::MAX,
    };
    while hits != 0 {
        let lane = hits.trailing_zeros() as usize;
        hits &= hits - 1;
        let (t, id) = (ts[lane], is[lane] as u32);
        if t < best.t || (t == best.t && id < best.sphere) {
            best = Hit { t, sphere: id };
        }
    }
    Some(best)
}

/// Whether one ray hits any sphere of a [`SphereSet`], eight spheres per
/// step, stopping at the first chunk with a hit: the 1×8 twin of
/// [`super::any_hit`].
#[inline]
#[must_use]
pub fn any_hit_1x8(set: &SphereSet<'_>, ray: &Ray) -> bool {
    let lanes = ray.lanes_x8();
    let inf = f32x8::splat(f32::INFINITY);
    set.chunks.iter().any(|c| {
        let t = sphere_t(&lanes, &c.lanes());
        lanes_bitmask(t.lt(inf)) != 0
    })
}

/// Eight rays as structure of arrays, with an active-lane mask.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Ray, RayPacket8};
/// let rays = [Ray::new(Vec3::ZERO, Vec3::X), Ray::new(Vec3::ONE, Vec3::Y)];
/// let p = RayPacket8::from_rays(&rays);
/// assert_eq!(p.active_bits(), 0b11);
/// assert_eq!(p.ray(1), rays[1]);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct RayPacket8 {
    /// Origin x per lane.
    pub(crate) ox: f32x8,
    /// Origin y per lane.
    pub(crate) oy: f32x8,
    /// Origin z per lane.
    pub(crate) oz: f32x8,
    /// Unit direction x per lane.
    pub(crate) dx: f32x8,
    /// Unit direction y per lane.
    pub(crate) dy: f32x8,
    /// Unit direction z per lane.
    pub(crate) dz: f32x8,
    /// Open interval start per lane.
    pub(crate) t_min: f32x8,
    /// Open interval end per lane.
    pub(crate) t_max: f32x8,
    /// All ones in lanes that carry a ray, zeros elsewhere. Private: a
    /// mask of other bit patterns would select differently per SIMD level.
    active: f32x8,
}

impl RayPacket8 {
    /// The packet's rays as lanes.
    #[inline(always)]
    pub(crate) fn lanes(&self) -> RayLanes<f32x8> {
        RayLanes {
            origin: V3::new(self.ox, self.oy, self.oz),
            dir: V3::new(self.dx, self.dy, self.dz),
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    /// A packet of these rays, active where `active` is set.
    #[inline(always)]
    pub(crate) fn from_lanes(r: &RayLanes<f32x8>, active: f32x8) -> Self {
        Self {
            ox: r.origin.x,
            oy: r.origin.y,
            oz: r.origin.z,
            dx: r.dir.x,
            dy: r.dir.y,
            dz: r.dir.z,
            t_min: r.t_min,
            t_max: r.t_max,
            active,
        }
    }

    /// A packet of up to eight rays: lane `k` holds `rays[k]`; lanes past
    /// the end (and every lane past the eighth ray, which is ignored) are
    /// inactive and hold a zero ray.
    #[inline]
    #[must_use]
    pub fn from_rays(rays: &[Ray]) -> Self {
        let mut a = [[0.0f32; 8]; 8];
        let mut on = [false; 8];
        for (lane, r) in rays.iter().take(8).enumerate() {
            let v = [
                r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.t_min, r.t_max,
            ];
            for (k, x) in v.into_iter().enumerate() {
                a[k][lane] = x;
            }
            on[lane] = true;
        }
        Self {
            ox: f32x8::new(a[0]),
            oy: f32x8::new(a[1]),
            oz: f32x8::new(a[2]),
            dx: f32x8::new(a[3]),
            dy: f32x8::new(a[4]),
            dz: f32x8::new(a[5]),
            t_min: f32x8::new(a[6]),
            t_max: f32x8::new(a[7]),
            active: mask_from_bools(on),
        }
    }

    /// The ray in `lane` (0–7; taken modulo 8).
    #[inline]
    #[must_use]
    pub fn ray(&self, lane: usize) -> Ray {
        let l = lane % 8;
        let g = |v: &f32x8| v.as_array()[l];
        Ray {
            origin: Vec3::new(g(&self.ox), g(&self.oy), g(&self.oz)),
            dir: Vec3::new(g(&self.dx), g(&self.dy), g(&self.dz)),
            t_min: g(&self.t_min),
            t_max: g(&self.t_max),
        }
    }

    /// Bit `k` set when lane `k` is active.
    #[inline]
    #[must_use]
    pub fn active_bits(&self) -> u32 {
        lanes_bitmask(self.active)
    }

    /// The same rays with exactly the lanes of `bits` active (bit `k` for
    /// lane `k`), e.g. to retire lanes whose paths have ended.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::{Ray, RayPacket8};
    /// let p = RayPacket8::from_rays(&[Ray::new(Vec3::ZERO, Vec3::X); 8]);
    /// assert_eq!(p.with_active_bits(0b1010_0001).active_bits(), 0b1010_0001);
    /// ```
    #[inline]
    #[must_use]
    pub fn with_active_bits(self, bits: u8) -> Self {
        Self {
            active: mask_from_bits(bits),
            ..self
        }
    }
}

/// The kernel for all eight rays of a packet against sphere `lane` of a
/// chunk, broadcast to every lane.
#[inline(always)]
fn packet_sphere_t(p: &RayPacket8, c: &SphereChunk8, lane: usize) -> f32x8 {
    let at = |v: &f32x8| f32x8::splat(v.as_array()[lane]);
    let sphere = SphereLanes {
        center: V3::new(at(&c.cx), at(&c.cy), at(&c.cz)),
        radius: at(&c.r),
    };
    sphere_t(&p.lanes(), &sphere)
}

/// Per-lane closest hits of a [`RayPacket8`]: `t` (`+∞` for none) and the
/// sphere index (−1 for none), read as arrays or lane by lane.
///
/// ```
/// use strata::trace::HitPacket8;
/// let mut t = [f32::INFINITY; 8];
/// let mut id = [-1; 8];
/// (t[3], id[3]) = (2.5, 7);
/// let hits = HitPacket8::new(t, id);
/// assert_eq!(hits.hit(3).map(|h| (h.t, h.sphere)), Some((2.5, 7)));
/// assert_eq!(hits.hit_bits(), 1 << 3);
/// assert_eq!((hits.t(), hits.spheres()), (t, id));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct HitPacket8 {
    /// Hit distance per lane, `+∞` where nothing was hit.
    pub(crate) t: f32x8,
    /// Sphere index per lane, −1 where nothing was hit.
    pub(crate) sphere: i32x8,
}

impl Default for HitPacket8 {
    #[inline]
    fn default() -> Self {
        Self::NONE
    }
}

impl HitPacket8 {
    /// No hit in any lane.
    pub const NONE: HitPacket8 = HitPacket8 {
        t: f32x8::splat(f32::INFINITY),
        sphere: i32x8::splat(-1),
    };

    /// Hits from per-lane distances and sphere indices (`+∞` and −1 for
    /// none), e.g. to start a query from earlier hits.
    #[inline]
    #[must_use]
    pub fn new(t: [f32; 8], sphere: [i32; 8]) -> Self {
        Self {
            t: f32x8::new(t),
            sphere: i32x8::new(sphere),
        }
    }

    /// The hit distance of every lane (`+∞` where nothing was hit).
    #[inline]
    #[must_use]
    pub fn t(&self) -> [f32; 8] {
        self.t.to_array()
    }

    /// The sphere index of every lane (−1 where nothing was hit).
    #[inline]
    #[must_use]
    pub fn spheres(&self) -> [i32; 8] {
        self.sphere.to_array()
    }

    /// Bit `k` set when lane `k` has a hit ([`HitPacket8::hit`] is
    /// `Some`).
    #[inline]
    #[must_use]
    pub fn hit_bits(&self) -> u32 {
        (0..8).fold(0, |bits, k| bits | (self.hit(k).is_some() as u32) << k)
    }

    /// The lanes with a hit (bit `k`: lane `k`), and each lane's distance
    /// and sphere where it has one (others: `t = 0`, sphere 0), for code
    /// that keeps hits as lanes: the hits [`HitPacket8::hit`] gives.
    #[inline(always)]
    pub(crate) fn found_lanes(&self) -> (u32, [f32; 8], [u32; 8]) {
        let some = lanes_lt(self.t, f32x8::splat(f32::INFINITY));
        let hit = lanes_lt_i32(i32x8::splat(-1), self.sphere);
        let found: f32x8 = some & wide::bytemuck::cast::<i32x8, f32x8>(hit);
        let t = lanes_select(found, self.t, f32x8::splat(0.0));
        let sphere = lanes_select_i32(found, self.sphere, i32x8::splat(0));
        let sphere = sphere.to_array().map(|s| s as u32);
        (lanes_bitmask(found), t.to_array(), sphere)
    }

    /// A packet holding `hits` in its first lanes (at most 8; the others
    /// without a hit).
    #[inline(always)]
    pub(crate) fn from_hits(hits: &[Option<Hit>]) -> Self {
        let mut t = [f32::INFINITY; 8];
        let mut sphere = [-1i32; 8];
        for (k, h) in hits.iter().take(8).enumerate() {
            if let Some(h) = h {
                (t[k], sphere[k]) = (h.t, h.sphere as i32);
            }
        }
        Self {
            t: f32x8::new(t),
            sphere: i32x8::new(sphere),
        }
    }

    /// The hit of `lane` (0–7; taken modulo 8), if any.
    #[inline]
    #[must_use]
    pub fn hit(&self, lane: usize) -> Option<Hit> {
        let l = lane % 8;
        let t = self.t.as_array()[l];
        let s = self.sphere.as_array()[l];
        (t < f32::INFINITY && s >= 0).then_some(Hit {
            t,
            sphere: s as u32,
        })
    }
}

/// The closest hits of a packet against a [`SphereSet`], one sphere for all
/// eight rays per step: the packet twin of [`super::closest_hit`], lane by
/// lane the same bits.
///
/// `hits` is read and updated: a lane takes a sphere only if it is strictly
/// closer than the lane's current [`HitPacket8::t`], so a fresh [`HitPacket8::NONE`]
/// gives the closest hit (a NaN `t` passed in never updates). Sphere
/// indices are those of `set`. Inactive lanes are not written.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::*;
/// let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0)];
/// let mut storage = [SphereChunk8::EMPTY];
/// let set = SphereSet::build(&spheres, &mut storage).unwrap();
/// let rays = [Ray::new(Vec3::ZERO, -Vec3::Z), Ray::new(Vec3::ZERO, Vec3::Z)];
/// let mut hits = HitPacket8::NONE;
/// closest_hit_x8(&set, &RayPacket8::from_rays(&rays), &mut hits);
/// assert_eq!(hits.hit(0), closest_hit(&spheres, &rays[0]));
/// assert_eq!(hits.hit(1), None);
/// ```
#[inline]
pub fn closest_hit_x8(set: &SphereSet<'_>, packet: &RayPacket8, hits: &mut HitPacket8) {
    let p = packet;
    if lanes_bitmask(p.active) == 0 {
        return;
    }
    let mut best_t = hits.t;
    let mut best_i = hits.sphere;
    for (k, c) in set.chunks.iter().enumerate() {
        for lane in 0..(set.len - 8 * k).min(8) {
            let t = packet_sphere_t(p, c, lane);
            let closer = p.active & t.lt(best_t);
            best_t = lanes_select(closer, t, best_t);
            best_i = lanes_select_i32(closer, i32x8::splat((8 * k + lane) as i32), best_i);
        }
    }
    hits.t = best_t;
    hits.sphere = best_i;
}

/// Which rays of a packet hit any sphere of a [`SphereSet`] in their
/// interval: bit `k` set when active lane `k` is occluded. Stops as soon as
/// every active lane is occluded. The packet twin of [`super::any_hit`].
///
/// ```
/// use glam::Vec3;
/// use strata::trace::*;
/// let spheres = [Sphere::new(Vec3::new(0.0, 2.0, 0.0), 0.5)];
/// let mut storage = [SphereChunk8::EMPTY];
/// let set = SphereSet::build(&spheres, &mut storage).unwrap();
/// let up = Ray::new(Vec3::ZERO, Vec3::Y).with_range(1e-4, 5.0);
/// let side = Ray::new(Vec3::ZERO, Vec3::X).with_range(1e-4, 5.0);
/// assert_eq!(any_hit_x8(&set, &RayPacket8::from_rays(&[up, side])), 0b01);
/// ```
#[inline]
#[must_use]
pub fn any_hit_x8(set: &SphereSet<'_>, packet: &RayPacket8) -> u32 {
    let p = packet;
    let active = lanes_bitmask(p.active);
    if active == 0 {
        return 0;
    }
    let inf = f32x8::splat(f32::INFINITY);
    let mut occluded = 0u32;
    for (k, c) in set.chunks.iter().enumerate() {
        for lane in 0..(set.len - 8 * k).min(8) {
            let t = packet_sphere_t(p, c, lane);
            occluded |= lanes_bitmask(p.active & t.lt(inf));
            if occluded == active {
                return occluded;
            }
        }
    }
    occluded
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_sizing_and_what_a_set_refuses() {
        let spheres = [Sphere::new(Vec3::ZERO, 1.0); 17];
        assert_eq!(chunks_for(17), 3);
        let mut small = [SphereChunk8::EMPTY; 2];
        assert_eq!(
            SphereSet::build(&spheres, &mut small).unwrap_err(),
            SphereSetError::StorageTooSmall {
                needed: 3,
                provided: 2
            }
        );
        let mut big = [SphereChunk8::EMPTY; 5];
        let set = SphereSet::build(&spheres, &mut big).unwrap();
        assert_eq!((set.len(), set.chunks().len()), (17, 3));
        assert_eq!(set.sphere(16), Some(spheres[16]));
        assert_eq!(set.sphere(17), None);
        // Padding lanes have radius 0.
        assert!((1..8).all(|k| set.chunks()[2].sphere(k).radius == 0.0));
        // A kept view of built chunks, and what it refuses.
        let view = SphereSet::from_chunks(&big[..3], 17).unwrap();
        assert_eq!(view.sphere(16), Some(spheres[16]));
        assert_eq!(
            SphereSet::from_chunks(&big[..2], 17).unwrap_err(),
            SphereSetError::StorageTooSmall {
                needed: 3,
                provided: 2
            }
        );
        let mut corrupt = [big[0], big[1], big[2]];
        let mut lanes: [Sphere; 8] = core::array::from_fn(|k| corrupt[2].sphere(k));
        lanes[5].radius = 1.0;
        corrupt[2] = SphereChunk8::from_spheres(lanes);
        assert_eq!(
            SphereSet::from_chunks(&corrupt, 17).unwrap_err(),
            SphereSetError::Padding
        );
        let empty = SphereSet::build(&[], &mut []).unwrap();
        assert!(empty.is_empty());
        assert_eq!(
            super::closest_hit_1x8(&empty, &Ray::new(Vec3::ZERO, Vec3::X)),
            None
        );
    }
}
