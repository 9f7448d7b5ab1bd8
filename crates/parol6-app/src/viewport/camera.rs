//! Z-up orbit camera: yaw/pitch/distance around a target point, right-handed, wgpu clip space
//! (depth 0…1).

use eframe::egui;
use parol6_core::na::{Matrix4, Point3, Vector3, Vector4};

/// Default orbit target, m (about the middle of the PAROL6's working height).
const DEFAULT_TARGET_M: [f32; 3] = [0.0, 0.0, 0.21];
/// Default yaw, rad (camera in front-right of the robot).
const DEFAULT_YAW_RAD: f32 = -0.65;
/// Default pitch, rad (looking slightly down).
const DEFAULT_PITCH_RAD: f32 = 0.38;
/// Default distance from the target, m.
const DEFAULT_DISTANCE_M: f32 = 0.95;
/// Closest and farthest zoom, m.
const DISTANCE_RANGE_M: (f32, f32) = (0.05, 20.0);
/// Pitch limit, rad (just short of the poles).
const PITCH_LIMIT_RAD: f32 = 1.55;
/// How far from the robot's base a remembered orbit target may be, m (farther: the default view).
const TARGET_RANGE_M: f32 = 10.0;
/// Views narrower than this (width / height) widen their vertical field of view so that the
/// horizontal one stays that of this aspect: a tall, narrow view still shows the whole arm.
const MIN_FIT_ASPECT: f32 = 1.3;

/// An orbit camera looking at `target_m` from `distance_m` away.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// Point the camera orbits and looks at, world m.
    pub target_m: Vector3<f32>,
    /// Azimuth about world z, rad (0 = camera on +x looking back towards −x).
    pub yaw_rad: f32,
    /// Elevation above the xy plane, rad.
    pub pitch_rad: f32,
    /// Distance from the target, m.
    pub distance_m: f32,
    /// Vertical field of view, rad.
    pub fov_y_rad: f32,
    /// Near clip plane, m.
    pub near_m: f32,
    /// Far clip plane, m.
    pub far_m: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target_m: Vector3::from(DEFAULT_TARGET_M),
            yaw_rad: DEFAULT_YAW_RAD,
            pitch_rad: DEFAULT_PITCH_RAD,
            distance_m: DEFAULT_DISTANCE_M,
            fov_y_rad: 40f32.to_radians(),
            near_m: 0.01,
            far_m: 60.0,
        }
    }
}

impl OrbitCamera {
    /// Back to the default view.
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// A view read back from the settings (see [`Self::reset`]'s default): the pitch clamped
    /// to its limit, the yaw wrapped to one turn; `None` (the default view, then) for a NaN or
    /// infinite number, a distance outside the zoom range or a target farther than 10 m.
    pub fn remembered(target_m: [f32; 3], yaw_rad: f32, pitch_rad: f32, distance_m: f32) -> Option<Self> {
        let finite = target_m.iter().chain([&yaw_rad, &pitch_rad, &distance_m]).all(|v| v.is_finite());
        let (near, far) = DISTANCE_RANGE_M;
        if !finite || !(near..=far).contains(&distance_m) || target_m.iter().any(|v| v.abs() > TARGET_RANGE_M) {
            return None;
        }
        Some(Self {
            target_m: Vector3::from(target_m),
            yaw_rad: yaw_rad.rem_euclid(std::f32::consts::TAU),
            pitch_rad: pitch_rad.clamp(-PITCH_LIMIT_RAD, PITCH_LIMIT_RAD),
            distance_m,
            ..Self::default()
        })
    }

    /// Camera position, world m.
    pub fn eye_m(&self) -> Vector3<f32> {
        let (sy, cy) = self.yaw_rad.sin_cos();
        let (sp, cp) = self.pitch_rad.sin_cos();
        self.target_m + Vector3::new(cp * cy, cp * sy, sp) * self.distance_m
    }

