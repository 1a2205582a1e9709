//! How a wall (a plane other than the ground) is drawn: a finite wall as its rectangle
//! of grid lines; an unbounded one as a square patch of them, centred where the
//! scene's things stand off it and as large as the scene, so that a ramp reads as a
//! ramp in 3D and as a line in the side view.

use glam::Vec3;

use crate::physics::{Plane, Plate};

/// Grid lines each way across a wall's patch (the edges included: one more).
pub const WALL_LINES: usize = 8;

/// The smallest half side of a patch (m): a wall by a single small particle is still
/// seen, and a ramp is long enough for a ball to roll down in view.
pub const MIN_HALF_SIDE: f32 = 2.0;

/// A patch's half side as a multiple of the diagonal of the box the scene fills.
pub const SCENE_SPANS: f32 = 1.5;

/// The patch drawn for `plane` around the box `lo`..`hi` (m) that the scene's
/// particles and anchors fill: centred on the box's centre moved onto the plane, its
/// half side [`SCENE_SPANS`] times the box's diagonal (at least [`MIN_HALF_SIDE`]), its lines along the
/// plane's slope and across it. An empty box (`lo` above `hi`) draws around the origin.
/// Pushes `2 (WALL_LINES + 1)` segments onto `out`.
pub fn plane_patch(plane: &Plane, lo: Vec3, hi: Vec3, out: &mut Vec<(Vec3, Vec3)>) {
    let (lo, hi) = if lo.cmple(hi).all() { (lo, hi) } else { (Vec3::ZERO, Vec3::ZERO) };
    let n = plane.normal;
    let centre = 0.5 * (lo + hi);
    let on_plane = centre - (n.dot(centre) - plane.offset) * n;
    let half = (SCENE_SPANS * (hi - lo).length()).max(MIN_HALF_SIDE);
    if let Some(e) = &plane.extent {
        let v = n.cross(e.along);
        grid(e.center, e.along * e.half_along, v * e.half_across, out);
        return;
    }
    let u = slope_direction(n);
    grid(on_plane, u * half, n.cross(u) * half, out);
}

/// Sides of the polygon that draws a plate's opening.
pub const RIM_SIDES: usize = 32;

/// The lines drawn for `plate`: a square grid on its plane around its opening's
/// centre, as wide as the box `lo`..`hi` the scene fills (as [`plane_patch`]), its
/// lines broken where they cross the opening, and the opening's rim.
pub fn plate_patch(plate: &Plate, lo: Vec3, hi: Vec3, out: &mut Vec<(Vec3, Vec3)>) {
    let (lo, hi) = if lo.cmple(hi).all() { (lo, hi) } else { (Vec3::ZERO, Vec3::ZERO) };
    let n = plate.normal;
    let half = (SCENE_SPANS * (hi - lo).length()).max(MIN_HALF_SIDE).max(2.0 * plate.opening);
    let u = slope_direction(n);
    let v = n.cross(u);
    let mut lines = Vec::new();
    grid(plate.center, u * half, v * half, &mut lines);
    let (c, r) = (plate.center, plate.opening);
    for (a, b) in lines {
        // Where the segment a + t (b - a) is inside the circle: |a - c + t d|² < r².
        let (d, m) = (b - a, a - c);
        let (qa, qb, qc) = (d.dot(d), 2.0 * m.dot(d), m.dot(m) - r * r);
        let disc = qb * qb - 4.0 * qa * qc;
        if r <= 0.0 || qa == 0.0 || disc <= 0.0 {
            out.push((a, b));
            continue;
        }
        let root = disc.sqrt();
        let (t0, t1) = ((-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa));
        if t0 > 0.0 {
            out.push((a, a + d * t0.min(1.0)));
        }
        if t1 < 1.0 {
            out.push((a + d * t1.max(0.0), b));
        }
    }
    if r > 0.0 {
        let at = |k: usize| {
            let angle = k as f32 / RIM_SIDES as f32 * std::f32::consts::TAU;
            c + (u * angle.cos() + v * angle.sin()) * r
        };
        out.extend((0..RIM_SIDES).map(|k| (at(k), at(k + 1))));
    }
}

/// The lines of a rectangle's grid: centre `c`, half sides `a` and `b` (m).
fn grid(c: Vec3, a: Vec3, b: Vec3, out: &mut Vec<(Vec3, Vec3)>) {
    for k in 0..=WALL_LINES {
        let t = 2.0 * k as f32 / WALL_LINES as f32 - 1.0;
        out.push((c + a * t - b, c + a * t + b));
        out.push((c - a + b * t, c + a + b * t));
    }
}

