//! The grid finds exactly the pairs the all-pairs test finds, in the same order.

use glam::Vec3;
use particle_lab::physics::BroadPhase;
use particle_lab::physics::broad_phase::all_pairs;
use proptest::prelude::*;

/// A configuration: positions and reach radii.
fn configuration() -> impl Strategy<Value = (Vec<Vec3>, Vec<f32>)> {
    let spread = (1usize..400).prop_flat_map(|n| {
        (
            prop::collection::vec((-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0), n),
            prop::collection::vec(0.1f32..1.5, n),
        )
    });
    // Dense clusters around a few centres, many touching.
    let clustered = (1usize..400, 1usize..5).prop_flat_map(|(n, clusters)| {
        (
            prop::collection::vec((0..clusters, -2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0), n),
            prop::collection::vec(0.05f32..0.6, n),
        )
    });
    // Mixed radii: mostly small, a few up to 100 times larger (oversized for the grid),
    // some of them 0 (no collisions).
    let mixed = (1usize..300).prop_flat_map(|n| {
        (
            prop::collection::vec((-20.0f32..20.0, -20.0f32..20.0, -20.0f32..20.0), n),
            prop::collection::vec(prop_oneof![8 => 0.05f32..0.3, 1 => 2.0f32..20.0, 1 => Just(0.0)], n),
        )
    });
    // Coincident: many particles at exactly the same few points.
    let coincident = (1usize..200)
        .prop_flat_map(|n| (prop::collection::vec(0..3u8, n), prop::collection::vec(0.1f32..1.0, n)));
    prop_oneof![
        spread.prop_map(|(p, r)| (p.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect(), r)),
        clustered.prop_map(|(p, r)| {
            let centres =
                [Vec3::ZERO, Vec3::new(30.0, 0.0, 0.0), Vec3::new(0.0, -40.0, 7.0), Vec3::splat(-1e4)];
            (p.into_iter().map(|(c, x, y, z)| centres[c % 4] + Vec3::new(x, y, z)).collect(), r)
        }),
        mixed.prop_map(|(p, r)| (p.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect(), r)),
        coincident.prop_map(|(p, r)| (p.into_iter().map(|i| Vec3::splat(f32::from(i) * 0.5)).collect(), r)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn grid_pairs_equal_all_pairs((positions, reach) in configuration()) {
        let mut grid = BroadPhase::new();
        let (mut found, mut expected) = (Vec::new(), Vec::new());
        grid.find_pairs(&positions, &reach, &mut found);
        all_pairs(&positions, &reach, &mut expected);
        prop_assert_eq!(&found, &expected);
        // Reused buffers give the same answer the second time.
        grid.find_pairs(&positions, &reach, &mut found);
        prop_assert_eq!(found, expected);
    }
}

#[test]
fn large_worlds_take_the_threaded_path_and_agree() {
    // 20,000 particles: above the size where the search is split across threads.
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let positions: Vec<Vec3> = (0..20_000).map(|_| Vec3::new(next(), next(), next()) * 60.0).collect();
    let reach: Vec<f32> = (0..20_000).map(|i| if i % 97 == 0 { 3.0 } else { 0.5 + 0.2 * next() }).collect();
    let (mut found, mut expected) = (Vec::new(), Vec::new());
    BroadPhase::new().find_pairs(&positions, &reach, &mut found);
    all_pairs(&positions, &reach, &mut expected);
    assert!(expected.len() > 1000, "the test should see many pairs, saw {}", expected.len());
    assert_eq!(found, expected);
}

#[test]
fn far_flung_and_non_finite_positions_do_not_panic() {
    let positions = [Vec3::ZERO, Vec3::splat(1e30), Vec3::splat(-1e30), Vec3::NAN, Vec3::new(0.5, 0.0, 0.0)];
    let reach = [0.5, 0.5, 0.5, 0.5, 0.5];
    let mut found = Vec::new();
    BroadPhase::new().find_pairs(&positions, &reach, &mut found);
    assert_eq!(found, vec![(0, 4)]);
}
