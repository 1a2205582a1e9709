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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// One grid searched step after step while the spheres move, a little or a lot,
    /// and their reaches change: whether it tests its kept pairs again or searches
    /// anew, it finds exactly the pairs of the all-pairs test every time.
    #[test]
    fn kept_pairs_equal_all_pairs_as_spheres_move(
        (mut positions, mut reach) in configuration(),
        moves in prop::collection::vec((0.0f32..0.2, 0.0f32..0.05, any::<u64>(), 0u8..=4), 1..8),
    ) {
        let mut grid = BroadPhase::new();
        let (mut found, mut expected) = (Vec::new(), Vec::new());
        for (step, &(distance, growth, seed, moving)) in moves.iter().enumerate() {
            grid.find_pairs(&positions, &reach, &mut found);
            all_pairs(&positions, &reach, &mut expected);
            prop_assert_eq!(&found, &expected, "step {}", step);
            // Each sphere moves up to `distance` and grows its reach by up to `growth`.
            let mut state = seed | 1;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5
            };
            // A share of the spheres moves (none, a few, ..., all): a few movers are
            // brought up to date in the kept pairs, many make the grid search anew.
            for (p, r) in positions.iter_mut().zip(reach.iter_mut()) {
                if moving < 4 && next() + 0.5 >= f32::from(moving) / 4.0 {
                    continue;
                }
                *p += Vec3::new(next(), next(), next()) * 2.0 * distance;
                if *r > 0.0 {
                    *r = (*r + next() * 2.0 * growth).max(0.01);
                }
            }
        }
    }
}

