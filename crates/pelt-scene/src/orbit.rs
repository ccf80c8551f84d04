//! The orbit camera of `pelt view` (and `pelt render --orbit`): a camera held as a target, a
//! distance and a direction from the target, so that dragging orbits around the target about
//! the scene's up axis, panning moves the target in the view plane, the wheel zooms, and `F`
//! frames an asset's bounds. It starts exactly at the scene's camera, so the first frame of a
//! window equals `pelt render` of the same input.

use glam::{Mat3, Vec3};

use crate::scene::Camera;

/// Directions closer than this (radians) to the up axis are not orbited into: the view
/// would flip.
const POLE_MARGIN: f32 = 0.02;

/// Nearest and farthest zoom, as multiples of the starting distance.
const ZOOM_RANGE: (f32, f32) = (1e-3, 1e3);

/// An orbiting camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The point orbited.
    pub target: Vec3,
    /// Unit direction from the target to the eye.
    pub dir: Vec3,
    /// Eye to target distance.
    pub distance: f32,
    /// Unit up axis (orbits turn about it).
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    /// The scene camera's near plane at `start_distance`.
    near: f32,
    /// The scene camera's far plane at `start_distance`.
    far: f32,
    /// The distance `near` and `far` were given for.
    start_distance: f32,
}

impl Orbit {
    /// The orbit that reproduces `camera` exactly.
    pub fn new(camera: &Camera) -> Orbit {
        let eye = Vec3::from(camera.position);
        let target = Vec3::from(camera.target);
        let offset = eye - target;
        let distance = offset.length().max(1e-6);
        Orbit {
            target,
            dir: offset.normalize_or(Vec3::Z),
            distance,
            up: Vec3::from(camera.up).normalize_or(Vec3::Y),
            fov_y_deg: camera.fov_y_deg,
            near: camera.near,
            far: camera.far,
            start_distance: distance,
        }
    }

    /// The scene camera this orbit stands for. Near and far follow the zoom: near scales
    /// with the distance, far keeps its reach beyond the target.
    pub fn camera(&self) -> Camera {
        let k = self.distance / self.start_distance;
        let near = (self.near * k).max(1e-5);
        let far = (self.far + self.distance - self.start_distance).max(near * 2.0);
        Camera {
            position: (self.target + self.dir * self.distance).to_array(),
            target: self.target.to_array(),
            up: self.up.to_array(),
            fov_y_deg: self.fov_y_deg,
            near,
            far,
        }
    }

    /// Turns the eye `yaw` radians about the up axis and `pitch` radians towards it
    /// (positive: the eye rises), stopping short of the poles.
    pub fn rotate(&mut self, yaw: f32, pitch: f32) {
        let d = Mat3::from_axis_angle(self.up, yaw) * self.dir;
        let height = d.dot(self.up).clamp(-1.0, 1.0).asin();
        let limit = std::f32::consts::FRAC_PI_2 - POLE_MARGIN;
        let pitch = (height + pitch).clamp(-limit, limit) - height;
        let right = self.up.cross(d).normalize_or(Vec3::X);
        self.dir = (Mat3::from_axis_angle(right, -pitch) * d).normalize();
    }

    /// Moves the target (and the eye with it) by `dx`, `dy` in units of the view's height at
    /// the target: (1, 0) moves one screen height to the right.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let height = 2.0 * self.distance * (self.fov_y_deg.to_radians() / 2.0).tan();
        let right = self.up.cross(self.dir).normalize_or(Vec3::X);
        let screen_up = self.dir.cross(right);
        self.target += (right * dx + screen_up * dy) * height;
    }

    /// Zooms by `steps` wheel steps (positive: closer), each 15 % of the distance.
    pub fn zoom(&mut self, steps: f32) {
        let (lo, hi) = ZOOM_RANGE;
        self.distance = (self.distance * 0.85_f32.powf(steps))
            .clamp(self.start_distance * lo, self.start_distance * hi);
    }

    /// Frames `camera` (the default framing of an asset) while keeping this orbit's
    /// direction: `F` in the window.
    pub fn frame(&mut self, camera: &Camera) {
        let fresh = Orbit::new(camera);
        *self = Orbit {
            dir: self.dir,
            ..fresh
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: [1.0, 2.0, 5.0],
            target: [0.5, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.5,
            far: 30.0,
        }
    }

    fn close(a: [f32; 3], b: [f32; 3]) -> bool {
        (Vec3::from(a) - Vec3::from(b)).length() < 1e-5
    }

    #[test]
    fn the_first_view_is_the_scene_camera() {
        let c = camera();
        let o = Orbit::new(&c);
        let back = o.camera();
        assert!(close(back.position, c.position), "{back:?}");
        assert_eq!(back.target, c.target);
        assert_eq!(
            (back.near, back.far, back.fov_y_deg),
            (c.near, c.far, c.fov_y_deg)
        );
    }

    #[test]
    fn orbiting_keeps_the_distance_and_a_full_turn_comes_back() {
        let c = camera();
        let mut o = Orbit::new(&c);
        let d0 = o.distance;
        for _ in 0..36 {
            o.rotate(10f32.to_radians(), 0.0);
        }
        assert!(close(o.camera().position, c.position), "{:?}", o.camera());
        o.rotate(0.3, 0.2);
        let eye = Vec3::from(o.camera().position);
        assert!(((eye - o.target).length() - d0).abs() < 1e-4);
        // A quarter turn about +Y moves an eye on +Z to +X.
        let mut q = Orbit::new(&Camera {
            position: [0.0, 0.0, 3.0],
            target: [0.0; 3],
            ..c
        });
        q.rotate(90f32.to_radians(), 0.0);
        assert!(
            close(q.camera().position, [3.0, 0.0, 0.0]),
            "{:?}",
            q.camera()
        );
    }

    #[test]
    fn pitch_stops_short_of_the_poles() {
        let mut o = Orbit::new(&camera());
        o.rotate(0.0, 10.0);
        let up_dot = o.dir.dot(Vec3::Y);
        assert!(up_dot < 1.0 - 1e-5 && up_dot > 0.99, "{up_dot}");
        o.rotate(0.0, -20.0);
        assert!(o.dir.dot(Vec3::Y) > -1.0 + 1e-5);
        assert!(o.camera().position.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn pan_moves_target_and_eye_together_and_zoom_moves_the_planes() {
        let mut o = Orbit::new(&camera());
        let before = o.camera();
        o.pan(0.5, 0.0);
        let after = o.camera();
        let moved = Vec3::from(after.target) - Vec3::from(before.target);
        let eye_moved = Vec3::from(after.position) - Vec3::from(before.position);
        assert!((moved - eye_moved).length() < 1e-5);
        assert!(moved.dot(o.dir).abs() < 1e-5, "in the view plane");
        assert!(moved.length() > 0.1);
        let d = o.distance;
        o.zoom(2.0);
        assert!((o.distance - d * 0.85 * 0.85).abs() < 1e-5);
        let z = o.camera();
        assert!(z.near < before.near && z.far < before.far && z.near > 0.0);
        o.zoom(-1e6);
        assert!(o.distance.is_finite() && o.distance <= d * 1e3 + 1e-3);
    }

    #[test]
    fn framing_keeps_the_direction() {
        let mut o = Orbit::new(&camera());
        o.rotate(1.0, 0.3);
        o.zoom(5.0);
        let dir = o.dir;
        o.frame(&camera());
        assert_eq!(o.dir, dir);
        assert_eq!(o.distance, Orbit::new(&camera()).distance);
    }
}
