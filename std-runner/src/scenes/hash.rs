//! The scene hash: what film keys, image metadata and study caches carry,
//! so parts of different scenes never merge. Locked by the golden table's
//! `scene` rows.

use strata::render::Background;

use super::SceneData;
use crate::hash::Fnv;

impl SceneData {
    /// A stable 64-bit hash of everything that defines the picture: FNV-1a
    /// over the exact bits of the spheres, materials, textures, images,
    /// camera and background, fed as a stream (no formatting, so it does
    /// not change with the toolchain). The name and the render defaults are
    /// left out: renaming a scene file does not change its renders.
    pub fn content_hash(&self) -> u64 {
        let mut h = Fnv::default();
        h.u64(self.spheres.len() as u64);
        for s in &self.spheres {
            h.v3(s.center);
            h.f(s.radius);
        }
        for &m in &self.sphere_material {
            h.u32(m);
        }
        h.u64(self.materials.len() as u64);
        for m in &self.materials {
            // A tag per kind, then each parameter's bits; image texels
            // come below, with the image list.
            m.content_bytes(|b| h.bytes(b));
        }
        for &(m, i) in &self.image_albedo {
            h.u64(m as u64);
            h.u64(i as u64);
        }
        for img in &self.images {
            h.u32(img.width);
            h.u32(img.height);
            for &t in &img.texels {
                h.v3(t);
            }
        }
        let c = &self.camera;
        for v in [c.look_from, c.look_at, c.up] {
            h.v3(v);
        }
        for x in [c.vfov_deg, c.defocus_angle_deg, c.focus_dist] {
            h.f(x);
        }
        match self.background {
            Background::Sky => h.u32(1),
            Background::Flat(c) => {
                h.u32(2);
                h.v3(c);
            }
        }
        h.finish()
    }
}
