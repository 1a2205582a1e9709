// particle-lab's 3D pass: ground grid, sphere impostors, thick segments, water.

struct Globals {
    view_proj: mat4x4<f32>,
    // xyz: eye position (m); w: height of the ground (m).
    eye: vec4<f32>,
    // x, y: viewport size (px); z: 1 when the grid is on; w: near plane distance (m).
    viewport: vec4<f32>,
    // xyz: unit direction towards the light; w: the camera's orbit distance (m).
    light: vec4<f32>,
    // xyz: the camera's unit viewing direction; w: 1 for an orthographic projection
    // (rays parallel to it), 0 for perspective (rays from the eye).
    forward: vec4<f32>,
};

fn orthographic() -> bool {
    return globals.forward.w > 0.5;
}

@group(0) @binding(0) var<uniform> globals: Globals;

// Mirrors `SphereInstance` (48 bytes).
struct Sphere {
    // Centre (m).
    center: vec3<f32>,
    // Radius (m).
    radius: f32,
    // Linear RGBA colour.
    color: vec4<f32>,
    // Orientation of a sphere that rolls (unit quaternion xyzw); all zero: unmarked.
    spin: vec4<f32>,
};

// The spheres come to the vertex shaders one of two ways, both below. By index from a
// storage buffer (`spheres.wgsl`, appended where the GPU has vertex storage): one plain
// draw for them all, sphere i drawn by vertices 3i..3i+2. Or as instances, each
// sphere's fields as vertex attributes (`vs_*_instanced`): for GPUs without storage
// buffers, WebGL2 among them.
struct SphereIn {
    @location(0) center: vec3<f32>,
    @location(1) radius: f32,
    @location(2) color: vec4<f32>,
    @location(3) spin: vec4<f32>,
};

const SKY: vec3<f32> = vec3<f32>(0.55, 0.65, 0.80);
const GROUND_BOUNCE: vec3<f32> = vec3<f32>(0.20, 0.18, 0.15);

// How much of the background a point this far from the eye shows through (0..1):
// none within 60 m, all beyond 310 m; further out for a camera backed off beyond 50 m,
// so what it was backed off to show is not lost in the fog.
fn fog(world: vec3<f32>) -> f32 {
    let orbit = globals.light.w;
    let start = max(60.0, 1.2 * orbit);
    let span = max(250.0, 5.0 * orbit);
    return clamp((length(world - globals.eye.xyz) - start) / span, 0.0, 1.0);
}

fn depth_of(world: vec3<f32>) -> f32 {
    let clip = globals.view_proj * vec4<f32>(world, 1.0);
    return clip.z / clip.w;
}

// ---------------------------------------------------------------- ground

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

const GROUND_HALF_SIZE: f32 = 400.0;

