//! An orbiting perspective camera.

use glam::camera::rh;
use glam::{Mat4, Vec2, Vec3};

use crate::scenes::{CameraHint, Scene};

/// A camera that orbits a target point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// Point looked at (m).
    pub target: Vec3,
    /// Distance from the target (m).
    pub distance: f32,
    /// Rotation about the vertical axis (radians); 0 puts the eye on +z looking along -z.
    pub yaw: f32,
    /// Elevation of the eye (radians); positive looks down.
    pub pitch: f32,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// Parallel projection: no perspective, sizes read the same at every depth (the 2D
    /// side view). It shows what a perspective view shows at the target's distance.
    pub orthographic: bool,
    /// Height of the ground drawn under the scene (m), which the eye stays above.
    pub ground: f32,
    /// Draw only this piece of the view (a tile of a frame too big for one GPU
    /// target); `None`, the whole view. Only the renderer reads it: picking, labels
    /// and [`Self::project`] always see the whole view.
    pub piece: Option<ViewPiece>,
}

/// A piece of a view drawn on its own: a frame larger than one GPU target is drawn a
/// tile at a time, each with the whole view's projection moved and scaled so that
/// every pixel lands where it would in the whole (see [`OrbitCamera::piece_projection`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewPiece {
    /// Width and height of the whole view (px).
    pub whole: [f32; 2],
    /// The piece's top-left corner in the whole view (px from the view's top left).
    pub offset: [f32; 2],
}

impl OrbitCamera {
    /// Closest the eye may get to the target (m): near enough to see millimetre
    /// particles whole.
    pub const MIN_DISTANCE: f32 = 0.005;
    /// Furthest the eye may get from the target (m).
    pub const MAX_DISTANCE: f32 = 500.0;
    /// Highest elevation: almost straight down.
    const PITCH_MAX: f32 = 1.55;
    /// Lowest elevation: a little below the horizon, not under the ground.
    const PITCH_MIN: f32 = -0.15;

    /// A camera placed as a scene asks, over the ground at y = 0.
    #[must_use]
    pub fn from_hint(hint: CameraHint) -> Self {
        Self {
            target: hint.target,
            distance: hint.distance,
            yaw: hint.yaw,
            pitch: hint.pitch,
            fov_y: 45f32.to_radians(),
            orthographic: false,
            ground: 0.0,
            piece: None,
        }
    }

    /// A camera framing `scene` as it asks, over the ground it stands on.
    #[must_use]
    pub fn framing(scene: &dyn Scene) -> Self {
        Self { ground: scene.ground(), ..Self::from_hint(scene.camera()) }
    }

    /// Position of the eye (m).
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        let (sin_yaw, cos_yaw) = self.yaw.sin_cos();
        let (sin_pitch, cos_pitch) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cos_pitch * sin_yaw, sin_pitch, cos_pitch * cos_yaw)
    }

    /// Distance of the near clipping plane (m): a hundredth of the orbit distance,
    /// at least 0.1 mm (a camera centimetres from millimetre particles).
    #[must_use]
    pub fn near(&self) -> f32 {
        (self.distance * 0.01).max(1e-4)
    }

    /// Distance of the far clipping plane (m): 2 km, or twenty orbits for a camera
    /// backed off further (a projectile's path kilometres long).
    #[must_use]
    pub fn far(&self) -> f32 {
        (self.distance * 20.0).max(2000.0)
    }

    /// World to clip space for a viewport of this aspect ratio (width / height).
    #[must_use]
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        let near = self.near();
        // wgpu's clip space is DirectX's: depth 0..1, y up.
        let aspect = aspect.max(1e-3);
        let projection = if self.orthographic {
            let half_height = self.distance * (self.fov_y * 0.5).tan();
            let half_width = half_height * aspect;
            rh::proj::directx::orthographic(
                -half_width,
                half_width,
                -half_height,
                half_height,
                near,
                self.far(),
            )
        } else {
            rh::proj::directx::perspective(self.fov_y, aspect, near, self.far())
        };
        projection * rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// World to clip space for `piece` of the view, drawn into a viewport `size` pixels
    /// large: [`Self::view_projection`] of the whole view, then moved and scaled in clip
    /// space so the piece's rectangle fills the viewport. Depth is untouched, and a
    /// pixel's footprint is the same as in the whole view, so lines a number of pixels
    /// wide and screen-space derivatives come out as they would there.
    #[must_use]
    pub fn piece_projection(&self, piece: ViewPiece, size: [f32; 2]) -> Mat4 {
        let [width, height] = piece.whole.map(|side| side.max(1e-3));
        let [piece_width, piece_height] = size.map(|side| side.max(1e-3));
        let [left, top] = piece.offset;
        // The piece spans whole-view NDC x from 2 left / width - 1 to 2 (left +
        // piece_width) / width - 1, y from 1 - 2 top / height down: those go to -1 and 1.
        let scale = Vec3::new(width / piece_width, height / piece_height, 1.0);
        let shift = Vec3::new(
            (width - 2.0 * left - piece_width) / piece_width,
            (2.0 * top + piece_height - height) / piece_height,
            0.0,
        );
        Mat4::from_translation(shift) * Mat4::from_scale(scale) * self.view_projection(width / height)
    }

    /// The unit direction the camera looks in.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye()).normalize_or_zero()
    }

    /// Turns the camera by a drag of `delta` pixels.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(Self::PITCH_MIN, Self::PITCH_MAX);
        self.keep_above_ground();
    }

    /// Lowest the eye may be (m): the ground is opaque from below.
    const MIN_EYE_HEIGHT: f32 = 0.05;

    /// Raises the target to the ground and the pitch until the eye is above it.
    fn keep_above_ground(&mut self) {
        self.target.y = self.target.y.max(self.ground);
        let above = self.target.y - self.ground;
        let lowest = ((Self::MIN_EYE_HEIGHT - above) / self.distance).clamp(-1.0, 1.0).asin();
        self.pitch = self.pitch.max(lowest).min(Self::PITCH_MAX);
    }

    /// The screen's rightward direction in the world (unit, horizontal).
    #[must_use]
    pub fn right(&self) -> Vec3 {
        let (sin_yaw, cos_yaw) = self.yaw.sin_cos();
        Vec3::new(cos_yaw, 0.0, -sin_yaw)
    }

    /// Moves the target sideways by a drag of `delta` pixels in a view `height` pixels high.
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let forward = (self.target - self.eye()).normalize_or_zero();
        let right = self.right();
        let up = right.cross(forward);
        let metres_per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0);
        self.target += (-right * delta.x + up * delta.y) * metres_per_pixel;
        self.keep_above_ground();
    }

    /// Zooms by wheel `steps` (positive zooms in).
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(Self::MIN_DISTANCE, Self::MAX_DISTANCE);
        self.keep_above_ground();
    }

    /// The ray through a pixel: origin and unit direction. `pixel` is from the top left
    /// of a viewport `size` pixels large.
    #[must_use]
    pub fn ray(&self, pixel: Vec2, size: Vec2) -> (Vec3, Vec3) {
        let ndc = Vec2::new(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
        let inverse = self.view_projection(size.x / size.y).inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or_zero())
    }

    /// Where a world point lands in a viewport, in pixels from the top left, or `None`
    /// if it is behind the eye.
    #[must_use]
    pub fn project(&self, point: Vec3, size: Vec2) -> Option<Vec2> {
        let clip = self.view_projection(size.x / size.y) * point.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y))
    }
}