    /// Turns the camera about the target by `d_yaw_rad` (about world z) and `d_pitch_rad`.
    pub fn orbit(&mut self, d_yaw_rad: f32, d_pitch_rad: f32) {
        if d_yaw_rad.is_finite() {
            self.yaw_rad = (self.yaw_rad + d_yaw_rad).rem_euclid(std::f32::consts::TAU);
        }
        if d_pitch_rad.is_finite() {
            self.pitch_rad = (self.pitch_rad + d_pitch_rad).clamp(-PITCH_LIMIT_RAD, PITCH_LIMIT_RAD);
        }
    }

    /// Multiplies the distance by `factor` (< 1 zooms in).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance_m = (self.distance_m * factor).clamp(DISTANCE_RANGE_M.0, DISTANCE_RANGE_M.1);
        }
    }

    /// Vertical field of view used for a view of `aspect` (width / height), rad: [`Self::fov_y_rad`],
    /// widened for views narrower than 1.3 so that the horizontal field stays the same.
    pub fn effective_fov_y_rad(&self, aspect: f32) -> f32 {
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        if aspect >= MIN_FIT_ASPECT {
            return self.fov_y_rad;
        }
        (2.0 * ((0.5 * self.fov_y_rad).tan() * MIN_FIT_ASPECT / aspect).atan()).min(170f32.to_radians())
    }

    /// Moves the target so that the scene follows a mouse drag of (`dx_px`, `dy_px`) in a view
    /// of `view_width_px` × `view_height_px`.
    pub fn pan_px(&mut self, dx_px: f32, dy_px: f32, view_width_px: f32, view_height_px: f32) {
        if !(dx_px.is_finite() && dy_px.is_finite()) || view_height_px <= 0.0 || view_width_px <= 0.0 {
            return;
        }
        let fov = self.effective_fov_y_rad(view_width_px / view_height_px);
        let m_per_px = 2.0 * self.distance_m * (0.5 * fov).tan() / view_height_px;
        let (right, up) = self.right_up();
        self.target_m += (-right * dx_px + up * dy_px) * m_per_px;
    }

    /// Camera right and up unit vectors, world.
    fn right_up(&self) -> (Vector3<f32>, Vector3<f32>) {
        let forward = (self.target_m - self.eye_m()).normalize();
        let right = forward.cross(&Vector3::z()).try_normalize(1e-6).unwrap_or_else(Vector3::x);
        let up = right.cross(&forward);
        (right, up)
    }

    /// World → view matrix.
    pub fn view(&self) -> Matrix4<f32> {
        let eye = self.eye_m();
        Matrix4::look_at_rh(&Point3::from(eye), &Point3::from(self.target_m), &Vector3::z())
    }

    /// View → clip projection for wgpu (depth 0 at near, 1 at far).
    pub fn projection(&self, aspect: f32) -> Matrix4<f32> {
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        let f = 1.0 / (0.5 * self.effective_fov_y_rad(aspect)).tan();
        let (n, fa) = (self.near_m, self.far_m);
        Matrix4::new(
            f / aspect,
            0.0,
            0.0,
            0.0,
            0.0,
            f,
            0.0,
            0.0,
            0.0,
            0.0,
            fa / (n - fa),
            n * fa / (n - fa),
            0.0,
            0.0,
            -1.0,
            0.0,
        )
    }

    /// World → clip matrix for a view of width/height `aspect`.
    pub fn view_proj(&self, aspect: f32) -> Matrix4<f32> {
        self.projection(aspect) * self.view()
    }
}