@vertex
fn vs_ground(@builtin(vertex_index) index: u32) -> GroundOut {
    // Two triangles covering a large square centred under the eye.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    // Wider for a camera backed off far (a kilometres-long projectile path).
    let c = corners[index] * max(GROUND_HALF_SIZE, 8.0 * globals.light.w);
    let world = vec3<f32>(c.x + floor(globals.eye.x), globals.eye.w, c.y + floor(globals.eye.z));
    var out: GroundOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

// Anti-aliased grid line intensity for lines every `spacing` metres.
fn grid_line(p: vec2<f32>, spacing: f32, width_px: f32) -> f32 {
    let coord = p / spacing;
    let derivative = fwidth(coord);
    let distance = abs(fract(coord - 0.5) - 0.5) / max(derivative, vec2<f32>(1e-6));
    let line = min(distance.x, distance.y);
    return 1.0 - clamp(line - width_px * 0.5 + 0.5, 0.0, 1.0);
}

@fragment
fn fs_ground(in: GroundOut) -> @location(0) vec4<f32> {
    var color = vec3<f32>(0.035, 0.038, 0.042);
    if (globals.viewport.z > 0.5) {
        let minor = grid_line(in.world.xz, 1.0, 1.0);
        let major = grid_line(in.world.xz, 5.0, 1.5);
        color = mix(color, vec3<f32>(0.075, 0.08, 0.085), minor);
        color = mix(color, vec3<f32>(0.15, 0.16, 0.17), major);
        // The x axis red, the z axis blue, as in most 3D tools.
        let axis_x = 1.0 - clamp(abs(in.world.z) / max(fwidth(in.world.z), 1e-6) - 0.5, 0.0, 1.0);
        let axis_z = 1.0 - clamp(abs(in.world.x) / max(fwidth(in.world.x), 1e-6) - 0.5, 0.0, 1.0);
        color = mix(color, vec3<f32>(0.60, 0.15, 0.12), axis_x);
        color = mix(color, vec3<f32>(0.12, 0.25, 0.65), axis_z);
    }
    // Fade into the background with distance.
    return vec4<f32>(mix(color, vec3<f32>(0.045, 0.05, 0.065), fog(in.world)), 1.0);
}

// ---------------------------------------------------------------- spheres

// Corner `k` (0..2) of the equilateral triangle around the unit circle: the circle
// touches its sides, so the corners lie 2 from the centre. One triangle per sphere
// instead of a two-triangle square: a software GPU pays per triangle set up, and
// pays less for the 30% more (mostly discarded) pixels.
fn triangle_corner(k: u32) -> vec2<f32> {
    let sqrt3 = 1.7320508;
    return select(select(vec2<f32>(sqrt3, -1.0), vec2<f32>(-sqrt3, -1.0), k == 1u), vec2<f32>(0.0, 2.0), k == 0u);
}

struct SphereOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) center: vec3<f32>,
    @location(2) radius: f32,
    @location(3) color: vec4<f32>,
    @location(4) spin: vec4<f32>,
};

@vertex
fn vs_sphere_instanced(@builtin(vertex_index) corner: u32, sphere: SphereIn) -> SphereOut {
    return sphere_vertex(Sphere(sphere.center, sphere.radius, sphere.color, sphere.spin), corner);
}

// Corner `k` (0..2) of the triangle drawn around `sphere`.
fn sphere_vertex(sphere: Sphere, k: u32) -> SphereOut {
    // A triangle facing the eye, in front of the sphere, around its silhouette: at
    // distance q the silhouette's radius is q tan(asin(r / d)) = q r / sqrt(d² - r²).
    // The triangle stays beyond the near plane; with the eye inside the sphere it
    // collapses.
    let corner = triangle_corner(k);
    let to_center = sphere.center - globals.eye.xyz;
    let d = length(to_center);
    var forward = to_center / max(d, 1e-6);
    if (orthographic()) {
        forward = globals.forward.xyz;
    }
    var up = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(forward.y) > 0.999) {
        up = vec3<f32>(1.0, 0.0, 0.0);
    }
    let right = normalize(cross(forward, up));
    let up2 = cross(right, forward);
    let q = max(d - sphere.radius, globals.viewport.w * 1.01);
    let tangent = sphere.radius / sqrt(max(d * d - sphere.radius * sphere.radius, 1e-12));
    // A little margin so the anti-aliased edge has room.
    var silhouette = select(q * tangent * 1.08, 0.0, d <= sphere.radius);
    var world = globals.eye.xyz + forward * q + (right * corner.x + up2 * corner.y) * silhouette;
    if (orthographic()) {
        // Parallel rays: the silhouette is the sphere's own radius, seen in front of it.
        silhouette = sphere.radius * 1.08;
        world = sphere.center - forward * sphere.radius + (right * corner.x + up2 * corner.y) * silhouette;
    }
    var out: SphereOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.center = sphere.center;
    out.radius = sphere.radius;
    out.color = sphere.color;
    out.spin = sphere.spin;
    return out;
}

// `v` turned by the inverse of the unit quaternion `q`: from the world into the
// sphere's own frame.
fn unrotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let u = -q.xyz;
    return v + 2.0 * cross(u, cross(u, v) + q.w * v);
}

