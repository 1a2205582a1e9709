//! Off-screen frames at 1280x720 with the panel, per scene, on whatever adapter wgpu
//! picks (lavapipe on these machines): milliseconds per frame, read-back included.

use criterion::{Criterion, criterion_group, criterion_main};
use particle_lab::scenes::SCENES;
use particle_lab::snapshot::Snapshotter;
use particle_lab::ui::Lab;

fn render(c: &mut Criterion) {
    let mut snapshotter = match Snapshotter::new() {
        Ok(s) => s,
        Err(error) => {
            eprintln!("skipping the render benchmark: {error}");
            return;
        }
    };
    for msaa in [true, false] {
        let name = if msaa { "frame_1280x720_ui_msaa4" } else { "frame_1280x720_ui_no_msaa" };
        let mut group = c.benchmark_group(name);
        group.sample_size(20);
        for entry in SCENES {
            let mut lab = Lab::new(entry.info.name, &[]).expect("default scene");
            lab.view.msaa = msaa;
            lab.run_steps_recorded(120);
            group.bench_function(entry.info.name, |b| {
                b.iter(|| snapshotter.render(&mut lab, [1280, 720], true).expect("frame renders"))
            });
        }
        group.finish();
    }
}

criterion_group!(benches, render);
criterion_main!(benches);