/// Spheres that keep still are searched once: later searches test the kept pairs
/// again (the grid is not rebuilt) and find the same pairs; a sphere moving by more
/// than the skin, or a sleeping sphere, makes the grid search anew.
#[test]
fn a_still_world_reuses_its_pairs() {
    let positions: Vec<Vec3> = (0..1000)
        .map(|i| Vec3::new((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32) * 0.95)
        .collect();
    let reach = vec![0.5; positions.len()];
    let (mut grid, mut found, mut expected) = (BroadPhase::new(), Vec::new(), Vec::new());
    all_pairs(&positions, &reach, &mut expected);
    assert!(expected.len() > 2000, "a packed block makes many pairs: {}", expected.len());
    grid.find_pairs(&positions, &reach, &mut found);
    assert!(!grid.reused_pairs(), "the first search builds the grid");
    for _ in 0..3 {
        grid.find_pairs(&positions, &reach, &mut found);
        assert!(grid.reused_pairs(), "nothing moved: the kept pairs serve");
        assert_eq!(found, expected);
    }
    // A small move (a hundredth of a radius) is within the skin.
    let mut moved = positions.clone();
    moved[0] += Vec3::new(0.005, 0.0, 0.0);
    grid.find_pairs(&moved, &reach, &mut found);
    assert!(grid.reused_pairs());
    all_pairs(&moved, &reach, &mut expected);
    assert_eq!(found, expected);
    // Half a radius is not: that sphere's pairs are found again, the rest kept.
    moved[0] += Vec3::new(0.25, 0.0, 0.0);
    grid.find_pairs(&moved, &reach, &mut found);
    assert!(grid.reused_pairs(), "one sphere past its skin is brought up to date alone");
    all_pairs(&moved, &reach, &mut expected);
    assert_eq!(found, expected);
    // A few more, one after another, some of them twice, some into another's place.
    for (k, i) in [5usize, 17, 0, 333, 999, 5, 550].into_iter().enumerate() {
        moved[i] += Vec3::new(0.1, -0.3, 0.2) * (k as f32 + 1.0) * 0.5;
        grid.find_pairs(&moved, &reach, &mut found);
        assert!(grid.reused_pairs());
        all_pairs(&moved, &reach, &mut expected);
        assert_eq!(found, expected, "after moving sphere {i}");
    }
    // Many at once (more than one in 32): the grid searches anew.
    for p in moved.iter_mut().step_by(10) {
        *p += Vec3::new(0.0, 0.3, 0.0);
    }
    grid.find_pairs(&moved, &reach, &mut found);
    assert!(!grid.reused_pairs(), "a hundred movers make the grid search anew");
    all_pairs(&moved, &reach, &mut expected);
    assert_eq!(found, expected);
    // With sleeping spheres the plain search runs.
    let asleep = vec![false; positions.len()];
    grid.find_pairs_awake(&moved, &reach, Some(&asleep), &mut found);
    assert!(!grid.reused_pairs());
    assert_eq!(found, expected);
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

/// Spheres `side` × `side` × `side` 0.95 m apart, in x-fastest order: with a reach of
/// 0.5 m each overlaps its neighbours.
fn packed_block(side: usize) -> Vec<Vec3> {
    (0..side * side * side)
        .map(|i| Vec3::new((i % side) as f32, ((i / side) % side) as f32, (i / (side * side)) as f32) * 0.95)
        .collect()
}

/// A still block with more kept pairs than one task tests (16,384) serves them on
/// several threads: on a 2-thread pool the kept pairs give exactly the all-pairs
/// list, in its order, step after step, with a sphere moving within its skin.
#[test]
fn many_kept_pairs_are_served_on_several_threads_in_order() {
    let positions = packed_block(20);
    let reach = vec![0.5; positions.len()];
    let (mut found, mut expected) = (Vec::new(), Vec::new());
    all_pairs(&positions, &reach, &mut expected);
    assert!(expected.len() > 16_384, "enough pairs for several tasks: {}", expected.len());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
    pool.install(|| {
        let mut grid = BroadPhase::new();
        let mut moved = positions.clone();
        for step in 0..4 {
            grid.find_pairs(&moved, &reach, &mut found);
            assert_eq!(grid.reused_pairs(), step > 0, "step {step}: the kept pairs serve after the first");
            all_pairs(&moved, &reach, &mut expected);
            assert_eq!(found, expected, "step {step}");
            // Sphere 4,321 closes on its neighbour along x by a quarter of the gap each
            // step: within the skin, so the kept pairs still serve.
            moved[4321].x += 0.01;
        }
    });
}

/// A still block of more spheres than one task looks through for movers (8,192), on a
/// 2-thread pool: spheres past their skin in each of its chunks are found and brought
/// up to date (the kept pairs give exactly the all-pairs list), and more movers than
/// one sphere in 32, spread over the chunks, make the grid search anew.
#[test]
fn movers_are_found_on_several_threads() {
    let positions = packed_block(26);
    assert!(positions.len() > 2 * 8192, "three chunks of movers: {}", positions.len());
    let reach = vec![0.5; positions.len()];
    let (mut found, mut expected) = (Vec::new(), Vec::new());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
    pool.install(|| {
        let mut grid = BroadPhase::new();
        let mut moved = positions.clone();
        grid.find_pairs(&moved, &reach, &mut found);
        assert!(!grid.reused_pairs(), "the first search builds the grid");
        // One sphere in each chunk jumps two places along z, onto spheres it had no pair
        // with: only brought up to date does it have its new pairs.
        for (step, movers) in [[100usize, 9_000, 17_000], [8_191, 8_192, 16_384]].into_iter().enumerate() {
            for i in movers {
                moved[i].z += if moved[i].z > 10.0 { -1.9 } else { 1.9 };
            }
            grid.find_pairs(&moved, &reach, &mut found);
            assert!(grid.reused_pairs(), "step {step}: three movers are brought up to date");
            all_pairs(&moved, &reach, &mut expected);
            assert_eq!(found, expected, "step {step}");
        }
        // 704 movers, one sphere in 25 (the limit is one in 32, and 16 more).
        for p in moved.iter_mut().step_by(25) {
            p.y += 1.9;
        }
        grid.find_pairs(&moved, &reach, &mut found);
        assert!(!grid.reused_pairs(), "too many movers: the grid searches anew");
        all_pairs(&moved, &reach, &mut expected);
        assert_eq!(found, expected);
    });
}

#[test]
fn far_flung_and_non_finite_positions_do_not_panic() {
    let positions = [Vec3::ZERO, Vec3::splat(1e30), Vec3::splat(-1e30), Vec3::NAN, Vec3::new(0.5, 0.0, 0.0)];
    let reach = [0.5, 0.5, 0.5, 0.5, 0.5];
    let mut found = Vec::new();
    BroadPhase::new().find_pairs(&positions, &reach, &mut found);
    assert_eq!(found, vec![(0, 4)]);
}
