//! The scene hash: what film keys, image metadata and study caches carry,
//! so parts of different scenes never merge. Locked by the golden table's
//! `scene` rows.

use strata::render::{Background, Material, Texture};

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
            hash_material(&mut h, m);
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

fn hash_texture(h: &mut Fnv, t: &Texture<'_>) {
    match t {
        Texture::Solid(c) => {
            h.u32(1);
            h.v3(*c);
        }
        Texture::Checker { scale, even, odd } => {
            h.u32(2);
            h.f(*scale);
            h.v3(*even);
            h.v3(*odd);
        }
        // Images are hashed with the scene's image list.
        Texture::Image(_) => h.u32(3),
    }
}

fn hash_material(h: &mut Fnv, m: &Material<'_>) {
    let lobe = |h: &mut Fnv, tag: u32, albedo: &Texture<'_>, params: &[f32]| {
        h.u32(tag);
        hash_texture(h, albedo);
        for &p in params {
            h.f(p);
        }
    };
    match m {
        Material::Lambertian { albedo } => lobe(h, 1, albedo, &[]),
        Material::Mirror { albedo } => {
            h.u32(2);
            h.v3(*albedo);
        }
        Material::Metal { albedo, roughness } => {
            h.u32(3);
            h.v3(*albedo);
            h.f(*roughness);
        }
        Material::Dielectric { ior } => {
            h.u32(4);
            h.f(*ior);
        }
        Material::Phong {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 5, albedo, &[*kd, *ks, *exponent]),
        Material::Blinn {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 6, albedo, &[*kd, *ks, *exponent]),
        Material::PhongNormalized {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 7, albedo, &[*kd, *ks, *exponent]),
        Material::BlinnNormalized {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 8, albedo, &[*kd, *ks, *exponent]),
        Material::CookTorrance {
            albedo,
            kd,
            ks,
            alpha,
            ior,
        } => lobe(h, 9, albedo, &[*kd, *ks, *alpha, *ior]),
        Material::DiffuseLight { emit } => {
            h.u32(10);
            h.v3(*emit);
        }
    }
}