// The marking of a sphere that rolls, at the unit surface normal `n` (world): 0 plain,
// 1 the dark band around its own equator, 2 the light dot on the band; edges blended.
// (Derivatives are taken before the choice: they must be in uniform control flow.)
fn marking(spin: vec4<f32>, n: vec3<f32>) -> vec2<f32> {
    let body = unrotate(spin, n);
    let band_width = fwidth(body.y) + 1e-4;
    let dot_width = fwidth(body.x) + 1e-4;
    let band = 1.0 - smoothstep(0.16 - band_width, 0.16 + band_width, abs(body.y));
    let spot = smoothstep(0.93 - dot_width, 0.93 + dot_width, body.x);
    return select(vec2<f32>(band, spot), vec2<f32>(0.0, 0.0), dot(spin, spin) < 0.25);
}

struct SphereFragment {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_sphere(in: SphereOut) -> SphereFragment {
    // The ray through this pixel: from the eye, or with an orthographic projection
    // along the viewing direction from the point drawn.
    var eye = globals.eye.xyz;
    var ray = normalize(in.world - eye);
    if (orthographic()) {
        ray = globals.forward.xyz;
        eye = in.world - ray * (in.radius * 2.0);
    }
    let to_eye = eye - in.center;
    let b = dot(to_eye, ray);
    // Distance from the centre to the ray, and the edge coverage it gives.
    let closest = sqrt(max(dot(to_eye, to_eye) - b * b, 0.0));
    let coverage = clamp((in.radius - closest) / max(fwidth(closest), 1e-6) + 0.5, 0.0, 1.0);
    if (coverage <= 0.0) {
        discard;
    }
    let h = max(in.radius * in.radius - closest * closest, 0.0);
    let t = -b - sqrt(h);
    let hit = eye + ray * t;
    // Powers by repeated products, not `pow`: a software GPU evaluates this for
    // millions of pixels a frame when a crowd of spheres is on screen.
    let normal = (hit - in.center) / in.radius;
    let light = globals.light.xyz;
    let diffuse = max(dot(normal, light), 0.0);
    let ambient = mix(GROUND_BOUNCE, SKY, normal.y * 0.5 + 0.5);
    let s = max(dot(reflect(-light, normal), -ray), 0.0);
    let s4 = (s * s) * (s * s);
    let s8 = s4 * s4;
    let s32 = (s8 * s8) * (s8 * s8);
    let specular = s32 * s8;
    let edge = 1.0 - max(dot(normal, -ray), 0.0);
    let rim = edge * edge * edge * 0.15;
    let mark = marking(in.spin, normal);
    let base = mix(mix(in.color.rgb, in.color.rgb * 0.35, mark.x), vec3<f32>(0.95, 0.95, 0.9), mark.y);
    let lit = base * (0.35 * ambient + 0.8 * diffuse) + vec3<f32>(0.35 * specular + rim);
    var out: SphereFragment;
    out.color = vec4<f32>(lit, coverage);
    out.depth = depth_of(hit);
    return out;
}

// ---------------------------------------------------------------- shadows

// A soft dark disc on the ground under each sphere: wider and fainter the higher it
// is, so heights read at a glance.
struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) local: vec2<f32>,
    @location(1) strength: f32,
};

@vertex
fn vs_shadow_instanced(@builtin(vertex_index) corner: u32, sphere: SphereIn) -> ShadowOut {
    return shadow_vertex(Sphere(sphere.center, sphere.radius, sphere.color, sphere.spin), corner);
}

fn shadow_vertex(sphere: Sphere, k: u32) -> ShadowOut {
    let corner = triangle_corner(k);
    let ground = globals.eye.w;
    let height = max(sphere.center.y - sphere.radius - ground, 0.0);
    let size = sphere.radius * (1.1 + height * 0.12);
    let world = vec3<f32>(sphere.center.x + corner.x * size, ground, sphere.center.z + corner.y * size);
    var out: ShadowOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.local = corner;
    // Nothing under the ground casts a shadow on it; far away it fades with the ground.
    let strength = 0.65 * clamp(1.0 - height / 15.0, 0.0, 1.0) * (1.0 - fog(world));
    out.strength = select(strength, 0.0, sphere.center.y < ground);
    return out;
}