/// The direction in a plane of normal `n` (unit) that a wall's length runs along by
/// default: down the slope, across z, where the plane leans about z as a ramp in x-y
/// does; else across x.
#[must_use]
pub fn slope_direction(n: Vec3) -> Vec3 {
    let across_z = n.cross(Vec3::Z);
    if across_z.length_squared() > 1e-2 { across_z.normalize() } else { n.cross(Vec3::X).normalize() }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    /// A plate's lines stay on its plane and out of its opening, and its rim is drawn.
    #[test]
    fn a_plates_lines_stop_at_its_opening() {
        let plate = crate::physics::Plate::new(Vec3::Y, Vec3::new(0.5, 1.0, 0.0), 0.4, 0.0, 0.5).unwrap();
        let mut out = Vec::new();
        super::plate_patch(&plate, Vec3::splat(-2.0), Vec3::splat(2.0), &mut out);
        let mut rim = 0;
        for &(a, b) in &out {
            for t in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let p = a.lerp(b, t);
                assert!((p.y - 1.0).abs() < 1e-5, "off the plane: {p}");
                let r = Vec3::new(p.x - 0.5, 0.0, p.z).length();
                assert!(r >= 0.4 * 0.99, "inside the opening: {p} ({r} m from its centre)");
            }
            if (a.x - 0.5).hypot(a.z) - 0.4 < 1e-4 && (b.x - 0.5).hypot(b.z) - 0.4 < 1e-4 {
                rim += 1;
            }
        }
        assert!(rim >= super::RIM_SIDES, "the rim's {} sides, found {rim}", super::RIM_SIDES);
    }

    use super::{MIN_HALF_SIDE, SCENE_SPANS, WALL_LINES, plane_patch};
    use crate::physics::Plane;

    /// Every end of every line lies on the plane, within the patch's square, and the
    /// patch is centred on the box's centre moved onto the plane along its normal.
    #[test]
    fn a_patch_lies_on_its_plane_around_the_scene() {
        for normal in [Vec3::new(-0.5, 1.0, 0.0), Vec3::X, Vec3::Y, Vec3::new(0.3, 0.4, -0.9), Vec3::Z] {
            let plane = Plane::new(normal, Vec3::new(500.0, 0.0, 2.0), 0.3, 0.5).unwrap();
            let (lo, hi) = (Vec3::new(499.0, 1.0, -1.0), Vec3::new(502.0, 4.0, 1.0));
            let mut lines = Vec::new();
            plane_patch(&plane, lo, hi, &mut lines);
            assert_eq!(lines.len(), 2 * (WALL_LINES + 1));
            let n = plane.normal;
            let centre = 0.5 * (lo + hi);
            // The foot of the perpendicular from the centre, found another way: the
            // point of the plane nearest the centre is where the distance along n is 0.
            let distance = n.dot(centre) - plane.offset;
            let foot = centre - distance * n;
            let half = SCENE_SPANS * (hi - lo).length();
            let mut sum = Vec3::ZERO;
            for &(a, b) in &lines {
                for p in [a, b] {
                    assert!((n.dot(p) - plane.offset).abs() < 1e-3, "{p} is off the plane {normal}");
                    let within = (p - foot).length();
                    assert!(within <= half * 2f32.sqrt() * 1.0001, "{p} is {within} m from the centre");
                    sum += p;
                }
            }
            let mean = sum / (4 * (WALL_LINES + 1)) as f32;
            assert!((mean - foot).length() < 1e-3, "centred on {mean}, not {foot}");
        }
    }

    #[test]
    fn an_empty_scene_gets_a_patch_at_the_origin_of_the_least_size() {
        let plane = Plane::new(Vec3::X, Vec3::new(3.0, 0.0, 0.0), 0.3, 0.5).unwrap();
        let mut lines = Vec::new();
        plane_patch(&plane, Vec3::INFINITY, Vec3::NEG_INFINITY, &mut lines);
        let reach = lines
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .map(|p| (p - Vec3::new(3.0, 0.0, 0.0)).abs().max_element());
        let reach = reach.fold(0.0f32, f32::max);
        assert!((reach - MIN_HALF_SIDE).abs() < 1e-5, "{reach}");
    }
}
