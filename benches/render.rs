//! Off-screen frames at 1280x720 with the panel, on whatever adapter wgpu picks
//! (lavapipe on these machines): milliseconds per frame, read-back included.
//!
//! - `frame_1280x720_ui_msaa4/<scene>` and `frame_1280x720_ui_no_msaa/<scene>`: every
//!   scene at its defaults after 120 steps.
//! - `pile_1280x720_ui/<count>`: the pile at 2,000 and 100,000 spheres (the window's
//!   default view options for it) after 120 steps, the frame as the window draws it.
//! - `pile_frame_data/<count>`: building the instance data alone (CPU).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use particle_lab::capture::FrameCapture;
use particle_lab::render::FrameBuilder;
use particle_lab::scenes::SCENES;
use particle_lab::ui::Lab;

fn capture() -> Option<FrameCapture> {
    FrameCapture::new().map_err(|error| eprintln!("skipping the render benchmark: {error}")).ok()
}

fn scenes(c: &mut Criterion) {
    let Some(mut capture) = capture() else { return };
    for msaa in [true, false] {
        let name = if msaa { "frame_1280x720_ui_msaa4" } else { "frame_1280x720_ui_no_msaa" };
        let mut group = c.benchmark_group(name);
        group.sample_size(20);
        for entry in SCENES {
            let mut lab = Lab::new(&entry.info().name, &[]).expect("default scene");
            lab.view.msaa = msaa;
            lab.run_steps_recorded(120);
            group.bench_function(&*entry.info().name, |b| {
                b.iter(|| capture.render(&mut lab, [1280, 720], true).expect("frame renders"))
            });
        }
        group.finish();
    }
}

/// The pile with `count` spheres in a box wide enough for about 13 layers of them.
fn pile_lab(count: u32) -> Lab {
    let width = if count > 10_000 { 111 } else { 16 };
    let settings = [format!("count={count}"), format!("width={width}")];
    let mut lab = Lab::new("pile", &settings).expect("valid pile settings");
    lab.run_steps_recorded(120);
    lab
}

fn pile(c: &mut Criterion) {
    let Some(mut capture) = capture() else { return };
    let counts = [2_000, 100_000];
    let mut group = c.benchmark_group("pile_1280x720_ui");
    group.sample_size(10);
    for count in counts {
        let mut lab = pile_lab(count);
        group.bench_function(BenchmarkId::from_parameter(count), |b| {
            b.iter(|| capture.render(&mut lab, [1280, 720], true).expect("frame renders"))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("pile_frame_data");
    for count in counts {
        let lab = pile_lab(count);
        let mut builder = FrameBuilder::default();
        let now = lab.scene.world().time();
        group.bench_function(BenchmarkId::from_parameter(count), |b| {
            b.iter(|| builder.build(lab.scene.as_ref(), Some(&lab.trails), now, lab.view, None).spheres.len())
        });
    }
    group.finish();
}

criterion_group!(benches, scenes, pile);
criterion_main!(benches);