@fragment
fn fs_shadow(in: ShadowOut) -> @location(0) vec4<f32> {
    let falloff = 1.0 - smoothstep(0.2, 1.0, length(in.local));
    return vec4<f32>(0.0, 0.0, 0.0, in.strength * falloff);
}

// ---------------------------------------------------------------- segments

struct SegmentIn {
    @location(0) from_point: vec3<f32>,
    @location(1) width: f32,
    @location(2) to_point: vec3<f32>,
    @location(3) color: vec4<f32>,
};

struct SegmentOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

// Moves a clip-space end that lies behind the eye onto the near side.
fn clip_to_front(p: vec4<f32>, other: vec4<f32>) -> vec4<f32> {
    let near_w = 1e-3;
    if (p.w >= near_w) {
        return p;
    }
    let t = (near_w - p.w) / (other.w - p.w);
    return mix(p, other, t);
}

// Expands one segment into a quad `width` pixels wide; `extend` lengthens the ends by
// half a width so the joints of a chain meet.
fn expand_segment(index: u32, segment: SegmentIn, extend: f32) -> SegmentOut {
    var ends = array<f32, 6>(0.0, 1.0, 1.0, 0.0, 1.0, 0.0);
    var sides = array<f32, 6>(-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
    var out: SegmentOut;
    out.color = segment.color;
    let a0 = globals.view_proj * vec4<f32>(segment.from_point, 1.0);
    let b0 = globals.view_proj * vec4<f32>(segment.to_point, 1.0);
    if (a0.w < 1e-3 && b0.w < 1e-3) {
        // Wholly behind the eye: a degenerate quad draws nothing.
        out.clip = vec4<f32>(0.0, 0.0, 0.0, 1.0);
        return out;
    }
    let a = clip_to_front(a0, b0);
    let b = clip_to_front(b0, a0);
    let half_viewport = globals.viewport.xy * 0.5;
    let a_px = a.xy / a.w * half_viewport;
    let b_px = b.xy / b.w * half_viewport;
    var direction = b_px - a_px;
    if (length(direction) < 1e-6) {
        direction = vec2<f32>(1.0, 0.0);
    }
    direction = normalize(direction);
    let normal = vec2<f32>(-direction.y, direction.x);
    let end = ends[index];
    var p = mix(a, b, end);
    let offset_px = normal * sides[index] * segment.width * 0.5
        + direction * (end * 2.0 - 1.0) * segment.width * 0.5 * extend;
    p = vec4<f32>(p.xy + offset_px / half_viewport * p.w, p.z, p.w);
    out.clip = p;
    return out;
}

@vertex
fn vs_segment(@builtin(vertex_index) index: u32, segment: SegmentIn) -> SegmentOut {
    return expand_segment(index, segment, 1.0);
}

// Trails: translucent, so ends must not overlap (they would blend twice).
@vertex
fn vs_trail(@builtin(vertex_index) index: u32, segment: SegmentIn) -> SegmentOut {
    return expand_segment(index, segment, 0.0);
}

@fragment
fn fs_segment(in: SegmentOut) -> @location(0) vec4<f32> {
    return in.color;
}

@fragment
fn fs_trail(in: SegmentOut) -> @location(0) vec4<f32> {
    return in.color;
}

// ---------------------------------------------------------------- water

struct WaterIn {
    @location(0) center: vec4<f32>,
    @location(1) half_extent: vec4<f32>,
};

struct WaterOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_water(@builtin(vertex_index) index: u32, water: WaterIn) -> WaterOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[index] * water.half_extent.xy;
    let world = vec3<f32>(water.center.x + c.x, water.center.y, water.center.z + c.y);
    var out: WaterOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

@fragment
fn fs_water(in: WaterOut) -> @location(0) vec4<f32> {
    let view = normalize(globals.eye.xyz - in.world);
    // More reflective at grazing angles (Schlick's Fresnel for water).
    let fresnel = 0.02 + 0.98 * pow(1.0 - max(view.y, 0.0), 5.0);
    let deep = vec3<f32>(0.05, 0.25, 0.45);
    let color = mix(deep, SKY, fresnel);
    return vec4<f32>(color, mix(0.45, 0.85, fresnel));
}
