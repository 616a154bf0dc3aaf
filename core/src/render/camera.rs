//! The course's camera: look-from, look-at, up, vertical field of view,
//! and a thin lens given by a defocus angle and a focus distance.

use glam::{UVec2, Vec2, Vec3};

use crate::lanes::{Lanes, V3};
use crate::mapping::concentric;
use crate::trace::Ray;

/// Where a camera is and how it sees, as the course states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position.
    pub look_from: Vec3,
    /// Point the view is centred on.
    pub look_at: Vec3,
    /// The up direction (need not be perpendicular to the view).
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub vfov_deg: f32,
    /// Cone angle in degrees at the focus plane subtended by the lens;
    /// 0 is a pinhole.
    pub defocus_angle_deg: f32,
    /// Distance to the plane in perfect focus, `> 0`.
    pub focus_dist: f32,
}

/// Why a camera could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraError {
    /// Width or height is 0.
    EmptyImage,
    /// `look_from` equals `look_at`, `up` is parallel to the view, or a
    /// vector is not finite.
    DegenerateView,
    /// The field of view is not in `(0, 180)` degrees.
    FieldOfView,
    /// The focus distance is not positive and finite (or so extreme that a
    /// pixel on the focus plane is not representable), or the defocus
    /// angle is not in `[0, 180)` degrees.
    Lens,
}

impl core::fmt::Display for CameraError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            CameraError::EmptyImage => "the image width or height is 0",
            CameraError::DegenerateView => {
                "look_from equals look_at, up is parallel to the view, or a vector is not finite"
            }
            CameraError::FieldOfView => "the field of view must be in (0, 180) degrees",
            CameraError::Lens => {
                "the focus distance must be positive and finite (and a pixel on the focus plane \
                 representable), and the defocus angle in [0, 180) degrees"
            }
        })
    }
}

impl core::error::Error for CameraError {}

/// A camera for an image of `width × height` pixels. Pixel `(0, 0)` is the
/// top-left; a pixel offset `(0, 0)` is its top-left corner, `(0.5, 0.5)`
/// its centre (the course's pixel centre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    origin: Vec3,
    /// Top-left corner of pixel (0, 0) on the focus plane.
    corner: Vec3,
    /// One pixel to the right, one pixel down, on the focus plane.
    du: Vec3,
    dv: Vec3,
    /// Lens axes scaled by the lens radius.
    lens_u: Vec3,
    lens_v: Vec3,
    /// A lens of radius 0: every ray leaves `origin`.
    pinhole: bool,
    size: UVec2,
}

