//! Debug drawing never looks like a particle (issue 19): link limits, contacts, arrows
//! and the tape measure add lines, not balls; the tape lying on the ground is drawn
//! above it.

use glam::Vec3;
use particle_lab::render::{FrameBuilder, FrameData, ViewOptions};
use particle_lab::ui::Lab;
use particle_lab::ui::paint::{self, TAPE_LIFT};

fn frame(lab: &Lab, options: ViewOptions) -> FrameData {
    let mut builder = FrameBuilder::default();
    builder.build(lab.scene.as_ref(), None, lab.scene.world().time(), options, None);
    builder.frame
}

#[test]
fn link_limits_and_contacts_add_no_balls() {
    for scene in ["springForces", "cradle", "bridge"] {
        let mut lab = Lab::new(scene, &[]).unwrap();
        lab.run_steps(120);
        let plain = frame(&lab, ViewOptions { contacts: false, ..ViewOptions::default() });
        let debug = frame(&lab, ViewOptions { contacts: true, ..ViewOptions::default() });
        assert_eq!(debug.spheres, plain.spheres, "{scene}: debug drawing added balls");
        assert!(debug.segments.len() > plain.segments.len(), "{scene}: no debug drawing at all");
    }
}

#[test]
fn arrows_have_heads_not_balls() {
    let mut lab = Lab::new("springForces", &[]).unwrap();
    lab.run_steps(60);
    lab.select(lab.scene.world().particles.id(0));
    let mut frame = FrameData::default();
    paint::vectors(&lab, &mut frame);
    assert!(frame.spheres.is_empty(), "arrow tips are balls: {:?}", frame.spheres);
    // A shaft and two barbs per arrow.
    assert!(frame.segments.len() >= 3 && frame.segments.len() % 3 == 0, "{} segments", frame.segments.len());
}

/// Issue 19: a tape measured along the ground lay in the ground's plane and was hidden.
#[test]
fn the_tape_on_the_ground_is_drawn_above_it() {
    let mut lab = Lab::new("bridge", &[]).unwrap();
    lab.tape = true;
    lab.tape_points = vec![Vec3::new(-3.0, 0.0, 1.0), Vec3::new(2.5, 0.0, 1.0)];
    let mut frame = FrameData::default();
    paint::tape(&lab, &mut frame);
    assert!(frame.spheres.is_empty(), "tape ends are balls");
    assert!(!frame.segments.is_empty());
    for segment in &frame.segments {
        assert!(segment.from[1] >= TAPE_LIFT * 0.5 || segment.to[1] >= TAPE_LIFT * 0.5, "{segment:?}");
    }
    // The tape itself, end to end, above the ground.
    let tape = frame
        .segments
        .iter()
        .find(|s| (s.from[0] + 3.0).abs() < 1e-6 && (s.to[0] - 2.5).abs() < 1e-6)
        .expect("the tape between its ends");
    assert_eq!((tape.from[1], tape.to[1]), (TAPE_LIFT, TAPE_LIFT));
}