/// Screen position of world point `p` inside `rect`, or `None` when it is behind the camera
/// or outside the depth range.
pub fn project_to_rect(view_proj: &Matrix4<f32>, p: &Point3<f32>, rect: egui::Rect) -> Option<egui::Pos2> {
    let c = view_proj * Vector4::new(p.x, p.y, p.z, 1.0);
    if c.w <= 1e-6 {
        return None;
    }
    let (x, y, z) = (c.x / c.w, c.y / c.w, c.z / c.w);
    if !(0.0..=1.0).contains(&z) {
        return None;
    }
    Some(egui::pos2(rect.left() + (x + 1.0) * 0.5 * rect.width(), rect.top() + (1.0 - y) * 0.5 * rect.height()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_centre() {
        let cam = OrbitCamera::default();
        let rect = egui::Rect::from_min_size(egui::pos2(10.0, 20.0), egui::vec2(400.0, 200.0));
        let vp = cam.view_proj(2.0);
        let p = project_to_rect(&vp, &Point3::from(cam.target_m), rect);
        let p = p.unwrap_or(egui::pos2(-1.0, -1.0));
        assert!((p.x - 210.0).abs() < 1e-3 && (p.y - 120.0).abs() < 1e-3, "{p:?}");
    }

    #[test]
    fn up_is_up_and_behind_is_hidden() {
        let cam = OrbitCamera::default();
        let rect = egui::Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(100.0, 100.0));
        let vp = cam.view_proj(1.0);
        let above = cam.target_m + Vector3::new(0.0, 0.0, 0.1);
        let p = project_to_rect(&vp, &Point3::from(above), rect).unwrap_or(egui::pos2(0.0, 100.0));
        assert!(p.y < 50.0, "a point above the target must be drawn above the centre: {p:?}");
        let behind = cam.eye_m() + (cam.eye_m() - cam.target_m);
        assert!(project_to_rect(&vp, &Point3::from(behind), rect).is_none());
    }

    #[test]
    fn pan_zoom_orbit_and_reset() {
        let mut cam = OrbitCamera::default();
        cam.zoom(0.5);
        assert!((cam.distance_m - DEFAULT_DISTANCE_M * 0.5).abs() < 1e-6);
        cam.zoom(f32::NAN);
        cam.zoom(1e-9);
        assert!(cam.distance_m >= DISTANCE_RANGE_M.0);
        cam.orbit(0.0, 10.0);
        assert!(cam.pitch_rad <= PITCH_LIMIT_RAD);
        let t0 = cam.target_m;
        cam.pan_px(100.0, 0.0, 800.0, 500.0);
        assert!((cam.target_m - t0).norm() > 1e-3);
        assert!(cam.target_m.z.is_finite());
        cam.reset();
        assert_eq!(cam, OrbitCamera::default());
    }

    #[test]
    fn a_remembered_view_is_clamped_or_refused() {
        let cam = OrbitCamera::remembered([0.1, -0.2, 0.3], 7.0, 3.0, 2.0).expect("a sane view");
        assert_eq!(cam.pitch_rad, PITCH_LIMIT_RAD);
        assert!((cam.yaw_rad - (7.0 - std::f32::consts::TAU)).abs() < 1e-6);
        assert_eq!((cam.distance_m, cam.target_m.x), (2.0, 0.1));
        for bad in [
            ([0.0, 0.0, f32::NAN], 0.0, 0.0, 1.0),
            ([0.0; 3], f32::INFINITY, 0.0, 1.0),
            ([0.0; 3], 0.0, 0.0, 1e9),
            ([0.0; 3], 0.0, 0.0, 0.0),
            ([0.0; 3], 0.0, 0.0, -1.0),
            ([50.0, 0.0, 0.0], 0.0, 0.0, 1.0),
        ] {
            assert_eq!(OrbitCamera::remembered(bad.0, bad.1, bad.2, bad.3), None, "{bad:?}");
        }
    }

    #[test]
    fn narrow_views_keep_the_horizontal_field() {
        let cam = OrbitCamera::default();
        assert_eq!(cam.effective_fov_y_rad(1.6), cam.fov_y_rad);
        let half_w = |aspect: f32| (0.5 * cam.effective_fov_y_rad(aspect)).tan() * aspect;
        assert!((half_w(0.6) - half_w(MIN_FIT_ASPECT)).abs() < 1e-5);
        assert!(cam.effective_fov_y_rad(0.01) < std::f32::consts::PI);
    }
}