impl Camera {
    /// The course's construction: `w = unit(from − at)`, `u = unit(up ×
    /// w)`, `v = w × u`; a viewport `2 tan(vfov/2) · focus_dist` high on the
    /// focus plane; a lens of radius `focus_dist · tan(defocus/2)`.
    ///
    /// ```
    /// use glam::{UVec2, Vec2, Vec3};
    /// use strata::render::{Camera, CameraDesc};
    /// let desc = CameraDesc {
    ///     look_from: Vec3::new(-2.0, 2.0, 1.0),
    ///     look_at: Vec3::new(0.0, 0.0, -1.0),
    ///     up: Vec3::Y,
    ///     vfov_deg: 60.0,
    ///     defocus_angle_deg: 0.0,
    ///     focus_dist: 5.0,
    /// };
    /// let cam = Camera::new(&desc, 320, 180).unwrap();
    /// // A ray through the image centre looks at the target.
    /// let ray = cam.ray(UVec2::new(160, 90), Vec2::ZERO, Vec2::splat(0.5));
    /// let want = (desc.look_at - desc.look_from).normalize();
    /// assert!((ray.dir - want).length() < 1e-3);
    /// ```
    #[inline]
    pub fn new(desc: &CameraDesc, width: u32, height: u32) -> Result<Self, CameraError> {
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyImage);
        }
        if !(desc.vfov_deg > 0.0 && desc.vfov_deg < 180.0) {
            return Err(CameraError::FieldOfView);
        }
        let lens_ok = desc.focus_dist > 0.0
            && desc.focus_dist.is_finite()
            && desc.defocus_angle_deg >= 0.0
            && desc.defocus_angle_deg < 180.0;
        if !lens_ok {
            return Err(CameraError::Lens);
        }
        let view = desc.look_from - desc.look_at;
        let side = desc.up.cross(view);
        let finite = desc.look_from.is_finite() && desc.look_at.is_finite() && desc.up.is_finite();
        if !finite || view.length_squared() == 0.0 || side.length_squared() == 0.0 {
            return Err(CameraError::DegenerateView);
        }
        let w = crate::float::normalize(view);
        let u = crate::float::normalize(side);
        let v = w.cross(u);
        let half = libm::tanf(desc.vfov_deg.to_radians() * 0.5);
        let viewport_h = 2.0 * half * desc.focus_dist;
        let viewport_w = viewport_h * width as f32 / height as f32;
        let across = u * viewport_w;
        let down = -v * viewport_h;
        let du = across / width as f32;
        let dv = down / height as f32;
        let corner = desc.look_from - w * desc.focus_dist - across * 0.5 - down * 0.5;
        let lens_radius = desc.focus_dist * libm::tanf(desc.defocus_angle_deg.to_radians() * 0.5);
        // A focus distance so small or large that a pixel step underflows
        // or overflows would make every ray NaN: refuse it.
        let step_ok = |v: Vec3| v.is_finite() && v.length_squared() > 0.0;
        if !(step_ok(du) && step_ok(dv) && corner.is_finite() && lens_radius.is_finite()) {
            return Err(CameraError::Lens);
        }
        Ok(Self {
            origin: desc.look_from,
            corner,
            du,
            dv,
            lens_u: u * lens_radius,
            lens_v: v * lens_radius,
            pinhole: lens_radius == 0.0,
            size: UVec2::new(width, height),
        })
    }

    /// The image size in pixels.
    #[inline]
    #[must_use]
    pub fn size(&self) -> UVec2 {
        self.size
    }

    /// The ray through `pixel` at `offset ∈ [0, 1)²` inside it, leaving the
    /// lens at the concentric-disk point of `lens ∈ [0, 1)²` (ignored for a
    /// pinhole, where the lens has radius 0: its rays leave the camera's
    /// position exactly, a `−0.0` coordinate included, and the disk point
    /// is not computed). Unit direction, `t ∈ (0, ∞)`.
    #[inline(always)]
    #[must_use]
    pub fn ray(&self, pixel: UVec2, offset: Vec2, lens: Vec2) -> Ray {
        let (origin, dir) = self.ray_lanes(
            (pixel.x as f32, pixel.y as f32),
            (offset.x, offset.y),
            (lens.x, lens.y),
        );
        Ray::new(Vec3::from(origin), Vec3::from(dir))
    }

    /// [`Camera::ray`] over lanes, from the pixel's corner as floats: the
    /// origin and unit direction.
    #[inline(always)]
    pub(crate) fn ray_lanes<L: Lanes>(
        &self,
        pixel: (L, L),
        offset: (L, L),
        lens: (L, L),
    ) -> (V3<L>, V3<L>) {
        let target = V3::splat(self.corner)
            + V3::splat(self.du) * (pixel.0 + offset.0)
            + V3::splat(self.dv) * (pixel.1 + offset.1);
        let origin = if self.pinhole {
            V3::splat(self.origin)
        } else {
            let (_, x, y) = concentric(lens.0, lens.1);
            V3::splat(self.origin) + V3::splat(self.lens_u) * x + V3::splat(self.lens_v) * y
        };
        (origin, (target - origin).normalize())
    }

    /// Whether the lens has radius 0 (a defocus angle of 0), so that
    /// [`Camera::ray`] ignores its lens sample: a renderer can skip making
    /// it.
    ///
    /// ```
    /// use glam::{UVec2, Vec2, Vec3};
    /// use strata::render::{Camera, CameraDesc};
    /// let mut desc = CameraDesc {
    ///     look_from: Vec3::new(0.0, 1.0, 4.0), look_at: Vec3::ZERO, up: Vec3::Y,
    ///     vfov_deg: 40.0, defocus_angle_deg: 0.0, focus_dist: 4.0,
    /// };
    /// let pinhole = Camera::new(&desc, 64, 48).unwrap();
    /// assert!(pinhole.is_pinhole());
    /// let (px, offset) = (UVec2::new(10, 20), Vec2::splat(0.5));
    /// let ray = pinhole.ray(px, offset, Vec2::new(0.9, 0.1));
    /// assert_eq!(ray, pinhole.ray(px, offset, Vec2::ZERO));
    /// let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    /// assert_eq!(bits(ray.origin), bits(desc.look_from));
    /// desc.defocus_angle_deg = 2.0;
    /// assert!(!Camera::new(&desc, 64, 48).unwrap().is_pinhole());
    /// ```
    #[inline]
    #[must_use]
    pub fn is_pinhole(&self) -> bool {
        self.pinhole
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc() -> CameraDesc {
        CameraDesc {
            look_from: Vec3::new(13.0, 2.0, 3.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 20.0,
            defocus_angle_deg: 0.6,
            focus_dist: 10.0,
        }
    }

    #[test]
    fn refuses_bad_cameras() {
        let d = desc();
        assert_eq!(Camera::new(&d, 0, 10), Err(CameraError::EmptyImage));
        let e = |f: fn(&mut CameraDesc)| {
            let mut d = desc();
            f(&mut d);
            Camera::new(&d, 10, 10).unwrap_err()
        };
        assert_eq!(e(|d| d.vfov_deg = 0.0), CameraError::FieldOfView);
        assert_eq!(e(|d| d.vfov_deg = 180.0), CameraError::FieldOfView);
        assert_eq!(e(|d| d.vfov_deg = f32::NAN), CameraError::FieldOfView);
        assert_eq!(e(|d| d.focus_dist = 0.0), CameraError::Lens);
        assert_eq!(e(|d| d.focus_dist = 1e-40), CameraError::Lens);
        assert_eq!(e(|d| d.focus_dist = 1e38), CameraError::Lens);
        assert_eq!(e(|d| d.defocus_angle_deg = -1.0), CameraError::Lens);
        assert_eq!(e(|d| d.look_at = d.look_from), CameraError::DegenerateView);
        assert_eq!(
            e(|d| d.up = d.look_from - d.look_at),
            CameraError::DegenerateView
        );
        assert_eq!(e(|d| d.up = Vec3::NAN), CameraError::DegenerateView);
    }

    #[test]
    fn rays_focus_on_the_focus_plane() {
        let cam = Camera::new(&desc(), 64, 36).unwrap();
        let p = UVec2::new(20, 7);
        let off = Vec2::new(0.25, 0.75);
        // Every lens point's ray passes the same point at the focus plane.
        let a = cam.ray(p, off, Vec2::splat(0.5));
        let focus = a.origin + a.dir * (10.0 / a.dir.dot(-Vec3::new(13.0, 2.0, 3.0).normalize()));
        for lens in [Vec2::new(0.1, 0.9), Vec2::new(0.9, 0.2)] {
            let b = cam.ray(p, off, lens);
            assert!(b.origin != a.origin);
            let t = (focus - b.origin).dot(b.dir);
            assert!(
                (b.at(t) - focus).length() < 1e-4,
                "{}",
                (b.at(t) - focus).length()
            );
        }
    }

    #[test]
    fn lens_radius_is_focus_times_tan_half_angle() {
        let cam = Camera::new(&desc(), 16, 9).unwrap();
        let centre = cam.ray(UVec2::new(3, 3), Vec2::ZERO, Vec2::splat(0.5));
        // The lens sample (1, 0.5) is the rim of the concentric disk.
        let rim = cam.ray(UVec2::new(3, 3), Vec2::ZERO, Vec2::new(1.0, 0.5));
        let want = 10.0 * (0.6f32.to_radians() * 0.5).tan();
        assert_eq!(centre.origin, Vec3::new(13.0, 2.0, 3.0));
        assert!(((rim.origin - centre.origin).length() - want).abs() < 1e-6);
    }

    #[test]
    fn pixel_rows_go_down() {
        let cam = Camera::new(&desc(), 16, 9).unwrap();
        let top = cam.ray(UVec2::new(8, 0), Vec2::splat(0.5), Vec2::splat(0.5));
        let bottom = cam.ray(UVec2::new(8, 8), Vec2::splat(0.5), Vec2::splat(0.5));
        assert!(top.dir.y > bottom.dir.y);
        assert!((top.dir.length() - 1.0).abs() < 1e-6);
    }
}
